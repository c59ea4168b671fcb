//! Polygon faces through the one triangulator (`mesh::triangulate_faces`): non-convex caps,
//! collinear corners and self-overlapping polygons, in the self-intersection check and the
//! exact engine, with exact volumes (issue 9).

use csgkit::exact::{BooleanError, BooleanOptions, InvalidOperand, boolean};
use csgkit::mesh::{Overlap, PolygonError, are_collinear, triangulate_faces};
use csgkit::primitives::cuboid;
use csgkit::{FaceId, Mesh, Operation, self_intersections};
use num_rational::BigRational;
use num_traits::Zero;

use crate::util::exact_volume;

/// One mesh of polygon faces.
fn polygon_mesh(positions: Vec<[f64; 3]>, faces: &[Vec<u32>]) -> Mesh {
    Mesh::from_polygons(positions, faces).expect("valid by construction")
}

/// The prism over a counter-clockwise `outline` between heights `z0 < z1`: two caps of the
/// outline's corners and one quad per side, oriented outward.
fn prism(outline: &[[f64; 2]], z0: f64, z1: f64) -> Mesh {
    let n = outline.len() as u32;
    let mut positions: Vec<[f64; 3]> = outline.iter().map(|p| [p[0], p[1], z0]).collect();
    positions.extend(outline.iter().map(|p| [p[0], p[1], z1]));
    let mut faces = vec![(0..n).rev().collect(), (n..2 * n).collect()];
    faces.extend((0..n).map(|i| vec![i, (i + 1) % n, n + (i + 1) % n, n + i]));
    polygon_mesh(positions, &faces)
}

/// An L: the square [0, 4]² without [2, 4]², counter-clockwise from (4, 0), the corner whose
/// fan leaves the polygon (its triangle (4, 0), (2, 2), (2, 4) is clockwise).
const L_OUTLINE: [[f64; 2]; 6] = [
    [4.0, 0.0],
    [4.0, 2.0],
    [2.0, 2.0],
    [2.0, 4.0],
    [0.0, 4.0],
    [0.0, 0.0],
];

/// A five-pointed star of integer corners, counter-clockwise around the origin.
const STAR_OUTLINE: [[f64; 2]; 10] = [
    [0.0, 10.0],
    [-2.0, 3.0],
    [-10.0, 3.0],
    [-4.0, -1.0],
    [-6.0, -8.0],
    [0.0, -4.0],
    [6.0, -8.0],
    [4.0, -1.0],
    [10.0, 3.0],
    [2.0, 3.0],
];

fn q(n: i64) -> BigRational {
    BigRational::from_integer(n.into())
}

/// The shoelace area of an outline, exactly.
fn area(outline: &[[f64; 2]]) -> BigRational {
    let n = outline.len();
    let twice = (0..n).fold(BigRational::zero(), |sum, i| {
        let (a, b) = (outline[i].map(rational), outline[(i + 1) % n].map(rational));
        sum + &a[0] * &b[1] - &b[0] * &a[1]
    });
    twice / q(2)
}

fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// The exact volume of `op` on `operands`, after checking the result is a valid solid.
fn volume_of(op: Operation, operands: &[&Mesh]) -> BigRational {
    let result = boolean(op, operands, &BooleanOptions::default())
        .unwrap_or_else(|e| panic!("{op:?} failed: {e}"));
    assert!(result.mesh.report().is_valid_solid(), "{op:?}: not a solid");
    exact_volume(&result.mesh)
}

/// Asserts that every face triangulates into n − 2 triangles of positive area whose sides
/// marked as polygon edges are exactly the face's own directed edges.
fn assert_exact_triangulation(mesh: &Mesh) {
    let triangles = triangulate_faces(mesh).expect("every face is simple");
    let mut marked: Vec<Vec<[u32; 2]>> = vec![Vec::new(); mesh.face_count()];
    for t in 0..triangles.len() {
        let ids = triangles.triangle(t);
        let [a, b, c] = ids.map(|v| mesh.positions()[v as usize]);
        assert!(!are_collinear(a, b, c), "degenerate triangle {ids:?}");
        for i in 0..3 {
            if triangles.edge_mask(t) >> i & 1 == 1 {
                marked[triangles.face(t).index()].push([ids[i], ids[(i + 1) % 3]]);
            }
        }
    }
    for (f, face) in mesh.faces().enumerate() {
        let n = face.len();
        let mut edges: Vec<[u32; 2]> = (0..n).map(|i| [face[i], face[(i + 1) % n]]).collect();
        edges.sort_unstable();
        marked[f].sort_unstable();
        assert_eq!(marked[f], edges, "face {f}");
    }
    let expected: usize = mesh.faces().map(|f| f.len() - 2).sum();
    assert_eq!(triangles.len(), expected);
}

#[test]
fn issue_9_l_prism_is_a_solid_without_self_intersection() {
    let l = prism(&L_OUTLINE, 0.0, 2.0);
    assert!(l.report().is_valid_solid());
    assert_exact_triangulation(&l);
    assert_eq!(self_intersections(&l), Default::default());
    assert_eq!(exact_volume(&l), q(24));
}

