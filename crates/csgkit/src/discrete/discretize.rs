//! Discretisation: a closed triangle mesh to a [`Solid`] at one level, exactly (§B3.2).
//!
//! Contract: [`discretize`] takes any [`Mesh`] (polygons are fan-triangulated) and a level ℓ of
//! the grid (cell width `w = 2^ℓ·h`). With the default [`Rounding::Centre`], level-ℓ voxel
//! `(i, j, k)` is inside iff the winding number of the mesh at its perturbed centre
//! `(x + ε², y − ε³, z + ε)`, with `(x, y, z) = ((i+½)w, (j+½)w, (k+½)w)`, passes the
//! [`FillRule`]. That is the brute-force set of §B3.5, and the convention of the peers harness
//! (a crossing exactly at a centre height counts below the centre).
//!
//! # Algorithm
//! 1. Check every coordinate is finite and on the lattice's index range.
//! 2. Per triangle, in parallel: skip it if its xy projection has zero area (`orient2d` = 0);
//!    orient it counter-clockwise; for every column centre in its projected bounding box, test
//!    coverage with `orient2d` and the **top-left rule** (a centre on an edge belongs to the
//!    triangle iff the edge, directed counter-clockwise, points to −y, or is horizontal and
//!    points to −x). This is the perturbation `(x + ε², y − ε³)`, so on a closed surface every
//!    crossing of a ray, through a vertex or along an edge, is counted exactly once.
//! 3. Locate each crossing in depth exactly (see *Numeric model*) and record
//!    `(column, position, Δwinding)`; Δ = −1 for an upward-facing triangle, +1 otherwise.
//! 4. Sort all records (a total order, so the result does not depend on the thread count),
//!    and per column, in parallel: group equal positions (their Δ apply together), run the
//!    winding number upward, keep the voxels whose winding passes the rule, and return
//!    [`DiscretizeError::NotClosed`] if the winding is not 0 above the last crossing.
//! 5. Build the normalised multi-scale solid from the columns ([`Solid::from_columns`]).
//!
//! # Numeric model
//! Only exact predicates decide. A crossing's depth `z*` is never computed: for a test height
//! `q` (a voxel centre `fl((k+½)w)` or a lattice plane `fl(k·w)`), the sign of
//! `orient3d(a, b, c, (x, y, q))` on the counter-clockwise triangle says whether `q` is below,
//! at or above `z*`. An f64 interpolation of `z*` only picks the first `k` to test; a galloping
//! search with the exact predicate then finds the first height at or above the crossing, so a
//! wrong guess costs time, never correctness. Crossings exactly at a centre height, common on
//! CAD and voxel-derived models, are decided exactly.
//!
//! # Roundings
//! - [`Rounding::Centre`] (default): voxel inside iff its perturbed centre is.
//! - [`Rounding::Inner`] (the seed's ⌈z_in/w⌉, ⌊z_out/w⌋): voxel inside iff the inside set
//!   holds just above its bottom plane and no crossing lies strictly between its two planes.
//! - [`Rounding::Outer`]: voxel inside iff the inside set holds just above its bottom plane or
//!   some crossing lies strictly between its planes.
//!
//! Both are exact for solids whose shells do not overlap. Where shells overlap, a crossing
//! strictly inside a cell that leaves the winding inside on both sides is still treated as a
//! boundary (Inner drops the voxel, Outer keeps it); the crossings within one cell are not
//! ordered, since that would need exact comparisons of two planes' depths.
//!
//! # Complexity
//! `O(T + C log C)` for `T` triangles and `C` column crossings (plus the columns each
//! triangle's bounding box covers); memory `O(C)`, that is, proportional to the surface.

use crate::par::*;
use robust::{Coord, Coord3D, orient2d, orient3d};

use super::column::{Column, Interval};
use super::grid::{Grid, MAX_LEVEL};
use super::tile::Solid;
use crate::Operation;
use crate::mesh::Mesh;
use crate::progress::{Cancelled, Counter, Progress, Stage};

