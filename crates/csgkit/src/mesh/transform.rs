//! Affine maps of meshes: the one place where a mesh is moved, shared by the CSG layer (leaf
//! transforms) and the readers of formats whose files place parts (3MF build items and
//! components, glTF nodes).
//!
//! A map is applied to every position in f64 (the identity leaves positions bit-identical).
//! Corner normals are mapped by the inverse transpose (the cofactor matrix over the
//! determinant), keeping their length, so they stay perpendicular to their faces and point
//! out of the moved solid. A map that mirrors (negative determinant) also reverses every
//! face's corner order, with its corner attributes, so a closed outward mesh stays outward.

use super::{FaceId, Mesh, MeshParts};

/// An affine map, row-major: `x' = M·x + t` for rows `[m0, m1, m2, t]`.
pub type Affine = [[f64; 4]; 3];

/// The identity map.
pub const IDENTITY: Affine = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
];

/// `outer ∘ inner`: the map that applies `inner`, then `outer`.
pub fn compose(outer: Affine, inner: Affine) -> Affine {
    let mut out = [[0.0; 4]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, value) in row.iter_mut().enumerate() {
            *value = (0..3).map(|k| outer[i][k] * inner[k][j]).sum::<f64>();
            if j == 3 {
                *value += outer[i][3];
            }
        }
    }
    out
}

/// The determinant of the linear part of `m`.
pub(crate) fn determinant(m: &Affine) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// `p` moved by `transform`.
pub fn moved(transform: &Affine, p: [f64; 3]) -> [f64; 3] {
    let m = transform;
    [0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3])
}

/// `mesh` moved by `transform`, faces reversed where it mirrors; `None` when the transform is
/// singular (determinant zero) or has a non-finite entry.
pub fn transformed(mesh: &Mesh, transform: &Affine) -> Option<Mesh> {
    let m = transform;
    let det = determinant(m);
    if !det.is_finite() || det == 0.0 || !m.as_flattened().iter().all(|x| x.is_finite()) {
        return None;
    }
    if *m == IDENTITY {
        return Some(mesh.clone());
    }
    let mut parts: MeshParts = mesh.clone().into_parts();
    for p in &mut parts.positions {
        *p = moved(m, *p);
    }
    if let Some(normals) = parts.corner_normals.as_mut() {
        let cofactor = cofactors(m);
        for n in normals.iter_mut() {
            let v = n.map(f64::from);
            let length = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            let w = [0, 1, 2].map(|i| (0..3).map(|j| cofactor[i][j] * v[j]).sum::<f64>() / det);
            let scale = length / w.iter().map(|x| x * x).sum::<f64>().sqrt();
            if scale.is_finite() {
                *n = w.map(|x| (x * scale) as f32);
            }
        }
    }
    if det < 0.0 {
        reverse_faces(&mut parts, mesh);
    }
    Some(Mesh::from_parts(parts).expect("the same faces over moved positions"))
}

/// The cofactor matrix of the linear part of `m`: `det(m) · m⁻ᵀ`.
fn cofactors(m: &Affine) -> [[f64; 3]; 3] {
    let c = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]
    };
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| c(i, j)))
}

/// Reverses every face's corner order (and its corner attributes with it; the normals were
/// mapped already).
fn reverse_faces(parts: &mut MeshParts, mesh: &Mesh) {
    for f in 0..mesh.face_count() {
        let range = mesh.face_range(FaceId::new(f));
        parts.corners[range.clone()].reverse();
        if let Some(uvs) = parts.corner_uvs.as_mut() {
            uvs[range.clone()].reverse();
        }
        if let Some(normals) = parts.corner_normals.as_mut() {
            normals[range].reverse();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::measure;
    use crate::primitives::cuboid;

    #[test]
    fn mirrors_keep_closed_meshes_outward_and_singular_maps_are_refused() {
        let cube = cuboid([0.0; 3], [1.0, 2.0, 3.0]);
        let mirror = [
            [-2.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        let moved = transformed(&cube, &mirror).expect("a regular map");
        assert_eq!(measure(&moved).volume, 12.0);
        let bbox = measure(&moved).bbox.expect("faces");
        assert_eq!((bbox.min[0], bbox.max[0]), (-1.0, 1.0));
        assert_eq!(transformed(&cube, &IDENTITY), Some(cube.clone()));
        let flat = [[0.0; 4], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]];
        assert_eq!(transformed(&cube, &flat), None);
        let shift = [
            [1.0, 0.0, 0.0, 5.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        let mut parts = cube.clone().into_parts();
        parts.corner_normals = Some(vec![[3.0, 4.0, 0.0]; cube.corner_count()]);
        let with_normals = Mesh::from_parts(parts).unwrap();
        // x doubled and mirrored: the normal (3, 4, 0) of a plane becomes (-1.5, 4, 0), length 5.
        let normal = transformed(&with_normals, &mirror)
            .unwrap()
            .corner_normals()
            .unwrap()[0];
        let expected = [-1.5, 4.0, 0.0].map(|x: f64| x * 5.0 / 4.272001872658765);
        assert!(
            normal
                .iter()
                .zip(expected)
                .all(|(a, b)| (f64::from(*a) - b).abs() < 1e-6)
        );
        assert_eq!(compose(shift, mirror)[0], [-2.0, 0.0, 0.0, 6.0]);
    }
}
