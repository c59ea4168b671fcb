//! Incremental mesh assembly shared by the readers.
//!
//! Files declare attributes late or for only some elements (an OBJ `usemtl` after the first
//! faces, a `vt` index on some corners), while [`Mesh`] wants each attribute absent or complete.
//! [`MeshBuilder`] keeps every attribute absent until its first value arrives, then fills the
//! earlier entries with a default (material or group `"default"`, white, UV `[0, 0]`,
//! normal `[0, 0, 0]`) so that the buffer stays complete.

use super::error::ParseError;
use crate::mesh::attributes::{DEFAULT_NAME, Names, WHITE};
use crate::mesh::{FaceId, Mesh, MeshParts, OperandId, Provenance, Rgba};

/// Pushes `value` on a lazily created buffer, first filling `len` defaults if it is absent.
#[inline]
fn put<T: Copy>(buffer: &mut Option<Vec<T>>, len: usize, value: T, default: T) {
    buffer.get_or_insert_with(|| vec![default; len]).push(value);
}

/// Pushes `value` if given, or `default` if the buffer exists; leaves an absent buffer absent.
#[inline]
fn put_opt<T: Copy>(buffer: &mut Option<Vec<T>>, len: usize, value: Option<T>, default: T) {
    match (value, buffer.as_mut()) {
        (Some(value), _) => put(buffer, len, value, default),
        (None, Some(buffer)) => buffer.push(default),
        (None, None) => {}
    }
}

/// Pushes the id of `name` (or of the default name) on a lazily created face id buffer.
#[inline]
fn name_id(names: &mut Names, buffer: &mut Option<Vec<u32>>, faces: usize, name: Option<&str>) {
    let needs_default = match name {
        Some(_) => buffer.is_none() && faces > 0,
        None => buffer.is_some(),
    };
    let default = if needs_default {
        names.id(DEFAULT_NAME)
    } else {
        0
    };
    let id = name.map(|name| names.id(name));
    put_opt(buffer, faces, id, default);
}

/// A mesh under construction; see the module docs.
#[derive(Default)]
pub(crate) struct MeshBuilder {
    parts: MeshParts,
    starts: Vec<u32>,
    all_triangles: bool,
    materials: Names,
    groups: Names,
}

impl MeshBuilder {
    /// An empty builder with room for about `vertices` vertices and `faces` triangles.
    pub(crate) fn with_capacity(vertices: usize, faces: usize) -> Self {
        let mut builder = Self {
            all_triangles: true,
            ..Self::default()
        };
        builder.parts.positions.reserve(vertices);
        builder.parts.corners.reserve(3 * faces);
        builder.starts.reserve(faces + 1);
        builder.starts.push(0);
        builder
    }

    /// Number of vertices so far.
    #[inline]
    pub(crate) fn vertex_count(&self) -> usize {
        self.parts.positions.len()
    }

    /// Number of faces so far.
    #[inline]
    pub(crate) fn face_count(&self) -> usize {
        self.starts.len() - 1
    }

    /// Adds a vertex with an optional colour.
    #[inline]
    pub(crate) fn push_vertex(&mut self, p: [f64; 3], color: Option<Rgba>) {
        let len = self.parts.positions.len();
        put_opt(&mut self.parts.vertex_colors, len, color, WHITE);
        self.parts.positions.push(p);
    }

    /// Adds one corner of the face under construction; `uv` and `normal` are optional.
    #[inline]
    pub(crate) fn push_corner(
        &mut self,
        vertex: u32,
        uv: Option<[f64; 2]>,
        normal: Option<[f32; 3]>,
    ) {
        let len = self.parts.corners.len();
        put_opt(&mut self.parts.corner_uvs, len, uv, [0.0; 2]);
        put_opt(&mut self.parts.corner_normals, len, normal, [0.0; 3]);
        self.parts.corners.push(vertex);
    }

    /// Adds corners without UV or normal to the face under construction.
    #[inline]
    pub(crate) fn push_corners(&mut self, vertices: impl Iterator<Item = u32>) {
        if self.parts.corner_uvs.is_none() && self.parts.corner_normals.is_none() {
            self.parts.corners.extend(vertices);
        } else {
            vertices.for_each(|v| self.push_corner(v, None, None));
        }
    }

