#!/usr/bin/env python3
"""Exact self-intersection check of triangle meshes with libigl (CGAL kernel inside).

For each input file (OBJ, OFF, STL, PLY) this loads the mesh, merges vertices with
bit-identical coordinates (so a triangle soup or an STL file has shared vertices), and runs

    igl.copyleft.cgal.remesh_self_intersections(V, F, detect_only=True)

which returns (VV, FF, IF, J, IM); IF lists the pairs of faces that intersect other than
through a shared vertex or edge.  It prints one JSON line per file:

    {"file": "...", "faces": 17160, "self_intersecting_pairs": 12}

and exits with code 1 if any file has at least one pair (2 on a load error).  Faces are
fan-triangulated polygons ("faces" counts triangles after triangulation); faces that
repeat a vertex index after the merge (degenerate by index) are dropped first and counted
in "dropped_faces" when there are any.

It needs numpy and libigl (and trimesh for STL/PLY/OFF); the peers harness venv has all
three.  Usage, from a csgkit checkout whose sibling is ../shared/peers (after setup.sh;
with a private copy of the harness use that copy's .venv/bin/python):

    ../shared/peers/.venv/bin/python scripts/igl_selfcheck.py A.obj B.off C.stl ...
    ../shared/peers/.venv/bin/python scripts/igl_selfcheck.py --first-only big.obj

Option --first-only stops at the first intersecting pair (a faster yes/no; the count is
then 0 or 1).

OBJ files are read by the small parser below (full double precision, `v` and `f` lines,
`f a/b/c` and negative indices accepted, polygons fan-triangulated); other formats go
through trimesh with process=False.
"""

import argparse
import json
import os
import sys

import numpy as np


def read_obj(path):
    verts, faces = [], []
    with open(path, "r", errors="replace") as fh:
        for line in fh:
            if line.startswith("v "):
                parts = line.split()
                verts.append((float(parts[1]), float(parts[2]), float(parts[3])))
            elif line.startswith("f "):
                idx = []
                for tok in line.split()[1:]:
                    i = int(tok.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    V = np.array(verts, dtype=np.float64).reshape(-1, 3)
    F = np.array(faces, dtype=np.int64).reshape(-1, 3)
    return V, F


def read_mesh(path):
    if path.lower().endswith(".obj"):
        return read_obj(path)
    import trimesh

    m = trimesh.load(path, process=False, force="mesh")
    return np.asarray(m.vertices, dtype=np.float64), np.asarray(m.faces, dtype=np.int64)


def merge_identical(V, F):
    """Merge vertices with bit-identical coordinates (-0.0 and 0.0 count as equal)."""
    if len(V) == 0:
        return V, F
    key = np.ascontiguousarray(V + 0.0)  # + 0.0 turns -0.0 into 0.0
    _, first, inverse = np.unique(key.view(np.dtype((np.void, 24))).ravel(),
                                  return_index=True, return_inverse=True)
    return V[first], inverse.reshape(-1)[F]


def check(path, first_only=False):
    import igl.copyleft.cgal

    V, F = read_mesh(path)
    V, F = merge_identical(V, F)
    degenerate = (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 0] == F[:, 2])
    F = np.ascontiguousarray(F[~degenerate])
    rec = {"file": path, "faces": int(len(F))}
    if degenerate.any():
        rec["dropped_faces"] = int(degenerate.sum())
    if len(F) == 0:
        rec["self_intersecting_pairs"] = 0
        return rec
    res = igl.copyleft.cgal.remesh_self_intersections(V, F, detect_only=True,
                                                      first_only=first_only)
    IF = np.asarray(res[2]).reshape(-1, 2)
    rec["self_intersecting_pairs"] = int(len(IF))
    return rec


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--first-only", action="store_true", help="stop at the first pair")
    args = ap.parse_args(argv)
    worst = 0
    for path in args.files:
        try:
            rec = check(path, args.first_only)
        except Exception as exc:  # report and go on with the other files
            print(json.dumps({"file": path, "error": f"{type(exc).__name__}: {exc}"}), flush=True)
            worst = max(worst, 2)
            continue
        print(json.dumps(rec), flush=True)
        if rec["self_intersecting_pairs"] > 0:
            worst = max(worst, 1)
    return worst


if __name__ == "__main__":
    sys.exit(main())
