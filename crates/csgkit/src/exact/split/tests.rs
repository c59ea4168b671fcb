//! Tests of the split stage against an exact rational oracle.
//!
//! Every test triangle is `A, B, C` in space and every point is given by exact rational
//! parameters `(s, t)` with `P = A + s (B - A) + t (C - A)`; in the `(s, t)` frame the corners
//! are `(0, 0), (1, 0), (0, 1)` and "counterclockwise" means "oriented like the input". The
//! oracle checks the output there: positive triangles whose areas sum to 1/2, every directed
//! edge once, unpaired edges on the boundary, no vertex inside an edge (no T-junction), every
//! distinct point used, merged points equal to their kept vertex, every segment a chain of
//! output edges. Random inputs use fixed seeds.

use crate::kernel::tests::config;
use num_rational::Ratio;
use proptest::prelude::*;

use super::*;

type Q = Ratio<i128>;

fn q(n: i128, d: i128) -> Q {
    Q::new(n, d)
}

/// Twice the signed area of `a, b, c` in the `(s, t)` frame.
fn area2(a: [Q; 2], b: [Q; 2], c: [Q; 2]) -> Q {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// True when `p` lies on the closed segment `a b` (with `a != b`).
fn on_segment(a: [Q; 2], b: [Q; 2], p: [Q; 2]) -> bool {
    let zero = Q::from(0);
    area2(a, b, p) == zero
        && (p[0] - a[0]) * (p[0] - b[0]) <= zero
        && (p[1] - a[1]) * (p[1] - b[1]) <= zero
}

/// True when the open segments `a b` and `c d` cross at one point interior to both.
fn cross_properly(a: [Q; 2], b: [Q; 2], c: [Q; 2], d: [Q; 2]) -> bool {
    let zero = Q::from(0);
    area2(a, b, c) * area2(a, b, d) < zero && area2(c, d, a) * area2(c, d, b) < zero
}

/// A test input: corners, points, and the oracle's `(s, t)` of every vertex id.
struct Case {
    corners: [Point3; 3],
    points: Vec<Point>,
    st: Vec<[Q; 2]>,
}

impl Case {
    /// The triangle `A, B, C`; explicit grid points need `A, B, C` multiples of their `d`.
    fn new(corners: [Point3; 3]) -> Case {
        let (z, o) = (q(0, 1), q(1, 1));
        Case {
            corners,
            points: Vec::new(),
            st: vec![[z, z], [o, z], [z, o]],
        }
    }

    fn at(&self, st: [Q; 2]) -> Point3 {
        let [a, b, c] = self.corners;
        let f = |x: Q| *x.numer() as f64 / *x.denom() as f64;
        let (s, t) = (f(st[0]), f(st[1]));
        std::array::from_fn(|k| a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]))
    }

    /// Adds the explicit point at `(i / d, j / d)`; returns its vertex id.
    fn grid(&mut self, i: i128, j: i128, d: i128) -> u32 {
        let st = [q(i, d), q(j, d)];
        let p = self.at(st);
        self.points.push(Point::Explicit(p));
        self.st.push(st);
        self.st.len() as u32 - 1
    }

    /// Adds the implicit point where the line through `x1 + al m` and `x2 - be m` meets the
    /// plane: `x1 + al / (al + be) (x2 - x1)`.
    fn lpi(&mut self, x1: [Q; 2], x2: [Q; 2], m: Point3, al: i128, be: i128) -> u32 {
        let (p1, p2) = (self.at(x1), self.at(x2));
        let (alf, bef) = (al as f64, be as f64);
        let p: Point3 = std::array::from_fn(|k| p1[k] + alf * m[k]);
        let r: Point3 = std::array::from_fn(|k| p2[k] - bef * m[k]);
        let [a, b, c] = self.corners;
        let pt = Point::lpi(p, r, a, b, c).expect("the line crosses the plane");
        let lam = q(al, al + be);
        self.points.push(pt);
        self.st.push([0, 1].map(|k| x1[k] + lam * (x2[k] - x1[k])));
        self.st.len() as u32 - 1
    }

    /// Splits, checks the Cdt's invariants and the output against the oracle.
    fn check(&self, segs: &[[u32; 2]]) -> Result<Split, SplitError> {
        let cdt = Cdt::build(self.corners, &self.points, segs)?;
        cdt.check_invariants().unwrap();
        let tris: Vec<[u32; 3]> = cdt.triangles().collect();
        let split = split_triangle(self.corners, &self.points, segs)?;
        assert_eq!(split.triangles, tris);
        self.check_output(&split, segs);
        Ok(split)
    }

    fn check_output(&self, split: &Split, segs: &[[u32; 2]]) {
        let st = |v: u32| self.st[v as usize];
        let n = self.st.len();
        let mut kept: Vec<u32> = (0..n as u32).collect();
        for &[m, k] in &split.merged {
            assert_eq!(st(m), st(k), "merged {m} into {k} at another place");
            kept[m as usize] = k;
        }
        for (i, &k) in kept.iter().enumerate() {
            let first = (0..i).find(|&j| self.st[j] == self.st[i]);
            assert_eq!(first.is_some(), k != i as u32, "point {i} merged wrongly");
        }
        let mut total = q(0, 1);
        let mut edges = std::collections::HashSet::new();
        let mut used = vec![false; n];
        for t in &split.triangles {
            let a = area2(st(t[0]), st(t[1]), st(t[2]));
            assert!(a > q(0, 1), "triangle {t:?} not positive");
            total += a;
            for i in 0..3 {
                used[t[i] as usize] = true;
                assert!(edges.insert((t[i], t[(i + 1) % 3])), "edge twice in {t:?}");
            }
        }
        assert_eq!(total, q(1, 1), "the areas do not add up to the triangle's");
        for (i, (&u, &k)) in used.iter().zip(&kept).enumerate() {
            assert_eq!(u, k == i as u32, "vertex {i} used wrongly");
        }
        let on_boundary = |p: [Q; 2]| [p[0], p[1], q(1, 1) - p[0] - p[1]];
        for &(a, b) in &edges {
            if !edges.contains(&(b, a)) {
                let (pa, pb) = (on_boundary(st(a)), on_boundary(st(b)));
                let zero = q(0, 1);
                assert!(
                    (0..3).any(|k| pa[k] == zero && pb[k] == zero),
                    "unpaired edge {a} {b} inside"
                );
            }
            for v in (0..n as u32).filter(|&v| used[v as usize] && v != a && v != b) {
                assert!(
                    !on_segment(st(a), st(b), st(v)),
                    "vertex {v} on edge {a} {b}"
                );
            }
        }
        for &[a, b] in segs {
            let (a, b) = (kept[a as usize], kept[b as usize]);
            if a == b {
                continue;
            }
            let mut on: Vec<u32> = (0..n as u32)
                .filter(|&v| used[v as usize] && on_segment(st(a), st(b), st(v)))
                .collect();
            let dist = |v: u32| {
                let d = [0, 1].map(|k| st(v)[k] - st(a)[k]);
                d[0] * d[0] + d[1] * d[1]
            };
            on.sort_by_key(|&v| dist(v));
            for w in on.windows(2) {
                let covered = edges.contains(&(w[0], w[1])) || edges.contains(&(w[1], w[0]));
                assert!(covered, "segment {a} {b} lacks edge {} {}", w[0], w[1]);
            }
        }
    }
}

