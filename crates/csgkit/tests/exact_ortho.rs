//! Cross-check of the exact engine with the orthogonal engine (`design/exact.md`, "Tests that
//! define done"): the union of integer boxes computed by `exact` (one n-ary union of cuboid
//! meshes) and by `ortho` (`box_union`, then `BRep::to_mesh`) has the same volume and the same
//! boundary area.
//!
//! Both results have only axis-aligned faces, so both are measured exactly, in rationals
//! ([`exact_volume`], [`axis_aligned_area`]), and compared for equality. The exact engine's vertices include
//! rounded crossings of the boxes' face diagonals (coplanar faces are triangulated together),
//! which stay in their planes and so do not change the exact area or volume; `mesh.report()`'s
//! float area is compared to a relative 1e-12.

use csgkit::exact::{BooleanOptions, boolean};
use csgkit::ortho::{MeshOptions, box_union, random_grid_boxes};
use csgkit::primitives::cuboid;
use csgkit::{Mesh, Operation};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

use crate::util::{assert_no_self_intersection, axis_aligned_area, exact_volume};

/// The union by the exact engine, as one n-ary operation on cuboid meshes.
fn exact_union(boxes: &[[f64; 6]]) -> Mesh {
    let meshes: Vec<Mesh> = (boxes.iter())
        .map(|b| cuboid([b[0], b[1], b[2]], [b[3], b[4], b[5]]))
        .collect();
    let operands: Vec<&Mesh> = meshes.iter().collect();
    boolean(Operation::Union, &operands, &BooleanOptions::default())
        .unwrap_or_else(|e| panic!("exact union of {} boxes failed: {e}", boxes.len()))
        .mesh
}

/// The union by the orthogonal engine, triangulated.
fn ortho_union(boxes: &[[f64; 6]]) -> Mesh {
    let options = MeshOptions {
        triangles: true,
        manifold: false,
    };
    (box_union(boxes).and_then(|brep| brep.to_mesh(options)))
        .unwrap_or_else(|e| panic!("ortho union failed: {e}"))
        .mesh
}

/// Asserts both engines give valid solids with equal volume and area.
fn cross_check(boxes: &[[f64; 6]]) {
    let (exact, ortho) = (exact_union(boxes), ortho_union(boxes));
    let (exact_report, ortho_report) = (exact.report(), ortho.report());
    assert!(ortho_report.is_valid_solid(), "ortho: not a valid solid");
    assert!(
        exact_report.is_valid_solid(),
        "exact: not a closed, oriented solid: {} unbalanced, {} misoriented edges",
        exact_report.topology.unbalanced_edges,
        exact_report.topology.misoriented_edges
    );
    assert_no_self_intersection(&exact, "exact union of boxes");
    let (volume_e, volume_o) = (exact_volume(&exact), exact_volume(&ortho));
    assert!(
        volume_e == volume_o,
        "volume: exact {volume_e} vs ortho {volume_o} (as f64: {} vs {})",
        exact_report.measures.volume,
        ortho_report.measures.volume
    );
    let area_o = axis_aligned_area(&ortho).unwrap_or_else(|e| panic!("ortho: {e}"));
    let area_e = axis_aligned_area(&exact).unwrap_or_else(|e| panic!("exact: {e}"));
    assert!(area_e == area_o, "area: exact {area_e} vs ortho {area_o}");
    let (exact_area, ortho_area) = (exact_report.measures.area, ortho_report.measures.area);
    assert!(
        (exact_area - ortho_area).abs() <= 1e-12 * ortho_area,
        "mesh.report() area, exact {exact_area} vs ortho {ortho_area}"
    );
}

/// Integer boxes in `[0, 6]³` with sides 1–3: small enough that most sets touch and overlap.
fn integer_box() -> impl Strategy<Value = [f64; 6]> {
    let side = || (0..6i32).prop_flat_map(|lo| (Just(lo), lo + 1..=(lo + 3).min(6)));
    (side(), side(), side())
        .prop_map(|((x0, x1), (y0, y1), (z0, z1))| [x0, y0, z0, x1, y1, z1].map(f64::from))
}

