//! The exact engine on operands that are not simple solids (`exact::winding`): faces that
//! cross each other, shells that overlap or nest, inward shells. Such an operand's interior is
//! where its winding number is non-zero ([`WindingRule::NonZero`], the default) or positive
//! ([`WindingRule::Positive`]); a union of that operand alone resolves it (`csgkit repair`).
//!
//! Every result must be certified ([`certified`]): a closed, oriented solid without a
//! degenerate face, free of self-intersections ([`self_intersections`]), with every snapped
//! vertex within the guaranteed bound of 2^-28 of the bounding-box diagonal.
//!
//! - Two overlapping icospheres as one mesh resolve to their union.
//! - Nested and inward shells of integer boxes, under both rules, with exact volumes.
//! - A self-intersecting operand in every position of 3-operand booleans, against a voxel
//!   count.
//! - The peers-harness cases csgkit used to refuse (dragon, Generic_Twin, self_intersectA/B):
//!   the volume identities against the operands resolved alone.
//! - `repair` of the shared meshes that intersect themselves.
//! - Random rigidly moved primitives (proptest), pairwise and chained.
//! - A chain of cylinder cuts whose every step goes through an OBJ file.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

use csgkit::exact::{Boolean, BooleanError, BooleanOptions, InvalidOperand, WindingRule, boolean};
use csgkit::primitives::{cuboid, cylinder, icosphere};
use csgkit::{Mesh, Operation, WriteOptions, read_mesh, self_intersections, write_mesh};
use num_rational::BigRational;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

use crate::util::{
    assert_close, bbox, diagonal, exact_volume, load, rotation, shared_data, transformed,
    translated,
};

use Operation::{Difference, Intersection, Union, Xor};

/// Relative tolerance of volume comparisons.
///
/// Decisions are exact; the output rounds each intersection point once to an f64 within 2.5
/// ulps and the certify stage may snap a vertex by at most 2^-28 of the bounding-box
/// diagonal (it almost never does). For the solids here that moves volumes by far less than
/// 1e-9 of the operands' volumes, while a misclassified patch or a lost shell moves them by
/// much more; exact_real.rs derives the same bound for real meshes.
const VOLUME_TOLERANCE: f64 = 1e-9;

/// The certified bound on a snapped vertex's displacement, relative to the diagonal of the
/// result's bounding box (certify.rs: `2^-29 · max |coordinate|` per coordinate).
const MAX_SNAP_DISPLACEMENT: f64 = 1.0 / (1u64 << 28) as f64;

fn volume(mesh: &Mesh) -> f64 {
    mesh.report().measures.volume
}

/// Asserts `mesh` is what the certify stage promises: closed and oriented, no degenerate face,
/// no two faces meeting except along shared edges and vertices.
fn assert_certified(mesh: &Mesh, what: &str) {
    let report = mesh.report();
    assert!(
        report.is_valid_solid(),
        "{what}: not a closed, oriented solid: {} unbalanced, {} boundary, {} misoriented edges",
        report.topology.unbalanced_edges,
        report.topology.boundary_edges,
        report.topology.misoriented_edges
    );
    assert_eq!(report.degenerate_faces, 0, "{what}: degenerate faces");
    let found = self_intersections(mesh);
    assert!(
        found.is_empty(),
        "{what}: {} self-intersecting pairs, first {:?}; invalid polygons {:?}",
        found.pair_count(),
        found.pairs.iter().take(5).collect::<Vec<_>>(),
        found.invalid_polygons
    );
}

/// Runs `op`, asserts the result is certified (see [`assert_certified`]) and within the snap
/// bound, prints the time, and returns it.
fn certified(what: &str, op: Operation, operands: &[&Mesh], options: &BooleanOptions) -> Boolean {
    let start = Instant::now();
    let result =
        boolean(op, operands, options).unwrap_or_else(|e| panic!("{what}: {op:?} failed: {e}"));
    let seconds = start.elapsed().as_secs_f64();
    assert_certified(&result.mesh, &format!("{what}: {op:?}"));
    let s = &result.stats;
    assert!(
        s.max_snap_displacement <= MAX_SNAP_DISPLACEMENT,
        "{what}: {op:?} snapped a vertex by {:e} of the diagonal",
        s.max_snap_displacement
    );
    eprintln!(
        "{what}: {op:?} in {seconds:.2} s (+{:.2} s checking): {} triangles, volume {}, \
         {} self-intersecting pairs, winding {}, {} snapped in {} rounds",
        start.elapsed().as_secs_f64() - seconds,
        result.mesh.face_count(),
        volume(&result.mesh),
        s.self_intersecting_pairs,
        s.winding_classification,
        s.snapped_vertices,
        s.certify_rounds
    );
    if seconds > 2.0 {
        eprintln!(
            "{what}: {op:?} is slow: {} candidate pairs, {} patches, stages {:?}",
            s.candidate_pairs, s.patches, s.stage_seconds
        );
    }
    result
}

