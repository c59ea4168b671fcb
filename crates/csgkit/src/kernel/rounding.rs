//! Rounding an implicit point to the nearest f64 coordinates: once per output vertex, in the
//! assemble stage of the exact engine.
//!
//! First in double-doubles ([`nearest_by_double_doubles`]): the homogeneous coordinates with
//! the cascade's running error bound, an f64 estimate of each quotient `X / W`, and two signs
//! that place the exact quotient strictly between the midpoints from the estimate to its
//! neighbours (`X - m W` for each midpoint `m`). The nearest f64 is then the estimate, with
//! no tie possible. That decides nearly every point in a few dozen double-double
//! operations, where the integers divide 384-bit numbers; where a sign is not certain (a
//! quotient within about `2^-40` ulps of a midpoint, an exact tie, a magnitude out of the
//! double-doubles' range), the integers decide.
//!
//! The integers evaluate the homogeneous coordinates exactly (every input scaled by the same
//! power of two), and round each quotient to nearest, ties to even, by one integer division
//! with a sticky bit. A point whose coordinates are representable (a crossing on an
//! axis-aligned plane, say) therefore comes out exactly. The integers are 384-bit ([`Fixed`])
//! where they fit, which is every point whose inputs span an ordinary range of exponents, and
//! big integers otherwise.

use num_bigint::BigUint;
use num_integer::Integer;
use num_traits::Signed;

use super::Sign;
use super::arith::{Big, Fixed, decompose};
use super::cascade::Homogeneous;
use super::double_double::DoubleDouble;
use super::implicit::{Point, Point3};
use super::interval::{next_down, next_down_f32, next_up, next_up_f32, step_by};

/// The floating-point numbers a result's coordinates are written in: f64, or f32 for the
/// formats that store f32 (binary STL, glTF). The exact engine rounds its result to these
/// numbers and certifies it there, so a writer stores the very coordinates that were
/// certified: an f64 result rounded to f32 afterwards can cross itself.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Precision {
    /// 64-bit floats: OBJ, PLY, OFF, 3MF and ASCII STL (shortest round-trip decimals), and
    /// the meshes of the library and the bindings.
    #[default]
    F64,
    /// 32-bit floats: binary STL, glTF and GLB.
    F32,
}

impl Precision {
    /// Bits of the significand after the point: `ulp(x) = 2^(e - fraction_bits)` for a
    /// normal `x` in `[2^e, 2^(e+1))`.
    pub fn fraction_bits(self) -> i32 {
        match self {
            Precision::F64 => 52,
            Precision::F32 => 23,
        }
    }

    /// Whether `x` is a number of this precision, so writing it loses nothing.
    pub fn holds(self, x: f64) -> bool {
        match self {
            Precision::F64 => true,
            Precision::F32 => f64::from(x as f32) == x,
        }
    }

    /// The number of this precision nearest the exact value that `x` is the nearest f64 to,
    /// where the exact value lies on side `exact_side` of `x` (the sign of exact − `x`): an
    /// `x` halfway between two f32 numbers goes to the one on the exact value's side, so
    /// rounding first to f64, then to f32, still gives the nearest f32 (ties, where the exact
    /// value is `x`, to even).
    pub(crate) fn nearest(self, x: f64, exact_side: Sign) -> f64 {
        match self {
            Precision::F64 => x,
            Precision::F32 => {
                let single = x as f32;
                let rounded = f64::from(single);
                if rounded == x || exact_side == Sign::Zero || !rounded.is_finite() {
                    return rounded;
                }
                let other = if rounded < x {
                    next_up_f32(single)
                } else {
                    next_down_f32(single)
                };
                // Both differences are exact: the three numbers are within an f32 ulp.
                let (to_rounded, to_other) = ((x - rounded).abs(), (f64::from(other) - x).abs());
                let other_side = Sign::of(f64::from(other) - x);
                if to_rounded == to_other && other_side == exact_side {
                    f64::from(other)
                } else {
                    rounded
                }
            }
        }
    }

    /// `x`, a number of this precision, moved by `steps` of its neighbours, up when positive.
    pub(crate) fn step_by(self, x: f64, steps: i32) -> f64 {
        match self {
            Precision::F64 => step_by(x, steps),
            Precision::F32 => {
                let step = if steps > 0 {
                    next_up_f32
                } else {
                    next_down_f32
                };
                f64::from((0..steps.unsigned_abs()).fold(x as f32, |x, _| step(x)))
            }
        }
    }

