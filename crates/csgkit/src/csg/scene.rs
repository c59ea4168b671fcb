//! The JSON scene format: a CSG tree in a file, read into a [`Node`].
//!
//! A node is an object with exactly one of these keys, and optionally `"transform"` and
//! `"material"`:
//! - `"union"`, `"intersection"`, `"difference"`: an array of child nodes (a difference is
//!   the first minus the others);
//! - `"hull"`: an array of child nodes made of leaves and unions only: the exact convex hull
//!   of their placed points ([`convex_hull`]; empty where they lie in one plane);
//! - `"mesh"`: the path of a mesh file (any format csgkit reads);
//! - `"cube"`: `{"size": [x, y, z] | s, "center": bool}` (from the origin, or centred on it);
//! - `"sphere"`: `{"r": R, "segments": N}`, OpenSCAD's tessellation with N fragments
//!   ([`uv_sphere`]);
//! - `"cylinder"`: `{"r": R, "h": H, "segments": N, "center": bool}` along +z;
//! - `"boxes"`: the path of a MagicaVoxel `.vox` model (its palette becomes materials) or a
//!   box text file (`x0 y0 z0 x1 y1 z1` per line), through the orthogonal engine.
//!
//! `"transform"` is 3 × 4, row-major: `[[m00, m01, m02, t0], [m10, m11, m12, t1], [m20, m21,
//! m22, t2]]`, `x' = M·x + t`; `"material"` names the material of every face below that names
//! none closer. Relative paths are relative to the scene file. Every error names the JSON
//! path of the node at fault, as `/union/1/cube/size`.
//!
//! # Example
//! ```json
//! {"difference": [
//!   {"cube": {"size": 2, "center": true}, "material": "stone"},
//!   {"cylinder": {"r": 0.5, "h": 3, "segments": 32, "center": true},
//!    "transform": [[1, 0, 0, 0.2], [0, 1, 0, 0], [0, 0, 1, 0]]}
//! ]}
//! ```

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::tree::{Node, NodeKind};
use crate::Operation;
use crate::io::{ReadError, read_mesh};
use crate::mesh::Affine;
use crate::mesh::{Mesh, convex_hull};
use crate::ortho::{MeshOptions, box_union, box_union_with_materials, read_box_file};
use crate::primitives::{cuboid, cylinder, uv_sphere};

/// Why a scene could not be read. Every variant names the file or the JSON path at fault.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not JSON.
    #[error("{path}: not JSON: {message}")]
    Json {
        /// The file.
        path: PathBuf,
        /// What the parser said, with its line and column.
        message: String,
    },
    /// A node is not what the format allows.
    #[error("{at}: {message}")]
    Node {
        /// The JSON path of the node, as `/union/1/cube`.
        at: String,
        /// What is wrong.
        message: String,
    },
    /// A mesh file a node names could not be read.
    #[error("{at}: {source}")]
    Mesh {
        /// The JSON path of the node.
        at: String,
        /// The reader's error, naming the file.
        source: ReadError,
    },
}

/// Reads the scene in the file at `path`.
///
/// # Errors
/// [`SceneError`] naming the file, or the JSON path of the node at fault.
pub fn read_scene(path: &Path) -> Result<Node, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        path: path.to_owned(),
        source,
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    parse_scene(&text, path, base)
}

/// Parses `text` as a scene from `path`, resolving relative paths against `base`.
///
/// # Errors
/// As [`read_scene`].
pub fn parse_scene(text: &str, path: &Path, base: &Path) -> Result<Node, SceneError> {
    let value: Value = serde_json::from_str(text).map_err(|e| SceneError::Json {
        path: path.to_owned(),
        message: e.to_string(),
    })?;
    node(&value, "", base)
}

fn bad(at: &str, message: impl Into<String>) -> SceneError {
    SceneError::Node {
        at: if at.is_empty() {
            "/".to_owned()
        } else {
            at.to_owned()
        },
        message: message.into(),
    }
}