fn with_rule(winding: WindingRule) -> BooleanOptions {
    BooleanOptions {
        winding,
        ..BooleanOptions::default()
    }
}

/// `mesh` resolved alone under `rule`: the union of it with nothing.
fn resolve(what: &str, mesh: &Mesh, rule: WindingRule) -> Boolean {
    certified(what, Union, &[mesh], &with_rule(rule))
}

/// The meshes as one: their vertices and faces concatenated, nothing welded or resolved.
fn one_mesh(parts: &[&Mesh]) -> Mesh {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for part in parts {
        let base = positions.len() as u32;
        positions.extend_from_slice(part.positions());
        triangles.extend(part.faces().map(|f| {
            assert_eq!(f.len(), 3, "primitives are triangle meshes");
            [f[0] + base, f[1] + base, f[2] + base]
        }));
    }
    Mesh::from_triangles(positions, &triangles).expect("indices are offset into the parts")
}

/// `mesh` with every triangle's orientation reversed.
fn reversed(mesh: &Mesh) -> Mesh {
    let triangles: Vec<[u32; 3]> = mesh.faces().map(|f| [f[0], f[2], f[1]]).collect();
    Mesh::from_triangles(mesh.positions().to_vec(), &triangles).expect("same indices")
}

/// A volume as an exact rational, for comparison with [`exact_volume`].
fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// Asserts the exact volume of `mesh` is `expected`.
fn assert_exact_volume(mesh: &Mesh, expected: f64, what: &str) {
    let exact = exact_volume(mesh);
    assert!(
        exact == rational(expected),
        "{what}: exact volume {exact} (f64 {}), expected {expected}",
        volume(mesh)
    );
    assert_eq!(volume(mesh), expected, "{what}: the f64 volume");
}

// 1. Overlapping spheres as one operand.

/// Two icospheres overlapping by about half their radius, written as one mesh: closed and
/// outward, but their faces cross. Resolved alone (both rules agree: the winding number is 1
/// or 2 inside), it is their union as separate operands, and the inclusion–exclusion identity
/// holds with their intersection.
#[test]
fn overlapping_icospheres_as_one_mesh_resolve_to_their_union() {
    let s1 = icosphere([0.0; 3], 1.0, 3);
    let s2 = icosphere([0.9, 0.35, -0.2], 0.8, 3);
    let both = one_mesh(&[&s1, &s2]);
    assert!(both.report().is_valid_solid(), "closed and oriented");
    assert!(!self_intersections(&both).is_empty(), "the spheres cross");
    let (v1, v2) = (volume(&s1), volume(&s2));
    let scale = v1 + v2;

    let union = volume(&certified("s1, s2", Union, &[&s1, &s2], &Default::default()).mesh);
    let intersection =
        volume(&certified("s1, s2", Intersection, &[&s1, &s2], &Default::default()).mesh);
    assert!(
        intersection > 0.1 * v2,
        "the spheres overlap: {intersection}"
    );
    for rule in [WindingRule::NonZero, WindingRule::Positive] {
        let resolved = resolve(&format!("s1 + s2 as one, {rule:?}"), &both, rule);
        let stats = &resolved.stats;
        assert!(stats.self_intersecting_pairs > 0, "{rule:?}: {stats:?}");
        assert!(stats.winding_classification, "{rule:?}: {stats:?}");
        let v = volume(&resolved.mesh);
        assert_close(
            v,
            union,
            VOLUME_TOLERANCE,
            scale,
            &format!("{rule:?}: resolved vs s1 ∪ s2"),
        );
        assert_close(
            v + intersection,
            v1 + v2,
            VOLUME_TOLERANCE,
            scale,
            &format!("{rule:?}: vol(resolved) + vol(s1 ∩ s2) vs vol(s1) + vol(s2)"),
        );
    }
}

// 2. Nested and inward shells.

