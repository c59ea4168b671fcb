//! Removal of the slivers that rounding folds: a step of the [certify](super) stage.
//!
//! The exact arrangement can hold triangles far thinner than the f64 grid: a *needle*, whose
//! apex lies within an ulp of its longest side (an intersection curve passing that close to a
//! vertex or an edge), or a triangle with a side a few ulps long (two intersection points that
//! close). Rounded, such a triangle's orientation is noise: it folds over its neighbours, and
//! no choice of nearby f64 points for its corners unfolds it, while snapping and
//! re-refining it makes new slivers of the same kind. It is removed instead, by the two local
//! changes of Manifold's topology cleanup (`CollapseShortEdges` and `SwapDegenerates` in its
//! `edge_op.cpp`), each accepted only when the exact pair test of the self-intersection check
//! says its new faces cross nothing around them:
//! - a side shorter than the tolerance is **collapsed**: one end (a rounded point rather than
//!   an input vertex) is replaced by the other, and the two faces on the side vanish;
//! - a needle **flips** its longest side with the face across it: the quadrilateral of the
//!   two faces gets its other diagonal, from the needle's apex, and the needle is gone.
//!
//! Both keep the mesh closed and consistently oriented: a collapse only where the link
//! condition holds (the ends share no neighbour but the two opposite corners, so no edge gets
//! a third face), a flip only where the new diagonal is not an edge yet. Neither moves a vertex
//! to a new position, so no new coincident vertex appears, and the surface moves by at most
//! the tolerance: a collapse by the collapsed side's length, a flip by the needle's height
//! (its apex is that close to the side it replaces).
//!
//! Written here rather than taken from a mesh-processing crate: the decision to accept a
//! change is csgkit's exact crossing test on f64 positions, which is the point of the step.

use rustc_hash::FxHashSet;

use crate::index::{Aabb, Bvh};
use crate::kernel::Point3;
use crate::mesh::{Mesh, Provenance};

use super::super::intersect::Triangle;
use super::super::self_intersect::pair_intersects;

/// What [`dissolve`] changed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Dissolved {
    /// Collapses and flips done.
    pub changes: usize,
    /// The largest distance the surface moved in one change (a collapsed side's length, a
    /// flipped needle's height).
    pub displacement: f64,
}

/// Collapses the sides shorter than the tolerance and flips the needles lower than it among
/// the faces around `vertices` (sorted), thinnest first, where the exact check allows it,
/// trying `tolerances` in order until one changes something; marks the vertices of every
/// changed face as moved, so the next check looks at them. `moved` is remapped with the mesh
/// when vertices go.
pub(super) fn dissolve(
    mesh: &mut Mesh,
    moved: &mut Vec<bool>,
    vertices: &[u32],
    tolerances: &[f64],
) -> Dissolved {
    let mut surface = Surface::new(mesh);
    let around: FxHashSet<u32> = (vertices.iter())
        .flat_map(|&v| surface.faces_of[v as usize].iter().copied())
        .collect();
    let mut done = Dissolved::default();
    for &tolerance in tolerances {
        let mut candidates: Vec<(f64, u32)> = (around.iter())
            .filter_map(|&f| {
                let thinness = surface.shape(f).thinness();
                (thinness < tolerance).then_some((thinness, f))
            })
            .collect();
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for (_, f) in candidates {
            if !surface.alive[f as usize] {
                continue;
            }
            let shape = surface.shape(f);
            let changed = surface
                .collapse_short_side(f, &shape, tolerance, moved)
                .or_else(|| (shape.height < tolerance).then(|| surface.flip_needle(f, &shape))?);
            if let Some((touched, displacement)) = changed {
                for v in touched {
                    moved[v as usize] = true;
                }
                done.changes += 1;
                done.displacement = done.displacement.max(displacement);
            }
        }
        if done.changes > 0 {
            break;
        }
    }
    if done.changes == 0 {
        return done;
    }
    let (compacted, remap) = surface.into_mesh();
    *mesh = compacted;
    let mut kept = vec![false; mesh.vertex_count()];
    for (v, &to) in remap.iter().enumerate() {
        if let Some(to) = to {
            kept[to as usize] = moved[v];
        }
    }
    *moved = kept;
    done
}

/// The f64 shape of a triangle: its sides' lengths (side `i` from corner `i` to `i + 1`) and
/// its height over the longest side.
struct Shape {
    sides: [f64; 3],
    height: f64,
}

impl Shape {
    fn of(p: [Point3; 3]) -> Shape {
        let sides = [0, 1, 2].map(|i| length(sub(p[(i + 1) % 3], p[i])));
        let longest = sides.iter().copied().fold(0.0, f64::max);
        let doubled_area = length(cross(sub(p[1], p[0]), sub(p[2], p[0])));
        let height = if longest > 0.0 {
            doubled_area / longest
        } else {
            0.0
        };
        Shape { sides, height }
    }

