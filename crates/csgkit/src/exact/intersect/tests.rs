//! Property tests of [`intersect_triangles`] against a brute-force rational oracle: clip
//! triangle `a` by the plane of `b` and by the three side planes of `b`'s edges in exact
//! rational arithmetic, and compare the kind of the result and its points.

use num_traits::{Signed, Zero};
use proptest::prelude::*;

use super::*;
use crate::kernel::oracle::{Q, Q3, oracle_point, q3, qcross, qdot, qnormal, qsub};

/// Sutherland–Hodgman: the part of `poly` where `g >= 0`.
fn clip(poly: &[Q3], g: &dyn Fn(&Q3) -> Q) -> Vec<Q3> {
    let mut out = Vec::new();
    for k in 0..poly.len() {
        let (p, r) = (&poly[k], &poly[(k + 1) % poly.len()]);
        let (gp, gr) = (g(p), g(r));
        if !gp.is_negative() {
            out.push(p.clone());
        }
        if (gp.is_positive() && gr.is_negative()) || (gp.is_negative() && gr.is_positive()) {
            let t = &gp / (&gp - &gr);
            out.push([0, 1, 2].map(|i| &p[i] + (&r[i] - &p[i]) * &t));
        }
    }
    out
}

#[derive(Debug, PartialEq)]
enum Kind {
    Disjoint,
    Point,
    Touching,
    Crossing,
    Overlap,
}

/// The oracle: the kind and the distinct corner points of `a ∩ b`.
fn oracle(a: &[Point3; 3], b: &[Point3; 3]) -> (Kind, Vec<Q3>) {
    let (ta, tb) = (a.each_ref().map(q3), b.each_ref().map(q3));
    let (na, nb) = (qnormal(&ta), qnormal(&tb));
    let side = |n: &Q3, o: &Q3, x: &Q3| qdot(n, &qsub(x, o));
    let sa: Vec<Q> = ta.iter().map(|x| side(&nb, &tb[0], x)).collect();
    let sb: Vec<Q> = tb.iter().map(|x| side(&na, &ta[0], x)).collect();
    let coplanar = sa.iter().all(Zero::is_zero);
    let mut poly = ta.to_vec();
    if !coplanar {
        poly = clip(&poly, &|x| side(&nb, &tb[0], x));
        poly = clip(&poly, &|x| -side(&nb, &tb[0], x));
    }
    for j in 0..3 {
        let m = qcross(&nb, &qsub(&tb[(j + 1) % 3], &tb[j]));
        let o = tb[j].clone();
        let flip = side(&m, &o, &tb[(j + 2) % 3]).is_negative();
        poly = clip(&poly, &|x| {
            if flip {
                -side(&m, &o, x)
            } else {
                side(&m, &o, x)
            }
        });
    }
    let mut points: Vec<Q3> = Vec::new();
    for p in poly {
        if !points.contains(&p) {
            points.push(p);
        }
    }
    let straddle = |s: &[Q]| s.iter().any(Signed::is_positive) && s.iter().any(Signed::is_negative);
    let kind = match points.len() {
        0 => Kind::Disjoint,
        1 => Kind::Point,
        2 if straddle(&sa) && straddle(&sb) => Kind::Crossing,
        2 => Kind::Touching,
        _ => Kind::Overlap,
    };
    (kind, points)
}

fn kind_and_points(r: &Intersection) -> (Kind, Vec<&Contact>) {
    match r {
        Intersection::Disjoint => (Kind::Disjoint, vec![]),
        Intersection::TouchingPoint(c) => (Kind::Point, vec![c]),
        Intersection::TouchingSegment([c, d]) => (Kind::Touching, vec![c, d]),
        Intersection::Crossing([c, d]) => (Kind::Crossing, vec![c, d]),
        Intersection::CoplanarOverlap(cs) => (Kind::Overlap, cs.iter().collect()),
    }
}

