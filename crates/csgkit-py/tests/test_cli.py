"""The Python package and the `csgkit` command line agree on the same files: the same
booleans (vertex for vertex), the same box unions and voxelizations, the same reports."""

import json
import math
import subprocess

import numpy as np
import pytest

import csgkit
from conftest import cube


def run(cli, *args):
    done = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    assert done.returncode in (0, 1), done.stderr
    return done.stdout


def same_mesh(a, b):
    np.testing.assert_array_equal(a.vertices, b.vertices)
    if isinstance(a.faces, list):
        assert [f.tolist() for f in a.faces] == [f.tolist() for f in b.faces]
    else:
        np.testing.assert_array_equal(a.faces, b.faces)


PAIRS = [
    ("ballA.off", "ballB.off", "union", []),
    ("ballA.off", "ballB.off", "intersection", ["--polygons"]),
    ("ballA.off", "ballB.off", "difference", ["--quads"]),
    ("ballA.off", "ballB.off", "xor", []),
    ("Cray_left.obj", "Cray_right.obj", "difference", []),
    ("self_intersectA.obj", "self_intersectB.obj", "union", ["--winding", "positive"]),
]
OPTIONS = {"--polygons": {"faces": "polygons"}, "--quads": {"faces": "quads"}}


@pytest.mark.parametrize("first, second, operation, flags", PAIRS)
def test_booleans_agree_with_the_command_line(cli, shared_data, tmp_path, first, second, operation, flags):
    a, b = (shared_data / "meshes" / name for name in (first, second))
    out = tmp_path / "cli.obj"
    stats = json.loads(run(cli, operation, a, b, "-o", out, "--stats", *flags))
    options = {}
    for flag in flags:
        options.update(OPTIONS.get(flag, {}))
    if "--winding" in flags:
        options["winding"] = flags[flags.index("--winding") + 1]
    result = csgkit.boolean(operation, [csgkit.load(a), csgkit.load(b)], **options)
    report = csgkit.check(result, self_intersections=False)
    assert report["faces"] == stats["output_faces"]
    assert report["vertices"] == stats["output_vertices"]
    assert report["volume"] == stats["volume"]
    assert report["valid_solid"] and stats["valid_solid"]
    # OBJ writes the shortest round-tripping digits, so the file is the result exactly.
    same_mesh(csgkit.load(out), result)


def comparable(report):
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in report.items()}


@pytest.mark.parametrize(
    "name",
    ["joint.obj", "shared.stl", "cgal_non_manifold_face_graph.off", "two-boxes-bad-self-union.ply",
     "stanford-bunny.obj", "cow.obj", "Cray_right.obj"],
)
def test_check_reports_what_csgkit_check_json_reports(cli, shared_data, name):
    path = shared_data / "meshes" / name
    from_cli = json.loads(run(cli, "check", path, "--json"))
    from_python = comparable(csgkit.check(path))
    from_python["bbox"] = json.loads(json.dumps(from_python["bbox"]))
    shared = set(from_cli) & set(from_python)
    assert set(from_python) - shared == set()
    assert set(from_cli) - shared == {"file", "format", "selfint_first_pairs"}
    assert {k: from_python[k] for k in shared} == {k: from_cli[k] for k in shared}


@pytest.mark.parametrize("model", ["chr_knight.vox", "snow.vox", "test_multiple_model_scene.vox"])
def test_box_unions_agree_with_csgkit_boxes(cli, shared_data, tmp_path, model):
    path = shared_data / "voxels" / model
    out = tmp_path / "cli.ply"
    run(cli, "boxes", path, "-o", out)
    same_mesh(csgkit.load(out), csgkit.boxes(path))
    run(cli, "boxes", path, "-o", out, "--triangles")
    same_mesh(csgkit.load(out), csgkit.boxes(path, triangles=True))


def test_box_text_files_and_arrays_agree_with_csgkit_boxes(cli, tmp_path):
    rng = np.random.default_rng(7)
    lo = rng.integers(0, 20, size=(200, 3))
    boxes = np.hstack([lo, lo + rng.integers(1, 6, size=(200, 3))]).astype(float)
    text = tmp_path / "boxes.txt"
    text.write_text("\n".join(" ".join(f"{x:g}" for x in row) for row in boxes) + "\n")
    out = tmp_path / "cli.off"
    run(cli, "boxes", text, "-o", out)
    same_mesh(csgkit.load(out), csgkit.boxes(boxes))
    same_mesh(csgkit.boxes(text), csgkit.boxes(boxes))


def test_voxelize_agrees_with_csgkit_discrete_voxelize(cli, shared_data, tmp_path):
    path = shared_data / "meshes" / "spot.obj"
    out = tmp_path / "cli.ply"
    run(cli, "discrete", "voxelize", path, "-o", out, "--cell", "0.0625")
    same_mesh(csgkit.load(out), csgkit.voxelize(csgkit.load(path), 0.0625))


def test_generated_cubes_agree_vertex_for_vertex(cli, tmp_path):
    a, b = tmp_path / "a.ply", tmp_path / "b.ply"
    csgkit.save(cube(), a)
    csgkit.save(cube((0.5, 0.25, -0.5), (1.5, 0.75, 0.5)), b)
    for operation in ("union", "intersection", "difference", "xor"):
        out = tmp_path / f"{operation}.ply"
        run(cli, operation, a, b, "-o", out, "--polygons")
        same_mesh(csgkit.load(out), csgkit.boolean(operation, [csgkit.load(a), csgkit.load(b)], faces="polygons"))
