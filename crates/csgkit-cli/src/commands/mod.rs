//! One module per subcommand; each exposes its clap arguments and a `run` function that
//! returns the process exit code.

pub mod boxes;
pub mod check;
pub mod demo;
pub mod discrete;
pub mod info;

use std::path::Path;

use anyhow::Context;
use csgkit::LoadedMesh;

/// Reads a mesh file, naming the file in the error.
pub fn load(path: &Path) -> anyhow::Result<LoadedMesh> {
    csgkit::read_mesh(path).with_context(|| format!("cannot load {}", path.display()))
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
