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
use csgkit::{Format, LoadedMesh};

/// Reads a mesh file, naming the file in the error.
pub fn load(path: &Path) -> anyhow::Result<LoadedMesh> {
    csgkit::read_mesh(path).with_context(|| format!("cannot load {}", path.display()))
}

/// Warns that `--manifold` is lost when the output is STL, which stores positions rather than
/// shared vertices, so the vertices the split duplicated merge again on reading.
pub fn warn_if_manifold_lost(manifold: bool, output: &Path) {
    if manifold && Format::from_extension(output) == Some(Format::Stl) {
        eprintln!(
            "csgkit: warning: STL stores positions, not vertices: the manifold split is lost"
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
