//! The public entry of the exact engine: [`boolean`] runs the stages of the pipeline in
//! order and times each one.

use crate::Operation;
use crate::kernel::{Point3, Precision};
use crate::mesh::{FaceMode, Mesh};
use crate::par;
use crate::progress::{Cancelled, Progress, Stage, StageClock};

use super::assemble::Rounded;
use super::certify::CertifyError;
use super::expression::Expression;
use super::ingest::{InvalidOperand, TriangleTrees};
use super::subdivide::StageError;
use super::winding::{self, WindingRule};
use super::{assemble, broad, certify, classify, ingest, reconstruct, select, simplify, subdivide};

/// How [`boolean`] runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BooleanOptions {
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
    /// The numbers the result's coordinates are written in: f64, or f32 for a file that
    /// stores f32 (binary STL, glTF), where rounding an f64 result afterwards can make its
    /// faces cross. In f32 the operands are read as f32 first (as they would be from such
    /// files: every coordinate must lie in the f32 range) unless that makes one invalid (a
    /// folded polygon, a part turned inside out), and the result is rounded to f32 and
    /// certified there.
    pub precision: Precision,
}

impl Default for BooleanOptions {
    fn default() -> Self {
        Self {
            check_self_intersections: true,
            winding: WindingRule::NonZero,
            split_non_manifold: false,
            faces: FaceMode::Triangles,
            merge_coplanar: false,
            simplify: None,
            precision: Precision::F64,
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
    /// Triangle pairs of different operands whose boxes overlap and neither of whose planes
    /// has the other triangle strictly on one side.
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
    /// Output vertices that are intersection points rounded to the result's precision (in
    /// f32 the operands are read as f32 first, so their vertices stay, unless that reading
    /// made an operand invalid).
    pub rounded_vertices: usize,
    /// Output vertices moved to a coarser grid because rounding made faces cross or
    /// collapse (0 almost always; see the certify stage).
    pub snapped_vertices: usize,
    /// Slivers thinner than the f64 grid that certification removed (a short side collapsed
    /// or a needle flipped away; see the certify stage).
    pub dissolved_slivers: usize,
    /// Pairs of opposite faces over the same three vertices that certification removed (a
    /// sliver between two surfaces that rounded flat into a two-sided sheet).
    pub removed_sheets: usize,
    /// Closed shells thinner on average than a few ulps that certification removed whole (a
    /// slab between two surfaces an ulp apart, such as `(A − B) ∩ B` through a file).
    pub removed_shells: usize,
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
    /// An operand is not a closed, outward solid of finite coordinates.
    #[error(transparent)]
    InvalidOperand(#[from] InvalidOperand),
    /// Rounding the result to its precision made faces cross or collapse, and snapping their
    /// vertices to the coarsest grid allowed did not repair it; nothing was produced.
    ///
    /// *What to try*: report the input; the exact result exists but has no form in that
    /// precision within the certified displacement bound.
    #[error(
        "the result could not be written in {precision} without {crossing_pairs} crossing face pairs and {degenerate_faces} degenerate faces"
    )]
    NotCertified {
        /// The precision asked for ([`BooleanOptions::precision`]).
        precision: Precision,
        /// Crossing face pairs left.
        crossing_pairs: usize,
        /// Degenerate faces left.
        degenerate_faces: usize,
    },
    /// The run was cancelled through its [`Progress`].
    #[error(transparent)]
    Cancelled(#[from] Cancelled),
    /// A configuration the engine cannot handle yet; nothing was produced.
    #[error("unsupported configuration: {0}")]
    Unsupported(String),
}

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
/// [`BooleanError`] for an operand that is not a solid ([`BooleanError::InvalidOperand`]), or
/// a result without a certified f64 form.
pub fn boolean(
    op: Operation,
    operands: &[&Mesh],
    options: &BooleanOptions,
) -> Result<Boolean, BooleanError> {
    let expression = Expression::of(op, operands.len());
    boolean_expression(&expression, operands, options, &Progress::default())
}

/// Computes `expression` over `operands` (operand `k` is `Expression::Operand(k)`) in one
/// exact arrangement of all of them, rounded once: a CSG tree without a chain of binary
/// booleans, reporting its stages to `progress` (which can cancel it, from inside the long
/// stages). Otherwise as [`boolean`].
///
/// # Example
/// (A ∪ B) − C for three unit cubes in a row, C overlapping B by half.
/// ```
/// use csgkit::primitives::cuboid;
/// use csgkit::exact::{BooleanOptions, Expression, boolean_expression};
/// use csgkit::{Operation, Progress};
/// let cubes: Vec<_> = [0.0, 1.0, 1.5].iter().map(|&x| cuboid([x, 0.0, 0.0], [x + 1.0, 1.0, 1.0])).collect();
/// let union = Expression::Apply(Operation::Union, vec![Expression::Operand(0), Expression::Operand(1)]);
/// let tree = Expression::Apply(Operation::Difference, vec![union, Expression::Operand(2)]);
/// let operands: Vec<_> = cubes.iter().collect();
/// let options = BooleanOptions::default();
/// let result = boolean_expression(&tree, &operands, &options, &Progress::default()).unwrap();
/// assert_eq!(result.mesh.report().measures.volume, 1.5);
/// ```
///
/// # Errors
/// As [`boolean`]; [`BooleanError::Unsupported`] if `expression` names an operand that is
/// not given, [`BooleanError::Cancelled`] once `progress` is cancelled.
pub fn boolean_expression(
    expression: &Expression,
    operands: &[&Mesh],
    options: &BooleanOptions,
    progress: &Progress,
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
    let faces = operands.iter().map(|mesh| mesh.face_count()).sum();
    let mut rounded = match options.precision {
        Precision::F32 => in_f32(operands)?,
        Precision::F64 => Vec::new(),
    };
    loop {
        let read: Vec<&Mesh> = (operands.iter().enumerate())
            .map(|(k, &mesh)| rounded.get(k).and_then(Option::as_ref).unwrap_or(mesh))
            .collect();
        match par::on_pool_or_inline(faces, || {
            run_expression(expression, &read, options, progress)
        }) {
            // Reading the operand as f32 broke it: a polygon face folded or collapsed, or a
            // thin or far part turned inside out. The operand as given is valid, so it keeps
            // its f64 coordinates, and its vertices round with the result, where certify
            // checks them (at most one more run per operand).
            Err(BooleanError::InvalidOperand(error))
                if rounded.get(error.operand()).is_some_and(Option::is_some) =>
            {
                rounded[error.operand()] = None;
            }
            result => return result,
        }
    }
}

/// Each operand with a coordinate that is not an f32 number, read as f32 (each coordinate the
/// nearest), as from the file that will hold the result; `None` for the others. Every input
/// vertex is then a point of the f32 grid, so only intersection points round and certify
/// checks only the faces around them, and an operand the rounding folds is resolved as any
/// self-intersecting operand is (with the self-intersection check on); one the rounding makes
/// invalid is read as given after all (see [`boolean_expression`]). Refuses a coordinate
/// that rounds to an infinite f32.
fn in_f32(operands: &[&Mesh]) -> Result<Vec<Option<Mesh>>, BooleanError> {
    let mut rounded = Vec::with_capacity(operands.len());
    for (k, mesh) in operands.iter().enumerate() {
        let outside = (mesh.positions().iter().enumerate())
            .find(|(_, p)| p.iter().any(|&x| (x as f32).is_infinite()));
        if let Some((v, p)) = outside {
            return Err(BooleanError::Unsupported(format!(
                "operand {k}, vertex {v} ({p:?}) lies beyond the f32 range, so the result cannot be written in f32"
            )));
        }
        let held = (mesh.positions().iter().flatten()).all(|&x| Precision::F32.holds(x));
        rounded.push((!held).then(|| {
            let mut parts = (*mesh).clone().into_parts();
            for p in &mut parts.positions {
                *p = p.map(|x| f64::from(x as f32));
            }
            Mesh::from_parts(parts).expect("rounding changes positions only")
        }));
    }
    Ok(rounded)
}

/// [`boolean_expression`] on a worker thread of the pool.
fn run_expression(
    expression: &Expression,
    operands: &[&Mesh],
    options: &BooleanOptions,
    progress: &Progress,
) -> Result<Boolean, BooleanError> {
    let mut stats = BooleanStats::default();
    let mut clock = StageClock::new(progress);
    let rounded = rounded_result(
        expression, operands, options, &mut stats, &mut clock, progress,
    )?;

    // Re-refinement of a snapped soup: its union alone, where folds rounding turned inside
    // out (winding number −1) are outside. Its stages are not the caller's: it polls the
    // caller's cancellation but reports nothing.
    let refine_options = BooleanOptions {
        check_self_intersections: true,
        winding: WindingRule::Positive,
        precision: options.precision,
        ..BooleanOptions::default()
    };
    let silent = progress.silent();
    let certified = |rounded, merge_near| {
        certify::certify(
            rounded,
            options.precision,
            merge_near,
            progress,
            |soup, suspects| {
                exact_result(
                    &Expression::of(Operation::Union, 1),
                    &[soup],
                    &refine_options,
                    Some(suspects),
                    &mut BooleanStats::default(),
                    &mut StageClock::new(&silent),
                    &silent,
                )
                .ok()
            },
        )
    };
    // A second attempt, from the exact result again, with near vertices merged before any
    // snapping: it clears strips of slivers that snapping makes worse, where the first clears
    // others better (it is the first only because it is the one every result was certified
    // by so far). Recomputing costs a boolean, paid only by results the first cannot certify.
    let certificate = match certified(rounded, false) {
        Err(CertifyError::NotCertified { .. }) => {
            let again = rounded_result(
                expression,
                operands,
                options,
                &mut BooleanStats::default(),
                &mut StageClock::new(&silent),
                &silent,
            )?;
            certified(again, true)
        }
        first => first,
    };
    let (mesh, certificate) = certificate.map_err(|error| match error {
        CertifyError::NotCertified {
            crossing_pairs,
            degenerate_faces,
        } => BooleanError::NotCertified {
            precision: options.precision,
            crossing_pairs,
            degenerate_faces,
        },
        CertifyError::Cancelled(cancelled) => cancelled.into(),
    })?;
    stats.rounded_vertices = certificate.rounded_vertices;
    stats.snapped_vertices = certificate.snapped_vertices;
    stats.max_snap_displacement = certificate.max_snap_displacement;
    stats.certify_rounds = certificate.rounds;
    stats.dissolved_slivers = certificate.dissolved_slivers;
    stats.removed_sheets = certificate.removed_sheets;
    stats.removed_shells = certificate.removed_shells;
    stats.output_triangles = mesh.face_count();
    clock.record(Stage::Certify);
    let mut mesh = crate::mesh::merge_faces(mesh, options.faces, operands);
    if options.split_non_manifold {
        mesh = crate::mesh::split_non_manifold(&mesh);
    }
    stats.output_faces = mesh.face_count();
    clock.end(Stage::Faces)?;
    let mesh = crate::mesh::inherit_attributes(mesh, operands);
    clock.end(Stage::Attributes)?;
    stats.stage_seconds = clock.into_seconds();
    Ok(Boolean { mesh, stats })
}

/// The exact result rounded to the options' precision, and simplified when they ask: what
/// certification starts from.
fn rounded_result(
    expression: &Expression,
    operands: &[&Mesh],
    options: &BooleanOptions,
    stats: &mut BooleanStats,
    clock: &mut StageClock,
    progress: &Progress,
) -> Result<Rounded, BooleanError> {
    let mut rounded = exact_result(expression, operands, options, None, stats, clock, progress)?;
    if let Some(delta) = options.simplify {
        let removed;
        (rounded, removed) = simplify::simplify(rounded, operands, delta);
        stats.removed_vertices += removed;
        clock.end(Stage::Simplify)?;
    }
    Ok(rounded)
}

impl From<StageError> for BooleanError {
    fn from(error: StageError) -> Self {
        match error {
            StageError::Unsupported(reason) => BooleanError::Unsupported(reason),
            StageError::Cancelled(cancelled) => BooleanError::Cancelled(cancelled),
        }
    }
}

/// The stages from ingest to assemble: the exact result, rounded once to the options'
/// precision. With
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
    progress: &Progress,
) -> Result<Rounded, BooleanError> {
    let input = ingest::ingest(operands)?;
    stats.input_triangles = input.triangles.len();
    clock.end(Stage::Ingest)?;

    // The trees the self-intersection check keeps (both of two operands, and where the
    // winding classification will cast a ray per patch) serve the broad phase and
    // classification's rays; the others are built before the rays that need them.
    let (self_pairs, general, trees) = if options.check_self_intersections {
        let (pairs, trees) = match suspects {
            None => ingest::self_intersecting_pairs(&input, progress)?,
            Some(at) => (
                ingest::self_intersecting_pairs_at(&input, at),
                TriangleTrees::on_demand(&input),
            ),
        };
        let general =
            input.has_repeats || !pairs.is_empty() || winding::has_nested_shells(&input, &trees);
        clock.record(Stage::Validate);
        (pairs, general, trees)
    } else {
        (
            Vec::new(),
            input.has_repeats,
            TriangleTrees::on_demand(&input),
        )
    };
    stats.self_intersecting_pairs = self_pairs.len();
    stats.winding_classification = general;

    let mut pairs = broad::candidate_pairs(&input, &trees);
    if !self_pairs.is_empty() {
        pairs.extend(self_pairs);
        pairs.sort_unstable();
    }
    stats.candidate_pairs = pairs.len();
    clock.end(Stage::Broad)?;

    let contacts = subdivide::intersect_pairs(&input, &pairs, progress)?;
    stats.intersecting_pairs = contacts.intersecting_pairs;
    clock.record(Stage::Intersect);

    let arrangement = subdivide::split(&input, contacts, progress)?;
    stats.split_triangles = arrangement.split_triangles;
    clock.record(Stage::Split);

    // Local classification labels every patch that touches a classified one; where a whole
    // operand's surface lies on others' (a cube among touching cubes on every side), it
    // cannot start, and winding numbers, which classify any patch, decide instead.
    let labels = if general {
        None
    } else {
        match classify::classify(&input, &trees, &arrangement, progress) {
            Ok(labels) => Some(labels),
            Err(StageError::Unsupported(_)) => None,
            Err(error) => return Err(error.into()),
        }
    };
    let kept = match labels {
        Some(labels) => {
            stats.patches = labels.patch_count();
            select::select(expression, &input, &arrangement, &labels)
        }
        None => {
            let (patch_of, first_sub) = classify::patch_partition(&input, &arrangement);
            stats.patches = first_sub.len();
            stats.winding_classification = true;
            winding::select(
                expression,
                options.winding,
                &input,
                &trees,
                &arrangement,
                &patch_of,
                &first_sub,
                progress,
            )?
        }
    };
    clock.record(Stage::Classify);
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
    clock.end(Stage::Reconstruct)?;
    let rounded = assemble::assemble(&input, &arrangement, faces, options.precision);
    clock.end(Stage::Assemble)?;
    Ok(rounded)
}
