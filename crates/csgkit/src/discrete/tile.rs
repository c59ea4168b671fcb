//! Multi-scale tiles and the [`Solid`] that owns them (§B3.1).
//!
//! A solid is a sparse map of root tiles on its [`Grid`], keyed by root index; root `(I, J)`
//! covers finest columns `[I·2^R, (I+1)·2^R) × [J·2^R, (J+1)·2^R)`. A [`Tile`] of level ℓ covers
//! `2^ℓ × 2^ℓ` finest columns and is one of:
//! - `Uniform(column)`: every finest column of the footprint has this column;
//! - `Brick`: level 3 only, 8×8 finest columns as depth events with 64-bit masks;
//! - `Split`: level > 3 only, four children of level ℓ−1 in the order `dx + 2·dy`.
//!
//! **Invariants** ([`Solid::check_invariants`]):
//! 1. a uniform tile of level ℓ has endpoints that are multiples of `2^ℓ`, so it is a union
//!    of `2^ℓ`-cubes (the seed's square surfels);
//! 2. tiles are normalised bottom-up: no split has four equal uniform children whose column is
//!    aligned to its own level, and no brick is uniform with an 8-aligned column;
//! 3. every column and brick keeps its own invariant, and no root is empty.
//!
//! Together these make the representation canonical for a given grid: equal voxel sets give
//! equal solids, which is what lets tests compare structures and lets memory follow the
//! surface (a tile is split only where the surface passes), not the volume.
//!
//! Building from a set of level-ℓ columns ([`Solid::from_columns`]):
//! 1. group the columns by root tile (a column coarser than a root goes to every root it
//!    covers);
//! 2. per root, in parallel, descend: an empty region becomes an empty uniform tile, a region
//!    no larger than one level-ℓ column becomes that column's uniform tile, level 3 becomes a
//!    brick of the 64 finest columns, anything else splits in four;
//! 3. normalise each split and brick on the way up.
//!
//! Cost: `O(n·(R − max(ℓ, 3)))` for `n` non-empty columns.

use std::collections::BTreeMap;

use crate::par::*;

use super::brick::{BRICK_SIDE, Brick, BrickError};
use super::column::{Column, ColumnError};
use super::grid::{BRICK_LEVEL, Grid};

/// One node of the multi-scale tile tree. Its level is implied by its depth under the root.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Tile {
    /// The same column for every finest column of the footprint.
    Uniform(Column),
    /// 8×8 finest columns (level 3 only).
    Brick(Brick),
    /// Four children of the next finer level, in the order `dx + 2·dy`.
    Split(Box<[Tile; 4]>),
}

/// A multi-scale discrete solid: a sparse map of normalised root tiles on one grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    grid: Grid,
    roots: BTreeMap<(i32, i32), Tile>,
}

/// Where and how a solid breaks an invariant of the module docs.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TileError {
    /// A uniform tile's column has an endpoint that is not a multiple of its width.
    #[error("uniform tile at ({x}, {y}) level {level} is not aligned to its level")]
    Unaligned {
        /// Finest x index of the tile's corner.
        x: i32,
        /// Finest y index of the tile's corner.
        y: i32,
        /// The tile's level.
        level: u8,
    },
    /// A brick above level 3, or a split at level 3.
    #[error("tile at ({x}, {y}) has the wrong kind for level {level}")]
    WrongKind {
        /// Finest x index of the tile's corner.
        x: i32,
        /// Finest y index of the tile's corner.
        y: i32,
        /// The tile's level.
        level: u8,
    },
    /// A split or brick that normalisation should have merged.
    #[error("tile at ({x}, {y}) level {level} is not normalised")]
    NotNormalised {
        /// Finest x index of the tile's corner.
        x: i32,
        /// Finest y index of the tile's corner.
        y: i32,
        /// The tile's level.
        level: u8,
    },
    /// A root tile holding no voxel.
    #[error("root ({0}, {1}) is empty")]
    EmptyRoot(i32, i32),
    /// A column breaks its invariant.
    #[error("column at ({x}, {y}): {source}")]
    Column {
        /// Finest x index of the tile's corner.
        x: i32,
        /// Finest y index of the tile's corner.
        y: i32,
        /// The column's error.
        source: ColumnError,
    },
    /// A brick breaks its invariant.
    #[error("brick at ({x}, {y}): {source}")]
    Brick {
        /// Finest x index of the brick's corner.
        x: i32,
        /// Finest y index of the brick's corner.
        y: i32,
        /// The brick's error.
        source: BrickError,
    },
}