/// Which winding numbers count as inside.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FillRule {
    /// Winding number ≠ 0: robust to overlapping shells (default).
    #[default]
    NonZero,
    /// Winding number > 0.
    Positive,
    /// Odd winding number (the seed's parity rule).
    Parity,
}

impl FillRule {
    /// Whether winding number `w` is inside.
    pub fn inside(self, w: i64) -> bool {
        match self {
            Self::NonZero => w != 0,
            Self::Positive => w > 0,
            Self::Parity => w & 1 != 0,
        }
    }
}

/// How crossing depths become voxel boundaries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Rounding {
    /// A voxel is inside iff its centre is (default).
    #[default]
    Centre,
    /// A voxel is inside iff it lies entirely inside (the seed's inner approximation).
    Inner,
    /// A voxel is inside iff the solid meets its interior.
    Outer,
}

/// Options of [`discretize`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DiscretizeOptions {
    /// Which winding numbers are inside.
    pub fill: FillRule,
    /// How depths round to voxels.
    pub rounding: Rounding,
}

/// Why a mesh could not be discretised.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DiscretizeError {
    /// The mesh is not closed: along this column the winding number does not return to 0.
    ///
    /// *How to fix:* close the holes of the mesh (`csgkit check` lists its open edges).
    #[error(
        "mesh is not closed: column ({i}, {j}) at level {level} ends with winding number {winding}"
    )]
    NotClosed {
        /// Column index along x at the discretisation level.
        i: i32,
        /// Column index along y at the discretisation level.
        j: i32,
        /// The discretisation level.
        level: u8,
        /// The winding number above the last crossing.
        winding: i64,
    },
    /// A vertex coordinate is not finite or lies outside the grid's index range.
    #[error(
        "vertex {vertex} has coordinate {value} that is not finite or is out of the grid's range"
    )]
    BadCoordinate {
        /// The vertex index.
        vertex: usize,
        /// The offending coordinate.
        value: f64,
    },
    /// The run was cancelled through its [`Progress`].
    #[error("discretisation was cancelled")]
    Cancelled(#[from] Cancelled),
    /// The level is above the largest supported level.
    #[error("level {0} is above the largest level 20")]
    BadLevel(u8),
}

/// One ray crossing: column `(i, j)`, depth position code and winding change, packed into one
/// integer whose order is `(j, i, pos, delta)`, so sorting is one integer comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Crossing(u128);

impl Crossing {
    const OFFSET: i64 = 1 << 31;

    fn new(i: i32, j: i32, pos: i32, delta: i8) -> Self {
        let field = |v: i32| (i64::from(v) + Self::OFFSET) as u128;
        Self(field(j) << 72 | field(i) << 40 | field(pos) << 8 | u128::from(delta as u8 ^ 0x80))
    }

    fn j(self) -> i32 {
        ((self.0 >> 72) as u32 as i64 - Self::OFFSET) as i32
    }

    fn i(self) -> i32 {
        ((self.0 >> 40) as u32 as i64 - Self::OFFSET) as i32
    }

    fn pos(self) -> i32 {
        ((self.0 >> 8) as u32 as i64 - Self::OFFSET) as i32
    }

    fn delta(self) -> i8 {
        (self.0 as u8 ^ 0x80) as i8
    }

    /// The column, as one comparable key.
    fn column_key(self) -> u128 {
        self.0 >> 40
    }
}

/// A level-ℓ column and its index.
type KeyedColumn = ((i32, i32), Column);

/// Discretises `mesh` at `level` of `grid`.
///
/// # Errors
/// [`DiscretizeError::BadCoordinate`] for a non-finite or out-of-range vertex,
/// [`DiscretizeError::NotClosed`] if some column's winding number does not return to 0,
/// [`DiscretizeError::BadLevel`] for a level above 20.
pub fn discretize(
    mesh: &Mesh,
    grid: Grid,
    level: u8,
    options: DiscretizeOptions,
) -> Result<Solid, DiscretizeError> {
    discretize_with_progress(mesh, grid, level, options, &Progress::default())
}

