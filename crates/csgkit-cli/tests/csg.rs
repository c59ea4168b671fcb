//! `csgkit csg` end to end: a JSON scene evaluated in one pass, `--stats`, and errors that
//! name the JSON path of the bad node.

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
        r#"{"union": [{"cube": {"size": 1}}, {"hull": []}]}"#,
    )
    .unwrap();
    let out = dir.path().join("out.obj");
    let output = csgkit(&["csg", arg(&scene), "-o", arg(&out)]);
    assert_eq!(output.status.code(), Some(2));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(
        message.contains("/union/1: unknown key \"hull\""),
        "{message}"
    );
    assert!(!out.exists(), "nothing is written on an error");
}
