//! `csgkit union | intersection | difference | xor` and the demo's exact showcase end to end: exit
//! codes, outputs checked by their topology and measures, `--stats`, and errors that name the
//! file at fault.
//!
//! The operands are axis-aligned boxes on small integers, so every output coordinate is an
//! input coordinate; the volume and area are still rounded sums over the triangles (from the
//! origin), so they are compared to a few ulps.

use std::path::{Path, PathBuf};

use csgkit::primitives::cuboid;
use csgkit::{WriteOptions, write_mesh};
use serde_json::Value;
use tempfile::TempDir;

use crate::common::{arg, csgkit, csgkit_ok};

/// Writes the box `[min, max]` to `name` in `dir`, in the format its extension names.
fn cube(dir: &TempDir, name: &str, min: [f64; 3], max: [f64; 3]) -> PathBuf {
    let path = dir.path().join(name);
    write_mesh(&path, &cuboid(min, max), WriteOptions::default()).expect("the operand is written");
    path
}

/// `csgkit check --json` of `path`.
fn check(path: &Path) -> Value {
    let output = csgkit(&["check", "--json", arg(path)]);
    serde_json::from_slice(&output.stdout).expect("check prints one JSON object")
}

/// Whether every edge of the file's mesh, by vertex index, has at most two uses.
///
/// `csgkit check` welds coincident positions before its topology, so it sees the vertices a
/// manifold split duplicated as one again; the split shows only in the indices.
fn index_edge_manifold(path: &Path) -> bool {
    let mesh = csgkit::read_mesh(path).expect("the output reads back").mesh;
    csgkit::mesh::analyze_topology(&mesh).is_edge_manifold()
}

/// Asserts that a JSON number is `expected` up to the rounding of a sum over triangles.
fn assert_close(value: &Value, expected: f64) {
    let value = value.as_f64().expect("a finite number");
    assert!(
        (value - expected).abs() <= 1e-12 * expected.abs(),
        "{value} ≠ {expected}"
    );
}

/// Asserts that `path` is a valid solid of this volume and area with one component.
fn assert_solid(path: &Path, volume: f64, area: f64) {
    let report = check(path);
    assert_eq!(report["valid_solid"], true, "{report}");
    assert_close(&report["volume"], volume);
    assert_close(&report["area"], area);
    assert_eq!(report["components"], 1, "{report}");
    assert_eq!(report["genus"], 0, "{report}");
}

#[test]
fn union_of_cubes_sharing_a_face_is_a_box_of_volume_2() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [1.0; 3]);
    let b = cube(&dir, "b.stl", [1.0, 0.0, 0.0], [2.0, 1.0, 1.0]);
    let out = dir.path().join("ab.obj");
    let run = csgkit_ok(&["union", arg(&a), arg(&b), "-o", arg(&out), "--stats"]);
    assert_solid(&out, 2.0, 10.0);

    let stats: Value = serde_json::from_slice(&run.stdout).expect("stdout is one JSON object");
    assert_eq!(stats["command"], "union");
    assert_eq!(stats["input_triangles"], 24);
    assert_eq!(stats["output_triangles"], check(&out)["faces"]);
    assert_eq!(stats["valid_solid"], true);
    assert_close(&stats["volume"], 2.0);
    assert_close(&stats["area"], 10.0);
    assert_eq!(stats["self_check"], true);
    assert_eq!(stats["inputs"][1]["file"], arg(&b));
    for key in ["read_seconds", "validate_seconds", "write_seconds"] {
        assert!(stats[key].as_f64().is_some(), "{key}: {stats}");
    }
    // `op_seconds` is every stage but the self-intersection check.
    let stages = stats["stages"].as_object().expect("stages is an object");
    assert!(stages.contains_key("ingest"), "{stats}");
    let op: f64 = (stages.iter())
        .filter(|(name, _)| *name != "validate")
        .map(|(_, seconds)| seconds.as_f64().expect("seconds are numbers"))
        .sum();
    let reported = stats["op_seconds"]
        .as_f64()
        .expect("op_seconds is a number");
    assert!((op - reported).abs() <= 1e-9 * op.max(1.0), "{stats}");
}

