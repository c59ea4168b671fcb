use super::*;
use crate::io::no_external_files;
use crate::mesh::{Mesh, MeshParts};

/// A tetrahedron, faces grouped by (material, colour) as the writer's primitives group them.
fn tetrahedron(corner_attributes: bool) -> Mesh {
    Mesh::from_parts(MeshParts {
        positions: vec![
            [0.1, 0.2, 0.3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, -5.5],
            [2.0, 1e17, 7.25],
        ],
        corners: vec![0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2],
        face_materials: Some(vec![0, 0, 1, 1]),
        materials: vec!["stone".into(), "glass".into()],
        face_colors: Some(vec![
            [1, 2, 3, 4],
            [1, 2, 3, 4],
            [9, 9, 9, 255],
            [9, 9, 9, 255],
        ]),
        corner_uvs: corner_attributes.then(|| (0..12).map(|c| [f64::from(c) / 8.0, 0.5]).collect()),
        corner_normals: corner_attributes.then(|| (0..12).map(|c| [0.0, 1.0, c as f32]).collect()),
        ..MeshParts::default()
    })
    .unwrap()
}

/// `mesh` with each coordinate rounded to f32, as glTF stores it.
fn as_f32(mesh: &Mesh) -> Mesh {
    let mut parts = mesh.clone().into_parts();
    for p in &mut parts.positions {
        *p = p.map(|c| f64::from(c as f32));
    }
    Mesh::from_parts(parts).unwrap()
}

fn round_trip(mesh: &Mesh, format: Format) -> Mesh {
    let mut out = Vec::new();
    write::write(mesh, format, &mut out).unwrap();
    let loaded = read(&out, &no_external_files).unwrap();
    assert_eq!(loaded.format, format);
    assert_eq!(loaded.parts.len(), 1);
    loaded.parts.into_iter().next().unwrap().mesh
}

#[test]
fn round_trips_are_f32_exact_with_materials_and_colours() {
    let mesh = tetrahedron(false);
    for format in [Format::Glb, Format::Gltf] {
        assert_eq!(round_trip(&mesh, format), as_f32(&mesh), "{format}");
    }
}

#[test]
fn corner_uvs_and_normals_survive_split_vertices() {
    let mesh = tetrahedron(true);
    let back = round_trip(&mesh, Format::Glb);
    // Twelve written vertices (one per corner) weld back to the four positions.
    assert_eq!(back, as_f32(&mesh));
}

/// The little-endian bytes of `values`.
fn bytes<T: Copy, const N: usize>(values: &[T], to: fn(T) -> [u8; N]) -> Vec<u8> {
    values.iter().flat_map(|&v| to(v)).collect()
}

/// A `.gltf` with two nodes (a matrix parent and a TRS child) on one mesh of two primitives:
/// an indexed triangle with a material and a non-indexed one without; the buffer is `uri`.
fn document(uri: &str, byte_length: usize, mode: u32) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
        "nodes": [{{"name": "parent", "matrix": [2,0,0,0, 0,1,0,0, 0,0,1,0, 10,0,0,1], "children": [1]}},
                  {{"mesh": 0, "translation": [0, 0, 1], "rotation": [0, 0, 1, 0], "scale": [1, 1, 1]}}],
        "meshes": [{{"primitives": [
            {{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 0, "mode": {mode}}},
            {{"attributes": {{"POSITION": 0}}}}]}}],
        "materials": [{{"name": "red", "pbrMetallicRoughness": {{"baseColorFactor": [1, 0, 0, 0.5]}}}}],
        "buffers": [{{"uri": "{uri}", "byteLength": {byte_length}}}],
        "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}},
                        {{"buffer": 0, "byteOffset": 36, "byteLength": 6}}],
        "accessors": [
            {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]}},
            {{"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}}]}}"#
    )
}

