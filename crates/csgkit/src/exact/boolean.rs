//! The public entry of the exact engine: [`boolean`] runs the stages of the pipeline in
//! order and times each one.

use std::time::Instant;

use crate::kernel::Point3;
use crate::mesh::{FaceMode, Mesh, PolygonError};

use crate::Operation;

use super::assemble::Rounded;
use super::expression::Expression;
use super::winding::{self, WindingRule};
use super::{assemble, broad, certify, classify, ingest, reconstruct, select, simplify, subdivide};

/// A stage of the pipeline, as reported to a [`ProgressFn`] and in [`BooleanStats`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Stage {
    /// Welding, triangulation of polygons, removal of degenerate triangles, closedness.
    Ingest,
    /// The exact self-intersection check of every operand, and the search for nested shells.
    Validate,
    /// Candidate triangle pairs from bounding boxes.
    Broad,
    /// Exact triangle–triangle intersection of the candidates.
    Intersect,
    /// Constrained triangulation of every triangle that meets another operand.
    Split,
    /// Patches and their inside / outside / on labels.
    Classify,
    /// The output face of every kept sub-triangle, and the removal of the intersection
    /// points no face needs (exact).
    Reconstruct,
    /// Rounding to f64 and the output mesh.
    Assemble,
    /// Faces flat to within [`BooleanOptions::simplify`] merged, and the vertices only they
    /// need removed (when asked).
    Simplify,
    /// The output checked as f64 numbers, repaired where rounding folded or collapsed it
    /// (snap rounding).
    Certify,
    /// The certified triangles merged into polygons or quads ([`BooleanOptions::faces`]),
    /// and the optional 2-manifold split.
    Faces,
    /// Face and corner attributes (materials, UVs, normals) from the source faces.
    Attributes,
}

/// A progress callback, called with `(stage, done, total)`; returning `false` cancels.
pub type ProgressFn<'a> = &'a (dyn Fn(Stage, usize, usize) -> bool + Sync);

/// How [`boolean`] runs.
#[derive(Clone, Copy)]
pub struct BooleanOptions<'a> {
    /// Find the faces of each operand that cross each other (exact, costs about as much as
    /// the boolean itself) and resolve them: such operands are intersected with themselves
    /// in the same arrangement and classified by winding numbers. On by default; when off,
    /// every operand is assumed free of self-intersections and a self-intersecting one gives
    /// a wrong result without an error.
    pub check_self_intersections: bool,
    /// Which winding numbers are inside an operand that is not a simple solid
    /// (self-intersecting, or with nested shells). For simple solids both rules agree.
    pub winding: WindingRule,
    /// Split the non-manifold edges and vertices of the result by duplicating vertices, so
    /// the output is a 2-manifold (`--manifold`).
    pub split_non_manifold: bool,
    /// The faces of the result: triangles (the default), the polygons of the source faces
    /// (hole-free pieces), or triangles and convex quads ([`merge_faces`]).
    ///
    /// [`merge_faces`]: crate::mesh::merge_faces
    pub faces: FaceMode,
    /// Merge neighbouring faces that lie exactly in one plane and have the same material,
    /// group and colour (and no UVs or normals), even when they come from different source
    /// faces, so a chain of booleans read back from files does not accumulate triangles.
    pub merge_coplanar: bool,
    /// Merge neighbouring faces that are flat to within this distance (and look alike, as
    /// for `merge_coplanar`), and remove the vertices only they need, moving the surface by
    /// at most this distance per removal; the result is certified as always. For chains of
    /// booleans through files, whose rounded faces are flat only to within an ulp.
    pub simplify: Option<f64>,
    /// Called as stages progress.
    pub progress: Option<ProgressFn<'a>>,
}

impl Default for BooleanOptions<'_> {
    fn default() -> Self {
        Self {
            check_self_intersections: true,
            winding: WindingRule::NonZero,
            split_non_manifold: false,
            faces: FaceMode::Triangles,
            merge_coplanar: false,
            simplify: None,
            progress: None,
        }
    }
}

