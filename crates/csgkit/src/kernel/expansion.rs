//! Floating-point expansions (Shewchuk 1997, "Adaptive Precision Floating-Point Arithmetic and
//! Fast Robust Geometric Predicates", §2): the exact middle stage of the implicit predicates.
//!
//! An expansion is a sum of f64 components, nonoverlapping and sorted by increasing magnitude,
//! whose exact sum is the value; its sign is the sign of the largest component. Sums and
//! products of expansions are exact as long as no component overflows and no product
//! underflows.
//!
//! # Why hand-written
//! The `robust` crate implements the same primitives but keeps them private, and they do not
//! report underflow. Here every product checks the condition under which Dekker's
//! `two_product` is exact (below) and clears [`Expansion::ok`] when it may not be; the caller
//! then falls back to big integers. Overflow shows up as a non-finite component, which
//! [`Expansion::sign`] also reports as "undecided".
//!
//! # Exactness condition of `two_product(a, b)`
//! With `|a|, |b| < 2^995` the Veltkamp split (`a * (2^27 + 1)`) cannot overflow. With
//! `|fl(a*b)| >= 2^-900` every partial product of the split halves is a multiple of
//! `ulp(a) * ulp(b) >= |a*b| * 2^-106 > 2^-1022`, so none underflows and Dekker's error term
//! is exact. Components are allowed to be anything finite; only products are checked.
//!
//! # Cost
//! Runs only when the interval filter cannot decide. Components live inline up to
//! [`INLINE_COMPONENTS`] (every input and most intermediates of the predicates), so the common
//! expansion allocates nothing; a product reuses two buffers across its partial sums, and a
//! difference negates on the fly instead of building the negated copy.

use smallvec::SmallVec;

use super::Sign;

/// Components an expansion holds without a heap allocation. The predicates' inputs are one
/// component; their products and sums of a few terms stay under this; the long expansions of
/// the deepest implicit predicates spill to the heap as a `Vec` would.
const INLINE_COMPONENTS: usize = 16;

/// The components of an expansion, by increasing magnitude.
type Components = SmallVec<[f64; INLINE_COMPONENTS]>;

/// `2^27 + 1`, Veltkamp's splitter for 53-bit significands.
const SPLITTER: f64 = 134_217_729.0;
/// Factors at or above this magnitude could overflow in the split: `2^995`.
const SPLIT_LIMIT: f64 = f64::from_bits((1023 + 995) << 52);
/// Products below this magnitude could lose bits of the error term to underflow: `2^-900`.
const PRODUCT_FLOOR: f64 = f64::from_bits((1023 - 900) << 52);

/// An exact sum of f64 components (increasing magnitude, nonoverlapping, no zeros).
#[derive(Clone, Debug, Default)]
pub(crate) struct Expansion {
    c: Components,
    /// False once a product may have lost bits to underflow or overflow: the value is then
    /// unreliable and the caller must use another exact method.
    ok: bool,
}

#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    let br = b - bv;
    let ar = a - av;
    (x, ar + br)
}

#[inline]
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    (x, b - bv)
}

#[inline]
fn split(a: f64) -> (f64, f64) {
    let c = SPLITTER * a;
    let abig = c - a;
    let hi = c - abig;
    (hi, a - hi)
}

/// `a * b = x + y` exactly, when `safe` comes back true.
#[inline]
fn two_product(a: f64, b: f64, safe: &mut bool) -> (f64, f64) {
    let x = a * b;
    if x == 0.0 {
        // Exact only if a factor is zero; otherwise the product underflowed.
        *safe &= a == 0.0 || b == 0.0;
        return (x, 0.0);
    }
    *safe &= x.abs() >= PRODUCT_FLOOR && a.abs() < SPLIT_LIMIT && b.abs() < SPLIT_LIMIT;
    let (ahi, alo) = split(a);
    let (bhi, blo) = split(b);
    let err1 = x - ahi * bhi;
    let err2 = err1 - alo * bhi;
    let err3 = err2 - ahi * blo;
    (x, alo * blo - err3)
}

impl Expansion {
    /// The expansion of one f64.
    pub(crate) fn exact(x: f64) -> Self {
        Expansion {
            c: if x == 0.0 {
                Components::new()
            } else {
                smallvec::smallvec![x]
            },
            ok: x.is_finite(),
        }
    }

    /// An expansion already known to be unreliable (a lossy input conversion).
    pub(crate) fn poisoned() -> Self {
        Expansion {
            c: Components::new(),
            ok: false,
        }
    }

