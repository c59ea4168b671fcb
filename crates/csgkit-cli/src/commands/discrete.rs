//! `csgkit discrete …`: the multi-scale depth-list engine from the command line.
//!
//! - `csgkit discrete union|intersection|difference|xor A[@CELL] B[@CELL] … -o OUT --cell H`
//!   discretises each operand at its own cell size (cells must differ by powers of two; an
//!   operand without `@CELL` takes `--cell`), then folds the operation over them
//!   (`difference` is the first minus all others).
//! - `csgkit discrete voxelize A -o OUT --cell H`: the voxels whose centre is inside.
//! - `csgkit discrete demo [-o OUT]`: the paper's multi-scale showcase, a coarse wall minus a
//!   fine torus, built in code.
//!
//! Output: `.txt` writes the disjoint boxes (`x0 y0 z0 x1 y1 z1` per line, the input format of
//! `csgkit boxes`) of [`csgkit::discrete::combine`]'s solid; any mesh format writes the mesh
//! of the engine facade's [`csgkit::DiscreteEngine`], closed and without T-junctions: by
//! default the orthogonal engine's maximal faces, or with `--mesh surfels` the paper's unit
//! surfels.
//! Operands with materials keep them: each face of the result takes the material of the
//! operand behind it ([`csgkit::discrete::label`]); a mesh whose faces of each material are
//! closed (a voxel model through `csgkit boxes --per-material`) keeps all of them. `--stats` prints one
//! JSON object on stdout with counts and seconds per stage; `op_seconds` covers
//! discretisation, the booleans and the output conversion, without file I/O.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, bail};
use csgkit::discrete::{
    CombineError, DiscreteStats, DiscretizeOptions, FillRule, Grid, Rounding, Solid, combine,
};
use csgkit::primitives::{cuboid, torus};
use csgkit::{DiscreteEngine, DiscreteSurface, Engine, Error, Mesh, Operation, Stage, Stats};
use serde_json::json;

use super::load_each;
use crate::progress::{seconds_of, with_bar};

/// Arguments of `csgkit discrete`.
#[derive(clap::Args, Debug)]
pub struct DiscreteArgs {
    #[command(subcommand)]
    command: DiscreteCommand,
}

#[derive(clap::Subcommand, Debug)]
enum DiscreteCommand {
    /// Union of all operands.
    #[command(after_help = "Example:\n  csgkit discrete union wall.stl@4 bunny.obj@0.5 -o out.obj")]
    Union(OpArgs),
    /// Intersection of all operands.
    Intersection(OpArgs),
    /// The first operand minus all others.
    #[command(
        after_help = "Example:\n  csgkit discrete difference wall.stl@8 torus.obj -o out.obj --cell 1"
    )]
    Difference(OpArgs),
    /// Symmetric difference of all operands.
    Xor(OpArgs),
    /// The voxels whose centre is inside the mesh.
    #[command(
        after_help = "Example:\n  csgkit discrete voxelize bunny.obj -o bunny_vox.obj --cell 0.01 --stats"
    )]
    Voxelize(VoxelizeArgs),
    /// A coarse wall minus a fine torus (Burguet & Malgouyres' showcase), built in code.
    Demo(DemoArgs),
}

/// Options every discrete command shares.
#[derive(clap::Args, Debug)]
struct Common {
    /// Output file: `.txt` for boxes, otherwise a mesh (OBJ, STL, PLY, OFF).
    #[arg(short, long)]
    output: PathBuf,
    /// Cell size of operands given without `@CELL`.
    #[arg(long)]
    cell: Option<f64>,
    /// Which winding numbers are inside.
    #[arg(long, value_enum, default_value = "nonzero")]
    fill: Fill,
    /// How crossing depths round to voxels.
    #[arg(long, value_enum, default_value = "centre")]
    rounding: Round,
    /// Print one JSON object with counts and timings on stdout.
    #[arg(long)]
    stats: bool,
    /// No progress bar, even on a terminal.
    #[arg(long)]
    no_progress: bool,
    /// How a mesh output is built. `ortho` (the default) gives maximal faces, about a third
    /// as many as unit surfels; `surfels` builds faster on very fine grids (the bunny at
    /// 1024³: 34 s through the orthogonal engine, 4 s as surfels).
    #[arg(long, value_enum, default_value = "ortho")]
    mesh: MeshMode,
}

