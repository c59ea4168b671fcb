"""csgkit as a boolean engine of trimesh.

>>> import trimesh, csgkit.trimesh
>>> csgkit.trimesh.install()
>>> a = trimesh.creation.box(extents=(2, 2, 2))
>>> b = trimesh.creation.box(extents=(2, 2, 2)).apply_translation((1, 1, 1))
>>> float(trimesh.boolean.union([a, b], engine="csgkit").volume)
15.0
>>> float(csgkit.trimesh.difference(a, b).volume)
7.0

Why choose it over trimesh's default engine (manifold3d):

- exact in float64: trimesh hands manifold3d float32 copies of the vertices, so inputs lose
  precision before the boolean starts and results come back rounded to float32; csgkit
  decides every intersection exactly on the float64 coordinates and rounds each new vertex
  once;
- n-ary in one call: trimesh folds manifold3d's binary operations over the list, while
  csgkit computes the union, intersection or difference of all the meshes in one
  arrangement;
- coplanar and touching cases exact: faces that lie in one plane or meet along an edge or
  at a point are decided by exact predicates, not tolerances, so they neither leave
  slivers nor vanish;
- it accepts meshes whose faces cross themselves or whose shells nest (winding numbers),
  and certifies every result as closed, oriented and free of self-intersections.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
import trimesh

from . import _csgkit

if TYPE_CHECKING:
    from ._csgkit import Operation

ENGINE = "csgkit"


def install() -> None:
    """Registers csgkit as the trimesh boolean engine ``"csgkit"``, so that
    ``trimesh.boolean.union(meshes, engine="csgkit")`` and
    ``mesh.union(other, engine="csgkit")`` compute with csgkit. Installing twice is harmless.
    """
    trimesh.boolean._engines[ENGINE] = boolean
    trimesh.boolean.engines_available.add(ENGINE)


def boolean(
    meshes: Sequence[trimesh.Trimesh],
    operation: Operation,
    check_volume: bool = True,
    **options: Any,
) -> trimesh.Trimesh:
    """The engine, called by trimesh as ``engine(meshes, operation=..., check_volume=...,
    **kwargs)``: the exact ``operation`` of all ``meshes`` (a difference is the first minus
    the others) in one call. With ``check_volume``, meshes that trimesh does not consider
    volumes are refused as trimesh's engines refuse them; csgkit itself accepts every closed
    mesh. ``options`` are those of ``csgkit.boolean`` (winding, self_check, ...).
    """
    if check_volume and not all(m.is_volume for m in meshes):
        raise ValueError("Not all meshes are volumes!")
    if options.get("faces", "triangles") != "triangles":
        raise ValueError("a trimesh.Trimesh holds triangles: faces must be 'triangles'")
    result = _csgkit.boolean(operation, [(m.vertices, m.faces) for m in meshes], **options)
    return to_trimesh(result)


def to_trimesh(mesh: _csgkit.Mesh) -> trimesh.Trimesh:
    """A ``trimesh.Trimesh`` of a triangle mesh's vertices and faces (copies, which trimesh
    may change in place)."""
    return trimesh.Trimesh(
        vertices=np.array(mesh.vertices),
        faces=np.array(mesh.faces, dtype=np.int64),
        process=False,
    )


def union(*meshes: trimesh.Trimesh, **options: Any) -> trimesh.Trimesh:
    """The exact union of trimesh meshes, as a ``trimesh.Trimesh``."""
    return boolean(meshes, "union", check_volume=False, **options)


def intersection(*meshes: trimesh.Trimesh, **options: Any) -> trimesh.Trimesh:
    """The exact intersection of trimesh meshes, as a ``trimesh.Trimesh``."""
    return boolean(meshes, "intersection", check_volume=False, **options)


def difference(*meshes: trimesh.Trimesh, **options: Any) -> trimesh.Trimesh:
    """The first trimesh mesh minus all the others, exactly, as a ``trimesh.Trimesh``."""
    return boolean(meshes, "difference", check_volume=False, **options)