/// A tilted triangle whose corners are multiples of 8, oriented so that the projection
/// along the largest normal component flips orientations.
fn tilted() -> Case {
    Case::new([[0.0, 0.0, 0.0], [8.0, 0.0, 16.0], [-8.0, 16.0, 8.0]])
}

fn flat() -> Case {
    Case::new([[0.0, 0.0, 1.0], [8.0, 0.0, 1.0], [0.0, 8.0, 1.0]])
}

#[test]
fn no_points() {
    for case in [tilted(), flat()] {
        let split = case.check(&[]).unwrap();
        assert_eq!(split.triangles, vec![[0, 1, 2]]);
    }
}

#[test]
fn point_on_an_edge() {
    let mut case = tilted();
    case.grid(4, 4, 8);
    assert_eq!(case.check(&[]).unwrap().triangles.len(), 2);
}

#[test]
fn collinear_points_on_an_edge() {
    let mut case = flat();
    for i in [5, 1, 3, 2] {
        case.grid(i, 0, 8);
    }
    case.grid(0, 3, 8);
    assert_eq!(case.check(&[]).unwrap().triangles.len(), 6);
}

#[test]
fn interior_points() {
    let mut case = tilted();
    case.grid(1, 1, 8);
    assert_eq!(case.check(&[]).unwrap().triangles.len(), 3);
    case.grid(2, 2, 8);
    case.grid(3, 3, 8);
    case.grid(2, 1, 8);
    assert_eq!(case.check(&[]).unwrap().triangles.len(), 9);
}

