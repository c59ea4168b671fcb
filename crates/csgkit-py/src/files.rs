//! Files and reports: `load` and `save` through the library's generic [`read_mesh`] and
//! [`write_mesh`] (the format follows the extension and the content, so a format the
//! library learns is read and written here without a change), and `check`, the report of
//! `csgkit check --json`.

use std::ffi::CString;
use std::path::PathBuf;

use csgkit::mesh::analyze;
use csgkit::{Encoding, WriteOptions, read_mesh, write_mesh};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::detach::detached;
use crate::errors;
use crate::mesh::{PyMesh, extract_mesh};

/// Reads a mesh file in any format the library reads (OBJ, STL, PLY, OFF, 3MF, glTF, …),
/// chosen by the extension, or by the content where it says otherwise; the parts of a file
/// that holds several (3MF build items, glTF nodes) become one mesh. Raises ReadError naming
/// the file and the line or byte at fault.
///
/// >>> import csgkit, tempfile, os
/// >>> path = os.path.join(tempfile.mkdtemp(), "box.ply")
/// >>> csgkit.save(csgkit.boxes([[0, 0, 0, 1, 2, 3]]), path)
/// >>> csgkit.load(path).face_count
/// 6
#[pyfunction]
pub fn load(py: Python<'_>, path: PathBuf) -> PyResult<PyMesh> {
    let loaded = detached(py, None, |_| Ok(read_mesh(&path)?))?;
    PyMesh::from_mesh(py, loaded.mesh)
}

/// Writes a mesh (a csgkit.Mesh or anything `boolean` takes) in the format its extension
/// names (OBJ, STL, PLY, OFF, 3MF, glTF, …), whole or not at all (through a temporary file
/// renamed over `path`). STL and PLY are binary unless `ascii`. PLY keeps each face's
/// provenance, so a chain of booleans through PLY files merges split faces back. Formats that
/// store float32 (glTF, binary STL) round coordinates, and a `UserWarning` says how many.
/// Raises WriteError.
#[pyfunction]
#[pyo3(signature = (mesh, path, *, ascii=false))]
pub fn save(py: Python<'_>, mesh: &Bound<'_, PyAny>, path: PathBuf, ascii: bool) -> PyResult<()> {
    let mesh = extract_mesh(mesh)?;
    let options = WriteOptions {
        encoding: if ascii {
            Encoding::Ascii
        } else {
            Encoding::Binary
        },
        ..WriteOptions::default()
    };
    let written = detached(py, None, |_| Ok(write_mesh(&path, &mesh, options)?))?;
    if written.rounded_coordinates > 0 {
        let message = format!(
            "{} stores float32: {} of {} coordinates were rounded",
            path.display(),
            written.rounded_coordinates,
            3 * mesh.vertex_count()
        );
        let message = CString::new(message).map_err(|error| errors::input(error.to_string()))?;
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &message, 1)?;
    }
    Ok(())
}

/// Every validity check and measure of a mesh, as `csgkit check --json` reports them: a
/// dict with `vertices`, `faces`, `closed`, `oriented`, `valid_solid` (closed and
/// consistently oriented), `edge_manifold`, `components`, `genus`, `volume`, `area`, `bbox`,
/// … and, from the exact self-intersection check, `selfint_pairs`, `selfint_faces` and
/// `invalid_polygons` (each polygon whose projection overlaps itself, as `face` and
/// `problem`).
///
/// `mesh` is a path (then vertices are counted as the file stores them, three per STL
/// facet) or anything `boolean` takes. `self_intersections=False` skips the exact check,
/// which costs about as much as a boolean, and leaves its keys out. The GIL is released
/// while it runs.
///
/// >>> import csgkit
/// >>> report = csgkit.check(csgkit.boxes([[0, 0, 0, 1, 1, 1]]))
/// >>> report["valid_solid"], report["volume"], report["selfint_pairs"]
/// (True, 1.0, 0)
#[pyfunction]
#[pyo3(signature = (mesh, *, self_intersections=true))]
pub fn check<'py>(
    py: Python<'py>,
    mesh: &Bound<'py, PyAny>,
    self_intersections: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let (mesh, file_vertices) = match mesh.extract::<PathBuf>() {
        Ok(path) => {
            let loaded = detached(py, None, |_| Ok(read_mesh(&path)?))?;
            (loaded.mesh, Some(loaded.raw_vertex_count))
        }
        Err(_) => (extract_mesh(mesh)?, None),
    };
    let (report, crossings) = detached(py, None, |_| {
        let mut report = analyze(&mesh);
        if let Some(count) = file_vertices {
            report.count_file_vertices(count);
        }
        let crossings = self_intersections.then(|| csgkit::self_intersections(&mesh));
        Ok((report, crossings))
    })?;
    let dict = pythonize::pythonize(py, &report)?.cast_into::<PyDict>()?;
    if let Some(crossings) = crossings {
        dict.set_item("selfint_pairs", crossings.pair_count())?;
        dict.set_item("selfint_faces", crossings.face_count())?;
        let invalid = PyList::empty(py);
        for error in &crossings.invalid_polygons {
            let polygon = PyDict::new(py);
            polygon.set_item("face", error.face().get())?;
            polygon.set_item("problem", error.to_string())?;
            invalid.append(polygon)?;
        }
        dict.set_item("invalid_polygons", invalid)?;
    }
    Ok(dict)
}
