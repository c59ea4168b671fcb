//! Progress reports and cancellation: one mechanism for every engine. The contract is on
//! [`Progress`], which the crate root re-exports with [`Report`], [`Stage`] and
//! [`Cancelled`]; [`Counter`] and [`StageClock`] are how the stages keep it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use web_time::Instant;

use crate::par;

/// A stage of an engine, as reported to a [`Progress`] callback and timed in each engine's
/// statistics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Stage {
    /// Exact engine: welding, triangulation of polygons, removal of degenerate triangles,
    /// closedness (1 of 1).
    Ingest,
    /// Exact engine: the exact self-intersection check of every operand, and the search for
    /// nested shells (units: operands).
    Validate,
    /// Exact engine: candidate triangle pairs from bounding boxes (1 of 1).
    Broad,
    /// Exact engine: exact triangle–triangle intersection of the candidates (units: pairs).
    Intersect,
    /// Exact engine: constrained triangulation of every triangle that meets another operand
    /// (units: triangles).
    Split,
    /// Exact engine: patches and their inside / outside / on labels, or their winding numbers
    /// (units: patches and rays).
    Classify,
    /// Exact engine: the output face of every kept sub-triangle, and the removal of the
    /// intersection points no face needs (1 of 1).
    Reconstruct,
    /// Exact engine: rounding to f64 and the output mesh (1 of 1).
    Assemble,
    /// Exact engine: faces flat to within `BooleanOptions::simplify` merged, and the vertices
    /// only they need removed, when asked (1 of 1).
    Simplify,
    /// Exact engine: the output checked as f64 numbers and repaired where rounding folded or
    /// collapsed it (units: repair rounds, of at most a fixed number).
    Certify,
    /// Exact engine: the certified triangles merged into polygons or quads, and the optional
    /// 2-manifold split (1 of 1).
    Faces,
    /// Exact engine: face and corner attributes (materials, UVs, normals) from the source
    /// faces (1 of 1).
    Attributes,
    /// Orthogonal engine: ranking the box coordinates (1 of 1).
    Rank,
    /// Orthogonal engine: the octant-code sweep (units: z-planes).
    Sweep,
    /// Orthogonal engine: loop linking and hole assignment (units: face planes).
    Loops,
    /// Orthogonal engine: the B-rep as a mesh, faces with holes triangulated (1 of 1).
    Triangulate,
    /// Discrete engine: the operands' triangles cast onto the voxel columns (units:
    /// triangles of all operands).
    Discretize,
    /// Discrete engine: the operation on the solids, depth list by depth list (1 of 1).
    Combine,
    /// Discrete engine: the result's boundary as a mesh (1 of 1).
    Convert,
}

impl std::fmt::Display for Stage {
    /// The snake_case name ("ingest", "validate", …), as the command line's bars and `--stats`
    /// and the Python progress callback show it. It is derived from the variant's name, so a
    /// stage added later gets its own name without a change elsewhere.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, c) in format!("{self:?}").char_indices() {
            if c.is_ascii_uppercase() && i > 0 {
                f.write_str("_")?;
            }
            write!(f, "{}", c.to_ascii_lowercase())?;
        }
        Ok(())
    }
}

/// What a stage has done so far: `done` of `total` units (see [`Stage`] for each stage's
/// unit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Report {
    /// The stage running.
    pub stage: Stage,
    /// Units done, at most `total`.
    pub done: usize,
    /// Units the stage has (0 for a stage with nothing to do).
    pub total: usize,
}

/// The operation was cancelled: the progress callback returned `false`, or
/// [`Progress::cancel`] was called. Nothing was produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

/// The progress callback: receives a [`Report`], returns `false` to cancel.
pub type Callback<'a> = &'a (dyn Fn(Report) -> bool + Sync);

/// The progress and cancellation context of one operation, the one mechanism of every
/// engine.
///
/// A long operation takes a `&Progress`: an optional callback that receives a [`Report`]
/// (a [`Stage`] and how many of its units are done) and returns `false` to cancel, and a
/// cancelled flag that stays set. Stages report and poll *inside* their loops, not only
/// between stages: the parallel ones once per chunk of work, so polling costs one atomic
/// load per chunk and a cancellation takes effect within one chunk. Once the flag is set, the
/// remaining chunks are skipped and the operation returns [`Cancelled`] (wrapped in its
/// engine's error).
///
/// # The callback's contract
/// - It is called from whichever worker thread finished a chunk (hence `Sync`), one report at
///   a time, so it should be cheap; the reports of a stage arrive in order of `done`.
/// - Every stage that runs reports at least once, and last with `done == total`; a stage
///   without a natural unit (ingest, say) reports 1 of 1 when it ends. Stages come in
///   pipeline order, and a stage may be left out (the exact engine's `Simplify` runs only
///   when asked).
/// - Returning `false` cancels: the flag is set and every later poll fails. [`Progress::cancel`]
///   sets it from outside the callback, e.g. from another thread that holds the `Progress`.
///
/// Nested runs (the exact engine's re-refinement inside certification) poll the same flag
/// through a silent view of it but do not report, so the stages a caller sees are those of
/// the operation it asked for.
///
/// `Sync`, so the parallel stages poll it from every worker thread; `Clone` shares the flag.
#[derive(Clone, Default)]
pub struct Progress<'a> {
    callback: Option<Callback<'a>>,
    /// Shared with the [`silent`](Progress::silent) views of nested runs.
    cancelled: Arc<AtomicBool>,
}

