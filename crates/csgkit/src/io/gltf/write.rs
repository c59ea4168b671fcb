//! The glTF writer: one mesh of one primitive per (material, colour), as the module docs say.

use base64::Engine as _;
use rustc_hash::FxHashMap;
use serde_json::{Value, json};

use super::super::Format;
use super::super::error::WriteError;
use super::{BIN_CHUNK, GLB_MAGIC, JSON_CHUNK};
use crate::mesh::{FaceId, Mesh, Rgba, Triangulation, triangulate_faces};

/// glTF's codes for component types, buffer view targets and the TRIANGLES mode.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const TRIANGLES: u32 = 4;

/// Appends `mesh` as a `.glb` or a `.gltf` (buffer embedded as base64) to `out`.
pub(crate) fn write(mesh: &Mesh, format: Format, out: &mut Vec<u8>) -> Result<(), WriteError> {
    let triangles =
        triangulate_faces(mesh).map_err(|error| WriteError::InvalidPolygon { format, error })?;
    if (mesh.positions().iter().flatten()).any(|&c| !(c as f32).is_finite()) {
        return Err(WriteError::TooLarge {
            format,
            reason: "a coordinate is beyond the f32 range of glTF, or not finite",
        });
    }
    let table = VertexTable::new(mesh, &triangles);
    let primitives = Primitives::new(mesh, &triangles, &table);
    let mut document = Document::default();
    if !primitives.indices.is_empty() {
        document.mesh(mesh, &table, &primitives);
    }
    let json = document.json(format);
    let mut text = serde_json::to_vec(&json).expect("a JSON value serialises");
    match format {
        Format::Glb => {
            // Chunks are padded to 4 bytes: JSON with spaces, the binary chunk with zeros.
            text.resize(text.len().next_multiple_of(4), b' ');
            let mut bin = document.bin;
            bin.resize(bin.len().next_multiple_of(4), 0);
            let bin_chunk = if bin.is_empty() { 0 } else { 8 + bin.len() };
            let total = 12 + 8 + text.len() + bin_chunk;
            let total = u32::try_from(total).map_err(|_| WriteError::TooLarge {
                format,
                reason: "a GLB file holds at most 4 GiB",
            })?;
            out.extend_from_slice(GLB_MAGIC);
            out.extend_from_slice(&2u32.to_le_bytes());
            out.extend_from_slice(&total.to_le_bytes());
            out.extend_from_slice(&(text.len() as u32).to_le_bytes());
            out.extend_from_slice(&JSON_CHUNK.to_le_bytes());
            out.extend_from_slice(&text);
            if !bin.is_empty() {
                out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
                out.extend_from_slice(&BIN_CHUNK.to_le_bytes());
                out.extend_from_slice(&bin);
            }
        }
        _ => out.extend_from_slice(&text),
    }
    Ok(())
}

/// The written vertices: the mesh's, or one per distinct (vertex, UV, normal) of the corners
/// when the mesh has corner attributes.
struct VertexTable {
    /// The mesh vertex of each written vertex.
    vertices: Vec<u32>,
    uvs: Option<Vec<[f64; 2]>>,
    normals: Option<Vec<[f32; 3]>>,
    /// The written vertex of each triangle corner, triangle after triangle.
    corners: Vec<u32>,
}

