//! Times the exact self-intersection check on a subdivided icosphere and on mesh files:
//! `cargo run --release --example selfint_timing [SUBDIVISIONS] [FILE ...]`.
//!
//! Each input is timed three times after loading (`SELFINT_RUNS` sets another count; with 0
//! the example only loads, so `perf stat` of a run minus one of a load gives the check's
//! counts); the best run is printed with the counts.
//! Next to the best wall time it prints the smallest process CPU time of the runs (Linux
//! only, from `/proc/self/stat`), which a machine busy with other work inflates far less than
//! wall time.

use std::time::Instant;

use csgkit::primitives::icosphere;
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
    let runs: usize = std::env::var("SELFINT_RUNS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(3);
    for (name, mesh) in &inputs {
        let (mut best, mut best_cpu) = (f64::INFINITY, f64::INFINITY);
        let mut found = None;
        for _ in 0..runs {
            let (start, cpu) = (Instant::now(), cpu_seconds());
            found = Some(self_intersections(mesh));
            best = best.min(start.elapsed().as_secs_f64());
            best_cpu = best_cpu.min(cpu_seconds() - cpu);
        }
        let Some(found) = found else { continue };
        println!(
            "{name}: faces={} pairs={} involved={} wall={best:.3} s cpu={best_cpu:.2} s (threads={})",
            mesh.face_count(),
            found.pair_count(),
            found.face_count(),
            rayon::current_num_threads(),
        );
    }
}

/// User plus system CPU time of this process so far, in seconds (NaN where unavailable).
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // Fields after the command name (which may hold spaces, so split after its ')'):
    // utime and stime are the 12th and 13th, in clock ticks (100 per second on Linux).
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or("", |(_, rest)| rest)
        .split_whitespace()
        .collect();
    let ticks = |k: usize| fields.get(k).and_then(|f| f.parse::<f64>().ok());
    match (ticks(11), ticks(12)) {
        (Some(user), Some(system)) => (user + system) / 100.0,
        _ => f64::NAN,
    }
}
