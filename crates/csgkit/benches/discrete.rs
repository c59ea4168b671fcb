//! Discrete engine benches: `discrete/<input>/<columns per side>`.
//!
//! Inputs are built in code (an icosphere), so the benches need no data files; the peers
//! harness compares real models with other voxelisers (see `benches/README.md`).

use criterion::{Criterion, criterion_group, criterion_main};
use csgkit::Mesh;
use csgkit::discrete::{DiscretizeOptions, Grid, discretize};

/// A subdivided icosahedron of radius `r` around `c`.
fn icosphere(c: [f64; 3], r: f64, subdivisions: u32) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pts: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        for [a, b, c] in tris {
            let mut m = |i: u32, j: u32| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    pts.push([0, 1, 2].map(|d| (pts[i as usize][d] + pts[j as usize][d]) / 2.0));
                    pts.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    let positions = pts
        .iter()
        .map(|p| {
            let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            [0, 1, 2].map(|d| c[d] + r * p[d] / n)
        })
        .collect();
    Mesh::from_triangles(positions, &tris).unwrap()
}

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