/// The exact feature of a point of the plane of triangle `t` (`None` outside).
fn rational_feature(x: &Q3, t: &[Q3; 3]) -> Option<Feature> {
    let n = qnormal(t);
    let s: Vec<Q> = (0..3)
        .map(|i| qdot(&n, &qcross(&qsub(&t[(i + 1) % 3], &t[i]), &qsub(x, &t[i]))))
        .collect();
    if s.iter().any(Signed::is_negative) {
        return None;
    }
    match (s[0].is_zero(), s[1].is_zero(), s[2].is_zero()) {
        (true, true, _) => Some(Feature::Vertex(1)),
        (_, true, true) => Some(Feature::Vertex(2)),
        (true, _, true) => Some(Feature::Vertex(0)),
        (true, _, _) => Some(Feature::Edge(0)),
        (_, true, _) => Some(Feature::Edge(1)),
        (_, _, true) => Some(Feature::Edge(2)),
        _ => Some(Feature::Face),
    }
}

/// Checks `intersect_triangles` against the oracle, both ways round.
fn check(a: [Point3; 3], b: [Point3; 3], ids_b: [u32; 3]) -> Result<(), TestCaseError> {
    let (Some(ta), Some(tb)) = (Triangle::new(0, [0, 1, 2], a), Triangle::new(1, ids_b, b)) else {
        return Ok(());
    };
    for (x, y, pa, pb) in [(&ta, &tb, a, b), (&tb, &ta, b, a)] {
        let (kind, expected) = oracle(&pa, &pb);
        let result = intersect_triangles(x, y);
        let (got_kind, contacts) = kind_and_points(&result);
        prop_assert_eq!(&got_kind, &kind, "{:?} {:?} -> {:?}", pa, pb, result);
        prop_assert_eq!(
            contacts.len(),
            expected.len(),
            "{:?} {:?} -> {:?}",
            pa,
            pb,
            result
        );
        for c in contacts {
            let p = oracle_point(&c.point);
            prop_assert!(
                expected.contains(&p),
                "{:?} {:?}: point {:?} not in oracle",
                pa,
                pb,
                c
            );
            prop_assert_eq!(Some(c.on_a), rational_feature(&p, &pa.each_ref().map(q3)));
            prop_assert_eq!(Some(c.on_b), rational_feature(&p, &pb.each_ref().map(q3)));
        }
    }
    Ok(())
}

fn small() -> impl Strategy<Value = f64> {
    (-3i32..=3).prop_map(f64::from)
}

fn small_point() -> impl Strategy<Value = Point3> {
    [small(), small(), small()]
}

fn flat_point() -> impl Strategy<Value = Point3> {
    [small(), small()].prop_map(|[x, y]| [x, y, 0.0])
}

