//! `csgkit.Mesh` and the conversions between NumPy arrays and [`Mesh`].
//!
//! A `csgkit.Mesh` made by the library (an operation's result, a file read) owns its position
//! and corner buffers as NumPy arrays that took over the library's `Vec`s without a copy;
//! every other attribute (materials, groups, colours, UVs, normals, provenance) stays in the
//! library's [`MeshParts`] and becomes an array when asked for. The arrays are read-only, so
//! the mesh stays what the library made: copy one to change it and build a new mesh.
//!
//! An operand is a `csgkit.Mesh`, a `(vertices, faces)` pair, or any object with `vertices`
//! and `faces` attributes (a `trimesh.Trimesh`). Its arrays are checked here, where the
//! message can name the vertex or face at fault, and copied once into a [`Mesh`]:
//! - `vertices`: anything NumPy reads as float64 of shape (n, 3), every coordinate finite;
//! - `faces`: an integer array of shape (m, k), k ≥ 3 (triangles when k = 3), or a sequence
//!   of polygons, each a sequence of at least three vertex indices, every index in 0..n.

use csgkit::{FaceId, Mesh, MeshParts, OperandId, Output, Provenance, Stage};
use numpy::{
    AllowTypeChange, Element, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayLikeDyn,
    PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors;

/// A polygon mesh with float64 vertices, as every csgkit operation takes and returns it.
///
/// `vertices` is an (n, 3) float64 array; `faces` is an (m, 3) uint32 array when every face
/// is a triangle, and otherwise a list of m uint32 arrays, one per polygon. Meshes read from
/// files and results of operations also carry per-face materials and provenance, per-corner
/// UVs and normals and per-vertex colours, when their source has them. `vertices`, `faces`
/// and `corners` are read-only views of the mesh's own buffers (no copy is made), the
/// attributes read-only copies; copy an array to change it.
///
/// Example:
///
/// >>> import numpy as np, csgkit
/// >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
/// >>> f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
/// >>> tetrahedron = csgkit.Mesh(v, f)
/// >>> tetrahedron.faces.shape
/// (4, 3)
/// >>> csgkit.check(tetrahedron)["volume"]
/// 0.16666666666666666
#[pyclass(frozen, module = "csgkit", name = "Mesh")]
pub struct PyMesh {
    /// (n, 3) float64, read-only, the library's position buffer.
    vertices: Py<PyArray2<f64>>,
    /// The flat corner buffer (uint32, read-only): every face's vertex indices, face after face.
    corners: Py<PyArray1<u32>>,
    /// Where each face starts in `corners`, then the length of `corners`; `None` for a
    /// triangle mesh.
    face_starts: Option<Vec<u32>>,
    /// Every other buffer of the mesh (positions and corners left empty).
    attributes: MeshParts,
    /// The seconds of every stage of the operation that made the mesh, if one did.
    stage_seconds: Option<Vec<(Stage, f64)>>,
}

#[pymethods]
impl PyMesh {
    /// A mesh from vertices (float64, shape (n, 3)) and faces (integers of shape (m, k), or a
    /// sequence of polygons); raises `InputError` naming the vertex or face at fault.
    #[new]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        PyMesh::from_mesh(py, mesh_from_arrays(vertices, faces)?)
    }

    /// The vertex positions: an (n, 3) float64 array.
    #[getter]
    fn vertices(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.vertices.clone_ref(py)
    }

    /// The faces: an (m, 3) uint32 array when every face is a triangle, else a list of m
    /// uint32 arrays (views of `corners`).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let corners = self.corners.bind(py);
        match &self.face_starts {
            None => Ok(corners.reshape([corners.len() / 3, 3])?.into_any()),
            Some(starts) => {
                let inner = &starts[1..starts.len() - 1];
                let numpy = py.import("numpy")?;
                numpy.call_method1("split", (corners, inner.to_vec()))
            }
        }
    }

    /// The vertex indices of every face, face after face: a flat uint32 array, the order of
    /// `uvs` and `normals`.
    #[getter]
    fn corners(&self, py: Python<'_>) -> Py<PyArray1<u32>> {
        self.corners.clone_ref(py)
    }

    /// The number of vertices.
    #[getter]
    fn vertex_count(&self, py: Python<'_>) -> usize {
        self.vertices.bind(py).shape()[0]
    }

    /// The number of faces.
    #[getter]
    fn face_count(&self, py: Python<'_>) -> usize {
        match &self.face_starts {
            None => self.corners.bind(py).len() / 3,
            Some(starts) => starts.len() - 1,
        }
    }

    /// Per face, its index into `material_names` (uint32, shape (m,)), or None.
    #[getter]
    fn face_materials<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray1<u32>>>> {
        self.attributes
            .face_materials
            .as_deref()
            .map(|ids| read_only(PyArray1::from_slice(py, ids)))
            .transpose()
    }

    /// The material names (OBJ `usemtl`, PLY material names, voxel palette entries).
    #[getter]
    fn material_names(&self) -> Vec<String> {
        self.attributes.materials.clone()
    }

    /// Per face, its index into `group_names` (uint32, shape (m,)), or None.
    #[getter]
    fn face_groups<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray1<u32>>>> {
        self.attributes
            .face_groups
            .as_deref()
            .map(|ids| read_only(PyArray1::from_slice(py, ids)))
            .transpose()
    }

    /// The group names (OBJ `o` and `g`).
    #[getter]
    fn group_names(&self) -> Vec<String> {
        self.attributes.groups.clone()
    }

    /// Per face, an RGBA colour (uint8, shape (m, 4)), or None.
    #[getter]
    fn face_colors<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<u8>>>> {
        self.attributes
            .face_colors
            .as_deref()
            .map(|rows| rows_array(py, rows))
            .transpose()
    }

    /// Per corner (in the order of `corners`), a texture coordinate (float64, shape (c, 2)),
    /// or None.
    #[getter]
    fn uvs<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.attributes
            .corner_uvs
            .as_deref()
            .map(|rows| rows_array(py, rows))
            .transpose()
    }

    /// Per corner (in the order of `corners`), a normal (float32, shape (c, 3)), or None.
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f32>>>> {
        self.attributes
            .corner_normals
            .as_deref()
            .map(|rows| rows_array(py, rows))
            .transpose()
    }

    /// Per vertex, an RGBA colour (uint8, shape (n, 4)), or None.
    #[getter]
    fn vertex_colors<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<u8>>>> {
        self.attributes
            .vertex_colors
            .as_deref()
            .map(|rows| rows_array(py, rows))
            .transpose()
    }

    /// Per face, where it came from: `[operand, face]` (uint32, shape (m, 2)), the operand's
    /// position in the operation and the face's index in that operand; None for a mesh that
    /// no operation made.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<u32>>>> {
        let Some(provenance) = &self.attributes.face_provenance else {
            return Ok(None);
        };
        let rows: Vec<[u32; 2]> = (provenance.iter())
            .map(|p: &Provenance| [p.operand.get(), p.face.get()])
            .collect();
        rows_array(py, &rows).map(Some)
    }

    /// The seconds of each stage of the operation that made this mesh ({"ingest": ...,
    /// "intersect": ..., ...}, in the order they ran), or None for a mesh no operation made.
    #[getter]
    fn stage_seconds<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(stages) = &self.stage_seconds else {
            return Ok(None);
        };
        let seconds = PyDict::new(py);
        for (stage, time) in stages {
            let name = stage.to_string();
            let before: f64 = seconds.get_item(&name)?.map_or(Ok(0.0), |t| t.extract())?;
            seconds.set_item(name, before + time)?;
        }
        Ok(Some(seconds))
    }

    /// Pickling (for `multiprocessing`, Dask and caches): every buffer and attribute, as
    /// arrays and lists that `_mesh_from_state` turns back into the same mesh. The stage
    /// seconds stay behind: they describe a run in this process.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let attributes = &self.attributes;
        let state = PyDict::new(py);
        state.set_item("vertices", self.vertices.bind(py))?;
        state.set_item("corners", self.corners.bind(py))?;
        state.set_item(
            "face_starts",
            optional_array(py, self.face_starts.as_deref()),
        )?;
        state.set_item(
            "face_materials",
            optional_array(py, attributes.face_materials.as_deref()),
        )?;
        state.set_item("materials", &attributes.materials)?;
        state.set_item(
            "face_groups",
            optional_array(py, attributes.face_groups.as_deref()),
        )?;
        state.set_item("groups", &attributes.groups)?;
        state.set_item(
            "face_colors",
            flat_rows(py, attributes.face_colors.as_deref()),
        )?;
        let provenance: Option<Vec<[u32; 2]>> =
            (attributes.face_provenance.as_deref()).map(|rows| {
                rows.iter()
                    .map(|p| [p.operand.get(), p.face.get()])
                    .collect()
            });
        state.set_item("provenance", flat_rows(py, provenance.as_deref()))?;
        state.set_item("uvs", flat_rows(py, attributes.corner_uvs.as_deref()))?;
        state.set_item(
            "normals",
            flat_rows(py, attributes.corner_normals.as_deref()),
        )?;
        state.set_item(
            "vertex_colors",
            flat_rows(py, attributes.vertex_colors.as_deref()),
        )?;
        state.set_item("material_libraries", &attributes.material_libraries)?;
        let rebuild = py.import("csgkit._csgkit")?.getattr("_mesh_from_state")?;
        Ok((rebuild, (state,)))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let kind = match self.face_starts {
            None => "triangles",
            Some(_) => "polygons",
        };
        format!(
            "csgkit.Mesh({} vertices, {} faces: {kind})",
            self.vertex_count(py),
            self.face_count(py)
        )
    }
}