const KINDS: [&str; 9] = [
    "union",
    "intersection",
    "difference",
    "hull",
    "mesh",
    "cube",
    "sphere",
    "cylinder",
    "boxes",
];

fn node(value: &Value, at: &str, base: &Path) -> Result<Node, SceneError> {
    let Some(object) = value.as_object() else {
        return Err(bad(at, "a node must be an object"));
    };
    if let Some(key) = (object.keys())
        .find(|k| !KINDS.contains(&k.as_str()) && *k != "transform" && *k != "material")
    {
        return Err(bad(
            at,
            format!(
                "unknown key {key:?} (a node is one of {})",
                KINDS.join(", ")
            ),
        ));
    }
    let kinds: Vec<&str> = KINDS
        .into_iter()
        .filter(|k| object.contains_key(*k))
        .collect();
    let [kind] = kinds[..] else {
        return Err(bad(
            at,
            format!(
                "a node has exactly one of {}, not {kinds:?}",
                KINDS.join(", ")
            ),
        ));
    };
    let here = format!("{at}/{kind}");
    let body = &object[kind];
    let kind = match kind {
        "union" | "intersection" | "difference" => {
            let op = match kind {
                "union" => Operation::Union,
                "intersection" => Operation::Intersection,
                _ => Operation::Difference,
            };
            NodeKind::Apply(op, child_nodes(body, &here, base, "an operation")?)
        }
        "hull" => {
            let children = child_nodes(body, &here, base, "a hull")?;
            let mut points = Vec::new();
            if !Node::apply(Operation::Union, children).union_points(&mut points) {
                return Err(bad(
                    &here,
                    "a hull takes leaves and unions of them, not intersections or differences",
                ));
            }
            NodeKind::Mesh {
                mesh: Box::new(convex_hull(&points)),
                name: here.clone(),
            }
        }
        "mesh" => {
            let path = base.join(string(body, &here)?);
            let mesh = read_mesh(&path)
                .map_err(|source| SceneError::Mesh {
                    at: here.clone(),
                    source,
                })?
                .mesh;
            NodeKind::Mesh {
                mesh: Box::new(mesh),
                name: format!("{here} ({})", path.display()),
            }
        }
        "boxes" => {
            let path = base.join(string(body, &here)?);
            NodeKind::Mesh {
                mesh: Box::new(boxes(&path, &here)?),
                name: format!("{here} ({})", path.display()),
            }
        }
        primitive => NodeKind::Mesh {
            mesh: Box::new(primitive_mesh(primitive, body, &here)?),
            name: here.clone(),
        },
    };
    let transform = match object.get("transform") {
        Some(t) => Some(affine(t, &format!("{at}/transform"))?),
        None => None,
    };
    let material = match object.get("material") {
        Some(m) => Some(string(m, &format!("{at}/material"))?.to_owned()),
        None => None,
    };
    Ok(Node {
        kind,
        transform,
        material,
    })
}

/// The nodes of the array `body` at `here`, the children of `what` (an operation or a hull).
fn child_nodes(body: &Value, here: &str, base: &Path, what: &str) -> Result<Vec<Node>, SceneError> {
    let Some(children) = body.as_array() else {
        return Err(bad(here, format!("{what} takes an array of nodes")));
    };
    (children.iter().enumerate())
        .map(|(i, child)| node(child, &format!("{here}/{i}"), base))
        .collect()
}

fn string<'a>(value: &'a Value, at: &str) -> Result<&'a str, SceneError> {
    value.as_str().ok_or_else(|| bad(at, "expected a string"))
}

fn number(object: &Value, key: &str, at: &str) -> Result<f64, SceneError> {
    let here = format!("{at}/{key}");
    let value = object
        .get(key)
        .ok_or_else(|| bad(at, format!("{key} is missing")))?;
    value
        .as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| bad(&here, "expected a finite number"))
}

