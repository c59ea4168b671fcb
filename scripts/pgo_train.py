#!/usr/bin/env python3
"""The training workload of the profile-guided build (scripts/pgo-build.sh).

Runs an instrumented csgkit over booleans of the kinds users run, so that the profile it
writes tells the compiler which paths are hot: two boxes touching (on a face, an edge, a
vertex, overlapping, equal) and turned by tiny and large angles, OpenSCAD spheres of 12 to
500 segments offset from each other, models of ../shared/data/meshes (when that folder is
present) against a cylinder through their centre and against a turned copy, a cube drilled
by 81 cylinders, a level-2 Menger sponge built from cubes, the plain CLI on the resulting
files, and repair. It deliberately uses none of the peers harness's cases (boxes of other
sizes, other angles, sphere sizes and models), so the profile does not fit the benchmark it
is measured on.

Usage: pgo_train.py CSGKIT [--data DIR] [--work DIR]
Exits non-zero if any run fails: a profile of errors would optimise the wrong paths.
"""
import argparse
import contextlib
import json
import math
import pathlib
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
# Models of the shared data set that the peers harness does not use.
MODELS = ("cow.obj", "fandisk.obj", "joint.obj", "spot.obj")
OPERATIONS = ("union", "intersection", "difference")


def transform(axis="z", angle=0.0, offset=(0.0, 0.0, 0.0)):
    """The scene transform of a turn by `angle` about `axis`, then a translation."""
    c, s = math.cos(angle), math.sin(angle)
    m = {"x": [[1, 0, 0], [0, c, -s], [0, s, c]],
         "y": [[c, 0, s], [0, 1, 0], [-s, 0, c]],
         "z": [[c, -s, 0], [s, c, 0], [0, 0, 1]]}[axis]
    return [m[i] + [offset[i]] for i in range(3)]


def sponge_level_2():
    """The cube [-1/2, 1/2]^3 minus the bars of a level-2 Menger sponge."""
    def cross(size, centre):
        return [{"cube": {"size": dims, "center": True}, "transform": transform(offset=centre)}
                for dims in ([3 * size, size, size], [size, 3 * size, size],
                             [size, size, 3 * size])]
    holes = cross(1 / 3, (0, 0, 0))
    for i in (-1, 0, 1):
        for j in (-1, 0, 1):
            for k in (-1, 0, 1):
                if abs(i) + abs(j) + abs(k) >= 2:
                    holes += cross(1 / 9, (i / 3, j / 3, k / 3))
    return {"difference": [{"cube": {"size": 1, "center": True}}] + holes}


def centre(csgkit, path):
    """The centre of a mesh file's bounding box, as `csgkit info` prints the box (any format
    csgkit reads; a few digits are enough to aim a cylinder)."""
    info = subprocess.run([csgkit, "info", path], capture_output=True, text=True, check=True)
    box = next(line for line in info.stdout.splitlines() if line.startswith("bbox:"))
    low, high = (json.loads(corner) for corner in box.split(":", 1)[1].split(".."))
    return [(a + b) / 2 for a, b in zip(low, high)]


def turned_about(point, axis, angle, shift):
    """A turn about `point` (not the origin), then a shift."""
    m = transform(axis, angle)
    return [m[i][:3] + [point[i] - sum(m[i][j] * point[j] for j in range(3)) + shift[i]]
            for i in range(3)]


def scenes(csgkit, data):
    box = {"cube": {"size": [1, 1.25, 0.75]}}
    other = {"cube": {"size": [0.8, 1.1, 0.9]}}
    for op in OPERATIONS:
        for i, (axis, angle) in enumerate([("z", 3e-7), ("x", 2e-6), ("y", 0.4), ("z", 1e-4)]):
            yield f"turned_{op}_{i}", {op: [box, dict(box, transform=transform(axis, angle))]}
        for i, offset in enumerate([(0.5, 0.2, 0.1), (1, 0, 0), (1, 1.25, 0), (1, 1.25, 0.75),
                                    (0.3, 0.2, 0), (0, 0, 0), (0.25, 0.25, -0.15)]):
            yield f"touching_{op}_{i}", {op: [box, dict(other, transform=transform(offset=offset))]}
        yield f"equal_{op}", {op: [box, box]}
        for segments in (12, 40, 90, 200, 500):
            sphere = {"sphere": {"r": 1, "segments": segments}}
            yield f"spheres_{op}_{segments}", {op: [
                sphere, dict(sphere, transform=transform("y", 0.3, (0.6, 0.2, 0.1)))]}
        for name in MODELS:
            path = data / name
            if not path.exists():
                continue
            model, middle = {"mesh": str(path)}, centre(csgkit, path)
            yield f"{path.stem}_cylinder_{op}", {op: [
                model, {"cylinder": {"r": 0.05, "h": 1000, "segments": 48, "center": True},
                        "transform": transform(offset=middle)}]}
            yield f"{path.stem}_turned_{op}", {op: [
                model, dict(model, transform=turned_about(middle, "x", 0.2, (0.01, 0.02, 0.0)))]}
    yield "sponge_2", sponge_level_2()
    yield "drilled", {"difference": [{"cube": {"size": 2, "center": True}}] + [
        {"cylinder": {"r": 0.1, "h": 3, "segments": 24, "center": True},
         "transform": transform(offset=(x / 5, y / 5, 0))}
        for x in range(-4, 5) for y in range(-4, 5)]}


def run(argv):
    result = subprocess.run(argv, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"pgo_train.py: {' '.join(map(str, argv))} failed: {result.stderr.strip()}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csgkit", help="the instrumented csgkit binary")
    parser.add_argument("--data", default=str(HERE.parent.parent / "shared" / "data" / "meshes"),
                        help="the shared meshes (models are skipped where it is absent)")
    parser.add_argument("--work", default=None, help="where scenes and outputs go (a temporary "
                                                     "folder by default)")
    args = parser.parse_args()
    data = pathlib.Path(args.data).resolve()
    if not data.is_dir():
        print(f"pgo_train.py: {data} is absent: training without the models", file=sys.stderr)
    given = contextlib.nullcontext(args.work) if args.work else tempfile.TemporaryDirectory()
    with given as folder:
        work = pathlib.Path(folder)
        work.mkdir(parents=True, exist_ok=True)
        count = 0
        for name, scene in scenes(args.csgkit, data):
            path = work / f"{name}.json"
            path.write_text(json.dumps(scene))
            run([args.csgkit, "csg", path, "-o", work / f"{name}.obj", "--stats"])
            count += 1
        # The command most users type: operands from files, results written back.
        for op in OPERATIONS:
            for a, b in (("spheres_union_40", "spheres_intersection_90"),
                         ("turned_union_1", "touching_union_4"), ("sponge_2", "turned_union_2")):
                run([args.csgkit, op, work / f"{a}.obj", work / f"{b}.obj",
                     "-o", work / f"cli_{op}.obj", "--stats"])
                count += 1
        for name in ("joined_tetrahedra.obj", "block.obj"):
            if (data / name).exists():
                run([args.csgkit, "repair", data / name, "-o", work / "repaired.obj"])
                count += 1
        print(f"pgo_train.py: {count} runs")


if __name__ == "__main__":
    main()
