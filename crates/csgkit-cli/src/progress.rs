//! Progress bars on stderr for long operations, drawn by `indicatif`.
//!
//! The library reports progress through callbacks `(stage, done, total) -> keep going`; the
//! command names the stage and this adapter turns the reports into one bar per stage. Bars are
//! hidden when stderr is not a terminal (indicatif's default), so piped and scripted runs stay
//! quiet.

use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressStyle};

/// A bar that follows the stages a long operation reports, one after the other.
pub struct StageBar {
    current: Mutex<Option<(String, ProgressBar)>>,
}

impl StageBar {
    /// A bar for an operation on `size` items; none is drawn below `min_size` items, where
    /// the operation ends before a bar would help.
    pub fn new(size: usize, min_size: usize) -> Option<Self> {
        (size >= min_size).then(|| Self {
            current: Mutex::new(None),
        })
    }

    /// Records that `stage` has done `done` of `total` units; never cancels.
    pub fn update(&self, stage: &str, done: usize, total: usize) -> bool {
        let mut current = self.current.lock().unwrap_or_else(|e| e.into_inner());
        let same_stage = matches!(&*current, Some((name, _)) if name == stage);
        if !same_stage {
            if let Some((_, bar)) = current.take() {
                bar.finish();
            }
            let bar = ProgressBar::new(total as u64)
                .with_style(style())
                .with_prefix(stage.to_owned());
            *current = Some((stage.to_owned(), bar));
        }
        if let Some((_, bar)) = &*current {
            bar.set_position(done as u64);
        }
        true
    }

    /// Ends the last stage's bar.
    pub fn finish(&self) {
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