    /// The smaller of the height and the shortest side: how far the triangle is from
    /// collapsing.
    fn thinness(&self) -> f64 {
        self.sides.iter().copied().fold(self.height, f64::min)
    }

    fn longest_side(&self) -> usize {
        (0..3)
            .max_by(|&i, &j| self.sides[i].total_cmp(&self.sides[j]))
            .unwrap_or(0)
    }
}

/// A triangle mesh open to local changes: faces are killed and appended, never edited.
struct Surface {
    positions: Vec<Point3>,
    faces: Vec<[u32; 3]>,
    alive: Vec<bool>,
    provenance: Option<Vec<Provenance>>,
    /// Every face that ever used each vertex, dead ones included (filtered on use).
    faces_of: Vec<Vec<u32>>,
    /// The boxes of the faces the mesh came with; faces appended since are in `faces` after
    /// `indexed`.
    tree: Bvh,
    indexed: usize,
}

impl Surface {
    fn new(mesh: &Mesh) -> Surface {
        let parts = mesh.parts();
        debug_assert!(
            parts.face_starts.is_none(),
            "the exact engine writes triangles"
        );
        let faces: Vec<[u32; 3]> = (parts.corners.chunks_exact(3))
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let mut faces_of = vec![Vec::new(); parts.positions.len()];
        for (f, face) in faces.iter().enumerate() {
            for &v in face {
                faces_of[v as usize].push(f as u32);
            }
        }
        let positions = parts.positions.clone();
        let tree = Bvh::build_with(faces.len(), |f| {
            Aabb::from_points(faces[f].iter().map(|&v| &positions[v as usize]))
        });
        Surface {
            alive: vec![true; faces.len()],
            indexed: faces.len(),
            positions,
            faces,
            provenance: parts.face_provenance.clone(),
            faces_of,
            tree,
        }
    }

    fn corners(&self, face: [u32; 3]) -> [Point3; 3] {
        face.map(|v| self.positions[v as usize])
    }

    fn shape(&self, f: u32) -> Shape {
        Shape::of(self.corners(self.faces[f as usize]))
    }

    fn live_faces_of(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        (self.faces_of[v as usize].iter())
            .copied()
            .filter(|&f| self.alive[f as usize])
    }

    /// Collapses the shortest side of `f` if it is shorter than `tolerance`, moving a rounded
    /// end onto the other end first; returns the vertices of the new faces and the side's
    /// length.
    fn collapse_short_side(
        &mut self,
        f: u32,
        shape: &Shape,
        tolerance: f64,
        moved: &[bool],
    ) -> Option<(Vec<u32>, f64)> {
        let face = self.faces[f as usize];
        let mut sides: Vec<usize> = (0..3).filter(|&i| shape.sides[i] < tolerance).collect();
        sides.sort_by(|&i, &j| shape.sides[i].total_cmp(&shape.sides[j]));
        for i in sides {
            let (a, b) = (face[i], face[(i + 1) % 3]);
            // The exact result's own vertices stay where they are when a rounded one can go.
            let order = if moved[a as usize] && !moved[b as usize] {
                [(a, b), (b, a)]
            } else {
                [(b, a), (a, b)]
            };
            for (gone, kept) in order {
                if let Some(touched) = self.collapse(gone, kept) {
                    return Some((touched, shape.sides[i]));
                }
            }
        }
        None
    }

    /// Replaces vertex `gone` by `kept` where the link condition and the exact check allow;
    /// returns the vertices of the new faces.
    fn collapse(&mut self, gone: u32, kept: u32) -> Option<Vec<u32>> {
        let around: Vec<u32> = self.live_faces_of(gone).collect();
        let (shared, rest): (Vec<u32>, Vec<u32>) =
            (around.iter()).partition(|&&f| self.faces[f as usize].contains(&kept));
        if shared.len() != 2 {
            return None;
        }
        let opposite: FxHashSet<u32> = (shared.iter())
            .flat_map(|&f| self.faces[f as usize])
            .filter(|&v| v != gone && v != kept)
            .collect();
        let ring = |v: u32| -> FxHashSet<u32> {
            (self.live_faces_of(v))
                .flat_map(|f| self.faces[f as usize])
                .filter(|&u| u != v)
                .collect()
        };
        let common: FxHashSet<u32> = ring(gone).intersection(&ring(kept)).copied().collect();
        if opposite.len() != 2 || common != opposite {
            return None;
        }
        let replaced: Vec<(u32, [u32; 3])> = (rest.iter())
            .map(|&f| {
                let face = self.faces[f as usize].map(|v| if v == gone { kept } else { v });
                (f, face)
            })
            .collect();
        // A face that turns over crosses nothing next to it, yet is a fold: each keeps the
        // side its normal points to.
        let keeps_facing = replaced.iter().all(|&(f, face)| {
            let before = normal(self.corners(self.faces[f as usize]));
            dot(before, normal(self.corners(face))) > 0.0
        });
        let new: Vec<[u32; 3]> = replaced.iter().map(|&(_, face)| face).collect();
        if !keeps_facing || !self.fits(&new, &around) {
            return None;
        }
        let sources: Vec<u32> = replaced.iter().map(|&(f, _)| f).collect();
        self.replace(&around, &new, &sources);
        let mut touched: Vec<u32> = new.iter().flatten().copied().collect();
        touched.sort_unstable();
        touched.dedup();
        Some(touched)
    }

