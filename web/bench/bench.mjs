// Times the sphere_sphere_union_100k case of the peers harness in headless Chromium: csgkit's
// WebAssembly module beside manifold-3d's, single-threaded, on the same arrays (bench.js).
// The spheres come from the harness's own generator (cases.py, which needs numpy), written as
// raw float64 / uint32 arrays into dist/bench-data. Run web/build.sh first.
// Usage: node bench/bench.mjs [--peers ../shared/peers] [--python PY] [--repeat 5]
//                             [--chromium /usr/bin/chromium]
import { execFileSync } from "node:child_process";
import { existsSync, mkdirSync } from "node:fs";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { parseArgs } from "node:util";

import { launchChromium, serve } from "../tests/serve.mjs";

const web = resolve(dirname(fileURLToPath(import.meta.url)), "..");
const { values: args } = parseArgs({
  options: {
    peers: { type: "string", default: resolve(web, "..", "..", "shared", "peers") },
    python: { type: "string" },
    repeat: { type: "string", default: "5" },
    chromium: { type: "string", default: "/usr/bin/chromium" },
  },
});
const python = args.python ?? [join(args.peers, ".venv", "bin", "python")].find(existsSync) ?? "python3";
const data = join(web, "dist", "bench-data");
mkdirSync(data, { recursive: true });
execFileSync(python, ["-c", `
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np, cases
(va, fa), (vb, fb) = cases.sphere_pair(71)  # sphere_sphere_100k
for name, v, f in (("a", va, fa), ("b", vb, fb)):
    np.ascontiguousarray(v, "<f8").tofile(f"{sys.argv[2]}/{name}.f64")
    np.ascontiguousarray(f, "<u4").tofile(f"{sys.argv[2]}/{name}.u32")
`, args.peers, data], { stdio: "inherit" });

const server = await serve(join(web, "dist"));
const browser = await launchChromium(args.chromium);
const page = await browser.newPage();
await page.goto(`${server.url}/bench.html?repeat=${args.repeat}`);
await page.waitForFunction(() => document.getElementById("status").textContent !== "running…", null, { timeout: 900_000 });
const results = JSON.parse(await page.locator("#results").textContent());
await browser.close();
await server.close();
if (results.error) throw new Error(results.error);

console.log(JSON.stringify(results, null, 1));
const m = results.manifold;
console.log(`\nsphere_sphere_union_100k (${results.input_triangles.join(" + ")} triangles), median of ${results.repeat} runs:\n`);
console.log("| measure | csgkit ms | manifold-3d ms | csgkit / manifold-3d |");
console.log("|---|---|---|---|");
for (const [label, key] of [["union only", "op_ms"], ["arrays in, arrays out", "arrays_ms"]]) {
  console.log(`| ${label} | ${results.csgkit[key].toFixed(0)} | ${m[key].toFixed(0)} | ${(results.csgkit[key] / m[key]).toFixed(2)} |`);
  console.log(`| ${label}, selfCheck: false | ${results.csgkit_no_self_check[key].toFixed(0)} | ${m[key].toFixed(0)} | ${(results.csgkit_no_self_check[key] / m[key]).toFixed(2)} |`);
}
console.log(`\nresults: csgkit ${results.csgkit.triangles} triangles, volume ${results.csgkit.volume}; manifold-3d ${m.triangles} triangles, volume ${m.volume}`);
