//! The kernel against a big-rational oracle.
//!
//! The oracle (`oracle.rs`) shares no code with the kernel: it converts every f64 to an exact rational,
//! computes implicit points as rational coordinates (an LPI by its line parameter, a TPI by
//! Gaussian elimination), and evaluates the textbook determinants. Every predicate is checked
//! through its public function and, where a formula exists, stage by stage (filter,
//! expansions, big integers): a stage may abstain but never disagree.
//!
//! Inputs come from proptest with fixed seeds: random coordinates at many magnitudes, small
//! integers (which make coplanar, collinear and coincident configurations common), and
//! constructions that are degenerate by design (implicit points on their own planes, implicit
//! points equal to vertices and to each other), each scaled by powers of two from `2^-1000`
//! to `2^1000` and by non-dyadic factors up to `3.4e38`.

use std::cmp::Ordering;
use std::fmt::Write as _;

use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

use super::cascade::{Formula, stages};
use super::formulas::{AxisDiff, Det3, Det4, PlaneSide};
use super::oracle::{Q, Q3, oracle_lpi, oracle_point, oracle_tpi, q, q3, qcross, qdot, qsub};
use super::*;

/// A xorshift64 stream for the kernel's unit tests that draw many plain cases: reproducible,
/// and cheap enough for tens of thousands of rounds.
pub(crate) fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}

/// The sign of an exact rational.
pub(crate) fn qsign(x: &Q) -> Sign {
    if x.is_zero() {
        Sign::Zero
    } else if x.is_positive() {
        Sign::Positive
    } else {
        Sign::Negative
    }
}

fn oracle_orient3d(a: &Q3, b: &Q3, c: &Q3, d: &Q3) -> Sign {
    let (ad, bd, cd) = (qsub(a, d), qsub(b, d), qsub(c, d));
    qsign(&qdot(&ad, &qcross(&bd, &cd)))
}

fn oracle_orient2d(a: &Q3, b: &Q3, c: &Q3, drop: Axis) -> Sign {
    let k = drop.index();
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    let det = (&a[u] - &c[u]) * (&b[v] - &c[v]) - (&a[v] - &c[v]) * (&b[u] - &c[u]);
    qsign(&det)
}

const AXES: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

/// Checks every stage of a formula against the oracle's sign of the same polynomial.
fn check_stages(f: &impl Formula, want: Sign, what: &dyn Fn() -> String) {
    let got = stages(f);

    for (stage, s) in [
        "filter",
        "128-bit integers",
        "double-doubles",
        "expansions",
        "big integers",
    ]
    .iter()
    .zip(got)
    {
        if let Some(s) = s {
            assert_eq!(s, want, "{stage} disagrees with the oracle on {}", what());
        }
    }
}

/// The filter intervals an implicit point keeps (built in [`Tracked`](super::interval::Tracked)
/// arithmetic where its inputs allow, else in intervals) enclose its exact homogeneous
/// coordinates, where expansions give them exactly.
fn check_filter_encloses(p: &Point) {
    use super::cascade::Homogeneous;
    use super::expansion::Expansion;
    let exact = p.hom(&Expansion::exact, &Expansion::exact(1.0));
    for (interval, exact) in p.filter_hom().iter().zip(&exact) {
        let (lo, hi) = (interval.lo(), interval.hi());
        if !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        let below = exact.sub(&Expansion::exact(lo)).sign();
        let above = Expansion::exact(hi).sub(exact).sign();
        if let (Some(below), Some(above)) = (below, above) {
            assert!(
                below != Sign::Negative && above != Sign::Negative,
                "[{lo:e}, {hi:e}] does not enclose a coordinate of {p:?}"
            );
        }
    }
}

