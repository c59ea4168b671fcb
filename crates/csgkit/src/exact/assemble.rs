//! The **assemble** stage (`design/exact.md`, stage 8): the output mesh.
//!
//! Vertices the kept sub-triangles use keep their relative order (input vertices first); an
//! intersection point is rounded to f64 here, once, and every coordinate is scaled back by the
//! inverse of the ingest power of two (exact). Each face records its provenance: the operand
//! and the original face it lies on.
//!
//! # Rounding inward
//! An intersection point lies on the planes of the input triangles its faces come from (at
//! least one of each operand whose surfaces meet there), and is rounded to an f64 point on or
//! behind every one of those planes, in the closed inside of each operand's surface there: the
//! nearest f64 point when it is, else the nearest such point up to [`INWARD_STEPS`] steps
//! from it per coordinate (the corners of the f64 cell around the exact point first). A chain
//! of booleans through files meets these vertices again: `(A ∪ B) − B`, `(A − B) ∪ B` and
//! `(A ∩ B) − B` put B's faces back against the result's pieces of them, which are B's
//! triangles with rounded corners. A corner rounded in front of B's plane leaves a slab
//! between the piece and B's face, thinner than an ulp and as wide as the piece, that the
//! exact engine keeps (it is there) and no f64 rounding of its own corners can write
//! without folding; a corner on or behind it puts the piece inside closed B, where the next
//! boolean removes it whole or keeps B's face instead. Coordinates an f64 holds exactly (a
//! crossing on an axis plane) stay exact. Where no point that near is behind every plane
//! (three surfaces meeting at a sharp angle), the nearest point is taken.
//!
//! Rounding moves intersection points by up to `INWARD_STEPS + 1/2` ulps per coordinate,
//! which in near-degenerate configurations makes two output faces cross or a face collapse;
//! the [`certify`] stage finds and repairs those, starting from the vertices this stage marks
//! as moved.
//!
//! [`certify`]: super::certify

use crate::par::*;

use crate::kernel::{
    Axis, Point, Point3, Sign, compare_along, next_down, next_up, orient3d, round_point,
};
use crate::mesh::{Mesh, MeshParts};

use super::ingest::Input;
use super::reconstruct::Reconstructed;
use super::subdivide::Arrangement;

/// The output mesh in f64, and which of its vertices need checking.
pub(crate) struct Rounded {
    pub mesh: Mesh,
    /// Per vertex: an intersection point rounded to f64 (the only vertices where the f64 mesh
    /// may differ from the exact result; the triangles reconstruct made tile the exact result
    /// too).
    pub moved: Vec<bool>,
    /// How many vertices are intersection points rounded to f64.
    pub rounded: usize,
}

/// The mesh of the reconstructed triangles, with its rounded vertices marked.
pub(crate) fn assemble(input: &Input, arr: &Arrangement, faces: Reconstructed) -> Rounded {
    // Used vertices keep their relative order (input vertices, then intersection points), so
    // the numbering is deterministic and every step but the marking runs in parallel.
    let mut new_id = vec![u32::MAX; arr.vertex_count(input)];
    for t in &faces.triangles {
        for &v in t {
            new_id[v as usize] = 0;
        }
    }
    let mut used = Vec::new();
    for (v, id) in new_id.iter_mut().enumerate() {
        if *id == 0 {
            *id = used.len() as u32;
            used.push(v as u32);
        }
    }
    let explicit_count = input.positions.len() as u32;
    let unscale = 1.0 / input.scale;
    // (output vertex, input triangle) for every intersection point and the source triangle of
    // each face around it, sorted by vertex.
    let ids = &new_id;
    let mut planes: Vec<(u32, u32)> = (faces.triangles.par_iter().zip(&faces.source))
        .flat_map_iter(|(t, &source)| {
            (t.iter())
                .filter(|&&v| v >= explicit_count)
                .map(move |&v| (ids[v as usize], source))
        })
        .collect();
    planes.par_sort_unstable();
    planes.dedup();
    let positions: Vec<[f64; 3]> = (used.par_iter().enumerate())
        .map(|(i, &v)| {
            let point = arr.point(input, v);
            let i = i as u32;
            let around = &planes
                [planes.partition_point(|&(w, _)| w < i)..planes.partition_point(|&(w, _)| w <= i)];
            let behind = |q: Point3| {
                around.iter().all(|&(_, t)| {
                    let [a, b, c] = input.triangle(t as usize).positions();
                    orient3d(a, b, c, q) != Sign::Negative
                })
            };
            round_inward(&point, behind).map(|x| x * unscale)
        })
        .collect();
    // An intersection point the split stage simplified to an explicit one is exact.
    let moved: Vec<bool> = (used.par_iter())
        .map(|&v| v >= explicit_count && !arr.point(input, v).is_explicit())
        .collect();
    let rounded = moved.iter().filter(|&&m| m).count();
    let corners: Vec<u32> = (faces.triangles.par_iter())
        .flat_map_iter(|t| t.map(|v| new_id[v as usize]))
        .collect();
    let mesh = Mesh::from_parts(MeshParts {
        positions,
        corners,
        face_provenance: Some(faces.provenance),
        ..MeshParts::default()
    })
    .expect("reconstructed triangles index their own vertices");
    Rounded {
        mesh,
        moved,
        rounded,
    }
}

