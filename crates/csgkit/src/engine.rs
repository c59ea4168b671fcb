//! The engine facade: [`Engine`], one interface over the exact, orthogonal and discrete
//! engines, which the crate root re-exports with its engines, [`Output`] and [`Stats`]. It
//! sits at the top of the library: it uses the engines and the crate's [`Error`], and nothing
//! below it uses it.

use crate::Operation;
use crate::discrete::{DiscreteStats, DiscretizeOptions, Grid, combine, labelled_mesh};
use crate::error::Error;
use crate::exact::{BooleanOptions, BooleanStats, Expression, boolean_expression};
use crate::mesh::Mesh;
use crate::ortho::{MeshOptions, bounded_box, box_union_mesh, plain_box};
use crate::progress::{Progress, Stage, StageClock};

mod sealed {
    /// Only the crate's engines implement [`Engine`](super::Engine).
    pub trait Sealed {}
}

/// An engine: computes an [`Operation`] on meshes, with progress and cancellation, giving a
/// mesh and the engine's statistics; one interface over the three engines.
///
/// # Design
/// A sealed trait with one method, [`Engine::apply`], implemented by one
/// configuration struct per engine (as aho-corasick's `Automaton` is by its three automata):
/// - [`ExactEngine`]: the exact mesh booleans ([`crate::exact`]), every operation on any
///   closed meshes, certified as f64 numbers;
/// - [`OrthoEngine`]: the orthogonal engine ([`crate::ortho`]), the exact union of operands
///   that are axis-aligned boxes;
/// - [`DiscreteEngine`]: the discrete engine ([`crate::discrete`]), every operation on the
///   voxel sets of closed meshes, each operand at its own cell size.
///
/// A trait rather than an enum: a caller that knows its engine names its struct and its
/// options and nothing else, and a caller that chooses at run time (the command line, the
/// Python and WebAssembly bindings to come) holds a `Box<dyn Engine>`; the trait is
/// object-safe for that. It is sealed because the facade promises every engine's contract
/// (the output is a closed mesh; cancellation is [`Error::Cancelled`] from inside the long
/// stages), which an outside implementation could not be held to, and so that methods can be
/// added without breaking anyone. [`Output`] is one type for all engines: the mesh, and the
/// engine's own statistics in [`Stats`], whose stage seconds every engine fills in.
///
/// # Example
/// Two overlapping cubes through each engine.
/// ```
/// use csgkit::{DiscreteEngine, Engine, ExactEngine, OrthoEngine};
/// use csgkit::primitives::cuboid;
/// use csgkit::{Operation, Progress};
/// let (a, b) = (cuboid([0.0; 3], [2.0; 3]), cuboid([1.0; 3], [3.0; 3]));
/// let engines: [Box<dyn Engine>; 3] = [
///     Box::new(ExactEngine::default()),
///     Box::new(OrthoEngine::default()),
///     Box::new(DiscreteEngine::with_cell(0.5)),
/// ];
/// for engine in &engines {
///     let union = engine.apply(Operation::Union, &[&a, &b], &Progress::default()).unwrap();
///     let report = union.mesh.report();
///     assert!(report.is_valid_solid(), "{}", engine.name());
///     assert_eq!(report.measures.volume, 15.0, "{}", engine.name());
/// }
/// ```
pub trait Engine: sealed::Sealed + Send + Sync {
    /// The engine's name, lowercase ("exact", "ortho", "discrete").
    fn name(&self) -> &'static str;

    /// Computes `operation` on `operands` (a difference: the first minus all others),
    /// reporting the engine's stages to `progress`, which can cancel the run from inside its
    /// long stages. An empty mesh is the empty set.
    ///
    /// # Errors
    /// [`Error::Cancelled`] once `progress` is cancelled; [`Error::Unsupported`] for an
    /// operation or an operand the engine does not take; otherwise the engine's own error
    /// (an operand that is not a closed solid, say), as the [`Error`] variant wrapping it.
    fn apply(
        &self,
        operation: Operation,
        operands: &[&Mesh],
        progress: &Progress,
    ) -> Result<Output, Error>;
}

/// What an [`Engine`] computed.
#[derive(Clone, Debug)]
pub struct Output {
    /// The boundary of the result: a closed, consistently oriented mesh.
    pub mesh: Mesh,
    /// How it was computed.
    pub stats: Stats,
}

/// The statistics of the engine that ran.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Stats {
    /// The exact engine's.
    Exact(BooleanStats),
    /// The orthogonal engine's.
    Ortho(OrthoStats),
    /// The discrete engine's.
    Discrete(DiscreteStats),
}

