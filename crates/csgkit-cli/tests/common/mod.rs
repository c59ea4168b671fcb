//! Helpers the end-to-end tests of the binary share: running it and passing paths to it.

use std::path::Path;
use std::process::{Command, Output};

/// Runs the built binary with `args`.
pub fn csgkit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_csgkit"))
        .args(args)
        .output()
        .expect("the csgkit binary runs")
}

/// Runs the built binary and asserts that it succeeds.
pub fn csgkit_ok(args: &[&str]) -> Output {
    let output = csgkit(args);
    assert!(
        output.status.success(),
        "csgkit {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// A path as the `&str` the command line takes.
pub fn arg(path: &Path) -> &str {
    path.to_str().expect("temporary paths are UTF-8")
}