impl PyMesh {
    /// Takes over `mesh`'s position and corner buffers as NumPy arrays, without a copy.
    pub fn from_mesh(py: Python<'_>, mesh: Mesh) -> PyResult<Self> {
        PyMesh::computed(py, mesh, None)
    }

    /// [`PyMesh::from_mesh`] for the result of an operation, with its stage seconds.
    pub fn computed(
        py: Python<'_>,
        mesh: Mesh,
        stage_seconds: Option<Vec<(Stage, f64)>>,
    ) -> PyResult<Self> {
        let mut attributes = mesh.into_parts();
        let positions = std::mem::take(&mut attributes.positions);
        let count = positions.len();
        let flat = PyArray1::from_vec(py, positions.into_flattened());
        let vertices = read_only(flat.reshape([count, 3])?)?;
        let corners = read_only(PyArray1::from_vec(
            py,
            std::mem::take(&mut attributes.corners),
        ))?;
        Ok(PyMesh {
            vertices: vertices.unbind(),
            corners: corners.unbind(),
            face_starts: attributes.face_starts.take(),
            attributes,
            stage_seconds,
        })
    }

    /// An engine's output, with its stage seconds.
    pub fn from_output(py: Python<'_>, output: Output) -> PyResult<Self> {
        let stage_seconds = output.stats.stage_seconds().to_vec();
        PyMesh::computed(py, output.mesh, Some(stage_seconds))
    }

