//! The cascade that decides every predicate: interval filter, then 128-bit integers where the
//! inputs have few significant bits, then double-doubles with an error bound (non-zero
//! near-ties), then floating-point expansions, then big integers, stopping at the first stage
//! that decides (see the [module docs](super) for the numeric model).
//!
//! A predicate is a [`Formula`]: one generic polynomial in the homogeneous coordinates of some
//! points and in some explicit coordinates, written once over [`Arith`] and evaluated in
//! [`Interval`]s (from the points' cached coordinates, no allocation), then in 128-bit
//! integers ([`Wide`]), then in [`DoubleDouble`]s, then in [`Expansion`]s, then in big
//! integers ([`Big`]).
//!
//! The cascade sees points only through [`Homogeneous`], so it sits below the point types:
//! `implicit` builds a point by deciding the sign of its `W` here, and `formulas` and
//! `predicates` above it write their polynomials on those points.

use super::arith::{Arith, Big, Wide, decompose, exponent, scaled_expansion};
use super::double_double::DoubleDouble;
use super::expansion::Expansion;
use super::interval::Interval;
use super::{Sign, expansion_top_exponent};

/// A point given by homogeneous coordinates `(X, Y, Z, W)`, polynomials in its defining f64
/// coordinates.
pub(crate) trait Homogeneous {
    /// The homogeneous coordinates as intervals (cached for implicit points).
    fn filter_hom(&self) -> [Interval; 4];
    /// The homogeneous coordinates in number type `T`; `one` is the constant 1 of `T` (not
    /// scaled by `conv`, so that the polynomials stay homogeneous).
    fn hom<T: Arith>(&self, conv: &dyn Fn(f64) -> T, one: &T) -> [T; 4];
    /// Every defining f64 coordinate.
    fn coords(&self) -> &[f64];
    /// The homogeneous coordinates as expansions of the inputs scaled by `2^scale`, when the
    /// point keeps them at hand (a point met by many predicates); `None` to compute them.
    fn hom_expansion(&self, _scale: i32) -> Option<[Expansion; 4]> {
        None
    }
    /// The homogeneous coordinates as double-doubles, when the point keeps them at hand;
    /// `None` to compute them.
    fn hom_double_double(&self) -> Option<[DoubleDouble; 4]> {
        None
    }
}

/// A polynomial sign question about some points.
pub(crate) trait Formula {
    /// The points the polynomial is written on.
    type Point: Homogeneous;
    /// The polynomial in number type `T`: `hom` gives a point's homogeneous coordinates,
    /// `conv` converts an explicit input coordinate.
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Self::Point) -> [T; 4], conv: &dyn Fn(f64) -> T) -> T;
    /// The points whose homogeneous coordinates `eval` asks for.
    fn points(&self) -> impl Iterator<Item = &Self::Point>;
    /// The explicit coordinates `eval` converts with `conv`.
    fn explicit_coords(&self) -> impl Iterator<Item = f64>;
    /// The total degree of the polynomial in the input coordinates.
    fn degree(&self) -> u32;
}

/// The exact sign of a formula: filter first, then the exact stages.
#[inline]
pub(crate) fn decide(f: &impl Formula) -> Sign {
    filter(f).unwrap_or_else(|| decide_exact(f))
}

/// [`decide`], asking `known_zero` first: a structural proof that the value is zero (points
/// on one line or plane by construction), which the filter cannot give and the exact stages
/// pay dearly for. For a caller whose own filter on the points' nearby coordinates (see
/// `nearby.rs`) has just abstained: the value is then most often exactly zero, and the
/// interval filter (several times the cost of a proof) rarely decides: on the peers
/// harness's cases it decided 5 of the 430 projected orientations that reached it on two
/// cubes turned by 1e-7 rad (rotated_z_union, rotated_xyz_union), none of the 4,295 on
/// sphere_sphere_1k_union and fertility ∪ cylinder (the proofs settled all of them), and none
/// of the 112 coordinate comparisons on these four.
#[inline]
pub(crate) fn decide_proof_first(f: &impl Formula, known_zero: impl FnOnce() -> bool) -> Sign {
    if known_zero() {
        return Sign::Zero;
    }
    decide(f)
}

