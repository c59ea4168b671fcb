//! Constructive solid geometry: solids built in code, and later expression trees over them.
//!
//! DESIGN.md plans this module as the layer above the engines: expression trees of operands,
//! transforms and operations, a scene file, their evaluation, and primitives.
//! Only [`primitives`] exists so far: closed, outward-oriented meshes of simple solids (cuboid,
//! icosphere, torus, cylinder) that the demo, the tests and the benches build instead of each
//! keeping its own copy.

pub mod primitives;
