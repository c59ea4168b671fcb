//! Runs a computation with the GIL released, reporting to an optional Python callback.
//!
//! The callback receives `(stage, done, total)`, the library's [`Report`] with the stage's
//! snake_case name, and returns `False` to cancel. The library calls it from whichever worker
//! thread finished a chunk of work, so it re-attaches to the interpreter for each call; that
//! the calling thread released the GIL is what lets those threads attach at all. An exception
//! the callback raises cancels the run and is raised in place of the cancellation.

use std::sync::{Mutex, PoisonError};

use csgkit::{Progress, Report};
use pyo3::prelude::*;
use pyo3::types::PyBool;

use crate::errors;

/// Runs `work` detached from the interpreter with a [`Progress`] that reports to `callback`
/// (when given), and maps its error to the Python exception of its kind.
pub fn detached<T: Send>(
    py: Python<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Progress) -> Result<T, csgkit::Error> + Send,
) -> PyResult<T> {
    let callback: Option<Py<PyAny>> = callback.map(|c| c.clone().unbind());
    let raised: Mutex<Option<PyErr>> = Mutex::new(None);
    let report = |report: Report| -> bool {
        let Some(callback) = &callback else {
            return true;
        };
        Python::attach(|py| {
            let args = (report.stage.to_string(), report.done, report.total);
            match callback.call1(py, args) {
                Ok(answer) => !answer.bind(py).is(PyBool::new(py, false)),
                Err(error) => {
                    let mut raised = raised.lock().unwrap_or_else(PoisonError::into_inner);
                    raised.get_or_insert(error);
                    false
                }
            }
        })
    };
    let progress = match callback {
        Some(_) => Progress::new(&report),
        None => Progress::default(),
    };
    let result = py.detach(|| work(&progress));
    if let Some(error) = raised.into_inner().unwrap_or_else(PoisonError::into_inner) {
        return Err(error);
    }
    result.map_err(errors::from_library)
}
