//! glTF 2.0, as JSON (`.gltf`) and as one binary file (`.glb`): reader and writer.
//!
//! # Reading
//! 1. A GLB is split into its JSON and binary chunks (the container is checked here, so a
//!    short or lying header names the byte offset at fault).
//! 2. The JSON is parsed and validated by the `gltf` crate (`gltf::Document`): every index it
//!    holds is in range, or the error names the JSON path (`meshes[0].primitives[1].indices`).
//! 3. Buffers are the GLB binary chunk, `data:` URIs (base64), or files named by relative URI,
//!    which the caller's [`External`] gives (the path-based reader reads them beside the
//!    `.gltf`).
//! 4. The default scene (or the first, or every mesh once when there is no scene) is walked
//!    from its root nodes; each node with a mesh becomes one part ([`Part`]), moved by the
//!    product of the transforms (matrix, or translation·rotation·scale) from the root to it
//!    ([`transformed`]). A mesh's primitives are one part's faces: mode TRIANGLES, indexed or
//!    not (any other mode is an error naming the primitive); each primitive's material gives
//!    its faces their material (the material's name) and colour (`baseColorFactor`);
//!    `TEXCOORD_0` and `NORMAL` become corner UVs and normals.
//! 5. glTF repeats a vertex for each distinct normal or UV (seams, flat shading), while csgkit
//!    keeps those per corner; so bit-identical positions of a part are welded
//!    ([`mesh::weld`]), as STL's are, and [`LoadedMeshes::raw_vertex_count`] keeps the stored
//!    count. Primitives that share a `POSITION` accessor share their vertices before welding.
//!
//! Accessors are read here, not through `gltf`'s reader, whose element iterators index
//! slices without checking the element type against the data (a `POSITION` accessor of bytes
//! panics) and underflow on a count of zero; here every accessor's type, count, stride and
//! range is checked against its buffer first. Sparse accessors, morph targets and skins are
//! not read (sparse accessors are an error naming the accessor).
//!
//! # Writing
//! glTF stores positions as f32: each coordinate is rounded to the nearest f32, which
//! [`rounded_coordinates`] counts so callers can say so; a coordinate beyond the f32 range is
//! [`WriteError::TooLarge`]. One mesh with one primitive per distinct (material, colour) of
//! the faces, in order of first use; all primitives share one vertex table (the mesh's
//! vertices, or one vertex per distinct vertex, UV and normal when the mesh has corner
//! attributes) with `NORMAL` and `TEXCOORD_0` when present. Each primitive's material is named
//! after the face material and has the face colour as `baseColorFactor`. Faces are triangulated
//! by [`triangulate_faces`]. A `.glb` is one file; a `.gltf` embeds its buffer as a base64
//! `data:` URI, so it too is one file, written whole or not at all. Reading back gives the
//! same vertices (as f32), triangles grouped by primitive, materials and colours; faces with a
//! material but no colour come back white (a glTF material always has a base colour). Groups,
//! vertex colours and provenance are not written.
//!
//! The JSON is built with `serde_json` rather than `gltf-json`'s structs, which have no
//! defaults, so each object would spell out every optional field; the tests read every written
//! file back through `gltf`'s validation.
//!
//! [`rounded_coordinates`]: super::rounded_coordinates
//! [`mesh::weld`]: crate::mesh::weld

mod accessor;
mod write;

use base64::Engine as _;
use gltf::mesh::Mode;
use rustc_hash::FxHashMap;

use super::builder::{FaceAttributes, MeshBuilder};
use super::error::{Location, ParseError, within};
use super::text::channel;
use super::{Encoding, External, Format, LoadedMeshes, Part};
use crate::mesh::{Affine, IDENTITY, apply_welding, compose, transformed, weld_positions};

use accessor::{Buffers, read_f32s, read_indices};
pub(crate) use write::write;

/// The first bytes of a GLB file.
pub(crate) const GLB_MAGIC: &[u8] = b"glTF";

/// The chunk types of a GLB file.
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;

/// True for a JSON object (after whitespace and a byte order mark) with an `"asset"` key.
pub(crate) fn is_gltf_json(bytes: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace());
    start.is_some_and(|s| bytes[s] == b'{') && memchr::memmem::find(bytes, b"\"asset\"").is_some()
}

/// A [`ParseError::Structure`] of a glTF file.
fn structure(format: Format, reason: impl Into<String>) -> ParseError {
    ParseError::Structure {
        format,
        reason: reason.into(),
    }
}

