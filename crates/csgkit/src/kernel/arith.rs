//! The five number types of the predicate cascade behind one trait, so that each polynomial
//! is written once: [`Interval`] (filter), [`Wide`] (128-bit integers, exact while no
//! operation overflows), [`DoubleDouble`] (about 106 bits and an error bound, never zero),
//! [`Expansion`] (exact while no product underflows or overflows) and
//! [`Big`] (exact big integers, for every finite input); and [`Fixed`] (384-bit integers,
//! exact while no operation overflows), which rounding tries before [`Big`].

use num_bigint::BigInt;
use num_traits::{CheckedAdd, CheckedMul, CheckedSub, Zero};

use super::Sign;
use super::double_double::DoubleDouble;
use super::expansion::Expansion;
use super::interval::{Interval, Tracked};

/// Ring operations plus a possibly-undecided sign.
pub(crate) trait Arith: Clone {
    fn add(&self, o: &Self) -> Self;
    fn sub(&self, o: &Self) -> Self;
    fn mul(&self, o: &Self) -> Self;
    /// The sign of the exact value, or `None` when this number type cannot tell.
    fn sign(&self) -> Option<Sign>;
}

impl Arith for Interval {
    #[inline]
    fn add(&self, o: &Self) -> Self {
        Interval::add(self, o)
    }
    #[inline]
    fn sub(&self, o: &Self) -> Self {
        Interval::sub(self, o)
    }
    #[inline]
    fn mul(&self, o: &Self) -> Self {
        Interval::mul(self, o)
    }
    #[inline]
    fn sign(&self) -> Option<Sign> {
        Interval::sign(self)
    }
}

impl Arith for Tracked {
    #[inline]
    fn add(&self, o: &Self) -> Self {
        Tracked::add(self, o)
    }
    #[inline]
    fn sub(&self, o: &Self) -> Self {
        Tracked::sub(self, o)
    }
    #[inline]
    fn mul(&self, o: &Self) -> Self {
        Tracked::mul(self, o)
    }
    /// Never asked: a [`Tracked`] is turned into an [`Interval`] before any sign is read.
    fn sign(&self) -> Option<Sign> {
        None
    }
}

impl Arith for DoubleDouble {
    #[inline]
    fn add(&self, o: &Self) -> Self {
        DoubleDouble::add(self, o)
    }
    #[inline]
    fn sub(&self, o: &Self) -> Self {
        DoubleDouble::sub(self, o)
    }
    #[inline]
    fn mul(&self, o: &Self) -> Self {
        DoubleDouble::mul(self, o)
    }
    #[inline]
    fn sign(&self) -> Option<Sign> {
        DoubleDouble::sign(self)
    }
}

impl Arith for Expansion {
    fn add(&self, o: &Self) -> Self {
        Expansion::add(self, o)
    }
    fn sub(&self, o: &Self) -> Self {
        Expansion::sub(self, o)
    }
    fn mul(&self, o: &Self) -> Self {
        Expansion::mul(self, o)
    }
    fn sign(&self) -> Option<Sign> {
        Expansion::sign(self)
    }
}

/// An exact integer: an input f64 times `2^-e_min`, where `e_min` is the exponent of the lowest
/// significant bit over all inputs of one predicate call. The predicates are homogeneous
/// polynomials, so the common positive scale does not change any sign.
#[derive(Clone, Debug)]
pub(crate) struct Big(BigInt);

impl Arith for Big {
    fn add(&self, o: &Self) -> Self {
        Big(&self.0 + &o.0)
    }
    fn sub(&self, o: &Self) -> Self {
        Big(&self.0 - &o.0)
    }
    fn mul(&self, o: &Self) -> Self {
        Big(&self.0 * &o.0)
    }
    fn sign(&self) -> Option<Sign> {
        Some(match self.0.sign() {
            num_bigint::Sign::Minus => Sign::Negative,
            num_bigint::Sign::NoSign => Sign::Zero,
            num_bigint::Sign::Plus => Sign::Positive,
        })
    }
}

