//! The JavaScript class `Mesh` and the conversions between typed arrays and [`csgkit::Mesh`].
//!
//! A `Mesh` is a shared handle: the library mesh sits behind an [`Rc`], so `clone()` costs
//! nothing and an operation that takes an array of meshes keeps the caller's objects usable
//! (wasm-bindgen hands a Rust object in an array over to Rust for good; [`operands`] passes it
//! a fresh handle instead). Arrays leave as copies (`Float64Array`, `Uint32Array`,
//! `Uint8Array`), which JavaScript owns and may change freely.
//!
//! A mesh made from arrays is checked here, where the message can name the vertex or face at
//! fault, as the Python package does.

use std::collections::HashSet;
use std::rc::Rc;

use csgkit::mesh::triangulate_faces;
use csgkit::{MeshParts, Output, Rgba, Stage};
use js_sys::{Array, Object, Reflect};
use wasm_bindgen::convert::TryFromJsValue;
use wasm_bindgen::prelude::*;

use crate::errors::{self, Result};

/// A polygon mesh with float64 vertices, as every csgkit operation takes and returns it.
///
/// Meshes read from files and results of operations also carry per-face materials, colours
/// and provenance, per-corner UVs and normals and per-vertex colours, when their source has
/// them.
#[wasm_bindgen]
#[derive(Clone)]
pub struct Mesh {
    mesh: Rc<csgkit::Mesh>,
    /// The seconds of every stage of the operation that made the mesh, if one did.
    stage_seconds: Option<Rc<[(Stage, f64)]>>,
}

#[wasm_bindgen]
impl Mesh {
    /// A mesh from flat arrays: `vertices` holds x, y, z of each vertex (every coordinate
    /// finite), `faces` the vertex indices of each face one after the other: three per face,
    /// or `faceSizes[f]` for face f when given. Throws `InputError` naming the vertex or face
    /// at fault.
    #[wasm_bindgen(constructor)]
    pub fn new(vertices: &[f64], faces: &[u32], face_sizes: Option<Vec<u32>>) -> Result<Mesh> {
        let positions = positions(vertices)?;
        let face_starts = face_sizes
            .map(|sizes| face_starts(&sizes, faces.len()))
            .transpose()?;
        let face_count = face_starts
            .as_ref()
            .map_or(faces.len() / 3, |s| s.len() - 1);
        if face_starts.is_none() && faces.len() % 3 != 0 {
            return Err(errors::input(&format!(
                "faces holds {} indices, not three per triangle (give faceSizes for polygons)",
                faces.len()
            )));
        }
        for (corner, &index) in faces.iter().enumerate() {
            if index as usize >= positions.len() {
                let face = match &face_starts {
                    Some(starts) => starts.partition_point(|&s| s as usize <= corner) - 1,
                    None => corner / 3,
                };
                return Err(errors::input(&format!(
                    "face {face} of {face_count} names vertex {index}, but there are {} vertices",
                    positions.len()
                )));
            }
        }
        let parts = MeshParts {
            positions,
            corners: faces.to_vec(),
            face_starts,
            ..MeshParts::default()
        };
        Ok(Mesh::from_mesh(
            csgkit::Mesh::from_parts(parts).map_err(errors::from_library)?,
        ))
    }

    /// Another handle to the same mesh; meshes never change, so the two stay equal.
    #[wasm_bindgen(js_name = clone)]
    pub fn handle(&self) -> Mesh {
        self.clone()
    }

