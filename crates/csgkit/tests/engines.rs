//! The engine facade: every engine through one interface, on one table of cases; progress
//! reports stage by stage; cancellation from inside a long stage of each engine.

use std::sync::Mutex;

use csgkit::primitives::{cuboid, icosphere};
use csgkit::{
    DiscreteEngine, DiscreteSurface, Engine, Error, ExactEngine, Mesh, Operation, OrthoEngine,
    Progress, Report, Stage, Stats,
};

use crate::util::box_of_quads;

/// An operation of an engine on `operands`, checked to be a closed, oriented solid; its
/// volume.
fn volume_of(engine: &dyn Engine, op: Operation, operands: &[&Mesh]) -> f64 {
    let what = format!("{} {}", engine.name(), op.name());
    let output = (engine.apply(op, operands, &Progress::default()))
        .unwrap_or_else(|e| panic!("{what} failed: {e}"));
    let report = output.mesh.report();
    assert!(report.is_valid_solid(), "{what}: {report:?}");
    report.measures.volume
}

/// Cubes on the half-unit grid, so every engine is exact on them: (name, operands, expected
/// volume of ∪, ∩, −, ⊕).
fn cases() -> Vec<(&'static str, Vec<Mesh>, [f64; 4])> {
    vec![
        (
            "overlapping",
            vec![cuboid([0.0; 3], [2.0; 3]), cuboid([1.0; 3], [3.0; 3])],
            [15.0, 1.0, 7.0, 14.0],
        ),
        (
            "touching",
            vec![
                cuboid([0.0; 3], [1.0; 3]),
                cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
            ],
            [2.0, 0.0, 1.0, 2.0],
        ),
        (
            "coplanar",
            vec![
                cuboid([0.0; 3], [2.0; 3]),
                cuboid([1.0, 0.0, 0.0], [3.0, 2.0, 2.0]),
            ],
            [12.0, 4.0, 4.0, 8.0],
        ),
        (
            "three in a row",
            vec![
                cuboid([0.0; 3], [1.0; 3]),
                cuboid([0.5, 0.0, 0.0], [1.5, 1.0, 1.0]),
                cuboid([0.25, 0.0, 0.0], [1.25, 1.0, 1.0]),
            ],
            [1.5, 0.5, 0.25, 1.0],
        ),
    ]
}

/// The exact and discrete engines compute every operation; the orthogonal engine the unions.
#[test]
fn every_engine_computes_the_table() {
    let exact = ExactEngine::default();
    let discrete = DiscreteEngine::with_cell(0.25);
    let ortho = OrthoEngine::default();
    for (name, meshes, expected) in cases() {
        let operands: Vec<&Mesh> = meshes.iter().collect();
        for (op, want) in Operation::ALL.into_iter().zip(expected) {
            for engine in [&exact as &dyn Engine, &discrete] {
                let got = volume_of(engine, op, &operands);
                assert_eq!(got, want, "{name}: {} {op:?}", engine.name());
            }
        }
        let union = volume_of(&ortho, Operation::Union, &operands);
        assert_eq!(union, expected[0], "{name}: ortho union");
    }
}

/// Each engine's statistics, with the seconds of the stages it ran.
#[test]
fn outputs_carry_each_engines_stats() {
    let (a, b) = (cuboid([0.0; 3], [2.0; 3]), cuboid([1.0; 3], [3.0; 3]));
    let run = |engine: &dyn Engine| {
        let output = engine.apply(Operation::Union, &[&a, &b], &Progress::default());
        output.unwrap().stats
    };
    let stages =
        |stats: &Stats| -> Vec<Stage> { stats.stage_seconds().iter().map(|s| s.0).collect() };
    let exact = run(&ExactEngine::default());
    let Stats::Exact(s) = &exact else {
        panic!("{exact:?}")
    };
    assert_eq!(s.input_triangles, 24);
    assert!(stages(&exact).contains(&Stage::Certify));
    let ortho = run(&OrthoEngine::default());
    let Stats::Ortho(s) = &ortho else {
        panic!("{ortho:?}")
    };
    assert_eq!(s.boxes, 2);
    let want = [Stage::Rank, Stage::Sweep, Stage::Loops, Stage::Triangulate];
    assert_eq!(stages(&ortho), want);
    let discrete = run(&DiscreteEngine {
        surface: DiscreteSurface::Surfels,
        ..DiscreteEngine::with_cell(0.5)
    });
    let Stats::Discrete(s) = &discrete else {
        panic!("{discrete:?}")
    };
    assert_eq!(s.operand_voxels, [64, 64]);
    assert_eq!(s.voxels, 120);
    let want = [Stage::Discretize, Stage::Combine, Stage::Convert];
    assert_eq!(stages(&discrete), want);
}

