//! The operations: exact booleans through [`ExactEngine`], box unions through the orthogonal
//! engine, voxelization through [`DiscreteEngine`]; each runs with the GIL released.
//!
//! The booleans take their options as keyword arguments, parsed once by [`BooleanArgs`] for
//! `boolean` and its four shorthands; the type stubs spell them out.

use std::path::PathBuf;

use csgkit::exact::{BooleanOptions, WindingRule};
use csgkit::mesh::FaceMode;
use csgkit::ortho::{BoxFile, MeshOptions, box_union_mesh, read_box_file, with_palette_colors};
use csgkit::{
    DiscreteEngine, DiscreteSurface, Engine, ErrorKind, ExactEngine, Mesh, Operation, Precision,
};
use numpy::{AllowTypeChange, PyArrayLikeDyn};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::detach::detached;
use crate::errors;
use crate::mesh::{PyMesh, extract_operands};

/// The options of the exact booleans, from keyword arguments.
struct BooleanArgs<'py> {
    options: BooleanOptions,
    progress: Option<Bound<'py, PyAny>>,
}

impl<'py> BooleanArgs<'py> {
    /// Reads `winding`, `faces`, `self_check`, `manifold`, `merge_coplanar`, `simplify`,
    /// `precision` and `progress`; any other keyword is a `TypeError`, as for a Python
    /// function.
    fn from_kwargs(kwargs: Option<&Bound<'py, PyDict>>) -> PyResult<Self> {
        let mut args = BooleanArgs {
            options: BooleanOptions::default(),
            progress: None,
        };
        for (key, value) in kwargs.into_iter().flatten() {
            let key: String = key.extract()?;
            let wrong_type = |error: PyErr| PyTypeError::new_err(format!("{key}: {error}"));
            let options = &mut args.options;
            match key.as_str() {
                "winding" => {
                    options.winding = winding(&value.extract::<String>().map_err(wrong_type)?)?
                }
                "faces" => {
                    options.faces = face_mode(&value.extract::<String>().map_err(wrong_type)?)?
                }
                "self_check" => {
                    options.check_self_intersections = value.extract().map_err(wrong_type)?
                }
                "manifold" => options.split_non_manifold = value.extract().map_err(wrong_type)?,
                "merge_coplanar" => options.merge_coplanar = value.extract().map_err(wrong_type)?,
                "simplify" => options.simplify = simplify(value.extract().map_err(wrong_type)?)?,
                "precision" => {
                    options.precision = precision(&value.extract::<String>().map_err(wrong_type)?)?
                }
                "progress" => args.progress = (!value.is_none()).then_some(value),
                _ => {
                    return Err(PyTypeError::new_err(format!(
                        "unexpected keyword argument '{key}'"
                    )));
                }
            }
        }
        Ok(args)
    }
}

/// The winding rule named `name`.
fn winding(name: &str) -> PyResult<WindingRule> {
    match name {
        "nonzero" => Ok(WindingRule::NonZero),
        "positive" => Ok(WindingRule::Positive),
        _ => Err(errors::input(format!(
            "unknown winding rule '{name}': expected 'nonzero' or 'positive'"
        ))),
    }
}

/// The precision named `name`.
fn precision(name: &str) -> PyResult<Precision> {
    match name {
        "f64" => Ok(Precision::F64),
        "f32" => Ok(Precision::F32),
        _ => Err(errors::input(format!(
            "unknown precision '{name}': expected 'f64' or 'f32'"
        ))),
    }
}

/// The face mode named `name`.
fn face_mode(name: &str) -> PyResult<FaceMode> {
    match name {
        "triangles" => Ok(FaceMode::Triangles),
        "polygons" => Ok(FaceMode::Polygons),
        "quads" => Ok(FaceMode::Quads),
        _ => Err(errors::input(format!(
            "unknown face mode '{name}': expected 'triangles', 'polygons' or 'quads'"
        ))),
    }
}

/// A simplification tolerance: a positive length, or none.
fn simplify(tolerance: Option<f64>) -> PyResult<Option<f64>> {
    match tolerance {
        Some(t) if !(t.is_finite() && t > 0.0) => Err(errors::input(format!(
            "simplify must be a positive length, not {t}"
        ))),
        tolerance => Ok(tolerance),
    }
}

/// The operation named `name`.
fn operation(name: &str) -> PyResult<Operation> {
    (Operation::ALL.into_iter())
        .find(|op| op.name() == name)
        .ok_or_else(|| {
            errors::input(format!(
                "unknown operation '{name}': expected 'union', 'intersection', 'difference' or 'xor'"
            ))
        })
}

