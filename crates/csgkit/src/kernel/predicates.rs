//! Predicates with explicit and implicit arguments.
//!
//! Each is a [`Formula`](super::cascade::Formula) of `formulas`, decided by the cascade
//! (filter, expansions, big integers; see the [module docs](super)); the sign of the
//! polynomial is then multiplied by the signs of the points' `W`s, known exactly since
//! construction. All-explicit arguments take the `robust` fast path of [`orient2d`] and
//! [`orient3d`], and some configurations are decided by construction (a point on a plane or
//! a line that defines it).

use std::cmp::Ordering;

use super::cascade::{decide, decide_proof_first, filter};
use super::formulas::{AxisDiff, Det3, Det4, PlaneSide};
use super::implicit::{Point, Point3};
use super::nearby;
use super::{Axis, Sign, normal_component_is_zero, orient2d, orient3d, side_of_axis_plane};

/// Which side of the plane of the explicit triangle `a, b, c` the point `d` lies on.
///
/// Same convention as [`orient3d`]: [`Sign::Positive`] below the plane (opposite to the
/// normal `(b - a) × (c - a)`), [`Sign::Negative`] above, [`Sign::Zero`] on it; also
/// [`Sign::Zero`] for every `d` when the triangle is degenerate. The workhorse of the
/// intersect stage (an implicit point against the other triangle's plane).
pub fn orient3d_plane(a: Point3, b: Point3, c: Point3, d: &Point) -> Sign {
    if let Point::Explicit(p) = d {
        return orient3d(a, b, c, *p);
    }
    if d.defined_on_plane_of(&[a, b, c]) {
        // Exact by construction, and the most common query of the intersect stage: a
        // crossing point against the triangle that made it. Saves the exact stages.
        return Sign::Zero;
    }
    // A triangle in an axis plane and a point whose coordinate there its definition fixes
    // (a crossing on a face of a box, on the common top of two cubes turned about z): a
    // comparison, where the point is often on the plane and only the exact stages could
    // prove the zero.
    let axis_plane = [Axis::X, Axis::Y, Axis::Z].into_iter().find(|axis| {
        let k = axis.index();
        a[k] == b[k] && a[k] == c[k]
    });
    if let Some((axis, x)) =
        axis_plane.and_then(|axis| Some((axis, d.known_coordinate(axis.index())?)))
    {
        let turn = orient2d(axis.project(a), axis.project(b), axis.project(c));
        return side_of_axis_plane(a[axis.index()], x, turn);
    }
    if let Some(sign) = nearby::orient3d(a, b, c, &d.nearby()) {
        return sign;
    }
    // A crossing of an edge that lies in the plane (a face's own edge, met by a box turned
    // about it) is on the plane by its definition: two exact orientations of the edge's ends
    // prove the zero at a fraction of the exact stages' cost, asked only where the filter on
    // the nearby coordinates cannot decide.
    let on_edge_in_plane = || match d {
        Point::Lpi(l) => {
            let (p, q, _) = l.definition();
            orient3d(a, b, c, p) == Sign::Zero && orient3d(a, b, c, q) == Sign::Zero
        }
        _ => false,
    };
    decide_proof_first(&PlaneSide { tri: [a, b, c], d }, on_edge_in_plane).times(d.w_sign())
}

