//! The discrete engine against brute-force oracles (design/discrete.md §B3.5).
//!
//! The discretisation oracle is the generalised winding number (a sum of solid angles) at each
//! perturbed voxel centre `(x + ε², y − ε³, z + ε)`, evaluated in f64 with ε = 1e-4·w,
//! 1e-7·w, 1e-10·w: the shapes here keep every crossing either exactly at a centre height or
//! far (relative to ε) from one, so the f64 oracle is decisive. Booleans are compared with
//! voxel-set operations at the finest resolution.

use std::collections::BTreeSet;

use csgkit::discrete::{DiscretizeError, DiscretizeOptions, Grid, Solid, discretize};
use csgkit::primitives::{cuboid, icosphere};
use csgkit::{Mesh, Operation};
use robust::{Coord, orient2d};

use crate::util::{polygon_normal, repo_data, shared_data};

/// The parallelepiped `o + a·u + b·v + c·w`, `a, b, c ∈ [0, 1]`; `(u, v, w)` right-handed.
fn parallelepiped(o: [f64; 3], u: [f64; 3], v: [f64; 3], w: [f64; 3]) -> Mesh {
    // The unit cube's corners are the coefficients (a, b, c) and its triangles wind outward.
    let unit = cuboid([0.0; 3], [1.0; 3]);
    let positions = (unit.positions().iter())
        .map(|&[a, b, c]| [0, 1, 2].map(|d| o[d] + a * u[d] + b * v[d] + c * w[d]))
        .collect();
    let tris: Vec<[u32; 3]> = unit.fan_triangles().map(|(_, t)| t).collect();
    Mesh::from_triangles(positions, &tris).unwrap()
}

fn octahedron(c: [f64; 3], r: f64) -> Mesh {
    let mut positions = Vec::new();
    for d in 0..3 {
        for s in [1.0, -1.0] {
            let mut p = c;
            p[d] += s * r;
            positions.push(p);
        }
    }
    // Vertices: 0 +x, 1 −x, 2 +y, 3 −y, 4 +z, 5 −z.
    let mut tris = Vec::new();
    for (x, sx) in [(0u32, 1.0), (1, -1.0)] {
        for (y, sy) in [(2u32, 1.0), (3, -1.0)] {
            for (z, sz) in [(4u32, 1.0), (5, -1.0)] {
                let outward = sx * sy * sz > 0.0;
                tris.push(if outward { [x, y, z] } else { [x, z, y] });
            }
        }
    }
    Mesh::from_triangles(positions, &tris).unwrap()
}

fn concat(meshes: &[&Mesh]) -> Mesh {
    let (mut positions, mut tris) = (Vec::new(), Vec::new());
    for m in meshes {
        let n = positions.len() as u32;
        positions.extend_from_slice(m.positions());
        tris.extend(m.fan_triangles().map(|(_, t)| t.map(|v| v + n)));
    }
    Mesh::from_triangles(positions, &tris).unwrap()
}

fn triangles(mesh: &Mesh) -> Vec<[[f64; 3]; 3]> {
    mesh.fan_triangles()
        .map(|(_, t)| t.map(|v| mesh.positions()[v as usize]))
        .collect()
}

