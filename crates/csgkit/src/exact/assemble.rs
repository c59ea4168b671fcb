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
use smallvec::SmallVec;

use crate::kernel::{
    Axis, Point, Point3, Sign, compare_along, orient3d, round_point_with_offsets, step_by,
};
use crate::mesh::vector::{cross, dot, sub};
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
    // Per output vertex, the source triangles of the faces around it where it is an
    // intersection point (a few each, with repeats), in one pass of counts and one of fills.
    let mut starts = vec![0u32; used.len() + 1];
    for t in &faces.triangles {
        for &v in t.iter().filter(|&&v| v >= explicit_count) {
            starts[new_id[v as usize] as usize + 1] += 1;
        }
    }
    for i in 1..starts.len() {
        starts[i] += starts[i - 1];
    }
    let mut sources = vec![0u32; starts[used.len()] as usize];
    let mut next = starts.clone();
    for (t, &source) in faces.triangles.iter().zip(&faces.source) {
        for &v in t.iter().filter(|&&v| v >= explicit_count) {
            let slot = &mut next[new_id[v as usize] as usize];
            sources[*slot as usize] = source;
            *slot += 1;
        }
    }
    // An intersection point the split stage simplified to an explicit one is exact: only the
    // others move.
    let (positions, moved): (Vec<[f64; 3]>, Vec<bool>) = (used.par_iter().enumerate())
        .map(|(i, &v)| {
            let point = arr.point(input, v);
            let around = &sources[starts[i] as usize..starts[i + 1] as usize];
            let mut planes: SmallVec<[[Point3; 3]; 6]> = SmallVec::new();
            for (j, &t) in around.iter().enumerate() {
                if !around[..j].contains(&t) {
                    planes.push(input.triangle_positions(t as usize));
                }
            }
            let position = round_inward(&point, &planes).map(|x| x * unscale);
            (position, !point.is_explicit())
        })
        .unzip();
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

/// `point` rounded to f64: the nearest point if it lies on or behind every one of `planes`
/// (triangles through `point`, outward normals by their corners' order), else the first of
/// the f64 points up to [`INWARD_STEPS`] steps from it per coordinate, in [`INWARD_ORDER`],
/// that does, else the nearest (see the module docs); the points the f64 screen below passes
/// come first, so a nearest point the screen takes for in front by less than its error
/// yields to another that is behind. A coordinate `point` has exactly as an
/// f64 is kept, and none becomes newly subnormal: a step from 0 to ±5e-324 changes no shape a
/// reader can see, and readers whose predicates underflow there (Shewchuk's) take the faces
/// around for flat.
///
/// Every candidate is within an ulp or two of every plane, where `orient3d`'s filter cannot
/// decide and its exact stages run: the candidates are screened first in f64, by the planes'
/// normals against the candidate's offset from `point` (the rounding's offset, from
/// double-doubles, plus its steps), and only those the screen passes are tested exactly, then
/// the others if none of those is behind.
fn round_inward(point: &Point, planes: &[[Point3; 3]]) -> Point3 {
    if let Point::Explicit(exact) = point {
        return *exact;
    }
    let behind =
        |q: Point3| (planes.iter()).all(|&[a, b, c]| orient3d(a, b, c, q) != Sign::Negative);
    let (nearest, offsets) = round_point_with_offsets(point);
    // Per coordinate, the exact value minus the nearest: from double-doubles, or its sign
    // exactly where they cannot tell (0: the value is that f64).
    let at_nearest = Point::Explicit(nearest);
    let offset = [Axis::X, Axis::Y, Axis::Z].map(|axis| {
        offsets[axis.index()].unwrap_or_else(|| match compare_along(point, &at_nearest, axis) {
            std::cmp::Ordering::Less => -f64::MIN_POSITIVE,
            std::cmp::Ordering::Greater => f64::MIN_POSITIVE,
            std::cmp::Ordering::Equal => 0.0,
        })
    });
    let normals: SmallVec<[Point3; 6]> = (planes.iter())
        .map(|&[a, b, c]| cross(sub(b, a), sub(c, a)))
        .collect();
    // The candidate `steps` away (per coordinate, towards the exact value; negative: away
    // from it), and its f64 screen: every normal against its offset from `point`.
    let candidate = |steps: [i32; 3]| -> Option<(Point3, bool)> {
        let mut q = nearest;
        for k in 0..3 {
            if steps[k] == 0 {
                continue;
            }
            if offset[k] == 0.0 {
                return None;
            }
            // Towards the exact value is up where it lies above the nearest.
            q[k] = step_by(q[k], if offset[k] > 0.0 { steps[k] } else { -steps[k] });
            if q[k].is_subnormal() && !nearest[k].is_subnormal() {
                return None;
            }
        }
        let from_point = [0, 1, 2].map(|k| (q[k] - nearest[k]) - offset[k]);
        let screened = normals.iter().all(|&n| dot(n, from_point) <= 0.0);
        Some((q, screened))
    };
    let all = std::iter::once([0; 3]).chain(INWARD_ORDER.iter().copied());
    let screened = (all.clone().filter_map(candidate)).filter(|&(_, screened)| screened);
    let others = (all.filter_map(candidate)).filter(|&(_, screened)| !screened);
    (screened.chain(others))
        .map(|(q, _)| q)
        .find(|&q| behind(q))
        .unwrap_or(nearest)
}