proptest! {
    #![proptest_config(Config {
        cases: 64,
        rng_seed: RngSeed::Fixed(0x00c5_9c17),
        failure_persistence: None,
        max_shrink_iters: 512,
        ..Config::default()
    })]

    #[test]
    fn random_integer_boxes(boxes in proptest::collection::vec(integer_box(), 1..=8)) {
        cross_check(&boxes);
    }
}

/// The peers' `boxes_union` distribution (sides 1–4, about 70% coverage), larger sets.
#[test]
fn random_grid_box_sets() {
    for (n, seed) in [(10, 1), (20, 2), (40, 3)] {
        cross_check(&random_grid_boxes(n, seed));
    }
}

/// A 3 × 3 × 3 checkerboard of unit cubes: every contact is an edge or a vertex, so the
/// union has non-manifold edges and vertices everywhere (the output must keep them).
#[test]
fn checkerboard_of_cubes() {
    let mut boxes = Vec::new();
    for x in 0..3 {
        for y in 0..3 {
            for z in 0..3 {
                if (x + y + z) % 2 == 0 {
                    boxes.push([x, y, z, x + 1, y + 1, z + 1].map(f64::from));
                }
            }
        }
    }
    cross_check(&boxes);
}

/// Steps and slabs sharing faces: a staircase on a plate, with a bridge over it.
#[test]
fn staircase_on_a_plate() {
    let boxes = [
        [0.0, 0.0, 0.0, 6.0, 4.0, 1.0],
        [0.0, 0.0, 1.0, 2.0, 4.0, 2.0],
        [0.0, 0.0, 2.0, 1.0, 4.0, 3.0],
        [2.0, 1.0, 1.0, 4.0, 3.0, 2.0],
        [1.0, 1.0, 3.0, 5.0, 2.0, 4.0],
        [4.0, 0.0, 1.0, 5.0, 4.0, 4.0],
    ];
    cross_check(&boxes);
}

// Reduced cases of the failures above (smallest found by deleting and shrinking boxes).

/// Two boxes with coplanar faces (x = 1, y = 0, y = 1, z = 0, z = 2): the crossings of their
/// face diagonals are rounded to f64. Rounded to the nearest f64 they keep their plane
/// coordinate exactly; the union must stay axis-aligned.
#[test]
fn two_boxes_with_coplanar_faces() {
    cross_check(&[
        [0.0, 0.0, 0.0, 3.0, 1.0, 2.0],
        [0.0, 0.0, 0.0, 1.0, 1.0, 3.0],
    ]);
}

/// Three boxes whose faces coincide in the planes x = 0 and z = 1 (every pair alone works):
/// inside one triangle, the edges of the two other operands cross.
#[test]
fn three_boxes_with_three_coplanar_faces() {
    cross_check(&[
        [0.0, 1.0, 1.0, 1.0, 2.0, 2.0],
        [0.0, 0.0, 0.0, 1.0, 2.0, 1.0],
        [0.0, 1.0, 0.0, 2.0, 2.0, 1.0],
    ]);
}

/// A box flush inside another (five faces shared) and a third box on top of them: every pair
/// alone works.
#[test]
fn flush_box_inside_and_box_on_top() {
    cross_check(&[
        [0.0, 0.0, 0.0, 2.0, 1.0, 2.0],
        [0.0, 0.0, 1.0, 2.0, 1.0, 2.0],
        [0.0, 1.0, 1.0, 1.0, 2.0, 2.0],
    ]);
}

/// Two overlapping boxes flush with a third along the planes x = 2, y = 0, y = 1, z = 2.
#[test]
fn three_boxes_overlapping_flush() {
    cross_check(&[
        [0.0, 1.0, 0.0, 2.0, 2.0, 3.0],
        [1.0, 0.0, 0.0, 2.0, 1.0, 2.0],
        [0.0, 0.0, 1.0, 2.0, 1.0, 2.0],
    ]);
}

/// Three unit cubes in a row sharing faces, and a fourth far away (each part alone works).
#[test]
fn chain_of_cubes_and_a_disjoint_cube() {
    cross_check(&[
        [0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        [1.0, 0.0, 0.0, 2.0, 1.0, 1.0],
        [2.0, 0.0, 0.0, 3.0, 1.0, 1.0],
        [10.0, 10.0, 10.0, 11.0, 11.0, 11.0],
    ]);
}
