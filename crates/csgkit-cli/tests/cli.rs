//! The `csgkit` binary end to end: exit codes, `--json`, `--help`.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common::csgkit;

/// The closed unit cube of quads kept in the library's test data.
fn cube() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../csgkit/tests/data/cube.obj");
    path.to_string_lossy().into_owned()
}

/// Writes `content` to a fresh file named `name` in a per-test temporary folder.
fn temp_file(test: &str, name: &str, content: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("csgkit-cli-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, content).expect("temp file");
    path
}

/// A unit square: a mesh, but not a solid.
const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

fn code(output: &Output) -> Option<i32> {
    output.status.code()
}

#[test]
fn check_exits_0_for_a_valid_solid() {
    let output = csgkit(&["check", &cube()]);
    assert_eq!(code(&output), Some(0), "{output:?}");
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.contains("valid solid:"), "{text}");
    assert!(text.contains("genus:"), "{text}");
}

#[test]
fn check_exits_1_for_an_open_mesh() {
    let path = temp_file("open", "square.obj", SQUARE);
    let output = csgkit(&["check", path.to_str().expect("utf-8 temp path")]);
    assert_eq!(code(&output), Some(1), "{output:?}");
    assert!(String::from_utf8_lossy(&output.stdout).contains("no (not closed)"));
}

#[test]
fn check_exits_2_on_errors() {
    let missing = csgkit(&["check", "no/such/file.obj"]);
    assert_eq!(code(&missing), Some(2));
    let message = String::from_utf8_lossy(&missing.stderr);
    assert!(message.contains("no/such/file.obj"), "{message}");
    let bad = temp_file("bad", "bad.obj", "v 0 0 0\nf 1 2 3\n");
    assert_eq!(
        code(&csgkit(&["check", bad.to_str().expect("utf-8")])),
        Some(2)
    );
    let empty_stl = temp_file("empty", "empty.stl", "");
    assert_eq!(
        code(&csgkit(&["info", empty_stl.to_str().expect("utf-8")])),
        Some(2)
    );
    assert_eq!(code(&csgkit(&["check"])), Some(2), "usage errors exit 2");
}

#[test]
fn check_json_is_one_object_with_every_measure() {
    let output = csgkit(&["check", "--json", &cube()]);
    assert_eq!(code(&output), Some(0));
    let json: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("stdout is one JSON object");
    assert_eq!(json["closed"], true);
    assert_eq!(json["oriented"], true);
    assert_eq!(json["valid_solid"], true);
    assert_eq!(json["faces"], 6);
    assert_eq!(json["polygons"], 6);
    assert_eq!(json["genus"], 0);
    assert_eq!(json["volume"], 1.0);
    assert_eq!(json["format"], "OBJ (text)");
    assert_eq!(json["selfint_pairs"], 0);
}

#[test]
fn check_reports_self_intersecting_faces() {
    // A vertical triangle piercing a horizontal one; the check counts pairs on any mesh.
    let obj =
        "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0.5 0.5 -1\nv 0.5 0.5 1\nv 1.5 0.5 0\nf 1 2 3\nf 4 5 6\n";
    let path = temp_file("selfint", "pierce.obj", obj);
    let output = csgkit(&["check", "--json", path.to_str().expect("utf-8 temp path")]);
    let json: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("stdout is one JSON object");
    assert_eq!(json["selfint_pairs"], 1);
    assert_eq!(json["selfint_faces"], 2);
    assert_eq!(json["selfint_first_pairs"], serde_json::json!([[0, 1]]));
}

#[test]
fn check_reports_self_overlapping_polygons() {
    // A closed mesh of two bow ties, each the other reversed: balanced edges, but neither
    // polygon is simple in its projection.
    let obj = "v 0 0 0\nv 2 2 0\nv 2 0 0\nv 0 2 0\nf 1 2 3 4\nf 4 3 2 1\n";
    let path = temp_file("bowtie", "bowtie.obj", obj);
    let path = path.to_str().expect("utf-8 temp path");
    let output = csgkit(&["check", "--json", path]);
    let json: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("stdout is one JSON object");
    assert_eq!(json["invalid_polygons"][1]["face"], 1);
    let problem = json["invalid_polygons"][0]["problem"]
        .as_str()
        .unwrap_or("");
    assert!(problem.contains("face 0 overlaps itself"), "{problem}");
    let text = String::from_utf8_lossy(&csgkit(&["check", path]).stdout).into_owned();
    assert!(text.contains("invalid polygons:"), "{text}");
    assert!(text.contains("2 (first: face 0 overlaps itself"), "{text}");
}

#[test]
fn info_prints_format_counts_and_box() {
    let output = csgkit(&["info", &cube()]);
    assert_eq!(code(&output), Some(0), "{output:?}");
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.contains("OBJ"), "{text}");
    assert!(text.contains("vertices:    8"), "{text}");
    assert!(text.contains("[0, 0, 0] .. [1, 1, 1]"), "{text}");
}

#[test]
fn info_counts_the_vertices_an_stl_stores() {
    let facet = |a: &str, b: &str, c: &str| {
        format!(
            "facet normal 0 0 0\nouter loop\nvertex {a}\nvertex {b}\nvertex {c}\nendloop\nendfacet\n"
        )
    };
    let stl = format!(
        "solid square\n{}{}endsolid square\n",
        facet("0 0 0", "1 0 0", "1 1 0"),
        facet("0 0 0", "1 1 0", "0 1 0")
    );
    let path = temp_file("stl", "square.stl", &stl);
    let output = csgkit(&["info", path.to_str().expect("utf-8")]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.contains("STL (text)"), "{text}");
    assert!(
        text.contains("vertices:    4 (6 stored, welded on read)"),
        "{text}"
    );
    let check = csgkit(&["check", "--json", path.to_str().expect("utf-8")]);
    let json: serde_json::Value = serde_json::from_slice(&check.stdout).expect("JSON");
    assert_eq!(
        (
            json["vertices"].as_u64(),
            json["duplicate_vertices"].as_u64()
        ),
        (Some(6), Some(2))
    );
    assert_eq!(json["boundary_loops"], 1);
    assert_eq!(code(&check), Some(1));
}

#[test]
fn every_subcommand_help_has_an_example() {
    for subcommand in ["info", "check"] {
        let output = csgkit(&[subcommand, "--help"]);
        assert_eq!(code(&output), Some(0));
        let text = String::from_utf8_lossy(&output.stdout);
        assert!(text.contains("Example"), "{subcommand}: {text}");
    }
}
