//! Exact triangle–triangle intersection: the `intersect` stage of the exact engine
//! (`design/exact.md`, stage 4).
//!
//! # Contract
//! [`intersect_triangles`] classifies the intersection of two closed, non-degenerate
//! triangles ([`Triangle::new`] refuses degenerate ones) into an [`Intersection`], exactly for
//! the f64 inputs: one named arm per kind of contact. Every contact point is a typed kernel
//! [`Point`] (an input vertex, an [`Lpi`](crate::kernel::Lpi) edge–plane crossing or a
//! [`Tpi`](crate::kernel::Tpi) coplanar edge–edge crossing) with the [`Feature`] of each
//! triangle it lies on and a canonical [`PointKey`] built from the entities that define it, so
//! the same point found from two triangle pairs gets the same key. Vertices are shared when
//! their ids are equal or their positions are exactly equal.
//!
//! # Algorithm
//! 1. Sign vectors: [`orient3d`] of each vertex of `a` against the plane of `b`, and of `b`
//!    against `a`. All of one strict sign on either side: [`Intersection::Disjoint`]. All zero:
//!    the triangles are coplanar (step 5).
//! 2. Chords: the part of each triangle on the other's plane is a point or a segment on the
//!    common line `L` of the two planes. Its ends are vertices with sign zero and, for edges
//!    whose ends have strictly opposite signs, the [`Point::lpi`] of the edge and the plane.
//! 3. Order on `L`: take the first axis (x, y, z) on which two distinct chord ends differ; on
//!    `L`, ascending along it is the lexicographic order, decided by [`compare_along`].
//! 4. The intersection is the overlap of the two chords: the later start and the earlier end.
//!    Empty: disjoint; one point: [`Intersection::TouchingPoint`]; a segment:
//!    [`Intersection::Crossing`] when each triangle has vertices strictly on both sides of the
//!    other's plane (the segment runs through both interiors), else
//!    [`Intersection::TouchingSegment`]. An end of one chord is located on the other chord as
//!    one of its ends (the same point), its interior (an edge or the face of that triangle) or
//!    outside.
//! 5. Coplanar: in the projection that drops the coordinate [`Triangle`] chose (exact
//!    [`orient2d`] of the projected input vertices, orientation-preserving up to one known
//!    sign; [`orient2d_projected`] once crossing points are among them), collect the
//!    vertices of each triangle inside the other (closed) and the proper crossings of an edge
//!    of `a` with an edge of `b` ([`Point::edge_crossing`]). These are the corners of the
//!    convex overlap; none repeats (a vertex of `b` on a vertex of `a` is taken once). Zero,
//!    one or two corners: disjoint, touching point, touching segment; three or more:
//!    [`Intersection::CoplanarOverlap`], sorted counterclockwise about `a`'s normal around the
//!    lexicographically smallest corner.
//!
//! # Invariants
//! - Segment ends are distinct and in lexicographic order ([`compare_lex`]).
//! - A contact's [`Feature`]s are exact: `Vertex` when the point is that vertex, `Edge` when
//!   it is inside that edge, `Face` when it is inside the triangle.
//!
//! # Numeric model
//! Every decision is a kernel predicate ([`orient3d`], [`orient2d_projected`],
//! [`compare_along`]) on input vertices and implicit points: exact, no epsilon. Points are
//! never rounded.
//!
//! # Complexity
//! O(1) predicates per pair: at most 6 [`orient3d`], 4 constructions, about 10 comparisons
//! (transversal) or 27 orientation tests (coplanar). Only degenerate contacts reach the exact
//! stages of the kernel's cascade.

use std::cmp::Ordering;

use crate::kernel::{
    Axis, PlaneFilter, Point, Point3, Sign, compare_along, compare_lex, orient2d,
    orient2d_projected, orient3d, side_of_axis_plane,
};

/// A sorted pair of vertex ids: an edge, independent of the triangle that uses it.
pub type TriangleEdge = [u32; 2];

