//! Exact geometric predicates on input points and on implicit intersection points: the
//! `kernel` stage of the exact boolean engine (`design/exact.md`, stage 3).
//!
//! # What it computes
//! - [`orient2d`] and [`orient3d`] on explicit f64 points, by Shewchuk's adaptive predicates
//!   (the `robust` crate).
//! - [`Point`]: an explicit point, or an implicit one stored by what defines it —
//!   [`Lpi`] (the line through a segment meets the plane of a triangle) and [`Tpi`] (the planes
//!   of three triangles meet) — never by rounded coordinates.
//! - Predicates with any mix of explicit and implicit arguments: [`orient3d_points`] (side of a
//!   plane through three points), [`orient3d_plane`] (side of the plane of an explicit
//!   triangle), [`orient2d_projected`] (orientation after dropping one coordinate, for splitting
//!   faces in 2D; [`orient2d_projected_or_collinear`] also takes the caller's structural proof
//!   of collinearity, asked only where the filter cannot decide, and
//!   [`orient2d_projected_if_clear`] answers only where the filter decides, for choices a
//!   caller may decline), [`compare_along`] and [`compare_lex`] (order of points along an
//!   axis, lexicographic order), [`same_point`].
//!
//! Every predicate returns a [`Sign`] or an [`Ordering`](std::cmp::Ordering) that is the true
//! answer for the exact real numbers the f64 inputs denote. No epsilon anywhere.
//!
//! # Example
//! An edge of one mesh crossing a triangle of the other: the crossing point is kept as an
//! [`Lpi`], lies exactly on the triangle's plane, and sorts between the edge's endpoints.
//! ```
//! use csgkit::kernel::{Axis, Point, Sign, compare_along, orient3d, orient3d_plane};
//! let tri = [[0.0, 0.0, 0.1], [1.0, 0.0, 0.2], [0.0, 1.0, 0.3]];
//! let (p, q) = ([0.1, 0.1, -1.0], [0.3, 0.2, 1.0]);
//! // The endpoints are on opposite sides, so the line is not parallel to the plane.
//! assert_eq!(orient3d(tri[0], tri[1], tri[2], p), Sign::Positive);
//! assert_eq!(orient3d(tri[0], tri[1], tri[2], q), Sign::Negative);
//! let x = Point::lpi(p, q, tri[0], tri[1], tri[2]).expect("the segment crosses the plane");
//! assert_eq!(orient3d_plane(tri[0], tri[1], tri[2], &x), Sign::Zero);
//! assert!(compare_along(&Point::Explicit(p), &x, Axis::Z).is_lt());
//! assert!(compare_along(&x, &Point::Explicit(q), Axis::Z).is_lt());
//! ```
//!
//! # For the pipeline
//! - **intersect**: explicit [`orient3d`] of each vertex against the other triangle's plane;
//!   an edge with endpoints strictly on both sides gives an [`Lpi`] (always constructible);
//!   [`orient3d_plane`] and [`orient2d_projected`] place it against the other triangle's
//!   edges. Coplanar triangles: [`orient2d_projected`] on explicit points, and
//!   [`Point::edge_crossing`] for a crossing of two coplanar edges (a [`Tpi`]).
//! - **split**: project with `Axis::of_largest(normal)` and run the constrained triangulation
//!   on [`orient2d_projected`]; sort points on a segment with [`compare_along`] on an axis
//!   where the segment is not constant, deduplicate with [`same_point`].
//! - **classify**: ray parity or winding numbers use [`orient3d`] / [`orient3d_points`].
//! - Canonical keys (vertex id, edge × triangle, …) are the pipeline's job; the kernel answers
//!   whether two differently defined points are the same.
//!
//! # Numeric model
//! An implicit point is a homogeneous vector `(X, Y, Z, W)`, each a polynomial in the input
//! coordinates (the point is `(X/W, Y/W, Z/W)`); an explicit point has `W = 1`. Degrees, with
//! `n = (s - r) × (t - r)` the normal of a defining triangle:
//!
//! | point | `W` | degree of `W` | degree of `X, Y, Z` |
//! |---|---|---|---|
//! | explicit | `1` | 0 | 1 |
//! | [`Lpi`] `p,q` against `r,s,t` | `n · (q - p)` | 3 | 4 |
//! | [`Tpi`] of three planes | `det(n1, n2, n3)` | 6 | 7 |
//!
//! A predicate is the sign of a homogeneous polynomial in the inputs (a determinant of
//! homogeneous coordinates, times the signs of the `W`s, which are fixed when the point is
//! built). It is evaluated by a cascade; the first stage that can decide answers:
//! 0. **Shortcuts** — all-explicit arguments go to `robust` (for nonzero magnitudes in
//!    `[2^-200, 2^200)`, where it cannot overflow or underflow; otherwise to stage 1); an
//!    implicit point against a plane that defines it is on it, by construction; `orient2d`
//!    and coordinate order of implicit points first try their Cartesian coordinates to within
//!    a known error (`nearby.rs`), whose differences stay sharp for close points.
//! 1. **Filter** — interval arithmetic with outward rounding (`interval.rs`): sound for every
//!    finite input, including overflow (fails safe to "undecided") and gradual underflow.
//!    Implicit points cache their interval coordinates, so the filter does not allocate.
//! 2. **128-bit integers** — when every input of the call is an integer times `2^e_min` with
//!    few significant bits (the bit span below, times the degree, at most 120: integer
//!    coordinates, binary fractions, box unions, voxel models, most CAD parts), the polynomial
//!    is evaluated in `i128` with checked operations (`arith.rs`, `Wide`); an overflow leaves
//!    it undecided. This is the fixed-width integer predicate of EMBER (Trettner et al. 2022),
//!    chosen per call from the inputs instead of by a global grid, so nothing is rounded.
//! 3. **Double-doubles** — the polynomial in double-double arithmetic with a running error
//!    bound (`double_double.rs`): about 106 bits, enough for the near-ties of nearly
//!    coincident faces (points 1e-15 apart), at a fraction of the cost of expansions.
//!    Implicit points cache their double-double coordinates per thread. Never answers zero.
//! 4. **Expansions** — Shewchuk's exact floating-point expansions (`expansion.rs`), after
//!    scaling all inputs of the call by one power of two (exact; the polynomial is homogeneous,
//!    so the sign is unchanged). Exact unless a product underflows, which is detected.
//! 5. **Big integers** — every input is an integer times `2^e_min`; evaluation in `num-bigint`
//!    is exact for every finite input.
//!
//! # Layout
//! The files depend on each other in one direction, bottom to top:
//! - `interval.rs`, `double_double.rs`, `expansion.rs`, `arith.rs`: the five number types
//!   behind one trait;
//! - `cascade.rs`: stages 1–5 for any `Formula`, a polynomial over points it sees only as
//!   homogeneous coordinates;
//! - `nearby.rs`: Cartesian coordinates to within a known error, and the `orient2d` and
//!   coordinate-order filters on them that the predicates try before the cascade (far
//!   cheaper than the homogeneous filter, and sharp for close points);
//! - `implicit.rs`: [`Point`], [`Lpi`], [`Tpi`], built by deciding the sign of `W` in the
//!   cascade, each keeping its coordinates as intervals and as a `nearby` point;
//! - `formulas.rs`: the polynomials of the predicates (side of a plane, determinants,
//!   coordinate differences);
//! - `orient.rs`: [`orient2d`] and [`orient3d`], `robust` first and the cascade outside its
//!   range; `predicates.rs`: the predicates on mixed points, which use them for explicit
//!   arguments; `rounding.rs`: the nearest f64 point, for output, and the [`Precision`] an
//!   output is written in.
//!
//! Cost (see `benches/README.md`): the filter answers a random LPI-against-plane query in
//! about 100–200 ns, the exact stages a degenerate one in a few microseconds (expansions) to
//! tens of microseconds (big integers, rare: wide bit spans or degree above 20).
//!
//! # Valid input range
//! Every finite f64 ([`MAX_ALLOWED_VALUE`]): stages 1 and 5 have no range limit; stage 3
//! leaves undecided whatever leaves its range. NaN and
//! infinity are a precondition violation (ingest rejects them); a debug assertion checks.
//! Stage 4 is guaranteed to decide when the *bit span* of the call's inputs — the exponent of
//! the largest magnitude minus the exponent of the lowest set bit of any nonzero input — is at
//! most [`expansion_bit_span`]`(degree)`; beyond, stage 5 decides, slower but still exact. See
//! [`expansion_bit_span`] for the derivation and [`MAX_DEGREE`] for the highest degree.
//!
//! # Sign conventions
//! [`orient3d`] follows Shewchuk: positive when `d` lies below the plane through `a, b, c`,
//! where "below" is the side from which `a, b, c` appear clockwise; equivalently
//! `orient3d(a, b, c, d) = -((b - a) × (c - a)) · (d - a)`, so it is negative on the side the
//! right-handed normal of the triangle points to. [`orient2d`] is positive when `c` lies left of
//! the directed line `a → b`.

