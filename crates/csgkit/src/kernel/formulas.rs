//! The polynomials of the predicates, each a [`Formula`] over [`Point`]s that the cascade
//! decides: the side of a plane ([`PlaneSide`]), the 4 × 4 and 3 × 3 determinants of
//! homogeneous coordinates ([`Det4`], [`Det3`]) and a coordinate difference ([`AxisDiff`]).
//!
//! They sit between the cascade and the predicates that use them: `orient` (the fallback of
//! the explicit predicates outside `robust`'s range) and `predicates` (mixed explicit and
//! implicit arguments), so neither of those needs the other's internals.

use super::arith::Arith;
use super::cascade::Formula;
use super::implicit::{Point, Point3, conv3, normal};

/// `-(n · (X - W a))` with `n = (b - a) × (c - a)`: the orient3d of an explicit triangle and
/// a homogeneous point, before the factor `sign(W)`.
pub(crate) struct PlaneSide<'a> {
    pub(crate) tri: [Point3; 3],
    pub(crate) d: &'a Point,
}

impl Formula for PlaneSide<'_> {
    type Point = Point;

    #[inline]
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], conv: &dyn Fn(f64) -> T) -> T {
        let [a, b, c] = self.tri.map(|p| conv3(&p, conv));
        let n = normal(&a, &b, &c);
        let [x, y, z, w] = hom(self.d);
        // n · (W a - X)
        let e0 = w.mul(&a[0]).sub(&x);
        let e1 = w.mul(&a[1]).sub(&y);
        let e2 = w.mul(&a[2]).sub(&z);
        n[0].mul(&e0).add(&n[1].mul(&e1)).add(&n[2].mul(&e2))
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        std::iter::once(self.d)
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        self.tri.into_iter().flatten()
    }
    fn degree(&self) -> u32 {
        3 + self.d.w_degree()
    }
}

/// `det[[X_i, Y_i, Z_i, W_i]]` over four points: `orient3d` times `W_a W_b W_c W_d`.
pub(crate) struct Det4<'a>(pub(crate) [&'a Point; 4]);

impl Formula for Det4<'_> {
    type Point = Point;

    #[inline]
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], _conv: &dyn Fn(f64) -> T) -> T {
        let r = self.0.map(hom);
        // Laplace expansion along columns (0, 1) against columns (2, 3).
        let lo = |i: usize, j: usize| r[i][0].mul(&r[j][1]).sub(&r[j][0].mul(&r[i][1]));
        let hi = |i: usize, j: usize| r[i][2].mul(&r[j][3]).sub(&r[j][2].mul(&r[i][3]));
        let plus = lo(0, 1)
            .mul(&hi(2, 3))
            .add(&lo(0, 3).mul(&hi(1, 2)))
            .add(&lo(1, 2).mul(&hi(0, 3)))
            .add(&lo(2, 3).mul(&hi(0, 1)));
        let minus = lo(0, 2).mul(&hi(1, 3)).add(&lo(1, 3).mul(&hi(0, 2)));
        plus.sub(&minus)
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        self.0.into_iter()
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        std::iter::empty()
    }
    fn degree(&self) -> u32 {
        3 + self.0.iter().map(|p| p.w_degree()).sum::<u32>()
    }
}

/// `det[[U_i, V_i, W_i]]` over three points, `(U, V)` the coordinates kept after dropping
/// one: `orient2d` of the projection times `W_a W_b W_c`.
pub(crate) struct Det3<'a> {
    pub(crate) pts: [&'a Point; 3],
    pub(crate) u: usize,
    pub(crate) v: usize,
}

impl Formula for Det3<'_> {
    type Point = Point;

    #[inline]
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], _conv: &dyn Fn(f64) -> T) -> T {
        let r = self.pts.map(hom);
        let (u, v) = (self.u, self.v);
        let m = |i: usize, j: usize| r[i][u].mul(&r[j][v]).sub(&r[j][u].mul(&r[i][v]));
        // Expansion along the W column.
        r[2][3]
            .mul(&m(0, 1))
            .add(&r[0][3].mul(&m(1, 2)))
            .sub(&r[1][3].mul(&m(0, 2)))
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        self.pts.into_iter()
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        std::iter::empty()
    }
    fn degree(&self) -> u32 {
        2 + self.pts.iter().map(|p| p.w_degree()).sum::<u32>()
    }
}

/// `X_a W_b - X_b W_a` along one axis: the coordinate difference times `W_a W_b`.
pub(crate) struct AxisDiff<'a> {
    pub(crate) a: &'a Point,
    pub(crate) b: &'a Point,
    pub(crate) axis: usize,
}

impl Formula for AxisDiff<'_> {
    type Point = Point;

    #[inline]
    fn eval<T: Arith>(&self, hom: &dyn Fn(&Point) -> [T; 4], _conv: &dyn Fn(f64) -> T) -> T {
        let ha = hom(self.a);
        let hb = hom(self.b);
        let i = self.axis;
        ha[i].mul(&hb[3]).sub(&hb[i].mul(&ha[3]))
    }
    fn points(&self) -> impl Iterator<Item = &Point> {
        [self.a, self.b].into_iter()
    }
    fn explicit_coords(&self) -> impl Iterator<Item = f64> {
        std::iter::empty()
    }
    fn degree(&self) -> u32 {
        1 + self.a.w_degree() + self.b.w_degree()
    }
}