#[test]
fn duplicates_merge() {
    let mut case = flat();
    let a = case.grid(1, 1, 8);
    case.grid(8, 0, 8);
    let c = case.grid(1, 1, 8);
    let s = case.check(&[[a, 0], [c, 1]]).unwrap();
    assert_eq!(s.merged, vec![[4, 1], [5, 3]]);
}

#[test]
fn segment_edge_to_edge() {
    let mut case = tilted();
    let a = case.grid(4, 0, 8);
    let b = case.grid(0, 4, 8);
    case.grid(1, 5, 8);
    case.grid(2, 1, 8);
    case.grid(1, 2, 8);
    case.check(&[[a, b]]).unwrap();
}

#[test]
fn segment_through_existing_vertices() {
    let mut case = flat();
    let a = case.grid(0, 3, 8);
    case.grid(2, 3, 8);
    case.grid(4, 3, 8);
    let m = case.grid(3, 3, 8);
    let b = case.grid(5, 3, 8);
    let c = case.grid(1, 1, 8);
    case.grid(2, 5, 8);
    let d = case.grid(4, 4, 8);
    // Along y = 3 through three points, then the hypotenuse through `b` and `d`.
    case.check(&[[a, b], [2, 1]]).unwrap();
    // Through `m`, where it touches the first segment.
    case.check(&[[a, b], [c, d]]).unwrap();
    case.check(&[[d, c], [m, 0], [b, a]]).unwrap();
}

#[test]
fn chain_of_segments() {
    let mut case = tilted();
    let ids: Vec<u32> = [(1, 1), (5, 1), (2, 4), (1, 3), (2, 2), (3, 2)]
        .iter()
        .map(|&(i, j)| case.grid(i, j, 8))
        .collect();
    let chain: Vec<[u32; 2]> = ids.windows(2).map(|w| [w[0], w[1]]).collect();
    case.check(&chain).unwrap();
}

#[test]
fn segment_along_an_edge() {
    let mut case = flat();
    let a = case.grid(2, 0, 8);
    let b = case.grid(6, 0, 8);
    case.grid(4, 0, 8);
    case.grid(3, 3, 8);
    case.check(&[[a, b], [0, 1], [2, 1]]).unwrap();
}

#[test]
fn implicit_points_and_segments() {
    let mut case = tilted();
    let g = |i, j| [q(i, 8), q(j, 8)];
    let a = case.lpi(g(0, 1), g(5, 2), [1.0, -2.0, 3.0], 1, 2);
    let b = case.lpi(g(7, 0), g(0, 7), [0.0, 0.0, 1.0], 2, 3);
    let c = case.lpi(g(1, 1), g(3, 3), [1.0, 1.0, -1.0], 1, 1);
    case.grid(2, 2, 8);
    case.check(&[[a, b], [b, c], [c, 0]]).unwrap();
}

#[test]
fn crossing_segments_are_an_error() {
    let mut case = flat();
    let a = case.grid(2, 0, 8);
    let b = case.grid(2, 4, 8);
    let c = case.grid(0, 2, 8);
    let d = case.grid(4, 2, 8);
    let e = case.check(&[[a, b], [c, d]]).unwrap_err();
    assert_eq!(
        e,
        SplitError::ConstraintsCross {
            first: 0,
            second: 1
        }
    );
    // Through a point, the same segments are fine.
    case.grid(2, 2, 8);
    case.check(&[[a, b], [c, d]]).unwrap();
}