/// An exact integer of a fixed width `T`, scaled like [`Big`] (an input f64 times
/// `2^-e_min`), or `None` once an operation overflowed, which makes every later result
/// `None`: the caller then cannot tell from it and moves on to a wider type.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Checked<T>(Option<T>);

impl<T: CheckedAdd + CheckedSub + CheckedMul + Zero + Ord + Copy> Arith for Checked<T> {
    #[inline]
    fn add(&self, o: &Self) -> Self {
        Checked(self.0.zip(o.0).and_then(|(a, b)| a.checked_add(&b)))
    }
    #[inline]
    fn sub(&self, o: &Self) -> Self {
        Checked(self.0.zip(o.0).and_then(|(a, b)| a.checked_sub(&b)))
    }
    #[inline]
    fn mul(&self, o: &Self) -> Self {
        Checked(self.0.zip(o.0).and_then(|(a, b)| a.checked_mul(&b)))
    }
    #[inline]
    fn sign(&self) -> Option<Sign> {
        self.0.map(|v| match v.cmp(&T::zero()) {
            std::cmp::Ordering::Less => Sign::Negative,
            std::cmp::Ordering::Equal => Sign::Zero,
            std::cmp::Ordering::Greater => Sign::Positive,
        })
    }
}

impl<T: Copy> Checked<T> {
    /// The integer, `None` after an overflow.
    pub(crate) fn value(&self) -> Option<&T> {
        self.0.as_ref()
    }
}

/// 128-bit integers, the cascade's second stage. Inputs on a coarse grid (integer
/// coordinates, or binary fractions of a few bits, as in box unions, voxel models and most
/// CAD parts) have few significant bits between their largest magnitude and their lowest set
/// bit, so a predicate's polynomial fits, and one multiplication costs what an expansion's
/// two-product costs, with no growth and no allocation.
pub(crate) type Wide = Checked<i128>;

impl Wide {
    /// The constant 1 (the `W` of an explicit point; not scaled).
    pub(crate) const ONE: Wide = Checked(Some(1));

    /// `x * 2^-e_min` as an integer, `None` when it does not fit in 126 bits; `e_min` must not
    /// exceed the exponent of `x`'s lowest bit.
    #[inline]
    pub(crate) fn scaled(x: f64, e_min: i32) -> Self {
        let (m, e) = decompose(x);
        if m == 0 {
            return Checked(Some(0));
        }
        let shift = e - e_min;
        // |m| < 2^53, so a shift of at most 73 stays below 2^126.
        Checked((shift <= 73).then(|| i128::from(m) << shift))
    }
}

/// The integer type of [`Fixed`]: 384 bits, signed.
pub(crate) type Int384 = bnum::BInt<6>;

/// 384-bit integers, which rounding tries before [`Big`]. Rounding an output vertex
/// evaluates its homogeneous coordinates and divides three of them by the fourth: with inputs
/// of ordinary exponent spans these fit in 384 bits, and there each operation is a few dozen
/// word operations where a big integer allocates.
pub(crate) type Fixed = Checked<Int384>;

impl Fixed {
    /// The constant 1 (the `W` of an explicit point; not scaled).
    pub(crate) const ONE: Fixed = Checked(Some(Int384::ONE));

    /// `x * 2^-e_min` as an integer, `None` when it does not fit in 382 bits; `e_min` must not
    /// exceed the exponent of `x`'s lowest bit.
    pub(crate) fn scaled(x: f64, e_min: i32) -> Self {
        let (m, e) = decompose(x);
        if m == 0 {
            return Checked(Some(Int384::ZERO));
        }
        let shift = e - e_min;
        // |m| < 2^53, so a shift of at most 329 stays below 2^382.
        Checked((shift <= 329).then(|| Int384::from(m) << shift as u32))
    }
}

/// `x = m * 2^e` exactly, with `m` odd (or zero). `x` must be finite.
pub(crate) fn decompose(x: f64) -> (i64, i32) {
    let bits = x.to_bits();
    let exp_field = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (mut m, mut e) = if exp_field == 0 {
        (frac, -1074)
    } else {
        (frac | (1i64 << 52), exp_field - 1075)
    };
    if m == 0 {
        return (0, 0);
    }
    let tz = m.trailing_zeros();
    m >>= tz;
    e += tz as i32;
    if x < 0.0 { (-m, e) } else { (m, e) }
}