/// The outer box `[0, 3]³` and the inner box `[1, 2]³` as one mesh.
fn nested(inner_outward: bool) -> Mesh {
    let outer = cuboid([0.0; 3], [3.0; 3]);
    let inner = cuboid([1.0; 3], [2.0; 3]);
    let inner = if inner_outward {
        inner
    } else {
        reversed(&inner)
    };
    one_mesh(&[&outer, &inner])
}

/// Both shells outward: the winding number is 2 in the inner box, 1 around it, so both rules
/// fill the outer box (27); minus the inner box as a separate operand, 26. The general path
/// ran (the shells nest, though no faces cross).
#[test]
fn nested_outward_shells_fill_the_outer_box() {
    let mesh = nested(true);
    let cube = cuboid([1.0; 3], [2.0; 3]);
    for rule in [WindingRule::NonZero, WindingRule::Positive] {
        let what = format!("nested outward, {rule:?}");
        let resolved = resolve(&what, &mesh, rule);
        assert_exact_volume(&resolved.mesh, 27.0, &what);
        assert!(resolved.stats.winding_classification, "{what}");
        assert_eq!(resolved.stats.self_intersecting_pairs, 0, "{what}");

        let minus = certified(&what, Difference, &[&mesh, &cube], &with_rule(rule));
        assert_exact_volume(&minus.mesh, 26.0, &format!("{what} − [1, 2]³"));
        assert!(minus.stats.winding_classification, "{what}");
        let report = minus.mesh.report();
        assert_eq!(
            report.topology.components, 2,
            "{what}: a hollow box has two shells"
        );
    }
}

/// The inner box reversed: a hollow box, winding number 0 inside the cavity, 26 under both
/// rules. Every shell has winding number 0 in front and 1 behind, so the operand is a simple
/// solid (with a cavity) and the local-test path runs, not the winding classification.
#[test]
fn nested_inward_shell_is_a_cavity() {
    let mesh = nested(false);
    assert_eq!(volume(&mesh), 26.0, "the input's signed volume");
    for rule in [WindingRule::NonZero, WindingRule::Positive] {
        let what = format!("hollow box, {rule:?}");
        let resolved = resolve(&what, &mesh, rule);
        assert_exact_volume(&resolved.mesh, 26.0, &what);
        assert!(!resolved.stats.winding_classification, "{what}");
        assert_eq!(resolved.mesh.report().topology.components, 2, "{what}");
    }
}

/// An outward unit cube and an inward unit cube far from it: the signed volume is 0, which
/// ingest accepts. The inward cube has winding number −1 inside, so it is solid under the
/// non-zero rule (the result has two outward cubes, 2) and empty under the positive rule (1).
#[test]
fn separate_inward_shell_depends_on_the_rule() {
    let mesh = one_mesh(&[
        &cuboid([0.0; 3], [1.0; 3]),
        &reversed(&cuboid([5.0, 0.0, 0.0], [6.0, 1.0, 1.0])),
    ]);
    assert_eq!(volume(&mesh), 0.0);
    for (rule, expected) in [(WindingRule::NonZero, 2.0), (WindingRule::Positive, 1.0)] {
        let what = format!("outward + inward cube, {rule:?}");
        let resolved = resolve(&what, &mesh, rule);
        assert_exact_volume(&resolved.mesh, expected, &what);
        assert!(resolved.stats.winding_classification, "{what}");
        assert_eq!(
            resolved.mesh.report().topology.components,
            expected as usize,
            "{what}: components"
        );
    }
}

/// A plain cube alone is a simple solid: the local-test path runs, and it comes back as is.
#[test]
fn a_simple_cube_keeps_the_local_path() {
    let cube = cuboid([0.0; 3], [1.0; 3]);
    for rule in [WindingRule::NonZero, WindingRule::Positive] {
        let resolved = resolve("cube", &cube, rule);
        assert!(!resolved.stats.winding_classification, "{rule:?}");
        assert_eq!(resolved.stats.self_intersecting_pairs, 0, "{rule:?}");
        assert_exact_volume(&resolved.mesh, 1.0, "cube");
        assert_eq!(resolved.mesh.face_count(), 12, "{rule:?}");
    }
}

// 3. A self-intersecting operand among others.

/// An axis-aligned box `[min, max]` on the quarter-unit lattice.
type Block = ([f64; 3], [f64; 3]);

