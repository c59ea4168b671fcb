//! Thin layers between opposite faces: a step of the [certify](super) stage.
//!
//! A chain of booleans through files puts an operand's faces back against the result's pieces
//! of them: `(A ∪ B) − B` meets B's faces twice, once as the pieces `A ∪ B` wrote (their
//! corners on the intersection curve rounded, within an ulp of B's planes) and once as B's own
//! faces, reversed. Where such a corner was rounded in front of B's plane (rounding inward
//! finds no point behind every plane around it where a fan of long, nearly coplanar faces
//! meets B), the exact difference keeps the material between the piece and B's face: a layer
//! thinner than an ulp, bounded by two faces of opposite orientation, and as wide as the
//! piece, attached to the rest of the solid along the curve (so it is no closed shell that
//! [`thin_shells`](super::thin_shells) could remove). Its new corners, where the pieces cross
//! B's plane, round behind B (inside the solid the second time), its old ones stay in front:
//! the layer folds through itself, and since its old corners are input vertices of this
//! boolean, re-refining the folded soup computes the same layer again, with new intersection
//! points that fold again. Re-rounding a single corner cannot help either: wherever it
//! goes, either the layer or the faces around the corner still cross.
//!
//! This step turns the layer inside out instead: for each pair of crossing faces that face
//! opposite ways, the corners of one that lie behind the other's plane, within a few ulps of
//! it, move to the nearest point of the output's precision in front of it (at most
//! [`REROUND_MAX_STEPS`](super::REROUND_MAX_STEPS) steps per coordinate). The material between
//! the two faces then has winding number −1, and the exact re-refinement (a union under the
//! positive winding rule) drops it, with the pieces of the faces around it, and computes
//! where the moved corners' other faces now cross. Of the two faces, the corners of the one
//! that has fewer of them behind the other move: a layer's old corners are few among the
//! rounded points of its base. A thin gap between two facing surfaces that crossed is closed
//! the same way round (the crossing part, behind both, moves in front). The surface moves by
//! less than the push, and the dropped layer was thinner than it.

use rustc_hash::{FxHashMap, FxHashSet};

use crate::kernel::{Point3, Precision, Sign, orient3d};
use crate::mesh::Mesh;
use crate::mesh::vector::{cross, dot, norm, sub};

use super::{REROUND_MAX_STEPS, grid_step, neighbours};

/// How far behind the plane of an opposite face a corner may lie to be pushed through it, in
/// ulps of the largest coordinate magnitude (as `log2`): a layer an ulp or two thick.
const PUSH_LEVEL: i32 = 2;

/// The corners to push through the planes of the opposite faces they cross among `pairs`
/// (see the module docs), each with its new position: the nearest point of `precision` in
/// front of every such plane, up to [`REROUND_MAX_STEPS`] steps per coordinate away (corners
/// with none stay). Sorted by vertex.
pub(super) fn pushes(
    mesh: &Mesh,
    pairs: &[(u32, u32)],
    precision: Precision,
) -> Vec<(u32, Point3)> {
    let corners = mesh.corners();
    let positions = mesh.positions();
    let tolerance = grid_step(positions, PUSH_LEVEL, precision);
    let face = |f: u32| {
        let c = &corners[3 * f as usize..3 * f as usize + 3];
        [c[0], c[1], c[2]]
    };
    let position = |v: u32| positions[v as usize];
    // The corners of `a` behind the plane of `b` and within the tolerance of it, when the two
    // face opposite ways, and the plane.
    let behind = |a: u32, b: u32| -> Option<(Vec<u32>, [Point3; 3])> {
        let (fa, fb) = (face(a), face(b));
        let (pa, pb) = (fa.map(position), fb.map(position));
        let normal = |p: [Point3; 3]| cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let (na, nb) = (normal(pa), normal(pb));
        // A direction to compare sides with, from f64 arithmetic, not a topological decision.
        if dot(na, nb) >= 0.0 {
            return None;
        }
        let length = norm(nb);
        let corners: Vec<u32> = (fa.iter().copied())
            .filter(|v| !fb.contains(v))
            .filter(|&v| {
                let p = position(v);
                orient3d(pb[0], pb[1], pb[2], p) == Sign::Positive
                    && (dot(nb, sub(p, pb[0])) / length).abs() <= tolerance
            })
            .collect();
        Some((corners, pb))
    };
    let mut planes_of: FxHashMap<u32, Vec<[Point3; 3]>> = FxHashMap::default();
    for &(f, g) in pairs {
        let (Some(first), Some(second)) = (behind(f, g), behind(g, f)) else {
            continue;
        };
        let fewer = match (first.0.len(), second.0.len()) {
            (0, 0) => continue,
            (a, b) if a != 0 && (b == 0 || a <= b) => first,
            _ => second,
        };
        let (moving, plane) = fewer;
        for v in moving {
            planes_of.entry(v).or_default().push(plane);
        }
    }
    let mut pushes: Vec<(u32, Point3)> = (planes_of.into_iter())
        .filter_map(|(v, planes)| {
            let in_front = |q: Point3| {
                (planes.iter()).all(|p| orient3d(p[0], p[1], p[2], q) == Sign::Negative)
            };
            (neighbours(position(v), REROUND_MAX_STEPS, precision).into_iter())
                .find(|&q| in_front(q))
                .map(|q| (v, q))
        })
        .collect();
    pushes.sort_unstable_by_key(|&(v, _)| v);
    pushes
}

