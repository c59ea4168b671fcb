//! The exact mesh-boolean engine (`design/exact.md`): booleans on polygon meshes with every
//! topological decision exact.
//!
//! # Pipeline
//! Data flows forward through one module per stage (Freixas, Grau & Silva's subdivision,
//! classification and reconstruction, made exact):
//! 1. **ingest** — weld bit-identical vertices, triangulate polygons exactly keeping the face
//!    id ([`triangulate_faces`](crate::mesh::triangulate_faces)), drop exactly degenerate
//!    triangles, validate the operands, rescale by a power of two.
//! 2. **broad** — candidate triangle pairs whose boxes overlap ([`Bvh`](crate::Bvh)).
//! 3. **intersect** — exact triangle–triangle classification ([`intersect_triangles`]):
//!    disjoint, touching at a point or along a segment, crossing, coplanar overlap; every
//!    contact point is a typed kernel [`Point`](crate::kernel::Point) with a canonical
//!    [`PointKey`]. Built on it: [`self_intersections`], the exact self-intersection check of
//!    one mesh.
//! 4. **split** — [`split_triangle`]: the exact constrained triangulation of one triangle with
//!    the intersection points and segments that lie on it (`subdivide` runs both stages over
//!    all pairs and triangles).
//! 5. **classify** — inside / outside / on of every patch against the other operands.
//! 6. **select** — keep patches by the operation's table, written on winding numbers: the
//!    [`Expression`] (one operation on all operands, or a CSG tree over them) evaluated on
//!    the inside flags of each patch.
//!
//!    Operands that are not simple solids (faces that cross each other, nested or
//!    overlapping shells) take another path through stages 2–6: their self-intersecting
//!    triangle pairs join the arrangement, and **winding** replaces classify and select with
//!    the exact winding number of every operand in front of every patch (one ray per patch);
//!    an operand's interior is where its winding number is non-zero, or positive
//!    ([`WindingRule`]).
//! 7. **reconstruct** — the face every kept sub-triangle belongs to (its source face, joined
//!    through earlier booleans' provenance and, as an option, with coplanar look-alike
//!    neighbours), and the removal of intersection points no face needs; exact.
//! 8. **assemble** — round implicit points once, build the output mesh with provenance.
//! 9. **certify** — check the rounded mesh exactly where rounding moved it, and repair it
//!    (re-rounding within a few ulps, merging coincident vertices, iterative snap rounding
//!    with exact re-refinement), so every result is a valid operand of the next boolean.
//! 10. **faces** — the certified triangles merged back into the polygons of their faces, or
//!     convex quads, or left as triangles ([`merge_faces`](crate::mesh::merge_faces)); then
//!     every face inherits the attributes of its source face
//!     ([`inherit_attributes`](crate::mesh::inherit_attributes)).
//!
//! [`boolean`] runs them in order; the exact predicates are in [`kernel`](crate::kernel).
//! [`boolean_expression`] reports every stage to a [`Progress`](crate::Progress), and the
//! long ones (validate, intersect, split, classify, certify) report and poll it per chunk of
//! their parallel work, so a cancellation stops the run inside the stage.
//!
//! The driver, `boolean.rs`, imports the stages and no stage imports it: each returns its
//! own error ([`InvalidOperand`] from ingest; an unsupported configuration or a cancellation
//! from split, classify and winding; a result without a certified f64 form from certify),
//! which [`BooleanError`] wraps.

mod assemble;
mod boolean;
mod broad;
mod certify;
mod classify;
mod expression;
mod ingest;
pub mod intersect;
mod reconstruct;
mod select;
pub mod self_intersect;
mod simplify;
mod split;
mod star;
mod subdivide;
mod winding;

pub use boolean::{
    Boolean, BooleanError, BooleanOptions, BooleanStats, boolean, boolean_expression,
};
pub use expression::Expression;
pub use ingest::InvalidOperand;
pub use intersect::{
    Contact, Feature, Intersection, PointKey, Triangle, TriangleEdge, intersect_triangles,
};
pub use self_intersect::{SelfIntersections, self_intersections};
pub use split::{Split, SplitError, split_triangle};
pub use winding::WindingRule;
