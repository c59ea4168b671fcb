//! Geometric measures: signed volume, surface area and bounding box.
//!
//! # Definitions
//! - **Signed volume**: the sum over the fan triangles (a, b, c) of every face of the signed
//!   tetrahedron volume det(a, b, c) / 6, i.e. the cone from the origin. For a closed mesh this
//!   is the enclosed volume, positive when the faces wind counter-clockwise seen from outside,
//!   and does not depend on the apex; for an open mesh it depends on the apex, and the origin
//!   is used, as the reference measurements do.
//! - **Area**: the sum over faces of half the norm of the face's vector area, Σ (b − a) × (c − a)
//!   over its fan triangles (a, b, c): a triangle's area, and a planar polygon's area, convex
//!   or not (the fan of a non-convex polygon overlaps itself with triangles of opposite
//!   orientation, which cancel in the vector sum but not in a sum of triangle areas); for a
//!   non-planar polygon, the area of its projection on the plane normal to its vector area.
//! - **Bounding box**: the componentwise min and max over the vertices that faces use;
//!   `None` for a mesh without faces.
//!
//! # Numeric model
//! Coordinates are shifted to the bounding-box centre `m` before the products are formed,
//! which removes the cancellation of large offsets (geo's `area.rs` does the same). The cone
//! from `m` differs from the cone from the origin by `(1/3) m · A`, where `A` is the vector
//! area Σ (b − a) × (c − a) / 2 (zero for a closed mesh), so that term is added back; it is
//! computed from shifted coordinates too. Sums are compensated (Neumaier).
//! With coordinates near 3.4e38 (`Cray_right.obj`) the tetrahedron determinants reach about
//! 1e116, well inside f64, so the volume is finite. Past about 1e102 a determinant may
//! overflow to ±∞ and the volume becomes ±∞ or NaN; the area overflows past about 1e77.
//! Neither panics; the JSON report writes a non-finite value as `null`.
//!
//! # Complexity
//! O(C) time for C corners, O(1) extra memory.

use super::vector::{cross, dot, norm, sub};
use serde::Serialize;

use super::Mesh;

/// An axis-aligned box: componentwise minimum and maximum.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BoundingBox {
    /// The minimum corner.
    pub min: [f64; 3],
    /// The maximum corner.
    pub max: [f64; 3],
}

impl BoundingBox {
    /// The centre of the box.
    pub fn center(&self) -> [f64; 3] {
        // Halving first cannot overflow, unlike (min + max) / 2 near f64::MAX.
        std::array::from_fn(|i| self.min[i] / 2.0 + self.max[i] / 2.0)
    }
}

/// Volume and area of a mesh.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Measures {
    /// Signed volume of the cone from the origin over the faces.
    pub volume: f64,
    /// Surface area.
    pub area: f64,
    /// Bounding box of the used vertices, `None` without faces.
    pub bbox: Option<BoundingBox>,
}

/// The bounding box of the vertices that faces use, `None` for a mesh without faces.
pub fn bounding_box(mesh: &Mesh) -> Option<BoundingBox> {
    let mut corners = mesh.corners().iter();
    let first = mesh.positions()[*corners.next()? as usize];
    let mut bbox = BoundingBox {
        min: first,
        max: first,
    };
    for &v in corners {
        let p = mesh.positions()[v as usize];
        bbox.min = std::array::from_fn(|i| bbox.min[i].min(p[i]));
        bbox.max = std::array::from_fn(|i| bbox.max[i].max(p[i]));
    }
    Some(bbox)
}

/// Computes the signed volume, the area and the bounding box.
pub fn measure(mesh: &Mesh) -> Measures {
    let Some(bbox) = bounding_box(mesh) else {
        return Measures {
            volume: 0.0,
            area: 0.0,
            bbox: None,
        };
    };
    let m = bbox.center();
    let shifted = |v: u32| sub(mesh.positions()[v as usize], m);
    let mut volume = CompensatedSum::default();
    let mut area = CompensatedSum::default();
    let mut vector_area = [CompensatedSum::default(); 3];
    for corners in mesh.faces() {
        let a = shifted(corners[0]);
        let mut face_area = [0.0; 3];
        for k in 1..corners.len() - 1 {
            let (b, c) = (shifted(corners[k]), shifted(corners[k + 1]));
            volume.add(dot(a, cross(b, c)) / 6.0);
            let n = cross(sub(b, a), sub(c, a));
            face_area = std::array::from_fn(|i| face_area[i] + n[i]);
        }
        area.add(norm(face_area) / 2.0);
        for (sum, component) in vector_area.iter_mut().zip(face_area) {
            sum.add(component / 2.0);
        }
    }
    let vector_area = vector_area.map(|s| s.total());
    Measures {
        volume: volume.total() + dot(m, vector_area) / 3.0,
        area: area.total(),
        bbox: Some(bbox),
    }
}

/// Neumaier's compensated sum: the rounding error of each addition is carried separately.
#[derive(Clone, Copy, Debug, Default)]
struct CompensatedSum {
    sum: f64,
    compensation: f64,
}

impl CompensatedSum {
    fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.compensation += (self.sum - t) + x;
        } else {
            self.compensation += (x - t) + self.sum;
        }
        self.sum = t;
    }

    fn total(self) -> f64 {
        self.sum + self.compensation
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::test_meshes::{cube, open_box};

    #[test]
    fn cube_volume_area_and_box() {
        let measures = measure(&cube([1.0, 2.0, 3.0], 2.0));
        assert_eq!(measures.volume, 8.0);
        assert_eq!(measures.area, 24.0);
        let bbox = measures.bbox.unwrap();
        assert_eq!(bbox.min, [1.0, 2.0, 3.0]);
        assert_eq!(bbox.max, [3.0, 4.0, 5.0]);
    }

    #[test]
    fn open_mesh_volume_is_the_cone_from_the_origin() {
        // A unit square at z = 1 facing +z: the cone from the origin has volume 1/3.
        let square = Mesh::from_triangles(
            vec![
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
                [0.0, 1.0, 1.0],
            ],
            &[[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let volume = measure(&square).volume;
        assert!((volume - 1.0 / 3.0).abs() < 1e-15, "{volume}");
        assert_eq!(measure(&open_box()).area, 5.0);
    }

    #[test]
    fn non_convex_polygon_area_is_exact() {
        // An L hexagon fanned from (2, 0): the fan's triangles overlap, one of them clockwise,
        // and their areas alone would sum to 4.
        let positions = vec![
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 0.0],
        ];
        let parts = crate::MeshParts {
            positions,
            corners: vec![0, 1, 2, 3, 4, 5],
            face_starts: Some(vec![0, 6]),
            ..crate::MeshParts::default()
        };
        assert_eq!(measure(&Mesh::from_parts(parts).unwrap()).area, 3.0);
    }

    #[test]
    fn huge_coordinates_do_not_overflow() {
        let measures = measure(&cube([-3.0e38; 3], 6.0e38));
        let expected = 6.0e38f64.powi(3);
        assert!((measures.volume / expected - 1.0).abs() < 1e-12);
        assert!(measures.area.is_finite());
    }

    #[test]
    fn empty_mesh_has_no_box() {
        assert_eq!(measure(&Mesh::new()).bbox, None);
    }
}
