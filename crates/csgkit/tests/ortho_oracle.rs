//! The orthogonal engine against a brute-force grid oracle (`design/ortho.md` §A4.3, §A8) on
//! thousands of random box and voxel sets with fixed seeds, plus metamorphic relations.

use std::collections::HashMap;

use csgkit::Mesh;
use csgkit::ortho::{
    BRep, MeshOptions, OCTANT_TABLE, Orientation, box_union, box_union_per_material,
    box_union_with_materials, per_material_mesh,
};

/// A xorshift generator: fixed seeds make every case reproducible.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
}

/// The occupancy grid of a box set over its compressed coordinates.
struct Grid {
    coords: [Vec<f64>; 3],
    /// The material of each cell (the smallest of the boxes covering it), or `EMPTY`.
    cells: Vec<u32>,
}

const EMPTY: u32 = u32::MAX;

impl Grid {
    fn new(boxes: &[[f64; 6]]) -> Self {
        Self::with_materials(boxes, &vec![0; boxes.len()])
    }

    fn with_materials(boxes: &[[f64; 6]], materials: &[u32]) -> Self {
        let coords: [Vec<f64>; 3] = std::array::from_fn(|k| {
            let mut v: Vec<f64> = boxes.iter().flat_map(|b| [b[k], b[k + 3]]).collect();
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        });
        let n = coords.each_ref().map(|c| c.len().saturating_sub(1));
        let mut cells = vec![EMPTY; n[0] * n[1] * n[2]];
        for (b, &m) in boxes.iter().zip(materials) {
            let r: [usize; 6] =
                std::array::from_fn(|i| coords[i % 3].partition_point(|&c| c < b[i]));
            for z in r[2]..r[5] {
                for y in r[1]..r[4] {
                    for x in r[0]..r[3] {
                        let cell = &mut cells[(z * n[1] + y) * n[0] + x];
                        *cell = (*cell).min(m);
                    }
                }
            }
        }
        Self { coords, cells }
    }

    fn material(&self, c: [i64; 3]) -> u32 {
        let n = self.coords.each_ref().map(|c| c.len() as i64 - 1);
        if (0..3).any(|k| c[k] < 0 || c[k] >= n[k]) {
            return EMPTY;
        }
        self.cells[((c[2] * n[1] + c[1]) * n[0] + c[0]) as usize]
    }

    fn occupied(&self, c: [i64; 3]) -> bool {
        self.material(c) != EMPTY
    }

    /// Every grid point with a vertex code: (position, code), sorted by (z, y, x).
    fn vertices(&self) -> Vec<([f64; 3], u8)> {
        let mut out = Vec::new();
        let n = self.coords.each_ref().map(|c| c.len() as i64);
        for z in 0..n[2] {
            for y in 0..n[1] {
                for x in 0..n[0] {
                    let mut code = 0u8;
                    for o in 0..8 {
                        let c = [x - 1 + (o & 1), y - 1 + (o >> 1 & 1), z - 1 + (o >> 2)];
                        if self.occupied(c) {
                            code |= 1 << o;
                        }
                    }
                    if OCTANT_TABLE[code as usize].is_vertex() {
                        let p = [x, y, z].map(|i| i as usize);
                        out.push(([0, 1, 2].map(|k| self.coords[k][p[k]]), code));
                    }
                }
            }
        }
        out
    }

    fn volume(&self) -> f64 {
        let n = self.coords.each_ref().map(|c| c.len().saturating_sub(1));
        let size = |k: usize, i: usize| self.coords[k][i + 1] - self.coords[k][i];
        let mut v = 0.0;
        for z in 0..n[2] {
            for y in 0..n[1] {
                for x in 0..n[0] {
                    if self.cells[(z * n[1] + y) * n[0] + x] != EMPTY {
                        v += size(0, x) * size(1, y) * size(2, z);
                    }
                }
            }
        }
        v
    }

