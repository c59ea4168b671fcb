//! Every real mesh in the shared data folder loads with the counts manifest.json measured, and
//! meshes round-trip through every writer and reader.

use std::path::Path;

use csgkit::mesh::triangulate_faces;
use csgkit::{
    Encoding, Format, Mesh, MeshParts, WriteError, WriteOptions, read_mesh, read_mesh_from_bytes,
    write_mesh, write_mesh_to_bytes,
};
use proptest::prelude::*;

use crate::util::{repo_data, shared_data};

/// `(file name, raw vertex count, raw face count)` for every mesh in the manifest.
fn manifest(data: &Path) -> Vec<(String, u64, u64)> {
    let text =
        std::fs::read_to_string(data.join("manifest.json")).expect("manifest.json is readable");
    let json: serde_json::Value = serde_json::from_str(&text).expect("manifest.json is JSON");
    let meshes = json["meshes"].as_array().expect("manifest lists meshes");
    meshes
        .iter()
        .map(|entry| {
            let measured = &entry["measured"];
            let name = measured["file"].as_str().expect("measured.file").to_owned();
            let verts = measured["raw_verts"].as_u64().expect("measured.raw_verts");
            let faces = measured["raw_faces"].as_u64().expect("measured.raw_faces");
            (name, verts, faces)
        })
        .collect()
}

