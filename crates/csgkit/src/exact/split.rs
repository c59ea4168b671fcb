//! The **split** stage of the exact engine (`design/exact.md`, stage 5): the exact constrained
//! triangulation of one input triangle with the intersection points and segments lying on it.
//!
//! # Contract
//! In: the triangle's three explicit corners (in its orientation), extra points (kernel
//! [`Point`]s, explicit or implicit, each in the closed triangle and exactly on its plane) and
//! constraint segments as pairs of vertex ids. **Vertex ids** number the corners `0, 1, 2` and
//! `points[i]` as `3 + i`; segments and output use them.
//!
//! Out ([`Split`]): triangles that cover the input triangle exactly once, each oriented like
//! the input triangle, with every distinct point as a vertex and every segment a union of
//! output edges. A point on an edge of the triangle splits that edge, so the neighbour across
//! it, given the same point, stays conforming (no T-junction).
//!
//! A point equal to a corner or to an earlier point (by exact comparison) is *merged*: it
//! appears in no triangle, segments naming it use the earlier vertex, and [`Split::merged`]
//! reports the pair. Callers that deduplicate by canonical keys never see this; it makes the
//! stage total on geometrically coincident points with different keys.
//!
//! # Algorithm
//! 1. **Projection** ([`Projection::new`]): drop the coordinate [`Axis::of_largest`] of the
//!    f64 normal, confirmed exactly by [`orient2d_projected`] on the corners (another axis if
//!    that sign is zero, [`SplitError::DegenerateTriangle`] if all are). If the corners turn
//!    clockwise in that projection, every orientation is flipped, so the input triangle is
//!    counterclockwise in the 2D frame and "positive" means "oriented like the input".
//! 2. **Points**: start from the one triangle `0, 1, 2`; insert each point after locating it
//!    ([`Location`]) by a walk from the last created triangle (a visibility walk, with a step
//!    limit and a linear scan behind it, since visibility walks may cycle in non-Delaunay
//!    triangulations — Devillers, Pion & Teillaud 2002, "Walking in a triangulation"). Inside
//!    a triangle: split it in three. On an edge: split the edge and both triangles beside it
//!    (one on the boundary). On a vertex: merge.
//! 3. **Segments**, one at a time from its first vertex `v` toward its end `b`: find the
//!    triangle around `v` whose angle at `v` contains the direction to `b`. If `b` lies along
//!    one of its edges, that edge is part of the segment: constrain it and continue from its
//!    other vertex (this also splits a segment at every vertex it passes through exactly).
//!    Otherwise walk across the triangles the segment crosses, collecting the vertices left
//!    and right of it, until it reaches `b` or passes exactly through a vertex `e`; remove the
//!    crossed triangles, triangulate the two pseudo-polygons on either side of `v e` by ear
//!    clipping, constrain `v e`, and continue from `e` (Anglada 1997, "An improved
//!    incremental algorithm for constructing restricted Delaunay triangulations", without the
//!    Delaunay choice of vertex; spade's `cdt.rs` has the same structure).
//! 4. Crossing a constrained edge in step 3 means two segments cross at a point that is not a
//!    vertex: [`SplitError::ConstraintsCross`]. The crossing is representable (the
//!    [`Tpi`](crate::kernel::Tpi) of the triangle's plane and the planes that carry the two
//!    segments), but segments do not carry their planes yet; the intersect stage is expected
//!    to report such crossings as points.
//!
//! # Invariants
//! [`Cdt::check_invariants`] (run by the tests and by `debug_assert!` at the end): every
//! triangle has distinct vertices and positive orientation; neighbour links are symmetric
//! across the same edge in opposite directions; an edge's constraint mark is the same on
//! both sides; every vertex that is not merged has a triangle in `vtri` that contains it. Points are all inserted before any segment, so no point insertion splits a
//! constrained edge.
//!
//! # Numeric model
//! Only [`orient2d_projected`] decides, on explicit or implicit points; no coordinate is ever
//! rounded or computed. Where its filter cannot decide, three points on one cut (all on the
//! plane of a triangle not parallel to this one, by how they are defined) are collinear
//! without the exact stages ([`orient2d_projected_or_collinear`]), as are three points of
//! which two are one. The f64 normal only chooses the projection axis; any axis where the
//! exact orientation of the corners is nonzero gives the same answers (up to the global flip).
//! Delaunay flips, a choice of shape, are taken only where the filter alone proves the
//! quadrilateral convex ([`orient2d_projected_if_clear`]); the flips that remove flat
//! triangles decide it exactly.
//!
//! # Complexity
//! With `n` points and `m` segments: point location is a walk (expected short for inserted
//! points near each other), linear scan in the worst case, so `O(n^2)` worst. Each segment
//! step rotates around its current vertex (`O(degree)`, from the triangle per vertex kept in
//! `vtri`) and walks the crossed triangles; ear clipping a pseudo-polygon of `k` vertices
//! costs `O(k^2)` orientation tests when its ears follow each other (a fan), `O(k^3)` at
//! worst, and `k` is small unless a segment crosses many edges. The common case (0–4 points,
//! a few segments) allocates the triangle vector, the id maps (`alias`, `vtri`), the output,
//! and a few short-lived vectors per segment; point insertion itself reuses scratch buffers.

use crate::kernel::{
    Axis, Point, Point3, Sign, approx_point, incircle_value_if_clear, normal_component_is_zero,
    orient2d_projected, orient2d_projected_if_clear, orient2d_projected_or_collinear,
    orient2d_value_if_clear, orient3d, orient3d_plane,
};

#[cfg(test)]
mod tests;

/// More points than this on one triangle are inserted in coordinate order and get Delaunay
/// flips before its segments go in.
const DELAUNAY_BEFORE_SEGMENTS: usize = 8;

