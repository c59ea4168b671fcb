//! The **simplify** stage, an option (`BooleanOptions::simplify`): faces that are flat to
//! within a tolerance merged, and the vertices only they need removed, before certification.
//!
//! # Why
//! A face cut by one boolean and written to a file comes back as triangles whose rounded
//! corners are no longer exactly in one plane. The next boolean must keep every point where
//! its cut crosses a side between two such triangles, since the exact surface bends there by
//! an ulp; a chain of booleans through files therefore grows by the vertices of every cut
//! (design/exact.md; manifold3d merges such faces within its tolerance). This stage gives
//! that choice to the user, with a bound: every change moves the surface by at most the
//! tolerance, and the certify stage then checks every changed face exactly as it checks
//! rounded ones, so the result stays a valid solid.
//!
//! # Contract
//! In: the rounded triangles with provenance, the source meshes, and a tolerance `delta`
//! (a length). Out: the same solid, where
//! - neighbouring faces (across a side used by exactly two triangles) that look alike
//!   (material, group, colour, no corner attributes) and whose triangles' far corners are
//!   within `delta` of each other's planes record one provenance, that of the lowest;
//! - a vertex whose triangles form one disk inside one such face, or one disk split by a
//!   boundary between two faces that passes within `delta` of it, is collapsed onto a
//!   neighbour when every corner of its fan is within `delta` of the plane of every new
//!   triangle, no new triangle turns over, and the link condition holds (the two vertices
//!   share no neighbour but the corners of the triangles between them);
//! - the vertices of every new triangle are marked as moved, for certification.
//!
//! Decisions here use f64 and the tolerance: they choose which vertices to keep, the exact
//! checks of certification decide validity.

use crate::mesh::numbering::FaceNumbering;
use crate::mesh::union_find::UnionFind;
use crate::mesh::vector::{cross, dot, sub, triangle_normal, triangle_shape};
use crate::mesh::{Mesh, MeshParts, Provenance};

use super::assemble::Rounded;
use super::reconstruct::faces_look_alike;
use super::star::{self, Collapse};

/// Simplifies `rounded` within `delta` (see the module docs); returns the simplified mesh and
/// how many vertices it removed.
pub(crate) fn simplify(rounded: Rounded, operands: &[&Mesh], delta: f64) -> (Rounded, usize) {
    let Rounded {
        mesh,
        moved,
        rounded: rounded_count,
    } = rounded;
    let parts = mesh.into_parts();
    let provenance = parts
        .face_provenance
        .clone()
        .expect("engine output has provenance");
    let triangles: Vec<[u32; 3]> = (parts.corners.chunks_exact(3))
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let positions = parts.positions;
    let mut faces = Faces::new(operands, &provenance);
    faces.join_flat(operands, &positions, &triangles, &provenance, delta);
    let group: Vec<u32> = provenance.iter().map(|&p| faces.group(p)).collect();
    let mut mesh = Editable::new(&positions, triangles, provenance, group);
    let mut removed = 0;
    for v in 0..positions.len() as u32 {
        if mesh.remove(v, delta) {
            removed += 1;
        }
    }
    (
        mesh.into_rounded(&mut faces, &moved, rounded_count),
        removed,
    )
}

/// Source faces joined into groups by flatness.
struct Faces {
    numbering: FaceNumbering,
    groups: UnionFind,
}

impl Faces {
    fn new(operands: &[&Mesh], provenance: &[Provenance]) -> Self {
        debug_assert!(
            provenance
                .iter()
                .all(|p| p.operand.index() < operands.len())
        );
        let numbering = FaceNumbering::new(operands);
        let groups = UnionFind::new(numbering.total() as usize);
        Self { numbering, groups }
    }

    fn group(&mut self, p: Provenance) -> u32 {
        let dense = self.numbering.of(p);
        self.groups.find(dense)
    }

    /// Joins neighbouring faces that look alike and are flat to within `delta` together.
    fn join_flat(
        &mut self,
        operands: &[&Mesh],
        positions: &[[f64; 3]],
        triangles: &[[u32; 3]],
        provenance: &[Provenance],
        delta: f64,
    ) {
        for (k, l) in star::side_neighbours(triangles) {
            let (p, q) = (provenance[k as usize], provenance[l as usize]);
            let (g, h) = (self.group(p), self.group(q));
            if g == h || !faces_look_alike(operands, p, q) {
                continue;
            }
            let (s, u) = (triangles[k as usize], triangles[l as usize]);
            let p3 = |v: u32| positions[v as usize];
            let flat = s.iter().all(|&c| plane_distance(u.map(p3), p3(c)) <= delta)
                && u.iter().all(|&c| plane_distance(s.map(p3), p3(c)) <= delta);
            if flat {
                self.groups.union(g, h);
            }
        }
    }
}