/// A non-degenerate triangle ready for [`intersect_triangles`]: an id (for [`PointKey`]), its
/// vertex ids and positions, and a projection axis along which it does not collapse.
///
/// Vertex ids name points: two triangles that use one id must give it one position (the
/// keys of the intersection points, and the answers for shared corners without arithmetic,
/// rely on it), as a welded mesh's vertex indices do.
#[derive(Clone, Copy, Debug)]
pub struct Triangle {
    id: u32,
    vertices: [u32; 3],
    positions: [Point3; 3],
    /// The coordinate dropped for 2D tests; the normal's component on it is nonzero.
    drop: Axis,
    /// [`orient2d_projected`] of the vertices along `drop`: never zero.
    turn: Sign,
}

impl Triangle {
    /// A triangle with id `id` (a triangle index of the caller's), vertex ids and positions.
    ///
    /// `None` when the triangle is degenerate (its corners are exactly collinear, including
    /// repeated positions) or a coordinate is not finite.
    pub fn new(id: u32, vertices: [u32; 3], positions: [Point3; 3]) -> Option<Triangle> {
        if !positions.as_flattened().iter().all(|x| x.is_finite()) {
            return None;
        }
        // An f64 estimate of the normal picks the preferred axis; the exact test decides (on
        // the projected coordinates: what `orient2d_projected` does for input vertices,
        // without building three kernel points per triangle).
        let (u, v) = (
            sub(positions[1], positions[0]),
            sub(positions[2], positions[0]),
        );
        let normal = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let first = Axis::of_largest(normal);
        [first, Axis::X, Axis::Y, Axis::Z]
            .into_iter()
            .find_map(|drop| {
                let [p, q, r] = positions.map(|x| drop.project(x));
                let turn = orient2d(p, q, r);
                (turn != Sign::Zero).then_some(Triangle {
                    id,
                    vertices,
                    positions,
                    drop,
                    turn,
                })
            })
    }

    /// The same triangle with another id.
    pub(crate) fn with_id(self, id: u32) -> Triangle {
        Triangle { id, ..self }
    }

    /// The triangle without its positions and id, for a caller that keeps the positions in
    /// a vertex array (and the id as the record's index).
    pub(crate) fn indexed(&self) -> IndexedTriangle {
        IndexedTriangle {
            vertices: self.vertices,
            drop: self.drop,
            turn: self.turn,
        }
    }

    /// The coordinate dropped for 2D tests in the triangle's plane.
    pub(crate) fn drop_axis(&self) -> Axis {
        self.drop
    }

    /// [`orient2d_projected`] of the vertices along [`Triangle::drop_axis`]: never zero.
    pub(crate) fn turn(&self) -> Sign {
        self.turn
    }

    /// The caller's id of this triangle.
    pub fn id(&self) -> u32 {
        self.id
    }

    /// The vertex ids.
    pub fn vertices(&self) -> [u32; 3] {
        self.vertices
    }

    /// The vertex positions.
    pub fn positions(&self) -> [Point3; 3] {
        self.positions
    }

    /// [`orient3d`] of the corners and `p`, whose vertex id is `v`: the side of the
    /// triangle's plane `p` lies on. Two zeros the orientation filter cannot prove, and for
    /// which [`orient3d`] takes its slow path, are decided here first, because touching solids
    /// and CAD parts are full of them: `p` is a corner (by id; equal ids name one point), and
    /// the triangle lies in an axis plane ([`Triangle::axis_level`]), where the side is a
    /// comparison ([`side_of_axis_plane`]).
    pub(crate) fn side(&self, v: u32, p: Point3) -> Sign {
        if self.vertices.contains(&v) {
            return Sign::Zero;
        }
        if let Some(level) = self.axis_level() {
            return side_of_axis_plane(level, p[self.drop.index()], self.turn);
        }
        let [r, s, u] = self.positions;
        orient3d(r, s, u, p)
    }

    /// The common coordinate of the three corners along [`Triangle::drop_axis`], when they
    /// share it: the triangle then lies in that axis plane (and the drop axis is always that
    /// axis, the only one along which the projection does not collapse).
    pub(crate) fn axis_level(&self) -> Option<f64> {
        let k = self.drop.index();
        let level = self.positions[0][k];
        (self.positions[1][k] == level && self.positions[2][k] == level).then_some(level)
    }

