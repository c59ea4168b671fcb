//! Times the exact boolean on mesh files: `cargo run --release -p csgkit --example
//! exact_timing -- OP A B [C ...]` (OP = union, intersection or difference). Prints the stage
//! times, the counts and whether the result is a valid solid, with its volume.

use csgkit::Operation;
use csgkit::exact::{BooleanOptions, boolean};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let op = match args.first().map(String::as_str) {
        Some("union") => Operation::Union,
        Some("intersection") => Operation::Intersection,
        Some("difference") => Operation::Difference,
        _ => return Err("usage: exact_timing union|intersection|difference A B [C ...]".into()),
    };
    let meshes = (args[1..].iter())
        .map(|path| csgkit::read_mesh(path).map(|loaded| loaded.mesh))
        .collect::<Result<Vec<_>, _>>()?;
    let operands: Vec<&csgkit::Mesh> = meshes.iter().collect();
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
