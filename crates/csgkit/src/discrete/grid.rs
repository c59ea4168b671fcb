//! The lattice every discrete solid lives on.
//!
//! A [`Grid`] has a finest cell size `h` and a root level `R`. Level ℓ has cells of width
//! `w = 2^ℓ·h`; voxel `k` of level ℓ spans `[k·w, (k+1)·w)` on each axis, so the lattice is
//! anchored at the world origin and does not depend on any bounding box (§B3.1). Root tiles
//! cover `2^R × 2^R` finest columns; level 3 tiles are the 8×8 bricks.
//!
//! # Numeric model
//! Sample coordinates are the f64 values `fl((i+½)·w)` and lattice planes `fl(k·w)`. Both are
//! monotone in the index, and they are the exact lattice points whenever `h` is a dyadic number
//! with a short mantissa (a power of two, 0.25, 3·2^-10, …). Every decision compares input
//! coordinates with these f64 values through exact predicates, so the result is the exact
//! answer for these sample points; no tolerance is involved.
//!
//! Indices are `i32`; [`Grid::check_coordinate`] rejects coordinates whose index would leave
//! [`MAX_INDEX`], so index arithmetic never overflows.

/// The largest absolute finest-voxel index a solid may use (2^28).
///
/// Index arithmetic adds at most a few root tiles to an index, which stays far from `i32`
/// overflow with this bound.
pub const MAX_INDEX: i64 = 1 << 28;

/// The smallest root level: root tiles must hold at least one 8×8 brick.
pub const BRICK_LEVEL: u8 = 3;

/// The largest level (cell width `2^MAX_LEVEL·h`).
pub const MAX_LEVEL: u8 = 20;

/// A power-of-two lattice anchored at the origin: finest cell `h`, root tiles of level `levels`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    h: f64,
    levels: u8,
}

/// Why a grid could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GridError {
    /// The cell size is not a positive finite number.
    #[error("cell size {0} is not a positive finite number")]
    BadCell(f64),
    /// The root level is outside `BRICK_LEVEL..=MAX_LEVEL`.
    #[error("root level {0} is outside 3..=20")]
    BadLevels(u8),
    /// Two cell sizes do not differ by a power of two.
    #[error("cell size {cell} is not the finest cell size {finest} times a power of two")]
    NotPowerOfTwo {
        /// The offending cell size.
        cell: f64,
        /// The finest cell size of the grid.
        finest: f64,
    },
}

impl Grid {
    /// The default root level: root tiles of 256 × 256 finest columns.
    pub const DEFAULT_LEVELS: u8 = 8;

    /// A grid with finest cell `h` and root tiles of `2^levels` finest columns.
    ///
    /// # Errors
    /// [`GridError::BadCell`] if `h` is not positive and finite, [`GridError::BadLevels`] if
    /// `levels` is outside `3..=20`.
    pub fn new(h: f64, levels: u8) -> Result<Self, GridError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(GridError::BadCell(h));
        }
        if !(BRICK_LEVEL..=MAX_LEVEL).contains(&levels) {
            return Err(GridError::BadLevels(levels));
        }
        Ok(Self { h, levels })
    }

    /// The grid whose finest cell is the smallest of `cells`, with each cell's level.
    ///
    /// The root level is the larger of [`Grid::DEFAULT_LEVELS`] and the coarsest level.
    ///
    /// # Errors
    /// [`GridError`] if a cell is not positive and finite, or two cells do not differ by a
    /// power of two (exactly, in f64).
    pub fn for_cells(cells: &[f64]) -> Result<(Self, Vec<u8>), GridError> {
        let h = cells.iter().copied().fold(f64::INFINITY, f64::min);
        if let Some(bad) = cells.iter().find(|c| !(c.is_finite() && **c > 0.0)) {
            return Err(GridError::BadCell(*bad));
        }
        let levels = cells
            .iter()
            .map(|&cell| level_of(cell, h).ok_or(GridError::NotPowerOfTwo { cell, finest: h }))
            .collect::<Result<Vec<u8>, _>>()?;
        let top = levels.iter().copied().max().unwrap_or(0);
        let grid = Self::new(h, top.max(Self::DEFAULT_LEVELS))?;
        Ok((grid, levels))
    }

    /// The finest cell size.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// The root level: root tiles cover `2^levels × 2^levels` finest columns.
    pub fn levels(&self) -> u8 {
        self.levels
    }

    /// The cell width at `level`, `2^level·h` (exact: a power-of-two scaling).
    pub fn width(&self, level: u8) -> f64 {
        self.h * f64::from(1u32 << level)
    }

    /// The sample coordinate of index `i` at `level`: `fl((i+½)·w)`.
    pub fn centre(&self, level: u8, i: i64) -> f64 {
        (i as f64 + 0.5) * self.width(level)
    }

    /// The lattice plane of index `k` at `level`: `fl(k·w)`.
    pub fn plane(&self, level: u8, k: i64) -> f64 {
        k as f64 * self.width(level)
    }

    /// The world coordinate of finest lattice plane `k` (a box corner).
    pub fn finest_plane(&self, k: i32) -> f64 {
        f64::from(k) * self.h
    }

    /// Whether `v` is finite and its index at the finest level stays within [`MAX_INDEX`].
    pub fn check_coordinate(&self, v: f64) -> bool {
        v.is_finite() && (v / self.h).abs() < (MAX_INDEX - 4) as f64
    }
}

/// The level ℓ with `cell == 2^ℓ·h` exactly, if there is one.
fn level_of(cell: f64, h: f64) -> Option<u8> {
    (0..=MAX_LEVEL).find(|&l| h * f64::from(1u32 << l) == cell)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_cells_and_levels() {
        assert_eq!(Grid::new(0.0, 8), Err(GridError::BadCell(0.0)));
        assert!(matches!(Grid::new(f64::NAN, 8), Err(GridError::BadCell(_))));
        assert_eq!(Grid::new(1.0, 2), Err(GridError::BadLevels(2)));
        assert_eq!(Grid::new(1.0, 21), Err(GridError::BadLevels(21)));
    }

    #[test]
    fn cells_differing_by_powers_of_two_get_levels() {
        let (grid, levels) = Grid::for_cells(&[0.5, 2.0, 0.5]).unwrap();
        assert_eq!(grid.h(), 0.5);
        assert_eq!(levels, vec![0, 2, 0]);
        assert_eq!(grid.levels(), Grid::DEFAULT_LEVELS);
        let err = Grid::for_cells(&[0.5, 1.5]).unwrap_err();
        assert!(matches!(err, GridError::NotPowerOfTwo { .. }));
        assert_eq!(
            err.to_string(),
            "cell size 1.5 is not the finest cell size 0.5 times a power of two"
        );
    }

    #[test]
    fn centres_and_planes_are_on_the_origin_lattice() {
        let grid = Grid::new(0.25, 3).unwrap();
        assert_eq!(grid.width(2), 1.0);
        assert_eq!(grid.centre(2, -1), -0.5);
        assert_eq!(grid.centre(0, 3), 0.875);
        assert_eq!(grid.plane(1, -3), -1.5);
        assert!(grid.check_coordinate(1e6));
        assert!(!grid.check_coordinate(1e9));
        assert!(!grid.check_coordinate(f64::INFINITY));
    }
}