/// [`orient3d`] with any mix of explicit and implicit points: which side of the plane through
/// `a, b, c` the point `d` lies on (positive below, negative above, zero when the four points
/// are coplanar, see [`orient3d`]).
pub fn orient3d_points(a: &Point, b: &Point, c: &Point, d: &Point) -> Sign {
    if let (Point::Explicit(a), Point::Explicit(b), Point::Explicit(c)) = (a, b, c) {
        return orient3d_plane(*a, *b, *c, d);
    }
    // One implicit point among a, b, c and an explicit d: swapping two points flips the
    // sign, and the plane form is cheaper than the 4 × 4 determinant.
    if let Point::Explicit(e) = d {
        match (a, b, c) {
            (x, Point::Explicit(b), Point::Explicit(c)) => {
                return orient3d_plane(*e, *b, *c, x).flip();
            }
            (Point::Explicit(a), x, Point::Explicit(c)) => {
                return orient3d_plane(*a, *e, *c, x).flip();
            }
            (Point::Explicit(a), Point::Explicit(b), x) => {
                return orient3d_plane(*a, *b, *e, x).flip();
            }
            _ => {}
        }
    }
    let w = a
        .w_sign()
        .times(b.w_sign())
        .times(c.w_sign())
        .times(d.w_sign());
    decide(&Det4([a, b, c, d])).times(w)
}

/// [`orient2d`] of the projections of `a, b, c` after dropping coordinate `drop`.
///
/// The kept coordinates are taken in cyclic order — `(y, z)` for `X`, `(z, x)` for `Y`,
/// `(x, y)` for `Z` — so the result is the sign of component `drop` of the normal
/// `(b - a) × (c - a)`: positive when the triangle is counterclockwise seen from the positive
/// `drop` axis. Splitting a face with normal `n` in 2D with `drop = Axis::of_largest(n)`
/// therefore keeps orientations when `n[drop] > 0` and flips them all when `n[drop] < 0`.
pub fn orient2d_projected(a: &Point, b: &Point, c: &Point, drop: Axis) -> Sign {
    orient2d_projected_or_collinear(a, b, c, drop, || false)
}

/// [`orient2d_projected`], asking `collinear` only when the interval filter cannot decide: the
/// caller's structural proof that the three points lie on one line (the sign is then zero),
/// cheaper there than the exact stages and never asked where the filter decides.
pub fn orient2d_projected_or_collinear(
    a: &Point,
    b: &Point,
    c: &Point,
    drop: Axis,
    collinear: impl FnOnce() -> bool,
) -> Sign {
    match projected(a, b, c, drop) {
        Projected::Explicit(sign) => sign,
        Projected::Implicit(det, w) => {
            if let Some(sign) = orient2d_nearby(a, b, c, drop) {
                return sign;
            }
            let proven = || {
                on_an_axis_line(a, b, c, [det.u, det.v])
                    || collinear_by_construction(a, b, c)
                    || on_a_projected_line(a, b, c, drop)
                    || collinear()
            };
            decide_proof_first(&det, proven).times(w)
        }
    }
}

/// [`orient2d_projected`] of explicit points, answered; of others, the determinant to decide
/// and the sign its answer is multiplied by (the product of the points' `W` signs).
enum Projected<'p> {
    Explicit(Sign),
    Implicit(Det3<'p>, Sign),
}

/// The shared first step of [`orient2d_projected_or_collinear`] and
/// [`orient2d_projected_if_clear`].
fn projected<'p>(a: &'p Point, b: &'p Point, c: &'p Point, drop: Axis) -> Projected<'p> {
    if let (Point::Explicit(a), Point::Explicit(b), Point::Explicit(c)) = (a, b, c) {
        return Projected::Explicit(orient2d(
            drop.project(*a),
            drop.project(*b),
            drop.project(*c),
        ));
    }
    let k = drop.index();
    let det = Det3 {
        pts: [a, b, c],
        u: (k + 1) % 3,
        v: (k + 2) % 3,
    };
    Projected::Implicit(det, a.w_sign().times(b.w_sign()).times(c.w_sign()))
}

/// True when the three points have one [`Point::known_coordinate`] on one of the projection's
/// axes `axes`: in the projection they lie on that axis line.
fn on_an_axis_line(a: &Point, b: &Point, c: &Point, axes: [usize; 2]) -> bool {
    axes.into_iter().any(|k| {
        let Some(x) = a.known_coordinate(k) else {
            return false;
        };
        b.known_coordinate(k) == Some(x) && c.known_coordinate(k) == Some(x)
    })
}

