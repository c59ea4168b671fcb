//! No reader panics: truncated, corrupted and random bytes give `Ok` or `Err`, never a panic.

use csgkit::{Format, read_mesh_from_bytes};
use proptest::prelude::*;

use crate::util::shared_data;

const FORMATS: [Option<Format>; 5] = [
    None,
    Some(Format::Obj),
    Some(Format::Stl),
    Some(Format::Ply),
    Some(Format::Off),
];

/// Small valid files of every kind, the seeds that corruption starts from.
fn seeds() -> Vec<Vec<u8>> {
    let mut seeds = vec![
        b"v 0 0 0\nv 1 0 0\nv 0 1 0 1 0 0\nvt 0 0\nvn 0 0 1\ng a\nusemtl m\nf 1/1/1 2//1 -1/1\n".to_vec(),
        b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n".to_vec(),
        b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n".to_vec(),
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".to_vec(),
    ];
    let mut binary_ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
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
    seeds
}

/// Runs every reader on `bytes`; a panic fails the property.
fn read_all(bytes: &[u8]) {
    for hint in FORMATS {
        let _ = read_mesh_from_bytes(bytes, hint);
    }
}

/// The real files in the shared data folder smaller than 30 kB (none if it is absent).
fn small_real_files() -> Vec<Vec<u8>> {
    let Some(data) = shared_data() else {
        return Vec::new();
    };
    let entries = std::fs::read_dir(data.join("meshes")).expect("meshes folder");
    let mut files: Vec<_> = entries.map(|e| e.expect("folder entry").path()).collect();
    files.sort();
    files
        .iter()
        .map(|path| std::fs::read(path).expect("readable"))
        .filter(|bytes| bytes.len() < 30_000)
        .collect()
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

proptest! {
    #![proptest_config(ProptestConfig { cases: 4000, ..ProptestConfig::default() })]

    #[test]
    fn corrupted_seeds(seed in 0usize..6, flips in prop::collection::vec((any::<usize>(), any::<u8>()), 1..8)) {
        let mut bytes = seeds()[seed].clone();
        for (at, byte) in flips {
            let len = bytes.len();
            bytes[at % len] = byte;
        }
        read_all(&bytes);
    }

    #[test]
    fn random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        read_all(&bytes);
    }

    #[test]
    fn random_text_after_a_header(
        header in prop::sample::select(vec!["ply\nformat ascii 1.0\n", "OFF\n", "solid\n", "v 1 2 3\n", "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty list uint double x\nend_header\n"]),
        body in "[ -~\n]{0,200}",
    ) {
        read_all(format!("{header}{body}").as_bytes());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn corrupted_real_files(pick in any::<usize>(), flips in prop::collection::vec((any::<usize>(), any::<u8>()), 1..16), cut in any::<usize>()) {
        let files = small_real_files();
        if !files.is_empty() {
            let mut bytes = files[pick % files.len()].clone();
            for (at, byte) in flips {
                let len = bytes.len();
                bytes[at % len] = byte;
            }
            let len = bytes.len();
            read_all(&bytes);
            read_all(&bytes[..cut % len]);
        }
    }
}