/// Runs `op` on the operands through the exact engine.
fn exact(
    py: Python<'_>,
    op: Operation,
    meshes: &Bound<'_, PyAny>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyMesh> {
    let args = BooleanArgs::from_kwargs(kwargs)?;
    let meshes = extract_operands(meshes)?;
    let engine = ExactEngine {
        options: args.options,
    };
    let output = detached(py, args.progress.as_ref(), |progress| {
        let operands: Vec<&Mesh> = meshes.iter().collect();
        engine.apply(op, &operands, progress)
    })?;
    PyMesh::from_output(py, output)
}

/// The exact boolean `operation` ('union', 'intersection', 'difference' or 'xor') of
/// `meshes`, any number of closed meshes, in one pass.
///
/// A difference is the first mesh minus all others; xor keeps the points in an odd number of
/// meshes. Each mesh is a `csgkit.Mesh`, a `(vertices, faces)` pair of arrays, or an object
/// with `vertices` and `faces` (a `trimesh.Trimesh`). Every decision is exact on the float64
/// input, and the result is certified as float64 numbers (float32 with precision='f32'):
/// closed, consistently oriented, without self-intersections. Its faces carry the materials, UVs and provenance of the
/// input faces they were cut from.
///
/// Keyword options, as the command line's:
///   winding='nonzero' | 'positive': which winding numbers are inside a mesh whose faces
///     cross or whose shells nest (`--winding`);
///   faces='triangles' | 'polygons' | 'quads': the faces of the result (`--triangles`,
///     `--polygons`, `--quads`);
///   self_check=True: find and resolve each mesh's self-intersections (False:
///     `--no-self-check`, faster, wrong without an error if a mesh intersects itself);
///   manifold=False: split non-manifold edges and vertices (`--manifold`);
///   merge_coplanar=False: merge neighbouring faces in one plane (`--merge-coplanar`);
///   simplify=None: a length; merge faces flat to within it (`--simplify`);
///   precision='f64' | 'f32': the numbers the result is rounded to and certified in; 'f32'
///     for a result saved as binary STL or glTF (which store float32, as the command line
///     does for those files) or used as float32 arrays;
///   progress=None: a callable taking (stage, done, total), returning False to cancel.
///
/// The GIL is released while it runs. Raises InputError for bad arrays, an unknown name or
/// a mesh that is not closed (the message names the operand), CancelledError when progress
/// returns False, CsgkitError otherwise.
///
/// >>> import csgkit, numpy as np
/// >>> def cube(x):
/// ...     v = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
/// ...     f = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
/// ...     return (v + [x, 0, 0], f)
/// >>> csgkit.check(csgkit.boolean("union", [cube(0), cube(0.5)]))["volume"]
/// 1.5
#[pyfunction]
#[pyo3(signature = (operation, meshes, **options))]
#[pyo3(
    text_signature = "(operation, meshes, *, winding='nonzero', faces='triangles', self_check=True, manifold=False, merge_coplanar=False, simplify=None, precision='f64', progress=None)"
)]
pub fn boolean(
    py: Python<'_>,
    operation: &str,
    meshes: &Bound<'_, PyAny>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyMesh> {
    exact(py, self::operation(operation)?, meshes, options)
}

/// Defines the shorthand of `boolean` for one operation.
macro_rules! shorthand {
    ($name:ident, $operation:expr, $doc:literal) => {
        #[doc = $doc]
        ///
        /// Takes the keyword options of `boolean`; see its documentation.
        #[pyfunction]
        #[pyo3(signature = (*meshes, **options))]
        #[pyo3(
            text_signature = "(*meshes, winding='nonzero', faces='triangles', self_check=True, manifold=False, merge_coplanar=False, simplify=None, precision='f64', progress=None)"
        )]
        pub fn $name(
            py: Python<'_>,
            meshes: &Bound<'_, PyTuple>,
            options: Option<&Bound<'_, PyDict>>,
        ) -> PyResult<PyMesh> {
            exact(py, $operation, meshes.as_any(), options)
        }
    };
}

shorthand!(
    union,
    Operation::Union,
    "The exact union of the meshes: `csgkit.union(a, b, c)` is `boolean('union', [a, b, c])`."
);
shorthand!(
    intersection,
    Operation::Intersection,
    "The exact intersection of the meshes: `boolean('intersection', meshes)`."
);
shorthand!(
    difference,
    Operation::Difference,
    "The first mesh minus all the others, exactly: `boolean('difference', meshes)`."
);
shorthand!(
    xor,
    Operation::Xor,
    "The points in an odd number of the meshes, exactly: `boolean('xor', meshes)`."
);

