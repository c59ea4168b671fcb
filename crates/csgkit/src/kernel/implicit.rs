//! Implicit points: intersection points stored by what defines them (Attene 2020, "Indirect
//! predicates for geometric constructions"; Cherchi et al. 2020, "Fast and robust mesh
//! arrangements using floating-point arithmetic").
//!
//! A point's homogeneous coordinates `(X, Y, Z, W)` are polynomials in its defining f64
//! coordinates (table in the [module docs](super)). They are evaluated in whichever number
//! type the predicate cascade asks for (`hom`), and once, at construction, as intervals that
//! the filter reuses (`filter_hom`), and divided into Cartesian coordinates to within a known
//! error ([`Nearby`], for the filters of `nearby.rs`). The sign of `W` is computed exactly at
//! construction; a point whose `W` is exactly zero does not exist and is refused.

use std::cell::RefCell;
use std::collections::hash_map::Entry;
use std::sync::Arc;
use std::thread::LocalKey;

use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use super::arith::Arith;
use super::cascade::{Formula, Homogeneous, decide};
use super::double_double::DoubleDouble;
use super::expansion::Expansion;
use super::interval::{Interval, Tracked, next_down, next_up};
use super::nearby::{self, Nearby};
use super::{Axis, Sign};

/// A point given by three f64 coordinates.
pub type Point3 = [f64; 3];

/// A point of the exact pipeline: an input vertex or an intersection point.
///
/// 32 bytes: an input vertex inline, an intersection point shared behind an [`Arc`]. Why:
/// every move of a point copies the whole enum, and a [`Tpi`] inline is 336 bytes (its
/// definition, filter intervals and nearby coordinates), which made copying points (input
/// vertices above all) a tenth of the small booleans' time; an intersection point is built
/// once at a cost of a thousand instructions or more, beside which one allocation is small,
/// and is then moved and cloned many times.
#[derive(Clone, Debug)]
pub enum Point {
    /// An input vertex.
    Explicit(Point3),
    /// A line–plane intersection.
    Lpi(Arc<Lpi>),
    /// A three-plane intersection.
    Tpi(Arc<Tpi>),
}

/// Line–plane intersection: the line through `p, q` meets the plane through `r, s, t`.
///
/// With `n = (s - r) × (t - r)`: `W = n · (q - p)` and
/// `(X, Y, Z) = p W + (q - p) (n · (r - p))`, so the point is `p + (q - p) λ` with
/// `λ = n · (r - p) / n · (q - p)`. The point may lie outside the segment `p q` and outside
/// the triangle `r s t`: the construction is about the line and the plane.
#[derive(Clone, Copy, Debug)]
pub struct Lpi {
    /// `[p, q, r, s, t]`.
    def: [Point3; 5],
    filter: [Interval; 4],
    near: Nearby,
    w_sign: Sign,
}

/// Three-plane intersection: the common point of the planes of three triangles.
///
/// With normals `n_i = (b_i - a_i) × (c_i - a_i)` and offsets `d_i = n_i · a_i`:
/// `W = n_1 · (n_2 × n_3)` and
/// `(X, Y, Z) = d_1 (n_2 × n_3) + d_2 (n_3 × n_1) + d_3 (n_1 × n_2)` (Cramer's rule).
#[derive(Clone, Copy, Debug)]
pub struct Tpi {
    planes: [[Point3; 3]; 3],
    filter: [Interval; 4],
    near: Nearby,
    w_sign: Sign,
}

#[inline]
fn sub3<T: Arith>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [a[0].sub(&b[0]), a[1].sub(&b[1]), a[2].sub(&b[2])]
}

#[inline]
fn cross<T: Arith>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [
        a[1].mul(&b[2]).sub(&a[2].mul(&b[1])),
        a[2].mul(&b[0]).sub(&a[0].mul(&b[2])),
        a[0].mul(&b[1]).sub(&a[1].mul(&b[0])),
    ]
}

