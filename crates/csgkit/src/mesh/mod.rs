//! The polygon mesh every engine reads and writes.
//!
//! A [`Mesh`] holds f64 positions and polygon faces stored as one flat corner buffer.
//! Triangle meshes, the common case, store no per-face offsets at all: the offsets buffer exists
//! only once a face with more than three corners is added, so triangles cost nothing extra.
//!
//! Beside the geometry a mesh carries optional attributes, each either absent or complete:
//! - per face: a material id into [`Mesh::materials`], a group id into [`Mesh::groups`], an
//!   RGBA colour, and the [`Provenance`] (operand and original face) that lets later stages
//!   merge split faces back and carry attributes through every engine;
//! - per corner: a UV coordinate and a normal, as files such as OBJ store them;
//! - per vertex: an RGBA colour (PLY, OFF).
//!
//! **Invariant:** every corner index is below [`Mesh::vertex_count`], every face has at least
//! three corners, every present attribute buffer has exactly one entry per face, corner or
//! vertex, and every material or group id indexes its name table.
//! [`Mesh::check_invariants`] verifies all of it; [`Mesh::from_parts`] establishes it.
//! Positions may be any f64, including non-finite ones: readers reject those at the file
//! boundary, where they can name the line.
//!
//! # Validity and measures
//! Whether a mesh bounds a solid is a measure, not an invariant. [`analyze`] (or
//! [`Mesh::report`]) welds equal positions ([`weld`]), builds the edge table once
//! ([`EdgeTable`]) and gathers every check and measure in a [`MeshReport`]: boundary edges
//! and loops, closedness (every edge balanced), edge- and vertex-manifoldness, orientation,
//! components, Euler characteristic and genus ([`Topology`]), exactly decided degenerate and
//! duplicate faces ([`count_degenerate`]), and signed volume, area and bounding box
//! ([`measure`]). The submodules' docs define each number and say where it differs from the
//! reference measurements in `shared/data/manifest.json`.
//!
//! # Triangles
//! [`triangulate_faces`] is the one triangulator of polygons: triangles pass through, strictly
//! convex polygons keep the fan from their first corner, and every other polygon gets the
//! exact constrained triangulation of its projection, or a [`PolygonError`] naming the face
//! when that projection overlaps itself. The exact engine, the self-intersection check and the
//! STL writer read faces through it. [`Mesh::fan_triangles`] serves only sums of signed terms
//! (volume, vector area, winding numbers), which any triangulation of a polygon's boundary
//! loop gives alike.
//!
//! # Convex hulls
//! [`convex_hull`] (and [`convex_hull_2d`]) give the hull of points as a closed mesh (a
//! counterclockwise ring), every decision an exact orientation: OpenSCAD's `hull()`.
//!
//! # Making a mesh 2-manifold
//! A closed mesh may touch itself along edges and at vertices (two cubes sharing an edge).
//! [`split_non_manifold`] duplicates vertices until every edge has two uses and every vertex
//! one fan, keeping faces and their attributes, for consumers that need a 2-manifold.

pub(crate) mod attributes;
mod degenerate;
mod hull;
mod ids;
mod manifold_split;
mod measures;
mod merge_faces;
pub(crate) mod numbering;
mod report;
#[cfg(test)]
mod test_meshes;
mod topology;
pub(crate) mod transform;
pub mod triangulate;
pub(crate) mod union_find;
mod validation;
pub(crate) mod vector;
mod weld;

pub use attributes::{concatenate, inherit_attributes};
pub use degenerate::{
    DegenerateCounts, FaceShape, are_collinear, coincident_triangles, count_degenerate, face_shape,
    opposite_triangle_pairs,
};
pub use hull::{convex_hull, convex_hull_2d};
pub use ids::{FaceId, OperandId, VertexId};
pub use manifold_split::split_non_manifold;
pub use measures::{BoundingBox, Measures, bounding_box, measure};
pub use merge_faces::{FaceMode, merge_faces};
pub use report::{MeshReport, analyze};
pub use topology::{EdgeKind, EdgeTable, EdgeUses, Topology, analyze_topology};
pub use transform::{Affine, IDENTITY, compose, moved, transformed};
pub use triangulate::{
    Overlap, PolygonError, Triangulation, triangulate_faces, triangulate_faces_partial,
};
pub(crate) use triangulate::{PlanarFault, triangulate_planar};
pub use validation::InvalidMesh;
pub(crate) use weld::weld_positions_by;
pub use weld::{Welding, apply_welding, weld, weld_positions};

/// An RGBA colour with 8 bits per channel.
pub type Rgba = [u8; 4];

/// Where an output face came from: which operand of an operation and which face of it.
///
/// Engines copy the provenance of the input face that an output face lies on, so splitting a
/// face never loses its attributes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Provenance {
    /// The operand (input mesh) the face belongs to, in the order the operation received them.
    pub operand: OperandId,
    /// The face's index in that operand.
    pub face: FaceId,
}

