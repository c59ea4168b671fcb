//! Double-double numbers with a running error bound: the cascade's stage between the f64
//! filter and the exact stages.
//!
//! # Why
//! Most predicates the interval filter leaves undecided are not zero, only closer to zero
//! than f64 can see: two unit cubes turned by 1e-7 rad meet in intersection points 1e-15
//! apart, whose orientations and coordinate orders are non-zero far above the 106 bits of a
//! double-double. The exact stages decide them too, but multiply expansions of dozens of
//! components for each (the coordinates of a three-plane point have degree 7); a
//! double-double operation is some twenty f64 operations. Exact zeros are left to the exact
//! stages: this stage never answers zero.
//!
//! # Numeric model
//! A [`DoubleDouble`] is an unevaluated sum `hi + lo` (`|lo| <= ulp(hi) / 2`, as the
//! algorithms below leave it) and a radius `err`: the exact value of the expression lies in
//! `[hi + lo - err, hi + lo + err]`. Addition is Algorithm 6 (AccurateDWPlusDW) and
//! multiplication Algorithm 10 (DWTimesDW1, no fused multiply-add) of Joldes, Muller &
//! Popescu, "Tight and rigorous error bounds for basic building blocks of double-word
//! arithmetic" (ACM TOMS 44, 2017), whose relative error against the exact operation on the
//! operands' double-double values is at most `3u² + 13u³` for the sum (`u = 2^-53`) and, for
//! the product, below `2^-102` (the bound CRlibm states for the same algorithm, its `Mul22`;
//! the paper proves a tighter one), as long as nothing underflows or overflows. Each
//! operation charges its result's radius [`RELATIVE_ERROR`] times `|hi|` (several times those
//! bounds) plus [`ABSOLUTE_ERROR`] (far above what gradual underflow of a partial product
//! can lose), on top of the operands'
//! propagated radii (`err_a + err_b` for a sum, `|a| err_b + |b| err_a + err_a err_b` for a
//! product); the radius is summed in f64 and multiplied once by [`INFLATE`], which covers
//! the rounding of the few (at most eight) operations on non-negative terms that computed it,
//! so it stays an upper bound. (Stepping each term up by one ulp, as the interval filter
//! does, cost as many instructions as the product itself.)
//!
//! Range: a result whose `hi` is non-zero outside `[2^-400, 2^400]` has a NaN radius, which
//! makes every later result's radius NaN and [`DoubleDouble::sign`] undecided: Dekker's
//! product is exact while products stay far above the subnormal range and the split far
//! below overflow, which this keeps with hundreds of bits to spare.

use super::Sign;
use super::interval::next_up;

/// The charge of one operation, relative to `|hi|` of its result: `2^-100` is four times
/// the product's bound and over twenty times the sum's.
const RELATIVE_ERROR: f64 = f64::from_bits((1023 - 100) << 52);

/// The absolute charge of one operation: more than any underflowed partial product loses
/// (`2^-1074` each) and below any magnitude a valid result can have.
const ABSOLUTE_ERROR: f64 = f64::from_bits((1023 - 1000) << 52);

/// `1 + 2^-48`: a sum of non-negative f64 terms through `k` roundings to nearest is at least
/// `(1 - 2^-53)^k` times its exact value, and this factor (itself rounded once more) restores
/// an upper bound for `k` up to about thirty; a radius takes at most eight.
const INFLATE: f64 = 1.0 + 1.0 / (1u64 << 48) as f64;

/// The smallest and largest magnitude of a valid non-zero `hi`.
const LOWEST: f64 = f64::from_bits((1023 - 400) << 52);
const HIGHEST: f64 = f64::from_bits((1023 + 400) << 52);

/// A double-double value with an error bound (see the module docs).
#[derive(Clone, Copy, Debug)]
pub(crate) struct DoubleDouble {
    hi: f64,
    lo: f64,
    err: f64,
}

impl DoubleDouble {
    /// An input f64, exact.
    #[inline]
    pub(crate) fn exact(x: f64) -> Self {
        DoubleDouble {
            hi: x,
            lo: 0.0,
            err: 0.0,
        }
        .checked()
    }

    /// `hi + lo` rounded to f64: within about an ulp of the value when the radius is small.
    #[inline]
    pub(crate) fn estimate(&self) -> f64 {
        self.hi + self.lo
    }

    /// The sign of every number within the radius, or `None` when they differ, the value may
    /// be zero, or a result left the valid range.
    #[inline]
    pub(crate) fn sign(&self) -> Option<Sign> {
        // |hi + lo - value| <= err, so hi beyond |lo| + err fixes the sign.
        let margin = next_up(self.lo.abs() + self.err);
        if self.hi > margin {
            Some(Sign::Positive)
        } else if -self.hi > margin {
            Some(Sign::Negative)
        } else {
            None
        }
    }

