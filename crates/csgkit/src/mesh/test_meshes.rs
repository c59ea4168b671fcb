//! Small meshes built in code for the unit tests of the measures.

use super::{Mesh, MeshParts};
use crate::primitives::{self, cuboid};

/// An axis-aligned cube, 8 vertices and 12 outward triangles.
pub(crate) fn cube(origin: [f64; 3], size: f64) -> Mesh {
    cuboid(origin, origin.map(|x| x + size))
}

/// The triangles of `mesh`, which must be a triangle mesh.
fn triangles(mesh: &Mesh) -> Vec<[u32; 3]> {
    mesh.fan_triangles().map(|(_, t)| t).collect()
}

/// The unit cube without its top (z = 1) face: 10 triangles.
pub(crate) fn open_box() -> Mesh {
    let cube = cube([0.0; 3], 1.0);
    let mut sides = triangles(&cube);
    // Vertices 4..8 are the top corners (z from bit 2).
    sides.retain(|t| !t.iter().all(|&v| v >= 4));
    Mesh::from_triangles(cube.positions().to_vec(), &sides).expect("valid box")
}

/// Two unit cubes that share the edge x = y = 1, stored without shared vertices.
pub(crate) fn two_cubes_sharing_an_edge() -> Mesh {
    let (a, b) = (cube([0.0; 3], 1.0), cube([1.0, 1.0, 0.0], 1.0));
    let mut positions = a.positions().to_vec();
    positions.extend_from_slice(b.positions());
    let mut tris = triangles(&a);
    tris.extend(triangles(&b).iter().map(|t| t.map(|v| v + 8)));
    Mesh::from_triangles(positions, &tris).expect("valid cubes")
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
    let mesh = primitives::torus([0.0; 3], 3.0, 1.0, n, n);
    if split {
        return mesh;
    }
    // `primitives::torus` splits quad `a b c d` into the consecutive triangles `a b c`, `a c d`.
    let tris = triangles(&mesh);
    let corners = tris
        .chunks(2)
        .flat_map(|t| [t[0][0], t[0][1], t[0][2], t[1][2]]);
    let face_starts = (0..=tris.len() / 2).map(|k| 4 * k as u32).collect();
    Mesh::from_parts(MeshParts {
        positions: mesh.positions().to_vec(),
        corners: corners.collect(),
        face_starts: Some(face_starts),
        ..MeshParts::default()
    })
    .expect("valid torus")
}
