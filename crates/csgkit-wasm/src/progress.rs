//! The optional JavaScript progress callback of a call: `progress(stage, done, total)`, called
//! synchronously from inside the library's stages (the stage's snake_case name, as the command
//! line's bars and the Python callback show it); returning `false`, or throwing, cancels, and
//! the call throws `CancelledError`.
//!
//! The library's [`Progress`] takes a `Sync` callback, which a JavaScript function is not. On
//! wasm32 everything runs on one thread, so the function waits in a thread-local for the
//! length of the call and a plain function (which is `Sync`) calls it from there.

use std::cell::RefCell;

use csgkit::{Progress, Report};
use wasm_bindgen::JsValue;

use crate::errors::{self, Result};

thread_local! {
    /// The callback of the call running, if it has one.
    static CALLBACK: RefCell<Option<js_sys::Function>> = const { RefCell::new(None) };
}

/// Runs `run` with a [`Progress`] that reports to `callback`; the library's error becomes the
/// exception of its kind.
pub(crate) fn with_progress<T>(
    callback: Option<js_sys::Function>,
    run: impl FnOnce(&Progress) -> std::result::Result<T, csgkit::Error>,
) -> Result<T> {
    let outer = CALLBACK.replace(callback);
    let result = run(&Progress::new(&report));
    // A callback may itself call csgkit (a nested call restores this one when it ends).
    CALLBACK.set(outer);
    result.map_err(errors::from_library)
}

/// Hands one report to the callback; `false` cancels.
fn report(report: Report) -> bool {
    // A copy of the handle, so the cell is not borrowed while JavaScript runs.
    let Some(callback) = CALLBACK.with_borrow(Clone::clone) else {
        return true;
    };
    callback
        .call3(
            &JsValue::NULL,
            &JsValue::from_str(&report.stage.to_string()),
            &JsValue::from(report.done as f64),
            &JsValue::from(report.total as f64),
        )
        .is_ok_and(|answer| answer.as_bool() != Some(false))
}
