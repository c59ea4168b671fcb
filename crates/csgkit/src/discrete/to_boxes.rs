//! Output as axis-aligned boxes (§B3.4): the input of the orthogonal engine.
//!
//! Each interval of a uniform tile is one box: the tile's footprint × `[z0, z1)`, and each
//! interval of a brick sub-column is a one-column box. Boxes that abut along x with the same
//! y and z ranges are then merged, and after that those abutting along y with the same x and
//! z ranges (a sort and one linear pass each), which divides the count by about 3 on curved
//! models and so speeds up the orthogonal engine. The boxes have pairwise disjoint
//! interiors (tiles have disjoint footprints and a column's intervals are disjoint), so their
//! total volume is the voxel count times `h³`, and their union is the solid. Coordinates are
//! the lattice planes `fl(k·h)` (exact when `h` is dyadic).
//!
//! [`Solid::to_mesh`] runs them through the orthogonal engine ([`crate::ortho`]): an exact,
//! closed, T-junction-free mesh with maximal faces (with holes), non-manifold edges only where
//! the voxel set has them.
//!
//! Cost: one box per tile interval; `O(boxes)` time and memory, plus the orthogonal engine's.

use super::tile::Solid;
use crate::mesh::Mesh;
use crate::ortho::{MeshOptions, OrthoError, box_union};

impl Solid {
    /// The solid as boxes of finest voxel indices `[x0, y0, z0, x1, y1, z1]` (half-open).
    ///
    /// Interiors are pairwise disjoint; the order is deterministic.
    pub fn to_index_boxes(&self) -> Vec<[i32; 6]> {
        let mut out = Vec::new();
        self.for_each_column(|x, y, size, column| {
            for iv in column.intervals() {
                out.push([x, y, iv.z0, x + size, y + size, iv.z1]);
            }
        });
        merge_abutting(merge_abutting(out, 0), 1)
    }

    /// The solid as world-space boxes `[xmin, ymin, zmin, xmax, ymax, zmax]`.
    ///
    /// Interiors are pairwise disjoint; the order is deterministic.
    pub fn to_boxes(&self) -> Vec<[f64; 6]> {
        let grid = *self.grid();
        self.to_index_boxes()
            .into_iter()
            .map(|b| b.map(|k| grid.finest_plane(k)))
            .collect()
    }
}

impl Solid {
    /// The solid's boundary through the orthogonal engine: boxes → exact B-rep → closed mesh.
    ///
    /// # Errors
    /// [`OrthoError`] if the orthogonal engine rejects the boxes or its triangulation fails
    /// (coordinates outside its range).
    pub fn to_mesh(&self) -> Result<Mesh, OrthoError> {
        let brep = box_union(&self.to_boxes())?;
        Ok(brep.to_mesh(MeshOptions::default())?.mesh)
    }
}

/// Merges boxes that abut along `axis` and span the same ranges on the other two axes.
///
/// Interiors stay disjoint: a merged box is exactly the union of the boxes it replaces.
fn merge_abutting(mut boxes: Vec<[i32; 6]>, axis: usize) -> Vec<[i32; 6]> {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let cross = move |b: &[i32; 6]| [b[u], b[u + 3], b[v], b[v + 3]];
    boxes.sort_unstable_by_key(|b| (cross(b), b[axis]));
    let mut out: Vec<[i32; 6]> = Vec::with_capacity(boxes.len());
    for b in boxes {
        match out.last_mut() {
            Some(last) if cross(last) == cross(&b) && last[axis + 3] == b[axis] => {
                last[axis + 3] = b[axis + 3];
            }
            _ => out.push(b),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::discrete::column::{Column, Interval};
    use crate::discrete::{Grid, Solid};

    #[test]
    fn box_volume_is_voxel_count_times_cell_volume() {
        let grid = Grid::new(0.5, 4).unwrap();
        let tall = Column::from_intervals(vec![
            Interval { z0: 0, z1: 16 },
            Interval { z0: 32, z1: 48 },
        ]);
        let short = Column::from_intervals(vec![Interval { z0: 3, z1: 5 }]);
        let cols: Vec<_> = (0..16)
            .flat_map(|i| (0..16).map(move |j| (i, j)))
            .map(|(i, j)| {
                (
                    (i, j),
                    if (i + j) % 3 == 0 {
                        short.clone()
                    } else {
                        tall.clone()
                    },
                )
            })
            .collect();
        let solid = Solid::from_columns(grid, 0, &cols);
        let boxes = solid.to_boxes();
        let volume: f64 = boxes
            .iter()
            .map(|b| (b[3] - b[0]) * (b[4] - b[1]) * (b[5] - b[2]))
            .sum();
        assert_eq!(volume, solid.voxel_count() as f64 * 0.125);
        assert!(
            boxes
                .iter()
                .all(|b| b[0] < b[3] && b[1] < b[4] && b[2] < b[5])
        );
        // The orthogonal engine's mesh encloses the same volume.
        let mesh = solid.to_mesh().unwrap();
        let mut six = 0.0;
        for (_, [a, b, c]) in mesh.fan_triangles() {
            let [a, b, c] = [a, b, c].map(|v| mesh.positions()[v as usize]);
            six += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]);
        }
        assert_eq!(six / 6.0, volume);
        // Merging leaves fewer boxes than column intervals.
        let mut intervals = 0;
        solid.for_each_column(|_, _, _, c| intervals += c.intervals().len());
        assert!(
            boxes.len() < intervals * 2 / 3,
            "{} boxes for {intervals} intervals",
            boxes.len()
        );
        // Interiors are disjoint: no two index boxes overlap.
        let ib = solid.to_index_boxes();
        for (n, a) in ib.iter().enumerate() {
            for b in &ib[n + 1..] {
                let overlap = (0..3).all(|d| a[d] < b[d + 3] && b[d] < a[d + 3]);
                assert!(!overlap, "{a:?} {b:?}");
            }
        }
    }
}