/// True when two of the points are explicit and the third is an [`Lpi`](super::Lpi) whose
/// line's ends both project onto the line through the two (exact [`orient2d`] of explicit
/// points): the projection of that line, so of the point, lies on it. A crossing on a
/// triangle's edge line, where the crossing edge is another edge along that line (a
/// T-junction, a long edge beside short ones), is of this kind.
fn on_a_projected_line(a: &Point, b: &Point, c: &Point, drop: Axis) -> bool {
    let ((x, y), lpi) = match (a, b, c) {
        (Point::Explicit(x), Point::Explicit(y), Point::Lpi(l))
        | (Point::Explicit(x), Point::Lpi(l), Point::Explicit(y))
        | (Point::Lpi(l), Point::Explicit(x), Point::Explicit(y)) => ((x, y), l),
        _ => return false,
    };
    let (s, t, _) = lpi.definition();
    let (x, y) = (drop.project(*x), drop.project(*y));
    orient2d(x, y, drop.project(s)) == Sign::Zero && orient2d(x, y, drop.project(t)) == Sign::Zero
}

/// [`orient2d_projected`] where it is cheap to know: the exact sign of explicit points, the
/// interval filter's sign of others, `None` where only the exact stages could tell. For
/// choices a caller may decline when the answer is not at hand (an optional flip), so that
/// nearly degenerate configurations cost nothing there.
pub fn orient2d_projected_if_clear(a: &Point, b: &Point, c: &Point, drop: Axis) -> Option<Sign> {
    match projected(a, b, c, drop) {
        Projected::Explicit(sign) => Some(sign),
        Projected::Implicit(det, w) => {
            orient2d_nearby(a, b, c, drop).or_else(|| filter(&det).map(|s| s.times(w)))
        }
    }
}

/// [`orient2d_projected`] where the points' [`Nearby`](nearby::Nearby) coordinates decide it:
/// tried before the homogeneous filter, being both far cheaper and sharper for close points
/// (see `nearby.rs`).
#[inline]
fn orient2d_nearby(a: &Point, b: &Point, c: &Point, drop: Axis) -> Option<Sign> {
    let k = drop.index();
    // Three calls rather than an array `map`, which copied the three through a temporary.
    let (a, b, c) = (a.nearby(), b.nearby(), c.nearby());
    nearby::orient2d(&a, &b, &c, (k + 1) % 3, (k + 2) % 3)
}

/// True when the three points lie on one line by definition: some point is an
/// [`Lpi`](super::Lpi) and each is an endpoint of its line or another point defined on that
/// line. The split stage asks this of the intersection points along a triangle's edge (all
/// of them on the edge's line), and the answer saves the exact stages.
fn collinear_by_construction(a: &Point, b: &Point, c: &Point) -> bool {
    let line = [a, b, c].into_iter().find_map(|p| match p {
        Point::Lpi(l) => {
            let (s, t, _) = l.definition();
            Some([s, t])
        }
        _ => None,
    });
    let Some(line) = line else { return false };
    let on_line = |p: &Point| match p {
        Point::Explicit(x) => line.contains(x),
        Point::Lpi(l) => {
            let (s, t, _) = l.definition();
            line.contains(&s) && line.contains(&t) && s != t
        }
        Point::Tpi(_) => false,
    };
    on_line(a) && on_line(b) && on_line(c)
}

/// Order of `a` and `b` by their coordinate on `axis` (`Less` when `a`'s is smaller).
pub fn compare_along(a: &Point, b: &Point, axis: Axis) -> Ordering {
    let i = axis.index();
    if let (Some(x), Some(y)) = (a.known_coordinate(i), b.known_coordinate(i)) {
        // `partial_cmp` treats -0 and +0 as equal; NaN is excluded by precondition.
        return x.partial_cmp(&y).unwrap_or(Ordering::Equal);
    }
    if let Some(order) = nearby::compare_coordinate(&a.nearby(), &b.nearby(), i) {
        return order;
    }
    let w = a.w_sign().times(b.w_sign());
    let proven = || on_one_axis_parallel_line(a, b, axis);
    decide_proof_first(&AxisDiff { a, b, axis: i }, proven)
        .times(w)
        .to_ordering()
}

