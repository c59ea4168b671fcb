//! Booleans on solids with multi-scale alignment (§B3.3).
//!
//! Both operands live on the same [`Grid`], so their root tiles line up; the operands may have
//! been discretised at different levels, which shows only in how deep their trees go.
//!
//! Algorithm ([`Solid::op`]), per root index present in either operand, in parallel:
//! 1. descend both tile trees together;
//! 2. where one side is a split and the other uniform, split the uniform tile lazily into
//!    four copies (the seed's "only one is a leaf" case: push its list down);
//! 3. at level 3 a uniform tile meeting a brick becomes a brick of 64 equal sub-columns;
//!    uniform ∘ uniform is the column merge, brick ∘ brick the masked list merge;
//! 4. normalise bottom-up on the way back (four equal aligned uniform children merge, a
//!    uniform brick with 8-aligned depths becomes a uniform tile).
//!
//! An empty side short-cuts: `A ∪ ∅ = A`, `A ∩ ∅ = ∅`, and so on, so untouched regions cost
//! nothing. Results are normalised solids on the same grid, so operations chain without drift.
//! Cost: `O(Σ list lengths)` over the finer common tiling of the two operands. The output does
//! not depend on the thread count: roots are computed independently and collected in key order.

use crate::par::{self, *};

use super::brick::Brick;
use super::grid::Grid;
use super::tile::{Solid, Tile};
use crate::Operation;

/// Why two solids cannot be combined.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OpError {
    /// The operands are on different grids.
    #[error("operands are on different grids ({left:?} and {right:?})")]
    GridMismatch {
        /// The first operand's grid.
        left: Grid,
        /// The second operand's grid.
        right: Grid,
    },
}

impl Solid {
    /// `self op other`, a normalised solid on the same grid.
    ///
    /// # Errors
    /// [`OpError::GridMismatch`] if the operands are on different grids.
    pub fn op(&self, other: &Solid, op: Operation) -> Result<Solid, OpError> {
        if self.grid() != other.grid() {
            return Err(OpError::GridMismatch {
                left: *self.grid(),
                right: *other.grid(),
            });
        }
        let mut keys: Vec<(i32, i32)> = self
            .roots()
            .keys()
            .chain(other.roots().keys())
            .copied()
            .collect();
        keys.sort_unstable();
        keys.dedup();
        let level = self.grid().levels();
        let empty = Tile::empty();
        let roots: Vec<((i32, i32), Tile)> = keys
            .into_par_iter()
            .map(|key| {
                let a = self.roots().get(&key).unwrap_or(&empty);
                let b = other.roots().get(&key).unwrap_or(&empty);
                (key, tile_op(level, a, b, op))
            })
            .collect();
        let solid = Solid::from_roots(*self.grid(), roots);
        debug_assert_eq!(solid.check_invariants(), Ok(()));
        Ok(solid)
    }

    /// `first op second op …` for all of `operands`, left to right; for ∪, ∩ and ⊕ the
    /// operands are combined pairwise in a balanced tree, which gives the same solid (the
    /// operations are associative and solids are canonical) with smaller intermediates.
    /// `None` for no operand.
    ///
    /// # Errors
    /// As [`Solid::op`].
    pub fn op_all(operands: &[Solid], op: Operation) -> Result<Option<Solid>, OpError> {
        match operands {
            [] => Ok(None),
            [one] => Ok(Some(one.clone())),
            [first, rest @ ..] if op == Operation::Difference => {
                let subtrahend = Self::op_all(rest, Operation::Union)?.expect("rest is not empty");
                first.difference(&subtrahend).map(Some)
            }
            _ => {
                let (left, right) = operands.split_at(operands.len() / 2);
                let (l, r) = par::join(|| Self::op_all(left, op), || Self::op_all(right, op));
                let (l, r) = (
                    l?.expect("left half is not empty"),
                    r?.expect("right half is not empty"),
                );
                l.op(&r, op).map(Some)
            }
        }
    }

    /// `self ∪ other`.
    ///
    /// # Errors
    /// As [`Solid::op`].
    pub fn union(&self, other: &Solid) -> Result<Solid, OpError> {
        self.op(other, Operation::Union)
    }

    /// `self ∩ other`.
    ///
    /// # Errors
    /// As [`Solid::op`].
    pub fn intersection(&self, other: &Solid) -> Result<Solid, OpError> {
        self.op(other, Operation::Intersection)
    }

    /// `self − other`.
    ///
    /// # Errors
    /// As [`Solid::op`].
    pub fn difference(&self, other: &Solid) -> Result<Solid, OpError> {
        self.op(other, Operation::Difference)
    }

    /// `self ⊕ other`.
    ///
    /// # Errors
    /// As [`Solid::op`].
    pub fn xor(&self, other: &Solid) -> Result<Solid, OpError> {
        self.op(other, Operation::Xor)
    }
}

