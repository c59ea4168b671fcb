//! orient2d and orient3d on explicit f64 points: Shewchuk's adaptive predicates from the
//! `robust` crate (a faithful transcription of his `predicates.c`), with the answer as a
//! [`Sign`].
//!
//! Range: `robust` is exact unless an intermediate overflows or underflows. For polynomials of
//! degree 2 and 3 in differences of coordinates, that cannot happen while every nonzero
//! coordinate magnitude is in `[2^-200, 2^200)`: products stay below `2^609`, and every
//! partial product of Dekker's split stays above `2^(3 * (-200 - 53) - 53) > 2^-1022`.
//! Outside that range these functions answer through the implicit-point cascade (interval
//! filter, expansions, big integers), which is exact for every finite input.
//!
//! # Order of the tests
//! `robust`'s first stage (its floating-point filter, copied here) runs first: it decides
//! almost every answer in general position, and on a small grid (below) every nonzero answer
//! but those of coordinates spanning nearly the whole grid (the exact determinant is at least
//! one grid unit squared or cubed, above the filter's error bound until the coordinates
//! approach the span's limit). What it leaves is almost always a zero, which the following
//! tests find without `robust`'s adaptive stages (expansions, some thirty times the filter's
//! cost); every test is exact, so the order changes only the cost.
//!
//! # Zeros by comparison
//! Coplanar and collinear points are the rule in CAD parts, box unions, touching cubes and
//! parts rotated by a small angle, and many of these zeros need no arithmetic: points that
//! share one coordinate lie on one axis plane (the faces two operands share at `z = 0.5`, the
//! flat top of a cut), and a point given twice (a vertex tested against a triangle it belongs
//! to) makes any set coplanar and collinear.
//!
//! # Small grids
//! When every coordinate is a multiple of `2^e` below `2^(e + SPAN)` for a small bit span
//! (integers, quarter grids, the unit cube), the plain f64 formula has no rounding at all and
//! its sign is the answer: [`small_grid_span`] finds the span, stopping at the first
//! coordinate that rules it out. This also answers grid points outside `robust`'s safe range.

use robust::{Coord, Coord3D};

use super::arith::bit_range;
use super::cascade::decide;
use super::formulas::{Det3, PlaneSide};
use super::implicit::{Point, Point3};
use super::{Axis, Sign};

/// `|x|` at or above this may overflow or underflow inside `robust`: `2^200`.
const ROBUST_HIGH: f64 = f64::from_bits((1023 + 200) << 52);
/// Nonzero `|x|` below this may underflow inside `robust`: `2^-200`.
const ROBUST_LOW: f64 = f64::from_bits((1023 - 200) << 52);

#[inline]
fn in_robust_range(x: f64) -> bool {
    let a = x.abs();
    a < ROBUST_HIGH && (a >= ROBUST_LOW || a == 0.0)
}

/// Orientation of three points in the plane.
///
/// [`Sign::Positive`] when `c` lies to the left of the directed line `a → b` (counterclockwise
/// triangle), [`Sign::Negative`] when to the right, [`Sign::Zero`] when collinear. Exact for
/// all finite inputs.
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    let in_range = orient2d_filterable(&[a, b, c]);
    if let Some(sign) = in_range.then(|| orient2d_filter(a, b, c)).flatten() {
        return sign;
    }
    if zero_by_comparison(&[a, b, c]) {
        return Sign::Zero;
    }
    if small_grid_span(a.iter().chain(&b).chain(&c), ORIENT2D_SPAN) {
        // Differences take SPAN + 1 bits, products twice that, and their difference one more:
        // 2 (SPAN + 1) + 1 <= 53, so every operation is exact.
        let (acx, acy) = (a[0] - c[0], a[1] - c[1]);
        let (bcx, bcy) = (b[0] - c[0], b[1] - c[1]);
        return Sign::of(acx * bcy - acy * bcx);
    }
    if in_range {
        let v = robust::orient2d(
            Coord { x: a[0], y: a[1] },
            Coord { x: b[0], y: b[1] },
            Coord { x: c[0], y: c[1] },
        );
        return Sign::of(v);
    }
    orient2d_cascade(a, b, c)
}