#[inline]
fn dot<T: Arith>(a: &[T; 3], b: &[T; 3]) -> T {
    a[0].mul(&b[0]).add(&a[1].mul(&b[1])).add(&a[2].mul(&b[2]))
}

#[inline]
fn scale<T: Arith>(a: &[T; 3], k: &T) -> [T; 3] {
    [a[0].mul(k), a[1].mul(k), a[2].mul(k)]
}

#[inline]
fn add3<T: Arith>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [a[0].add(&b[0]), a[1].add(&b[1]), a[2].add(&b[2])]
}

/// Normal `(b - a) × (c - a)` of a triangle.
#[inline]
pub(crate) fn normal<T: Arith>(a: &[T; 3], b: &[T; 3], c: &[T; 3]) -> [T; 3] {
    cross(&sub3(b, a), &sub3(c, a))
}

#[inline]
pub(crate) fn conv3<T>(p: &Point3, conv: &dyn Fn(f64) -> T) -> [T; 3] {
    [conv(p[0]), conv(p[1]), conv(p[2])]
}

#[inline]
fn lpi_hom<T: Arith>(d: &[Point3; 5], conv: &dyn Fn(f64) -> T) -> [T; 4] {
    let [p, q, r, s, t] = d.map(|x| conv3(&x, conv));
    let n = normal(&r, &s, &t);
    let dir = sub3(&q, &p);
    let w = dot(&n, &dir);
    let num = dot(&n, &sub3(&r, &p));
    let xyz = add3(&scale(&p, &w), &scale(&dir, &num));
    let [x, y, z] = xyz;
    [x, y, z, w]
}

#[inline]
fn tpi_hom<T: Arith>(planes: &[[Point3; 3]; 3], conv: &dyn Fn(f64) -> T) -> [T; 4] {
    let nd = planes.map(|pl| {
        let [a, b, c] = pl.map(|x| conv3(&x, conv));
        let ni = normal(&a, &b, &c);
        let di = dot(&ni, &a);
        (ni, di)
    });
    let [(n0, d0), (n1, d1), (n2, d2)] = nd;
    let c23 = cross(&n1, &n2);
    let c31 = cross(&n2, &n0);
    let c12 = cross(&n0, &n1);
    let w = dot(&n0, &c23);
    let [x, y, z] = add3(
        &add3(&scale(&c23, &d0), &scale(&c31, &d1)),
        &scale(&c12, &d2),
    );
    [x, y, z, w]
}

/// The exact sign of a point's `W`, through the predicate cascade.
struct WSign<'a>(&'a Point);

impl Formula for WSign<'_> {
    type Point = Point;

    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], _conv: &dyn Fn(f64) -> T) -> T {
        let [_, _, _, w] = hom(self.0);
        w
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        std::iter::once(self.0)
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        std::iter::empty()
    }
    fn degree(&self) -> u32 {
        self.0.w_degree()
    }
}

fn all_finite(pts: &[Point3]) -> bool {
    pts.iter().flatten().all(|x| x.is_finite())
}

impl Point {
    /// The point's coordinate on axis `k` where its definition fixes it without arithmetic:
    /// an input vertex's own; for an [`Lpi`], the coordinate its three plane points share
    /// (the plane is the axis plane there) or its line's two ends share (the line lies in
    /// it); for a [`Tpi`], the coordinate the three points of one of its planes share.
    ///
    /// Exact and cheap: axis-aligned faces and edges (boxes, Menger sponges, extrusions, the
    /// tops of two cubes turned about z) make most exact zeros of the comparisons between
    /// intersection points ties of such coordinates, which the arithmetic stages would
    /// otherwise prove at thousands of instructions each.
    pub fn known_coordinate(&self, k: usize) -> Option<f64> {
        let shared = |points: &[Point3]| {
            let c = points[0][k];
            points.iter().all(|p| p[k] == c).then_some(c)
        };
        match self {
            Point::Explicit(p) => Some(p[k]),
            Point::Lpi(l) => shared(&l.def[2..]).or_else(|| shared(&l.def[..2])),
            Point::Tpi(t) => t.planes.iter().find_map(|plane| shared(plane)),
        }
    }