#[test]
fn every_shared_mesh_loads_with_manifest_counts() {
    let Some(data) = shared_data() else { return };
    let entries = manifest(&data);
    let files = std::fs::read_dir(data.join("meshes"))
        .expect("meshes folder")
        .count();
    assert_eq!(entries.len(), files, "manifest and meshes folder disagree");
    for (name, verts, faces) in entries {
        let loaded = read_mesh(data.join("meshes").join(&name)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            loaded.raw_vertex_count as u64, verts,
            "{name}: raw vertex count"
        );
        assert_eq!(loaded.mesh.face_count() as u64, faces, "{name}: face count");
        loaded
            .mesh
            .check_invariants()
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn binary_stl_with_solid_header_loads_as_binary() {
    let Some(data) = shared_data() else { return };
    let loaded = read_mesh(data.join("meshes/plate_holes.stl")).expect("plate_holes.stl loads");
    assert_eq!(
        (loaded.format, loaded.encoding),
        (Format::Stl, Encoding::Binary)
    );
    assert!(
        loaded.mesh.vertex_count() < loaded.raw_vertex_count,
        "STL vertices are welded"
    );
}

#[test]
fn attributes_survive_loading() {
    let Some(data) = shared_data() else { return };
    let capsule = read_mesh(data.join("meshes/capsule.obj"))
        .expect("capsule.obj loads")
        .mesh;
    assert!(capsule.corner_uvs().is_some() && capsule.corner_normals().is_some());
    assert!(capsule.face_materials().is_some());
    assert!(!capsule.material_libraries().is_empty());
    let mixed = read_mesh(data.join("meshes/cgal_non_manifold_face_graph.off"))
        .expect("loads")
        .mesh;
    assert!(!mixed.is_triangle_mesh());
}

#[test]
fn every_format_round_trips_the_repo_cube() {
    let cube = read_mesh(repo_data("cube.obj"))
        .expect("cube.obj loads")
        .mesh;
    let dir = tempfile::tempdir().expect("temporary folder");
    for (name, encoding) in [
        ("c.obj", Encoding::Ascii),
        ("c.off", Encoding::Ascii),
        ("c.ply", Encoding::Binary),
        ("c.ply", Encoding::Ascii),
        ("c.stl", Encoding::Ascii),
    ] {
        let path = dir.path().join(name);
        let options = WriteOptions {
            encoding,
            ..WriteOptions::default()
        };
        write_mesh(&path, &cube, options).expect("writes");
        let back = read_mesh(&path).expect("reads back").mesh;
        if name == "c.stl" {
            // STL stores triangles and welds vertices in order of first use.
            let sorted = |mesh: &Mesh| {
                let mut positions = mesh.positions().to_vec();
                positions.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
                positions
            };
            assert_eq!(sorted(&back), sorted(&cube));
            assert_eq!(back.face_count(), 12);
        } else {
            assert_eq!(back.positions(), cube.positions(), "{name}");
            assert_eq!(back.corners(), cube.corners(), "{name}");
        }
    }
}

#[test]
fn content_wins_where_the_extension_lies() {
    let Some(data) = shared_data() else { return };
    let dir = tempfile::tempdir().expect("temporary folder");
    for (source, disguise, format) in [
        ("plate_holes.stl", "plate.obj", Format::Stl),
        ("two-boxes-bad-self-union.ply", "boxes.off", Format::Ply),
        ("ballA.off", "ball.stl", Format::Off),
        ("joint.obj", "joint.ply", Format::Obj),
    ] {
        let path = dir.path().join(disguise);
        std::fs::copy(data.join("meshes").join(source), &path).expect("copies");
        let loaded = read_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(loaded.format, format, "{source} as {disguise}");
    }
}

/// A random polygon mesh: finite positions of any magnitude and faces of 3 to 6 corners.
fn polygon_mesh() -> impl Strategy<Value = Mesh> {
    let finite = any::<f64>().prop_filter("finite", |c| c.is_finite());
    let positions = prop::collection::vec([finite.clone(), finite.clone(), finite], 3..20);
    positions.prop_flat_map(|positions| {
        let n = positions.len() as u32;
        let face = prop::collection::vec(0..n, 3..7);
        prop::collection::vec(face, 0..12).prop_map(move |faces| {
            let mut starts = vec![0];
            let corners: Vec<u32> = faces.concat();
            for face in &faces {
                starts.push(starts[starts.len() - 1] + face.len() as u32);
            }
            let parts = MeshParts {
                positions: positions.clone(),
                corners,
                face_starts: Some(starts),
                ..MeshParts::default()
            };
            Mesh::from_parts(parts).expect("valid by construction")
        })
    })
}

/// What STL keeps of a mesh: its triangles ([`triangulate_faces`]) as position triples, or
/// `None` when a polygon cannot be triangulated, which the writer refuses.
fn triangle_soup(mesh: &Mesh) -> Option<Vec<[[f64; 3]; 3]>> {
    let positions = mesh.positions();
    let triangles = triangulate_faces(mesh).ok()?;
    Some(
        triangles
            .iter()
            .map(|(_, t)| t.map(|v| positions[v as usize]))
            .collect(),
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn random_polygon_meshes_round_trip_exactly(mesh in polygon_mesh()) {
        for (format, encoding) in [
            (Format::Obj, Encoding::Ascii),
            (Format::Off, Encoding::Ascii),
            (Format::Ply, Encoding::Binary),
            (Format::Ply, Encoding::Ascii),
        ] {
            let bytes = write_mesh_to_bytes(&mesh, format, encoding).expect("writes");
            let back = read_mesh_from_bytes(&bytes, Some(format)).expect("reads back").mesh;
            prop_assert_eq!(back.positions(), mesh.positions(), "{:?} {:?}", format, encoding);
            prop_assert_eq!(back.faces().collect::<Vec<_>>(), mesh.faces().collect::<Vec<_>>());
        }
        let written = write_mesh_to_bytes(&mesh, Format::Stl, Encoding::Ascii);
        match triangle_soup(&mesh) {
            Some(soup) => {
                let bytes = written.expect("writes");
                let back = read_mesh_from_bytes(&bytes, Some(Format::Stl)).expect("reads back");
                prop_assert_eq!(triangle_soup(&back.mesh), Some(soup));
            }
            None => {
                let refused = matches!(written, Err(WriteError::InvalidPolygon { .. }));
                prop_assert!(refused, "{:?}", written.map(|b| b.len()));
            }
        }
    }
}
