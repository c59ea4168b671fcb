//! `csgkit info FILE`: what a mesh file holds, without the validity analysis.
//!
//! Prints the format, the vertex and face counts, the bounding box and which attributes are
//! present, and for a file of several parts (3MF build items, glTF mesh nodes) each part and
//! the unit a 3MF declares. It is cheap (no edge table); `csgkit check` runs the full
//! analysis.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use csgkit::Mesh;

use super::{describe_format, load_parts, point};

/// Arguments of `csgkit info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// The mesh file (OBJ, STL, PLY, OFF, 3MF, glTF or GLB).
    pub file: PathBuf,
}

/// Prints the summary; exit status 0.
pub fn run(args: &InfoArgs) -> anyhow::Result<ExitCode> {
    let parts = load_parts(&args.file)?;
    let unit = parts.unit;
    let names: Vec<(String, usize)> = (parts.parts.iter())
        .map(|p| (p.name.clone(), p.mesh.face_count()))
        .collect();
    let loaded = parts.merge()?;
    let mesh = &loaded.mesh;
    let mut out = String::new();
    writeln!(out, "file:        {}", args.file.display())?;
    writeln!(out, "format:      {}", describe_format(&loaded))?;
    if let Some(unit) = unit {
        writeln!(out, "unit:        {} (read as millimetres)", unit.name())?;
    }
    if names.len() != 1 {
        writeln!(out, "parts:       {}", names.len())?;
        for (name, faces) in &names {
            writeln!(out, "  {name}: {faces} faces")?;
        }
    }
    let stored = loaded.raw_vertex_count;
    if stored == mesh.vertex_count() {
        writeln!(out, "vertices:    {stored}")?;
    } else {
        writeln!(
            out,
            "vertices:    {} ({stored} stored, welded on read)",
            mesh.vertex_count()
        )?;
    }
    let polygons = mesh.faces().filter(|f| f.len() > 3).count();
    writeln!(
        out,
        "faces:       {} ({polygons} with more than 3 corners)",
        mesh.face_count()
    )?;
    match csgkit::mesh::bounding_box(mesh) {
        Some(b) => writeln!(out, "bbox:        {} .. {}", point(b.min), point(b.max))?,
        None => writeln!(out, "bbox:        none (no face)")?,
    }
    writeln!(out, "attributes:  {}", attributes(mesh))?;
    std::io::stdout().lock().write_all(out.as_bytes())?;
    Ok(ExitCode::SUCCESS)
}

/// The attributes present, comma-separated, or "none".
fn attributes(mesh: &Mesh) -> String {
    let named = |what: &str, names: &[String]| format!("{what} ({})", names.join(", "));
    let mut present = Vec::new();
    if mesh.face_materials().is_some() {
        present.push(named("materials", mesh.materials()));
    }
    if mesh.face_groups().is_some() {
        present.push(named("groups", mesh.groups()));
    }
    let flags = [
        ("face colours", mesh.face_colors().is_some()),
        ("provenance", mesh.face_provenance().is_some()),
        ("corner UVs", mesh.corner_uvs().is_some()),
        ("corner normals", mesh.corner_normals().is_some()),
        ("vertex colours", mesh.vertex_colors().is_some()),
    ];
    present.extend(flags.iter().filter(|f| f.1).map(|f| f.0.to_owned()));
    if !mesh.material_libraries().is_empty() {
        present.push(named("material libraries", mesh.material_libraries()));
    }
    if present.is_empty() {
        "none".to_owned()
    } else {
        present.join(", ")
    }
}
