//! Criterion benches of the exact boolean engine:
//! - `exact/<op>/spheres/<triangles per sphere>`: the cost that grows with the input;
//! - `exact/cubes/<case>`: the fixed cost of one boolean, on the two unit cubes of the peers
//!   harness's `coplanar` family (issue 12's target: under 0.3 ms in any touching
//!   configuration), since CSG trees and chained operations run thousands of small booleans;
//! - `exact/rotated/<axis>_<op>`: the unit cube against itself turned by 1e-7 rad, as the
//!   harness's `rotated` family: the small case where every intersection point is in general
//!   position and nearly every predicate lands within an ulp of zero.
//!
//! Spheres: two icospheres of radius 1 (`primitives::icosphere`, 20·4^s triangles), the
//! second moved by (0.5, 0.1, 0.05) so the intersection curve crosses triangles in general
//! position, like the peers harness's `sphere_sphere` family. The operation runs without the
//! self-intersection check (its cost is the check's, measured by `csgkit check`).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use csgkit::Operation;
use csgkit::exact::{BooleanOptions, boolean};
use csgkit::mesh::{Affine, transformed};
use csgkit::primitives::{cuboid, icosphere};

fn spheres(c: &mut Criterion) {
    let mut group = c.benchmark_group("exact");
    group.sample_size(10);
    let options = BooleanOptions {
        check_self_intersections: false,
        ..BooleanOptions::default()
    };
    for subdivisions in [3u32, 5, 7] {
        let a = icosphere([0.0; 3], 1.0, subdivisions);
        let b = icosphere([0.5, 0.1, 0.05], 1.0, subdivisions);
        for op in Operation::ALL {
            let name = format!("{op:?}/spheres").to_lowercase();
            group.bench_with_input(
                BenchmarkId::new(name, a.face_count()),
                &(&a, &b),
                |bench, (a, b)| bench.iter(|| boolean(op, &[a, b], &options).unwrap()),
            );
        }
    }
    group.finish();
}

/// The unit cube `A = [0, 1]³` against `B`, as the peers harness's `coplanar` cases, with the
/// self-intersection check of the operands (as `csgkit` runs by default).
fn cubes(c: &mut Criterion) {
    let mut group = c.benchmark_group("exact/cubes");
    let a = cuboid([0.0; 3], [1.0; 3]);
    let cases = [
        (
            "shared_face",
            Operation::Union,
            [1.0, 0.0, 0.0],
            [2.0, 1.0, 1.0],
        ),
        (
            "partial_face",
            Operation::Union,
            [0.5, 0.5, 1.0],
            [1.5, 1.5, 2.0],
        ),
        (
            "shared_edge",
            Operation::Union,
            [1.0, 1.0, 0.0],
            [2.0, 2.0, 1.0],
        ),
        ("shared_vertex", Operation::Union, [1.0; 3], [2.0; 3]),
        ("union_itself", Operation::Union, [0.0; 3], [1.0; 3]),
        (
            "intersect_itself",
            Operation::Intersection,
            [0.0; 3],
            [1.0; 3],
        ),
        ("minus_itself", Operation::Difference, [0.0; 3], [1.0; 3]),
        (
            "minus_flush",
            Operation::Difference,
            [0.25, 0.25, 0.5],
            [0.75, 0.75, 1.0],
        ),
    ];
    let options = BooleanOptions::default();
    for (name, op, min, max) in cases {
        let b = cuboid(min, max);
        group.bench_function(name, |bench| {
            bench.iter(|| boolean(op, &[&a, &b], &options).unwrap())
        });
    }
    group.finish();
}

/// The harness's `rotated` cases: `[-0.5, 0.5]³` and the same cube turned by 1e-7 rad about
/// `axis` (Rodrigues' formula), with the operands' self-intersection check.
fn rotated(c: &mut Criterion) {
    let mut group = c.benchmark_group("exact/rotated");
    let cube = cuboid([-0.5; 3], [0.5; 3]);
    let options = BooleanOptions::default();
    for (axis_name, axis) in [("z", [0.0, 0.0, 1.0]), ("xyz", [1.0, 2.0, 3.0])] {
        let turned = transformed(&cube, &rotation(axis, 1e-7)).expect("a rotation is regular");
        for op in Operation::ALL {
            let name = format!("{axis_name}_{op:?}").to_lowercase();
            group.bench_function(name, |bench| {
                bench.iter(|| boolean(op, &[&cube, &turned], &options).unwrap())
            });
        }
    }
    group.finish();
}

/// The rotation by `angle` about `axis` (any length).
fn rotation(axis: [f64; 3], angle: f64) -> Affine {
    let length = axis.iter().map(|x| x * x).sum::<f64>().sqrt();
    let [x, y, z] = axis.map(|a| a / length);
    let (sin, cos) = angle.sin_cos();
    let t = 1.0 - cos;
    [
        [
            t * x * x + cos,
            t * x * y - sin * z,
            t * x * z + sin * y,
            0.0,
        ],
        [
            t * x * y + sin * z,
            t * y * y + cos,
            t * y * z - sin * x,
            0.0,
        ],
        [
            t * x * z - sin * y,
            t * y * z + sin * x,
            t * z * z + cos,
            0.0,
        ],
    ]
}

criterion_group!(benches, spheres, cubes, rotated);
criterion_main!(benches);