/// True when `a` and `b` lie, by their definitions, on one line parallel to a coordinate axis
/// `m` other than `i`, so that their coordinates `i` are equal: both have the same
/// [`Point::known_coordinate`] `j` (the third axis), and a plane that defines both contains
/// the direction of axis `m` but not that of axis `i` (so it meets the plane of coordinate `j`
/// in a line along `m`). Two crossings on the vertical face of a cube turned about z, whose
/// lines lie in a face of the other cube, are of this kind: exact zeros that the filters
/// cannot see and that cost the exact stages thousands of instructions each.
fn on_one_axis_parallel_line(a: &Point, b: &Point, i: Axis) -> bool {
    const AXES: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];
    AXES.into_iter().filter(|&j| j != i).any(|j| {
        // The third axis: the indices of the three sum to 3.
        let m = AXES[3 - i.index() - j.index()];
        let same_known = match (a.known_coordinate(j.index()), b.known_coordinate(j.index())) {
            (Some(x), Some(y)) => x == y,
            _ => false,
        };
        same_known
            && a.defining_planes().any(|plane| {
                b.defined_on_plane_of(&plane)
                    && normal_component_is_zero(&plane, m)
                    && !normal_component_is_zero(&plane, i)
            })
    })
}

/// Lexicographic order of `a` and `b`: by x, then y, then z. A total order on points
/// (equal exactly when [`same_point`]), for sorting points along a segment or deduplicating.
pub fn compare_lex(a: &Point, b: &Point) -> Ordering {
    compare_along(a, b, Axis::X)
        .then_with(|| compare_along(a, b, Axis::Y))
        .then_with(|| compare_along(a, b, Axis::Z))
}

/// True when `a` and `b` are the same point of space, whatever their definitions.
pub fn same_point(a: &Point, b: &Point) -> bool {
    compare_lex(a, b) == Ordering::Equal
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::oracle::oracle_point;

    /// Two crossings on a face of a cube turned by 1e-7 rad about z (rotated_z_intersection):
    /// the lines of a face of the unit cube (y = -0.5) against the turned cube's vertical
    /// face. Their x is equal, which the filters cannot see; the vertical plane proves it.
    /// With the plane tilted off the vertical, nothing is proven and the answer still matches
    /// the exact rationals.
    #[test]
    fn crossings_on_one_vertical_line_compare_equal_by_definition() {
        let vertical = [
            [-0.49999994999999753, -0.5000000499999975, -0.5],
            [0.5000000499999975, -0.49999994999999753, 0.5],
            [-0.49999994999999753, -0.5000000499999975, 0.5],
        ];
        let mut tilted = vertical;
        tilted[2][0] = -0.4999999;
        for (plane, proven) in [(vertical, true), (tilted, false)] {
            let [r, s, t] = plane;
            let a = Point::lpi([-0.5, -0.5, -0.5], [0.5, -0.5, 0.5], r, s, t).unwrap();
            let b = Point::lpi([0.5, -0.5, 0.5], [-0.5, -0.5, 0.5], r, s, t).unwrap();
            assert_eq!(on_one_axis_parallel_line(&a, &b, Axis::X), proven);
            for axis in [Axis::X, Axis::Y, Axis::Z] {
                let k = axis.index();
                let want = oracle_point(&a)[k].cmp(&oracle_point(&b)[k]);
                assert_eq!(
                    compare_along(&a, &b, axis),
                    want,
                    "{axis:?}, proven {proven}"
                );
            }
        }
    }
}
