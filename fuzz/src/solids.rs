//! Small random solids for fuzzing the exact boolean engine, and the identities its results
//! must satisfy.
//!
//! Coordinates come from a grid of quarter units (exact in f64, so ties — shared faces,
//! edges through edges, identical operands — are common), except for turned boxes, whose
//! corners are rotated and so are not on any grid (rounding and certification get
//! exercised). A pair puts two solids in one mesh: overlapping or nested shells, which take
//! the winding-number path.

use arbitrary::Arbitrary;
use csgkit::exact::{BooleanOptions, boolean, self_intersections};
use csgkit::mesh::{FaceMode, concatenate, transformed};
use csgkit::primitives::{cuboid, icosphere};
use csgkit::{Encoding, Format, Mesh, Operation, write_mesh_to_bytes};

/// One fuzz input: three operands and how the result's faces are written.
#[derive(Arbitrary, Debug)]
pub struct Case {
    a: Solid,
    b: Solid,
    c: Solid,
    faces: Faces,
    merge_coplanar: bool,
}

#[derive(Arbitrary, Debug)]
enum Faces {
    Triangles,
    Polygons,
    Quads,
}

#[derive(Arbitrary, Debug)]
enum Solid {
    One(Shape),
    /// Two shapes in one mesh.
    Pair(Shape, Shape),
}

#[derive(Arbitrary, Debug)]
enum Shape {
    /// An axis-aligned box: its low corner and its size, in quarter units.
    Box { min: [i8; 3], size: [u8; 3] },
    /// A tetrahedron on the quarter grid (skipped when flat).
    Tetrahedron([[i8; 3]; 4]),
    /// A box turned by `angle` (of 2¹⁶ per turn) about the axis through the origin.
    TurnedBox {
        min: [i8; 3],
        size: [u8; 3],
        axis: u8,
        angle: u16,
    },
    /// An icosahedron: centre in quarter units, radius in units.
    Icosahedron { centre: [i8; 3], radius: u8 },
}

fn quarter(c: i8) -> f64 {
    f64::from(c) / 4.0
}

impl Shape {
    /// The mesh, `None` for a flat tetrahedron.
    fn mesh(&self) -> Option<Mesh> {
        match *self {
            Shape::Box { min, size } => Some(box_mesh(min, size)),
            Shape::Tetrahedron(corners) => {
                let p = corners.map(|c| c.map(quarter));
                let d = [1, 2, 3].map(|i| [0, 1, 2].map(|k| p[i][k] - p[0][k]));
                let det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
                    - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
                    + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
                // Exact: quarter-grid coordinates below 2⁵ in magnitude.
                if det == 0.0 {
                    return None;
                }
                let (b, c) = if det > 0.0 { (1, 2) } else { (2, 1) };
                let faces = [[0, c, b], [0, b, 3], [0, 3, c], [b, c, 3]];
                Some(Mesh::from_triangles(p.to_vec(), &faces).expect("indices below 4"))
            }
            Shape::TurnedBox {
                min,
                size,
                axis,
                angle,
            } => {
                let theta = f64::from(angle) * std::f64::consts::TAU / 65536.0;
                let (s, c) = theta.sin_cos();
                let (i, j) = [(1, 2), (2, 0), (0, 1)][usize::from(axis % 3)];
                let mut m = csgkit::mesh::IDENTITY;
                m[i][i] = c;
                m[i][j] = -s;
                m[j][i] = s;
                m[j][j] = c;
                transformed(&box_mesh(min, size), &m)
            }
            Shape::Icosahedron { centre, radius } => Some(icosphere(
                centre.map(quarter),
                f64::from(radius % 16 + 1),
                0,
            )),
        }
    }
}

fn box_mesh(min: [i8; 3], size: [u8; 3]) -> Mesh {
    let low = min.map(quarter);
    let high = [0, 1, 2].map(|k| low[k] + f64::from(size[k] % 32 + 1) / 4.0);
    cuboid(low, high)
}

impl Solid {
    fn mesh(&self) -> Option<Mesh> {
        match self {
            Solid::One(shape) => shape.mesh(),
            Solid::Pair(first, second) => concatenate(&[first.mesh()?, second.mesh()?]).ok(),
        }
    }
}

