//! The orthogonal engine against `design/ortho.md`: §A7 (E1–E10), the 2D vectors R1–R6, a
//! brute-force grid oracle on random box and voxel sets, and metamorphic relations.

use std::collections::HashMap;

use csgkit::Mesh;
use csgkit::ortho::{
    BRep, DegreeConvention, MeshOptions, OCTANT_TABLE, box_union, box_union_vertices,
    rect_union_corners,
};

/// Boxes from the design's `(x0, x1, y0, y1, z0, z1)` notation.
fn boxes(spec: &[[i32; 6]]) -> Vec<[f64; 6]> {
    spec.iter()
        .map(|b| [b[0], b[2], b[4], b[1], b[3], b[5]].map(f64::from))
        .collect()
}

/// Undirected B-rep edges (consecutive loop vertices) with the number of loops using each.
fn brep_edges(brep: &BRep) -> HashMap<(u32, u32), usize> {
    let mut edges = HashMap::new();
    for face in &brep.faces {
        for lp in std::iter::once(&face.outer).chain(&face.holes) {
            for i in 0..lp.len() {
                let (u, v) = (lp[i], lp[(i + 1) % lp.len()]);
                *edges.entry((u.min(v), u.max(v))).or_insert(0) += 1;
            }
        }
    }
    edges
}

/// Checks every directed edge of `mesh` has its reverse (closed, no T-junction) and returns
/// 6 × the signed volume.
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

struct Expected {
    boxes: &'static [[i32; 6]],
    v: usize,
    f: usize,
    h: usize,
    e: usize,
    nm: usize,
    t: usize,
    vol: f64,
    special: &'static [([i32; 3], &'static str)],
    comp: usize,
    chi: i64,
}

/// Components and Euler characteristic of a 2-manifold triangle mesh, after checking every
/// undirected edge has exactly two triangles with opposite directions.
fn manifold_components_and_chi(mesh: &Mesh) -> (usize, i64) {
    let mut edges: HashMap<(u32, u32), Vec<(usize, bool)>> = HashMap::new();
    for (t, face) in mesh.faces().enumerate() {
        for i in 0..3 {
            let (u, v) = (face[i], face[(i + 1) % 3]);
            edges
                .entry((u.min(v), u.max(v)))
                .or_default()
                .push((t, u < v));
        }
    }
    let mut parent: Vec<usize> = (0..mesh.face_count()).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            x = p[x];
        }
        x
    }
    for uses in edges.values() {
        assert_eq!(uses.len(), 2, "manifold edges carry two triangles");
        assert_ne!(
            uses[0].1, uses[1].1,
            "manifold edges are consistently oriented"
        );
        let (a, b) = (find(&mut parent, uses[0].0), find(&mut parent, uses[1].0));
        parent[a.max(b)] = a.min(b);
    }
    let comps = (0..parent.len())
        .filter(|&t| find(&mut parent, t) == t)
        .count();
    let mut used: Vec<u32> = mesh.corners().to_vec();
    used.sort_unstable();
    used.dedup();
    let chi = used.len() as i64 - edges.len() as i64 + mesh.face_count() as i64;
    (comps, chi)
}

