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

use robust::{Coord, Coord3D};

use super::Sign;
use super::cascade::decide;
use super::formulas::{Det3, PlaneSide};
use super::implicit::{Point, Point3};

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
    if a.iter().chain(&b).chain(&c).all(|&x| in_robust_range(x)) {
        let v = robust::orient2d(
            Coord { x: a[0], y: a[1] },
            Coord { x: b[0], y: b[1] },
            Coord { x: c[0], y: c[1] },
        );
        return Sign::of(v);
    }
    orient2d_cascade(a, b, c)
}

/// Orientation of four points in space.
///
/// [`Sign::Positive`] when `d` lies below the plane through `a, b, c` — the side from which
/// `a, b, c` appear clockwise, opposite to the right-handed normal `(b - a) × (c - a)` —
/// [`Sign::Negative`] above, [`Sign::Zero`] when coplanar. Equals the sign of
/// `det[a - d; b - d; c - d]`. Exact for all finite inputs.
pub fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
    if a.iter()
        .chain(&b)
        .chain(&c)
        .chain(&d)
        .all(|&x| in_robust_range(x))
    {
        let cv = |p: [f64; 3]| Coord3D {
            x: p[0],
            y: p[1],
            z: p[2],
        };
        return Sign::of(robust::orient3d(cv(a), cv(b), cv(c), cv(d)));
    }
    orient3d_cascade(a, b, c, d)
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