/// Whether [`orient2d`]'s f64 filter is sound on points with these coordinates: none so large
/// or so small (but zero) that its products overflow or underflow.
#[inline]
pub(crate) fn orient2d_filterable(points: &[[f64; 2]]) -> bool {
    points.as_flattened().iter().all(|&x| in_robust_range(x))
}

/// Orientation of four points in space.
///
/// [`Sign::Positive`] when `d` lies below the plane through `a, b, c` — the side from which
/// `a, b, c` appear clockwise, opposite to the right-handed normal `(b - a) × (c - a)` —
/// [`Sign::Negative`] above, [`Sign::Zero`] when coplanar. Equals the sign of
/// `det[a - d; b - d; c - d]`. Exact for all finite inputs.
pub fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
    let points = [a, b, c, d];
    let in_range = points.as_flattened().iter().all(|&x| in_robust_range(x));
    if let Some(sign) = in_range.then(|| orient3d_filter(a, b, c, d)).flatten() {
        return sign;
    }
    if zero_by_comparison(&points) {
        return Sign::Zero;
    }
    if small_grid_span(points.as_flattened().iter(), ORIENT3D_SPAN) {
        // Differences take SPAN + 1 bits, the 2×2 minors 2 (SPAN + 1) + 1, the three terms
        // one more bit each after the products and the sum: 3 (SPAN + 1) + 3 <= 53, so every
        // operation is exact.
        let diff = |p: [f64; 3]| [p[0] - d[0], p[1] - d[1], p[2] - d[2]];
        let ([adx, ady, adz], [bdx, bdy, bdz], [cdx, cdy, cdz]) = (diff(a), diff(b), diff(c));
        let det = adx * (bdy * cdz - bdz * cdy)
            + bdx * (cdy * adz - cdz * ady)
            + cdx * (ady * bdz - adz * bdy);
        return Sign::of(det);
    }
    if in_range {
        let cv = |p: [f64; 3]| Coord3D {
            x: p[0],
            y: p[1],
            z: p[2],
        };
        return Sign::of(robust::orient3d(cv(a), cv(b), cv(c), cv(d)));
    }
    orient3d_cascade(a, b, c, d)
}

/// [`orient3d`] of one triangle `p, q, r` and many points, where a semi-static filter decides:
/// the plane's part of the determinant is computed once, and each point costs a few
/// multiplications, against the two hundred instructions of a call of [`orient3d`] (range
/// checks, then `robust`'s filter).
///
/// The filter is CGAL's for `orient3d` (`Static_filters/Orientation_3.h`, error bound by Meyer
/// & Pion's FPG, "A C++ static floating-point filter generator", 2008): the determinant of the
/// rows `q - p`, `r - p`, `s - p` evaluated in f64 is the true sign when its magnitude
/// exceeds `5.1107127829973299e-15` times the product of the largest absolute entry of each
/// row, provided those three maxima lie in `[1e-97, 1e102)` (no underflow or overflow). CGAL
/// bounds the columns of its matrix; we evaluate the transposed matrix, whose columns are our
/// rows, with the same formula (CGAL's `determinant`: 2 × 2 minors of its first two columns,
/// then expansion along the third), so the minors involve only `q - p` and `r - p`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PlaneFilter {
    origin: [f64; 3],
    /// CGAL's `m01`, `m02`, `m12` of the transposed matrix.
    minors: [f64; 3],
    /// The error bound's constant times the maxima of the rows `q - p` and `r - p`; NaN when
    /// they are out of the filter's range, which fails every comparison.
    scale: f64,
}

/// The semi-static error bound of CGAL's `Orientation_3` filter (see [`PlaneFilter`]).
const O3D_STATIC_BOUND: f64 = 5.110_712_782_997_33e-15;
/// Row maxima below this may underflow in the filter: `cbrt(f64::MIN_POSITIVE / eps)`.
const O3D_STATIC_LOW: f64 = 1e-97;
/// Row maxima at or above this may overflow in the filter.
const O3D_STATIC_HIGH: f64 = 1e102;

