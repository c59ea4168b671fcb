//! Times a CSG tree in one exact pass and as a chain of binary booleans, and writes the tree's
//! placed leaves for other evaluators: `cargo run --release -p csgkit --example csg_trees --
//! MODEL.csg|SCENE.json [--expand DIR]`.
//!
//! Prints one JSON object: `one_pass` (seconds of the tree's boolean over its flattened
//! leaves), `chained` (the same expression as binary booleans from the leaves up, each
//! rounded, or `chain_error` when a step fails), the leaf count and both volumes. With `--expand DIR`, DIR gets the leaves as
//! `leaf_K.off` and `tree.json` (`{"leaves": [file, …], "expression": node}`, a node being
//! `{"leaf": K}` or `{"op": "union" | "intersection" | "difference" | "xor", "children": […]}`),
//! which `benches/openscad_trees.py` hands to manifold3d.

use std::time::Instant;

use csgkit::csg::{flatten, openscad::parse_openscad_csg, scene::read_scene};
use csgkit::exact::{BooleanOptions, Expression, boolean, boolean_expression};
use csgkit::{Mesh, Operation, Progress, WriteOptions, write_mesh};
use serde_json::{Value, json};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(model) = args.first() else {
        return Err("usage: csg_trees MODEL.csg|SCENE.json [--expand DIR]".into());
    };
    let path = std::path::Path::new(model);
    let tree = if model.ends_with(".json") {
        read_scene(path)?
    } else {
        let base = path.parent().unwrap_or(std::path::Path::new("."));
        parse_openscad_csg(&std::fs::read_to_string(model)?, base)?
    };
    let options = BooleanOptions::default();
    let flat = flatten(&tree, &options, &Progress::default())?;
    let operands: Vec<&Mesh> = flat.leaves.iter().collect();
    let clock = Instant::now();
    let one_pass = boolean_expression(&flat.expression, &operands, &options, &Progress::default())?;
    let one_pass_seconds = clock.elapsed().as_secs_f64();
    if let Some(dir) = args
        .iter()
        .position(|a| a == "--expand")
        .and_then(|i| args.get(i + 1))
    {
        std::fs::create_dir_all(dir)?;
        let mut files = Vec::new();
        for (k, leaf) in flat.leaves.iter().enumerate() {
            let name = format!("leaf_{k}.off");
            write_mesh(format!("{dir}/{name}"), leaf, WriteOptions::default())?;
            files.push(name);
        }
        let tree = json!({"leaves": files, "expression": to_json(&flat.expression)});
        std::fs::write(format!("{dir}/tree.json"), tree.to_string())?;
    }
    let volume = |mesh: &Mesh| mesh.report().measures.volume;
    let mut report = json!({
        "leaves": flat.leaves.len(),
        "one_pass": one_pass_seconds,
        "one_pass_volume": volume(&one_pass.mesh),
    });
    // A chain that fails is reported, not fatal: the one pass and the leaves stand.
    let clock = Instant::now();
    match chain(&flat.expression, &flat.leaves, &options) {
        Ok(chained) => {
            report["chained"] = json!(clock.elapsed().as_secs_f64());
            report["chained_volume"] = json!(volume(&chained));
        }
        Err(error) => report["chain_error"] = json!(error.to_string()),
    }
    println!("{report}");
    Ok(())
}

/// The expression as binary booleans from the leaves up, each result rounded.
fn chain(
    expression: &Expression,
    leaves: &[Mesh],
    options: &BooleanOptions,
) -> Result<Mesh, Box<dyn std::error::Error>> {
    match expression {
        Expression::Operand(k) => Ok(leaves[*k].clone()),
        Expression::Apply(op, children) => {
            let mut values = children.iter().map(|c| chain(c, leaves, options));
            let Some(first) = values.next() else {
                return Ok(Mesh::new());
            };
            values.try_fold(first?, |acc, next| {
                Ok(boolean(*op, &[&acc, &next?], options)?.mesh)
            })
        }
    }
}

fn to_json(expression: &Expression) -> Value {
    match expression {
        Expression::Operand(k) => json!({"leaf": k}),
        Expression::Apply(op, children) => {
            let op = match op {
                Operation::Union => "union",
                Operation::Intersection => "intersection",
                Operation::Difference => "difference",
                Operation::Xor => "xor",
            };
            json!({"op": op, "children": children.iter().map(to_json).collect::<Vec<_>>()})
        }
    }
}
