//! Times the exact self-intersection check on a subdivided icosphere and on mesh files:
//! `cargo run --release --example selfint_timing [SUBDIVISIONS] [FILE ...]`.
//!
//! Each input is timed three times after loading; the best run is printed with the counts.

use std::time::Instant;

use csgkit::csg::primitives::icosphere;
use csgkit::{Mesh, read_mesh, self_intersections};

fn main() {
    let mut args = std::env::args().skip(1);
    let subdivisions: u32 = args.next().and_then(|a| a.parse().ok()).unwrap_or(8);
    let mut inputs: Vec<(String, Mesh)> = vec![(
        format!("icosphere({subdivisions})"),
        icosphere([0.0; 3], 1.0, subdivisions),
    )];
    for path in args {
        let mesh = read_mesh(&path).unwrap_or_else(|e| panic!("{e}")).mesh;
        inputs.push((path, mesh));
    }
    for (name, mesh) in &inputs {
        let mut best = f64::INFINITY;
        let mut found = None;
        for _ in 0..3 {
            let start = Instant::now();
            found = Some(self_intersections(mesh));
            best = best.min(start.elapsed().as_secs_f64());
        }
        let found = found.expect("timed at least once");
        println!(
            "{name}: faces={} pairs={} involved={} best={best:.3} s (threads={})",
            mesh.face_count(),
            found.pair_count(),
            found.face_count(),
            rayon::current_num_threads(),
        );
    }
}