#[test]
fn bad_inputs() {
    let mut case = flat();
    case.grid(9, 0, 8);
    assert_eq!(case.check(&[]), Err(SplitError::PointOutside { point: 3 }));
    assert_eq!(
        case.check(&[[0, 7]]),
        Err(SplitError::SegmentOutOfRange { segment: 0 })
    );
    let line = Case::new([[0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]);
    assert_eq!(line.check(&[]), Err(SplitError::DegenerateTriangle));
}

/// Corners: multiples of `D` in a small box, not collinear.
const D: i128 = 8;

fn corners() -> impl Strategy<Value = [Point3; 3]> {
    prop::array::uniform9(-3i32..=3).prop_filter_map("collinear", |c| {
        let p = |k: usize| [0, 1, 2].map(|i| f64::from(c[3 * k + i]) * D as f64);
        let pts = [p(0), p(1), p(2)];
        Projection::new(&pts.map(Point::Explicit)).map(|_| pts)
    })
}

/// A grid point `(i, j) / d` in the closed triangle, from two random numbers.
fn grid_st(i: i128, j: i128, d: i128) -> (i128, i128) {
    let i = i.rem_euclid(d + 1);
    (i, j.rem_euclid(d + 1 - i))
}

/// Raw numbers for one LPI point: two grid points, a direction tweak, the weights.
type RawLpi = (i128, i128, i128, i128, (usize, i8), (i128, i128));

/// Builds a case from raw random numbers: grid points `(i, j) / d`, then LPI points between
/// grid points. `d` is a power of two, so every grid point is exact in f64.
fn random_case(c: [Point3; 3], d: i128, grid: &[(i128, i128)], lpis: &[RawLpi]) -> Case {
    let mut case = Case::new(c);
    for &(i, j) in grid {
        let (i, j) = grid_st(i, j, d);
        case.grid(i, j, d);
    }
    let [a, b, cc] = c;
    let (u, v) = (sub(b, a), sub(cc, a));
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    for &(i1, j1, i2, j2, (k, r), (al, be)) in lpis {
        let ((i1, j1), (i2, j2)) = (grid_st(i1, j1, d), grid_st(i2, j2, d));
        let g = |i, j| [q(i, d), q(j, d)];
        // `m = n + r e_k` with `|r| <= 2`: `n · m = |n|^2 + r n_k > 0`, since the components
        // of `n` are multiples of 64. So the two ends are on opposite sides of the plane.
        let mut m = n;
        m[k] += f64::from(r);
        case.lpi(g(i1, j1), g(i2, j2), m, al, be);
    }
    case
}

fn raw_lpi() -> impl Strategy<Value = RawLpi> {
    (
        0i128..100,
        0i128..100,
        0i128..100,
        0i128..100,
        (0usize..3, -2i8..=2),
        (1i128..4, 1i128..4),
    )
}

/// Greedily keeps the random segments that properly cross no kept one.
fn non_crossing(case: &Case, raw: &[(u32, u32)]) -> Vec<[u32; 2]> {
    let n = case.st.len() as u32;
    let mut kept: Vec<[u32; 2]> = Vec::new();
    for &(a, b) in raw {
        let (a, b) = (a % n, b % n);
        let st = |v: u32| case.st[v as usize];
        if kept
            .iter()
            .all(|s| !cross_properly(st(a), st(b), st(s[0]), st(s[1])))
        {
            kept.push([a, b]);
        }
    }
    kept
}

proptest! {
    #![proptest_config(config(1500, 0x7370_6c69_7400_0001))]

    #[test]
    fn random_grid_points_and_segments(
        c in corners(),
        grid in prop::collection::vec((0i128..100, 0i128..100), 0..12),
        raw in prop::collection::vec((0u32..100, 0u32..100), 0..10),
    ) {
        let case = random_case(c, D, &grid, &[]);
        let segs = non_crossing(&case, &raw);
        case.check(&segs).unwrap();
    }

    #[test]
    fn random_implicit_points_and_segments(
        c in corners(),
        grid in prop::collection::vec((0i128..100, 0i128..100), 0..5),
        lpis in prop::collection::vec(raw_lpi(), 0..6),
        raw in prop::collection::vec((0u32..100, 0u32..100), 0..8),
    ) {
        let case = random_case(c, D, &grid, &lpis);
        let segs = non_crossing(&case, &raw);
        case.check(&segs).unwrap();
    }

    /// Unfiltered segments: either a valid split, or a crossing that the oracle confirms.
    #[test]
    fn random_crossing_segments(
        c in corners(),
        grid in prop::collection::vec((0i128..100, 0i128..100), 0..10),
        raw in prop::collection::vec((0u32..100, 0u32..100), 0..8),
    ) {
        let case = random_case(c, D, &grid, &[]);
        let n = case.st.len() as u32;
        let segs: Vec<[u32; 2]> = raw.iter().map(|&(a, b)| [a % n, b % n]).collect();
        match case.check(&segs) {
            Ok(_) => {}
            Err(SplitError::ConstraintsCross { first, second }) => {
                let st = |v: u32| case.st[v as usize];
                let (s, t) = (segs[first], segs[second]);
                prop_assert!(cross_properly(st(s[0]), st(s[1]), st(t[0]), st(t[1])));
            }
            Err(e) => prop_assert!(false, "unexpected {e}"),
        }
    }
}

proptest! {
    #![proptest_config(config(150, 0x7370_6c69_7400_0002))]

    /// Many points on a finer grid: long walks, long segment corridors, big pseudo-polygons.
    #[test]
    fn random_many_points_and_segments(
        c in corners(),
        grid in prop::collection::vec((0i128..1000, 0i128..1000), 20..60),
        lpis in prop::collection::vec(raw_lpi(), 0..8),
        raw in prop::collection::vec((0u32..1000, 0u32..1000), 10..60),
    ) {
        let case = random_case(c, 64, &grid, &lpis);
        let segs = non_crossing(&case, &raw);
        case.check(&segs).unwrap();
    }
}

#[test]
fn projection_flips_when_the_dropped_component_is_negative() {
    let p = |c: [Point3; 3]| Projection::new(&c.map(Point::Explicit)).unwrap();
    let flat = flat().corners;
    assert!(!p(flat).flip);
    assert!(p([flat[0], flat[2], flat[1]]).flip);
    assert_eq!(p(tilted().corners).drop, Axis::X);
    assert!(p(tilted().corners).flip);
}

/// A triangle cut by both triangles of a planar quad: the crossings of the quad's two sides
/// and its diagonal lie on one line, proven by the plane through their lines (no point is
/// defined on the quad's plane, so the defining planes alone do not show it), and a line
/// moved off that plane is not taken for collinear.
#[test]
fn crossings_of_a_planar_quad_are_collinear_by_its_plane() {
    let own: [Point3; 3] = [[0.0, 0.0, 0.0], [8.0, 0.0, 0.75], [0.0, 8.0, 2.5]];
    let proj = Projection::new(&own.map(Point::Explicit)).unwrap();
    // A parallelogram, so exactly planar, crossing the triangle's plane.
    let (v1, w1) = ([3.0, 0.0, -5.0], [3.25, 0.5, 5.0]);
    let (v2, w2) = ([1.0, 4.0, -5.0], [1.25, 4.5, 5.0]);
    let cut = |p: Point3, q: Point3| Point::lpi(p, q, own[0], own[1], own[2]).unwrap();
    let (a, b, c) = (cut(v1, w1), cut(v2, w1), cut(v2, w2));
    assert!(proj.on_another_plane(&a, &b, &c));
    assert_eq!(proj.orient(&a, &b, &c), Sign::Zero);
    let off = cut(v2, [1.25, 4.75, 5.0]);
    assert!(!proj.on_another_plane(&a, &b, &off));
    assert_ne!(proj.orient(&a, &b, &off), Sign::Zero);
}

/// Two triangles sharing the edge `B C`, both given the same point on it, split it the same
/// way: the boundary edges of one are the reversed boundary edges of the other.
#[test]
fn neighbours_stay_conforming() {
    let (a, b, c, d) = (
        [0.0, 0.0, 0.0],
        [8.0, 0.0, 0.0],
        [0.0, 8.0, 0.0],
        [8.0, 8.0, 3.0],
    );
    let on_bc = [
        Point::Explicit([4.0, 4.0, 0.0]),
        Point::Explicit([2.0, 6.0, 0.0]),
    ];
    let first = split_triangle([a, b, c], &on_bc, &[]).unwrap();
    let second = split_triangle([c, b, d], &[on_bc[1].clone(), on_bc[0].clone()], &[]).unwrap();
    // Global ids: B, C, the two points.
    let g1 = |v: u32| [0, 10, 11, 20, 21][v as usize];
    let g2 = |v: u32| [11, 10, 12, 21, 20][v as usize];
    let on_shared = |x: u32| x == 10 || x == 11 || x >= 20;
    let edges = |s: &Split, g: &dyn Fn(u32) -> u32| {
        let mut e: Vec<(u32, u32)> = s
            .triangles
            .iter()
            .flat_map(|t| (0..3).map(move |i| (g(t[i]), g(t[(i + 1) % 3]))))
            .filter(|&(x, y)| on_shared(x) && on_shared(y))
            .collect();
        e.sort();
        e
    };
    let mut reversed: Vec<(u32, u32)> = edges(&second, &g2).iter().map(|&(x, y)| (y, x)).collect();
    reversed.sort();
    assert_eq!(edges(&first, &g1), reversed);
    assert_eq!(reversed.len(), 3);
}

/// A segment that crosses a fan of 63 edges: a long corridor and two big pseudo-polygons.
#[test]
fn segment_across_a_fan() {
    let mut case = flat();
    for i in 1..64 {
        case.grid(i, 0, 64);
    }
    let a = case.grid(0, 1, 64);
    let b = case.grid(63, 1, 64);
    let split = case.check(&[[a, b]]).unwrap();
    assert_eq!(split.triangles.len(), 2 * 65 - 65 + 1);
}

#[test]
fn in_circle_answers_only_where_certain() {
    let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [1.0, 1.0]);
    // The fourth corner of the square is on the circle: no certain side, no flip.
    assert_eq!(incircle_value_if_clear(a, b, c, [0.0, 1.0]), None);
    assert!(!delaunay_flip([a, b, c, [0.0, 1.0]]));
    // Clearly inside and clearly outside, with `a b c` counterclockwise.
    assert!(incircle_value_if_clear(a, b, c, [0.5, 0.5]).is_some_and(|d| d > 0.0));
    assert!(incircle_value_if_clear(a, b, c, [3.0, 3.0]).is_some_and(|d| d < 0.0));
    // A point an ulp off the circle is within the rounding of the f64 determinant.
    assert_eq!(
        incircle_value_if_clear(a, b, c, [0.0, 1.0f64.next_up()]),
        None
    );
    // Products that underflow prove nothing.
    let tiny = |p: [f64; 2]| p.map(|x| x * 1e-200);
    assert_eq!(
        incircle_value_if_clear(tiny(a), tiny(b), tiny(c), tiny([0.5, 0.5])),
        None
    );
}

