//! Triangulation of faces and mesh assembly (`design/ortho.md` §A6).
//!
//! A face is triangulated in its (a, b) frame from its loop vertices only: no Steiner point,
//! no dropped collinear vertex. Earcut-style libraries drop collinear points, and those are
//! exactly the conforming vertices that keep the mesh free of T-junctions, so we use the
//! crate's one triangulator of polygons, the constrained Delaunay triangulation of
//! `mesh::triangulate` (its planar core, which takes holes), instead:
//! 1. insert the face's distinct loop vertices, with every loop edge as a constraint
//!    (a conflict is an error, never a panic);
//! 2. flood-fill from the outer face, flipping inside/outside across constraint edges;
//! 3. keep the inside triangles, CCW in (a, b), hence CCW seen from outside.
//!
//! A face with n loop positions (counting repeats) and h holes gives exactly n + 2h − 2
//! triangles; the count is checked and a mismatch is an error. Loops may be weakly simple
//! (a vertex visited twice), which the mesh polygons' stricter checks of
//! `mesh::triangulate_faces` reject, so only the planar core is shared.
//!
//! Numeric model: spade's exact predicates on the input coordinates, scaled by a power of two
//! into spade's range when needed (exact); no coordinate is created.
//! Complexity: O(n log n) per face.

use crate::par::*;

use super::manifold::TriangleSoup;
use super::{BRep, OrthoError};
use crate::mesh::{PlanarFault, triangulate_planar};
use crate::{FaceId, Mesh, MeshParts, OperandId, Provenance};

/// How [`BRep::to_mesh`] writes faces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshOptions {
    /// Triangulate every face. Otherwise a face without holes is one polygon and only faces
    /// with holes (or weakly simple loops) are triangulated.
    pub triangles: bool,
    /// Split non-manifold edges and vertices into a 2-manifold (implies `triangles`); see
    /// the `manifold` stage.
    pub manifold: bool,
}

/// A mesh built from a [`BRep`].
#[derive(Clone, Debug, PartialEq)]
pub struct MeshOutput {
    /// The mesh.
    pub mesh: Mesh,
    /// In manifold mode, non-manifold edges left shared because f64 holds no value strictly
    /// between their endpoints (always 0 otherwise).
    pub unsplit_edges: usize,
}

impl BRep {
    /// The shared-vertex mesh of the boundary: one vertex per B-rep vertex (indexed by exact
    /// position), faces as polygons or triangles by `options`, each output face's provenance
    /// naming its B-rep face (operand 0). The mesh is closed: every directed edge has its
    /// reverse; non-manifold edges carry four faces.
    ///
    /// # Errors
    /// [`OrthoError::InvalidBRep`] if the B-rep breaks [`BRep::check_invariants`],
    /// [`OrthoError::Triangulation`] if spade rejects a coordinate (outside its range).
    pub fn to_mesh(&self, options: MeshOptions) -> Result<MeshOutput, OrthoError> {
        self.check_invariants()
            .map_err(|reason| OrthoError::InvalidBRep { reason })?;
        if options.manifold {
            return self.to_manifold_mesh();
        }
        // Faces are independent: triangulate in parallel, concatenate in face order. `None`
        // keeps the outer loop as the one polygon, without copying it.
        let per_face: Vec<Result<Option<Vec<[u32; 3]>>, OrthoError>> = (0..self.faces.len())
            .into_par_iter()
            .map(|f| {
                let face = &self.faces[f];
                if !options.triangles && face.holes.is_empty() && is_simple(&face.outer) {
                    Ok(None)
                } else {
                    self.triangulate_face(f).map(Some)
                }
            })
            .collect();
        let mut corners = Vec::new();
        let mut starts = vec![0u32];
        let mut provenance = Vec::new();
        for (f, polygons) in per_face.into_iter().enumerate() {
            let tag = Provenance {
                operand: OperandId::new(0),
                face: FaceId::new(f),
            };
            let mut push = |polygon: &[u32]| {
                corners.extend_from_slice(polygon);
                starts.push(corners.len() as u32);
                provenance.push(tag);
            };
            match polygons? {
                Some(triangles) => triangles.iter().for_each(|t| push(t)),
                None => push(&self.faces[f].outer),
            }
        }
        let all_triangles = starts.windows(2).all(|w| w[1] - w[0] == 3);
        let mut parts = MeshParts {
            positions: self.vertices.iter().map(|v| v.position).collect(),
            corners,
            face_starts: (!all_triangles).then_some(starts),
            ..MeshParts::default()
        };
        self.set_face_attributes(&mut parts, provenance);
        let mesh = Mesh::from_parts(parts).expect("B-rep loops index existing vertices");
        Ok(MeshOutput {
            mesh,
            unsplit_edges: 0,
        })
    }

    /// The 2-manifold triangle mesh (`manifold` stage).
    fn to_manifold_mesh(&self) -> Result<MeshOutput, OrthoError> {
        let mut soup = TriangleSoup {
            positions: self.vertices.iter().map(|v| v.position).collect(),
            triangles: Vec::new(),
            normals: Vec::new(),
            sources: Vec::new(),
        };
        let per_face: Vec<Result<Vec<[u32; 3]>, OrthoError>> = (0..self.faces.len())
            .into_par_iter()
            .map(|f| self.triangulate_face(f))
            .collect();
        for (f, triangles) in per_face.into_iter().enumerate() {
            let triangles = triangles?;
            soup.normals.extend(std::iter::repeat_n(
                self.faces[f].orientation,
                triangles.len(),
            ));
            soup.sources
                .extend(std::iter::repeat_n(f as u32, triangles.len()));
            soup.triangles.extend(triangles);
        }
        let unsplit_edges = soup.make_manifold();
        let provenance = soup
            .sources
            .iter()
            .map(|&f| Provenance {
                operand: OperandId::new(0),
                face: FaceId::new(f as usize),
            })
            .collect();
        let mut parts = MeshParts {
            positions: soup.positions,
            corners: soup.triangles.into_iter().flatten().collect(),
            ..MeshParts::default()
        };
        self.set_face_attributes(&mut parts, provenance);
        let mesh = Mesh::from_parts(parts).expect("the split keeps indices in range");
        Ok(MeshOutput {
            mesh,
            unsplit_edges,
        })
    }

