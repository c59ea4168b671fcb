//! Times the exact boolean on mesh files: `cargo run --release -p csgkit --example
//! exact_timing -- [--repeat N] OP A B [C ...]` (OP = union, intersection or difference).
//! Prints the stage times, the counts and whether the result is a valid solid, with its
//! volume. With `--repeat N`, runs the boolean N times in this process, with the operands'
//! self-intersection check as the CLI runs it (its `Validate` time is not the op's, and the
//! broad phase walks the trees it built), and prints the median of each stage: the warm
//! figures, against which the CLI's `--stats` of a fresh process show its first-touch costs.

use csgkit::Operation;
use csgkit::exact::{BooleanOptions, boolean};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let repeat = match args.first().map(String::as_str) {
        Some("--repeat") => {
            let count = args
                .get(1)
                .ok_or("--repeat needs a count")?
                .parse::<usize>()?;
            args.drain(..2);
            Some(count.max(1))
        }
        _ => None,
    };
    let op = match args.first().map(String::as_str) {
        Some("union") => Operation::Union,
        Some("intersection") => Operation::Intersection,
        Some("difference") => Operation::Difference,
        _ => {
            return Err(
                "usage: exact_timing [--repeat N] union|intersection|difference A B [C ...]".into(),
            );
        }
    };
    let meshes = (args[1..].iter())
        .map(|path| csgkit::read_mesh(path).map(|loaded| loaded.mesh))
        .collect::<Result<Vec<_>, _>>()?;
    let operands: Vec<&csgkit::Mesh> = meshes.iter().collect();
    if let Some(count) = repeat {
        let mut runs = Vec::with_capacity(count);
        for _ in 0..count {
            runs.push(boolean(op, &operands, &BooleanOptions::default())?.stats);
        }
        let median = |mut seconds: Vec<f64>| {
            seconds.sort_by(f64::total_cmp);
            seconds[seconds.len() / 2]
        };
        for (stage, _) in &runs[0].stage_seconds {
            let of_stage = |stats: &csgkit::exact::BooleanStats| {
                (stats.stage_seconds.iter())
                    .find(|(s, _)| s == stage)
                    .map_or(0.0, |&(_, seconds)| seconds)
            };
            let seconds = median(runs.iter().map(of_stage).collect());
            println!("{stage:?}: {:.1} µs (median of {count})", seconds * 1e6);
        }
        let op_seconds = median(runs.iter().map(|s| s.op_seconds()).collect());
        println!("op: {:.1} µs (median of {count})", op_seconds * 1e6);
        return Ok(());
    }
    let result = boolean(op, &operands, &BooleanOptions::default())?;
    let stats = &result.stats;
    for (stage, seconds) in &stats.stage_seconds {
        println!("{stage:?}: {:.4} s", seconds);
    }
    println!("op: {:.4} s", stats.op_seconds());
    println!("{stats:?}");
    let report = result.mesh.report();
    println!(
        "valid solid: {}, edge manifold: {}, volume: {}",
        report.is_valid_solid(),
        report.edge_manifold,
        report.measures.volume
    );
    Ok(())
}
