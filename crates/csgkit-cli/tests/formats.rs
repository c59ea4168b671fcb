//! 3MF and glTF end to end: booleans across formats keep materials and colours, a 3MF of
//! several build items gives several operands (or one with `--merge`), `csgkit info` reports
//! parts and units, booleans written to glTF or binary STL are certified in f32, and writing
//! another mesh there warns once when coordinates are rounded to f32.

use std::io::Write;
use std::path::{Path, PathBuf};

use csgkit::primitives::cuboid;
use csgkit::{Mesh, MeshParts, Rgba, WriteOptions, write_mesh};
use tempfile::TempDir;

use crate::common::{arg, csgkit, csgkit_ok};

const RED: Rgba = [255, 0, 0, 255];
const BLUE: Rgba = [0, 0, 255, 255];

/// The box `[min, max]` with every face of `material` and `color`.
fn painted(min: [f64; 3], max: [f64; 3], material: &str, color: Rgba) -> Mesh {
    let cube = cuboid(min, max);
    let faces = cube.face_count();
    Mesh::from_parts(MeshParts {
        face_materials: Some(vec![0; faces]),
        materials: vec![material.to_owned()],
        face_colors: Some(vec![color; faces]),
        ..cube.into_parts()
    })
    .expect("one material and colour per face")
}

fn write(dir: &TempDir, name: &str, mesh: &Mesh) -> PathBuf {
    let path = dir.path().join(name);
    write_mesh(&path, mesh, WriteOptions::default()).expect("the operand is written");
    path
}

fn volume(path: &Path) -> f64 {
    let mesh = csgkit::read_mesh(path).expect("the output reads back").mesh;
    csgkit::mesh::measure(&mesh).volume
}

#[test]
fn a_union_of_3mf_and_glb_keeps_materials_and_colours() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let a = write(&dir, "a.3mf", &painted([0.0; 3], [2.0; 3], "stone", RED));
    let b = write(&dir, "b.glb", &painted([1.0; 3], [3.0; 3], "glass", BLUE));
    let out = dir.path().join("out.3mf");
    let output = csgkit_ok(&["union", arg(&a), arg(&b), "-o", arg(&out)]);
    assert!(
        output.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let mesh = csgkit::read_mesh(&out).expect("the union reads back").mesh;
    assert_eq!(csgkit::mesh::measure(&mesh).volume, 15.0);
    let (materials, colors) = (mesh.face_materials().unwrap(), mesh.face_colors().unwrap());
    let mut seen = [false; 2];
    for (&material, &color) in materials.iter().zip(colors) {
        let name = mesh.materials()[material as usize].as_str();
        let expected = match name {
            "stone" => RED,
            "glass" => BLUE,
            other => panic!("unexpected material {other}"),
        };
        seen[usize::from(name == "glass")] = true;
        assert_eq!(color, expected, "{name}");
    }
    assert_eq!(seen, [true, true]);
    // The same through a .gltf, whose buffer is embedded: one file, read back alike.
    let gltf = dir.path().join("out.gltf");
    csgkit_ok(&["union", arg(&a), arg(&b), "-o", arg(&gltf)]);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 4);
    assert_eq!(volume(&gltf), 15.0);
}