/// Two unit cubes offset by 0.5 along every axis, as one mesh: 1.875 when resolved.
const CROSSING: [Block; 2] = [([0.0; 3], [1.0; 3]), ([0.5; 3], [1.5; 3])];
/// Two boxes that cut through [`CROSSING`] and through each other.
const SLAB: Block = ([0.25, -0.5, 0.25], [0.75, 2.0, 1.25]);
const PLATE: Block = ([-0.25, 0.25, 0.75], [1.25, 1.25, 1.75]);

/// The volume of `op` on operands that are each a union of blocks, by counting the cells of
/// the quarter-unit lattice (every block's faces lie on it, so each cell is wholly in or out).
fn cell_volume(op: Operation, operands: &[&[Block]]) -> f64 {
    let q = |x: f64| (x * 4.0) as i32;
    let cell = |i: i32| f64::from(i) * 0.25 + 0.125;
    let mut count = 0u32;
    for x in q(-1.0)..q(2.5) {
        for y in q(-1.0)..q(2.5) {
            for z in q(-1.0)..q(2.5) {
                let c = [cell(x), cell(y), cell(z)];
                let in_block = |(min, max): &Block| (0..3).all(|i| min[i] < c[i] && c[i] < max[i]);
                let inside = operands.iter().map(|blocks| blocks.iter().any(in_block));
                count += u32::from(op.contains(inside));
            }
        }
    }
    f64::from(count) / 64.0
}

/// The crossing cubes in each position of a 3-operand union, intersection and difference
/// with two boxes: exact volumes, equal to the lattice count.
#[test]
fn self_intersecting_operand_in_every_position() {
    let block = |(min, max): &Block| cuboid(*min, *max);
    let crossing = one_mesh(&[&block(&CROSSING[0]), &block(&CROSSING[1])]);
    assert!(!self_intersections(&crossing).is_empty());
    assert_exact_volume(
        &resolve("crossing cubes", &crossing, WindingRule::NonZero).mesh,
        1.875,
        "crossing cubes resolved",
    );
    let (slab, plate) = (block(&SLAB), block(&PLATE));
    let meshes: [(&Mesh, &[Block]); 3] =
        [(&crossing, &CROSSING), (&slab, &[SLAB]), (&plate, &[PLATE])];
    // Each rotation puts the crossing cubes first, second and third.
    for shift in 0..3 {
        let order: Vec<usize> = (0..3).map(|i| (i + 3 - shift) % 3).collect();
        let operands: Vec<&Mesh> = order.iter().map(|&i| meshes[i].0).collect();
        let blocks: Vec<&[Block]> = order.iter().map(|&i| meshes[i].1).collect();
        for op in Operation::ALL {
            let what = format!("crossing cubes at position {shift}");
            let expected = cell_volume(op, &blocks);
            let result = certified(&what, op, &operands, &Default::default());
            assert!(result.stats.self_intersecting_pairs > 0, "{what}: {op:?}");
            assert!(result.stats.winding_classification, "{what}: {op:?}");
            assert!(expected > 0.0, "{what}: {op:?} is not empty");
            assert_exact_volume(&result.mesh, expected, &format!("{what}: {op:?}"));
        }
    }
}

// 4. The peers-harness cases.

/// The volume of a shared mesh resolved alone (certified), computed once per test run for
/// all the tests that need it (the cases below and `repair` share several meshes).
fn resolved_volume(data: &Path, name: &'static str) -> f64 {
    type Slot = Arc<OnceLock<f64>>;
    static CACHE: Mutex<BTreeMap<&'static str, Slot>> = Mutex::new(BTreeMap::new());
    let cell = {
        let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
        Arc::clone(cache.entry(name).or_default())
    };
    *cell.get_or_init(|| {
        let mesh = load(data, name);
        let before = volume(&mesh);
        let start = Instant::now();
        let result = resolve(&format!("{name} resolved"), &mesh, WindingRule::NonZero);
        let after = volume(&result.mesh);
        eprintln!(
            "{name}: repaired in {:.2} s, volume {before} before, {after} after; {} triangles \
             in, {} out, {} self-intersecting pairs",
            start.elapsed().as_secs_f64(),
            mesh.face_count(),
            result.mesh.face_count(),
            result.stats.self_intersecting_pairs
        );
        after
    })
}