    /// The line through `p, q` meets the plane through `r, s, t` ([`Lpi`]).
    ///
    /// `None` when the line is parallel to the plane or the triangle `r, s, t` is degenerate
    /// (`W` exactly zero), or when a coordinate is not finite. A segment whose endpoints are
    /// on strictly opposite sides of the plane (by [`orient3d`](super::orient3d)) always gives
    /// `Some`.
    pub fn lpi(p: Point3, q: Point3, r: Point3, s: Point3, t: Point3) -> Option<Point> {
        let def = [p, q, r, s, t];
        if !all_finite(&def) {
            return None;
        }
        if let Some(pinned) = lpi_on_axis_planes(p, q, &[r, s, t]) {
            return Some(pinned);
        }
        let filter = filter_hom(&def, |conv| lpi_hom(&def, conv), |conv| lpi_hom(&def, conv));
        Point::Lpi(Arc::new(Lpi {
            def,
            filter,
            near: Nearby::of_box(&bounds_of(&filter)),
            w_sign: Sign::Zero,
        }))
        .with_w_sign()
    }

    /// The common point of the planes of three triangles ([`Tpi`]).
    ///
    /// `None` when the planes do not meet in exactly one point (`W = det(n1, n2, n3)` exactly
    /// zero: two planes parallel, the three through one line, or a degenerate triangle), or
    /// when a coordinate is not finite.
    pub fn tpi(planes: [[Point3; 3]; 3]) -> Option<Point> {
        if !all_finite(planes.as_flattened()) {
            return None;
        }
        if let Some(pinned) = tpi_on_axis_planes(&planes) {
            return Some(pinned);
        }
        let filter = filter_hom(
            planes.as_flattened(),
            |conv| tpi_hom(&planes, conv),
            |conv| tpi_hom(&planes, conv),
        );
        Point::Tpi(Arc::new(Tpi {
            planes,
            filter,
            near: Nearby::of_box(&bounds_of(&filter)),
            w_sign: Sign::Zero,
        }))
        .with_w_sign()
    }

    /// A newly built implicit point with the exact sign of its `W` stored, `None` when `W` is
    /// exactly zero (no such point). Its definition is not shared yet, so storing the sign
    /// writes in place.
    fn with_w_sign(mut self) -> Option<Point> {
        let w_sign = decide(&WSign(&self));
        if w_sign == Sign::Zero {
            return None;
        }
        match &mut self {
            Point::Explicit(_) => {}
            Point::Lpi(l) => Arc::make_mut(l).w_sign = w_sign,
            Point::Tpi(t) => Arc::make_mut(t).w_sign = w_sign,
        }
        Some(self)
    }

    /// The crossing point of the lines of two coplanar edges `e` and `f`, both lying in the
    /// plane of `tri` (the coplanar edge–edge case of triangle–triangle intersection).
    ///
    /// Built as a [`Tpi`] of the plane of `tri` and, for each edge, a plane through the edge
    /// and the direction of axis `drop`: its third point is the edge's first endpoint with
    /// coordinate `drop` halved (or set to 1 when zero), which is exact and always differs
    /// from the endpoint. Use `drop = Axis::of_largest(normal of tri)`.
    ///
    /// `None` when the lines are parallel in the projection along `drop`, when the plane of
    /// `tri` is parallel to axis `drop`, or when a triangle is degenerate. If the edges are
    /// not in the plane of `tri`, the point is still well defined (the plane of `tri` meets
    /// the two edge planes) but is not on the edges: that is the caller's precondition.
    pub fn edge_crossing(
        tri: [Point3; 3],
        e: [Point3; 2],
        f: [Point3; 2],
        drop: Axis,
    ) -> Option<Point> {
        let k = drop.index();
        let lift = |a: Point3| {
            let mut c = a;
            c[k] = if a[k] == 0.0 { 1.0 } else { a[k] * 0.5 };
            c
        };
        Point::tpi([tri, [e[0], e[1], lift(e[0])], [f[0], f[1], lift(f[0])]])
    }

