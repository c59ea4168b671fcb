//! Command-line definition and dispatch: one subcommand per job.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Exact boolean operations on 3D solids.
#[derive(Parser, Debug)]
#[command(name = "csgkit", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {}

/// Parses the command line and runs the chosen subcommand.
pub fn run() -> anyhow::Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {}
}