/// Counts of tile kinds, for statistics and memory tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TileStats {
    /// Root tiles.
    pub roots: usize,
    /// Uniform tiles holding at least one interval.
    pub uniform: usize,
    /// Empty uniform tiles.
    pub empty: usize,
    /// Bricks.
    pub bricks: usize,
    /// Split tiles.
    pub splits: usize,
    /// Intervals in uniform tiles plus events in bricks.
    pub entries: usize,
}

impl Tile {
    /// The empty uniform tile.
    pub fn empty() -> Tile {
        Tile::Uniform(Column::new())
    }

    /// True for the empty uniform tile.
    pub fn is_empty(&self) -> bool {
        matches!(self, Tile::Uniform(c) if c.is_empty())
    }

    /// The normalised tile of level `level` with these four children.
    pub(crate) fn normalise_split(level: u8, children: [Tile; 4]) -> Tile {
        if let Tile::Uniform(first) = &children[0] {
            let same = children[1..]
                .iter()
                .all(|c| matches!(c, Tile::Uniform(col) if col == first));
            if same && first.is_aligned(level) {
                return children.into_iter().next().expect("four children");
            }
        }
        Tile::Split(Box::new(children))
    }

    /// The normalised level-3 tile holding `brick`.
    pub(crate) fn normalise_brick(brick: Brick) -> Tile {
        match brick.as_uniform() {
            Some(column) if column.is_aligned(BRICK_LEVEL) => Tile::Uniform(column),
            _ => Tile::Brick(brick),
        }
    }

    /// The four children of a uniform tile: copies of its column.
    pub(crate) fn split_uniform(column: &Column) -> [Tile; 4] {
        std::array::from_fn(|_| Tile::Uniform(column.clone()))
    }

    fn voxel_count(&self, level: u8) -> u64 {
        match self {
            // Saturates only past 2^64 voxels (a level-20 tile of a 2^24-voxel column).
            Tile::Uniform(c) => c.len().saturating_mul(1 << (2 * u32::from(level))),
            Tile::Brick(b) => b.voxel_count(),
            Tile::Split(children) => children
                .iter()
                .fold(0, |n, c| n.saturating_add(c.voxel_count(level - 1))),
        }
    }

    /// Calls `f(x, y, size, column)` for each uniform footprint and each brick sub-column.
    fn for_each_column(
        &self,
        level: u8,
        x: i32,
        y: i32,
        f: &mut impl FnMut(i32, i32, i32, &Column),
    ) {
        match self {
            Tile::Uniform(c) => {
                if !c.is_empty() {
                    f(x, y, 1 << level, c);
                }
            }
            Tile::Brick(b) => {
                for (c, column) in (0i32..).zip(b.columns()) {
                    if !column.is_empty() {
                        f(x + c % BRICK_SIDE, y + c / BRICK_SIDE, 1, &column);
                    }
                }
            }
            Tile::Split(children) => {
                let half = 1 << (level - 1);
                for (q, child) in children.iter().enumerate() {
                    let (dx, dy) = ((q & 1) as i32 * half, (q >> 1) as i32 * half);
                    child.for_each_column(level - 1, x + dx, y + dy, f);
                }
            }
        }
    }

    fn contains(&self, level: u8, dx: i32, dy: i32, z: i32) -> bool {
        match self {
            Tile::Uniform(c) => c.contains(z),
            Tile::Brick(b) => b.contains((dx + BRICK_SIDE * dy) as u32, z),
            Tile::Split(children) => {
                let half = 1 << (level - 1);
                let q = usize::from(dx >= half) + 2 * usize::from(dy >= half);
                children[q].contains(level - 1, dx % half, dy % half, z)
            }
        }
    }