/// Reads a `.gltf` or `.glb` held in memory: one part per node with a mesh.
pub(crate) fn read(data: &[u8], external: External<'_>) -> Result<LoadedMeshes, ParseError> {
    let (json, bin, format) = if data.starts_with(GLB_MAGIC) {
        let (json, bin) = glb_chunks(data)?;
        (json, bin, Format::Glb)
    } else {
        (data, None, Format::Gltf)
    };
    let root = gltf::json::deserialize::from_slice(json)
        .map_err(|e| structure(format, format!("invalid JSON: {e}")))?;
    check_position_indices(&root, format)?;
    let document = gltf::Document::from_json(root).map_err(|e| validation(format, e))?;
    let buffers = Buffers::load(&document, bin, external, format)?;
    let mut reader = Reader {
        format,
        buffers,
        parts: Vec::new(),
        raw_vertex_count: 0,
        nodes: document.nodes().count(),
    };
    match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => {
            for node in scene.nodes() {
                reader.visit(node, IDENTITY, 0)?;
            }
        }
        None => {
            for mesh in document.meshes() {
                let name = mesh
                    .name()
                    .map_or_else(|| format!("meshes[{}]", mesh.index()), str::to_owned);
                reader.part(&mesh, IDENTITY, name)?;
            }
        }
    }
    Ok(LoadedMeshes {
        parts: reader.parts,
        format,
        encoding: if format == Format::Glb {
            Encoding::Binary
        } else {
            Encoding::Ascii
        },
        raw_vertex_count: reader.raw_vertex_count,
        unit: None,
    })
}

/// The first validation error, with its JSON path.
fn validation(format: Format, error: gltf::Error) -> ParseError {
    match error {
        gltf::Error::Validation(errors) => match errors.first() {
            Some((path, error)) => {
                // gltf capitalises its messages; csgkit's are lower case.
                let message = error.to_string();
                let mut chars = message.chars();
                let first = chars.next().map(|c| c.to_ascii_lowercase());
                let reason: String = first.into_iter().chain(chars).collect();
                within(path.to_string(), structure(format, reason))
            }
            None => structure(format, "invalid document"),
        },
        other => structure(format, other.to_string()),
    }
}

/// Fails unless every primitive's `POSITION` names an accessor that exists: `gltf`'s
/// validation indexes the accessors with it unchecked (and would panic).
fn check_position_indices(root: &gltf::json::Root, format: Format) -> Result<(), ParseError> {
    let positions = gltf::json::validation::Checked::Valid(gltf::json::mesh::Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive.attributes.get(&positions) {
                if index.value() >= root.accessors.len() {
                    let element = format!("meshes[{m}].primitives[{p}].attributes[\"POSITION\"]");
                    return Err(within(element, structure(format, "index out of bounds")));
                }
            }
        }
    }
    Ok(())
}

/// A little-endian `u32` at `offset`, if the data holds it.
fn u32_at(data: &[u8], offset: usize) -> Option<u32> {
    let bytes = data.get(offset..offset.checked_add(4)?)?;
    Some(u32::from_le_bytes(bytes.try_into().ok()?))
}

/// A GLB chunk: its type, its body and the offset of the next chunk.
type Chunk<'a> = (u32, &'a [u8], usize);

/// The JSON chunk and the binary chunk (if any) of a GLB file.
fn glb_chunks(data: &[u8]) -> Result<(&[u8], Option<&[u8]>), ParseError> {
    let truncated = |what, expected| ParseError::Truncated {
        what,
        expected,
        actual: data.len(),
    };
    let (Some(version), Some(length)) = (u32_at(data, 4), u32_at(data, 8)) else {
        return Err(truncated("GLB header", 12));
    };
    if version != 2 {
        let at = Location::Byte(4);
        return Err(within(
            format!("{at}"),
            ParseError::Feature {
                format: Format::Glb,
                feature: format!("GLB version {version} (csgkit reads glTF 2)"),
            },
        ));
    }
    let length = length as usize;
    if length > data.len() {
        return Err(truncated("GLB file", length));
    }
    let data = &data[..length];
    let chunk = |offset: usize, what| -> Result<Option<Chunk<'_>>, ParseError> {
        if offset >= data.len() {
            return Ok(None);
        }
        let (Some(size), Some(kind)) = (u32_at(data, offset), u32_at(data, offset + 4)) else {
            return Err(truncated(what, offset + 8));
        };
        let start = offset + 8;
        let end = start.saturating_add(size as usize);
        let body = data.get(start..end).ok_or_else(|| truncated(what, end))?;
        // Chunks start on 4-byte boundaries.
        Ok(Some((kind, body, end.next_multiple_of(4))))
    };
    let Some((kind, json, next)) = chunk(12, "GLB JSON chunk")? else {
        return Err(truncated("GLB JSON chunk", 20));
    };
    if kind != JSON_CHUNK {
        let reason = "the first chunk is not the JSON chunk";
        return Err(super::error::malformed(
            Format::Glb,
            Location::Byte(16),
            reason,
        ));
    }
    let mut offset = next;
    while let Some((kind, body, next)) = chunk(offset, "GLB chunk")? {
        if kind == BIN_CHUNK {
            return Ok((json, Some(body)));
        }
        // Chunks of unknown types are skipped, as the specification asks.
        offset = next;
    }
    Ok((json, None))
}

