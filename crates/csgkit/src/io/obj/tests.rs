use super::*;
use crate::mesh::MeshParts;

fn read_str(text: &str) -> Result<Mesh, ParseError> {
    read(text.as_bytes()).map(|loaded| loaded.mesh)
}

#[test]
fn reads_every_index_form_and_negative_indices() {
    let mesh = read_str(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n\
         f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf -4/-3/-1 -3/-2/-1 -1/-1/-1 \\\n -2/1/1\n",
    )
    .unwrap();
    assert_eq!(mesh.face_count(), 4);
    assert_eq!(mesh.face(FaceId::new(3)), &[0, 1, 3, 2]);
    let uvs = mesh.corner_uvs().unwrap();
    assert_eq!(uvs[0], [0.0, 0.0]);
    assert_eq!(uvs[4], [1.0, 0.0]);
    assert_eq!(mesh.corner_normals().unwrap()[6], [0.0, 0.0, 1.0]);
}

#[test]
fn groups_materials_colours_and_crlf() {
    let mesh = read_str(
        "mtllib a.mtl b.mtl\r\nv 0 0 0 1 0 0\r\nv 1 0 0\r\nv 0 1 0 # c\r\no part\r\n\
         usemtl red\r\nf 1 2 3\r\ns off\r\nl 1 2\r\ng other\r\nusemtl blue\r\nf 3 2 1\r\n",
    )
    .unwrap();
    assert_eq!(mesh.material_libraries(), ["a.mtl", "b.mtl"]);
    assert_eq!(mesh.materials(), ["red", "blue"]);
    assert_eq!(mesh.face_materials(), Some(&[0, 1][..]));
    assert_eq!(mesh.groups(), ["part", "other"]);
    assert_eq!(mesh.vertex_colors().unwrap()[0], [255, 0, 0, 255]);
    assert_eq!(mesh.vertex_colors().unwrap()[1], [255; 4]);
}

#[test]
fn round_trip_keeps_positions_faces_and_attributes() {
    let parts = MeshParts {
        positions: vec![
            [0.1, -1e-300, 3.0e10],
            [1.0 / 3.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0; 3],
        ],
        corners: vec![0, 1, 2, 3, 0, 2, 1],
        face_starts: Some(vec![0, 4, 7]),
        face_materials: Some(vec![0, 1]),
        materials: vec!["a".into(), "b".into()],
        face_groups: Some(vec![0, 1]),
        groups: vec!["g0".into(), "g1".into()],
        corner_uvs: Some((0..7).map(|i| [i as f64 * 0.1, 0.5]).collect()),
        corner_normals: Some(vec![[0.0, 0.0, 1.0]; 7]),
        vertex_colors: Some(vec![[1, 2, 3, 255]; 4]),
        material_libraries: vec!["m.mtl".into()],
        ..MeshParts::default()
    };
    let mesh = Mesh::from_parts(parts).unwrap();
    let mut out = Vec::new();
    write(&mesh, &mut out);
    assert_eq!(read(&out).unwrap().mesh, mesh);
}

/// Names that the statement syntax would misread (a trailing `\` joins the next line, `#`
/// starts a comment, a line break ends the statement) are written so that every face comes
/// back; the fuzz target `read_obj` found the trailing backslash.
#[test]
fn names_that_break_statements_are_written_readable() {
    let parts = MeshParts {
        positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        corners: vec![0, 1, 2, 0, 2, 1],
        face_groups: Some(vec![0, 1]),
        groups: vec!["ends in \\\\".into(), "line\nbreak # not a comment".into()],
        face_materials: Some(vec![0, 1]),
        materials: vec!["\r\0".into(), "fine".into()],
        ..MeshParts::default()
    };
    let mut out = Vec::new();
    write(&Mesh::from_parts(parts).unwrap(), &mut out);
    let back = read(&out).unwrap().mesh;
    assert_eq!(back.face_count(), 2);
    assert_eq!(
        back.groups(),
        ["ends in \\\\_", "line_break _ not a comment"]
    );
    assert_eq!(back.materials(), ["_", "fine"]);
}

