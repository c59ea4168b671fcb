//! The degenerate suite of `design/exact.md`: touching, coplanar, identical, nested and
//! disjoint operands, with exact volumes.

use csgkit::Mesh;
use csgkit::csg::primitives::cuboid;
use csgkit::exact::{BooleanOptions, Operation, boolean};

use Operation::{Difference, Intersection, Union};

/// Runs `op`, checks the result is a closed, oriented solid, and returns its volume.
fn volume_of(op: Operation, operands: &[&Mesh]) -> f64 {
    let result = boolean(op, operands, &BooleanOptions::default())
        .unwrap_or_else(|e| panic!("{op:?} failed: {e}"));
    let report = result.mesh.report();
    assert!(
        report.is_valid_solid(),
        "{op:?}: not a closed oriented solid: {report:?}"
    );
    report.measures.volume
}

fn unit_cube_at(x: f64, y: f64, z: f64) -> Mesh {
    cuboid([x, y, z], [x + 1.0, y + 1.0, z + 1.0])
}

/// Asserts `actual` is `expected` up to the rounding of summing a volume.
fn assert_volume(actual: f64, expected: f64, what: &str) {
    let error = (actual - expected).abs();
    assert!(
        error <= 1e-12 * expected.abs().max(1.0),
        "{what}: volume {actual}, expected {expected}"
    );
}

/// Volumes of ∪, ∩, − for two operands, checked against the expected values.
fn check_all(a: &Mesh, b: &Mesh, union: f64, intersection: f64, difference: f64) {
    assert_volume(volume_of(Union, &[a, b]), union, "union");
    assert_volume(
        volume_of(Intersection, &[a, b]),
        intersection,
        "intersection",
    );
    assert_volume(volume_of(Difference, &[a, b]), difference, "difference");
}

#[test]
fn cubes_sharing_a_face() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(1.0, 0.0, 0.0),
        2.0,
        0.0,
        1.0,
    );
}

#[test]
fn cubes_sharing_part_of_a_face() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(1.0, 0.5, 0.5),
        2.0,
        0.0,
        1.0,
    );
}

#[test]
fn cubes_sharing_an_edge() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(1.0, 1.0, 0.0),
        2.0,
        0.0,
        1.0,
    );
}

#[test]
fn cubes_sharing_a_vertex() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(1.0, 1.0, 1.0),
        2.0,
        0.0,
        1.0,
    );
}

#[test]
fn overlapping_cubes() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(0.5, 0.5, 0.5),
        1.875,
        0.125,
        0.875,
    );
}

#[test]
fn cube_with_itself() {
    let a = unit_cube_at(0.0, 0.0, 0.0);
    check_all(&a, &a.clone(), 1.0, 1.0, 0.0);
}

#[test]
fn cube_minus_a_flush_cube() {
    let a = cuboid([0.0; 3], [2.0; 3]);
    let b = cuboid([0.5, 0.5, 1.0], [1.5, 1.5, 2.0]);
    check_all(&a, &b, 8.0, 1.0, 7.0);
}

#[test]
fn nested_and_disjoint_cubes() {
    let outer = cuboid([0.0; 3], [3.0; 3]);
    let inner = unit_cube_at(1.0, 1.0, 1.0);
    check_all(&outer, &inner, 27.0, 1.0, 26.0);
    check_all(&inner, &outer, 27.0, 1.0, 0.0);
    let far = unit_cube_at(5.0, 0.0, 0.0);
    check_all(&inner, &far, 2.0, 0.0, 1.0);
}