/// The Delaunay phase's choice for the quadrilateral `[a, b, c, d]` (see
/// [`Cdt::flip_while`]): flip `b c` to `a d` when `d` is clearly inside the circle of `a b c`
/// and no triangle of the pair is flat.
///
/// The in-circle test is the f64 filter alone, not `robust::incircle`: the choice needs no
/// exact answer (the points are approximations, and either diagonal of four points on a
/// circle is Delaunay), and the cocircular quadrilaterals of grid parts (the squares of a
/// Menger sponge) sent every test to its adaptive stages, which clear some 9 KB of buffers
/// per call. Flipping only on certain signs still ends: each flip is a Lawson flip by the
/// exact answer for these points.
///
/// The in-circle test comes first and the four flatness tests only where it asks for a flip:
/// most quadrilaterals a Lawson pass visits are already Delaunay, and the answer is the same
/// in either order (every test can only refuse).
fn delaunay_flip([pa, pb, pc, pd]: [[f64; 2]; 4]) -> bool {
    let (Some(turn), Some(inside)) = (
        orient2d_value_if_clear(pa, pb, pc),
        incircle_value_if_clear(pa, pb, pc, pd),
    ) else {
        return false;
    };
    inside * turn > 0.0
        && !(is_flat(pa, pb, pc)
            || is_flat(pb, pd, pc)
            || is_flat(pa, pb, pd)
            || is_flat(pa, pd, pc))
}

/// How [`Cdt::flip_while`] decides that a quadrilateral is strictly convex, so that its
/// diagonal may be flipped.
#[derive(Clone, Copy)]
enum Convexity {
    /// Exactly, whatever it costs: for flips that remove flat triangles.
    Exact,
    /// Only where the kernel's filter decides; a quadrilateral it cannot judge keeps its
    /// diagonal. For the Delaunay flips, which only improve shapes: nearly degenerate
    /// quadrilaterals are where their in-circle tests on approximations flip back and forth,
    /// and each flip there cost two exact orientation tests (pair_cray_difference spent two
    /// thirds of its time on 1660 such flips in one triangle).
    IfClear,
}

/// "No triangle" (a boundary edge's neighbour) and "not constrained".
const NONE: u32 = u32::MAX;

/// The result of [`split_triangle`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Split {
    /// The output triangles, as vertex ids (corners `0, 1, 2`, then `3 + i` for point `i`),
    /// each oriented like the input triangle.
    pub triangles: Vec<[u32; 3]>,
    /// `[merged, kept]` vertex ids: each point equal to an earlier vertex, and that vertex.
    /// Usually empty (no allocation).
    pub merged: Vec<[u32; 2]>,
}

/// Why a triangle could not be split.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SplitError {
    /// The corners are collinear (exactly), so the triangle has no plane to project on.
    ///
    /// *How to fix*: ingest removes exactly degenerate triangles; do not split them.
    #[error("the triangle is degenerate (its corners are collinear)")]
    DegenerateTriangle,
    /// A point is not in the closed triangle (in the projection): a precondition violation.
    #[error("point {point} lies outside the triangle")]
    PointOutside {
        /// The vertex id of the point (`3 + i` for `points[i]`).
        point: u32,
    },
    /// A segment names a vertex id beyond the corners and points.
    #[error("segment {segment} names a vertex that does not exist")]
    SegmentOutOfRange {
        /// The index of the segment.
        segment: usize,
    },
    /// Two segments cross at a point that is not one of the points.
    ///
    /// *What to try*: add the crossing point (a [`Tpi`](crate::kernel::Tpi) of the triangle's
    /// plane and the two segments' planes) to the points and split both segments there.
    #[error("segments {first} and {second} cross at a point that is not a vertex")]
    ConstraintsCross {
        /// The segment inserted first.
        first: usize,
        /// The segment whose insertion met the first.
        second: usize,
    },
}

/// Triangulates the triangle `corners` with `points` on it and the constraint `segments`:
/// the split stage of the exact engine.
///
/// Vertex ids number the corners `0, 1, 2` and `points[i]` as `3 + i`; `segments` and the
/// output use them. Every point must lie in the closed triangle, exactly on its plane. The
/// output triangles cover the triangle once, are oriented like it, use every distinct point as
/// a vertex (a point on an edge splits it) and contain every segment as a chain of edges. A
/// point equal to an earlier vertex is merged into it and reported in [`Split::merged`].
///
/// # Example
/// A segment across the triangle, from a point on one edge to an implicit point (an edge of
/// another mesh crossing the triangle):
/// ```
/// use csgkit::kernel::Point;
/// let tri = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
/// let x = Point::lpi([1.0, 1.0, -1.0], [1.0, 2.0, 2.0], tri[0], tri[1], tri[2]).unwrap();
/// let points = [Point::Explicit([2.0, 0.0, 0.0]), x];
/// let split = csgkit::split_triangle(tri, &points, &[[3, 4]]).unwrap();
/// // Two points, one on the boundary: 2 * 2 - 1 + 1 triangles.
/// assert_eq!(split.triangles.len(), 4);
/// assert!(split.triangles.iter().any(|t| t.contains(&3) && t.contains(&4)));
/// ```
///
/// # Errors
/// [`SplitError::DegenerateTriangle`] for collinear corners, [`SplitError::PointOutside`]
/// when a point is outside the closed triangle, [`SplitError::SegmentOutOfRange`] for a bad
/// vertex id, [`SplitError::ConstraintsCross`] when two segments cross away from the points.
pub fn split_triangle(
    corners: [Point3; 3],
    points: &[Point],
    segments: &[[u32; 2]],
) -> Result<Split, SplitError> {
    let cdt = Cdt::build(corners, points, segments)?;
    debug_assert_eq!(cdt.check_invariants(), Ok(()));
    Ok(cdt.into_split())
}

/// The 2D frame: which coordinate is dropped and whether orientations flip.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Projection {
    drop: Axis,
    flip: bool,
    /// The triangle's corners, when explicit: for the structural collinearity test.
    corners: Option<[Point3; 3]>,
}

