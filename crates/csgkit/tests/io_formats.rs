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

/// Each face as the formats keep it: its corner positions (as `round` leaves them), its
/// material name and its colour; sorted, since glTF groups faces by material.
fn face_descriptions(mesh: &Mesh, round: fn(f64) -> f64) -> Vec<(Vec<[u64; 3]>, String, [u8; 4])> {
    let mut faces: Vec<_> = (mesh.faces().enumerate())
        .map(|(f, corners)| {
            let points = (corners.iter())
                .map(|&v| mesh.positions()[v as usize].map(|c| round(c).to_bits()))
                .collect();
            let material = (mesh.face_materials())
                .map_or_else(String::new, |m| mesh.materials()[m[f] as usize].clone());
            let color = mesh.face_colors().map_or([255; 4], |c| c[f]);
            (points, material, color)
        })
        .collect();
    faces.sort();
    faces
}

fn to_f32(c: f64) -> f64 {
    f64::from(c as f32)
}

/// `c` as glTF gives it back: rounded to f32, and −0 as +0, since the reader welds equal
/// positions (two vertices that differ only in the sign of a zero are one).
fn as_gltf(c: f64) -> f64 {
    to_f32(c) + 0.0
}

/// A random triangle mesh with materials and colours from small sets: finite positions in the
/// f32 range (so glTF can hold them), any bits otherwise.
fn painted_triangle_mesh() -> impl Strategy<Value = Mesh> {
    let coordinate = any::<f64>().prop_filter("finite, in f32 range", |c| c.abs() < 1e38);
    let positions =
        prop::collection::vec([coordinate.clone(), coordinate.clone(), coordinate], 3..20);
    positions.prop_flat_map(|positions| {
        let n = positions.len() as u32;
        let face = ([0..n, 0..n, 0..n], 0u32..3, 0usize..3);
        prop::collection::vec(face, 1..12).prop_map(move |faces| {
            let colors = [[255, 0, 0, 255], [0, 128, 255, 64], [7, 7, 7, 7]];
            let parts = MeshParts {
                positions: positions.clone(),
                corners: faces.iter().flat_map(|f| f.0).collect(),
                face_materials: Some(faces.iter().map(|f| f.1).collect()),
                materials: vec!["stone".into(), "glass <&>".into(), "wood".into()],
                face_colors: Some(faces.iter().map(|f| colors[f.2]).collect()),
                ..MeshParts::default()
            };
            Mesh::from_parts(parts).expect("valid by construction")
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// csgkit → csgkit keeps positions bit-identical (3MF, OBJ, PLY, OFF) or f32-exact
    /// (glTF, GLB), and the materials and colours each format holds.
    #[test]
    fn every_format_round_trips_positions_materials_and_colours(mesh in painted_triangle_mesh()) {
        let exact = |c: f64| c;
        for format in [Format::ThreeMf, Format::Gltf, Format::Glb] {
            let bytes = write_mesh_to_bytes(&mesh, format, Encoding::default()).expect("writes");
            let back = read_mesh_from_bytes(&bytes, Some(format)).expect("reads back").mesh;
            let round = if format == Format::ThreeMf { exact } else { as_gltf };
            prop_assert_eq!(face_descriptions(&back, round), face_descriptions(&mesh, round));
            if format == Format::ThreeMf {
                prop_assert_eq!(back.positions(), mesh.positions());
                prop_assert_eq!(back.corners(), mesh.corners());
            }
        }
        // OBJ keeps materials (grouping faces by material), PLY and OFF keep colours.
        for format in [Format::Obj, Format::Ply, Format::Off] {
            let bytes = write_mesh_to_bytes(&mesh, format, Encoding::Binary).expect("writes");
            let back = read_mesh_from_bytes(&bytes, Some(format)).expect("reads back").mesh;
            prop_assert_eq!(back.positions(), mesh.positions(), "{}", format);
            if format == Format::Obj {
                let faces = |m: &Mesh| {
                    let ids = m.face_materials().expect("materials");
                    let mut faces: Vec<(Vec<u32>, String)> = (m.faces().zip(ids))
                        .map(|(f, &id)| (f.to_vec(), m.materials()[id as usize].clone()))
                        .collect();
                    faces.sort();
                    faces
                };
                prop_assert_eq!(faces(&back), faces(&mesh));
            } else {
                prop_assert_eq!(back.corners(), mesh.corners(), "{}", format);
                prop_assert_eq!(back.face_colors(), mesh.face_colors(), "{}", format);
            }
        }
    }
}

#[test]
fn glb_positions_are_the_nearest_f32_and_the_rounding_is_counted() {
    let mesh = Mesh::from_triangles(
        vec![[0.1, 0.5, 1e-40], [1.0, 0.0, 0.0], [0.0, 1.0 / 3.0, 0.0]],
        &[[0, 1, 2]],
    )
    .expect("a triangle");
    let bytes = write_mesh_to_bytes(&mesh, Format::Glb, Encoding::default()).expect("writes");
    let back = read_mesh_from_bytes(&bytes, None).expect("reads back").mesh;
    let expected: Vec<[f64; 3]> = mesh.positions().iter().map(|p| p.map(to_f32)).collect();
    assert_eq!(back.positions(), expected.as_slice());
    assert_eq!(
        csgkit::rounded_coordinates(&mesh, Format::Glb, Encoding::Binary),
        3
    );
    assert_eq!(
        csgkit::rounded_coordinates(&mesh, Format::ThreeMf, Encoding::Binary),
        0
    );
    let dir = tempfile::tempdir().expect("temporary folder");
    let written =
        write_mesh(dir.path().join("t.gltf"), &mesh, WriteOptions::default()).expect("writes");
    assert_eq!(written.rounded_coordinates, 3);
    let huge = Mesh::from_triangles(
        vec![[1e39, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2]],
    )
    .expect("a triangle");
    let refused = write_mesh_to_bytes(&huge, Format::Glb, Encoding::default()).unwrap_err();
    assert_eq!(
        refused.to_string(),
        "cannot write GLB: a coordinate is beyond the f32 range of glTF, or not finite"
    );
}

#[test]
fn the_stl_writer_triangulates_a_non_convex_polygon_exactly() {
    // An L-shaped hexagon: the fan from its first corner would cover the missing square.
    let l_shape = Mesh::from_polygons(
        vec![
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
        ],
        &[[0u32, 1, 2, 3, 4, 5]],
    )
    .expect("a hexagon");
    for format in [Format::Stl, Format::ThreeMf, Format::Glb] {
        let bytes = write_mesh_to_bytes(&l_shape, format, Encoding::Binary).expect("writes");
        let back = read_mesh_from_bytes(&bytes, Some(format))
            .expect("reads back")
            .mesh;
        assert_eq!(back.face_count(), 4, "{format}");
        let measures = csgkit::mesh::measure(&back);
        assert_eq!(measures.area, 3.0, "{format}");
        // No triangle covers the square (1..2, 1..2) that the L leaves out.
        for (_, t) in back.fan_triangles() {
            let centroid = [0, 1].map(|k| {
                t.iter()
                    .map(|&v| back.positions()[v as usize][k])
                    .sum::<f64>()
                    / 3.0
            });
            assert!(
                !(centroid[0] > 1.0 && centroid[1] > 1.0),
                "{format}: {centroid:?}"
            );
        }
    }
}

/// A 3MF archive holding `model` as its model part, and nothing else.
fn archive(model: &str) -> Vec<u8> {
    use std::io::Write;
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    zip.start_file("3D/3dmodel.model", zip::write::SimpleFileOptions::default())
        .expect("an entry");
    zip.write_all(model.as_bytes()).expect("written");
    zip.finish().expect("an archive").into_inner()
}

#[test]
fn malformed_files_of_every_format_get_exact_errors() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let model = "<model xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n\
        <resources><object id=\"7\"><mesh><vertices>\n<vertex x=\"0\" y=\"0\" z=\"0\"/>\n\
        <vertex x=\"1\" y=\"0\" z=\"0\"/>\n<vertex x=\"0\" y=\"1\" z=\"0\"/>\n</vertices><triangles>\n\
        <triangle v1=\"0\" v2=\"1\" v3=\"3\"/>\n</triangles></mesh></object></resources>\n\
        <build><item objectid=\"7\"/></build></model>\n";
    let mut not_3mf = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    not_3mf
        .start_file("a.txt", zip::write::SimpleFileOptions::default())
        .expect("an entry");
    let not_3mf = not_3mf.finish().expect("an archive").into_inner();
    let triangle = Mesh::from_triangles(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2]],
    )
    .expect("a triangle");
    let glb = write_mesh_to_bytes(&triangle, Format::Glb, Encoding::default()).expect("writes");
    let gltf = String::from_utf8(
        write_mesh_to_bytes(&triangle, Format::Gltf, Encoding::default()).expect("writes"),
    )
    .expect("JSON text");
    let cases: Vec<(&str, Vec<u8>, String)> = vec![
        ("a.obj", b"v 0 0 0\nv 1 0 0\nf 1 2 3\n".to_vec(), "line 3: face 0 refers to vertex 3, but 2 are defined".into()),
        ("a.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n".to_vec(), "line 4: malformed STL file: vertex needs 3 coordinates".into()),
        ("a.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 zero\n".to_vec(), "line 8: malformed number \"zero\"".into()),
        ("a.off", b"OFF\n1 0 0\n0 0\n".to_vec(), "line 3: malformed OFF file: a vertex needs 3 coordinates".into()),
        ("a.3mf", archive(model), "3D/3dmodel.model: object 7: line 7: face 0 refers to vertex 3, but 3 are defined".into()),
        ("b.3mf", archive(&model.replace("x=\"1\"", "x=\"1,5\"")), "3D/3dmodel.model: object 7, vertex 1, attribute x: line 4: malformed number \"1,5\"".into()),
        ("c.3mf", archive(&model.replace(" y=\"1\"", "")), "3D/3dmodel.model: object 7, vertex 2: line 5: malformed 3MF file: missing attribute y".into()),
        ("d.3mf", not_3mf, "malformed 3MF file: not a 3MF file: the zip archive has no 3D model part (no 3dmodel relationship in _rels/.rels and no 3D/3dmodel.model)".into()),
        ("a.glb", glb[..glb.len() - 4].to_vec(), format!("truncated file: GLB file needs {} bytes, the file has {}", glb.len(), glb.len() - 4)),
        ("a.gltf", gltf.replace("\"mode\":4", "\"mode\":0").into_bytes(), "nodes[0]: meshes[0].primitives[0]: unsupported glTF feature: primitive mode Points (csgkit reads Triangles)".into()),
    ];
    for (name, bytes, message) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).expect("written");
        let error = read_mesh(&path).expect_err(name);
        assert_eq!(
            error.to_string(),
            format!("{}: {message}", path.display()),
            "{name}"
        );
    }
}