/// Computes `a ∪ b`, `a ∩ b` and, for a difference case, `a − b`; asserts each is certified and
/// the identities hold against `ra` and `rb`, the volumes of the operands resolved alone.
fn check_case(what: &str, a: &Mesh, b: &Mesh, ra: f64, rb: f64, difference: bool) {
    let start = Instant::now();
    let options = BooleanOptions::default();
    let union = volume(&certified(what, Union, &[a, b], &options).mesh);
    let intersection = volume(&certified(what, Intersection, &[a, b], &options).mesh);
    let scale = ra.abs() + rb.abs();
    assert_close(
        union + intersection,
        ra + rb,
        VOLUME_TOLERANCE,
        scale,
        &format!("{what}: vol(A∪B) + vol(A∩B) vs vol(res A) + vol(res B)"),
    );
    assert!(intersection > 0.0, "{what}: the operands overlap");
    if difference {
        let minus = volume(&certified(what, Difference, &[a, b], &options).mesh);
        assert_close(
            minus,
            ra - intersection,
            VOLUME_TOLERANCE,
            ra.abs(),
            &format!("{what}: vol(A−B) vs vol(res A) − vol(A∩B)"),
        );
        assert!(minus > 0.0, "{what}: the difference is not empty");
    }
    eprintln!(
        "{what}: identities hold in {:.2} s (∪ {union}, ∩ {intersection}, res A {ra}, res B {rb})",
        start.elapsed().as_secs_f64()
    );
}

/// The dragon (27 self-intersecting pairs) ∪ a cylinder along z through its body, sticking
/// out 10% of the depth on each side (as exact_real.rs's armadillo ∪ cylinder).
#[test]
fn dragon_union_cylinder() {
    let Some(data) = shared_data() else { return };
    let dragon = load(&data, "dragon.obj");
    let b = bbox(&dragon);
    let centre = b.center();
    let depth = b.max[2] - b.min[2];
    let radius = 0.08 * (b.max[0] - b.min[0]);
    let base = [centre[0], centre[1], b.min[2] - 0.1 * depth];
    let c = cylinder(base, radius, 1.2 * depth, 96);
    let ra = resolved_volume(&data, "dragon.obj");
    let rc = volume(&c);
    check_case("dragon, cylinder", &dragon, &c, ra, rc, false);
}

/// The dragon minus a copy shifted by 3% of its diagonal along (2, 3, 6) / 7 (as
/// exact_real.rs's bunny − shifted copy): both operands intersect themselves.
#[test]
fn dragon_minus_shifted_copy() {
    let Some(data) = shared_data() else { return };
    let dragon = load(&data, "dragon.obj");
    let step = 0.03 * diagonal(&bbox(&dragon)) / 7.0;
    let shifted = translated(&dragon, [2.0 * step, 3.0 * step, 6.0 * step]);
    let ra = resolved_volume(&data, "dragon.obj");
    let rb = volume(&resolve("shifted dragon", &shifted, WindingRule::NonZero).mesh);
    check_case("dragon, shifted dragon", &dragon, &shifted, ra, rb, true);
}

const TWIN_LEFT: &str = "Generic_Twin_7081.1.t0_left.obj";
const TWIN_RIGHT: &str = "Generic_Twin_7081.1.t0_right.obj";

/// manifold's GenericTwinBooleanTest7081 as a difference: left (3 self-intersecting pairs)
/// minus right (64). The checked booleans resolve both: each operand's interior is where its
/// winding number is non-zero, and the union, intersection and difference are certified
/// solids whose volumes agree with the operands resolved alone.
#[test]
fn generic_twin_left_minus_right() {
    let Some(data) = shared_data() else { return };
    for name in [TWIN_LEFT, TWIN_RIGHT] {
        let pairs = manifest_count(&data, name, "selfint_pairs");
        assert!(
            pairs > 0,
            "{name}: the manifest counts its self-intersections"
        );
    }
    let (left, right) = (load(&data, TWIN_LEFT), load(&data, TWIN_RIGHT));
    let (ra, rb) = (
        resolved_volume(&data, TWIN_LEFT),
        resolved_volume(&data, TWIN_RIGHT),
    );
    check_case("Generic_Twin left, right", &left, &right, ra, rb, true);
}

/// self_intersectA ∪ self_intersectB (338 self-intersecting pairs each).
#[test]
fn self_intersect_a_union_b() {
    let Some(data) = shared_data() else { return };
    let (a, b) = (
        load(&data, "self_intersectA.obj"),
        load(&data, "self_intersectB.obj"),
    );
    let (ra, rb) = (
        resolved_volume(&data, "self_intersectA.obj"),
        resolved_volume(&data, "self_intersectB.obj"),
    );
    check_case("self_intersectA, self_intersectB", &a, &b, ra, rb, false);
}

// 5. Repair of shared meshes.

