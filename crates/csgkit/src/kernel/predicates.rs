//! Predicates with explicit and implicit arguments, and the cascade that evaluates them.
//!
//! Each predicate is a [`Formula`]: one generic polynomial, evaluated first in
//! [`Interval`]s (from the points' cached coordinates, no allocation), then in
//! [`Expansion`]s, then in big integers ([`Big`]), stopping at the first stage that decides
//! (see the [module docs](super) for the numeric model). The sign of the polynomial is then
//! multiplied by the signs of the points' `W`s, known exactly since construction.

use std::cmp::Ordering;

use super::arith::{Arith, Big, decompose, exponent, scaled_expansion};
use super::expansion::Expansion;
use super::implicit::{Point, Point3, conv3, normal};
use super::interval::Interval;
use super::{Axis, Sign, expansion_top_exponent, orient2d, orient3d};

/// A polynomial sign question about some points.
pub(crate) trait Formula {
    /// The polynomial in number type `T`: `hom` gives a point's homogeneous coordinates,
    /// `conv` converts an explicit input coordinate.
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], conv: &dyn Fn(f64) -> T) -> T;
    /// The points whose homogeneous coordinates `eval` asks for.
    fn points(&self) -> impl Iterator<Item = &Point>;
    /// The explicit coordinates `eval` converts with `conv`.
    fn explicit_coords(&self) -> impl Iterator<Item = f64>;
    /// The total degree of the polynomial in the input coordinates.
    fn degree(&self) -> u32;
}

/// The exact sign of a formula: filter first, then the exact stages.
#[inline]
pub(crate) fn decide(f: &impl Formula) -> Sign {
    let v = f.eval::<Interval>(&|p| p.filter_hom(), &Interval::exact);
    match v.sign() {
        Some(s) => s,
        None => decide_exact(f),
    }
}

/// Stages 2 and 3 of the cascade.
fn decide_exact(f: &impl Formula) -> Sign {
    let (top, e_low) = scan(f);
    match expansion_stage(f, top) {
        Some(s) => s,
        None => big_stage(f, e_low),
    }
}

/// The exponent of the largest input magnitude and the exponent of the lowest set bit over
/// all inputs (both 0 when every input is zero).
fn scan(f: &impl Formula) -> (i32, i32) {
    let mut max = 0.0f64;
    let mut e_low = i32::MAX;
    let mut visit = |x: f64| {
        debug_assert!(x.is_finite(), "predicate inputs are finite");
        if x != 0.0 {
            max = max.max(x.abs());
            e_low = e_low.min(decompose(x).1);
        }
    };
    f.points().flat_map(|p| p.coords()).for_each(|&x| visit(x));
    f.explicit_coords().for_each(&mut visit);
    if max == 0.0 {
        (0, 0)
    } else {
        (exponent(max), e_low)
    }
}

/// Stage 2: expansions after scaling the largest input to `2^T` (see
/// [`expansion_bit_span`](super::expansion_bit_span)); `None` if a product may have
/// underflowed.
fn expansion_stage(f: &impl Formula, top: i32) -> Option<Sign> {
    let s = expansion_top_exponent(f.degree().max(1)) - top;
    let conv = |x: f64| scaled_expansion(x, s);
    let one = Expansion::exact(1.0);
    f.eval::<Expansion>(&|p| p.hom(&conv, &one), &conv).sign()
}

/// Stage 3: big integers, exact for every finite input.
fn big_stage(f: &impl Formula, e_low: i32) -> Sign {
    let conv = |x: f64| Big::scaled(x, e_low);
    let one = Big::one();
    f.eval::<Big>(&|p| p.hom(&conv, &one), &conv)
        .sign()
        .expect("big integers always decide")
}

/// What each stage of the cascade answers on its own: filter, expansions, big integers.
#[cfg(test)]
pub(crate) fn stages(f: &impl Formula) -> [Option<Sign>; 3] {
    let filter = f
        .eval::<Interval>(&|p| p.filter_hom(), &Interval::exact)
        .sign();
    let (top, e_low) = scan(f);
    [filter, expansion_stage(f, top), Some(big_stage(f, e_low))]
}

/// `-(n · (X - W a))` with `n = (b - a) × (c - a)`: the orient3d of an explicit triangle and
/// a homogeneous point, before the factor `sign(W)`.
pub(crate) struct PlaneSide<'a> {
    pub(crate) tri: [Point3; 3],
    pub(crate) d: &'a Point,
}

impl Formula for PlaneSide<'_> {
    #[inline]
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], conv: &dyn Fn(f64) -> T) -> T {
        let [a, b, c] = self.tri.map(|p| conv3(&p, conv));
        let n = normal(&a, &b, &c);
        let [x, y, z, w] = hom(self.d);
        // n · (W a - X)
        let e0 = w.mul(&a[0]).sub(&x);
        let e1 = w.mul(&a[1]).sub(&y);
        let e2 = w.mul(&a[2]).sub(&z);
        n[0].mul(&e0).add(&n[1].mul(&e1)).add(&n[2].mul(&e2))
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        std::iter::once(self.d)
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        self.tri.into_iter().flatten()
    }
    fn degree(&self) -> u32 {
        3 + self.d.w_degree()
    }
}

