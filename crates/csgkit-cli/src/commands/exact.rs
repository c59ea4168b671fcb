//! `csgkit union | intersection | difference | xor A B [C ...] -o OUT`: the exact mesh booleans.
//!
//! Reads every operand (any format [`csgkit::read_mesh`] reads), runs the exact engine through
//! the facade ([`csgkit::ExactEngine`]) once on all of them (`difference` is the first minus
//! all others) and writes the result, whole or not at all, in the format the output's
//! extension names.
//!
//! A file of several parts (a 3MF with several build items, a glTF with several mesh nodes)
//! gives one operand per part, or one merged operand with `--merge`.
//!
//! The library names a faulty operand by its index; errors here name it by its file (and
//! part), so `csgkit union a.obj b.obj` reports "b.obj: operand 1 is not closed …".
//!
//! `--stats` prints one JSON object, and nothing else, on stdout: the peers benchmark harness
//! reads `op_seconds` from it. `op_seconds` is [`BooleanStats::op_seconds`], the pipeline
//! without the self-intersection check (`validate_seconds`) and without file I/O
//! (`read_seconds`, `write_seconds`); `stages` holds the seconds of every stage that ran, by
//! its snake_case name.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use clap::Args;
use csgkit::exact::{Boolean, BooleanError, BooleanOptions, BooleanStats, WindingRule};
use csgkit::mesh::{FaceMode, MeshReport};
use csgkit::{Engine, ExactEngine, Format, Mesh, Operation, Stats, WriteError, WriteOptions};
use serde_json::json;

use super::{load_each, load_parts, save, warn_if_manifold_lost, warn_if_thinned_away};
use crate::progress::{seconds_of, with_bar};

/// Below this many input faces the boolean ends before a progress bar would help.
const PROGRESS_MIN_FACES: usize = 20_000;

/// Arguments of `csgkit union`, `intersection`, `difference` and `xor`.
#[derive(Args, Debug, Clone)]
pub struct ExactArgs {
    /// The operands: closed meshes (OBJ, STL, PLY, OFF, 3MF, glTF/GLB), two or more in all;
    /// each build item of a 3MF and each mesh node of a glTF is an operand of its own (see
    /// --merge). Their faces may cross each other and their shells may nest (see --winding).
    #[arg(required = true, num_args = 1.., value_name = "FILE")]
    pub inputs: Vec<PathBuf>,
    /// The output mesh; its extension chooses the format (obj, ply, off, stl, 3mf, gltf, glb;
    /// binary STL and glTF store f32, so the result is rounded to f32 and certified there).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Read each file as one operand: the build items of a 3MF, or the mesh nodes of a glTF,
    /// merged into one mesh.
    #[arg(long)]
    pub merge: bool,
    /// Split the result's non-manifold edges and vertices by duplicating vertices, so it is a
    /// 2-manifold (lost in STL, which stores no shared vertices).
    #[arg(long)]
    pub manifold: bool,
    /// Print one JSON object on stdout: counts, seconds per stage, and the result's validity,
    /// volume and area.
    #[arg(long)]
    pub stats: bool,
    /// Skip the exact self-intersection check of the operands, which costs about as much as
    /// the boolean itself. Classification then assumes that no operand intersects itself; if
    /// one does, the result may be wrong and no error says so.
    #[arg(long)]
    pub no_self_check: bool,
    /// Which points are inside an operand whose faces cross each other or whose shells nest:
    /// where its winding number is non-zero, or only where it is positive.
    #[arg(long, value_enum, default_value_t = Winding::Nonzero)]
    pub winding: Winding,
    /// Which faces to write.
    #[command(flatten)]
    pub faces: FaceArgs,
}

/// How the result's faces are written (`--polygons`, `--quads`, `--triangles`,
/// `--merge-coplanar`), shared by every command that writes an exact result.
#[derive(Args, Debug, Clone, Default)]
pub struct FaceArgs {
    /// Write each face of the result as polygons: the part of its source face it keeps, in
    /// hole-free pieces that the fan from their first corner triangulates; a face nothing cut
    /// comes back as it was read (OBJ, PLY and OFF; STL stores triangles).
    #[arg(long, group = "face_mode")]
    pub polygons: bool,
    /// Write triangles and strictly convex quads only.
    #[arg(long, group = "face_mode")]
    pub quads: bool,
    /// Write triangles: per face, a triangulation without extra vertices, the one the result
    /// was certified with. The default, since many readers take only triangles.
    #[arg(long, group = "face_mode")]
    pub triangles: bool,
    /// Also merge neighbouring faces that lie exactly in one plane and have the same
    /// material, group and colour (and no UVs or normals), though they come from different
    /// source faces: chains of booleans through files then stay small.
    #[arg(long)]
    pub merge_coplanar: bool,
    /// Also merge neighbouring faces that are flat to within TOL (a length, in the model's
    /// units; they must look alike as for --merge-coplanar) and remove the vertices only they
    /// need, each removal moving the surface by at most TOL; the result is still certified.
    /// For chains of booleans through files, whose faces come back flat only to an ulp.
    #[arg(long, value_name = "TOL")]
    pub simplify: Option<f64>,
}

