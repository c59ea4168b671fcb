//! The operations: exact booleans through [`ExactEngine`], box unions through the orthogonal
//! engine, voxelization through [`DiscreteEngine`], and the built-in solids of
//! [`csgkit::primitives`].
//!
//! Options come as a plain object whose keys are read one by one, as the Python package reads
//! keyword arguments: an unknown key or a value of the wrong type is an `InputError` naming it.

use csgkit::exact::{BooleanOptions, WindingRule};
use csgkit::mesh::FaceMode;
use csgkit::ortho::{BoxFile, MeshOptions, box_union_mesh, read_box_file, with_palette_colors};
use csgkit::{
    DiscreteEngine, DiscreteSurface, Engine, ExactEngine, Operation, Precision, primitives,
};
use js_sys::{Array, Object};
use wasm_bindgen::prelude::*;

use crate::errors::{self, Result};
use crate::mesh::{Mesh, operands};
use crate::progress::with_progress;

/// The entries of an options object (none for `undefined`).
pub(crate) fn entries(options: Option<Object>) -> Vec<(String, JsValue)> {
    let Some(options) = options else {
        return Vec::new();
    };
    (Object::entries(&options).iter())
        .map(|entry| {
            let pair = Array::from(&entry);
            (pair.get(0).as_string().unwrap_or_default(), pair.get(1))
        })
        .collect()
}

/// A boolean option.
pub(crate) fn flag(key: &str, value: &JsValue) -> Result<bool> {
    (value.as_bool()).ok_or_else(|| errors::input(&format!("{key} must be true or false")))
}

/// A string option.
fn text(key: &str, value: &JsValue) -> Result<String> {
    (value.as_string()).ok_or_else(|| errors::input(&format!("{key} must be a string")))
}

/// A progress callback option (`null` and `undefined` for none).
pub(crate) fn callback(value: &JsValue) -> Result<Option<js_sys::Function>> {
    if value.is_null() || value.is_undefined() {
        return Ok(None);
    }
    (value.clone().dyn_into().map(Some))
        .map_err(|_| errors::input("progress must be a function (stage, done, total)"))
}

/// An unknown option.
pub(crate) fn unknown(key: &str) -> js_sys::Error {
    errors::input(&format!("unknown option '{key}'"))
}

/// The options of the exact booleans.
struct BooleanArgs {
    options: BooleanOptions,
    progress: Option<js_sys::Function>,
}

impl BooleanArgs {
    /// Reads `winding`, `faces`, `selfCheck`, `manifold`, `mergeCoplanar`, `simplify`,
    /// `precision` and `progress`.
    fn from_options(options: Option<Object>) -> Result<Self> {
        let mut args = BooleanArgs {
            options: BooleanOptions::default(),
            progress: None,
        };
        for (key, value) in entries(options) {
            let options = &mut args.options;
            match key.as_str() {
                "winding" => options.winding = winding(&text(&key, &value)?)?,
                "faces" => options.faces = face_mode(&text(&key, &value)?)?,
                "selfCheck" => options.check_self_intersections = flag(&key, &value)?,
                "manifold" => options.split_non_manifold = flag(&key, &value)?,
                "mergeCoplanar" => options.merge_coplanar = flag(&key, &value)?,
                "simplify" => options.simplify = simplify(&value)?,
                "precision" => options.precision = precision(&text(&key, &value)?)?,
                "progress" => args.progress = callback(&value)?,
                _ => return Err(unknown(&key)),
            }
        }
        Ok(args)
    }
}

/// The winding rule named `name`.
fn winding(name: &str) -> Result<WindingRule> {
    match name {
        "nonzero" => Ok(WindingRule::NonZero),
        "positive" => Ok(WindingRule::Positive),
        _ => Err(errors::input(&format!(
            "unknown winding rule '{name}': expected 'nonzero' or 'positive'"
        ))),
    }
}

/// The precision named `name`.
fn precision(name: &str) -> Result<Precision> {
    match name {
        "f64" => Ok(Precision::F64),
        "f32" => Ok(Precision::F32),
        _ => Err(errors::input(&format!(
            "unknown precision '{name}': expected 'f64' or 'f32'"
        ))),
    }
}