    /// The sign of the exact value, or `None` if underflow or overflow may have spoiled it.
    pub(crate) fn sign(&self) -> Option<Sign> {
        if !self.ok || !self.c.iter().all(|x| x.is_finite()) {
            return None;
        }
        Some(match self.c.last() {
            None => Sign::Zero,
            Some(&x) => Sign::of(x),
        })
    }

    pub(crate) fn add(&self, o: &Self) -> Self {
        self.plus(o, 1.0)
    }

    pub(crate) fn sub(&self, o: &Self) -> Self {
        self.plus(o, -1.0)
    }

    /// `self + sign · o`, `sign` being ±1.
    fn plus(&self, o: &Self, sign: f64) -> Self {
        let mut c = Components::new();
        sum_zeroelim(&self.c, &o.c, sign, &mut c);
        Expansion {
            c,
            ok: self.ok && o.ok,
        }
    }

    /// The product, as the sum over the shorter expansion's components of the longer one
    /// scaled by each (Shewchuk's `scale_expansion` and `expansion_sum`), accumulated in two
    /// buffers that take turns (by index: swapping them would copy their inline arrays)
    /// rather than one new vector per partial sum.
    pub(crate) fn mul(&self, o: &Self) -> Self {
        let mut ok = self.ok && o.ok;
        let (short, long) = if self.c.len() <= o.c.len() {
            (&self.c, &o.c)
        } else {
            (&o.c, &self.c)
        };
        let mut sums = [Components::new(), Components::new()];
        let mut part = Components::new();
        let mut current = 0;
        for &b in short {
            scale_zeroelim(long, b, &mut ok, &mut part);
            let [first, second] = &mut sums;
            let (acc, next) = if current == 0 {
                (first, second)
            } else {
                (second, first)
            };
            sum_zeroelim(acc, &part, 1.0, next);
            current = 1 - current;
        }
        let [first, second] = sums;
        let c = if current == 0 { first } else { second };
        Expansion { c, ok }
    }

    /// The same value in as few components as Shewchuk's `compress` gets (nonadjacent, so
    /// at most one per 53 bits of the value's span): products and sums grow expansions
    /// quadratically, and an expansion that is used many times is worth compressing once.
    pub(crate) fn compressed(&self) -> Self {
        let e = &self.c;
        let Some(&last) = e.last() else {
            return self.clone();
        };
        let mut h: Components = smallvec::smallvec![0.0; e.len()];
        let mut bottom = e.len() - 1;
        let mut q = last;
        for &now in e[..e.len() - 1].iter().rev() {
            let (sum, err) = fast_two_sum(q, now);
            if err != 0.0 {
                h[bottom] = sum;
                bottom -= 1;
                q = err;
            } else {
                q = sum;
            }
        }
        let mut top = 0;
        for i in bottom + 1..e.len() {
            let (sum, err) = fast_two_sum(h[i], q);
            if err != 0.0 {
                h[top] = err;
                top += 1;
            }
            q = sum;
        }
        h[top] = q;
        h.truncate(top + 1);
        if q == 0.0 {
            h.clear();
        }
        Expansion { c: h, ok: self.ok }
    }

    /// `self · 2^k`, or `None` where a component would leave the normal range (then the
    /// scaling would not be exact).
    pub(crate) fn scaled_by_pow2(&self, k: i32) -> Option<Self> {
        // Steps of at most 2^±1000 keep each factor a normal f64.
        let steps: smallvec::SmallVec<[f64; 4]> = {
            let mut left = k;
            let mut steps = smallvec::SmallVec::new();
            while left != 0 {
                let step = left.clamp(-1000, 1000);
                steps.push(f64::from_bits(((step + 1023) as u64) << 52));
                left -= step;
            }
            steps
        };
        let mut c = self.c.clone();
        for x in &mut c {
            for &factor in &steps {
                *x *= factor;
                if !x.is_normal() {
                    return None;
                }
            }
        }
        Some(Expansion { c, ok: self.ok })
    }
}