/// Runs every predicate on `pts` (at least four points) and compares with the oracle.
/// Returns the number of predicate evaluations checked.
fn check_all(pts: &[Point]) -> usize {
    pts.iter().for_each(check_filter_encloses);
    let qs: Vec<Q3> = pts.iter().map(oracle_point).collect();
    let n = pts.len();
    let w: Vec<Sign> = pts.iter().map(|p| p.w_sign()).collect();
    let desc = |idx: &[usize]| {
        let mut s = String::new();
        for &i in idx {
            let _ = write!(s, "\n  {:?}", pts[i]);
        }
        s
    };
    let mut count = 0;
    for start in 0..n {
        let [i, j, k, l] = [0, 1, 2, 3].map(|o| (start + o) % n);
        let (a, b, c, d) = (&pts[i], &pts[j], &pts[k], &pts[l]);

        let want = oracle_orient3d(&qs[i], &qs[j], &qs[k], &qs[l]);
        let what = || format!("orient3d_points{}", desc(&[i, j, k, l]));
        assert_eq!(orient3d_points(a, b, c, d), want, "{}", what());
        let wprod = w[i].times(w[j]).times(w[k]).times(w[l]);
        check_stages(&Det4([a, b, c, d]), want.times(wprod), &what);
        count += 1;

        if let (Point::Explicit(ea), Point::Explicit(eb), Point::Explicit(ec)) = (a, b, c) {
            let what = || format!("orient3d_plane{}", desc(&[i, j, k, l]));
            assert_eq!(orient3d_plane(*ea, *eb, *ec, d), want, "{}", what());
            // The filter on nearby coordinates on its own (`orient3d_plane` asks it only
            // after its proofs by definition): it may abstain, never disagree.
            if let Some(sign) = super::nearby::orient3d(*ea, *eb, *ec, &d.nearby()) {
                assert_eq!(sign, want, "nearby {}", what());
            }
            let f = PlaneSide {
                tri: [*ea, *eb, *ec],
                d,
            };
            check_stages(&f, want.times(w[l]), &what);
            count += 1;
        }

        for axis in AXES {
            let want = oracle_orient2d(&qs[i], &qs[j], &qs[k], axis);
            let what = || format!("orient2d_projected {axis:?}{}", desc(&[i, j, k]));
            assert_eq!(orient2d_projected(a, b, c, axis), want, "{}", what());
            let k3 = axis.index();
            let f = Det3 {
                pts: [a, b, c],
                u: (k3 + 1) % 3,
                v: (k3 + 2) % 3,
            };
            check_stages(&f, want.times(w[i].times(w[j]).times(w[k])), &what);

            let want = qs[i][axis.index()].cmp(&qs[j][axis.index()]);
            let what = || format!("compare_along {axis:?}{}", desc(&[i, j]));
            assert_eq!(compare_along(a, b, axis), want, "{}", what());
            let f = AxisDiff {
                a,
                b,
                axis: axis.index(),
            };
            let ws = match want {
                Ordering::Less => Sign::Negative,
                Ordering::Equal => Sign::Zero,
                Ordering::Greater => Sign::Positive,
            };
            check_stages(&f, ws.times(w[i].times(w[j])), &what);
            count += 2;
        }
        let want = qs[i].cmp(&qs[j]);
        assert_eq!(compare_lex(a, b), want, "compare_lex{}", desc(&[i, j]));
        assert_eq!(same_point(a, b), want == Ordering::Equal);
        count += 1;
    }
    count
}

/// Turns a pool of coordinates into points: explicit, LPI or TPI as `sel` says, falling
/// back to an explicit point when an implicit one does not exist.
struct Builder<'a> {
    c: &'a [f64],
    i: usize,
    sel: u64,
}

impl Builder<'_> {
    fn coord(&mut self) -> f64 {
        let x = self.c[self.i % self.c.len()];
        self.i += 1;
        x
    }
    fn p3(&mut self) -> Point3 {
        [self.coord(), self.coord(), self.coord()]
    }
    fn bits(&mut self, n: u32) -> u64 {
        let b = self.sel & ((1 << n) - 1);
        self.sel = self.sel.rotate_right(n);
        b
    }
    fn point(&mut self) -> Point {
        match self.bits(2) {
            0 | 1 => Point::Explicit(self.p3()),
            2 => {
                let d = [self.p3(), self.p3(), self.p3(), self.p3(), self.p3()];
                Point::lpi(d[0], d[1], d[2], d[3], d[4]).unwrap_or(Point::Explicit(d[0]))
            }
            _ => {
                let t = [
                    [self.p3(), self.p3(), self.p3()],
                    [self.p3(), self.p3(), self.p3()],
                    [self.p3(), self.p3(), self.p3()],
                ];
                Point::tpi(t).unwrap_or(Point::Explicit(t[0][0]))
            }
        }
    }
    fn points(&mut self, n: usize) -> Vec<Point> {
        (0..n).map(|_| self.point()).collect()
    }
}

/// A proptest configuration with a fixed seed and no persisted failures, so every run
/// explores the same cases (shared with the split stage's tests).
pub(crate) fn config(cases: u32, seed: u64) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        ..Config::default()
    }
}

/// Random f64 coordinates of one magnitude class per case.
fn coords_at(scale: f64) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1.0f64..1.0, 48)
        .prop_map(move |v| v.into_iter().map(|x| x * scale).collect())
}

/// Small integers times `scale`: collinear, coplanar and coincident configurations are
/// frequent, and exact when `scale` is a power of two.
fn ints_at(scale: f64) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-3i32..=3, 48)
        .prop_map(move |v| v.into_iter().map(|x| f64::from(x) * scale).collect())
}

const POW2_SCALES: [i32; 7] = [-1000, -300, -40, 0, 40, 300, 1000];

fn pow2(k: i32) -> f64 {
    2f64.powi(k)
}

proptest! {
    #![proptest_config(config(300, 0x6b65_726e_656c_0001))]

    #[test]
    fn random_unit_coordinates_match_oracle(c in coords_at(1.0), sel in any::<u64>()) {
        let pts = Builder { c: &c, i: 0, sel }.points(5);
        check_all(&pts);
    }

    #[test]
    fn small_integer_coordinates_match_oracle(c in ints_at(1.0), sel in any::<u64>()) {
        let pts = Builder { c: &c, i: 0, sel }.points(5);
        check_all(&pts);
    }
}