    /// The library's mesh: the arrays copied back, the attributes cloned.
    pub fn to_mesh(&self, py: Python<'_>) -> PyResult<Mesh> {
        let vertices = self.vertices.bind(py).readonly();
        let corners = self.corners.bind(py).readonly();
        let positions = (vertices.as_array().outer_iter())
            .map(|p| [p[0], p[1], p[2]])
            .collect();
        let parts = MeshParts {
            positions,
            corners: corners.as_array().to_vec(),
            face_starts: self.face_starts.clone(),
            ..self.attributes.clone()
        };
        Mesh::from_parts(parts).map_err(|error| errors::input(error.to_string()))
    }
}

/// The mesh a pickled `csgkit.Mesh` held (see `Mesh.__reduce__`); checked as any mesh is.
#[pyfunction]
pub fn _mesh_from_state(py: Python<'_>, state: &Bound<'_, PyDict>) -> PyResult<PyMesh> {
    let item = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        (state.get_item(key)?)
            .ok_or_else(|| errors::input(format!("a pickled csgkit.Mesh lacks {key}")))
    };
    let names = |key: &str| -> PyResult<Vec<String>> {
        (item(key)?.extract()).map_err(|error| errors::input(format!("pickled {key}: {error}")))
    };
    let provenance: Option<Vec<[u32; 2]>> = rows(values(&item("provenance")?)?);
    let parts = MeshParts {
        positions: rows(values(&item("vertices")?)?).unwrap_or_default(),
        corners: values(&item("corners")?)?.unwrap_or_default(),
        face_starts: values(&item("face_starts")?)?,
        face_materials: values(&item("face_materials")?)?,
        materials: names("materials")?,
        face_groups: values(&item("face_groups")?)?,
        groups: names("groups")?,
        face_colors: rows(values(&item("face_colors")?)?),
        face_provenance: provenance.map(|rows| {
            (rows.into_iter())
                .map(|[operand, face]| Provenance {
                    operand: OperandId::new(operand as usize),
                    face: FaceId::new(face as usize),
                })
                .collect()
        }),
        corner_uvs: rows(values(&item("uvs")?)?),
        corner_normals: rows(values(&item("normals")?)?),
        vertex_colors: rows(values(&item("vertex_colors")?)?),
        material_libraries: names("material_libraries")?,
    };
    let mesh = Mesh::from_parts(parts).map_err(|error| errors::input(error.to_string()))?;
    PyMesh::from_mesh(py, mesh)
}