    /// Sets the provenance (operand 0, B-rep face) of every mesh face and, when the B-rep has
    /// materials, its material: material id m is named `material_m`.
    fn set_face_attributes(&self, parts: &mut MeshParts, provenance: Vec<Provenance>) {
        if self.has_materials {
            let materials: Vec<u32> = provenance
                .iter()
                .map(|p| self.faces[p.face.index()].material)
                .collect();
            let count = materials.iter().max().map_or(0, |&m| m as usize + 1);
            parts.materials = (0..count).map(|m| format!("material_{m}")).collect();
            parts.face_materials = Some(materials);
        }
        parts.face_provenance = Some(provenance);
    }

    /// The triangles of face `f` as vertex-index triples, CCW seen from outside.
    ///
    /// # Errors
    /// [`OrthoError::Triangulation`] if the loops' edges cross or their vertices coincide, if
    /// no power of two brings the face's coordinates into spade's range, or if the result does
    /// not have n + 2h − 2 triangles.
    ///
    /// # Panics
    /// If `f` is not a face index, or a loop names a missing vertex (see
    /// [`BRep::check_invariants`]).
    pub fn triangulate_face(&self, f: usize) -> Result<Vec<[u32; 3]>, OrthoError> {
        let face = &self.faces[f];
        let fail = |reason: String| OrthoError::Triangulation { face: f, reason };
        let (a, b) = face.orientation.frame();
        let loops = || std::iter::once(&face.outer).chain(&face.holes);
        // Steps 1-3 on the face's distinct loop vertices, in the (a, b) frame.
        let mut ids: Vec<u32> = loops().flatten().copied().collect();
        ids.sort_unstable();
        ids.dedup();
        let local = |v: u32| ids.binary_search(&v).expect("loop vertex was collected");
        let points = (ids.iter())
            .map(|&v| {
                let p = self.vertices[v as usize].position;
                [p[a], p[b]]
            })
            .collect();
        let edges = loops()
            .flat_map(|lp| (0..lp.len()).map(|i| [local(lp[i]), local(lp[(i + 1) % lp.len()])]))
            .collect();
        let planar = triangulate_planar(points, edges).map_err(|fault| {
            fail(match fault {
                PlanarFault::OutOfRange => "coordinates outside spade's range".into(),
                PlanarFault::CoincidentPoints | PlanarFault::CrossingEdges => {
                    "loop edges cross or vertices coincide".into()
                }
            })
        })?;
        let triangles: Vec<[u32; 3]> = (planar.triangles.iter())
            .map(|t| t.map(|i| ids[i]))
            .collect();
        let n: usize = face.holes.iter().map(Vec::len).sum::<usize>() + face.outer.len();
        let expected = n + 2 * face.holes.len() - 2;
        if triangles.len() != expected {
            return Err(fail(format!(
                "{} triangles instead of n + 2h - 2 = {expected}",
                triangles.len()
            )));
        }
        Ok(triangles)
    }
}

/// True if no vertex repeats in the loop (it is simple, not weakly simple).
fn is_simple(lp: &[u32]) -> bool {
    let mut sorted = lp.to_vec();
    sorted.sort_unstable();
    sorted.windows(2).all(|w| w[0] != w[1])
}

/// One mesh holding every solid of [`box_union_per_material`](super::box_union_per_material):
/// solid i's faces have operand i in their provenance and its material id, named
/// `material_m`. Solids keep separate vertices, so where two materials touch, both faces are
/// present with opposite orientations.
///
/// # Errors
/// As [`BRep::to_mesh`].
pub fn per_material_mesh(
    solids: &[(u32, BRep)],
    options: MeshOptions,
) -> Result<MeshOutput, OrthoError> {
    let mut parts = MeshParts::default();
    let mut starts = vec![0u32];
    let mut materials = Vec::new();
    let mut provenance = Vec::new();
    let mut unsplit_edges = 0;
    for (operand, (material, brep)) in solids.iter().enumerate() {
        let out = brep.to_mesh(options)?;
        unsplit_edges += out.unsplit_edges;
        let mesh = out.mesh;
        let offset = parts.positions.len() as u32;
        parts.positions.extend_from_slice(mesh.positions());
        for (f, face) in mesh.faces().enumerate() {
            parts.corners.extend(face.iter().map(|&v| v + offset));
            starts.push(parts.corners.len() as u32);
            materials.push(*material);
            let face = mesh.face_provenance().map_or(FaceId::new(f), |p| p[f].face);
            provenance.push(Provenance {
                operand: OperandId::new(operand),
                face,
            });
        }
    }
    let all_triangles = starts.windows(2).all(|w| w[1] - w[0] == 3);
    parts.face_starts = (!all_triangles).then_some(starts);
    let count = materials.iter().max().map_or(0, |&m| m as usize + 1);
    parts.materials = (0..count).map(|m| format!("material_{m}")).collect();
    parts.face_materials = Some(materials);
    parts.face_provenance = Some(provenance);
    let mesh = Mesh::from_parts(parts).expect("concatenated meshes keep indices in range");
    Ok(MeshOutput {
        mesh,
        unsplit_edges,
    })
}