/// What a [`boolean`] run did, for `--stats`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BooleanStats {
    /// Seconds spent in each stage that ran, in pipeline order.
    pub stage_seconds: Vec<(Stage, f64)>,
    /// Triangles of all operands after ingest.
    pub input_triangles: usize,
    /// Triangle pairs of different operands whose boxes overlap.
    pub candidate_pairs: usize,
    /// Candidate pairs that really touch or cross.
    pub intersecting_pairs: usize,
    /// Triangles that were split.
    pub split_triangles: usize,
    /// Patches: pieces of one operand's surface bounded by intersection curves.
    pub patches: usize,
    /// Triangle pairs within one operand that intersect, resolved in the arrangement.
    pub self_intersecting_pairs: usize,
    /// Whether patches were classified by winding numbers (operands that are not simple
    /// solids) rather than by local tests.
    pub winding_classification: bool,
    /// Triangles of the result, before any merging into polygons.
    pub output_triangles: usize,
    /// Faces of the result, as [`BooleanOptions::faces`] asks.
    pub output_faces: usize,
    /// Vertices removed: intersection points on a straight stretch of the boundary between
    /// two faces or inside one (reconstruct), and with `simplify`, vertices only faces flat
    /// to within its tolerance needed.
    pub removed_vertices: usize,
    /// Output vertices that are intersection points rounded to f64.
    pub rounded_vertices: usize,
    /// Output vertices moved to a coarser grid because rounding made faces cross or
    /// collapse (0 almost always; see the certify stage).
    pub snapped_vertices: usize,
    /// Slivers thinner than the f64 grid that certification removed (a short side collapsed
    /// or a needle flipped away; see the certify stage).
    pub dissolved_slivers: usize,
    /// The largest distance certification moved the surface (a re-rounded or snapped vertex,
    /// a collapsed side, a flipped needle), relative to the diagonal of the result's bounding
    /// box.
    pub max_snap_displacement: f64,
    /// Rounds of snapping and exact re-refinement certification needed.
    pub certify_rounds: usize,
}

impl BooleanStats {
    /// The total seconds of every stage except [`Stage::Validate`]: the operation itself.
    pub fn op_seconds(&self) -> f64 {
        (self.stage_seconds.iter())
            .filter(|(stage, _)| *stage != Stage::Validate)
            .map(|(_, s)| s)
            .sum()
    }
}

/// The result of [`boolean`]: the mesh and how it was made.
#[derive(Clone, Debug)]
pub struct Boolean {
    /// The boundary of the result: closed, oriented outward, triangles, with per-face
    /// provenance (operand, original face).
    pub mesh: Mesh,
    /// Counts and stage times.
    pub stats: BooleanStats,
}

/// Why a boolean could not be computed. Every variant names the operand (its index in the
/// order given) and where the problem is.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BooleanError {
    /// No operand was given.
    #[error("no operand given")]
    NoOperands,
    /// A vertex has a NaN or infinite coordinate.
    ///
    /// *How to fix*: repair or remove the vertex.
    #[error("operand {operand}: vertex {vertex} has a non-finite coordinate")]
    NonFinite {
        /// The operand.
        operand: usize,
        /// The vertex index in that operand.
        vertex: u32,
    },
    /// A polygon of the operand cannot be triangulated: its projection overlaps itself, or it
    /// has zero area (see [`PolygonError`], which names the face).
    ///
    /// *How to fix*: split the face into simple polygons, or remove it if it has no area
    /// (`csgkit check` lists such faces).
    #[error("operand {operand}: {error}")]
    InvalidPolygon {
        /// The operand.
        operand: usize,
        /// The face and what is wrong with it.
        error: PolygonError,
    },
    /// Some edges are not used equally often in both directions: the operand has holes or
    /// inconsistently oriented faces, so it does not bound a solid.
    ///
    /// *How to fix*: close the holes and orient the faces consistently (`csgkit check`
    /// lists them).
    #[error(
        "operand {operand} is not closed and consistently oriented: {count} edges are unbalanced, first {}",
        format_edges(first)
    )]
    NotClosed {
        /// The operand.
        operand: usize,
        /// How many edges are unbalanced.
        count: usize,
        /// The first few, as pairs of the operand's vertex indices.
        first: Vec<[u32; 2]>,
    },
    /// The operand is oriented inward (negative volume).
    ///
    /// *How to fix*: reverse every face.
    #[error("operand {operand} is oriented inward (its volume {volume} is negative)")]
    Inverted {
        /// The operand.
        operand: usize,
        /// Its signed volume.
        volume: f64,
    },
    /// Rounding the result to f64 made faces cross or collapse, and snapping their vertices
    /// to the coarsest grid allowed did not repair it; nothing was produced.
    ///
    /// *What to try*: report the input; the exact result exists but has no f64 form within
    /// the certified displacement bound.
    #[error(
        "the result could not be written in f64 without {crossing_pairs} crossing face pairs and {degenerate_faces} degenerate faces"
    )]
    NotCertified {
        /// Crossing face pairs left.
        crossing_pairs: usize,
        /// Degenerate faces left.
        degenerate_faces: usize,
    },
    /// The progress callback asked to stop.
    #[error("cancelled")]
    Cancelled,
    /// A configuration the engine cannot handle yet; nothing was produced.
    #[error("unsupported configuration: {0}")]
    Unsupported(String),
}

