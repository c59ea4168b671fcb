//! Discrete engine benches: `discrete/<input>/<columns per side>`.
//!
//! Inputs are built in code (an icosphere), so the benches need no data files; the peers
//! harness compares real models with other voxelisers (see `benches/README.md`).

use criterion::{Criterion, criterion_group, criterion_main};
use csgkit::discrete::{DiscretizeOptions, Grid, discretize};
use csgkit::primitives::icosphere;

fn voxelize(c: &mut Criterion) {
    let sphere = icosphere([0.5; 3], 0.45, 6);
    let mut group = c.benchmark_group("discrete");
    group.sample_size(10);
    for n in [256u32, 1024] {
        let grid = Grid::new(1.0 / f64::from(n), 8).unwrap();
        group.bench_function(format!("voxelize/icosphere6/{n}"), |b| {
            b.iter(|| discretize(&sphere, grid, 0, DiscretizeOptions::default()).unwrap())
        });
    }
    let other = icosphere([0.7, 0.5, 0.55], 0.3, 6);
    let grid = Grid::new(1.0 / 512.0, 8).unwrap();
    let a = discretize(&sphere, grid, 0, DiscretizeOptions::default()).unwrap();
    let b = discretize(&other, grid, 0, DiscretizeOptions::default()).unwrap();
    group.bench_function("union/icosphere6/512", |bench| {
        bench.iter(|| a.union(&b).unwrap())
    });
    group.bench_function("difference/icosphere6/512", |bench| {
        bench.iter(|| a.difference(&b).unwrap())
    });
    group.bench_function("surfels/icosphere6/512", |bench| {
        bench.iter(|| a.to_surfel_mesh().unwrap())
    });
    group.finish();
}

criterion_group!(benches, voxelize);
criterion_main!(benches);