impl VertexTable {
    fn new(mesh: &Mesh, triangles: &Triangulation<'_>) -> VertexTable {
        let (uvs, normals) = (mesh.corner_uvs(), mesh.corner_normals());
        if uvs.is_none() && normals.is_none() {
            return VertexTable {
                vertices: (0..mesh.vertex_count() as u32).collect(),
                uvs: None,
                normals: None,
                corners: triangles.iter().flat_map(|(_, t)| t).collect(),
            };
        }
        let mut table = VertexTable {
            vertices: Vec::new(),
            uvs: uvs.map(|_| Vec::new()),
            normals: normals.map(|_| Vec::new()),
            corners: Vec::with_capacity(3 * triangles.len()),
        };
        let mut index: FxHashMap<(u32, [u64; 2], [u32; 3]), u32> = FxHashMap::default();
        for (face, t) in triangles.iter() {
            let range = mesh.face_range(face);
            for v in t {
                // The face's corner at `v` (its first, should the face repeat the vertex).
                let corner = (range.clone())
                    .find(|&c| mesh.corners()[c] == v)
                    .expect("a triangle of a face uses its corners");
                let uv = uvs.map_or([0.0; 2], |uvs| uvs[corner]);
                let normal = normals.map_or([0.0; 3], |normals| normals[corner]);
                let key = (v, uv.map(f64::to_bits), normal.map(f32::to_bits));
                let k = *index.entry(key).or_insert_with(|| {
                    table.vertices.push(v);
                    if let Some(uvs) = table.uvs.as_mut() {
                        uvs.push(uv);
                    }
                    if let Some(normals) = table.normals.as_mut() {
                        normals.push(normal);
                    }
                    table.vertices.len() as u32 - 1
                });
                table.corners.push(k);
            }
        }
        table.in_vertex_order();
        table
    }

    /// Renumbers the written vertices in the order of the mesh vertices they copy (stably),
    /// so reading back welds them into the mesh's own vertex order.
    fn in_vertex_order(&mut self) {
        let mut order: Vec<u32> = (0..self.vertices.len() as u32).collect();
        order.sort_by_key(|&k| self.vertices[k as usize]);
        let mut new_index = vec![0u32; order.len()];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        for corner in &mut self.corners {
            *corner = new_index[*corner as usize];
        }
        self.vertices = order.iter().map(|&k| self.vertices[k as usize]).collect();
        if let Some(uvs) = self.uvs.as_mut() {
            *uvs = order.iter().map(|&k| uvs[k as usize]).collect();
        }
        if let Some(normals) = self.normals.as_mut() {
            *normals = order.iter().map(|&k| normals[k as usize]).collect();
        }
    }
}

/// The faces grouped by (material, colour), in order of first use.
struct Primitives {
    /// Each primitive's key: material id and colour, as the mesh has them.
    keys: Vec<(Option<u32>, Option<Rgba>)>,
    /// Each primitive's written vertex indices, three per triangle.
    indices: Vec<Vec<u32>>,
}

impl Primitives {
    fn new(mesh: &Mesh, triangles: &Triangulation<'_>, table: &VertexTable) -> Primitives {
        let key_of = |face: FaceId| {
            (
                mesh.face_materials().map(|m| m[face.index()]),
                mesh.face_colors().map(|c| c[face.index()]),
            )
        };
        let mut primitives = Primitives {
            keys: Vec::new(),
            indices: Vec::new(),
        };
        let mut index: FxHashMap<(Option<u32>, Option<Rgba>), usize> = FxHashMap::default();
        for (t, (face, _)) in triangles.iter().enumerate() {
            let key = key_of(face);
            let k = *index.entry(key).or_insert_with(|| {
                primitives.keys.push(key);
                primitives.indices.push(Vec::new());
                primitives.keys.len() - 1
            });
            primitives.indices[k].extend_from_slice(&table.corners[3 * t..3 * t + 3]);
        }
        primitives
    }
}

/// The JSON arrays under construction and the binary buffer they describe.
#[derive(Default)]
struct Document {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    materials: Vec<Value>,
    primitives: Vec<Value>,
}