#[test]
fn a_cube_minus_a_flush_corner_cube_keeps_its_area() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.ply", [0.0; 3], [2.0; 3]);
    let b = cube(&dir, "b.off", [1.0; 3], [2.0; 3]);
    let out = dir.path().join("a-b.obj");
    let run = csgkit_ok(&["difference", arg(&a), arg(&b), "-o", arg(&out)]);
    assert!(run.stdout.is_empty(), "nothing on stdout without --stats");
    assert_solid(&out, 7.0, 24.0);
}

/// A ⊕ B of overlapping cubes: both cubes but their common box, bounded by both surfaces
/// (the two pieces meet along edges, non-manifold but closed).
#[test]
fn xor_of_overlapping_cubes_leaves_out_their_common_box() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [2.0; 3]);
    let b = cube(&dir, "b.obj", [1.0; 3], [3.0; 3]);
    let out = dir.path().join("ab.obj");
    let run = csgkit_ok(&["xor", arg(&a), arg(&b), "-o", arg(&out), "--stats"]);
    let stats: Value = serde_json::from_slice(&run.stdout).expect("stdout is one JSON object");
    assert_eq!(stats["command"], "xor");
    let report = check(&out);
    assert_eq!(report["valid_solid"], true, "{report}");
    assert_close(&report["volume"], 14.0);
    assert_close(&report["area"], 48.0);
}

#[test]
fn intersection_of_overlapping_cubes_is_their_common_box() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [2.0; 3]);
    let b = cube(&dir, "b.obj", [1.0; 3], [3.0; 3]);
    let out = dir.path().join("ab.off");
    csgkit_ok(&["intersection", arg(&a), arg(&b), "-o", arg(&out)]);
    assert_solid(&out, 1.0, 6.0);
}

#[test]
fn manifold_splits_the_edge_two_cubes_share() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [1.0; 3]);
    let b = cube(&dir, "b.obj", [1.0, 1.0, 0.0], [2.0, 2.0, 1.0]);
    let shared = dir.path().join("shared.obj");
    csgkit_ok(&["union", arg(&a), arg(&b), "-o", arg(&shared)]);
    let report = check(&shared);
    assert_eq!(report["valid_solid"], true, "{report}");
    assert_eq!(report["edge_manifold"], false, "{report}");
    assert!(!index_edge_manifold(&shared));

    let split = dir.path().join("split.obj");
    csgkit_ok(&["union", arg(&a), arg(&b), "-o", arg(&split), "--manifold"]);
    assert!(index_edge_manifold(&split));
    let report = check(&split);
    assert_eq!(report["valid_solid"], true, "{report}");
    assert_close(&report["volume"], 2.0);
}

#[test]
fn union_of_three_overlapping_cubes_is_one_bar() {
    let dir = tempfile::tempdir().unwrap();
    let bars: Vec<PathBuf> = (0..3)
        .map(|i| {
            let x = f64::from(i);
            let name = format!("c{i}.obj");
            cube(&dir, &name, [x, 0.0, 0.0], [x + 2.0, 1.0, 1.0])
        })
        .collect();
    let out = dir.path().join("bar.ply");
    let run = csgkit_ok(&[
        "union",
        arg(&bars[0]),
        arg(&bars[1]),
        arg(&bars[2]),
        "-o",
        arg(&out),
        "--stats",
    ]);
    assert_solid(&out, 4.0, 18.0);
    let stats: Value = serde_json::from_slice(&run.stdout).expect("stdout is one JSON object");
    // Three plain boxes are united by the orthogonal engine first: the exact engine meets
    // one operand, the 4 × 1 × 1 bar, in 12 triangles.
    assert_eq!(stats["input_triangles"], 12);
    assert!(stats["stages"]["sweep"].is_number(), "{stats}");
    assert_eq!(stats["inputs"].as_array().map(Vec::len), Some(3));
}

#[test]
fn difference_removes_every_later_operand_from_the_first() {
    // A 3 × 1 × 1 bar minus two boxes that each swallow one end (overhanging the bar's four
    // long sides) leaves the middle unit cube, cut at x = 1 and x = 2.
    let dir = tempfile::tempdir().unwrap();
    let bar = cube(&dir, "bar.obj", [0.0; 3], [3.0, 1.0, 1.0]);
    let left = cube(&dir, "left.obj", [-1.0; 3], [1.0, 2.0, 2.0]);
    let right = cube(&dir, "right.obj", [2.0, -1.0, -1.0], [4.0, 2.0, 2.0]);
    let out = dir.path().join("middle.obj");
    csgkit_ok(&[
        "difference",
        arg(&bar),
        arg(&left),
        arg(&right),
        "-o",
        arg(&out),
    ]);
    assert_solid(&out, 1.0, 6.0);
}

