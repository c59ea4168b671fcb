//! The `csgkit` binary end to end, one module per command family. One test crate, so the
//! tests link against the library once.

mod common;

// `csgkit boxes` and `csgkit demo`.
mod boxes;
// Exit codes, `--json` and `--help` of `check` and `info`.
mod cli;
// `csgkit csg`: JSON and OpenSCAD scenes.
mod csg;
// `csgkit discrete`.
mod discrete;
// The exact booleans: files in every format, `--stats`, faces modes, errors.
mod exact;
// Reading and writing every format.
mod formats;
// `csgkit repair`.
mod repair;