#[test]
fn booleans_written_in_f32_are_certified_there_and_other_meshes_warn() {
    let dir = tempfile::tempdir().expect("temporary folder");
    // 0.1 is no f32 number: the boolean rounds it, and every intersection point, to f32 and
    // certifies the result there, so writing GLB or binary STL rounds nothing more.
    let a = write(&dir, "a.ply", &cuboid([0.1; 3], [2.0; 3]));
    let b = write(&dir, "b.ply", &cuboid([1.0; 3], [3.0; 3]));
    for name in ["out.glb", "out.stl"] {
        let out = dir.path().join(name);
        let output = csgkit_ok(&["union", arg(&a), arg(&b), "-o", arg(&out)]);
        assert!(
            output.stderr.is_empty(),
            "{name}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        let mesh = csgkit::read_mesh(&out).expect("the output reads back").mesh;
        let report = mesh.report();
        assert!(report.is_valid_solid(), "{name}");
        // The union of [0.1f32, 2]³ and [1, 3]³ (overlapping in [1, 2]³).
        let expected = (2.0 - f64::from(0.1f32)).powi(3) + 8.0 - 1.0;
        let volume = report.measures.volume;
        assert!(
            (volume - expected).abs() < 1e-12,
            "{name}: {volume} vs {expected}"
        );
    }
    // A mesh that is no boolean's result is rounded on writing, with one warning line.
    let boxes = dir.path().join("boxes.txt");
    std::fs::write(&boxes, "0.1 0 0 1 1 1\n").expect("box file");
    let out = dir.path().join("boxes.glb");
    let output = csgkit_ok(&["boxes", arg(&boxes), "-o", arg(&out)]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("csgkit: warning: GLB stores f32: "),
        "{stderr}"
    );
    let exact = dir.path().join("out.3mf");
    let output = csgkit_ok(&["union", arg(&a), arg(&b), "-o", arg(&exact)]);
    assert!(output.stderr.is_empty());
}

/// A solid thinner than an f32 ulp (a sliver of 3.1 cubic units spanning 8e5 units, a result
/// csgkit wrote in f64) has no f32 form: binary STL gets the empty result, with a warning
/// that says why, where OBJ gets the sliver.
#[test]
fn a_solid_thinner_than_f32_is_written_empty_with_a_warning() {
    let dir = TempDir::new().expect("temp dir");
    let sliver = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../csgkit/tests/data/regression/f32_inverts_a_sliver.obj");
    let cube = write(&dir, "cube.obj", &cuboid([0.0; 3], [1.0; 3]));
    let stl = dir.path().join("out.stl");
    let output = csgkit_ok(&["difference", arg(&sliver), arg(&cube), "-o", arg(&stl)]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.starts_with("csgkit: warning: the result written to ")
            && stderr.contains("is empty: its 1 closed shells are thinner"),
        "{stderr}"
    );
    assert_eq!(volume(&stl), 0.0);
    let obj = dir.path().join("out.obj");
    let output = csgkit_ok(&["difference", arg(&sliver), arg(&cube), "-o", arg(&obj)]);
    assert!(output.stderr.is_empty());
    assert!(volume(&obj) > 3.0, "{}", volume(&obj));
}

/// A 3MF of two build items, the boxes [0, 2]³ and [1, 3]³ (the second a moved copy of the
/// first), in inches.
fn two_items(dir: &TempDir) -> PathBuf {
    let cube = cuboid([0.0; 3], [2.0; 3]);
    let mut vertices = String::new();
    for p in cube.positions() {
        vertices += &format!("<vertex x=\"{}\" y=\"{}\" z=\"{}\"/>\n", p[0], p[1], p[2]);
    }
    let mut triangles = String::new();
    for f in cube.faces() {
        triangles += &format!(
            "<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>\n",
            f[0], f[1], f[2]
        );
    }
    let model = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"inch\" \
         xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n<resources>\n\
         <object id=\"1\" name=\"box\"><mesh><vertices>\n{vertices}</vertices><triangles>\n\
         {triangles}</triangles></mesh></object>\n</resources>\n<build>\n<item objectid=\"1\"/>\n\
         <item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 1 1 1\"/>\n</build>\n</model>\n"
    );
    let path = dir.path().join("two.3mf");
    let file = std::fs::File::create(&path).expect("a new file");
    let mut zip = zip::ZipWriter::new(file);
    zip.start_file("3D/3dmodel.model", zip::write::SimpleFileOptions::default())
        .expect("a zip entry");
    zip.write_all(model.as_bytes()).expect("written");
    zip.finish().expect("a zip archive");
    path
}

#[test]
fn build_items_are_operands_unless_merged() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let two = two_items(&dir);
    let far = write(&dir, "far.obj", &cuboid([100.0; 3], [101.0; 3]));
    let out = dir.path().join("out.obj");
    // Items in inches, read as millimetres: each box has side 50.8 and they overlap by 25.4.
    let (side, overlap) = (50.8f64, 25.4f64);
    csgkit_ok(&["difference", arg(&two), arg(&far), "-o", arg(&out)]);
    let first_minus_second = side.powi(3) - overlap.powi(3);
    assert!((volume(&out) - first_minus_second).abs() < 1e-9 * first_minus_second);
    csgkit_ok(&[
        "difference",
        "--merge",
        arg(&two),
        arg(&far),
        "-o",
        arg(&out),
    ]);
    let union = 2.0 * side.powi(3) - overlap.powi(3);
    assert!((volume(&out) - union).abs() < 1e-9 * union);
    // One file of two items is enough for a union.
    csgkit_ok(&["union", arg(&two), "-o", arg(&out)]);
    assert!((volume(&out) - union).abs() < 1e-9 * union);
    let single = csgkit(&["intersection", arg(&far), "-o", arg(&out)]);
    assert_eq!(single.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&single.stderr);
    assert!(
        stderr.contains("the intersection needs 2 or more operands; the files give 1"),
        "{stderr}"
    );
    let info = csgkit_ok(&["info", arg(&two)]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(text.contains("format:      3MF (binary)"), "{text}");
    assert!(
        text.contains("unit:        inch (read as millimetres)"),
        "{text}"
    );
    assert!(
        text.contains("parts:       2\n  box: 12 faces\n  box: 12 faces\n"),
        "{text}"
    );
}

#[test]
fn a_zip_that_is_not_a_3mf_is_an_exact_error() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let path = dir.path().join("notes.3mf");
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).expect("a new file"));
    zip.start_file("notes.txt", zip::write::SimpleFileOptions::default())
        .expect("an entry");
    zip.write_all(b"not a model").expect("written");
    zip.finish().expect("a zip archive");
    let output = csgkit(&["info", arg(&path)]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    let expected = format!(
        "cannot load {0}: {0}: malformed 3MF file: not a 3MF file: the zip archive has no 3D \
         model part (no 3dmodel relationship in _rels/.rels and no 3D/3dmodel.model)",
        path.display()
    );
    assert!(stderr.contains(&expected), "{stderr}");
}
