//! A point's Cartesian coordinates to within a known error, and the cheap filters on them
//! that the predicates try before the homogeneous interval filter.
//!
//! # Why
//! The interval filter evaluates a predicate's polynomial in homogeneous coordinates: its
//! error grows with the coordinates themselves, so two intersection points a 1e-8 apart
//! (a cube turned by 1e-7 rad against itself) defeat it and go to the exact stages at about
//! 20 000 instructions each. Differences of Cartesian coordinates lose only each point's own
//! rounding: an `orient2d` of three such points is decided down to about `1e-30` here. Each
//! intersection point keeps its coordinates as a [`Nearby`] from construction, so the filters
//! below cost a few dozen floating-point operations, against about a thousand for the 3 × 3
//! homogeneous determinant in intervals.
//!
//! # Numeric model
//! Round to nearest: `|fl(x ∘ y) − x ∘ y| ≤ ε |fl(x ∘ y)|` with `ε = f64::EPSILON` (twice the
//! unit roundoff, so it also covers the bound taken on the rounded result) away from
//! underflow, and at most `2^-1075` in absolute value in it; a difference of two f64 that
//! underflows is exact. Each filter computes its error bound in round to nearest too, from
//! non-negative terms through at most a dozen roundings, so the computed bound times
//! `1 + 16 ε` covers the exact one, and `f64::MIN_POSITIVE` added covers every absolute
//! underflow error. An overflow gives an infinite or NaN value or bound, and every comparison
//! with NaN or an infinite bound is false: the filter abstains.

use super::Sign;
use super::interval::{Interval, next_down, next_up};

/// Three coordinates (the kernel's `Point3`; this module sits below the point types).
type Coords = [f64; 3];

/// `|exact[k] − at[k]| ≤ error[k]` for each coordinate `k` of a point.
///
/// An unbounded point (the interval of its `W` contains zero) has an infinite error, and
/// every filter abstains on it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Nearby {
    pub(crate) at: Coords,
    pub(crate) error: Coords,
}

/// The relative error of one rounding, with the margin described in the module docs.
const EPS: f64 = f64::EPSILON;

/// Inflates a bound computed in round to nearest from non-negative terms so that it covers
/// the exact bound (module docs).
#[inline(always)]
fn covered(bound: f64) -> f64 {
    bound * (1.0 + 16.0 * EPS) + f64::MIN_POSITIVE
}

impl Nearby {
    /// An input vertex: exact.
    #[inline]
    pub(crate) fn exact(p: Coords) -> Nearby {
        Nearby {
            at: p,
            error: [0.0; 3],
        }
    }

    /// A point the filters know nothing about.
    const UNBOUNDED: Nearby = Nearby {
        at: [0.0; 3],
        error: [f64::INFINITY; 3],
    };

    /// The midpoint and half-width of each interval of `box_`, rounded outward.
    pub(crate) fn of_box(box_: &[Interval; 3]) -> Nearby {
        let mut near = Nearby::UNBOUNDED;
        for ((at, error), i) in near.at.iter_mut().zip(&mut near.error).zip(box_) {
            let (lo, hi) = (i.lo(), i.hi());
            if !(lo.is_finite() && hi.is_finite()) {
                return Nearby::UNBOUNDED;
            }
            // Halves first: `lo + hi` may overflow. Halving is exact above the subnormals,
            // and `next_up` covers the rounding of both differences below.
            *at = lo * 0.5 + hi * 0.5;
            *error = next_up((hi - *at).max(*at - lo));
        }
        near
    }

    /// A box certain to contain the point: `(min, max)`, infinite when unbounded.
    pub(crate) fn enclosure(&self) -> (Coords, Coords) {
        if self.error.iter().any(|e| !e.is_finite()) {
            return ([f64::NEG_INFINITY; 3], [f64::INFINITY; 3]);
        }
        let lo = std::array::from_fn(|k| next_down(next_down(self.at[k] - self.error[k])));
        let hi = std::array::from_fn(|k| next_up(next_up(self.at[k] + self.error[k])));
        (lo, hi)
    }
}

/// The order of `a` and `b` on coordinate `k` where the errors allow telling it, `None`
/// where they do not.
#[inline]
pub(crate) fn compare_coordinate(a: &Nearby, b: &Nearby, k: usize) -> Option<std::cmp::Ordering> {
    let d = b.at[k] - a.at[k];
    let bound = covered(EPS * d.abs() + a.error[k] + b.error[k]);
    if d > bound {
        Some(std::cmp::Ordering::Less)
    } else if -d > bound {
        Some(std::cmp::Ordering::Greater)
    } else {
        None
    }
}