mod arith;
mod cascade;
mod double_double;
mod expansion;
mod formulas;
mod implicit;
mod interval;
mod nearby;
mod orient;
mod predicates;
mod rounding;

#[cfg(test)]
pub(crate) mod oracle;
#[cfg(test)]
pub(crate) mod tests;

pub use implicit::{Lpi, Point, Point3, Tpi};
pub(crate) use orient::{
    PlaneFilter, incircle_value_if_clear, normal_component_is_zero, orient2d_filterable,
    orient2d_value_if_clear,
};
pub use orient::{orient2d, orient3d, side_of_axis_plane};
pub use predicates::{
    compare_along, compare_lex, orient2d_projected, orient2d_projected_if_clear,
    orient2d_projected_or_collinear, orient3d_plane, orient3d_points, same_point,
};
pub use rounding::{Precision, simplify};
pub(crate) use rounding::{approx_point, enclosing_box, round_point, round_point_with_offsets};

/// The sign of an exact quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sign {
    /// Strictly below zero.
    Negative,
    /// Exactly zero: the degenerate case (collinear, coplanar, equal).
    Zero,
    /// Strictly above zero.
    Positive,
}

impl Sign {
    /// The sign of an f64 (`-0.0` and `0.0` are [`Sign::Zero`]). NaN is a precondition
    /// violation and gives [`Sign::Zero`].
    #[inline]
    pub fn of(x: f64) -> Sign {
        if x > 0.0 {
            Sign::Positive
        } else if x < 0.0 {
            Sign::Negative
        } else {
            Sign::Zero
        }
    }