/// [`discretize`], reporting the triangles done to `progress` ([`Stage::Discretize`]), which
/// can cancel the work.
///
/// # Errors
/// As [`discretize`], and [`DiscretizeError::Cancelled`] once `progress` is cancelled.
pub fn discretize_with_progress(
    mesh: &Mesh,
    grid: Grid,
    level: u8,
    options: DiscretizeOptions,
    progress: &Progress,
) -> Result<Solid, DiscretizeError> {
    let counter = progress.counter(Stage::Discretize, triangle_count(mesh));
    let solid = discretize_counted(mesh, grid, level, options, &counter)?;
    counter.finish()?;
    Ok(solid)
}

/// The triangles [`discretize`] casts: those of the mesh's fans.
pub(crate) fn triangle_count(mesh: &Mesh) -> usize {
    mesh.fan_triangles().count()
}

/// [`discretize`], advancing `counter` by the triangles done (of a count that may span
/// several meshes). After a cancellation the solid is incomplete: the caller's
/// [`Counter::finish`] reports it.
///
/// # Errors
/// As [`discretize`].
pub(crate) fn discretize_counted(
    mesh: &Mesh,
    grid: Grid,
    level: u8,
    options: DiscretizeOptions,
    counter: &Counter,
) -> Result<Solid, DiscretizeError> {
    if level > MAX_LEVEL {
        return Err(DiscretizeError::BadLevel(level));
    }
    check_coordinates(mesh, &grid)?;
    let lattice = Lattice {
        grid,
        level,
        rounding: options.rounding,
    };
    let mut crossings = all_crossings(mesh, &lattice, counter);
    if counter.is_cancelled() {
        return Ok(Solid::from_columns(grid, level, &[]));
    }
    crossings.par_sort_unstable();
    let groups: Vec<&[Crossing]> = crossings
        .chunk_by(|a, b| a.column_key() == b.column_key())
        .collect();
    let columns: Vec<Result<KeyedColumn, DiscretizeError>> = groups
        .into_par_iter()
        .map(|g| {
            lattice
                .column(g, options.fill)
                .map(|c| ((g[0].i(), g[0].j()), c))
        })
        .collect();
    let columns = columns.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok(Solid::from_columns(grid, level, &columns))
}

/// Steps 2–3 over all triangles, in parallel chunks, in triangle order; each chunk advances
/// `counter`, and once the run is cancelled the remaining chunks give nothing.
fn all_crossings(mesh: &Mesh, lattice: &Lattice, counter: &Counter) -> Vec<Crossing> {
    let triangles: Vec<[u32; 3]> = mesh.fan_triangles().map(|(_, t)| t).collect();
    let positions = mesh.positions();
    counter.par_chunks(&triangles, |chunk, out| {
        for t in chunk {
            lattice.triangle_crossings(t.map(|v| positions[v as usize]), out);
        }
    })
}

/// Step 1: every coordinate finite and within the grid's index range.
fn check_coordinates(mesh: &Mesh, grid: &Grid) -> Result<(), DiscretizeError> {
    for (vertex, p) in mesh.positions().iter().enumerate() {
        if let Some(&value) = p.iter().find(|&&v| !grid.check_coordinate(v)) {
            return Err(DiscretizeError::BadCoordinate { vertex, value });
        }
    }
    Ok(())
}

/// The sample lattice of one level, with the rounding that positions crossings.
struct Lattice {
    grid: Grid,
    level: u8,
    rounding: Rounding,
}