    /// Flips the longest side of the needle `f` with the face across it; returns the four
    /// corners and the needle's height.
    fn flip_needle(&mut self, f: u32, shape: &Shape) -> Option<(Vec<u32>, f64)> {
        let face = self.faces[f as usize];
        let i = shape.longest_side();
        let (a, b, apex) = (face[i], face[(i + 1) % 3], face[(i + 2) % 3]);
        let across: Vec<u32> = (self.live_faces_of(a))
            .filter(|&g| g != f && self.faces[g as usize].contains(&b))
            .collect();
        let &[g] = across.as_slice() else {
            return None;
        };
        let other = self.faces[g as usize];
        let j = (0..3).find(|&j| other[j] == b && other[(j + 1) % 3] == a)?;
        let far = other[(j + 2) % 3];
        let diagonal_exists = far == apex
            || self
                .live_faces_of(apex)
                .any(|h| self.faces[h as usize].contains(&far));
        if diagonal_exists {
            return None;
        }
        let new = [[apex, a, far], [b, apex, far]];
        // Flips only raise the lower height of the pair, so they never cycle.
        let lower = |faces: &[[u32; 3]]| {
            (faces.iter())
                .map(|&face| Shape::of(self.corners(face)).height)
                .fold(f64::INFINITY, f64::min)
        };
        if lower(&new) <= lower(&[face, other]) {
            return None;
        }
        // The needle's normal is rounding noise; the face across it says which way is out.
        let outward = normal(self.corners(other));
        let keeps_facing = new
            .iter()
            .all(|&face| dot(outward, normal(self.corners(face))) > 0.0);
        if !keeps_facing || !self.fits(&new, &[f, g]) {
            return None;
        }
        self.replace(&[f, g], &new, &[g, g]);
        Some((vec![a, b, apex, far], shape.height))
    }

    /// Whether `new` faces, replacing `removed`, are non-degenerate and cross no live face
    /// around them nor each other (the self-intersection check's rules).
    fn fits(&self, new: &[[u32; 3]], removed: &[u32]) -> bool {
        let Some(new): Option<Vec<Triangle>> = (new.iter().enumerate())
            .map(|(k, &face)| Triangle::new(u32::MAX - k as u32, face, self.corners(face)))
            .collect()
        else {
            return false;
        };
        let bounds = (new.iter().map(|t| Aabb::from_points(t.positions().iter())))
            .reduce(|a, b| a.union(&b))
            .expect("at least one new face");
        let mut others: Vec<u32> = Vec::new();
        self.tree.visit_overlapping(&bounds, |f| others.push(f));
        others.extend((self.indexed as u32..self.faces.len() as u32).filter(|&f| {
            let b = Aabb::from_points(self.corners(self.faces[f as usize]).iter());
            b.overlaps(&bounds)
        }));
        let others = (others.into_iter())
            .filter(|&f| self.alive[f as usize] && !removed.contains(&f))
            .filter_map(|f| {
                let face = self.faces[f as usize];
                Triangle::new(f, face, self.corners(face))
            });
        for other in others {
            if new.iter().any(|t| pair_intersects(t, &other)) {
                return false;
            }
        }
        (new.iter().enumerate()).all(|(k, t)| new[k + 1..].iter().all(|u| !pair_intersects(t, u)))
    }

    /// Kills `removed` and appends `new`, each with the provenance of its `sources` face.
    fn replace(&mut self, removed: &[u32], new: &[[u32; 3]], sources: &[u32]) {
        for &f in removed {
            self.alive[f as usize] = false;
        }
        for (&face, &source) in new.iter().zip(sources) {
            let id = self.faces.len() as u32;
            self.faces.push(face);
            self.alive.push(true);
            if let Some(provenance) = self.provenance.as_mut() {
                provenance.push(provenance[source as usize]);
            }
            for v in face {
                self.faces_of[v as usize].push(id);
            }
        }
    }