    /// Edge `i` (from vertex `i` to vertex `i + 1 mod 3`) as a sorted vertex-id pair.
    pub fn edge(&self, i: usize) -> TriangleEdge {
        let (x, y) = (self.vertices[i], self.vertices[(i + 1) % 3]);
        [x.min(y), x.max(y)]
    }
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A [`Triangle`] by its vertex ids alone, with the projection [`Triangle::new`] chose: what
/// the pipeline keeps per input triangle, the positions living once in the welded vertex
/// array. A fifth of a [`Triangle`]'s bytes: on two meshes of a million triangles each,
/// writing and reading full records (positions copied three times over) cost more than the
/// work done with them in the stages that pass over every triangle (ingest, broad phase,
/// classification), and their 200 MB set the peak memory.
#[derive(Clone, Copy, Debug)]
pub(crate) struct IndexedTriangle {
    vertices: [u32; 3],
    drop: Axis,
    turn: Sign,
}

impl IndexedTriangle {
    /// The vertex ids.
    pub(crate) fn vertices(&self) -> [u32; 3] {
        self.vertices
    }

    /// [`Triangle::drop_axis`] of the whole triangle.
    pub(crate) fn drop_axis(&self) -> Axis {
        self.drop
    }

    /// The full triangle with id `id`, its corners at `positions[v]` for its vertex ids `v`
    /// (the array it was made from).
    #[inline]
    pub(crate) fn with_positions(&self, id: u32, positions: &[Point3]) -> Triangle {
        Triangle {
            id,
            vertices: self.vertices,
            // Element by element: an array `map` went through a temporary.
            positions: [
                positions[self.vertices[0] as usize],
                positions[self.vertices[1] as usize],
                positions[self.vertices[2] as usize],
            ],
            drop: self.drop,
            turn: self.turn,
        }
    }
}

/// Where a contact point lies on one triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Feature {
    /// It is vertex `i` (0, 1 or 2).
    Vertex(usize),
    /// It is strictly inside edge `i`, from vertex `i` to vertex `i + 1 mod 3`.
    Edge(usize),
    /// It is strictly inside the triangle.
    Face,
}

/// The canonical name of a contact point, from the entities that define it. Two triangle
/// pairs that find the same point through the same entities give the same key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PointKey {
    /// An input vertex (the smaller id when two vertices with different ids coincide).
    Vertex(u32),
    /// An edge meets the inside of a triangle (transversally, or coplanar with it).
    EdgeTriangle {
        /// The edge.
        edge: TriangleEdge,
        /// The [`Triangle::id`] of the triangle.
        triangle: u32,
    },
    /// Two edges cross at a point inside both; the pair is sorted.
    EdgeEdge {
        /// The two edges, smaller first.
        edges: [TriangleEdge; 2],
    },
    /// The planes of three triangles of three operands meet inside all three (found by the
    /// split stage where two intersection segments cross); the ids are sorted.
    Triple {
        /// The three [`Triangle::id`]s, ascending.
        triangles: [u32; 3],
    },
}

/// A point where two triangles `a` and `b` touch or cross.
#[derive(Clone, Debug)]
pub struct Contact {
    /// The point, exact: an input vertex or an implicit point.
    pub point: Point,
    /// Its canonical key.
    pub key: PointKey,
    /// Where it lies on `a`.
    pub on_a: Feature,
    /// Where it lies on `b`.
    pub on_b: Feature,
}

/// The exact intersection of two closed triangles `a` and `b`.
#[derive(Clone, Debug)]
pub enum Intersection {
    /// No common point.
    Disjoint,
    /// Exactly one common point (a shared vertex, a vertex on an edge or face, two edges
    /// crossing, …).
    TouchingPoint(Contact),
    /// A segment on the boundary of at least one triangle (a shared edge, an edge lying in
    /// the other triangle, coplanar triangles meeting along an edge, …); ends in
    /// lexicographic order.
    TouchingSegment([Contact; 2]),
    /// A segment through the interiors of both triangles: each has vertices strictly on both
    /// sides of the other's plane. Ends in lexicographic order.
    Crossing([Contact; 2]),
    /// Coplanar triangles overlapping in a convex polygon of positive area: its corners,
    /// counterclockwise about `a`'s normal.
    CoplanarOverlap(Vec<Contact>),
}

