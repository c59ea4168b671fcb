"""csgkit as a trimesh boolean engine, and the functions on trimesh.Trimesh objects."""

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

import csgkit  # noqa: E402
import csgkit.trimesh  # noqa: E402


@pytest.fixture(scope="module", autouse=True)
def installed():
    csgkit.trimesh.install()
    assert "csgkit" in trimesh.boolean.engines_available


def boxes():
    a = trimesh.creation.box(extents=(2, 2, 2))
    b = trimesh.creation.box(extents=(2, 2, 2))
    b.apply_translation((1, 1, 1))
    return a, b


def test_trimesh_boolean_functions_run_csgkit():
    a, b = boxes()
    cases = {"union": 15.0, "intersection": 1.0, "difference": 7.0}
    for operation, expected in cases.items():
        result = getattr(trimesh.boolean, operation)([a, b], engine="csgkit")
        assert isinstance(result, trimesh.Trimesh)
        assert result.is_volume
        assert result.volume == expected
    assert a.union(b, engine="csgkit").volume == 15.0
    assert a.difference(b, engine="csgkit").volume == 7.0
    assert a.intersection(b, engine="csgkit").volume == 1.0


def test_the_engine_is_n_ary_and_takes_csgkit_options():
    spheres = [trimesh.creation.icosphere(subdivisions=2).apply_translation((0.6 * k, 0, 0)) for k in range(3)]
    once = trimesh.boolean.union(spheres, engine="csgkit", self_check=False)
    direct = csgkit.union(*[(s.vertices, s.faces) for s in spheres])
    np.testing.assert_array_equal(once.vertices, direct.vertices)
    np.testing.assert_array_equal(once.faces, direct.faces)
    minus = trimesh.boolean.difference(spheres, engine="csgkit")
    rest = csgkit.trimesh.union(spheres[1], spheres[2])
    both = trimesh.boolean.intersection([spheres[0], rest], engine="csgkit")
    assert 0 < minus.volume < spheres[0].volume
    assert minus.volume == pytest.approx(spheres[0].volume - both.volume, rel=1e-12)


def test_check_volume_refuses_what_trimesh_would_refuse():
    a, b = boxes()
    open_box = trimesh.Trimesh(a.vertices, a.faces[:-1], process=False)
    with pytest.raises(ValueError, match="Not all meshes are volumes"):
        trimesh.boolean.union([open_box, b], engine="csgkit")
    with pytest.raises(csgkit.InputError, match="operand 0 is not closed"):
        trimesh.boolean.union([open_box, b], engine="csgkit", check_volume=False)
    with pytest.raises(ValueError, match="faces must be 'triangles'"):
        trimesh.boolean.union([a, b], engine="csgkit", faces="polygons")


def test_functions_on_trimesh_objects():
    a, b = boxes()
    union = csgkit.trimesh.union(a, b)
    assert isinstance(union, trimesh.Trimesh) and union.is_watertight
    assert union.volume == 15.0
    assert csgkit.trimesh.intersection(a, b).volume == 1.0
    assert csgkit.trimesh.difference(a, b).volume == 7.0
    # Results can be changed in place, as trimesh expects.
    union.vertices += 1.0
    assert union.bounds[0].tolist() == [0.0, 0.0, 0.0]


def test_float64_coordinates_survive_exactly():
    """manifold3d through trimesh works in float32; csgkit keeps float64 coordinates."""
    a, b = boxes()
    offset = 1e-9  # far below float32's resolution at 1 (trimesh's transforms ignore it too)
    b = trimesh.Trimesh(b.vertices + (offset, 0, 0), b.faces, process=False)
    union = csgkit.trimesh.union(a, b)
    assert union.bounds[1][0] == 2.0 + offset
    assert union.volume == pytest.approx(15.0 + offset, abs=1e-12)  # 16 − (1 − offset)