    /// The number of vertices.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.mesh.vertex_count()
    }

    /// The number of faces.
    #[wasm_bindgen(getter, js_name = faceCount)]
    pub fn face_count(&self) -> usize {
        self.mesh.face_count()
    }

    /// The vertex positions, x, y, z of each vertex in order (a copy).
    pub fn vertices(&self) -> Vec<f64> {
        self.mesh.positions().as_flattened().to_vec()
    }

    /// The vertex indices of every face, face after face (a copy).
    pub fn corners(&self) -> Vec<u32> {
        self.mesh.corners().to_vec()
    }

    /// Where each face starts in `corners()`, then the number of corners; `undefined` for a
    /// triangle mesh.
    #[wasm_bindgen(js_name = faceStarts)]
    pub fn face_starts(&self) -> Option<Vec<u32>> {
        self.mesh.parts().face_starts.clone()
    }

    /// Per face, its index into `materialNames()`, or `undefined`.
    #[wasm_bindgen(js_name = faceMaterials)]
    pub fn face_materials(&self) -> Option<Vec<u32>> {
        self.mesh.face_materials().map(<[u32]>::to_vec)
    }

    /// The material names (OBJ `usemtl`, 3MF and glTF materials, voxel palette entries).
    #[wasm_bindgen(js_name = materialNames)]
    pub fn material_names(&self) -> Vec<String> {
        self.mesh.materials().to_vec()
    }

    /// Per face, its colour as r, g, b, a bytes, or `undefined`.
    #[wasm_bindgen(js_name = faceColors)]
    pub fn face_colors(&self) -> Option<Vec<u8>> {
        self.mesh.face_colors().map(|c| c.as_flattened().to_vec())
    }

    /// Per vertex, its colour as r, g, b, a bytes, or `undefined`.
    #[wasm_bindgen(js_name = vertexColors)]
    pub fn vertex_colors(&self) -> Option<Vec<u8>> {
        self.mesh.vertex_colors().map(|c| c.as_flattened().to_vec())
    }

    /// The seconds of each stage of the operation that made this mesh (`{ingest: …,
    /// intersect: …}` in the order they ran), or `undefined` for a mesh no operation made.
    #[wasm_bindgen(js_name = stageSeconds)]
    pub fn stage_seconds(&self) -> Option<Object> {
        let stages = self.stage_seconds.as_ref()?;
        let seconds = Object::new();
        for (stage, time) in stages.iter() {
            let name = JsValue::from_str(&stage.to_string());
            let before = Reflect::get(&seconds, &name).ok().and_then(|t| t.as_f64());
            let total = before.unwrap_or(0.0) + time;
            Reflect::set(&seconds, &name, &total.into()).expect("setting a key of a new object");
        }
        Some(seconds)
    }

    /// This mesh with every face of material `name` and colour `color` (r, g, b, a bytes), as
    /// a file's material would give it.
    #[wasm_bindgen(js_name = withMaterial)]
    pub fn with_material(&self, name: &str, color: &[u8]) -> Result<Mesh> {
        let color: Rgba = color.try_into().map_err(|_| {
            errors::input(&format!(
                "a colour is 4 bytes (r, g, b, a), not {}",
                color.len()
            ))
        })?;
        let faces = self.mesh.face_count();
        let parts = MeshParts {
            face_materials: Some(vec![0; faces]),
            materials: vec![name.to_owned()],
            face_colors: Some(vec![color; faces]),
            ..self.mesh.parts().clone()
        };
        Ok(Mesh::from_mesh(
            csgkit::Mesh::from_parts(parts).map_err(errors::from_library)?,
        ))
    }

    /// The triangles a viewer draws: `{corners, faces, edges}`, where `corners` holds three
    /// vertex indices per triangle (every face triangulated exactly, without new vertices),
    /// `faces` the face of each triangle, and `edges` two vertex indices per polygon edge,
    /// each edge once (the diagonals inside polygons left out). Throws `InputError` for a
    /// polygon whose projection overlaps itself.
    pub fn triangulate(&self) -> Result<Object> {
        let triangulation = triangulate_faces(&self.mesh).map_err(errors::from_library)?;
        let mut corners = Vec::with_capacity(3 * triangulation.len());
        let mut faces = Vec::with_capacity(triangulation.len());
        let mut edges = Vec::new();
        let mut seen = HashSet::new();
        for t in 0..triangulation.len() {
            let triangle = triangulation.triangle(t);
            corners.extend_from_slice(&triangle);
            faces.push(triangulation.face(t).get() as u32);
            let mask = triangulation.edge_mask(t);
            for side in (0..3).filter(|i| mask & (1 << i) != 0) {
                let (a, b) = (triangle[side], triangle[(side + 1) % 3]);
                if seen.insert((a.min(b), a.max(b))) {
                    edges.extend_from_slice(&[a, b]);
                }
            }
        }
        let result = Object::new();
        for (key, value) in [
            ("corners", js_sys::Uint32Array::from(&corners[..])),
            ("faces", js_sys::Uint32Array::from(&faces[..])),
            ("edges", js_sys::Uint32Array::from(&edges[..])),
        ] {
            Reflect::set(&result, &key.into(), &value).expect("setting a key of a new object");
        }
        Ok(result)
    }
}

