// The page in a real browser: serves web/dist on 127.0.0.1, drives headless Chromium, and
// checks what a person would see.
//   1. index.html?demo=union runs the built-in union in the worker; its stats in <pre id="stats">
//      must match `csgkit check --json` on the CLI's union of the same files (volume, triangle
//      count, valid solid), and the viewer must have drawn the two colours.
//   2. the Save buttons download the result as GLB, 3MF and OBJ, each the CLI's volume.
//   3. two files dropped on the page: their intersection is the CLI's.
//   4. index.html?demo=bad shows csgkit's error message for a malformed file, the CLI's.
//   5. index.html?demo=menger (a 31-operand difference) reports progress while the page keeps
//      drawing frames: the work is off the main thread.
// Usage: node tests/browser.mjs [--csgkit PATH] [--chromium PATH] [--screenshots DIR]
import { execFileSync, spawnSync } from "node:child_process";
import { mkdirSync, mkdtempSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { parseArgs } from "node:util";

import { launchChromium, serve } from "./serve.mjs";

const web = resolve(dirname(fileURLToPath(import.meta.url)), "..");
const { values: args } = parseArgs({
  options: {
    csgkit: { type: "string", default: resolve(web, "..", process.env.CARGO_TARGET_DIR ?? "target", "release", "csgkit") },
    chromium: { type: "string", default: "/usr/bin/chromium" },
    screenshots: { type: "string", default: join(web, "dist", "test-screenshots") },
  },
});
const dist = join(web, "dist");
const examples = join(dist, "examples");
const scratch = mkdtempSync(join(tmpdir(), "csgkit-web-test-"));
mkdirSync(args.screenshots, { recursive: true });

let passed = 0;
let failed = 0;
async function test(name, body) {
  try {
    await body();
    passed++;
    console.log(`ok   ${name}`);
  } catch (error) {
    failed++;
    console.log(`FAIL ${name}\n     ${error.stack ?? error}`);
  }
}
function check(condition, message) {
  if (!condition) throw new Error(message);
}

const server = await serve(dist);
const browser = await launchChromium(args.chromium);
const page = await browser.newPage();
const consoleErrors = [];
page.on("pageerror", (error) => consoleErrors.push(String(error)));

await test("union: stats match the CLI, the viewer shows both colours", async () => {
  await page.goto(`${server.url}/index.html?demo=union`);
  await page.waitForFunction(() => document.getElementById("stats").textContent || !document.getElementById("error").hidden, null, { timeout: 120_000 });
  const error = await page.locator("#error").textContent();
  check(!error, `the page shows an error: ${error}`);
  const stats = JSON.parse(await page.locator("#stats").textContent());
  check(["triangles", "volume", "valid_solid", "op_ms"].every((k) => k in stats), `stats keys: ${Object.keys(stats)}`);

  const union = join(scratch, "union.ply");
  // The page's booleans merge faces as --polygons --merge-coplanar do (worker.js).
  execFileSync(args.csgkit, ["union", join(examples, "cube.glb"), join(examples, "sphere.3mf"), "--polygons", "--merge-coplanar", "-o", union]);
  const cli = JSON.parse(execFileSync(args.csgkit, ["check", "--json", union], { encoding: "utf8" }));
  const relative = Math.abs(stats.volume - cli.volume) / Math.abs(cli.volume);
  check(relative <= 1e-12, `volume ${stats.volume} in the page, ${cli.volume} from the CLI`);
  check(stats.triangles === cli.triangles, `triangles ${stats.triangles} in the page, ${cli.triangles} from the CLI`);
  check(stats.valid_solid === true && cli.valid_solid === true, `valid_solid ${stats.valid_solid}, CLI ${cli.valid_solid}`);
  check(stats.op_ms > 0, `op_ms ${stats.op_ms}`);
  console.log(`     page ${JSON.stringify(stats)}; CLI volume ${cli.volume}, triangles ${cli.triangles}`);

  await page.screenshot({ path: join(args.screenshots, "union.png") });
  // Count what the viewer drew, read back from its canvas: pixels off the background, and
  // the red of the cube and the blue of the sphere.
  const pixels = await page.evaluate(() => {
    const canvas = document.getElementById("canvas");
    const copy = Object.assign(document.createElement("canvas"), { width: canvas.width, height: canvas.height });
    const context = copy.getContext("2d");
    context.drawImage(canvas, 0, 0);
    const data = context.getImageData(0, 0, copy.width, copy.height).data;
    const background = [0xf4, 0xf5, 0xf7];
    let drawn = 0;
    let red = 0;
    let blue = 0;
    for (let i = 0; i < data.length; i += 4) {
      const [r, g, b] = [data[i], data[i + 1], data[i + 2]];
      if (Math.abs(r - background[0]) + Math.abs(g - background[1]) + Math.abs(b - background[2]) > 24) drawn++;
      if (r > g + 60 && r > b + 60) red++;
      if (b > r + 60 && b > g + 20) blue++;
    }
    return { total: data.length / 4, drawn, red, blue };
  });
  console.log(`     canvas: ${JSON.stringify(pixels)}`);
  check(pixels.drawn > 0.05 * pixels.total, `only ${pixels.drawn} of ${pixels.total} pixels drawn`);
  check(pixels.red > 0.005 * pixels.total, `too few red pixels (${pixels.red}): the cube's colour is not shown`);
  check(pixels.blue > 0.005 * pixels.total, `too few blue pixels (${pixels.blue}): the sphere's colour is not shown`);
});

await test("save: the result downloads as GLB, 3MF and OBJ, the CLI's volume each time", async () => {
  // The page still shows the union of the first test.
  const cli = JSON.parse(execFileSync(args.csgkit, ["check", "--json", join(scratch, "union.ply")], { encoding: "utf8" }));
  for (const ext of ["glb", "3mf", "obj"]) {
    const [download] = await Promise.all([page.waitForEvent("download"), page.click(`button[data-ext="${ext}"]`)]);
    const path = join(scratch, download.suggestedFilename());
    await download.saveAs(path);
    check(path.endsWith(`.${ext}`), `downloaded ${path}`);
    const saved = JSON.parse(execFileSync(args.csgkit, ["check", "--json", path], { encoding: "utf8" }));
    // GLB stores float32 coordinates; 3MF and OBJ keep every digit of the float64 result.
    const tolerance = ext === "glb" ? 1e-6 : 1e-12;
    const relative = Math.abs(saved.volume - cli.volume) / cli.volume;
    check(saved.valid_solid, `${ext}: not a valid solid`);
    // The GLB's result was certified in float32: its own coordinates cross nothing.
    check(saved.selfint_pairs === 0 && saved.degenerate_faces === 0, `${ext}: ${saved.selfint_pairs} crossing pairs, ${saved.degenerate_faces} degenerate faces`);
    check(relative <= tolerance, `${ext}: volume ${saved.volume}, the CLI's ${cli.volume}`);
  }
});

await test("dropped files: their intersection is the CLI's", async () => {
  await page.goto(`${server.url}/index.html`);
  // Drop the two example files on the drop zone, as a person drags them from a folder.
  await page.evaluate(async () => {
    const transfer = new DataTransfer();
    for (const name of ["cube.glb", "sphere.3mf"]) {
      const bytes = await (await fetch(`examples/${name}`)).arrayBuffer();
      transfer.items.add(new File([bytes], name));
    }
    document.getElementById("drop").dispatchEvent(new DragEvent("drop", { dataTransfer: transfer, bubbles: true, cancelable: true }));
  });
  await page.waitForFunction(() => !document.getElementById("run").disabled, null, { timeout: 60_000 });
  const listed = await page.locator("#operands li").allTextContents();
  check(listed.length === 2 && listed[0].startsWith("cube.glb"), `operands listed: ${listed}`);
  await page.selectOption("#op", "intersection");
  await page.click("#run");
  await page.waitForFunction(() => document.getElementById("stats").textContent || !document.getElementById("error").hidden, null, { timeout: 120_000 });
  check(!(await page.locator("#error").textContent()), await page.locator("#error").textContent());
  const stats = JSON.parse(await page.locator("#stats").textContent());
  const out = join(scratch, "intersection.ply");
  execFileSync(args.csgkit, ["intersection", join(examples, "cube.glb"), join(examples, "sphere.3mf"), "--polygons", "--merge-coplanar", "-o", out]);
  const cli = JSON.parse(execFileSync(args.csgkit, ["check", "--json", out], { encoding: "utf8" }));
  check(Math.abs(stats.volume - cli.volume) <= 1e-12 * cli.volume, `volume ${stats.volume}, the CLI's ${cli.volume}`);
  check(stats.triangles === cli.triangles, `triangles ${stats.triangles}, the CLI's ${cli.triangles}`);
});

await test("bad file: the page shows csgkit's error message", async () => {
  await page.goto(`${server.url}/index.html?demo=bad`);
  await page.locator("#error").waitFor({ state: "visible", timeout: 60_000 });
  const message = await page.locator("#error").textContent();
  await page.screenshot({ path: join(args.screenshots, "bad.png") });
  console.log(`     page: ${message}`);
  check(message.startsWith("bad.obj: "), `the message does not name the file: ${message}`);
  // The CLI on the same file prints the same library message after its own path.
  const cli = spawnSync(args.csgkit, ["check", join(examples, "bad.obj")], { encoding: "utf8" });
  check(cli.status === 2, `csgkit check exited ${cli.status}`);
  const libraryMessage = message.slice("bad.obj: ".length);
  check(cli.stderr.includes(`bad.obj: ${libraryMessage}`), `the CLI says '${cli.stderr.trim()}'`);
  check((await page.locator("#stats").textContent()) === "", "stats shown for a failed run");
});

await test("a long run reports progress and the page keeps drawing", async () => {
  await page.goto(`${server.url}/index.html`);
  await page.selectOption("#example", "menger");
  await page.waitForFunction(() => !document.getElementById("run").disabled, null, { timeout: 60_000 });
  // Watch the main thread while the worker computes: the longest gap between animation
  // frames, and every stage the progress line names. The stages are recorded on each change
  // of the line, not sampled once a frame: a stage that lasts less than a frame (the
  // intersections of a level-2 sponge take a few milliseconds) is still seen.
  await page.evaluate(() => {
    window.watch = { longest: 0, stages: new Set() };
    const line = document.getElementById("stage");
    new MutationObserver(() => {
      if (line.textContent) window.watch.stages.add(line.textContent.split(" ")[0]);
    }).observe(line, { childList: true, characterData: true, subtree: true });
    let last = performance.now();
    const frame = (now) => {
      window.watch.longest = Math.max(window.watch.longest, now - last);
      last = now;
      if (!document.getElementById("stats").textContent) requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
  });
  await page.click("#run");
  await page.waitForFunction(() => document.getElementById("stats").textContent, null, { timeout: 180_000 });
  const watch = await page.evaluate(() => ({ longest: window.watch.longest, stages: [...window.watch.stages] }));
  const stats = JSON.parse(await page.locator("#stats").textContent());
  await page.screenshot({ path: join(args.screenshots, "menger.png") });
  console.log(`     ${JSON.stringify(stats)}; longest frame gap ${watch.longest.toFixed(0)} ms; stages seen: ${watch.stages.join(", ")}`);
  check(stats.valid_solid, "the sponge is not a valid solid");
  // A level-2 Menger sponge of side 9: 20 · 20 unit cubes of the 729.
  check(Math.abs(stats.volume - 400) < 1e-9, `volume ${stats.volume}, expected 400`);
  check(watch.stages.includes("intersect") && watch.stages.includes("classify"), `progress showed ${watch.stages}`);
  check(watch.longest < 500, `the main thread stalled for ${watch.longest} ms`);
});

await test("no uncaught errors in the page", async () => {
  check(consoleErrors.length === 0, consoleErrors.join("\n"));
});

await browser.close();
await server.close();
console.log(`screenshots in ${args.screenshots}`);
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
