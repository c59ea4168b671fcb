//! Every input the fuzz targets (`fuzz/`, cargo-fuzz) found to crash, replayed through the
//! same checks the targets run, from `tests/data/fuzz/<target>/`. Each test is named after
//! what the input broke; the fix made it pass.

#[path = "../../../fuzz/src/lib.rs"]
#[allow(dead_code)] // Only the checks of targets that found something are replayed.
mod checks;

use arbitrary::{Arbitrary, Unstructured};
use csgkit::Format;

use crate::util::repo_data;

/// The bytes of the saved input `name` of `target`.
fn input(target: &str, name: &str) -> Vec<u8> {
    let path = repo_data(&format!("fuzz/{target}/{name}"));
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A boolean case decoded as the `boolean_solids` target decodes its bytes.
fn solids_case(name: &str) -> checks::solids::Case {
    let bytes = input("boolean_solids", name);
    checks::solids::Case::arbitrary_take_rest(Unstructured::new(&bytes))
        .expect("the saved input decodes as the fuzz target decoded it")
}

/// An operand that is one icosahedron written twice over the same vertices: its single-operand
/// union (a repair) kept both copies, twice the volume, while its union with another operand
/// counted it once. Repeated triangles now count once in ingest.
#[test]
fn boolean_of_a_doubled_icosahedron() {
    checks::solids::check_case(&solids_case("doubled_icosahedron"));
}

/// The same with a box written twice, beside a box equal to it.
#[test]
fn boolean_of_a_doubled_box() {
    checks::solids::check_case(&solids_case("doubled_box"));
}

/// Two shells in one operand, a turned box and a small cube, the cube also the second operand:
/// the winding classification kept a sliver of the cube's bottom face (thinner than the f64
/// grid, so classified from its neighbour) once per operand, and the result had a face twice
/// and three unbalanced edges. A sliver's coincident stack is now the sub-triangles over its
/// corners.
#[test]
fn boolean_keeps_a_sliver_of_a_coincident_stack_once() {
    checks::solids::check_case(&solids_case("sliver_in_a_coincident_stack"));
}

/// The same shells beside a slab that holds the cube: the three bottom faces lie in one plane,
/// each triangulated its own way, so a sliver of the stack (thinner than the f64 grid) had no
/// sub-triangle over its corners in the slab's face. The sliver was kept as if it were the
/// stack's lowest face, and the union had three unbalanced edges. A sliver's coincident faces
/// are now the input triangles of its plane that contain it, found exactly.
#[test]
fn boolean_keeps_a_sliver_of_a_stack_triangulated_differently_once() {
    checks::solids::check_case(&solids_case("sliver_triangulated_differently_in_a_stack"));
}

/// (A ∪ B) ∪ C: certification unfolded a face of the chained union by moving a vertex from
/// `y = 0` to `y = -5e-324`, and the validity report, whose collinearity test underflowed
/// there, called a face around it flat. The report now decides collinearity with the kernel's
/// exact orient2d, and re-rounding makes no coordinate newly subnormal.
#[test]
fn boolean_chained_through_a_file_has_no_collinear_face() {
    checks::solids::check_case(&solids_case("collinear_face_after_a_chain"));
}

/// A solid whose corner touches the inside of the other's face: the face's triangles around
/// that vertex were merged into one polygon (`--polygons`, `--quads`) without it, and the
/// faces at the vertex touched the polygon's interior (13 crossing pairs). The sides at such
/// a pinch now stay.
#[test]
fn boolean_keeps_a_pinch_vertex_as_a_corner_of_merged_faces() {
    checks::solids::check_case(&solids_case("solid_touching_a_polygon_inside"));
}

/// (A ∪ B) ∪ C written as quads: a quad of two certified triangles whose four corners are
/// not coplanar (three on the box's plane x = 8, one off it) was written from a corner off
/// their shared side, so readers that fan from the first corner (csgkit among them) took the
/// other diagonal, a triangle in that plane that overlapped the box's face there. A quad now
/// starts at a corner of the side its triangles share.
#[test]
fn boolean_writes_a_quad_fanned_across_its_shared_side() {
    checks::solids::check_case(&solids_case("quad_across_the_other_diagonal"));
}

/// (A ∪ B) ∪ C with C a cube of side 0.25 at the origin: A ∪ B has a face that is a sliver
/// (thinner than the f64 grid, two corners within 2e-18 of the origin) in the plane of C's
/// bottom face, whose triangles lie on all three of its edges. The winding
/// classification took a sliver's winding numbers only from a neighbour in its own input
/// triangle, and it has none. A sliver now takes them from a classified patch of its coincident
/// stack when its face has none.
#[test]
fn boolean_classifies_a_sliver_input_triangle_from_its_coincident_stack() {
    checks::solids::check_case(&solids_case("sliver_input_triangle_in_a_coplanar_stack"));
}

/// The same in another plane of the cube, with C two copies of it: two coincident faces of C
/// over the sliver.
#[test]
fn boolean_classifies_a_sliver_input_triangle_in_a_doubled_stack() {
    checks::solids::check_case(&solids_case(
        "sliver_input_triangle_in_a_doubled_coplanar_stack",
    ));
}

/// (A ∪ B) ∪ C: a face of A ∪ B in the plane of C's top face is cut by C's diagonal into a
/// sliver and a sub-triangle about 5e-19 wide near the origin, which holds f64 points, but the
/// sample candidates were built from the f64 approximation of its implicit corner, 40 times
/// too far from the origin, so neither had a sample point and the sliver no classified
/// neighbour. Patches with no sample from the approximations now try the corners rounded
/// correctly.
#[test]
fn boolean_samples_a_sub_triangle_near_the_origin_from_rounded_corners() {
    checks::solids::check_case(&solids_case("sliver_near_origin_with_an_implicit_corner"));
}

/// An OBJ group whose name ends in `\` once its comment is cut: written as it was, the name
/// joined the next line, a face, and the round trip lost it.
#[test]
fn obj_group_name_ending_in_a_backslash_round_trips() {
    checks::check_reader(
        &input("read_obj", "group_name_ending_in_backslash"),
        Format::Obj,
    );
}

/// The same found through the STL target (OBJ content wins over the hint).
#[test]
fn obj_content_in_an_stl_file_round_trips() {
    checks::check_reader(&input("read_stl", "obj_in_an_stl_file"), Format::Stl);
}

/// An OpenSCAD `cylinder` with radius 0 at both ends: its side faces had two corners and
/// building the leaf panicked. It is now no solid, as in OpenSCAD.
#[test]
fn openscad_cylinder_of_no_radius_is_empty() {
    checks::check_openscad_csg(&input("read_openscad_csg", "cylinder_of_no_radius"));
}

/// The same inside nested groups, with other arguments around it.
#[test]
fn openscad_cylinder_of_no_radius_in_groups_is_empty() {
    checks::check_openscad_csg(&input(
        "read_openscad_csg",
        "cylinder_of_no_radius_in_groups",
    ));
}

/// A polygon point written `666…e666…`: the literal parsed as an infinity, and the exact
/// predicates of the prism built from it were given a non-finite coordinate. Literals beyond
/// f64's range are now an error naming their line.
#[test]
fn openscad_number_beyond_f64_is_an_error() {
    checks::check_openscad_csg(&input("read_openscad_csg", "number_beyond_f64"));
}

/// `cylinder($fn = 2444…4)`: the fragment count saturated to 2³² − 1 and building the
/// cylinder asked for 64 GiB. A `$fn` or `slices` above 10 000 is now an error.
#[test]
fn openscad_huge_fragment_count_is_an_error() {
    checks::check_openscad_csg(&input("read_openscad_csg", "huge_fn"));
}

/// Every other input the `read_openscad_csg` run found (`other_*`), replayed: each reads, or
/// fails with an error naming its line.
#[test]
fn openscad_inputs_found_by_fuzzing_read_or_fail_cleanly() {
    let folder = crate::util::repo_data("fuzz/read_openscad_csg");
    let mut replayed = 0;
    for entry in std::fs::read_dir(&folder).expect("the fuzz inputs are in the repository") {
        let path = entry.expect("a readable folder").path();
        if path
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("other_"))
        {
            checks::check_openscad_csg(&std::fs::read(&path).expect("a readable input"));
            replayed += 1;
        }
    }
    assert!(
        replayed >= 20,
        "only {replayed} inputs in {}",
        folder.display()
    );
}

/// (A ∪ B) ∪ C written as polygons: a face of the result merged from two triangles had two
/// corners an ulp apart (intersection points that rounded to neighbours), and in the
/// polygon's own projection (its Newell normal's, where readers triangulate it) its sides
/// crossed, though the pieces are grown valid in the region's projection. A merged polygon
/// that the triangulator rejects is now written as its certified triangles.
#[test]
fn boolean_writes_no_polygon_crossing_itself_in_its_own_projection() {
    checks::solids::check_case(&solids_case(
        "polygon_crossing_itself_in_its_own_projection",
    ));
}

/// The same with two corners of a merged polygon at one point of its projection.
#[test]
fn boolean_writes_no_polygon_with_corners_projecting_together() {
    checks::solids::check_case(&solids_case("polygon_with_corners_projecting_together"));
}