/// Plain boxes among the operands of a union or a difference are united by the orthogonal
/// engine before the exact engine runs: a Menger sponge of level 2 (a cube minus 30 bars)
/// has volume 400 = 20² and its stages start with the orthogonal ones; the exact engine's
/// own n-ary arrangement (`exact::boolean`, no routing) gives the same volume; painted boxes
/// are not routed.
#[test]
fn the_exact_engine_unites_plain_boxes_first() {
    // The bars of levels 1 and 2 through the whole cube [0, 9]³, along each axis.
    let mut bars = Vec::new();
    for step in [3.0, 1.0] {
        for a in (0..9).map(f64::from).filter(|a| a % (3.0 * step) == step) {
            for b in (0..9).map(f64::from).filter(|b| (b % (3.0 * step)) == step) {
                for axis in 0..3 {
                    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                    let mut min = [0.0; 3];
                    let mut max = [9.0; 3];
                    (min[u], max[u], min[v], max[v]) = (a, a + step, b, b + step);
                    bars.push(cuboid(min, max));
                }
            }
        }
    }
    let cube = cuboid([0.0; 3], [9.0; 3]);
    let operands: Vec<&Mesh> = std::iter::once(&cube).chain(&bars).collect();
    let output = (ExactEngine::default())
        .apply(Operation::Difference, &operands, &Progress::default())
        .unwrap();
    let report = output.mesh.report();
    assert!(report.is_valid_solid(), "{report:?}");
    assert_eq!(report.measures.volume, 400.0);
    let direct = csgkit::exact::boolean(
        Operation::Difference,
        &operands,
        &csgkit::exact::BooleanOptions::default(),
    )
    .unwrap();
    assert_eq!(report.measures.volume, direct.mesh.report().measures.volume);
    let Stats::Exact(stats) = output.stats else {
        panic!("the exact engine's stats")
    };
    assert_eq!(stats.stage_seconds[0].0, Stage::Rank, "{stats:?}");
    // A painted box keeps its own faces: no routing with fewer than three plain boxes.
    let painted = box_of_quads([3.0, 3.0, -1.0], [6.0, 6.0, 10.0], ["a", "b", "c"]);
    let two_plain: Vec<&Mesh> = [&cube, &painted, &bars[0], &bars[1]].into();
    let output = (ExactEngine::default())
        .apply(Operation::Difference, &two_plain, &Progress::default())
        .unwrap();
    let Stats::Exact(stats) = output.stats else {
        panic!("the exact engine's stats")
    };
    assert_ne!(stats.stage_seconds[0].0, Stage::Rank, "{stats:?}");
}

