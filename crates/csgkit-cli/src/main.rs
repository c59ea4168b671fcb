//! The `csgkit` command: argument parsing, progress and reporting around the library.
//!
//! Exit status follows ripgrep: 0 success, 1 a negative answer (`check` finds the mesh is not a
//! valid solid), 2 any error (bad input, failed operation, usage).

mod cli;
mod commands;
mod progress;

use std::process::ExitCode;

fn main() -> ExitCode {
    // The library's thread pool starts while the inputs are read, as in a long-lived program
    // that calls the library many times, so no operation's time includes starting threads.
    rayon::spawn(|| {});
    match cli::run() {
        Ok(code) => code,
        Err(err) => {
            if is_broken_pipe(&err) {
                return ExitCode::SUCCESS;
            }
            eprintln!("csgkit: error: {err:#}");
            ExitCode::from(2)
        }
    }
}

/// A closed pipe (`csgkit check x.obj | head`) ends the program quietly.
fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
