//! Rounding an implicit point to the nearest f64 coordinates: once per output vertex, in the
//! assemble stage of the exact engine.
//!
//! The homogeneous coordinates are evaluated exactly with big integers (every input scaled by
//! the same power of two), and each quotient `X / W` is rounded to nearest, ties to even, by
//! one big-integer division with a sticky bit. A point whose coordinates are representable
//! (a crossing on an axis-aligned plane, say) therefore comes out exactly.

use num_bigint::BigInt;

use super::arith::{Big, decompose};
use super::cascade::Homogeneous;
use super::implicit::{Point, Point3};

/// The coordinates of `p` rounded to the nearest f64 (ties to even), each independently.
pub(crate) fn round_point(p: &Point) -> Point3 {
    if let Point::Explicit(x) = p {
        return *x;
    }
    let ([x, y, z, w], e_low) = exact_hom(p);
    [x, y, z].map(|n| quotient(n.value(), w.value(), e_low).0)
}

/// The homogeneous coordinates of `p` as exact integers, every input scaled by `2^-e_low`
/// (the lowest bit of any input), and `e_low`. Coordinates are `X / W * 2^e_low`: `X` has one
/// input degree more than `W`.
fn exact_hom(p: &Point) -> ([Big; 4], i32) {
    let e_low = (p.coords().iter())
        .filter(|&&x| x != 0.0)
        .map(|&x| decompose(x).1)
        .min()
        .unwrap_or(0);
    let conv = |x: f64| Big::scaled(x, e_low);
    (p.hom(&conv, &Big::one()), e_low)
}

/// `p` as an explicit point when its exact coordinates are f64 numbers, else `p`.
///
/// Intersection points of inputs on a grid (integer boxes, voxel models) usually are; as
/// explicit points every later predicate on them takes the fast path. Only points whose
/// rounded coordinates are short binary numbers (at least 16 trailing zero bits) are tried,
/// so the big-integer test is skipped for points in general position.
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
    let ([x, y, z, w], e_low) = exact_hom(&p);
    let exact = |n: &Big| {
        let (value, exact) = quotient(n.value(), w.value(), e_low);
        exact.then_some(value)
    };
    match (exact(&x), exact(&y), exact(&z)) {
        (Some(x), Some(y), Some(z)) => Point::Explicit([x, y, z]),
        _ => p,
    }
}

/// `n / d * 2^e` rounded to the nearest f64, ties to even, and whether that was exact; `d`
/// nonzero. The result is assumed to be a normal number or zero (intersection points lie
/// among finite inputs).
fn quotient(n: &BigInt, d: &BigInt, e: i32) -> (f64, bool) {
    use num_bigint::Sign;
    if n.sign() == Sign::NoSign {
        return (0.0, true);
    }
    let negative = (n.sign() == Sign::Minus) != (d.sign() == Sign::Minus);
    let (n, d) = (n.magnitude(), d.magnitude());
    // Scale so that the integer quotient has 55 or 56 bits: 53 kept, one to round, one spare.
    let k = 55 + d.bits() as i64 - n.bits() as i64;
    let (q, r) = if k >= 0 {
        let num = n << (k as u64);
        (&num / d, &num % d)
    } else {
        let den = d << ((-k) as u64);
        (n / &den, n % &den)
    };
    let sticky = r.bits() > 0;
    let q: u64 = q.try_into().expect("the quotient has at most 56 bits");
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
    (if negative { -magnitude } else { magnitude }, exact)
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

    #[test]
    fn rounding_agrees_with_the_rational_oracle() {
        let mut random = xorshift(0x1234_5678);
        let mut next = || (random() >> 11) as f64 / (1u64 << 53) as f64 * 200.0 - 100.0;
        for _ in 0..500 {
            let mut pt = || [next(), next(), next()];
            let (p, q, r, s, t) = (pt(), pt(), pt(), pt(), pt());
            let Some(x) = Point::lpi(p, q, r, s, t) else {
                continue;
            };
            let rounded = round_point(&x);
            let exact = oracle::oracle_point(&x);
            for k in 0..3 {
                // No neighbouring f64 is strictly closer to the exact coordinate.
                let error = |y: f64| (oracle::q(y) - &exact[k]).abs();
                let own = error(rounded[k]);
                assert!(own <= error(rounded[k].next_up()), "coordinate {k}");
                assert!(own <= error(rounded[k].next_down()), "coordinate {k}");
            }
        }
    }
}
