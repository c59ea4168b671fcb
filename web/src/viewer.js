// The 3D viewer: three.js with orbit controls, one layer per operand and one for the result,
// faces in their colours (flat shaded), an optional overlay of the polygon edges.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

export class Viewer {
  constructor(canvas) {
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xf4f5f7);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener("change", () => this.render());
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667080, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(3, -2, 5);
    this.camera.add(sun);
    this.scene.add(this.camera);
    this.layers = new Map();
    this.showEdges = true;
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  resize() {
    const canvas = this.renderer.domElement;
    const { clientWidth: w, clientHeight: h } = canvas;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  /** Removes every layer. */
  clear() {
    for (const layer of this.layers.values()) {
      this.scene.remove(layer.group);
      layer.group.traverse((o) => o.geometry?.dispose());
    }
    this.layers.clear();
    this.render();
  }

  /** Adds (or replaces) layer `key`: the drawable of a mesh (see worker.js). A ghost layer is
   * drawn translucent, so the result inside it shows. */
  setLayer(key, drawable, { visible = true, ghost = false } = {}) {
    if (this.layers.has(key)) {
      this.scene.remove(this.layers.get(key).group);
    }
    const group = new THREE.Group();
    const { positions, corners, faces, edges, faceColours, vertexColours } = drawable;
    // One vertex per triangle corner, so every face is flat and has its own colour.
    const count = corners.length;
    const xyz = new Float32Array(3 * count);
    const rgb = new Float32Array(3 * count);
    for (let i = 0; i < count; i++) {
      const v = corners[i];
      xyz.set(positions.subarray(3 * v, 3 * v + 3), 3 * i);
      const [colours, at] = vertexColours ? [vertexColours, 4 * v] : [faceColours, 4 * faces[(i / 3) | 0]];
      rgb[3 * i] = srgbToLinear(colours[at]);
      rgb[3 * i + 1] = srgbToLinear(colours[at + 1]);
      rgb[3 * i + 2] = srgbToLinear(colours[at + 2]);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(xyz, 3));
    geometry.setAttribute("color", new THREE.BufferAttribute(rgb, 3));
    geometry.computeVertexNormals();
    const material = new THREE.MeshStandardMaterial({
      vertexColors: true,
      flatShading: true,
      roughness: 0.65,
      metalness: 0.05,
      side: THREE.DoubleSide,
      transparent: ghost,
      opacity: ghost ? 0.18 : 1,
      depthWrite: !ghost,
      polygonOffset: true,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    group.add(new THREE.Mesh(geometry, material));
    const lines = new THREE.BufferGeometry();
    lines.setAttribute("position", new THREE.BufferAttribute(positions, 3));
    lines.setIndex(new THREE.BufferAttribute(edges, 1));
    const edgeLines = new THREE.LineSegments(
      lines,
      new THREE.LineBasicMaterial({ color: 0x20242c, transparent: true, opacity: ghost ? 0.15 : 0.55 }),
    );
    edgeLines.name = "edges";
    edgeLines.visible = this.showEdges;
    group.add(edgeLines);
    group.visible = visible;
    this.scene.add(group);
    this.layers.set(key, { group, drawable });
    this.render();
  }

  setVisible(key, visible) {
    const layer = this.layers.get(key);
    if (layer) layer.group.visible = visible;
    this.render();
  }

  setEdges(show) {
    this.showEdges = show;
    for (const { group } of this.layers.values()) group.getObjectByName("edges").visible = show;
    this.render();
  }

  /** Points the camera at everything visible. */
  frame() {
    const box = new THREE.Box3();
    for (const { group } of this.layers.values()) if (group.visible) box.expandByObject(group);
    if (box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const radius = box.getSize(new THREE.Vector3()).length() / 2;
    const distance = radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2)) * 1.05;
    const direction = new THREE.Vector3(1.1, -1.6, 0.9).normalize();
    this.camera.position.copy(centre).addScaledVector(direction, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.render();
  }
}

/** A colour byte in sRGB as the linear value three.js shades with. */
function srgbToLinear(byte) {
  const c = byte / 255;
  return c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4;
}