    /// True for an input vertex.
    pub fn is_explicit(&self) -> bool {
        matches!(self, Point::Explicit(_))
    }

    /// Coordinates rounded to f64 (from the midpoints of the cached filter intervals, so a
    /// few ulps off, and possibly far off or not finite where the filter cannot bound `W` away
    /// from zero: the engine's stages read the kernel's `approx_point`, which rounds those
    /// exactly). No decision may be based on them.
    pub fn approx(&self) -> Point3 {
        match self {
            Point::Explicit(p) => *p,
            Point::Lpi(_) | Point::Tpi(_) => {
                let filter = self.filter_hom();
                let mid = |i: &Interval| i.mid();
                let w = mid(&filter[3]);
                [
                    mid(&filter[0]) / w,
                    mid(&filter[1]) / w,
                    mid(&filter[2]) / w,
                ]
            }
        }
    }

    /// A box certain to contain the exact point, `(min, max)`. Unbounded when the interval
    /// of `W` contains zero (a nearly degenerate definition, where [`Point::approx`] may be
    /// far off).
    pub fn enclosure(&self) -> (Point3, Point3) {
        match self {
            Point::Explicit(p) => (*p, *p),
            Point::Lpi(l) => l.near.enclosure(),
            Point::Tpi(t) => t.near.enclosure(),
        }
    }

    /// The point's Cartesian coordinates to within a known error: an input vertex's own,
    /// exactly; an intersection point's as cached at construction.
    #[inline]
    pub(crate) fn nearby(&self) -> Nearby {
        match self {
            Point::Explicit(p) => Nearby::exact(*p),
            Point::Lpi(l) => l.near,
            Point::Tpi(t) => t.near,
        }
    }

    /// The triangles whose planes define the point: none for an input vertex, one for an
    /// [`Lpi`], three for a [`Tpi`]. The point lies on each of these planes exactly.
    pub(crate) fn defining_planes(&self) -> impl Iterator<Item = [Point3; 3]> + '_ {
        let (lpi, tpi): (Option<[Point3; 3]>, &[[Point3; 3]]) = match self {
            Point::Explicit(_) => (None, &[]),
            Point::Lpi(l) => (Some(l.definition().2), &[]),
            Point::Tpi(t) => (None, t.planes()),
        };
        lpi.into_iter().chain(tpi.iter().copied())
    }

    /// True when the point is defined as lying on the plane of a triangle whose vertices are
    /// those of `tri` (in any order): the plane of an [`Lpi`], one of the planes of a [`Tpi`].
    /// A cheap structural test; `false` says nothing.
    pub(crate) fn defined_on_plane_of(&self, tri: &[Point3; 3]) -> bool {
        let same = |u: &[Point3], v: &[Point3; 3]| v.iter().all(|x| u.contains(x));
        match self {
            Point::Explicit(_) => false,
            Point::Lpi(l) => same(&l.def[2..], tri),
            Point::Tpi(t) => t.planes.iter().any(|pl| same(pl, tri)),
        }
    }

    /// Degree of `W` as a polynomial in the defining coordinates.
    pub(crate) fn w_degree(&self) -> u32 {
        match self {
            Point::Explicit(_) => 0,
            Point::Lpi(_) => 3,
            Point::Tpi(_) => 6,
        }
    }

    /// The exact sign of `W` (positive for explicit points).
    pub(crate) fn w_sign(&self) -> Sign {
        match self {
            Point::Explicit(_) => Sign::Positive,
            Point::Lpi(l) => l.w_sign,
            Point::Tpi(t) => t.w_sign,
        }
    }
}

