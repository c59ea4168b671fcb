//! A big-rational oracle for exact geometry: every f64 is converted to an exact rational and
//! implicit points get rational coordinates (an LPI by its line parameter, a TPI by Gaussian
//! elimination).
//!
//! It shares no code with the kernel, so the kernel's tests (`kernel/tests.rs`) check every
//! predicate against it, and the exact engine's tests (`exact/intersect/tests.rs`) use it to
//! locate the kernel points they are given. Test-only: exact rationals are far too slow for
//! the engines.

use num_rational::BigRational;
use num_traits::Zero;

use super::{Point, Point3};

/// An exact rational.
pub(crate) type Q = BigRational;
/// An exact point or vector.
pub(crate) type Q3 = [Q; 3];

/// The exact value of a finite f64.
pub(crate) fn q(x: f64) -> Q {
    Q::from_float(x).expect("finite")
}

/// The exact coordinates of an input point.
pub(crate) fn q3(p: &Point3) -> Q3 {
    p.map(q)
}

/// `a − b`.
pub(crate) fn qsub(a: &Q3, b: &Q3) -> Q3 {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

/// The cross product `a × b`.
pub(crate) fn qcross(a: &Q3, b: &Q3) -> Q3 {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}

/// The dot product `a · b`.
pub(crate) fn qdot(a: &Q3, b: &Q3) -> Q {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

/// Plane `n · x = d` of a triangle, as rationals.
fn qplane(tri: &[Point3; 3]) -> (Q3, Q) {
    let t = tri.each_ref().map(q3);
    let n = qnormal(&t);
    let d = qdot(&n, &t[0]);
    (n, d)
}

/// The normal `(b − a) × (c − a)` of triangle `a b c` (right-handed, not normalised).
pub(crate) fn qnormal(t: &[Q3; 3]) -> Q3 {
    qcross(&qsub(&t[1], &t[0]), &qsub(&t[2], &t[0]))
}

/// LPI by its line parameter; `None` when the line is parallel to the plane.
pub(crate) fn oracle_lpi(p: &Point3, qq: &Point3, tri: &[Point3; 3]) -> Option<Q3> {
    let (n, d) = qplane(tri);
    let p = q3(p);
    let dir = qsub(&q3(qq), &p);
    let den = qdot(&n, &dir);
    if den.is_zero() {
        return None;
    }
    let lambda = (d - qdot(&n, &p)) / den;
    Some([0, 1, 2].map(|i| &p[i] + &dir[i] * &lambda))
}

/// TPI by Gaussian elimination with partial pivoting on nonzero entries.
pub(crate) fn oracle_tpi(planes: &[[Point3; 3]; 3]) -> Option<Q3> {
    let mut m: Vec<Vec<Q>> = planes
        .iter()
        .map(|t| {
            let (n, d) = qplane(t);
            let [a, b, c] = n;
            vec![a, b, c, d]
        })
        .collect();
    for col in 0..3 {
        let piv = (col..3).find(|&r| !m[r][col].is_zero())?;
        m.swap(col, piv);
        let pivot = m[col].clone();
        for (r, row) in m.iter_mut().enumerate() {
            if r != col && !row[col].is_zero() {
                let f = &row[col] / &pivot[col];
                for (x, p) in row.iter_mut().zip(&pivot).skip(col) {
                    *x -= p * &f;
                }
            }
        }
    }
    Some([0, 1, 2].map(|i| &m[i][3] / &m[i][i]))
}

/// The exact coordinates of a kernel point, explicit or implicit.
pub(crate) fn oracle_point(p: &Point) -> Q3 {
    match p {
        Point::Explicit(p) => q3(p),
        Point::Lpi(l) => {
            let (a, b, tri) = l.definition();
            oracle_lpi(&a, &b, &tri).expect("a built Lpi exists")
        }
        Point::Tpi(t) => oracle_tpi(t.planes()).expect("a built Tpi exists"),
    }
}