impl Big {
    /// The exact integer.
    pub(crate) fn value(&self) -> &BigInt {
        &self.0
    }

    /// The constant 1 (the `W` of an explicit point; not scaled).
    pub(crate) fn one() -> Self {
        Big(BigInt::from(1))
    }

    /// `x * 2^-e_min` as an integer; `e_min` must not exceed the exponent of `x`'s lowest bit.
    pub(crate) fn scaled(x: f64, e_min: i32) -> Self {
        let (m, e) = decompose(x);
        if m == 0 {
            return Big(BigInt::from(0));
        }
        Big(BigInt::from(m) << ((e - e_min) as u32))
    }
}

/// The exponent `k` with `2^k <= |x| < 2^(k+1)` for finite nonzero `x`.
pub(crate) fn exponent(x: f64) -> i32 {
    bit_range(x).1
}

/// The exponents of the lowest and the highest set bit of finite nonzero `x`: `x = m · 2^low`
/// with `m` odd, and `2^top <= |x| < 2^(top + 1)`.
pub(crate) fn bit_range(x: f64) -> (i32, i32) {
    let (m, low) = decompose(x);
    (low, low + (63 - m.unsigned_abs().leading_zeros() as i32))
}

/// `x * 2^s` as an expansion, poisoned if the scaling is not exact.
pub(crate) fn scaled_expansion(x: f64, s: i32) -> Expansion {
    // Two steps keep each factor a normal power of two for any |s| <= 2100.
    let half = s / 2;
    let y = x * pow2(half) * pow2(s - half);
    if y.is_finite() && y * pow2(-half) * pow2(half - s) == x {
        Expansion::exact(y)
    } else {
        Expansion::poisoned()
    }
}

/// `2^k` for `-1022 <= k <= 1023`.
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k), "pow2 stays normal");
    f64::from_bits(((k + 1023) as u64) << 52)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decompose_is_exact_and_minimal() {
        assert_eq!(decompose(1.0), (1, 0));
        assert_eq!(decompose(-6.0), (-3, 1));
        assert_eq!(decompose(0.375), (3, -3));
        assert_eq!(decompose(f64::from_bits(1)), (1, -1074));
        assert_eq!(decompose(0.0), (0, 0));
        assert_eq!(exponent(1.0), 0);
        assert_eq!(exponent(3.9), 1);
        assert_eq!(exponent(f64::MAX), 1023);
        assert_eq!(exponent(f64::from_bits(1)), -1074);
    }

    #[test]
    fn wide_integers_are_exact_until_they_overflow() {
        let x = Wide::scaled(0.75, -2);
        assert_eq!(x.0, Some(3));
        assert_eq!(Wide::scaled(-6.0, 1).0, Some(-3));
        assert_eq!(Wide::scaled(0.0, -1074).0, Some(0));
        assert_eq!(Wide::scaled(1.0, -74).0, None);
        let big: Wide = Checked(Some(1 << 100));
        assert_eq!(
            big.mul(&Checked(Some(1 << 26))).sign(),
            Some(Sign::Positive)
        );
        assert_eq!(big.mul(&Checked(Some(1 << 27))).sign(), None);
        assert_eq!(big.mul(&big).sub(&big).sign(), None, "overflow is sticky");
        assert_eq!(x.sub(&Checked(Some(3))).sign(), Some(Sign::Zero));
    }

    #[test]
    fn scaling_is_exact_or_poisoned() {
        assert_eq!(scaled_expansion(3.0, -1000).sign(), Some(Sign::Positive));
        assert_eq!(scaled_expansion(3.0, -1080).sign(), None);
        assert_eq!(scaled_expansion(f64::MAX, 1).sign(), None);
        assert_eq!(
            scaled_expansion(f64::MAX, -2000).sign(),
            Some(Sign::Positive)
        );
    }
}
