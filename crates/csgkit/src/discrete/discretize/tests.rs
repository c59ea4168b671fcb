use super::*;
use crate::discrete::{Grid, Solid};
use crate::primitives::cuboid;
use crate::progress::Report;

fn concat(a: &Mesh, b: &Mesh) -> Mesh {
    let mut positions = a.positions().to_vec();
    positions.extend_from_slice(b.positions());
    let n = a.vertex_count() as u32;
    let mut tris: Vec<[u32; 3]> = a.fan_triangles().map(|(_, t)| t).collect();
    tris.extend(b.fan_triangles().map(|(_, t)| t.map(|v| v + n)));
    Mesh::from_triangles(positions, &tris).unwrap()
}

fn reversed(m: &Mesh) -> Mesh {
    let tris: Vec<[u32; 3]> = m.fan_triangles().map(|(_, [a, b, c])| [a, c, b]).collect();
    Mesh::from_triangles(m.positions().to_vec(), &tris).unwrap()
}

fn grid() -> Grid {
    Grid::new(1.0, 4).unwrap()
}

fn run(mesh: &Mesh, level: u8, fill: FillRule, rounding: Rounding) -> Solid {
    let s = discretize(mesh, grid(), level, DiscretizeOptions { fill, rounding }).unwrap();
    s.check_invariants().unwrap();
    s
}

fn centre(mesh: &Mesh) -> Solid {
    run(mesh, 0, FillRule::NonZero, Rounding::Centre)
}

#[test]
fn faces_on_centre_planes_count_below_the_centre() {
    // Faces at 0.5 and 4.5 pass through voxel centres. Along z a crossing at a centre counts
    // below it: voxels 0..4. Across the rays the top-left rule is the perturbation
    // (x + ε, y − ε): columns 0..4 along x, 1..5 along y.
    let s = centre(&cuboid([0.5; 3], [4.5; 3]));
    assert_eq!(s.voxel_count(), 64);
    assert!(s.contains(0, 1, 0) && s.contains(3, 4, 3));
    assert!(!s.contains(4, 1, 0) && !s.contains(0, 0, 0) && !s.contains(0, 5, 0));
    assert!(!s.contains(-1, 1, 0) && !s.contains(0, 1, -1) && !s.contains(0, 1, 4));
}

#[test]
fn negative_coordinates_use_the_origin_lattice() {
    let s = centre(&cuboid([-2.0, -3.5, -1.25], [1.0, -0.5, 2.75]));
    // x centres -1.5..0.5 (3), y centres -2.5..-0.5 (3; -3.5 is on the bottom edge),
    // z centres -0.5..2.5 (4).
    assert_eq!(s.voxel_count(), 36);
    assert!(s.contains(-2, -3, -1) && s.contains(0, -1, 2));
    assert!(!s.contains(0, -4, 2) && !s.contains(0, 0, 2) && !s.contains(1, -1, 2));
}

#[test]
fn inner_and_outer_rounding() {
    let cube = cuboid([0.5; 3], [4.5; 3]);
    // z planes: inner keeps cells [1,2)..[3,4) whole inside, outer cells [0,1)..[4,5).
    assert_eq!(
        run(&cube, 0, FillRule::NonZero, Rounding::Inner).voxel_count(),
        16 * 3
    );
    assert_eq!(
        run(&cube, 0, FillRule::NonZero, Rounding::Outer).voxel_count(),
        16 * 5
    );
    // Faces on lattice planes: all three roundings agree.
    let exact = cuboid([0.0; 3], [4.0; 3]);
    for rounding in [Rounding::Centre, Rounding::Inner, Rounding::Outer] {
        assert_eq!(
            run(&exact, 0, FillRule::NonZero, rounding).voxel_count(),
            64
        );
    }
}

#[test]
fn fill_rules_on_overlapping_and_inverted_shells() {
    let cube = cuboid([0.0; 3], [4.0; 3]);
    let twice = concat(&cube, &cube);
    assert_eq!(
        run(&twice, 0, FillRule::NonZero, Rounding::Centre).voxel_count(),
        64
    );
    assert_eq!(
        run(&twice, 0, FillRule::Positive, Rounding::Centre).voxel_count(),
        64
    );
    assert_eq!(
        run(&twice, 0, FillRule::Parity, Rounding::Centre).voxel_count(),
        0
    );
    let inverted = reversed(&cube);
    assert_eq!(
        run(&inverted, 0, FillRule::NonZero, Rounding::Centre).voxel_count(),
        64
    );
    assert_eq!(
        run(&inverted, 0, FillRule::Positive, Rounding::Centre).voxel_count(),
        0
    );
    // A box inside a box, both outward: winding 2 in the inner one.
    let nested = concat(&cube, &cuboid([1.0; 3], [3.0; 3]));
    assert_eq!(
        run(&nested, 0, FillRule::Parity, Rounding::Centre).voxel_count(),
        64 - 8
    );
    assert_eq!(
        run(&nested, 0, FillRule::NonZero, Rounding::Centre).voxel_count(),
        64
    );
}