/// The face mode named `name`.
fn face_mode(name: &str) -> Result<FaceMode> {
    match name {
        "triangles" => Ok(FaceMode::Triangles),
        "polygons" => Ok(FaceMode::Polygons),
        "quads" => Ok(FaceMode::Quads),
        _ => Err(errors::input(&format!(
            "unknown face mode '{name}': expected 'triangles', 'polygons' or 'quads'"
        ))),
    }
}

/// A simplification tolerance: a positive length, or `null` / `undefined` for none.
fn simplify(value: &JsValue) -> Result<Option<f64>> {
    if value.is_null() || value.is_undefined() {
        return Ok(None);
    }
    match value.as_f64() {
        Some(t) if t.is_finite() && t > 0.0 => Ok(Some(t)),
        _ => Err(errors::input("simplify must be a positive length")),
    }
}

/// The operation named `name`.
fn operation(name: &str) -> Result<Operation> {
    (Operation::ALL.into_iter())
        .find(|op| op.name() == name)
        .ok_or_else(|| {
            errors::input(&format!(
                "unknown operation '{name}': expected 'union', 'intersection', 'difference' or 'xor'"
            ))
        })
}

/// Runs `op` on the meshes through the exact engine.
fn exact(op: Operation, meshes: &Array, options: Option<Object>) -> Result<Mesh> {
    let args = BooleanArgs::from_options(options)?;
    let meshes = operands(meshes)?;
    let engine = ExactEngine {
        options: args.options,
    };
    let output = with_progress(args.progress, |progress| {
        let operands: Vec<&csgkit::Mesh> = meshes.iter().map(Mesh::library).collect();
        engine.apply(op, &operands, progress)
    })?;
    Ok(Mesh::from_output(output))
}

/// The exact boolean `operation` ('union', 'intersection', 'difference' or 'xor') of
/// `meshes`, an array of any number of closed meshes, in one pass.
///
/// A difference is the first mesh minus all others; xor keeps the points in an odd number of
/// meshes. Every decision is exact on the float64 input, and the result is certified as
/// float64 numbers (float32 with `precision: 'f32'`): closed, consistently oriented, without
/// self-intersections. Its faces carry
/// the materials, colours and UVs of the input faces they were cut from.
///
/// Options, as the command line's: `winding` ('nonzero' or 'positive'), `faces`
/// ('triangles', 'polygons' or 'quads'), `selfCheck` (true), `manifold` (false),
/// `mergeCoplanar` (false), `simplify` (a length, or none), `precision` ('f64', or 'f32' for a
/// result saved as GLB or binary STL, which store float32), `progress` (a function of
/// (stage, done, total) that returns false to cancel). Throws `InputError` for an unknown
/// name or a mesh that is not closed (the message names the operand), `CancelledError`,
/// or `CsgkitError`.
#[wasm_bindgen]
pub fn boolean(operation: &str, meshes: &Array, options: Option<Object>) -> Result<Mesh> {
    exact(self::operation(operation)?, meshes, options)
}

/// The exact union of the meshes: `boolean('union', meshes, options)`.
#[wasm_bindgen]
pub fn union(meshes: &Array, options: Option<Object>) -> Result<Mesh> {
    exact(Operation::Union, meshes, options)
}

/// The exact intersection of the meshes: `boolean('intersection', meshes, options)`.
#[wasm_bindgen]
pub fn intersection(meshes: &Array, options: Option<Object>) -> Result<Mesh> {
    exact(Operation::Intersection, meshes, options)
}

/// The first mesh minus all the others, exactly: `boolean('difference', meshes, options)`.
#[wasm_bindgen]
pub fn difference(meshes: &Array, options: Option<Object>) -> Result<Mesh> {
    exact(Operation::Difference, meshes, options)
}

/// The points in an odd number of the meshes, exactly: `boolean('xor', meshes, options)`.
#[wasm_bindgen]
pub fn xor(meshes: &Array, options: Option<Object>) -> Result<Mesh> {
    exact(Operation::Xor, meshes, options)
}

