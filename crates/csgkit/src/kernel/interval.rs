//! Interval arithmetic with outward rounding: the floating-point filter of the implicit
//! predicates.
//!
//! # Numeric model
//! An [`Interval`] `[lo, hi]` encloses one real number. Every operation computes its endpoints
//! in round-to-nearest f64 and then moves each endpoint one ulp outwards (`next_down` on `lo`,
//! `next_up` on `hi`). Under IEEE 754 round-to-nearest the rounded result `r` of an exact value
//! `x` satisfies `next_down(r) <= x <= next_up(r)`, also when `r` is subnormal or zero (gradual
//! underflow keeps the error below one ulp of the subnormal spacing), so the enclosure is
//! rigorous without changing the rounding mode (which stable Rust cannot do).
//!
//! Overflow fails safe: an overflowing endpoint becomes infinite, `next_down(+inf)` is
//! `f64::MAX` and `next_up(-inf)` is `-f64::MAX`, so `lo` is never `+inf` and `hi` never
//! `-inf`, and an addition never forms `inf - inf`. A product corner `0 * inf` is NaN; `f64::min`
//! and `f64::max` skip it, which is sound because the other corner on the same zero endpoint
//! is `0` (or, if both corners are NaN or infinite, the interval is unbounded or NaN). A NaN
//! endpoint compares false, so [`Interval::sign`] answers "undecided" and the caller falls to
//! the exact path.
//!
//! # Cost
//! About four times the floating-point work of the plain expression, no allocation, no branch
//! that depends on anything but signs. The predicates asked most (`orient2d_projected` and
//! `compare_along` of implicit points) first try `nearby.rs`, a running error bound on
//! Cartesian coordinates, several times cheaper; this filter decides the rest, and for
//! every predicate it is the simple, obviously-sound one.

use super::Sign;

/// A closed interval `[lo, hi]` that contains the exact value of the expression it stands for.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Interval {
    lo: f64,
    hi: f64,
}

/// The next f64 above `x` (towards `+inf`); `+inf` and NaN map to themselves.
///
/// Written with selects rather than branches (the compiler keeps them branch-free): the
/// filter steps every endpoint of every operation, and branches on the sign of each
/// endpoint mispredict in runs of mixed signs.
#[inline(always)]
pub(crate) fn next_up(x: f64) -> f64 {
    let bits = x.to_bits();
    // The bit pattern steps by +1 above zero and by -1 below (towards zero in magnitude);
    // `-inf` steps to `-f64::MAX`.
    let step = ((bits as i64 >> 63) | 1) as u64;
    let stepped = bits.wrapping_add(step);
    // Both +0 and -0: the smallest positive subnormal.
    let stepped = if bits << 1 == 0 { 1 } else { stepped };
    let keep = x.is_nan() | (x == f64::INFINITY);
    if keep { x } else { f64::from_bits(stepped) }
}

/// The next f64 below `x` (towards `-inf`); `-inf` and NaN map to themselves.
#[inline(always)]
pub(crate) fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// The next f32 above `x`, as [`next_up`] for f64 (`f32::next_up` is newer than the crate's
/// minimum Rust version).
pub(crate) fn next_up_f32(x: f32) -> f32 {
    if x.is_nan() || x == f32::INFINITY {
        return x;
    }
    let bits = x.to_bits();
    if bits << 1 == 0 {
        return f32::from_bits(1);
    }
    f32::from_bits(if x > 0.0 { bits + 1 } else { bits - 1 })
}

/// The next f32 below `x`.
pub(crate) fn next_down_f32(x: f32) -> f32 {
    -next_up_f32(-x)
}

/// `x` moved by `steps` f64 steps, up when positive: the f64 points around an output vertex
/// that rounding and certification choose among.
pub(crate) fn step_by(x: f64, steps: i32) -> f64 {
    let step = if steps > 0 { next_up } else { next_down };
    (0..steps.unsigned_abs()).fold(x, |x, _| step(x))
}

impl Interval {
    /// The point interval of an f64, exact by definition.
    #[inline]
    pub(crate) fn exact(x: f64) -> Self {
        Interval { lo: x, hi: x }
    }

