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