proptest! {
    #![proptest_config(config(200, 0x6b65_726e_656c_0002))]

    #[test]
    fn power_of_two_scaled_integers_match_oracle(
        c in ints_at(1.0), sel in any::<u64>(), k in 0usize..POW2_SCALES.len()
    ) {
        let s = pow2(POW2_SCALES[k]);
        let c: Vec<f64> = c.iter().map(|x| x * s).collect();
        let pts = Builder { c: &c, i: 0, sel }.points(5);
        check_all(&pts);
    }

    #[test]
    fn huge_and_tiny_random_coordinates_match_oracle(
        c in prop::collection::vec(-1.0f64..1.0, 48),
        sel in any::<u64>(),
        k in 0usize..7,
    ) {
        // f64::MAX: every filter interval overflows and the exact stages must still answer.
        let s = [1e30, 3.4e38, 1e300, f64::MAX, 1e-30, 1e-300, 4.9e-324][k];
        let c: Vec<f64> = c.iter().map(|x| x * s).collect();
        let pts = Builder { c: &c, i: 0, sel }.points(5);
        check_all(&pts);
    }
}

proptest! {
    // Fewer cases: full-mantissa coordinates over a wide span make rationals expensive.
    #![proptest_config(config(60, 0x6b65_726e_656c_0006))]

    #[test]
    fn mixed_magnitudes_match_oracle(
        c in prop::collection::vec((-1.0f64..1.0, -60i32..60), 48),
        sel in any::<u64>(),
    ) {
        // Coordinates spread over 2^120 within one call: wide bit spans for the expansion stage.
        let c: Vec<f64> = c.iter().map(|&(x, e)| x * pow2(e)).collect();
        let pts = Builder { c: &c, i: 0, sel }.points(5);
        check_all(&pts);
    }
}

