//! Loading speed of the readers on the largest shared meshes, in bytes per second, writing
//! speed of the writers on the largest mesh, in triangles per second, and both for 3MF and GLB
//! on that mesh (1.1 M triangles), in bytes of the file per second.
//!
//! Run: `cargo bench -p csgkit --bench io -- --warm-up-time 1 --measurement-time 3`.
//! Skips with a message when `../shared/data` is absent; `$CSGKIT_SHARED_DATA` overrides the
//! folder for a work tree kept elsewhere.

use std::path::{Path, PathBuf};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use csgkit::{Encoding, Format};

/// The benchmarked files: the large binary PLY, the largest OBJ and the largest ASCII STL.
const FILES: [&str; 3] = [
    "bunny_watertight_loop2.ply",
    "armadillo.obj",
    "ADIS16480.stl",
];

fn load(c: &mut Criterion) {
    let data = std::env::var_os("CSGKIT_SHARED_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
        PathBuf::from,
    );
    let dir = data.join("meshes");
    if !dir.is_dir() {
        eprintln!("skipping io benchmark: {} is absent", dir.display());
        return;
    }
    let mut group = c.benchmark_group("load");
    for name in FILES {
        let bytes = std::fs::read(dir.join(name)).expect("benchmark file is readable");
        let hint = csgkit::Format::from_extension(name.as_ref());
        let loaded = csgkit::read_mesh_from_bytes(&bytes, hint).expect("benchmark file loads");
        let triangles = loaded.mesh.fan_triangles().count();
        eprintln!("{name}: {} bytes, {triangles} triangles", bytes.len());
        group.throughput(Throughput::Bytes(bytes.len() as u64));
        group.bench_function(name, |b| {
            b.iter(|| csgkit::read_mesh_from_bytes(&bytes, hint).expect("loads"));
        });
    }
    group.finish();
    save(c, &dir);
    parts_formats(c, &dir);
}

/// Rendering the large PLY mesh in every format (into memory: the disk is not measured).
fn save(c: &mut Criterion, dir: &Path) {
    let name = FILES[0];
    let mesh = csgkit::read_mesh(dir.join(name))
        .expect("benchmark file loads")
        .mesh;
    let mut group = c.benchmark_group("save");
    group.throughput(Throughput::Elements(mesh.face_count() as u64));
    for (format, encoding) in [
        (Format::Ply, Encoding::Binary),
        (Format::Stl, Encoding::Binary),
        (Format::Obj, Encoding::Ascii),
        (Format::Off, Encoding::Ascii),
    ] {
        group.bench_function(format!("{name} as {format} {encoding:?}"), |b| {
            b.iter(|| csgkit::write_mesh_to_bytes(&mesh, format, encoding).expect("writes"));
        });
    }
    group.finish();
}

/// Writing and reading the large PLY mesh as 3MF and GLB, in bytes of the file per second
/// (the file csgkit writes is the one it reads; `scripts/trimesh_formats.py --bench` times
/// trimesh on the same mesh).
fn parts_formats(c: &mut Criterion, dir: &Path) {
    let name = FILES[0];
    let mesh = csgkit::read_mesh(dir.join(name))
        .expect("benchmark file loads")
        .mesh;
    let mut group = c.benchmark_group("formats");
    group.sample_size(10);
    for (format, extension) in [(Format::ThreeMf, "3mf"), (Format::Glb, "glb")] {
        let bytes = csgkit::write_mesh_to_bytes(&mesh, format, Encoding::Binary).expect("writes");
        eprintln!("{name} as {extension}: {} bytes", bytes.len());
        group.throughput(Throughput::Bytes(bytes.len() as u64));
        group.bench_function(format!("write/{extension}/{}", mesh.face_count()), |b| {
            b.iter(|| {
                csgkit::write_mesh_to_bytes(&mesh, format, Encoding::Binary).expect("writes")
            });
        });
        group.bench_function(format!("read/{extension}/{}", mesh.face_count()), |b| {
            b.iter(|| csgkit::read_mesh_from_bytes(&bytes, Some(format)).expect("reads"));
        });
    }
    group.finish();
}

criterion_group!(benches, load);
criterion_main!(benches);
