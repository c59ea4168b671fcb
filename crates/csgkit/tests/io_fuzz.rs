//! No reader panics: truncated, corrupted and random bytes give `Ok` or `Err`, never a panic.

use std::sync::OnceLock;

use csgkit::{Encoding, Format, Mesh, MeshParts, read_mesh_from_bytes, write_mesh_to_bytes};
use proptest::prelude::*;

use crate::util::shared_data;

const FORMATS: [Option<Format>; 8] = [
    None,
    Some(Format::Obj),
    Some(Format::Stl),
    Some(Format::Ply),
    Some(Format::Off),
    Some(Format::ThreeMf),
    Some(Format::Gltf),
    Some(Format::Glb),
];

const PLY_HEADER: &str = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
    element face 1\nproperty list uchar int vertex_indices\nend_header\n";

/// Small valid files of every kind, the seeds that corruption starts from.
fn seeds() -> Vec<Vec<u8>> {
    let mut seeds = vec![
        b"v 0 0 0\nv 1 0 0\nv 0 1 0 1 0 0\nvt 0 0\nvn 0 0 1\ng a\nusemtl m\nf 1/1/1 2//1 -1/1\n"
            .to_vec(),
        b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n".to_vec(),
        b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
          endloop\nendfacet\nendsolid\n"
            .to_vec(),
        format!("ply\nformat ascii 1.0\n{PLY_HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes(),
    ];
    let mut binary_ply = format!("ply\nformat binary_little_endian 1.0\n{PLY_HEADER}").into_bytes();
    for c in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        binary_ply.extend_from_slice(&c.to_le_bytes());
    }
    binary_ply.push(3);
    for v in [0i32, 1, 2] {
        binary_ply.extend_from_slice(&v.to_le_bytes());
    }
    seeds.push(binary_ply);
    let mut binary_stl = b"solid but binary".to_vec();
    binary_stl.resize(80, 0);
    binary_stl.extend_from_slice(&1u32.to_le_bytes());
    for c in [
        0.0f32, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0,
    ] {
        binary_stl.extend_from_slice(&c.to_le_bytes());
    }
    binary_stl.extend_from_slice(&[0, 0]);
    seeds.push(binary_stl);
    let mut binary_off = b"OFF BINARY\n".to_vec();
    for n in [3i32, 1, 0] {
        binary_off.extend_from_slice(&n.to_be_bytes());
    }
    for c in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        binary_off.extend_from_slice(&c.to_be_bytes());
    }
    for n in [3i32, 0, 1, 2, 0] {
        binary_off.extend_from_slice(&n.to_be_bytes());
    }
    seeds.push(binary_off);
    let triangle = Mesh::from_parts(MeshParts {
        positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        corners: vec![0, 1, 2],
        face_materials: Some(vec![0]),
        materials: vec!["m".into()],
        face_colors: Some(vec![[1, 2, 3, 4]]),
        corner_uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        ..MeshParts::default()
    })
    .expect("a valid triangle");
    for format in [Format::ThreeMf, Format::Gltf, Format::Glb] {
        seeds.push(write_mesh_to_bytes(&triangle, format, Encoding::default()).expect("written"));
    }
    seeds
}

/// The real files in the shared data folder smaller than 30 kB (none if it is absent).
fn small_real_files() -> &'static [Vec<u8>] {
    static FILES: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    FILES.get_or_init(|| {
        let Some(data) = shared_data() else {
            return Vec::new();
        };
        let entries = std::fs::read_dir(data.join("meshes")).expect("meshes folder");
        let mut paths: Vec<_> = entries.map(|e| e.expect("folder entry").path()).collect();
        paths.sort();
        paths
            .iter()
            .map(|path| std::fs::read(path).expect("readable"))
            .filter(|bytes| bytes.len() < 30_000)
            .collect()
    })
}

/// Runs every reader on `bytes`; a panic fails the property.
fn read_all(bytes: &[u8]) {
    for hint in FORMATS {
        let _ = read_mesh_from_bytes(bytes, hint);
    }
}

/// `bytes` with the byte at each `(position modulo length, value)` of `flips` replaced.
fn corrupt(mut bytes: Vec<u8>, flips: &[(usize, u8)]) -> Vec<u8> {
    let len = bytes.len();
    for &(at, byte) in flips {
        bytes[at % len] = byte;
    }
    bytes
}

#[test]
fn seeds_are_valid() {
    for seed in seeds() {
        let loaded = read_mesh_from_bytes(&seed, None).expect("seed parses");
        assert_eq!(loaded.mesh.face_count(), 1);
    }
}

#[test]
fn every_truncation_of_every_seed() {
    for seed in seeds() {
        for len in 0..seed.len() {
            read_all(&seed[..len]);
        }
    }
}

fn flips(max: usize) -> impl Strategy<Value = Vec<(usize, u8)>> {
    prop::collection::vec((any::<usize>(), any::<u8>()), 1..max)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4000, ..ProptestConfig::default() })]

    #[test]
    fn corrupted_seeds(seed in 0usize..10, flips in flips(8)) {
        read_all(&corrupt(seeds()[seed].clone(), &flips));
    }

    #[test]
    fn random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        read_all(&bytes);
    }

    #[test]
    fn random_text_after_a_header(
        header in prop::sample::select(vec![
            "ply\nformat ascii 1.0\n",
            "OFF\n",
            "solid\n",
            "v 1 2 3\n",
            "{\"asset\": {\"version\": \"2.0\"}, ",
            "OFF BINARY\n",
            "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty list uint double x\n\
             end_header\n",
        ]),
        body in "[ -~\n]{0,200}",
    ) {
        read_all(format!("{header}{body}").as_bytes());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn corrupted_real_files(pick in any::<usize>(), flips in flips(16), cut in any::<usize>()) {
        let files = small_real_files();
        if !files.is_empty() {
            let bytes = corrupt(files[pick % files.len()].clone(), &flips);
            read_all(&bytes);
            read_all(&bytes[..cut % bytes.len()]);
        }
    }
}