/// `h = e + sign · f` (`sign` is ±1, so negating is exact), into `h` (cleared first): Shewchuk's
/// `fast_expansion_sum_zeroelim`, with `two_sum` in place of the one `fast_two_sum` whose
/// precondition needs round-to-even reasoning (same result, one less assumption).
fn sum_zeroelim(e: &[f64], f: &[f64], sign: f64, h: &mut Components) {
    h.clear();
    if e.is_empty() {
        h.extend(f.iter().map(|x| sign * x));
        return;
    }
    if f.is_empty() {
        h.extend_from_slice(e);
        return;
    }
    h.reserve(e.len() + f.len());
    let (mut ei, mut fi) = (0, 0);
    let next = |ei: &mut usize, fi: &mut usize| -> f64 {
        let take_e = *fi >= f.len() || (*ei < e.len() && e[*ei].abs() < f[*fi].abs());
        if take_e {
            *ei += 1;
            e[*ei - 1]
        } else {
            *fi += 1;
            sign * f[*fi - 1]
        }
    };
    let mut q = next(&mut ei, &mut fi);
    while ei < e.len() || fi < f.len() {
        let now = next(&mut ei, &mut fi);
        let (qn, hh) = two_sum(q, now);
        q = qn;
        if hh != 0.0 {
            h.push(hh);
        }
    }
    if q != 0.0 {
        h.push(q);
    }
}

/// Shewchuk's `scale_expansion_zeroelim`: `h = e * b` (cleared first), clearing `ok` if a
/// product is not exact.
fn scale_zeroelim(e: &[f64], b: f64, ok: &mut bool, h: &mut Components) {
    h.clear();
    h.reserve(2 * e.len());
    let (mut q, hh) = two_product(e[0], b, ok);
    if hh != 0.0 {
        h.push(hh);
    }
    for &en in &e[1..] {
        let (p1, p0) = two_product(en, b, ok);
        let (sum, hh) = two_sum(q, p0);
        if hh != 0.0 {
            h.push(hh);
        }
        let (qn, hh) = fast_two_sum(p1, sum);
        q = qn;
        if hh != 0.0 {
            h.push(hh);
        }
    }
    if q != 0.0 {
        h.push(q);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_are_the_stated_powers_of_two() {
        assert_eq!(SPLIT_LIMIT, 2f64.powi(995));
        assert_eq!(PRODUCT_FLOOR, 2f64.powi(-900));
    }

    #[test]
    fn cancellation_is_exact() {
        // (1 + 2^-60)^2 - 1 - 2^-59 = 2^-120.
        let a = Expansion::exact(1.0).add(&Expansion::exact(2f64.powi(-60)));
        let sq = a.mul(&a);
        let r = sq
            .sub(&Expansion::exact(1.0))
            .sub(&Expansion::exact(2f64.powi(-59)));
        assert_eq!(r.sign(), Some(Sign::Positive));
        assert_eq!(r.c.as_slice(), [2f64.powi(-120)]);
        let z = r.sub(&Expansion::exact(2f64.powi(-120)));
        assert_eq!(z.sign(), Some(Sign::Zero));
    }

    #[test]
    fn compression_keeps_the_value_in_fewer_components() {
        // Single bits side by side: nonoverlapping, but one f64 holds their sum.
        let bits = Expansion {
            c: smallvec::smallvec![0.125, 0.25, 0.5, 1.0, 2.0],
            ok: true,
        };
        assert_eq!(bits.compressed().c.as_slice(), [3.875]);
        // A cube of a three-part number: the same value, sorted, in no more components.
        let a = Expansion::exact(1.0)
            .add(&Expansion::exact(2f64.powi(-30)))
            .add(&Expansion::exact(-2f64.powi(-70)));
        let cube = a.mul(&a).mul(&a);
        let small = cube.compressed();
        assert!(small.c.len() <= cube.c.len());
        assert!(small.c.windows(2).all(|w| w[0].abs() < w[1].abs()));
        assert_eq!(cube.sub(&small).sign(), Some(Sign::Zero));
        assert_eq!(Expansion::exact(0.0).compressed().sign(), Some(Sign::Zero));
        // Cancelling to zero compresses to no component.
        assert!(cube.sub(&cube).compressed().c.is_empty());
    }

    #[test]
    fn scaling_by_a_power_of_two_is_exact_or_refused() {
        let a = Expansion::exact(3.0).add(&Expansion::exact(2f64.powi(-80)));
        let up = a.scaled_by_pow2(900).expect("in range");
        let back = up.scaled_by_pow2(-900).expect("in range");
        assert_eq!(back.sub(&a).sign(), Some(Sign::Zero));
        assert!(a.scaled_by_pow2(-1000).is_none(), "2^-1080 is subnormal");
        assert!(a.scaled_by_pow2(1100).is_none(), "overflows");
    }

    #[test]
    fn underflow_and_overflow_are_reported() {
        let t = Expansion::exact(1e-200);
        assert_eq!(t.mul(&t).sign(), None);
        let h = Expansion::exact(1e300);
        assert_eq!(h.mul(&h).sign(), None);
        let z = Expansion::exact(0.0);
        assert_eq!(z.mul(&h).sign(), Some(Sign::Zero));
    }
}
