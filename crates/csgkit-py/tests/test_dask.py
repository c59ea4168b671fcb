"""examples/batch_dask.py on a LocalCluster of 2 workers over the shared meshes: every pair's
result is written and right, a pair that fails is reported and does not stop the batch."""

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import pytest

import csgkit

pytest.importorskip("dask.distributed")

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "batch_dask.py"


def example_module():
    spec = importlib.util.spec_from_file_location("batch_dask", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_pairs_are_found_by_name(shared_data):
    pairs = example_module().find_pairs(shared_data / "meshes", "union")
    names = {(Path(a).name, Path(b).name) for _, a, b in pairs}
    assert ("ballA.off", "ballB.off") in names
    assert ("Cray_left.obj", "Cray_right.obj") in names
    assert ("self_intersectA.obj", "self_intersectB.obj") in names
    assert all(op == "union" for op, _, _ in pairs)


def test_a_batch_on_a_local_cluster(shared_data, manifest, tmp_path):
    # The boolean pairs of the manifest small enough for a test, with the operation their
    # source library tests (Cray: A minus B), and a pair whose first mesh is open.
    small = [name for name, e in manifest.items()
             if e["category"] == "boolean-pair" and e["measured"]["raw_faces"] < 5000]
    assert {"ballA.off", "ballB.off", "Cray_left.obj", "Cray_right.obj"} <= set(small)
    listing = tmp_path / "pairs.txt"
    listing.write_text(
        "# operation first second\n"
        "union ballA.off ballB.off\n"
        "intersection ballA.off ballB.off\n"
        "difference Cray_left.obj Cray_right.obj\n"
        "union stanford-bunny.obj ballA.off   # open: fails\n"
        "union missing.obj ballA.off          # absent: fails\n"
    )
    out = tmp_path / "out"
    done = subprocess.run(
        [sys.executable, str(EXAMPLE), str(shared_data / "meshes"), "-o", str(out),
         "--pairs", str(listing), "--workers", "2"],
        capture_output=True, text=True, timeout=600,
    )
    assert done.returncode == 1, done.stderr  # some pairs failed, the batch went on
    assert "3 of 5 pairs done, 2 failed" in done.stdout
    records = json.loads((out / "report.json").read_text())
    assert [r["status"] for r in records] == ["ok", "ok", "ok", "error", "error"]
    assert "operand 0 is not closed" in records[3]["error"]
    assert "ReadError" in records[4]["error"] and "missing.obj" in records[4]["error"]
    meshes = shared_data / "meshes"
    for record in records[:3]:
        written = csgkit.load(record["output"])
        expected = csgkit.boolean(record["operation"],
                                  [csgkit.load(record["first"]), csgkit.load(record["second"])])
        assert written.face_count == record["faces"] == expected.face_count
        assert csgkit.check(written, self_intersections=False)["volume"] == record["volume"]
        assert Path(record["first"]).parent == meshes
    assert sorted(p.name for p in out.iterdir()) == [
        "Cray_left__difference__Cray_right.ply", "ballA__intersection__ballB.ply",
        "ballA__union__ballB.ply", "report.json",
    ]