/// The exact intersection of `a` and `b` (see the [module docs](self) for the algorithm).
///
/// # Example
/// A vertical triangle pierces a horizontal one; an edge of each crosses the other's inside.
/// ```
/// use csgkit::{Feature, Intersection, PointKey, Triangle, intersect_triangles};
/// let a = Triangle::new(0, [0, 1, 2], [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]);
/// let b = Triangle::new(1, [3, 4, 5], [[1.0, 1.0, -1.0], [1.0, 1.0, 1.0], [2.0, 1.0, 1.0]]);
/// let (a, b) = (a.expect("non-degenerate"), b.expect("non-degenerate"));
/// let Intersection::Crossing([start, end]) = intersect_triangles(&a, &b) else {
///     panic!("the triangles cross");
/// };
/// // Edge 3–4 of `b` meets the inside of `a` at (1, 1, 0).
/// assert_eq!(start.key, PointKey::EdgeTriangle { edge: [3, 4], triangle: 0 });
/// assert_eq!((start.on_a, start.on_b), (Feature::Face, Feature::Edge(0)));
/// assert_eq!(end.on_a, Feature::Face);
/// ```
pub fn intersect_triangles(a: &Triangle, b: &Triangle) -> Intersection {
    let sa = plane_signs(a, b);
    if one_side(&sa) {
        return Intersection::Disjoint;
    }
    let sb = plane_signs(b, a);
    if one_side(&sb) {
        return Intersection::Disjoint;
    }
    if sa == [Sign::Zero; 3] {
        return coplanar(a, b);
    }
    if !sa.contains(&Sign::Zero) && !sb.contains(&Sign::Zero) && separated(a, b, &sa, &sb) {
        return Intersection::Disjoint;
    }
    transversal(a, b, &sa, &sb)
}

/// Guigue & Devillers' test ("Fast and robust triangle–triangle overlap test using
/// orientation predicates", 2003) for two triangles that each have vertices strictly on both
/// sides of the other's plane and none on it: true when the chords are disjoint on the common
/// line, decided by two [`orient3d`] on input vertices, without intersection points.
///
/// Each triangle is turned so that its lone vertex (alone on its side) comes first; when the
/// lone vertex of one is below the other's plane, the other's orientation is reversed.
fn separated(a: &Triangle, b: &Triangle, sa: &[Sign; 3], sb: &[Sign; 3]) -> bool {
    // Guigue–Devillers' signs are positive above the plane: the opposite of `orient3d`.
    let above = |s: Sign| s == Sign::Negative;
    let ([p1, q1, r1], [p2, q2, r2]) = (a.positions, b.positions);
    let [dp, dq, dr] = sb.map(above);
    let b_up = (p2, q2, r2, dp, dq, dr);
    let b_down = (p2, r2, q2, dp, dr, dq);
    let (t1, t2) = match sa.map(above) {
        [true, true, _] => ([r1, p1, q1], b_down),
        [true, false, true] => ([q1, r1, p1], b_down),
        [true, false, false] => ([p1, q1, r1], b_up),
        [false, false, _] => ([r1, p1, q1], b_up),
        [false, true, false] => ([q1, r1, p1], b_up),
        [false, true, true] => ([p1, q1, r1], b_down),
    };
    let [p1, q1, r1] = t1;
    let (p2, q2, r2, dp, dq, dr) = t2;
    let chords_apart = |[p1, q1, r1]: [Point3; 3], [p2, q2, r2]: [Point3; 3]| {
        orient3d(q1, p2, p1, q2) == Sign::Negative || orient3d(p1, p2, r1, r2) == Sign::Negative
    };
    match (dp, dq, dr) {
        (true, true, _) => chords_apart([p1, r1, q1], [r2, p2, q2]),
        (true, false, true) => chords_apart([p1, r1, q1], [q2, r2, p2]),
        (true, false, false) => chords_apart([p1, q1, r1], [p2, q2, r2]),
        (false, false, _) => chords_apart([p1, q1, r1], [r2, p2, q2]),
        (false, true, false) => chords_apart([p1, q1, r1], [q2, r2, p2]),
        (false, true, true) => chords_apart([p1, r1, q1], [p2, q2, r2]),
    }
}