    /// The interval `[lo, hi]`, which the caller knows to contain the value.
    #[inline]
    pub(crate) fn new(lo: f64, hi: f64) -> Self {
        debug_assert!(lo <= hi, "an interval's ends are ordered");
        Interval { lo, hi }
    }

    /// The sign of every number in the interval, or `None` when the interval contains numbers
    /// of different signs (or is NaN): the filter cannot decide.
    #[inline]
    pub(crate) fn sign(&self) -> Option<Sign> {
        if self.lo > 0.0 {
            Some(Sign::Positive)
        } else if self.hi < 0.0 {
            Some(Sign::Negative)
        } else if self.lo == 0.0 && self.hi == 0.0 {
            Some(Sign::Zero)
        } else {
            None
        }
    }

    #[inline]
    pub(crate) fn add(&self, o: &Self) -> Self {
        Interval {
            lo: next_down(self.lo + o.lo),
            hi: next_up(self.hi + o.hi),
        }
    }

    #[inline]
    pub(crate) fn sub(&self, o: &Self) -> Self {
        Interval {
            lo: next_down(self.lo - o.hi),
            hi: next_up(self.hi - o.lo),
        }
    }

    #[inline]
    pub(crate) fn mul(&self, o: &Self) -> Self {
        let a = self.lo * o.lo;
        let b = self.lo * o.hi;
        let c = self.hi * o.lo;
        let d = self.hi * o.hi;
        Interval {
            lo: next_down(a.min(b).min(c.min(d))),
            hi: next_up(a.max(b).max(c.max(d))),
        }
    }

    /// The midpoint, for approximate coordinates only.
    pub(crate) fn mid(&self) -> f64 {
        self.lo * 0.5 + self.hi * 0.5
    }

    /// Lower endpoint.
    pub(crate) fn lo(&self) -> f64 {
        self.lo
    }

    /// Upper endpoint.
    pub(crate) fn hi(&self) -> f64 {
        self.hi
    }
}

/// A number evaluated in plain f64 from exact f64 inputs by `+`, `-` and `×`, with a running
/// bound on its rounding error.
///
/// Why: an implicit point's filter intervals are built once per point, and interval
/// arithmetic pays four products, six comparisons and two outward steps per product; this
/// pays three products and two additions, and the outward steps once at the end
/// ([`Tracked::enclosure`]). Its bounds are as tight as the intervals' (a bound from the
/// count of roundings alone, without the running error, was some eight times wider, and the
/// filters downstream of the points failed where they had decided).
///
/// # Numeric model
/// `value` is the computed `x̂` of an exact `x`, and `|x̂ - x| ≤ error` up to the slack that
/// [`Tracked::enclosure`] adds. A sum `ẑ = fl(x̂ ± ŷ)` is within `u |ẑ| (1 + 2u)` of `x̂ ± ŷ`
/// (`u = 2^-53`), so within `e_x + e_y + u |ẑ| (1 + 2u)` of `x ± y`; a product `ẑ = fl(x̂ ŷ)`
/// is within `(|x̂| + e_x) e_y + |ŷ| e_x + u |ẑ| (1 + 2u)` of `x y`. Each bound is computed
/// in round to nearest from non-negative terms, at most four roundings, so the computed
/// bound times `1 + 6u` covers the one stated, whose own inputs were covered the same way:
/// over a chain of at most 30 operations (the formulas of an [`Lpi`](super::Lpi) and a
/// [`Tpi`](super::Tpi) chain fewer than 10), `(1 + 6u)^30 < 1 + 128 ε` (`ε = 2u`).
/// Underflow loses at most `2^-1074` per product, which later products multiply by at most
/// the magnitudes of the other factors; with inputs of magnitude at most `2^30` (the
/// caller's range, see `implicit::filter_hom`) and polynomials of degree 7 or less, that
/// stays below `2^-800` in all. Overflow gives a non-finite value or bound, and no
/// enclosure.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tracked {
    value: f64,
    error: f64,
}

/// The unit roundoff `u = 2^-53` times `1 + 2u`, rounded up: the error of one rounding of a
/// result, relative to the rounded result.
const ROUNDING: f64 = 0.5 * f64::EPSILON * (1.0 + 2.0 * f64::EPSILON);

impl Tracked {
    /// An exact input.
    #[inline]
    pub(crate) fn exact(x: f64) -> Self {
        Tracked {
            value: x,
            error: 0.0,
        }
    }