/// The boxes of an (n, 6) array of `[x0, y0, z0, x1, y1, z1]` rows.
fn boxes_of_array(boxes: &Bound<'_, PyAny>) -> PyResult<BoxFile> {
    let array: PyArrayLikeDyn<'_, f64, AllowTypeChange> = boxes
        .extract()
        .map_err(|error| errors::input(format!("boxes: {error}")))?;
    let view = array.as_array();
    let boxes = match view.shape() {
        [_, 6] => (view.outer_iter())
            .map(|b| [b[0], b[1], b[2], b[3], b[4], b[5]])
            .collect(),
        [0] => Vec::new(),
        shape => {
            return Err(errors::input(format!(
                "boxes must be an array of shape (n, 6), not {shape:?}"
            )));
        }
    };
    Ok(BoxFile {
        boxes,
        ..BoxFile::default()
    })
}

/// A MagicaVoxel `.vox` file (by extension or content; model `model` alone if given), or a
/// text file of `x0 y0 z0 x1 y1 z1` lines, as `csgkit boxes` reads them; errors name the file.
fn boxes_of_file(path: PathBuf, model: Option<usize>) -> PyResult<BoxFile> {
    let in_file = |kind: ErrorKind, message: &dyn std::fmt::Display| {
        errors::exception(kind, format!("{}: {message}", path.display()))
    };
    let bytes = std::fs::read(&path).map_err(|error| in_file(ErrorKind::Read, &error))?;
    let vox = (path.extension()).is_some_and(|e| e.eq_ignore_ascii_case("vox"));
    read_box_file(&bytes, vox, model).map_err(|error| {
        let error = csgkit::Error::from(error);
        in_file(error.kind(), &error)
    })
}

/// The exact union of axis-aligned boxes through the orthogonal engine, as a mesh of
/// maximal faces.
///
/// `boxes` is an (n, 6) array of `[x0, y0, z0, x1, y1, z1]` rows, or the path of a
/// MagicaVoxel `.vox` file (voxels become unit boxes; faces get the material and colour of
/// their voxels; `model` takes one model of the file alone) or of a text file with one box
/// per line. Faces are polygons (those with holes triangulated) unless `triangles`;
/// `manifold` splits non-manifold edges and vertices (and implies triangles). The GIL is
/// released while it runs.
///
/// >>> import csgkit
/// >>> union = csgkit.boxes([[0, 0, 0, 2, 2, 2], [1, 1, 1, 3, 3, 3]])
/// >>> csgkit.check(union)["volume"]
/// 15.0
#[pyfunction]
#[pyo3(signature = (boxes, *, triangles=false, manifold=false, model=None, progress=None))]
pub fn boxes(
    py: Python<'_>,
    boxes: &Bound<'_, PyAny>,
    triangles: bool,
    manifold: bool,
    model: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyMesh> {
    let input = match boxes.extract::<PathBuf>() {
        Ok(path) => boxes_of_file(path, model)?,
        Err(_) => boxes_of_array(boxes)?,
    };
    let options = MeshOptions {
        triangles: triangles || manifold,
        manifold,
    };
    let (mesh, stage_seconds) = detached(py, progress, |progress| {
        let materials = input.materials.as_deref();
        let (out, stage_seconds) = box_union_mesh(&input.boxes, materials, options, progress)?;
        let mesh = match &input.palette {
            Some(palette) => with_palette_colors(out.mesh, palette),
            None => out.mesh,
        };
        Ok((mesh, stage_seconds))
    })?;
    PyMesh::computed(py, mesh, Some(stage_seconds))
}

/// The voxels of a closed mesh whose centres are inside it, on a grid of cell size `cell`
/// anchored at the origin, as a closed mesh, through the discrete engine (as
/// `csgkit discrete voxelize`).
///
/// `surface='ortho'` gives maximal faces through the orthogonal engine; 'surfels' gives the
/// unit faces of the voxels, faster on very fine grids. The GIL is released while it runs.
///
/// >>> import csgkit
/// >>> cube = csgkit.boxes([[0, 0, 0, 1, 1, 1]], triangles=True)
/// >>> csgkit.check(csgkit.voxelize(cube, 0.25))["volume"]
/// 1.0
#[pyfunction]
#[pyo3(signature = (mesh, cell, *, surface="ortho", progress=None))]
pub fn voxelize(
    py: Python<'_>,
    mesh: &Bound<'_, PyAny>,
    cell: f64,
    surface: &str,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyMesh> {
    let surface = match surface {
        "ortho" => DiscreteSurface::Ortho,
        "surfels" => DiscreteSurface::Surfels,
        _ => {
            return Err(errors::input(format!(
                "unknown surface '{surface}': expected 'ortho' or 'surfels'"
            )));
        }
    };
    let mesh = crate::mesh::extract_mesh(mesh)?;
    let engine = DiscreteEngine {
        surface,
        ..DiscreteEngine::with_cell(cell)
    };
    let output = detached(py, progress, |progress| {
        engine.apply(Operation::Union, &[&mesh], progress)
    })?;
    PyMesh::from_output(py, output)
}
