"""The Python overhead of csgkit.union: the peers harness's sphere_sphere_union_100k case
(two geodesic spheres of 100,820 triangles, the second rotated and offset) through
``csgkit.union`` on NumPy arrays, against the same union through the command line (its
``--stats`` stage seconds, without file I/O) and through manifold3d from Python on the same
arrays.

    python crates/csgkit-py/benches/overhead.py --csgkit target/release/csgkit \
        [--peers ../shared/peers] [--repeat 5]

Needs csgkit (``pip install ./crates/csgkit-py``) and manifold3d in the running
interpreter, and the peers harness folder, whose ``cases.py`` generates the spheres. Every
figure is the median of ``--repeat`` runs; the table goes to stdout as Markdown.

The overhead of a csgkit call is its wall time minus the seconds of the engine's stages
inside it (``Mesh.stage_seconds``): the conversion of the arrays, the GIL's release and the
result's hand-over to NumPy. The CLI column is the same union's stage seconds in a fresh
process (``--stats``: ``validate_seconds + op_seconds``). For manifold3d the overhead is its
wall time minus the union alone on Manifolds built beforehand (``a + b`` and ``to_mesh64``).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from importlib.metadata import version
from pathlib import Path

import numpy as np

import csgkit

REPO = Path(__file__).resolve().parents[3]


def median_seconds(function, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def command_line(binary, a, b, repeat, self_check):
    """Median seconds of the CLI's validate stage and of the rest of the operation, and the
    face count, from ``--stats``."""
    out = Path(a).with_name("cli.obj")
    flags = [] if self_check else ["--no-self-check"]
    runs = []
    for _ in range(repeat):
        done = subprocess.run([str(binary), "union", str(a), str(b), "-o", str(out), "--stats", *flags],
                              capture_output=True, text=True, check=True)
        runs.append(json.loads(done.stdout))
    validate = statistics.median(r["validate_seconds"] for r in runs)
    op = statistics.median(r["op_seconds"] for r in runs)
    return validate, op, runs[0]["output_faces"]


def manifold(a, b, repeat):
    """Median seconds of manifold3d's union with the conversion from the arrays, and without."""
    import manifold3d as m

    def convert(vf):
        v, f = vf
        return m.Manifold(m.Mesh64(vert_properties=np.ascontiguousarray(v, np.float64),
                                   tri_verts=np.ascontiguousarray(f, np.uint64)))

    def whole():
        return (convert(a) + convert(b)).to_mesh64()

    whole_seconds, mesh = median_seconds(whole, repeat)
    ma, mb = convert(a), convert(b)
    op_seconds, _ = median_seconds(lambda: (ma + mb).to_mesh64(), repeat)
    return whole_seconds, op_seconds, len(np.asarray(mesh.tri_verts))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--csgkit", type=Path, default=REPO / "target" / "release" / "csgkit")
    parser.add_argument("--peers", type=Path, default=REPO.parent / "shared" / "peers")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    sys.path.insert(0, str(args.peers))
    import cases  # the peers harness's generator

    (va, fa), (vb, fb) = cases.sphere_pair(71)  # sphere_sphere_100k
    a, b = (va, fa), (vb, fb)
    folder = Path(tempfile.mkdtemp())
    csgkit.save(a, folder / "a.obj")
    csgkit.save(b, folder / "b.obj")

    convert_in, _ = median_seconds(lambda: (csgkit.Mesh(va, fa), csgkit.Mesh(vb, fb)), args.repeat)
    print(f"sphere_sphere_union_100k: {len(fa)} + {len(fb)} triangles, median of {args.repeat} runs\n")
    print("| call from Python | Python call (s) | engine inside the call (s) | overhead (s) "
          "| same union by the CLI (s) | output triangles |")
    print("|---|---|---|---|---|---|")
    for self_check in (True, False):
        runs = []
        for _ in range(args.repeat):
            start = time.perf_counter()
            result = csgkit.union(a, b, self_check=self_check)
            runs.append((time.perf_counter() - start, sum(result.stage_seconds.values())))
        call = statistics.median(t for t, _ in runs)
        engine = statistics.median(e for _, e in runs)
        overhead = statistics.median(t - e for t, e in runs)
        validate, op, faces = command_line(args.csgkit, folder / "a.obj", folder / "b.obj", args.repeat,
                                           self_check)
        assert result.face_count == faces, (result.face_count, faces)
        print(f"| csgkit.union, self_check={self_check} | {call:.3f} | {engine:.3f} | {overhead:+.3f} "
              f"| {validate + op:.3f} | {faces} |")
    whole, op, faces = manifold(a, b, args.repeat)
    print(f"| manifold3d {version('manifold3d')}: Mesh64 in, to_mesh64 out | {whole:.3f} | {op:.3f} "
          f"| {whole - op:+.3f} | | {faces} |")
    print(f"\ncsgkit.Mesh from the two arrays (part of the overhead): {convert_in * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