/// Stage 1 of the cascade alone: the sign where the interval filter decides it, `None` where
/// only the exact stages could.
#[inline]
pub(crate) fn filter(f: &impl Formula) -> Option<Sign> {
    f.eval::<Interval>(&|p| p.filter_hom(), &Interval::exact)
        .sign()
}

/// Stages 2–5 of the cascade.
fn decide_exact(f: &impl Formula) -> Sign {
    let (top, e_low) = scan(f);
    if let Some(s) = integer_stage(f, top, e_low) {
        return s;
    }
    if let Some(s) = double_double_stage(f) {
        return s;
    }
    match expansion_stage(f, top) {
        Some(s) => s,
        None => big_stage(f, e_low),
    }
}

/// The bits a scaled input may have for [`integer_stage`] to try, times the degree: a product
/// of `degree` such inputs then fits in 128 bits with a few bits left for the sums of terms
/// (an overflow there is caught, and the next stage decides).
const WIDE_PRODUCT_BITS: i32 = 120;

/// Stage 2: 128-bit integers, after scaling every input by `2^-e_low` (exact; the polynomial
/// is homogeneous, so the sign is unchanged), when the inputs' bit span times the degree
/// fits; `None` when it does not or an operation overflowed.
fn integer_stage(f: &impl Formula, top: i32, e_low: i32) -> Option<Sign> {
    let span = top - e_low + 1;
    if span.saturating_mul(f.degree().max(1) as i32) > WIDE_PRODUCT_BITS {
        return None;
    }
    let conv = |x: f64| Wide::scaled(x, e_low);
    f.eval::<Wide>(&|p| p.hom(&conv, &Wide::ONE), &conv).sign()
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

/// Stage 3: double-doubles with a running error bound, for the near-ties f64 cannot see
/// (never zero: those go on).
fn double_double_stage<F: Formula>(f: &F) -> Option<Sign> {
    let one = DoubleDouble::exact(1.0);
    let hom =
        |p: &F::Point| (p.hom_double_double()).unwrap_or_else(|| p.hom(&DoubleDouble::exact, &one));
    f.eval::<DoubleDouble>(&hom, &DoubleDouble::exact).sign()
}

/// Stage 4: expansions after scaling the largest input to `2^T` (see
/// [`expansion_bit_span`](super::expansion_bit_span)); `None` if a product may have
/// underflowed.
fn expansion_stage<F: Formula>(f: &F, top: i32) -> Option<Sign> {
    let s = expansion_top_exponent(f.degree().max(1)) - top;
    let conv = |x: f64| scaled_expansion(x, s);
    let one = Expansion::exact(1.0);
    let hom = |p: &F::Point| p.hom_expansion(s).unwrap_or_else(|| p.hom(&conv, &one));
    f.eval::<Expansion>(&hom, &conv).sign()
}

/// Stage 5: big integers, exact for every finite input.
fn big_stage(f: &impl Formula, e_low: i32) -> Sign {
    let conv = |x: f64| Big::scaled(x, e_low);
    let one = Big::one();
    f.eval::<Big>(&|p| p.hom(&conv, &one), &conv)
        .sign()
        .expect("big integers always decide")
}

/// What each stage of the cascade answers on its own: filter, 128-bit integers,
/// double-doubles, expansions, big integers.
#[cfg(test)]
pub(crate) fn stages(f: &impl Formula) -> [Option<Sign>; 5] {
    let filter = f
        .eval::<Interval>(&|p| p.filter_hom(), &Interval::exact)
        .sign();
    let (top, e_low) = scan(f);
    [
        filter,
        integer_stage(f, top, e_low),
        double_double_stage(f),
        expansion_stage(f, top),
        Some(big_stage(f, e_low)),
    ]
}