    /// Whether `x` is subnormal as a number of this precision.
    pub(crate) fn is_subnormal(self, x: f64) -> bool {
        match self {
            Precision::F64 => x.is_subnormal(),
            Precision::F32 => (x as f32).is_subnormal(),
        }
    }
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Precision::F64 => "f64",
            Precision::F32 => "f32",
        })
    }
}

/// [`round_point`], and per coordinate the exact value minus that rounding, approximately
/// but with its sign certain, where double-doubles decide the sign (`None` where they cannot:
/// a difference within about `2^-100` of the coordinates, or a magnitude out of their range),
/// from one evaluation of the homogeneous coordinates: which way, and about how far, an
/// intersection point lies from its rounding, for a fraction of the cost of
/// [`compare_along`](super::compare_along)'s exact stages, which a difference under an ulp
/// always reaches.
pub(crate) fn round_point_with_offsets(p: &Point) -> (Point3, [Option<f64>; 3]) {
    if let Point::Explicit(x) = p {
        return (*x, [Some(0.0); 3]);
    }
    let hom = p.hom(&DoubleDouble::exact, &DoubleDouble::exact(1.0));
    let nearest = nearest(p, &hom);
    let [x, y, z, w] = hom;
    let (n, w_sign, w_estimate) = ([x, y, z], w.sign(), w.estimate());
    let offsets = std::array::from_fn(|k| match p.known_coordinate(k) {
        Some(c) => Some(c - nearest[k]),
        None => {
            let difference = n[k].sub(&DoubleDouble::exact(nearest[k]).mul(&w));
            let sign = difference.sign()?.times(w_sign?);
            let offset = difference.estimate() / w_estimate;
            (Sign::of(offset) == sign).then_some(offset)
        }
    });
    (nearest, offsets)
}

/// Coordinates of `p` for choices among valid alternatives (insertion orders, diagonals,
/// projection axes, shapes), which no topological decision reads: [`Point::approx`], a few
/// ulps off, where the filter bounds the point's `W` away from zero; else its coordinates
/// rounded exactly. A nearly degenerate definition (a line almost parallel to the plane it
/// meets, far from the origin) leaves zero inside `W`'s interval, and the midpoints' quotients
/// can then be far off, infinite or 0 / 0, which sorted or compared as coordinates failed.
pub(crate) fn approx_point(p: &Point) -> Point3 {
    match p.filter_hom()[3].sign() {
        Some(Sign::Positive | Sign::Negative) => p.approx(),
        _ => round_point(p),
    }
}

/// A box certain to hold `p`, as its lowest and highest corners: the filter's enclosure
/// where it is narrow (within 64 ulps per coordinate), else the correctly rounded point
/// widened by one f64 step each way, since a nearly degenerate definition's enclosure can be
/// unbounded. For tests that boxes can skip, where the exact predicates would otherwise
/// decide that two far-apart triangles are apart.
pub(crate) fn enclosing_box(p: &Point) -> (Point3, Point3) {
    let (lo, hi) = p.enclosure();
    let narrow = (0..3).all(|k| {
        let width = hi[k] - lo[k];
        width.is_finite() && width <= 64.0 * f64::EPSILON * lo[k].abs().max(hi[k].abs())
    });
    if narrow {
        return (lo, hi);
    }
    let nearest = round_point(p);
    (nearest.map(next_down), nearest.map(next_up))
}

/// The coordinates of `p` rounded to the nearest f64 (ties to even), each independently.
pub(crate) fn round_point(p: &Point) -> Point3 {
    if let Point::Explicit(x) = p {
        return *x;
    }
    nearest(p, &p.hom(&DoubleDouble::exact, &DoubleDouble::exact(1.0)))
}

/// The nearest f64 point to `p`, given its homogeneous coordinates in double-doubles: by
/// them where they decide every coordinate, else exactly.
fn nearest(p: &Point, hom: &[DoubleDouble; 4]) -> Point3 {
    nearest_by_double_doubles(p, hom).unwrap_or_else(|| quotients(p).map(|(value, _)| value))
}

