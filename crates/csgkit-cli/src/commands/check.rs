//! `csgkit check FILE [--json]`: every validity check and measure of a mesh.
//!
//! Runs [`csgkit::mesh::analyze`] and the exact [`csgkit::self_intersections`] check, and
//! prints a table, or with `--json` one JSON object with the file, its format, every field of
//! [`csgkit::mesh::MeshReport`] (non-finite numbers as `null`) and the self-intersection
//! counts (`selfint_pairs`, `selfint_faces`, and the first pairs in `selfint_first_pairs`),
//! and the polygons that cannot be triangulated because their projection overlaps itself
//! (`invalid_polygons`, each with its `face` and `problem`). Exit status 0 when the mesh is a
//! valid solid (closed and consistently oriented; non-manifold edges allowed), 1 when it is
//! not; errors exit 2 through `main`.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use csgkit::SelfIntersections;
use csgkit::mesh::MeshReport;

use super::{describe_format, load, point};

/// Arguments of `csgkit check`.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The mesh file (OBJ, STL, PLY or OFF).
    pub file: PathBuf,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Analyses the mesh and prints the report; exit status 0 for a valid solid, 1 otherwise.
pub fn run(args: &CheckArgs) -> anyhow::Result<ExitCode> {
    let loaded = load(&args.file)?;
    let mut report = loaded.mesh.report();
    report.count_file_vertices(loaded.raw_vertex_count);
    let crossings = csgkit::self_intersections(&loaded.mesh);
    let text = if args.json {
        let mut json = serde_json::to_value(&report)?;
        if let Some(object) = json.as_object_mut() {
            object.insert("file".into(), args.file.display().to_string().into());
            object.insert("format".into(), describe_format(&loaded).into());
            object.insert("selfint_pairs".into(), crossings.pair_count().into());
            object.insert("selfint_faces".into(), crossings.face_count().into());
            object.insert("selfint_first_pairs".into(), first_pairs(&crossings).into());
            object.insert("invalid_polygons".into(), invalid_polygons(&crossings));
        }
        format!("{json}\n")
    } else {
        table(
            &args.file.display().to_string(),
            &describe_format(&loaded),
            &report,
            &crossings,
        )?
    };
    std::io::stdout().lock().write_all(text.as_bytes())?;
    Ok(if report.is_valid_solid() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// The human-readable report: one measure per line, then the verdict.
fn table(
    file: &str,
    format: &str,
    r: &MeshReport,
    crossings: &SelfIntersections,
) -> anyhow::Result<String> {
    let t = &r.topology;
    let yes = |b: bool| if b { "yes" } else { "no" };
    let genus = t
        .genus
        .map_or("undefined (not a closed oriented 2-manifold)".into(), |g| {
            g.to_string()
        });
    let bbox = r.measures.bbox.map_or("none".into(), |b| {
        format!("{} .. {}", point(b.min), point(b.max))
    });
    let rows: [(&str, String); 28] = [
        ("file", file.into()),
        ("format", format.into()),
        (
            "vertices",
            format!(
                "{} ({} duplicate, {} unreferenced)",
                r.vertices, r.duplicate_vertices, t.unreferenced_vertices
            ),
        ),
        (
            "faces",
            format!(
                "{} ({} triangles when split, {} polygons)",
                r.faces, r.triangles, r.polygons
            ),
        ),
        ("edges", t.edges.to_string()),
        (
            "closed",
            format!(
                "{} ({} unbalanced edges)",
                yes(r.closed),
                t.unbalanced_edges
            ),
        ),
        ("boundary edges", t.boundary_edges.to_string()),
        ("boundary loops", t.boundary_loops.to_string()),
        ("edge-manifold", yes(r.edge_manifold).into()),
        ("non-manifold edges", t.non_manifold_edges.to_string()),
        ("vertex-manifold", yes(r.vertex_manifold).into()),
        ("non-manifold vertices", t.non_manifold_vertices.to_string()),
        ("oriented", yes(r.oriented).into()),
        ("misoriented edges", t.misoriented_edges.to_string()),
        ("components", t.components.to_string()),
        ("vertex components", t.vertex_components.to_string()),
        ("euler characteristic", t.euler.to_string()),
        ("genus", genus),
        ("repeated-vertex faces", r.repeated_vertex_faces.to_string()),
        ("collinear faces", r.collinear_faces.to_string()),
        ("duplicate faces", r.duplicate_faces.to_string()),
        (
            "faces left out",
            format!("{} (fewer than 3 distinct vertices)", t.excluded_faces),
        ),
        ("self-intersections", self_intersection_summary(crossings)),
        ("invalid polygons", invalid_polygon_summary(crossings)),
        ("volume", r.measures.volume.to_string()),
        ("area", r.measures.area.to_string()),
        ("bbox", bbox),
        ("valid solid", verdict(r)),
    ];
    let mut out = String::new();
    for (name, value) in rows {
        writeln!(out, "{:<22} {value}", format!("{name}:"))?;
    }
    Ok(out)
}

/// "yes", or "no" with the reasons.
fn verdict(r: &MeshReport) -> String {
    let mut reasons = Vec::new();
    if !r.closed {
        reasons.push("not closed");
    }
    if !r.oriented {
        reasons.push("not consistently oriented");
    }
    if reasons.is_empty() {
        "yes".into()
    } else {
        format!("no ({})", reasons.join(", "))
    }
}

/// How many face pairs of the first self-intersecting ones the report lists.
const LISTED_PAIRS: usize = 5;

/// The first intersecting face pairs, as `[face, face]` lists.
fn first_pairs(crossings: &SelfIntersections) -> Vec<[u32; 2]> {
    crossings
        .pairs
        .iter()
        .take(LISTED_PAIRS)
        .map(|(a, b)| [a.get(), b.get()])
        .collect()
}

/// "none", or the counts and the first pairs.
fn self_intersection_summary(crossings: &SelfIntersections) -> String {
    if crossings.pairs.is_empty() {
        return "none".into();
    }
    let listed: Vec<String> = first_pairs(crossings)
        .iter()
        .map(|[a, b]| format!("{a}-{b}"))
        .collect();
    format!(
        "{} face pairs, {} faces (first pairs: {})",
        crossings.pair_count(),
        crossings.face_count(),
        listed.join(", ")
    )
}

/// The polygons that cannot be triangulated, as `{"face": f, "problem": "..."}` objects.
fn invalid_polygons(crossings: &SelfIntersections) -> serde_json::Value {
    (crossings.invalid_polygons.iter())
        .map(|e| serde_json::json!({ "face": e.face().get(), "problem": e.to_string() }))
        .collect()
}

/// "none", or how many polygons overlap themselves and the first few problems.
fn invalid_polygon_summary(crossings: &SelfIntersections) -> String {
    let invalid = &crossings.invalid_polygons;
    if invalid.is_empty() {
        return "none".into();
    }
    let listed: Vec<String> = (invalid.iter().take(LISTED_PAIRS))
        .map(ToString::to_string)
        .collect();
    format!("{} (first: {})", invalid.len(), listed.join("; "))
}