impl Stats {
    /// The seconds of every stage that ran, in order.
    pub fn stage_seconds(&self) -> &[(Stage, f64)] {
        match self {
            Stats::Exact(stats) => &stats.stage_seconds,
            Stats::Ortho(stats) => &stats.stage_seconds,
            Stats::Discrete(stats) => &stats.stage_seconds,
        }
    }
}

/// The exact engine: [`boolean_expression`] with these options. Three or more operands of a
/// union (of a difference, after the first) that are plain axis-aligned boxes are united
/// by the orthogonal engine first and enter the exact engine as one operand, as box unions
/// in CSG trees do: its stages ([`Stage::Rank`], [`Stage::Sweep`], [`Stage::Loops`],
/// [`Stage::Triangulate`]) come first in the statistics, and the result's provenance
/// numbers the remaining operands in order, then the united boxes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExactEngine {
    /// How the boolean runs.
    pub options: BooleanOptions,
}

impl sealed::Sealed for ExactEngine {}

impl Engine for ExactEngine {
    fn name(&self) -> &'static str {
        "exact"
    }

    fn apply(
        &self,
        operation: Operation,
        operands: &[&Mesh],
        progress: &Progress,
    ) -> Result<Output, Error> {
        let boxes = plain_boxes(operation, operands);
        if boxes.is_empty() {
            let expression = Expression::of(operation, operands.len());
            let result = boolean_expression(&expression, operands, &self.options, progress)?;
            return Ok(Output {
                mesh: result.mesh,
                stats: Stats::Exact(result.stats),
            });
        }
        // The boxes are united by the orthogonal engine (exactly, from comparisons of their
        // coordinates), and the exact engine meets one operand instead of many, as in CSG
        // trees: a union or a difference is associative over its united operands.
        let corners: Vec<[f64; 6]> = boxes.iter().map(|&(_, corners)| corners).collect();
        let (out, mut stage_seconds) =
            box_union_mesh(&corners, None, MeshOptions::default(), progress)?;
        let united = out.mesh;
        let mut rest: Vec<&Mesh> = (operands.iter().enumerate())
            .filter(|(k, _)| boxes.binary_search_by_key(k, |&(b, _)| b).is_err())
            .map(|(_, mesh)| *mesh)
            .collect();
        rest.push(&united);
        let expression = Expression::of(operation, rest.len());
        let mut result = boolean_expression(&expression, &rest, &self.options, progress)?;
        stage_seconds.append(&mut result.stats.stage_seconds);
        result.stats.stage_seconds = stage_seconds;
        Ok(Output {
            mesh: result.mesh,
            stats: Stats::Exact(result.stats),
        })
    }
}

/// The operands of `operation` that the orthogonal engine can unite first, in order, with
/// their boxes: for a union every operand, for a difference those after the first, that is
/// a plain box ([`plain_box`]); none unless there are at least
/// [`MIN_UNITED_BOXES`].
fn plain_boxes(operation: Operation, operands: &[&Mesh]) -> Vec<(usize, [f64; 6])> {
    let first = match operation {
        Operation::Union => 0,
        Operation::Difference => 1,
        Operation::Intersection | Operation::Xor => return Vec::new(),
    };
    let boxes: Vec<(usize, [f64; 6])> = (first..operands.len())
        .filter_map(|k| plain_box(operands[k]).map(|corners| (k, corners)))
        .collect();
    if boxes.len() >= MIN_UNITED_BOXES {
        boxes
    } else {
        Vec::new()
    }
}

/// The fewest boxes [`ExactEngine`] unites with the orthogonal engine. Two boxes make an
/// arrangement too small for the detour to pay, and the exact engine's own result keeps
/// each box face as a face of its own (the orthogonal engine's are maximal).
const MIN_UNITED_BOXES: usize = 3;

/// The orthogonal engine on meshes: the union of operands that each bound one axis-aligned
/// box (any tessellation of the box's surface, outward), as maximal faces.
///
/// An operand is taken as a box when every face lies in a plane of its bounding box and it
/// is closed with positive volume: a closed surface on a box's boundary covers it a whole
/// number of times, so that the operand is the box. Unions of other sets of boxes go to
/// [`box_union`](crate::ortho::box_union) directly.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OrthoEngine {
    /// How the B-rep becomes a mesh.
    pub mesh: MeshOptions,
}