impl Projection {
    /// The projection in which `corners` are counterclockwise, or `None` if they are
    /// collinear.
    pub(crate) fn new(corners: &[Point; 3]) -> Option<Projection> {
        let f = |i: usize| approx_point(&corners[i]);
        let (a, b, c) = (f(0), f(1), f(2));
        let (u, v) = (sub(b, a), sub(c, a));
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let first = Axis::of_largest(n);
        let axes = [first, Axis::X, Axis::Y, Axis::Z];
        axes.into_iter().find_map(|drop| {
            match orient2d_projected(&corners[0], &corners[1], &corners[2], drop) {
                Sign::Zero => None,
                s => Some(Projection {
                    drop,
                    flip: s == Sign::Negative,
                    corners: match corners {
                        [Point::Explicit(a), Point::Explicit(b), Point::Explicit(c)] => {
                            Some([*a, *b, *c])
                        }
                        _ => None,
                    },
                }),
            }
        })
    }

    /// Orientation of `a, b, c` in the frame: positive when turning like the input triangle.
    pub(crate) fn orient(&self, a: &Point, b: &Point, c: &Point) -> Sign {
        let on_a_cut = || self.on_another_plane(a, b, c);
        let s = orient2d_projected_or_collinear(a, b, c, self.drop, on_a_cut);
        if self.flip { s.flip() } else { s }
    }

    /// [`Projection::orient`] where the kernel's filter decides it, `None` elsewhere.
    fn orient_if_clear(&self, a: &Point, b: &Point, c: &Point) -> Option<Sign> {
        let s = orient2d_projected_if_clear(a, b, c, self.drop)?;
        Some(if self.flip { s.flip() } else { s })
    }

    /// True when `a, b, c` lie on the plane of some triangle `π` other than this one: all
    /// three are on both planes, so on their common line. `π` is a plane that defines one of
    /// them, or the plane through the line of one of them and a point that defines another.
    /// Points along one cut are of this kind (the ends of a crossing lie on the other
    /// triangle's plane, or on its edges, or on the edges of a triangle coplanar with it, as
    /// where a planar quad is split in two, or on the edges of both triangles of such a quad),
    /// and such exactly collinear triples would otherwise go to the slow exact stages of the
    /// kernel. Asked only where the kernel's filter cannot decide, so the exact tests on
    /// explicit points here cost little.
    fn on_another_plane(&self, a: &Point, b: &Point, c: &Point) -> bool {
        let Some(own) = self.corners else {
            return false;
        };
        let points = [a, b, c];
        let candidates =
            (points.iter().flat_map(|p| p.defining_planes())).chain(plane_through_lines(&points));
        candidates
            .into_iter()
            .any(|plane| !same_plane(&plane, &own) && points.iter().all(|p| lies_on(p, &plane)))
    }
}

/// The plane through the line of the first line–plane point among `points` and the first
/// input point that defines another of them (a vertex, an end of its line) off that line:
/// the plane that holds all three lines when they are edges of one planar face. One
/// candidate, not every pairing, as this is asked of every triple the filter cannot decide,
/// most of them not collinear at all.
fn plane_through_lines(points: &[&Point; 3]) -> Option<[Point3; 3]> {
    let (index, (s, t, _)) = points.iter().enumerate().find_map(|(i, p)| match p {
        Point::Lpi(l) => Some((i, l.definition())),
        _ => None,
    })?;
    let anchors = |p: &Point| -> [Option<Point3>; 2] {
        match p {
            Point::Explicit(x) => [Some(*x), None],
            Point::Lpi(l) => {
                let (s, t, _) = l.definition();
                [Some(s), Some(t)]
            }
            Point::Tpi(_) => [None, None],
        }
    };
    let others = (points.iter().enumerate()).filter(|&(i, _)| i != index);
    let x = (others.flat_map(|(_, p)| anchors(p)).flatten()).find(|x| !collinear(&s, &t, x))?;
    Some([s, t, x])
}

/// True when three input points lie on one line (exactly: their normal is zero).
fn collinear(a: &Point3, b: &Point3, c: &Point3) -> bool {
    [Axis::X, Axis::Y, Axis::Z]
        .into_iter()
        .all(|axis| normal_component_is_zero(&[*a, *b, *c], axis))
}

/// True when `p` lies on the plane of the (non-degenerate) triangle `plane` by the way it is
/// defined, decided exactly on explicit points: a vertex on that plane, a line–plane point
/// whose plane is that plane or whose line has both ends on it, a three-plane point one of
/// whose planes is that plane. `false` says nothing.
fn lies_on(p: &Point, plane: &[Point3; 3]) -> bool {
    let on =
        |x: &Point3| plane.contains(x) || orient3d(plane[0], plane[1], plane[2], *x) == Sign::Zero;
    match p {
        Point::Explicit(x) => on(x),
        Point::Lpi(l) => {
            let (s, t, other) = l.definition();
            same_plane(&other, plane) || (on(&s) && on(&t))
        }
        Point::Tpi(t) => t.planes().iter().any(|q| same_plane(q, plane)),
    }
}

/// True when the plane of `x` is the plane of `y` (exactly). Called only for planes that
/// share a point, so this is also the test for parallel planes.
fn same_plane(x: &[Point3; 3], y: &[Point3; 3]) -> bool {
    x.iter()
        .all(|&p| orient3d(y[0], y[1], y[2], p) == Sign::Zero)
}

/// The height below which a triangle of f64 approximations is flat, relative to its largest
/// coordinate magnitude: a few ulps, where rounding its corners may turn it over.
const FLAT_HEIGHT: f64 = 16.0 * f64::EPSILON;