/// The triangles as the removals edit them.
struct Editable<'a> {
    positions: &'a [[f64; 3]],
    triangles: Vec<[u32; 3]>,
    provenance: Vec<Provenance>,
    group: Vec<u32>,
    alive: Vec<bool>,
    /// Per vertex: the triangles that use it, dead ones included.
    incident: Vec<Vec<u32>>,
    /// Vertices of the triangles made here.
    changed: Vec<bool>,
}

impl<'a> Editable<'a> {
    fn new(
        positions: &'a [[f64; 3]],
        triangles: Vec<[u32; 3]>,
        provenance: Vec<Provenance>,
        group: Vec<u32>,
    ) -> Self {
        let mut incident = vec![Vec::new(); positions.len()];
        for (f, t) in triangles.iter().enumerate() {
            for &v in t {
                incident[v as usize].push(f as u32);
            }
        }
        let n = triangles.len();
        Self {
            positions,
            triangles,
            provenance,
            group,
            alive: vec![true; n],
            incident,
            changed: vec![false; positions.len()],
        }
    }

    fn at(&self, v: u32) -> [f64; 3] {
        self.positions[v as usize]
    }

    /// Removes `v` if the module docs allow it; whether it did.
    fn remove(&mut self, v: u32, delta: f64) -> bool {
        let fan: Vec<u32> = (self.incident[v as usize].iter())
            .copied()
            .filter(|&f| self.alive[f as usize])
            .collect();
        if fan.len() < 3 {
            return false;
        }
        let Some(spokes) = star::disk(&self.triangles, v, &fan) else {
            return false;
        };
        let bounding = star::bounding(&spokes, |f| self.group[f as usize]);
        let targets: Vec<u32> = match bounding[..] {
            [] => spokes.iter().map(|s| s.to).collect(),
            [u, w] if on_segment(self.at(u), self.at(v), self.at(w), delta) => vec![u, w],
            _ => return false,
        };
        let link: Vec<u32> = spokes.iter().map(|s| s.to).collect();
        let mut best: Option<Collapse> = None;
        for z in targets {
            if let Some((shape, new)) = self.collapse(v, z, &fan, &link, delta)
                && best.as_ref().is_none_or(|(s, _)| shape > *s)
            {
                best = Some((shape, new));
            }
        }
        let Some((_, new)) = best else {
            return false;
        };
        for &f in &fan {
            self.alive[f as usize] = false;
        }
        for (old, t) in new {
            let f = self.triangles.len() as u32;
            self.triangles.push(t);
            self.provenance.push(self.provenance[old as usize]);
            self.group.push(self.group[old as usize]);
            self.alive.push(true);
            for x in t {
                self.incident[x as usize].push(f);
                self.changed[x as usize] = true;
            }
        }
        true
    }

    /// The triangles replacing `fan` when `v` collapses onto `z` (each with the triangle it
    /// replaces) and the shape of the worst, if the module docs allow the collapse.
    fn collapse(&self, v: u32, z: u32, fan: &[u32], link: &[u32], delta: f64) -> Option<Collapse> {
        // Link condition: `z`'s other neighbours are not in `v`'s link, except the corners of
        // the triangles `v` and `z` share.
        let wings: Vec<u32> = (fan.iter())
            .map(|&f| self.triangles[f as usize])
            .filter(|t| t.contains(&z))
            .flat_map(|t| t.into_iter().filter(|&x| x != v && x != z))
            .collect();
        let outside = (self.incident[z as usize].iter())
            .filter(|&&f| self.alive[f as usize] && !fan.contains(&f))
            .flat_map(|&f| self.triangles[f as usize]);
        for x in outside {
            if x != z && link.contains(&x) && !wings.contains(&x) {
                return None;
            }
        }
        let mut new = Vec::with_capacity(fan.len());
        let mut worst = f64::INFINITY;
        for &f in fan {
            let t = self.triangles[f as usize];
            if t.contains(&z) {
                continue;
            }
            let moved = t.map(|x| if x == v { z } else { x });
            let (old_normal, new_normal) = (
                triangle_normal(t.map(|x| self.at(x))),
                triangle_normal(moved.map(|x| self.at(x))),
            );
            if dot(old_normal, new_normal) <= 0.0 {
                return None;
            }
            let corners = moved.map(|x| self.at(x));
            // The fan's corners of this face stay within `delta` of the new triangle's plane.
            let flat = (fan.iter())
                .filter(|&&g| self.group[g as usize] == self.group[f as usize])
                .flat_map(|&g| self.triangles[g as usize])
                .all(|x| plane_distance(corners, self.at(x)) <= delta);
            if !flat {
                return None;
            }
            worst = worst.min(triangle_shape(corners));
            new.push((f, moved));
        }
        Some((worst, new))
    }

