"""Every error path: a Python exception of the right class whose message names the problem
and where it is; nothing crashes, nothing is written half."""

import numpy as np
import pytest

import csgkit
from conftest import cube


def test_the_exception_classes():
    assert issubclass(csgkit.InputError, csgkit.CsgkitError)
    assert issubclass(csgkit.InputError, ValueError)
    for cls in (csgkit.ReadError, csgkit.WriteError, csgkit.CancelledError):
        assert issubclass(cls, csgkit.CsgkitError)


@pytest.mark.parametrize(
    "vertices, message",
    [
        (np.zeros((8, 2)), r"vertices must be an array of shape \(n, 3\), not \[8, 2\]"),
        (np.zeros(24), r"vertices must be an array of shape \(n, 3\), not \[24\]"),
        (np.zeros((2, 4, 3)), r"not \[2, 4, 3\]"),
        ("abc", "vertices: "),
    ],
)
def test_vertices_of_the_wrong_shape(vertices, message):
    with pytest.raises(csgkit.InputError, match=message):
        csgkit.Mesh(vertices, cube()[1])


@pytest.mark.parametrize("value, shown", [(np.nan, "NaN"), (np.inf, "inf"), (-np.inf, "-inf")])
def test_non_finite_coordinates_name_the_vertex(value, shown):
    v, f = cube()
    v[5, 1] = value
    with pytest.raises(csgkit.InputError, match=f"vertex 5 has a non-finite coordinate {shown}$"):
        csgkit.Mesh(v, f)
    with pytest.raises(csgkit.InputError, match="operand 1: vertex 5 has a non-finite"):
        csgkit.union(cube(), (v, f))


@pytest.mark.parametrize("index", [8, 1000, -1, 2**40])
def test_out_of_range_indices_name_the_face(index):
    v, f = cube()
    f = f.copy()
    f[7, 2] = index
    with pytest.raises(csgkit.InputError, match=f"face 7 refers to vertex {index}, but there are 8 vertices"):
        csgkit.Mesh(v, f)
    polygons = f.tolist()
    with pytest.raises(csgkit.InputError, match=f"face 7 refers to vertex {index}"):
        csgkit.Mesh(v, [polygons[0] + [0]] + polygons[1:])


def test_faces_with_fewer_than_three_corners():
    v, f = cube()
    with pytest.raises(csgkit.InputError, match=r"at least 3 corners each, not an array of shape \(12, 2\)"):
        csgkit.Mesh(v, f[:, :2])
    with pytest.raises(csgkit.InputError, match="face 1 has 2 corners; a face needs at least 3"):
        csgkit.Mesh(v, [[0, 2, 1, 3], [0, 1]])
    with pytest.raises(csgkit.InputError, match="face 0 is not a sequence of vertex indices"):
        csgkit.Mesh(v, [[0.5, 1, 2], [0, 1, 2, 3]])


def test_something_that_is_no_mesh():
    with pytest.raises(csgkit.InputError, match="operand 1: a mesh is a csgkit.Mesh, .* not int"):
        csgkit.union(cube(), 3)
    with pytest.raises(TypeError):
        csgkit.union(cube(), cube(), faces_mode="polygons")

    class Broken:
        faces = cube()[1]

        @property
        def vertices(self):
            raise RuntimeError("no vertices today")

    # An exception that is not about the input passes through as it is.
    with pytest.raises(RuntimeError, match="^no vertices today$"):
        csgkit.union(cube(), Broken())


