#!/usr/bin/env python3
"""The "drill chain": a long chain of differences, each fed the previous result from a file.

Start from the cube [-1,1]^3 (12 triangles).  Step i (i = 0 .. STEPS-1) subtracts a closed
48-sided cylinder of radius 0.2 and length 3.5 (caps fanned from a centre vertex, 192
triangles), centred at a random point of [-0.6,0.6]^3 with a random axis direction, drawn
from numpy.random.default_rng(SEED + i) (SEED = 9): the cylinders are the same for every
engine and every run.  Each step's input is the previous step's output *as read back from
the OBJ file it was written to* (coordinates written with repr(), so exactly; polygons are
fan-triangulated on reading), which is how a pipeline of command-line calls sees it: the
result has to survive being rounded to doubles and stored.

After each step it records the triangle count, the signed volume, closedness (after merging
bit-identical vertices: every undirected edge used equally often in both directions) and
edge-manifoldness (every edge in exactly two triangles, once in each direction), and
libigl's exact count of self-intersecting face pairs
(igl.copyleft.cgal.remesh_self_intersections with detect_only=True, via igl_selfcheck.py
next to this file), plus the op time.  A step that fails (exception, non-zero exit) ends
that engine's chain; the step and the error text are recorded.  One table per engine is
printed, then the volumes side by side.

Engines:  manifold3d, trueform (in-process Python; `--peers manifold3d,trueform`, the
default) and csgkit (`--csgkit PATH`: each step runs
`PATH difference prev.obj cyl.obj -o next.obj --stats ARGS`, ARGS from `--csgkit-args`,
`--triangles` by default; op time = "op_seconds" of --stats).

Run it with the peers harness venv, which has numpy, manifold3d, trueform and libigl
(from a csgkit checkout whose sibling is ../shared/peers, after its setup.sh; with a private
copy of the harness use that copy's .venv/bin/python):

    ../shared/peers/.venv/bin/python scripts/chain_peers.py
    ../shared/peers/.venv/bin/python scripts/chain_peers.py --peers '' --csgkit target/release/csgkit
    ../shared/peers/.venv/bin/python scripts/chain_peers.py --steps 10 --out /tmp/chain --json chain.json

Files: OUT/<engine>/step_NN.obj (the result of step NN; step_-1 = the cube is in.obj) and
OUT/cyl_NN.obj (the cylinders); OUT defaults to ./chain_out.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from igl_selfcheck import merge_identical, read_obj  # noqa: E402


# --------------------------------------------------------------------------- geometry

def cube():
    V = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    # vertex index = 4*ix + 2*iy + iz; faces outward
    quads = [(0, 1, 3, 2), (4, 6, 7, 5),   # x = -1, x = +1
             (0, 4, 5, 1), (2, 3, 7, 6),   # y = -1, y = +1
             (0, 2, 6, 4), (1, 5, 7, 3)]   # z = -1, z = +1
    F = []
    for a, b, c, d in quads:
        F += [(a, b, c), (a, c, d)]
    return V, np.array(F, dtype=np.int64)


def cylinder(centre, axis, radius=0.2, length=3.5, sides=48):
    axis = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    t = 2.0 * math.pi * np.arange(sides) / sides
    ring = radius * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)
    bot = centre - 0.5 * length * axis
    top = centre + 0.5 * length * axis
    V = np.vstack([bot + ring, top + ring, bot, top])
    cb, ct = 2 * sides, 2 * sides + 1
    F = []
    for k in range(sides):
        k1 = (k + 1) % sides
        F += [(k, k1, sides + k1), (k, sides + k1, sides + k)]   # side, outward
        F.append((cb, k1, k))                                    # bottom cap, facing -axis
        F.append((ct, sides + k, sides + k1))                    # top cap, facing +axis
    return V, np.array(F, dtype=np.int64)


def step_cylinder(i, seed):
    rng = np.random.default_rng(seed + i)
    centre = rng.uniform(-0.6, 0.6, 3)
    axis = rng.normal(size=3)
    return cylinder(centre, axis)


def write_obj(path, V, F):
    tmp = path + ".tmp"
    with open(tmp, "w") as fh:
        fh.write("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V.tolist()))
        fh.write("".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F.tolist()))
    os.replace(tmp, path)


# --------------------------------------------------------------------------- measures

def measures(V, F):
    Vm, Fm = merge_identical(V, F)
    rec = {"tris": int(len(F))}
    if len(F) == 0:
        rec.update(volume=0.0, closed=True, manifold=True, boundary=0, nonmanifold=0)
        return rec, Vm, Fm
    a, b, c = Vm[Fm[:, 0]], Vm[Fm[:, 1]], Vm[Fm[:, 2]]
    rec["volume"] = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
    he = np.concatenate([Fm[:, [0, 1]], Fm[:, [1, 2]], Fm[:, [2, 0]]])   # directed half-edges
    lo, hi = he.min(axis=1), he.max(axis=1)
    fwd = (he[:, 0] < he[:, 1]).astype(np.int64)
    key = lo.astype(np.int64) * (len(Vm) + 1) + hi
    uk, inv = np.unique(key, return_inverse=True)
    n_fwd = np.bincount(inv, weights=fwd, minlength=len(uk))
    n_all = np.bincount(inv, minlength=len(uk))
    n_bwd = n_all - n_fwd
    imbalance = np.abs(n_fwd - n_bwd)
    rec["boundary"] = int(imbalance.sum())             # half-edges without a partner
    rec["nonmanifold"] = int((n_all > 2).sum())        # edges in more than two triangles
    rec["closed"] = bool(imbalance.sum() == 0)
    rec["manifold"] = bool(np.all((n_fwd == 1) & (n_bwd == 1)))
    return rec, Vm, Fm


def self_pairs(Vm, Fm):
    import igl.copyleft.cgal

    ok = (Fm[:, 0] != Fm[:, 1]) & (Fm[:, 1] != Fm[:, 2]) & (Fm[:, 0] != Fm[:, 2])
    F = np.ascontiguousarray(Fm[ok])
    if len(F) == 0:
        return 0
    res = igl.copyleft.cgal.remesh_self_intersections(np.ascontiguousarray(Vm), F,
                                                      detect_only=True)
    return int(np.asarray(res[2]).reshape(-1, 2).shape[0])


# --------------------------------------------------------------------------- engines

class Manifold3dEngine:
    name = "manifold3d"

    def __init__(self):
        import manifold3d
        self.m = manifold3d

    def difference(self, a_path, b_path, out_path):
        m = self.m
        mans = []
        for p in (a_path, b_path):
            V, F = read_obj(p)
            x = m.Manifold(m.Mesh64(vert_properties=np.ascontiguousarray(V, np.float64),
                                    tri_verts=np.ascontiguousarray(F, np.uint64)))
            if not str(x.status()).endswith("NoError"):
                raise RuntimeError(f"{os.path.basename(p)} rejected: {x.status()}")
            mans.append(x)
        t0 = time.perf_counter()
        r = mans[0] - mans[1]
        mesh = r.to_mesh64()
        dt = time.perf_counter() - t0
        if not str(r.status()).endswith("NoError"):
            raise RuntimeError(f"manifold status {r.status()}")
        V = np.asarray(mesh.vert_properties)[:, :3].astype(np.float64)
        F = np.asarray(mesh.tri_verts).astype(np.int64)
        write_obj(out_path, V, F)
        return dt


class TrueformEngine:
    name = "trueform"

    def __init__(self):
        import trueform
        self.tf = trueform

    def difference(self, a_path, b_path, out_path):
        tf = self.tf
        meshes = []
        for p in (a_path, b_path):
            V, F = read_obj(p)
            meshes.append(tf.Mesh(np.ascontiguousarray(F, np.int32),
                                  np.ascontiguousarray(V, np.float64)))
        t0 = time.perf_counter()
        (faces, points), *_ = tf.boolean_difference(meshes[0], meshes[1])
        dt = time.perf_counter() - t0
        write_obj(out_path, np.asarray(points, np.float64), np.asarray(faces, np.int64))
        return dt


class CsgkitEngine:
    name = "csgkit"

    def __init__(self, exe, extra):
        self.exe = exe
        self.extra = extra

    def difference(self, a_path, b_path, out_path):
        cmd = [self.exe, "difference", a_path, b_path, "-o", out_path, "--stats", *self.extra]
        t0 = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if p.returncode != 0:
            err = (p.stderr.strip() or p.stdout.strip()).splitlines()
            raise RuntimeError(f"exit {p.returncode}: " + " | ".join(err[-3:]))
        stats = None
        for line in p.stdout.splitlines():
            line = line.strip()
            if line.startswith("{"):
                try:
                    stats = json.loads(line)
                except ValueError:
                    pass
        if stats is None:
            try:
                stats = json.loads(p.stdout)
            except ValueError:
                stats = {}
        self.last_stats = stats
        return float(stats.get("op_seconds", wall))


# --------------------------------------------------------------------------- chain

def run_chain(engine, steps, seed, out, check_self):
    d = os.path.join(out, engine.name)
    os.makedirs(d, exist_ok=True)
    prev = os.path.join(d, "in.obj")
    write_obj(prev, *cube())
    rows, failure = [], None
    for i in range(steps):
        cyl = os.path.join(out, f"cyl_{i:02d}.obj")
        if not os.path.exists(cyl):
            write_obj(cyl, *step_cylinder(i, seed))
        nxt = os.path.join(d, f"step_{i:02d}.obj")
        try:
            dt = engine.difference(prev, cyl, nxt)
        except Exception as exc:
            failure = {"step": i, "error": f"{type(exc).__name__}: {exc}"}
            print(f"[{engine.name}] step {i}: FAILED {failure['error']}", file=sys.stderr, flush=True)
            break
        V, F = read_obj(nxt)
        rec, Vm, Fm = measures(V, F)
        rec["step"] = i
        rec["op_s"] = dt
        rec["self_pairs"] = self_pairs(Vm, Fm) if check_self else None
        extra = getattr(engine, "last_stats", None)
        if extra:
            rec["rounding_self_intersections"] = extra.get("rounding_self_intersections")
        rows.append(rec)
        print(f"[{engine.name}] step {i:2d}: tris={rec['tris']} vol={rec['volume']:.12g} "
              f"closed={rec['closed']} manifold={rec['manifold']} si_pairs={rec['self_pairs']} "
              f"op={dt * 1e3:.1f}ms", file=sys.stderr, flush=True)
        prev = nxt
    return {"engine": engine.name, "rows": rows, "failure": failure}


def print_table(res):
    print(f"\n### {res['engine']}\n")
    has_round = any(r.get("rounding_self_intersections") is not None for r in res["rows"])
    head = "| step | triangles | volume | closed | edge-manifold | libigl self-int. pairs | op time |"
    sep = "|---|---|---|---|---|---|---|"
    if has_round:
        head += " csgkit rounding_self_intersections |"
        sep += "---|"
    print(head)
    print(sep)
    for r in res["rows"]:
        closed = "yes" if r["closed"] else f"no ({r['boundary']} open half-edges)"
        man = "yes" if r["manifold"] else f"no ({r['nonmanifold']} edges in >2 tris)"
        line = (f"| {r['step']} | {r['tris']} | {r['volume']:.12g} | {closed} | {man} | "
                f"{r['self_pairs']} | {r['op_s'] * 1e3:.1f} ms |")
        if has_round:
            line += f" {r.get('rounding_self_intersections')} |"
        print(line)
    if res["failure"]:
        print(f"| {res['failure']['step']} | FAILED: {res['failure']['error']} |")
    else:
        print(f"\n{res['engine']}: all {len(res['rows'])} steps done")


def print_volumes(results):
    if len(results) < 2:
        return
    names = [r["engine"] for r in results]
    by = [{row["step"]: row for row in r["rows"]} for r in results]
    steps = sorted(set().union(*[b.keys() for b in by]))
    print("\n### volumes side by side (relative difference to the first engine)\n")
    print("| step | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    for s in steps:
        base = by[0].get(s, {}).get("volume")
        cells = []
        for k, b in enumerate(by):
            row = b.get(s)
            if row is None:
                cells.append("-")
            elif k == 0 or base is None:
                cells.append(f"{row['volume']:.12g}")
            else:
                rel = abs(row["volume"] - base) / abs(base) if base else float("nan")
                cells.append(f"{row['volume']:.12g} ({rel:.1e})")
        print(f"| {s} | " + " | ".join(cells) + " |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--peers", default="manifold3d,trueform",
                    help="comma-separated Python engines: manifold3d, trueform ('' for none)")
    ap.add_argument("--csgkit", metavar="PATH", help="also run this csgkit binary")
    ap.add_argument("--csgkit-args", default="--triangles",
                    help="more arguments of each csgkit step (default: --triangles, since this "
                         "script fan-triangulates polygons on reading; add --merge-coplanar)")
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--seed", type=int, default=9, help="step i uses default_rng(SEED + i)")
    ap.add_argument("--out", default="chain_out", help="directory for the OBJ files")
    ap.add_argument("--json", help="write all results to this JSON file")
    ap.add_argument("--no-selfcheck", action="store_true", help="skip the libigl check")
    args = ap.parse_args(argv)

    engines = []
    for name in [p.strip() for p in args.peers.split(",") if p.strip()]:
        cls = {"manifold3d": Manifold3dEngine, "trueform": TrueformEngine}.get(name)
        if cls is None:
            ap.error(f"unknown engine {name!r} (manifold3d, trueform; csgkit via --csgkit)")
        engines.append(cls())
    if args.csgkit:
        engines.append(CsgkitEngine(os.path.abspath(args.csgkit), args.csgkit_args.split()))
    if not engines:
        ap.error("no engine selected")

    os.makedirs(args.out, exist_ok=True)
    results = [run_chain(e, args.steps, args.seed, args.out, not args.no_selfcheck)
               for e in engines]
    for r in results:
        print_table(r)
    print_volumes(results)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"steps": args.steps, "seed": args.seed, "results": results}, fh, indent=1)
    return 1 if any(r["failure"] for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())