impl PlaneFilter {
    /// The plane of `p, q, r`.
    #[inline]
    pub(crate) fn new(&[p, q, r]: &[[f64; 3]; 3]) -> PlaneFilter {
        let (pq, pr) = (sub3(q, p), sub3(r, p));
        let minors = [
            pq[0] * pr[1] - pq[1] * pr[0],
            pq[0] * pr[2] - pq[2] * pr[0],
            pq[1] * pr[2] - pq[2] * pr[1],
        ];
        let (mq, mr) = (max_abs(pq), max_abs(pr));
        // Same operation order as CGAL's `eps = c * maxx * maxy * maxz`.
        let scale = if in_static_range(mq) && in_static_range(mr) {
            O3D_STATIC_BOUND * mq * mr
        } else {
            f64::NAN
        };
        PlaneFilter {
            origin: p,
            minors,
            scale,
        }
    }

    /// [`orient3d`]`(p, q, r, s)` where the filter decides it, `None` elsewhere.
    #[inline]
    pub(crate) fn side_if_clear(&self, s: [f64; 3]) -> Option<Sign> {
        match self.verdict(s) {
            (true, _) => Some(Sign::Positive),
            (_, true) => Some(Sign::Negative),
            _ => None,
        }
    }

    /// The filter's verdict on `s`, without branches: whether [`orient3d`] is certainly
    /// positive (`s` below the plane), and whether certainly negative. Neither when the
    /// filter cannot decide; never both.
    #[inline]
    pub(crate) fn verdict(&self, s: [f64; 3]) -> (bool, bool) {
        let [m01, m02, m12] = self.minors;
        let ps = sub3(s, self.origin);
        let det = m01 * ps[2] - m02 * ps[1] + m12 * ps[0];
        let ms = max_abs(ps);
        let eps = self.scale * ms;
        // A NaN `scale` fails both comparisons. `orient3d` is positive below the plane: the
        // opposite of this determinant's sign.
        let certain = in_static_range(ms);
        (certain & (det < -eps), certain & (det > eps))
    }
}

fn in_static_range(m: f64) -> bool {
    (O3D_STATIC_LOW..O3D_STATIC_HIGH).contains(&m)
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn max_abs(v: [f64; 3]) -> f64 {
    v[0].abs().max(v[1].abs()).max(v[2].abs())
}

/// True when component `axis` of the normal `(b − a) × (c − a)` of triangle `t` is exactly
/// zero: the triangle's plane contains the direction of that axis (or the triangle is
/// degenerate), as its projection along the axis is.
pub(crate) fn normal_component_is_zero(t: &[[f64; 3]; 3], axis: Axis) -> bool {
    let [p, q, r] = t.map(|x| axis.project(x));
    orient2d(p, q, r) == Sign::Zero
}

/// [`orient3d`] of the corners of a triangle in the axis plane `x_k = level` and a point
/// whose coordinate `k` is `coordinate`, where `turn` is the triangle's orientation projected
/// along `k` ([`orient2d`] of coordinates `k + 1`, `k + 2`, the frame of
/// [`Axis::project`](super::Axis::project)): expanded along column `k`, the determinant is
/// `(level - coordinate)` times that turn. Exact, with no arithmetic at all: where the
/// triangle is a face of a box or of a CAD part, the zeros that the orientation filter
/// cannot prove cost nothing.
pub fn side_of_axis_plane(level: f64, coordinate: f64, turn: Sign) -> Sign {
    let below = match coordinate.partial_cmp(&level) {
        Some(std::cmp::Ordering::Less) => Sign::Positive,
        Some(std::cmp::Ordering::Greater) => Sign::Negative,
        _ => Sign::Zero,
    };
    below.times(turn)
}

/// The bit span up to which [`orient2d`] evaluates its formula in plain f64: `2 (25 + 1) + 1 =
/// 53`.
const ORIENT2D_SPAN: i32 = 25;
/// The bit span up to which [`orient3d`] evaluates its formula in plain f64: `3 (15 + 1) + 3 =
/// 51 <= 53`.
const ORIENT3D_SPAN: i32 = 15;
/// Exponents of the lowest and highest set bits allowed on a small grid, so that no product of
/// three differences underflows or overflows: `3 · -300 > -1022` and `3 · (300 + 2) < 1023`.
const GRID_EXPONENTS: std::ops::RangeInclusive<i32> = -300..=300;

/// Whether the nonzero coordinates are all multiples of `2^low` below `2^(top + 1)` with
/// `top - low + 1 <= span` (and both within [`GRID_EXPONENTS`], which leaves out subnormal
/// numbers): the small-grid case of the [module docs](self).
#[inline]
fn small_grid_span<'a>(coords: impl Iterator<Item = &'a f64>, span: i32) -> bool {
    let (mut top, mut low) = (i32::MIN, i32::MAX);
    for &x in coords.filter(|&&x| x != 0.0) {
        let (x_low, x_top) = bit_range(x);
        (top, low) = (top.max(x_top), low.min(x_low));
        if top - low + 1 > span || !GRID_EXPONENTS.contains(&top) || !GRID_EXPONENTS.contains(&low)
        {
            return false;
        }
    }
    true
}

