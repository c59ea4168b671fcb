//! Command-line definition and dispatch: one subcommand per job.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use csgkit::Operation;

use crate::commands::{self, boxes, demo, exact};

/// Exact boolean operations on 3D solids.
#[derive(Parser, Debug)]
#[command(name = "csgkit", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print a mesh file's format, counts, bounding box and attributes.
    #[command(after_help = "Example:\n  csgkit info crates/csgkit/tests/data/cube.obj")]
    Info(commands::info::InfoArgs),
    /// Check whether a mesh is a valid solid and print every measure.
    ///
    /// Exit status: 0 when the mesh is closed (every edge used as often in each direction)
    /// and consistently oriented, 1 when it is not, 2 on any error.
    #[command(
        after_help = "Examples:\n  csgkit check crates/csgkit/tests/data/cube.obj\n  \
                            csgkit check --json part.stl"
    )]
    Check(commands::check::CheckArgs),
    /// The exact union of two or more solids: the points in any operand.
    #[command(after_help = "Examples:\n  \
        csgkit union a.obj b.stl -o ab.obj\n  \
        csgkit union a.obj b.obj c.obj -o abc.ply --manifold --stats")]
    Union(exact::ExactArgs),
    /// The exact intersection of two or more solids: the points in every operand.
    #[command(after_help = "Example:\n  csgkit intersection a.obj b.obj -o common.obj")]
    Intersection(exact::ExactArgs),
    /// The exact difference: the first solid minus all the others.
    #[command(after_help = "Example (the block minus both holes):\n  \
        csgkit difference block.obj hole1.obj hole2.obj -o drilled.obj")]
    Difference(exact::ExactArgs),
    /// The exact symmetric difference (xor): the points in an odd number of the solids.
    #[command(after_help = "Example (the parts of a and b outside the other):\n  \
        csgkit xor a.obj b.obj -o either.obj")]
    Xor(exact::ExactArgs),
    /// The boundary of the region inside a mesh whose faces may cross or whose shells may
    /// nest: a valid solid, certified free of self-intersections.
    #[command(after_help = "Examples:\n  \
        csgkit repair downloaded.stl -o solid.obj\n  \
        csgkit repair folded.obj -o fixed.obj --winding positive --stats")]
    Repair(commands::repair::RepairArgs),
    /// The exact boundary of a union of axis-aligned boxes (.vox or a box text file).
    Boxes(boxes::BoxesArgs),
    /// Runs the engine on built-in data and writes its outputs.
    Demo(demo::DemoArgs),
    /// A CSG tree of solids, evaluated exactly in one pass: a JSON scene of unions,
    /// intersections and differences over meshes, boxes and primitives, with transforms and
    /// materials.
    #[command(after_help = CSG_HELP)]
    Csg(commands::csg::CsgArgs),
    /// Booleans and voxelisation with the multi-scale depth-list engine.
    #[command(
        after_help = "Examples:\n  csgkit discrete voxelize bunny.obj -o bunny_vox.obj --cell 0.01 --stats\n  \
                            csgkit discrete difference wall.stl@8 torus.obj@1 -o out.obj\n  \
                            csgkit discrete demo"
    )]
    Discrete(commands::discrete::DiscreteArgs),
}

/// The scene format, for `csgkit help csg`.
const CSG_HELP: &str = "\
A node is an object with exactly one of these keys, and optionally \"transform\" and \"material\":
  {\"union\" | \"intersection\" | \"difference\": [node, ...]}   (difference: the first minus the others)
  {\"hull\": [node, ...]}                                   the exact convex hull of leaves and unions
  {\"mesh\": \"part.stl\"}                                      any format csgkit reads
  {\"cube\": {\"size\": [x, y, z] | s, \"center\": bool}}
  {\"sphere\": {\"r\": R, \"segments\": N}}                       OpenSCAD's tessellation
  {\"cylinder\": {\"r\": R, \"h\": H, \"segments\": N, \"center\": bool}}
  {\"boxes\": \"model.vox\" | \"boxes.txt\"}                       through the orthogonal engine
\"transform\": [[m00, m01, m02, t0], [m10, m11, m12, t1], [m20, m21, m22, t2]]   (x' = M x + t)
\"material\": \"name\"   the material of every face below that names none closer
Relative paths are relative to the scene file; errors name the JSON path of the bad node.

Example scene (a block drilled through, the block in stone):
  {\"difference\": [
    {\"cube\": {\"size\": 2, \"center\": true}, \"material\": \"stone\"},
    {\"cylinder\": {\"r\": 0.5, \"h\": 3, \"segments\": 32, \"center\": true},
     \"transform\": [[1, 0, 0, 0.2], [0, 1, 0, 0], [0, 0, 1, 0]]}]}

Example:
  csgkit csg drilled.json -o drilled.obj --stats

OpenSCAD: `csgkit csg model.csg` reads what `openscad -o model.csg model.scad` writes (and a .scad
through openscad when it is on PATH), with OpenSCAD 2021's tessellation: group, union, difference,
intersection, render, multmatrix, color (a material), cube, sphere, cylinder, polyhedron, and 2D
square, circle, polygon (paths, even-odd) under linear_extrude (height, center, twist, slices,
scale) and rotate_extrude (angle); 2D booleans are exact; hull of solids or 2D shapes (exact,
over unions of leaves); import of mesh files (STL, OBJ, OFF, 3MF, PLY, glTF; a relative path
starts from the .csg file's directory, or the .scad's), read once each, their materials kept.
minkowski, offset, text, surface, projection, resize and imported 2D drawings (DXF, SVG) are
errors naming the node and its line.";

/// Parses the command line and runs the chosen subcommand.
pub fn run() -> anyhow::Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {
        Command::Info(args) => commands::info::run(&args),
        Command::Check(args) => commands::check::run(&args),
        Command::Union(args) => exact::run(Operation::Union, &args).map(|_| ExitCode::SUCCESS),
        Command::Intersection(args) => {
            exact::run(Operation::Intersection, &args).map(|_| ExitCode::SUCCESS)
        }
        Command::Difference(args) => {
            exact::run(Operation::Difference, &args).map(|_| ExitCode::SUCCESS)
        }
        Command::Xor(args) => exact::run(Operation::Xor, &args).map(|_| ExitCode::SUCCESS),
        Command::Repair(args) => commands::repair::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Boxes(args) => boxes::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Demo(args) => demo::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Csg(args) => commands::csg::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Discrete(args) => commands::discrete::run(&args),
    }
}
