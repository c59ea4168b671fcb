"""csgkit: exact boolean operations on 3D solids.

Every decision is exact on the float64 input (no epsilon, no cast to float32), any number of
meshes combine in one call, touching and coplanar faces come out right, and every result is
certified as float64 numbers: closed, consistently oriented, free of self-intersections.

A mesh is a ``csgkit.Mesh``, a ``(vertices, faces)`` pair of NumPy arrays (float64 of shape
(n, 3); integers of shape (m, 3), or a list of polygons) or any object with ``vertices`` and
``faces`` (a ``trimesh.Trimesh``). Every operation returns a ``csgkit.Mesh`` and releases the
GIL while it runs.

>>> import csgkit
>>> a = csgkit.boxes([[0, 0, 0, 2, 2, 2]])
>>> b = csgkit.boxes([[1, 1, 1, 3, 3, 3]])
>>> union = csgkit.union(a, b)
>>> csgkit.check(union)["volume"], csgkit.check(csgkit.intersection(a, b))["volume"]
(15.0, 1.0)
>>> union.provenance.shape[1]  # per face: [operand, face of that operand]
2

- ``boolean(op, meshes, ...)`` and ``union``, ``intersection``, ``difference``, ``xor``:
  the exact engine.
- ``boxes(array_or_path)``: unions of axis-aligned boxes (or a MagicaVoxel ``.vox`` file)
  through the orthogonal engine.
- ``voxelize(mesh, cell)``: the discrete engine.
- ``check(mesh)``: validity and measures as a dict; ``load(path)`` and ``save(mesh, path)``
  in every format the library reads and writes.
- ``csgkit.trimesh``: csgkit as a trimesh boolean engine.
"""

from ._csgkit import (
    Mesh,
    __version__,
    boolean,
    boxes,
    check,
    difference,
    intersection,
    load,
    save,
    union,
    voxelize,
    xor,
)
from ._errors import CancelledError, CsgkitError, InputError, ReadError, WriteError

__all__ = [
    "CancelledError",
    "CsgkitError",
    "InputError",
    "Mesh",
    "ReadError",
    "WriteError",
    "__version__",
    "boolean",
    "boxes",
    "check",
    "difference",
    "intersection",
    "load",
    "save",
    "union",
    "voxelize",
    "xor",
]