    #[inline]
    pub(crate) fn add(&self, o: &Self) -> Self {
        // AccurateDWPlusDW.
        let (sh, sl) = two_sum(self.hi, o.hi);
        let (th, tl) = two_sum(self.lo, o.lo);
        let (vh, vl) = fast_two_sum(sh, sl + th);
        let (hi, lo) = fast_two_sum(vh, tl + vl);
        DoubleDouble {
            hi,
            lo,
            err: (self.err + o.err + charge(hi)) * INFLATE,
        }
        .checked()
    }

    #[inline]
    pub(crate) fn sub(&self, o: &Self) -> Self {
        self.add(&DoubleDouble {
            hi: -o.hi,
            lo: -o.lo,
            err: o.err,
        })
    }

    #[inline]
    pub(crate) fn mul(&self, o: &Self) -> Self {
        // DWTimesDW1.
        let (ch, cl1) = two_prod(self.hi, o.hi);
        let cl2 = self.hi * o.lo + self.lo * o.hi;
        let (hi, lo) = fast_two_sum(ch, cl1 + cl2);
        // `|self| <= |hi| + |lo|`, so `|self| err_o + |o| err_self + err_self err_o` bounds
        // what the operands' radii propagate.
        let (a, b) = (self.hi.abs() + self.lo.abs(), o.hi.abs() + o.lo.abs());
        let propagated = a * o.err + b * self.err + self.err * o.err;
        DoubleDouble {
            hi,
            lo,
            err: (propagated + charge(hi)) * INFLATE,
        }
        .checked()
    }

    /// `self`, or with a NaN radius when `hi` left the valid range.
    #[inline]
    fn checked(self) -> Self {
        let magnitude = self.hi.abs();
        if self.hi == 0.0 || (LOWEST..=HIGHEST).contains(&magnitude) {
            self
        } else {
            DoubleDouble {
                err: f64::NAN,
                ..self
            }
        }
    }
}

/// One operation's rounding error bound for a result whose high part is `hi`, before the
/// radius's [`INFLATE`] (`hi.abs() * RELATIVE_ERROR` is exact: a power of two, and `hi` is
/// far above the subnormals).
#[inline]
fn charge(hi: f64) -> f64 {
    hi.abs() * RELATIVE_ERROR + ABSOLUTE_ERROR
}

/// Knuth's TwoSum: `s + e == a + b` exactly.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Dekker's Fast2Sum: `s + e == a + b` exactly when `a`'s exponent is at least `b`'s.
#[inline]
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// Veltkamp's split of `a` into two halves of 26 bits each.
#[inline]
fn split(a: f64) -> (f64, f64) {
    let c = 134_217_729.0 * a; // 2^27 + 1
    let high = c - (c - a);
    (high, a - high)
}