/// `x y − z w` of numbers each known to within its bound (`(x, hx)`: `|x − exact| ≤ hx`),
/// and a bound on its distance from the exact value, before [`covered`].
#[inline(always)]
fn det2(
    (x, hx): (f64, f64),
    (y, hy): (f64, f64),
    (z, hz): (f64, f64),
    (w, hw): (f64, f64),
) -> (f64, f64) {
    let (left, right) = (x * y, z * w);
    let det = left - right;
    let bound = x.abs() * hy
        + y.abs() * hx
        + hx * hy
        + z.abs() * hw
        + w.abs() * hz
        + hz * hw
        + EPS * (left.abs() + right.abs() + det.abs());
    (det, bound)
}

/// The sign of `(b_u − a_u)(c_v − a_v) − (b_v − a_v)(c_u − a_u)` for the exact points, where
/// the errors allow telling it: `orient2d` of the points projected onto coordinates `u, v`.
#[inline]
pub(crate) fn orient2d(a: &Nearby, b: &Nearby, c: &Nearby, u: usize, v: usize) -> Option<Sign> {
    // Each difference and a bound on its distance from the exact difference.
    let diff = |p: &Nearby, k: usize| {
        let d = p.at[k] - a.at[k];
        (d, EPS * d.abs() + p.error[k] + a.error[k])
    };
    let (det, bound) = det2(diff(b, u), diff(c, v), diff(b, v), diff(c, u));
    sign_beyond(det, covered(bound))
}

/// [`orient3d`](super::orient3d) of input vertices `a, b, c` and a point `d` known to within
/// its errors, where they allow telling it: the sign of `−((b − a) × (c − a)) · (d − a)`
/// (positive below the plane, as `orient3d`). The differences from `a` and the normal carry
/// bounds as in [`orient2d`]; the normal's bounds and the final one are each [`covered`],
/// their sums of non-negative terms rounding at most 30 times (`30 u = 15 EPS`, within the
/// `16 EPS` margin).
#[inline]
pub(crate) fn orient3d(a: Coords, b: Coords, c: Coords, d: &Nearby) -> Option<Sign> {
    let u: Coords = std::array::from_fn(|k| b[k] - a[k]);
    let v: Coords = std::array::from_fn(|k| c[k] - a[k]);
    let hu = u.map(|x| EPS * x.abs());
    let hv = v.map(|x| EPS * x.abs());
    let w: Coords = std::array::from_fn(|k| d.at[k] - a[k]);
    let hw: Coords = std::array::from_fn(|k| EPS * w[k].abs() + d.error[k]);
    // The normal `u × v`, each component with a bound on its distance from the exact one.
    let normal = |i: usize, j: usize| {
        let (n, bound) = det2((u[i], hu[i]), (v[j], hv[j]), (u[j], hu[j]), (v[i], hv[i]));
        (n, covered(bound))
    };
    let [(nx, hx), (ny, hy), (nz, hz)] = [normal(1, 2), normal(2, 0), normal(0, 1)];
    let (n, hn) = ([nx, ny, nz], [hx, hy, hz]);
    let products: Coords = std::array::from_fn(|k| n[k] * w[k]);
    let det = products[0] + products[1] + products[2];
    let mut bound = EPS * det.abs();
    for k in 0..3 {
        bound += n[k].abs() * hw[k] + w[k].abs() * hn[k] + hn[k] * hw[k];
        bound += 2.0 * EPS * products[k].abs();
    }
    sign_beyond(-det, covered(bound))
}

