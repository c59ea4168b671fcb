"""load and save: round trips through every format, and the shared meshes read as the
manifest measured them."""

import warnings

import numpy as np
import pytest

import csgkit
from conftest import cube, sphere

FORMATS = [("obj", False), ("off", False), ("ply", False), ("ply", True), ("stl", False), ("stl", True),
           ("3mf", False), ("glb", False), ("gltf", False)]
#: Formats that store float32 coordinates (glTF, binary STL) and those that hold triangles only.
FLOAT32 = {("stl", False), ("glb", False), ("gltf", False)}
TRIANGLES = {"stl", "3mf", "glb", "gltf"}


@pytest.mark.parametrize("extension, ascii", FORMATS)
def test_round_trips_keep_every_coordinate(tmp_path, extension, ascii):
    result = csgkit.union(sphere(subdivisions=2), sphere((0.3, 0.2, 0.1), 0.9, 2))
    path = tmp_path / f"result.{extension}"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        csgkit.save(result, path, ascii=ascii)
    back = csgkit.load(path)
    corners = result.vertices[result.faces]
    if (extension, ascii) in FLOAT32:
        # The exact result rounded to float32, and a warning that says so.
        assert [str(w.message) for w in caught] == [
            f"{path} stores float32: {np.count_nonzero(result.vertices != result.vertices.astype(np.float32))}"
            f" of {result.vertices.size} coordinates were rounded"
        ]
        corners = corners.astype(np.float32).astype(np.float64)
    else:
        assert caught == []
    if extension in ("stl", "glb", "gltf"):
        # STL and glTF store positions per facet or per primitive; reading welds equal ones.
        np.testing.assert_array_equal(back.vertices[back.faces], corners)
    else:
        np.testing.assert_array_equal(back.vertices, result.vertices)
        np.testing.assert_array_equal(back.faces, result.faces)
        assert csgkit.check(back)["volume"] == csgkit.check(result)["volume"]


@pytest.mark.parametrize("extension", ["stl", "glb"])
def test_a_result_in_float32_is_what_the_file_stores(tmp_path, extension):
    # Certified in float32, the result saves to a float32 format without rounding, so no
    # warning, and reads back as the same valid solid without self-intersections.
    result = csgkit.union(sphere(subdivisions=2), sphere((0.3, 0.2, 0.1), 0.9, 2), precision="f32")
    np.testing.assert_array_equal(result.vertices, result.vertices.astype(np.float32))
    path = tmp_path / f"result.{extension}"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        csgkit.save(result, path)
    report = csgkit.check(csgkit.load(path))
    assert report["valid_solid"] and report["selfint_pairs"] == 0 and report["degenerate_faces"] == 0
    assert report["volume"] == pytest.approx(csgkit.check(result)["volume"], rel=1e-12)


def test_polygons_round_trip_where_the_format_holds_them(tmp_path):
    result = csgkit.union(cube(), cube((0.5, 0.5, 0), (2, 2, 1)), faces="polygons")
    assert isinstance(result.faces, list)
    for extension in ("obj", "off", "ply"):
        path = tmp_path / f"polygons.{extension}"
        csgkit.save(result, path)
        back = csgkit.load(path)
        assert [f.tolist() for f in back.faces] == [f.tolist() for f in result.faces]
    for extension in TRIANGLES:
        path = tmp_path / f"triangulated.{extension}"
        csgkit.save(result, path, ascii=True)
        back = csgkit.load(path)
        assert back.faces.shape[1] == 3
        assert csgkit.check(back)["volume"] == csgkit.check(result)["volume"] == 3.0


def test_ply_keeps_provenance_so_a_chain_merges_faces_back(tmp_path):
    a, b, c = cube(), cube((0.25, 0.25, 0.5), (0.75, 0.75, 2)), cube((0.5, -1, 0.25), (0.6, 2, 0.75))
    first = csgkit.difference(a, b)
    csgkit.save(first, tmp_path / "first.ply")
    back = csgkit.load(tmp_path / "first.ply")
    np.testing.assert_array_equal(back.provenance, first.provenance)
    through_file = csgkit.difference(back, c, faces="polygons")
    in_memory = csgkit.difference(first, c, faces="polygons")
    assert through_file.face_count == in_memory.face_count
    assert csgkit.check(through_file)["volume"] == csgkit.check(in_memory)["volume"]


def test_paths_may_be_strings_or_path_objects(tmp_path):
    csgkit.save(cube(), str(tmp_path / "a.off"))
    assert csgkit.load(str(tmp_path / "a.off")).face_count == 12
    assert csgkit.check(tmp_path / "a.off")["faces"] == 12


CLEAN = ["spot.obj", "fandisk.obj", "joint.obj", "plate_holes.stl", "ballA.off", "thingi10k_65004.stl"]
DEFECTS = ["stanford-bunny.obj", "joined_tetrahedra.obj", "shared.stl", "cgal_non_manifold_face_graph.off",
           "two-boxes-bad-self-union.ply", "soup.stl"]


@pytest.mark.parametrize("name", CLEAN + DEFECTS)
def test_shared_meshes_measure_as_the_manifest_says(shared_data, manifest, name):
    measured = manifest[name]["measured"]
    report = csgkit.check(shared_data / "meshes" / name, self_intersections=False)
    assert report["vertices"] == measured["raw_verts"]
    assert report["faces"] == measured["raw_faces"]
    assert report["closed"] == measured["closed"]
    assert report["boundary_edges"] == measured["boundary_e"]
    assert report["components"] == measured["components"]
    assert report["volume"] == pytest.approx(measured["volume"], rel=1e-9, abs=1e-12)
    mesh = csgkit.load(shared_data / "meshes" / name)
    assert mesh.face_count == measured["raw_faces"]
