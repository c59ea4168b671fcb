"""csgkit.Mesh: construction from arrays, its arrays, and the attributes operations carry."""

import numpy as np
import pytest

import csgkit
from conftest import cube


def test_triangles_come_back_as_an_m_by_3_array():
    v, f = cube()
    mesh = csgkit.Mesh(v, f)
    assert mesh.vertices.dtype == np.float64 and mesh.vertices.shape == (8, 3)
    assert mesh.faces.dtype == np.uint32 and mesh.faces.shape == (12, 3)
    np.testing.assert_array_equal(mesh.vertices, v)
    np.testing.assert_array_equal(mesh.faces, f)
    assert (mesh.vertex_count, mesh.face_count) == (8, 12)
    assert repr(mesh) == "csgkit.Mesh(8 vertices, 12 faces: triangles)"


def test_quads_and_ragged_polygons_come_back_as_lists():
    v, _ = cube()
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    for faces in (np.array(quads), quads):
        mesh = csgkit.Mesh(v, faces)
        assert isinstance(mesh.faces, list) and len(mesh.faces) == 6
        assert [list(face) for face in mesh.faces] == quads
        assert csgkit.check(mesh)["volume"] == 1.0
    # Two pentagons (a vertex added in the middle of the edge 0-1) beside triangles and quads.
    v5 = np.vstack([v, [[0.5, 0.0, 0.0]]])
    ragged = [[0, 2, 3, 1, 8], [0, 8, 1, 5, 4], [4, 5, 6], [5, 7, 6], [2, 6, 7, 3],
              [0, 4, 6, 2], [1, 3, 7, 5]]
    mesh = csgkit.Mesh(v5, ragged)
    assert [face.tolist() for face in mesh.faces] == ragged
    np.testing.assert_array_equal(mesh.corners, np.concatenate(ragged))
    report = csgkit.check(mesh)
    assert report["valid_solid"] and report["volume"] == 1.0


def test_arrays_are_read_only_views():
    mesh = csgkit.union(cube(), cube((0.5, 0.5, 0.5), (2, 2, 2)))
    for array in (mesh.vertices, mesh.faces, mesh.corners):
        assert not array.flags.writeable
        with pytest.raises(ValueError):
            array[0] = 0
    # The vertices are the library's buffer handed to NumPy, not a copy per access.
    assert not mesh.vertices.flags.owndata
    assert np.shares_memory(mesh.vertices, mesh.vertices)
    assert mesh.vertices.base is not None


def test_any_numbers_convert_but_faces_must_be_integers():
    v, f = cube()
    mesh = csgkit.Mesh(v.astype(np.float32).tolist(), f.astype(np.uint16))
    np.testing.assert_array_equal(mesh.vertices, v)
    with pytest.raises(csgkit.InputError, match="faces must be integer vertex indices"):
        csgkit.Mesh(v, f.astype(float))


def test_operands_may_be_meshes_pairs_or_objects_with_vertices_and_faces():
    class Shape:
        def __init__(self, v, f):
            self.vertices, self.faces = v, f

    a, b = cube(), cube((0.5, 0, 0), (1.5, 1, 1))
    volumes = {
        csgkit.check(csgkit.union(*pair))["volume"]
        for pair in [(a, b), (csgkit.Mesh(*a), csgkit.Mesh(*b)), (Shape(*a), b)]
    }
    assert volumes == {1.5}


def test_results_carry_provenance_and_a_result_is_an_operand_again():
    a, b, c = cube(), cube((0.5, 0, 0), (1.5, 1, 1)), cube((1, 0, 0), (2, 1, 1))
    ab = csgkit.union(a, b)
    provenance = ab.provenance
    assert provenance.shape == (ab.face_count, 2) and provenance.dtype == np.uint32
    assert set(provenance[:, 0]) == {0, 1}
    assert provenance[:, 1].max() < 12
    abc = csgkit.union(ab, c)
    assert csgkit.check(abc)["volume"] == 2.0
    assert set(abc.provenance[:, 0]) == {0, 1}