#[test]
fn errors_name_the_line_face_and_vertex() {
    assert!(matches!(
        read_str("v 0 0 0\nv 1 nan 0\n"),
        Err(ParseError::NonFinite { vertex: 1, at: Location::Line(2), value }) if value.is_nan()
    ));
    assert!(matches!(
        read_str("v 0 0 0\nv inf 0 0\n"),
        Err(ParseError::NonFinite {
            vertex: 1,
            at: Location::Line(2),
            ..
        })
    ));
    assert_eq!(
        read_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n"),
        Err(ParseError::IndexOutOfRange {
            face: 1,
            what: "vertex",
            index: 4,
            count: 3,
            at: Location::Line(5)
        })
    );
    assert_eq!(
        read_str("v 0 0 0\nv 1 0 0\nf 1 2\n"),
        Err(ParseError::TooFewCorners {
            face: 0,
            corners: 2,
            at: Location::Line(3)
        })
    );
    assert!(matches!(
        read_str("v 0 0 0\nf 0 1 1\n"),
        Err(ParseError::IndexOutOfRange { index: 0, .. })
    ));
    assert!(matches!(
        read_str("v 0 x 0\n"),
        Err(ParseError::MalformedNumber { .. })
    ));
}

#[test]
fn empty_and_face_free_files_are_empty_meshes() {
    assert!(read_str("").unwrap().is_empty());
    assert_eq!(read_str("# nothing\nv 1 2 3\n").unwrap().vertex_count(), 1);
}

#[test]
fn blocks_of_lines_name_each_material_and_group_once_per_run() {
    // Enough faces for several blocks of lines formatted apart (16 k lines each). The faces
    // are written sorted by material, the last 12.5 k (material "a") first; in that order a
    // material run spans each block boundary, and the group changes exactly at each.
    let faces = 50_000;
    let material = |f: usize| (3 - f / 12_500) as u32;
    let order: Vec<usize> = (0..4)
        .rev()
        .flat_map(|m| m * 12_500..(m + 1) * 12_500)
        .collect();
    let mut groups = vec![0u32; faces];
    for (line, &f) in order.iter().enumerate() {
        groups[f] = (line / 16_384 % 2) as u32;
    }
    let parts = MeshParts {
        positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        corners: (0..faces).flat_map(|_| [0, 1, 2]).collect(),
        face_materials: Some((0..faces).map(material).collect()),
        materials: ["a", "b", "c", "d"].map(String::from).to_vec(),
        face_groups: Some(groups.clone()),
        groups: ["even", "odd"].map(String::from).to_vec(),
        ..MeshParts::default()
    };
    let mesh = Mesh::from_parts(parts).unwrap();
    let mut out = Vec::new();
    write(&mesh, &mut out);
    let text = String::from_utf8(out).unwrap();
    let count = |keyword: &str| text.lines().filter(|l| l.starts_with(keyword)).count();
    let runs =
        |of: &dyn Fn(usize) -> u32| 1 + (order.windows(2)).filter(|w| of(w[0]) != of(w[1])).count();
    assert_eq!(count("usemtl "), runs(&material));
    assert_eq!(count("g "), runs(&|f| groups[f]));
    let back = read_str(&text).unwrap();
    let names = |m: &Mesh| {
        let named = |ids: &[u32], list: &[String]| -> Vec<String> {
            ids.iter().map(|&i| list[i as usize].clone()).collect()
        };
        let materials = named(m.face_materials().unwrap(), m.materials());
        let groups = named(m.face_groups().unwrap(), m.groups());
        materials.into_iter().zip(groups).collect::<Vec<_>>()
    };
    // Read back in the written order.
    let given = names(&mesh);
    let written: Vec<_> = order.iter().map(|&f| given[f].clone()).collect();
    assert_eq!(names(&back), written);
}