/// The coordinates of `p` rounded to the nearest f64, where double-doubles decide every one
/// (see the module docs); `None` otherwise. A coordinate the point's definition fixes
/// ([`Point::known_coordinate`]: on an axis plane) is itself. `hom` is `p`'s homogeneous
/// coordinates in double-doubles.
fn nearest_by_double_doubles(p: &Point, hom: &[DoubleDouble; 4]) -> Option<Point3> {
    let [x, y, z, w] = hom;
    let w_sign = w.sign()?;
    let nearest = |k: usize, n: &DoubleDouble| {
        if let Some(c) = p.known_coordinate(k) {
            return Some(c);
        }
        // `sign(n / w - m) = sign(n - m w) · sign(w)`; the midpoint `m` of two adjacent f64
        // is exact as a double-double (their difference is a power of two).
        let side_of_midpoint = |a: f64, b: f64| -> Option<Sign> {
            let midpoint = DoubleDouble::exact(a).add(&DoubleDouble::exact((b - a) * 0.5));
            Some(n.sub(&midpoint.mul(w)).sign()?.times(w_sign))
        };
        // The estimate is within an ulp or two: step towards the quotient until it lies
        // strictly between the midpoints around the candidate.
        let mut candidate = n.estimate() / w.estimate();
        for _ in 0..4 {
            if !candidate.is_finite() {
                return None;
            }
            if side_of_midpoint(next_down(candidate), candidate)? == Sign::Negative {
                candidate = next_down(candidate);
            } else if side_of_midpoint(candidate, next_up(candidate))? == Sign::Positive {
                candidate = next_up(candidate);
            } else {
                return Some(candidate);
            }
        }
        None
    };
    Some([nearest(0, x)?, nearest(1, y)?, nearest(2, z)?])
}

/// `p` as an explicit point when its exact coordinates are f64 numbers, else `p`.
///
/// Intersection points of inputs on a grid (integer boxes, voxel models) usually are; as
/// explicit points every later predicate on them takes the fast path. Only points whose
/// rounded coordinates are short binary numbers (at least 16 trailing zero bits) are tried,
/// so the exact test is skipped for points in general position.
pub fn simplify(p: Point) -> Point {
    if p.is_explicit() {
        return p;
    }
    // The approximation may be some ulps off: accept low bits near all zeros or all ones.
    let short = |x: f64| {
        let low = x.to_bits() & 0xff_ffff;
        x == 0.0 || low <= 0xfff || low >= 0xff_ffff - 0xfff
    };
    if !p.approx().iter().all(|&x| x.is_finite() && short(x)) {
        return p;
    }
    match quotients(&p) {
        [(x, true), (y, true), (z, true)] => Point::Explicit([x, y, z]),
        _ => p,
    }
}

/// Each coordinate of `p` rounded to the nearest f64, and whether that was exact: in 384-bit
/// integers where the homogeneous coordinates and the scaled quotients fit, else in big
/// integers.
fn quotients(p: &Point) -> [(f64, bool); 3] {
    // Every input times `2^-e_low`: coordinates are `X / W * 2^e_low` (`X` has one input
    // degree more than `W`).
    let e_low = lowest_bit(p);
    let conv = |x: f64| Fixed::scaled(x, e_low);
    let [x, y, z, w] = p.hom(&conv, &Fixed::ONE);
    let fixed = |n: &Fixed| {
        let (n, d) = (n.value()?, w.value()?);
        quotient(&n.unsigned_abs(), &d.unsigned_abs(), negative(n, d), e_low)
    };
    if let (Some(x), Some(y), Some(z)) = (fixed(&x), fixed(&y), fixed(&z)) {
        return [x, y, z];
    }
    let conv = |x: f64| Big::scaled(x, e_low);
    let [x, y, z, w] = p.hom(&conv, &Big::one());
    [x, y, z].map(|n| {
        let (n, d) = (n.value(), w.value());
        quotient(n.magnitude(), d.magnitude(), negative(n, d), e_low)
            .expect("big integers do not overflow")
    })
}

/// The exponent of the lowest set bit over `p`'s defining coordinates (0 when all are zero).
fn lowest_bit(p: &Point) -> i32 {
    (p.coords().iter())
        .filter(|&&x| x != 0.0)
        .map(|&x| decompose(x).1)
        .min()
        .unwrap_or(0)
}

/// Whether `n / d` is negative.
fn negative<T: Signed>(n: &T, d: &T) -> bool {
    !n.is_zero() && n.is_negative() != d.is_negative()
}

