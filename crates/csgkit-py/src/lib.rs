//! `csgkit._csgkit`, the native module of the Python package `csgkit`: the library's engine
//! facade and file readers over NumPy arrays.
//!
//! # Layout
//! - `mesh`: the Python class `csgkit.Mesh` and the conversions between NumPy arrays and
//!   [`csgkit::Mesh`]; results hand their position and corner buffers to NumPy without a copy.
//! - `operations`: `boolean` and its four shorthands (the exact engine through
//!   [`csgkit::ExactEngine`]), `boxes` (the orthogonal engine), `voxelize` (the discrete engine
//!   through [`csgkit::DiscreteEngine`]).
//! - `files`: `load`, `save` (the library's generic [`csgkit::read_mesh`] and
//!   [`csgkit::write_mesh`], so every format they learn arrives here unchanged) and `check`
//!   ([`csgkit::mesh::analyze`] and the exact self-intersection check, as `csgkit check`).
//! - `detach`: every computation runs with the GIL released, reporting to an optional Python
//!   progress callback that can cancel it.
//! - `errors`: [`csgkit::Error`] to the exception classes of `csgkit/_errors.py`, with the
//!   library's messages.
//!
//! The Python package (`python/csgkit`) re-exports this module, adds the trimesh engine
//! (`csgkit.trimesh`) and carries the type stubs.

#![deny(unsafe_code)]

mod detach;
mod errors;
mod files;
mod mesh;
mod operations;

use pyo3::prelude::*;

/// The native module; `csgkit/__init__.py` re-exports its contents.
#[pymodule]
fn _csgkit(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    module.add_class::<mesh::PyMesh>()?;
    module.add_function(wrap_pyfunction!(mesh::_mesh_from_state, module)?)?;
    module.add_function(wrap_pyfunction!(operations::boolean, module)?)?;
    module.add_function(wrap_pyfunction!(operations::union, module)?)?;
    module.add_function(wrap_pyfunction!(operations::intersection, module)?)?;
    module.add_function(wrap_pyfunction!(operations::difference, module)?)?;
    module.add_function(wrap_pyfunction!(operations::xor, module)?)?;
    module.add_function(wrap_pyfunction!(operations::boxes, module)?)?;
    module.add_function(wrap_pyfunction!(operations::voxelize, module)?)?;
    module.add_function(wrap_pyfunction!(files::load, module)?)?;
    module.add_function(wrap_pyfunction!(files::save, module)?)?;
    module.add_function(wrap_pyfunction!(files::check, module)?)?;
    Ok(())
}