    /// Per (orientation, plane coordinate, material): the sorted areas of the 4-connected
    /// components of boundary cells of that material.
    fn faces(&self) -> HashMap<FaceKey, Vec<f64>> {
        let mut out: HashMap<FaceKey, Vec<f64>> = HashMap::new();
        for o in Orientation::ALL {
            let (k, (a, b)) = (o.axis(), o.frame());
            let (na, nb) = (self.coords[a].len() - 1, self.coords[b].len() - 1);
            for c in 0..self.coords[k].len() {
                // The material of the face on cell (i, j), or EMPTY.
                let face_material = |i: usize, j: usize| {
                    let mut lo = [0i64; 3];
                    lo[a] = i as i64;
                    lo[b] = j as i64;
                    lo[k] = c as i64 - 1;
                    let mut hi = lo;
                    hi[k] = c as i64;
                    let (inner, outer) = if o.is_positive() { (lo, hi) } else { (hi, lo) };
                    if self.occupied(outer) {
                        EMPTY
                    } else {
                        self.material(inner)
                    }
                };
                let mut seen = vec![false; na * nb];
                for start in 0..na * nb {
                    let m = face_material(start % na, start / na);
                    if seen[start] || m == EMPTY {
                        continue;
                    }
                    let mut area = 0.0;
                    let mut stack = vec![start];
                    seen[start] = true;
                    while let Some(cell) = stack.pop() {
                        let (i, j) = (cell % na, cell / na);
                        area += (self.coords[a][i + 1] - self.coords[a][i])
                            * (self.coords[b][j + 1] - self.coords[b][j]);
                        let around = [
                            (i.wrapping_sub(1), j),
                            (i + 1, j),
                            (i, j.wrapping_sub(1)),
                            (i, j + 1),
                        ];
                        for (u, v) in around {
                            if u < na && v < nb && !seen[v * na + u] && face_material(u, v) == m {
                                seen[v * na + u] = true;
                                stack.push(v * na + u);
                            }
                        }
                    }
                    let key = (o, self.coords[k][c].to_bits(), m);
                    out.entry(key).or_default().push(area);
                }
            }
        }
        out.values_mut().for_each(|v| v.sort_by(f64::total_cmp));
        out
    }
}

/// Twice the signed area of a loop in its face's frame.
fn loop_area2(brep: &BRep, o: Orientation, lp: &[u32]) -> f64 {
    let (a, b) = o.frame();
    let p = |i: usize| brep.vertices[lp[i % lp.len()] as usize].position;
    (0..lp.len())
        .map(|i| p(i)[a] * p(i + 1)[b] - p(i + 1)[a] * p(i)[b])
        .sum()
}

/// (orientation, plane coordinate bits, material).
type FaceKey = (Orientation, u64, u32);

fn brep_faces(brep: &BRep) -> HashMap<FaceKey, Vec<f64>> {
    let mut out: HashMap<FaceKey, Vec<f64>> = HashMap::new();
    for f in &brep.faces {
        let k = f.orientation.axis();
        let plane = brep.vertices[f.outer[0] as usize].position[k];
        let outer = loop_area2(brep, f.orientation, &f.outer);
        assert!(outer > 0.0, "outer loops are CCW");
        let holes: f64 = f
            .holes
            .iter()
            .map(|h| loop_area2(brep, f.orientation, h))
            .sum();
        assert!(
            f.holes
                .iter()
                .all(|h| loop_area2(brep, f.orientation, h) < 0.0),
            "holes are CW"
        );
        out.entry((f.orientation, plane.to_bits(), f.material))
            .or_default()
            .push((outer + holes) / 2.0);
    }
    out.values_mut().for_each(|v| v.sort_by(f64::total_cmp));
    out
}

/// 6 × signed volume, after checking every directed edge has its reverse.
fn closed_six_volume(mesh: &Mesh) -> f64 {
    let mut balance: HashMap<(u32, u32), i32> = HashMap::new();
    for face in mesh.faces() {
        for i in 0..face.len() {
            let (u, v) = (face[i], face[(i + 1) % face.len()]);
            *balance.entry((u.min(v), u.max(v))).or_insert(0) += if u < v { 1 } else { -1 };
        }
    }
    assert!(balance.values().all(|&b| b == 0), "mesh is not closed");
    let p = mesh.positions();
    mesh.fan_triangles()
        .map(|(_, [a, b, c])| {
            let (a, b, c) = (p[a as usize], p[b as usize], p[c as usize]);
            a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0])
        })
        .sum()
}

