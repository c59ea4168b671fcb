// The built-in examples, shared by the page's worker and by examples.mjs (which writes the
// file-based ones into dist/examples at build time, through the same wasm module).
//
// Every example is a list of operands and an operation. The operands of "union" are files,
// so the browser test can run the command-line tool on the very same bytes.

/** Colours (r, g, b, a bytes) of the built-in operands. */
export const COLOURS = {
  red: [214, 69, 65, 255],
  blue: [52, 120, 200, 255],
  gold: [232, 178, 48, 255],
  green: [74, 160, 90, 255],
  slate: [150, 160, 175, 255],
};

/** The examples the page offers: a label, the operation, and where the operands come from. */
export const EXAMPLES = {
  union: { label: "Union: red cube ∪ blue sphere (GLB + 3MF files)", op: "union", files: ["cube.glb", "sphere.3mf"] },
  solids: { label: "The demo's solids: cube − bowl − moat − hole", op: "difference" },
  vox: { label: "A .vox castle minus a sphere (orthogonal engine, then exact)", op: "difference", files: ["castle.vox"] },
  menger: { label: "Menger sponge: a cube minus 30 bars (n-ary difference)", op: "difference" },
  bad: { label: "A malformed OBJ file (shows csgkit's error)", op: "union", files: ["bad.obj", "cube.glb"] },
};

/** The two operands of the union example, made with the library's primitives. */
export function unionOperands(csgkit) {
  const cube = csgkit.cube([-1, -1, -1], [1, 1, 1]).withMaterial("red", COLOURS.red);
  const sphere = csgkit.sphere([0.9, 0.9, 0.9], 0.8, 4).withMaterial("blue", COLOURS.blue);
  return { cube, sphere };
}

/** The command line's demo solids: a cube minus a bowl, a moat and a hole (`csgkit demo`). */
export function demoSolids(csgkit) {
  return [
    csgkit.cube([-1, -1, -1], [1, 1, 1]).withMaterial("slate", COLOURS.slate),
    csgkit.sphere([0, 0, 1], 0.6, 3).withMaterial("gold", COLOURS.gold),
    csgkit.torus([0, 0, 1], 0.7, 0.25, 48, 16).withMaterial("red", COLOURS.red),
    csgkit.cylinder([0, 0, -1.5], 0.3, 3, 32).withMaterial("blue", COLOURS.blue),
  ];
}

/** A level-2 Menger sponge as one n-ary difference: the cube [0, 9]³ minus the bars through
 * its holes (3 axes × (1 + 9) bars), each running one unit past the cube. */
export function mengerOperands(csgkit) {
  const size = 9;
  const operands = [csgkit.cube([0, 0, 0], [size, size, size]).withMaterial("gold", COLOURS.gold)];
  for (let level = 1; level <= 2; level++) {
    const cell = size / 3 ** level;
    const count = 3 ** (level - 1);
    for (let axis = 0; axis < 3; axis++) {
      const [u, v] = [0, 1, 2].filter((a) => a !== axis);
      for (let p = 0; p < count; p++) {
        for (let q = 0; q < count; q++) {
          const min = [0, 0, 0];
          const max = [0, 0, 0];
          min[axis] = -1;
          max[axis] = size + 1;
          [min[u], max[u]] = [(3 * p + 1) * cell, (3 * p + 2) * cell];
          [min[v], max[v]] = [(3 * q + 1) * cell, (3 * q + 2) * cell];
          operands.push(csgkit.cube(min, max).withMaterial("blue", COLOURS.blue));
        }
      }
    }
  }
  return operands;
}

/** The sphere bitten out of the castle. */
export function castleBite(csgkit) {
  return csgkit.sphere([16, 3, 14], 6, 3).withMaterial("green", COLOURS.green);
}

/** A small castle as MagicaVoxel voxels: walls with battlements, four towers with roofs, a
 * gate, on a lawn; `[x, y, z, paletteIndex]` rows in a 24 × 24 × 20 model. */