/// `robust::orient2d`'s first stage on its own: the sign of the f64 determinant where its
/// error bound (Ozaki et al.'s, as `robust` has it) proves it, `None` elsewhere. Copied so that
/// the [zeros by comparison](self#zeros-by-comparison) are asked only where it cannot decide;
/// `robust` then repeats it, a few operations, before its adaptive stages.
#[inline]
fn orient2d_filter(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<Sign> {
    orient2d_value_if_clear(a, b, c).map(Sign::of)
}

/// The f64 determinant of [`orient2d`] (twice the signed area of `a b c`) where the filter
/// proves its sign, the value `robust::orient2d` returns there; `None` where it cannot, which
/// bounds the area: at most [`ORIENT2D_THETA`] `· 2 |a - c| |b - c|`.
#[inline]
pub(crate) fn orient2d_value_if_clear(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<f64> {
    let left = (a[0] - c[0]) * (b[1] - c[1]);
    let right = (a[1] - c[1]) * (b[0] - c[0]);
    let det = left - right;
    let bound = ORIENT2D_THETA * (left + right).abs();
    (det >= bound || -det >= bound).then_some(det)
}

/// The error bound factor of the f64 orient2d determinant (Ozaki et al.'s, as `robust` has it):
/// `|exact - f64| <= THETA |left + right|` when the two products have one sign.
const ORIENT2D_THETA: f64 = 3.330_669_062_177_372_2e-16;

/// The f64 in-circle determinant of `d` against `a b c` (positive inside when `a b c` turns
/// counterclockwise) where Shewchuk's error bound (`iccerrboundA` of his `predicates.c`) makes
/// its sign certain; `None` where only exact arithmetic could tell (`d` on or within rounding
/// of the circle) or a value overflows or underflows. For choices of shape, which need no
/// exact answer.
pub(crate) fn incircle_value_if_clear(
    a: [f64; 2],
    b: [f64; 2],
    c: [f64; 2],
    d: [f64; 2],
) -> Option<f64> {
    const BOUND: f64 = (10.0 + 96.0 * EPSILON) * EPSILON;
    let (adx, ady) = (a[0] - d[0], a[1] - d[1]);
    let (bdx, bdy) = (b[0] - d[0], b[1] - d[1]);
    let (cdx, cdy) = (c[0] - d[0], c[1] - d[1]);
    let (bdxcdy, cdxbdy) = (bdx * cdy, cdx * bdy);
    let (cdxady, adxcdy) = (cdx * ady, adx * cdy);
    let (adxbdy, bdxady) = (adx * bdy, bdx * ady);
    let alift = adx * adx + ady * ady;
    let blift = bdx * bdx + bdy * bdy;
    let clift = cdx * cdx + cdy * cdy;
    let det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * alift
        + (cdxady.abs() + adxcdy.abs()) * blift
        + (adxbdy.abs() + bdxady.abs()) * clift;
    // A bound below the normal range may not cover products that underflowed.
    let bound = BOUND * permanent;
    (bound.is_normal() && (det > bound || -det > bound)).then_some(det)
}

/// Shewchuk's `ε`, half an ulp of 1, in which his error bounds are written.
const EPSILON: f64 = f64::EPSILON / 2.0;

/// `robust::orient3d`'s first stage on its own (Shewchuk's `o3derrboundA`), as
/// [`orient2d_filter`] is `robust::orient2d`'s.
#[inline]
fn orient3d_filter(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Option<Sign> {
    const BOUND: f64 = (7.0 + 56.0 * EPSILON) * EPSILON;
    let diff = |p: [f64; 3]| [p[0] - d[0], p[1] - d[1], p[2] - d[2]];
    let ([adx, ady, adz], [bdx, bdy, bdz], [cdx, cdy, cdz]) = (diff(a), diff(b), diff(c));
    let (bdxcdy, cdxbdy) = (bdx * cdy, cdx * bdy);
    let (cdxady, adxcdy) = (cdx * ady, adx * cdy);
    let (adxbdy, bdxady) = (adx * bdy, bdx * ady);
    let det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * adz.abs()
        + (cdxady.abs() + adxcdy.abs()) * bdz.abs()
        + (adxbdy.abs() + bdxady.abs()) * cdz.abs();
    let bound = BOUND * permanent;
    (det > bound || -det > bound).then(|| Sign::of(det))
}

/// Whether the orientation of `points` (`N + 1` of them in `N` dimensions) is zero because
/// they all share one coordinate or one of them is given twice: the
/// [zeros by comparison](self#zeros-by-comparison).
#[inline]
fn zero_by_comparison<const N: usize>(points: &[[f64; N]]) -> bool {
    let [first, rest @ ..] = points else {
        return true;
    };
    let on_axis_plane = (0..N).any(|axis| rest.iter().all(|p| p[axis] == first[axis]));
    on_axis_plane
        || (points.iter().enumerate()).any(|(i, p)| points[i + 1..].iter().any(|q| q == p))
}

/// [`orient3d`] through the cascade (for inputs outside `robust`'s safe range).
fn orient3d_cascade(a: Point3, b: Point3, c: Point3, d: Point3) -> Sign {
    decide(&PlaneSide {
        tri: [a, b, c],
        d: &Point::Explicit(d),
    })
}

/// [`orient2d`] through the cascade (for inputs outside `robust`'s safe range).
fn orient2d_cascade(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    let lift = |p: [f64; 2]| Point::Explicit([p[0], p[1], 0.0]);
    decide(&Det3 {
        pts: [&lift(a), &lift(b), &lift(c)],
        u: 0,
        v: 1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::tests::xorshift;

    #[test]
    fn conventions() {
        assert_eq!(orient2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), Sign::Positive);
        assert_eq!(orient2d([0.0, 0.0], [1.0, 0.0], [2.0, 0.0]), Sign::Zero);
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // The normal (b - a) × (c - a) is +z; a point above is negative.
        assert_eq!(orient3d(a, b, c, [0.0, 0.0, 1.0]), Sign::Negative);
        assert_eq!(orient3d(a, b, c, [0.0, 0.0, -1.0]), Sign::Positive);
        assert_eq!(orient3d(a, b, c, [5.0, 7.0, 0.0]), Sign::Zero);
    }

    #[test]
    fn plane_filter_bound_is_cgals() {
        assert_eq!(
            O3D_STATIC_BOUND,
            "5.1107127829973299e-15".parse::<f64>().unwrap()
        );
    }

    /// Wherever the plane filter decides, it gives [`orient3d`]'s sign: random triangles and
    /// points at several scales, many within a few ulps of the plane.
    #[test]
    fn plane_filter_agrees_with_orient3d() {
        let mut next = xorshift(0x706c_616e_6566_0001);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let (mut decided, mut total) = (0, 0);
        for scale in [1e-90, 1e-3, 1.0, 1e7, 1e100] {
            for _ in 0..2000 {
                let mut point = || [unit(), unit(), unit()].map(|x| x * scale);
                let t = [point(), point(), point()];
                let far = point();
                let plane = PlaneFilter::new(&t);
                // A point near the plane: an affine combination of the corners, rounded.
                let (u, v) = (unit(), unit());
                let near =
                    [0, 1, 2].map(|k| t[0][k] + u * (t[1][k] - t[0][k]) + v * (t[2][k] - t[0][k]));
                for s in [far, near] {
                    total += 1;
                    if let Some(side) = plane.side_if_clear(s) {
                        decided += 1;
                        assert_eq!(side, orient3d(t[0], t[1], t[2], s), "{t:?} {s:?}");
                    }
                }
            }
        }
        assert!(decided * 2 > total, "{decided} of {total} decided");
    }

    #[test]
    fn small_grids_are_recognised_by_their_bit_span() {
        let grid = |v: &[f64], span| small_grid_span(v.iter(), span);
        assert!(grid(&[0.0, 1.0, 2.0, 0.25, -3.0], 4));
        assert!(!grid(&[0.0, 1.0, 2.0, 0.25, -3.0], 3));
        assert!(grid(&[0.0, 0.0], 1), "zeros alone are on every grid");
        assert!(!grid(&[0.1], 15), "0.1 uses all 53 bits");
        assert!(
            !grid(&[1e-310], 15),
            "subnormals are left to the other stages"
        );
        assert!(!grid(&[2f64.powi(301)], 15));
        assert!(grid(&[2f64.powi(300), 2f64.powi(290)], 15));
    }

    /// The plain formula on small grids agrees with the exact cascade, including the zeros it
    /// exists for, near the largest spans it accepts.
    #[test]
    fn small_grid_answers_match_the_cascade() {
        let mut random = xorshift(0x2545_f491_4f6c_dd1d);
        let mut next = |bits: u32| {
            let state = random();
            let magnitude = (state >> 11) % (1 << bits);
            let value = magnitude as f64 * 2f64.powi(-3);
            if state & 1 == 0 { value } else { -value }
        };
        let mut zeros = 0;
        for round in 0..20_000 {
            // Spans up to the limits, and tiny grids where coplanar and collinear cases abound.
            let bits3 = if round % 2 == 0 {
                2
            } else {
                ORIENT3D_SPAN as u32 - 1
            };
            let p3 = |next: &mut dyn FnMut(u32) -> f64| [next(bits3), next(bits3), next(bits3)];
            let (a, b, c, d) = (p3(&mut next), p3(&mut next), p3(&mut next), p3(&mut next));
            let coords = || a.iter().chain(&b).chain(&c).chain(&d);
            assert!(
                small_grid_span(coords(), ORIENT3D_SPAN),
                "{a:?} {b:?} {c:?} {d:?}"
            );
            let fast = orient3d(a, b, c, d);
            assert_eq!(
                fast,
                orient3d_cascade(a, b, c, d),
                "{a:?} {b:?} {c:?} {d:?}"
            );
            zeros += usize::from(fast == Sign::Zero);
            let bits2 = if round % 2 == 0 {
                2
            } else {
                ORIENT2D_SPAN as u32 - 1
            };
            let p2 = |next: &mut dyn FnMut(u32) -> f64| [next(bits2), next(bits2)];
            let (a, b, c) = (p2(&mut next), p2(&mut next), p2(&mut next));
            assert_eq!(
                orient2d(a, b, c),
                orient2d_cascade(a, b, c),
                "{a:?} {b:?} {c:?}"
            );
        }
        assert!(zeros > 100, "the tiny grids give coplanar cases: {zeros}");
    }

    /// Points on one axis plane (or axis line) are answered zero by comparison, and points
    /// off it are not: the cascade agrees on both, at coordinates no small grid holds.
    #[test]
    fn axis_planes_and_repeated_points_are_zero_and_only_they() {
        let (p, q, r) = (0.1, 0.30000000000000004, 0.7);
        let plane = [[p, q, 0.5], [r, p, 0.5], [q, r, 0.5], [0.2, 0.9, 0.5]];
        assert!(zero_by_comparison(&plane));
        let [a, b, c, d] = plane;
        assert_eq!(orient3d(a, b, c, d), Sign::Zero);
        assert_eq!(orient3d_cascade(a, b, c, d), Sign::Zero);
        let below = [0.2, 0.9, 0.5f64.next_down()];
        assert!(!zero_by_comparison(&[a, b, c, below]));
        assert_eq!(orient3d(a, b, c, below), orient3d_cascade(a, b, c, below));
        assert_ne!(orient3d(a, b, c, below), Sign::Zero);
        let line = [[p, 0.25], [q, 0.25], [r, 0.25]];
        assert_eq!(orient2d(line[0], line[1], line[2]), Sign::Zero);
        let off = [r, 0.25f64.next_up()];
        assert_eq!(
            orient2d(line[0], line[1], off),
            orient2d_cascade(line[0], line[1], off)
        );
        assert_ne!(orient2d(line[0], line[1], off), Sign::Zero);
        let (u, v, w) = ([p, q, r], [q, r, 0.9], [r, 0.2, q]);
        assert!(zero_by_comparison(&[u, v, w, v]));
        assert_eq!(orient3d(u, v, w, v), Sign::Zero);
        assert!(!zero_by_comparison(&[u, v, w, [0.2, p, r]]));
        assert!(zero_by_comparison(&[[p, q], [r, p], [p, q]]));
        assert_eq!(orient2d([p, q], [r, p], [p, q]), Sign::Zero);
    }

    /// Off every grid, near and on planes and lines (where the filter must pass the question
    /// on) and away from them (where it answers), the answers are the cascade's.
    #[test]
    fn filtered_answers_match_the_cascade() {
        let mut random = xorshift(0x9e37_79b9_7f4a_7c15);
        let mut next = || (random() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
        let (mut zeros, mut decided) = (0, 0);
        for round in 0..20_000 {
            let mut p3 = || [next(), next(), next()];
            let (a, b, c, far) = (p3(), p3(), p3(), p3());
            // `d` on the segment from `a` to the midpoint of `b c`, nudged by 0, 1 or 2 ulps.
            let t = a[0].abs();
            let mut d = [0.0; 3];
            for k in 0..3 {
                d[k] = a[k] + t * ((b[k] + c[k]) / 2.0 - a[k]);
                for _ in 0..round % 3 {
                    d[k] = d[k].next_up();
                }
            }
            for d in [d, far] {
                let fast = orient3d(a, b, c, d);
                assert_eq!(
                    fast,
                    orient3d_cascade(a, b, c, d),
                    "{a:?} {b:?} {c:?} {d:?}"
                );
                decided += usize::from(orient3d_filter(a, b, c, d).is_some());
            }
            let (a2, b2) = ([a[0], a[1]], [b[0], b[1]]);
            let c2 = [a2[0] + t * (b2[0] - a2[0]), a2[1] + t * (b2[1] - a2[1])];
            for c2 in [c2, [far[0], far[1]], a2] {
                let fast = orient2d(a2, b2, c2);
                assert_eq!(fast, orient2d_cascade(a2, b2, c2), "{a2:?} {b2:?} {c2:?}");
                zeros += usize::from(fast == Sign::Zero);
            }
        }
        assert!(
            zeros >= 20_000,
            "the repeated points and some on lines are zeros: {zeros}"
        );
        assert!(
            decided > 20_000,
            "the points off the plane are decided by the filter"
        );
    }

    #[test]
    fn out_of_robust_range_is_still_exact() {
        let h = 1e300;
        let (a, b, c) = ([0.0, 0.0, 0.0], [h, 0.0, 0.0], [0.0, h, 0.0]);
        assert_eq!(orient3d(a, b, c, [h, h, h]), Sign::Negative);
        assert_eq!(orient3d(a, b, c, [h, h, 0.0]), Sign::Zero);
        let t = 1e-310;
        assert_eq!(orient2d([0.0, 0.0], [t, 0.0], [0.0, t]), Sign::Positive);
        assert_eq!(orient2d([0.0, 0.0], [t, t], [2.0 * t, 2.0 * t]), Sign::Zero);
    }
}
