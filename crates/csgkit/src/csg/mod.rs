//! Constructive solid geometry: the layer above the engines.
//!
//! - [`primitives`]: closed, outward-oriented meshes of simple solids (cuboid, icosphere,
//!   OpenSCAD's UV sphere, torus, cylinder), the one definition the demo, the tests, the
//!   benches and scenes share.
//! - [`tree`]: CSG trees of meshes with transforms and materials, evaluated by the exact
//!   engine in one arrangement of all leaves.
//! - [`scene`]: the JSON scene format, read into a tree.

pub mod primitives;
pub mod scene;
pub mod tree;

pub use tree::{Affine, CsgError, Evaluation, IDENTITY, Node, NodeKind, evaluate};