export function castleVoxels() {
  const [GRASS, STONE, DARK, ROOF, WOOD] = [1, 2, 3, 4, 5];
  const voxels = new Map();
  const put = (x, y, z, c) => voxels.set(`${x},${y},${z}`, [x, y, z, c]);
  const n = 24;
  for (let x = 0; x < n; x++) for (let y = 0; y < n; y++) put(x, y, 0, GRASS);
  const towers = [[3, 3], [3, 20], [20, 3], [20, 20]];
  // Walls between the towers, two voxels thick, with battlements on top.
  for (let i = 3; i <= 20; i++) {
    for (const [x, y] of [[i, 3], [i, 20], [3, i], [20, i]]) {
      for (let z = 1; z <= 8; z++) put(x, y, z, STONE);
      if (i % 2 === 0) put(x, y, 9, DARK);
    }
  }
  // The gate in the south wall.
  for (let x = 10; x <= 13; x++) for (let z = 1; z <= 5; z++) voxels.delete(`${x},3,${z}`);
  for (let x = 10; x <= 13; x++) put(x, 4, 1, WOOD);
  // Round towers (radius 2.5) with cone roofs.
  for (const [cx, cy] of towers) {
    for (let x = cx - 3; x <= cx + 3; x++) {
      for (let y = cy - 3; y <= cy + 3; y++) {
        const r = Math.hypot(x - cx, y - cy);
        if (r <= 2.6) for (let z = 1; z <= 12; z++) put(x, y, z, STONE);
        for (let z = 13; z <= 18; z++) if (r <= 3.2 - 0.55 * (z - 13)) put(x, y, z, ROOF);
      }
    }
  }
  const palette = [
    [96, 168, 72], // grass
    [170, 170, 165], // stone
    [120, 120, 118], // battlements
    [190, 60, 50], // roofs
    [120, 80, 40], // gate
  ];
  return { size: [n, n, 20], voxels: [...voxels.values()], palette };
}

/** A MagicaVoxel file (version 150) of one model: `SIZE`, `XYZI` and an `RGBA` palette. */
export function voxFile({ size, voxels, palette }) {
  const chunk = (id, content) => {
    const head = new DataView(new ArrayBuffer(12));
    [...id].forEach((c, i) => head.setUint8(i, c.charCodeAt(0)));
    head.setUint32(4, content.length, true);
    return [new Uint8Array(head.buffer), content];
  };
  const sizeBytes = new Uint8Array(new Uint32Array(size).buffer);
  const xyzi = new Uint8Array(4 + 4 * voxels.length);
  new DataView(xyzi.buffer).setUint32(0, voxels.length, true);
  voxels.forEach((v, i) => xyzi.set(v, 4 + 4 * i));
  const rgba = new Uint8Array(256 * 4);
  palette.forEach((c, i) => rgba.set([...c, 255], 4 * i)); // entry i is colour index i + 1
  const children = [...chunk("SIZE", sizeBytes), ...chunk("XYZI", xyzi), ...chunk("RGBA", rgba)];
  const childBytes = children.reduce((sum, part) => sum + part.length, 0);
  const main = new DataView(new ArrayBuffer(20));
  [..."VOX "].forEach((c, i) => main.setUint8(i, c.charCodeAt(0)));
  main.setUint32(4, 150, true);
  [..."MAIN"].forEach((c, i) => main.setUint8(8 + i, c.charCodeAt(0)));
  main.setUint32(12, 0, true);
  main.setUint32(16, childBytes, true);
  const parts = [new Uint8Array(main.buffer), ...children];
  const out = new Uint8Array(parts.reduce((sum, part) => sum + part.length, 0));
  let at = 0;
  for (const part of parts) {
    out.set(part, at);
    at += part.length;
  }
  return out;
}

/** A malformed OBJ file: its face names a vertex the file does not have. */
export const BAD_OBJ = "# a triangle whose third corner does not exist\nv 0 0 0\nv 1 0 0\nf 1 2 3\n";