impl std::fmt::Debug for Progress<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Progress")
            .field("callback", &self.callback.is_some())
            .field("cancelled", &self.is_cancelled())
            .finish()
    }
}

impl<'a> Progress<'a> {
    /// A context that reports to `callback`. [`Progress::default`] reports to nobody and is
    /// cancelled only by [`Progress::cancel`].
    ///
    /// # Example
    /// Stop the exact engine as soon as it starts intersecting triangles.
    /// ```
    /// use csgkit::exact::{BooleanError, BooleanOptions, boolean_expression, Expression};
    /// use csgkit::primitives::cuboid;
    /// use csgkit::{Cancelled, Operation, Progress, Report, Stage};
    /// let (a, b) = (cuboid([0.0; 3], [2.0; 3]), cuboid([1.0; 3], [3.0; 3]));
    /// let stop = |report: Report| report.stage != Stage::Intersect;
    /// let progress = Progress::new(&stop);
    /// let union = Expression::of(Operation::Union, 2);
    /// let result = boolean_expression(&union, &[&a, &b], &BooleanOptions::default(), &progress);
    /// assert_eq!(result.unwrap_err(), BooleanError::Cancelled(Cancelled));
    /// assert!(progress.is_cancelled());
    /// ```
    pub fn new(callback: Callback<'a>) -> Self {
        Self {
            callback: Some(callback),
            cancelled: Arc::default(),
        }
    }

    /// Cancels the operation: every later poll fails, whatever the callback says.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// True once the operation is cancelled.
    #[inline]
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// Polls the flag.
    ///
    /// # Errors
    /// [`Cancelled`] once the operation is cancelled.
    #[inline]
    pub fn check(&self) -> Result<(), Cancelled> {
        if self.is_cancelled() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }

    /// Reports that `stage` has done `done` of `total` units, and polls.
    ///
    /// # Errors
    /// [`Cancelled`] when the callback returns `false`, or the operation was cancelled before.
    pub fn report(&self, stage: Stage, done: usize, total: usize) -> Result<(), Cancelled> {
        if let Some(callback) = self.callback
            && !callback(Report { stage, done, total })
        {
            self.cancel();
        }
        self.check()
    }

    /// The same cancelled flag without the callback: for a nested run whose stages are not
    /// the caller's, which must stop when the caller's run is cancelled.
    pub(crate) fn silent(&self) -> Progress<'static> {
        Progress {
            callback: None,
            cancelled: Arc::clone(&self.cancelled),
        }
    }

    /// A counter of the `total` units of `stage`, reported as they are done.
    pub(crate) fn counter(&self, stage: Stage, total: usize) -> Counter<'_> {
        Counter {
            progress: self,
            stage,
            total,
            done: Mutex::new(0),
        }
    }
}

/// Counts the units of one stage as workers finish them, reporting each step.
pub(crate) struct Counter<'p> {
    progress: &'p Progress<'p>,
    stage: Stage,
    total: usize,
    /// Units done; held while reporting, so a stage's reports arrive in order.
    done: Mutex<usize>,
}

impl Counter<'_> {
    /// Records `n` more units done and reports the count (from any thread; one report at a
    /// time, in order, which costs nothing next to a chunk of work).
    pub(crate) fn advance(&self, n: usize) {
        // The lock is held through the report, so no later count is reported first.
        let mut done = self.done.lock().unwrap_or_else(|e| e.into_inner());
        *done += n;
        // A cancellation shows in the flag, which the loops poll.
        let _ = (self.progress).report(self.stage, (*done).min(self.total), self.total);
    }

    /// True once the operation is cancelled: the loops skip their remaining work.
    #[inline]
    pub(crate) fn is_cancelled(&self) -> bool {
        self.progress.is_cancelled()
    }

    /// Ends the stage: reports `total` of `total` unless a step already did, then polls.
    ///
    /// # Errors
    /// [`Cancelled`] once the operation is cancelled: the stage's result is incomplete.
    pub(crate) fn finish(self) -> Result<(), Cancelled> {
        self.progress.check()?;
        let done = *self.done.lock().unwrap_or_else(|e| e.into_inner());
        if done < self.total || self.total == 0 {
            self.progress.report(self.stage, self.total, self.total)?;
        }
        Ok(())
    }

    /// Runs `f` on `items` in parallel chunks ([`par::chunks`]), each appending its chunk's
    /// results to the vector it is given; returns the results in item order. A chunk is
    /// skipped once the operation is cancelled, and advances the count by its length when
    /// done, so after a cancellation the result is incomplete, which [`Counter::finish`]
    /// reports.
    pub(crate) fn par_chunks<T, R>(
        &self,
        items: &[T],
        f: impl Fn(&[T], &mut Vec<R>) + Sync,
    ) -> Vec<R>
    where
        T: Sync,
        R: Send,
    {
        par::chunks(items, |chunk, out| {
            if !self.is_cancelled() {
                f(chunk, out);
                self.advance(chunk.len());
            }
        })
    }
}

