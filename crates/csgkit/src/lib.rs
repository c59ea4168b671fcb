//! csgkit computes boolean operations ([`Operation`]: union, intersection, difference,
//! symmetric difference) on 3D solids, exactly: no epsilon takes part in any topological
//! decision.
//!
//! # Overview
//! Files are read by [`io`] into a [`Mesh`], an engine computes the result, and [`io`]
//! writes it back. The engines share the mesh model and its contracts (see
//! `ARCHITECTURE.md`):
//! - the exact mesh-boolean engine for arbitrary closed polygon meshes;
//! - the orthogonal engine for unions of axis-aligned boxes;
//! - the discrete engine for multi-scale depth-list solids.
//!
//! [`Engine`] is one interface over the three ([`ExactEngine`], [`OrthoEngine`],
//! [`DiscreteEngine`]): an [`Operation`] on meshes, reported to and cancellable through a
//! [`Progress`], giving an [`Output`] or the crate's one [`Error`]. Each engine's own module
//! keeps its full interface (the exact engine's CSG expressions, the orthogonal engine's
//! B-reps and materials, the discrete engine's solids).
//!
//! [`primitives`] builds closed meshes of simple solids (cuboid, icosphere, torus,
//! cylinder) in code.
//!
//! # API themes
//! - Fallible functions return a typed error naming what is wrong and where; no input makes
//!   the library panic.
//! - Indices are `u32` newtypes ([`VertexId`], [`FaceId`], [`OperandId`]).

#![deny(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod csg;
pub mod discrete;
mod engine;
mod error;
pub mod exact;
mod index;
pub mod io;
pub mod kernel;
pub mod mesh;
mod operation;
pub mod ortho;
mod par;
pub mod primitives;
mod progress;

pub use engine::{
    DiscreteEngine, DiscreteSurface, Engine, ExactEngine, OrthoEngine, OrthoStats, Output, Stats,
};
pub use error::{Error, ErrorKind};
pub use exact::{
    Contact, Feature, Intersection, PointKey, SelfIntersections, Split, SplitError, Triangle,
    TriangleEdge, intersect_triangles, self_intersections, split_triangle,
};
pub use index::{Aabb, Bvh};
pub use io::{
    Encoding, External, Format, LoadedMesh, LoadedMeshes, Location, ParseError, Part, ReadError,
    Unit, WriteError, WriteOptions, Written, no_external_files, read_mesh, read_mesh_from_bytes,
    read_meshes, read_meshes_from_bytes, rounded_coordinates, write_mesh, write_mesh_to_bytes,
};
pub use kernel::Precision;
pub use mesh::{FaceId, InvalidMesh, Mesh, MeshParts, OperandId, Provenance, Rgba, VertexId};
pub use operation::Operation;
pub use progress::{Callback, Cancelled, Progress, Report, Stage};