/// The unsigned integers [`quotient`] divides: big, and 384-bit.
trait Magnitude: Integer + Clone {
    fn bit_length(&self) -> u64;
    /// `self * 2^k`, `None` if it does not fit.
    fn shifted(&self, k: u64) -> Option<Self>;
    /// The value, known to fit in 64 bits.
    fn low_u64(&self) -> u64;
}

impl Magnitude for BigUint {
    fn bit_length(&self) -> u64 {
        self.bits()
    }
    fn shifted(&self, k: u64) -> Option<Self> {
        Some(self << k)
    }
    fn low_u64(&self) -> u64 {
        u64::try_from(self).expect("the quotient has at most 56 bits")
    }
}

impl Magnitude for bnum::BUint<6> {
    fn bit_length(&self) -> u64 {
        u64::from(self.bits())
    }
    fn shifted(&self, k: u64) -> Option<Self> {
        (self.bit_length() + k <= 384).then(|| *self << k as u32)
    }
    fn low_u64(&self) -> u64 {
        u64::try_from(*self).expect("the quotient has at most 56 bits")
    }
}

/// `n / d * 2^e` (negated when `negative`) rounded to the nearest f64, ties to even, and
/// whether that was exact; `d` nonzero; `None` when a fixed-width operand overflowed. The
/// result is assumed to be a normal number or zero (intersection points lie among finite
/// inputs).
fn quotient<M: Magnitude>(n: &M, d: &M, negative: bool, e: i32) -> Option<(f64, bool)> {
    if n.is_zero() {
        return Some((0.0, true));
    }
    // Scale so that the integer quotient has 55 or 56 bits: 53 kept, one to round, one spare.
    let k = 55 + d.bit_length() as i64 - n.bit_length() as i64;
    let (q, r) = if k >= 0 {
        n.shifted(k as u64)?.div_rem(d)
    } else {
        n.div_rem(&d.shifted((-k) as u64)?)
    };
    let sticky = !r.is_zero();
    let q = q.low_u64();
    let shift = 64 - q.leading_zeros() as i32 - 53;
    let mut mantissa = q >> shift;
    let dropped = q & ((1u64 << shift) - 1);
    let half = 1u64 << (shift - 1);
    if dropped > half || (dropped == half && (sticky || mantissa & 1 == 1)) {
        mantissa += 1;
    }
    // value = mantissa * 2^(shift + e - k); mantissa <= 2^53 is exact as an f64.
    let exp = shift as i64 + e as i64 - k;
    let magnitude = times_pow2(mantissa as f64, exp);
    let exact = dropped == 0 && !sticky;
    Some((if negative { -magnitude } else { magnitude }, exact))
}