def test_an_open_mesh_is_refused_naming_the_operand():
    v, f = cube()
    with pytest.raises(csgkit.InputError, match="operand 1 is not closed and consistently oriented: 3 edges"):
        csgkit.union(cube(), (v, f[:-1]))
    with pytest.raises(csgkit.InputError, match=r"operand 0 is oriented inward \(its volume -1 is negative\)"):
        csgkit.union((v, f[:, ::-1]), cube())
    with pytest.raises(csgkit.InputError, match="operand 0: mesh is not closed"):
        csgkit.voxelize((v, np.delete(f, 2, axis=0)), 0.25)  # a top triangle


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: csgkit.boolean("merge", [cube(), cube()]), "unknown operation 'merge': expected 'union', "),
        (lambda: csgkit.union(cube(), winding="odd"), "unknown winding rule 'odd'"),
        (lambda: csgkit.union(cube(), faces="hexagons"), "unknown face mode 'hexagons'"),
        (lambda: csgkit.union(cube(), simplify=-1.0), "simplify must be a positive length, not -1"),
        (lambda: csgkit.union(cube(), precision="f16"), "unknown precision 'f16': expected 'f64' or 'f32'"),
        (lambda: csgkit.voxelize(cube(), 0.3, surface="dots"), "unknown surface 'dots'"),
        (lambda: csgkit.voxelize(cube(), -1.0), "cell size -1 is not a positive finite number"),
        (lambda: csgkit.boxes(np.zeros((3, 5))), r"boxes must be an array of shape \(n, 6\), not \[3, 5\]"),
        (lambda: csgkit.boxes([[0, 0, 0, 1, 1, 1], [0, 0, 0, 1, np.nan, 1]]), "box 1 has a non-finite coordinate"),
    ],
)
def test_unknown_names_and_bad_values(call, message):
    with pytest.raises(csgkit.InputError, match=message):
        call()


def test_wrong_option_types_are_type_errors():
    with pytest.raises(TypeError, match="self_check"):
        csgkit.union(cube(), cube(), self_check="yes")
    with pytest.raises(TypeError, match="winding"):
        csgkit.union(cube(), cube(), winding=1)


def test_bad_files_name_the_file_and_the_place(tmp_path):
    missing = tmp_path / "missing.obj"
    with pytest.raises(csgkit.ReadError, match=f"cannot read {missing}"):
        csgkit.load(missing)
    truncated = tmp_path / "cut.stl"
    csgkit.save(cube(), truncated)
    truncated.write_bytes(truncated.read_bytes()[:84 + 50 * 12 - 7])
    with pytest.raises(csgkit.ReadError, match=f"{truncated}: .*"):
        csgkit.load(truncated)
    bad_index = tmp_path / "bad.obj"
    bad_index.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
    with pytest.raises(csgkit.ReadError, match="line 4: face 0 refers to vertex 4, but 3 are defined"):
        csgkit.load(bad_index)
    garbage = tmp_path / "noise.bin"
    garbage.write_bytes(b"\x00\x01\x02garbage")
    with pytest.raises(csgkit.ReadError, match="unknown format"):
        csgkit.load(garbage)
    vox = tmp_path / "cut.vox"
    vox.write_bytes(b"VOX \x96\x00\x00\x00MAIN\x00\x00")
    with pytest.raises(csgkit.ReadError, match=f"{vox}: malformed .vox data at byte"):
        csgkit.boxes(vox)
    with pytest.raises(csgkit.ReadError, match="check.stl"):
        csgkit.check(tmp_path / "check.stl")


def test_bad_destinations_leave_nothing_behind(tmp_path):
    with pytest.raises(csgkit.WriteError, match="unknown extension"):
        csgkit.save(cube(), tmp_path / "box.xyz")
    with pytest.raises(csgkit.WriteError, match="cannot write"):
        csgkit.save(cube(), tmp_path / "no" / "such" / "folder.obj")
    assert list(tmp_path.iterdir()) == []


def test_a_progress_callback_cancels_or_raises():
    a, b = cube(), cube((0.5, 0.5, 0.5), (2, 2, 2))
    stages = []

    def stop_at_intersect(stage, done, total):
        stages.append(stage)
        return stage != "intersect"

    with pytest.raises(csgkit.CancelledError, match="cancelled"):
        csgkit.union(a, b, progress=stop_at_intersect)
    assert stages[-1] == "intersect" and "ingest" in stages

    def fail(stage, done, total):
        raise KeyError(stage)

    with pytest.raises(KeyError, match="ingest"):
        csgkit.union(a, b, progress=fail)
    with pytest.raises(csgkit.CancelledError):
        csgkit.boxes([[0, 0, 0, 1, 1, 1]], progress=lambda *report: False)
    # Any answer but False goes on.
    assert csgkit.check(csgkit.union(a, b, progress=lambda *r: None))["valid_solid"]
