#!/usr/bin/env python3
"""3MF and GLB between csgkit and trimesh, both ways, and trimesh's read and write speed.

1. csgkit -> trimesh: exact booleans of meshes in ../shared/data written by the csgkit CLI as
   .3mf and .glb load in trimesh with the same face count and volume as csgkit measures
   (`csgkit check --json`); the volume agrees to 1e-12 for 3MF (f64 decimals) and to 1e-6 for
   GLB (f32 positions).
2. trimesh -> csgkit: meshes and a two-part scene exported by trimesh as .3mf and .glb load in
   csgkit with trimesh's face count and volume; the scene's parts are csgkit operands.
3. With --bench: trimesh writes and reads the 1.1 M-triangle bunny as 3MF and GLB (best of
   --repeat runs, file in memory for writing, on disk for reading), in MB/s of the file; the
   criterion bench `cargo bench -p csgkit --bench io -- formats` gives csgkit's figures.

Run with a Python that has trimesh, numpy, networkx and lxml (the peers venv):
    cargo build --release -p csgkit-cli
    /work/peers/.venv/bin/python scripts/trimesh_formats.py --csgkit target/release/csgkit [--bench]
Exits 1 if a check fails.
"""

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np
import trimesh

REPO = pathlib.Path(__file__).resolve().parent.parent


def shared_data():
    return pathlib.Path(os.environ.get("CSGKIT_SHARED_DATA", REPO.parent / "shared" / "data"))


def run(csgkit, *args):
    result = subprocess.run([csgkit, *map(str, args)], capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"csgkit {' '.join(map(str, args))}: {result.stderr.strip()}")
    return result


def csgkit_measures(csgkit, path):
    report = json.loads(run(csgkit, "check", "--json", path).stdout)
    return report["faces"], report["volume"]


def trimesh_measures(path):
    mesh = trimesh.load(str(path), force="mesh")
    return len(mesh.faces), float(mesh.volume)


def close(a, b, tolerance):
    return abs(a - b) <= tolerance * max(abs(a), abs(b), 1e-300)


def report(ok, what):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    return ok


def forward(csgkit, folder):
    """csgkit writes, trimesh reads."""
    meshes = shared_data() / "meshes"
    cases = [
        ("union", [meshes / "ballA.off", meshes / "ballB.off"]),
        ("difference", [meshes / "block.obj", meshes / "ballA.off"]),
        ("union", [meshes / "bunny_watertight.obj", meshes / "ballB.off"]),
    ]
    ok = True
    for op, inputs in cases:
        for extension, tolerance in [("3mf", 1e-12), ("glb", 1e-6)]:
            out = folder / f"{op}_{inputs[0].stem}_{inputs[1].stem}.{extension}"
            run(csgkit, op, *inputs, "-o", out)
            faces, volume = csgkit_measures(csgkit, out)
            t_faces, t_volume = trimesh_measures(out)
            ok &= report(
                faces == t_faces and close(volume, t_volume, tolerance),
                f"csgkit -> trimesh {out.name}: faces {faces} / {t_faces}, "
                f"volume {volume!r} / {t_volume!r}",
            )
    return ok


def backward(csgkit, folder):
    """trimesh writes, csgkit reads."""
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=1.5)
    sphere.apply_translation([0.25, 0.0, 0.0])
    box = trimesh.creation.box(extents=[2.0, 1.0, 3.0])
    bunny = trimesh.load(str(shared_data() / "meshes" / "bunny_watertight.obj"), force="mesh")
    ok = True
    for name, mesh in [("sphere", sphere), ("box", box), ("bunny", bunny)]:
        for extension, tolerance in [("3mf", 1e-9), ("glb", 1e-6)]:
            path = folder / f"trimesh_{name}.{extension}"
            mesh.export(str(path))
            faces, volume = csgkit_measures(csgkit, path)
            expected = float(mesh.volume)
            ok &= report(
                faces == len(mesh.faces) and close(volume, expected, tolerance),
                f"trimesh -> csgkit {path.name}: faces {len(mesh.faces)} / {faces}, "
                f"volume {expected!r} / {volume!r}",
            )
    # A scene of two parts: two operands for csgkit, whose union trimesh can measure too.
    scene = trimesh.Scene([sphere, box])
    for extension in ["3mf", "glb"]:
        path = folder / f"trimesh_scene.{extension}"
        scene.export(str(path))
        info = run(csgkit, "info", path).stdout
        out = folder / f"scene_union_{extension}.3mf"
        run(csgkit, "union", path, "-o", out)
        _, volume = csgkit_measures(csgkit, out)
        reference = None
        if _has_manifold():
            reference = float(sphere.volume + box.volume - sphere.intersection(box).volume)
        union_ok = reference is None or close(volume, reference, 1e-6)
        ok &= report(
            "parts:       2" in info and union_ok,
            f"trimesh scene -> csgkit {path.name}: 2 parts, union volume {volume!r}"
            + ("" if reference is None else f" / trimesh {reference!r}"),
        )
    return ok


def _has_manifold():
    try:
        import manifold3d  # noqa: F401
    except ImportError:
        return False
    return True


def best_of(repeat, function):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def bench(folder, repeat):
    """trimesh's write and read speed for the 1.1 M-triangle bunny as 3MF and GLB."""
    mesh = trimesh.load(str(shared_data() / "meshes" / "bunny_watertight_loop2.ply"), force="mesh")
    print(f"\ntrimesh {trimesh.__version__} on bunny_watertight_loop2.ply "
          f"({len(mesh.faces)} triangles), best of {repeat}:")
    print("| format | file size | write | write MB/s | read | read MB/s |")
    print("|---|---|---|---|---|---|")
    for extension in ["3mf", "glb"]:
        data = {}

        def write():
            data["bytes"] = mesh.export(file_type=extension)

        write_seconds = best_of(repeat, write)
        path = folder / f"bunny.{extension}"
        path.write_bytes(data["bytes"])
        size = len(data["bytes"])
        read_seconds = best_of(repeat, lambda: trimesh.load(str(path), force="mesh"))
        mb = size / 1e6
        print(f"| {extension} | {mb:.1f} MB | {write_seconds:.2f} s | {mb / write_seconds:.0f} "
              f"| {read_seconds:.2f} s | {mb / read_seconds:.0f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--csgkit", default=str(REPO / "target" / "release" / "csgkit"))
    parser.add_argument("--bench", action="store_true", help="also time trimesh on the bunny")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    if not (shared_data() / "meshes").is_dir():
        print(f"skipping: {shared_data()} is absent")
        return 0
    print(f"trimesh {trimesh.__version__}, numpy {np.__version__}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp)
        ok = forward(args.csgkit, folder)
        ok &= backward(args.csgkit, folder)
        if args.bench:
            bench(folder, args.repeat)
    print("all checks passed" if ok else "some checks FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