/// The state of one read: the buffers and the parts found so far.
struct Reader<'a> {
    format: Format,
    buffers: Buffers<'a>,
    parts: Vec<Part>,
    raw_vertex_count: usize,
    /// The node count, which no path from a root can exceed without a cycle.
    nodes: usize,
}

impl Reader<'_> {
    /// Visits `node` and its children under `outer`.
    fn visit(
        &mut self,
        node: gltf::Node<'_>,
        outer: Affine,
        depth: usize,
    ) -> Result<(), ParseError> {
        let element = || format!("nodes[{}]", node.index());
        if depth > self.nodes {
            let reason = "the node hierarchy has a cycle";
            return Err(within(element(), structure(self.format, reason)));
        }
        let placement = compose(outer, node_transform(&node.transform()));
        if let Some(mesh) = node.mesh() {
            let name = node.name().map_or_else(element, str::to_owned);
            self.part(&mesh, placement, name)
                .map_err(|e| within(element(), e))?;
        }
        for child in node.children() {
            self.visit(child, placement, depth + 1)?;
        }
        Ok(())
    }

    /// Reads `mesh` as one part placed by `placement`.
    fn part(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        placement: Affine,
        name: String,
    ) -> Result<(), ParseError> {
        let mut builder = MeshBuilder::with_capacity(0, 0);
        // Vertex offset of each POSITION accessor read so far.
        let mut offsets: FxHashMap<usize, u32> = FxHashMap::default();
        for primitive in mesh.primitives() {
            let element = format!("meshes[{}].primitives[{}]", mesh.index(), primitive.index());
            self.primitive(&primitive, &mut builder, &mut offsets)
                .map_err(|e| within(element, e))?;
        }
        let mesh_element = || format!("meshes[{}]", mesh.index());
        let read = builder.finish().map_err(|e| within(mesh_element(), e))?;
        self.raw_vertex_count += read.vertex_count();
        let welding = weld_positions(read.positions());
        let welded = if welding.duplicate_count() > 0 {
            apply_welding(&read, &welding)
        } else {
            read
        };
        let placed = transformed(&welded, &placement).ok_or_else(|| {
            let reason = "the node transforms are singular or not finite";
            within(mesh_element(), structure(self.format, reason))
        })?;
        self.parts.push(Part { name, mesh: placed });
        Ok(())
    }

    /// Adds one primitive's vertices (unless shared) and triangles to `builder`.
    fn primitive(
        &self,
        primitive: &gltf::Primitive<'_>,
        builder: &mut MeshBuilder,
        offsets: &mut FxHashMap<usize, u32>,
    ) -> Result<(), ParseError> {
        let format = self.format;
        if primitive.mode() != Mode::Triangles {
            let feature = format!(
                "primitive mode {:?} (csgkit reads Triangles)",
                primitive.mode()
            );
            return Err(ParseError::Feature { format, feature });
        }
        let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
            return Err(structure(format, "the primitive has no POSITION attribute"));
        };
        let count = positions.count();
        let offset = match offsets.get(&positions.index()) {
            Some(&offset) => offset,
            None => {
                let offset = builder.vertex_count() as u32;
                let values = read_f32s::<3>(&self.buffers, &positions, "POSITION", format)?;
                for (v, p) in values.iter().enumerate() {
                    let p = p.map(f64::from);
                    super::text::check_finite(p, v, Location::Byte(0))
                        .map_err(|e| within(format!("accessors[{}]", positions.index()), e))?;
                    builder.push_vertex(p, None);
                }
                offsets.insert(positions.index(), offset);
                offset
            }
        };
        let attribute = |semantic: gltf::Semantic,
                         name: &str|
         -> Result<Option<gltf::Accessor<'_>>, ParseError> {
            match primitive.get(&semantic) {
                Some(accessor) if accessor.count() != count => Err(structure(
                    format,
                    format!("{name} has {} elements, POSITION {count}", accessor.count()),
                )),
                other => Ok(other),
            }
        };
        let normals = match attribute(gltf::Semantic::Normals, "NORMAL")? {
            Some(accessor) => Some(read_f32s::<3>(&self.buffers, &accessor, "NORMAL", format)?),
            None => None,
        };
        let uvs = match attribute(gltf::Semantic::TexCoords(0), "TEXCOORD_0")? {
            Some(accessor) => Some(read_f32s::<2>(
                &self.buffers,
                &accessor,
                "TEXCOORD_0",
                format,
            )?),
            None => None,
        };
        let indices = match primitive.indices() {
            Some(accessor) => Some(read_indices(&self.buffers, &accessor, format)?),
            None => None,
        };
        let corners = indices
            .as_ref()
            .map_or(count, |indices| indices.values.len());
        if corners % 3 != 0 {
            let reason = format!("{corners} vertices do not make whole triangles");
            return Err(structure(format, reason));
        }
        let material = primitive.material();
        let name = material.index().and(material.name());
        let color = material.index().map(|_| {
            let factor = material.pbr_metallic_roughness().base_color_factor();
            factor.map(|c| channel(f64::from(c), true))
        });
        for face in 0..corners / 3 {
            for k in 0..3 {
                let corner = 3 * face + k;
                let v = match &indices {
                    Some(indices) => {
                        let v = indices.values[corner];
                        if v as usize >= count {
                            let error = ParseError::IndexOutOfRange {
                                face,
                                what: "vertex",
                                index: i64::from(v),
                                count,
                                at: indices.at(corner),
                            };
                            return Err(within("indices", error));
                        }
                        v as usize
                    }
                    None => corner,
                };
                let uv = uvs.as_ref().map(|uvs| uvs[v].map(f64::from));
                let normal = normals.as_ref().map(|normals| normals[v]);
                builder.push_corner(offset + v as u32, uv, normal);
            }
            let attributes = FaceAttributes {
                material: name,
                color,
                ..FaceAttributes::default()
            };
            builder.end_face(attributes)?;
        }
        Ok(())
    }
}