/// Checks every undirected edge has two triangles and χ is even.
fn assert_even_chi_two_per_edge(mesh: &Mesh) {
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    for face in mesh.faces() {
        for i in 0..3 {
            let (u, v) = (face[i], face[(i + 1) % 3]);
            *edges.entry((u.min(v), u.max(v))).or_insert(0) += 1;
        }
    }
    assert!(edges.values().all(|&n| n == 2), "two triangles per edge");
    let mut used = mesh.corners().to_vec();
    used.sort_unstable();
    used.dedup();
    let chi = used.len() as i64 - edges.len() as i64 + mesh.face_count() as i64;
    assert_eq!(chi % 2, 0, "even Euler characteristic");
}

/// Checks a box set against the oracle: vertices and codes, faces and areas, loop pairing,
/// triangle count, closedness and volume.
fn check_against_oracle(boxes: &[[f64; 6]]) {
    let brep = box_union(boxes).unwrap();
    let grid = Grid::new(boxes);
    let got: Vec<([f64; 3], u8)> = brep.vertices.iter().map(|v| (v.position, v.code)).collect();
    assert_eq!(got, grid.vertices(), "vertices of {boxes:?}");
    for v in &brep.vertices {
        assert_eq!(
            v.degrees,
            OCTANT_TABLE[v.code as usize].degrees(Default::default())
        );
    }
    check_brep(&brep, &grid, boxes);
}

/// Checks a B-rep against the oracle grid: faces and areas per material, loop pairing,
/// triangle count, closedness and volume in every mesh mode.
fn check_brep(brep: &BRep, grid: &Grid, boxes: &[[f64; 6]]) {
    brep.check_invariants().unwrap();
    assert_eq!(brep_faces(brep), grid.faces(), "faces of {boxes:?}");
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for f in &brep.faces {
        for lp in std::iter::once(&f.outer).chain(&f.holes) {
            for i in 0..lp.len() {
                let (u, v) = (lp[i], lp[(i + 1) % lp.len()]);
                *edges.entry((u.min(v), u.max(v))).or_insert(0) += if u < v { 1 } else { -1 };
            }
        }
    }
    assert!(
        edges.values().all(|&b| b == 0),
        "loops are edge-paired in {boxes:?}"
    );
    let tri = brep
        .to_mesh(MeshOptions {
            triangles: true,
            manifold: false,
        })
        .unwrap()
        .mesh;
    let expected: usize = brep
        .faces
        .iter()
        .map(|f| {
            f.outer.len() + f.holes.iter().map(Vec::len).sum::<usize>() + 2 * f.holes.len() - 2
        })
        .sum();
    assert_eq!(tri.face_count(), expected);
    let volume = grid.volume();
    assert_eq!(closed_six_volume(&tri), 6.0 * volume, "volume of {boxes:?}");
    let manifold = brep
        .to_mesh(MeshOptions {
            triangles: true,
            manifold: true,
        })
        .unwrap();
    assert_eq!(manifold.unsplit_edges, 0);
    assert_even_chi_two_per_edge(&manifold.mesh);
    assert_eq!(closed_six_volume(&manifold.mesh), 6.0 * volume);
    let poly = brep.to_mesh(MeshOptions::default()).unwrap().mesh;
    assert_eq!(closed_six_volume(&poly), 6.0 * volume);
}

/// Random boxes with coordinates drawn from `values` distinct values per axis.
fn random_boxes(rng: &mut Rng, n: usize, values: u64) -> Vec<[f64; 6]> {
    (0..n)
        .map(|_| {
            let mut b = [0.0; 6];
            for k in 0..3 {
                let lo = rng.below(values - 1);
                let hi = lo + 1 + rng.below(values - 1 - lo);
                b[k] = lo as f64;
                b[k + 3] = hi as f64;
            }
            b
        })
        .collect()
}

