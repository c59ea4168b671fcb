//! Spatial index: a bounding-volume hierarchy over axis-aligned boxes, and a coarse grid that
//! narrows what the hierarchy indexes.
//!
//! The exact engine's broad phase asks one question of it: which pairs of triangles, one from
//! each of two meshes (or two from one mesh, for the self-intersection check), have
//! overlapping bounding boxes? Only those pairs go on to the exact triangle–triangle test.
//!
//! # Why a hand-written BVH
//! `rstar` answers the same query, but its R*-tree is built for incremental insertion and
//! nearest-neighbour search. The broad phase builds a throw-away tree over up to millions of
//! boxes and runs one all-pairs query, so a Morton-ordered tree with an implicit balanced
//! layout (as in Manifold's `collider.h`) is both simpler and faster: the build is one
//! parallel sort, and the tree needs no pointers.
//!
//! # Layout
//! - [`Aabb`] (`aabb.rs`): closed boxes; touching boxes overlap, so contacts at a single
//!   point still reach the exact test. Box coordinates are copied from input coordinates,
//!   never computed, so the overlap test is exact.
//! - [`Bvh`] (`bvh_build.rs`): primitives sorted by the Morton code of their box centre, then
//!   a balanced binary tree over that order; [`Bvh::build_with`] takes the boxes from a
//!   function instead of a list, and [`Bvh::into_tree_order`] renumbers the primitives in
//!   tree order, so a caller can copy its data into the order the queries read it.
//! - Queries (`bvh_query.rs`): [`Bvh::overlapping_pairs`] between two trees and
//!   [`Bvh::self_overlapping_pairs`] within one, both parallel and deterministic; their
//!   `_filter_map` forms decide each pair as the walk finds it and keep only what the caller
//!   returns, without storing the candidates.
//! - [`Occupancy`] (`occupancy.rs`): the cells of a coarse uniform grid that a set of boxes
//!   overlaps; the broad phase indexes only the triangles of each operand in cells the other
//!   occupies (near where the surfaces meet), so its trees are built over a fraction of the
//!   overlap of two large operands.

mod aabb;
mod bvh_build;
mod bvh_query;
mod occupancy;

pub use aabb::Aabb;
pub use bvh_build::Bvh;
pub use occupancy::{CellSpan, Occupancy};
