//! `csgkit csg` end to end: a JSON scene evaluated in one pass, `--stats`, errors that name
//! the JSON path of the bad node, and an OpenSCAD `.csg` file that imports a part beside it.

use serde_json::Value;
use tempfile::TempDir;

use crate::common::{arg, csgkit, csgkit_ok};

#[test]
fn a_scene_is_evaluated_with_its_materials_and_counts() {
    let dir = TempDir::new().unwrap();
    let scene = dir.path().join("drilled.json");
    std::fs::write(
        &scene,
        r#"{"difference": [
            {"cube": {"size": 2, "center": true}, "material": "stone"},
            {"cube": {"size": [1, 1, 3], "center": true}, "material": "hole"}]}"#,
    )
    .unwrap();
    let out = dir.path().join("drilled.obj");
    let output = csgkit_ok(&["csg", arg(&scene), "-o", arg(&out), "--stats", "--polygons"]);
    let stats: Value = serde_json::from_slice(&output.stdout).expect("one JSON object");
    assert_eq!(stats["leaves"], 2);
    assert_eq!(stats["operations"], 1);
    assert_eq!(stats["valid_solid"], true);
    assert_eq!(stats["volume"], 6.0);
    assert!(stats["op_seconds"].as_f64().is_some() && stats["stages"]["classify"].is_number());
    let text = std::fs::read_to_string(&out).unwrap();
    for line in ["usemtl stone", "usemtl hole"] {
        assert!(text.lines().any(|l| l == line), "no `{line}`");
    }
}

#[test]
fn a_bad_node_is_named_by_its_json_path() {
    let dir = TempDir::new().unwrap();
    let scene = dir.path().join("bad.json");
    std::fs::write(
        &scene,
        r#"{"union": [{"cube": {"size": 1}}, {"minkowski": []}]}"#,
    )
    .unwrap();
    let out = dir.path().join("out.obj");
    let output = csgkit(&["csg", arg(&scene), "-o", arg(&out)]);
    assert_eq!(output.status.code(), Some(2));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(
        message.contains("/union/1: unknown key \"minkowski\""),
        "{message}"
    );
    assert!(!out.exists(), "nothing is written on an error");
}

#[test]
fn a_csg_file_imports_its_parts_from_its_own_directory() {
    let dir = TempDir::new().unwrap();
    let part = "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nv 0 0 2\nv 2 0 2\nv 2 2 2\nv 0 2 2\n\
                usemtl brass\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    std::fs::write(dir.path().join("part.obj"), part).unwrap();
    let model = dir.path().join("model.csg");
    std::fs::write(
        &model,
        "difference() {\n  import(file = \"part.obj\", convexity = 2);\n  \
         cube(size = [1, 1, 3]);\n}\n",
    )
    .unwrap();
    let out = dir.path().join("drilled.obj");
    // The tests run in the crate's directory: the part is found beside the model.
    let output = csgkit_ok(&["csg", arg(&model), "-o", arg(&out), "--stats"]);
    let stats: Value = serde_json::from_slice(&output.stdout).expect("one JSON object");
    // 2³ less the 1 × 1 × 2 the bar cuts from the part.
    assert_eq!(stats["volume"], 6.0);
    assert_eq!(stats["valid_solid"], true);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.lines().any(|l| l == "usemtl brass"), "{text}");

    std::fs::remove_file(dir.path().join("part.obj")).unwrap();
    let output = csgkit(&["csg", arg(&model), "-o", arg(&out)]);
    assert_eq!(output.status.code(), Some(2));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(
        message.contains("line 2: import(\"part.obj\")"),
        "{message}"
    );
    assert!(message.contains("part.obj"), "{message}");
}
