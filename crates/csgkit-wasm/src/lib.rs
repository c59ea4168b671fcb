//! `csgkit-wasm`: csgkit in JavaScript, through wasm-bindgen, over bytes and typed arrays.
//!
//! The operations mirror the Python package (`crates/csgkit-py`), with JavaScript's
//! spelling: the exact booleans `boolean(operation, meshes, options)` and its shorthands
//! `union`, `intersection`, `difference` and `xor` (n-ary), `boxes` (the orthogonal engine,
//! from a `.vox` file's bytes, box text or a `Float64Array` of boxes), `voxelize` (the
//! discrete engine), `load` (any format the library reads, from bytes and a file name),
//! `save` (bytes in the format a file name's extension names) and `check` (the report of
//! `csgkit check --json`). The built-in solids of `csgkit::primitives` are there too, so a
//! page can make operands without a file.
//!
//! # Layout
//! - `mesh`: the class `Mesh` (a shared handle to a library mesh: passing one to an operation
//!   never gives it up) and what a viewer needs of it (`triangulate`: triangles, their faces,
//!   the polygon edges without the diagonals).
//! - `operations`: the engines and the primitives.
//! - `files`: `load`, `loadParts`, `save`, `check`.
//! - `progress`: an optional JavaScript `progress(stage, done, total)` callback, called
//!   synchronously from inside the library's stages; returning `false` cancels.
//! - `errors`: every [`csgkit::Error`] becomes a thrown JavaScript `Error` whose `name` is the
//!   Python package's class (`InputError`, `ReadError`, `WriteError`, `CancelledError`,
//!   `CsgkitError`) and whose message is the library's, unchanged.
//!
//! The library is built without its `parallel` feature: wasm32 has no threads, and the page
//! runs every call in a Web Worker so the interface never waits for it.
//!
//! Everything is for `wasm32`: on other targets the crate is empty.

#![cfg(target_arch = "wasm32")]

mod errors;
mod files;
mod mesh;
mod operations;
mod progress;
