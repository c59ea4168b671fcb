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
//! # Onto a corner nearby
//! A point within [`INWARD_STEPS`] ulps (of its largest coordinate) of a corner of a triangle
//! it lies on goes onto that corner, where the corner is on or behind every plane too and
//! keeps the coordinates the point has exactly. A
//! chain of booleans meets its own rounded points again. Split a solid in two, `(A ∪ B) − B`
//! and `A ∩ B`, and join the pieces back: the intersection's curve points are the union's
//! (the same exact points, rounded the same way), but the difference computes where the
//! union's pieces of A's faces, whose corners on the curve rounded behind B's planes, cross
//! B: new points an ulp or two from those corners. Rounded on their own, the two pieces'
//! seams differed by ulps, and the join kept a slit thinner than an ulp along the whole cut,
//! whose walls crossed everywhere once rounded (on a bunny through OBJ, 4,705 crossing pairs,
//! `NotCertified` after 18 s). Onto the corners, the pieces share their seam's vertices and
//! their cut faces cancel: the join certified in 1.9 s. The window is in ulps of the largest
//! coordinate, not of each: the exact point's error in a small coordinate is that of the
//! planes it is computed from, as large as in the others.
//!
//! Rounding moves intersection points by up to `INWARD_STEPS + 1/2` ulps of their largest
//! coordinate per coordinate, which in near-degenerate configurations makes two output faces
//! cross or a face collapse; the [`certify`] stage finds and repairs those, starting from the
//! vertices this stage marks as moved.
//!
//! [`certify`]: super::certify

use crate::par::*;
use smallvec::SmallVec;

use crate::kernel::{
    Axis, Point, Point3, Precision, Sign, compare_along, orient3d, round_point_with_offsets,
};
use crate::mesh::vector::{cross, dot, sub};
use crate::mesh::{Mesh, MeshParts};

use super::ingest::Input;
use super::reconstruct::Reconstructed;
use super::subdivide::Arrangement;

/// The output mesh in its precision, and which of its vertices need checking.
pub(crate) struct Rounded {
    pub mesh: Mesh,
    /// Per vertex: an intersection point moved by rounding (the only vertices where the
    /// rounded mesh may differ from the exact result: input vertices are numbers of its
    /// precision, and the triangles reconstruct made tile the exact result too).
    pub moved: Vec<bool>,
    /// How many vertices rounding moved.
    pub rounded: usize,
}