impl Lattice {
    /// Steps 2–3 for one triangle: append its crossings with the column rays to `out`.
    fn triangle_crossings(&self, [a, b, c]: [[f64; 3]; 3], out: &mut Vec<Crossing>) {
        let area = orient2d(xy(a), xy(b), xy(c));
        if area == 0.0 {
            return;
        }
        // Counter-clockwise in projection; an upward-facing triangle is left going up: Δ = −1.
        let (tri, delta) = if area > 0.0 {
            ([a, b, c], -1)
        } else {
            ([a, c, b], 1)
        };
        let (lo, hi) = bounds(&tri);
        let (i0, i1) = (
            self.first_centre_at_least(lo[0]),
            self.last_centre_at_most(hi[0]),
        );
        let (j0, j1) = (
            self.first_centre_at_least(lo[1]),
            self.last_centre_at_most(hi[1]),
        );
        for j in j0..=j1 {
            let y = self.grid.centre(self.level, j);
            for i in i0..=i1 {
                let x = self.grid.centre(self.level, i);
                if let Some(weights) = covers(&tri, x, y) {
                    let pos = self.locate(&tri, x, y, weights, (lo[2], hi[2]));
                    out.push(Crossing::new(i as i32, j as i32, pos, delta));
                }
            }
        }
    }

    /// The first index whose centre is at or above `v` (exact comparison of f64 values).
    fn first_centre_at_least(&self, v: f64) -> i64 {
        let centre = |k| self.grid.centre(self.level, k);
        let mut k = (v / self.grid.width(self.level) - 0.5).ceil() as i64;
        while centre(k - 1) >= v {
            k -= 1;
        }
        while centre(k) < v {
            k += 1;
        }
        k
    }

    /// The last index whose centre is at or below `v`.
    fn last_centre_at_most(&self, v: f64) -> i64 {
        let centre = |k| self.grid.centre(self.level, k);
        let mut k = (v / self.grid.width(self.level) - 0.5).floor() as i64;
        while centre(k + 1) <= v {
            k += 1;
        }
        while centre(k) > v {
            k -= 1;
        }
        k
    }

    /// Step 3: the position code of the crossing of `tri` with the ray at `(x, y)`.
    ///
    /// Centre rounding: the first voxel `k` whose centre is at or above the crossing. Inner
    /// and outer rounding: `2f` if the crossing lies on plane `f`, `2f − 1` if strictly
    /// between planes `f − 1` and `f`.
    fn locate(
        &self,
        tri: &[[f64; 3]; 3],
        x: f64,
        y: f64,
        weights: [f64; 3],
        zrange: (f64, f64),
    ) -> i32 {
        let w = self.grid.width(self.level);
        let guess = interpolate(tri, weights).clamp(zrange.0, zrange.1);
        // `height(k) >= z*`, decided exactly; monotone in k.
        let at_or_above = |height: f64| {
            orient3d(xyz(tri[0]), xyz(tri[1]), xyz(tri[2]), xyz([x, y, height])) <= 0.0
        };
        match self.rounding {
            Rounding::Centre => {
                let start = (guess / w - 0.5).ceil() as i64;
                first_true(start, |k| at_or_above(self.grid.centre(self.level, k))) as i32
            }
            Rounding::Inner | Rounding::Outer => {
                let start = (guess / w).ceil() as i64;
                let f = first_true(start, |k| at_or_above(self.grid.plane(self.level, k)));
                let on_plane = orient3d(
                    xyz(tri[0]),
                    xyz(tri[1]),
                    xyz(tri[2]),
                    xyz([x, y, self.grid.plane(self.level, f)]),
                ) == 0.0;
                (2 * f - i64::from(!on_plane)) as i32
            }
        }
    }

