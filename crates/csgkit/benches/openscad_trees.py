#!/usr/bin/env python3
"""CSG trees against OpenSCAD and manifold3d: the OpenSCAD examples, each evaluated four ways.

For every example under OpenSCAD's examples folder:
- OpenSCAD 2021 exports its tree (`openscad -o model.csg`) and renders that tree with CGAL
  (`openscad -o model.off model.csg`, wall time: what these users wait for);
- `csgkit csg model.csg --stats` evaluates it in one exact pass (its `op_seconds`, and wall time);
- the example `csg_trees` evaluates the same tree in one pass and as a chain of binary csgkit
  booleans, and writes the tree's leaves (the same tessellated, placed meshes csgkit uses) and its
  expression;
- manifold3d evaluates that expression on those leaves (`Manifold` from `Mesh64`, each node's
  children in one `batch_boolean`), timed from the leaf meshes to the evaluated result.

Volumes are compared with OpenSCAD's render. Ratios are OpenSCAD or manifold3d time over
csgkit's, so above 1 means csgkit is faster.

Usage (from the repository root, after `cargo build --release -p csgkit-cli --example csg_trees`):
    python3 crates/csgkit/benches/openscad_trees.py [--examples /usr/share/openscad/examples]
        [--manifold-python /path/to/venv/bin/python] [--out DIR]

manifold3d is imported in the interpreter `--manifold-python` names (the peers harness venv has
it); without it the manifold column is left out.
"""

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

MANIFOLD_EVALUATOR = r'''
import json, sys, time
import numpy as np
import manifold3d as m

def read_off(path):
    words = open(path).read().split()
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    at = 4
    verts = np.array(words[at:at + 3 * nv], dtype=np.float64).reshape(nv, 3)
    at += 3 * nv
    tris = []
    for _ in range(nf):
        k = int(words[at])
        face = [int(w) for w in words[at + 1:at + 1 + k]]
        at += 1 + k
        tris.extend([face[0], face[i], face[i + 1]] for i in range(1, k - 1))
    return verts, np.array(tris, dtype=np.uint64).reshape(-1, 3)

tree = json.load(open(sys.argv[1]))
folder = sys.argv[1].rsplit("/", 1)[0]
meshes = [read_off(f"{folder}/{name}") for name in tree["leaves"]]
ops = {"union": m.OpType.Add, "difference": m.OpType.Subtract, "intersection": m.OpType.Intersect}

start = time.perf_counter()
leaves = [m.Manifold(m.Mesh64(vert_properties=v, tri_verts=t)) for v, t in meshes]

def build(node):
    if "leaf" in node:
        return leaves[node["leaf"]]
    children = [build(c) for c in node["children"]]
    if not children:
        return m.Manifold()
    if len(children) == 1:
        return children[0]
    if node["op"] == "difference":
        rest = m.Manifold.batch_boolean(children[1:], m.OpType.Add) if len(children) > 2 else children[1]
        return m.Manifold.batch_boolean([children[0], rest], m.OpType.Subtract)
    if node["op"] == "xor":
        raise SystemExit("xor has no manifold3d batch operation")
    return m.Manifold.batch_boolean(children, ops[node["op"]])

result = build(tree["expression"])
mesh = result.to_mesh64()
seconds = time.perf_counter() - start
print(json.dumps({"seconds": seconds, "volume": result.volume(), "status": str(result.status()),
                  "triangles": len(mesh.tri_verts)}))
'''


def off_volume(path):
    words = open(path).read().split()
    nv, nf = int(words[1]), int(words[2])
    at = 4
    verts = [tuple(map(float, words[at + 3 * i:at + 3 * i + 3])) for i in range(nv)]
    at += 3 * nv
    volume = 0.0
    for _ in range(nf):
        k = int(words[at])
        face = [int(w) for w in words[at + 1:at + 1 + k]]
        at += 1 + k
        a = verts[face[0]]
        for i in range(1, k - 1):
            b, c = verts[face[i]], verts[face[i + 1]]
            volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                       + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
    return volume


def timed(cmd, timeout):
    start = time.perf_counter()
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, time.perf_counter() - start
    return done, time.perf_counter() - start