/// Whether the triangle `p q r` of f64 approximations is flat: its height over its longest
/// side below [`FLAT_HEIGHT`] of its largest coordinate (its exact orientation on these
/// approximations may even be zero or reversed).
///
/// The longest side is at most the largest `|dx| + |dy|` of a side, so a triangle whose area
/// clears the limit on that bound twice over is not flat without the square roots of the
/// side lengths: most triangles, as the Delaunay phase asks this four times per flip test.
/// The factor two absorbs every rounding, so the answer is the one the height gives.
///
/// Where the orientation filter cannot prove a sign, the doubled area is at most
/// `θ · 2 |pr| |qr| <= θ · 2 longest²` (θ ≈ 1.5 ε, the filter's bound), so the height is at most
/// `2 θ longest <= 4 √2 θ magnitude ≈ 8.5 ε magnitude`, below the limit: flat, with no exact
/// area (collinear points, common on grid parts, sent `robust`'s orient2d to its adaptive
/// stages, only to be called flat).
fn is_flat(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> bool {
    let limit = FLAT_HEIGHT * magnitude(&[p, q, r]);
    let Some(det) = orient2d_value_if_clear(p, q, r) else {
        // Three equal corners at the origin have no limit to be below.
        return limit > 0.0;
    };
    let twice_area = det.abs();
    let taxicab = |u: [f64; 2], v: [f64; 2]| (u[0] - v[0]).abs() + (u[1] - v[1]).abs();
    let longest_bound = taxicab(p, q).max(taxicab(q, r)).max(taxicab(r, p));
    if twice_area > 2.0 * limit * longest_bound {
        return false;
    }
    height(twice_area, p, q, r) < limit
}

/// The height of the triangle `p q r` of doubled area `twice_area` over its longest side (0
/// when its corners are equal; NaN for non-finite input, which no comparison accepts).
fn height(twice_area: f64, p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> f64 {
    let side = |u: [f64; 2], v: [f64; 2]| (u[0] - v[0]).hypot(u[1] - v[1]);
    let longest = side(p, q).max(side(q, r)).max(side(r, p));
    if longest > 0.0 {
        twice_area / longest
    } else {
        0.0
    }
}

/// The largest coordinate magnitude of `points`.
fn magnitude(points: &[[f64; 2]]) -> f64 {
    points.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// One triangle: vertices counterclockwise; edge `i` runs from `v[i + 1]` to `v[i + 2]`
/// (opposite `v[i]`), `nbr[i]` is the triangle across it ([`NONE`] on the boundary) and
/// `cons[i]` the segment constraining it ([`NONE`] if none).
#[derive(Clone, Copy, Debug)]
struct Tri {
    v: [u32; 3],
    nbr: [u32; 3],
    cons: [u32; 3],
}

impl Tri {
    /// The edge `i` as `(from, to)`.
    fn edge(&self, i: usize) -> (u32, u32) {
        (self.v[(i + 1) % 3], self.v[(i + 2) % 3])
    }

    /// The index of the directed edge `from → to`, if this triangle has it.
    fn edge_index(&self, from: u32, to: u32) -> Option<usize> {
        find_edge(self.v, from, to)
    }
}

/// The index of the directed edge `from → to` in the triangle `v` (see [`Tri`]).
fn find_edge(v: [u32; 3], from: u32, to: u32) -> Option<usize> {
    (0..3).find(|&i| (v[(i + 1) % 3], v[(i + 2) % 3]) == (from, to))
}

/// Where a point lies in the triangulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Location {
    /// Strictly inside the triangle.
    InTriangle(u32),
    /// On edge `.1` of triangle `.0`, strictly between its endpoints.
    OnEdge(u32, usize),
    /// On this existing vertex.
    OnVertex(u32),
}

/// One step of a walk: the point's location, or an edge with the point strictly beyond it.
enum Step {
    Found(Location),
    Beyond(usize),
}

/// The triangulation under construction (see the [module docs](self)).
pub(crate) struct Cdt<'a> {
    corners: [Point; 3],
    points: &'a [Point],
    proj: Projection,
    tris: Vec<Tri>,
    /// `alias[id]`: the vertex that stands for vertex `id` (itself unless merged).
    alias: Vec<u32>,
    merged: Vec<[u32; 2]>,
    /// The walk's starting triangle.
    last: u32,
    /// `vtri[id]`: a triangle with vertex `id` ([`NONE`] until it is inserted).
    vtri: Vec<u32>,
    /// Scratch for [`Cdt::replace`].
    rim: Vec<RimEdge>,
    /// Scratch for [`Cdt::replace`].
    ids: Vec<u32>,
}

/// An edge on the rim of the region [`Cdt::replace`] re-triangulates, with what lies across.
#[derive(Clone, Copy, Debug)]
struct RimEdge {
    from: u32,
    to: u32,
    nbr: u32,
    cons: u32,
}

impl<'a> Cdt<'a> {
    /// Steps 1–4 of the [module docs](self).
    pub(crate) fn build(
        corners: [Point3; 3],
        points: &'a [Point],
        segments: &[[u32; 2]],
    ) -> Result<Cdt<'a>, SplitError> {
        let n = 3 + points.len() as u32;
        if let Some(segment) = segments.iter().position(|s| s[0] >= n || s[1] >= n) {
            return Err(SplitError::SegmentOutOfRange { segment });
        }
        debug_assert!(
            points
                .iter()
                .all(|p| orient3d_plane(corners[0], corners[1], corners[2], p) == Sign::Zero),
            "every point lies on the plane of the triangle"
        );
        let corners = corners.map(Point::Explicit);
        let proj = Projection::new(&corners).ok_or(SplitError::DegenerateTriangle)?;
        let mut tris = Vec::with_capacity(1 + 2 * points.len());
        tris.push(Tri {
            v: [0, 1, 2],
            nbr: [NONE; 3],
            cons: [NONE; 3],
        });
        let mut cdt = Cdt {
            corners,
            points,
            proj,
            tris,
            alias: (0..n).collect(),
            merged: Vec::new(),
            last: 0,
            vtri: (0..n).map(|v| if v < 3 { 0 } else { NONE }).collect(),
            rim: Vec::new(),
            ids: Vec::new(),
        };
        // f64 approximations: they choose shapes (insertion order, diagonals), never topology.
        let coords = cdt.coords();
        let mut order: Vec<u32> = (3..n).collect();
        if points.len() > DELAUNAY_BEFORE_SEGMENTS {
            // Each location walks from the last new triangle: in coordinate order the walks
            // stay short.
            order.sort_by(|&a, &b| {
                coords[a as usize]
                    .partial_cmp(&coords[b as usize])
                    .expect("finite")
            });
        }
        for p in order {
            cdt.insert_point(p)?;
        }
        if points.len() > DELAUNAY_BEFORE_SEGMENTS {
            // Points inserted without flips leave long thin triangles, which every segment
            // then crosses by the hundred (the overlay of two coplanar fans puts hundreds of
            // points on one triangle); Delaunay flips first keep the crossings few.
            let budget = 16 * cdt.tris.len() + 64;
            let all = cdt.edges(|_| true);
            cdt.flip_while(&coords, budget, all, Convexity::IfClear, delaunay_flip);
        }
        for (s, seg) in segments.iter().enumerate() {
            cdt.insert_segment(s as u32, seg[0], seg[1])?;
        }
        cdt.improve(&coords);
        Ok(cdt)
    }

    /// Step 5: Lawson flips of unconstrained interior edges towards the Delaunay
    /// triangulation, then away from triangles that are flat in f64, so the output has as few
    /// slivers as its constraints allow (a sliver whose corner rounding to f64 moves across
    /// the opposite edge folds the result).
    ///
    /// Which diagonal of a quadrilateral to keep is a choice of shape, not of topology: it is
    /// made on f64 approximations of the points, and a flip is done only when both new
    /// triangles are positively oriented by the exact predicate, so every state is a valid
    /// triangulation of the same region with the same constrained edges.
    /// - **Delaunay**, by the in-circle test where its f64 sign is certain, among triangles
    ///   that are not flat (lower than [`FLAT_HEIGHT`] relative to their coordinates). A flip
    ///   budget stops the (rare) cycles that inexact answers could cause.
    /// - **Unflattening**: where a triangle is flat, the in-circle test reads rounding noise.
    ///   There a flip is done when it leaves fewer flat triangles in the pair, so the count
    ///   of flat triangles only falls and this phase ends. Flat triangles are what rounding
    ///   folds: three intersection points along one nearly straight curve, like the
    ///   crossings of a drill with the fan of a face that an earlier boolean rounded.
    fn improve(&mut self, coords: &[[f64; 2]]) {
        if self.tris.len() < 2 {
            return;
        }
        let budget = 16 * self.tris.len() + 64;
        self.flip_while(
            coords,
            budget,
            self.edges(|_| true),
            Convexity::IfClear,
            delaunay_flip,
        );
        // Only a quadrilateral with a flat triangle can lose one, so the phase starts from
        // the edges of the flat triangles (the triangles a flip makes are queued anyway),
        // not from every edge with four flatness tests each.
        let flat = |t: &Tri| {
            let [a, b, c] = t.v.map(|x| coords[x as usize]);
            is_flat(a, b, c)
        };
        let seeds = self.edges(flat);
        self.flip_while(
            coords,
            budget,
            seeds,
            Convexity::Exact,
            |[pa, pb, pc, pd]| {
                let now = usize::from(is_flat(pa, pb, pc)) + usize::from(is_flat(pb, pd, pc));
                let after = usize::from(is_flat(pa, pb, pd)) + usize::from(is_flat(pa, pd, pc));
                after < now
            },
        );
    }

    /// The edges `(triangle, side)` of the triangles `which` selects, in triangle order.
    fn edges(&self, which: impl Fn(&Tri) -> bool) -> Vec<(u32, usize)> {
        (self.tris.iter().enumerate())
            .filter(|(_, t)| which(t))
            .flat_map(|(t, _)| (0..3).map(move |i| (t as u32, i)))
            .collect()
    }

    /// f64 approximations of every vertex in the 2D frame, for choices of shape.
    fn coords(&self) -> Vec<[f64; 2]> {
        let k = self.proj.drop.index();
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        (0..self.alias.len() as u32)
            .map(|id| {
                let p = approx_point(self.point(id));
                [p[u], p[v]]
            })
            .collect()
    }

    /// Flips edges, from `stack` (the last first) and the edges of the triangles each flip
    /// makes, while `wanted` says so and the budget lasts: for the quadrilateral
    /// `[a, b, c, d]` of the triangles `a b c` and `d c b` (approximations), whether to
    /// replace the diagonal `b c` by `a d`.
    fn flip_while(
        &mut self,
        coords: &[[f64; 2]],
        mut budget: usize,
        mut stack: Vec<(u32, usize)>,
        convexity: Convexity,
        wanted: impl Fn([[f64; 2]; 4]) -> bool,
    ) {
        let turns_left = |cdt: &Self, [a, b, c]: [u32; 3]| match convexity {
            Convexity::Exact => cdt.orient(a, b, c) == Sign::Positive,
            Convexity::IfClear => cdt.orient_if_clear(a, b, c) == Some(Sign::Positive),
        };
        while let Some((t, i)) = stack.pop() {
            if budget == 0 {
                break;
            }
            let tri = self.tris[t as usize];
            let n = tri.nbr[i];
            if n == NONE || tri.cons[i] != NONE {
                continue;
            }
            let (a, (b, c)) = (tri.v[i], tri.edge(i));
            let other = self.tris[n as usize];
            let Some(j) = other.edge_index(c, b) else {
                continue;
            };
            let d = other.v[j];
            if !wanted([a, b, c, d].map(|x| coords[x as usize])) {
                continue;
            }
            if !turns_left(self, [a, b, d]) || !turns_left(self, [a, d, c]) {
                continue;
            }
            budget -= 1;
            self.replace(&[t, n], &[[a, b, d], [a, d, c]]);
            for x in [t, n] {
                for e in 0..3 {
                    stack.push((x, e));
                }
            }
        }
    }

    fn into_split(self) -> Split {
        Split {
            triangles: self.tris.into_iter().map(|t| t.v).collect(),
            merged: self.merged,
        }
    }

    /// [`Cdt::orient`] where the kernel's filter decides it, `None` elsewhere (and for a
    /// repeated point, which the filter cannot see).
    fn orient_if_clear(&self, a: u32, b: u32, c: u32) -> Option<Sign> {
        if a == b || b == c || a == c {
            return None;
        }
        (self.proj).orient_if_clear(self.point(a), self.point(b), self.point(c))
    }

    fn point(&self, id: u32) -> &Point {
        match id {
            0..3 => &self.corners[id as usize],
            _ => &self.points[id as usize - 3],
        }
    }

    fn orient(&self, a: u32, b: u32, c: u32) -> Sign {
        // A repeated point is a zero the filter cannot see: the exact stages would compute it.
        if a == b || b == c || a == c {
            return Sign::Zero;
        }
        self.proj
            .orient(self.point(a), self.point(b), self.point(c))
    }

    /// Where point `p` lies relative to triangle `t`.
    fn step(&self, t: u32, p: u32) -> Step {
        let tri = &self.tris[t as usize];
        let mut zeros = [false; 3];
        for (i, z) in zeros.iter_mut().enumerate() {
            let (a, b) = tri.edge(i);
            match self.orient(a, b, p) {
                Sign::Negative => return Step::Beyond(i),
                Sign::Zero => *z = true,
                Sign::Positive => {}
            }
        }
        Step::Found(match zeros {
            [false, false, false] => Location::InTriangle(t),
            [true, false, false] => Location::OnEdge(t, 0),
            [false, true, false] => Location::OnEdge(t, 1),
            [false, false, true] => Location::OnEdge(t, 2),
            // Two zero edges meet at the vertex opposite the third; three zeros would need a
            // degenerate triangle.
            [false, true, true] => Location::OnVertex(tri.v[0]),
            [true, false, true] => Location::OnVertex(tri.v[1]),
            _ => Location::OnVertex(tri.v[2]),
        })
    }

    /// Locates point `p`: a walk from the last triangle, then a scan if the walk is too long.
    fn locate(&self, p: u32) -> Result<Location, SplitError> {
        let mut t = self.last;
        for _ in 0..=self.tris.len() {
            match self.step(t, p) {
                Step::Found(loc) => return Ok(loc),
                // The triangulated domain is the convex input triangle: beyond a boundary
                // edge is outside it.
                Step::Beyond(i) => match self.tris[t as usize].nbr[i] {
                    NONE => return Err(SplitError::PointOutside { point: p }),
                    n => t = n,
                },
            }
        }
        (0..self.tris.len() as u32)
            .find_map(|t| match self.step(t, p) {
                Step::Found(loc) => Some(loc),
                Step::Beyond(_) => None,
            })
            .ok_or(SplitError::PointOutside { point: p })
    }

    /// Step 2 for one point.
    fn insert_point(&mut self, p: u32) -> Result<(), SplitError> {
        match self.locate(p)? {
            Location::OnVertex(w) if w > p => {
                // Out of order (coordinate order): the earlier point is the one kept, so the
                // vertex already in place takes its id.
                for tri in &mut self.tris {
                    tri.v.iter_mut().filter(|v| **v == w).for_each(|v| *v = p);
                }
                self.vtri[p as usize] = self.vtri[w as usize];
                self.vtri[w as usize] = NONE;
                for kept in self.alias.iter_mut().filter(|k| **k == w) {
                    *kept = p;
                }
                for pair in self.merged.iter_mut().filter(|pair| pair[1] == w) {
                    pair[1] = p;
                }
                self.merged.push([w, p]);
            }
            Location::OnVertex(w) => {
                self.alias[p as usize] = w;
                self.merged.push([p, w]);
            }
            Location::InTriangle(t) => {
                let [a, b, c] = self.tris[t as usize].v;
                self.replace(&[t], &[[a, b, p], [b, c, p], [c, a, p]]);
            }
            Location::OnEdge(t, i) => {
                let tri = self.tris[t as usize];
                debug_assert_eq!(tri.cons[i], NONE, "points are inserted before segments");
                let a = tri.v[i];
                let (b, c) = tri.edge(i);
                match tri.nbr[i] {
                    NONE => self.replace(&[t], &[[a, b, p], [a, p, c]]),
                    n => {
                        let other = &self.tris[n as usize];
                        let j = other.edge_index(c, b).expect("neighbours share the edge");
                        let d = other.v[j];
                        let new = [[a, b, p], [a, p, c], [d, c, p], [d, p, b]];
                        self.replace(&[t, n], &new);
                    }
                }
            }
        }
        Ok(())
    }

    /// Replaces triangles `old` (a region) by triangles `new` covering the same region,
    /// reusing the slots of `old`, and relinks neighbours and constraint marks: an edge of
    /// `new` on the region's boundary takes the old neighbour and mark, an edge shared by two
    /// new triangles links them, any other edge is on the input triangle's boundary.
    fn replace(&mut self, old: &[u32], new: &[[u32; 3]]) {
        // The scratch buffers live in `self` so that point insertion does not allocate.
        let (mut rim, mut ids) = (std::mem::take(&mut self.rim), std::mem::take(&mut self.ids));
        rim.clear();
        ids.clear();
        for &t in old {
            let tri = self.tris[t as usize];
            for i in 0..3 {
                if !old.contains(&tri.nbr[i]) {
                    let (a, b) = tri.edge(i);
                    rim.push(RimEdge {
                        from: a,
                        to: b,
                        nbr: tri.nbr[i],
                        cons: tri.cons[i],
                    });
                }
            }
        }
        for (k, &v) in new.iter().enumerate() {
            let id = old.get(k).copied().unwrap_or_else(|| {
                self.tris.push(Tri {
                    v,
                    nbr: [NONE; 3],
                    cons: [NONE; 3],
                });
                self.tris.len() as u32 - 1
            });
            self.tris[id as usize].v = v;
            for x in v {
                self.vtri[x as usize] = id;
            }
            ids.push(id);
        }
        for (k, &id) in ids.iter().enumerate() {
            for i in 0..3 {
                let link = self.link_edge(&rim, new, &ids, k, i);
                let tri = &mut self.tris[id as usize];
                (tri.nbr[i], tri.cons[i]) = link;
            }
        }
        self.last = ids[0];
        (self.rim, self.ids) = (rim, ids);
    }

    /// The neighbour and mark of edge `i` of the new triangle `k` in [`Cdt::replace`]; also
    /// points an old neighbour back at it.
    fn link_edge(
        &mut self,
        rim: &[RimEdge],
        new: &[[u32; 3]],
        ids: &[u32],
        k: usize,
        i: usize,
    ) -> (u32, u32) {
        let id = ids[k];
        let (a, b) = self.tris[id as usize].edge(i);
        if let Some(e) = rim.iter().find(|e| (e.from, e.to) == (a, b)) {
            if e.nbr != NONE {
                let back = self.tris[e.nbr as usize].edge_index(b, a);
                let j = back.expect("a neighbour has the reversed edge");
                self.tris[e.nbr as usize].nbr[j] = id;
            }
            (e.nbr, e.cons)
        } else if let Some(m) =
            (0..new.len()).find(|&m| m != k && find_edge(new[m], b, a).is_some())
        {
            (ids[m], NONE)
        } else {
            // A half of a split boundary edge.
            (NONE, NONE)
        }
    }

    /// Step 3 for one segment: constrain the edges along `a → b`, splitting at the vertices
    /// it passes through.
    fn insert_segment(&mut self, s: u32, a: u32, b: u32) -> Result<(), SplitError> {
        let (mut v, b) = (self.alias[a as usize], self.alias[b as usize]);
        while v != b {
            v = self.advance_segment(s, v, b)?;
        }
        Ok(())
    }

    /// Constrains the part of `v → b` from `v` to the next vertex on it, and returns that
    /// vertex.
    fn advance_segment(&mut self, s: u32, v: u32, b: u32) -> Result<u32, SplitError> {
        let (t, i) = match self.leave_vertex(v, b) {
            Leave::Along(w, t, i) => {
                self.mark(t, i, s);
                return Ok(w);
            }
            Leave::Through(t, i) => (t, i),
        };
        let (end, removed, left, right) = self.walk_segment(s, v, b, t, i)?;
        let mut new = Vec::with_capacity(removed.len());
        let mut poly: Vec<u32> = [v, end].into_iter().chain(left.into_iter().rev()).collect();
        self.ear_clip(&mut poly, &mut new);
        poly.clear();
        poly.extend([end, v].into_iter().chain(right));
        self.ear_clip(&mut poly, &mut new);
        debug_assert_eq!(new.len(), removed.len(), "re-triangulation keeps the count");
        self.replace(&removed, &new);
        let (t, i) = (self.ids.iter())
            .find_map(|&t| Some((t, self.tris[t as usize].edge_index(v, end)?)))
            .expect("the left pseudo-polygon has the edge v → end");
        self.mark(t, i, s);
        Ok(end)
    }

    /// How segment `v → b` leaves vertex `v`: along an edge `v w` (edge `i` of triangle
    /// `t`), or into triangle `t` across its edge `i` (opposite `v`). Rotates around `v`
    /// counterclockwise from the triangle `vtri` names, then clockwise if `v` is on the
    /// boundary.
    fn leave_vertex(&self, v: u32, b: u32) -> Leave {
        let start = self.vtri[v as usize];
        for dir in [1, 2] {
            let mut t = start;
            loop {
                let tri = &self.tris[t as usize];
                let k = tri
                    .v
                    .iter()
                    .position(|&x| x == v)
                    .expect("vtri names a triangle of v");
                if dir == 1 || t != start {
                    if let Some(leave) = self.leave_through(t, k, b) {
                        return leave;
                    }
                }
                // Edge k + 1 (q → v) leads counterclockwise, edge k + 2 (v → p) clockwise.
                t = tri.nbr[(k + dir) % 3];
                if t == NONE || t == start {
                    break;
                }
            }
        }
        unreachable!("the triangles around a vertex cover every direction into the triangle")
    }

    /// [`Cdt::leave_vertex`] in triangle `t`, whose vertex `k` is `v`.
    fn leave_through(&self, t: u32, k: usize, b: u32) -> Option<Leave> {
        let tri = &self.tris[t as usize];
        let v = tri.v[k];
        let (p, q) = tri.edge(k);
        // The triangle's angle at `v` runs counterclockwise from ray `v p` to ray `v q`.
        match (self.orient(v, p, b), self.orient(v, q, b)) {
            (Sign::Zero, Sign::Negative) => Some(Leave::Along(p, t, (k + 2) % 3)),
            (Sign::Positive, Sign::Zero) => Some(Leave::Along(q, t, (k + 1) % 3)),
            (Sign::Positive, Sign::Negative) => Some(Leave::Through(t, k)),
            _ => None,
        }
    }

    /// Walks from triangle `t`, entered by segment `v → b` across edge `i`, through the
    /// triangles the segment crosses, up to `b` or the first vertex exactly on the segment.
    /// Returns that vertex, the crossed triangles, and the vertices left and right of the
    /// segment in order from `v`.
    fn walk_segment(&self, s: u32, v: u32, b: u32, t: u32, i: usize) -> Result<Walk, SplitError> {
        let (mut t, mut i) = (t, i);
        let (p, q) = self.tris[t as usize].edge(i);
        let (mut removed, mut left, mut right) = (vec![t], vec![q], vec![p]);
        loop {
            let tri = self.tris[t as usize];
            if tri.cons[i] != NONE {
                return Err(SplitError::ConstraintsCross {
                    first: tri.cons[i] as usize,
                    second: s as usize,
                });
            }
            let n = tri.nbr[i];
            assert_ne!(
                n, NONE,
                "a segment inside the triangle crosses no boundary edge"
            );
            let (p, q) = tri.edge(i);
            let other = &self.tris[n as usize];
            let j = other.edge_index(q, p).expect("neighbours share the edge");
            let r = other.v[j];
            removed.push(n);
            let side = if r == b {
                Sign::Zero
            } else {
                self.orient(v, b, r)
            };
            match side {
                Sign::Zero => return Ok((r, removed, left, right)),
                // The edges of `other` after `q → p` are `p → r` (index j + 1), `r → q`.
                Sign::Positive => {
                    left.push(r);
                    i = (j + 1) % 3;
                }
                Sign::Negative => {
                    right.push(r);
                    i = (j + 2) % 3;
                }
            }
            t = n;
        }
    }

    /// Triangulates the counterclockwise simple polygon `poly` (consecutive collinear
    /// vertices allowed) by ear clipping, appending to `out`; consumes `poly`'s vertices.
    ///
    /// The search for the next ear starts beside the last one, where the polygon changed, so
    /// a polygon whose ears follow each other (a fan) costs `O(k^2)` tests, not `O(k^3)`.
    fn ear_clip(&self, poly: &mut Vec<u32>, out: &mut Vec<[u32; 3]>) {
        let mut start = 0;
        while poly.len() > 3 {
            let n = poly.len();
            let k = (0..n)
                .map(|d| (start + d) % n)
                .find(|&k| self.is_ear(poly, k))
                .expect("a simple polygon with four or more vertices has an ear");
            out.push([poly[(k + n - 1) % n], poly[k], poly[(k + 1) % n]]);
            poly.remove(k);
            start = (k + n - 2) % (n - 1);
        }
        out.push([poly[0], poly[1], poly[2]]);
    }

    /// True when vertex `k` of `poly` is strictly convex and no other vertex lies in the
    /// closed triangle it forms with its neighbours: the diagonal between the neighbours is
    /// then inside the polygon.
    fn is_ear(&self, poly: &[u32], k: usize) -> bool {
        let n = poly.len();
        let (a, b, c) = (poly[(k + n - 1) % n], poly[k], poly[(k + 1) % n]);
        if self.orient(a, b, c) != Sign::Positive {
            return false;
        }
        poly.iter()
            .filter(|&&w| w != a && w != b && w != c)
            .all(|&w| {
                self.orient(a, b, w) == Sign::Negative
                    || self.orient(b, c, w) == Sign::Negative
                    || self.orient(c, a, w) == Sign::Negative
            })
    }

    /// Marks edge `i` of triangle `t` (on both sides) as constrained by segment `s`, unless
    /// an earlier segment already constrains it.
    fn mark(&mut self, t: u32, i: usize, s: u32) {
        let tri = &mut self.tris[t as usize];
        if tri.cons[i] != NONE {
            return;
        }
        tri.cons[i] = s;
        let (a, b) = tri.edge(i);
        let n = tri.nbr[i];
        if n != NONE {
            let other = &mut self.tris[n as usize];
            let j = other.edge_index(b, a).expect("neighbours share the edge");
            other.cons[j] = s;
        }
    }

    /// Checks the invariants of the [module docs](self); the first violation as text.
    pub(crate) fn check_invariants(&self) -> Result<(), String> {
        for (v, &t) in self.vtri.iter().enumerate() {
            let kept = self.alias[v] == v as u32;
            if kept
                && !self
                    .tris
                    .get(t as usize)
                    .is_some_and(|tri| tri.v.contains(&(v as u32)))
            {
                return Err(format!("vtri of vertex {v} names triangle {t} without it"));
            }
        }
        for (t, tri) in self.tris.iter().enumerate() {
            let [a, b, c] = tri.v;
            if a == b || b == c || c == a {
                return Err(format!("triangle {t} {:?} repeats a vertex", tri.v));
            }
            if self.orient(a, b, c) != Sign::Positive {
                return Err(format!("triangle {t} {:?} is not positive", tri.v));
            }
            for i in 0..3 {
                let (x, y) = tri.edge(i);
                let n = tri.nbr[i];
                if n == NONE {
                    continue;
                }
                let other = &self.tris[n as usize];
                let Some(j) = other.edge_index(y, x) else {
                    return Err(format!("triangle {n} lacks edge {y} → {x} of triangle {t}"));
                };
                if other.nbr[j] != t as u32 || other.cons[j] != tri.cons[i] {
                    return Err(format!("triangles {t} and {n} disagree on edge {x} {y}"));
                }
            }
        }
        Ok(())
    }

    /// The triangles, for tests.
    #[cfg(test)]
    pub(crate) fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.tris.iter().map(|t| t.v)
    }
}

/// How a segment leaves a vertex (see [`Cdt::leave_vertex`]).
enum Leave {
    /// Along the edge to this vertex: edge `.2` of triangle `.1`.
    Along(u32, u32, usize),
    /// Into triangle `.0`, across its edge `.1`.
    Through(u32, usize),
}

/// What [`Cdt::walk_segment`] returns: the end vertex, the crossed triangles, the left and
/// right vertex chains.
type Walk = (u32, Vec<u32>, Vec<u32>, Vec<u32>);