#[test]
fn flatness_without_exact_areas_is_the_height_test() {
    // The reference: the height over the longest side from `robust`'s exact-sign area.
    let by_height = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        let limit = FLAT_HEIGHT * magnitude(&[p, q, r]);
        let coord = |p: [f64; 2]| robust::Coord { x: p[0], y: p[1] };
        let twice_area = robust::orient2d(coord(p), coord(q), coord(r)).abs();
        height(twice_area, p, q, r) < limit
    };
    let mut random = crate::kernel::tests::xorshift(0x5eed_f1a7);
    let mut unit = || (random() >> 11) as f64 / (1u64 << 53) as f64;
    let (mut flat, mut total) = (0, 0);
    for _ in 0..20_000 {
        let p = [unit() * 8.0 - 4.0, unit() * 8.0 - 4.0];
        let q = [unit() * 8.0 - 4.0, unit() * 8.0 - 4.0];
        // `r` on the line p q, then moved by a few ulps: flat, nearly flat and clear cases.
        let t = unit() * 3.0 - 1.0;
        let ulps = (unit() * 1024.0) as i32 - 512;
        let mut r = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
        for _ in 0..ulps.unsigned_abs() {
            r[1] = if ulps > 0 {
                r[1].next_up()
            } else {
                r[1].next_down()
            };
        }
        flat += usize::from(is_flat(p, q, r));
        total += 1;
        assert_eq!(is_flat(p, q, r), by_height(p, q, r), "{p:?} {q:?} {r:?}");
        assert_eq!(is_flat(p, q, q), by_height(p, q, q));
    }
    // Both kinds were met.
    assert!(flat > 1000 && flat < total - 1000, "{flat} of {total} flat");
}