/// The steps [`round_inward`] tries, per coordinate towards the exact value (negative: away
/// from it), in its order: fewest steps, then fewest coordinates moved away, then fewest
/// moved (the corners of the cell around the exact point first, those nearest the nearest
/// point first). Built once: the nearest point fails a plane for most points where three
/// surfaces meet.
static INWARD_ORDER: std::sync::LazyLock<Vec<[i32; 3]>> = std::sync::LazyLock::new(|| {
    let range = -INWARD_STEPS..=INWARD_STEPS;
    let mut order: Vec<[i32; 3]> = (range.clone())
        .flat_map(|x| range.clone().map(move |y| (x, y)))
        .flat_map(|(x, y)| range.clone().map(move |z| [x, y, z]))
        .filter(|&steps| steps != [0; 3])
        .collect();
    order.sort_by_key(|steps| {
        let farthest = steps.iter().map(|s| s.abs()).max().unwrap_or(0);
        let moved = steps.iter().filter(|&&s| s != 0).count();
        let away = steps.iter().filter(|&&s| s < 0).count();
        (farthest, away, moved)
    });
    order
});

/// How far [`round_inward`] looks from the nearest f64 point, in steps per coordinate: every
/// coordinate ends within `INWARD_STEPS + 1/2` ulps of the exact one. The corners of the
/// cell around the point lie within one step; where three surfaces meet (an edge of one
/// operand through a face of another), the cone behind all their planes often misses the
/// cell but reaches a point two steps out.
const INWARD_STEPS: i32 = 2;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::round_point;

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
            let rounded = round_inward(&point, &[plane]);
            assert!(behind(rounded), "{rounded:?} is in front of the plane");
            let (_, offsets) = round_point_with_offsets(&point);
            for k in 0..3 {
                // The exact coordinate lies between the nearest and the rounding, or the
                // rounding is the nearest.
                let exact_side = offsets[k].map(Sign::of);
                let moved = Sign::of(rounded[k] - nearest[k]);
                assert!(
                    moved == Sign::Zero
                        || (exact_side == Some(moved)
                            && (rounded[k] == step_by(nearest[k], 1)
                                || rounded[k] == step_by(nearest[k], -1))),
                    "{rounded:?} is outside the cell of {nearest:?}"
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
        // A crossing of an axis plane, also on a tilted plane through its line, taken both
        // ways round: z stays 0.5 exactly, and the rounding is behind each.
        let axis_plane = [[0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5]];
        let (p, q) = ([0.1, 0.2, 0.0], [0.4, 0.7, 1.3]);
        let point = crossing(p, q, axis_plane);
        let nearest = round_point(&point);
        assert_eq!(nearest[2], 0.5);
        let mut moved = 0;
        for tilted in [[p, q, [0.9, 0.1, 0.3]], [q, p, [0.9, 0.1, 0.3]]] {
            let rounded = round_inward(&point, &[axis_plane, tilted]);
            assert_eq!(rounded[2], 0.5);
            assert_ne!(
                orient3d(tilted[0], tilted[1], tilted[2], rounded),
                Sign::Negative
            );
            moved += usize::from(rounded != nearest);
        }
        assert!(
            moved >= 1,
            "the nearest point is in front of one of the two"
        );
    }
}
