"""Volume identities of exact booleans: vol(A ∪ B) + vol(A ∩ B) = vol(A) + vol(B),
vol(A − B) = vol(A) − vol(A ∩ B), vol(A ⊕ B) = vol(A ∪ B) − vol(A ∩ B), on boxes with
dyadic coordinates (every volume is exact in float64, so the identities hold exactly) and on
overlapping spheres (to rounding)."""

import numpy as np
import pytest

import csgkit
from conftest import cube, sphere


def volume(mesh):
    report = csgkit.check(mesh, self_intersections=False)
    assert report["valid_solid"]
    return report["volume"]


def random_box(rng):
    lo = rng.integers(0, 8, size=3) / 4
    return cube(lo, lo + rng.integers(1, 8, size=3) / 4)


@pytest.mark.parametrize("seed", range(8))
def test_identities_hold_exactly_on_boxes(seed):
    rng = np.random.default_rng(seed)
    a, b = random_box(rng), random_box(rng)
    union, both = volume(csgkit.union(a, b)), volume(csgkit.intersection(a, b))
    assert union + both == volume(a) + volume(b)
    assert volume(csgkit.difference(a, b)) == volume(a) - both
    assert volume(csgkit.xor(a, b)) == union - both
    # The orthogonal engine's union of the same boxes is the same solid.
    boxes = [np.concatenate([m[0].min(axis=0), m[0].max(axis=0)]) for m in (a, b)]
    assert volume(csgkit.boxes(boxes)) == union


def test_touching_and_coplanar_boxes_are_exact():
    a, b = cube(), cube((1, 0, 0), (2, 1, 1))  # sharing a face
    assert volume(csgkit.union(a, b)) == 2.0
    assert csgkit.intersection(a, b).face_count == 0
    c = cube((0, 0, 0), (1, 1, 0.5))  # coplanar with a on five faces
    assert volume(csgkit.difference(a, c)) == 0.5
    assert volume(csgkit.union(a, c)) == 1.0


def test_identities_hold_on_overlapping_spheres():
    a = sphere((0, 0, 0), 1.0, 3)
    b = sphere((0.6, 0.3, 0.1), 0.8, 3)
    va, vb = volume(a), volume(b)
    union, both = volume(csgkit.union(a, b)), volume(csgkit.intersection(a, b))
    assert union + both == pytest.approx(va + vb, rel=1e-12)
    assert volume(csgkit.difference(a, b)) == pytest.approx(va - both, rel=1e-12)
    assert volume(csgkit.xor(a, b)) == pytest.approx(union - both, rel=1e-12)
    assert 0 < both < min(va, vb) < max(va, vb) < union


def test_an_n_ary_union_is_the_fold_of_binary_ones():
    spheres = [sphere((0.5 * k, 0.1 * k, 0), 0.7, 2) for k in range(4)]
    at_once = csgkit.union(*spheres)
    folded = spheres[0]
    for s in spheres[1:]:
        folded = csgkit.union(folded, s)
    assert volume(at_once) == pytest.approx(volume(folded), rel=1e-12)
    first_minus_rest = csgkit.difference(*spheres)
    assert volume(first_minus_rest) == pytest.approx(
        volume(spheres[0]) - volume(csgkit.intersection(spheres[0], csgkit.union(*spheres[1:]))), rel=1e-12
    )
