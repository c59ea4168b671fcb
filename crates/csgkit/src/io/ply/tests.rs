use super::*;
use crate::mesh::{FaceId, MeshParts};

fn sample() -> Mesh {
    Mesh::from_parts(MeshParts {
        positions: vec![
            [0.1, 0.2, 0.3],
            [1e-300, 0.0, 0.0],
            [0.0, 1.0, -5.5],
            [2.0; 3],
        ],
        corners: vec![0, 1, 2, 3, 0, 2, 1],
        face_starts: Some(vec![0, 4, 7]),
        face_materials: Some(vec![1, 0]),
        materials: vec!["material_0".into(), "material_1".into()],
        face_colors: Some(vec![[1, 2, 3, 4], [5, 6, 7, 8]]),
        vertex_colors: Some(vec![[9, 8, 7, 6]; 4]),
        ..MeshParts::default()
    })
    .unwrap()
}

/// A big-endian file with an unknown element, an unknown list property and int coordinates.
fn big_endian() -> Vec<u8> {
    let mut data = b"ply\r\nformat binary_big_endian 1.0\r\ncomment x\r\nelement vertex 3\r\n\
        property int x\r\nproperty short y\r\nproperty float z\r\nproperty list uchar int junk\r\n\
        element extra 1\r\nproperty list ushort double stuff\r\n\
        element face 1\r\nproperty uchar flags\r\nproperty list ushort uint vertex_index\r\n\
        end_header\r\n"
        .to_vec();
    for (x, y, z) in [(0i32, 0i16, 0.5f32), (1, 0, 0.0), (0, -1, 0.0)] {
        data.extend_from_slice(&x.to_be_bytes());
        data.extend_from_slice(&y.to_be_bytes());
        data.extend_from_slice(&z.to_be_bytes());
        data.extend_from_slice(&[1, 0, 0, 0, 7]);
    }
    data.extend_from_slice(&2u16.to_be_bytes());
    data.extend_from_slice(&[0; 16]);
    data.push(9);
    data.extend_from_slice(&3u16.to_be_bytes());
    for v in [0u32, 2, 1] {
        data.extend_from_slice(&v.to_be_bytes());
    }
    data
}

#[test]
fn binary_and_ascii_round_trips_are_exact() {
    for encoding in [Encoding::Binary, Encoding::Ascii] {
        let mut out = Vec::new();
        write(&sample(), encoding, &mut out);
        let loaded = read(&out).unwrap();
        assert_eq!(loaded.encoding, encoding);
        assert_eq!(loaded.mesh, sample());
    }
}

#[test]
fn big_endian_with_unknown_elements_and_lists() {
    let mesh = read(&big_endian()).unwrap().mesh;
    assert_eq!(
        mesh.positions(),
        &[[0.0, 0.0, 0.5], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]
    );
    assert_eq!(mesh.face(FaceId::new(0)), &[0, 2, 1]);
    assert!(mesh.vertex_colors().is_none());
}

#[test]
fn ascii_with_float_colours_and_materials() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
        property float z\nproperty float red\nproperty float green\nproperty float blue\n\
        element face 2\nproperty list uchar int vertex_indices\nproperty int material_index\n\
        end_header\n0 0 0 1 0 0\n1 0 0 0 1 0\n0 1 0 0 0 1\n3 0 1 2 7\n3 2 1 0 -2\n";
    let mesh = read(text.as_bytes()).unwrap().mesh;
    assert_eq!(mesh.vertex_colors().unwrap()[1], [0, 255, 0, 255]);
    assert_eq!(mesh.materials(), ["material_-2", "material_7"]);
    assert_eq!(mesh.face_materials(), Some(&[1, 0][..]));
}

#[test]
fn errors_are_exact() {
    assert_eq!(
        read(b""),
        Err(ParseError::Empty {
            format: Format::Ply
        })
    );
    let data = big_endian();
    let cut = data.len() - 3;
    assert_eq!(
        read(&data[..cut]),
        Err(ParseError::Truncated {
            what: "PLY body",
            expected: data.len(),
            actual: cut
        })
    );
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
        property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let with = |body: &str| read(format!("{header}{body}").as_bytes());
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
        Err(ParseError::IndexOutOfRange {
            face: 0,
            what: "vertex",
            index: 3,
            count: 3,
            at: Location::Line(13)
        })
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
        Err(ParseError::TooFewCorners {
            face: 0,
            corners: 2,
            at: Location::Line(13)
        })
    );
    assert!(matches!(
        with("0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"),
        Err(ParseError::NonFinite {
            vertex: 1,
            at: Location::Line(11),
            ..
        })
    ));
    assert!(matches!(
        read(b"ply\nformat binary_middle_endian 1.0\nend_header\n"),
        Err(ParseError::Unsupported { .. })
    ));
    assert!(matches!(
        read(
            b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n\
              property float x\nend_header\n"
        ),
        Err(ParseError::CountTooLarge {
            what: "PLY element",
            ..
        })
    ));
}

#[test]
fn face_free_files_are_empty_meshes() {
    let text = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
        property float z\nend_header\n";
    assert!(read(text.as_bytes()).unwrap().mesh.is_empty());
}

#[test]
fn the_face_element_may_precede_the_vertex_element() {
    let text = "ply\nformat ascii 1.0\nelement face 2\nproperty list uchar int vertex_indices\n\
        element vertex 4\nproperty double x\nproperty double y\nproperty double z\nend_header\n\
        3 0 1 2\n3 0 2 3\n0 0 0\n1 0 0\n1 1 0\n0 1 0.5\n";
    let mesh = read(text.as_bytes()).unwrap().mesh;
    assert_eq!(mesh.corners(), &[0, 1, 2, 0, 2, 3]);
    assert_eq!(mesh.positions()[3], [0.0, 1.0, 0.5]);
    let bad = text.replace("3 0 2 3\n", "3 0 2 4\n");
    assert_eq!(
        read(bad.as_bytes()),
        Err(ParseError::IndexOutOfRange {
            face: 1,
            what: "vertex",
            index: 4,
            count: 4,
            at: Location::Line(11)
        })
    );
}
