//! Constructive solid geometry: the layer above the engines.
//!
//! - [`tree`]: CSG trees of meshes with transforms and materials, evaluated by the exact
//!   engine in one arrangement of all leaves.
//! - [`extrude`]: 2D shapes as prisms, and the solids OpenSCAD's `linear_extrude` and
//!   `rotate_extrude` sweep from them.
//! - [`scene`]: the JSON scene format, read into a tree.
//! - [`openscad`]: OpenSCAD's `.csg` export, read into a tree with OpenSCAD's tessellation.

pub mod extrude;
pub mod openscad;
pub mod scene;
pub mod tree;

pub use crate::mesh::{Affine, IDENTITY};
pub use tree::{CsgError, Evaluation, Flat, Node, NodeKind, evaluate, flatten};