/// Unit voxels of an `s`³ grid, each present with probability `percent`/100.
fn random_voxels(rng: &mut Rng, s: u64, percent: u64) -> Vec<[f64; 6]> {
    let mut out = Vec::new();
    for z in 0..s {
        for y in 0..s {
            for x in 0..s {
                if rng.below(100) < percent {
                    let p = [x, y, z].map(|c| c as f64);
                    out.push([p[0], p[1], p[2], p[0] + 1.0, p[1] + 1.0, p[2] + 1.0]);
                }
            }
        }
    }
    out
}

#[test]
fn random_box_sets_match_the_oracle() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for case in 0..3000 {
        let values = 2 + case % 5;
        let n = 1 + rng.below(9) as usize;
        check_against_oracle(&random_boxes(&mut rng, n, values as u64));
    }
}

#[test]
fn random_voxel_sets_match_the_oracle_and_hit_every_class() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut classes = std::collections::BTreeSet::new();
    for case in 0..1500 {
        let s = 3 + case % 2;
        let percent = 45 + rng.below(26);
        let boxes = random_voxels(&mut rng, s, percent);
        if let Ok(brep) = box_union(&boxes) {
            classes.extend(
                brep.vertices
                    .iter()
                    .map(|v| OCTANT_TABLE[v.code as usize].class),
            );
        }
        check_against_oracle(&boxes);
    }
    assert_eq!(
        classes.into_iter().collect::<Vec<_>>(),
        [1, 6, 7, 22, 23, 24, 25, 27, 30, 105]
    );
}

