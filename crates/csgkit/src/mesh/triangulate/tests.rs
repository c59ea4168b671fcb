//! Tests of the polygon triangulator against exact rational areas and a brute-force
//! simplicity oracle.
//!
//! The oracle checks a triangulation in the polygon's plane: it has m − 2 triangles for the m
//! corners left after merging consecutive equal ones, each of the polygon's orientation and
//! non-zero area, their areas sum to the shoelace area exactly, and the sides marked as
//! polygon edges are exactly the polygon's directed edges. Random inputs use fixed seeds.

use num_rational::BigRational;
use num_traits::{Signed, Zero};
use proptest::prelude::*;

use super::*;
use crate::kernel::tests::config;

type Q = BigRational;

/// One mesh holding `polygons` over `positions`.
fn mesh(positions: Vec<[f64; 3]>, polygons: &[&[u32]]) -> Mesh {
    Mesh::from_polygons(positions, polygons).expect("valid by construction")
}

/// A mesh of one polygon in the plane z = 0 with corners `0, 1, …`.
fn plane_polygon(points: &[[f64; 2]]) -> Mesh {
    let positions = points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let corners: Vec<u32> = (0..points.len() as u32).collect();
    mesh(positions, &[&corners])
}

/// The L-shaped hexagon of the module example, counter-clockwise.
const L_HEXAGON: [[f64; 2]; 6] = [
    [0.0, 0.0],
    [2.0, 0.0],
    [2.0, 1.0],
    [1.0, 1.0],
    [1.0, 2.0],
    [0.0, 2.0],
];

fn q(x: f64) -> Q {
    Q::from_float(x).expect("finite coordinate")
}

/// Twice the signed area of a triangle.
fn area2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Q {
    (q(b[0]) - q(a[0])) * (q(c[1]) - q(a[1])) - (q(b[1]) - q(a[1])) * (q(c[0]) - q(a[0]))
}

/// Twice the signed shoelace area of a loop.
fn shoelace2(points: &[[f64; 2]]) -> Q {
    let n = points.len();
    (0..n).fold(Q::zero(), |sum, i| {
        let (a, b) = (points[i], points[(i + 1) % n]);
        sum + q(a[0]) * q(b[1]) - q(b[0]) * q(a[1])
    })
}

/// The loop with consecutive equal points merged (as the triangulator does).
fn merged(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = points.len();
    (0..n)
        .filter(|&i| points[i] != points[(i + n - 1) % n])
        .map(|i| points[i])
        .collect()
}

/// Checks the triangulation of the single polygon `points` (corners `0, 1, …` of a mesh in
/// the plane z = 0) against the oracle of the module docs.
fn check(points: &[[f64; 2]], found: &Triangulation<'_>) -> Result<(), TestCaseError> {
    let corners = merged(points);
    let total = shoelace2(&corners);
    prop_assert!(!total.is_zero());
    prop_assert_eq!(found.len(), corners.len() - 2);
    let at = |v: u32| points[v as usize];
    let mut sum = Q::zero();
    let mut marked = Vec::new();
    for t in 0..found.len() {
        prop_assert_eq!(found.face(t), FaceId::new(0));
        let [a, b, c] = found.triangle(t).map(at);
        let area = area2(a, b, c);
        prop_assert!(!area.is_zero(), "degenerate triangle {:?}", [a, b, c]);
        prop_assert_eq!(area.is_positive(), total.is_positive(), "orientation");
        sum += area;
        let ids = found.triangle(t);
        for i in 0..3 {
            if found.edge_mask(t) >> i & 1 == 1 {
                marked.push([at(ids[i]), at(ids[(i + 1) % 3])]);
            }
        }
    }
    prop_assert_eq!(sum, total);
    let n = corners.len();
    let mut edges: Vec<[[f64; 2]; 2]> =
        (0..n).map(|i| [corners[i], corners[(i + 1) % n]]).collect();
    let key = |e: &[[f64; 2]; 2]| [e[0][0], e[0][1], e[1][0], e[1][1]].map(f64::to_bits);
    edges.sort_by_key(key);
    marked.sort_by_key(key);
    prop_assert_eq!(marked, edges, "polygon edges");
    Ok(())
}