#[test]
fn no_self_check_skips_only_the_validation() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [1.0; 3]);
    let b = cube(&dir, "b.obj", [1.0, 0.0, 0.0], [2.0, 1.0, 1.0]);
    let out = dir.path().join("ab.obj");
    let run = csgkit_ok(&[
        "union",
        arg(&a),
        arg(&b),
        "-o",
        arg(&out),
        "--stats",
        "--no-self-check",
    ]);
    let stats: Value = serde_json::from_slice(&run.stdout).expect("stdout is one JSON object");
    assert_eq!(stats["self_check"], false);
    assert_eq!(stats["validate_seconds"], 0.0);
    assert!(
        !stats["stages"]
            .as_object()
            .unwrap()
            .contains_key("validate")
    );
    assert_solid(&out, 2.0, 10.0);
}

#[test]
fn one_operand_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [1.0; 3]);
    let out = dir.path().join("out.obj");
    for op in ["union", "intersection", "difference"] {
        let run = csgkit(&[op, arg(&a), "-o", arg(&out)]);
        assert_eq!(run.status.code(), Some(2), "{op}");
        let stderr = String::from_utf8_lossy(&run.stderr);
        let expected = format!("the {op} needs 2 or more operands; the files give 1");
        assert!(stderr.contains(&expected), "{stderr}");
        assert!(!out.exists(), "{op}");
    }
}

#[test]
fn a_missing_operand_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [1.0; 3]);
    let missing = dir.path().join("no-such-operand.obj");
    let out = dir.path().join("out.obj");
    let run = csgkit(&["union", arg(&a), arg(&missing), "-o", arg(&out), "--stats"]);
    assert_eq!(run.status.code(), Some(2));
    let message = String::from_utf8_lossy(&run.stderr);
    assert!(message.contains(arg(&missing)), "{message}");
    assert!(run.stdout.is_empty(), "no stats after an error");
    assert!(!out.exists());
}

#[test]
fn a_malformed_operand_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [1.0; 3]);
    let bad = dir.path().join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nf 1 2 3\n").unwrap();
    let out = dir.path().join("out.obj");
    let run = csgkit(&["difference", arg(&a), arg(&bad), "-o", arg(&out)]);
    assert_eq!(run.status.code(), Some(2));
    let message = String::from_utf8_lossy(&run.stderr);
    assert!(message.contains(arg(&bad)), "{message}");
    assert!(!out.exists());
}

#[test]
fn an_open_operand_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let a = cube(&dir, "a.obj", [0.0; 3], [1.0; 3]);
    // A unit square apart from the cube: a mesh, but it bounds no solid.
    let square = dir.path().join("square.obj");
    std::fs::write(&square, "v 0 0 3\nv 1 0 3\nv 1 1 3\nv 0 1 3\nf 1 2 3 4\n").unwrap();
    let out = dir.path().join("out.obj");
    let run = csgkit(&["union", arg(&a), arg(&square), "-o", arg(&out)]);
    assert_eq!(run.status.code(), Some(2));
    let message = String::from_utf8_lossy(&run.stderr);
    assert!(message.contains(arg(&square)), "{message}");
    assert!(message.contains("not closed"), "{message}");
    assert!(
        !message.contains(arg(&a)),
        "only the open operand is blamed: {message}"
    );
    assert!(!out.exists());
}

#[test]
fn an_unknown_output_format_fails_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.obj");
    let out = dir.path().join("out.xyz");
    let run = csgkit(&["union", arg(&missing), arg(&missing), "-o", arg(&out)]);
    assert_eq!(run.status.code(), Some(2));
    let message = String::from_utf8_lossy(&run.stderr);
    assert!(message.contains("out.xyz"), "{message}");
    assert!(!message.contains("missing.obj"), "{message}");
}

#[test]
fn help_shows_examples_and_the_self_check_assumption() {
    for op in ["union", "intersection", "difference"] {
        let run = csgkit_ok(&[op, "--help"]);
        let text = String::from_utf8_lossy(&run.stdout);
        assert!(text.contains("Example"), "{op}: {text}");
        assert!(text.contains("--no-self-check"), "{op}: {text}");
        assert!(text.contains("assumes"), "{op}: {text}");
    }
}