    fn stats(&self, s: &mut TileStats) {
        match self {
            Tile::Uniform(c) if c.is_empty() => s.empty += 1,
            Tile::Uniform(c) => {
                s.uniform += 1;
                s.entries += c.intervals().len();
            }
            Tile::Brick(b) => {
                s.bricks += 1;
                s.entries += b.events().len();
            }
            Tile::Split(children) => {
                s.splits += 1;
                children.iter().for_each(|c| c.stats(s));
            }
        }
    }

    fn check(&self, level: u8, x: i32, y: i32) -> Result<(), TileError> {
        let wrong = TileError::WrongKind { x, y, level };
        let unnormalised = TileError::NotNormalised { x, y, level };
        match self {
            Tile::Uniform(c) => {
                c.check_invariants()
                    .map_err(|source| TileError::Column { x, y, source })?;
                if !c.is_aligned(level) {
                    return Err(TileError::Unaligned { x, y, level });
                }
            }
            Tile::Brick(b) => {
                if level != BRICK_LEVEL {
                    return Err(wrong);
                }
                b.check_invariants()
                    .map_err(|source| TileError::Brick { x, y, source })?;
                if !matches!(Tile::normalise_brick(b.clone()), Tile::Brick(_)) {
                    return Err(unnormalised);
                }
            }
            Tile::Split(children) => {
                if level <= BRICK_LEVEL {
                    return Err(wrong);
                }
                let half = 1 << (level - 1);
                for (q, child) in children.iter().enumerate() {
                    let (dx, dy) = ((q & 1) as i32 * half, (q >> 1) as i32 * half);
                    child.check(level - 1, x + dx, y + dy)?;
                }
                if !matches!(
                    Tile::normalise_split(level, (**children).clone()),
                    Tile::Split(_)
                ) {
                    return Err(unnormalised);
                }
            }
        }
        Ok(())
    }
}

/// A level-ℓ column placed at its finest corner, while building.
type Placed<'a> = (i32, i32, &'a Column);

impl Solid {
    /// The empty solid on `grid`.
    pub fn empty(grid: Grid) -> Self {
        Self {
            grid,
            roots: BTreeMap::new(),
        }
    }