impl FaceArgs {
    /// `options` with the faces, merging and simplification these arguments ask for, for a
    /// result written in `format`, and the precision it stores (f32 in binary STL and glTF:
    /// the result is certified in the coordinates written).
    pub fn apply(&self, format: Format, options: BooleanOptions) -> BooleanOptions {
        BooleanOptions {
            faces: self.face_mode(format),
            merge_coplanar: self.merge_coplanar,
            simplify: self.simplify,
            precision: format.precision(WriteOptions::default().encoding),
            ..options
        }
    }

    /// The faces to write in `format`: as asked, triangles by default and in STL.
    fn face_mode(&self, format: Format) -> FaceMode {
        if format == Format::Stl {
            FaceMode::Triangles
        } else if self.quads {
            FaceMode::Quads
        } else if self.polygons {
            FaceMode::Polygons
        } else {
            FaceMode::Triangles
        }
    }
}

/// The values of `--winding`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Winding {
    /// Inside where the winding number is not zero.
    Nonzero,
    /// Inside where the winding number is positive.
    Positive,
}

impl Winding {
    /// The library's rule.
    pub fn rule(self) -> WindingRule {
        match self {
            Winding::Nonzero => WindingRule::NonZero,
            Winding::Positive => WindingRule::Positive,
        }
    }
}

/// Runs `csgkit union`, `intersection`, `difference` or `xor` on two or more operands;
/// returns what the library reported.
pub fn run(op: Operation, args: &ExactArgs) -> anyhow::Result<BooleanStats> {
    run_operands(op, args, 2)
}

/// Runs the operation on at least `min_operands` operands (`repair`: a union of one).
pub fn run_operands(
    op: Operation,
    args: &ExactArgs,
    min_operands: usize,
) -> anyhow::Result<BooleanStats> {
    // The format is settled before any work, so a mistyped extension costs nothing.
    let format = Format::from_extension(&args.output).ok_or_else(|| WriteError::UnknownFormat {
        path: args.output.clone(),
    })?;
    let clock = Instant::now();
    let operands = load_operands(&args.inputs, args.merge)?;
    if operands.len() < min_operands {
        anyhow::bail!(
            "the {} needs {min_operands} or more operands; the files give {}",
            op.name(),
            operands.len()
        );
    }
    let (names, meshes): (Vec<String>, Vec<Mesh>) = operands.into_iter().unzip();
    let read_seconds = clock.elapsed().as_secs_f64();
    let result = compute(op, args, format, &meshes, &names)
        .with_context(|| format!("cannot compute the {}", op.name()))?;
    warn_if_manifold_lost(args.manifold, &args.output);
    let clock = Instant::now();
    let options = WriteOptions {
        format: Some(format),
        ..WriteOptions::default()
    };
    save(&args.output, &result.mesh, options)?;
    warn_if_thinned_away(&result.stats, &args.output);
    let write_seconds = clock.elapsed().as_secs_f64();
    if args.stats {
        let seconds = IoSeconds {
            read: read_seconds,
            write: write_seconds,
        };
        let stats = stats_json(op, args, &names, &meshes, &result, seconds);
        println!("{stats}");
    }
    Ok(result.stats)
}

/// The operands the files give, each with its name for errors and `--stats`: one per file, or
/// with several parts and no `--merge`, one per part ("a.3mf, item 2 (bolt)").
fn load_operands(paths: &[PathBuf], merge: bool) -> anyhow::Result<Vec<(String, Mesh)>> {
    let mut operands = Vec::new();
    for (path, loaded) in paths.iter().zip(load_each(paths, load_parts)?) {
        let file = path.display().to_string();
        if merge || loaded.parts.len() == 1 {
            let merged = loaded
                .merge()
                .with_context(|| format!("cannot load {file}"))?;
            operands.push((file, merged.mesh));
        } else {
            for (k, part) in loaded.parts.into_iter().enumerate() {
                operands.push((format!("{file}, part {k} ({})", part.name), part.mesh));
            }
        }
    }
    Ok(operands)
}