impl Document {
    /// Appends `bytes` as a buffer view with `target`; returns the accessor index it gets
    /// with `count` elements of `kind`, extended by `extra` (min, max).
    fn accessor(
        &mut self,
        bytes: &[u8],
        target: u32,
        component: u32,
        count: usize,
        kind: &str,
        extra: Value,
    ) -> usize {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.views.push(json!({
            "buffer": 0, "byteOffset": offset, "byteLength": bytes.len(), "target": target
        }));
        let mut accessor = json!({
            "bufferView": self.views.len() - 1,
            "componentType": component,
            "count": count,
            "type": kind,
        });
        if let (Value::Object(accessor), Value::Object(extra)) = (&mut accessor, extra) {
            accessor.extend(extra);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Adds the mesh: its vertex attributes, materials and primitives.
    fn mesh(&mut self, mesh: &Mesh, table: &VertexTable, primitives: &Primitives) {
        let positions: Vec<[f32; 3]> = (table.vertices.iter())
            .map(|&v| mesh.positions()[v as usize].map(|c| c as f32))
            .collect();
        let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in &positions {
            for k in 0..3 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
            }
        }
        let bytes: Vec<u8> = positions
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        let count = positions.len();
        let mut attributes = serde_json::Map::new();
        let bounds = json!({"min": min, "max": max});
        let position = self.accessor(&bytes, ARRAY_BUFFER, FLOAT, count, "VEC3", bounds);
        attributes.insert("POSITION".into(), position.into());
        if let Some(normals) = &table.normals {
            let bytes: Vec<u8> = normals
                .iter()
                .flatten()
                .flat_map(|c| c.to_le_bytes())
                .collect();
            let normal = self.accessor(&bytes, ARRAY_BUFFER, FLOAT, count, "VEC3", json!({}));
            attributes.insert("NORMAL".into(), normal.into());
        }
        if let Some(uvs) = &table.uvs {
            let bytes: Vec<u8> = (uvs.iter().flatten())
                .flat_map(|&c| (c as f32).to_le_bytes())
                .collect();
            let uv = self.accessor(&bytes, ARRAY_BUFFER, FLOAT, count, "VEC2", json!({}));
            attributes.insert("TEXCOORD_0".into(), uv.into());
        }
        let has_material = mesh.face_materials().is_some() || mesh.face_colors().is_some();
        for (key, indices) in primitives.keys.iter().zip(&primitives.indices) {
            let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
            let (index_min, index_max) = (indices.iter().min(), indices.iter().max());
            let bounds = json!({"min": [index_min], "max": [index_max]});
            let n = indices.len();
            let accessor = self.accessor(
                &bytes,
                ELEMENT_ARRAY_BUFFER,
                UNSIGNED_INT,
                n,
                "SCALAR",
                bounds,
            );
            let mut primitive = json!({
                "attributes": attributes.clone(), "indices": accessor, "mode": TRIANGLES
            });
            if has_material {
                primitive["material"] = self.materials.len().into();
                self.materials.push(material(mesh, *key));
            }
            self.primitives.push(primitive);
        }
    }

    /// The whole JSON document; `.gltf` embeds the buffer as a data URI.
    fn json(&self, format: Format) -> Value {
        let mut document = json!({
            "asset": {"version": "2.0", "generator": "csgkit"},
            "scene": 0,
            "scenes": [{"nodes": []}],
        });
        if self.primitives.is_empty() {
            return document;
        }
        let mut buffer = json!({"byteLength": self.bin.len()});
        if format != Format::Glb {
            let payload = base64::engine::general_purpose::STANDARD.encode(&self.bin);
            buffer["uri"] = format!("data:application/octet-stream;base64,{payload}").into();
        }
        document["scenes"] = json!([{"nodes": [0]}]);
        document["nodes"] = json!([{"mesh": 0}]);
        document["meshes"] = json!([{"primitives": self.primitives}]);
        if !self.materials.is_empty() {
            document["materials"] = self.materials.clone().into();
        }
        document["buffers"] = json!([buffer]);
        document["bufferViews"] = self.views.clone().into();
        document["accessors"] = self.accessors.clone().into();
        document
    }
}

/// The material of a primitive: named after the face material, coloured by the face colour.
fn material(mesh: &Mesh, (material, color): (Option<u32>, Option<Rgba>)) -> Value {
    let mut pbr = json!({"metallicFactor": 0.0, "roughnessFactor": 1.0});
    if let Some(color) = color {
        pbr["baseColorFactor"] = color.map(|c| f32::from(c) / 255.0).to_vec().into();
    }
    let mut value = json!({"pbrMetallicRoughness": pbr});
    if let Some(id) = material {
        value["name"] = mesh.materials()[id as usize].clone().into();
    }
    value
}
