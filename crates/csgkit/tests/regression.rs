//! Regressions, each named after the issue whose work found it, or after the stress run of
//! random chains of booleans (solids at random places, scales and turns, each result read back
//! for the next step) that found it.

use csgkit::exact::{BooleanOptions, boolean};
use csgkit::primitives::cuboid;
use csgkit::{Format, Mesh, Operation, Precision, read_mesh};

use crate::util::{assert_no_self_intersection, assert_valid_operand, repo_data, through_a_file};

/// A mesh of the repository's `tests/data/regression/`.
fn load_regression(name: &str) -> Mesh {
    read_mesh(repo_data(&format!("regression/{name}")))
        .unwrap()
        .mesh
}

/// Issue 11: in the chain of binary unions of OpenSCAD's `example018`, step 21 (`step20 ∪
/// leaf 27`, a box) wrote 8 pairs of opposite triangles over the same three vertices: step
/// 20's faces lie only nearly in the box's planes (a vertex at 175.00000000000003), and the
/// sliver between the two surfaces rounded flat into a two-sided sheet. The next union could
/// not sample it. Certification now removes such sheets, so the result has no duplicate face
/// and the chain goes on.
#[test]
fn issue_11_rounded_union_leaves_no_two_sided_sheet() {
    let (step20, leaf27) = (
        load_regression("example018_step20.ply"),
        load_regression("example018_leaf27.off"),
    );
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

/// Stress run: a box of side 0.5 a million units from the origin (a result csgkit wrote, read
/// back) was refused as "oriented inward": its volume, summed over cones from the origin,
/// cancelled to −7.4. Ingest now takes the cones from the centre of each operand's box.
#[test]
fn stress_run_far_small_operands_are_not_inverted() {
    let (cube, far_box) = (
        load_regression("far_cube_half.obj"),
        load_regression("far_box_half.obj"),
    );
    let volume = |m: &Mesh| m.report().measures.volume;
    let (a, b) = (volume(&cube), volume(&far_box));
    assert!(
        (a - 0.125).abs() < 1e-9 && (b - 0.25).abs() < 1e-9,
        "{a} {b}"
    );
    let options = BooleanOptions::default();
    let union = boolean(Operation::Union, &[&cube, &far_box], &options)
        .unwrap_or_else(|e| panic!("union failed: {e}"));
    let intersection = boolean(Operation::Intersection, &[&cube, &far_box], &options)
        .unwrap_or_else(|e| panic!("intersection failed: {e}"));
    let report = union.mesh.report();
    assert!(report.is_valid_solid(), "{report:?}");
    let expected = a + b - volume(&intersection.mesh);
    let error = (volume(&union.mesh) - expected).abs();
    assert!(
        error < 1e-9,
        "union volume {} against {expected}",
        volume(&union.mesh)
    );
    assert_no_self_intersection(&union.mesh, "the union");
}

/// Stress run: `(A ∪ B) − B` written and read back, then xor-ed with `A`, a box a million
/// units across whose faces the rebuilt copy matches to rounding. Intersection points of
/// nearly parallel faces have no usable f64 estimate from the filter (its `W` interval holds
/// zero), and the split's insertion order sorted their infinite or NaN coordinates and
/// panicked. The stages' estimates now round such points exactly.
#[test]
fn stress_run_nearly_parallel_intersections_do_not_panic() {
    let (rebuilt, original) = (
        load_regression("rebuilt_box.obj"),
        load_regression("rebuilt_box_original.obj"),
    );
    let xor = boolean(
        Operation::Xor,
        &[&rebuilt, &original],
        &BooleanOptions::default(),
    )
    .unwrap_or_else(|e| panic!("xor failed: {e}"));
    let report = xor.mesh.report();
    assert!(report.is_valid_solid(), "{report:?}");
    assert_no_self_intersection(&xor.mesh, "the xor");
    // What separates the two is a skin an ulp or so thick over a box of volume 1.15e18.
    let volume = report.measures.volume;
    assert!((0.0..1e3).contains(&volume), "{volume}");
}

/// Stress run: results csgkit wrote in f64 (OBJ), read back and written as binary STL, were
/// refused as invalid: the f32 reading of the operands, before the boolean, folded a polygon
/// face ("overlaps itself in its projection") or turned a sliver solid a million units
/// across inside out ("oriented inward"). An operand that reading breaks now keeps its f64
/// coordinates, which round with the result and are certified in f32.
#[test]
fn stress_run_f32_results_of_operands_f32_reading_breaks() {
    let f32_options = BooleanOptions {
        precision: Precision::F32,
        ..BooleanOptions::default()
    };
    let folds = load_regression("f32_folds_a_polygon.obj");
    let exact = boolean(Operation::Union, &[&folds], &BooleanOptions::default())
        .unwrap_or_else(|e| panic!("f64 union failed: {e}"));
    let in_f32 = boolean(Operation::Union, &[&folds], &f32_options)
        .unwrap_or_else(|e| panic!("f32 union failed: {e}"));
    let report = in_f32.mesh.report();
    assert!(report.is_valid_solid(), "{report:?}");
    assert_no_self_intersection(&in_f32.mesh, "the f32 union");
    let off_f32 = (in_f32.mesh.positions().iter().flatten()).find(|&&x| !Precision::F32.holds(x));
    assert_eq!(off_f32, None, "a coordinate is not an f32");
    let (volume, expected) = (report.measures.volume, exact.mesh.report().measures.volume);
    assert!(
        (volume - expected).abs() < 1e-5 * expected,
        "f32 volume {volume} against {expected}"
    );

    // The sliver bounds 3.1 cubic units over 8e5 units: thinner than an f32 ulp there, so
    // its f32 form is empty, and certification says so by removing the shell.
    let sliver = load_regression("f32_inverts_a_sliver.obj");
    let cube = cuboid([0.0; 3], [1.0; 3]);
    let difference = boolean(Operation::Difference, &[&sliver, &cube], &f32_options)
        .unwrap_or_else(|e| panic!("f32 difference failed: {e}"));
    assert_eq!(difference.mesh.face_count(), 0);
    assert_eq!(difference.stats.removed_shells, 1);
    assert_eq!(
        difference.mesh.vertex_count(),
        0,
        "unused vertices are kept"
    );
}

/// Stress run: a result csgkit wrote, a sliver solid of volume 7.6e-9 in two shells (16
/// non-manifold edges), could not be an operand: `r2 − r2` failed as "surface patch N has no
/// sub-triangle wide enough to sample". The check for nested shells cast its ray from each
/// shell's first triangle, a sliver too thin for an f64 sample, and so took the winding path,
/// which has no sample for such patches either. It now casts from the first of the shell's
/// triangles wide enough.
#[test]
fn stress_run_sliver_shells_are_operands() {
    let sliver = load_regression("sliver_shells.obj");
    let options = BooleanOptions::default();
    let volume = |m: &Mesh| m.report().measures.volume;
    let run = |op| {
        boolean(op, &[&sliver, &sliver], &options)
            .unwrap_or_else(|e| panic!("{op:?} of the sliver with itself failed: {e}"))
    };
    let difference = run(Operation::Difference);
    assert_eq!(difference.mesh.face_count(), 0);
    for op in [Operation::Union, Operation::Intersection] {
        let result = run(op);
        let report = result.mesh.report();
        assert!(report.is_valid_solid(), "{op:?}: {report:?}");
        assert_eq!(result.mesh.face_count(), sliver.face_count(), "{op:?}");
        assert_eq!(volume(&result.mesh), volume(&sliver), "{op:?}");
    }
}

/// Stress run: a result csgkit wrote (126 faces) holds a thin closed shell of four sliver
/// triangles, attached to the rest of the solid along three non-manifold edges. No f64 sample
/// point fits in any of them, no other part of their faces is classified, and nothing lies
/// in their planes, so `r1 − cube` failed as "surface patch 8 has no sub-triangle wide enough
/// to sample", even with the cube far away. The winding numbers now turn about an edge of the
/// sliver from a classified sheet in another plane.
#[test]
fn stress_run_a_thin_shell_on_edges_is_an_operand() {
    let solid = load_regression("thin_shell_on_edges.off");
    let options = BooleanOptions::default();
    let volume = |m: &Mesh| m.report().measures.volume;
    let run = |op: Operation, other: &Mesh| {
        let result = boolean(op, &[&solid, other], &options)
            .unwrap_or_else(|e| panic!("{op:?} failed: {e}"))
            .mesh;
        assert_valid_operand(&result, &format!("{op:?}"));
        volume(&result)
    };
    // Far from the solid: the difference is the solid, the union both.
    let far = cuboid([-0.5, 0.75, -0.375], [1.0, 1.25, 0.875]);
    assert_eq!(run(Operation::Difference, &far), volume(&solid));
    let union = run(Operation::Union, &far);
    assert!((union - volume(&solid) - volume(&far)).abs() <= 1e-12);
    // A cube through the solid beside the sliver: vol(A ∪ B) + vol(A ∩ B) = vol(A) + vol(B).
    let through = cuboid([0.25, -0.5, -1.5], [1.0, 0.0, -0.5]);
    let (union, intersection) = (
        run(Operation::Union, &through),
        run(Operation::Intersection, &through),
    );
    let expected = volume(&solid) + volume(&through);
    assert!((union + intersection - expected).abs() <= 1e-12 * expected);
    assert!(intersection > 0.0);
}

/// Stress run: a solid A split in two by a solid B through files and joined back. The cut
/// piece is `(A ∪ B) − B` and the core piece `A ∩ B`, each a result csgkit wrote as OBJ;
/// their union is A again, up to where rounding left the two pieces. Their cut faces lie in
/// B's planes and cancel exactly, but along the seam where those faces meet A's surface the
/// two pieces' rounded curves differ by ulps, so the exact union keeps slivers that fold when
/// rounded. Certification re-refined those folds into ever more of them (234 crossing pairs,
/// then 403 after four re-refinements, then 7,735 on a coarser grid), and the union ran for
/// over 100 seconds. A re-refinement that adds crossings is now rolled back for a coarser
/// grid.
#[test]
fn stress_run_a_solid_split_in_two_joins_back() {
    let cut = load_regression("rejoin_cut_piece.obj");
    let core = load_regression("rejoin_core_piece.obj");
    let union = boolean(Operation::Union, &[&cut, &core], &BooleanOptions::default())
        .unwrap_or_else(|e| panic!("the union of the two pieces failed: {e}"))
        .mesh;
    assert_valid_operand(&union, "the union");
    // The pieces overlap only in slivers along the seam.
    let volume = |m: &Mesh| m.report().measures.volume;
    let expected = volume(&cut) + volume(&core);
    assert!(
        (volume(&union) - expected).abs() <= 1e-9 * expected,
        "the union has volume {}, the pieces {expected}",
        volume(&union)
    );
}

/// Stress run: the same chain from its operands, a solid A (split_solid.obj, 1,280 faces) and
/// a turned box B (split_box.obj) through it, each step's result read back from the file it
/// was written to: `A ∪ B` and `A ∩ B` as OBJ, `(A ∪ B) − B` as OFF, then the union of the
/// two pieces. It failed with `NotCertified` on two counts:
/// - the difference recomputed the union's curve points, an ulp or two off, so the two
///   pieces' seams differed; assemble now rounds such a point onto the corner beside it;
/// - the pieces then share their seam's vertices, but triangulate the cut between them
///   differently, and the union keeps thin pockets between the two triangulations, which
///   fold when rounded; certify now removes thin closed pockets whole.
///
/// The union must certify, be a valid operand, and be A up to the seam: of its volume to
/// 1e-9.
#[test]
fn stress_run_a_solid_split_by_a_box_joins_back_through_files() {
    let solid = load_regression("split_solid.obj");
    let cut_by = load_regression("split_box.obj");
    let run = |op, operands: &[&Mesh], format| {
        let result = boolean(op, operands, &BooleanOptions::default())
            .unwrap_or_else(|e| panic!("{op:?} failed: {e}"))
            .mesh;
        through_a_file(&result, format)
    };
    let union = run(Operation::Union, &[&solid, &cut_by], Format::Obj);
    let cut = run(Operation::Difference, &[&union, &cut_by], Format::Off);
    let core = run(Operation::Intersection, &[&solid, &cut_by], Format::Obj);
    let joined = boolean(Operation::Union, &[&cut, &core], &BooleanOptions::default())
        .unwrap_or_else(|e| panic!("joining the pieces failed: {e}"))
        .mesh;
    assert_valid_operand(&joined, "the joined solid");
    let volume = |m: &Mesh| m.report().measures.volume;
    assert!(
        (volume(&joined) - volume(&solid)).abs() <= 1e-9 * volume(&solid),
        "the joined solid has volume {}, the solid {}",
        volume(&joined),
        volume(&solid)
    );
}