/// A point `x`, segments through it and triangles whose planes contain it.
fn through(x: Point3, dirs: &[Point3]) -> Vec<[Point3; 3]> {
    let add = |a: Point3, b: Point3| [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
    dirs.chunks(2)
        .map(|d| [x, add(x, d[0]), add(x, d[1])])
        .collect()
}

proptest! {
    #![proptest_config(config(300, 0x6b65_726e_656c_0003))]

    /// Implicit points that coincide with a vertex and with each other, and lie on their own
    /// planes: every filter abstains here, so this exercises the exact stages.
    #[test]
    fn coincident_implicit_points_match_oracle(
        x in prop::array::uniform3(-4i32..=4),
        dirs in prop::collection::vec(prop::array::uniform3(-3i32..=3), 12),
        other in ints_at(1.0),
        k in 0usize..POW2_SCALES.len(),
    ) {
        let s = pow2(POW2_SCALES[k]);
        let x = x.map(|v| f64::from(v) * s);
        let dirs: Vec<Point3> = dirs.iter().map(|d| d.map(|v| f64::from(v) * s)).collect();
        let tris = through(x, &dirs);
        let sub = |a: Point3, b: Point3| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let add = |a: Point3, b: Point3| [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        let mut pts = vec![Point::Explicit(x)];
        // Segments through x (x is their midpoint), against planes through x.
        for (i, t) in tris.iter().enumerate() {
            let d = dirs[(i + 3) % dirs.len()];
            if let Some(p) = Point::lpi(sub(x, d), add(x, d), t[0], t[1], t[2]) {
                pts.push(p);
            }
        }
        if let Some(p) = Point::tpi([tris[0], tris[1], tris[2]]) {
            pts.push(p);
        }
        if let Some(p) = Point::tpi([tris[3], tris[4], tris[5]]) {
            pts.push(p);
        }
        for p in &pts {
            prop_assert!(same_point(p, &pts[0]), "{:?} is not at {:?}", p, x);
            for t in &tris {
                prop_assert_eq!(orient3d_plane(t[0], t[1], t[2], p), Sign::Zero);
            }
        }
        // Mix with other points so the predicates are not all trivially zero.
        let other: Vec<f64> = other.iter().map(|v| v * s).collect();
        let mut b = Builder { c: &other, i: 0, sel: 0x5555_5555_5555_5555 };
        while pts.len() < 6 {
            pts.push(b.point());
        }
        pts.push(Point::Explicit(b.p3()));
        check_all(&pts);
    }

    /// Implicit points on one line (a segment against several planes) and on one plane.
    #[test]
    fn collinear_and_coplanar_implicit_points_match_oracle(
        seg in prop::array::uniform6(-4i32..=4),
        c in ints_at(1.0),
        k in 0usize..POW2_SCALES.len(),
    ) {
        let s = pow2(POW2_SCALES[k]);
        let p = [seg[0], seg[1], seg[2]].map(|v| f64::from(v) * s);
        let q = [seg[3], seg[4], seg[5]].map(|v| f64::from(v) * s);
        let c: Vec<f64> = c.iter().map(|v| v * s).collect();
        let mut b = Builder { c: &c, i: 0, sel: 0 };
        let mut on_line = vec![Point::Explicit(p), Point::Explicit(q)];
        for _ in 0..4 {
            let t = [b.p3(), b.p3(), b.p3()];
            if let Some(x) = Point::lpi(p, q, t[0], t[1], t[2]) {
                on_line.push(x);
            }
        }
        // Every point on the line pq is collinear with p and q in every projection.
        for x in &on_line {
            for axis in AXES {
                prop_assert_eq!(
                    orient2d_projected(&on_line[0], &on_line[1], x, axis),
                    Sign::Zero
                );
            }
        }
        // Points on one plane: LPIs of several segments against the same triangle.
        let t = [b.p3(), b.p3(), b.p3()];
        let mut on_plane = vec![];
        for _ in 0..4 {
            if let Some(x) = Point::lpi(b.p3(), b.p3(), t[0], t[1], t[2]) {
                on_plane.push(x);
            }
        }
        if on_plane.len() >= 3 {
            let e = Point::Explicit(b.p3());
            let a = &on_plane;
            prop_assert_eq!(orient3d_points(&a[0], &a[1], &a[2], &Point::Explicit(t[0])), Sign::Zero);
            let want = orient3d(t[0], t[1], t[2], b.p3());
            let _ = (e, want);
        }
        let mut all = on_line;
        all.extend(on_plane);
        all.push(Point::Explicit(t[1]));
        all.push(Point::Explicit(t[2]));
        if all.len() >= 4 {
            check_all(&all);
        }
    }
}

proptest! {
    #![proptest_config(config(300, 0x6b65_726e_656c_0008))]

    /// Intersection points on axis planes and on axis-parallel lines, as boxes and extrusions
    /// make them, on a coarse grid so that many share coordinates: every coordinate
    /// [`Point::known_coordinate`] gives is the exact one, and the predicates that use them
    /// (ties of [`compare_along`], collinear triples of [`orient2d_projected`]) match the
    /// oracle.
    #[test]
    fn axis_aligned_implicit_points_match_oracle(
        grid in prop::collection::vec(-2i32..=2, 120),
        axes in prop::collection::vec(0usize..3, 10),
    ) {
        let mut values = grid.iter().map(|&v| f64::from(v) * 0.5).cycle();
        let mut point = || [(); 3].map(|()| values.next().unwrap_or(0.0));
        let on_axis_plane = |mut t: [Point3; 3], k: usize| {
            let c = t[0][k];
            t.iter_mut().for_each(|p| p[k] = c);
            t
        };
        let mut pts = vec![Point::Explicit(point())];
        for (i, &k) in axes.iter().enumerate() {
            let (p, mut q) = (point(), point());
            let t = [point(), point(), point()];
            let made = match i % 3 {
                // A line against an axis plane.
                0 => {
                    let [r, s, u] = on_axis_plane(t, k);
                    Point::lpi(p, q, r, s, u)
                }
                // An axis-parallel line (its ends share coordinate k) against a plane.
                1 => {
                    q[k] = p[k];
                    Point::lpi(p, q, t[0], t[1], t[2])
                }
                // An axis plane and two other planes.
                _ => Point::tpi([on_axis_plane(t, k), [p, q, t[0]], [q, t[1], p]]),
            };
            pts.extend(made);
        }
        for p in &pts {
            let exact = oracle_point(p);
            for (k, exact) in exact.iter().enumerate() {
                if let Some(x) = p.known_coordinate(k) {
                    prop_assert_eq!(&q(x), exact, "{:?} on axis {}", p, k);
                }
            }
        }
        if pts.len() >= 4 {
            check_all(&pts);
        }
    }
}

proptest! {
    #![proptest_config(config(300, 0x6b65_726e_656c_0009))]

    /// An axis-parallel line against an axis plane across it, and three axis planes of the
    /// three axes, are built as explicit points: exactly the oracle's, and refused exactly
    /// where the oracle finds no single point (degenerate triangles, on a coarse grid where
    /// many are). Any other placement is left implicit.
    #[test]
    fn points_on_axis_planes_are_explicit_and_exact(
        grid in prop::collection::vec(-2i32..=2, 42),
        axes in prop::array::uniform3(0usize..3),
    ) {
        let c: Vec<f64> = grid.iter().map(|&v| f64::from(v) * 0.5).collect();
        let p = |i: usize| [c[3 * i], c[3 * i + 1], c[3 * i + 2]];
        let on_axis_plane = |mut t: [Point3; 3], k: usize| {
            let level = t[0][k];
            t.iter_mut().for_each(|x| x[k] = level);
            t
        };
        let agrees = |made: Option<Point>, exact: Option<Q3>, pinned: bool| {
            match (made, exact) {
                (None, None) => Ok(()),
                (Some(x), Some(exact)) => {
                    prop_assert_eq!(x.is_explicit(), pinned, "{:?}", x);
                    prop_assert_eq!(oracle_point(&x), exact);
                    Ok(())
                }
                (made, exact) => Err(TestCaseError::fail(format!("{made:?} against {exact:?}"))),
            }
        };
        // The line along axis k (its ends share the other two coordinates).
        let k = axes[0];
        let (a, mut b) = (p(0), p(1));
        for i in [(k + 1) % 3, (k + 2) % 3] {
            b[i] = a[i];
        }
        let plane = on_axis_plane([p(2), p(3), p(4)], axes[1]);
        let pinned = axes[1] == k && a[k] != b[k];
        agrees(Point::lpi(a, b, plane[0], plane[1], plane[2]), oracle_lpi(&a, &b, &plane), pinned)?;
        let planes = [0, 1, 2].map(|i| on_axis_plane([p(5 + 3 * i), p(6 + 3 * i), p(7 + 3 * i)], axes[i]));
        let distinct = axes[0] != axes[1] && axes[1] != axes[2] && axes[0] != axes[2];
        agrees(Point::tpi(planes), oracle_tpi(&planes), distinct)?;
    }
}

/// Explicit orient2d/orient3d against the oracle at every magnitude, including the ranges
/// where `robust` is bypassed.
#[test]
fn explicit_predicates_match_oracle_at_every_magnitude() {
    let mut runner = proptest::test_runner::TestRunner::new(config(600, 0x6b65_726e_656c_0004));
    let strat = (
        prop::collection::vec(-3i32..=3, 12),
        prop::collection::vec(-1.0f64..1.0, 12),
        0usize..9,
        any::<bool>(),
    );
    runner
        .run(&strat, |(ints, floats, k, use_ints)| {
            let s = [
                1.0,
                1e-30,
                1e30,
                3.4e38,
                1e-300,
                1e300,
                pow2(-1070),
                pow2(1020),
                1e-200,
            ][k];
            let c: Vec<f64> = if use_ints {
                ints.iter().map(|&v| f64::from(v) * s).collect()
            } else {
                floats.iter().map(|&v| v * s).collect()
            };
            let p = |i: usize| [c[3 * i], c[3 * i + 1], c[3 * i + 2]];
            let want = oracle_orient3d(&q3(&p(0)), &q3(&p(1)), &q3(&p(2)), &q3(&p(3)));
            prop_assert_eq!(orient3d(p(0), p(1), p(2), p(3)), want);
            for axis in AXES {
                let want = oracle_orient2d(&q3(&p(0)), &q3(&p(1)), &q3(&p(2)), axis);
                let k = axis.index();
                let (u, v) = ((k + 1) % 3, (k + 2) % 3);
                let pr = |i: usize| [p(i)[u], p(i)[v]];
                prop_assert_eq!(orient2d(pr(0), pr(1), pr(2)), want);
            }
            Ok(())
        })
        .expect("explicit predicates agree with the oracle");
}

/// A point exactly on its own plane, and the same point nudged by one ulp along each axis:
/// the classic case a plain floating-point evaluation gets wrong.
#[test]
fn one_ulp_off_the_plane_is_seen() {
    let (r, s, t) = ([0.1, 0.2, 0.3], [1.7, -0.4, 0.9], [-0.6, 1.3, 0.25]);
    let on = Point::lpi([0.0, 0.0, -5.0], [0.3, 0.1, 5.0], r, s, t).expect("crosses");
    assert_eq!(orient3d_plane(r, s, t, &on), Sign::Zero);
    let x = oracle_point(&on);
    // Explicit points near the implicit one: the oracle decides, the kernel must agree.
    let a = on.approx();
    for axis in 0..3 {
        for dir in [-1.0f64, 1.0] {
            let mut b = a;
            b[axis] = if dir > 0.0 {
                super::interval::next_up(a[axis])
            } else {
                super::interval::next_down(a[axis])
            };
            let e = Point::Explicit(b);
            let want = oracle_orient3d(&q3(&r), &q3(&s), &q3(&t), &q3(&b));
            assert_eq!(orient3d_plane(r, s, t, &e), want);
            let cmp = q(b[axis]).cmp(&x[axis]);
            assert_eq!(compare_along(&e, &on, AXES[axis]), cmp);
        }
    }
}

/// The filter on nearby coordinates decides an intersection point against planes a
/// millionth to a trillionth from it, and agrees with the oracle there; on the point's own
/// plane it abstains.
#[test]
fn nearby_orient3d_decides_points_close_to_a_plane() {
    let (r, s, t) = ([0.1, 0.2, 0.3], [1.7, -0.4, 0.9], [-0.6, 1.3, 0.25]);
    let on = Point::lpi([0.0, 0.0, -5.0], [0.3, 0.1, 5.0], r, s, t).expect("crosses");
    assert_eq!(super::nearby::orient3d(r, s, t, &on.nearby()), None);
    let x = oracle_point(&on);
    for offset in [1e-6, 1e-9, 1e-12, -1e-6, -1e-9, -1e-12] {
        // The plane moved along z by `offset`: the point is off it by about that much.
        let lift = |p: Point3| [p[0], p[1], p[2] + offset];
        let (r2, s2, t2) = (lift(r), lift(s), lift(t));
        let want = oracle_orient3d(&q3(&r2), &q3(&s2), &q3(&t2), &x);
        assert_ne!(want, Sign::Zero);
        let sign = super::nearby::orient3d(r2, s2, t2, &on.nearby());
        assert_eq!(sign, Some(want), "offset {offset:e}");
        assert_eq!(orient3d_plane(r2, s2, t2, &on), want, "offset {offset:e}");
    }
}

/// A caller's proof of collinearity is asked only where the filter cannot decide, and a
/// refused proof leaves the answer to the exact stages.
#[test]
fn the_collinearity_proof_is_asked_only_where_the_filter_cannot_decide() {
    let (r, s, t) = ([0.1, 0.2, 0.3], [1.7, -0.4, 0.9], [-0.6, 1.3, 0.25]);
    let crossing = |p: Point3, q: Point3| Point::lpi(p, q, r, s, t).expect("crosses");
    let a = crossing([0.0, 0.0, -5.0], [0.3, 0.1, 5.0]);
    let b = crossing([1.0, 0.0, -5.0], [0.7, 0.2, 5.0]);
    let c = crossing([0.0, 1.0, -5.0], [0.1, 0.9, 5.0]);
    let asked = std::cell::Cell::new(0);
    let proof = |answer: bool| {
        asked.set(asked.get() + 1);
        answer
    };
    let generic = orient2d_projected_or_collinear(&a, &b, &c, Axis::Z, || proof(true));
    assert_eq!(generic, orient2d_projected(&a, &b, &c, Axis::Z));
    assert_ne!(generic, Sign::Zero);
    assert_eq!(
        asked.get(),
        0,
        "the filter decides three points in general position"
    );
    // A repeated point: the filter cannot see the zero, the proof (or the exact stages) can.
    assert_eq!(
        orient2d_projected_or_collinear(&a, &b, &b, Axis::Z, || proof(true)),
        Sign::Zero
    );
    assert_eq!(
        orient2d_projected_or_collinear(&a, &b, &b, Axis::Z, || proof(false)),
        Sign::Zero
    );
    assert_eq!(asked.get(), 2);
}

/// The `W` of a point is exactly zero iff the oracle finds no unique intersection.
#[test]
fn construction_refuses_exactly_the_degenerate_definitions() {
    let r = [0.0, 0.0, 0.0];
    let (s, t) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    // Parallel segment, degenerate triangle, non-finite input.
    assert!(Point::lpi([0.0, 0.0, 1.0], [1.0, 1.0, 1.0], r, s, t).is_none());
    assert!(Point::lpi([0.0, 0.0, 1.0], [0.0, 0.0, -1.0], r, s, [2.0, 0.0, 0.0]).is_none());
    assert!(Point::lpi([0.0, 0.0, f64::NAN], [0.0, 0.0, -1.0], r, s, t).is_none());
    // A segment parallel to the plane only up to rounding is not parallel.
    let z = 1e-300;
    assert!(Point::lpi([0.0, 0.0, 1.0], [1.0, 1.0, 1.0 + f64::EPSILON], r, s, t).is_some());
    assert!(Point::lpi([0.0, 0.0, z], [1.0, 1.0, 0.0], r, s, t).is_some());
    // Three planes through one line; two parallel planes.
    let xy = [r, s, t];
    let xz = [r, s, [0.0, 0.0, 1.0]];
    let tilted = [r, s, [0.0, 1.0, 1.0]];
    assert!(Point::tpi([xy, xz, tilted]).is_none());
    let xy_up = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
    let yz = [r, [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(Point::tpi([xy, xy_up, yz]).is_none());
    let p = Point::tpi([xy, xz, yz]).expect("the three coordinate planes meet at the origin");
    assert!(same_point(&p, &Point::Explicit([0.0, 0.0, 0.0])));
    assert_eq!(p.approx(), [0.0, 0.0, 0.0]);
}

proptest! {
    #![proptest_config(config(300, 0x6b65_726e_656c_0007))]

    /// Coplanar edge–edge crossings: the point is on both edges' lines (collinear in the
    /// projection), on the plane, equal to the LPI of one edge against the other edge's
    /// vertical plane, and every predicate on it matches the oracle.
    #[test]
    fn coplanar_edge_crossings_match_oracle(
        v in prop::collection::vec(prop::array::uniform3(-4i32..=4), 4),
        tri in prop::collection::vec(prop::array::uniform3(-4i32..=4), 3),
        k in 0usize..POW2_SCALES.len(),
        float in any::<bool>(),
        c in coords_at(1.0),
    ) {
        let s = pow2(POW2_SCALES[k]);
        let tri: Vec<Point3> = tri.iter().map(|p| p.map(|x| f64::from(x) * s)).collect();
        let tri = [tri[0], tri[1], tri[2]];
        let (a, b0, c0) = (tri[0], tri[1], tri[2]);
        // Edge endpoints in the plane: integer affine combinations of the triangle's vertices.
        let in_plane = |w: [i32; 3]| {
            let (i, j) = (f64::from(w[0]), f64::from(w[1]));
            [0, 1, 2].map(|m| a[m] + i * (b0[m] - a[m]) + j * (c0[m] - a[m]))
        };
        let mut e: Vec<Point3> = v.iter().map(|w| in_plane(*w)).collect();
        if float {
            // Random-float endpoints are generally off the plane; still a valid construction.
            e[3] = [c[0], c[1], c[2]].map(|x| x * s);
        }
        let n = {
            let u = [0, 1, 2].map(|m| b0[m] - a[m]);
            let w = [0, 1, 2].map(|m| c0[m] - a[m]);
            [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
        };
        let drop = Axis::of_largest(n);
        if let Some(x) = Point::edge_crossing(tri, [e[0], e[1]], [e[2], e[3]], drop) {
            prop_assert_eq!(orient3d_plane(a, b0, c0, &x), Sign::Zero);
            let (p, q) = (Point::Explicit(e[0]), Point::Explicit(e[1]));
            prop_assert_eq!(orient2d_projected(&p, &q, &x, drop), Sign::Zero);
            if !float {
                let (p, q) = (Point::Explicit(e[2]), Point::Explicit(e[3]));
                prop_assert_eq!(orient2d_projected(&p, &q, &x, drop), Sign::Zero);
            }
            let mut pts = vec![x.clone(), Point::Explicit(e[0]), Point::Explicit(e[3])];
            let kk = drop.index();
            let mut g = e[2];
            g[kk] = if g[kk] == 0.0 { 1.0 } else { g[kk] * 0.5 };
            if let Some(l) = Point::lpi(e[0], e[1], e[2], e[3], g) {
                prop_assert!(same_point(&x, &l));
                pts.push(l);
            }
            pts.push(Point::Explicit(e[1]));
            pts.push(Point::Explicit(a));
            check_all(&pts);
        }
    }
}

/// An input vertex's three coordinates and the tag: points are moved through every stage, so
/// their size is watched (an intersection point's definition stays behind its `Arc`).
#[test]
fn points_stay_small() {
    assert!(std::mem::size_of::<Point>() <= 32);
}

/// The oracle agrees with construction on random small-integer definitions at every scale.
#[test]
fn existence_matches_oracle() {
    let mut runner = proptest::test_runner::TestRunner::new(config(500, 0x6b65_726e_656c_0005));
    let strat = (
        prop::collection::vec(-2i32..=2, 27),
        0usize..POW2_SCALES.len(),
    );
    runner
        .run(&strat, |(v, k)| {
            let s = pow2(POW2_SCALES[k]);
            let c: Vec<f64> = v.iter().map(|&x| f64::from(x) * s).collect();
            let p = |i: usize| [c[3 * i], c[3 * i + 1], c[3 * i + 2]];
            let tri = [p(2), p(3), p(4)];
            prop_assert_eq!(
                Point::lpi(p(0), p(1), p(2), p(3), p(4)).is_some(),
                oracle_lpi(&p(0), &p(1), &tri).is_some()
            );
            let planes = [[p(0), p(1), p(2)], [p(3), p(4), p(5)], [p(6), p(7), p(8)]];
            prop_assert_eq!(Point::tpi(planes).is_some(), oracle_tpi(&planes).is_some());
            Ok(())
        })
        .expect("construction agrees with the oracle");
}

/// Replays `fixtures/implicit.txt`, naming the line of any failure.
#[test]
fn fixtures_replay() {
    let text = include_str!("fixtures/implicit.txt");
    let mut n = 0;
    for (lineno, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (got, want) = run_fixture_line(line)
            .unwrap_or_else(|e| panic!("fixtures/implicit.txt:{}: {e}: {line}", lineno + 1));
        assert_eq!(got, want, "fixtures/implicit.txt:{}: {line}", lineno + 1);
        n += 1;
    }
    assert!(n >= 20, "the fixture file has {n} cases");
}

/// Parses one fixture line: `PRED POINT... = EXPECTED`, a point being `E x y z`,
/// `L` and 15 numbers (p q r s t) or `T` and 27 numbers (three triangles). Returns
/// (kernel answer, expected answer) as -1, 0, 1.
fn run_fixture_line(line: &str) -> Result<(i32, i32), String> {
    let (lhs, rhs) = line.split_once('=').ok_or("no '='")?;
    let want: i32 = rhs
        .trim()
        .parse()
        .map_err(|e| format!("expected value: {e}"))?;
    let mut tok = lhs.split_whitespace();
    let pred = tok.next().ok_or("empty")?;
    let mut pts = Vec::new();
    while let Some(kind) = tok.next() {
        let count = match kind {
            "E" => 3,
            "L" => 15,
            "T" => 27,
            k => return Err(format!("unknown point kind {k}")),
        };
        let mut v = Vec::with_capacity(count);
        for _ in 0..count {
            let x: f64 = tok
                .next()
                .ok_or("too few numbers")?
                .parse()
                .map_err(|e| format!("number: {e}"))?;
            v.push(x);
        }
        let p = |i: usize| [v[3 * i], v[3 * i + 1], v[3 * i + 2]];
        pts.push(match kind {
            "E" => Point::Explicit(p(0)),
            "L" => Point::lpi(p(0), p(1), p(2), p(3), p(4)).ok_or("no such LPI")?,
            _ => Point::tpi([[p(0), p(1), p(2)], [p(3), p(4), p(5)], [p(6), p(7), p(8)]])
                .ok_or("no such TPI")?,
        });
    }
    let sign = |s: Sign| match s {
        Sign::Negative => -1,
        Sign::Zero => 0,
        Sign::Positive => 1,
    };
    let ord = |o: Ordering| o as i32;
    let need = |k: usize| {
        if pts.len() == k {
            Ok(())
        } else {
            Err(format!("{pred} takes {k} points, got {}", pts.len()))
        }
    };
    let got = match pred {
        "o3d" => {
            need(4)?;
            sign(orient3d_points(&pts[0], &pts[1], &pts[2], &pts[3]))
        }
        "o2d_x" | "o2d_y" | "o2d_z" => {
            need(3)?;
            let axis = AXES[usize::from(pred.as_bytes()[4] - b'x')];
            sign(orient2d_projected(&pts[0], &pts[1], &pts[2], axis))
        }
        "cmp_x" | "cmp_y" | "cmp_z" => {
            need(2)?;
            let axis = AXES[usize::from(pred.as_bytes()[4] - b'x')];
            ord(compare_along(&pts[0], &pts[1], axis))
        }
        "lex" => {
            need(2)?;
            ord(compare_lex(&pts[0], &pts[1]))
        }
        p => return Err(format!("unknown predicate {p}")),
    };
    // Every fixture is also checked against the oracle, so a wrong expected value in the
    // file cannot hide a wrong kernel.
    let qs: Vec<Q3> = pts.iter().map(oracle_point).collect();
    let oracle = match pred {
        "o3d" => sign(oracle_orient3d(&qs[0], &qs[1], &qs[2], &qs[3])),
        "o2d_x" | "o2d_y" | "o2d_z" => {
            let axis = AXES[usize::from(pred.as_bytes()[4] - b'x')];
            sign(oracle_orient2d(&qs[0], &qs[1], &qs[2], axis))
        }
        "cmp_x" | "cmp_y" | "cmp_z" => {
            let i = usize::from(pred.as_bytes()[4] - b'x');
            ord(qs[0][i].cmp(&qs[1][i]))
        }
        _ => ord(qs[0].cmp(&qs[1])),
    };
    if oracle != want {
        return Err(format!("the oracle says {oracle}, the file {want}"));
    }
    Ok((got, want))
}

/// Big-integer conversion keeps tiny and huge inputs exact (a sanity check of the oracle's
/// counterpart inside the kernel).
#[test]
fn big_integer_stage_handles_the_full_range() {
    let h = f64::MAX;
    let t = f64::from_bits(1);
    let a = Point::Explicit([t, 0.0, 0.0]);
    let b = Point::Explicit([h, 0.0, 0.0]);
    let f = AxisDiff {
        a: &a,
        b: &b,
        axis: 0,
    };
    assert_eq!(stages(&f)[4], Some(Sign::Negative));
    let big = BigInt::from(1) << 2000;
    assert!(big > BigInt::from(0));
}

/// A crossing of an edge that lies in a tilted plane is on that plane, as the oracle says:
/// `orient3d_plane` proves the zero from the edge's ends when the filter cannot.
#[test]
fn a_crossing_of_an_edge_in_a_plane_is_on_it() {
    // The plane z = x + 2 y, and an edge in it crossing a tilted plane.
    let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 1.0, 2.0]);
    let (p, q) = ([0.125, 0.375, 0.875], [1.5, -0.25, 1.0]);
    let (r, s, t) = ([0.7, -5.0, -5.0], [0.7, 5.0, -5.0], [0.71, 0.0, 5.0]);
    let x = Point::lpi(p, q, r, s, t).expect("the edge crosses the plane");
    let want = oracle_orient3d(&q3(&a), &q3(&b), &q3(&c), &oracle_point(&x));
    assert_eq!(want, Sign::Zero);
    assert_eq!(orient3d_plane(a, b, c, &x), Sign::Zero);
    // Off the plane by the last bit of one end: no longer zero, and the sign is the oracle's.
    let q_off = [1.5, -0.25, f64::from_bits(1.0f64.to_bits() + 1)];
    let y = Point::lpi(p, q_off, r, s, t).expect("the edge crosses the plane");
    let want = oracle_orient3d(&q3(&a), &q3(&b), &q3(&c), &oracle_point(&y));
    assert_ne!(want, Sign::Zero);
    assert_eq!(orient3d_plane(a, b, c, &y), want);
}

#[test]
fn f32_rounding_of_an_f64_breaks_ties_by_the_exact_side() {
    use super::Precision;
    let single = Precision::F32;
    use super::interval::{next_down_f32, next_up_f32};
    let (low, high) = (1.0f32, next_up_f32(1.0));
    // An f64 halfway between two f32 numbers: the nearest f64 to exact values on either side.
    let midpoint = (f64::from(low) + f64::from(high)) / 2.0;
    assert_eq!(single.nearest(midpoint, Sign::Positive), f64::from(high));
    assert_eq!(single.nearest(midpoint, Sign::Negative), f64::from(low));
    assert_eq!(
        single.nearest(midpoint, Sign::Zero),
        f64::from(low),
        "ties to even"
    );
    assert_eq!(single.nearest(-midpoint, Sign::Negative), -f64::from(high));
    // Off the midpoint, the side does not matter; in f64, nothing moves.
    let above = super::interval::step_by(midpoint, 1);
    assert_eq!(single.nearest(above, Sign::Negative), f64::from(high));
    assert_eq!(Precision::F64.nearest(above, Sign::Negative), above);
    assert_eq!(single.step_by(1.0, 2), f64::from(next_up_f32(high)));
    assert_eq!(single.step_by(1.0, -1), f64::from(next_down_f32(1.0)));
    assert_eq!(next_up_f32(-0.0), f32::from_bits(1));
    assert_eq!(next_down_f32(f32::from_bits(1)), 0.0);
    assert_eq!(
        next_up_f32(-f32::MIN_POSITIVE),
        -f32::from_bits(0x007f_ffff)
    );
    assert!(single.is_subnormal(f64::from(f32::MIN_POSITIVE) / 2.0));
    assert!(!Precision::F64.is_subnormal(f64::from(f32::MIN_POSITIVE) / 2.0));
    assert!(single.holds(0.5) && !single.holds(0.1) && Precision::F64.holds(0.1));
}