/// The axis plane a non-degenerate triangle lies in, as the axis and the coordinate its
/// corners share, when they share exactly one and the filter shows the corners, projected
/// along that axis, are not collinear (the normal, along that axis, is that orientation);
/// `None` otherwise, degenerate triangles included.
fn axis_plane(t: &[Point3; 3]) -> Option<(usize, f64)> {
    let shares = |k: usize| t[1][k] == t[0][k] && t[2][k] == t[0][k];
    let k = match [shares(0), shares(1), shares(2)] {
        [true, false, false] => 0,
        [false, true, false] => 1,
        [false, false, true] => 2,
        _ => return None,
    };
    let [a, b, c] = t.map(Nearby::exact);
    nearby::orient2d(&a, &b, &c, (k + 1) % 3, (k + 2) % 3)?;
    Some((k, t[0][k]))
}

/// [`Point::lpi`] as an explicit point when its plane is an axis plane (of a non-degenerate
/// triangle) and its line runs along that axis (its ends share their other two coordinates):
/// the point is then those three input coordinates.
///
/// Why: on boxes, Menger sponges and most CAD parts, edges along one axis cross faces across
/// it. Such points are input coordinates exactly; built as implicit points they cost a
/// thousand instructions or more each (filter intervals, the sign of `W`), and every later
/// predicate on them many more, where on an explicit point it is a few float operations.
fn lpi_on_axis_planes(p: Point3, q: Point3, plane: &[Point3; 3]) -> Option<Point> {
    let (k, level) = axis_plane(plane)?;
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    if p[i] != q[i] || p[j] != q[j] || p[k] == q[k] {
        return None;
    }
    let mut x = p;
    x[k] = level;
    Some(Point::Explicit(x))
}

/// [`Point::tpi`] as an explicit point when its planes are axis planes (of non-degenerate
/// triangles) of the three axes: the point is their three coordinates. The coplanar crossings
/// of axis-aligned edges (two faces of two boxes) are such points; see
/// [`lpi_on_axis_planes`] for why.
fn tpi_on_axis_planes(planes: &[[Point3; 3]; 3]) -> Option<Point> {
    let mut coordinates = [None; 3];
    for plane in planes {
        let (k, level) = axis_plane(plane)?;
        coordinates[k] = Some(level);
    }
    // Two planes along one axis leave a coordinate unset.
    let [Some(x), Some(y), Some(z)] = coordinates else {
        return None;
    };
    Some(Point::Explicit([x, y, z]))
}

/// The range of defining coordinates [`filter_hom`] evaluates as [`Tracked`] numbers:
/// `[2^-30, 2^30]`.
const TRACKED_LOW: f64 = f64::from_bits((1023 - 30) << 52);
const TRACKED_HIGH: f64 = f64::from_bits((1023 + 30) << 52);

/// A point's homogeneous coordinates as filter intervals, from its defining points `def`:
/// evaluated as [`Tracked`] numbers when every defining coordinate is zero or of magnitude in
/// `[2^-30, 2^30]` (at most `2^30` for its numeric model, at least `2^-30` so that its
/// allowance for underflow, `2^-800`, stays far below the coordinates' own errors), else (or
/// when that overflows) in interval arithmetic.
fn filter_hom(
    def: &[Point3],
    tracked: impl FnOnce(&dyn Fn(f64) -> Tracked) -> [Tracked; 4],
    interval: impl FnOnce(&dyn Fn(f64) -> Interval) -> [Interval; 4],
) -> [Interval; 4] {
    let in_range = |x: f64| x == 0.0 || (TRACKED_LOW..=TRACKED_HIGH).contains(&x.abs());
    if def.iter().flatten().all(|&x| in_range(x)) {
        let [x, y, z, w] = tracked(&Tracked::exact).map(|t| t.enclosure());
        if let (Some(x), Some(y), Some(z), Some(w)) = (x, y, z, w) {
            return [x, y, z, w];
        }
    }
    interval(&Interval::exact)
}