fn format_edges(edges: &[[u32; 2]]) -> String {
    let list: Vec<String> = edges.iter().map(|[a, b]| format!("{a}–{b}")).collect();
    list.join(", ")
}

/// How many offending items an error lists.
pub(crate) const ERROR_EXAMPLES: usize = 5;

/// Computes `op` on `operands`: union or intersection of all, the first minus all others, or
/// the points in an odd number of them (see [`Operation`]).
///
/// Every decision is exact (see the [module docs](super)). Empty operands are the empty set.
///
/// # Example
/// Two unit cubes sharing a face make a 2 × 1 × 1 box.
/// ```
/// use csgkit::primitives::cuboid;
/// use csgkit::exact::{BooleanOptions, boolean};
/// use csgkit::Operation;
/// let a = cuboid([0.0; 3], [1.0; 3]);
/// let b = cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]);
/// let result = boolean(Operation::Union, &[&a, &b], &BooleanOptions::default()).unwrap();
/// let report = result.mesh.report();
/// assert!(report.is_valid_solid());
/// assert_eq!(report.measures.volume, 2.0);
/// ```
///
/// # Errors
/// [`BooleanError`] for an operand that is not a solid, or [`BooleanError::Cancelled`].
pub fn boolean(
    op: Operation,
    operands: &[&Mesh],
    options: &BooleanOptions,
) -> Result<Boolean, BooleanError> {
    boolean_expression(&Expression::of(op, operands.len()), operands, options)
}

/// Computes `expression` over `operands` (operand `k` is `Expression::Operand(k)`) in one
/// exact arrangement of all of them, rounded once: a CSG tree without a chain of binary
/// booleans. Otherwise as [`boolean`].
///
/// # Example
/// (A ∪ B) − C for three unit cubes in a row, C overlapping B by half.
/// ```
/// use csgkit::primitives::cuboid;
/// use csgkit::exact::{BooleanOptions, Expression, boolean_expression};
/// use csgkit::Operation;
/// let cubes: Vec<_> = [0.0, 1.0, 1.5].iter().map(|&x| cuboid([x, 0.0, 0.0], [x + 1.0, 1.0, 1.0])).collect();
/// let union = Expression::Apply(Operation::Union, vec![Expression::Operand(0), Expression::Operand(1)]);
/// let tree = Expression::Apply(Operation::Difference, vec![union, Expression::Operand(2)]);
/// let operands: Vec<_> = cubes.iter().collect();
/// let result = boolean_expression(&tree, &operands, &BooleanOptions::default()).unwrap();
/// assert_eq!(result.mesh.report().measures.volume, 1.5);
/// ```
///
/// # Errors
/// As [`boolean`]; [`BooleanError::Unsupported`] if `expression` names an operand that is
/// not given.
pub fn boolean_expression(
    expression: &Expression,
    operands: &[&Mesh],
    options: &BooleanOptions,
) -> Result<Boolean, BooleanError> {
    if operands.is_empty() {
        return Err(BooleanError::NoOperands);
    }
    if expression.operand_count() > operands.len() {
        return Err(BooleanError::Unsupported(format!(
            "the expression names operand {} of {}",
            expression.operand_count() - 1,
            operands.len()
        )));
    }
    let mut stats = BooleanStats::default();
    let mut clock = StageClock::new(options.progress);
    let mut rounded = exact_result(expression, operands, options, None, &mut stats, &mut clock)?;
    if let Some(delta) = options.simplify {
        let removed;
        (rounded, removed) = simplify::simplify(rounded, operands, delta);
        stats.removed_vertices += removed;
        clock.finish(Stage::Simplify, &mut stats)?;
    }

    // Re-refinement of a snapped soup: its union alone, where folds rounding turned inside
    // out (winding number −1) are outside.
    let refine_options = BooleanOptions {
        check_self_intersections: true,
        winding: WindingRule::Positive,
        ..BooleanOptions::default()
    };
    let (mesh, certificate) = certify::certify(rounded, |soup, suspects| {
        let mut inner = BooleanStats::default();
        exact_result(
            &Expression::of(Operation::Union, 1),
            &[soup],
            &refine_options,
            Some(suspects),
            &mut inner,
            &mut StageClock::new(None),
        )
    })?;
    stats.rounded_vertices = certificate.rounded_vertices;
    stats.snapped_vertices = certificate.snapped_vertices;
    stats.max_snap_displacement = certificate.max_snap_displacement;
    stats.certify_rounds = certificate.rounds;
    stats.dissolved_slivers = certificate.dissolved_slivers;
    stats.output_triangles = mesh.face_count();
    clock.finish(Stage::Certify, &mut stats)?;
    let mut mesh = crate::mesh::merge_faces(mesh, options.faces, operands);
    if options.split_non_manifold {
        mesh = crate::mesh::split_non_manifold(&mesh);
    }
    stats.output_faces = mesh.face_count();
    clock.finish(Stage::Faces, &mut stats)?;
    let mesh = crate::mesh::inherit_attributes(mesh, operands);
    clock.finish(Stage::Attributes, &mut stats)?;
    Ok(Boolean { mesh, stats })
}