/// The raw buffers of a mesh, with public fields, for building a [`Mesh`] in one step.
///
/// Readers fill a `MeshParts` and hand it to [`Mesh::from_parts`], which checks every
/// invariant once.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshParts {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Corner vertex indices of all faces, face after face.
    pub corners: Vec<u32>,
    /// Start of each face in `corners`, plus one final entry equal to `corners.len()`.
    /// `None` means every face is a triangle.
    pub face_starts: Option<Vec<u32>>,
    /// Per-face material id into `materials`.
    pub face_materials: Option<Vec<u32>>,
    /// Material names (OBJ `usemtl`, PLY material property names, or palette names).
    pub materials: Vec<String>,
    /// Per-face group id into `groups`.
    pub face_groups: Option<Vec<u32>>,
    /// Group names (OBJ `o` and `g`).
    pub groups: Vec<String>,
    /// Per-face colour.
    pub face_colors: Option<Vec<Rgba>>,
    /// Per-face provenance.
    pub face_provenance: Option<Vec<Provenance>>,
    /// Per-corner texture coordinate.
    pub corner_uvs: Option<Vec<[f64; 2]>>,
    /// Per-corner normal.
    pub corner_normals: Option<Vec<[f32; 3]>>,
    /// Per-vertex colour.
    pub vertex_colors: Option<Vec<Rgba>>,
    /// Material libraries the file referred to (OBJ `mtllib`), kept so a writer can name them.
    pub material_libraries: Vec<String>,
}

/// A polygon mesh with f64 positions and optional face, corner and vertex attributes.
///
/// See the [module documentation](self) for the storage layout and its invariants.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    parts: MeshParts,
}

impl Mesh {
    /// An empty mesh: no vertex, no face. Booleans accept it as the empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds a mesh from its buffers after checking every invariant of the module docs.
    ///
    /// # Errors
    /// [`InvalidMesh`] naming the first face, corner or buffer that breaks an invariant.
    pub fn from_parts(parts: MeshParts) -> Result<Self, InvalidMesh> {
        validation::check_parts(&parts)?;
        Ok(Self { parts })
    }

    /// Builds a triangle mesh from positions and index triples.
    ///
    /// # Errors
    /// [`InvalidMesh`] if an index is out of range.
    pub fn from_triangles(
        positions: Vec<[f64; 3]>,
        triangles: &[[u32; 3]],
    ) -> Result<Self, InvalidMesh> {
        let corners = triangles.iter().flatten().copied().collect();
        Self::from_parts(MeshParts {
            positions,
            corners,
            ..MeshParts::default()
        })
    }

    /// Builds a polygon mesh from positions and one corner list per face.
    ///
    /// # Errors
    /// [`InvalidMesh`] if an index is out of range or a face has fewer than three corners.
    pub fn from_polygons<F: AsRef<[u32]>>(
        positions: Vec<[f64; 3]>,
        polygons: &[F],
    ) -> Result<Self, InvalidMesh> {
        let mut corners = Vec::new();
        let mut starts = Vec::with_capacity(polygons.len() + 1);
        starts.push(0);
        for polygon in polygons {
            corners.extend_from_slice(polygon.as_ref());
            starts.push(corners.len() as u32);
        }
        Self::from_parts(MeshParts {
            positions,
            corners,
            face_starts: Some(starts),
            ..MeshParts::default()
        })
    }

    /// Gives back the raw buffers, for callers that transform a mesh wholesale.
    pub fn into_parts(self) -> MeshParts {
        self.parts
    }

    /// Read access to every buffer at once.
    pub fn parts(&self) -> &MeshParts {
        &self.parts
    }

    /// Checks every invariant of the module docs; tests and `debug_assert!` call it.
    ///
    /// # Errors
    /// The first broken invariant.
    pub fn check_invariants(&self) -> Result<(), InvalidMesh> {
        validation::check_parts(&self.parts)
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.parts.positions.len()
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        match &self.parts.face_starts {
            Some(starts) => starts.len() - 1,
            None => self.parts.corners.len() / 3,
        }
    }

    /// Number of corners (the sum of the face sizes).
    pub fn corner_count(&self) -> usize {
        self.parts.corners.len()
    }

    /// True when the mesh has no face.
    pub fn is_empty(&self) -> bool {
        self.parts.corners.is_empty()
    }

    /// True when every face is a triangle.
    pub fn is_triangle_mesh(&self) -> bool {
        self.parts.face_starts.is_none()
    }