    /// Builds the normalised solid whose level-`level` column `(i, j)` is `column`.
    ///
    /// Column `(i, j)` covers finest columns `[i·2^ℓ, (i+1)·2^ℓ) × [j·2^ℓ, (j+1)·2^ℓ)`; its
    /// intervals are in finest voxel indices and must be multiples of `2^ℓ` (the discretiser
    /// produces them so). Repeated keys are not allowed.
    pub(crate) fn from_columns(grid: Grid, level: u8, columns: &[((i32, i32), Column)]) -> Self {
        let r = grid.levels();
        let mut placed: Vec<((i32, i32), Placed<'_>)> = Vec::with_capacity(columns.len());
        for ((i, j), column) in columns.iter().filter(|(_, c)| !c.is_empty()) {
            let (fx, fy) = (i << level, j << level);
            let span = if level > r { 1 << (level - r) } else { 1 };
            for a in 0..span {
                for b in 0..span {
                    let root = ((fx >> r) + a, (fy >> r) + b);
                    placed.push((root, ((root.0 << r).max(fx), (root.1 << r).max(fy), column)));
                }
            }
        }
        // Group by root only: a root's tile does not depend on the order of its columns.
        placed.par_sort_unstable_by_key(|p| (i64::from(p.0.0) << 32) + i64::from(p.0.1));
        let groups: Vec<&[((i32, i32), Placed<'_>)]> = placed.chunk_by(|a, b| a.0 == b.0).collect();
        let roots = groups
            .into_par_iter()
            .map(|group| {
                let key = group[0].0;
                let mut cols: Vec<Placed<'_>> = group.iter().map(|p| p.1).collect();
                (key, build(r, key.0 << r, key.1 << r, level, &mut cols))
            })
            .filter(|(_, tile)| !tile.is_empty())
            .collect();
        let solid = Self { grid, roots };
        debug_assert_eq!(solid.check_invariants(), Ok(()));
        solid
    }

    /// Assembles a solid from already normalised roots, dropping empty ones.
    pub(crate) fn from_roots(grid: Grid, roots: Vec<((i32, i32), Tile)>) -> Self {
        let roots = roots.into_iter().filter(|(_, t)| !t.is_empty()).collect();
        Self { grid, roots }
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The root tiles by root index.
    pub fn roots(&self) -> &BTreeMap<(i32, i32), Tile> {
        &self.roots
    }

    /// True when no voxel is inside.
    pub fn is_empty(&self) -> bool {
        self.roots.is_empty()
    }

    /// The number of finest voxels inside (saturating at `u64::MAX`).
    pub fn voxel_count(&self) -> u64 {
        let r = self.grid.levels();
        self.roots
            .values()
            .fold(0, |n, t| n.saturating_add(t.voxel_count(r)))
    }

    /// Whether finest voxel `(x, y, z)` is inside.
    pub fn contains(&self, x: i32, y: i32, z: i32) -> bool {
        let r = self.grid.levels();
        let mask = (1 << r) - 1;
        self.roots
            .get(&(x >> r, y >> r))
            .is_some_and(|t| t.contains(r, x & mask, y & mask, z))
    }

    /// Calls `f(x, y, size, column)` for every non-empty column footprint: `size × size`
    /// finest columns from finest corner `(x, y)` that all hold `column`. Deterministic order.
    pub fn for_each_column(&self, mut f: impl FnMut(i32, i32, i32, &Column)) {
        let r = self.grid.levels();
        for (&(i, j), tile) in &self.roots {
            tile.for_each_column(r, i << r, j << r, &mut f);
        }
    }

    /// Counts of tile kinds.
    pub fn stats(&self) -> TileStats {
        let mut s = TileStats {
            roots: self.roots.len(),
            ..TileStats::default()
        };
        self.roots.values().for_each(|t| t.stats(&mut s));
        s
    }

    /// Checks every invariant of the module docs.
    ///
    /// # Errors
    /// The first tile that breaks one.
    pub fn check_invariants(&self) -> Result<(), TileError> {
        let r = self.grid.levels();
        for (&(i, j), tile) in &self.roots {
            if tile.is_empty() {
                return Err(TileError::EmptyRoot(i, j));
            }
            tile.check(r, i << r, j << r)?;
        }
        Ok(())
    }
}

/// Builds the tile of `level` at finest corner `(x, y)` from the level-`col_level` columns in
/// `cols` (all inside its footprint), normalised.
fn build(level: u8, x: i32, y: i32, col_level: u8, cols: &mut [Placed<'_>]) -> Tile {
    if cols.is_empty() {
        return Tile::empty();
    }
    if col_level >= level {
        return Tile::Uniform(cols[0].2.clone());
    }
    if level == BRICK_LEVEL {
        return Tile::normalise_brick(brick_of(x, y, col_level, cols));
    }
    let half = 1 << (level - 1);
    let (low_y, high_y) = partition(cols, |p| p.1 < y + half);
    let (q0, q1) = partition(low_y, |p| p.0 < x + half);
    let (q2, q3) = partition(high_y, |p| p.0 < x + half);
    let children = [
        build(level - 1, x, y, col_level, q0),
        build(level - 1, x + half, y, col_level, q1),
        build(level - 1, x, y + half, col_level, q2),
        build(level - 1, x + half, y + half, col_level, q3),
    ];
    Tile::normalise_split(level, children)
}

/// Splits `cols` in place into those satisfying `pred` and the rest.
fn partition<'s, 'a>(
    cols: &'s mut [Placed<'a>],
    pred: impl Fn(&Placed<'a>) -> bool,
) -> (&'s mut [Placed<'a>], &'s mut [Placed<'a>]) {
    let mut k = 0;
    for i in 0..cols.len() {
        if pred(&cols[i]) {
            cols.swap(i, k);
            k += 1;
        }
    }
    cols.split_at_mut(k)
}

/// The brick at finest corner `(x, y)` whose sub-columns come from level-`col_level` columns.
fn brick_of(x: i32, y: i32, col_level: u8, cols: &[Placed<'_>]) -> Brick {
    let empty = Column::new();
    let mut sub: Vec<&Column> = vec![&empty; 64];
    let size = 1 << col_level;
    for &(cx, cy, column) in cols {
        for dy in 0..size {
            for dx in 0..size {
                sub[((cx - x + dx) + BRICK_SIDE * (cy - y + dy)) as usize] = column;
            }
        }
    }
    Brick::from_columns(&sub)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::column::Interval;

    fn col(pairs: &[(i32, i32)]) -> Column {
        Column::from_intervals(pairs.iter().map(|&(z0, z1)| Interval { z0, z1 }).collect())
    }

    fn grid() -> Grid {
        Grid::new(1.0, 4).unwrap()
    }

    #[test]
    fn a_full_root_of_aligned_columns_collapses_to_one_uniform_tile() {
        let column = col(&[(-16, 32)]);
        let cols: Vec<_> = (0..16)
            .flat_map(|i| (0..16).map(move |j| (i, j)))
            .map(|k| (k, column.clone()))
            .collect();
        let solid = Solid::from_columns(grid(), 0, &cols);
        solid.check_invariants().unwrap();
        assert_eq!(solid.roots().len(), 1);
        assert_eq!(solid.roots()[&(0, 0)], Tile::Uniform(column));
        assert_eq!(solid.voxel_count(), 256 * 48);
    }

    #[test]
    fn unaligned_columns_stay_in_bricks() {
        let column = col(&[(0, 3)]);
        let cols: Vec<_> = (0..16)
            .flat_map(|i| (0..16).map(move |j| (i, j)))
            .map(|k| (k, column.clone()))
            .collect();
        let solid = Solid::from_columns(grid(), 0, &cols);
        solid.check_invariants().unwrap();
        let stats = solid.stats();
        assert_eq!((stats.splits, stats.bricks), (1, 4));
        assert_eq!(solid.voxel_count(), 256 * 3);
    }

    #[test]
    fn coarse_and_negative_columns_are_placed_on_the_origin_lattice() {
        // One level-5 column (32×32 finest columns) spans four level-4 roots.
        let solid = Solid::from_columns(grid(), 5, &[((-1, 0), col(&[(32, 64)]))]);
        solid.check_invariants().unwrap();
        assert_eq!(solid.roots().len(), 4);
        assert_eq!(solid.voxel_count(), 32 * 32 * 32);
        assert!(solid.contains(-32, 0, 32) && solid.contains(-1, 31, 63));
        assert!(!solid.contains(0, 0, 40) && !solid.contains(-1, 32, 40));
        // A level-1 column: 2×2 finest columns inside one brick.
        let fine = Solid::from_columns(grid(), 1, &[((-3, 2), col(&[(2, 6)]))]);
        fine.check_invariants().unwrap();
        assert_eq!(fine.voxel_count(), 16);
        assert!(fine.contains(-6, 4, 2) && fine.contains(-5, 5, 5) && !fine.contains(-4, 4, 3));
        let mut seen = 0;
        fine.for_each_column(|_, _, size, c| seen += size as u64 * size as u64 * c.len());
        assert_eq!(seen, 16);
    }

    #[test]
    fn unnormalised_tiles_are_reported() {
        let column = col(&[(0, 16)]);
        let split = Tile::Split(Box::new(Tile::split_uniform(&column)));
        let solid = Solid::from_roots(grid(), vec![((0, 0), split)]);
        assert_eq!(
            solid.check_invariants(),
            Err(TileError::NotNormalised {
                x: 0,
                y: 0,
                level: 4
            })
        );
        let unaligned = Solid::from_roots(grid(), vec![((1, 0), Tile::Uniform(col(&[(0, 8)])))]);
        assert_eq!(
            unaligned.check_invariants(),
            Err(TileError::Unaligned {
                x: 16,
                y: 0,
                level: 4
            })
        );
    }
}