/// Triangulates the polygon `points` in the plane z = 0 and checks it.
fn check_polygon(points: &[[f64; 2]]) -> Result<usize, TestCaseError> {
    let mesh = plane_polygon(points);
    let found = triangulate_faces(&mesh).map_err(|e| TestCaseError::fail(e.to_string()))?;
    check(points, &found)?;
    Ok(found.len())
}

#[test]
fn triangles_pass_through_in_place() {
    let positions = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0]];
    // The second triangle is degenerate: it passes through too.
    let mesh = Mesh::from_triangles(positions, &[[0, 1, 2], [0, 1, 3]]).unwrap();
    let found = triangulate_faces(&mesh).unwrap();
    assert!(matches!(found.repr, Repr::Triangles(c) if std::ptr::eq(c, mesh.corners())));
    assert_eq!(found.len(), 2);
    assert_eq!(found.triangle(1), [0, 1, 3]);
    assert_eq!(found.face(1), FaceId::new(1));
    assert_eq!(found.edge_mask(1), Triangulation::ALL_SIDES);
}

#[test]
fn convex_quad_keeps_the_fan_with_its_diagonal_marked() {
    let mesh = plane_polygon(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    let found = triangulate_faces(&mesh).unwrap();
    let all: Vec<_> = found.iter().collect();
    assert_eq!(
        all,
        vec![(FaceId::new(0), [0, 1, 2]), (FaceId::new(0), [0, 2, 3])]
    );
    // Sides 0 1 and 1 2, then 2 3 and 3 0; the diagonal 0 2 is not a polygon edge.
    assert_eq!((found.edge_mask(0), found.edge_mask(1)), (0b011, 0b110));
}

#[test]
fn l_hexagon_gets_four_triangles_inside() {
    // Starting at (2, 0), whose fan would leave the polygon: its triangle (2, 0), (1, 1),
    // (1, 2) is clockwise.
    let mut points = L_HEXAGON.to_vec();
    points.rotate_left(1);
    check_polygon(&points).unwrap();
}

#[test]
fn clockwise_polygons_give_clockwise_triangles() {
    let mut points = L_HEXAGON.to_vec();
    points.reverse();
    check_polygon(&points).unwrap();
}

#[test]
fn collinear_corners_are_kept_without_degenerate_triangles() {
    // A square with the midpoint of every side: not strictly convex.
    let points = [
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [2.0, 2.0],
        [1.0, 2.0],
        [0.0, 2.0],
        [0.0, 1.0],
    ];
    assert_eq!(check_polygon(&points).unwrap(), 6);
}

#[test]
fn consecutive_equal_corners_count_once() {
    // A square with its second corner repeated, and the first repeated at the end.
    let points = [
        [0.0, 0.0],
        [1.0, 0.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [0.0, 0.0],
    ];
    assert_eq!(check_polygon(&points).unwrap(), 2);
    // -0.0 is 0.0: a triangle with a repeated corner is that triangle.
    let points = [[0.0, 0.0], [1.0, 0.0], [-0.0, 1.0], [0.0, 1.0]];
    check_polygon(&points).unwrap();
}

#[test]
fn self_overlapping_polygons_name_the_face_and_the_overlap() {
    let cases: [(&[[f64; 2]], Overlap); 4] = [
        // A bow tie.
        (
            &[[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]],
            Overlap::CrossingEdges,
        ),
        // A pentagram: every turn has one sign, but it winds twice.
        (
            &[
                [0.0, 10.0],
                [6.0, -8.0],
                [-10.0, 3.0],
                [10.0, 3.0],
                [-6.0, -8.0],
            ],
            Overlap::CrossingEdges,
        ),
        // Corner (2, 0) lies on the edge from (0, 0) to (4, 0).
        (
            &[[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [2.0, 0.0], [0.0, 3.0]],
            Overlap::CornerOnEdge,
        ),
        // Two lobes touching at (1, 1), visited twice.
        (
            &[
                [0.0, 0.0],
                [2.0, 0.0],
                [1.0, 1.0],
                [2.0, 2.0],
                [0.0, 2.0],
                [1.0, 1.0],
            ],
            Overlap::CoincidentCorners,
        ),
    ];
    for (points, overlap) in cases {
        // Face 0 is a good triangle, face 1 the polygon.
        let mut positions = vec![[5.0, 5.0, 0.0], [6.0, 5.0, 0.0], [5.0, 6.0, 0.0]];
        positions.extend(points.iter().map(|p| [p[0], p[1], 0.0]));
        let polygon: Vec<u32> = (3..positions.len() as u32).collect();
        let mesh = mesh(positions, &[&[0, 1, 2], &polygon]);
        let expected = PolygonError::SelfOverlapping {
            face: FaceId::new(1),
            overlap,
        };
        assert_eq!(triangulate_faces(&mesh), Err(expected), "{points:?}");
        let (partial, errors) = triangulate_faces_partial(&mesh);
        assert_eq!(errors, vec![expected]);
        assert_eq!(
            partial.iter().collect::<Vec<_>>(),
            vec![(FaceId::new(0), [0, 1, 2])]
        );
        assert!(expected.to_string().starts_with("face 1 overlaps itself"));
    }
}

#[test]
fn zero_area_and_non_finite_polygons_are_errors() {
    let face = FaceId::new(0);
    let line = plane_polygon(&[[0.0, 0.0], [1.0, 0.0], [3.0, 0.0], [2.0, 0.0]]);
    assert_eq!(
        triangulate_faces(&line),
        Err(PolygonError::ZeroArea { face })
    );
    let point = plane_polygon(&[[1.0, 1.0]; 4]);
    assert_eq!(
        triangulate_faces(&point),
        Err(PolygonError::ZeroArea { face })
    );
    let nan = plane_polygon(&[[0.0, 0.0], [1.0, 0.0], [1.0, f64::NAN], [0.0, 1.0]]);
    assert_eq!(
        triangulate_faces(&nan),
        Err(PolygonError::NonFinite { face })
    );
}

#[test]
fn coordinates_are_scaled_into_spades_range() {
    for scale in [1e-300, 1e-160, 1e250, 1e300, f64::MAX / 4.0] {
        let points: Vec<[f64; 2]> = L_HEXAGON.iter().map(|p| p.map(|x| x * scale)).collect();
        check_polygon(&points).unwrap();
    }
    // Subnormal coordinates scale up exactly.
    let points: Vec<[f64; 2]> = L_HEXAGON.iter().map(|p| p.map(|x| x * 1e-320)).collect();
    check_polygon(&points).unwrap();
    // No power of two brings both 1e-200 and 2e200 into range.
    let mut points: Vec<[f64; 2]> = L_HEXAGON.iter().map(|p| p.map(|x| x * 1e200)).collect();
    points[0] = [1e-200, 0.0];
    let face = FaceId::new(0);
    assert_eq!(
        triangulate_faces(&plane_polygon(&points)),
        Err(PolygonError::OutOfRange { face })
    );
}

#[test]
fn binary_exponents_and_the_scale() {
    assert_eq!(exponent(1.0), 0);
    assert_eq!(exponent(-0.75), -1);
    assert_eq!(exponent(f64::MAX), 1023);
    assert_eq!(exponent(f64::MIN_POSITIVE), -1022);
    assert_eq!(exponent(5e-324), -1074);
    assert_eq!(exponent(3.0 * 5e-324), -1073);
    assert_eq!(spade_scale(&[[1.0, -3.0], [0.0, 1e-40]]), Some(1.0));
    assert_eq!(
        spade_scale(&[[1e-50, 0.0]]),
        Some(power_of_two(-142 - exponent(1e-50)))
    );
    assert_eq!(
        spade_scale(&[[f64::MAX, 1e250]]),
        Some(power_of_two(200 - 1023))
    );
    assert_eq!(spade_scale(&[[f64::MAX, 1.0]]), None);
    assert_eq!(spade_scale(&[[f64::MAX, 5e-324]]), None);
    assert_eq!(spade_scale(&[[f64::INFINITY, 0.0]]), None);
}

#[test]
fn every_axis_plane_and_non_planar_polygons() {
    // The L hexagon in the planes x = 1, y = -2 and z = 3, and lifted off its plane.
    for (axis, level) in [(0, 1.0), (1, -2.0), (2, 3.0)] {
        let positions = L_HEXAGON
            .iter()
            .map(|p| {
                let mut q = [0.0; 3];
                q[axis] = level;
                q[(axis + 1) % 3] = p[0];
                q[(axis + 2) % 3] = p[1];
                q
            })
            .collect();
        let mesh = mesh(positions, &[&[0, 1, 2, 3, 4, 5]]);
        check(&L_HEXAGON, &triangulate_faces(&mesh).unwrap()).unwrap();
    }
    let lifted = L_HEXAGON
        .iter()
        .enumerate()
        .map(|(i, p)| [p[0], p[1], (i * i) as f64 / 8.0])
        .collect();
    let mesh = mesh(lifted, &[&[0, 1, 2, 3, 4, 5]]);
    check(&L_HEXAGON, &triangulate_faces(&mesh).unwrap()).unwrap();
}

#[test]
fn an_underflowing_normal_falls_back_to_another_projection() {
    // In the plane y = 0 at 1e-200: every Newell product underflows to zero, so the normal
    // ranks z first, where the projection is a segment, and then x, also a segment.
    let positions = L_HEXAGON
        .iter()
        .map(|p| [p[0] * 1e-200, 0.0, p[1] * 1e-200])
        .collect();
    let mesh = mesh(positions, &[&[0, 1, 2, 3, 4, 5]]);
    assert_eq!(triangulate_faces(&mesh).unwrap().len(), 4);
}

/// A polygon around the origin with corners at increasing angles (one per sector, so
/// consecutive ones are less than π apart) and the given radii: star-shaped, hence simple.
fn star(radii: &[f64], jitter: &[f64]) -> Vec<[f64; 2]> {
    let n = radii.len() as f64;
    (radii.iter().zip(jitter).enumerate())
        .map(|(i, (&r, &j))| {
            let angle = std::f64::consts::TAU * (i as f64 + 0.5 + 0.4 * j) / n;
            [r * angle.cos(), r * angle.sin()]
        })
        .collect()
}

/// Integer directions in increasing angle, 16 around the circle: integer multiples of them
/// are star-shaped polygons with many collinear corners.
const DIRECTIONS: [[i32; 2]; 16] = [
    [1, 0],
    [2, 1],
    [1, 1],
    [1, 2],
    [0, 1],
    [-1, 2],
    [-1, 1],
    [-2, 1],
    [-1, 0],
    [-2, -1],
    [-1, -1],
    [-1, -2],
    [0, -1],
    [1, -2],
    [1, -1],
    [2, -1],
];

/// `points` rotated to start at `start`, reversed when `reverse`.
fn reorder(mut points: Vec<[f64; 2]>, start: usize, reverse: bool) -> Vec<[f64; 2]> {
    let n = points.len();
    points.rotate_left(start % n);
    if reverse {
        points.reverse();
    }
    points
}

proptest! {
    #![proptest_config(config(400, 0x7472_6961_6e67_0001))]

    /// Random star-shaped polygons with f64 corners: n − 2 triangles of the polygon's
    /// orientation whose areas sum exactly to the shoelace area.
    #[test]
    fn star_polygons_triangulate_exactly(
        corners in (3usize..40).prop_flat_map(|n| (
            prop::collection::vec(0.1f64..100.0, n),
            prop::collection::vec(-1.0f64..1.0, n),
        )),
        start in 0usize..40,
        reverse in any::<bool>(),
    ) {
        let points = reorder(star(&corners.0, &corners.1), start, reverse);
        check_polygon(&points)?;
    }

    /// Integer star-shaped polygons along 16 directions: collinear runs of corners, convex and
    /// not, all kept.
    #[test]
    fn integer_star_polygons_keep_collinear_corners(
        radii in prop::collection::vec(1i32..4, 16),
        skip in prop::collection::vec(any::<bool>(), 16),
        start in 0usize..16,
        reverse in any::<bool>(),
    ) {
        let points: Vec<[f64; 2]> = (0..16)
            .filter(|&i| !skip[i] || i % 4 == 0)
            .map(|i| DIRECTIONS[i].map(|d| f64::from(d * radii[i])))
            .collect();
        let points = reorder(points, start, reverse);
        check_polygon(&points)?;
    }
}

/// Twice the signed area of a triangle of small integer points, exactly.
fn int_area2(a: [i64; 2], b: [i64; 2], c: [i64; 2]) -> i64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether `p` lies on the closed segment `a b`.
fn on_segment(a: [i64; 2], b: [i64; 2], p: [i64; 2]) -> bool {
    int_area2(a, b, p) == 0
        && (p[0] - a[0]) * (p[0] - b[0]) <= 0
        && (p[1] - a[1]) * (p[1] - b[1]) <= 0
}

/// Whether the closed segments `a b` and `c d` meet.
fn segments_meet(a: [i64; 2], b: [i64; 2], c: [i64; 2], d: [i64; 2]) -> bool {
    let (d1, d2) = (int_area2(a, b, c).signum(), int_area2(a, b, d).signum());
    let (d3, d4) = (int_area2(c, d, a).signum(), int_area2(c, d, b).signum());
    (d1 * d2 < 0 && d3 * d4 < 0)
        || on_segment(a, b, c)
        || on_segment(a, b, d)
        || on_segment(c, d, a)
        || on_segment(c, d, b)
}

/// Brute force: a loop of distinct points is simple when consecutive edges meet only at their
/// shared corner and other edges not at all.
fn is_simple(points: &[[i64; 2]]) -> bool {
    let n = points.len();
    let mut sorted = points.to_vec();
    sorted.sort_unstable();
    if sorted.windows(2).any(|w| w[0] == w[1]) {
        return false;
    }
    let edge = |i: usize| (points[i], points[(i + 1) % n]);
    for i in 0..n {
        for j in i + 1..n {
            let ((a, b), (c, d)) = (edge(i), edge(j));
            if j == i + 1 || (i == 0 && j == n - 1) {
                // Adjacent: they overlap beyond their shared corner when the far end of one
                // lies on the other.
                let (far_i, far_j) = if j == i + 1 { (a, d) } else { (b, c) };
                if on_segment(a, b, far_j) || on_segment(c, d, far_i) {
                    return false;
                }
            } else if segments_meet(a, b, c, d) {
                return false;
            }
        }
    }
    true
}

proptest! {
    #![proptest_config(config(3000, 0x7472_6961_6e67_0002))]

    /// Random loops on a small grid (mostly not simple): the triangulator succeeds exactly on
    /// the simple ones (after merging consecutive equal corners), with the oracle's checks,
    /// says zero area exactly when every corner is on one line, and self-overlap otherwise.
    #[test]
    fn exactly_the_simple_polygons_triangulate(
        grid in prop::collection::vec([0i64..5, 0i64..5], 4..9),
    ) {
        let points: Vec<[f64; 2]> = grid.iter().map(|p| p.map(|x| x as f64)).collect();
        let loop_: Vec<[i64; 2]> = {
            let n = grid.len();
            (0..n).filter(|&i| grid[i] != grid[(i + n - 1) % n]).map(|i| grid[i]).collect()
        };
        let collinear = loop_.len() < 3
            || (0..loop_.len()).all(|i| int_area2(loop_[0], loop_[1], loop_[i]) == 0);
        let mesh = plane_polygon(&points);
        match triangulate_faces(&mesh) {
            Ok(t) => {
                prop_assert!(!collinear && is_simple(&loop_), "{:?}", loop_);
                check(&points, &t)?;
            }
            Err(PolygonError::ZeroArea { .. }) => prop_assert!(collinear, "{:?}", loop_),
            Err(PolygonError::SelfOverlapping { .. }) => {
                prop_assert!(!collinear && !is_simple(&loop_), "{:?}", loop_)
            }
            Err(e) => prop_assert!(false, "{e}"),
        }
    }
}