/// Runs the exact engine with a bar per stage; an error about an operand names its file.
fn compute(
    op: Operation,
    args: &ExactArgs,
    format: Format,
    meshes: &[Mesh],
    names: &[String],
) -> anyhow::Result<Boolean> {
    let operands: Vec<&Mesh> = meshes.iter().collect();
    let faces = meshes.iter().map(Mesh::face_count).sum();
    let options = BooleanOptions {
        check_self_intersections: !args.no_self_check,
        winding: args.winding.rule(),
        split_non_manifold: args.manifold,
        ..BooleanOptions::default()
    };
    let engine = ExactEngine {
        options: args.faces.apply(format, options),
    };
    let output = with_bar(faces, PROGRESS_MIN_FACES, |progress| {
        engine.apply(op, &operands, progress)
    })
    .map_err(|err| name_operand(err, names))?;
    let Stats::Exact(stats) = output.stats else {
        unreachable!("the exact engine gives the exact engine's statistics")
    };
    Ok(Boolean {
        mesh: output.mesh,
        stats,
    })
}

/// The library's error, under the file name of the operand it names (if any).
fn name_operand(err: csgkit::Error, names: &[String]) -> anyhow::Error {
    let operand = match &err {
        csgkit::Error::Boolean(BooleanError::InvalidOperand(invalid)) => {
            names.get(invalid.operand())
        }
        _ => None,
    };
    match operand {
        Some(name) => anyhow::Error::new(err).context(name.clone()),
        None => err.into(),
    }
}

/// The `stages` object of `--stats`: seconds per stage, by snake_case name.
pub fn stages_json(stats: &BooleanStats) -> serde_json::Map<String, serde_json::Value> {
    (stats.stage_seconds.iter())
        .map(|&(stage, secs)| (stage.to_string(), secs.into()))
        .collect()
}

/// The seconds of the self-intersection check, which `op_seconds` leaves out.
pub fn validate_seconds(stats: &BooleanStats) -> f64 {
    seconds_of(&stats.stage_seconds, csgkit::Stage::Validate)
}

/// The seconds spent reading the operands and writing the result.
#[derive(Clone, Copy)]
struct IoSeconds {
    read: f64,
    write: f64,
}

/// The `--stats` object.
fn stats_json(
    op: Operation,
    args: &ExactArgs,
    names: &[String],
    meshes: &[Mesh],
    result: &Boolean,
    seconds: IoSeconds,
) -> serde_json::Value {
    let s: &BooleanStats = &result.stats;
    let report: MeshReport = result.mesh.report();
    let inputs: Vec<_> = (names.iter().zip(meshes))
        .map(|(name, mesh)| input_json(name, mesh))
        .collect();
    let stages = stages_json(s);
    let validate_seconds = validate_seconds(s);
    json!({
        "command": op.name(),
        "inputs": inputs,
        "self_check": !args.no_self_check,
        "manifold": args.manifold,
        "input_triangles": s.input_triangles,
        "candidate_pairs": s.candidate_pairs,
        "intersecting_pairs": s.intersecting_pairs,
        "split_triangles": s.split_triangles,
        "patches": s.patches,
        "self_intersecting_pairs": s.self_intersecting_pairs,
        "winding_classification": s.winding_classification,
        "output_triangles": s.output_triangles,
        "output_faces": s.output_faces,
        "removed_vertices": s.removed_vertices,
        "rounded_vertices": s.rounded_vertices,
        "snapped_vertices": s.snapped_vertices,
        "dissolved_slivers": s.dissolved_slivers,
        "removed_sheets": s.removed_sheets,
        "removed_shells": s.removed_shells,
        "max_snap_displacement": s.max_snap_displacement,
        "certify_rounds": s.certify_rounds,
        "output_vertices": result.mesh.vertex_count(),
        "valid_solid": report.valid_solid,
        "volume": report.measures.volume,
        "area": report.measures.area,
        "stages": stages,
        "read_seconds": seconds.read,
        "validate_seconds": validate_seconds,
        "op_seconds": s.op_seconds(),
        "write_seconds": seconds.write,
    })
}

/// One operand in `--stats`: its file (and part) and counts as read.
fn input_json(name: &str, mesh: &Mesh) -> serde_json::Value {
    json!({
        "file": name,
        "vertices": mesh.vertex_count(),
        "faces": mesh.face_count(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use csgkit::exact::InvalidOperand;

    #[test]
    fn an_operand_error_names_the_file() {
        let inputs = ["a.obj".to_owned(), "dir/b.stl".to_owned()];
        let err = csgkit::Error::from(BooleanError::InvalidOperand(InvalidOperand::Inverted {
            operand: 1,
            volume: -1.0,
        }));
        let message = format!("{:#}", name_operand(err, &inputs));
        assert!(message.starts_with("dir/b.stl: operand 1 "), "{message}");
        let cancelled = csgkit::Error::from(BooleanError::Cancelled(csgkit::Cancelled));
        let message = format!("{:#}", name_operand(cancelled, &inputs));
        assert_eq!(message, "cancelled");
    }
}