/// True when the plane of one triangle has the other strictly on one side: the first test of
/// [`intersect_triangles`] on its own, for the broad phase, which keeps such pairs out of its
/// list instead of storing and sorting them (long thin triangles have boxes that overlap many
/// triangles they cannot touch).
pub(crate) fn planes_separate(a: &Triangle, b: &Triangle) -> bool {
    one_side(&plane_signs(a, b)) || one_side(&plane_signs(b, a))
}

/// [`orient3d`] of each vertex of `t` against the plane of `other` ([`Triangle::side`]), where
/// a [`PlaneFilter`] of that plane does not decide first (planes along an axis decide by a
/// comparison there).
fn plane_signs(t: &Triangle, other: &Triangle) -> [Sign; 3] {
    let plane = (other.axis_level().is_none()).then(|| PlaneFilter::new(&other.positions));
    std::array::from_fn(|i| {
        let clear = plane.and_then(|plane| plane.side_if_clear(t.positions[i]));
        clear.unwrap_or_else(|| other.side(t.vertices[i], t.positions[i]))
    })
}

fn one_side(s: &[Sign; 3]) -> bool {
    s.iter().all(|&x| x == Sign::Positive) || s.iter().all(|&x| x == Sign::Negative)
}

fn straddles(s: &[Sign; 3]) -> bool {
    s.contains(&Sign::Positive) && s.contains(&Sign::Negative)
}

/// Where a point that a triangle contributes lies on that triangle.
#[derive(Clone, Copy, Debug)]
enum Boundary {
    Vertex(usize),
    Edge(usize),
}

impl Boundary {
    fn feature(self) -> Feature {
        match self {
            Boundary::Vertex(i) => Feature::Vertex(i),
            Boundary::Edge(i) => Feature::Edge(i),
        }
    }
}

/// An end of a chord: a point of triangle `x` on the other's plane.
#[derive(Clone, Debug)]
struct End {
    point: Point,
    own: Boundary,
}

/// The contact for a point that `x` contributes as `own`, lying on `y` at `other`.
fn contact(x: &Triangle, own: Boundary, y: &Triangle, other: Feature, point: Point) -> Contact {
    let key = match (own, other) {
        (Boundary::Vertex(i), Feature::Vertex(j)) => {
            PointKey::Vertex(x.vertices[i].min(y.vertices[j]))
        }
        (Boundary::Vertex(i), _) => PointKey::Vertex(x.vertices[i]),
        (Boundary::Edge(_), Feature::Vertex(j)) => PointKey::Vertex(y.vertices[j]),
        (Boundary::Edge(i), Feature::Edge(j)) => {
            let (e, f) = (x.edge(i), y.edge(j));
            PointKey::EdgeEdge {
                edges: [e.min(f), e.max(f)],
            }
        }
        (Boundary::Edge(i), Feature::Face) => PointKey::EdgeTriangle {
            edge: x.edge(i),
            triangle: y.id,
        },
    };
    Contact {
        point,
        key,
        on_a: own.feature(),
        on_b: other,
    }
}

/// The same contact with the roles of `a` and `b` exchanged.
fn swapped(c: Contact) -> Contact {
    Contact {
        on_a: c.on_b,
        on_b: c.on_a,
        ..c
    }
}