/// The values of an array of any shape in C order (`None` for `None`), of the element type
/// the pickle wrote.
fn values<T: Element + Copy>(object: &Bound<'_, PyAny>) -> PyResult<Option<Vec<T>>> {
    if object.is_none() {
        return Ok(None);
    }
    let array: numpy::PyReadonlyArrayDyn<'_, T> = object
        .extract()
        .map_err(|error| errors::input(format!("pickled csgkit.Mesh: {error}")))?;
    Ok(Some(array.as_array().iter().copied().collect()))
}

/// An optional column as an array (`None` stays `None`).
fn optional_array<'py, T: Element + Copy>(
    py: Python<'py>,
    values: Option<&[T]>,
) -> Option<Bound<'py, PyArray1<T>>> {
    values.map(|values| PyArray1::from_slice(py, values))
}

/// Rows of `K` values flattened into a 1-D array (a copy), for pickling.
fn flat_rows<'py, T: Element + Copy, const K: usize>(
    py: Python<'py>,
    rows: Option<&[[T; K]]>,
) -> Option<Bound<'py, PyArray1<T>>> {
    optional_array(py, rows.map(<[[T; K]]>::as_flattened))
}

/// Values taken `K` at a time, as [`flat_rows`] wrote them.
fn rows<T: Copy, const K: usize>(values: Option<Vec<T>>) -> Option<Vec<[T; K]>> {
    values.map(|values| {
        (values.chunks_exact(K))
            .map(|row| std::array::from_fn(|k| row[k]))
            .collect()
    })
}

/// Marks `array` read-only (and the array it views, if any).
fn read_only<T, D>(
    array: Bound<'_, numpy::PyArray<T, D>>,
) -> PyResult<Bound<'_, numpy::PyArray<T, D>>> {
    array.getattr("flags")?.setattr("writeable", false)?;
    let base = array.getattr("base")?;
    if base.cast::<PyUntypedArray>().is_ok() {
        base.getattr("flags")?.setattr("writeable", false)?;
    }
    Ok(array)
}

/// Rows of `K` values as a read-only (rows, K) array (a copy).
fn rows_array<'py, T: Element + Copy, const K: usize>(
    py: Python<'py>,
    rows: &[[T; K]],
) -> PyResult<Bound<'py, PyArray2<T>>> {
    read_only(PyArray1::from_slice(py, rows.as_flattened()).reshape([rows.len(), K])?)
}

/// Any operand: a `csgkit.Mesh`, a `(vertices, faces)` pair, or an object with `vertices`
/// and `faces` attributes.
pub fn extract_mesh(object: &Bound<'_, PyAny>) -> PyResult<Mesh> {
    let py = object.py();
    if let Ok(mesh) = object.cast::<PyMesh>() {
        return mesh.get().to_mesh(py);
    }
    if let Ok((vertices, faces)) = object.extract::<(Bound<'_, PyAny>, Bound<'_, PyAny>)>() {
        return mesh_from_arrays(&vertices, &faces);
    }
    if object.hasattr("vertices")? && object.hasattr("faces")? {
        return mesh_from_arrays(&object.getattr("vertices")?, &object.getattr("faces")?);
    }
    let type_name = object.get_type().name()?;
    Err(errors::input(format!(
        "a mesh is a csgkit.Mesh, a (vertices, faces) pair or an object with vertices and faces, not {type_name}"
    )))
}

