//! `csgkit discrete …` end to end: files in, files and JSON out, exit codes.

use std::path::PathBuf;
use std::process::Command;

fn csgkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_csgkit"))
}

fn repo_cube() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../csgkit/tests/data/cube.obj")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("csgkit-discrete-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn voxelize_writes_maximal_faces_or_surfels_and_stats() {
    let dir = temp_dir("voxelize");
    let out = dir.join("cube_vox.obj");
    let run = csgkit()
        .args(["discrete", "voxelize"])
        .arg(repo_cube())
        .arg("-o")
        .arg(&out)
        .args(["--cell", "0.125", "--stats", "--mesh", "surfels"])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stats: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(stats["voxels"], 512);
    assert!(stats["op_seconds"].as_f64().unwrap() >= 0.0);
    // 8³ voxels: 6·64 unit quads.
    let mesh = csgkit::io::read_mesh(&out).unwrap().mesh;
    assert_eq!(mesh.face_count(), 6 * 64);
    // By default through the orthogonal engine: one maximal face per side.
    let ortho = csgkit()
        .args(["discrete", "voxelize"])
        .arg(repo_cube())
        .arg("-o")
        .arg(&out)
        .args(["--cell", "0.125"])
        .output()
        .unwrap();
    assert!(
        ortho.status.success(),
        "{}",
        String::from_utf8_lossy(&ortho.stderr)
    );
    let mesh = csgkit::io::read_mesh(&out).unwrap().mesh;
    assert_eq!(mesh.face_count(), 6);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn mixed_cell_difference_writes_boxes() {
    let dir = temp_dir("difference");
    let out = dir.join("boxes.txt");
    let cube = repo_cube().display().to_string();
    let run = csgkit()
        .args([
            "discrete",
            "difference",
            &format!("{cube}@0.5"),
            &format!("{cube}@0.125"),
        ])
        .arg("-o")
        .arg(&out)
        .arg("--stats")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stats: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    // The unit cube at cell 0.5 is the unit cube at cell 0.125: nothing is left.
    assert_eq!(stats["voxels"], 0);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "");
    let union = csgkit()
        .args([
            "discrete",
            "union",
            &format!("{cube}@0.5"),
            &format!("{cube}@0.125"),
        ])
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(union.status.success());
    let volume: f64 = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|t| t.parse().unwrap()).collect();
            (v[3] - v[0]) * (v[4] - v[1]) * (v[5] - v[2])
        })
        .sum();
    assert_eq!(volume, 1.0);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_cells_and_missing_files_exit_2() {
    let dir = temp_dir("errors");
    let out = dir.join("x.obj");
    let cube = repo_cube().display().to_string();
    let uneven = csgkit()
        .args([
            "discrete",
            "union",
            &format!("{cube}@0.5"),
            &format!("{cube}@0.3"),
        ])
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(uneven.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&uneven.stderr).contains("power of two"));
    let missing = csgkit()
        .args([
            "discrete",
            "voxelize",
            "no/such/file.obj",
            "--cell",
            "1",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(missing.status.code(), Some(2));
    assert!(!out.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn demo_runs_the_multi_scale_showcase() {
    let run = csgkit().args(["discrete", "demo"]).output().unwrap();
    assert!(run.status.success());
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(text.contains("wall - torus"), "{text}");
}