/// The boxes of a `Float64Array` of `x0, y0, z0, x1, y1, z1` per box.
fn boxes_of_numbers(numbers: &[f64]) -> Result<BoxFile> {
    if numbers.len() % 6 != 0 {
        return Err(errors::input(&format!(
            "boxes holds {} numbers, not six per box",
            numbers.len()
        )));
    }
    let boxes = (numbers.chunks_exact(6))
        .map(|b| [b[0], b[1], b[2], b[3], b[4], b[5]])
        .collect();
    Ok(BoxFile {
        boxes,
        ..BoxFile::default()
    })
}

/// The exact union of axis-aligned boxes through the orthogonal engine, as a mesh of maximal
/// faces.
///
/// `input` is a `Float64Array` of `x0, y0, z0, x1, y1, z1` per box, or the bytes
/// (`Uint8Array`) of a MagicaVoxel `.vox` file (voxels become unit boxes; faces get the
/// material and colour of their voxels) or of a text file with one box per line. Options:
/// `triangles` (false: faces are polygons, those with holes triangulated), `manifold` (false:
/// split non-manifold edges and vertices; implies triangles), `model` (an index: one model of
/// a `.vox` file alone), `progress`.
#[wasm_bindgen]
pub fn boxes(input: &JsValue, options: Option<Object>) -> Result<Mesh> {
    let (mut mesh_options, mut model, mut progress) = (MeshOptions::default(), None, None);
    for (key, value) in entries(options) {
        match key.as_str() {
            "triangles" => mesh_options.triangles = flag(&key, &value)?,
            "manifold" => mesh_options.manifold = flag(&key, &value)?,
            "model" => {
                let index = value.as_f64().filter(|m| m.fract() == 0.0 && *m >= 0.0);
                let index = index.ok_or_else(|| errors::input("model must be an index"))?;
                model = Some(index as usize);
            }
            "progress" => progress = callback(&value)?,
            _ => return Err(unknown(&key)),
        }
    }
    mesh_options.triangles |= mesh_options.manifold;
    let input = if let Some(numbers) = input.dyn_ref::<js_sys::Float64Array>() {
        boxes_of_numbers(&numbers.to_vec())?
    } else if let Some(bytes) = input.dyn_ref::<js_sys::Uint8Array>() {
        read_box_file(&bytes.to_vec(), false, model).map_err(errors::from_library)?
    } else {
        return Err(errors::input(
            "boxes takes a Float64Array of boxes or the bytes (Uint8Array) of a .vox or box text file",
        ));
    };
    let (mesh, stage_seconds) = with_progress(progress, |progress| {
        let materials = input.materials.as_deref();
        let (out, stage_seconds) = box_union_mesh(&input.boxes, materials, mesh_options, progress)?;
        let mesh = match &input.palette {
            Some(palette) => with_palette_colors(out.mesh, palette),
            None => out.mesh,
        };
        Ok((mesh, stage_seconds))
    })?;
    Ok(Mesh::computed(mesh, stage_seconds))
}

/// The voxels of a closed mesh whose centres are inside it, on a grid of cell size `cell`
/// anchored at the origin, as a closed mesh, through the discrete engine (as `csgkit discrete
/// voxelize`). Options: `surface` ('ortho': maximal faces through the orthogonal engine;
/// 'surfels': the unit faces of the voxels, faster on very fine grids), `progress`.
#[wasm_bindgen]
pub fn voxelize(mesh: &Mesh, cell: f64, options: Option<Object>) -> Result<Mesh> {
    let mut engine = DiscreteEngine::with_cell(cell);
    let mut progress = None;
    for (key, value) in entries(options) {
        match key.as_str() {
            "surface" => {
                engine.surface = match text(&key, &value)?.as_str() {
                    "ortho" => DiscreteSurface::Ortho,
                    "surfels" => DiscreteSurface::Surfels,
                    surface => {
                        return Err(errors::input(&format!(
                            "unknown surface '{surface}': expected 'ortho' or 'surfels'"
                        )));
                    }
                }
            }
            "progress" => progress = callback(&value)?,
            _ => return Err(unknown(&key)),
        }
    }
    let output = with_progress(progress, |progress| {
        engine.apply(Operation::Union, &[mesh.library()], progress)
    })?;
    Ok(Mesh::from_output(output))
}