const CASES: [(&str, Expected); 10] = [
    (
        "E1",
        Expected {
            comp: 1,
            chi: 2,
            boxes: &[[0, 1, 0, 1, 0, 1]],
            v: 8,
            f: 6,
            h: 0,
            e: 12,
            nm: 0,
            t: 12,
            vol: 1.0,
            special: &[],
        },
    ),
    (
        "E2",
        Expected {
            comp: 2,
            chi: 4,
            boxes: &[[0, 1, 0, 1, 0, 1], [1, 2, 1, 2, 0, 1]],
            v: 14,
            f: 12,
            h: 0,
            e: 23,
            nm: 1,
            t: 24,
            vol: 2.0,
            special: &[
                ([0, 0, 0], "010101"),
                ([0, 0, 1], "010110"),
                ([0, 1, 0], "011001"),
                ([0, 1, 1], "011010"),
                ([1, 0, 0], "100101"),
                ([1, 0, 1], "100110"),
                ([1, 1, 0], "111102"),
                ([1, 1, 1], "111120"),
                ([1, 2, 0], "011001"),
                ([1, 2, 1], "011010"),
                ([2, 1, 0], "100101"),
                ([2, 1, 1], "100110"),
                ([2, 2, 0], "101001"),
                ([2, 2, 1], "101010"),
            ],
        },
    ),
    (
        "E3",
        Expected {
            comp: 2,
            chi: 4,
            boxes: &[[0, 1, 0, 1, 0, 1], [1, 2, 1, 2, 1, 2]],
            v: 15,
            f: 12,
            h: 0,
            e: 24,
            nm: 0,
            t: 24,
            vol: 2.0,
            special: &[([1, 1, 1], "111111")],
        },
    ),
    (
        "E4",
        Expected {
            comp: 1,
            chi: 2,
            boxes: &[[0, 2, 0, 1, 0, 1], [0, 1, 1, 2, 0, 1]],
            v: 12,
            f: 8,
            h: 0,
            e: 18,
            nm: 0,
            t: 20,
            vol: 3.0,
            special: &[([1, 1, 0], "101001"), ([1, 1, 1], "101010")],
        },
    ),
    (
        "E5",
        Expected {
            comp: 1,
            chi: 2,
            boxes: &[[0, 2, 0, 2, 0, 1], [1, 3, 1, 3, 1, 2]],
            v: 18,
            f: 12,
            h: 0,
            e: 28,
            nm: 0,
            t: 32,
            vol: 8.0,
            special: &[
                ([1, 2, 1], "022011"),
                ([2, 1, 1], "200211"),
                ([1, 1, 1], "010110"),
                ([2, 2, 1], "101001"),
            ],
        },
    ),
    (
        "E6",
        Expected {
            comp: 1,
            chi: 2,
            boxes: &[[0, 3, 1, 2, 0, 1], [1, 2, 0, 3, 1, 2]],
            v: 20,
            f: 14,
            h: 0,
            e: 32,
            nm: 0,
            t: 36,
            vol: 6.0,
            special: &[
                ([1, 1, 1], "020211"),
                ([1, 2, 1], "022011"),
                ([2, 1, 1], "200211"),
                ([2, 2, 1], "202011"),
            ],
        },
    ),
    (
        "E7",
        Expected {
            comp: 1,
            chi: 2,
            boxes: &[[1, 2, 1, 2, 0, 1], [0, 2, 1, 2, 1, 2], [1, 2, 0, 2, 1, 2]],
            v: 17,
            f: 12,
            h: 0,
            e: 27,
            nm: 0,
            t: 30,
            vol: 4.0,
            special: &[([1, 1, 1], "020202")],
        },
    ),
    (
        "E8",
        Expected {
            comp: 2,
            chi: 4,
            boxes: &[[0, 2, 0, 1, 0, 1], [0, 1, 1, 2, 1, 2]],
            v: 15,
            f: 12,
            h: 0,
            e: 24,
            nm: 1,
            t: 26,
            vol: 3.0,
            special: &[([1, 1, 1], "102121"), ([0, 1, 1], "021111")],
        },
    ),
    (
        "E9",
        Expected {
            comp: 1,
            chi: 0,
            boxes: &[
                [0, 3, 0, 1, 0, 1],
                [0, 3, 2, 3, 0, 1],
                [0, 1, 0, 3, 0, 1],
                [2, 3, 0, 3, 0, 1],
            ],
            v: 16,
            f: 10,
            h: 2,
            e: 24,
            nm: 0,
            t: 32,
            vol: 8.0,
            special: &[([1, 1, 1], "101010")],
        },
    ),
    (
        "E10",
        Expected {
            comp: 4,
            chi: 8,
            boxes: &[
                [0, 1, 0, 1, 0, 1],
                [1, 2, 1, 2, 0, 1],
                [1, 2, 0, 1, 1, 2],
                [0, 1, 1, 2, 1, 2],
            ],
            v: 23,
            f: 24,
            h: 0,
            e: 42,
            nm: 6,
            t: 48,
            vol: 4.0,
            special: &[([1, 1, 1], "222222"), ([1, 1, 0], "111102")],
        },
    ),
];

fn degrees_str(d: [u8; 6]) -> String {
    d.iter().map(|x| x.to_string()).collect()
}