/// What the orthogonal engine did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OrthoStats {
    /// Seconds of [`Stage::Rank`], [`Stage::Sweep`], [`Stage::Loops`] and
    /// [`Stage::Triangulate`].
    pub stage_seconds: Vec<(Stage, f64)>,
    /// Boxes given (the non-empty operands).
    pub boxes: usize,
    /// In manifold mode, non-manifold edges left shared (see
    /// [`MeshOutput`](crate::ortho::MeshOutput)).
    pub unsplit_edges: usize,
}

impl sealed::Sealed for OrthoEngine {}

impl Engine for OrthoEngine {
    fn name(&self) -> &'static str {
        "ortho"
    }

    fn apply(
        &self,
        operation: Operation,
        operands: &[&Mesh],
        progress: &Progress,
    ) -> Result<Output, Error> {
        let unsupported = |reason: String| Error::Unsupported {
            engine: self.name(),
            reason,
        };
        if operation != Operation::Union {
            return Err(unsupported(format!(
                "computes unions only, not the {}",
                operation.name()
            )));
        }
        let mut boxes = Vec::with_capacity(operands.len());
        for (k, mesh) in operands.iter().enumerate() {
            if mesh.face_count() == 0 {
                continue;
            }
            let solid = bounded_box(mesh).ok_or_else(|| {
                unsupported(format!(
                    "takes boxes only: operand {k} is not an axis-aligned box"
                ))
            })?;
            boxes.push(solid);
        }
        let (out, stage_seconds) = box_union_mesh(&boxes, None, self.mesh, progress)?;
        Ok(Output {
            mesh: out.mesh,
            stats: Stats::Ortho(OrthoStats {
                stage_seconds,
                boxes: boxes.len(),
                unsplit_edges: out.unsplit_edges,
            }),
        })
    }
}

/// The discrete engine on meshes: each operand discretised at its cell size, the operation
/// on the voxel sets, and the result's boundary as a mesh ([`combine`]).
#[derive(Clone, Debug, PartialEq)]
pub struct DiscreteEngine {
    /// The cell size of each operand, in operand order; cells must differ by powers of two.
    /// One cell is every operand's.
    pub cells: Vec<f64>,
    /// How meshes become voxels.
    pub options: DiscretizeOptions,
    /// How the result becomes a mesh.
    pub surface: DiscreteSurface,
}

/// How the discrete engine's result becomes a mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DiscreteSurface {
    /// Boxes through the orthogonal engine: maximal faces (with holes triangulated), with
    /// the operands' materials.
    #[default]
    Ortho,
    /// The paper's top, bottom and lateral surfels as unit quads: faster on very fine grids,
    /// about three times as many faces.
    Surfels,
}

impl DiscreteEngine {
    /// Every operand at cell size `cell`, with the default options.
    pub fn with_cell(cell: f64) -> Self {
        Self {
            cells: vec![cell],
            options: DiscretizeOptions::default(),
            surface: DiscreteSurface::default(),
        }
    }
}

impl sealed::Sealed for DiscreteEngine {}

impl Engine for DiscreteEngine {
    fn name(&self) -> &'static str {
        "discrete"
    }

    fn apply(
        &self,
        operation: Operation,
        operands: &[&Mesh],
        progress: &Progress,
    ) -> Result<Output, Error> {
        let cells = match self.cells.as_slice() {
            // At least one cell, so that no operand still makes a grid (and the empty set).
            [one] => vec![*one; operands.len().max(1)],
            cells if cells.len() == operands.len() => cells.to_vec(),
            cells => {
                return Err(Error::Unsupported {
                    engine: self.name(),
                    reason: format!(
                        "needs one cell size or one per operand, not {} for {} operands",
                        cells.len(),
                        operands.len()
                    ),
                });
            }
        };
        let (grid, mut levels) = Grid::for_cells(&cells)?;
        levels.truncate(operands.len());
        let combined = combine(operation, operands, grid, &levels, self.options, progress)?;
        let mut clock = StageClock::new(progress);
        let mesh = match (self.surface, &combined.parts) {
            (DiscreteSurface::Ortho, Some(parts)) => labelled_mesh(parts)?,
            (DiscreteSurface::Ortho, None) => combined.solid.to_mesh()?,
            (DiscreteSurface::Surfels, _) => combined.solid.to_surfel_mesh()?,
        };
        clock.end(Stage::Convert)?;
        let mut stats = combined.stats;
        stats.stage_seconds.extend(clock.into_seconds());
        Ok(Output {
            mesh,
            stats: Stats::Discrete(stats),
        })
    }
}