    /// The live faces as a mesh without the vertices no face uses, and where each old vertex
    /// went.
    fn into_mesh(self) -> (Mesh, Vec<Option<u32>>) {
        let mut remap: Vec<Option<u32>> = vec![None; self.positions.len()];
        let mut positions = Vec::new();
        let mut corners = Vec::new();
        let mut provenance = self.provenance.as_ref().map(|_| Vec::new());
        for (f, face) in self.faces.iter().enumerate() {
            if !self.alive[f] {
                continue;
            }
            for &v in face {
                let id = *remap[v as usize].get_or_insert_with(|| {
                    positions.push(self.positions[v as usize]);
                    positions.len() as u32 - 1
                });
                corners.push(id);
            }
            if let (Some(out), Some(source)) = (provenance.as_mut(), self.provenance.as_ref()) {
                out.push(source[f]);
            }
        }
        let parts = crate::mesh::MeshParts {
            positions,
            corners,
            face_provenance: provenance,
            ..Default::default()
        };
        let mesh = Mesh::from_parts(parts).expect("live faces use live vertices");
        (mesh, remap)
    }
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(u: Point3, v: Point3) -> Point3 {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

fn dot(u: Point3, v: Point3) -> f64 {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}

fn length(u: Point3) -> f64 {
    dot(u, u).sqrt()
}

/// The (unnormalised) normal of a triangle, from f64 arithmetic: a direction to compare
/// sides with, not a decision of topology.
fn normal(p: [Point3; 3]) -> Point3 {
    cross(sub(p[1], p[0]), sub(p[2], p[0]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::self_intersections;
    use crate::mesh::analyze_topology;

    /// The tetrahedron `A B C D` (A at the origin, the others on the axes) whose bottom face
    /// `B A C` is split at `v` (vertex 4), a point near the side `B A`, with the needle
    /// `A v B` between that side and the path `B v A`.
    fn tetrahedron_with_needle(v: Point3) -> Mesh {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            v,
        ];
        let (a, b, c, d, v) = (0, 1, 2, 3, 4);
        let faces = [
            [a, b, d],
            [a, d, c],
            [b, c, d],
            [b, v, c],
            [v, a, c],
            [a, v, b],
        ];
        Mesh::from_triangles(positions, &faces).expect("in range")
    }

    fn assert_valid(mesh: &Mesh) {
        assert!(self_intersections(mesh).is_empty());
        let topology = analyze_topology(mesh);
        assert_eq!(topology.unbalanced_edges, 0);
        assert!(topology.is_closed());
    }

    #[test]
    fn a_folded_needle_is_flipped_away() {
        // v is 1e-17 outside the bottom face, so the needle A v B faces inwards and lies
        // over the two faces beside it; flipping B A to v D removes it.
        let mut mesh = tetrahedron_with_needle([0.5, -1e-17, 0.0]);
        assert!(!self_intersections(&mesh).is_empty());
        let mut moved = vec![false; 5];
        let done = dissolve(&mut mesh, &mut moved, &[4], &[1e-15]);
        assert_eq!(done.changes, 1);
        assert!(done.displacement > 0.0 && done.displacement < 1e-16);
        assert_eq!((mesh.vertex_count(), mesh.face_count()), (5, 6));
        assert_valid(&mesh);
        assert_eq!(moved, [true, true, false, true, true]);
    }

    #[test]
    fn a_side_shorter_than_the_tolerance_is_collapsed() {
        // v is 1e-17 from A, across the side A C: the face v A C turns over onto B v C; v
        // goes into A and the two faces on the side v A vanish.
        let mut mesh = tetrahedron_with_needle([-1e-17, 1e-17, 0.0]);
        assert!(!self_intersections(&mesh).is_empty());
        let mut moved = vec![false, false, false, false, true];
        let done = dissolve(&mut mesh, &mut moved, &[4], &[1e-15]);
        assert_eq!(done.changes, 1);
        assert_eq!((mesh.vertex_count(), mesh.face_count()), (4, 4));
        assert_valid(&mesh);
        assert_eq!(moved.len(), 4);
    }

    #[test]
    fn faces_thicker_than_the_tolerance_stay() {
        let mut mesh = tetrahedron_with_needle([0.5, -1e-17, 0.0]);
        let before = mesh.clone();
        let mut moved = vec![false; 5];
        assert_eq!(dissolve(&mut mesh, &mut moved, &[4], &[1e-18]).changes, 0);
        assert_eq!(mesh, before);
    }
}