/// The Cartesian coordinates `X / W`, `Y / W`, `Z / W` of interval homogeneous coordinates,
/// divided with outward rounding; unbounded when the interval of `W` contains zero or a
/// quotient overflows.
fn bounds_of(hom: &[Interval; 4]) -> [Interval; 3] {
    let unbounded = [Interval::new(f64::NEG_INFINITY, f64::INFINITY); 3];
    let w = &hom[3];
    if !(w.lo() > 0.0 || w.hi() < 0.0) {
        return unbounded;
    }
    let mut bounds = unbounded;
    for (bound, n) in bounds.iter_mut().zip(hom) {
        let q = [
            n.lo() / w.lo(),
            n.lo() / w.hi(),
            n.hi() / w.lo(),
            n.hi() / w.hi(),
        ];
        if q.iter().any(|x| !x.is_finite()) {
            return unbounded;
        }
        // Each quotient is within half an ulp of the true one: one step outward covers it.
        *bound = Interval::new(
            next_down(q.iter().copied().fold(f64::INFINITY, f64::min)),
            next_up(q.iter().copied().fold(f64::NEG_INFINITY, f64::max)),
        );
    }
    bounds
}

impl Homogeneous for Point {
    fn hom<T: Arith>(&self, conv: &dyn Fn(f64) -> T, one: &T) -> [T; 4] {
        match self {
            Point::Explicit(p) => [conv(p[0]), conv(p[1]), conv(p[2]), one.clone()],
            Point::Lpi(l) => lpi_hom(&l.def, conv),
            Point::Tpi(t) => tpi_hom(&t.planes, conv),
        }
    }

    #[inline]
    fn filter_hom(&self) -> [Interval; 4] {
        match self {
            Point::Explicit(p) => [
                Interval::exact(p[0]),
                Interval::exact(p[1]),
                Interval::exact(p[2]),
                Interval::exact(1.0),
            ],
            Point::Lpi(l) => l.filter,
            Point::Tpi(t) => t.filter,
        }
    }

    fn coords(&self) -> &[f64] {
        match self {
            Point::Explicit(p) => p,
            Point::Lpi(l) => l.def.as_flattened(),
            Point::Tpi(t) => t.planes.as_flattened().as_flattened(),
        }
    }

    /// An implicit point's expansions from this thread's [`EXACT_HOM`] cache, computed and
    /// compressed on first use.
    fn hom_expansion(&self, scale: i32) -> Option<[Expansion; 4]> {
        if !self.coords().iter().all(|&x| in_cache_range(x)) {
            return None;
        }
        let compute = || {
            let one = Expansion::exact(1.0);
            let hom = self.hom(&Expansion::exact, &one);
            // A product that may have underflowed unscaled: the caller's scaled inputs
            // decide instead.
            (hom.iter().all(|h| h.sign().is_some())).then(|| hom.map(|h| h.compressed()))
        };
        // Inputs scaled by 2^s scale a coordinate of degree d by 2^(s d); W has the degree
        // of the point's definition, X, Y and Z one more.
        let w_degree = self.w_degree() as i32;
        let scaled = |[x, y, z, w]: &[Expansion; 4]| {
            Some([
                x.scaled_by_pow2(scale * (w_degree + 1))?,
                y.scaled_by_pow2(scale * (w_degree + 1))?,
                z.scaled_by_pow2(scale * (w_degree + 1))?,
                w.scaled_by_pow2(scale * w_degree)?,
            ])
        };
        cached(&EXACT_HOM, self, compute, scaled)?
    }