/// `point` rounded to f64: the nearest point if `behind` accepts it, else the nearest of the
/// f64 points up to [`INWARD_STEPS`] steps from it in each coordinate that `behind` accepts
/// (fewest steps first, then fewest coordinates moved, then towards `point`: the corners of
/// the f64 cell around it before the points beyond), else the nearest (see the module docs).
/// A coordinate `point` has exactly as an f64 is kept, and none becomes newly subnormal: a
/// step from 0 to ±5e-324 changes no shape a reader can see, and readers whose predicates
/// underflow there (Shewchuk's) take the faces around for flat.
fn round_inward(point: &Point, behind: impl Fn(Point3) -> bool) -> Point3 {
    let nearest = round_point(point);
    if point.is_explicit() || behind(nearest) {
        return nearest;
    }
    // Per coordinate, the direction of the exact value from the nearest (0: it is an f64).
    let at_nearest = Point::Explicit(nearest);
    let towards =
        [Axis::X, Axis::Y, Axis::Z].map(|axis| match compare_along(point, &at_nearest, axis) {
            std::cmp::Ordering::Less => -1,
            std::cmp::Ordering::Greater => 1,
            std::cmp::Ordering::Equal => 0,
        });
    let stepped = |k: usize, steps: i32| {
        let mut x = nearest[k];
        for _ in 0..steps.unsigned_abs() {
            x = if steps > 0 { next_up(x) } else { next_down(x) };
        }
        (!x.is_subnormal() || nearest[k].is_subnormal()).then_some(x)
    };
    let range = -INWARD_STEPS..=INWARD_STEPS;
    let mut candidates: Vec<([i32; 3], (i32, usize, usize))> = Vec::new();
    for dx in range.clone() {
        for dy in range.clone() {
            for dz in range.clone() {
                let steps = [dx, dy, dz];
                if steps == [0; 3] || (0..3).any(|k| towards[k] == 0 && steps[k] != 0) {
                    continue;
                }
                let farthest = steps.iter().map(|s| s.abs()).max().unwrap_or(0);
                let moved = steps.iter().filter(|&&s| s != 0).count();
                let away = (0..3).filter(|&k| steps[k] * towards[k] < 0).count();
                candidates.push((steps, (farthest, moved, away)));
            }
        }
    }
    candidates.sort_by_key(|&(_, key)| key);
    (candidates.iter())
        .filter_map(|&(steps, _)| {
            Some([
                stepped(0, steps[0])?,
                stepped(1, steps[1])?,
                stepped(2, steps[2])?,
            ])
        })
        .find(|&q| behind(q))
        .unwrap_or(nearest)
}

/// How far [`round_inward`] looks from the nearest f64 point, in steps per coordinate: every
/// coordinate ends within `INWARD_STEPS + 1/2` ulps of the exact one. The corners of the
/// cell around the point lie within one step; where three surfaces meet (an edge of one
/// operand through a face of another), the cone behind all their planes often misses the
/// cell but reaches a point two steps out.
const INWARD_STEPS: i32 = 2;

#[cfg(test)]
mod tests {
    use super::*;

    /// The point where the line from `p` to `q` meets the plane of `plane`.
    fn crossing(p: Point3, q: Point3, plane: [Point3; 3]) -> Point {
        Point::lpi(p, q, plane[0], plane[1], plane[2]).expect("the line crosses the plane")
    }

    #[test]
    fn a_point_rounds_behind_its_planes_within_its_cell() {
        // A tilted plane, and lines across it at many places: whichever way the nearest f64
        // point falls, the rounding is on or behind the plane and within the cell around it.
        let plane = [[0.0, 0.0, 0.1], [1.0, 0.1, 0.3], [0.2, 1.0, 0.7]];
        let behind = |q: Point3| orient3d(plane[0], plane[1], plane[2], q) != Sign::Negative;
        let mut nearest_in_front = 0;
        for i in 0..200 {
            let t = f64::from(i) / 200.0;
            let point = crossing([t, 0.3 * t, -1.0], [0.7 - t, t, 2.0], plane);
            let nearest = round_point(&point);
            nearest_in_front += usize::from(!behind(nearest));
            let rounded = round_inward(&point, behind);
            assert!(behind(rounded), "{rounded:?} is in front of the plane");
            for k in 0..3 {
                let step =
                    (next_up(nearest[k]) - nearest[k]).max(nearest[k] - next_down(nearest[k]));
                assert!(
                    (rounded[k] - nearest[k]).abs() <= step,
                    "{rounded:?} vs {nearest:?}"
                );
            }
        }
        assert!(
            nearest_in_front > 10,
            "the nearest point falls in front often: {nearest_in_front}"
        );
    }

    #[test]
    fn coordinates_an_f64_holds_stay() {
        // An axis plane: every crossing keeps z = 0.5 exactly, whatever `behind` asks.
        let plane = [[0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5]];
        let point = crossing([0.1, 0.2, 0.0], [0.4, 0.7, 1.3], plane);
        let rounded = round_inward(&point, |q| q[0] > 1.0);
        assert_eq!(rounded, round_point(&point));
        assert_eq!(rounded[2], 0.5);
        let moved = round_inward(&point, |q| q != round_point(&point));
        assert_eq!(moved[2], 0.5);
        assert_ne!(moved, round_point(&point));
    }
}
