//! Integration tests, one module per area.

mod util;

// CSG trees in one exact pass: JSON scenes and random trees against chains of binary
// booleans, touching and coplanar leaves.
mod csg_trees;
// The discrete engine against brute-force voxel oracles.
mod discrete_cases;
// The engine facade: every engine on one table of cases, stage reports, cancellation inside
// the long stages.
mod engines;
// The exact engine: the degenerate suite of design/exact.md with exact volumes.
mod exact_cases;
// Reconstruction: faces merged back by source in polygons, quads and triangles modes, fewest
// vertices, untouched faces as read, chained provenance.
mod exact_faces;
// The exact engine against the orthogonal engine: unions of random integer boxes.
mod exact_ortho;
// The exact engine's properties (proptest) on random convex solids and box sets; error paths.
mod exact_props;
// The exact engine on real meshes of the shared data folder: valid solids, volume identities.
mod exact_real;
// The exact engine on operands that are not simple solids: crossing faces, nested and inward
// shells, winding rules, repair; certified results and chains through files.
mod exact_winding;
// Inputs the fuzz targets (fuzz/) found to crash, replayed through the targets' checks.
mod fuzz_regressions;
// Every shared data mesh loads with the manifest's counts; every format (3MF and glTF too)
// round-trips positions, materials and colours; malformed files of each format get exact errors.
mod io_formats;
// ARCHITECTURE.md's layering: no two modules of the library import each other.
mod layering;
// Truncated, corrupted and random bytes make no reader panic (3MF, glTF and binary OFF too).
mod io_fuzz;
// Non-convex, collinear and self-overlapping polygons: the triangulator, the self-intersection
// check and exact booleans of polygon solids.
mod polygons;
// Regressions named after the issue whose work found them.
mod regression;
// Every shared data mesh analysed: topology and measures agree with the manifest.
mod real_data;
// The orthogonal engine: design vectors E1-E10 and R1-R6.
mod ortho_cases;
// The orthogonal engine against a brute-force grid oracle; metamorphic relations.
mod ortho_oracle;
// The orthogonal engine on the shared MagicaVoxel models.
mod ortho_vox;
// Exact self-intersection counts agree with the manifest's reference.
mod self_intersection;
