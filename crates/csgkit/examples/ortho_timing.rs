//! Prints the stage times of the orthogonal engine on random box sets and the empirical
//! growth exponent: `cargo run --release --example ortho_timing [N ...]`.

use std::time::Instant;

use csgkit::ortho::{MeshOptions, box_union_timed, random_grid_boxes};
use csgkit::{Progress, Stage};

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![100, 1_000, 10_000, 100_000]
    } else {
        sizes
    };
    let mut points = Vec::new();
    for n in sizes {
        let boxes = random_grid_boxes(n, 0x5eed);
        let start = Instant::now();
        let (brep, stages) =
            box_union_timed(&boxes, None, &Progress::default()).expect("random boxes are finite");
        let seconds = |stage: Stage| (stages.iter().find(|s| s.0 == stage)).map_or(0.0, |s| s.1);
        let mesh_start = Instant::now();
        let mesh = brep
            .to_mesh(MeshOptions::default())
            .expect("triangulation succeeds")
            .mesh;
        let mesh_s = mesh_start.elapsed().as_secs_f64();
        let total = start.elapsed().as_secs_f64();
        println!(
            "n={n:>7} vertices={:>8} faces={:>7} mesh_faces={:>8} rank={:.4} sweep={:.4} loops={:.4} mesh={mesh_s:.4} total={total:.4}",
            brep.vertices.len(),
            brep.faces.len(),
            mesh.face_count(),
            seconds(Stage::Rank),
            seconds(Stage::Sweep),
            seconds(Stage::Loops),
        );
        points.push(((n as f64).ln(), total.ln()));
    }
    if points.len() >= 2 {
        let m = points.len() as f64;
        let (sx, sy) = points
            .iter()
            .fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
        let (mx, my) = (sx / m, sy / m);
        let num: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let den: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
        println!(
            "growth exponent (least squares on log-log): {:.2}",
            num / den
        );
    }
}