/// How the result becomes a mesh.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum MeshMode {
    /// Boxes through the orthogonal engine: maximal faces with holes.
    Ortho,
    /// The paper's top, bottom and lateral surfels as unit quads.
    Surfels,
}

impl MeshMode {
    /// The library's name for the mode.
    fn surface(self) -> DiscreteSurface {
        match self {
            MeshMode::Ortho => DiscreteSurface::Ortho,
            MeshMode::Surfels => DiscreteSurface::Surfels,
        }
    }
}

#[derive(clap::Args, Debug)]
struct OpArgs {
    /// Operands, each `FILE` or `FILE@CELL`.
    #[arg(required = true, num_args = 2..)]
    operands: Vec<String>,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args, Debug)]
struct VoxelizeArgs {
    /// The mesh, `FILE` or `FILE@CELL`.
    input: String,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args, Debug)]
struct DemoArgs {
    /// Where to write the result (`.txt` for boxes, otherwise a mesh); nothing is written
    /// without it.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum Fill {
    Nonzero,
    Positive,
    Parity,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum Round {
    Centre,
    Inner,
    Outer,
}

/// Runs a discrete subcommand.
pub fn run(args: &DiscreteArgs) -> anyhow::Result<ExitCode> {
    match &args.command {
        DiscreteCommand::Union(a) => run_op(&a.operands, &a.common, Operation::Union, "union"),
        DiscreteCommand::Intersection(a) => run_op(
            &a.operands,
            &a.common,
            Operation::Intersection,
            "intersection",
        ),
        DiscreteCommand::Difference(a) => {
            run_op(&a.operands, &a.common, Operation::Difference, "difference")
        }
        DiscreteCommand::Xor(a) => run_op(&a.operands, &a.common, Operation::Xor, "xor"),
        DiscreteCommand::Voxelize(a) => run_op(
            std::slice::from_ref(&a.input),
            &a.common,
            Operation::Union,
            "voxelize",
        ),
        DiscreteCommand::Demo(a) => run_demo(a),
    }
}

/// An operand `FILE@CELL` split into its path and cell (the text after the last `@`, when it
/// is a number).
fn parse_operand(text: &str, default: Option<f64>) -> anyhow::Result<(PathBuf, f64)> {
    if let Some((path, cell)) = text.rsplit_once('@')
        && let Ok(cell) = cell.parse::<f64>()
    {
        return Ok((PathBuf::from(path), cell));
    }
    match default {
        Some(cell) => Ok((PathBuf::from(text), cell)),
        None => bail!("operand {text} has no cell size: give FILE@CELL or --cell"),
    }
}

fn run_op(
    operands: &[String],
    common: &Common,
    op: Operation,
    name: &str,
) -> anyhow::Result<ExitCode> {
    let parsed = operands
        .iter()
        .map(|o| parse_operand(o, common.cell))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let cells: Vec<f64> = parsed.iter().map(|p| p.1).collect();
    let (grid, levels) = Grid::for_cells(&cells).context("invalid cell sizes")?;
    let t_read = Instant::now();
    let paths: Vec<&Path> = parsed.iter().map(|(path, _)| path.as_path()).collect();
    let meshes = load_each(&paths, load)?;
    let read_seconds = t_read.elapsed().as_secs_f64();
    let options = DiscretizeOptions {
        fill: match common.fill {
            Fill::Nonzero => FillRule::NonZero,
            Fill::Positive => FillRule::Positive,
            Fill::Parity => FillRule::Parity,
        },
        rounding: match common.rounding {
            Round::Centre => Rounding::Centre,
            Round::Inner => Rounding::Inner,
            Round::Outer => Rounding::Outer,
        },
    };
    let operands: Vec<&Mesh> = meshes.iter().collect();
    let min_size = if common.no_progress { usize::MAX } else { 0 };
    let faces = meshes.iter().map(Mesh::face_count).sum();
    let named = |err: Error| name_operand(err, &parsed);
    // Boxes are the solid's own; a mesh is the engine facade's output.
    let (stats, report) = if is_box_file(&common.output) {
        let combined = with_bar(faces, min_size, |progress| {
            combine(op, &operands, grid, &levels, options, progress)
        })
        .map_err(|err| named(err.into()))?;
        let report = write_boxes(&combined.solid, &common.output)?;
        (combined.stats, report)
    } else {
        let engine = DiscreteEngine {
            cells,
            options,
            surface: common.mesh.surface(),
        };
        let output = with_bar(faces, min_size, |progress| {
            engine.apply(op, &operands, progress)
        })
        .map_err(named)?;
        let Stats::Discrete(stats) = output.stats else {
            unreachable!("the discrete engine gives the discrete engine's statistics")
        };
        let convert_seconds = seconds_of(&stats.stage_seconds, Stage::Convert);
        let report = write_mesh(&output.mesh, &common.output, convert_seconds)?;
        (stats, report)
    };
    if common.stats {
        let inputs: Vec<_> = (parsed.iter().zip(&meshes).zip(&stats.operand_voxels))
            .map(|(((path, cell), mesh), voxels)| {
                json!({"file": path.display().to_string(), "cell": cell,
                       "vertices": mesh.vertex_count(), "faces": mesh.face_count(),
                       "voxels": voxels})
            })
            .collect();
        println!(
            "{}",
            stats_json(name, &inputs, grid, &stats, read_seconds, &report)
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The library's error, naming the file of an operand that could not be discretised, and
/// the engine that failed to build the mesh.
fn name_operand(err: Error, parsed: &[(PathBuf, f64)]) -> anyhow::Error {
    match err {
        Error::Combine(CombineError::Operand { operand, error }) => anyhow::Error::new(error)
            .context(format!("cannot discretise {}", parsed[operand].0.display())),
        err @ Error::Ortho(_) => anyhow::Error::new(err).context("orthogonal engine failed"),
        err @ Error::InvalidMesh(_) => anyhow::Error::new(err).context("surfel mesh too large"),
        err => err.into(),
    }
}

/// The `--stats` object.
fn stats_json(
    name: &str,
    inputs: &[serde_json::Value],
    grid: Grid,
    stats: &DiscreteStats,
    read_seconds: f64,
    report: &Written,
) -> serde_json::Value {
    let t = &stats.tiles;
    let discretize_seconds = seconds_of(&stats.stage_seconds, Stage::Discretize);
    let boolean_seconds = seconds_of(&stats.stage_seconds, Stage::Combine);
    json!({
        "command": format!("discrete {name}"),
        "inputs": inputs,
        "cell": grid.h(),
        "voxels": stats.voxels,
        "tiles": {"roots": t.roots, "uniform": t.uniform, "bricks": t.bricks, "splits": t.splits,
                  "entries": t.entries},
        "output": report.json,
        "read_seconds": read_seconds,
        "discretize_seconds": discretize_seconds,
        "boolean_seconds": boolean_seconds,
        "convert_seconds": report.convert_seconds,
        "write_seconds": report.write_seconds,
        "op_seconds": discretize_seconds + boolean_seconds + report.convert_seconds,
    })
}

/// What writing the result produced.
struct Written {
    json: serde_json::Value,
    convert_seconds: f64,
    write_seconds: f64,
}

/// Whether `path` names a box text file (`.txt`) rather than a mesh.
fn is_box_file(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("txt"))
}

/// Writes the disjoint boxes of `solid` to `path`, one `x0 y0 z0 x1 y1 z1` line each.
fn write_boxes(solid: &Solid, path: &Path) -> anyhow::Result<Written> {
    let t = Instant::now();
    let boxes = solid.to_boxes();
    let mut text = String::with_capacity(boxes.len() * 64);
    for b in &boxes {
        text.push_str(&format!(
            "{} {} {} {} {} {}\n",
            b[0], b[1], b[2], b[3], b[4], b[5]
        ));
    }
    let convert_seconds = t.elapsed().as_secs_f64();
    let t = Instant::now();
    write_atomic(path, text.as_bytes())?;
    Ok(Written {
        json: json!({"boxes": boxes.len()}),
        convert_seconds,
        write_seconds: t.elapsed().as_secs_f64(),
    })
}

/// Writes `mesh`, built in `convert_seconds`, to `path`.
fn write_mesh(mesh: &Mesh, path: &Path, convert_seconds: f64) -> anyhow::Result<Written> {
    let t = Instant::now();
    super::save(path, mesh, csgkit::WriteOptions::default())
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(Written {
        json: json!({"vertices": mesh.vertex_count(), "faces": mesh.face_count()}),
        convert_seconds,
        write_seconds: t.elapsed().as_secs_f64(),
    })
}

/// Writes to a temporary file beside `path`, then renames it over `path`.
fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let temp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    std::fs::write(&temp, bytes)
        .and_then(|()| std::fs::rename(&temp, path))
        .inspect_err(|_| {
            let _ = std::fs::remove_file(&temp);
        })
        .with_context(|| format!("cannot write {}", path.display()))
}

fn load(path: &Path) -> anyhow::Result<Mesh> {
    let loaded =
        csgkit::io::read_mesh(path).with_context(|| format!("cannot read {}", path.display()))?;
    Ok(loaded.mesh)
}

/// `csgkit discrete demo`: the showcase, written to `-o` when given.
fn run_demo(args: &DemoArgs) -> anyhow::Result<ExitCode> {
    let result = showcase()?;
    if let Some(path) = &args.output {
        let written = if is_box_file(path) {
            write_boxes(&result, path)?
        } else {
            let t = Instant::now();
            let mesh = result.to_mesh().context("orthogonal engine failed")?;
            write_mesh(&mesh, path, t.elapsed().as_secs_f64())?
        };
        println!("  wrote {} ({})", path.display(), written.json);
    }
    Ok(ExitCode::SUCCESS)
}

/// The paper's multi-scale showcase, printed: an 8-cell wall minus a 1-cell torus in a 64
/// box. Returns the result.
pub fn showcase() -> anyhow::Result<Solid> {
    let (grid, levels) = Grid::for_cells(&[8.0, 1.0])?;
    let wall = cuboid([8.0, 0.0, 0.0], [40.0, 64.0, 64.0]);
    let torus = torus([24.0, 32.0, 32.0], 18.0, 5.0, 96, 32);
    let options = DiscretizeOptions::default();
    let t = Instant::now();
    let coarse = csgkit::discrete::discretize(&wall, grid, levels[0], options)?;
    let fine = csgkit::discrete::discretize(&torus, grid, levels[1], options)?;
    let result = coarse.difference(&fine)?;
    let seconds = t.elapsed().as_secs_f64();
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "multi-scale showcase: wall (cell 8) minus torus (cell 1)"
    )?;
    for (name, s) in [
        ("wall", &coarse),
        ("torus", &fine),
        ("wall - torus", &result),
    ] {
        let t = s.stats();
        writeln!(
            out,
            "  {name:<13} {:>8} voxels  {:>5} uniform tiles  {:>5} bricks  {:>5} splits",
            s.voxel_count(),
            t.uniform,
            t.bricks,
            t.splits
        )?;
    }
    writeln!(
        out,
        "  {seconds:.3} s; only the tiles the torus touches are refined"
    )?;
    Ok(result)
}