/// The chord of `t` on the plane of `other` (signs `s`), as two ends (equal for a point).
///
/// The ends' places are found first and each point is built once, where it goes.
fn chord(t: &Triangle, s: &[Sign; 3], other: &Triangle) -> Option<[End; 2]> {
    // A vertex on the plane, or an edge with ends on strictly opposite sides: at most two
    // (three would need all three vertices on the plane, the coplanar case).
    let mut owns = [Boundary::Vertex(0); 2];
    let mut n = 0;
    for i in 0..3 {
        let own = if s[i] == Sign::Zero {
            Boundary::Vertex(i)
        } else if s[(i + 1) % 3] == s[i].flip() {
            Boundary::Edge(i)
        } else {
            continue;
        };
        owns[n] = own;
        n += 1;
    }
    let [r, q, u] = other.positions;
    let end = |own: Boundary| {
        let point = match own {
            Boundary::Vertex(i) => Point::Explicit(t.positions[i]),
            // Ends on strictly opposite sides: `lpi` gives a point.
            Boundary::Edge(i) => Point::lpi(t.positions[i], t.positions[(i + 1) % 3], r, q, u)?,
        };
        Some(End { point, own })
    };
    match n {
        0 => None,
        1 => end(owns[0]).map(|x| [x.clone(), x]),
        _ => Some([end(owns[0])?, end(owns[1])?]),
    }
}

/// The first axis on which `p` and `q` differ, and their order there.
fn first_axis(p: &Point, q: &Point) -> Option<(Axis, Ordering)> {
    [Axis::X, Axis::Y, Axis::Z].into_iter().find_map(|axis| {
        let order = compare_along(p, q, axis);
        (order != Ordering::Equal).then_some((axis, order))
    })
}

/// Locates a point on the chord `c` of triangle `t` (ends sorted along the chords' axis),
/// given its order against the chord's start (`lo`) and end (`hi`, asked only when needed):
/// the feature of `t` and, when the point is an end of `c`, which end.
fn on_chord(
    lo: Ordering,
    hi: impl FnOnce() -> Ordering,
    c: &[&End; 2],
    t_chord_inside: Feature,
) -> Option<(Feature, Option<usize>)> {
    if lo == Ordering::Equal {
        return Some((c[0].own.feature(), Some(0)));
    }
    match (lo, hi()) {
        (_, Ordering::Equal) => Some((c[1].own.feature(), Some(1))),
        (Ordering::Greater, Ordering::Less) => Some((t_chord_inside, None)),
        _ => None,
    }
}

/// A chord's ends by reference, the first first along the axis given their `order` there:
/// no point is moved or cloned.
fn in_order(c: &[End; 2], order: Ordering) -> [&End; 2] {
    if order == Ordering::Greater {
        [&c[1], &c[0]]
    } else {
        [&c[0], &c[1]]
    }
}

/// The feature of the inside of a chord: the edge between two vertex ends, else the face.
fn chord_inside(c: &[&End; 2]) -> Feature {
    match (c[0].own, c[1].own) {
        (Boundary::Vertex(i), Boundary::Vertex(j)) if i != j => {
            Feature::Edge(if (i + 1) % 3 == j { i } else { j })
        }
        _ => Feature::Face,
    }
}

