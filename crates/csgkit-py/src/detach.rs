//! Runs a computation with the GIL released, reporting to an optional Python callback.
//!
//! The callback receives `(stage, done, total)`, the library's [`Report`] with the stage's
//! snake_case name, and returns `False` to cancel. The library calls it from whichever worker
//! thread finished a chunk of work, so it re-attaches to the interpreter for each call; that
//! the calling thread released the GIL is what lets those threads attach at all. An exception
//! the callback raises cancels the run and is raised in place of the cancellation.
//!
//! Ctrl-C cancels too. The interpreter runs signal handlers only on the main thread and only
//! when that thread asks, so the work runs on a worker of rayon's pool (the one the library's
//! parallel stages use) while the calling thread waits for it, waking every [`SIGNAL_POLL`]
//! to let the interpreter check its signals; a `KeyboardInterrupt` (or any exception a signal
//! handler raises) cancels the run at its next progress poll and is raised in place of the
//! cancellation. A pool worker rather than a thread of its own: spawning and joining one
//! costs about 67 µs here, as much as the whole boolean of two touching cubes, and waking a
//! worker a fraction of that.

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
    // Set by the worker once the run is over, by return or by unwinding, before it wakes the
    // waiting thread, which reads it after each wake-up: the wait ends with the run, not a
    // poll later (waiting until the worker's thread itself had exited, as this did once, lost
    // that race nearly every time and made every call last at least one poll, 50 ms).
    let finished = AtomicBool::new(false);
    let mut result = None;
    py.detach(|| {
        if rayon::current_thread_index().is_some() {
            // Called from a pool worker (a progress callback that runs a boolean): a job
            // spawned here would wait on this worker's queue while it waits for the job. No
            // signal to poll: only the main thread runs their handlers.
            result = Some(work(&progress));
            return;
        }
        let waiting = std::thread::current();
        // The scope's own closure runs on this thread (`in_place_scope`); its end waits for
        // the spawned run, over by then, and rethrows a panic of it.
        rayon::in_place_scope(|scope| {
            scope.spawn(|_| {
                let _finished = OnDrop(|| {
                    finished.store(true, Ordering::Release);
                    waiting.unpark();
                });
                result = Some(work(&progress));
            });
            loop {
                std::thread::park_timeout(SIGNAL_POLL);
                if finished.load(Ordering::Acquire) {
                    break;
                }
                if let Err(error) = Python::attach(|py| py.check_signals()) {
                    keep(error);
                    interrupted.store(true, Ordering::Relaxed);
                }
            }
        })
    });
    let result = result.expect("the run returned, or its panic was rethrown");
    if let Some(error) = raised.into_inner().unwrap_or_else(PoisonError::into_inner) {
        return Err(error);
    }
    result.map_err(errors::from_library)
}

/// Calls its closure when dropped: at the end of a run, by return or by unwinding.
struct OnDrop<F: FnMut()>(F);

impl<F: FnMut()> Drop for OnDrop<F> {
    fn drop(&mut self) {
        (self.0)();
    }
}