/// Times the consecutive stages of one run.
pub(crate) struct StageClock<'p> {
    progress: &'p Progress<'p>,
    start: Instant,
    seconds: Vec<(Stage, f64)>,
}

impl<'p> StageClock<'p> {
    /// A clock whose first stage starts now.
    pub(crate) fn new(progress: &'p Progress<'p>) -> Self {
        Self {
            progress,
            start: Instant::now(),
            seconds: Vec::new(),
        }
    }

    /// Ends a stage without units of its own: records its seconds and reports it done (1 of
    /// 1).
    ///
    /// # Errors
    /// [`Cancelled`] once the operation is cancelled.
    pub(crate) fn end(&mut self, stage: Stage) -> Result<(), Cancelled> {
        self.record(stage);
        self.progress.report(stage, 1, 1)
    }

    /// Ends a stage that reported its units through a [`Counter`]: records its seconds.
    pub(crate) fn record(&mut self, stage: Stage) {
        let now = Instant::now();
        self.seconds.push((stage, (now - self.start).as_secs_f64()));
        self.start = now;
    }

    /// The seconds of every stage ended, in order.
    pub(crate) fn into_seconds(self) -> Vec<(Stage, f64)> {
        self.seconds
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stage_names_are_snake_case() {
        let names: Vec<String> = [Stage::Ingest, Stage::Validate, Stage::Triangulate]
            .iter()
            .map(ToString::to_string)
            .collect();
        assert_eq!(names, ["ingest", "validate", "triangulate"]);
    }

    #[test]
    fn a_false_callback_cancels_for_good() {
        let stop = |r: Report| r.done < 3;
        let progress = Progress::new(&stop);
        let counter = progress.counter(Stage::Sweep, 10);
        counter.advance(2);
        assert!(!counter.is_cancelled());
        counter.advance(1);
        assert!(counter.is_cancelled());
        assert_eq!(counter.finish(), Err(Cancelled));
        assert_eq!(progress.report(Stage::Loops, 0, 1), Err(Cancelled));
        assert!(
            progress.silent().is_cancelled(),
            "a silent view shares the flag"
        );
    }

    /// Every report `work` makes through a recording context.
    fn recorded(work: impl FnOnce(&Progress)) -> Vec<Report> {
        let seen = std::sync::Mutex::new(Vec::new());
        let record = |r: Report| {
            seen.lock().unwrap().push(r);
            true
        };
        work(&Progress::new(&record));
        seen.into_inner().unwrap()
    }

    #[test]
    fn chunks_keep_item_order_and_count_every_item() {
        let items: Vec<u32> = (0..10_000).collect();
        let seen = recorded(|progress| {
            let counter = progress.counter(Stage::Intersect, items.len());
            let odd: Vec<u32> = counter.par_chunks(&items, |chunk, out| {
                out.extend(chunk.iter().filter(|&&x| x % 2 == 1));
            });
            counter.finish().unwrap();
            assert_eq!(odd, (0..10_000).filter(|x| x % 2 == 1).collect::<Vec<_>>());
        });
        assert!(
            seen.iter()
                .all(|r| r.stage == Stage::Intersect && r.total == 10_000)
        );
        let done: Vec<usize> = seen.iter().map(|r| r.done).collect();
        assert!(done.is_sorted(), "reports arrive in order");
        assert_eq!(done.last(), Some(&10_000), "the count reaches the total");
        assert_eq!(seen.iter().filter(|r| r.done == 10_000).count(), 1);
    }

    #[test]
    fn a_stage_with_nothing_to_do_still_reports() {
        let seen = recorded(|progress| {
            progress.counter(Stage::Split, 0).finish().unwrap();
            let mut clock = StageClock::new(progress);
            clock.end(Stage::Ingest).unwrap();
            assert_eq!(clock.into_seconds().len(), 1);
        });
        assert_eq!(
            seen,
            [
                Report {
                    stage: Stage::Split,
                    done: 0,
                    total: 0
                },
                Report {
                    stage: Stage::Ingest,
                    done: 1,
                    total: 1
                }
            ]
        );
    }
}
