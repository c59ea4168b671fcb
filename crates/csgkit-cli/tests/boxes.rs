//! `csgkit boxes` and `csgkit demo` end to end: exit codes, outputs and `--stats`.

use std::path::Path;

use crate::common::csgkit;

/// Counts the `v` and `f` lines of an OBJ file.
fn obj_counts(path: &Path) -> (usize, usize) {
    let text = std::fs::read_to_string(path).unwrap();
    let count = |k: &str| text.lines().filter(|l| l.starts_with(k)).count();
    (count("v "), count("f "))
}

#[test]
fn boxes_writes_the_union_and_prints_stats() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("e2.txt");
    std::fs::write(&input, "# E2: edge contact\n0 0 0 1 1 1\n1 1 0 2 2 1\n").unwrap();
    let out = dir.path().join("e2.obj");
    let run = csgkit(&[
        "boxes",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--stats",
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(obj_counts(&out), (14, 12));
    let stats: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(stats["brep_vertices"], 14);
    assert!(stats["op_seconds"].as_f64().is_some());
    let manifold = dir.path().join("e2m.obj");
    let run = csgkit(&[
        "boxes",
        input.to_str().unwrap(),
        "-o",
        manifold.to_str().unwrap(),
        "--manifold",
    ]);
    assert!(run.status.success());
    assert_eq!(obj_counts(&manifold), (16, 24));
}

#[test]
fn a_bad_line_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("bad.txt");
    std::fs::write(&input, "0 0 0 1 1 1\n0 0 0 1 one 1\n").unwrap();
    let out = dir.path().join("bad.obj");
    let run = csgkit(&[
        "boxes",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("line 2"));
    assert!(!out.exists());
}

#[test]
fn demo_writes_its_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let run = csgkit(&["demo", "-o", dir.path().to_str().unwrap()]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for name in [
        "random_boxes.obj",
        "random_boxes_manifold.obj",
        "menger.obj",
        "menger_per_material.ply",
    ] {
        assert!(dir.path().join(name).is_file(), "{name}");
    }
}