#[test]
fn issue_9_l_prism_booleans_with_a_cube_are_exact() {
    let l = prism(&L_OUTLINE, 0.0, 2.0);
    let cube = cuboid([1.0; 3], [3.0; 3]);
    // The L meets [1, 3]² in area 3 (the notch takes [2, 3]²), over heights [1, 2].
    assert_eq!(volume_of(Operation::Intersection, &[&l, &cube]), q(3));
    assert_eq!(volume_of(Operation::Union, &[&l, &cube]), q(24 + 8 - 3));
    assert_eq!(volume_of(Operation::Difference, &[&l, &cube]), q(21));
    assert_eq!(volume_of(Operation::Difference, &[&cube, &l]), q(5));
}

/// The cube [0, 2]³ whose top face is an 8-corner square through the midpoints of its sides,
/// and whose side faces are pentagons with three collinear top corners.
fn cube_with_midpoints() -> Mesh {
    let mut positions = vec![
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
        [0.0, 2.0, 0.0],
    ];
    let top = [
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [2.0, 2.0],
        [1.0, 2.0],
        [0.0, 2.0],
        [0.0, 1.0],
    ];
    positions.extend(top.iter().map(|p| [p[0], p[1], 2.0]));
    // Bottom corners 0..4, top corners 4..12.
    let t = |k: u32| 4 + k % 8;
    let mut faces = vec![vec![3, 2, 1, 0], (4..12).collect()];
    faces.extend((0..4).map(|s| vec![s, (s + 1) % 4, t(2 * s + 2), t(2 * s + 1), t(2 * s)]));
    polygon_mesh(positions, &faces)
}

#[test]
fn issue_9_collinear_corners_give_no_degenerate_triangle() {
    let cube = cube_with_midpoints();
    assert!(cube.report().is_valid_solid());
    assert_exact_triangulation(&cube);
    assert_eq!(triangulate_faces(&cube).unwrap().len(), 2 + 6 + 4 * 3);
    assert!(self_intersections(&cube).is_empty());
    let other = cuboid([1.0; 3], [3.0; 3]);
    assert_eq!(volume_of(Operation::Intersection, &[&cube, &other]), q(1));
    assert_eq!(volume_of(Operation::Union, &[&cube, &other]), q(15));
    assert_eq!(volume_of(Operation::Difference, &[&cube, &other]), q(7));
}

#[test]
fn issue_9_star_prism_volumes_are_exact() {
    let star = prism(&STAR_OUTLINE, 0.0, 2.0);
    assert!(star.report().is_valid_solid());
    assert_exact_triangulation(&star);
    assert!(self_intersections(&star).is_empty());
    let a = area(&STAR_OUTLINE);
    assert_eq!(exact_volume(&star), &a * q(2));
    // The same star one unit higher: the walls overlap, the caps cut them at half height,
    // and every contact point is a corner or a midpoint, so even rounded volumes are exact.
    let higher = prism(&STAR_OUTLINE, 1.0, 3.0);
    assert_eq!(volume_of(Operation::Intersection, &[&star, &higher]), a);
    assert_eq!(volume_of(Operation::Difference, &[&star, &higher]), a);
    assert_eq!(volume_of(Operation::Union, &[&star, &higher]), &a * q(3));
}

#[test]
fn issue_9_a_bow_tie_is_an_error_naming_the_face() {
    // A closed "pillow" of two bow ties, each the other reversed: balanced edges, but neither
    // face is simple in its projection.
    let positions = vec![
        [0.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
    ];
    let pillow = polygon_mesh(positions, &[vec![0, 1, 2, 3], vec![3, 2, 1, 0]]);
    let overlap = Overlap::CrossingEdges;
    let face = FaceId::new(0);
    assert_eq!(
        triangulate_faces(&pillow),
        Err(PolygonError::SelfOverlapping { face, overlap })
    );
    let found = self_intersections(&pillow);
    let faces: Vec<FaceId> = found.invalid_polygons.iter().map(|e| e.face()).collect();
    assert_eq!(faces, [FaceId::new(0), FaceId::new(1)]);
    assert!(!found.is_empty());
    let cube = cuboid([0.0; 3], [1.0; 3]);
    let err = boolean(
        Operation::Union,
        &[&cube, &pillow],
        &BooleanOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        err,
        BooleanError::InvalidOperand(InvalidOperand::InvalidPolygon {
            operand: 1,
            error: PolygonError::SelfOverlapping { face, overlap }
        })
    );
    assert_eq!(
        err.to_string(),
        "operand 1: face 0 overlaps itself in its projection (two edges cross)"
    );
}

#[test]
fn issue_9_convex_quads_mark_their_diagonal() {
    // The unit cube of quads: each quad's fan, with the diagonal unmarked.
    let cube = prism(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], 0.0, 1.0);
    let triangles = triangulate_faces(&cube).unwrap();
    assert_eq!(triangles.len(), 12);
    for t in 0..12 {
        let face = cube.face(triangles.face(t));
        let expected = if t % 2 == 0 { 0b011 } else { 0b110 };
        assert_eq!(triangles.edge_mask(t), expected, "triangle {t}");
        assert_eq!(triangles.triangle(t)[0], face[0]);
    }
    assert_exact_triangulation(&cube);
}