#[test]
fn the_orthogonal_engine_takes_unions_of_boxes_only() {
    let ortho = OrthoEngine::default();
    let (a, b) = (cuboid([0.0; 3], [2.0; 3]), cuboid([1.0; 3], [3.0; 3]));
    let err = ortho.apply(Operation::Difference, &[&a, &b], &Progress::default());
    assert_eq!(
        err.unwrap_err().to_string(),
        "the ortho engine computes unions only, not the difference"
    );
    let sphere = icosphere([0.0; 3], 1.0, 1);
    let err = ortho.apply(Operation::Union, &[&a, &sphere], &Progress::default());
    assert_eq!(
        err.unwrap_err().to_string(),
        "the ortho engine takes boxes only: operand 1 is not an axis-aligned box"
    );
    // An open box, and an inward one, bound no box.
    let open = Mesh::from_triangles(a.positions().to_vec(), &triangles(&a)[2..]).unwrap();
    let inward: Vec<[u32; 3]> = triangles(&a).iter().map(|t| [t[0], t[2], t[1]]).collect();
    let inward = Mesh::from_triangles(a.positions().to_vec(), &inward).unwrap();
    for not_a_box in [open, inward] {
        let err = ortho.apply(Operation::Union, &[&not_a_box], &Progress::default());
        assert!(matches!(err, Err(Error::Unsupported { .. })), "{err:?}");
    }
    // Any outward tessellation of a box is a box; an empty mesh is the empty set.
    let quads = box_of_quads([1.0; 3], [3.0; 3], ["a", "b", "c"]);
    let volume = volume_of(&ortho, Operation::Union, &[&a, &quads, &Mesh::new()]);
    assert_eq!(volume, 15.0);
}

fn triangles(mesh: &Mesh) -> Vec<[u32; 3]> {
    mesh.faces().map(|f| [f[0], f[1], f[2]]).collect()
}

#[test]
fn the_discrete_engine_needs_a_cell_per_operand_or_one() {
    let (a, b, c) = (
        cuboid([0.0; 3], [2.0; 3]),
        cuboid([1.0; 3], [3.0; 3]),
        cuboid([2.0; 3], [4.0; 3]),
    );
    let engine = DiscreteEngine {
        cells: vec![1.0, 0.5],
        ..DiscreteEngine::with_cell(1.0)
    };
    assert_eq!(volume_of(&engine, Operation::Intersection, &[&a, &b]), 1.0);
    let err = engine.apply(Operation::Union, &[&a, &b, &c], &Progress::default());
    assert_eq!(
        err.unwrap_err().to_string(),
        "the discrete engine needs one cell size or one per operand, not 2 for 3 operands"
    );
    let uneven = DiscreteEngine {
        cells: vec![1.0, 0.3],
        ..DiscreteEngine::with_cell(1.0)
    };
    let err = uneven.apply(Operation::Union, &[&a, &b], &Progress::default());
    assert!(matches!(err, Err(Error::Grid(_))), "{err:?}");
}

/// Every report of a run, in the order received.
fn reports_of(engine: &dyn Engine, operands: &[&Mesh]) -> Vec<Report> {
    let seen = Mutex::new(Vec::new());
    let record = |report: Report| {
        seen.lock().unwrap().push(report);
        true
    };
    let output = engine.apply(Operation::Union, operands, &Progress::new(&record));
    output.unwrap_or_else(|e| panic!("{}: {e}", engine.name()));
    seen.into_inner().unwrap()
}

/// Stages come in pipeline order, each counting up to `done == total`.
#[test]
fn stages_are_reported_in_order_and_end_done() {
    let (a, b) = (icosphere([0.0; 3], 1.0, 3), icosphere([0.5; 3], 1.0, 3));
    let (c, d) = (cuboid([0.0; 3], [2.0; 3]), cuboid([1.0; 3], [3.0; 3]));
    let runs: [(&dyn Engine, [&Mesh; 2], &[Stage]); 3] = [
        (
            &ExactEngine::default(),
            [&a, &b],
            &[
                Stage::Ingest,
                Stage::Validate,
                Stage::Broad,
                Stage::Intersect,
                Stage::Split,
                Stage::Classify,
                Stage::Reconstruct,
                Stage::Assemble,
                Stage::Certify,
                Stage::Faces,
                Stage::Attributes,
            ],
        ),
        (
            &OrthoEngine::default(),
            [&c, &d],
            &[Stage::Rank, Stage::Sweep, Stage::Loops, Stage::Triangulate],
        ),
        (
            &DiscreteEngine::with_cell(0.125),
            [&a, &b],
            &[Stage::Discretize, Stage::Combine, Stage::Convert],
        ),
    ];
    for (engine, operands, want) in runs {
        let reports = reports_of(engine, &operands);
        let mut stages: Vec<Stage> = reports.iter().map(|r| r.stage).collect();
        stages.dedup();
        assert_eq!(stages, want, "{}", engine.name());
        for stage in want {
            let done: Vec<usize> = (reports.iter())
                .filter(|r| r.stage == *stage)
                .map(|r| r.done)
                .collect();
            let last = reports
                .iter()
                .rfind(|r| r.stage == *stage)
                .expect("reported");
            assert_eq!(last.done, last.total, "{}: {stage:?}", engine.name());
            assert!(done.is_sorted(), "{}: {stage:?} {done:?}", engine.name());
        }
    }
}