    /// Step 4 for one column's sorted crossings: its inside intervals in finest voxels.
    fn column(&self, crossings: &[Crossing], fill: FillRule) -> Result<Column, DiscretizeError> {
        let (i, j) = (crossings[0].i(), crossings[0].j());
        let mut base: Vec<Interval> = Vec::new();
        let mut special = Column::new();
        let mut winding = 0i64;
        let mut start: Option<i32> = None;
        for group in crossings.chunk_by(|a, b| a.pos() == b.pos()) {
            let pos = group[0].pos();
            let (first_voxel, strictly_inside) = match self.rounding {
                Rounding::Centre => (pos, false),
                _ => ((pos + 1).div_euclid(2), pos % 2 != 0),
            };
            if strictly_inside {
                special.push_merge(first_voxel - 1, first_voxel);
            }
            winding += group.iter().map(|c| i64::from(c.delta())).sum::<i64>();
            match (start, fill.inside(winding)) {
                (None, true) => start = Some(first_voxel),
                (Some(s), false) => {
                    base.push(Interval {
                        z0: s,
                        z1: first_voxel,
                    });
                    start = None;
                }
                _ => {}
            }
        }
        if winding != 0 {
            return Err(DiscretizeError::NotClosed {
                i,
                j,
                level: self.level,
                winding,
            });
        }
        let base = Column::from_intervals(base);
        let column = match self.rounding {
            Rounding::Centre => base,
            Rounding::Inner => base.op(&special, Operation::Difference),
            Rounding::Outer => base.op(&special, Operation::Union),
        };
        Ok(scale(&column, self.level))
    }
}

/// Whether the counter-clockwise `tri` covers `(x, y)` under the top-left rule; if so, the
/// (approximate, correctly signed) barycentric weights of its three corners.
fn covers(tri: &[[f64; 3]; 3], x: f64, y: f64) -> Option<[f64; 3]> {
    let p = Coord { x, y };
    let mut weights = [0.0; 3];
    for e in 0..3 {
        let (u, v) = (tri[(e + 1) % 3], tri[(e + 2) % 3]);
        let side = orient2d(xy(u), xy(v), p);
        let top_left = v[1] < u[1] || (v[1] == u[1] && v[0] < u[0]);
        if side < 0.0 || (side == 0.0 && !top_left) {
            return None;
        }
        weights[e] = side;
    }
    Some(weights)
}

/// The f64 estimate of the crossing depth from barycentric weights (a search start only).
fn interpolate(tri: &[[f64; 3]; 3], weights: [f64; 3]) -> f64 {
    let sum = weights[0] + weights[1] + weights[2];
    let z = (weights[0] * tri[0][2] + weights[1] * tri[1][2] + weights[2] * tri[2][2]) / sum;
    if z.is_finite() { z } else { tri[0][2] }
}

/// The smallest `k` with `pred(k)`, for a monotone `pred`, galloping from `start`.
///
/// The predicate must turn true somewhere above and stay false somewhere below, which holds
/// because a crossing lies within its triangle's depth range, inside the lattice's range.
fn first_true(start: i64, pred: impl Fn(i64) -> bool) -> i64 {
    let (mut lo, mut hi); // pred(lo) false, pred(hi) true
    if pred(start) {
        hi = start;
        let mut step = 1;
        lo = start - 1;
        while pred(lo) {
            hi = lo;
            step *= 2;
            lo = start - step;
        }
    } else {
        lo = start;
        let mut step = 1;
        hi = start + 1;
        while !pred(hi) {
            lo = hi;
            step *= 2;
            hi = start + step;
        }
    }
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if pred(mid) { hi = mid } else { lo = mid }
    }
    hi
}

/// A level-ℓ column's intervals in finest voxel indices.
fn scale(column: &Column, level: u8) -> Column {
    Column::from_intervals(
        column
            .intervals()
            .iter()
            .map(|iv| Interval {
                z0: iv.z0 << level,
                z1: iv.z1 << level,
            })
            .collect(),
    )
}

fn bounds(tri: &[[f64; 3]; 3]) -> ([f64; 3], [f64; 3]) {
    let mut lo = tri[0];
    let mut hi = tri[0];
    for p in &tri[1..] {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}

fn xy(p: [f64; 3]) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

fn xyz(p: [f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

#[cfg(test)]
mod tests;