    #[inline]
    pub(crate) fn add(&self, o: &Self) -> Self {
        self.sum_with(o, self.value + o.value)
    }

    #[inline]
    pub(crate) fn sub(&self, o: &Self) -> Self {
        self.sum_with(o, self.value - o.value)
    }

    /// The sum or difference of `self` and `o` computed as `value`: the operands' errors and
    /// one rounding of the result.
    #[inline]
    fn sum_with(&self, o: &Self, value: f64) -> Self {
        Tracked {
            value,
            error: self.error + o.error + ROUNDING * value.abs(),
        }
    }

    #[inline]
    pub(crate) fn mul(&self, o: &Self) -> Self {
        let value = self.value * o.value;
        Tracked {
            value,
            error: (self.value.abs() + self.error) * o.error
                + o.value.abs() * self.error
                + ROUNDING * value.abs(),
        }
    }

    /// An interval certain to contain the exact value, when the evaluation stayed finite;
    /// valid only for inputs in the range of the numeric model above.
    #[inline]
    pub(crate) fn enclosure(&self) -> Option<Interval> {
        const SLACK: f64 = 1.0 + 128.0 * f64::EPSILON;
        const UNDERFLOW: f64 = f64::from_bits((1023 - 800) << 52);
        let bound = self.error * SLACK + UNDERFLOW;
        (self.value.is_finite() && bound.is_finite()).then(|| Interval {
            lo: next_down(self.value - bound),
            hi: next_up(self.value + bound),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition step by step, against which the select form is checked.
    fn next_up_by_cases(x: f64) -> f64 {
        if x.is_nan() || x == f64::INFINITY {
            return x;
        }
        if x == 0.0 {
            return f64::from_bits(1);
        }
        let bits = x.to_bits();
        if x > 0.0 {
            f64::from_bits(bits + 1)
        } else {
            f64::from_bits(bits - 1)
        }
    }

    #[test]
    fn next_up_agrees_with_its_definition_bit_for_bit() {
        let special = [
            0.0,
            -0.0,
            f64::from_bits(1),
            -f64::from_bits(1),
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            1.0,
            -1.0,
            f64::MAX,
            -f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        // A fixed pseudo-random walk over bit patterns (xorshift), NaNs included.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let walk = std::iter::repeat_with(move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            f64::from_bits(state)
        });
        for x in special.into_iter().chain(walk.take(100_000)) {
            let (got, want) = (next_up(x), next_up_by_cases(x));
            assert_eq!(got.to_bits(), want.to_bits(), "next_up({x:e})");
        }
    }

    #[test]
    fn next_up_and_down_step_one_ulp_across_zero_and_infinity() {
        assert_eq!(next_up(0.0), f64::from_bits(1));
        assert_eq!(next_up(-0.0), f64::from_bits(1));
        assert_eq!(next_down(0.0), -f64::from_bits(1));
        assert_eq!(next_up(1.0), 1.0 + f64::EPSILON);
        assert_eq!(next_down(-1.0), -1.0 - f64::EPSILON);
        assert_eq!(next_up(-f64::from_bits(1)), -0.0);
        assert_eq!(next_down(f64::INFINITY), f64::MAX);
        assert_eq!(next_up(f64::NEG_INFINITY), -f64::MAX);
        assert_eq!(next_up(f64::INFINITY), f64::INFINITY);
    }

    #[test]
    fn overflow_and_zero_times_infinity_stay_sound() {
        let big = Interval::exact(f64::MAX);
        let sq = big.mul(&big);
        assert_eq!(sq.lo(), f64::MAX);
        assert_eq!(sq.hi(), f64::INFINITY);
        assert_eq!(sq.sign(), Some(Sign::Positive));
        let z = Interval::exact(0.0);
        let p = z.mul(&sq);
        assert!(p.lo() <= 0.0 && p.hi() >= 0.0);
        let diff = sq.sub(&sq);
        assert_eq!(diff.sign(), None);
    }

    #[test]
    fn underflowing_product_is_not_decided_as_zero() {
        let tiny = Interval::exact(1e-200);
        let p = tiny.mul(&tiny);
        assert_eq!(p.sign(), None);
        assert!(p.lo() <= 0.0 && p.hi() > 0.0);
    }
}
