//! `csgkit repair IN -o OUT`: the boundary of the region inside a mesh, as a valid solid.
//!
//! The mesh's faces may cross each other, its shells may overlap or nest, and rounding by
//! another tool may have folded it: the result is the exact boundary of the points where its
//! winding number is non-zero (or positive, `--winding positive`), certified as f64 numbers
//! like every exact boolean's result. It is the union of the mesh alone
//! ([`csgkit::exact::boolean`] with one operand). Open meshes stay an error naming their
//! boundary edges.

use std::path::PathBuf;

use clap::Args;
use csgkit::Operation;

use super::exact::{ExactArgs, FaceArgs, Winding, run_operands};

/// Arguments of `csgkit repair`.
#[derive(Args, Debug, Clone)]
pub struct RepairArgs {
    /// The mesh to repair: closed (every edge used as often in each direction), any format
    /// csgkit reads (the parts of a 3MF or glTF are repaired as one mesh).
    pub input: PathBuf,
    /// The output mesh; its extension chooses the format (obj, ply, off, stl, 3mf, gltf, glb).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Which points are inside: where the winding number is non-zero, or only positive.
    #[arg(long, value_enum, default_value_t = Winding::Nonzero)]
    pub winding: Winding,
    /// Split the result's non-manifold edges and vertices so it is a 2-manifold.
    #[arg(long)]
    pub manifold: bool,
    /// Print one JSON object on stdout instead of the summary on stderr.
    #[arg(long)]
    pub stats: bool,
    /// Which faces to write.
    #[command(flatten)]
    pub faces: FaceArgs,
}

/// Runs `csgkit repair`.
pub fn run(args: &RepairArgs) -> anyhow::Result<()> {
    let exact = ExactArgs {
        inputs: vec![args.input.clone()],
        output: args.output.clone(),
        merge: true,
        manifold: args.manifold,
        stats: args.stats,
        no_self_check: false,
        winding: args.winding,
        faces: args.faces.clone(),
    };
    let stats = run_operands(Operation::Union, &exact, 1)?;
    if !args.stats {
        eprintln!(
            "csgkit: resolved {} crossing triangle pairs{}; wrote {} faces to {}",
            stats.self_intersecting_pairs,
            if stats.winding_classification {
                " by winding numbers"
            } else {
                ""
            },
            stats.output_faces,
            args.output.display()
        );
    }
    Ok(())
}