/// Checks and copies the arrays of an operand (see the module docs).
fn mesh_from_arrays(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Mesh> {
    let positions = positions(vertices)?;
    let (corners, face_starts) = faces_of(faces, positions.len())?;
    let parts = MeshParts {
        positions,
        corners,
        face_starts,
        ..MeshParts::default()
    };
    Mesh::from_parts(parts).map_err(|error| errors::input(error.to_string()))
}

/// The positions of an (n, 3) array of finite numbers.
fn positions(vertices: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; 3]>> {
    let array: PyArrayLikeDyn<'_, f64, AllowTypeChange> = vertices
        .extract()
        .map_err(|error| errors::input(format!("vertices: {error}")))?;
    let view = array.as_array();
    match view.shape() {
        [_, 3] => {}
        [0] => return Ok(Vec::new()),
        shape => {
            return Err(errors::input(format!(
                "vertices must be an array of shape (n, 3), not {shape:?}"
            )));
        }
    }
    let mut positions = Vec::with_capacity(view.shape()[0]);
    for (vertex, row) in view.outer_iter().enumerate() {
        let p = [row[0], row[1], row[2]];
        if let Some(value) = p.iter().find(|x| !x.is_finite()) {
            return Err(errors::input(format!(
                "vertex {vertex} has a non-finite coordinate {value}"
            )));
        }
        positions.push(p);
    }
    Ok(positions)
}

/// The corner buffer and, unless every face is a triangle, the face starts.
fn faces_of(
    faces: &Bound<'_, PyAny>,
    vertex_count: usize,
) -> PyResult<(Vec<u32>, Option<Vec<u32>>)> {
    if let Some(array) = integer_matrix(faces)? {
        let view = array.readonly();
        let view = view.as_array();
        let [count, size] = [view.shape()[0], view.shape()[1]];
        if size < 3 {
            return Err(errors::input(format!(
                "faces must have at least 3 corners each, not an array of shape ({count}, {size})"
            )));
        }
        let mut corners = Vec::with_capacity(count * size);
        for (face, row) in view.outer_iter().enumerate() {
            for &index in row {
                corners.push(vertex_index(face, index, vertex_count)?);
            }
        }
        let starts = (size != 3).then(|| (0..=count).map(|f| (f * size) as u32).collect());
        return Ok((corners, starts));
    }
    let mut corners = Vec::new();
    let mut starts = vec![0];
    for (face, polygon) in faces.try_iter()?.enumerate() {
        let polygon: Vec<i64> = polygon?.extract().map_err(|error| {
            errors::input(format!(
                "face {face} is not a sequence of vertex indices: {error}"
            ))
        })?;
        for index in polygon {
            corners.push(vertex_index(face, index, vertex_count)?);
        }
        starts.push(u32::try_from(corners.len()).map_err(|_| errors::input("too many corners"))?);
    }
    Ok((corners, Some(starts)))
}

/// `faces` as a 2-D int64 array when it is an integer array of two dimensions or a sequence
/// NumPy reads as one; `None` for polygons of different sizes.
fn integer_matrix<'py>(faces: &Bound<'py, PyAny>) -> PyResult<Option<Bound<'py, PyArray2<i64>>>> {
    let py = faces.py();
    let array = match faces.cast::<PyUntypedArray>() {
        Ok(array) => array.clone(),
        Err(_) => match py.import("numpy")?.call_method1("asarray", (faces,)) {
            Ok(array) => array.cast_into::<PyUntypedArray>()?,
            // Ragged polygons: NumPy refuses to make one array of them.
            Err(_) => return Ok(None),
        },
    };
    let kind = array.dtype().kind();
    if array.ndim() != 2 {
        return Ok(None);
    }
    if kind != b'i' && kind != b'u' {
        return Err(errors::input(format!(
            "faces must be integer vertex indices, not {}",
            array.dtype()
        )));
    }
    let converted = array.call_method1("astype", ("int64",))?;
    Ok(Some(converted.cast_into::<PyArray2<i64>>()?))
}

/// `index` as a vertex index of a mesh of `vertex_count` vertices.
fn vertex_index(face: usize, index: i64, vertex_count: usize) -> PyResult<u32> {
    match usize::try_from(index) {
        Ok(i) if i < vertex_count => Ok(i as u32),
        _ => Err(errors::input(format!(
            "face {face} refers to vertex {index}, but there are {vertex_count} vertices"
        ))),
    }
}

/// The list of operands `meshes`, each converted; an error names the operand.
pub fn extract_operands(meshes: &Bound<'_, PyAny>) -> PyResult<Vec<Mesh>> {
    let mut operands = Vec::new();
    for (k, operand) in meshes.try_iter()?.enumerate() {
        let mesh = extract_mesh(&operand?)
            .map_err(|error| errors::with_prefix(error, &format!("operand {k}")))?;
        operands.push(mesh);
    }
    Ok(operands)
}