#[test]
fn design_vectors_e1_to_e10() {
    for (name, ex) in &CASES {
        let input = boxes(ex.boxes);
        let brep = box_union(&input).unwrap();
        brep.check_invariants().unwrap();
        let at: HashMap<[i64; 3], [u8; 6]> = brep
            .vertices
            .iter()
            .map(|v| (v.position.map(|c| c as i64), v.degrees))
            .collect();
        for (p, d) in ex.special {
            let got = at.get(&p.map(i64::from)).map(|&d| degrees_str(d));
            assert_eq!(got.as_deref(), Some(*d), "{name} vertex {p:?}");
        }
        let edges = brep_edges(&brep);
        let holes: usize = brep.faces.iter().map(|f| f.holes.len()).sum();
        let nm = edges.values().filter(|&&n| n == 4).count();
        assert!(edges.values().all(|&n| n == 2 || n == 4), "{name}");
        let tri = brep
            .to_mesh(MeshOptions {
                triangles: true,
                manifold: false,
            })
            .unwrap()
            .mesh;
        let got = (
            brep.vertices.len(),
            brep.faces.len(),
            holes,
            edges.len(),
            nm,
            tri.face_count(),
        );
        assert_eq!(
            got,
            (ex.v, ex.f, ex.h, ex.e, ex.nm, ex.t),
            "{name} V/F/H/E(nm)/T"
        );
        assert_eq!(closed_six_volume(&tri), 6.0 * ex.vol, "{name} volume");
        let manifold = brep
            .to_mesh(MeshOptions {
                triangles: true,
                manifold: true,
            })
            .unwrap();
        assert_eq!(manifold.unsplit_edges, 0);
        assert_eq!(
            manifold_components_and_chi(&manifold.mesh),
            (ex.comp, ex.chi),
            "{name} comp, chi"
        );
        assert_eq!(
            closed_six_volume(&manifold.mesh),
            6.0 * ex.vol,
            "{name} manifold volume"
        );
        let poly = brep.to_mesh(MeshOptions::default()).unwrap().mesh;
        assert_eq!(
            closed_six_volume(&poly),
            6.0 * ex.vol,
            "{name} polygon volume"
        );
        // Every vertex not listed is a trihedral corner: degree 1 in one direction per axis.
        for v in &brep.vertices {
            let d = v.degrees;
            let trihedral = (0..3).all(|k| d[2 * k] + d[2 * k + 1] == 1);
            let listed = ex
                .special
                .iter()
                .any(|(p, _)| p.map(f64::from) == v.position);
            // E10 has six class-6 vertices at the face centres of the 2-cube; one is listed.
            let face_centre = *name == "E10" && OCTANT_TABLE[v.code as usize].class == 6;
            assert!(
                listed || trihedral || face_centre,
                "{name} vertex {:?} {d:?}",
                v.position
            );
        }
        if *name == "E10" {
            let class6 = brep
                .vertices
                .iter()
                .filter(|v| OCTANT_TABLE[v.code as usize].class == 6);
            assert_eq!(class6.count(), 6);
        }
    }
}

#[test]
fn e8_seed_convention_leaves_the_class_25_degrees() {
    let input = boxes(&[[0, 2, 0, 1, 0, 1], [0, 1, 1, 2, 1, 2]]);
    let seed = box_union_vertices(&input, DegreeConvention::Seed).unwrap();
    let v = seed.iter().find(|v| v.position == [1.0, 1.0, 1.0]).unwrap();
    assert_eq!(degrees_str(v.degrees), "100101");
}

fn record(x: f64, y: f64, dirs: &str) -> ([f64; 2], [bool; 4]) {
    let d: Vec<bool> = dirs.chars().map(|c| c == '1').collect();
    ([x, y], [d[0], d[1], d[2], d[3]])
}

fn corners(rects: &[[f64; 4]]) -> Vec<([f64; 2], [bool; 4])> {
    rect_union_corners(rects)
        .unwrap()
        .into_iter()
        .map(|c| (c.position, c.dirs))
        .collect()
}

#[test]
fn rectangle_vectors_r1_to_r5() {
    let r1 = corners(&[[0.0, 0.0, 2.0, 1.0]]);
    let want = [
        record(0.0, 0.0, "0101"),
        record(2.0, 0.0, "1001"),
        record(0.0, 1.0, "0110"),
        record(2.0, 1.0, "1010"),
    ];
    assert_eq!(r1, want);
    let r2 = corners(&[[0.0, 0.0, 1.0, 1.0], [1.0, 1.0, 2.0, 2.0]]);
    assert_eq!(r2.len(), 8);
    let at11: Vec<_> = r2.iter().filter(|c| c.0 == [1.0, 1.0]).collect();
    assert!(at11.contains(&&record(1.0, 1.0, "1010")) && at11.contains(&&record(1.0, 1.0, "0101")));
    let r3 = corners(&[[0.0, 1.0, 1.0, 2.0], [1.0, 0.0, 2.0, 1.0]]);
    let at11: Vec<_> = r3.iter().filter(|c| c.0 == [1.0, 1.0]).collect();
    assert_eq!(at11.len(), 2);
    assert!(at11.contains(&&record(1.0, 1.0, "1001")) && at11.contains(&&record(1.0, 1.0, "0110")));
    let r4 = corners(&[[0.0, 1.0, 3.0, 2.0], [1.0, 0.0, 2.0, 3.0]]);
    assert_eq!(r4.len(), 12);
    for want in [
        record(1.0, 1.0, "0101"),
        record(2.0, 1.0, "1001"),
        record(1.0, 2.0, "0110"),
        record(2.0, 2.0, "1010"),
    ] {
        assert!(r4.contains(&want), "{want:?}");
    }
    let r5 = corners(&[
        [0.0, 0.0, 3.0, 1.0],
        [0.0, 2.0, 3.0, 3.0],
        [0.0, 0.0, 1.0, 3.0],
        [2.0, 0.0, 3.0, 3.0],
    ]);
    assert_eq!(r5.len(), 8);
    for want in [
        record(1.0, 1.0, "1010"),
        record(2.0, 1.0, "0110"),
        record(1.0, 2.0, "1001"),
        record(2.0, 2.0, "0101"),
    ] {
        assert!(r5.contains(&want), "{want:?}");
    }
}