/// The stages from ingest to assemble: the exact result, rounded to f64 once. With
/// `suspects` (a re-refinement in certification), the self-intersection check looks only at
/// triangles with a vertex at one of those positions (the rest is known to be free of
/// crossings), and no vertex is removed (certification snaps every new vertex).
fn exact_result(
    expression: &Expression,
    operands: &[&Mesh],
    options: &BooleanOptions,
    suspects: Option<&[Point3]>,
    stats: &mut BooleanStats,
    clock: &mut StageClock,
) -> Result<Rounded, BooleanError> {
    let input = ingest::ingest(operands)?;
    stats.input_triangles = input.triangles.len();
    clock.finish(Stage::Ingest, stats)?;

    let (self_pairs, general) = if options.check_self_intersections {
        let pairs = match suspects {
            None => ingest::self_intersecting_pairs(&input),
            Some(at) => ingest::self_intersecting_pairs_at(&input, at),
        };
        let general = !pairs.is_empty() || winding::has_nested_shells(&input);
        clock.finish(Stage::Validate, stats)?;
        (pairs, general)
    } else {
        (Vec::new(), false)
    };
    stats.self_intersecting_pairs = self_pairs.len();
    stats.winding_classification = general;

    let mut pairs = broad::candidate_pairs(&input);
    if !self_pairs.is_empty() {
        pairs.extend(self_pairs);
        pairs.sort_unstable();
    }
    stats.candidate_pairs = pairs.len();
    clock.finish(Stage::Broad, stats)?;

    let contacts = subdivide::intersect_pairs(&input, &pairs);
    stats.intersecting_pairs = contacts.intersecting_pairs;
    clock.finish(Stage::Intersect, stats)?;

    let arrangement = subdivide::split(&input, contacts)?;
    stats.split_triangles = arrangement.split_triangles;
    clock.finish(Stage::Split, stats)?;

    // Local classification labels every patch that touches a classified one; where a whole
    // operand's surface lies on others' (a cube among touching cubes on every side), it
    // cannot start, and winding numbers, which classify any patch, decide instead.
    let labels = if general {
        None
    } else {
        match classify::classify(&input, &arrangement) {
            Ok(labels) => Some(labels),
            Err(BooleanError::Unsupported(_)) => None,
            Err(error) => return Err(error),
        }
    };
    let kept = match labels {
        Some(labels) => {
            stats.patches = labels.patch_count();
            clock.finish(Stage::Classify, stats)?;
            select::select(expression, &input, &arrangement, &labels)
        }
        None => {
            let (patch_of, patch_count) = classify::patch_partition(&input, &arrangement);
            stats.patches = patch_count;
            stats.winding_classification = true;
            let kept = winding::select(
                expression,
                options.winding,
                &input,
                &arrangement,
                &patch_of,
                patch_count,
            )?;
            clock.finish(Stage::Classify, stats)?;
            kept
        }
    };
    let faces = reconstruct::reconstruct(
        &input,
        &arrangement,
        &kept,
        operands,
        reconstruct::Options {
            merge_coplanar: options.merge_coplanar,
            remove_vertices: suspects.is_none(),
        },
    );
    stats.removed_vertices = faces.removed_vertices;
    clock.finish(Stage::Reconstruct, stats)?;
    let rounded = assemble::assemble(&input, &arrangement, faces);
    clock.finish(Stage::Assemble, stats)?;
    Ok(rounded)
}

/// Times consecutive stages and reports each to the progress callback.
struct StageClock<'a> {
    start: Instant,
    progress: Option<ProgressFn<'a>>,
}

impl<'a> StageClock<'a> {
    fn new(progress: Option<ProgressFn<'a>>) -> Self {
        Self {
            start: Instant::now(),
            progress,
        }
    }

    /// Records the time since the last stage ended; `Cancelled` if the callback says stop.
    fn finish(&mut self, stage: Stage, stats: &mut BooleanStats) -> Result<(), BooleanError> {
        let now = Instant::now();
        stats
            .stage_seconds
            .push((stage, (now - self.start).as_secs_f64()));
        self.start = now;
        match self.progress {
            Some(report) if !report(stage, 1, 1) => Err(BooleanError::Cancelled),
            _ => Ok(()),
        }
    }
}