#[test]
fn demo_writes_the_exact_showcase() {
    let dir = tempfile::tempdir().unwrap();
    let run = csgkit_ok(&["demo", "-o", arg(dir.path())]);
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(text.contains("valid solid: yes"), "{text}");
    let report = check(&dir.path().join("cube_minus_sphere_torus_cylinder.obj"));
    assert_eq!(report["valid_solid"], true, "{report}");
    assert_eq!(report["components"], 1, "{report}");
    // The drilled cylinder is the one hole through; the torus and the sphere only dent.
    assert_eq!(report["genus"], 1, "{report}");
    // The cube's 8 minus the hole (0.56), the bowl (a hemisphere, 0.45) and the moat (half
    // the torus, 0.43), less what they share (about 0.24).
    let volume = report["volume"].as_f64().expect("a finite volume");
    assert!((6.6..7.0).contains(&volume), "{report}");
}

/// An OBJ box of six quads with texture coordinates and one material, in `library`.
fn textured_box(
    dir: &TempDir,
    name: &str,
    min: [f64; 3],
    max: [f64; 3],
    material: &str,
) -> PathBuf {
    let mut text = format!("mtllib {material}.mtl\n");
    for i in 0..8 {
        let p = [0, 1, 2].map(|k| if i >> k & 1 == 1 { max[k] } else { min[k] });
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    text += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    text += &format!("usemtl {material}\n");
    for quad in [
        [1, 5, 7, 3],
        [2, 4, 8, 6],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 3, 4, 2],
        [5, 6, 8, 7],
    ] {
        text += "f";
        for (corner, v) in quad.iter().enumerate() {
            text += &format!(" {v}/{}", corner + 1);
        }
        text += "\n";
    }
    let path = dir.path().join(name);
    std::fs::write(&path, text).expect("the operand is written");
    path
}

/// The faces of an OBJ file, as corner counts.
fn obj_face_sizes(path: &Path) -> Vec<usize> {
    let text = std::fs::read_to_string(path).expect("the output reads");
    let mut sizes: Vec<usize> = (text.lines())
        .filter(|l| l.starts_with("f "))
        .map(|l| l.split_whitespace().count() - 1)
        .collect();
    sizes.sort_unstable();
    sizes
}

/// A textured box pushed into another: the result keeps both material libraries and both
/// materials, every corner has a texture coordinate, and the three face modes write the
/// counts of the library's reconstruction (16 vertices; 28 triangles, 14 quads, or 12
/// polygons of which the top face's two hexagons).
#[test]
fn booleans_write_materials_uvs_and_the_face_mode_asked_for() {
    let dir = TempDir::new().expect("a temporary directory");
    let a = textured_box(&dir, "a.obj", [0.0; 3], [2.0; 3], "stone");
    let b = textured_box(&dir, "b.obj", [0.5, 0.5, 1.5], [1.5, 1.5, 3.0], "wood");
    let cases = [
        (None, vec![3; 28]),
        (Some("--quads"), vec![4; 14]),
        (Some("--polygons"), [vec![4; 10], vec![6; 2]].concat()),
    ];
    for (flag, sizes) in cases {
        let out = dir.path().join("out.obj");
        let mut args = vec!["difference", arg(&a), arg(&b), "-o", arg(&out)];
        args.extend(flag);
        csgkit_ok(&args);
        assert_eq!(obj_face_sizes(&out), sizes, "{flag:?}");
        let text = std::fs::read_to_string(&out).expect("the output reads");
        for line in [
            "mtllib stone.mtl",
            "mtllib wood.mtl",
            "usemtl stone",
            "usemtl wood",
        ] {
            assert!(text.lines().any(|l| l == line), "{flag:?}: no `{line}`");
        }
        assert!(
            text.lines().any(|l| l.starts_with("vt ")),
            "{flag:?}: no vt"
        );
        let corners_without_uv = (text.lines())
            .filter(|l| l.starts_with("f "))
            .flat_map(|l| l.split_whitespace().skip(1))
            .filter(|c| !c.contains('/'))
            .count();
        assert_eq!(corners_without_uv, 0, "{flag:?}");
        assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 16);
        assert_solid(&out, 7.5, 26.0);
    }
}
