//! Coordinate compression: boxes in f64 become boxes in per-axis ranks.
//!
//! Every later stage up to triangulation only compares coordinates, so it can run on the rank
//! of each coordinate among the distinct values of its axis; the rank tables map back. This is
//! exact: ranking sorts (comparisons only) and `-0.0` is identified with `0.0`.
//!
//! Input contract: each box is `[x0, y0, z0, x1, y1, z1]`; the two bounds of an axis may come
//! in either order. Non-finite coordinates are an error; boxes with zero thickness on some
//! axis are dropped and counted.

use super::OrthoError;

/// Boxes in coordinate ranks with the tables mapping ranks back to f64.
#[derive(Clone, Debug, Default)]
pub(crate) struct RankedBoxes {
    /// Sorted distinct coordinates per axis.
    pub coords: [Vec<f64>; 3],
    /// `[x0, y0, z0, x1, y1, z1]` in ranks, `lo < hi` on every axis.
    pub boxes: Vec<[u32; 6]>,
    /// The material of each kept box (0 when none was given).
    pub materials: Vec<u32>,
    /// Number of input boxes dropped for zero thickness.
    pub dropped: usize,
}

impl RankedBoxes {
    /// Ranks `boxes`, normalising bound order and dropping flat boxes.
    ///
    /// # Errors
    /// [`OrthoError::NonFinite`] naming the first box with a NaN or infinite coordinate.
    pub(crate) fn new(boxes: &[[f64; 6]]) -> Result<Self, OrthoError> {
        Self::with_materials(boxes, None)
    }

    /// Like [`RankedBoxes::new`], keeping each box's material.
    ///
    /// # Errors
    /// [`OrthoError::NonFinite`], or [`OrthoError::MaterialCount`] if `materials` does not
    /// have one entry per box.
    pub(crate) fn with_materials(
        boxes: &[[f64; 6]],
        materials: Option<&[u32]>,
    ) -> Result<Self, OrthoError> {
        if let Some(m) = materials.filter(|m| m.len() != boxes.len()) {
            return Err(OrthoError::MaterialCount {
                boxes: boxes.len(),
                materials: m.len(),
            });
        }
        let mut kept = Vec::with_capacity(boxes.len());
        let mut kept_materials = Vec::with_capacity(boxes.len());
        for (index, b) in boxes.iter().enumerate() {
            if b.iter().any(|v| !v.is_finite()) {
                return Err(OrthoError::NonFinite { index });
            }
            // Adding +0.0 maps -0.0 to +0.0, so the total order below agrees with `==`.
            let lo: [f64; 3] = std::array::from_fn(|k| b[k].min(b[k + 3]) + 0.0);
            let hi: [f64; 3] = std::array::from_fn(|k| b[k].max(b[k + 3]) + 0.0);
            if (0..3).all(|k| lo[k] < hi[k]) {
                kept.push([lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]]);
                kept_materials.push(materials.map_or(0, |m| m[index]));
            }
        }
        let coords: [Vec<f64>; 3] = std::array::from_fn(|k| {
            let mut v: Vec<f64> = kept.iter().flat_map(|b| [b[k], b[k + 3]]).collect();
            v.sort_unstable_by(f64::total_cmp);
            v.dedup();
            v
        });
        let rank = |k: usize, x: f64| coords[k].partition_point(|&c| c < x) as u32;
        let ranked = kept
            .iter()
            .map(|b| std::array::from_fn(|i| rank(i % 3, b[i])))
            .collect();
        Ok(Self {
            dropped: boxes.len() - kept.len(),
            boxes: ranked,
            materials: kept_materials,
            coords,
        })
    }

    /// The f64 position of a rank triple.
    pub(crate) fn position(&self, rank: [u32; 3]) -> [f64; 3] {
        std::array::from_fn(|k| self.coords[k][rank[k] as usize])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_normalise_order_drop_flat_boxes_and_merge_signed_zeros() {
        let r = RankedBoxes::new(&[
            [1.0, 0.0, -0.0, 0.0, 2.0, 3.0],
            [5.0, 5.0, 5.0, 6.0, 5.0, 6.0],
            [0.0, 0.0, 0.0, 0.5, 0.5, 0.5],
        ])
        .unwrap();
        assert_eq!(r.dropped, 1);
        assert_eq!(r.coords[0], [0.0, 0.5, 1.0]);
        assert_eq!(r.coords[2], [0.0, 0.5, 3.0]);
        assert_eq!(r.boxes, [[0, 0, 0, 2, 2, 2], [0, 0, 0, 1, 1, 1]]);
        assert_eq!(r.position([1, 2, 2]), [0.5, 2.0, 3.0]);
    }

    #[test]
    fn non_finite_coordinates_name_the_box() {
        let err = RankedBoxes::new(&[[0.0; 6], [0.0, 0.0, 0.0, 1.0, f64::NAN, 1.0]]);
        assert_eq!(err.unwrap_err(), OrthoError::NonFinite { index: 1 });
    }
}
