//! Regressions, each named after the issue whose work found it.

use csgkit::exact::{BooleanOptions, boolean};
use csgkit::primitives::cuboid;
use csgkit::{Mesh, Operation, read_mesh};

use crate::util::{assert_no_self_intersection, repo_data};

/// Issue 11: in the chain of binary unions of OpenSCAD's `example018`, step 21 (`step20 ∪
/// leaf 27`, a box) wrote 8 pairs of opposite triangles over the same three vertices: step
/// 20's faces lie only nearly in the box's planes (a vertex at 175.00000000000003), and the
/// sliver between the two surfaces rounded flat into a two-sided sheet. The next union could
/// not sample it. Certification now removes such sheets, so the result has no duplicate face
/// and the chain goes on.
#[test]
fn issue_11_rounded_union_leaves_no_two_sided_sheet() {
    let load = |name: &str| {
        read_mesh(repo_data(&format!("regression/{name}")))
            .unwrap()
            .mesh
    };
    let (step20, leaf27) = (load("example018_step20.ply"), load("example018_leaf27.off"));
    let options = BooleanOptions::default();
    let run = |op: Operation, operands: &[&Mesh]| {
        boolean(op, operands, &options).unwrap_or_else(|e| panic!("{op:?} failed: {e}"))
    };
    let union = run(Operation::Union, &[&step20, &leaf27]);
    assert!(union.stats.removed_sheets > 0, "{:?}", union.stats);
    let report = union.mesh.report();
    assert!(report.is_valid_solid(), "{report:?}");
    assert_eq!(report.duplicate_faces, 0, "{report:?}");
    assert_no_self_intersection(&union.mesh, "step 21");
    // The sheets had no volume: vol(A ∪ B) = vol(A) + vol(B) − vol(A ∩ B).
    let volume = |m: &Mesh| m.report().measures.volume;
    let intersection = run(Operation::Intersection, &[&step20, &leaf27]).mesh;
    let expected = volume(&step20) + volume(&leaf27) - volume(&intersection);
    let error = (volume(&union.mesh) - expected).abs();
    assert!(error <= 1e-9 * expected, "union volume off by {error}");
    // The result is a valid operand of the next step.
    let shifted = cuboid([140.0, 140.0, -10.0], [160.0, 160.0, 60.0]);
    let next = run(Operation::Union, &[&union.mesh, &shifted]);
    assert!(next.mesh.report().is_valid_solid());
}

/// A file that carries a two-sided sheet inside a solid (other tools write them where a
/// sliver collapsed) is accepted as the solid without it: the sheet adds nothing to any
/// winding number.
#[test]
fn issue_11_operand_with_a_two_sided_sheet_is_the_solid_without_it() {
    let cube = cuboid([0.0; 3], [2.0; 3]);
    let mut parts = cube.into_parts();
    let corner = |p: [f64; 3]| parts.positions.iter().position(|&q| q == p).unwrap() as u32;
    let (a, b, c) = (corner([0.0; 3]), corner([2.0, 0.0, 0.0]), corner([2.0; 3]));
    parts.corners.extend([a, b, c, a, c, b]);
    let with_sheet = Mesh::from_parts(parts).unwrap();
    let other = cuboid([1.0; 3], [3.0; 3]);
    let options = BooleanOptions::default();
    for (op, expected) in [
        (Operation::Union, 15.0),
        (Operation::Intersection, 1.0),
        (Operation::Difference, 7.0),
    ] {
        let result = boolean(op, &[&with_sheet, &other], &options)
            .unwrap_or_else(|e| panic!("{op:?} failed: {e}"));
        // Ingest dropped the sheet: two cubes of 12 triangles each are left.
        assert_eq!(result.stats.input_triangles, 24, "{op:?}");
        let report = result.mesh.report();
        assert!(report.is_valid_solid(), "{op:?}: {report:?}");
        assert_eq!(report.duplicate_faces, 0, "{op:?}: {report:?}");
        assert_eq!(report.measures.volume, expected, "{op:?}");
    }
    let repaired = boolean(Operation::Union, &[&with_sheet], &options).unwrap();
    assert_eq!(repaired.mesh.report().measures.volume, 8.0);
    assert_eq!(repaired.mesh.report().duplicate_faces, 0);
}

/// Issue 13 (fuzzing): geometry a file holds twice. A cube with one face written twice (its
/// edges then unbalanced: not closed as stored) is the cube without the repeat; a cube written
/// twice over the same vertices (every edge with four uses, winding number 2 inside) is the
/// cube by the winding rule. Both for every operation and for a repair; before, the first
/// was refused as open, and the second's repair kept both copies (twice the volume).
#[test]
fn issue_13_repeated_faces_count_once() {
    let cube = cuboid([0.0; 3], [2.0; 3]);
    let parts = cube.clone().into_parts();
    let mut one_face_twice = parts.clone();
    one_face_twice
        .corners
        .extend_from_slice(&parts.corners[..3]);
    let mut all_twice = parts.clone();
    all_twice.corners.extend_from_slice(&parts.corners);
    let other = cuboid([1.0; 3], [3.0; 3]);
    let options = BooleanOptions::default();
    for (repeated, triangles) in [(one_face_twice, 12), (all_twice, 24)] {
        let operand = Mesh::from_parts(repeated).unwrap();
        for (op, expected) in [
            (Operation::Union, 15.0),
            (Operation::Intersection, 1.0),
            (Operation::Difference, 7.0),
        ] {
            let result = boolean(op, &[&operand, &other], &options)
                .unwrap_or_else(|e| panic!("{op:?} failed: {e}"));
            assert_eq!(result.stats.input_triangles, triangles + 12, "{op:?}");
            let report = result.mesh.report();
            assert!(report.is_valid_solid(), "{op:?}: {report:?}");
            assert_eq!(report.duplicate_faces, 0, "{op:?}: {report:?}");
            assert_eq!(report.measures.volume, expected, "{op:?}");
        }
        let repaired = boolean(Operation::Union, &[&operand], &options).unwrap();
        let report = repaired.mesh.report();
        assert_eq!(report.measures.volume, 8.0);
        assert_eq!(report.duplicate_faces, 0);
        assert_eq!(repaired.stats.input_triangles, triangles);
    }
}
