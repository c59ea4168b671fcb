//! Criterion benches of the exact boolean engine: `exact/<op>/spheres/<triangles per sphere>`.
//!
//! Inputs: two icospheres of radius 1 (`primitives::icosphere`, 20·4^s triangles), the
//! second moved by (0.5, 0.1, 0.05) so the intersection curve crosses triangles in general
//! position, like the peers harness's `sphere_sphere` family. The operation runs without the
//! self-intersection check (its cost is the check's, measured by `csgkit check`).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use csgkit::Operation;
use csgkit::exact::{BooleanOptions, boolean};
use csgkit::primitives::icosphere;

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

criterion_group!(benches, spheres);
criterion_main!(benches);