/// `repair` (the union of one operand) of the shared meshes that intersect themselves: every
/// result is certified (see [`resolved_volume`], which prints the volumes and times).
#[test]
fn repair_shared_meshes() {
    let Some(data) = shared_data() else { return };
    for name in ["cow.obj", "block.obj", "self_intersectA.obj", TWIN_LEFT] {
        let after = resolved_volume(&data, name);
        assert!(after > 0.0, "{name}: the repaired solid has volume");
    }
}

/// The manifest's `measured.<key>` of `name`, a count.
fn manifest_count(data: &Path, name: &str, key: &str) -> u64 {
    let text =
        std::fs::read_to_string(data.join("manifest.json")).expect("manifest.json is readable");
    let json: serde_json::Value = serde_json::from_str(&text).expect("manifest.json is JSON");
    let entry = (json["meshes"]
        .as_array()
        .expect("manifest lists meshes")
        .iter())
    .find(|m| m["measured"]["file"].as_str() == Some(name))
    .unwrap_or_else(|| panic!("{name} is not in manifest.json"));
    (entry["measured"][key].as_u64()).unwrap_or_else(|| panic!("{name}: measured.{key}"))
}

/// two-boxes-bad-self-union.ply is not closed even after welding (the manifest counts 80
/// boundary edges in 10 loops: another tool's union left T-junctions), so it bounds no
/// solid and `repair` refuses it, naming operand 0 and its unbalanced edges, rather than
/// guess. (Resolving crossings does not close holes.)
#[test]
fn repair_refuses_the_open_two_boxes() {
    let Some(data) = shared_data() else { return };
    let name = "two-boxes-bad-self-union.ply";
    let mesh = load(&data, name);
    let boundary = manifest_count(&data, name, "boundary_e");
    assert!(boundary > 0, "the manifest says {name} is open");
    match boolean(Union, &[&mesh], &BooleanOptions::default()) {
        Err(BooleanError::InvalidOperand(InvalidOperand::NotClosed {
            operand,
            count,
            first,
        })) => {
            assert_eq!(operand, 0);
            assert_eq!(
                count as u64, boundary,
                "unbalanced edges vs the manifest's boundary"
            );
            assert!(!first.is_empty(), "the error lists edges");
        }
        Err(e) => panic!("{name}: expected NotClosed, got {e:?}"),
        Ok(r) => panic!(
            "{name}: repaired an open mesh into {} triangles",
            r.mesh.face_count()
        ),
    }
}

/// openscad-nonmanifold-crash.obj (the mesh that crashed OpenSCAD): closed after welding but
/// with 18 non-manifold edges, 3 duplicate faces, a zero-area face and 7518 crossing pairs.
/// `repair` resolves it (Ok): the result is certified, found by winding numbers, and some
/// rounded vertices had to be snapped. It is the slowest repair here (about 19 s in release
/// on 2 cores, in the split and classify stages).
#[test]
fn repair_resolves_the_openscad_crash_mesh() {
    let Some(data) = shared_data() else { return };
    let mesh = load(&data, "openscad-nonmanifold-crash.obj");
    let before = volume(&mesh);
    let result = resolve(
        "openscad-nonmanifold-crash.obj",
        &mesh,
        WindingRule::NonZero,
    );
    let after = volume(&result.mesh);
    eprintln!("openscad-nonmanifold-crash.obj: volume {before} before, {after} after");
    let stats = &result.stats;
    assert!(stats.winding_classification, "{stats:?}");
    assert!(stats.self_intersecting_pairs > 0, "{stats:?}");
    assert!(
        after > 0.0 && after < before,
        "overlaps counted once: {after} vs {before}"
    );
}

// 6. Random rigidly moved primitives.

/// Few cases (each runs several booleans and checks), a fixed seed so a failure reproduces on
/// every run, and no regression files in the source tree (as exact_props.rs).
fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x0057_1d17),
        failure_persistence: None,
        max_shrink_iters: 256,
        ..Config::default()
    }
}

/// A random primitive, kept as its parameters so a failing case prints readably; every one is
/// centred near the origin and then turned by `angle` about `axis` and moved by `centre`.
#[derive(Clone, Debug)]
enum Primitive {
    Cylinder {
        radius: f64,
        height: f64,
        segments: u32,
    },
    Sphere {
        radius: f64,
        subdivisions: u32,
    },
    Cuboid {
        half: [f64; 3],
    },
}