    /// Corners pushed since the last [`MeshBuilder::end_face`].
    #[inline]
    pub(crate) fn open_corners(&self) -> usize {
        self.parts.corners.len() - self.starts[self.starts.len() - 1] as usize
    }

    /// Closes the face made of the corners pushed since the last call.
    ///
    /// # Errors
    /// [`ParseError::CountTooLarge`] past `u32::MAX` corners.
    #[inline]
    pub(crate) fn end_face(&mut self, attributes: FaceAttributes<'_>) -> Result<(), ParseError> {
        let corners = self.parts.corners.len();
        let end = u32::try_from(corners).map_err(|_| ParseError::CountTooLarge {
            what: "corner",
            count: corners as u64,
            reason: "meshes are limited to u32::MAX corners",
        })?;
        self.all_triangles &= self.open_corners() == 3;
        let faces = self.face_count();
        name_id(
            &mut self.materials,
            &mut self.parts.face_materials,
            faces,
            attributes.material,
        );
        name_id(
            &mut self.groups,
            &mut self.parts.face_groups,
            faces,
            attributes.group,
        );
        put_opt(&mut self.parts.face_colors, faces, attributes.color, WHITE);
        put_opt(
            &mut self.parts.face_provenance,
            faces,
            attributes.provenance,
            Provenance {
                operand: OperandId::new(0),
                face: FaceId::new(0),
            },
        );
        self.starts.push(end);
        Ok(())
    }

    /// Sets every face's material at once (readers whose files store material numbers).
    pub(crate) fn set_materials(&mut self, ids: Vec<u32>, names: Vec<String>) {
        self.parts.face_materials = Some(ids);
        self.materials = Names::default();
        for name in &names {
            self.materials.id(name);
        }
    }

    /// Records a material library name.
    pub(crate) fn push_material_library(&mut self, name: &str) {
        self.parts.material_libraries.push(name.to_owned());
    }

    /// Builds the mesh; faces are triangles-only storage when every face is a triangle.
    ///
    /// # Errors
    /// [`ParseError::Invalid`] if a buffer breaks a mesh invariant (readers check indices
    /// before, so this only reports size limits).
    pub(crate) fn finish(mut self) -> Result<Mesh, ParseError> {
        if !self.all_triangles {
            self.parts.face_starts = Some(self.starts);
        }
        self.parts.materials = self.materials.into_names();
        self.parts.groups = self.groups.into_names();
        Ok(Mesh::from_parts(self.parts)?)
    }
}

/// The per-face values a reader found for one face; `None` means the file gives none.
#[derive(Clone, Copy, Default)]
pub(crate) struct FaceAttributes<'a> {
    /// Material name.
    pub material: Option<&'a str>,
    /// Group name.
    pub group: Option<&'a str>,
    /// Face colour.
    pub color: Option<Rgba>,
    /// The source face (files csgkit wrote from an engine's result).
    pub provenance: Option<Provenance>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(builder: &mut MeshBuilder, attributes: FaceAttributes<'_>) {
        for v in 0..3 {
            builder.push_corner(v, None, None);
        }
        builder.end_face(attributes).unwrap();
    }

    #[test]
    fn late_attributes_backfill_defaults() {
        let mut builder = MeshBuilder::with_capacity(3, 2);
        for _ in 0..3 {
            builder.push_vertex([0.0; 3], None);
        }
        triangle(&mut builder, FaceAttributes::default());
        let red = FaceAttributes {
            material: Some("red"),
            group: Some("g"),
            ..FaceAttributes::default()
        };
        triangle(&mut builder, red);
        let mesh = builder.finish().unwrap();
        assert!(mesh.is_triangle_mesh());
        assert_eq!(mesh.materials(), ["default", "red"]);
        assert_eq!(mesh.face_materials(), Some(&[0, 1][..]));
        assert_eq!(mesh.groups(), ["default", "g"]);
        assert_eq!(mesh.face_groups(), Some(&[0, 1][..]));
    }
}