def geomean(values):
    values = [v for v in values if v and v > 0]
    return math.exp(sum(map(math.log, values)) / len(values)) if values else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--examples", default="/usr/share/openscad/examples")
    parser.add_argument("--csgkit", default="target/release/csgkit")
    parser.add_argument("--csg-trees", default="target/release/examples/csg_trees")
    parser.add_argument("--manifold-python", default=None)
    parser.add_argument("--out", default=None)
    parser.add_argument("--timeout", type=float, default=600)
    args = parser.parse_args()
    out = args.out or tempfile.mkdtemp(prefix="openscad-trees-")
    os.makedirs(out, exist_ok=True)
    evaluator = os.path.join(out, "manifold_tree.py")
    open(evaluator, "w").write(MANIFOLD_EVALUATOR)

    rows = []
    for group in sorted(os.listdir(args.examples)):
        folder = os.path.join(args.examples, group)
        if not os.path.isdir(folder):
            continue
        # The mesh parts the models import, beside their exports: an export names them as
        # the model does, relative to its directory.
        for part in os.listdir(folder):
            if part.endswith(".stl"):
                shutil.copy(os.path.join(folder, part), out)
        for name in sorted(f for f in os.listdir(folder) if f.endswith(".scad")):
            stem = name[:-5]
            scad = os.path.join(folder, name)
            csg = os.path.join(out, stem + ".csg")
            row = {"model": f"{group}/{name}"}
            rows.append(row)
            done, _ = timed(["openscad", "-o", csg, scad], args.timeout)
            if done is None or done.returncode != 0:
                row["note"] = "OpenSCAD cannot export it"
                continue
            mine, wall = timed([args.csgkit, "csg", csg, "-o", os.path.join(out, stem + ".csgkit.off"),
                                "--stats"], args.timeout)
            if mine is None or mine.returncode != 0:
                row["note"] = "csgkit: " + ("timeout" if mine is None else mine.stderr.strip().splitlines()[-1])
                continue
            stats = json.loads(mine.stdout.strip().splitlines()[-1])
            row.update(csgkit_op=stats["evaluate_seconds"], csgkit_wall=wall, volume=stats["volume"],
                       leaves=stats["leaves"], valid=stats["valid_solid"])
            ref = os.path.join(out, stem + ".openscad.off")
            theirs, scad_wall = timed(["openscad", "-o", ref, csg], args.timeout)
            if theirs is not None and theirs.returncode == 0:
                row["openscad_wall"] = scad_wall
                row["openscad_volume"] = off_volume(ref)
            expand = os.path.join(out, stem + ".tree")
            passes, _ = timed([args.csg_trees, csg, "--expand", expand], args.timeout)
            if passes is not None and passes.returncode == 0:
                row.update(json.loads(passes.stdout.strip().splitlines()[-1]))
                if args.manifold_python:
                    peer, _ = timed([args.manifold_python, evaluator, os.path.join(expand, "tree.json")],
                                    args.timeout)
                    if peer is not None and peer.returncode == 0:
                        result = json.loads(peer.stdout.strip().splitlines()[-1])
                        row["manifold"] = result["seconds"]
                        row["manifold_volume"] = result["volume"]
            print(json.dumps(row), file=sys.stderr)

    print("| model | leaves | csgkit op (s) | csgkit wall (s) | chain of binaries (s) | OpenSCAD render (s) "
          "| manifold3d (s) | OpenSCAD / csgkit wall | manifold3d / csgkit op | volume rel. diff. |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        if "csgkit_op" not in row:
            print(f"| {row['model']} | {row.get('note', '')} |||||||||")
            continue
        rel = (abs(row["volume"] - row["openscad_volume"]) / abs(row["openscad_volume"])
               if row.get("openscad_volume") else float("nan"))
        fmt = lambda key: f"{row[key]:.3f}" if key in row else "—"
        ratio = lambda a, b: f"{row[a] / row[b]:.1f}×" if a in row and row.get(b) else "—"
        print(f"| {row['model']} | {row['leaves']} | {fmt('csgkit_op')} | {fmt('csgkit_wall')} | "
              f"{fmt('chained')} | {fmt('openscad_wall')} | {fmt('manifold')} | "
              f"{ratio('openscad_wall', 'csgkit_wall')} | {ratio('manifold', 'csgkit_op')} | {rel:.1e} |")
    evaluated = [r for r in rows if "csgkit_op" in r]
    for label, a, b in [("OpenSCAD render / csgkit wall", "openscad_wall", "csgkit_wall"),
                        ("manifold3d / csgkit op", "manifold", "csgkit_op"),
                        ("chain of binaries / one pass", "chained", "one_pass")]:
        ratios = [r[a] / r[b] for r in evaluated if a in r and r.get(b)]
        if ratios:
            print(f"\n{label}: geometric mean {geomean(ratios):.2f}×, median {statistics.median(ratios):.2f}× "
                  f"over {len(ratios)} models")
    print(f"\n{len(evaluated)} of {len(rows)} examples evaluate; outputs in {out}")


if __name__ == "__main__":
    main()