/// `x * 2^exp`, by steps that keep each factor a normal power of two.
fn times_pow2(mut x: f64, mut exp: i64) -> f64 {
    while exp != 0 {
        let step = exp.clamp(-1000, 1000);
        x *= f64::from_bits(((step + 1023) as u64) << 52);
        exp -= step;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::oracle;
    use crate::kernel::tests::xorshift;
    use num_traits::Signed;

    /// `p`'s homogeneous coordinates in double-doubles, as rounding evaluates them.
    fn in_double_doubles(p: &Point) -> [DoubleDouble; 4] {
        p.hom(&DoubleDouble::exact, &DoubleDouble::exact(1.0))
    }

    /// The segment (0,0,0)-(4,2,6) meets the plane z = 3 at (2, 1, 3).
    fn on_grid() -> Point {
        let plane = [[0.0, 0.0, 3.0], [1.0, 0.0, 3.0], [0.0, 1.0, 3.0]];
        Point::lpi([0.0; 3], [4.0, 2.0, 6.0], plane[0], plane[1], plane[2])
            .expect("the segment crosses the plane")
    }

    /// The segment (0,0,0)-(3,1,0) meets the plane x = 1 at (1, 1/3, 0).
    fn a_third() -> Point {
        let plane = [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 1.0]];
        Point::lpi([0.0; 3], [3.0, 1.0, 0.0], plane[0], plane[1], plane[2])
            .expect("the segment crosses the plane")
    }

    #[test]
    fn representable_crossings_round_exactly() {
        assert_eq!(round_point(&on_grid()), [2.0, 1.0, 3.0]);
    }

    #[test]
    fn a_third_rounds_to_nearest() {
        assert_eq!(round_point(&a_third()), [1.0, 1.0 / 3.0, 0.0]);
    }

    #[test]
    fn grid_points_become_explicit() {
        assert!(matches!(
            simplify(on_grid()),
            Point::Explicit([2.0, 1.0, 3.0])
        ));
        assert!(!simplify(a_third()).is_explicit());
    }

    /// Lines and planes with coordinates from 1e-150 to 1e150: their homogeneous
    /// coordinates overflow 384 bits, so rounding takes the big integers.
    #[test]
    fn rounding_with_huge_exponent_spans_agrees_with_the_rational_oracle() {
        let mut random = xorshift(0x9abc_def0);
        let mut next = || {
            let unit = (random() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            let scale = 10f64.powi((random() % 301) as i32 - 150);
            unit * scale
        };
        let mut checked = 0;
        for _ in 0..300 {
            let mut pt = || [next(), next(), next()];
            let (p, q, r, s, t) = (pt(), pt(), pt(), pt(), pt());
            let Some(x) = Point::lpi(p, q, r, s, t) else {
                continue;
            };
            let e_low = lowest_bit(&x);
            let fixed = x.hom(&|c: f64| Fixed::scaled(c, e_low), &Fixed::ONE);
            if fixed.iter().all(|h| h.value().is_some()) {
                continue;
            }
            checked += 1;
            assert_rounds_to_nearest(&x);
        }
        assert!(checked > 100, "only {checked} points took the big integers");
    }

    /// The line–plane points of `tries` random lines and planes with coordinates in
    /// `[-100, 100)` (the few parallel ones left out).
    fn random_points(seed: u64, tries: usize) -> Vec<Point> {
        let mut random = xorshift(seed);
        let mut next = || (random() >> 11) as f64 / (1u64 << 53) as f64 * 200.0 - 100.0;
        (0..tries)
            .filter_map(|_| {
                let mut pt = || [next(), next(), next()];
                let (p, q, r, s, t) = (pt(), pt(), pt(), pt(), pt());
                Point::lpi(p, q, r, s, t)
            })
            .collect()
    }

    #[test]
    fn rounding_agrees_with_the_rational_oracle() {
        for x in random_points(0x1234_5678, 500) {
            assert_rounds_to_nearest(&x);
        }
    }

    /// Where the double-doubles decide, they give the integers' answer, and they decide
    /// nearly always: the property the fast path rests on, not only its outcome.
    #[test]
    fn double_doubles_round_as_the_integers_do() {
        let points = random_points(0x5eed_f00d, 2000);
        let mut decided = 0;
        for x in &points {
            let exact = quotients(x).map(|(value, _)| value.to_bits());
            if let Some(fast) = nearest_by_double_doubles(x, &in_double_doubles(x)) {
                assert_eq!(fast.map(f64::to_bits), exact);
                decided += 1;
            }
        }
        assert!(
            decided * 100 >= points.len() * 99,
            "{decided} of {} decided",
            points.len()
        );
    }

    /// A coordinate exactly halfway between two f64 (the crossing of `x = 1` with the line
    /// from `(0, 1, 0)` to `(2, 1 + 2^-52, 0)` has `y = 1 + 2^-53`) has no certain side in
    /// double-doubles: the integers decide it, ties to even.
    #[test]
    fn a_tie_is_left_to_the_integers() {
        let plane = [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 1.0]];
        let end = [2.0, 1.0f64.next_up(), 0.0];
        let tie = Point::lpi([0.0, 1.0, 0.0], end, plane[0], plane[1], plane[2])
            .expect("the line crosses the plane");
        assert_eq!(
            nearest_by_double_doubles(&tie, &in_double_doubles(&tie)),
            None
        );
        assert_eq!(round_point(&tie), [1.0, 1.0, 0.0]);
        assert_rounds_to_nearest(&tie);
    }

    /// No neighbouring f64 of a rounded coordinate is strictly closer to the exact one.
    fn assert_rounds_to_nearest(x: &Point) {
        let rounded = round_point(x);
        let exact = oracle::oracle_point(x);
        for k in 0..3 {
            let error = |y: f64| (oracle::q(y) - &exact[k]).abs();
            let own = error(rounded[k]);
            assert!(own <= error(rounded[k].next_up()), "coordinate {k}");
            assert!(own <= error(rounded[k].next_down()), "coordinate {k}");
        }
    }
}
