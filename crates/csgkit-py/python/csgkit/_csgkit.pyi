"""Type stubs of the native module (crates/csgkit-py/src); csgkit re-exports all of it."""

import os
from typing import Any, Callable, Literal, Optional, Protocol, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
PathLike = Union[str, os.PathLike[str]]
#: A mesh operand: a csgkit.Mesh, a (vertices, faces) pair, or an object with vertices and
#: faces attributes (a trimesh.Trimesh).
MeshLike = Union["Mesh", Tuple[ArrayLike, Union[ArrayLike, Sequence[Sequence[int]]]], Any]
#: Called with (stage, done, total) from the worker threads; return False to cancel.
ProgressCallback = Callable[[str, int, int], Optional[bool]]
Operation = Literal["union", "intersection", "difference", "xor"]
Winding = Literal["nonzero", "positive"]
FaceMode = Literal["triangles", "polygons", "quads"]
Precision = Literal["f64", "f32"]

class Mesh:
    """A polygon mesh with float64 vertices, as every csgkit operation takes and returns it.
    Its arrays are read-only views of the mesh's own buffers."""

    def __init__(
        self, vertices: ArrayLike, faces: Union[ArrayLike, Sequence[Sequence[int]]]
    ) -> None: ...
    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """(n, 3) float64."""
    @property
    def faces(self) -> Union[npt.NDArray[np.uint32], list[npt.NDArray[np.uint32]]]:
        """(m, 3) uint32 when every face is a triangle, else one uint32 array per face."""
    @property
    def corners(self) -> npt.NDArray[np.uint32]:
        """Every face's vertex indices, face after face (the order of uvs and normals)."""
    @property
    def vertex_count(self) -> int: ...
    @property
    def face_count(self) -> int: ...
    @property
    def face_materials(self) -> Optional[npt.NDArray[np.uint32]]:
        """(m,) indices into material_names, or None."""
    @property
    def material_names(self) -> list[str]: ...
    @property
    def face_groups(self) -> Optional[npt.NDArray[np.uint32]]:
        """(m,) indices into group_names, or None."""
    @property
    def group_names(self) -> list[str]: ...
    @property
    def face_colors(self) -> Optional[npt.NDArray[np.uint8]]:
        """(m, 4) RGBA, or None."""
    @property
    def uvs(self) -> Optional[npt.NDArray[np.float64]]:
        """(corners, 2) texture coordinates, or None."""
    @property
    def normals(self) -> Optional[npt.NDArray[np.float32]]:
        """(corners, 3) normals, or None."""
    @property
    def vertex_colors(self) -> Optional[npt.NDArray[np.uint8]]:
        """(n, 4) RGBA, or None."""
    @property
    def provenance(self) -> Optional[npt.NDArray[np.uint32]]:
        """(m, 2): per face, [operand, face of that operand], or None."""
    @property
    def stage_seconds(self) -> Optional[dict[str, float]]:
        """Seconds of each stage of the operation that made the mesh, or None."""
    def __reduce__(self) -> tuple[Any, tuple[dict[str, Any]]]:
        """Pickling keeps every array and attribute (not stage_seconds)."""

def boolean(
    operation: Operation,
    meshes: Sequence[MeshLike],
    *,
    winding: Winding = "nonzero",
    faces: FaceMode = "triangles",
    self_check: bool = True,
    manifold: bool = False,
    merge_coplanar: bool = False,
    simplify: Optional[float] = None,
    precision: Precision = "f64",
    progress: Optional[ProgressCallback] = None,
) -> Mesh: ...
class _Operation(Protocol):
    """union, intersection, difference and xor: boolean() of one operation."""

    def __call__(
        self,
        *meshes: MeshLike,
        winding: Winding = "nonzero",
        faces: FaceMode = "triangles",
        self_check: bool = True,
        manifold: bool = False,
        merge_coplanar: bool = False,
        simplify: Optional[float] = None,
        precision: Precision = "f64",
        progress: Optional[ProgressCallback] = None,
    ) -> Mesh: ...

union: _Operation
intersection: _Operation
difference: _Operation
xor: _Operation

def boxes(
    boxes: Union[ArrayLike, PathLike],
    *,
    triangles: bool = False,
    manifold: bool = False,
    model: Optional[int] = None,
    progress: Optional[ProgressCallback] = None,
) -> Mesh: ...
def voxelize(
    mesh: MeshLike,
    cell: float,
    *,
    surface: Literal["ortho", "surfels"] = "ortho",
    progress: Optional[ProgressCallback] = None,
) -> Mesh: ...
def load(path: PathLike) -> Mesh: ...
def _mesh_from_state(state: dict[str, Any]) -> Mesh:
    """The mesh a pickle holds (Mesh.__reduce__ writes it)."""
def save(mesh: MeshLike, path: PathLike, *, ascii: bool = False) -> None: ...
def check(
    mesh: Union[MeshLike, PathLike], *, self_intersections: bool = True
) -> dict[str, Any]: ...
