//! The exact mesh-boolean engine (`design/exact.md`): booleans on polygon meshes with every
//! topological decision exact.
//!
//! # Pipeline plan
//! Data flows forward through one module per stage (Freixas, Grau & Silva's subdivision,
//! classification and reconstruction, made exact). This branch holds only stage 5:
//! - **split** — [`split_triangle`]: the exact constrained triangulation of one triangle with
//!   the intersection points and segments that lie on it.
//!
//! The exact predicates it uses are in [`kernel`](crate::kernel).

mod split;

pub use split::{Split, SplitError, split_triangle};
