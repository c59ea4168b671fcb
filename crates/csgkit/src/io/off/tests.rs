use super::*;
use crate::mesh::{FaceId, MeshParts};

fn read_str(text: &str) -> Result<Mesh, ParseError> {
    read(text.as_bytes()).map(|loaded| loaded.mesh)
}

#[test]
fn reads_polygons_comments_and_colours() {
    let mesh = read_str(
        "# comment\nCOFF 4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n\
         0 1 0 1 1 1 1 # c\n3 0 1 2 1.0 0.5 0.0\n4 0 1 2 3 10 20 30\n",
    )
    .unwrap();
    assert_eq!(mesh.face_count(), 2);
    assert_eq!(mesh.face(FaceId::new(1)), &[0, 1, 2, 3]);
    assert_eq!(mesh.vertex_colors().unwrap()[0], [255, 0, 0, 255]);
    assert_eq!(
        mesh.face_colors().unwrap(),
        &[[255, 128, 0, 255], [10, 20, 30, 255]]
    );
}

#[test]
fn round_trip_keeps_positions_faces_and_colours() {
    let mesh = Mesh::from_parts(MeshParts {
        positions: vec![
            [0.1, 0.2, 0.3],
            [1e-7, 0.0, 0.0],
            [0.0, 1.0, -5.5],
            [2.0; 3],
        ],
        corners: vec![0, 1, 2, 3, 0, 2, 1],
        face_starts: Some(vec![0, 4, 7]),
        face_colors: Some(vec![[1, 2, 3, 4], [5, 6, 7, 8]]),
        vertex_colors: Some(vec![[9, 8, 7, 6]; 4]),
        ..MeshParts::default()
    })
    .unwrap();
    let mut out = Vec::new();
    write(&mesh, &mut out);
    assert_eq!(read(&out).unwrap().mesh, mesh);
}

#[test]
fn errors_are_exact() {
    assert_eq!(
        read_str(""),
        Err(ParseError::Empty {
            format: Format::Off
        })
    );
    assert_eq!(
        read_str("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
        Err(ParseError::IndexOutOfRange {
            face: 0,
            what: "vertex",
            index: 3,
            count: 3,
            at: Location::Line(6)
        })
    );
    assert_eq!(
        read_str("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
        Err(ParseError::TooFewCorners {
            face: 0,
            corners: 2,
            at: Location::Line(6)
        })
    );
    assert!(matches!(
        read_str("OFF\n2 0 0\n0 0 0\n1 inf 0\n"),
        Err(ParseError::NonFinite {
            vertex: 1,
            at: Location::Line(4),
            ..
        })
    ));
    assert!(matches!(
        read_str("OFF\n4000000000 1 0\n"),
        Err(ParseError::CountTooLarge { what: "vertex", .. })
    ));
    assert!(matches!(
        read_str("OFF\n3 1 0\n0 0 0\n"),
        Err(ParseError::Malformed { .. })
    ));
    assert!(matches!(
        read_str("OFF\n1000 1 0\n0 0 0\n"),
        Err(ParseError::CountTooLarge {
            what: "vertex",
            count: 1000,
            ..
        })
    ));
}

#[test]
fn face_free_files_are_empty_meshes() {
    assert!(read_str("OFF\n0 0 0\n").unwrap().is_empty());
}

/// A binary OFF file (Geomview's `OFF BINARY`): big-endian counts, floats and indices.
fn binary_off(faces: &[&[i32]], color: &[f32]) -> Vec<u8> {
    let mut data = b"# a comment\nCOFF BINARY\n".to_vec();
    for n in [4, faces.len() as i32, 0] {
        data.extend_from_slice(&n.to_be_bytes());
    }
    for p in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.25],
    ] {
        for c in p.into_iter().chain([1.0, 0.0, 0.0, 1.0]) {
            data.extend_from_slice(&c.to_be_bytes());
        }
    }
    for face in faces {
        data.extend_from_slice(&(face.len() as i32).to_be_bytes());
        for v in *face {
            data.extend_from_slice(&v.to_be_bytes());
        }
        data.extend_from_slice(&(color.len() as i32).to_be_bytes());
        for c in color {
            data.extend_from_slice(&c.to_be_bytes());
        }
    }
    data
}

#[test]
fn binary_off_reads_big_endian_polygons_and_colours() {
    let loaded = read(&binary_off(&[&[0, 1, 2, 3]], &[0.0, 0.5, 1.0])).unwrap();
    assert_eq!(loaded.encoding, Encoding::Binary);
    let mesh = loaded.mesh;
    assert_eq!(mesh.face(FaceId::new(0)), &[0, 1, 2, 3]);
    assert_eq!(mesh.positions()[3], [0.0, 1.0, 0.25]);
    assert_eq!(mesh.vertex_colors().unwrap()[0], [255, 0, 0, 255]);
    assert_eq!(mesh.face_colors().unwrap(), &[[0, 128, 255, 255]]);
    assert!(super::has_header(&binary_off(&[], &[])));
}

#[test]
fn binary_off_errors_are_exact() {
    let data = binary_off(&[&[0, 1, 4]], &[]);
    // Header (24 bytes) + counts (12) + 4 vertices of 7 floats (112): the face starts at 148,
    // its third index at 160.
    assert_eq!(
        read(&data),
        Err(ParseError::IndexOutOfRange {
            face: 0,
            what: "vertex",
            index: 4,
            count: 4,
            at: Location::Byte(160)
        })
    );
    let data = binary_off(&[&[0, 1, 3]], &[]);
    let cut = data.len() - 2;
    assert_eq!(
        read(&data[..cut]),
        Err(ParseError::Truncated {
            what: "binary OFF faces",
            expected: data.len(),
            actual: cut
        })
    );
    let mut huge = data.clone();
    huge[24..28].copy_from_slice(&i32::MAX.to_be_bytes());
    assert!(matches!(
        read(&huge),
        Err(ParseError::CountTooLarge { what: "vertex", .. })
    ));
}