/// The buffer of [`document`]: three positions and the indices `indices`.
fn buffer(indices: [u16; 3]) -> Vec<u8> {
    let positions = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut data = bytes(&positions, f32::to_le_bytes);
    data.extend(bytes(&indices, u16::to_le_bytes));
    data
}

#[test]
fn node_transforms_primitives_and_external_buffers() {
    let data = buffer([0, 2, 1]);
    let json = document("part%201.bin", data.len(), 4);
    let external = |uri: &str| match uri {
        "part 1.bin" => Ok(data.clone()),
        _ => no_external_files(uri),
    };
    let loaded = read(json.as_bytes(), &external).unwrap();
    assert_eq!(loaded.format, Format::Gltf);
    assert_eq!(loaded.raw_vertex_count, 3);
    let part = &loaded.parts[0];
    assert_eq!(part.name, "nodes[1]");
    let mesh = &part.mesh;
    // The child turns by 180° about z and moves up; the parent doubles x and moves by 10.
    assert_eq!(
        mesh.positions(),
        &[[10.0, 0.0, 1.0], [8.0, 0.0, 1.0], [10.0, -1.0, 1.0]]
    );
    assert_eq!(mesh.corners(), &[0, 2, 1, 0, 1, 2]);
    assert_eq!(mesh.materials(), ["red", "default"]);
    assert_eq!(mesh.face_colors(), Some(&[[255, 0, 0, 128], [255; 4]][..]));
    let embedded = document(
        &format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&data)
        ),
        data.len(),
        4,
    );
    assert_eq!(
        read(embedded.as_bytes(), &no_external_files).unwrap(),
        loaded
    );
}

fn message(data: &[u8]) -> String {
    read(data, &no_external_files).unwrap_err().to_string()
}

#[test]
fn errors_name_the_element() {
    let data = buffer([0, 2, 3]);
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&data)
    );
    assert_eq!(
        message(document(&uri, data.len(), 4).as_bytes()),
        "nodes[1]: meshes[0].primitives[0]: indices: byte offset 40: face 0 refers to vertex 3, \
         but 3 are defined"
    );
    assert_eq!(
        message(document(&uri, data.len(), 1).as_bytes()),
        "nodes[1]: meshes[0].primitives[0]: unsupported glTF feature: primitive mode Lines \
         (csgkit reads Triangles)"
    );
    assert_eq!(
        message(document("missing.bin", data.len(), 4).as_bytes()),
        "buffers[0]: malformed glTF file: cannot read missing.bin: missing.bin is not in memory \
         (only a file read from a folder has neighbours)"
    );
    assert_eq!(
        message(document(&uri, data.len() + 4, 4).as_bytes()),
        "buffers[0]: malformed glTF file: it holds 42 bytes, byteLength says 46"
    );
    let bad_index = document(&uri, data.len(), 4).replace("\"indices\": 1", "\"indices\": 7");
    assert_eq!(
        message(bad_index.as_bytes()),
        "meshes[0].primitives[0].indices: malformed glTF file: index out of bounds"
    );
    assert!(
        message(b"{\"asset\": {\"version\": \"2.0\"}, ")
            .starts_with("malformed glTF file: invalid JSON: ")
    );
    let mut glb = Vec::new();
    write::write(&tetrahedron(false), Format::Glb, &mut glb).unwrap();
    let cut = glb.len() - 1;
    assert_eq!(
        message(&glb[..cut]),
        format!(
            "truncated file: GLB file needs {} bytes, the file has {cut}",
            glb.len()
        )
    );
    assert_eq!(
        message(&glb[..10]),
        "truncated file: GLB header needs 12 bytes, the file has 10"
    );
    let mut short = glb.clone();
    short[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(message(&short).starts_with("truncated file: GLB JSON chunk needs "));
}

#[test]
fn content_is_recognised() {
    assert!(is_gltf_json(b"\xEF\xBB\xBF  {\"asset\": {}}"));
    assert!(!is_gltf_json(b"[\"asset\"]"));
}