#[test]
fn coarse_levels_sample_coarse_centres() {
    // Level 1 (w = 2): centres at 1, 3, 5, 7; the box [0, 6.5] holds centres 1, 3, 5.
    let s = run(
        &cuboid([0.0; 3], [6.5; 3]),
        1,
        FillRule::NonZero,
        Rounding::Centre,
    );
    assert_eq!(s.voxel_count(), 27 * 8);
    assert!(s.contains(5, 5, 5) && !s.contains(6, 0, 0));
    // Level 4 (w = 16, one root per column): centre 8 is inside [0, 9].
    let s = run(
        &cuboid([0.0; 3], [9.0; 3]),
        4,
        FillRule::NonZero,
        Rounding::Centre,
    );
    assert_eq!(s.voxel_count(), 16 * 16 * 16);
    assert_eq!(s.stats().uniform, 1);
}

#[test]
fn an_open_mesh_is_an_error() {
    let cube = cuboid([0.0; 3], [4.0; 3]);
    let tris: Vec<[u32; 3]> = cube.fan_triangles().map(|(_, t)| t).skip(1).collect();
    let open = Mesh::from_triangles(cube.positions().to_vec(), &tris).unwrap();
    let err = discretize(&open, grid(), 0, DiscretizeOptions::default()).unwrap_err();
    assert!(
        matches!(err, DiscretizeError::NotClosed { level: 0, .. }),
        "{err}"
    );
    assert!(err.to_string().starts_with("mesh is not closed: column ("));
}

#[test]
fn bad_coordinates_and_levels_are_errors() {
    let mut parts = cuboid([0.0; 3], [4.0; 3]).into_parts();
    parts.positions[5][1] = f64::NAN;
    let bad = Mesh::from_parts(parts).unwrap();
    let err = discretize(&bad, grid(), 0, DiscretizeOptions::default()).unwrap_err();
    assert!(matches!(
        err,
        DiscretizeError::BadCoordinate { vertex: 5, .. }
    ));
    let far = cuboid([0.0; 3], [4.0, 4.0, 1e12]);
    assert!(matches!(
        discretize(&far, grid(), 0, DiscretizeOptions::default()),
        Err(DiscretizeError::BadCoordinate { .. })
    ));
    let cube = cuboid([0.0; 3], [4.0; 3]);
    assert_eq!(
        discretize(&cube, grid(), 21, DiscretizeOptions::default()),
        Err(DiscretizeError::BadLevel(21))
    );
    assert!(
        discretize(&Mesh::new(), grid(), 0, DiscretizeOptions::default())
            .unwrap()
            .is_empty()
    );
}

#[test]
fn first_true_finds_the_boundary_from_any_start() {
    for boundary in [-40i64, -1, 0, 3, 100] {
        for start in [-100i64, -3, 0, 2, 50] {
            assert_eq!(first_true(start, |k| k >= boundary), boundary);
        }
    }
}

#[test]
fn result_does_not_depend_on_the_thread_count() {
    let mesh = concat(
        &cuboid([0.3, 0.1, 0.2], [9.7, 5.5, 3.3]),
        &cuboid([2.5, 2.5, 2.5], [12.0, 7.0, 8.5]),
    );
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let a = one.install(|| centre(&mesh));
    let b = centre(&mesh);
    assert_eq!(a, b);
    assert_eq!(a.to_index_boxes(), b.to_index_boxes());
}

#[test]
fn crossings_pack_and_sort_by_column_then_depth() {
    let a = Crossing::new(-5, 7, -3, -1);
    assert_eq!((a.i(), a.j(), a.pos(), a.delta()), (-5, 7, -3, -1));
    let b = Crossing::new(i32::MIN + 1, i32::MAX, i32::MAX, 1);
    assert_eq!(
        (b.i(), b.j(), b.pos(), b.delta()),
        (i32::MIN + 1, i32::MAX, i32::MAX, 1)
    );
    let mut v = [
        Crossing::new(0, 1, 0, 1),
        Crossing::new(1, 0, 5, -1),
        Crossing::new(0, 0, 2, 1),
        Crossing::new(0, 0, 2, -1),
        Crossing::new(-1, 0, 9, 1),
    ];
    v.sort_unstable();
    let keys: Vec<_> = v
        .iter()
        .map(|c| (c.j(), c.i(), c.pos(), c.delta()))
        .collect();
    assert_eq!(
        keys,
        vec![
            (0, -1, 9, 1),
            (0, 0, 2, -1),
            (0, 0, 2, 1),
            (0, 1, 5, -1),
            (1, 0, 0, 1)
        ]
    );
}

#[test]
fn progress_is_reported_and_cancellation_stops() {
    let cube = cuboid([0.0; 3], [4.0; 3]);
    let seen = std::sync::Mutex::new(Vec::new());
    let record = |report: Report| {
        seen.lock().unwrap().push(report);
        true
    };
    let options = DiscretizeOptions::default();
    let s = discretize_with_progress(&cube, grid(), 0, options, &Progress::new(&record)).unwrap();
    assert_eq!(s.voxel_count(), 64);
    let last = *seen.lock().unwrap().last().expect("reported");
    assert_eq!((last.stage, last.done), (Stage::Discretize, last.total));
    let stop = |_: Report| false;
    let err = discretize_with_progress(&cube, grid(), 0, options, &Progress::new(&stop));
    assert_eq!(err, Err(DiscretizeError::Cancelled(Cancelled)));
}