/// `det[[X_i, Y_i, Z_i, W_i]]` over four points: `orient3d` times `W_a W_b W_c W_d`.
pub(crate) struct Det4<'a>(pub(crate) [&'a Point; 4]);

impl Formula for Det4<'_> {
    #[inline]
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], _conv: &dyn Fn(f64) -> T) -> T {
        let r = self.0.map(hom);
        // Laplace expansion along columns (0, 1) against columns (2, 3).
        let lo = |i: usize, j: usize| r[i][0].mul(&r[j][1]).sub(&r[j][0].mul(&r[i][1]));
        let hi = |i: usize, j: usize| r[i][2].mul(&r[j][3]).sub(&r[j][2].mul(&r[i][3]));
        let plus = lo(0, 1)
            .mul(&hi(2, 3))
            .add(&lo(0, 3).mul(&hi(1, 2)))
            .add(&lo(1, 2).mul(&hi(0, 3)))
            .add(&lo(2, 3).mul(&hi(0, 1)));
        let minus = lo(0, 2).mul(&hi(1, 3)).add(&lo(1, 3).mul(&hi(0, 2)));
        plus.sub(&minus)
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        self.0.into_iter()
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        std::iter::empty()
    }
    fn degree(&self) -> u32 {
        3 + self.0.iter().map(|p| p.w_degree()).sum::<u32>()
    }
}

/// `det[[U_i, V_i, W_i]]` over three points, `(U, V)` the coordinates kept after dropping
/// one: `orient2d` of the projection times `W_a W_b W_c`.
pub(crate) struct Det3<'a> {
    pub(crate) pts: [&'a Point; 3],
    pub(crate) u: usize,
    pub(crate) v: usize,
}

impl Formula for Det3<'_> {
    #[inline]
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], _conv: &dyn Fn(f64) -> T) -> T {
        let r = self.pts.map(hom);
        let (u, v) = (self.u, self.v);
        let m = |i: usize, j: usize| r[i][u].mul(&r[j][v]).sub(&r[j][u].mul(&r[i][v]));
        // Expansion along the W column.
        r[2][3]
            .mul(&m(0, 1))
            .add(&r[0][3].mul(&m(1, 2)))
            .sub(&r[1][3].mul(&m(0, 2)))
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        self.pts.into_iter()
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        std::iter::empty()
    }
    fn degree(&self) -> u32 {
        2 + self.pts.iter().map(|p| p.w_degree()).sum::<u32>()
    }
}

/// `X_a W_b - X_b W_a` along one axis: the coordinate difference times `W_a W_b`.
pub(crate) struct AxisDiff<'a> {
    pub(crate) a: &'a Point,
    pub(crate) b: &'a Point,
    pub(crate) axis: usize,
}

impl Formula for AxisDiff<'_> {
    #[inline]
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], _conv: &dyn Fn(f64) -> T) -> T {
        let ha = hom(self.a);
        let hb = hom(self.b);
        let i = self.axis;
        ha[i].mul(&hb[3]).sub(&hb[i].mul(&ha[3]))
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        [self.a, self.b].into_iter()
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        std::iter::empty()
    }
    fn degree(&self) -> u32 {
        1 + self.a.w_degree() + self.b.w_degree()
    }
}

/// [`orient3d`] through the cascade (for inputs outside `robust`'s safe range).
pub(crate) fn orient3d_cascade(a: Point3, b: Point3, c: Point3, d: Point3) -> Sign {
    decide(&PlaneSide {
        tri: [a, b, c],
        d: &Point::Explicit(d),
    })
}

/// [`orient2d`] through the cascade (for inputs outside `robust`'s safe range).
pub(crate) fn orient2d_cascade(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    let lift = |p: [f64; 2]| Point::Explicit([p[0], p[1], 0.0]);
    decide(&Det3 {
        pts: [&lift(a), &lift(b), &lift(c)],
        u: 0,
        v: 1,
    })
}

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
    decide(&PlaneSide { tri: [a, b, c], d }).times(d.w_sign())
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
    let k = drop.index();
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    if let (Point::Explicit(a), Point::Explicit(b), Point::Explicit(c)) = (a, b, c) {
        return orient2d([a[u], a[v]], [b[u], b[v]], [c[u], c[v]]);
    }
    if collinear_by_construction(a, b, c) {
        return Sign::Zero;
    }
    let w = a.w_sign().times(b.w_sign()).times(c.w_sign());
    decide(&Det3 {
        pts: [a, b, c],
        u,
        v,
    })
    .times(w)
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
    if let (Point::Explicit(pa), Point::Explicit(pb)) = (a, b) {
        // `partial_cmp` treats -0 and +0 as equal; NaN is excluded by precondition.
        return pa[i].partial_cmp(&pb[i]).unwrap_or(Ordering::Equal);
    }
    let w = a.w_sign().times(b.w_sign());
    decide(&AxisDiff { a, b, axis: i }).times(w).to_ordering()
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