fn any_point() -> impl Strategy<Value = Point3> {
    [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn random_float_pairs(a in [any_point(), any_point(), any_point()],
                          b in [any_point(), any_point(), any_point()]) {
        check(a, b, [3, 4, 5])?;
    }

    #[test]
    fn small_integer_pairs(a in [small_point(), small_point(), small_point()],
                           b in [small_point(), small_point(), small_point()]) {
        check(a, b, [3, 4, 5])?;
    }

    #[test]
    fn coplanar_pairs(a in [flat_point(), flat_point(), flat_point()],
                      b in [flat_point(), flat_point(), flat_point()]) {
        check(a, b, [3, 4, 5])?;
    }

    #[test]
    fn shared_vertex(a in [small_point(), small_point(), small_point()],
                     b in [small_point(), small_point()]) {
        check(a, [a[0], b[0], b[1]], [0, 4, 5])?;
    }

    #[test]
    fn shared_edge(a in [small_point(), small_point(), small_point()], b in small_point()) {
        check(a, [a[1], a[0], b], [1, 0, 5])?;
    }

    #[test]
    fn coplanar_shared_edge(a in [flat_point(), flat_point(), flat_point()], b in flat_point()) {
        check(a, [a[1], a[0], b], [1, 0, 5])?;
    }

    #[test]
    fn side_is_orient3d(t in [small_point(), small_point(), small_point()],
                        p in small_point(), corner in 0usize..4) {
        // Grid points put many triangles in axis planes and many points on their planes;
        // `corner` < 3 asks about a corner by its id.
        let Some(tri) = Triangle::new(0, [0, 1, 2], t) else { return Ok(()); };
        let (v, p) = if corner < 3 { (corner as u32, t[corner]) } else { (3, p) };
        prop_assert_eq!(tri.side(v, p), orient3d(t[0], t[1], t[2], p));
    }

    #[test]
    fn vertex_on_edge_or_face(a in [small_point(), small_point(), small_point()],
                              b in [small_point(), small_point()],
                              w in [0u8..=2, 0u8..=2, 0u8..=2]) {
        // A vertex of `b` at a dyadic combination of `a`'s vertices: on an edge or inside.
        let total = f64::from(w.iter().map(|&x| u32::from(x)).sum::<u32>().max(1));
        let v: Point3 = [0, 1, 2].map(|k| {
            (0..3).map(|i| a[i][k] * f64::from(w[i])).sum::<f64>() / total
        });
        check(a, [v, b[0], b[1]], [3, 4, 5])?;
    }

    #[test]
    fn edges_crossing(a in [small_point(), small_point(), small_point()],
                      b in small_point(), t in 0u8..=4) {
        // `b` has an edge through the midpoint of an edge of `a`.
        let m: Point3 = [0, 1, 2].map(|k| (a[0][k] + a[1][k]) * 0.5);
        let f = f64::from(t) - 2.0;
        let e: Point3 = [0, 1, 2].map(|k| m[k] + (m[k] - b[k]) * f);
        check(a, [b, e, [b[1], b[2], b[0]]], [3, 4, 5])?;
    }
}

#[test]
fn named_cases() {
    let a = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
    let t = |p: [Point3; 3], ids| Triangle::new(1, ids, p).expect("non-degenerate");
    let ta = t(a, [0, 1, 2]);
    // Crossing: a vertical triangle through the inside of `a`.
    let b = [[1.0, 1.0, -1.0], [1.0, 1.0, 1.0], [2.0, 1.0, 1.0]];
    assert!(matches!(
        intersect_triangles(&ta, &t(b, [3, 4, 5])),
        Intersection::Crossing(_)
    ));
    // Shared vertex only.
    let b = [[0.0, 0.0, 0.0], [-1.0, 0.0, 1.0], [0.0, -1.0, 1.0]];
    match intersect_triangles(&ta, &t(b, [0, 4, 5])) {
        Intersection::TouchingPoint(c) => assert_eq!(c.key, PointKey::Vertex(0)),
        other => panic!("{other:?}"),
    }
    // Coplanar overlap: a square's worth of corners.
    let b = [[1.0, -1.0, 0.0], [1.0, 3.0, 0.0], [-3.0, 3.0, 0.0]];
    match intersect_triangles(&ta, &t(b, [3, 4, 5])) {
        Intersection::CoplanarOverlap(cs) => assert!(cs.len() >= 3),
        other => panic!("{other:?}"),
    }
    // Degenerate triangles are refused.
    assert!(Triangle::new(0, [0, 1, 2], [[0.0; 3], [1.0; 3], [2.0; 3]]).is_none());
}

#[test]
fn orientation_test_separates_chords_without_intersection_points() {
    let a = Triangle::new(
        0,
        [0, 1, 2],
        [[5.0, 0.5, -1.0], [5.0, 0.5, 1.0], [6.0, 0.6, 1.0]],
    );
    let b = Triangle::new(
        1,
        [3, 4, 5],
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    );
    let (a, b) = (a.expect("non-degenerate"), b.expect("non-degenerate"));
    let (sa, sb) = (plane_signs(&a, &b), plane_signs(&b, &a));
    assert!(straddles(&sa) && straddles(&sb) && !sa.contains(&Sign::Zero));
    assert!(separated(&a, &b, &sa, &sb));
    assert!(separated(&b, &a, &sb, &sa));
    // Crossing triangles are not separated.
    let c = Triangle::new(
        2,
        [6, 7, 8],
        [[0.2, 0.2, -1.0], [0.2, 0.3, 1.0], [0.4, 0.2, 1.0]],
    );
    let c = c.expect("non-degenerate");
    let (sc, sbc) = (plane_signs(&c, &b), plane_signs(&b, &c));
    assert!(!separated(&c, &b, &sc, &sbc));
}