/// A point from three numbers.
fn point(name: &str, numbers: &[f64]) -> Result<[f64; 3]> {
    let point: [f64; 3] = (numbers.try_into())
        .map_err(|_| errors::input(&format!("{name} is 3 numbers, not {}", numbers.len())))?;
    match point.iter().all(|x| x.is_finite()) {
        true => Ok(point),
        false => Err(errors::input(&format!(
            "{name} has a non-finite coordinate"
        ))),
    }
}

/// `value` if it is finite and positive.
fn positive(name: &str, value: f64) -> Result<f64> {
    match value.is_finite() && value > 0.0 {
        true => Ok(value),
        false => Err(errors::input(&format!(
            "{name} must be positive, not {value}"
        ))),
    }
}

/// `value` if it is at least `least`.
fn at_least(name: &str, value: u32, least: u32) -> Result<u32> {
    match value >= least {
        true => Ok(value),
        false => Err(errors::input(&format!(
            "{name} must be at least {least}, not {value}"
        ))),
    }
}

/// The axis-aligned box from corner `min` to corner `max` (each 3 numbers, min < max).
#[wasm_bindgen]
pub fn cube(min: &[f64], max: &[f64]) -> Result<Mesh> {
    let (min, max) = (point("min", min)?, point("max", max)?);
    if (0..3).any(|k| min[k] >= max[k]) {
        return Err(errors::input("min must be below max on every axis"));
    }
    Ok(Mesh::from_mesh(primitives::cuboid(min, max)))
}

/// The most subdivisions of [`sphere`]: 20·4⁸ = 1,310,720 triangles, past which a page
/// asking for more has made a typo rather than a sphere.
const MAX_SUBDIVISIONS: u32 = 8;

/// A geodesic sphere: the icosahedron of `radius` around `centre`, each triangle split
/// `subdivisions` times in four (at most 8).
#[wasm_bindgen]
pub fn sphere(centre: &[f64], radius: f64, subdivisions: u32) -> Result<Mesh> {
    let centre = point("centre", centre)?;
    if subdivisions > MAX_SUBDIVISIONS {
        return Err(errors::input(&format!(
            "subdivisions must be at most {MAX_SUBDIVISIONS}, not {subdivisions}"
        )));
    }
    Ok(Mesh::from_mesh(primitives::icosphere(
        centre,
        positive("radius", radius)?,
        subdivisions,
    )))
}

/// A torus around the z axis through `centre`: `major` radius to the tube's centre, `minor`
/// radius of the tube (0 < minor < major), with `majorSegments` and `minorSegments` (each at
/// least 3).
#[wasm_bindgen]
pub fn torus(
    centre: &[f64],
    major: f64,
    minor: f64,
    #[wasm_bindgen(js_name = majorSegments)] major_segments: u32,
    #[wasm_bindgen(js_name = minorSegments)] minor_segments: u32,
) -> Result<Mesh> {
    let centre = point("centre", centre)?;
    let (major, minor) = (positive("major", major)?, positive("minor", minor)?);
    if minor >= major {
        return Err(errors::input("minor must be below major"));
    }
    Ok(Mesh::from_mesh(primitives::torus(
        centre,
        major,
        minor,
        at_least("majorSegments", major_segments, 3)?,
        at_least("minorSegments", minor_segments, 3)?,
    )))
}

/// A cylinder along z from `base`, of `radius` and `height`, its circle cut in `segments`
/// (at least 3).
#[wasm_bindgen]
pub fn cylinder(base: &[f64], radius: f64, height: f64, segments: u32) -> Result<Mesh> {
    Ok(Mesh::from_mesh(primitives::cylinder(
        point("base", base)?,
        positive("radius", radius)?,
        positive("height", height)?,
        at_least("segments", segments, 3)?,
    )))
}
