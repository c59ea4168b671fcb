//! The exact self-intersection check agrees with the reference counts (libigl/CGAL,
//! detect-only) in manifest.json for every mesh of the shared data folder.

use std::path::Path;
use std::time::Instant;

use csgkit::{read_mesh, self_intersections};

use crate::util::shared_data;

/// `(file name, selfint_pairs, selfint_faces)` for every mesh in the manifest.
fn manifest(data: &Path) -> Vec<(String, usize, usize)> {
    let text =
        std::fs::read_to_string(data.join("manifest.json")).expect("manifest.json is readable");
    let json: serde_json::Value = serde_json::from_str(&text).expect("manifest.json is JSON");
    let count = |v: &serde_json::Value, key: &str| {
        v[key].as_u64().unwrap_or_else(|| panic!("measured.{key}")) as usize
    };
    json["meshes"]
        .as_array()
        .expect("manifest lists meshes")
        .iter()
        .map(|entry| {
            let measured = &entry["measured"];
            let name = measured["file"].as_str().expect("measured.file").to_owned();
            let pairs = count(measured, "selfint_pairs");
            let faces = count(measured, "selfint_faces");
            (name, pairs, faces)
        })
        .collect()
}

#[test]
fn self_intersections_match_manifest() {
    let Some(data) = shared_data() else { return };
    let mut disagreements = Vec::new();
    for (name, pairs, faces) in manifest(&data) {
        let mesh = read_mesh(data.join("meshes").join(&name))
            .unwrap_or_else(|e| panic!("{e}"))
            .mesh;
        let start = Instant::now();
        let found = self_intersections(&mesh);
        eprintln!(
            "{name}: {} pairs / {} faces (manifest {pairs} / {faces}), {:.3} s",
            found.pair_count(),
            found.face_count(),
            start.elapsed().as_secs_f64()
        );
        if (found.pair_count(), found.face_count()) != (pairs, faces) {
            disagreements.push(name);
        }
    }
    assert!(disagreements.is_empty(), "disagree: {disagreements:?}");
}