/// Triangles that are not coplanar and whose sign vectors are not one-sided (steps 2–4).
fn transversal(a: &Triangle, b: &Triangle, sa: &[Sign; 3], sb: &[Sign; 3]) -> Intersection {
    let (Some(ca), Some(cb)) = (chord(a, sa, b), chord(b, sb, a)) else {
        return Intersection::Disjoint;
    };
    // Each comparison of two chord ends is asked once: near ties of implicit points (a cube
    // turned by 1e-7 rad) go to the exact stages, and the overlap below meets the same pairs
    // of ends again.
    let ends_a = first_axis(&ca[0].point, &ca[1].point);
    let ends_b = match ends_a {
        None => first_axis(&cb[0].point, &cb[1].point),
        Some(_) => None,
    };
    let axis = (ends_a.or(ends_b).map(|(axis, _)| axis))
        .or_else(|| first_axis(&ca[0].point, &cb[0].point).map(|(axis, _)| axis));
    let Some(axis) = axis else {
        // All chord ends are one point.
        let (end, other) = (&ca[0], &cb[0]);
        let feature = other.own.feature();
        return Intersection::TouchingPoint(merged(a, end, b, feature, Some(&other.point)));
    };
    // The order of each chord's ends along the axis; equal ends on every axis keep theirs.
    let order_a = ends_a.map_or(Ordering::Equal, |(_, order)| order);
    let order_b = match (ends_a, ends_b) {
        (None, Some((_, order))) => order,
        (None, None) => Ordering::Equal,
        (Some(_), _) => compare_along(&cb[0].point, &cb[1].point, axis),
    };
    let (ca, cb) = (&in_order(&ca, order_a), &in_order(&cb, order_b));
    let inside = (chord_inside(ca), chord_inside(cb));
    // The overlap of the chords: the later start and the earlier end, from `a` when tied.
    let cmp = |x: &End, y: &End| compare_along(&x.point, &y.point, axis);
    let starts = cmp(ca[0], cb[0]);
    let stops = cmp(ca[1], cb[1]);
    let (lo_from_a, hi_from_a) = (starts != Ordering::Less, stops != Ordering::Greater);
    let end_contact = |from_a: bool, k: usize| {
        if from_a {
            // `a`'s end `k` against `b`'s chord.
            let lo = if k == 0 { starts } else { cmp(ca[1], cb[0]) };
            let hi = || if k == 1 { stops } else { cmp(ca[0], cb[1]) };
            let (f, end) = on_chord(lo, hi, cb, inside.1)?;
            Some(merged(a, ca[k], b, f, end.map(|e| &cb[e].point)))
        } else {
            // `b`'s end `k` against `a`'s chord.
            let lo = if k == 0 {
                starts.reverse()
            } else {
                cmp(cb[1], ca[0])
            };
            let hi = || {
                if k == 1 {
                    stops.reverse()
                } else {
                    cmp(cb[0], ca[1])
                }
            };
            let (f, end) = on_chord(lo, hi, ca, inside.0)?;
            Some(swapped(merged(b, cb[k], a, f, end.map(|e| &ca[e].point))))
        }
    };
    let (Some(lo), Some(hi)) = (end_contact(lo_from_a, 0), end_contact(hi_from_a, 1)) else {
        return Intersection::Disjoint;
    };
    match compare_along(&lo.point, &hi.point, axis) {
        Ordering::Greater => Intersection::Disjoint,
        Ordering::Equal => Intersection::TouchingPoint(lo),
        Ordering::Less if straddles(sa) && straddles(sb) => Intersection::Crossing([lo, hi]),
        Ordering::Less => Intersection::TouchingSegment([lo, hi]),
    }
}

/// The contact for chord end `end` of `x` lying on `y` at `other`, where `y`'s own point
/// there, if it has one, is `theirs`; keeps an input vertex when either point is one.
fn merged(
    x: &Triangle,
    end: &End,
    y: &Triangle,
    other: Feature,
    theirs: Option<&Point>,
) -> Contact {
    let point = match theirs {
        Some(p) if !end.point.is_explicit() => p.clone(),
        _ => end.point.clone(),
    };
    contact(x, end.own, y, other, point)
}

/// Locates vertex `i` of `x`, in the plane of `t`, on `t`: `None` outside.
///
/// Like the rest of the coplanar case, on the projected f64 coordinates of input vertices:
/// exact [`orient2d`], with no kernel [`Point`] built or copied. A vertex of `t` (by id) is
/// that vertex without a test: coplanar triangles of touching solids share most of theirs.
fn locate(x: &Triangle, i: usize, t: &Triangle) -> Option<Feature> {
    if let Some(j) = t.vertices.iter().position(|&v| v == x.vertices[i]) {
        return Some(Feature::Vertex(j));
    }
    let p = t.drop.project(x.positions[i]);
    let v = t.positions.map(|x| t.drop.project(x));
    let s = [0, 1, 2].map(|i| orient2d(v[i], v[(i + 1) % 3], p).times(t.turn));
    if s.contains(&Sign::Negative) {
        return None;
    }
    let zero = |i: usize| s[i] == Sign::Zero;
    match (zero(0), zero(1), zero(2)) {
        (false, false, false) => Some(Feature::Face),
        (true, true, _) => Some(Feature::Vertex(1)),
        (_, true, true) => Some(Feature::Vertex(2)),
        (true, _, true) => Some(Feature::Vertex(0)),
        (true, false, false) => Some(Feature::Edge(0)),
        (false, true, false) => Some(Feature::Edge(1)),
        (false, false, true) => Some(Feature::Edge(2)),
    }
}