/// `a op b` for two normalised tiles of `level`, normalised.
fn tile_op(level: u8, a: &Tile, b: &Tile, op: Operation) -> Tile {
    if let Some(t) = with_empty_side(a, b, op) {
        return t;
    }
    match (a, b) {
        (Tile::Uniform(ca), Tile::Uniform(cb)) => Tile::Uniform(ca.op(cb, op)),
        (Tile::Brick(ba), Tile::Brick(bb)) => Tile::normalise_brick(ba.op(bb, op)),
        (Tile::Brick(ba), Tile::Uniform(cb)) => {
            Tile::normalise_brick(ba.op(&Brick::uniform(cb), op))
        }
        (Tile::Uniform(ca), Tile::Brick(bb)) => {
            Tile::normalise_brick(Brick::uniform(ca).op(bb, op))
        }
        (Tile::Split(ca), Tile::Split(cb)) => Tile::normalise_split(
            level,
            std::array::from_fn(|q| tile_op(level - 1, &ca[q], &cb[q], op)),
        ),
        (Tile::Split(ca), Tile::Uniform(cb)) => {
            let cb = Tile::split_uniform(cb);
            Tile::normalise_split(
                level,
                std::array::from_fn(|q| tile_op(level - 1, &ca[q], &cb[q], op)),
            )
        }
        (Tile::Uniform(ca), Tile::Split(cb)) => {
            let ca = Tile::split_uniform(ca);
            Tile::normalise_split(
                level,
                std::array::from_fn(|q| tile_op(level - 1, &ca[q], &cb[q], op)),
            )
        }
        (Tile::Brick(_), Tile::Split(_)) | (Tile::Split(_), Tile::Brick(_)) => {
            unreachable!("tile invariant: bricks live at level 3 and splits only above it")
        }
    }
}

/// The result when one side is empty, without descending.
fn with_empty_side(a: &Tile, b: &Tile, op: Operation) -> Option<Tile> {
    match (a.is_empty(), b.is_empty(), op) {
        (true, _, Operation::Union | Operation::Xor) => Some(b.clone()),
        (_, true, Operation::Union | Operation::Xor | Operation::Difference) => Some(a.clone()),
        (true, _, Operation::Intersection | Operation::Difference) => Some(Tile::empty()),
        (_, true, Operation::Intersection) => Some(Tile::empty()),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::column::{Column, Interval};
    use std::collections::BTreeSet;

    fn col(pairs: &[(i32, i32)]) -> Column {
        Column::from_intervals(pairs.iter().map(|&(z0, z1)| Interval { z0, z1 }).collect())
    }

    fn voxels(s: &Solid) -> BTreeSet<(i32, i32, i32)> {
        let mut out = BTreeSet::new();
        s.for_each_column(|x, y, size, c| {
            for dx in 0..size {
                for dy in 0..size {
                    for iv in c.intervals() {
                        out.extend((iv.z0..iv.z1).map(|z| (x + dx, y + dy, z)));
                    }
                }
            }
        });
        out
    }

    #[test]
    fn mixed_levels_combine_voxelwise() {
        let grid = Grid::new(1.0, 4).unwrap();
        // A coarse 16-cube (level 4) and a fine staircase (level 0).
        let a = Solid::from_columns(grid, 4, &[((0, 0), col(&[(0, 16)]))]);
        let cols: Vec<_> = (0..20).map(|i| ((i, i % 5), col(&[(i, i + 3)]))).collect();
        let b = Solid::from_columns(grid, 0, &cols);
        let (va, vb) = (voxels(&a), voxels(&b));
        for op in Operation::ALL {
            let r = a.op(&b, op).unwrap();
            r.check_invariants().unwrap();
            let expect: BTreeSet<_> = match op {
                Operation::Union => va.union(&vb).copied().collect(),
                Operation::Intersection => va.intersection(&vb).copied().collect(),
                Operation::Difference => va.difference(&vb).copied().collect(),
                Operation::Xor => va.symmetric_difference(&vb).copied().collect(),
            };
            assert_eq!(voxels(&r), expect, "{op:?}");
            assert_eq!(r.voxel_count(), expect.len() as u64);
        }
        // A ∪ B − B ∪ (A ∩ B) = A, and the result is structurally A again (canonical form).
        let back = a
            .union(&b)
            .unwrap()
            .difference(&b)
            .unwrap()
            .union(&a.intersection(&b).unwrap())
            .unwrap();
        assert_eq!(back, a);
    }

    #[test]
    fn n_ary_ops_fold_all_operands() {
        let grid = Grid::new(1.0, 4).unwrap();
        let solids: Vec<Solid> = (0..5)
            .map(|n| {
                Solid::from_columns(
                    grid,
                    0,
                    &[((n, n), col(&[(n, n + 4)])), ((0, 0), col(&[(0, 2 + n)]))],
                )
            })
            .collect();
        let chained = |op: Operation| {
            solids[1..]
                .iter()
                .fold(solids[0].clone(), |acc, s| acc.op(s, op).unwrap())
        };
        for op in Operation::ALL {
            assert_eq!(
                Solid::op_all(&solids, op).unwrap(),
                Some(chained(op)),
                "{op:?}"
            );
        }
        assert_eq!(Solid::op_all(&[], Operation::Union), Ok(None));
    }

    #[test]
    fn grids_must_match() {
        let a = Solid::empty(Grid::new(1.0, 4).unwrap());
        let b = Solid::empty(Grid::new(0.5, 4).unwrap());
        assert!(matches!(a.union(&b), Err(OpError::GridMismatch { .. })));
    }
}
