//! `csgkit repair IN -o OUT` end to end: a mesh whose faces cross resolves to a valid solid
//! without self-intersections, `--stats` prints the resolved pairs as JSON, `--winding`
//! chooses the rule, and an open mesh exits 2 naming its unbalanced edges.
//!
//! The inputs are unit cubes on quarter-unit coordinates, so every output coordinate is exact
//! and the volumes are compared with `==`.

use std::path::{Path, PathBuf};

use csgkit::primitives::cuboid;
use csgkit::{Mesh, WriteOptions, self_intersections, write_mesh};
use serde_json::Value;
use tempfile::TempDir;

use crate::common::{arg, csgkit, csgkit_ok};

/// The meshes as one: vertices and triangles concatenated, nothing welded or resolved.
fn one_mesh(parts: &[Mesh]) -> Mesh {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for part in parts {
        let base = positions.len() as u32;
        positions.extend_from_slice(part.positions());
        triangles.extend(
            part.faces()
                .map(|f| [f[0] + base, f[1] + base, f[2] + base]),
        );
    }
    Mesh::from_triangles(positions, &triangles).expect("indices are offset into the parts")
}

/// `mesh` with every triangle reversed.
fn reversed(mesh: &Mesh) -> Mesh {
    let triangles: Vec<[u32; 3]> = mesh.faces().map(|f| [f[0], f[2], f[1]]).collect();
    Mesh::from_triangles(mesh.positions().to_vec(), &triangles).expect("same indices")
}

/// Writes `mesh` to `name` in `dir`.
fn write(dir: &TempDir, name: &str, mesh: &Mesh) -> PathBuf {
    let path = dir.path().join(name);
    write_mesh(&path, mesh, WriteOptions::default()).expect("the input is written");
    path
}

/// The unit cubes at the origin and at (0.5, 0.5, 0.5), as one OBJ: closed and outward, but
/// their faces cross. Their union has volume 2 − 1/8.
fn crossing_cubes(dir: &TempDir) -> PathBuf {
    let both = one_mesh(&[cuboid([0.0; 3], [1.0; 3]), cuboid([0.5; 3], [1.5; 3])]);
    assert!(!self_intersections(&both).is_empty(), "the cubes cross");
    write(dir, "crossing.obj", &both)
}

/// `csgkit check --json` of `path`.
fn check(path: &Path) -> Value {
    let output = csgkit(&["check", "--json", arg(path)]);
    serde_json::from_slice(&output.stdout).expect("check prints one JSON object")
}

/// Asserts `path` is a valid solid of exactly `volume` whose faces do not cross.
fn assert_repaired(path: &Path, volume: f64) {
    let report = check(path);
    assert_eq!(report["valid_solid"], true, "{report}");
    assert_eq!(report["volume"].as_f64(), Some(volume), "{report}");
    let mesh = csgkit::read_mesh(path).expect("the output reads back").mesh;
    let found = self_intersections(&mesh);
    assert!(found.is_empty(), "{:?}", found.pairs);
}

#[test]
fn repair_resolves_crossing_cubes() {
    let dir = tempfile::tempdir().unwrap();
    let input = crossing_cubes(&dir);
    let out = dir.path().join("fixed.obj");
    let run = csgkit_ok(&["repair", arg(&input), "-o", arg(&out)]);
    assert!(run.stdout.is_empty(), "nothing on stdout without --stats");
    let message = String::from_utf8_lossy(&run.stderr);
    assert!(message.contains("by winding numbers"), "{message}");
    assert_repaired(&out, 1.875);
}

#[test]
fn repair_stats_count_the_crossing_pairs() {
    let dir = tempfile::tempdir().unwrap();
    let input = crossing_cubes(&dir);
    let out = dir.path().join("fixed.ply");
    let run = csgkit_ok(&["repair", arg(&input), "-o", arg(&out), "--stats"]);
    let stats: Value = serde_json::from_slice(&run.stdout).expect("stdout is one JSON object");
    let pairs = stats["self_intersecting_pairs"].as_u64();
    assert!(pairs.is_some_and(|n| n > 0), "{stats}");
    assert_eq!(stats["winding_classification"], true, "{stats}");
    assert_eq!(stats["valid_solid"], true, "{stats}");
    assert_eq!(stats["volume"].as_f64(), Some(1.875), "{stats}");
    assert_eq!(stats["input_triangles"], 24, "{stats}");
    assert_eq!(stats["inputs"].as_array().map(Vec::len), Some(1), "{stats}");
    assert_repaired(&out, 1.875);
}

/// An outward cube and an inward one beside it (signed volume 0): the inward cube is solid
/// where the winding number is non-zero (the default) and empty where it must be positive.
#[test]
fn repair_winding_rule_decides_an_inward_shell() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = one_mesh(&[
        cuboid([0.0; 3], [1.0; 3]),
        reversed(&cuboid([3.0, 0.0, 0.0], [4.0, 1.0, 1.0])),
    ]);
    let input = write(&dir, "inward.obj", &mesh);
    let nonzero = dir.path().join("nonzero.obj");
    csgkit_ok(&["repair", arg(&input), "-o", arg(&nonzero)]);
    assert_repaired(&nonzero, 2.0);
    let positive = dir.path().join("positive.obj");
    csgkit_ok(&[
        "repair",
        arg(&input),
        "-o",
        arg(&positive),
        "--winding",
        "positive",
    ]);
    assert_repaired(&positive, 1.0);
}

/// A unit cube without its z = 0 face (the first two triangles of `cuboid`, on vertices 0–3):
/// its four edges 0–1, 0–2, 1–3 and 2–3 (OBJ numbers from 1, the message from 0) have one
/// use each.
#[test]
fn repair_of_an_open_mesh_names_its_boundary_edges() {
    let dir = tempfile::tempdir().unwrap();
    let cube = cuboid([0.0; 3], [1.0; 3]);
    let triangles: Vec<[u32; 3]> = (cube.faces().skip(2)).map(|f| [f[0], f[1], f[2]]).collect();
    let open = Mesh::from_triangles(cube.positions().to_vec(), &triangles).expect("indices");
    let input = write(&dir, "open.obj", &open);
    let out = dir.path().join("out.obj");
    let run = csgkit(&["repair", arg(&input), "-o", arg(&out), "--stats"]);
    assert_eq!(run.status.code(), Some(2));
    let message = String::from_utf8_lossy(&run.stderr);
    assert!(message.contains(arg(&input)), "names the file: {message}");
    assert!(message.contains("not closed"), "{message}");
    assert!(message.contains("4 edges are unbalanced"), "{message}");
    for [a, b] in [[0, 1], [0, 2], [1, 3], [2, 3]] {
        assert!(
            message.contains(&format!("{a}–{b}")) || message.contains(&format!("{b}–{a}")),
            "edge {a}–{b}: {message}"
        );
    }
    assert!(run.stdout.is_empty(), "no stats after an error");
    assert!(!out.exists(), "no output after an error");
}
