//! Files as bytes: `load` and `loadParts` through the library's [`read_meshes_from_bytes`]
//! (the format follows the file name's extension and the content, so a format the library
//! learns is read here without a change), `save` through [`write_mesh_to_bytes`], and
//! `check`, the report of `csgkit check --json`.

use std::path::{Path, PathBuf};

use csgkit::mesh::analyze;
use csgkit::{
    Encoding, Format, LoadedMeshes, ReadError, no_external_files, read_meshes_from_bytes,
    write_mesh_to_bytes,
};
use js_sys::{Array, Object, Reflect};
use serde::Serialize;
use wasm_bindgen::prelude::*;

use crate::errors::{self, Result};
use crate::mesh::Mesh;
use crate::operations::{entries, flag, unknown};

/// Reads the parts of a file; errors name the file as the command line's do.
fn read(bytes: &[u8], name: &str) -> Result<LoadedMeshes> {
    let hint = Format::from_extension(Path::new(name));
    read_meshes_from_bytes(bytes, hint, &no_external_files).map_err(|error| match error {
        ReadError::Parse { path: None, error } => errors::from_library(ReadError::Parse {
            path: Some(PathBuf::from(name)),
            error,
        }),
        error => errors::from_library(error),
    })
}

/// Reads a mesh file from its bytes, in any format the library reads (OBJ, STL, PLY, OFF,
/// 3MF, glTF as `.gltf` with embedded buffers or `.glb`), chosen by the extension of `name`,
/// or by the content where it says otherwise; the parts of a file that holds several (3MF
/// build items, glTF nodes) become one mesh. Throws `ReadError` naming the file and the line
/// or byte at fault.
#[wasm_bindgen]
pub fn load(bytes: &[u8], name: &str) -> Result<Mesh> {
    let merged = read(bytes, name)?.merge().map_err(|error| {
        errors::from_library(ReadError::Parse {
            path: Some(PathBuf::from(name)),
            error,
        })
    })?;
    Ok(Mesh::from_mesh(merged.mesh))
}

/// The parts of a mesh file, each a mesh in its place (3MF build items, glTF nodes with a
/// mesh; one part for the other formats): the operands `csgkit union` takes from one file.
#[wasm_bindgen(js_name = loadParts)]
pub fn load_parts(bytes: &[u8], name: &str) -> Result<Vec<Mesh>> {
    let loaded = read(bytes, name)?;
    Ok((loaded.parts.into_iter())
        .map(|part| Mesh::from_mesh(part.mesh))
        .collect())
}

/// The bytes of `mesh` in the format the extension of `name` names (`.glb`, `.gltf`, `.3mf`,
/// `.obj`, `.ply`, `.stl`, `.off`); STL and PLY are binary. PLY keeps each face's provenance;
/// glTF and binary STL store float32, so coordinates are rounded. Throws `InputError` for an
/// unknown extension, `WriteError` for a mesh the format cannot hold.
#[wasm_bindgen]
pub fn save(mesh: &Mesh, name: &str) -> Result<Vec<u8>> {
    let format = Format::from_extension(Path::new(name)).ok_or_else(|| {
        errors::input(&format!(
            "{name}: unknown extension (expected .glb, .gltf, .3mf, .obj, .ply, .stl or .off)"
        ))
    })?;
    write_mesh_to_bytes(mesh.library(), format, Encoding::Binary).map_err(errors::from_library)
}

/// Every validity check and measure of a mesh, as `csgkit check --json` reports them: an
/// object with `vertices`, `faces`, `closed`, `oriented`, `valid_solid` (closed and
/// consistently oriented), `edge_manifold`, `components`, `genus`, `volume`, `area`, `bbox`,
/// … and, from the exact self-intersection check, `selfint_pairs`, `selfint_faces` and
/// `invalid_polygons` (each polygon whose projection overlaps itself, as `face` and
/// `problem`). Option `selfIntersections` (true): false skips the exact check, which costs
/// about as much as a boolean, and leaves its keys out.
#[wasm_bindgen]
pub fn check(mesh: &Mesh, options: Option<Object>) -> Result<JsValue> {
    let mut self_intersections = true;
    for (key, value) in entries(options) {
        match key.as_str() {
            "selfIntersections" => self_intersections = flag(&key, &value)?,
            _ => return Err(unknown(&key)),
        }
    }
    let mesh = mesh.library();
    let serializer = serde_wasm_bindgen::Serializer::json_compatible();
    let report = (analyze(mesh).serialize(&serializer))
        .map_err(|error| errors::input(&error.to_string()))?;
    if self_intersections {
        let crossings = csgkit::self_intersections(mesh);
        let invalid = Array::new();
        for error in &crossings.invalid_polygons {
            let polygon = Object::new();
            set(&polygon, "face", error.face().get().into());
            set(&polygon, "problem", error.to_string().into());
            invalid.push(&polygon);
        }
        set(
            &report,
            "selfint_pairs",
            (crossings.pair_count() as f64).into(),
        );
        set(
            &report,
            "selfint_faces",
            (crossings.face_count() as f64).into(),
        );
        set(&report, "invalid_polygons", invalid.into());
    }
    Ok(report)
}

/// Sets `key` of a report object.
fn set(object: &JsValue, key: &str, value: JsValue) {
    Reflect::set(object, &key.into(), &value).expect("setting a key of a plain object");
}
