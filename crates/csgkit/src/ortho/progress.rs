//! Progress reports and cancellation for long runs.
//!
//! The sweep and the loop extraction run as many independent tasks (planes); after each
//! task a [`Tracker`] counts it and calls the caller's [`ProgressFn`], from whichever thread
//! finished it. When the callback returns `false` the remaining tasks are skipped and the run
//! returns [`OrthoError::Cancelled`](super::OrthoError::Cancelled).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The stage a progress report is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Stage {
    /// The octant-code sweep: `done` of `total` z-planes.
    Sweep,
    /// Loop linking: `done` of `total` face planes.
    Loops,
}

/// A progress callback, called with `(stage, done, total)`; returning `false` cancels.
pub type ProgressFn<'a> = &'a (dyn Fn(Stage, usize, usize) -> bool + Sync);

/// Counts finished tasks of one stage and remembers a cancellation.
pub(crate) struct Tracker<'a> {
    progress: Option<ProgressFn<'a>>,
    stage: Stage,
    total: usize,
    done: AtomicUsize,
    cancelled: AtomicBool,
}

impl<'a> Tracker<'a> {
    pub(crate) fn new(progress: Option<ProgressFn<'a>>, stage: Stage, total: usize) -> Self {
        Self {
            progress,
            stage,
            total,
            done: AtomicUsize::new(0),
            cancelled: AtomicBool::new(false),
        }
    }

    /// Records one finished task and reports it.
    pub(crate) fn tick(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(report) = self.progress {
            if !report(self.stage, done, self.total) {
                self.cancelled.store(true, Ordering::Relaxed);
            }
        }
    }

    /// True once the callback has asked to stop.
    pub(crate) fn cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }
}
