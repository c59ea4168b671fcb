use super::*;
use crate::mesh::MeshParts;

/// A tetrahedron with awkward coordinates, materials and colours.
fn tetrahedron(materials: bool, colors: bool) -> Mesh {
    Mesh::from_parts(MeshParts {
        positions: vec![
            [0.1, 0.2, 0.3],
            [1.0 / 3.0, -0.0, 1e-300],
            [0.0, 1.0, -5.5],
            [2.0, 1e17, 7.25],
        ],
        corners: vec![0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2],
        face_materials: materials.then(|| vec![0, 1, 0, 1]),
        materials: if materials {
            vec!["stone & co".into(), "glass".into()]
        } else {
            Vec::new()
        },
        face_colors: colors.then(|| vec![[1, 2, 3, 4], [5, 6, 7, 8], [1, 2, 3, 4], [9, 9, 9, 255]]),
        ..MeshParts::default()
    })
    .unwrap()
}

fn written(mesh: &Mesh) -> Vec<u8> {
    let mut out = Vec::new();
    write(mesh, &mut out).unwrap();
    out
}

/// A 3MF archive around `model` (with a root relationship to it unless `rels` is false).
fn archive(model: &str, rels: bool) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default();
    zip.start_file("[Content_Types].xml", options).unwrap();
    zip.write_all(CONTENT_TYPES.as_bytes()).unwrap();
    if rels {
        zip.start_file("_rels/.rels", options).unwrap();
        zip.write_all(RELATIONSHIPS.as_bytes()).unwrap();
    }
    zip.start_file(DEFAULT_MODEL, options).unwrap();
    zip.write_all(model.as_bytes()).unwrap();
    zip.finish().unwrap().into_inner()
}

/// A model with `resources` and `build`, in the core and materials namespaces.
fn model(unit: &str, resources: &str, build: &str) -> String {
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"{unit}\" xmlns=\"{CORE_NAMESPACE}\" \
         xmlns:m=\"{MATERIAL_NAMESPACE}\">\n<resources>\n{resources}</resources>\n<build>\n{build}</build>\n</model>\n"
    )
}

/// One triangle object: vertices (0,0,0) (1,0,0) (0,1,0) and triangle `triangle`.
fn triangle_object(id: u32, triangle: &str) -> String {
    format!(
        "<object id=\"{id}\" type=\"model\">\n<mesh>\n<vertices>\n<vertex x=\"0\" y=\"0\" z=\"0\"/>\n\
         <vertex x=\"1\" y=\"0\" z=\"0\"/>\n<vertex x=\"0\" y=\"1\" z=\"0\"/>\n</vertices>\n\
         <triangles>\n{triangle}\n</triangles>\n</mesh>\n</object>\n"
    )
}

fn message(data: &[u8]) -> String {
    read(data).unwrap_err().to_string()
}

#[test]
fn round_trips_are_bit_exact_with_materials_and_colours() {
    for (materials, colors) in [(true, true), (false, true), (false, false)] {
        let mesh = tetrahedron(materials, colors);
        let loaded = read(&written(&mesh)).unwrap();
        assert_eq!(loaded.unit, Some(Unit::Millimeter));
        assert_eq!(loaded.parts.len(), 1);
        assert_eq!(
            loaded.parts[0].mesh, mesh,
            "materials {materials}, colours {colors}"
        );
    }
    // A base material always has a colour: materials alone come back white.
    let back = read(&written(&tetrahedron(true, false))).unwrap();
    assert_eq!(back.parts[0].mesh.face_colors(), Some(&[[255; 4]; 4][..]));
    assert_eq!(back.parts[0].mesh.materials(), ["stone & co", "glass"]);
}

#[test]
fn items_components_transforms_and_units() {
    let resources = format!(
        "{}{}<object id=\"3\" name=\"pair\">\n<components>\n<component objectid=\"1\"/>\n\
         <component objectid=\"2\" transform=\"1 0 0 0 1 0 0 0 1 10 0 0\"/>\n</components>\n</object>\n",
        triangle_object(1, "<triangle v1=\"0\" v2=\"1\" v3=\"2\"/>"),
        triangle_object(2, "<triangle v1=\"0\" v2=\"1\" v3=\"2\"/>"),
    );
    let build =
        "<item objectid=\"1\"/>\n<item objectid=\"3\" transform=\"-1 0 0 0 1 0 0 0 1 0 0 5\"/>\n";
    let loaded = read(&archive(&model("inch", &resources, build), true)).unwrap();
    assert_eq!(loaded.unit, Some(Unit::Inch));
    assert_eq!(loaded.raw_vertex_count, 6);
    let names: Vec<&str> = loaded.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["item 0", "pair"]);
    assert_eq!(loaded.parts[0].mesh.positions()[1], [25.4, 0.0, 0.0]);
    let pair = &loaded.parts[1].mesh;
    assert_eq!(pair.face_count(), 2);
    // The mirror (x → -x) reverses the faces; the second component moved by 10 first.
    assert_eq!(pair.positions()[4], [-11.0 * 25.4, 0.0, 5.0 * 25.4]);
    assert_eq!(pair.corners()[..3], [2, 1, 0]);
    // Without _rels/.rels the model is found at its usual place.
    assert!(read(&archive(&model("millimeter", &resources, build), false)).is_ok());
}

