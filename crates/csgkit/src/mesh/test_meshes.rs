//! Small meshes built in code for the unit tests of the measures.

use super::{Mesh, MeshParts};

/// The triangles of the unit cube with vertex `x + 2y + 4z`, wound outward.
const CUBE_TRIANGLES: [[u32; 3]; 12] = [
    [0, 2, 3],
    [0, 3, 1],
    [4, 5, 7],
    [4, 7, 6],
    [0, 1, 5],
    [0, 5, 4],
    [2, 6, 7],
    [2, 7, 3],
    [0, 4, 6],
    [0, 6, 2],
    [1, 3, 7],
    [1, 7, 5],
];

fn cube_positions(origin: [f64; 3], size: f64) -> Vec<[f64; 3]> {
    (0..8)
        .map(|i| {
            let bit = |k: usize| f64::from((i >> k) & 1) * size;
            [origin[0] + bit(0), origin[1] + bit(1), origin[2] + bit(2)]
        })
        .collect()
}

/// An axis-aligned cube, 8 vertices and 12 outward triangles.
pub(crate) fn cube(origin: [f64; 3], size: f64) -> Mesh {
    Mesh::from_triangles(cube_positions(origin, size), &CUBE_TRIANGLES).expect("valid cube")
}

/// The unit cube without its top (z = 1) face: 10 triangles.
pub(crate) fn open_box() -> Mesh {
    let triangles: Vec<[u32; 3]> = CUBE_TRIANGLES
        .iter()
        .copied()
        .filter(|t| !t.iter().all(|&v| v >= 4))
        .collect();
    Mesh::from_triangles(cube_positions([0.0; 3], 1.0), &triangles).expect("valid box")
}

/// Two unit cubes that share the edge x = y = 1, stored without shared vertices.
pub(crate) fn two_cubes_sharing_an_edge() -> Mesh {
    let mut positions = cube_positions([0.0; 3], 1.0);
    positions.extend(cube_positions([1.0, 1.0, 0.0], 1.0));
    let triangles: Vec<[u32; 3]> = CUBE_TRIANGLES
        .iter()
        .copied()
        .chain(CUBE_TRIANGLES.iter().map(|t| t.map(|v| v + 8)))
        .collect();
    Mesh::from_triangles(positions, &triangles).expect("valid cubes")
}

/// The tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), optionally with its slanted face flipped.
pub(crate) fn tetrahedron(flip_one: bool) -> Mesh {
    let positions = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let slanted = if flip_one { [1, 3, 2] } else { [1, 2, 3] };
    Mesh::from_triangles(positions, &[[0, 2, 1], [0, 1, 3], [0, 3, 2], slanted])
        .expect("valid tetrahedron")
}

/// An `n` × `n` quad grid wrapped around a torus (major radius 3, minor radius 1): genus 1.
/// With `split` the quads are split into triangles.
pub(crate) fn torus(n: u32, split: bool) -> Mesh {
    let angle = |k: u32| std::f64::consts::TAU * f64::from(k) / f64::from(n);
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (angle(i), angle(j));
            let r = 3.0 + v.cos();
            positions.push([r * u.cos(), r * u.sin(), v.sin()]);
        }
    }
    let id = |i: u32, j: u32| (i % n) * n + (j % n);
    let mut corners = Vec::new();
    let mut face_starts = vec![0];
    for i in 0..n {
        for j in 0..n {
            let quad = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if split {
                corners.extend([quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]);
            } else {
                corners.extend(quad);
                face_starts.push(corners.len() as u32);
            }
        }
    }
    let face_starts = (!split).then_some(face_starts);
    Mesh::from_parts(MeshParts {
        positions,
        corners,
        face_starts,
        ..MeshParts::default()
    })
    .expect("valid torus")
}