/// Runs every operation on the case's operands and checks the results (panics on a
/// violation; see [`check_result`] and the identities below).
pub fn check_case(case: &Case) {
    let (Some(a), Some(b), Some(c)) = (case.a.mesh(), case.b.mesh(), case.c.mesh()) else {
        return;
    };
    // To triage a failing case with the command line: its operands as OBJ files (exact f64).
    if let Some(folder) = std::env::var_os("CSGKIT_FUZZ_DUMP") {
        for (name, mesh) in [("a.obj", &a), ("b.obj", &b), ("c.obj", &c)] {
            let bytes = write_mesh_to_bytes(mesh, Format::Obj, Encoding::Ascii).expect("OBJ");
            std::fs::write(std::path::Path::new(&folder).join(name), bytes).expect("dump");
        }
    }
    let options = BooleanOptions {
        faces: match case.faces {
            Faces::Triangles => FaceMode::Triangles,
            Faces::Polygons => FaceMode::Polygons,
            Faces::Quads => FaceMode::Quads,
        },
        merge_coplanar: case.merge_coplanar,
        ..BooleanOptions::default()
    };
    let run = |op: Operation, operands: &[&Mesh]| -> f64 {
        let result = boolean(op, operands, &options)
            .unwrap_or_else(|e| panic!("{op:?} of {} valid solids failed: {e}", operands.len()));
        check_result(&result.mesh, op, operands.len());
        result.mesh.report().measures.volume
    };
    // Each operand's volume as the engine reads it (a pair's overlap counts once).
    let (va, vb) = (run(Operation::Union, &[&a]), run(Operation::Union, &[&b]));
    let union = boolean(Operation::Union, &[&a, &b], &options)
        .unwrap_or_else(|e| panic!("union of valid solids failed: {e}"));
    check_result(&union.mesh, Operation::Union, 2);
    let vu = union.mesh.report().measures.volume;
    let vi = run(Operation::Intersection, &[&a, &b]);
    let vd = run(Operation::Difference, &[&a, &b]);
    let vx = run(Operation::Xor, &[&a, &b]);
    let tolerance = 1e-9 * (va.abs() + vb.abs()).max(1.0);
    let close = |x: f64, y: f64| (x - y).abs() <= tolerance;
    assert!(
        close(vu + vi, va + vb),
        "vol(A∪B) + vol(A∩B) = {vu} + {vi} ≠ vol(A) + vol(B) = {va} + {vb}"
    );
    assert!(
        close(vd, va - vi),
        "vol(A−B) = {vd} ≠ vol(A) − vol(A∩B) = {va} − {vi}"
    );
    assert!(
        close(vx, vu - vi),
        "vol(A⊕B) = {vx} ≠ vol(A∪B) − vol(A∩B) = {vu} − {vi}"
    );
    assert!(
        vi <= va.min(vb) + tolerance && vi >= -tolerance,
        "vol(A∩B) = {vi} outside [0, min(vol A, vol B)]"
    );
    // Valid in, valid out: the union is an operand of the next boolean, whose result is the
    // n-ary union's.
    let chained = run(Operation::Union, &[&union.mesh, &c]);
    let n_ary = run(Operation::Union, &[&a, &b, &c]);
    assert!(
        close(chained, n_ary),
        "(A∪B)∪C has volume {chained}, ∪(A, B, C) {n_ary}"
    );
}

/// A result of the exact engine (`op` on `operands` operands) is a closed, oriented solid
/// (or empty), with finite coordinates, no face twice and no two faces crossing.
pub fn check_result(mesh: &Mesh, op: Operation, operands: usize) {
    if mesh.face_count() == 0 {
        return;
    }
    let op = format!("{op:?} of {operands}");
    assert!(
        mesh.positions().iter().flatten().all(|c| c.is_finite()),
        "{op} wrote a non-finite coordinate"
    );
    let report = mesh.report();
    assert!(
        report.is_valid_solid(),
        "{op} result is not a closed, oriented solid"
    );
    assert_eq!(
        report.degenerate_faces, 0,
        "{op} result has degenerate faces"
    );
    let crossings = self_intersections(mesh);
    assert_eq!(
        crossings.pair_count(),
        0,
        "{op} result has faces that cross"
    );
    assert!(
        crossings.invalid_polygons.is_empty(),
        "{op} result has a self-overlapping polygon"
    );
}