/// Runs `engine` with a callback that returns `false` at the first report of `stage` before
/// its end (so the cancellation comes from inside the stage), and checks the run returns
/// [`Error::Cancelled`] without reporting any later stage.
fn assert_cancels_inside(engine: &dyn Engine, operands: &[&Mesh], stage: Stage) {
    let what = format!("{} in {stage:?}", engine.name());
    let seen = Mutex::new(Vec::new());
    let stop = |report: Report| {
        seen.lock().unwrap().push(report);
        !(report.stage == stage && report.done < report.total)
    };
    let progress = Progress::new(&stop);
    let result = engine.apply(Operation::Union, operands, &progress);
    assert!(
        matches!(result, Err(Error::Cancelled(_))),
        "{what}: {result:?}"
    );
    assert!(progress.is_cancelled(), "{what}");
    let seen = seen.into_inner().unwrap();
    let first = (seen.iter())
        .position(|r| r.stage == stage && r.done < r.total)
        .unwrap_or_else(|| panic!("{what}: no report inside the stage: {seen:?}"));
    assert!(
        seen[first..].iter().all(|r| r.stage == stage),
        "{what}: a later stage ran: {:?}",
        &seen[first..]
    );
}

/// A pair of 20 480-triangle spheres through the exact engine, cancelled inside each long
/// stage.
#[test]
fn the_exact_engine_cancels_inside_its_long_stages() {
    let (a, b) = (
        icosphere([0.0; 3], 1.0, 5),
        icosphere([0.3, 0.2, 0.1], 1.0, 5),
    );
    for stage in [
        Stage::Validate,
        Stage::Intersect,
        Stage::Split,
        Stage::Classify,
    ] {
        assert_cancels_inside(&ExactEngine::default(), &[&a, &b], stage);
    }
}

/// 2000 boxes through the orthogonal engine, cancelled inside the sweep and the loops.
#[test]
fn the_orthogonal_engine_cancels_inside_its_long_stages() {
    let boxes: Vec<Mesh> = (csgkit::ortho::random_grid_boxes(2000, 7).iter())
        .map(|b| cuboid([b[0], b[1], b[2]], [b[3], b[4], b[5]]))
        .collect();
    let operands: Vec<&Mesh> = boxes.iter().collect();
    for stage in [Stage::Sweep, Stage::Loops] {
        assert_cancels_inside(&OrthoEngine::default(), &operands, stage);
    }
}

/// A 20 480-triangle sphere through the discrete engine, cancelled inside the triangle pass.
#[test]
fn the_discrete_engine_cancels_inside_its_triangle_pass() {
    let sphere = icosphere([0.0; 3], 1.0, 5);
    let engine = DiscreteEngine::with_cell(1.0 / 64.0);
    assert_cancels_inside(&engine, &[&sphere], Stage::Discretize);
}

/// A context cancelled before the run stops every engine at its first poll.
#[test]
fn a_context_cancelled_beforehand_stops_every_engine() {
    let (a, b) = (cuboid([0.0; 3], [2.0; 3]), cuboid([1.0; 3], [3.0; 3]));
    let engines: [&dyn Engine; 3] = [
        &ExactEngine::default(),
        &OrthoEngine::default(),
        &DiscreteEngine::with_cell(0.5),
    ];
    for engine in engines {
        let progress = Progress::default();
        progress.cancel();
        let result = engine.apply(Operation::Union, &[&a, &b], &progress);
        assert!(
            matches!(result, Err(Error::Cancelled(_))),
            "{}: {result:?}",
            engine.name()
        );
    }
}
