//! The discrete engine: multi-scale depth-list solids and their booleans.
//!
//! This is the method of Burguet & Malgouyres ("Multiscale discrete surfaces"), in the clean
//! form of `design/discrete.md` §B3: a solid is a set of voxels on one power-of-two lattice
//! anchored at the origin ([`Grid`]), stored per column as sorted depth intervals, held in a
//! quadtree of tiles whose resolution follows the surface ([`Solid`], [`Tile`]). Booleans merge
//! depth lists; operands discretised at different resolutions combine exactly.
//!
//! # Pipeline
//! 1. [`discretize`] (`discretize.rs`): closed mesh → per-column winding numbers along rays
//!    through voxel centres, decided with exact predicates (top-left fill rule across the
//!    rays, exact above/below tests along them) → [`Column`]s at one level.
//! 2. `Solid::from_columns` (`tile.rs`): columns → normalised tiles: uniform tiles, 8×8
//!    [`Brick`]s with 64-bit masks (`brick.rs`), split tiles.
//! 3. [`Solid::op`] (`ops.rs`): ∪ ∩ − ⊕ with multi-scale alignment, normalised bottom-up.
//! 4. [`Solid::to_boxes`] (`to_boxes.rs`): disjoint axis-aligned boxes, the orthogonal
//!    engine's input for a closed mesh; [`Solid::to_surfel_mesh`] (`surfels.rs`): the
//!    paper's top/bottom/lateral surfel reconstruction as a closed unit-quad mesh.
//! 5. Materials (`materials.rs`): one solid per material in ([`discretize_parts`]), the
//!    result's voxels labelled by the first operand part containing them ([`label`]), and
//!    the mesh with the material of the solid behind each face ([`labelled_mesh`]).
//!
//! [`combine`] (`combine.rs`) runs steps 1, 3 and 5 for an operation on meshes, each operand
//! at its own level of one grid, reporting the triangles cast to a
//! [`Progress`](crate::Progress) that can cancel it: what `csgkit discrete` and the engine
//! facade run.
//!
//! # Invariants
//! - Everything is an integer after step 1, so booleans are exact and chain without drift.
//! - Solids are canonical: equal voxel sets on one grid give equal solids (normalisation).
//! - Deterministic: parallel stages collect in a fixed order; no result depends on threads.

mod brick;
mod column;
mod combine;
mod discretize;
mod grid;
mod materials;
mod ops;
mod surfels;
mod tile;
mod to_boxes;

pub use brick::{BRICK_SIDE, Brick, BrickError};
pub use column::{Column, ColumnError, Interval};
pub use combine::{CombineError, Combined, DiscreteStats, combine};
pub use discretize::{
    DiscretizeError, DiscretizeOptions, FillRule, Rounding, discretize, discretize_with_progress,
};
pub use grid::{BRICK_LEVEL, Grid, GridError, MAX_INDEX, MAX_LEVEL};
pub use materials::{MaterialSolid, discretize_parts, label, labelled_mesh, material_parts};
pub use ops::OpError;
pub use tile::{Solid, Tile, TileError, TileStats};