/// A node's local transform as an [`Affine`]: its matrix (column-major), or translation ·
/// rotation · scale, computed in f64 from the file's f32 values.
fn node_transform(transform: &gltf::scene::Transform) -> Affine {
    match *transform {
        gltf::scene::Transform::Matrix { matrix } => {
            [0, 1, 2].map(|i| [0, 1, 2, 3].map(|j| f64::from(matrix[j][i])))
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let [x, y, z, w] = rotation.map(f64::from);
            let rotation = [
                [
                    1.0 - 2.0 * (y * y + z * z),
                    2.0 * (x * y - z * w),
                    2.0 * (x * z + y * w),
                ],
                [
                    2.0 * (x * y + z * w),
                    1.0 - 2.0 * (x * x + z * z),
                    2.0 * (y * z - x * w),
                ],
                [
                    2.0 * (x * z - y * w),
                    2.0 * (y * z + x * w),
                    1.0 - 2.0 * (x * x + y * y),
                ],
            ];
            let scale = scale.map(f64::from);
            [0, 1, 2].map(|i| {
                [
                    rotation[i][0] * scale[0],
                    rotation[i][1] * scale[1],
                    rotation[i][2] * scale[2],
                    f64::from(translation[i]),
                ]
            })
        }
    }
}

/// Decodes the payload of a `data:` URI, which must be base64.
fn data_uri(uri: &str) -> Option<Result<Vec<u8>, String>> {
    let rest = uri.strip_prefix("data:")?;
    Some(match rest.split_once(";base64,") {
        Some((_, payload)) => base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| format!("the data URI is not valid base64: {e}")),
        None => Err("the data URI is not base64".to_owned()),
    })
}

/// `%XX` escapes of a relative URI decoded, so `my%20part.bin` names `my part.bin`.
fn percent_decoded(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        let hex = bytes
            .get(k + 1..k + 3)
            .and_then(|h| std::str::from_utf8(h).ok());
        match (bytes[k], hex.and_then(|h| u8::from_str_radix(h, 16).ok())) {
            (b'%', Some(byte)) => {
                out.push(byte);
                k += 3;
            }
            (byte, _) => {
                out.push(byte);
                k += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests;