/// The generalised winding number at `q` (van Oosterom–Strackee solid angles).
fn winding(tris: &[[[f64; 3]; 3]], q: [f64; 3]) -> f64 {
    let sub = |p: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let norm = |a: [f64; 3]| dot(a, a).sqrt();
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let total: f64 = tris
        .iter()
        .map(|t| {
            let (a, b, c) = (sub(t[0]), sub(t[1]), sub(t[2]));
            let (la, lb, lc) = (norm(a), norm(b), norm(c));
            let det = dot(a, cross(b, c));
            let den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
            2.0 * det.atan2(den)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

/// Column centres lying exactly on a projected edge or vertex of some triangle.
fn ray_incidences(
    tris: &[[[f64; 3]; 3]],
    grid: &Grid,
    level: u8,
    range: ([i64; 3], [i64; 3]),
) -> usize {
    let xy = |p: [f64; 3]| Coord { x: p[0], y: p[1] };
    let mut n = 0;
    for t in tris {
        let area = orient2d(xy(t[0]), xy(t[1]), xy(t[2]));
        for i in range.0[0]..range.1[0] {
            for j in range.0[1]..range.1[1] {
                let p = Coord {
                    x: grid.centre(level, i),
                    y: grid.centre(level, j),
                };
                let sides = [0, 1, 2]
                    .map(|e| orient2d(xy(t[(e + 1) % 3]), xy(t[(e + 2) % 3]), p) * area.signum());
                if area != 0.0 && sides.iter().all(|&s| s >= 0.0) && sides.contains(&0.0) {
                    n += 1;
                }
            }
        }
    }
    n
}

/// Compares `discretize(mesh, level)` with the winding-number oracle over the mesh's bounding
/// box plus one voxel; returns (mismatches, voxels inside, ray incidences).
fn compare_with_oracle(mesh: &Mesh, grid: Grid, level: u8) -> (usize, usize, usize) {
    let solid = discretize(mesh, grid, level, DiscretizeOptions::default()).unwrap();
    solid.check_invariants().unwrap();
    let tris = triangles(mesh);
    let w = grid.width(level);
    let (mut lo, mut hi) = ([i64::MAX; 3], [i64::MIN; 3]);
    for p in mesh.positions() {
        for d in 0..3 {
            lo[d] = lo[d].min((p[d] / w).floor() as i64 - 1);
            hi[d] = hi[d].max((p[d] / w).ceil() as i64 + 1);
        }
    }
    let (mut mismatches, mut inside) = (0, 0);
    for i in lo[0]..hi[0] {
        for j in lo[1]..hi[1] {
            for k in lo[2]..hi[2] {
                let q = [
                    grid.centre(level, i) + 1e-7 * w,
                    grid.centre(level, j) - 1e-10 * w,
                    grid.centre(level, k) + 1e-4 * w,
                ];
                let expect = winding(&tris, q).round() != 0.0;
                let s = 1i64 << level;
                let got = solid.contains((i * s) as i32, (j * s) as i32, (k * s) as i32);
                mismatches += usize::from(expect != got);
                inside += usize::from(expect);
            }
        }
    }
    assert_eq!(
        solid.voxel_count(),
        inside as u64 * 8u64.pow(u32::from(level))
    );
    (
        mismatches,
        inside,
        ray_incidences(&tris, &grid, level, (lo, hi)),
    )
}

/// Shapes whose vertices sit on the column rays and centre heights of level `w`.
fn lattice_shapes(w: f64) -> Vec<Mesh> {
    let c = |i: f64| (i + 0.5) * w;
    vec![
        octahedron([c(3.0), c(2.0), c(1.0)], 3.0 * w),
        octahedron([c(-2.0), c(1.0), c(0.0)], 2.0 * w),
        parallelepiped(
            [c(0.0), c(0.0), c(0.0)],
            [3.0 * w, 4.0 * w, 0.0],
            [-4.0 * w, 3.0 * w, 0.0],
            [0.0, 0.0, 5.0 * w],
        ),
        parallelepiped(
            [c(1.0), c(-1.0), c(2.0)],
            [4.0 * w, 4.0 * w, 2.0 * w],
            [4.0 * w, -2.0 * w, -4.0 * w],
            [-2.0 * w, 4.0 * w, -4.0 * w],
        ),
        cuboid([c(-1.0), c(0.0), c(-2.0)], [c(3.0), c(4.0), c(1.0)]),
        concat(&[
            &octahedron([c(0.0), c(0.0), c(0.0)], 3.0 * w),
            &cuboid([c(0.0), c(0.0), c(0.0)], [c(3.0), c(2.0), c(2.0)]),
        ]),
    ]
}

#[test]
fn discretisation_equals_the_winding_number_oracle() {
    let grid = Grid::new(1.0, 4).unwrap();
    let (mut incidences, mut inside) = (0, 0);
    for level in 0..3u8 {
        let mut shapes = lattice_shapes(grid.width(level));
        // Off-lattice shapes in general position at every level.
        shapes.push(octahedron([0.3, 0.7, 0.1], 5.3));
        shapes.push(icosphere([1.1, -0.4, 0.6], 6.2, 2));
        for (n, mesh) in shapes.iter().enumerate() {
            let (bad, count, hits) = compare_with_oracle(mesh, grid, level);
            assert_eq!(bad, 0, "shape {n} at level {level}: {bad} mismatches");
            assert!(count > 0, "shape {n} at level {level} is empty");
            incidences += hits;
            inside += count;
        }
    }
    // The lattice shapes must really exercise rays through vertices and edges.
    eprintln!("{incidences} exact ray incidences, {inside} voxels inside, 0 mismatches");
    assert!(incidences > 300, "only {incidences} exact ray incidences");
    assert!(inside > 1000);
}

#[test]
fn icosphere_volume_converges() {
    let mesh = icosphere([32.0, 32.0, 32.0], 20.0, 4);
    let volume: f64 = triangles(&mesh)
        .iter()
        .map(|[a, b, c]| {
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum();
    let grid = Grid::new(1.0, 6).unwrap();
    let errors: Vec<f64> = (0..5u8)
        .map(|level| {
            let s = discretize(&mesh, grid, level, DiscretizeOptions::default()).unwrap();
            (s.voxel_count() as f64 - volume).abs() / volume
        })
        .collect();
    // Not monotone at coarse widths: test the trend and the fine end.
    assert!(errors[0] < 0.005, "{errors:?}");
    assert!(errors[0] < errors[3] && errors[1] < errors[4], "{errors:?}");
}

fn voxel_set(s: &Solid) -> BTreeSet<(i32, i32, i32)> {
    let mut out = BTreeSet::new();
    for b in s.to_index_boxes() {
        for x in b[0]..b[3] {
            for y in b[1]..b[4] {
                out.extend((b[2]..b[5]).map(|z| (x, y, z)));
            }
        }
    }
    out
}

fn apply(
    op: Operation,
    a: &BTreeSet<(i32, i32, i32)>,
    b: &BTreeSet<(i32, i32, i32)>,
) -> BTreeSet<(i32, i32, i32)> {
    match op {
        Operation::Union => a.union(b).copied().collect(),
        Operation::Intersection => a.intersection(b).copied().collect(),
        Operation::Difference => a.difference(b).copied().collect(),
        _ => a.symmetric_difference(b).copied().collect(),
    }
}

#[test]
fn mixed_resolution_booleans_equal_voxel_set_operations() {
    let grid = Grid::new(1.0, 5).unwrap();
    let opts = DiscretizeOptions::default();
    // An octahedron at w = 4 and a rotated cube at w = 1, overlapping.
    let a = discretize(&octahedron([10.0, 10.0, 10.0], 13.0), grid, 2, opts).unwrap();
    let b = discretize(
        &parallelepiped(
            [14.5, 3.5, 6.5],
            [8.0, 8.0, 4.0],
            [8.0, -4.0, -8.0],
            [-4.0, 8.0, -8.0],
        ),
        grid,
        0,
        opts,
    )
    .unwrap();
    let (va, vb) = (voxel_set(&a), voxel_set(&b));
    assert!(!va.is_empty() && !vb.is_empty());
    for op in Operation::ALL {
        let r = a.op(&b, op).unwrap();
        r.check_invariants().unwrap();
        let expect = apply(op, &va, &vb);
        assert!(!expect.is_empty(), "{op:?}");
        assert_eq!(voxel_set(&r), expect, "{op:?}");
        assert_eq!(r.voxel_count(), expect.len() as u64);
    }
}

#[test]
fn operand_order_and_grouping_do_not_change_the_result() {
    let grid = Grid::new(0.5, 4).unwrap();
    let opts = DiscretizeOptions::default();
    let a = discretize(&icosphere([4.0, 4.0, 4.0], 3.7, 2), grid, 0, opts).unwrap();
    let b = discretize(&cuboid([1.0, 2.0, 3.0], [9.0, 6.5, 7.5]), grid, 3, opts).unwrap();
    let c = discretize(&octahedron([6.0, 3.0, 5.0], 4.0), grid, 1, opts).unwrap();
    // Canonical form: equal voxel sets give structurally equal solids.
    assert_eq!(a.union(&b).unwrap(), b.union(&a).unwrap());
    assert_eq!(a.intersection(&c).unwrap(), c.intersection(&a).unwrap());
    let left = a.union(&b).unwrap().union(&c).unwrap();
    let right = a.union(&b.union(&c).unwrap()).unwrap();
    assert_eq!(left, right);
    // A − B = A ∩ ¬B, with ¬B taken within a box holding everything.
    let bounds = discretize(&cuboid([-8.0; 3], [24.0; 3]), grid, 4, opts).unwrap();
    let not_b = bounds.difference(&b).unwrap();
    assert_eq!(a.difference(&b).unwrap(), a.intersection(&not_b).unwrap());
    // vol(A ∪ B) + vol(A ∩ B) = vol(A) + vol(B).
    let (u, i) = (a.union(&c).unwrap(), a.intersection(&c).unwrap());
    assert_eq!(
        u.voxel_count() + i.voxel_count(),
        a.voxel_count() + c.voxel_count()
    );
    // Chained ops normalise back: (A ∪ B) − (B − A) = A.
    assert_eq!(
        a.union(&b)
            .unwrap()
            .difference(&b.difference(&a).unwrap())
            .unwrap(),
        a
    );
}

#[test]
fn box_output_volume_is_voxel_count_times_cell_volume() {
    let grid = Grid::new(0.25, 5).unwrap();
    let s = discretize(
        &icosphere([1.0, 2.0, 3.0], 2.3, 3),
        grid,
        0,
        DiscretizeOptions::default(),
    )
    .unwrap();
    let volume: f64 = s
        .to_boxes()
        .iter()
        .map(|b| (b[3] - b[0]) * (b[4] - b[1]) * (b[5] - b[2]))
        .sum();
    assert_eq!(volume, s.voxel_count() as f64 / 64.0);
    assert!(s.voxel_count() > 1000);
}

#[test]
fn memory_follows_the_surface_not_the_volume() {
    let mesh = icosphere([64.0, 64.0, 64.0], 50.0, 4);
    let opts = DiscretizeOptions::default();
    let coarse = discretize(&mesh, Grid::new(2.0, 8).unwrap(), 0, opts).unwrap();
    let fine = discretize(&mesh, Grid::new(1.0, 8).unwrap(), 0, opts).unwrap();
    let voxels = fine.voxel_count() as f64 / coarse.voxel_count() as f64;
    let entries = fine.stats().entries as f64 / coarse.stats().entries as f64;
    assert!(voxels > 7.5, "{voxels}");
    assert!(
        entries < 4.5,
        "entries grew {entries}× for {voxels}× voxels"
    );
}

#[test]
fn an_open_mesh_is_an_error_not_a_panic() {
    let closed = octahedron([0.5, 0.5, 0.5], 4.0);
    let tris: Vec<[u32; 3]> = closed.fan_triangles().map(|(_, t)| t).take(7).collect();
    let open = Mesh::from_triangles(closed.positions().to_vec(), &tris).unwrap();
    let err = discretize(
        &open,
        Grid::new(1.0, 4).unwrap(),
        0,
        DiscretizeOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(err, DiscretizeError::NotClosed { .. }), "{err}");
}

#[test]
fn the_repo_cube_file_voxelises_exactly() {
    // Unit cube of quads at h = 1/8: centres 1/16 .. 15/16 on each axis, 8³ voxels.
    let mesh = csgkit::io::read_mesh(repo_data("cube.obj")).unwrap().mesh;
    let s = discretize(
        &mesh,
        Grid::new(0.125, 3).unwrap(),
        0,
        DiscretizeOptions::default(),
    )
    .unwrap();
    assert_eq!(s.voxel_count(), 512);
    assert_eq!(s.stats().uniform, 1);
}

/// A shared data mesh and the cell giving `n` cells along its longest side.
fn data_mesh(name: &str, n: f64) -> Option<(Mesh, f64)> {
    let path = shared_data()?.join("meshes").join(name);
    let mesh = csgkit::io::read_mesh(&path).unwrap().mesh;
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for p in mesh.positions() {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let longest = (0..3).map(|d| hi[d] - lo[d]).fold(0.0, f64::max);
    Some((mesh, longest / n))
}

fn signed_volume(mesh: &Mesh) -> f64 {
    triangles(mesh)
        .iter()
        .map(|[a, b, c]| {
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum()
}

#[test]
fn data_meshes_voxelise_to_their_volume_with_a_closed_surfel_mesh() {
    for name in ["bunny_watertight.obj", "armadillo.obj"] {
        let Some((mesh, h)) = data_mesh(name, 64.0) else {
            return;
        };
        let grid = Grid::new(h, 8).unwrap();
        let s = discretize(&mesh, grid, 0, DiscretizeOptions::default()).unwrap();
        s.check_invariants().unwrap();
        let exact = signed_volume(&mesh);
        let voxels = s.voxel_count() as f64 * h * h * h;
        assert!(
            (voxels - exact).abs() / exact < 0.02,
            "{name}: {voxels} vs {exact}"
        );
        // The surfel mesh: every directed edge matched, volume = voxel count exactly (in
        // lattice units, where the coordinates are integers).
        let surfels = s.to_surfel_mesh().unwrap();
        let mut edges = std::collections::HashMap::new();
        let mut six = 0i128;
        for face in surfels.faces() {
            let p: Vec<[i128; 3]> = face
                .iter()
                .map(|&v| surfels.positions()[v as usize].map(|x| (x / h).round() as i128))
                .collect();
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                *edges.entry((a.min(b), a.max(b))).or_insert(0i64) += if a < b { 1 } else { -1 };
            }
            for k in 1..p.len() - 1 {
                let (a, b, c) = (p[0], p[k], p[k + 1]);
                six += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]);
            }
        }
        assert!(
            edges.values().all(|&n| n == 0),
            "{name}: surfel mesh is open"
        );
        assert_eq!(six, 6 * i128::from(s.voxel_count()), "{name}");
    }
}

#[test]
fn data_meshes_at_mixed_resolutions_combine_voxelwise() {
    let Some((bunny, h)) = data_mesh("bunny_watertight.obj", 48.0) else {
        return;
    };
    let grid = Grid::new(h, 8).unwrap();
    let opts = DiscretizeOptions::default();
    let coarse = discretize(&bunny, grid, 2, opts).unwrap();
    // The same bunny at the fine level, shifted by 5.5 cells along x.
    let shifted: Vec<[f64; 3]> = bunny
        .positions()
        .iter()
        .map(|p| [p[0] + 5.5 * h, p[1], p[2]])
        .collect();
    let tris: Vec<[u32; 3]> = bunny.fan_triangles().map(|(_, t)| t).collect();
    let fine = discretize(
        &Mesh::from_triangles(shifted, &tris).unwrap(),
        grid,
        0,
        opts,
    )
    .unwrap();
    let (va, vb) = (voxel_set(&coarse), voxel_set(&fine));
    for op in Operation::ALL {
        let r = coarse.op(&fine, op).unwrap();
        r.check_invariants().unwrap();
        assert_eq!(voxel_set(&r), apply(op, &va, &vb), "{op:?}");
    }
}

#[test]
fn a_data_mesh_with_a_hole_is_an_error() {
    let Some((bunny, h)) = data_mesh("bunny_watertight.obj", 32.0) else {
        return;
    };
    // Drop a triangle that is not vertical and move the mesh so a column ray hits its centroid.
    let xy = |p: [f64; 3]| Coord { x: p[0], y: p[1] };
    let mut tris: Vec<[u32; 3]> = bunny.fan_triangles().map(|(_, t)| t).collect();
    let hole = tris
        .iter()
        .position(|t| {
            let [a, b, c] = t.map(|v| bunny.positions()[v as usize]);
            orient2d(xy(a), xy(b), xy(c)).abs() > 1e-6 * h * h
        })
        .unwrap();
    let removed = tris.remove(hole).map(|v| bunny.positions()[v as usize]);
    let centroid = [0, 1].map(|d| (removed[0][d] + removed[1][d] + removed[2][d]) / 3.0);
    let shift = [0.5 * h - centroid[0], 0.5 * h - centroid[1]];
    let moved: Vec<[f64; 3]> = bunny
        .positions()
        .iter()
        .map(|p| [p[0] + shift[0], p[1] + shift[1], p[2]])
        .collect();
    let open = Mesh::from_triangles(moved, &tris).unwrap();
    let grid = Grid::new(h, 8).unwrap();
    let err = discretize(&open, grid, 0, DiscretizeOptions::default());
    assert!(
        matches!(err, Err(DiscretizeError::NotClosed { .. })),
        "{err:?}"
    );
}

#[test]
fn inner_and_outer_bracket_the_centre_rounding() {
    use csgkit::discrete::Rounding;
    let grid = Grid::new(1.0, 4).unwrap();
    let shapes = [
        icosphere([0.3, -0.2, 0.45], 5.1, 2),
        octahedron([0.5, 0.5, 0.5], 5.0),
        parallelepiped(
            [0.5, -1.5, 0.25],
            [4.0, 4.0, 2.0],
            [4.0, -2.0, -4.0],
            [-2.0, 4.0, -4.0],
        ),
    ];
    for (n, mesh) in shapes.iter().enumerate() {
        let tris = triangles(mesh);
        let with = |rounding| {
            let opts = DiscretizeOptions {
                rounding,
                ..DiscretizeOptions::default()
            };
            let s = discretize(mesh, grid, 0, opts).unwrap();
            s.check_invariants().unwrap();
            voxel_set(&s)
        };
        let (inner, centre, outer) = (
            with(Rounding::Inner),
            with(Rounding::Centre),
            with(Rounding::Outer),
        );
        assert!(
            inner.is_subset(&centre) && centre.is_subset(&outer),
            "shape {n}"
        );
        assert!(
            inner.len() < centre.len() && centre.len() < outer.len(),
            "shape {n}"
        );
        // Inner voxels are inside near both of their z faces; voxels left out of Outer are
        // outside near both.
        let inside_at = |x: i32, y: i32, z: f64| {
            let q = [f64::from(x) + 0.5 + 1e-7, f64::from(y) + 0.5 - 1e-10, z];
            winding(&tris, q).round() != 0.0
        };
        for &(x, y, z) in &inner {
            let z = f64::from(z);
            assert!(
                inside_at(x, y, z + 1e-3) && inside_at(x, y, z + 1.0 - 1e-3),
                "shape {n}"
            );
        }
        for &(x, y, z) in centre.iter().chain(&outer) {
            for dz in [-1, 1] {
                let (zz, f) = (z + dz, f64::from(z + dz));
                if !outer.contains(&(x, y, zz)) {
                    assert!(
                        !inside_at(x, y, f + 1e-3) && !inside_at(x, y, f + 1.0 - 1e-3),
                        "shape {n}"
                    );
                }
            }
        }
    }
}

#[test]
fn touching_and_coplanar_shells() {
    let grid = Grid::new(1.0, 4).unwrap();
    let opts = DiscretizeOptions::default();
    for (lo, mid, hi) in [(0.0, 4.0, 8.0), (0.5, 4.5, 8.5)] {
        let a = cuboid([lo; 3], [mid, mid, mid]);
        let b = cuboid([lo, lo, mid], [mid, mid, hi]);
        let (sa, sb) = (
            discretize(&a, grid, 0, opts).unwrap(),
            discretize(&b, grid, 0, opts).unwrap(),
        );
        assert_eq!(sa.voxel_count(), 64);
        assert_eq!(sb.voxel_count(), 64);
        assert!(sa.intersection(&sb).unwrap().is_empty());
        let union = sa.union(&sb).unwrap();
        // One mesh holding both shells: the shared face's crossings cancel at one depth.
        let both = discretize(&concat(&[&a, &b]), grid, 0, opts).unwrap();
        assert_eq!(both, union);
        assert_eq!(union.voxel_count(), 128);
        // Coplanar overlap: the same cube twice is the cube.
        let twice = discretize(&concat(&[&a, &a]), grid, 0, opts).unwrap();
        assert_eq!(twice, sa);
    }
}

#[test]
fn random_half_lattice_tetrahedra_match_the_oracle() {
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    // Vertices on the half-integer lattice: rays through vertices and edges, and crossings at
    // centre heights, are frequent; other crossings stay ≥ 1/1024 from a centre, far above the
    // oracle's ε.
    let point = || proptest::array::uniform3((-8i32..=8).prop_map(|v| f64::from(v) * 0.5));
    let mut runner = TestRunner::new_with_rng(
        Config::with_cases(60),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[5; 32]),
    );
    let grid = Grid::new(1.0, 4).unwrap();
    runner
        .run(&proptest::array::uniform4(point()), |p| {
            let tris = [[0u32, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]];
            let mesh = Mesh::from_triangles(p.to_vec(), &tris).unwrap();
            let [a, b, c, d] = p;
            let sub = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
            let (u, v, w) = (sub(b, a), sub(c, a), sub(d, a));
            let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]);
            prop_assume!(det != 0.0);
            for level in 0..2 {
                let (bad, _, _) = compare_with_oracle(&mesh, grid, level);
                prop_assert_eq!(bad, 0, "level {}", level);
            }
            Ok(())
        })
        .unwrap();
}

/// `mesh` with every face of material `name`.
fn painted(mesh: &Mesh, name: &str) -> Mesh {
    Mesh::from_parts(csgkit::MeshParts {
        face_materials: Some(vec![0; mesh.face_count()]),
        materials: vec![name.to_owned()],
        ..mesh.clone().into_parts()
    })
    .expect("one material")
}

/// The area of the faces of each material of `mesh`, by name (each face's vector area, so
/// non-convex faces count right).
fn area_by_material(mesh: &Mesh) -> std::collections::BTreeMap<String, f64> {
    let ids = mesh.face_materials().expect("materials");
    let mut out = std::collections::BTreeMap::new();
    for (f, face) in mesh.faces().enumerate() {
        let corners: Vec<[f64; 3]> = face.iter().map(|&v| mesh.positions()[v as usize]).collect();
        let n = polygon_normal(&corners);
        let area = 0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        *out.entry(mesh.materials()[ids[f] as usize].clone())
            .or_insert(0.0) += area;
    }
    out
}

/// Materials survive the discrete engine: an operand made of a red and a blue solid side by
/// side (one closed shell per material) united with a green bar keeps red and blue where it
/// had them and the bar is green only where it adds voxels; the difference keeps red and
/// blue on what is left, and the faces the bar cut are those of the solid behind them. Face
/// areas per material are exact (integer boxes on a unit grid).
#[test]
fn discrete_results_keep_the_material_of_the_solid_behind_each_face() {
    use csgkit::discrete::{discretize_parts, label, labelled_mesh};
    let (grid, _) = Grid::for_cells(&[1.0]).expect("a unit grid");
    let two = {
        let red = painted(&cuboid([0.0; 3], [2.0; 3]), "red");
        let blue = painted(&cuboid([2.0, 0.0, 0.0], [4.0, 2.0, 2.0]), "blue");
        let mut parts = concat(&[&red, &blue]).into_parts();
        parts.face_materials = Some((0..24).map(|f| u32::from(f >= 12)).collect());
        parts.materials = vec!["red".into(), "blue".into()];
        Mesh::from_parts(parts).expect("two painted boxes")
    };
    let bar = painted(&cuboid([1.0, 1.0, 1.0], [3.0, 3.0, 2.0]), "green");
    let options = DiscretizeOptions::default();
    let operands = [
        discretize_parts(&two, grid, 0, options).expect("two parts"),
        discretize_parts(&bar, grid, 0, options).expect("one part"),
    ];
    assert_eq!(operands[0].len(), 2, "one part per closed material");
    let whole = |parts: &[csgkit::discrete::MaterialSolid]| {
        let solids: Vec<Solid> = parts.iter().map(|p| p.solid.clone()).collect();
        Solid::op_all(&solids, Operation::Union).unwrap().unwrap()
    };
    let (a, b) = (whole(&operands[0]), whole(&operands[1]));

    let union = label(&a.union(&b).unwrap(), &operands).unwrap();
    let counts: Vec<(&str, u64)> = (union.iter())
        .map(|p| (p.material.as_str(), p.solid.voxel_count()))
        .collect();
    assert_eq!(counts, [("red", 8), ("blue", 8), ("green", 2)]);
    let mesh = labelled_mesh(&union).expect("a mesh");
    assert!(mesh.report().is_valid_solid());
    assert_eq!(mesh.report().measures.volume, 18.0);
    let areas = area_by_material(&mesh);
    assert_eq!(
        areas["green"],
        2.0 + 2.0 * 2.0 + 2.0,
        "top, sides and back of the bar's overhang"
    );

    let difference = label(&a.difference(&b).unwrap(), &operands).unwrap();
    let counts: Vec<(&str, u64)> = (difference.iter())
        .map(|p| (p.material.as_str(), p.solid.voxel_count()))
        .collect();
    assert_eq!(counts, [("red", 7), ("blue", 7)]);
    let mesh = labelled_mesh(&difference).expect("a mesh");
    assert!(mesh.report().is_valid_solid());
    let areas = area_by_material(&mesh);
    assert_eq!(areas.keys().collect::<Vec<_>>(), ["blue", "red"]);
    // The 4 × 2 × 2 box's 40, less the two unit-wide strips the notch takes from its top and
    // back, plus the notch's four inner faces.
    assert_eq!(areas["red"] + areas["blue"], 40.0 - 4.0 + 6.0);
}