def test_materials_and_uvs_of_a_file_survive_an_operation(tmp_path):
    v, f = cube()
    lines = ["mtllib box.mtl"] + [f"v {x} {y} {z}" for x, y, z in v]
    lines += ["vt 0 0", "vt 1 0", "vt 0 1", "usemtl red"]
    lines += [f"f {a + 1}/1 {b + 1}/2 {c + 1}/3" for a, b, c in f[:6]]
    lines += ["usemtl blue"] + [f"f {a + 1}/1 {b + 1}/2 {c + 1}/3" for a, b, c in f[6:]]
    path = tmp_path / "box.obj"
    path.write_text("\n".join(lines) + "\n")
    box = csgkit.load(path)
    assert box.material_names == ["red", "blue"]
    np.testing.assert_array_equal(box.face_materials, [0] * 6 + [1] * 6)
    assert box.uvs.shape == (36, 2)
    cut = csgkit.difference(box, cube((0.5, 0.5, 0.5), (2, 2, 2)))
    # Each face keeps the material of the face it was cut from; the cutter's faces, which
    # have none, get the default material.
    names = np.array(cut.material_names)[cut.face_materials]
    operand, source = cut.provenance.T
    from_box = operand == 0
    assert from_box.any() and not from_box.all()
    np.testing.assert_array_equal(names[from_box], np.array(box.material_names)[box.face_materials[source[from_box]]])
    assert set(names[~from_box]) == {"default"}
    assert cut.uvs.shape == (len(cut.corners), 2)
    assert cut.normals is None and cut.vertex_colors is None


def test_voxel_colours_become_materials_and_face_colours(shared_data):
    knight = csgkit.boxes(shared_data / "voxels" / "chr_knight.vox")
    assert knight.face_colors.shape == (knight.face_count, 4)
    assert knight.face_materials.shape == (knight.face_count,)
    assert len(knight.material_names) > 1


def test_results_time_the_stages_their_progress_reported():
    a, b = cube(), cube((0.5, 0.5, 0.5), (2, 2, 2))
    assert csgkit.Mesh(*a).stage_seconds is None
    for run in (
        lambda progress: csgkit.union(a, b, progress=progress),
        lambda progress: csgkit.boxes([[0, 0, 0, 2, 2, 2], [1, 1, 1, 3, 3, 3]], progress=progress),
        lambda progress: csgkit.voxelize(a, 0.25, progress=progress),
    ):
        reported = []
        result = run(lambda stage, done, total: reported.append(stage))
        seconds = result.stage_seconds
        assert list(seconds) == list(dict.fromkeys(reported))
        assert all(t >= 0 for t in seconds.values())
    assert list(csgkit.union(a, b).stage_seconds)[:2] == ["ingest", "validate"]


def test_meshes_pickle_with_every_attribute(tmp_path):
    """A result (provenance, polygons) and a file's mesh (materials, groups, UVs, normals)
    come back from pickle equal in every array, as Dask and multiprocessing move them."""
    import pickle

    v, f = cube()
    result = csgkit.union(csgkit.Mesh(v, f), (v + [0.5, 0.25, 0.0], f), faces="polygons")
    obj = tmp_path / "attributes.obj"
    obj.write_text(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvn 0 0 1\n"
        "g part\nusemtl red\nf 1/1/1 3/2/1 2/1/1\nusemtl blue\nf 1/2/1 2/1/1 4/1/1\n"
        "f 1/1/1 4/2/1 3/1/1\nf 2/1/1 3/2/1 4/1/1\n"
    )
    loaded = csgkit.load(obj)
    for mesh in (result, loaded):
        copy = pickle.loads(pickle.dumps(mesh))
        assert type(copy) is csgkit.Mesh and repr(copy) == repr(mesh)
        for name in ("vertices", "corners", "face_materials", "face_groups", "face_colors",
                     "uvs", "normals", "vertex_colors", "provenance"):
            mine, theirs = getattr(mesh, name), getattr(copy, name)
            assert (mine is None) == (theirs is None), name
            if mine is not None:
                assert mine.dtype == theirs.dtype, name
                np.testing.assert_array_equal(mine, theirs, err_msg=name)
        assert [list(x) for x in copy.faces] == [list(x) for x in mesh.faces]
        assert copy.material_names == mesh.material_names
        assert copy.group_names == mesh.group_names
    assert loaded.uvs is not None and loaded.face_materials is not None
    assert result.provenance is not None


def test_a_damaged_pickle_is_an_input_error():
    state = csgkit.union(cube())
    rebuild, (fields,) = state.__reduce__()
    fields = dict(fields, corners=np.array([0, 1, 99], dtype=np.uint32), face_starts=None)
    with pytest.raises(csgkit.InputError):
        rebuild(fields)
