//! `csgkit boxes`: the exact boundary of a union of axis-aligned boxes.
//!
//! Input is a MagicaVoxel `.vox` file (by extension) or a text file of `x0 y0 z0 x1 y1 z1`
//! lines. Voxel colours become face materials (named `material_<palette index>`) and face
//! colours; `--per-material` writes one solid per colour instead of one solid with coloured
//! faces.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::Args;
use csgkit::ortho::{
    BRep, BoxFile, MeshOptions, MeshOutput, box_union_per_material, box_union_timed,
    per_material_mesh, read_box_file, with_palette_colors,
};
use csgkit::{Mesh, Stage, WriteOptions};

use crate::progress::{seconds_of, with_bar};

/// Below this many boxes the union ends before a progress bar would help.
const PROGRESS_MIN_BOXES: usize = 50_000;

/// Arguments of `csgkit boxes`.
#[derive(Args, Debug, Clone)]
#[command(after_help = "Examples:\n  \
    csgkit boxes boxes.txt -o union.obj\n  \
    csgkit boxes castle.vox -o castle.ply --per-material --stats\n  \
    csgkit boxes castle.vox -o castle.obj --manifold --model 2")]
pub struct BoxesArgs {
    /// A `.vox` file, or a text file with one box `x0 y0 z0 x1 y1 z1` per line.
    pub input: PathBuf,
    /// The output mesh; its extension chooses the format (obj, ply, off, stl).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Split non-manifold edges and vertices into a 2-manifold (triangles; not for STL).
    #[arg(long)]
    pub manifold: bool,
    /// Write faces without holes as polygons (the default); faces with holes are triangulated.
    #[arg(long, conflicts_with = "triangles")]
    pub polygons: bool,
    /// Triangulate every face.
    #[arg(long)]
    pub triangles: bool,
    /// One solid per material (voxel colour): interfaces appear in both, opposite ways.
    #[arg(long)]
    pub per_material: bool,
    /// Print one JSON object with counts and seconds per stage.
    #[arg(long)]
    pub stats: bool,
    /// In a `.vox` file, take model N alone (0-based), ignoring the scene graph.
    #[arg(long, value_name = "N")]
    pub model: Option<usize>,
}

/// Counts and seconds for `--stats`.
#[derive(Default)]
struct Report {
    read_seconds: f64,
    stage_seconds: Vec<(Stage, f64)>,
    mesh_seconds: f64,
    write_seconds: f64,
    vertices: usize,
    faces: usize,
    holes: usize,
    dropped: usize,
    solids: usize,
}

/// Runs `csgkit boxes`.
pub fn run(args: &BoxesArgs) -> anyhow::Result<()> {
    let clock = Instant::now();
    let input = read_input(&args.input, args.model)?;
    let mut report = Report {
        read_seconds: clock.elapsed().as_secs_f64(),
        ..Report::default()
    };
    let options = MeshOptions {
        triangles: args.triangles || args.manifold,
        manifold: args.manifold,
    };
    let op_clock = Instant::now();
    let out = build_mesh(&input, args.per_material, options, &mut report)
        .with_context(|| format!("computing the union of {}", args.input.display()))?;
    let op_seconds = op_clock.elapsed().as_secs_f64();
    if out.unsplit_edges > 0 {
        eprintln!(
            "csgkit: warning: {} non-manifold edges kept shared (no f64 strictly between their ends)",
            out.unsplit_edges
        );
    }
    super::warn_if_manifold_lost(args.manifold, &args.output);
    let mesh = match &input.palette {
        Some(palette) => with_palette_colors(out.mesh, palette),
        None => out.mesh,
    };
    let write_clock = Instant::now();
    super::save(&args.output, &mesh, WriteOptions::default())
        .with_context(|| format!("writing {}", args.output.display()))?;
    report.write_seconds = write_clock.elapsed().as_secs_f64();
    if args.stats {
        println!("{}", stats_json(&input, &report, &mesh, op_seconds));
    }
    Ok(())
}

fn read_input(path: &Path, model: Option<usize>) -> anyhow::Result<BoxFile> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let vox = (path.extension()).is_some_and(|e| e.eq_ignore_ascii_case("vox"));
    read_box_file(&bytes, vox, model).with_context(|| format!("reading {}", path.display()))
}

fn build_mesh(
    input: &BoxFile,
    per_material: bool,
    options: MeshOptions,
    report: &mut Report,
) -> anyhow::Result<MeshOutput> {
    let solids: Vec<(u32, BRep)> = match (&input.materials, per_material) {
        (Some(materials), true) => {
            let clock = Instant::now();
            let solids = box_union_per_material(&input.boxes, materials)?;
            report.stage_seconds = vec![(Stage::Sweep, clock.elapsed().as_secs_f64())];
            solids
        }
        (materials, _) => {
            let (brep, stage_seconds) =
                with_bar(input.boxes.len(), PROGRESS_MIN_BOXES, |progress| {
                    box_union_timed(&input.boxes, materials.as_deref(), progress)
                })?;
            report.stage_seconds = stage_seconds;
            vec![(0, brep)]
        }
    };
    for (_, brep) in &solids {
        report.vertices += brep.vertices.len();
        report.faces += brep.faces.len();
        report.holes += brep.faces.iter().map(|f| f.holes.len()).sum::<usize>();
        report.dropped = brep.dropped_boxes;
    }
    report.solids = solids.len();
    let clock = Instant::now();
    let out = if solids.len() == 1 && !per_material {
        solids[0].1.to_mesh(options)?
    } else {
        per_material_mesh(&solids, options)?
    };
    report.mesh_seconds = clock.elapsed().as_secs_f64();
    Ok(out)
}

fn stats_json(input: &BoxFile, r: &Report, mesh: &Mesh, op_seconds: f64) -> serde_json::Value {
    serde_json::json!({
        "input_boxes": input.boxes.len(),
        "dropped_boxes": r.dropped,
        "voxels": input.voxel_count,
        "solids": r.solids,
        "brep_vertices": r.vertices,
        "brep_faces": r.faces,
        "brep_holes": r.holes,
        "output_vertices": mesh.vertex_count(),
        "output_faces": mesh.face_count(),
        "read_seconds": r.read_seconds,
        "rank_seconds": seconds_of(&r.stage_seconds, Stage::Rank),
        "sweep_seconds": seconds_of(&r.stage_seconds, Stage::Sweep),
        "loops_seconds": seconds_of(&r.stage_seconds, Stage::Loops),
        "mesh_seconds": r.mesh_seconds,
        "write_seconds": r.write_seconds,
        "op_seconds": op_seconds,
    })
}