    /// All vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.parts.positions
    }

    /// The position of one vertex.
    ///
    /// # Panics
    /// If `v` is not a vertex of this mesh.
    pub fn position(&self, v: VertexId) -> [f64; 3] {
        self.parts.positions[v.index()]
    }

    /// The flat corner buffer: the vertex indices of all faces, face after face.
    pub fn corners(&self) -> &[u32] {
        &self.parts.corners
    }

    /// The range of face `f`'s corners in [`Mesh::corners`].
    ///
    /// # Panics
    /// If `f` is not a face of this mesh.
    pub fn face_range(&self, f: FaceId) -> std::ops::Range<usize> {
        let i = f.index();
        match &self.parts.face_starts {
            Some(starts) => starts[i] as usize..starts[i + 1] as usize,
            None => 3 * i..3 * i + 3,
        }
    }

    /// The vertex indices of face `f`, in order around the face.
    ///
    /// # Panics
    /// If `f` is not a face of this mesh.
    pub fn face(&self, f: FaceId) -> &[u32] {
        &self.parts.corners[self.face_range(f)]
    }

    /// Every face's vertex indices, in face order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        (0..self.face_count()).map(|f| self.face(FaceId::new(f)))
    }

    /// Triangles of a fan triangulation of every face, tagged with their face.
    ///
    /// Only for sums of signed terms over a closed polygon loop — signed volume, vector area,
    /// winding numbers — which every triangulation of the loop gives alike; the fan of a
    /// non-convex polygon leaves the polygon and overlaps itself. Consumers that need the
    /// polygon's own triangles use [`triangulate_faces`].
    pub fn fan_triangles(&self) -> impl Iterator<Item = (FaceId, [u32; 3])> + '_ {
        self.faces().enumerate().flat_map(|(f, corners)| {
            (1..corners.len() - 1)
                .map(move |k| (FaceId::new(f), [corners[0], corners[k], corners[k + 1]]))
        })
    }

    /// Material names.
    pub fn materials(&self) -> &[String] {
        &self.parts.materials
    }

    /// Per-face material ids, if the mesh has them.
    pub fn face_materials(&self) -> Option<&[u32]> {
        self.parts.face_materials.as_deref()
    }

    /// Group names.
    pub fn groups(&self) -> &[String] {
        &self.parts.groups
    }

    /// Per-face group ids, if the mesh has them.
    pub fn face_groups(&self) -> Option<&[u32]> {
        self.parts.face_groups.as_deref()
    }

    /// Per-face colours, if the mesh has them.
    pub fn face_colors(&self) -> Option<&[Rgba]> {
        self.parts.face_colors.as_deref()
    }

    /// Per-face provenance, if the mesh has it.
    pub fn face_provenance(&self) -> Option<&[Provenance]> {
        self.parts.face_provenance.as_deref()
    }

    /// Per-corner texture coordinates, if the mesh has them.
    pub fn corner_uvs(&self) -> Option<&[[f64; 2]]> {
        self.parts.corner_uvs.as_deref()
    }

    /// Per-corner normals, if the mesh has them.
    pub fn corner_normals(&self) -> Option<&[[f32; 3]]> {
        self.parts.corner_normals.as_deref()
    }

    /// Per-vertex colours, if the mesh has them.
    pub fn vertex_colors(&self) -> Option<&[Rgba]> {
        self.parts.vertex_colors.as_deref()
    }

    /// Material libraries the source file named.
    pub fn material_libraries(&self) -> &[String] {
        &self.parts.material_libraries
    }

    /// Sets every face's provenance to `(operand, own index)`: how an engine tags an input.
    pub fn set_operand(&mut self, operand: OperandId) {
        let provenance = (0..self.face_count())
            .map(|f| Provenance {
                operand,
                face: FaceId::new(f),
            })
            .collect();
        self.parts.face_provenance = Some(provenance);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad_and_triangle() -> Mesh {
        Mesh::from_parts(MeshParts {
            positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            corners: vec![0, 1, 2, 3, 0, 2, 1],
            face_starts: Some(vec![0, 4, 7]),
            ..MeshParts::default()
        })
        .expect("valid by construction")
    }

    #[test]
    fn triangle_meshes_store_no_offsets() {
        let mesh = Mesh::from_triangles(vec![[0.0; 3]; 3], &[[0, 1, 2]]).unwrap();
        assert!(mesh.is_triangle_mesh());
        assert_eq!(mesh.face_count(), 1);
        assert_eq!(mesh.face(FaceId::new(0)), &[0, 1, 2]);
    }

    #[test]
    fn polygon_faces_are_addressed_through_offsets() {
        let mesh = quad_and_triangle();
        assert_eq!(mesh.face_count(), 2);
        assert_eq!(mesh.face(FaceId::new(0)), &[0, 1, 2, 3]);
        assert_eq!(mesh.face(FaceId::new(1)), &[0, 2, 1]);
        assert_eq!(mesh.fan_triangles().count(), 3);
    }

    #[test]
    fn set_operand_tags_every_face() {
        let mut mesh = quad_and_triangle();
        mesh.set_operand(OperandId::new(3));
        let provenance = mesh.face_provenance().unwrap();
        assert_eq!(provenance[1].operand, OperandId::new(3));
        assert_eq!(provenance[1].face, FaceId::new(1));
        mesh.check_invariants().unwrap();
    }
}
