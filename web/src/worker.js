// The Web Worker that runs csgkit: every call into the wasm module happens here, so the page
// stays responsive however long a boolean takes. Messages in: {type: "load", files} (mesh or
// .vox files as {name, bytes}), {type: "example", name}, {type: "run", op},
// {type: "save", name}. Messages out: {type: "operands", ...}, {type: "progress", stage, done,
// total}, {type: "result", ...}, {type: "saved", name, bytes}, {type: "error", message, name}.
// "csgkit-wasm" is the JavaScript glue wasm-bindgen writes to dist/pkg (an esbuild alias).
import init, * as csgkit from "csgkit-wasm";
import { EXAMPLES, castleBite, demoSolids, mengerOperands } from "./examples.js";

const ready = init({ module_or_path: new URL("pkg/csgkit_wasm_bg.wasm", self.location.href) });

/** The operands loaded, each {name, mesh}, the last result and the operation that made it. */
let operands = [];
let result = null;
let resultOp = null;

/** What the viewer draws of a mesh: positions as float32, its triangles, their faces, the
 * polygon edges, and a colour per face. */
function drawable(mesh, fallbackColour) {
  const { corners, faces, edges } = mesh.triangulate();
  return {
    positions: new Float32Array(mesh.vertices()),
    corners,
    faces,
    edges,
    faceColours: faceColours(mesh, fallbackColour),
    vertexColours: mesh.vertexColors() ?? null,
  };
}

/** A colour per face (r, g, b, a bytes): the face's own colour, else its material's (a colour
 * made from the material's name), else the operand's. */
function faceColours(mesh, fallback) {
  const own = mesh.faceColors();
  if (own) return own;
  const count = mesh.faceCount;
  const colours = new Uint8Array(4 * count);
  const materials = mesh.faceMaterials();
  const names = materials ? mesh.materialNames().map(colourOfName) : [];
  for (let f = 0; f < count; f++) colours.set(materials ? names[materials[f]] : fallback, 4 * f);
  return colours;
}

/** A stable, saturated colour for a material name. */
function colourOfName(name) {
  let hash = 2166136261;
  for (const c of name) hash = Math.imul(hash ^ c.charCodeAt(0), 16777619) >>> 0;
  const hue = (hash % 360) / 360;
  const f = (n) => {
    const k = (n + hue * 12) % 12;
    return Math.round(255 * (0.55 - 0.4 * Math.max(-1, Math.min(k - 3, 9 - k, 1))));
  };
  return [f(0), f(8), f(4), 255];
}

/** Default colours of operands without colours or materials, in operand order. */
const OPERAND_COLOURS = [[214, 69, 65, 255], [52, 120, 200, 255], [232, 178, 48, 255], [74, 160, 90, 255]];

/** The operands of a list of files: each part of a mesh file is an operand (as `csgkit union`
 * takes them), a .vox file becomes one operand through the orthogonal engine. */
function operandsOf(files) {
  const list = [];
  for (const { name, bytes } of files) {
    if (/\.vox$/i.test(name)) {
      list.push({ name, mesh: csgkit.boxes(bytes, { progress }) });
    } else {
      const parts = csgkit.loadParts(bytes, name);
      parts.forEach((mesh, i) => list.push({ name: parts.length > 1 ? `${name} [${i}]` : name, mesh }));
    }
  }
  return list;
}

/** Reports a stage's progress to the page. */
function progress(stage, done, total) {
  postMessage({ type: "progress", stage, done, total });
  return true;
}

/** Sends the operands to the page. */
function sendOperands(op) {
  result = null;
  postMessage({
    type: "operands",
    op,
    operands: operands.map(({ name, mesh }, i) => ({
      name,
      faces: mesh.faceCount,
      drawable: drawable(mesh, OPERAND_COLOURS[i % OPERAND_COLOURS.length]),
    })),
  });
}

/** Fetches a file of the built-in examples. */
async function exampleFile(name) {
  const response = await fetch(new URL(`examples/${name}`, self.location.href));
  if (!response.ok) throw new Error(`examples/${name}: ${response.status} ${response.statusText}`);
  return { name, bytes: new Uint8Array(await response.arrayBuffer()) };
}

/** Loads a built-in example's operands. */
async function loadExample(name) {
  const example = EXAMPLES[name];
  if (!example) throw new Error(`no example named '${name}'`);
  const files = await Promise.all((example.files ?? []).map(exampleFile));
  operands = [];
  if (name === "solids") {
    operands = demoSolids(csgkit).map((mesh, i) => ({ name: ["cube", "bowl", "moat", "hole"][i], mesh }));
  } else if (name === "menger") {
    operands = mengerOperands(csgkit).map((mesh, i) => ({ name: i ? `bar ${i}` : "cube", mesh }));
  } else {
    operands = operandsOf(files);
    if (name === "vox") operands.push({ name: "bite", mesh: castleBite(csgkit) });
  }
  sendOperands(example.op);
}

/** The options of the page's booleans: faces merged into polygons, neighbouring faces in one
 * plane with equal material and colour merged too (`csgkit union --polygons
 * --merge-coplanar`), so the edges drawn are the solid's, not a triangulation's. */
const BOOLEAN_OPTIONS = { faces: "polygons", mergeCoplanar: true };

/** Runs the boolean on the operands and sends the result with its stats. */
function run(op) {
  if (operands.length < 2) throw new Error("a boolean needs two or more operands: drop more files");
  const meshes = operands.map((o) => o.mesh);
  const start = performance.now();
  result = csgkit.boolean(op, meshes, { ...BOOLEAN_OPTIONS, progress });
  resultOp = op;
  const opMs = performance.now() - start;
  const report = csgkit.check(result, { selfIntersections: false });
  postMessage({
    type: "result",
    op,
    stats: {
      triangles: report.triangles,
      volume: report.volume,
      valid_solid: report.valid_solid,
      op_ms: Math.round(opMs * 10) / 10,
    },
    drawable: drawable(result, [200, 200, 200, 255]),
  });
}

onmessage = async ({ data }) => {
  try {
    await ready;
    if (data.type === "load") {
      operands = operandsOf(data.files);
      sendOperands(null);
    } else if (data.type === "example") {
      await loadExample(data.name);
    } else if (data.type === "run") {
      run(data.op);
    } else if (data.type === "save") {
      if (!result) throw new Error("nothing to save: run an operation first");
      // GLB stores float32: the result written there is computed again, rounded to f32 and
      // certified in it, so the file holds a valid solid, not the f64 result rounded after.
      const mesh = /\.(glb|gltf|stl)$/i.test(data.name)
        ? csgkit.boolean(resultOp, operands.map((o) => o.mesh), { ...BOOLEAN_OPTIONS, precision: "f32", progress })
        : result;
      const bytes = csgkit.save(mesh, data.name);
      postMessage({ type: "saved", name: data.name, bytes }, [bytes.buffer]);
    }
  } catch (error) {
    postMessage({ type: "error", request: data.type, name: error.name, message: error.message ?? String(error) });
  }
};
