//! Runs a computation with the GIL released, reporting to an optional Python callback.
//!
//! The callback receives `(stage, done, total)`, the library's [`Report`] with the stage's
//! snake_case name, and returns `False` to cancel. The library calls it from whichever worker
//! thread finished a chunk of work, so it re-attaches to the interpreter for each call; that
//! the calling thread released the GIL is what lets those threads attach at all. An exception
//! the callback raises cancels the run and is raised in place of the cancellation.
//!
//! Ctrl-C cancels too. The interpreter runs signal handlers only on the main thread and only
//! when that thread asks, so the work runs on a scoped thread while the calling thread waits
//! for it, waking every [`SIGNAL_POLL`] to let the interpreter check its signals; a
//! `KeyboardInterrupt` (or any exception a signal handler raises) cancels the run at its
//! next progress poll and is raised in place of the cancellation.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::Duration;

use csgkit::{Progress, Report};
use pyo3::prelude::*;
use pyo3::types::PyBool;

use crate::errors;

/// How often the waiting thread lets the interpreter run its signal handlers.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` detached from the interpreter with a [`Progress`] that reports to `callback`
/// (when given), and maps its error to the Python exception of its kind.
pub fn detached<T: Send>(
    py: Python<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Progress) -> Result<T, csgkit::Error> + Send,
) -> PyResult<T> {
    let callback: Option<Py<PyAny>> = callback.map(|c| c.clone().unbind());
    let raised: Mutex<Option<PyErr>> = Mutex::new(None);
    let interrupted = AtomicBool::new(false);
    let keep = |error: PyErr| {
        let mut raised = raised.lock().unwrap_or_else(PoisonError::into_inner);
        raised.get_or_insert(error);
    };
    let report = |report: Report| -> bool {
        if interrupted.load(Ordering::Relaxed) {
            return false;
        }
        let Some(callback) = &callback else {
            return true;
        };
        Python::attach(|py| {
            let args = (report.stage.to_string(), report.done, report.total);
            match callback.call1(py, args) {
                Ok(answer) => !answer.bind(py).is(PyBool::new(py, false)),
                Err(error) => {
                    keep(error);
                    false
                }
            }
        })
    };
    let progress = Progress::new(&report);
    let result = py.detach(|| {
        let waiting = std::thread::current();
        std::thread::scope(|scope| {
            let worker = scope.spawn(|| {
                let result = work(&progress);
                waiting.unpark();
                result
            });
            while !worker.is_finished() {
                std::thread::park_timeout(SIGNAL_POLL);
                if let Err(error) = Python::attach(|py| py.check_signals()) {
                    keep(error);
                    interrupted.store(true, Ordering::Relaxed);
                }
            }
            worker
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        })
    });
    if let Some(error) = raised.into_inner().unwrap_or_else(PoisonError::into_inner) {
        return Err(error);
    }
    result.map_err(errors::from_library)
}
