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
enum Command {
    /// Booleans and voxelisation with the multi-scale depth-list engine.
    #[command(
        after_help = "Examples:\n  csgkit discrete voxelize bunny.obj -o bunny_vox.obj --cell 0.01 --stats\n  \
                            csgkit discrete difference wall.stl@8 torus.obj@1 -o out.obj\n  \
                            csgkit discrete demo"
    )]
    Discrete(crate::discrete::DiscreteArgs),
}

/// Parses the command line and runs the chosen subcommand.
pub fn run() -> anyhow::Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {
        Command::Discrete(args) => crate::discrete::run(&args),
    }
}