/// The mesh of the reconstructed triangles with coordinates of `precision`, its rounded
/// vertices marked.
pub(crate) fn assemble(
    input: &Input,
    arr: &Arrangement,
    faces: Reconstructed,
    precision: Precision,
) -> Rounded {
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
    // Only faces of split triangles have such corners: a few thousand of the 1.3 M faces of
    // two 1 M spheres' union, found on all threads.
    let with_intersection_points: Vec<u32> = (faces.triangles.par_iter().enumerate())
        .filter(|(_, t)| t.iter().any(|&v| v >= explicit_count))
        .map(|(f, _)| f as u32)
        .collect();
    let mut starts = vec![0u32; used.len() + 1];
    for &f in &with_intersection_points {
        for &v in faces.triangles[f as usize]
            .iter()
            .filter(|&&v| v >= explicit_count)
        {
            starts[new_id[v as usize] as usize + 1] += 1;
        }
    }
    for i in 1..starts.len() {
        starts[i] += starts[i - 1];
    }
    let mut sources = vec![0u32; starts[used.len()] as usize];
    let mut next = starts.clone();
    for &f in &with_intersection_points {
        let (t, source) = (faces.triangles[f as usize], faces.source[f as usize]);
        for &v in t.iter().filter(|&&v| v >= explicit_count) {
            let slot = &mut next[new_id[v as usize] as usize];
            sources[*slot as usize] = source;
            *slot += 1;
        }
    }
    let grid = Grid {
        precision,
        scale: input.scale,
    };
    // An intersection point the split stage simplified to an explicit one is exact: in f64,
    // only the others move.
    let (positions, moved): (Vec<[f64; 3]>, Vec<bool>) = (used.par_iter().enumerate())
        .map(|(i, &v)| {
            if v < explicit_count {
                // An input vertex: a number of the precision (see `round_inward`).
                let exact = input.positions[v as usize];
                if grid.holds_point(&exact) {
                    return (exact.map(|x| x * unscale), false);
                }
            }
            let point = arr.point(input, v);
            let around = &sources[starts[i] as usize..starts[i + 1] as usize];
            let mut planes: SmallVec<[[Point3; 3]; 6]> = SmallVec::new();
            for (j, &t) in around.iter().enumerate() {
                if !around[..j].contains(&t) {
                    planes.push(input.triangle_positions(t as usize));
                }
            }
            let rounded = round_inward(&point, &planes, &grid);
            let moved = match &*point {
                Point::Explicit(exact) => rounded != *exact,
                _ => true,
            };
            (rounded.map(|x| x * unscale), moved)
        })
        .unzip();
    let rounded = moved.iter().filter(|&&m| m).count();
    // Renumbered in place, then flattened without a copy.
    let mut triangles = faces.triangles;
    (triangles.par_iter_mut()).for_each(|t| *t = t.map(|v| new_id[v as usize]));
    let corners: Vec<u32> = triangles.into_flattened();
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

/// The numbers of the output's precision in the ingest's scaled coordinates: the scale is
/// an exact power of two, so a number of the precision, scaled, is one after scaling back.
struct Grid {
    precision: Precision,
    scale: f64,
}

impl Grid {
    /// See [`Precision::nearest`].
    fn nearest(&self, x: f64, exact_side: Sign) -> f64 {
        (self.precision).nearest(x / self.scale, exact_side) * self.scale
    }

    /// See [`Precision::step_by`].
    fn step_by(&self, x: f64, steps: i32) -> f64 {
        self.precision.step_by(x / self.scale, steps) * self.scale
    }

    /// See [`Precision::holds`].
    fn holds(&self, x: f64) -> bool {
        self.precision.holds(x / self.scale)
    }

    /// Whether the grid holds every coordinate of `p`: such a point stays as it is.
    fn holds_point(&self, p: &Point3) -> bool {
        p.iter().all(|&x| self.holds(x))
    }

    /// See [`Precision::is_subnormal`].
    fn is_subnormal(&self, x: f64) -> bool {
        self.precision.is_subnormal(x / self.scale)
    }
}

/// `point` rounded to `grid`: a corner of `planes` (triangles through `point`, outward
/// normals by their corners' order) near it ([`nearby_corner`]), else the nearest point if it
/// lies on or behind every one of `planes`, else the
/// first of the grid's points up to [`INWARD_STEPS`] steps from it per coordinate, in
/// [`INWARD_ORDER`], that does, else the nearest (see the module docs); the points the f64
/// screen below passes come first, so a nearest point the screen takes for in front by less
/// than its error yields to another that is behind. A coordinate `point` has exactly as a
/// number of the grid is kept, and none becomes newly subnormal: a step from 0 to ±5e-324
/// changes no shape a reader can see, and readers whose predicates underflow there
/// (Shewchuk's) take the faces around for flat. A point the grid holds stays (every input
/// vertex: in f32 the driver rounds the operands first).
///
/// Every candidate is within an ulp or two of every plane, where `orient3d`'s filter cannot
/// decide and its exact stages run: the candidates are screened first in f64, by the planes'
/// normals against the candidate's offset from `point` (the rounding's offset, from
/// double-doubles, plus its steps), and only those the screen passes are tested exactly, then
/// the others if none of those is behind.
fn round_inward(point: &Point, planes: &[[Point3; 3]], grid: &Grid) -> Point3 {
    if let Point::Explicit(exact) = point {
        if grid.holds_point(exact) {
            return *exact;
        }
    }
    let behind =
        |q: Point3| (planes.iter()).all(|&[a, b, c]| orient3d(a, b, c, q) != Sign::Negative);
    let (nearest_f64, offsets) = round_point_with_offsets(point);
    // Per coordinate, the exact value minus the nearest f64: from double-doubles, or its sign
    // exactly where they cannot tell (0: the value is that f64).
    let at_nearest = Point::Explicit(nearest_f64);
    let offset_f64 = [Axis::X, Axis::Y, Axis::Z].map(|axis| {
        offsets[axis.index()].unwrap_or_else(|| match compare_along(point, &at_nearest, axis) {
            std::cmp::Ordering::Less => -f64::MIN_POSITIVE,
            std::cmp::Ordering::Greater => f64::MIN_POSITIVE,
            std::cmp::Ordering::Equal => 0.0,
        })
    });
    // The nearest point of the grid, and the exact value minus it, with its sign certain: in
    // f32 the two nearest points differ by at least an f64 ulp, which outweighs the f64
    // offset (an f64 step placeholder included), or they are one point.
    let nearest: Point3 =
        std::array::from_fn(|k| grid.nearest(nearest_f64[k], Sign::of(offset_f64[k])));
    let offset: [f64; 3] = std::array::from_fn(|k| (nearest_f64[k] - nearest[k]) + offset_f64[k]);
    // Whether a coordinate of the rounding may be `x`: a coordinate the point has exactly (a
    // crossing on an axis plane) stays, and none becomes non-finite or newly subnormal.
    let may_take = |k: usize, x: f64| {
        x == nearest[k]
            || (offset[k] != 0.0
                && x.is_finite()
                && (!grid.is_subnormal(x) || grid.is_subnormal(nearest[k])))
    };
    if let Some(corner) = nearby_corner(planes, nearest, offset, grid, may_take, behind) {
        return corner;
    }
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
            // Towards the exact value is up where it lies above the nearest.
            q[k] = grid.step_by(q[k], if offset[k] > 0.0 { steps[k] } else { -steps[k] });
            if !may_take(k, q[k]) {
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

/// The corner of `planes` nearest the exact point (`nearest`, the grid's nearest point, plus
/// `offset`) among those within [`INWARD_STEPS`] steps of the grid at its largest coordinate
/// from `nearest` in every coordinate, that the grid holds, whose every coordinate `k` the
/// rounding `may_take`, and that are `behind` every plane (see the module docs, "Onto a
/// corner nearby").
fn nearby_corner(
    planes: &[[Point3; 3]],
    nearest: Point3,
    offset: [f64; 3],
    grid: &Grid,
    may_take: impl Fn(usize, f64) -> bool,
    behind: impl Fn(Point3) -> bool,
) -> Option<Point3> {
    let largest = nearest.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    // One step up from the largest coordinate is its ulp, at the top of a binade too.
    let reach = f64::from(INWARD_STEPS) * (grid.step_by(largest, 1) - largest);
    if !reach.is_finite() {
        return None;
    }
    let from_point = |c: &Point3| -> f64 {
        (0..3)
            .map(|k| ((c[k] - nearest[k]) - offset[k]).powi(2))
            .sum()
    };
    (planes.iter().flatten())
        .filter(|c| (0..3).all(|k| (c[k] - nearest[k]).abs() <= reach && may_take(k, c[k])))
        .filter(|&&c| grid.holds_point(&c) && behind(c))
        .min_by(|a, b| from_point(a).total_cmp(&from_point(b)))
        .copied()
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

    /// Rounding in `precision`, unscaled.
    fn grid(precision: Precision) -> Grid {
        Grid {
            precision,
            scale: 1.0,
        }
    }

    #[test]
    fn a_point_rounds_behind_its_planes_within_its_cell() {
        // A tilted plane, and lines across it at many places: whichever way the nearest point
        // of either precision falls, the rounding is on or behind the plane and within the
        // cell around the exact point (checked in rationals).
        use crate::kernel::oracle::{oracle_point, q};
        let plane = [[0.0, 0.0, 0.1], [1.0, 0.1, 0.3], [0.2, 1.0, 0.7]];
        let behind = |q: Point3| orient3d(plane[0], plane[1], plane[2], q) != Sign::Negative;
        for precision in [Precision::F64, Precision::F32] {
            let grid = grid(precision);
            let mut nearest_in_front = 0;
            for i in 0..200 {
                let t = f64::from(i) / 200.0;
                let point = crossing([t, 0.3 * t, -1.0], [0.7 - t, t, 2.0], plane);
                let exact = oracle_point(&point);
                let rounded = round_inward(&point, &[plane], &grid);
                assert!(behind(rounded), "{rounded:?} is in front of the plane");
                let mut nearest = rounded;
                for k in 0..3 {
                    assert!(
                        precision.holds(rounded[k]),
                        "{} is not {precision}",
                        rounded[k]
                    );
                    // The exact coordinate lies between the rounding and its neighbour on
                    // the exact side, and the nearer of the two is the nearest.
                    let x = &exact[k];
                    let (down, up) = (grid.step_by(rounded[k], -1), grid.step_by(rounded[k], 1));
                    let (low, high) = if *x >= q(rounded[k]) {
                        (rounded[k], up)
                    } else {
                        (down, rounded[k])
                    };
                    assert!(
                        q(low) <= *x && *x <= q(high),
                        "{rounded:?} is outside the cell"
                    );
                    nearest[k] = if x - q(low) <= q(high) - x { low } else { high };
                }
                nearest_in_front += usize::from(!behind(nearest));
            }
            assert!(
                nearest_in_front > 10,
                "in {precision}, the nearest point falls in front often: {nearest_in_front}"
            );
        }
    }

    #[test]
    fn a_point_an_ulp_from_a_corner_of_its_triangle_goes_onto_it() {
        // A slanted line through the plane an ulp (in x) beside its corner (1, 0.1, 0.3): the
        // crossing rounds onto the corner, not to its nearest f64 point; 256 ulps away, to a
        // point of its own. With a second plane through the line, the corner is taken only
        // where it is behind that plane too (one of its two orientations).
        let plane = [[0.0, 0.0, 0.1], [1.0, 0.1, 0.3], [0.2, 1.0, 0.7]];
        let corner = plane[1];
        // The plane's z over (x, y) rises by 1/7 per unit of x.
        let line = |dx: f64| {
            let on_plane = [1.0 + dx, 0.1, 0.3 + dx / 7.0];
            let along = [0.3, 0.2, 1.0];
            (
                [0, 1, 2].map(|k| on_plane[k] - along[k]),
                [0, 1, 2].map(|k| on_plane[k] + along[k]),
            )
        };
        let f64_grid = grid(Precision::F64);
        let (p, q) = line(f64::EPSILON);
        let near = crossing(p, q, plane);
        assert_ne!(round_point(&near), corner);
        assert_eq!(round_inward(&near, &[plane], &f64_grid), corner);
        let (p_far, q_far) = line(256.0 * f64::EPSILON);
        let far = round_inward(&crossing(p_far, q_far, plane), &[plane], &f64_grid);
        assert!(
            far[0] > 1.0 + 200.0 * f64::EPSILON,
            "{far:?} is not its own point"
        );
        let r = [2.0, 0.5, 0.0];
        let onto_corner = [[p, q, r], [q, p, r]]
            .map(|through_line| round_inward(&near, &[plane, through_line], &f64_grid) == corner);
        assert_eq!(onto_corner.iter().filter(|&&c| c).count(), 1);
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
            let rounded = round_inward(&point, &[axis_plane, tilted], &grid(Precision::F64));
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
        // A corner of a plane through the line, beside the point and an ulp below the axis
        // plane (so behind it): not taken, since the point's z is exact.
        let beside = [nearest[0], nearest[1], 0.5 - f64::EPSILON / 4.0];
        for tilted in [[p, q, beside], [q, p, beside]] {
            let rounded = round_inward(&point, &[axis_plane, tilted], &grid(Precision::F64));
            assert_eq!(rounded[2], 0.5);
        }
    }
}