    /// The sign of a product of two numbers with these signs.
    #[inline]
    #[must_use]
    pub fn times(self, o: Sign) -> Sign {
        match (self, o) {
            (Sign::Zero, _) | (_, Sign::Zero) => Sign::Zero,
            (a, b) if a == b => Sign::Positive,
            _ => Sign::Negative,
        }
    }

    /// The opposite sign.
    #[inline]
    #[must_use]
    pub fn flip(self) -> Sign {
        match self {
            Sign::Negative => Sign::Positive,
            Sign::Zero => Sign::Zero,
            Sign::Positive => Sign::Negative,
        }
    }

    /// `Less`, `Equal`, `Greater` for negative, zero, positive.
    #[inline]
    pub fn to_ordering(self) -> std::cmp::Ordering {
        match self {
            Sign::Negative => std::cmp::Ordering::Less,
            Sign::Zero => std::cmp::Ordering::Equal,
            Sign::Positive => std::cmp::Ordering::Greater,
        }
    }
}

/// A coordinate axis; also names the coordinate dropped by [`orient2d_projected`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The first coordinate.
    X,
    /// The second coordinate.
    Y,
    /// The third coordinate.
    Z,
}

impl Axis {
    /// 0, 1, 2 for X, Y, Z.
    #[inline]
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// The projection that drops this coordinate, keeping the other two in cyclic order —
    /// `(y, z)` for `X`, `(z, x)` for `Y`, `(x, y)` for `Z` — the frame of
    /// [`orient2d_projected`].
    #[inline]
    pub fn project(self, p: Point3) -> [f64; 2] {
        let k = self.index();
        [p[(k + 1) % 3], p[(k + 2) % 3]]
    }