fn positive(object: &Value, key: &str, at: &str) -> Result<f64, SceneError> {
    let x = number(object, key, at)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(bad(
            &format!("{at}/{key}"),
            format!("must be positive, not {x}"),
        ))
    }
}

fn segments(object: &Value, at: &str) -> Result<u32, SceneError> {
    let here = format!("{at}/segments");
    let value = object
        .get("segments")
        .ok_or_else(|| bad(at, "segments is missing"))?;
    (value.as_u64())
        .filter(|n| (3..=1 << 20).contains(n))
        .map(|n| n as u32)
        .ok_or_else(|| bad(&here, "expected a whole number from 3 to 2^20"))
}

fn centred(object: &Value, at: &str) -> Result<bool, SceneError> {
    match object.get("center") {
        None => Ok(false),
        Some(v) => v
            .as_bool()
            .ok_or_else(|| bad(&format!("{at}/center"), "expected true or false")),
    }
}

fn primitive_mesh(kind: &str, body: &Value, at: &str) -> Result<Mesh, SceneError> {
    if !body.is_object() {
        return Err(bad(at, "expected an object of parameters"));
    }
    match kind {
        "cube" => {
            let here = format!("{at}/size");
            let size = match body.get("size") {
                Some(Value::Array(xs)) if xs.len() == 3 => {
                    let mut s = [0.0; 3];
                    for (k, x) in xs.iter().enumerate() {
                        s[k] = x
                            .as_f64()
                            .filter(|x| *x > 0.0 && x.is_finite())
                            .ok_or_else(|| {
                                bad(&format!("{here}/{k}"), "expected a positive number")
                            })?;
                    }
                    s
                }
                Some(_) => [positive(body, "size", at)?; 3],
                None => return Err(bad(at, "size is missing")),
            };
            let min = if centred(body, at)? {
                size.map(|s| -s / 2.0)
            } else {
                [0.0; 3]
            };
            Ok(cuboid(min, [0, 1, 2].map(|k| min[k] + size[k])))
        }
        "sphere" => Ok(uv_sphere(
            [0.0; 3],
            positive(body, "r", at)?,
            segments(body, at)?,
        )),
        _ => {
            let (r, h) = (positive(body, "r", at)?, positive(body, "h", at)?);
            let z = if centred(body, at)? { -h / 2.0 } else { 0.0 };
            Ok(cylinder([0.0, 0.0, z], r, h, segments(body, at)?))
        }
    }
}

/// The mesh of a `.vox` model (palette indices as materials) or a box text file.
fn boxes(path: &Path, at: &str) -> Result<Mesh, SceneError> {
    let bytes =
        std::fs::read(path).map_err(|e| bad(at, format!("cannot read {}: {e}", path.display())))?;
    let vox = (path.extension()).is_some_and(|e| e.eq_ignore_ascii_case("vox"));
    let in_file = |e: &dyn std::fmt::Display| bad(at, format!("{}: {e}", path.display()));
    let file = read_box_file(&bytes, vox, None).map_err(|e| in_file(&e))?;
    let brep = match &file.materials {
        Some(materials) => box_union_with_materials(&file.boxes, materials),
        None => box_union(&file.boxes),
    };
    let brep = brep.map_err(|e| in_file(&e))?;
    let mesh = brep
        .to_mesh(MeshOptions::default())
        .map_err(|e| in_file(&e))?;
    Ok(mesh.mesh)
}