    /// An implicit point's double-doubles from this thread's [`DOUBLE_DOUBLE_HOM`] cache,
    /// computed on first use.
    fn hom_double_double(&self) -> Option<[DoubleDouble; 4]> {
        let compute = || Some(self.hom(&DoubleDouble::exact, &DoubleDouble::exact(1.0)));
        cached(&DOUBLE_DOUBLE_HOM, self, compute, |hom| *hom)
    }
}

/// `read` of `point`'s entry in a thread's cache of homogeneous coordinates (`None` for an
/// explicit point, which has its coordinates at hand), made by `compute` on a miss (`None`:
/// nothing to cache). A full cache starts again.
fn cached<T, R>(
    cache: &'static LocalKey<RefCell<FxHashMap<HomKey, T>>>,
    point: &Point,
    compute: impl FnOnce() -> Option<T>,
    read: impl FnOnce(&T) -> R,
) -> Option<R> {
    if point.is_explicit() {
        return None;
    }
    let key: HomKey = point.coords().iter().map(|x| x.to_bits()).collect();
    cache.with(|cache| {
        let mut cache = cache.borrow_mut();
        if cache.len() >= HOM_CACHE_CAPACITY && !cache.contains_key(&key) {
            cache.clear();
        }
        // One hash of the key, hit or miss.
        match cache.entry(key) {
            Entry::Occupied(found) => Some(read(found.get())),
            Entry::Vacant(slot) => Some(read(slot.insert(compute()?))),
        }
    })
}

/// Whether an input coordinate is 0 or of magnitude in `[2^-60, 2^60]`: then a point's
/// unscaled expansions neither overflow (its `X` is of degree 7, under `2^(7 · 62)`) nor, in
/// the common case, underflow; other points are computed from the scaled inputs as before.
fn in_cache_range(x: f64) -> bool {
    const LOW: f64 = f64::from_bits((1023 - 60) << 52);
    const HIGH: f64 = f64::from_bits((1023 + 60) << 52);
    x == 0.0 || (LOW..=HIGH).contains(&x.abs())
}

/// A point's defining coordinates, bit for bit: equal keys define the same point the same
/// way (an [`Lpi`] has 15, a [`Tpi`] 27, so the kinds never collide).
type HomKey = SmallVec<[u64; 27]>;

/// Implicit points a thread's cache holds before it starts again: thousands of points, a few
/// megabytes of expansions at most.
const HOM_CACHE_CAPACITY: usize = 4096;

thread_local! {
    /// Per thread, the exact homogeneous coordinates of the implicit points the expansion
    /// stage has met, unscaled and compressed. Why: the filter fails in runs (the points of a
    /// near-degenerate configuration, such as a cube turned by 1e-7 rad, are compared with
    /// each other over and over while one triangle is split), and computing an intersection
    /// point's coordinates as expansions costs most of each such predicate (a [`Tpi`]'s `X`
    /// is a degree-7 polynomial); a compressed copy also makes every product with it short.
    static EXACT_HOM: RefCell<FxHashMap<HomKey, [Expansion; 4]>> =
        RefCell::new(FxHashMap::default());

    /// Per thread, the double-double homogeneous coordinates of the implicit points the
    /// double-double stage has met: the same runs, where the coordinates cost far more than
    /// the predicate's own products.
    static DOUBLE_DOUBLE_HOM: RefCell<FxHashMap<HomKey, [DoubleDouble; 4]>> =
        RefCell::new(FxHashMap::default());
}

impl Lpi {
    /// The segment endpoints `p, q` and the plane's triangle `r, s, t`.
    pub fn definition(&self) -> (Point3, Point3, [Point3; 3]) {
        let [p, q, r, s, t] = self.def;
        (p, q, [r, s, t])
    }
}

impl Tpi {
    /// The three triangles whose planes meet at this point.
    pub fn planes(&self) -> &[[Point3; 3]; 3] {
        &self.planes
    }
}