    /// The axis of the largest absolute component of `v` (the first on ties): the coordinate
    /// to drop when projecting a face with normal `v` to 2D. Any choice with a nonzero
    /// component is exact; the largest keeps the projection well-shaped.
    pub fn of_largest(v: [f64; 3]) -> Axis {
        let a = v.map(f64::abs);
        if a[0] >= a[1] && a[0] >= a[2] {
            Axis::X
        } else if a[1] >= a[2] {
            Axis::Y
        } else {
            Axis::Z
        }
    }
}

/// The largest coordinate magnitude the predicates accept: every finite f64. (Contrast spade's
/// `MAX_ALLOWED_VALUE = 2^201`: here a third, big-integer stage removes the limit.)
pub const MAX_ALLOWED_VALUE: f64 = f64::MAX;

/// The highest polynomial degree of any predicate: [`orient3d_points`] on four [`Tpi`] points,
/// `3 * 7 + 6 = 27`.
pub const MAX_DEGREE: u32 = 27;

/// The largest bit span of a call's inputs for which the expansion stage is guaranteed to
/// decide a predicate of polynomial degree `degree` (larger spans fall to big integers).
///
/// # Derivation
/// The call scales its inputs by `2^k` so that the largest magnitude is below `2^(T+1)` with
/// `T = 900 / degree - 1`. Every monomial is then below `2^900`, and with at most `2^95`
/// monomials (coefficients included; far more than any predicate has) no component reaches the
/// `2^995` split limit: no overflow. Every input is a multiple of `2^(T - span)`, so every
/// product of expansion components is a multiple of `2^(degree * (T - span))`; that is at least
/// the `2^-900` underflow floor of `two_product` when `span <= T + 900 / degree`, i.e.
/// `span <= 1800 / degree - 1` (integer division throughout).
///
/// Examples: an [`Lpi`] against an explicit plane (degree 6) allows a span of 299 bits, an
/// `orient2d` of three [`Lpi`] (degree 11) 161 bits, of three [`Tpi`] (degree 20) 89 bits —
/// i.e. full-precision coordinates within about `2^37` of each other.
pub const fn expansion_bit_span(degree: u32) -> i32 {
    2 * (900 / degree) as i32 - 1
}

/// The exponent the expansion stage scales the largest input to (see [`expansion_bit_span`]).
pub(crate) const fn expansion_top_exponent(degree: u32) -> i32 {
    (900 / degree) as i32 - 1
}

#[cfg(test)]
mod sign_tests {
    use super::*;

    #[test]
    fn sign_algebra() {
        use Sign::*;
        assert_eq!(Sign::of(-0.0), Zero);
        assert_eq!(Sign::of(-1e-320), Negative);
        assert_eq!(Negative.times(Negative), Positive);
        assert_eq!(Negative.times(Positive), Negative);
        assert_eq!(Zero.times(Negative), Zero);
        assert_eq!(Positive.flip(), Negative);
        assert_eq!(Zero.flip(), Zero);
        assert!(Negative.to_ordering().is_lt());
    }

    #[test]
    fn largest_axis() {
        assert_eq!(Axis::of_largest([0.0, -3.0, 2.0]), Axis::Y);
        assert_eq!(Axis::of_largest([1.0, 1.0, 1.0]), Axis::X);
        assert_eq!(Axis::of_largest([0.0, 0.0, -1e-300]), Axis::Z);
        assert_eq!(expansion_bit_span(6), 299);
        assert_eq!(expansion_bit_span(MAX_DEGREE), 65);
    }
}