    /// The edited mesh, its unused vertices dropped, with the moved flags carried over and
    /// the vertices of new triangles marked; every triangle records its group's provenance.
    fn into_rounded(self, faces: &mut Faces, moved: &[bool], rounded: usize) -> Rounded {
        let positions = self.positions;
        let mut new_id = vec![u32::MAX; positions.len()];
        let mut out_positions = Vec::new();
        let mut out_moved = Vec::new();
        let mut corners = Vec::with_capacity(3 * self.triangles.len());
        let mut provenance = Vec::with_capacity(self.triangles.len());
        for (f, t) in self.triangles.iter().enumerate() {
            if !self.alive[f] {
                continue;
            }
            for &v in t {
                if new_id[v as usize] == u32::MAX {
                    new_id[v as usize] = out_positions.len() as u32;
                    out_positions.push(positions[v as usize]);
                    out_moved.push(moved[v as usize] || self.changed[v as usize]);
                }
                corners.push(new_id[v as usize]);
            }
            let root = faces.groups.find(self.group[f]);
            provenance.push(faces.numbering.provenance(root));
        }
        let mesh = Mesh::from_parts(MeshParts {
            positions: out_positions,
            corners,
            face_provenance: Some(provenance),
            ..MeshParts::default()
        })
        .expect("simplified triangles index their own vertices");
        Rounded {
            mesh,
            moved: out_moved,
            rounded,
        }
    }
}

/// Whether `v` is within `delta` of the segment from `u` to `w`, strictly between them.
fn on_segment(u: [f64; 3], v: [f64; 3], w: [f64; 3], delta: f64) -> bool {
    let (d, e) = (sub(w, u), sub(v, u));
    let length2 = dot(d, d);
    let along = dot(e, d);
    if length2 == 0.0 || along <= 0.0 || along >= length2 {
        return false;
    }
    let c = cross(d, e);
    dot(c, c) <= delta * delta * length2
}

/// The distance from `p` to the plane of `t` (infinite for a degenerate `t`).
fn plane_distance(t: [[f64; 3]; 3], p: [f64; 3]) -> f64 {
    let n = triangle_normal(t);
    let length = dot(n, n).sqrt();
    if length == 0.0 {
        return f64::INFINITY;
    }
    dot(n, sub(p, t[0])).abs() / length
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{FaceId, OperandId};

    /// The unit cube as triangles, with the top face fanned around a centre raised by
    /// `lift`, and the front bottom edge split at a midpoint moved out by `lift`: each face
    /// its own provenance.
    fn cube_with_extra_vertices(lift: f64) -> Mesh {
        let mut positions: Vec<[f64; 3]> = (0..8)
            .map(|i| [0, 1, 2].map(|k| f64::from((i >> k) & 1)))
            .collect();
        positions.push([0.5, 0.5, 1.0 + lift]); // 8: centre of the top
        positions.push([0.5, -lift, 0.0]); // 9: on the edge from 0 to 1
        let triangles: Vec<[u32; 3]> = vec![
            [0, 4, 6],
            [0, 6, 2], // x = 0
            [1, 3, 7],
            [1, 7, 5], // x = 1
            [0, 9, 5],
            [0, 5, 4],
            [9, 1, 5], // y = 0, split at 9
            [2, 6, 7],
            [2, 7, 3], // y = 1
            [0, 2, 9],
            [9, 2, 3],
            [9, 3, 1], // z = 0, split at 9
            [4, 5, 8],
            [5, 7, 8],
            [7, 6, 8],
            [6, 4, 8], // z = 1, fanned at 8
        ];
        let provenance = (0..triangles.len())
            .map(|f| Provenance {
                operand: OperandId::new(0),
                face: FaceId::new(f),
            })
            .collect();
        Mesh::from_parts(MeshParts {
            positions,
            corners: triangles.concat(),
            face_provenance: Some(provenance),
            ..MeshParts::default()
        })
        .expect("a valid mesh")
    }

    fn simplified(lift: f64, delta: f64) -> (Mesh, usize) {
        let mesh = cube_with_extra_vertices(lift);
        let rounded = Rounded {
            moved: vec![false; mesh.vertex_count()],
            mesh: mesh.clone(),
            rounded: 0,
        };
        let (out, removed) = simplify(rounded, &[&mesh], delta);
        (out.mesh, removed)
    }

    #[test]
    fn vertices_off_flat_faces_by_less_than_the_tolerance_go() {
        let (mesh, removed) = simplified(1e-13, 1e-9);
        assert_eq!(removed, 2);
        assert_eq!(mesh.vertex_count(), 8);
        assert_eq!(mesh.face_count(), 12);
        let report = mesh.report();
        assert!(report.is_valid_solid());
        assert!((report.measures.volume - 1.0).abs() < 1e-12);
    }

    #[test]
    fn vertices_farther_than_the_tolerance_stay() {
        let (mesh, removed) = simplified(1e-6, 1e-9);
        assert_eq!(removed, 0);
        assert_eq!(mesh.vertex_count(), 10);
    }

    #[test]
    fn faces_flat_to_within_the_tolerance_share_a_provenance() {
        let (mesh, _) = simplified(1e-13, 1e-9);
        let provenance = mesh.face_provenance().expect("provenance");
        let mut faces: Vec<Provenance> = provenance.to_vec();
        faces.sort_unstable();
        faces.dedup();
        assert_eq!(faces.len(), 6, "one provenance per side of the cube");
    }
}
