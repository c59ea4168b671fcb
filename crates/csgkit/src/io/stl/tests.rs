use super::*;

fn square() -> Mesh {
    Mesh::from_parts(MeshParts {
        positions: vec![
            [0.1, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        corners: vec![0, 1, 2, 3],
        face_starts: Some(vec![0, 4]),
        ..MeshParts::default()
    })
    .unwrap()
}

#[test]
fn binary_round_trip_welds_and_fans() {
    let mut out = Vec::new();
    write(&square(), Encoding::Binary, &mut out).unwrap();
    assert_eq!(out.len(), HEADER + 2 * FACET);
    let loaded = read(&out).unwrap();
    assert_eq!(loaded.encoding, Encoding::Binary);
    assert_eq!(loaded.raw_vertex_count, 6);
    assert_eq!(loaded.mesh.vertex_count(), 4);
    assert_eq!(loaded.mesh.corners(), &[0, 1, 2, 0, 2, 3]);
    assert_eq!(loaded.mesh.positions()[0], [f64::from(0.1f32), 0.0, 0.0]);
}

/// One polygon in the plane z = 0 with corners `0, 1, …`.
fn polygon(points: &[[f64; 2]]) -> Mesh {
    Mesh::from_parts(MeshParts {
        positions: points.iter().map(|p| [p[0], p[1], 0.0]).collect(),
        corners: (0..points.len() as u32).collect(),
        face_starts: Some(vec![0, points.len() as u32]),
        ..MeshParts::default()
    })
    .unwrap()
}

#[test]
fn non_convex_polygons_are_written_as_their_triangles() {
    // An L hexagon starting at (2, 0): its fan would cover area outside it.
    let l = [
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
        [0.0, 0.0],
    ];
    let mut out = Vec::new();
    write(&polygon(&l), Encoding::Ascii, &mut out).unwrap();
    let loaded = read(&out).unwrap();
    assert_eq!(loaded.mesh.face_count(), 4);
    assert_eq!(crate::mesh::measure(&loaded.mesh).area, 3.0);
    let bow_tie = [[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]];
    let err = write(&polygon(&bow_tie), Encoding::Binary, &mut Vec::new()).unwrap_err();
    assert!(matches!(err, WriteError::InvalidPolygon { .. }), "{err}");
    assert_eq!(
        err.to_string(),
        "cannot write STL: face 0 overlaps itself in its projection (two edges cross)"
    );
}

#[test]
fn ascii_round_trip_is_exact_and_reads_crlf() {
    let mut out = Vec::new();
    write(&square(), Encoding::Ascii, &mut out).unwrap();
    let crlf = String::from_utf8(out).unwrap().replace('\n', "\r\n");
    let loaded = read(crlf.as_bytes()).unwrap();
    assert_eq!(loaded.encoding, Encoding::Ascii);
    assert_eq!(loaded.mesh.positions(), square().positions());
    assert_eq!(loaded.mesh.face_count(), 2);
    let upper = "SOLID x\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\n\
        VERTEX 0 1 0\nENDLOOP\nENDFACET\nENDSOLID x\n";
    assert_eq!(read(upper.as_bytes()).unwrap().raw_vertex_count, 3);
}

#[test]
fn binary_with_solid_header_loads_as_binary() {
    let mut out = Vec::new();
    write(&square(), Encoding::Binary, &mut out).unwrap();
    out[..6].copy_from_slice(b"solid ");
    assert_eq!(read(&out).unwrap().encoding, Encoding::Binary);
    // Trailing bytes defeat the size check; the failed ASCII parse falls back to binary.
    out.extend_from_slice(b"\n\n");
    assert_eq!(read(&out).unwrap().mesh.face_count(), 2);
}

#[test]
fn errors_are_exact() {
    assert_eq!(
        read(b""),
        Err(ParseError::Empty {
            format: Format::Stl
        })
    );
    let mut out = Vec::new();
    write(&square(), Encoding::Binary, &mut out).unwrap();
    assert_eq!(
        read(&out[..120]),
        Err(ParseError::Truncated {
            what: "binary STL facets",
            expected: 184,
            actual: 120
        })
    );
    assert_eq!(
        read(&out[..50]),
        Err(ParseError::Truncated {
            what: "binary STL header",
            expected: 84,
            actual: 50
        })
    );
    out[84 + 12..84 + 16].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert_eq!(
        read(&out),
        Err(ParseError::NonFinite {
            vertex: 0,
            value: f64::INFINITY,
            at: Location::Byte(96)
        })
    );
    let two = "solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n";
    assert_eq!(
        read(two.as_bytes()),
        Err(ParseError::TooFewCorners {
            face: 0,
            corners: 2,
            at: Location::Line(6)
        })
    );
    assert!(matches!(
        read(b"solid\nvertex 0 nan 0\n"),
        Err(ParseError::NonFinite {
            vertex: 0,
            at: Location::Line(2),
            ..
        })
    ));
}

#[test]
fn face_free_files_are_empty_meshes() {
    assert!(
        read(b"solid empty\nendsolid empty\n")
            .unwrap()
            .mesh
            .is_empty()
    );
    let mut header = vec![b' '; 84];
    header[80..].copy_from_slice(&0u32.to_le_bytes());
    assert!(read(&header).unwrap().mesh.is_empty());
}