/// The proper crossing of edge `i` of `a` with edge `j` of coplanar `b`, if any. Edges with
/// an end in common (by id) have none: that end is on both lines.
fn edge_crossing(a: &Triangle, i: usize, b: &Triangle, j: usize) -> Option<Point> {
    let ends = |t: &Triangle, k: usize| [t.vertices[k], t.vertices[(k + 1) % 3]];
    let (ea, eb) = (ends(a, i), ends(b, j));
    if ea.iter().any(|v| eb.contains(v)) {
        return None;
    }
    let e = [a.positions[i], a.positions[(i + 1) % 3]];
    let f = [b.positions[j], b.positions[(j + 1) % 3]];
    let [e0, e1, f0, f1] = [e[0], e[1], f[0], f[1]].map(|x| a.drop.project(x));
    let (s0, s1) = (orient2d(f0, f1, e0), orient2d(f0, f1, e1));
    let (s2, s3) = (orient2d(e0, e1, f0), orient2d(e0, e1, f1));
    let proper = s0 != Sign::Zero && s1 == s0.flip() && s2 != Sign::Zero && s3 == s2.flip();
    proper.then(|| Point::edge_crossing(a.positions, e, f, a.drop))?
}

/// Coplanar triangles (step 5).
fn coplanar(a: &Triangle, b: &Triangle) -> Intersection {
    let mut corners = Vec::new();
    for i in 0..3 {
        if let Some(f) = locate(a, i, b) {
            let p = Point::Explicit(a.positions[i]);
            corners.push(contact(a, Boundary::Vertex(i), b, f, p));
        }
    }
    for j in 0..3 {
        let p = b.positions[j];
        match locate(b, j, a) {
            // Found from `a`'s side already.
            Some(Feature::Vertex(_)) | None => {}
            Some(f) => corners.push(swapped(contact(
                b,
                Boundary::Vertex(j),
                a,
                f,
                Point::Explicit(p),
            ))),
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            if let Some(p) = edge_crossing(a, i, b, j) {
                corners.push(contact(a, Boundary::Edge(i), b, Feature::Edge(j), p));
            }
        }
    }
    match corners.len() {
        0 => Intersection::Disjoint,
        1 => Intersection::TouchingPoint(corners.swap_remove(0)),
        2 => {
            let d = corners.swap_remove(1);
            let c = corners.swap_remove(0);
            match compare_lex(&c.point, &d.point) {
                Ordering::Greater => Intersection::TouchingSegment([d, c]),
                _ => Intersection::TouchingSegment([c, d]),
            }
        }
        _ => Intersection::CoplanarOverlap(counterclockwise(corners, a)),
    }
}

/// Sorts the corners of a convex polygon in the plane of `a` counterclockwise about `a`'s
/// normal, starting at the lexicographically smallest (an extreme corner).
fn counterclockwise(mut corners: Vec<Contact>, a: &Triangle) -> Vec<Contact> {
    let first = (1..corners.len()).fold(0, |m, k| {
        if compare_lex(&corners[k].point, &corners[m].point) == Ordering::Less {
            k
        } else {
            m
        }
    });
    corners.swap(0, first);
    let origin = corners[0].point.clone();
    let before = |p: &Contact, q: &Contact| {
        orient2d_projected(&origin, &p.point, &q.point, a.drop).times(a.turn) == Sign::Positive
    };
    // Insertion sort: at most six corners, and no reliance on a total order.
    for k in 2..corners.len() {
        let mut m = k;
        while m > 1 && before(&corners[m], &corners[m - 1]) {
            corners.swap(m, m - 1);
            m -= 1;
        }
    }
    corners
}

#[cfg(test)]
mod tests;
