//! One module per subcommand; each exposes its clap arguments and a `run` function that
//! returns the process exit code.

pub mod boxes;
pub mod check;
pub mod csg;
pub mod demo;
pub mod discrete;
pub mod exact;
pub mod info;
pub mod repair;

use std::path::Path;

use anyhow::Context;
use csgkit::exact::BooleanStats;
use csgkit::{Format, LoadedMesh, LoadedMeshes, Mesh, WriteOptions};
use rayon::prelude::*;

/// Reads a mesh file (its parts merged), naming the file in the error.
pub fn load(path: &Path) -> anyhow::Result<LoadedMesh> {
    csgkit::read_mesh(path).with_context(|| format!("cannot load {}", path.display()))
}

/// Reads a mesh file with its parts (3MF build items, glTF nodes), naming the file in the error.
pub fn load_parts(path: &Path) -> anyhow::Result<LoadedMeshes> {
    csgkit::read_meshes(path).with_context(|| format!("cannot load {}", path.display()))
}

/// `load` of every path, the files read side by side on the thread pool: a parser runs on one
/// thread, and two 1 M-triangle OBJ operands read one after the other kept the second core
/// idle for as long as the boolean took. The results come in the order given; an error is
/// the first path's that fails in that order, as if they were read in turn.
pub fn load_each<P: AsRef<Path> + Sync, T: Send>(
    paths: &[P],
    load: impl Fn(&Path) -> anyhow::Result<T> + Sync,
) -> anyhow::Result<Vec<T>> {
    let loaded: Vec<anyhow::Result<T>> = paths.par_iter().map(|p| load(p.as_ref())).collect();
    loaded.into_iter().collect()
}

/// Writes `mesh` to `path`, whole or not at all, and warns once on stderr when the format
/// rounded coordinates (glTF and binary STL store f32), since the result was exact.
pub fn save(path: &Path, mesh: &Mesh, options: WriteOptions) -> anyhow::Result<()> {
    let written = csgkit::write_mesh(path, mesh, options)?;
    if written.rounded_coordinates > 0 {
        let format = options.format.or_else(|| Format::from_extension(path));
        let name = format.map_or_else(|| "the format".to_owned(), |f| f.to_string());
        eprintln!(
            "csgkit: warning: {name} stores f32: {} of {} coordinates written to {} were rounded",
            written.rounded_coordinates,
            3 * mesh.vertex_count(),
            path.display()
        );
    }
    Ok(())
}

/// Warns that `--manifold` is lost when the output is STL or glTF, whose readers weld
/// positions (STL stores no shared vertices, glTF splits them by normal and UV), so the
/// vertices the split duplicated merge again on reading.
pub fn warn_if_manifold_lost(manifold: bool, output: &Path) {
    let format = Format::from_extension(output);
    if manifold && matches!(format, Some(Format::Stl | Format::Gltf | Format::Glb)) {
        let name = format.map(|f| f.to_string()).unwrap_or_default();
        eprintln!(
            "csgkit: warning: {name} readers weld equal positions: the manifold split is lost"
        );
    }
}

/// Warns when the result is empty only because certification removed its closed shells as
/// thinner than a few ulps of the numbers it is written in (a sliver solid far from the
/// origin, or any thin solid in f32), so an empty file is not taken for an empty exact result.
pub fn warn_if_thinned_away(stats: &BooleanStats, output: &Path) {
    if stats.output_faces == 0 && stats.removed_shells > 0 {
        eprintln!(
            "csgkit: warning: the result written to {} is empty: its {} closed shells are thinner than a few ulps of its coordinates",
            output.display(),
            stats.removed_shells
        );
    }
}

/// The format and encoding of a loaded file, e.g. "STL (binary)".
pub fn describe_format(loaded: &LoadedMesh) -> String {
    let encoding = match loaded.encoding {
        csgkit::Encoding::Binary => "binary",
        csgkit::Encoding::Ascii => "text",
    };
    format!("{} ({encoding})", loaded.format)
}

/// A point as "[x, y, z]" with the shortest round-tripping digits.
pub fn point(p: [f64; 3]) -> String {
    format!("[{}, {}, {}]", p[0], p[1], p[2])
}
