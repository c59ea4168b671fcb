// The JavaScript module (dist/pkg, built by build.sh) in Node.js, call by call: every export
// against values known independently (volumes of boxes and their unions, the command line's
// messages), and its errors. Run: node --test tests/module.mjs
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { dirname, join, resolve } from "node:path";
import { test } from "node:test";
import { fileURLToPath, pathToFileURL } from "node:url";

const dist = resolve(dirname(fileURLToPath(import.meta.url)), "..", "dist");
const csgkit = await import(pathToFileURL(join(dist, "pkg", "csgkit_wasm.js")).href);
csgkit.initSync({ module: readFileSync(join(dist, "pkg", "csgkit_wasm_bg.wasm")) });

/** The unit cube moved by x along the first axis, as flat arrays with quads. */
function cube(x) {
  const vertices = [];
  for (const i of [0, 1]) for (const j of [0, 1]) for (const k of [0, 1]) vertices.push(i + x, j, k);
  const faces = [0, 1, 3, 2, 4, 6, 7, 5, 0, 4, 5, 1, 2, 3, 7, 6, 0, 2, 6, 4, 1, 5, 7, 3];
  return new csgkit.Mesh(new Float64Array(vertices), new Uint32Array(faces), new Uint32Array([4, 4, 4, 4, 4, 4]));
}

const volume = (mesh) => csgkit.check(mesh, { selfIntersections: false }).volume;

/** Calls `f` and returns what it threw. */
function thrown(f) {
  try {
    f();
  } catch (error) {
    return error;
  }
  assert.fail("nothing was thrown");
}

test("the booleans of two unit cubes overlapping by half", () => {
  const [a, b] = [cube(0), cube(0.5)];
  assert.equal(volume(csgkit.union([a, b])), 1.5);
  assert.equal(volume(csgkit.intersection([a, b])), 0.5);
  assert.equal(volume(csgkit.difference([a, b])), 0.5);
  assert.equal(volume(csgkit.xor([a, b])), 1);
  assert.equal(volume(csgkit.boolean("union", [a, b, cube(1)])), 2);
  // The operands are still the caller's.
  assert.equal(a.faceCount, 6);
  assert.equal(volume(a), 1);
});

test("check reports what `csgkit check --json` reports", () => {
  const report = csgkit.check(cube(0));
  assert.equal(report.valid_solid, true);
  assert.equal(report.closed, true);
  assert.equal(report.faces, 6);
  assert.equal(report.triangles, 12);
  assert.equal(report.selfint_pairs, 0);
  assert.deepEqual(report.invalid_polygons, []);
});

test("a result keeps its stage seconds and its operands' colours", () => {
  const red = cube(0).withMaterial("red", new Uint8Array([255, 0, 0, 255]));
  const union = csgkit.union([red, cube(0.5)], { faces: "polygons" });
  assert.ok(union.stageSeconds().intersect >= 0);
  assert.ok(union.materialNames().includes("red"));
  const colours = union.faceColors();
  assert.equal(colours.length, 4 * union.faceCount);
  assert.ok(colours.some((c, i) => i % 4 === 0 && c === 255));
  const { corners, faces, edges } = union.triangulate();
  assert.equal(corners.length, 3 * faces.length);
  // A closed polygon mesh of F faces, E edges and V vertices: V − E + F = 2 for one sphere.
  assert.equal(union.vertexCount - edges.length / 2 + union.faceCount, 2);
});

test("boxes: arrays, box text and a .vox file", () => {
  const boxes = new Float64Array([0, 0, 0, 2, 2, 2, 1, 1, 1, 3, 3, 3]);
  assert.equal(volume(csgkit.boxes(boxes)), 15);
  assert.equal(volume(csgkit.boxes(new TextEncoder().encode("0 0 0 2 2 2\n1 1 1 3 3 3\n"))), 15);
  const vox = readFileSync(join(dist, "examples", "castle.vox"));
  const castle = csgkit.boxes(new Uint8Array(vox), { triangles: true });
  assert.equal(csgkit.check(castle, { selfIntersections: false }).valid_solid, true);
  assert.ok(castle.materialNames().length >= 5);
});

test("voxelize: a box on the grid is its own voxels", () => {
  const box = csgkit.cube(new Float64Array([0, 0, 0]), new Float64Array([1, 2, 3]));
  assert.equal(volume(csgkit.voxelize(box, 0.25)), 6);
  assert.equal(volume(csgkit.voxelize(box, 0.5, { surface: "surfels" })), 6);
});

test("load, loadParts and save round-trip every format", () => {
  const union = csgkit.union([cube(0), cube(0.5)]);
  for (const name of ["u.glb", "u.gltf", "u.3mf", "u.obj", "u.ply", "u.stl", "u.off"]) {
    const back = csgkit.load(csgkit.save(union, name), name);
    assert.equal(volume(back), 1.5, name);
  }
  const parts = csgkit.loadParts(readFileSync(join(dist, "examples", "sphere.3mf")), "sphere.3mf");
  assert.equal(parts.length, 1);
  assert.equal(parts[0].faceCount, 5120);
});

test("progress reports every stage, and false cancels", () => {
  const stages = [];
  csgkit.union([cube(0), cube(0.5)], { progress: (stage, done, total) => stages.push([stage, done, total]) });
  assert.ok(stages.some(([stage]) => stage === "intersect"));
  assert.ok(stages.every(([, done, total]) => done <= total));
  const error = thrown(() => csgkit.union([cube(0), cube(0.5)], { progress: () => false }));
  assert.equal(error.name, "CancelledError");
  assert.equal(error.message, "cancelled");
});

test("errors carry csgkit's messages and the Python package's class names", () => {
  const bad = thrown(() => csgkit.load(new TextEncoder().encode("v 0 0 0\nf 1 2 3\n"), "bad.obj"));
  assert.equal(bad.name, "ReadError");
  assert.match(bad.message, /^bad\.obj: line 2: face 0 refers to vertex 2/);
  const open = new csgkit.Mesh(new Float64Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), new Uint32Array([0, 1, 2]));
  const notClosed = thrown(() => csgkit.union([open, cube(0)]));
  assert.equal(notClosed.name, "InputError");
  assert.match(notClosed.message, /operand 0/);
  assert.equal(thrown(() => csgkit.boolean("merge", [cube(0)])).name, "InputError");
  assert.match(thrown(() => csgkit.union([cube(0), "cube"])).message, /meshes\[1\] is not a csgkit Mesh/);
  assert.match(thrown(() => csgkit.union([cube(0)], { colour: true })).message, /unknown option 'colour'/);
  assert.match(thrown(() => new csgkit.Mesh(new Float64Array([0, 0, NaN]), new Uint32Array([]))).message, /vertex 0 has a non-finite coordinate NaN/);
  assert.match(thrown(() => new csgkit.Mesh(new Float64Array(9), new Uint32Array([0, 1, 3]))).message, /face 0 of 1 names vertex 3/);
  assert.match(thrown(() => csgkit.save(cube(0), "cube.xyz")).message, /unknown extension/);
});
