//! Command-line definition and dispatch: one subcommand per job.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::commands::{boxes, demo};

/// Exact boolean operations on 3D solids.
#[derive(Parser, Debug)]
#[command(name = "csgkit", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The exact boundary of a union of axis-aligned boxes (.vox or a box text file).
    Boxes(boxes::BoxesArgs),
    /// Runs the engine on built-in data and writes its outputs.
    Demo(demo::DemoArgs),
}

/// Parses the command line and runs the chosen subcommand.
pub fn run() -> anyhow::Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {
        Command::Boxes(args) => boxes::run(&args)?,
        Command::Demo(args) => demo::run(&args)?,
    }
    Ok(ExitCode::SUCCESS)
}