/// The moved flags of `refined`, the re-refinement of `soup` (whose vertices it keeps where
/// they are): its new intersection points (`moved`), and the vertices that were moved in the
/// soup (`soup_moved`) or pushed into it. Those are input vertices of the re-refinement, but
/// not where the exact result has them, so their faces are checked, and a thin shell through
/// them goes at the end.
pub(super) fn moved_after(
    refined: &Mesh,
    mut moved: Vec<bool>,
    soup: &Mesh,
    soup_moved: &[bool],
    pushes: &[(u32, Point3)],
) -> Vec<bool> {
    let key = |p: Point3| p.map(|x| (x + 0.0).to_bits());
    let at: FxHashSet<[u64; 3]> = (soup.positions().iter().zip(soup_moved))
        .filter(|&(_, &m)| m)
        .map(|(&p, _)| key(p))
        .chain(pushes.iter().map(|&(_, q)| key(q)))
        .collect();
    for (v, &p) in refined.positions().iter().enumerate() {
        if at.contains(&key(p)) {
            moved[v] = true;
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::super::moved_to;
    use super::*;

    /// A triangle in the plane z = 16 facing down, and a small one facing up over it whose
    /// corner 3 lies `lift` steps of f64 above that plane and whose corners 4 and 5 lie `drop`
    /// steps below it: where the upper one is above the lower, the material between them is a
    /// layer at most `lift` ulps thick.
    fn layer(lift: i32, drop: i32) -> Mesh {
        let z = |steps: i32| Precision::F64.step_by(16.0, steps);
        let positions = vec![
            [-10.0, -10.0, 16.0],
            [-10.0, 30.0, 16.0],
            [30.0, -10.0, 16.0],
            [1.0, 1.0, z(lift)],
            [3.0, 0.5, z(-drop)],
            [0.5, 3.0, z(-drop)],
        ];
        Mesh::from_triangles(positions, &[[0, 1, 2], [3, 4, 5]]).expect("in range")
    }

    #[test]
    fn the_corner_behind_an_opposite_face_goes_in_front() {
        let mesh = layer(1, 1);
        let moves = pushes(&mesh, &[(0, 1)], Precision::F64);
        assert_eq!(moves.len(), 1);
        let (v, q) = moves[0];
        assert_eq!(v, 3);
        // The nearest point in front of the lower face: a step below its plane.
        assert_eq!(q, [1.0, 1.0, Precision::F64.step_by(16.0, -1)]);
        let (moved, displacement) = moved_to(mesh.clone(), &moves);
        assert_eq!(moved.positions()[3], q);
        assert!(displacement > 0.0);
        // In front of the lower face now, the upper one crosses nothing.
        assert!(pushes(&moved, &[(0, 1)], Precision::F64).is_empty());
    }

    #[test]
    fn corners_far_from_the_plane_or_faces_facing_one_way_stay() {
        // A crossing far thicker than the tolerance: no layer.
        assert!(pushes(&layer(64, 64), &[(0, 1)], Precision::F64).is_empty());
        // The lower face turned to face up like the other: no layer between them.
        let mut parts = layer(1, 1).into_parts();
        parts.corners.swap(1, 2);
        let mesh = Mesh::from_parts(parts).expect("in range");
        assert!(pushes(&mesh, &[(0, 1)], Precision::F64).is_empty());
    }
}
