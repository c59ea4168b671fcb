//! Criterion benches of the orthogonal engine: `ortho/<stage>/<input>/<size>`.
//!
//! Inputs: n random integer boxes with sides 1–4 in a cube of side G = round((25n/0.7)^⅓)
//! (the peers harness's `boxes_union` family, fixed seed), and the shared `.vox` models
//! (`../shared/data/voxels`, or `$CSGKIT_SHARED_DATA/voxels`).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use csgkit::ortho::{MeshOptions, MeshOutput, VoxOptions, box_union, random_grid_boxes, read_vox};

fn random_boxes(c: &mut Criterion) {
    let mut group = c.benchmark_group("ortho");
    group.sample_size(10);
    for n in [100usize, 1_000, 10_000, 100_000] {
        let boxes = random_grid_boxes(n, 0x5eed);
        group.bench_with_input(BenchmarkId::new("brep/random", n), &boxes, |b, boxes| {
            b.iter(|| box_union(boxes).unwrap())
        });
        group.bench_with_input(BenchmarkId::new("mesh/random", n), &boxes, |b, boxes| {
            b.iter(|| union_mesh(boxes))
        });
    }
    group.finish();
}

fn vox_models(c: &mut Criterion) {
    let dir =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/voxels");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!("skipping .vox benches: {} is absent", dir.display());
        return;
    };
    let mut paths: Vec<_> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    let mut group = c.benchmark_group("ortho");
    group.sample_size(10);
    for path in paths
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "vox"))
    {
        let Ok(bytes) = std::fs::read(path) else {
            continue;
        };
        let Ok(read) = read_vox(&bytes, VoxOptions::default()) else {
            continue;
        };
        let name = path
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        group.bench_with_input(
            BenchmarkId::new("mesh/vox", name),
            &read.boxes,
            |b, boxes| b.iter(|| union_mesh(boxes)),
        );
    }
    group.finish();
}

criterion_group!(benches, random_boxes, vox_models);
criterion_main!(benches);

/// The whole engine: boxes to B-rep to the default shared-vertex mesh.
fn union_mesh(boxes: &[[f64; 6]]) -> MeshOutput {
    box_union(boxes)
        .expect("benchmark boxes are valid")
        .to_mesh(MeshOptions::default())
        .expect("benchmark unions fit a mesh")
}
