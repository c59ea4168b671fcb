//! `csgkit csg SCENE -o OUT`: a CSG tree evaluated in one exact pass.
//!
//! The scene is a JSON file ([`csgkit::csg::scene`]) or an OpenSCAD tree ([`csgkit::csg::openscad`]); its tree is flattened and evaluated by
//! the exact engine in one arrangement of all leaves ([`csgkit::csg::evaluate`]), rounded
//! once. `--stats` prints one JSON object on stdout: `op_seconds` (the tree's boolean without
//! the self-intersection check and file I/O), `evaluate_seconds` (everything between reading
//! and writing: placing leaves, the 2D booleans and sweeps of extrusions, the check and the
//! boolean), the seconds of every stage of the tree's boolean, and the leaf and operation
//! counts.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail};
use clap::Args;
use csgkit::csg::openscad::parse_openscad_csg;
use csgkit::csg::scene::read_scene;
use csgkit::csg::{Node, NodeKind, evaluate};
use csgkit::exact::BooleanOptions;
use csgkit::{Format, WriteError, WriteOptions};
use serde_json::json;

use super::exact::{FaceArgs, stages_json, validate_seconds};
use crate::progress::with_bar;

/// Below this many leaf faces the evaluation ends before a progress bar would help.
const PROGRESS_MIN_FACES: usize = 20_000;

/// Arguments of `csgkit csg`.
#[derive(Args, Debug, Clone)]
pub struct CsgArgs {
    /// The scene: a JSON tree of unions, intersections and differences over meshes, boxes
    /// and primitives, with transforms and materials (see `csgkit help csg`), an OpenSCAD
    /// CSG export (.csg), or an OpenSCAD model (.scad, exported by `openscad` on PATH).
    pub scene: PathBuf,
    /// The output mesh; its extension chooses the format (obj, ply, off, stl).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Print one JSON object on stdout: counts, seconds per stage, the result's validity,
    /// volume and area.
    #[arg(long)]
    pub stats: bool,
    /// Which faces to write.
    #[command(flatten)]
    pub faces: FaceArgs,
}

/// Runs `csgkit csg`.
pub fn run(args: &CsgArgs) -> anyhow::Result<()> {
    let format = Format::from_extension(&args.output).ok_or_else(|| WriteError::UnknownFormat {
        path: args.output.clone(),
    })?;
    let clock = Instant::now();
    let tree = read_tree(&args.scene)?;
    let read_seconds = clock.elapsed().as_secs_f64();
    let options = args.faces.apply(format, BooleanOptions::default());
    let clock = Instant::now();
    let evaluation = with_bar(leaf_faces(&tree), PROGRESS_MIN_FACES, |progress| {
        evaluate(&tree, &options, progress)
    });
    let evaluation =
        evaluation.with_context(|| format!("cannot evaluate {}", args.scene.display()))?;
    let evaluate_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let options = WriteOptions {
        format: Some(format),
        ..WriteOptions::default()
    };
    let mesh = &evaluation.result.mesh;
    super::save(&args.output, mesh, options)?;
    super::warn_if_thinned_away(&evaluation.result.stats, &args.output);
    let write_seconds = clock.elapsed().as_secs_f64();
    if args.stats {
        let s = &evaluation.result.stats;
        let report = mesh.report();
        let stats = json!({
            "command": "csg",
            "scene": args.scene.display().to_string(),
            "leaves": evaluation.leaves,
            "operations": evaluation.operations,
            "input_triangles": s.input_triangles,
            "output_triangles": s.output_triangles,
            "output_faces": s.output_faces,
            "output_vertices": mesh.vertex_count(),
            "valid_solid": report.valid_solid,
            "volume": report.measures.volume,
            "area": report.measures.area,
            "stages": stages_json(s),
            "read_seconds": read_seconds,
            "validate_seconds": validate_seconds(s),
            "op_seconds": s.op_seconds(),
            "evaluate_seconds": evaluate_seconds,
            "write_seconds": write_seconds,
        });
        println!("{stats}");
    }
    Ok(())
}

/// The directory of `file`, from which the paths it names start.
fn directory_of(file: &Path) -> &Path {
    file.parent().unwrap_or(Path::new("."))
}

/// The tree of a JSON scene, an OpenSCAD `.csg` file, or a `.scad` file (through `openscad
/// -o TMP.csg` when OpenSCAD is on PATH).
fn read_tree(scene: &Path) -> anyhow::Result<Node> {
    let extension = (scene.extension().and_then(|e| e.to_str()))
        .unwrap_or_default()
        .to_ascii_lowercase();
    match extension.as_str() {
        "json" => Ok(read_scene(scene)?),
        "csg" => {
            let text = std::fs::read_to_string(scene)
                .with_context(|| format!("cannot read {}", scene.display()))?;
            parse_openscad_csg(&text, directory_of(scene))
                .with_context(|| format!("{}", scene.display()))
        }
        "scad" => {
            let dir = tempfile::TempDir::new().context("cannot make a temporary directory")?;
            let csg = dir.path().join("model.csg");
            let status = std::process::Command::new("openscad")
                .arg("-o")
                .arg(&csg)
                .arg(scene)
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .status();
            match status {
                Ok(s) if s.success() && csg.exists() => {
                    let text = std::fs::read_to_string(&csg)?;
                    // The export writes an imported file's path as the model names it:
                    // relative to the model's directory, not the temporary one.
                    parse_openscad_csg(&text, directory_of(scene))
                        .with_context(|| format!("{} (exported by openscad)", scene.display()))
                }
                Ok(_) => bail!("openscad could not export {}", scene.display()),
                Err(_) => bail!(
                    "{}: OpenSCAD is not on PATH; export the tree with `openscad -o model.csg {}` and pass model.csg",
                    scene.display(),
                    scene.display()
                ),
            }
        }
        _ => bail!(
            "{}: a scene is a JSON file (.json), an OpenSCAD CSG export (.csg) or an OpenSCAD model (.scad)",
            scene.display()
        ),
    }
}

/// The faces of every leaf of `node`.
fn leaf_faces(node: &Node) -> usize {
    match &node.kind {
        NodeKind::Mesh { mesh, .. } => mesh.face_count(),
        NodeKind::Apply(_, children) => children.iter().map(leaf_faces).sum(),
        NodeKind::Extrude { profile, .. } => leaf_faces(profile),
    }
}