/// The B-rep's combinatorics with positions mapped by `f`: a sorted list of loops as position
/// lists rotated to start at their smallest position.
fn loops_by_position(
    brep: &BRep,
    f: impl Fn([f64; 3]) -> [f64; 3],
) -> Vec<(usize, Vec<Vec<[u64; 3]>>)> {
    let key = |v: u32| f(brep.vertices[v as usize].position).map(f64::to_bits);
    let canon = |lp: &Vec<u32>| {
        let p: Vec<[u64; 3]> = lp.iter().map(|&v| key(v)).collect();
        let m = (0..p.len()).min_by_key(|&i| p[i]).unwrap();
        let mut r = p[m..].to_vec();
        r.extend_from_slice(&p[..m]);
        r
    };
    let mut out: Vec<_> = brep
        .faces
        .iter()
        .map(|face| {
            let mut loops: Vec<_> = std::iter::once(&face.outer)
                .chain(&face.holes)
                .map(canon)
                .collect();
            loops[1..].sort();
            (face.holes.len(), loops)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn monotone_warps_translations_and_scalings_preserve_the_combinatorics() {
    let mut rng = Rng(0x0123_4567_89ab_cdef);
    let warp = |x: f64| x * x * x + 2.0 * x - 7.5;
    for _ in 0..300 {
        let n = 1 + rng.below(8) as usize;
        let boxes = random_boxes(&mut rng, n, 5);
        let warped: Vec<[f64; 6]> = boxes.iter().map(|b| b.map(warp)).collect();
        let (plain, bent) = (box_union(&boxes).unwrap(), box_union(&warped).unwrap());
        assert_eq!(
            loops_by_position(&plain, |p| p.map(warp)),
            loops_by_position(&bent, |p| p)
        );
        let codes = |b: &BRep| {
            b.vertices
                .iter()
                .map(|v| (v.code, v.degrees))
                .collect::<Vec<_>>()
        };
        assert_eq!(codes(&plain), codes(&bent));
        check_against_oracle(&warped);
    }
}

#[test]
fn axis_permutations_and_mirrors_permute_the_output() {
    let mut rng = Rng(0xfeed_face_cafe_beef);
    for _ in 0..300 {
        let n = 1 + rng.below(8) as usize;
        let boxes = random_boxes(&mut rng, n, 5);
        let brep = box_union(&boxes).unwrap();
        // Cyclic permutation (x, y, z) → (y, z, x) preserves orientation.
        let cyc = |p: [f64; 3]| [p[1], p[2], p[0]];
        let rotated: Vec<[f64; 6]> = boxes
            .iter()
            .map(|b| [b[1], b[2], b[0], b[4], b[5], b[3]])
            .collect();
        assert_eq!(
            loops_by_position(&brep, cyc),
            loops_by_position(&box_union(&rotated).unwrap(), |p| p)
        );
        // A mirror reverses loops, so compare the vertex sets and face areas instead.
        let mirror = |p: [f64; 3]| [-p[0], p[1], p[2]];
        let mirrored: Vec<[f64; 6]> = boxes
            .iter()
            .map(|b| [-b[3], b[1], b[2], -b[0], b[4], b[5]])
            .collect();
        let other = box_union(&mirrored).unwrap();
        let mut a: Vec<[u64; 3]> = brep
            .vertices
            .iter()
            .map(|v| mirror(v.position).map(|c| (c + 0.0).to_bits()))
            .collect();
        let mut b: Vec<[u64; 3]> = other
            .vertices
            .iter()
            .map(|v| v.position.map(|c| (c + 0.0).to_bits()))
            .collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
        assert_eq!(brep.faces.len(), other.faces.len());
    }
}

#[test]
fn splitting_duplicating_and_reordering_boxes_change_nothing() {
    let mut rng = Rng(0x1357_9bdf_2468_ace0);
    for _ in 0..500 {
        let n = 1 + rng.below(8) as usize;
        let boxes = random_boxes(&mut rng, n, 6);
        let brep = box_union(&boxes).unwrap();
        let mut changed = boxes.clone();
        let i = rng.below(changed.len() as u64) as usize;
        let (k, b) = (rng.below(3) as usize, changed[i]);
        let cut = b[k] + (b[k + 3] - b[k]) * 0.5;
        let (mut lo, mut hi) = (b, b);
        lo[k + 3] = cut;
        hi[k] = cut;
        changed[i] = lo;
        changed.push(hi);
        // The cut plane may add a coordinate; the B-rep ignores coordinates that carry nothing.
        assert_eq!(
            box_union(&changed).unwrap().faces,
            brep.faces,
            "split {boxes:?}"
        );
        changed.push(changed[0]);
        changed.reverse();
        assert_eq!(
            box_union(&changed).unwrap(),
            brep,
            "duplicate and reverse {boxes:?}"
        );
    }
}

#[test]
fn material_faces_match_the_oracle_per_material() {
    let mut rng = Rng(0x0bad_cafe_dead_beef);
    for case in 0..1500 {
        let n = 1 + rng.below(8) as usize;
        let boxes = if case % 2 == 0 {
            random_boxes(&mut rng, n, 2 + case as u64 % 5)
        } else {
            random_voxels(&mut rng, 3, 55)
        };
        let materials: Vec<u32> = boxes.iter().map(|_| rng.below(3) as u32 * 5).collect();
        let brep = box_union_with_materials(&boxes, &materials)
            .unwrap_or_else(|e| panic!("{e}: {boxes:?} {materials:?}"));
        check_brep(&brep, &Grid::with_materials(&boxes, &materials), &boxes);
        let mesh = brep.to_mesh(MeshOptions::default()).unwrap().mesh;
        let face_materials = mesh.face_materials().unwrap();
        assert!(face_materials.iter().all(|m| materials.contains(m)));
    }
}

#[test]
fn one_material_gives_the_plain_union() {
    let mut rng = Rng(0x7777_1234_5678_9abc);
    for _ in 0..500 {
        let n = 1 + rng.below(8) as usize;
        let boxes = random_boxes(&mut rng, n, 5);
        let plain = box_union(&boxes).unwrap();
        let mut one = box_union_with_materials(&boxes, &vec![0; boxes.len()]).unwrap();
        assert!(one.has_materials);
        one.has_materials = false;
        assert_eq!(one, plain, "{boxes:?}");
    }
}

#[test]
fn per_material_solids_share_their_interfaces() {
    let mut rng = Rng(0x4242_4242_4242_4242);
    for _ in 0..300 {
        let boxes = random_voxels(&mut rng, 3, 60);
        let materials: Vec<u32> = boxes.iter().map(|_| rng.below(3) as u32).collect();
        let solids = box_union_per_material(&boxes, &materials).unwrap();
        let mut total = 0.0;
        let mut directed: HashMap<[[u64; 3]; 2], i32> = HashMap::new();
        for (m, brep) in &solids {
            assert!(brep.faces.iter().all(|f| f.material == *m));
            let mesh = brep.to_mesh(MeshOptions::default()).unwrap().mesh;
            total += closed_six_volume(&mesh);
            let p = mesh.positions();
            for face in mesh.faces() {
                for i in 0..face.len() {
                    let (u, v) = (face[i], face[(i + 1) % face.len()]);
                    let key = [p[u as usize], p[v as usize]].map(|q| q.map(f64::to_bits));
                    *directed.entry(key).or_insert(0) += 1;
                }
            }
        }
        assert_eq!(total, 6.0 * boxes.len() as f64);
        let joined = per_material_mesh(&solids, MeshOptions::default())
            .unwrap()
            .mesh;
        assert_eq!(closed_six_volume(&joined), total);
        assert_eq!(
            joined.face_materials().map(<[u32]>::len),
            Some(joined.face_count())
        );
        // An interface face of one solid is a face of the other with the opposite direction,
        // so the per-material meshes together stay balanced edge by edge.
        for (&[u, v], &n) in &directed {
            assert_eq!(directed.get(&[v, u]).copied().unwrap_or(0), n);
        }
    }
}

#[test]
fn huge_tiny_and_negative_coordinates_keep_the_combinatorics() {
    let mut rng = Rng(0x5151_2727_9393_abab);
    let warps: [fn(f64) -> f64; 4] = [
        |x| (x - 2.0) * 1e250,
        |x| (x - 2.0) * 1e-300,
        |x| -1e15 + x * 0.125,
        |x| {
            if x < 2.0 {
                -f64::MAX / 4.0 * (2.0 - x)
            } else {
                f64::MAX / 4.0 * (x - 2.0)
            }
        },
    ];
    for case in 0..400 {
        let n = 1 + rng.below(8) as usize;
        let boxes = random_boxes(&mut rng, n, 2 + case % 4);
        let plain = box_union(&boxes).unwrap();
        for warp in warps {
            let warped: Vec<[f64; 6]> = boxes.iter().map(|b| b.map(warp)).collect();
            let bent = box_union(&warped).unwrap();
            assert_eq!(
                loops_by_position(&plain, |p| p.map(warp)),
                loops_by_position(&bent, |p| p)
            );
            // Triangulation either succeeds with the exact count or reports the range error;
            // it never panics.
            if let Err(e) = bent.to_mesh(MeshOptions {
                triangles: true,
                manifold: false,
            }) {
                assert!(e.to_string().contains("cannot be triangulated"), "{e}");
            }
        }
    }
}

#[test]
fn the_output_does_not_depend_on_the_thread_count() {
    let boxes = csgkit::ortho::random_grid_boxes(3000, 7);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let brep = box_union(&boxes).unwrap();
            let manifold = brep
                .to_mesh(MeshOptions {
                    triangles: true,
                    manifold: true,
                })
                .unwrap();
            (brep, manifold)
        })
    };
    let (one, four) = (on(1), on(4));
    assert_eq!(one.0, four.0);
    assert_eq!(one.1, four.1);
}

#[test]
fn progress_counts_every_plane_and_can_cancel() {
    use std::sync::Mutex;

    use csgkit::ortho::{OrthoError, box_union_timed};
    use csgkit::{Cancelled, Progress, Report, Stage};
    let boxes = csgkit::ortho::random_grid_boxes(500, 3);
    let seen = Mutex::new(Vec::new());
    let record = |report: Report| {
        seen.lock().unwrap().push(report);
        true
    };
    let (brep, _) = box_union_timed(&boxes, None, &Progress::new(&record)).unwrap();
    assert_eq!(brep, box_union(&boxes).unwrap());
    let seen = seen.into_inner().unwrap();
    for stage in [Stage::Sweep, Stage::Loops] {
        let reports: Vec<_> = seen.iter().filter(|r| r.stage == stage).collect();
        let total = reports[0].total;
        assert_eq!(reports.len(), total, "{stage:?} reports once per task");
        assert!(reports.iter().any(|r| r.done == total));
    }
    let stop = |report: Report| report.done < 3;
    let cancelled = box_union_timed(&boxes, None, &Progress::new(&stop));
    assert_eq!(cancelled.unwrap_err(), OrthoError::Cancelled(Cancelled));
}