impl Mesh {
    /// A handle to `mesh`, which no operation made.
    pub(crate) fn from_mesh(mesh: csgkit::Mesh) -> Mesh {
        Mesh {
            mesh: Rc::new(mesh),
            stage_seconds: None,
        }
    }

    /// A handle to `mesh`, made by an operation that took `stage_seconds`.
    pub(crate) fn computed(mesh: csgkit::Mesh, stage_seconds: Vec<(Stage, f64)>) -> Mesh {
        Mesh {
            mesh: Rc::new(mesh),
            stage_seconds: Some(stage_seconds.into()),
        }
    }

    /// An engine's output, with its stage seconds.
    pub(crate) fn from_output(output: Output) -> Mesh {
        let stage_seconds = output.stats.stage_seconds().to_vec();
        Mesh::computed(output.mesh, stage_seconds)
    }

    /// The library mesh.
    pub(crate) fn library(&self) -> &csgkit::Mesh {
        &self.mesh
    }
}

/// The meshes of a JavaScript array, each a `Mesh`, as handles; the caller's objects stay
/// theirs. Throws `InputError` naming the first element that is not a `Mesh`.
pub(crate) fn operands(meshes: &Array) -> Result<Vec<Mesh>> {
    let not_a_mesh = |i: u32| errors::input(&format!("meshes[{i}] is not a csgkit Mesh"));
    (0..meshes.length())
        .map(|i| {
            let element = meshes.get(i);
            // `clone()` is looked up as a JavaScript method, so any object that is not a Mesh
            // (or has no such method) is refused below by wasm-bindgen's instance check.
            let handle = (Reflect::get(&element, &"clone".into()).ok())
                .and_then(|clone| clone.dyn_into::<js_sys::Function>().ok())
                .and_then(|clone| clone.call0(&element).ok())
                .ok_or_else(|| not_a_mesh(i))?;
            Mesh::try_from_js_value(handle).map_err(|_| not_a_mesh(i))
        })
        .collect()
}

/// The positions of a flat array of x, y, z, every coordinate finite.
fn positions(vertices: &[f64]) -> Result<Vec<[f64; 3]>> {
    if vertices.len() % 3 != 0 {
        return Err(errors::input(&format!(
            "vertices holds {} numbers, not three per vertex",
            vertices.len()
        )));
    }
    if let Some(i) = vertices.iter().position(|x| !x.is_finite()) {
        return Err(errors::input(&format!(
            "vertex {} has a non-finite coordinate {}",
            i / 3,
            vertices[i]
        )));
    }
    Ok(vertices
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect())
}

/// The face starts of faces of `sizes` corners each, which must add up to `corner_count`.
fn face_starts(sizes: &[u32], corner_count: usize) -> Result<Vec<u32>> {
    let mut starts = Vec::with_capacity(sizes.len() + 1);
    starts.push(0u32);
    let mut total = 0usize;
    for (face, &size) in sizes.iter().enumerate() {
        if size < 3 {
            return Err(errors::input(&format!(
                "face {face} has {size} corners; a face has at least 3"
            )));
        }
        total += size as usize;
        starts.push(u32::try_from(total).map_err(|_| errors::input("too many corners"))?);
    }
    if total != corner_count {
        return Err(errors::input(&format!(
            "faceSizes add up to {total} corners, but faces holds {corner_count}"
        )));
    }
    Ok(starts)
}