#[test]
fn properties_follow_pid_and_p1_with_object_defaults() {
    let resources = format!(
        "<basematerials id=\"5\">\n<base name=\"red\" displaycolor=\"#FF0000\"/>\n\
         <base name=\"blue\" displaycolor=\"#0000FF80\"/>\n</basematerials>\n\
         <m:colorgroup id=\"6\">\n<m:color color=\"#00FF00FF\"/>\n</m:colorgroup>\n{}",
        triangle_object(1, "<triangle v1=\"0\" v2=\"1\" v3=\"2\" pid=\"5\" p1=\"1\" p2=\"0\"/>\n\
         <triangle v1=\"0\" v2=\"2\" v3=\"1\" pid=\"6\" p1=\"0\"/>\n<triangle v1=\"1\" v2=\"0\" v3=\"2\"/>")
            .replace("type=\"model\"", "pid=\"5\" pindex=\"0\""),
    );
    let loaded = read(&archive(
        &model("millimeter", &resources, "<item objectid=\"1\"/>"),
        true,
    ));
    let mesh = loaded.unwrap().parts.remove(0).mesh;
    assert_eq!(mesh.materials(), ["blue", "default", "red"]);
    assert_eq!(mesh.face_materials(), Some(&[0, 1, 2][..]));
    let colors = [[0, 0, 255, 128], [0, 255, 0, 255], [255, 0, 0, 255]];
    assert_eq!(mesh.face_colors(), Some(&colors[..]));
}

#[test]
fn errors_name_the_part_and_element() {
    assert!(
        message(b"PK\x03\x04 not really a zip")
            .starts_with("malformed 3MF file: not a zip archive: ")
    );
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    zip.start_file("readme.txt", zip::write::SimpleFileOptions::default())
        .unwrap();
    zip.write_all(b"hello").unwrap();
    let not_3mf = zip.finish().unwrap().into_inner();
    assert_eq!(
        message(&not_3mf),
        "malformed 3MF file: not a 3MF file: the zip archive has no 3D model part (no 3dmodel \
         relationship in _rels/.rels and no 3D/3dmodel.model)"
    );
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    zip.start_file("_rels/.rels", zip::write::SimpleFileOptions::default())
        .unwrap();
    zip.write_all(RELATIONSHIPS.as_bytes()).unwrap();
    let missing = zip.finish().unwrap().into_inner();
    assert_eq!(
        message(&missing),
        "malformed 3MF file: the 3D model part /3D/3dmodel.model that _rels/.rels names is not in \
         the archive"
    );
    let with = |triangle: &str| {
        let resources = triangle_object(1, triangle);
        archive(
            &model("millimeter", &resources, "<item objectid=\"1\"/>"),
            true,
        )
    };
    assert_eq!(
        message(&with("<triangle v1=\"0\" v2=\"1\" v3=\"3\"/>")),
        "3D/3dmodel.model: object 1: line 12: face 0 refers to vertex 3, but 3 are defined"
    );
    assert_eq!(
        message(&with("<triangle v1=\"0\" v2=\"1\"/>")),
        "3D/3dmodel.model: object 1, triangle 0: line 12: malformed 3MF file: missing attribute v3"
    );
    assert_eq!(
        message(&with(
            "<triangle v1=\"0\" v2=\"1\" v3=\"2\" pid=\"9\" p1=\"0\"/>"
        )),
        "3D/3dmodel.model: object 1, triangle 0: line 12: malformed 3MF file: pid 9 names no \
         property group defined before it"
    );
    let bad_number = archive(
        &model(
            "millimeter",
            &triangle_object(1, "").replace("x=\"1\"", "x=\"1.0x\""),
            "",
        ),
        true,
    );
    assert_eq!(
        message(&bad_number),
        "3D/3dmodel.model: object 1, vertex 1, attribute x: line 8: malformed number \"1.0x\""
    );
    let cut = model("millimeter", &triangle_object(1, ""), "");
    assert!(message(&archive(&cut[..cut.len() - 30], true)).starts_with("3D/3dmodel.model: line "));
    let unknown_item = archive(&model("millimeter", "", "<item objectid=\"4\"/>"), true);
    assert_eq!(
        message(&unknown_item),
        "3D/3dmodel.model, build item 0 (object 4): malformed 3MF file: object 4 is not defined"
    );
    let lattice = model("millimeter", "", "")
        .replace("<model ", "<model xmlns:b=\"http://schemas.microsoft.com/3dmanufacturing/beamlattice/2017/02\" requiredextensions=\"b\" ");
    assert_eq!(
        message(&archive(&lattice, true)),
        "3D/3dmodel.model: model: unsupported 3MF feature: required extension \
         http://schemas.microsoft.com/3dmanufacturing/beamlattice/2017/02"
    );
}
