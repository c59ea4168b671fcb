//! An operation on meshes through the discrete engine, as `csgkit discrete` and the engine
//! facade run it: [`combine`].

use crate::Operation;
use crate::mesh::Mesh;
use crate::progress::{Cancelled, Progress, Stage, StageClock};

use super::discretize::{DiscretizeError, DiscretizeOptions, discretize_counted, triangle_count};
use super::grid::Grid;
use super::materials::{MaterialSolid, discretize_parts_counted, label};
use super::tile::{Solid, TileStats};

/// Why [`combine`] produced nothing.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CombineError {
    /// An operand could not be discretised.
    ///
    /// *How to fix:* see the [`DiscretizeError`].
    #[error("operand {operand}: {error}")]
    Operand {
        /// The operand, in the order given.
        operand: usize,
        /// Why it failed.
        error: DiscretizeError,
    },
    /// The run was cancelled through its [`Progress`].
    #[error(transparent)]
    Cancelled(#[from] Cancelled),
}

/// The result of [`combine`].
#[derive(Clone, Debug)]
pub struct Combined {
    /// The result of the operation.
    pub solid: Solid,
    /// The result's voxels by material, when an operand had face materials.
    pub parts: Option<Vec<MaterialSolid>>,
    /// Counts and stage times.
    pub stats: DiscreteStats,
}

/// What a run of the discrete engine did, for `--stats`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DiscreteStats {
    /// Seconds of each stage that ran, in order ([`Stage::Discretize`], [`Stage::Combine`],
    /// and [`Stage::Convert`] when the result became a mesh).
    pub stage_seconds: Vec<(Stage, f64)>,
    /// The voxels of each operand, in operand order.
    pub operand_voxels: Vec<u64>,
    /// The voxels of the result.
    pub voxels: u64,
    /// The result's tiles.
    pub tiles: TileStats,
}

/// Computes `op` on `operands`, operand `k` discretised at `levels[k]` of `grid`, reporting
/// the triangles cast to `progress`, which can cancel the run:
/// 1. Discretise each operand at its own level of one [`Grid`] (cells that differ by powers
///    of two, [`Grid::for_cells`]), counting the triangles cast in one [`Stage::Discretize`]
///    report over all operands. When any operand has face materials, every operand is one
///    solid per material ([`discretize_parts`](super::discretize_parts)) and their union is
///    the operand.
/// 2. Fold the operation over the solids ([`Solid::op_all`]: a difference is the first minus
///    the union of the others), [`Stage::Combine`].
/// 3. With materials, label the result's voxels by the first operand part containing them
///    ([`label`]), so its mesh keeps them ([`labelled_mesh`](super::labelled_mesh)).
///
/// The result stays a [`Solid`]: it becomes boxes ([`Solid::to_boxes`]) or a mesh (through
/// the orthogonal engine, or as surfels) as the caller chooses.
///
/// # Example
/// A wall of cell 8 minus a cube of cell 1 that cuts through it.
/// ```
/// use csgkit::discrete::{DiscretizeOptions, Grid, combine};
/// use csgkit::primitives::cuboid;
/// use csgkit::{Operation, Progress};
/// let (grid, levels) = Grid::for_cells(&[8.0, 1.0]).unwrap();
/// let wall = cuboid([0.0; 3], [16.0, 16.0, 8.0]);
/// let cut = cuboid([4.0, 4.0, 4.0], [12.0, 12.0, 12.0]);
/// let options = DiscretizeOptions::default();
/// let progress = Progress::default();
/// let result = combine(Operation::Difference, &[&wall, &cut], grid, &levels, options, &progress).unwrap();
/// assert_eq!(result.solid.voxel_count(), 16 * 16 * 8 - 8 * 8 * 4);
/// ```
///
/// # Errors
/// [`CombineError::Operand`] for the first operand that cannot be discretised,
/// [`CombineError::Cancelled`] once `progress` is cancelled.
///
/// # Panics
/// If `levels` does not have one level per operand.
pub fn combine(
    op: Operation,
    operands: &[&Mesh],
    grid: Grid,
    levels: &[u8],
    options: DiscretizeOptions,
    progress: &Progress,
) -> Result<Combined, CombineError> {
    assert_eq!(levels.len(), operands.len(), "one level per operand");
    let mut clock = StageClock::new(progress);
    let with_materials = operands.iter().any(|m| m.face_materials().is_some());
    let total = operands.iter().map(|m| triangle_count(m)).sum();
    let counter = progress.counter(Stage::Discretize, total);
    let mut solids = Vec::with_capacity(operands.len());
    let mut parts = Vec::with_capacity(operands.len());
    for (operand, (mesh, &level)) in operands.iter().zip(levels).enumerate() {
        let named = |error| CombineError::Operand { operand, error };
        if with_materials {
            // One solid per material: the result's faces take the material of the operand
            // behind them.
            let own =
                discretize_parts_counted(mesh, grid, level, options, &counter).map_err(named)?;
            let whole: Vec<Solid> = own.iter().map(|p| p.solid.clone()).collect();
            let union = Solid::op_all(&whole, Operation::Union).expect("parts share the grid");
            solids.push(union.expect("a mesh has at least one part"));
            parts.push(own);
        } else {
            solids.push(discretize_counted(mesh, grid, level, options, &counter).map_err(named)?);
        }
    }
    counter.finish()?;
    clock.record(Stage::Discretize);
    let solid = Solid::op_all(&solids, op)
        .expect("operands share the grid")
        .unwrap_or_else(|| Solid::empty(grid));
    let parts = with_materials.then(|| label(&solid, &parts).expect("parts share the grid"));
    clock.end(Stage::Combine)?;
    let stats = DiscreteStats {
        stage_seconds: clock.into_seconds(),
        operand_voxels: solids.iter().map(Solid::voxel_count).collect(),
        voxels: solid.voxel_count(),
        tiles: solid.stats(),
    };
    Ok(Combined {
        solid,
        parts,
        stats,
    })
}