#[derive(Clone, Debug)]
struct Placed {
    primitive: Primitive,
    axis: [f64; 3],
    angle: f64,
    centre: [f64; 3],
}

impl Placed {
    fn mesh(&self) -> Mesh {
        let local = match self.primitive {
            Primitive::Cylinder {
                radius,
                height,
                segments,
            } => cylinder([0.0, 0.0, -height / 2.0], radius, height, segments),
            Primitive::Sphere {
                radius,
                subdivisions,
            } => icosphere([0.0; 3], radius, subdivisions),
            Primitive::Cuboid { half } => cuboid(half.map(|h| -h), half),
        };
        transformed(&local, &rotation(self.axis, self.angle), self.centre)
    }
}

/// A rotation axis of length at least 0.1 (normalised by [`rotation`]).
fn axis() -> impl Strategy<Value = [f64; 3]> {
    proptest::array::uniform3(-1.0..1.0f64).prop_filter("axis of a reasonable length", |a| {
        a.iter().map(|x| x * x).sum::<f64>() > 0.01
    })
}

fn placed() -> impl Strategy<Value = Placed> {
    let primitive = prop_oneof![
        (0.3..1.2f64, 0.5..3.0f64, 3u32..=40).prop_map(|(radius, height, segments)| {
            Primitive::Cylinder {
                radius,
                height,
                segments,
            }
        }),
        (0.4..1.5f64, 0u32..=2).prop_map(|(radius, subdivisions)| Primitive::Sphere {
            radius,
            subdivisions
        }),
        proptest::array::uniform3(0.2..1.2f64).prop_map(|half| Primitive::Cuboid { half }),
    ];
    (
        primitive,
        axis(),
        0.0..std::f64::consts::TAU,
        proptest::array::uniform3(-1.0..1.0f64),
    )
        .prop_map(|(primitive, axis, angle, centre)| Placed {
            primitive,
            axis,
            angle,
            centre,
        })
}

/// Intersections are rarer, so a chain seldom shrinks to nothing.
fn operation() -> impl Strategy<Value = Operation> {
    prop_oneof![2 => Just(Union), 1 => Just(Intersection), 2 => Just(Difference)]
}

proptest! {
    #![proptest_config(config(16))]

    /// Every result is certified and the identities hold.
    #[test]
    fn random_primitives_pairwise(a in placed(), b in placed()) {
        let (a, b) = (a.mesh(), b.mesh());
        let (va, vb) = (volume(&a), volume(&b));
        let options = BooleanOptions::default();
        let union = volume(&certified("pair", Union, &[&a, &b], &options).mesh);
        let intersection = volume(&certified("pair", Intersection, &[&a, &b], &options).mesh);
        let difference = volume(&certified("pair", Difference, &[&a, &b], &options).mesh);
        let xor = volume(&certified("pair", Xor, &[&a, &b], &options).mesh);
        let scale = va + vb;
        assert_close(union + intersection, va + vb, VOLUME_TOLERANCE, scale, "vol(A∪B) + vol(A∩B) vs vol(A) + vol(B)");
        assert_close(difference, va - intersection, VOLUME_TOLERANCE, scale, "vol(A−B) vs vol(A) − vol(A∩B)");
        assert_close(xor, va + vb - 2.0 * intersection, VOLUME_TOLERANCE, scale, "vol(A⊕B) vs vol(A) + vol(B) − 2 vol(A∩B)");
    }

    /// Six steps, each combining the previous result with a new primitive: every result is a
    /// certified operand of the next step, and its volume is in range.
    #[test]
    fn random_primitives_chained(
        first in placed(),
        steps in proptest::collection::vec((operation(), placed()), 6),
    ) {
        let mut current = first.mesh();
        for (i, (op, next)) in steps.iter().enumerate() {
            let next = next.mesh();
            let (before, other) = (volume(&current), volume(&next));
            let what = format!("step {i}");
            current = certified(&what, *op, &[&current, &next], &Default::default()).mesh;
            let after = volume(&current);
            let slack = VOLUME_TOLERANCE * (before + other);
            let in_range = match op {
                Union => after >= before.max(other) - slack && after <= before + other + slack,
                Intersection => after >= -slack && after <= before.min(other) + slack,
                Difference => after >= -slack && after <= before + slack,
                Xor => after >= -slack && after <= before + other + slack,
            };
            assert!(in_range, "{what}: {op:?} of {before} and {other} gave {after}");
        }
    }
}

// 7. A chain of cuts through files.