/// Dekker's TwoProduct: `p + e == a b` exactly (within the valid range).
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::arith::Arith;
    use crate::kernel::interval::Interval;
    use crate::kernel::oracle::q;
    use crate::kernel::tests::qsign;
    use num_rational::BigRational;
    use proptest::prelude::*;

    #[test]
    fn a_tie_far_below_f64_is_decided() {
        // (1 + 2^-60) - 1 - 2^-60 · (1 - 2^-30): 2^-90, 37 bits below what f64 resolves.
        let one = DoubleDouble::exact(1.0);
        let tiny = DoubleDouble::exact(2f64.powi(-60));
        let almost = DoubleDouble::exact(1.0 - 2f64.powi(-30));
        let value = one.add(&tiny).sub(&one).sub(&tiny.mul(&almost));
        assert_eq!(value.sign(), Some(Sign::Positive));
        // An exact zero is never claimed.
        assert_eq!(one.add(&tiny).sub(&one).sub(&tiny).sign(), None);
    }

    #[test]
    fn out_of_range_results_are_undecided() {
        let big = DoubleDouble::exact(2f64.powi(300));
        assert_eq!(big.sign(), Some(Sign::Positive));
        assert_eq!(big.mul(&big).sign(), None);
        let small = DoubleDouble::exact(2f64.powi(-300));
        assert_eq!(small.sign(), Some(Sign::Positive));
        assert_eq!(small.mul(&small).sign(), None);
        assert_eq!(DoubleDouble::exact(f64::MIN_POSITIVE).sign(), None);
    }

    /// The random expression of the tests: the inputs combined left to right by `ops` (a
    /// sum, a difference or a product, by `op % 3`), in any number type; sums of products of
    /// sums, where the f64 filter loses most of its bits to cancellation.
    fn evaluate<T>(
        xs: &[f64],
        ops: &[u8],
        conv: impl Fn(f64) -> T,
        combine: impl Fn(u8, T, T) -> T,
    ) -> T {
        let mut value = conv(xs[0]);
        for (i, &op) in ops.iter().enumerate() {
            value = combine(op % 3, value, conv(xs[(i + 1) % xs.len()]));
        }
        value
    }

    fn in_arith<T: Arith>(op: u8, a: T, b: T) -> T {
        match op {
            0 => a.add(&b),
            1 => a.sub(&b),
            _ => a.mul(&b),
        }
    }

    fn in_rationals(op: u8, a: BigRational, b: BigRational) -> BigRational {
        match op {
            0 => a + b,
            1 => a - b,
            _ => a * b,
        }
    }

    /// The difference of the expression at `xs` and at `nudged`, in double-doubles.
    fn difference(xs: &[f64], nudged: &[f64], ops: &[u8]) -> DoubleDouble {
        let at = |xs: &[f64]| evaluate(xs, ops, DoubleDouble::exact, in_arith);
        at(xs).sub(&at(nudged))
    }

    proptest! {
        #![proptest_config(crate::kernel::tests::config(3000, 0x6464_6b65_726e_0001))]

        /// Whenever the stage decides, it agrees with exact rationals. The value is one
        /// expression at some inputs minus the same expression at inputs a few ulps away:
        /// a difference far below what f64 resolves (or exactly zero), as between two
        /// intersection points of nearly coincident faces.
        #[test]
        fn decided_signs_are_exact(
            xs in prop::collection::vec(-4.0f64..4.0, 2..5),
            nudges in prop::collection::vec(-3i64..=3, 2..5),
            ops in prop::collection::vec(any::<u8>(), 1..14),
        ) {
            let nudged: Vec<f64> = (xs.iter().zip(nudges.iter().cycle()))
                .map(|(&x, &n)| f64::from_bits((x.to_bits() as i64 + n) as u64))
                .collect();
            let exact = evaluate(&xs, &ops, q, in_rationals) - evaluate(&nudged, &ops, q, in_rationals);
            match difference(&xs, &nudged, &ops).sign() {
                Some(s) => prop_assert_eq!(s, qsign(&exact)),
                None => prop_assert!(!is_decided_by_f64(&xs, &nudged, &ops)),
            }
        }
    }

    /// Whether the interval filter decides the difference of [`decided_signs_are_exact`]:
    /// where it does, the double-double stage must too.
    fn is_decided_by_f64(xs: &[f64], nudged: &[f64], ops: &[u8]) -> bool {
        let at = |xs: &[f64]| evaluate(xs, ops, Interval::exact, in_arith);
        at(xs).sub(&at(nudged)).sign().is_some()
    }

    /// Expressions that are exactly zero whatever their inputs (associativity and
    /// distributivity, on double-doubles with low parts) leave only rounding behind: the
    /// stage must never decide them, so its radius must cover every rounding. With the
    /// charge per operation a thousandth of [`RELATIVE_ERROR`], some are decided.
    #[test]
    fn rounding_residues_are_never_decided() {
        let mut next = crate::kernel::tests::xorshift(0x6464_6b65_726e_0003);
        let mut uniform = || (next() >> 11) as f64 / (1u64 << 53) as f64 * 8.0 - 4.0;
        for _ in 0..20_000 {
            // Products of two f64 values: double-doubles with a low part.
            let mut value = || DoubleDouble::exact(uniform()).mul(&DoubleDouble::exact(uniform()));
            let (x, y, z) = (value(), value(), value());
            let residues = [
                x.mul(&y).mul(&z).sub(&x.mul(&y.mul(&z))),
                x.mul(&y.add(&z)).sub(&x.mul(&y).add(&x.mul(&z))),
                x.add(&y).add(&z).sub(&x.add(&y.add(&z))),
                x.add(&y).mul(&x.sub(&y)).sub(&x.mul(&x).sub(&y.mul(&y))),
            ];
            for (k, residue) in residues.iter().enumerate() {
                assert_eq!(residue.sign(), None, "identity {k} at {x:?}, {y:?}, {z:?}");
            }
        }
    }

    /// How often the stage decides where the f64 filter cannot, on the inputs of
    /// [`decided_signs_are_exact`]: nearly always, or it would only cost time.
    #[test]
    fn near_ties_are_mostly_decided() {
        let mut next = crate::kernel::tests::xorshift(0x6464_6b65_726e_0002);
        let (mut ties, mut decided) = (0, 0);
        for _ in 0..2000 {
            let mut uniform = || (next() >> 11) as f64 / (1u64 << 53) as f64 * 8.0 - 4.0;
            let xs: Vec<f64> = (0..4).map(|_| uniform()).collect();
            let nudged: Vec<f64> = (xs.iter().enumerate())
                .map(|(i, &x)| f64::from_bits(x.to_bits() + 1 + i as u64 % 2))
                .collect();
            let ops: Vec<u8> = (0..8).map(|_| (next() % 3) as u8).collect();
            if is_decided_by_f64(&xs, &nudged, &ops) {
                continue;
            }
            ties += 1;
            decided += usize::from(difference(&xs, &nudged, &ops).sign().is_some());
        }
        assert!(ties > 1000, "{ties} of 2000 differences are f64 ties");
        assert!(
            decided * 100 >= ties * 95,
            "{decided} of {ties} ties decided"
        );
    }
}
