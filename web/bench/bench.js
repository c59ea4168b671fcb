// The benchmark page (dist/bench.html?repeat=N): the union of the two spheres of bench-data/
// (written by bench.mjs) with csgkit's module and with manifold-3d (Manifold's WebAssembly
// build, single-threaded), from the same arrays, in this page's thread. Each figure is the
// median of N runs after one warm-up run, the libraries taking turns; the result goes into
// <pre id="results"> as JSON.
//
// Two measures per library:
//   op:     the union of two meshes already built (csgkit: union([a, b]); manifold:
//           a.add(b) and getMesh(), since Manifold evaluates lazily);
//   arrays: typed arrays in, the result's arrays out (building both operands, the union, and
//           reading the result's vertices and triangles).
// manifold-3d takes float32 vertex properties: its operands are the same coordinates rounded
// to float32 (csgkit reads float64).
import initCsgkit, * as csgkit from "csgkit-wasm";
import Module from "manifold-3d";

const repeat = Number(new URLSearchParams(location.search).get("repeat") ?? 5);

async function arrays(name) {
  const get = async (suffix) => (await fetch(`bench-data/${name}.${suffix}`)).arrayBuffer();
  return { vertices: new Float64Array(await get("f64")), triangles: new Uint32Array(await get("u32")) };
}

function median(values) {
  const sorted = [...values].sort((x, y) => x - y);
  return sorted[Math.floor(sorted.length / 2)];
}

/** Times each of `runs` (each returns its own op time) `repeat` times after a warm-up, the
 * runs interleaved so a change in the machine's load touches all of them alike. */
function timed(runs) {
  for (const run of Object.values(runs)) run();
  const samples = Object.fromEntries(Object.keys(runs).map((name) => [name, { ops: [], totals: [] }]));
  for (let i = 0; i < repeat; i++) {
    for (const [name, run] of Object.entries(runs)) {
      const start = performance.now();
      const op = run();
      samples[name].totals.push(performance.now() - start);
      samples[name].ops.push(op);
    }
  }
  return Object.fromEntries(
    Object.entries(samples).map(([name, { ops, totals }]) => [name, { op_ms: median(ops), arrays_ms: median(totals) }]),
  );
}

async function main() {
  await initCsgkit({ module_or_path: "pkg/csgkit_wasm_bg.wasm" });
  const manifold = await Module({ locateFile: () => "manifold.wasm" });
  manifold.setup();
  const [a, b] = [await arrays("a"), await arrays("b")];

  const csgkitRun = (options) => () => {
    const meshA = new csgkit.Mesh(a.vertices, a.triangles);
    const meshB = new csgkit.Mesh(b.vertices, b.triangles);
    const start = performance.now();
    const result = csgkit.union([meshA, meshB], options);
    const op = performance.now() - start;
    result.vertices();
    result.corners();
    for (const mesh of [meshA, meshB, result]) mesh.free();
    return op;
  };
  const manifoldRun = () => {
    const build = ({ vertices, triangles }) =>
      new manifold.Manifold(new manifold.Mesh({ numProp: 3, vertProperties: new Float32Array(vertices), triVerts: triangles }));
    const [meshA, meshB] = [build(a), build(b)];
    const start = performance.now();
    const union = meshA.add(meshB);
    const mesh = union.getMesh();
    const op = performance.now() - start;
    mesh.vertProperties.length;
    for (const m of [meshA, meshB, union]) m.delete();
    return op;
  };

  const check = csgkit.check(csgkit.union([new csgkit.Mesh(a.vertices, a.triangles), new csgkit.Mesh(b.vertices, b.triangles)]), { selfIntersections: false });
  const build = ({ vertices, triangles }) =>
    new manifold.Manifold(new manifold.Mesh({ numProp: 3, vertProperties: new Float32Array(vertices), triVerts: triangles }));
  const manifoldUnion = build(a).add(build(b));
  const times = timed({ csgkit: csgkitRun(), csgkit_no_self_check: csgkitRun({ selfCheck: false }), manifold: manifoldRun });
  const results = {
    input_triangles: [a.triangles.length / 3, b.triangles.length / 3],
    repeat,
    csgkit: { ...times.csgkit, triangles: check.triangles, volume: check.volume },
    csgkit_no_self_check: times.csgkit_no_self_check,
    manifold: { ...times.manifold, triangles: manifoldUnion.numTri(), volume: manifoldUnion.volume() },
    user_agent: navigator.userAgent,
  };
  document.getElementById("results").textContent = JSON.stringify(results);
  document.getElementById("status").textContent = "done";
}

main().catch((error) => {
  document.getElementById("results").textContent = JSON.stringify({ error: String(error) });
  document.getElementById("status").textContent = "failed";
});
