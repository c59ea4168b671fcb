//! Progress bars on stderr for long operations, drawn by `indicatif`.
//!
//! The library reports progress through one context, [`csgkit::Progress`], whose callback
//! receives a [`Report`] (stage, done, total) from inside the long stages; [`with_bar`] turns
//! the reports into one bar per stage. Bars are hidden when stderr is not a terminal
//! (indicatif's default), so piped and scripted runs stay quiet. The command line never
//! cancels.

use std::sync::Mutex;

use csgkit::{Progress, Report, Stage};
use indicatif::{ProgressBar, ProgressStyle};

/// Runs `work` with the library's progress context, drawing a bar per stage when the work is
/// on at least `min_size` items (`size`), where it lasts long enough for a bar to help.
pub fn with_bar<T>(size: usize, min_size: usize, work: impl FnOnce(&Progress) -> T) -> T {
    let bar = StageBar::new(size, min_size);
    let show = |report: Report| {
        if let Some(bar) = &bar {
            bar.update(report);
        }
        true
    };
    let out = work(&Progress::new(&show));
    bar.inspect(StageBar::finish);
    out
}

/// A bar that follows the stages a long operation reports, one after the other.
struct StageBar {
    current: Mutex<Option<(Stage, ProgressBar)>>,
}

impl StageBar {
    /// A bar for an operation on `size` items; none below `min_size` items.
    fn new(size: usize, min_size: usize) -> Option<Self> {
        (size >= min_size).then(|| Self {
            current: Mutex::new(None),
        })
    }

    /// Draws `report`: a new bar when its stage is not the current one.
    fn update(&self, report: Report) {
        let mut current = self.current.lock().unwrap_or_else(|e| e.into_inner());
        let same_stage = matches!(&*current, Some((stage, _)) if *stage == report.stage);
        if !same_stage {
            if let Some((_, bar)) = current.take() {
                bar.finish();
            }
            let bar = ProgressBar::new(report.total as u64)
                .with_style(style())
                .with_prefix(report.stage.to_string());
            *current = Some((report.stage, bar));
        }
        if let Some((_, bar)) = &*current {
            // A stage may count in several passes (the exact engine's classification falls
            // back to winding numbers), each with its own total.
            bar.set_length(report.total as u64);
            bar.set_position(report.done as u64);
        }
    }

    /// Ends the last stage's bar.
    fn finish(&self) {
        let mut current = self.current.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, bar)) = current.take() {
            bar.finish();
        }
    }
}

fn style() -> ProgressStyle {
    ProgressStyle::with_template("{prefix:>8} [{bar:30}] {percent:>3}% {elapsed_precise}")
        .expect("the template is valid")
        .progress_chars("=> ")
}

/// The seconds `stage` took in `stage_seconds` (0 when it did not run).
pub fn seconds_of(stage_seconds: &[(Stage, f64)], stage: Stage) -> f64 {
    (stage_seconds.iter())
        .filter(|(s, _)| *s == stage)
        .map(|(_, seconds)| seconds)
        .sum()
}