/// splitmix64: a fixed-seed stream of uniform numbers for the file chain, outside proptest.
struct SplitMix(u64);

impl SplitMix {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }
}

/// `count` cylinders of radius 0.2 and length 3.5 with [`DRILL_SIDES`] sides, each centred at
/// a random point of `[-0.6, 0.6]³` along a random axis: each goes through the cube
/// `[-1, 1]³` and out.
fn drills(count: usize) -> Vec<Mesh> {
    let mut rng = SplitMix(0x5eed_c4a1_2025);
    let local = cylinder([0.0, 0.0, -1.75], 0.2, 3.5, DRILL_SIDES);
    (0..count)
        .map(|_| {
            let centre = [(); 3].map(|()| rng.uniform(-0.6, 0.6));
            let axis = loop {
                let a = [(); 3].map(|()| rng.uniform(-1.0, 1.0));
                if a.iter().map(|x| x * x).sum::<f64>() > 0.01 {
                    break a;
                }
            };
            let angle = rng.uniform(0.0, std::f64::consts::TAU);
            transformed(&local, &rotation(axis, angle), centre)
        })
        .collect()
}

/// Steps of [`cuts_through_files_match_one_n_ary_difference`].
const FILE_CHAIN_STEPS: usize = 30;

/// Sides of each drill: fewer than the 48 of `scripts/chain_peers.py` (which runs 40 steps
/// of those), so the 30 steps, whose triangle count grows with every cut, fit in the test
/// suite's time.
const DRILL_SIDES: u32 = 16;

/// The cube `[-1, 1]³` minus drills one at a time, each result written to an OBJ file and
/// read back as the next step's operand: every step's output is certified, and the final
/// volume equals that of one n-ary difference of the cube minus all drills at once.
///
/// OBJ keeps every f64 (asserted), so the files change nothing; they are the path a user's
/// chain of commands takes. With `CSGKIT_KEEP_FAILED=<dir>`, a failing step's two operands are
/// written there as `current.obj` and `drill.obj`.
#[test]
fn cuts_through_files_match_one_n_ary_difference() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let cube = cuboid([-1.0; 3], [1.0; 3]);
    let drills = drills(FILE_CHAIN_STEPS);
    let start = Instant::now();
    let mut current = cube.clone();
    for (i, drill) in drills.iter().enumerate() {
        let what = format!("file chain step {i}");
        let step = Instant::now();
        let result = boolean(Difference, &[&current, drill], &BooleanOptions::default());
        if let (Err(_), Some(keep)) = (&result, std::env::var_os("CSGKIT_KEEP_FAILED")) {
            for (name, mesh) in [("current.obj", &current), ("drill.obj", drill)] {
                let path = Path::new(&keep).join(name);
                write_mesh(&path, mesh, WriteOptions::default())
                    .unwrap_or_else(|e| panic!("{what}: keeping the operands: {e}"));
            }
        }
        let result = result.unwrap_or_else(|e| panic!("{what} failed: {e:?}"));
        let s = &result.stats;
        eprintln!(
            "{what}: {:.2} s, {} triangles, {} rounded, {} snapped in {} rounds, {} slivers \
             dissolved (max {:e})",
            step.elapsed().as_secs_f64(),
            result.mesh.face_count(),
            s.rounded_vertices,
            s.snapped_vertices,
            s.certify_rounds,
            s.dissolved_slivers,
            s.max_snap_displacement
        );
        assert_certified(&result.mesh, &what);
        let path = dir.path().join(format!("step{i}.obj"));
        write_mesh(&path, &result.mesh, WriteOptions::default())
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        current = read_mesh(&path)
            .unwrap_or_else(|e| panic!("{what}: {e}"))
            .mesh;
        assert_eq!(
            current.positions(),
            result.mesh.positions(),
            "{what}: OBJ round-trips f64"
        );
    }
    let chained = volume(&current);
    eprintln!(
        "file chain: {FILE_CHAIN_STEPS} steps in {:.2} s, volume {chained}",
        start.elapsed().as_secs_f64()
    );
    let mut operands: Vec<&Mesh> = vec![&cube];
    operands.extend(drills.iter());
    let at_once = volume(
        &certified(
            "n-ary difference",
            Difference,
            &operands,
            &Default::default(),
        )
        .mesh,
    );
    assert_close(
        chained,
        at_once,
        VOLUME_TOLERANCE,
        volume(&cube),
        "chained vs n-ary difference",
    );
    assert!(chained > 0.0 && chained < 8.0, "{chained}");
}