#[test]
fn rectangle_vector_r6_gives_one_weakly_simple_loop() {
    let rects = [
        [0.0, 0.0, 3.0, 1.0],
        [0.0, 0.0, 1.0, 3.0],
        [1.0, 2.0, 2.0, 3.0],
        [2.0, 1.0, 3.0, 2.0],
    ];
    let r6 = corners(&rects);
    let at22: Vec<_> = r6.iter().filter(|c| c.0 == [2.0, 2.0]).collect();
    assert_eq!(at22.len(), 2);
    assert!(at22.contains(&&record(2.0, 2.0, "1001")) && at22.contains(&&record(2.0, 2.0, "0110")));
    let input: Vec<[f64; 6]> = rects
        .iter()
        .map(|r| [r[0], r[1], 0.0, r[2], r[3], 1.0])
        .collect();
    let brep = box_union(&input).unwrap();
    let top: Vec<_> = brep
        .faces
        .iter()
        .filter(|f| f.orientation == csgkit::ortho::Orientation::PosZ)
        .collect();
    assert_eq!(top.len(), 1);
    assert_eq!(top[0].outer.len(), 10);
    assert!(top[0].holes.is_empty());
    let pinch = brep
        .vertices
        .iter()
        .position(|v| v.position == [2.0, 2.0, 1.0])
        .unwrap() as u32;
    assert_eq!(top[0].outer.iter().filter(|&&v| v == pinch).count(), 2);
    let tri = brep
        .to_mesh(MeshOptions {
            triangles: true,
            manifold: false,
        })
        .unwrap()
        .mesh;
    assert_eq!(closed_six_volume(&tri), 6.0 * 7.0);
}

/// Eight voxels whose union has a non-manifold edge with single-fan endpoints (two class-25
/// vertices with five occupied octants): the manifold mode must split that edge with one
/// midpoint per sheet (§A6 step 3). Found by the random voxel search, then shrunk.
#[test]
fn manifold_mode_splits_a_sheet_edge_at_its_midpoints() {
    let voxels = [
        [0, 1, 0],
        [1, 1, 0],
        [1, 2, 0],
        [0, 1, 1],
        [1, 2, 1],
        [0, 1, 2],
        [1, 1, 2],
        [1, 2, 2],
    ];
    let input: Vec<[f64; 6]> = voxels
        .iter()
        .map(|v| {
            let p = v.map(f64::from);
            [p[0], p[1], p[2], p[0] + 1.0, p[1] + 1.0, p[2] + 1.0]
        })
        .collect();
    let brep = box_union(&input).unwrap();
    let out = brep
        .to_mesh(MeshOptions {
            triangles: true,
            manifold: true,
        })
        .unwrap();
    assert_eq!(out.unsplit_edges, 0);
    let midpoints = out
        .mesh
        .positions()
        .iter()
        .filter(|p| p.iter().any(|c| c.fract() != 0.0));
    assert_eq!(midpoints.count(), 2);
    let (_, chi) = manifold_components_and_chi(&out.mesh);
    assert_eq!(chi % 2, 0);
    assert_eq!(closed_six_volume(&out.mesh), 6.0 * 8.0);
}

#[test]
fn an_edited_brep_with_a_missing_vertex_is_an_error_not_a_panic() {
    let mut brep = box_union(&boxes(&[[0, 1, 0, 1, 0, 1]])).unwrap();
    brep.faces[0].outer[0] = 99;
    let err = brep.to_mesh(MeshOptions::default()).unwrap_err();
    assert!(err.to_string().contains("missing vertex"), "{err}");
}