fn affine(value: &Value, at: &str) -> Result<Affine, SceneError> {
    let rows = value
        .as_array()
        .filter(|r| r.len() == 3)
        .ok_or_else(|| bad(at, "a transform is 3 rows of 4 numbers"))?;
    let mut out = [[0.0; 4]; 3];
    for (i, row) in rows.iter().enumerate() {
        let row = row
            .as_array()
            .filter(|r| r.len() == 4)
            .ok_or_else(|| bad(&format!("{at}/{i}"), "a row is 4 numbers"))?;
        for (j, x) in row.iter().enumerate() {
            out[i][j] = x
                .as_f64()
                .filter(|x| x.is_finite())
                .ok_or_else(|| bad(&format!("{at}/{i}/{j}"), "expected a finite number"))?;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Node, SceneError> {
        parse_scene(text, Path::new("scene.json"), Path::new("."))
    }

    #[test]
    fn errors_name_the_json_path_of_the_node() {
        let cases = [
            (
                r#"{"union": [{"cube": {"size": [1, 0, 1]}}]}"#,
                "/union/0/cube/size/1: expected a positive number",
            ),
            (
                r#"{"union": [{"cube": {"size": 1}}, {"sphere": {"r": 1}}]}"#,
                "/union/1/sphere: segments is missing",
            ),
            (
                r#"{"difference": [{"cube": {"size": 1}, "transform": [[1, 0, 0]]}]}"#,
                "/difference/0/transform: a transform is 3 rows of 4 numbers",
            ),
            (
                r#"{"cube": {"size": 1}, "sphere": {"r": 1}}"#,
                "/: a node has exactly one of union, intersection, difference, hull, mesh, cube, sphere, cylinder, boxes, not [\"cube\", \"sphere\"]",
            ),
            (
                r#"{"minkowski": []}"#,
                "/: unknown key \"minkowski\" (a node is one of union, intersection, difference, hull, mesh, cube, sphere, cylinder, boxes)",
            ),
            (
                r#"{"hull": [{"difference": [{"cube": {"size": 2}}, {"cube": {"size": 1}}]}]}"#,
                "/hull: a hull takes leaves and unions of them, not intersections or differences",
            ),
            (
                r#"{"union": [{"hull": {"cube": {"size": 1}}}]}"#,
                "/union/0/hull: a hull takes an array of nodes",
            ),
        ];
        for (text, message) in cases {
            assert_eq!(parse(text).unwrap_err().to_string(), message, "{text}");
        }
    }

    #[test]
    fn a_scene_reads_into_a_tree_with_transforms_and_materials() {
        let node = parse(
            r#"{"difference": [
                {"cube": {"size": 2, "center": true}, "material": "stone"},
                {"cylinder": {"r": 0.5, "h": 3, "segments": 32, "center": true},
                 "transform": [[1, 0, 0, 0.2], [0, 1, 0, 0], [0, 0, 1, 0]]}]}"#,
        )
        .unwrap();
        let NodeKind::Apply(Operation::Difference, children) = &node.kind else {
            panic!("{node:?}")
        };
        assert_eq!(children[0].material.as_deref(), Some("stone"));
        assert_eq!(children[1].transform.unwrap()[0][3], 0.2);
    }

    #[test]
    fn a_hull_is_the_exact_convex_hull_of_its_placed_leaves() {
        // Two unit cubes a diagonal apart, one placed by a transform, inside a union: the hull
        // adds the prism between them, and its own transform and material apply to it.
        let node = parse(
            r#"{"hull": [
                {"cube": {"size": 1}},
                {"union": [{"cube": {"size": 1},
                            "transform": [[1, 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0]]}]}],
                "transform": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]], "material": "glass"}"#,
        )
        .unwrap();
        assert_eq!(node.material.as_deref(), Some("glass"));
        let out = super::super::evaluate(
            &node,
            &crate::exact::BooleanOptions::default(),
            &crate::Progress::default(),
        )
        .unwrap();
        let report = out.result.mesh.report();
        assert!(report.is_valid_solid(), "{report:?}");
        assert_eq!(report.measures.volume, 2.0 * 3.0);
        assert_eq!(out.result.mesh.materials(), ["glass"]);
        // A leaf of a hull that cannot be read is named by its JSON path.
        let missing = parse(r#"{"hull": [{"mesh": "none.obj"}]}"#);
        assert!(
            missing
                .unwrap_err()
                .to_string()
                .starts_with("/hull/0/mesh: ")
        );
    }
}
