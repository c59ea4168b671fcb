// Writes the file-based examples into dist/examples with the wasm module just built, so the
// files are the library's own output: node examples.mjs DIST_DIR
import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { join, resolve } from "node:path";
import { pathToFileURL } from "node:url";

const dist = process.argv[2];
const csgkit = await import(pathToFileURL(resolve(dist, "pkg", "csgkit_wasm.js")).href);
csgkit.initSync({ module: readFileSync(join(dist, "pkg", "csgkit_wasm_bg.wasm")) });
const { unionOperands, castleVoxels, voxFile, BAD_OBJ } = await import("./src/examples.js");

const out = join(dist, "examples");
mkdirSync(out, { recursive: true });
const { cube, sphere } = unionOperands(csgkit);
writeFileSync(join(out, "cube.glb"), csgkit.save(cube, "cube.glb"));
writeFileSync(join(out, "sphere.3mf"), csgkit.save(sphere, "sphere.3mf"));
writeFileSync(join(out, "castle.vox"), voxFile(castleVoxels()));
writeFileSync(join(out, "bad.obj"), BAD_OBJ);
console.log(`examples written to ${out}`);