/// The sign of `value` where its magnitude exceeds `bound`, `None` where it does not (or
/// either is NaN).
#[inline(always)]
fn sign_beyond(value: f64, bound: f64) -> Option<Sign> {
    if value > bound {
        Some(Sign::Positive)
    } else if -value > bound {
        Some(Sign::Negative)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::oracle::{Q, q, q3, qcross, qdot, qsub};
    use crate::kernel::tests::qsign;
    use num_traits::Signed;

    fn near(at: Coords, error: f64) -> Nearby {
        Nearby {
            at,
            error: [error; 3],
        }
    }

    /// The filters decide only what holds for every point within the errors: checked on the
    /// corners of the error boxes, exactly, over close triples at many scales.
    #[test]
    fn decisions_hold_for_every_point_within_the_errors() {
        let mut next = crate::kernel::tests::xorshift(0x6e65_6172_6279_0001);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let (mut decided, mut decided_3d) = (0, 0);
        for round in 0..20_000 {
            let scale = [1.0, 1e-8, 1e-150, 1e150][round % 4];
            let spread = [1e-7, 1e-12, 1e-15, 1.0][(round / 4) % 4];
            let error = [0.0, 1e-17, 1e-16][(round / 16) % 3] * scale;
            let base = [unit(), unit(), unit()].map(|x| x * scale);
            let pts = [0, 1, 2].map(|_| {
                let p = std::array::from_fn(|k| base[k] + unit() * spread * scale);
                near(p, error)
            });
            let corners = |p: &Nearby| -> Vec<[Q; 2]> {
                (0..4)
                    .map(|m| {
                        let s = |bit: usize| if m >> bit & 1 == 1 { 1.0 } else { -1.0 };
                        [
                            q(p.at[0]) + q(s(0) * p.error[0]),
                            q(p.at[1]) + q(s(1) * p.error[1]),
                        ]
                    })
                    .collect()
            };
            if let Some(sign) = orient2d(&pts[0], &pts[1], &pts[2], 0, 1) {
                decided += 1;
                for a in corners(&pts[0]) {
                    for b in corners(&pts[1]) {
                        for c in corners(&pts[2]) {
                            let det = (&b[0] - &a[0]) * (&c[1] - &a[1])
                                - (&b[1] - &a[1]) * (&c[0] - &a[0]);
                            let exact = if det.is_positive() {
                                Sign::Positive
                            } else if det.is_negative() {
                                Sign::Negative
                            } else {
                                Sign::Zero
                            };
                            assert_eq!(exact, sign, "orient2d of {pts:?}");
                        }
                    }
                }
            }
            // `orient3d` of three of them taken as exact and a fourth within its errors: the
            // determinant is affine in the fourth, so the corners of its box bound it.
            let d = near(
                std::array::from_fn(|k| base[k] + unit() * spread * scale),
                error,
            );
            let [a, b, c] = pts.map(|p| p.at);
            if let Some(sign) = orient3d(a, b, c, &d) {
                decided_3d += 1;
                let (qa, qb, qc) = (q3(&a), q3(&b), q3(&c));
                for m in 0..8 {
                    let s = |bit: usize| if m >> bit & 1 == 1 { 1.0 } else { -1.0 };
                    let corner: [Q; 3] = std::array::from_fn(|k| q(d.at[k]) + q(s(k) * d.error[k]));
                    let (ad, bd, cd) = (qsub(&qa, &corner), qsub(&qb, &corner), qsub(&qc, &corner));
                    let det = qdot(&ad, &qcross(&bd, &cd));
                    assert_eq!(qsign(&det), sign, "orient3d of {a:?} {b:?} {c:?} {d:?}");
                }
            }
            if let Some(order) = compare_coordinate(&pts[0], &pts[1], 0) {
                for a in corners(&pts[0]) {
                    for b in corners(&pts[1]) {
                        assert_eq!(a[0].cmp(&b[0]), order, "compare of {pts:?}");
                    }
                }
            }
        }
        assert!(
            decided > 10_000,
            "the filter decided only {decided} of 20000"
        );
        assert!(
            decided_3d > 5_000,
            "orient3d decided only {decided_3d} of 20000"
        );
    }

    #[test]
    fn unbounded_and_overflowing_points_are_not_decided() {
        let inf = Nearby::of_box(&[Interval::new(f64::NEG_INFINITY, f64::INFINITY); 3]);
        let p = Nearby::exact([0.0, 0.0, 0.0]);
        let q = Nearby::exact([1.0, 0.0, 0.0]);
        assert_eq!(orient2d(&p, &q, &inf, 0, 1), None);
        assert_eq!(compare_coordinate(&p, &inf, 0), None);
        assert_eq!(inf.enclosure().0, [f64::NEG_INFINITY; 3]);
        let huge = Nearby::exact([f64::MAX, -f64::MAX, 0.0]);
        let far = Nearby::exact([-f64::MAX, f64::MAX, 0.0]);
        assert_eq!(orient2d(&huge, &far, &p, 0, 1), None);
        assert_eq!(compare_coordinate(&huge, &far, 0), None);
    }

    #[test]
    fn a_box_is_within_its_nearby_point() {
        let b = [
            Interval::new(0.1, 0.3),
            Interval::new(-1e-300, 1e-300),
            Interval::new(f64::MAX / 2.0, f64::MAX),
        ];
        let near = Nearby::of_box(&b);
        let (lo, hi) = near.enclosure();
        for k in 0..3 {
            let (at, error) = (q(near.at[k]), q(near.error[k]));
            assert!(&at - &error <= q(b[k].lo()) && q(b[k].hi()) <= &at + &error);
            assert!(lo[k] <= b[k].lo() && b[k].hi() <= hi[k]);
        }
    }
}
