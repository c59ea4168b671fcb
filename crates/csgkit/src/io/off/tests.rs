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
