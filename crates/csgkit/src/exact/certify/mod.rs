//! The **certify** stage: the result as f64 numbers (or f32, its [`Precision`]) is a valid
//! solid, so it is a valid operand of the next boolean.
//!
//! # Contract
//! In: the [`Rounded`] mesh of the assemble stage (exact except at the intersection points it
//! rounded) and a way to re-run the exact arrangement on a triangle soup. Out: a mesh, as f64
//! numbers,
//! - in which no two faces share a point other than their common edges and vertices (the
//!   semantics of [`self_intersections`](super::self_intersections));
//! - with no exactly degenerate face and no two vertices at one position;
//! - closed and consistently oriented.
//!
//! Every vertex ends near where the exact result has it: rounding moves it by at most 2.5
//! ulps of its largest coordinate per coordinate, re-rounding (and pushing a corner through
//! a thin layer) by at most [`REROUND_MAX_STEPS`] ulps, and snapping (at most half a grid
//! step per level, the steps doubling up to `2^MAX_SNAP_LEVEL` ulps of the largest coordinate
//! magnitude `M`) by at most `2^MAX_SNAP_LEVEL` ulps of `M` in all: every coordinate stays
//! within `2^-27 · M` of the exact result. Removing a sliver moves the
//! surface by less than the tolerance it was found with, at most `2^MAX_SNAP_LEVEL` ulps of
//! `M`; a removed thin shell bounds less than its area times `2^THIN_SHELL_LEVEL` ulps of `M`,
//! and a thin layer turned inside out is thinner than the push that turned it.
//! Ulps are those of the result's [`Precision`]: in f32 (a result for binary STL or glTF,
//! whose operands the driver reads as f32 first where that keeps them valid) the coarsest
//! grid is `2^MAX_SNAP_LEVEL_F32` f32 ulps, so every coordinate stays within `2^-14 · M` of
//! the exact result of those operands.
//! If that is not enough, the stage fails with [`CertifyError::NotCertified`] rather than
//! return an invalid mesh.
//!
//! # Algorithm
//! Iterative snap rounding, after Lazard & Valque, "Iterative snap rounding of triangle soups"
//! (2025; CGAL 6.1's `autorefine_triangle_soup` with `apply_iterative_snap_rounding`), with
//! csgkit's own arrangement as the exact re-refinement:
//! 1. **Find problems** (`find_problems`): only faces with a moved vertex can differ from the
//!    exact result, which has no crossing, so the check looks at those faces and at every face
//!    whose box overlaps one of theirs: a [`Bvh`] over the moved faces, queried by every face,
//!    then the exact pair test of the self-intersection check on that neighbourhood, the
//!    exact degeneracy test, bit-identical positions, and pairs of opposite faces over the
//!    same three vertices (a sliver between two surfaces that rounded flat into a two-sided
//!    sheet, which the pair test does not see: it ignores faces with the same corners).
//! 2. **Done** if there is none, once the closed shells through a moved vertex that are
//!    thinner on average than a few ulps are removed whole though valid
//!    (`without_thin_shells`: a slab rounding left uncrossed, or turned inside out, which
//!    would give the result a negative volume the next boolean refuses). Otherwise,
//!    coincident vertices are merged and sheets removed (both
//!    faces: the sheet bounds no volume, and every edge stays balanced) before anything
//!    else is tried, then closed shells with a problem that are thinner on average than a few
//!    ulps (`thin_shells`), whole.
//! 3. **Re-round** (`reround`): move a vertex of a problem face to an f64 point at most a few
//!    ulps away where its faces have no problem with the faces around them (rounded points
//!    first, then any vertex); most folds are a sliver corner rounded across the opposite
//!    edge. Merge vertices that rounded to one position. Repeat from 1 while this helps.
//! 4. **Dissolve slivers** ([`slivers`]): a face thinner than the f64 grid folds whatever its
//!    corners' rounding; around the problem vertices, collapse sides and flip needles lower
//!    than a tolerance (from a few ulps up to the coarsest snap grid, [`SLIVER_LEVELS`]),
//!    each change checked exactly. Repeat from 1 while this helps.
//!    Then, in the driver's second attempt only (from the exact result again, after the
//!    first failed), **merge near vertices** (`merge_near`): a problem vertex within
//!    [`NEAR_LEVEL`] ulps of another vertex near it goes onto it, clusters at once, where
//!    single collapses each fold a neighbour (a strip of slivers between a new intersection
//!    point and the rounded vertex of an earlier boolean beside it), kept where it leaves
//!    fewer problems. Repeat from 1 while this helps. Not in the first attempt: on some
//!    results snapping certifies, merging pinches two surfaces an ulp apart into a knot that
//!    nothing after clears. Once an attempt, it is tried before dissolving goes on where a
//!    round of dissolving left as many problems as before (it takes every sliver around a
//!    problem vertex, often not the problem's): on a CAD model's fans through binary STL,
//!    38 such rounds of a whole check each came before the near-merge that cleared them.
//!    Then, where none of those helps, closed **pockets** with a problem, thinner on
//!    average than a few ulps (`thin_pockets`: faces joined across edges used once each
//!    way, closed by themselves, such as a pocket hanging on its shell by edges of four
//!    uses): the thin tetrahedra that the union of a solid's two pieces keeps between two
//!    triangulations of their cut. They go whole, as thin shells do.
//! 5. **Push through thin layers** ([`layers`]): two crossing faces that face opposite ways,
//!    with corners of one within a few ulps behind the other's plane, bound a layer of
//!    material thinner than the grid (a chain such as `(A ∪ B) − B` through a file, where a
//!    corner of `A ∪ B` on the curve rounded in front of B's plane): attached to the solid
//!    along the curve, it is no closed shell, and re-refining it as it is computes it again,
//!    with new points that fold again. Those corners move in front of the other face's plane
//!    (at most [`REROUND_MAX_STEPS`] ulps): the layer turns inside out, and an exact
//!    re-refinement (step 7) drops it. Kept where it leaves fewer problems; otherwise rolled
//!    back and not tried again in this certification, whose rounds then go on as without it.
//!    Repeat from 1.
//! 6. **Snap** the vertices near crossing and degenerate faces to a coarser grid, the multiples
//!    of `2^level` ulps of the largest coordinate magnitude (exact: a power of two), `level`
//!    growing by [`SNAP_LEVEL_STEP`] after [`ROUNDS_PER_LEVEL`] rounds (the first rounds
//!    re-refine without snapping). The whole neighbourhood moves, so no face tilts between
//!    a snapped and an unsnapped corner.
//! 7. **Re-refine**: the snapped soup is one operand of a union under the positive winding
//!    rule, computed exactly by the same pipeline (its crossing faces are intersected with
//!    each other, folds that turned inside out are outside, coincident vertices are welded,
//!    collapsed and degenerate faces dropped); its new intersection points are snapped to
//!    the same grid (Lazard & Valque), its result must be closed, and the loop goes back to 1
//!    with those points as the moved vertices. A re-refinement that fails moves to the next
//!    grid, and so does one that leaves far more crossing pairs than it started from
//!    ([`RUNAWAY_FACTOR`]): the rounds go back to the mesh with the fewest crossing pairs a
//!    re-refinement started from (without a coarser grid, re-refining folds can cut them into
//!    ever finer folds, each round slower than the last).
//!
//! Where rounding folds nothing (nearly always), the stage is step 1 alone, and the thin-shell
//! test: a union-find over the vertices and a sum over the faces, a few per cent of the
//! boolean (20 ms of 490 on sphere_sphere 1M).
//!
//! # Complexity
//! Step 1: a tree over the moved faces (few: those around intersection curves) and one
//! query per face, then the exact test on the neighbourhood. Step 3 tries at most a few
//! hundred positions per problem vertex against its neighbourhood. Step 4 builds a tree over
//! all faces once per call and tests each change against the faces around it. Steps 5–7 run
//! only when re-rounding and sliver removal cannot help, and cost one exact boolean of the
//! result with itself per round.

use crate::par::*;
use rustc_hash::FxHashMap;

use crate::index::{Aabb, Bvh, Occupancy};
use crate::kernel::{Point3, Precision};
use crate::mesh::union_find::UnionFind;
use crate::mesh::vector::{cross, dot, norm, sub};
use crate::mesh::{
    EdgeTable, Mesh, MeshParts, apply_welding, opposite_triangle_pairs, weld_positions,
};
use smallvec::SmallVec;

use crate::progress::{Cancelled, Counter, Progress, Stage};

use super::assemble::Rounded;
use super::intersect::{IndexedTriangle, Triangle};
use super::self_intersect::pair_intersects;

mod layers;
mod slivers;

/// Snap levels grow by this many doublings of the grid each round.
pub(crate) const SNAP_LEVEL_STEP: i32 = 4;

/// One pass of re-rounding: which vertices of problem faces may move, and how far.
#[derive(Clone, Copy, Debug)]
struct Reround {
    /// Input vertices too, not only rounded intersection points.
    any_vertex: bool,
    /// f64 steps per coordinate.
    steps: u32,
}

/// The passes of re-rounding, tried in order until one makes progress: rounded points first
/// (the exact result's own vertices stay where they are whenever that suffices), then any
/// vertex of a problem face, then farther. The farthest move is [`REROUND_MAX_STEPS`] ulps
/// per coordinate.
const REROUND_PASSES: [Reround; 3] = [
    Reround {
        any_vertex: false,
        steps: 2,
    },
    Reround {
        any_vertex: true,
        steps: 2,
    },
    Reround {
        any_vertex: true,
        steps: REROUND_MAX_STEPS,
    },
];

/// Faces re-rounding may look at in one certification, over all candidate positions (about a
/// second): what it has not cleared by then is left to snapping, rather than searched on.
const REROUND_BUDGET: u64 = 5_000_000;

/// The farthest re-rounding, in f64 steps per coordinate.
pub(crate) const REROUND_MAX_STEPS: u32 = 4;

/// Checks of the rounded mesh one certification may make (each followed by a repair), and
/// exact re-refinements among them: bounds on its cost, after which it fails rather than
/// search on.
const MAX_ITERATIONS: usize = 64;
const MAX_REFINEMENTS: usize = 8;

/// A re-refinement that leaves more than `RUNAWAY_FACTOR` times the crossing pairs it started
/// from, plus `RUNAWAY_SLACK`, is dropped: the rounds go on from the mesh with the fewest
/// crossing pairs that a re-refinement of this attempt started from, and the next one snaps
/// it to a coarser grid. New intersection points may fold a few faces on the way to a
/// certified mesh (8 crossing pairs became 12 in a result that went on to certify), but
/// folds cut into more folds run away: on a solid split in two and joined back through
/// files, 234 crossing pairs became 403 after four re-refinements, then 7,735 on a coarser
/// grid, whose re-refinement alone took 47 s. Back to the fewest, not to the last: there, a
/// re-refinement had taken 75 crossing pairs to 134 (121 after dissolving slivers) before the
/// next ran away; snapped, the mesh with 121 ran away on every grid at 2.5 to 4.5 s a
/// re-refinement, where those from the one with 75 took 0.06 to 0.33 s, so the attempt,
/// whose re-refinements are bounded, gave way to the next in 2.4 s instead of 17 (the next
/// certified it).
const RUNAWAY_FACTOR: usize = 2;
const RUNAWAY_SLACK: usize = 16;

/// Rounds of snapping and re-refinement on one grid before a coarser one is tried.
pub(crate) const ROUNDS_PER_LEVEL: usize = 3;

/// The coarsest snap grid in f64: multiples of `2^MAX_SNAP_LEVEL` ulps of the largest
/// coordinate magnitude `M` (with a 53-bit significand, steps of `2^(MAX_SNAP_LEVEL − 52)` of
/// it, `2^-28 · M`).
pub(crate) const MAX_SNAP_LEVEL: i32 = 24;

/// The coarsest snap grid in f32, in f32 ulps of `M`: `2^(MAX_SNAP_LEVEL_F32 − 23) · M`,
/// `2^-15 · M` (3 µm on a part of 100 mm, where an f32 ulp is 8 nm), where the f64 levels
/// would reach `2 · M`.
const MAX_SNAP_LEVEL_F32: i32 = 8;

/// The tolerances of sliver removal in f64, in ulps of the largest coordinate magnitude (as
/// `log2`), tried in order until one removes something: sides and heights far below an ulp
/// first, up to the coarsest snap grid.
const SLIVER_LEVELS: [i32; 4] = [2, 10, 18, MAX_SNAP_LEVEL];

/// [`SLIVER_LEVELS`] in f32, up to its coarsest snap grid.
const SLIVER_LEVELS_F32: [i32; 4] = [2, 4, 6, MAX_SNAP_LEVEL_F32];

/// The mean thickness below which a shell with a problem is removed whole, in ulps of the
/// largest coordinate magnitude (as `log2`): the first tolerance of sliver removal, a few
/// ulps, above the error of the f64 volume it is measured by.
const THIN_SHELL_LEVEL: i32 = SLIVER_LEVELS[0];

/// The coarsest snap grid and the sliver tolerances of `precision`, in its ulps of `M`.
fn levels(precision: Precision) -> (i32, [i32; 4]) {
    match precision {
        Precision::F64 => (MAX_SNAP_LEVEL, SLIVER_LEVELS),
        Precision::F32 => (MAX_SNAP_LEVEL_F32, SLIVER_LEVELS_F32),
    }
}

/// What certification did, for the statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Certificate {
    /// Vertices rounding moved in the output (intersection points not representable in its
    /// precision).
    pub rounded_vertices: usize,
    /// Vertex moves to a coarser grid that removing crossings and degenerate faces took (a
    /// vertex moved in two rounds counts twice).
    pub snapped_vertices: usize,
    /// The largest distance a snapped vertex moved, divided by the diagonal of the result's
    /// bounding box (0 when nothing was snapped).
    pub max_snap_displacement: f64,
    /// Rounds of snapping and re-refinement (0 when rounding folded nothing).
    pub rounds: usize,
    /// Slivers removed by collapsing a short side or flipping a needle.
    pub dissolved_slivers: usize,
    /// Pairs of opposite faces over the same vertices (slivers that rounded flat) removed.
    pub removed_sheets: usize,
    /// Closed shells, and pockets hanging on a shell by its edges, thinner than the f64 grid,
    /// removed whole.
    pub removed_shells: usize,
}

/// What is wrong with a rounded mesh.
#[derive(Debug, Default)]
struct Problems {
    /// Face pairs that cross.
    pairs: Vec<(u32, u32)>,
    /// Faces whose corners are exactly collinear (distinct positions).
    degenerate_faces: usize,
    /// The vertices to snap: those of crossing and degenerate faces, sorted, without repeats.
    to_snap: Vec<u32>,
    /// Vertices at the position of another vertex (distinct ids, one position).
    coincident: Vec<u32>,
    /// Pairs of faces over the same three vertices in opposite orientations: a sliver
    /// between two surfaces that rounded flat. The pair test ignores faces with the same
    /// corners, but the sheet doubles the uses of its edges and has no inside for the next
    /// boolean to sample.
    sheets: Vec<[u32; 2]>,
}

impl Problems {
    fn is_empty(&self) -> bool {
        self.pairs.is_empty()
            && self.degenerate_faces == 0
            && self.coincident.is_empty()
            && self.sheets.is_empty()
    }

    /// Crossing pairs, degenerate faces and sheets: what a repair that keeps only where it
    /// leaves fewer problems compares.
    fn size(&self) -> usize {
        self.pairs.len() + self.degenerate_faces + self.sheets.len()
    }
}

/// Why certification produced nothing.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum CertifyError {
    /// The coarsest snap grid left problems.
    NotCertified {
        /// Crossing face pairs left.
        crossing_pairs: usize,
        /// Degenerate faces left.
        degenerate_faces: usize,
    },
    /// The caller cancelled the run.
    Cancelled(Cancelled),
}

impl From<Cancelled> for CertifyError {
    fn from(cancelled: Cancelled) -> Self {
        CertifyError::Cancelled(cancelled)
    }
}

impl CertifyError {
    fn not_certified(problems: &Problems) -> Self {
        CertifyError::NotCertified {
            crossing_pairs: problems.pairs.len(),
            degenerate_faces: problems.degenerate_faces,
        }
    }
}

/// Certifies `rounded` (see the module docs), reporting its rounds to `progress`.
/// `re_refine(soup, suspects)` computes the exact union of a soup under the positive winding
/// rule and rounds it, or `None` when the engine refuses the soup (or the run was cancelled,
/// which it sees in the same flag); `suspects` are the positions of the soup's vertices that
/// moved since it was last free of crossings, so only faces at those can cross.
///
/// # Errors
/// [`CertifyError::NotCertified`] when the coarsest grid leaves a problem (a refused
/// re-refinement is retried on a coarser grid); [`CertifyError::Cancelled`].
pub(crate) fn certify(
    rounded: Rounded,
    precision: Precision,
    merge_near: bool,
    progress: &Progress,
    re_refine: impl FnMut(&Mesh, &[Point3]) -> Option<Rounded>,
) -> Result<(Mesh, Certificate), CertifyError> {
    // Units: rounds, of at most MAX_ITERATIONS; almost always one.
    let counter = progress.counter(Stage::Certify, MAX_ITERATIONS);
    let certified = certify_rounds(rounded, precision, merge_near, &counter, re_refine)?;
    counter.finish()?;
    Ok(certified)
}

/// `mesh` without the vertices no face uses, numbered in their order. The rounds remove
/// faces (sheets, thin shells, collapsed slivers) and merge vertices but keep every vertex,
/// since their checks look only at faces; a written vertex no face uses is noise to the next
/// tool, and `csgkit check` counts it.
fn without_unused_vertices(mesh: Mesh) -> Mesh {
    let mut new_id = vec![u32::MAX; mesh.vertex_count()];
    for &v in mesh.corners() {
        new_id[v as usize] = 0;
    }
    if !new_id.contains(&u32::MAX) {
        return mesh;
    }
    let mut parts = mesh.into_parts();
    let mut positions = Vec::with_capacity(parts.positions.len());
    for (id, position) in new_id.iter_mut().zip(&parts.positions) {
        if *id == 0 {
            *id = positions.len() as u32;
            positions.push(*position);
        }
    }
    parts.positions = positions;
    for v in &mut parts.corners {
        *v = new_id[*v as usize];
    }
    Mesh::from_parts(parts).expect("every corner's vertex is kept")
}

/// The rounds of [`certify`]: steps 1–7 until no problem is left.
fn certify_rounds(
    rounded: Rounded,
    precision: Precision,
    merge_near: bool,
    counter: &Counter,
    mut re_refine: impl FnMut(&Mesh, &[Point3]) -> Option<Rounded>,
) -> Result<(Mesh, Certificate), CertifyError> {
    let mut certificate = Certificate {
        rounded_vertices: rounded.rounded,
        ..Certificate::default()
    };
    let Rounded {
        mut mesh,
        mut moved,
        ..
    } = rounded;
    let (max_snap_level, sliver_levels) = levels(precision);
    let mut level = 0;
    let mut rounds_at_level = 0;
    let work = std::cell::Cell::new(0u64);
    let mut pushing_refused = false;
    // The problems' size before the last round that dissolved slivers, and whether the
    // near-merge was tried early in this attempt (see below).
    let mut dissolved_from: Option<usize> = None;
    let mut merged_early = false;
    // The problems of `mesh` when the last round already found them (a re-refinement is
    // checked before it is kept).
    let mut known: Option<Problems> = None;
    // Of the meshes a re-refinement started from, the one with the fewest crossing pairs
    // (their count, the mesh, its moved vertices): where a re-refinement runs away, the
    // rounds go on from it.
    let mut fewest: Option<(usize, Mesh, Vec<bool>)> = None;
    for round in 0..MAX_ITERATIONS {
        if round > 0 {
            counter.advance(1);
        }
        if counter.is_cancelled() {
            return Err(Cancelled.into());
        }
        let problems = (known.take()).unwrap_or_else(|| find_problems(&mesh, &moved));
        if problems.is_empty() {
            let shells_before = certificate.removed_shells;
            let mesh = without_thin_shells(mesh, &moved, precision, &mut certificate);
            // Every round after the first follows a repair, which may leave vertices unused;
            // a result the first check finds free of problems is the exact result's rounding,
            // all of whose vertices are used, and is not scanned.
            if round == 0 && certificate.removed_shells == shells_before {
                return Ok((mesh, certificate));
            }
            return Ok((without_unused_vertices(mesh), certificate));
        }
        if certificate.rounds >= MAX_REFINEMENTS {
            return Err(CertifyError::not_certified(&problems));
        }
        let dissolving_stalls =
            (dissolved_from.take()).is_some_and(|before| problems.size() >= before);
        if !problems.coincident.is_empty() {
            // Two exact points rounded to one f64 point: they are one vertex of the f64
            // mesh; the faces between them collapse.
            (mesh, moved) = merge_coincident(mesh, &moved);
            continue;
        }
        if !problems.sheets.is_empty() {
            // The sheet bounds no volume: both faces go, and every edge stays balanced.
            certificate.removed_sheets += problems.sheets.len();
            mesh = remove_faces(mesh, problems.sheets.iter().flatten());
            continue;
        }
        // A shell thinner than the f64 grid folds whatever its rounding: it goes whole.
        let thin = grid_step(mesh.positions(), THIN_SHELL_LEVEL, precision);
        let (shells, faces) = thin_shells(&mesh, &problems.to_snap, thin);
        if shells > 0 {
            certificate.removed_shells += shells;
            mesh = remove_faces(mesh, &faces);
            continue;
        }
        // Each successful re-rounding clears the faces of one vertex and breaks none, so
        // this repeats only while it helps.
        let progress = REROUND_PASSES.iter().find_map(|pass| {
            let (count, displacement) =
                reround(&mut mesh, pass, precision, &moved, &problems, &work);
            (count > 0).then_some((count, displacement))
        });
        if let Some((count, displacement)) = progress {
            certificate.record_snap(count, displacement);
            continue;
        }
        // Where dissolving slivers left as many problems as before (it takes the slivers
        // around every problem vertex, not only the problem's), the near-merge is tried
        // before it goes on, once an attempt: on a CAD model's fans of long triangles through
        // binary STL, the dissolving went on for 38 rounds of a whole check each with the
        // problems unchanged before the near-merge, tried after it, cleared them.
        let merge_first = merge_near && dissolving_stalls && !merged_early;
        if merge_first {
            merged_early = true;
            if let Some((merged, count, displacement)) =
                near_merged(&mesh, &moved, &problems, precision)
            {
                certificate.record_snap(count, displacement);
                (mesh, moved) = merged;
                continue;
            }
        }
        // Faces thinner than the f64 grid fold whatever their corners' rounding: they go.
        let diagonal = diagonal_of(mesh.positions());
        let tolerances = sliver_levels.map(|level| grid_step(mesh.positions(), level, precision));
        let done = slivers::dissolve(&mut mesh, &mut moved, &problems.to_snap, &tolerances);
        if done.changes > 0 {
            certificate.dissolved_slivers += done.changes;
            let relative = relative_to(done.displacement, diagonal);
            certificate.max_snap_displacement = certificate.max_snap_displacement.max(relative);
            dissolved_from = Some(problems.size());
            continue;
        }
        // (Not again in the round where it was tried first: the mesh is the same.)
        if merge_near && !merge_first {
            if let Some((merged, count, displacement)) =
                near_merged(&mesh, &moved, &problems, precision)
            {
                certificate.record_snap(count, displacement);
                (mesh, moved) = merged;
                continue;
            }
        }
        // So does a thin pocket hanging on its shell by edges of four uses: two
        // triangulations of one cut, put back against each other (see [`thin_pockets`]).
        // It builds a table of every edge of the mesh, so it comes after the cheap repairs.
        let (pockets, faces) = thin_pockets(&mesh, &problems.to_snap, thin);
        if pockets > 0 {
            certificate.removed_shells += pockets;
            mesh = remove_faces(mesh, &faces);
            continue;
        }
        if !pushing_refused {
            // A layer thinner than the grid between opposite faces, turned inside out and
            // dropped by an exact re-refinement (see [`layers`]); kept where it leaves fewer
            // problems, else rolled back, and not tried again in this certification: the
            // rounds go on as without it.
            let pushes = layers::pushes(&mesh, &problems.pairs, precision);
            if !pushes.is_empty() {
                let (soup, displacement) = moved_to(mesh.clone(), &pushes);
                let suspects: Vec<Point3> = (problems.to_snap.iter())
                    .map(|&v| soup.positions()[v as usize])
                    .chain(pushes.iter().map(|&(_, q)| q))
                    .collect();
                let refined = closed_refinement(&mut re_refine, &soup, &suspects);
                if counter.is_cancelled() {
                    return Err(Cancelled.into());
                }
                let fewer = refined.and_then(|(refined, refined_moved)| {
                    let moved =
                        layers::moved_after(&refined, refined_moved, &soup, &moved, &pushes);
                    let after = find_problems(&refined, &moved);
                    (after.size() < problems.size()).then_some((refined, moved))
                });
                match fewer {
                    Some(next) => {
                        certificate.rounds += 1;
                        certificate.record_snap(pushes.len(), displacement);
                        (mesh, moved) = next;
                        continue;
                    }
                    None => pushing_refused = true,
                }
            }
        }
        let mut soup = mesh.clone();
        let mut snapped = Vec::new();
        let mut snap_displacement = 0.0;
        if !problems.to_snap.is_empty() {
            if rounds_at_level == ROUNDS_PER_LEVEL {
                level += SNAP_LEVEL_STEP;
                rounds_at_level = 0;
            }
            if level > max_snap_level {
                return Err(CertifyError::not_certified(&problems));
            }
            rounds_at_level += 1;
            if level > 0 {
                // The whole neighbourhood goes on the grid, not only the crossing faces:
                // a face between a snapped and an unsnapped vertex tilts, and crosses its
                // nearly coplanar neighbours.
                snapped = neighbourhood_vertices(&soup, &problems.to_snap);
                snap_displacement = snap(&mut soup, &snapped, level, precision);
            }
        }
        certificate.rounds += 1;
        // Every vertex that moved since the mesh was last checked: the problem vertices and
        // the whole snapped neighbourhood (a face there that moved with it can cross one
        // that did not).
        let suspects: Vec<Point3> = (problems.to_snap.iter())
            .chain(&problems.coincident)
            .chain(&snapped)
            .map(|&v| soup.positions()[v as usize])
            .collect();
        let (mut refined, refined_moved) = match closed_refinement(&mut re_refine, &soup, &suspects)
        {
            Some(next) => next,
            None if counter.is_cancelled() => return Err(Cancelled.into()),
            // Slivers too thin to sample in f64, an operand the engine refuses, or a result
            // with a hole: a coarser grid merges their vertices.
            None if !problems.to_snap.is_empty() => {
                rounds_at_level = ROUNDS_PER_LEVEL;
                known = Some(problems);
                continue;
            }
            None => return Err(CertifyError::not_certified(&problems)),
        };
        // The new intersection points go on the same grid (Lazard & Valque): on a coarse
        // grid, near-degenerate pieces collapse instead of shrinking further.
        let mut new_snapped = (0, 0.0);
        if level > 0 {
            let new_points: Vec<u32> = (refined_moved.iter().enumerate())
                .filter(|&(_, &m)| m)
                .map(|(v, _)| v as u32)
                .collect();
            new_snapped = (
                new_points.len(),
                snap(&mut refined, &new_points, level, precision),
            );
        }
        let after = find_problems(&refined, &refined_moved);
        if fewest.as_ref().is_none_or(|f| problems.pairs.len() < f.0) {
            fewest = Some((problems.pairs.len(), mesh, moved));
        }
        if after.pairs.len() > RUNAWAY_FACTOR * problems.pairs.len() + RUNAWAY_SLACK {
            // A step back: re-refining the folds on this grid cut them finer, into more
            // folds. The rounds go on from the mesh with the fewest crossings so far, and
            // the next one snaps it to a coarser grid.
            let (_, best, best_moved) = fewest.as_ref().expect("kept above");
            (mesh, moved) = (best.clone(), best_moved.clone());
            rounds_at_level = ROUNDS_PER_LEVEL;
            continue;
        }
        certificate.record_snap(snapped.len(), snap_displacement);
        certificate.record_snap(new_snapped.0, new_snapped.1);
        (mesh, moved) = (refined, refined_moved);
        known = Some(after);
    }
    let problems = (known.take()).unwrap_or_else(|| find_problems(&mesh, &moved));
    if problems.is_empty() {
        let mesh = without_thin_shells(mesh, &moved, precision, &mut certificate);
        return Ok((without_unused_vertices(mesh), certificate));
    }
    Err(CertifyError::not_certified(&problems))
}

/// [`merge_near`] on a copy of `mesh` with its `problems`, then the coincident vertices
/// merged: the mesh and its moved vertices, the vertices merged and the largest move, kept
/// only where it leaves fewer problems (merging vertices of two surfaces an ulp apart
/// pinches them).
fn near_merged(
    mesh: &Mesh,
    moved: &[bool],
    problems: &Problems,
    precision: Precision,
) -> Option<((Mesh, Vec<bool>), usize, f64)> {
    let tolerance = grid_step(mesh.positions(), NEAR_LEVEL, precision);
    let mut merged = mesh.clone();
    let (count, displacement) = merge_near(&mut merged, &problems.to_snap, tolerance);
    if count == 0 {
        return None;
    }
    let (merged, merged_moved) = merge_coincident(merged, moved);
    let after = find_problems(&merged, &merged_moved);
    (after.size() < problems.size()).then_some(((merged, merged_moved), count, displacement))
}

/// `mesh`, free of problems, without the closed shells through a moved vertex that are
/// thinner on average than a few ulps ([`thin_shells`]), though valid: such a shell is a
/// slab between two surfaces an ulp apart that rounding left uncrossed, `(A − B) ∩ B`
/// through a file, and bounds no volume the precision can hold; rounding may even have
/// turned it inside out, and a negative volume makes the next boolean refuse the result as
/// an inward operand. Removing closed shells whole makes no new problem.
fn without_thin_shells(
    mesh: Mesh,
    moved: &[bool],
    precision: Precision,
    certificate: &mut Certificate,
) -> Mesh {
    let moved: Vec<u32> = (moved.iter().enumerate())
        .filter(|&(_, &m)| m)
        .map(|(v, _)| v as u32)
        .collect();
    if moved.is_empty() {
        return mesh;
    }
    let tolerance = grid_step(mesh.positions(), THIN_SHELL_LEVEL, precision);
    let (shells, faces) = thin_shells(&mesh, &moved, tolerance);
    if shells == 0 {
        return mesh;
    }
    certificate.removed_shells += shells;
    remove_faces(mesh, &faces)
}

impl Certificate {
    fn record_snap(&mut self, vertices: usize, displacement: f64) {
        self.snapped_vertices += vertices;
        self.max_snap_displacement = self.max_snap_displacement.max(displacement);
    }
}

/// Finds the crossing pairs, degenerate faces and coincident vertices among the faces with a
/// moved vertex and the faces near them.
fn find_problems(mesh: &Mesh, moved: &[bool]) -> Problems {
    let corners = mesh.corners();
    let suspects: Vec<u32> = (0..mesh.face_count())
        .into_par_iter()
        .filter(|&f| corners[3 * f..3 * f + 3].iter().any(|&v| moved[v as usize]))
        .map(|f| f as u32)
        .collect();
    if suspects.is_empty() {
        return Problems::default();
    }
    let near = faces_near(
        mesh.positions(),
        corners,
        &suspects,
        0.0,
        None,
        Nearness::SameCells,
    );
    let mut problems = problems_among(mesh.positions(), corners, &near, &suspects);
    // Both faces of a sheet have its moved vertex, so the suspects hold every sheet.
    problems.sheets = opposite_triangle_pairs(
        (suspects.iter()).map(|&f| (f, [0, 1, 2].map(|i| corners[3 * f as usize + i]))),
    );
    problems
}

/// Which faces [`faces_near`] returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Nearness {
    /// Exactly those whose boxes overlap a seed's box.
    Overlapping,
    /// Those, and others not far from them: every face in a cell of a coarse grid that a
    /// seed's box covers, or every face when the seeds are half of them or more. For callers
    /// that test boxes again (the pair walk), where a tree query per face to sort out the
    /// few extra ones costs more than those faces do: on two offset copies of a model the
    /// moved faces lie everywhere, and the queries were a third of certify's time.
    SameCells,
}

/// The faces (of `within`, or of all) whose boxes overlap the box of one of `seeds` widened
/// by `margin` (and others with [`Nearness::SameCells`]), seeds included, sorted.
fn faces_near(
    positions: &[Point3],
    corners: &[u32],
    seeds: &[u32],
    margin: f64,
    within: Option<&[u32]>,
    nearness: Nearness,
) -> Vec<u32> {
    let face_box = |f: usize| {
        Aabb::from_points(
            corners[3 * f..3 * f + 3]
                .iter()
                .map(|&v| &positions[v as usize]),
        )
    };
    let widened = |f: usize| {
        let b = face_box(f);
        Aabb {
            min: b.min.map(|x| x - margin),
            max: b.max.map(|x| x + margin),
        }
    };
    let candidates = within.map_or(corners.len() / 3, <[u32]>::len);
    let with_seeds = |mut near: Vec<u32>| {
        near.extend_from_slice(seeds);
        near.sort_unstable();
        near.dedup();
        near
    };
    if nearness == Nearness::SameCells && 2 * seeds.len() >= candidates {
        // Small meshes, where most faces carry a rounded vertex: a grid over the seeds would
        // turn few faces away.
        return with_seeds(match within {
            Some(faces) => faces.to_vec(),
            None => (0..candidates as u32).collect(),
        });
    }
    let seed_boxes: Vec<Aabb> = seeds.iter().map(|&f| widened(f as usize)).collect();
    let bounds = (seed_boxes.iter()).fold(Aabb::EMPTY, |b, s| b.union(s));
    // A coarse grid of the cells the seeds' boxes cover turns most faces away in a few bit
    // tests: the moved faces lie along intersection curves, and a query of a tree of the
    // seeds from a face far from them still descends through the boxes of curves that cross
    // the model.
    let samples = Occupancy::size_samples(seeds.len()).map(|i| seed_boxes[i]);
    let side = Occupancy::side_for(&bounds, samples);
    let (cells, _) = Occupancy::of(&bounds, side, seeds.len(), |i| seed_boxes[i]);
    let tree = (nearness == Nearness::Overlapping).then(|| Bvh::build(&seed_boxes));
    let test = |f: u32| {
        let b = face_box(f as usize);
        b.overlaps(&bounds)
            && cells.touches(cells.span(&b))
            && tree
                .as_ref()
                .is_none_or(|tree| tree.any_overlapping(&b, |_| true))
    };
    with_seeds(match within {
        Some(faces) => faces.iter().copied().filter(|&f| test(f)).collect(),
        None => {
            // Per vertex, the sides of the bounds it lies beyond, a bit each: a face with all
            // its corners beyond one side misses the bounds, which a byte per corner tells
            // where the face's box reads its three positions from all over the mesh (most
            // faces lie far from the seeds; on two 1 M spheres this search, the suspects'
            // filter with it, went from 12.5–18 to 8.4–9.7 ms).
            let beyond: Vec<u8> = (positions.par_iter())
                .map(|p| sides_beyond(p, &bounds))
                .collect();
            (0..(corners.len() / 3) as u32)
                .into_par_iter()
                .filter(|&f| {
                    let c = &corners[3 * f as usize..3 * f as usize + 3];
                    let all_beyond =
                        beyond[c[0] as usize] & beyond[c[1] as usize] & beyond[c[2] as usize];
                    all_beyond == 0 && test(f)
                })
                .collect()
        }
    })
}

/// The sides of `bounds` that `p` lies beyond: bit `2 k` below its minimum along axis `k`,
/// bit `2 k + 1` above its maximum. Three points share a bit exactly when their box misses
/// `bounds` along that axis ([`Aabb::overlaps`] is false).
fn sides_beyond(p: &Point3, bounds: &Aabb) -> u8 {
    (0..3).fold(0, |bits, k| {
        bits | u8::from(p[k] < bounds.min[k]) << (2 * k)
            | u8::from(p[k] > bounds.max[k]) << (2 * k + 1)
    })
}

/// The problems of the faces `near` (sorted) that involve a face of `suspects` (sorted).
fn problems_among(
    positions: &[Point3],
    corners: &[u32],
    near: &[u32],
    suspects: &[u32],
) -> Problems {
    let face = |f: usize| [corners[3 * f], corners[3 * f + 1], corners[3 * f + 2]];
    // The neighbourhood as its own soup, welded by position, so the pair test sees shared
    // vertices the way a reader of the written file will. Local ids in order of first use,
    // kept by vertex in a dense table (one plus the id, zero while unseen: the table comes
    // zeroed from the allocator), so only a vertex's first use hashes its position.
    let mut local_vertex = vec![0u32; positions.len()];
    let mut local_of: FxHashMap<[u64; 3], u32> = FxHashMap::default();
    let mut local_positions = Vec::new();
    let mut coincident = Vec::new();
    let key = |p: [f64; 3]| p.map(|x| (x + 0.0).to_bits());
    for v in near.iter().flat_map(|&f| face(f as usize)) {
        if local_vertex[v as usize] == 0 {
            let p = positions[v as usize];
            let next = local_positions.len() as u32;
            let id = *local_of.entry(key(p)).or_insert(next);
            if id == next {
                local_positions.push(p);
            } else {
                coincident.push(v);
            }
            local_vertex[v as usize] = id + 1;
        }
    }
    // Each face's triangle by its local vertex ids, or whether it is degenerate (three
    // distinct vertices, collinear). Kept as indexed triangles, a fifth of a full one's bytes:
    // these records are made afresh every round, and full ones cost more in first touches of
    // their pages than making them did.
    let built: Vec<Result<IndexedTriangle, bool>> = (near.par_iter())
        .map(|&f| {
            let ids = face(f as usize).map(|v| local_vertex[v as usize] - 1);
            let made = Triangle::new(0, ids, ids.map(|v| local_positions[v as usize]));
            (made.as_ref().map(Triangle::indexed))
                .ok_or(ids[0] != ids[1] && ids[1] != ids[2] && ids[2] != ids[0])
        })
        .collect();
    // The faces that make a triangle: each one's place in `near`, and its triangle.
    let mut valid: Vec<(u32, IndexedTriangle)> = Vec::with_capacity(near.len());
    let mut degenerate = Vec::new();
    for (place, (built, &f)) in built.into_iter().zip(near).enumerate() {
        match built {
            Ok(t) => valid.push((place as u32, t)),
            Err(true) => degenerate.push(f),
            Err(false) => {}
        }
    }
    let triangle = |i: usize| {
        let (place, t) = valid[i];
        t.with_positions(place, &local_positions)
    };
    let face_of = |i: u32| near[valid[i as usize].0 as usize];
    // Both lists are sorted by face: one merge finds the suspects among the triangles.
    let mut suspects_left = suspects.iter().peekable();
    let marked: Vec<u32> = (0..valid.len() as u32)
        .filter(|&i| {
            let f = face_of(i);
            while suspects_left.next_if(|&&s| s < f).is_some() {}
            suspects_left.peek() == Some(&&f)
        })
        .collect();
    let pairs: Vec<(u32, u32)> =
        (super::self_intersect::intersecting_pairs_of(valid.len(), triangle, &marked).into_iter())
            .map(|(s, t)| (face_of(s), face_of(t)))
            .collect();
    let mut to_snap: Vec<u32> = (pairs.iter())
        .flat_map(|&(s, t)| [s, t])
        .chain(degenerate.iter().copied())
        .flat_map(|f| face(f as usize))
        .collect();
    to_snap.sort_unstable();
    to_snap.dedup();
    Problems {
        degenerate_faces: degenerate.len(),
        to_snap,
        coincident,
        sheets: Vec::new(),
        pairs,
    }
}

/// Moves each vertex of a problem face that `pass` allows to one of the f64 points around it
/// (each coordinate up to `pass.steps` steps down or up; nearest first) where its faces have no
/// problem with the faces around them, if there is one. Most folds are a sliver whose rounded
/// corner landed on the wrong side of the opposite edge by an ulp: the other rounding fixes it
/// without moving anything else. Returns how many vertices moved and the largest move
/// relative to the bounding box diagonal.
fn reround(
    mesh: &mut Mesh,
    pass: &Reround,
    precision: Precision,
    moved: &[bool],
    problems: &Problems,
    work: &std::cell::Cell<u64>,
) -> (usize, f64) {
    let vertices: Vec<u32> = (problems.to_snap.iter())
        .copied()
        .filter(|&v| pass.any_vertex || moved[v as usize])
        .collect();
    if vertices.is_empty() {
        return (0, 0.0);
    }
    let mut parts = std::mem::take(mesh).into_parts();
    let corners = std::mem::take(&mut parts.corners);
    let positions = &mut parts.positions;
    let mut faces_of: FxHashMap<u32, Vec<u32>> =
        vertices.iter().map(|&v| (v, Vec::new())).collect();
    for (f, c) in corners.chunks_exact(3).enumerate() {
        for v in c {
            if let Some(faces) = faces_of.get_mut(v) {
                faces.push(f as u32);
            }
        }
    }
    // Two ulps of the largest coordinate: more than any candidate moves a face's box.
    let margin = grid_step(positions, 1, precision);
    let seeds: Vec<u32> = {
        let mut all: Vec<u32> = faces_of.values().flatten().copied().collect();
        all.sort_unstable();
        all.dedup();
        all
    };
    let region = faces_near(
        positions,
        &corners,
        &seeds,
        margin,
        None,
        Nearness::Overlapping,
    );
    let diagonal = diagonal_of(positions);
    let (mut count, mut largest_move) = (0, 0.0f64);
    for v in vertices {
        if work.get() > REROUND_BUDGET {
            break;
        }
        let around = &faces_of[&v];
        let local = faces_near(
            positions,
            &corners,
            around,
            margin,
            Some(&region),
            Nearness::Overlapping,
        );
        let corners_of = |f: u32| {
            let c = &corners[3 * f as usize..3 * f as usize + 3];
            [c[0], c[1], c[2]]
        };
        // The faces near v that do not use it keep their shape while v moves.
        let others: Vec<Triangle> = (local.iter())
            .filter(|f| around.binary_search(f).is_err())
            .filter_map(|&f| {
                let ids = corners_of(f);
                Triangle::new(f, ids, ids.map(|u| positions[u as usize]))
            })
            .collect();
        let other_boxes: Vec<Aabb> = (others.iter())
            .map(|t| Aabb::from_points(t.positions().iter()))
            .collect();
        let fine = |positions: &[Point3]| {
            // Every face near v is looked at (its box at least) once per candidate.
            work.set(work.get() + local.len() as u64);
            if work.get() > REROUND_BUDGET {
                return false;
            }
            let p = positions[v as usize];
            let coincident = (local.iter().flat_map(|&f| corners_of(f)))
                .any(|u| u != v && positions[u as usize] == p);
            if coincident {
                return false;
            }
            let mine: Option<Vec<Triangle>> = (around.iter())
                .map(|&f| {
                    let ids = corners_of(f);
                    Triangle::new(f, ids, ids.map(|u| positions[u as usize]))
                })
                .collect();
            let Some(mine) = mine else { return false };
            let crossing = (mine.iter().enumerate()).any(|(i, a)| {
                let a_box = Aabb::from_points(a.positions().iter());
                let near_others = (others.iter().zip(&other_boxes))
                    .filter(|(_, b)| b.overlaps(&a_box))
                    .map(|(t, _)| t);
                near_others
                    .chain(&mine[i + 1..])
                    .any(|b| pair_intersects(a, b))
            });
            !crossing
        };
        if fine(positions) {
            continue;
        }
        let start = positions[v as usize];
        let found = neighbours(start, pass.steps, precision)
            .into_iter()
            .find(|&q| {
                positions[v as usize] = q;
                fine(positions)
            });
        match found {
            Some(q) => {
                count += 1;
                let d = distance(q, start);
                largest_move = largest_move.max(d);
            }
            None => positions[v as usize] = start,
        }
    }
    parts.corners = corners;
    *mesh = Mesh::from_parts(parts).expect("re-rounding changes positions only");
    (count, relative_to(largest_move, diagonal))
}

/// The f64 points around `p` up to `steps` steps away in each coordinate, nearest
/// (in steps, then in coordinates changed) first, with no coordinate newly subnormal: a step
/// from 0 to ±5e-324 changes no shape a reader can see, and readers whose predicates
/// underflow there (Shewchuk's) take the faces around such a vertex for flat.
fn neighbours(p: Point3, steps: u32, precision: Precision) -> Vec<Point3> {
    let n = steps as i32;
    let mut out: Vec<(i32, i32, Point3)> = Vec::new();
    for dx in -n..=n {
        for dy in -n..=n {
            for dz in -n..=n {
                let steps = [dx, dy, dz];
                if steps == [0, 0, 0] {
                    continue;
                }
                let q = [0, 1, 2].map(|k| precision.step_by(p[k], steps[k]));
                let newly_subnormal =
                    |k: usize| precision.is_subnormal(q[k]) && !precision.is_subnormal(p[k]);
                if (0..3).any(|k| !q[k].is_finite() || newly_subnormal(k)) {
                    continue;
                }
                let far = steps.iter().map(|s| s.abs()).max().unwrap_or(0);
                let changed = steps.iter().filter(|&&s| s != 0).count() as i32;
                out.push((far, changed, q));
            }
        }
    }
    out.sort_by_key(|e| (e.0, e.1));
    out.into_iter().map(|e| e.2).collect()
}

/// The distance from `p` to `q`, without underflow for moves of a few subnormal steps.
fn distance(p: Point3, q: Point3) -> f64 {
    let d = [0, 1, 2].map(|k| (q[k] - p[k]).abs());
    let largest = d.iter().copied().fold(0.0f64, f64::max);
    if largest == 0.0 {
        return 0.0;
    }
    largest * d.iter().map(|x| (x / largest).powi(2)).sum::<f64>().sqrt()
}

/// The diagonal of the bounding box of `positions`.
fn diagonal_of(positions: &[Point3]) -> f64 {
    let bounds = Aabb::from_points(positions.iter());
    (0..3)
        .map(|k| (bounds.max[k] - bounds.min[k]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// `mesh` with the vertices at one position merged and the faces that collapse dropped
/// (closedness is kept: a collapsed triangle's two remaining sides cancel), and the moved
/// flags carried over, merged vertices marked as moved so their faces are checked again.
fn merge_coincident(mesh: Mesh, moved: &[bool]) -> (Mesh, Vec<bool>) {
    let welding = weld_positions(mesh.positions());
    let mut merged_moved = vec![false; welding.welded_count()];
    for (v, &w) in welding.remap.iter().enumerate() {
        let merged = welding.representatives[w as usize] != v as u32;
        merged_moved[w as usize] |= moved[v] || merged;
        merged_moved[welding.remap[welding.representatives[w as usize] as usize] as usize] |=
            merged;
    }
    let welded = apply_welding(&mesh, &welding);
    let collapsed: Vec<u32> = (welded.corners().chunks_exact(3).enumerate())
        .filter(|(_, c)| c[0] == c[1] || c[1] == c[2] || c[2] == c[0])
        .map(|(f, _)| f as u32)
        .collect();
    (remove_faces(welded, &collapsed), merged_moved)
}

/// The closed shells (faces joined by shared vertices) that hold one of `vertices` (sorted)
/// and are thinner on average than `tolerance`: twice their volume, over their area, below
/// it. How many, and their faces.
///
/// Such a shell is a slab between two surfaces less than an ulp apart, as the exact result of
/// `(A − B) ∩ B` through a file is: the pieces of B's faces that A − B wrote with corners
/// rounded into B, against B's own faces. Its two sides are too close for any f64 corners to
/// keep them apart, and it bounds almost no volume: removing it whole keeps every other shell
/// closed and changes the volume by less than its area times the tolerance. Both sums run
/// from a vertex of the shell, so their rounding error is relative to the shell's size.
fn thin_shells(mesh: &Mesh, vertices: &[u32], tolerance: f64) -> (usize, Vec<u32>) {
    let corners = mesh.corners();
    let positions = mesh.positions();
    let sets = UnionFind::new(positions.len());
    corners.par_chunks(3).for_each(|c| {
        sets.union_shared(c[0], c[1]);
        sets.union_shared(c[0], c[2]);
    });
    let root_of = sets.roots();
    // Per shell with one of `vertices`, by its root: its slot among those shells.
    let mut slot_of_root = vec![u32::MAX; positions.len()];
    let mut roots = Vec::new();
    for &v in vertices {
        let root = root_of[v as usize];
        if slot_of_root[root as usize] == u32::MAX {
            slot_of_root[root as usize] = roots.len() as u32;
            roots.push(root);
        }
    }
    let origins: Vec<Point3> = roots.iter().map(|&r| positions[r as usize]).collect();
    let slot_of = |f: usize| slot_of_root[root_of[corners[3 * f] as usize] as usize];
    // A shell of faces joined by vertices is closed where the mesh is.
    thin_pieces(mesh, slot_of, &origins, |_| true, tolerance)
}

/// The closed pieces thinner on average than `tolerance` (as in [`thin_shells`]) among those
/// with a face around one of `vertices`: faces joined across edges used once each way, where
/// such a piece is closed by itself (at every edge, its own uses balanced). How many, and
/// their faces.
///
/// Such a piece is a whole shell or, what [`thin_shells`] does not find, a pocket that hangs
/// on the rest of its shell by edges of four uses or more (or at vertices). Joining the two
/// pieces of a solid split in two, `(A ∪ B) − B` and `A ∩ B`, puts their cut faces back
/// against each other: the two pieces triangulate the cut between the same vertices
/// differently, and wherever two triangulations of a quad that is not quite planar differ,
/// the exact union keeps the thin tetrahedron between them, a pocket of material or of empty
/// space. Those with an intersection point of the union fold when it is rounded, and nothing
/// but removing them whole clears them (re-refining a pocket computes it again). Removing a
/// closed pocket keeps every edge balanced.
fn thin_pockets(mesh: &Mesh, vertices: &[u32], tolerance: f64) -> (usize, Vec<u32>) {
    debug_assert!(mesh.is_triangle_mesh(), "face ids index corners in threes");
    let corners = mesh.corners();
    let positions = mesh.positions();
    let edges = EdgeTable::new(mesh);
    let mut pieces = UnionFind::new(mesh.face_count());
    for e in 0..edges.edge_count() {
        if let [(f, true), (g, false)] | [(f, false), (g, true)] =
            edges.face_uses(e).collect::<SmallVec<[_; 4]>>()[..]
        {
            pieces.union(f, g);
        }
    }
    let piece_of = pieces.roots();
    // Per piece with a face around one of `vertices`, by its root face: its slot.
    let mut around = vec![false; mesh.vertex_count()];
    for &v in vertices {
        around[v as usize] = true;
    }
    let mut slot_of_piece = vec![u32::MAX; mesh.face_count()];
    let mut origins = Vec::new();
    for (f, c) in corners.chunks_exact(3).enumerate() {
        let piece = piece_of[f] as usize;
        if c.iter().any(|&v| around[v as usize]) && slot_of_piece[piece] == u32::MAX {
            slot_of_piece[piece] = origins.len() as u32;
            origins.push(positions[corners[3 * piece] as usize]);
        }
    }
    let slot_of = |f: usize| slot_of_piece[piece_of[f] as usize];
    // A piece is closed where every edge's uses among its faces balance.
    let mut closed = vec![true; origins.len()];
    let mut balance: SmallVec<[(u32, i32); 4]> = SmallVec::new();
    for e in 0..edges.edge_count() {
        balance.clear();
        for (f, forward) in edges.face_uses(e) {
            let slot = slot_of(f as usize);
            if slot == u32::MAX {
                continue;
            }
            let step = if forward { 1 } else { -1 };
            match balance.iter_mut().find(|(s, _)| *s == slot) {
                Some((_, sum)) => *sum += step,
                None => balance.push((slot, step)),
            }
        }
        for &(slot, sum) in &balance {
            if sum != 0 {
                closed[slot as usize] = false;
            }
        }
    }
    thin_pieces(mesh, slot_of, &origins, |slot| closed[slot], tolerance)
}

/// Of the pieces of `mesh` (`slot_of(face)`: a face's piece, or `u32::MAX` for none), those
/// `is_closed` and thinner on average than `tolerance`: twice their volume, over their area,
/// below it, each summed from the piece's `origins` point. How many, and their faces.
fn thin_pieces(
    mesh: &Mesh,
    slot_of: impl Fn(usize) -> u32 + Sync,
    origins: &[Point3],
    is_closed: impl Fn(usize) -> bool,
    tolerance: f64,
) -> (usize, Vec<u32>) {
    let corners = mesh.corners();
    let positions = mesh.positions();
    // Per piece: six times its volume and twice its area, each face's terms from the
    // piece's origin; summed per chunk of faces in parallel, then over the chunks in order,
    // so the sums do not depend on the thread count.
    let chunk_sums = |faces: std::ops::Range<usize>| {
        let mut sums = vec![(0.0f64, 0.0f64); origins.len()];
        for f in faces {
            let slot = slot_of(f);
            if slot != u32::MAX {
                let origin = origins[slot as usize];
                let [a, b, c] =
                    [0, 1, 2].map(|k| sub(positions[corners[3 * f + k] as usize], origin));
                let (six_volume, twice_area) = &mut sums[slot as usize];
                *six_volume += dot(a, cross(b, c));
                *twice_area += norm(cross(sub(b, a), sub(c, a)));
            }
        }
        sums
    };
    let face_count = corners.len() / 3;
    let chunks: Vec<std::ops::Range<usize>> = block_ranges(face_count, THIN_SHELL_CHUNK).collect();
    let measures = if origins.len() * chunks.len() > THIN_SHELL_CHUNK {
        chunk_sums(0..face_count)
    } else {
        let partial: Vec<Vec<(f64, f64)>> = chunks.into_par_iter().map(chunk_sums).collect();
        let mut total = vec![(0.0f64, 0.0f64); origins.len()];
        for sums in partial {
            for (t, s) in total.iter_mut().zip(sums) {
                *t = (t.0 + s.0, t.1 + s.1);
            }
        }
        total
    };
    // Mean thickness 2 V / A = (2 / 3) · six_volume / twice_area.
    let thin: Vec<bool> = (measures.iter().enumerate())
        .map(|(slot, &(six_volume, twice_area))| {
            is_closed(slot) && (2.0 * six_volume).abs() < 3.0 * twice_area * tolerance
        })
        .collect();
    let pieces = thin.iter().filter(|&&t| t).count();
    if pieces == 0 {
        return (0, Vec::new());
    }
    let faces = (0..face_count)
        .filter(|&f| {
            let slot = slot_of(f);
            slot != u32::MAX && thin[slot as usize]
        })
        .map(|f| f as u32)
        .collect();
    (pieces, faces)
}

/// Faces per chunk of [`thin_pieces`]' parallel sums (and the most per-chunk sums it keeps).
const THIN_SHELL_CHUNK: usize = 1 << 16;

/// How close, in ulps of the largest coordinate magnitude (as `log2`), a problem vertex must
/// be to another for [`merge_near`] to merge them.
const NEAR_LEVEL: i32 = 1;

/// Merges each problem vertex of `to_snap` with the vertices near it that are within
/// `tolerance` of it in every coordinate, all of a cluster onto the position of its lowest
/// index (input vertices come first, so an unrounded one where there is one); the caller
/// then merges coincident vertices as always. Two exact points a step apart, such as a new
/// intersection point beside the rounded vertex of an earlier boolean it meets in a chain
/// through a file, leave a strip of slivers between them of which no single collapse
/// unfolds the rest ([`slivers`] tries those); merged, the strip collapses at once. Returns
/// how many vertices moved and the largest move relative to the bounding box diagonal.
fn merge_near(mesh: &mut Mesh, to_snap: &[u32], tolerance: f64) -> (usize, f64) {
    let candidates = neighbourhood_vertices(mesh, to_snap);
    let positions = mesh.positions();
    let cell = |p: Point3| p.map(|x| (x / tolerance).floor() as i64);
    let mut cells: FxHashMap<[i64; 3], Vec<u32>> = FxHashMap::default();
    for (i, &v) in candidates.iter().enumerate() {
        cells
            .entry(cell(positions[v as usize]))
            .or_default()
            .push(i as u32);
    }
    let mut sets = UnionFind::new(candidates.len());
    for &v in to_snap {
        let Ok(i) = candidates.binary_search(&v) else {
            continue;
        };
        let p = positions[v as usize];
        let [x, y, z] = cell(p);
        for key in (-1..=1).flat_map(|dx| {
            (-1..=1).flat_map(move |dy| (-1..=1).map(move |dz| [x + dx, y + dy, z + dz]))
        }) {
            for &j in cells.get(&key).into_iter().flatten() {
                let q = positions[candidates[j as usize] as usize];
                if (0..3).all(|k| (p[k] - q[k]).abs() <= tolerance) {
                    sets.union(i as u32, j);
                }
            }
        }
    }
    let roots = sets.roots();
    // Roots are the lowest index of their cluster, and candidates are sorted.
    let moves: Vec<(u32, Point3)> = (roots.iter().enumerate())
        .filter(|&(i, &root)| root as usize != i)
        .map(|(i, &root)| (candidates[i], positions[candidates[root as usize] as usize]))
        .filter(|&(v, target)| positions[v as usize] != target)
        .collect();
    let (moved, displacement) = moved_to(std::mem::take(mesh), &moves);
    *mesh = moved;
    (moves.len(), displacement)
}

/// `mesh` with each vertex of `moves` at its new position, and the largest move relative to
/// the diagonal of its bounding box.
fn moved_to(mesh: Mesh, moves: &[(u32, Point3)]) -> (Mesh, f64) {
    let mut parts = mesh.into_parts();
    let diagonal = diagonal_of(&parts.positions);
    let mut largest = 0.0f64;
    for &(v, q) in moves {
        let p = &mut parts.positions[v as usize];
        largest = largest.max(distance(*p, q));
        *p = q;
    }
    let mesh = Mesh::from_parts(parts).expect("moving vertices changes positions only");
    (mesh, relative_to(largest, diagonal))
}

/// `largest`, a vertex move, relative to `diagonal`, a bounding box's (0 for a mesh of no
/// extent).
fn relative_to(largest: f64, diagonal: f64) -> f64 {
    if diagonal > 0.0 {
        largest / diagonal
    } else {
        0.0
    }
}

/// The mesh without `faces`, keeping every vertex (the next check looks only at faces).
fn remove_faces<'a>(mesh: Mesh, faces: impl IntoIterator<Item = &'a u32>) -> Mesh {
    let mut parts = mesh.into_parts();
    let mut keep = vec![true; parts.corners.len() / 3];
    for &f in faces {
        keep[f as usize] = false;
    }
    parts.corners = (parts.corners.chunks_exact(3).zip(&keep))
        .filter(|(_, k)| **k)
        .flat_map(|(c, _)| c.iter().copied())
        .collect();
    if let Some(provenance) = parts.face_provenance.as_mut() {
        *provenance = (provenance.iter().zip(&keep))
            .filter(|(_, k)| **k)
            .map(|(p, _)| *p)
            .collect();
    }
    Mesh::from_parts(parts).expect("removing faces keeps indices in range")
}

/// The vertices of the faces whose boxes overlap a face around one of `vertices`.
fn neighbourhood_vertices(mesh: &Mesh, vertices: &[u32]) -> Vec<u32> {
    let corners = mesh.corners();
    let seeds: Vec<u32> = (0..mesh.face_count() as u32)
        .filter(|&f| {
            let c = &corners[3 * f as usize..3 * f as usize + 3];
            c.iter().any(|v| vertices.binary_search(v).is_ok())
        })
        .collect();
    let near = faces_near(
        mesh.positions(),
        corners,
        &seeds,
        0.0,
        None,
        Nearness::Overlapping,
    );
    let mut out: Vec<u32> = (near.iter())
        .flat_map(|&f| corners[3 * f as usize..3 * f as usize + 3].iter().copied())
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Moves `vertices` of `mesh` to the nearest multiple of `2^level` ulps of the largest
/// coordinate magnitude; returns the largest displacement relative to the diagonal of the
/// mesh's bounding box.
fn snap(mesh: &mut Mesh, vertices: &[u32], level: i32, precision: Precision) -> f64 {
    // A power of two, so x / step, its rounding and the product back are exact.
    let step = grid_step(mesh.positions(), level, precision);
    let moves: Vec<(u32, Point3)> = (vertices.iter())
        .map(|&v| {
            (
                v,
                mesh.positions()[v as usize].map(|x| (x / step).round() * step),
            )
        })
        .collect();
    let (snapped, displacement) = moved_to(std::mem::take(mesh), &moves);
    *mesh = snapped;
    displacement
}

/// `2^level` ulps of `precision` at the largest coordinate magnitude of `positions`:
/// ulp(M) = 2^(e − 52) in f64, 2^(e − 23) in f32, for M in [2^e, 2^(e+1)). Its multiples up
/// to M are numbers of `precision`.
fn grid_step(positions: &[Point3], level: i32, precision: Precision) -> f64 {
    let largest = (positions.iter().flatten()).fold(0.0f64, |m, x| m.max(x.abs()));
    let exponent = if largest > 0.0 {
        largest.log2().floor() as i32
    } else {
        0
    };
    2f64.powi(exponent - precision.fraction_bits() + level)
}

/// The exact re-refinement of `soup` (`suspects`: where its vertices moved since it was last
/// free of crossings), when the engine takes it and its result is closed: that mesh with the
/// provenance of `soup`'s faces, and its moved vertices. The re-refinement's own arrangement
/// decides exactly, but its input is a fold: its result is checked like any other before it
/// replaces the mesh.
fn closed_refinement(
    re_refine: &mut impl FnMut(&Mesh, &[Point3]) -> Option<Rounded>,
    soup: &Mesh,
    suspects: &[Point3],
) -> Option<(Mesh, Vec<bool>)> {
    let next = re_refine(soup, suspects)
        .filter(|next| crate::mesh::analyze_topology(&next.mesh).unbalanced_edges == 0)?;
    Some((with_source_provenance(next.mesh, soup), next.moved))
}

/// `refined` (a boolean of `soup` alone, whose provenance names faces of `soup`) with the
/// provenance of those faces: the operand and input face they came from.
fn with_source_provenance(refined: Mesh, soup: &Mesh) -> Mesh {
    let Some(source) = soup.parts().face_provenance.as_deref() else {
        return refined;
    };
    let mut parts: MeshParts = refined.into_parts();
    if let Some(provenance) = parts.face_provenance.as_mut() {
        for p in provenance.iter_mut() {
            *p = source[p.face.index()];
        }
    }
    Mesh::from_parts(parts).expect("provenance only")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{FaceId, OperandId, Provenance};

    fn cube(min: f64, max: f64) -> Mesh {
        crate::primitives::cuboid([min; 3], [max; 3])
    }

    /// A box 2 long and wide and `height` high, its corners from vertex `first` on.
    fn flat_box(height: f64, first: u32) -> (Vec<Point3>, Vec<u32>) {
        let cuboid = crate::primitives::cuboid([0.0, 0.0, 4.0], [2.0, 2.0, 4.0 + height]);
        let corners = cuboid.corners().iter().map(|&v| v + first).collect();
        (cuboid.positions().to_vec(), corners)
    }

    #[test]
    fn only_shells_thinner_than_the_tolerance_go() {
        let tolerance = grid_step(&[[4.0; 3]], THIN_SHELL_LEVEL, Precision::F64);
        let (mut positions, mut corners) = flat_box(tolerance / 4.0, 0);
        let (thick_positions, thick_corners) = flat_box(4.0 * tolerance, 8);
        positions.extend(thick_positions);
        corners.extend(thick_corners);
        let faces = corners.len() / 3;
        let mesh = Mesh::from_parts(MeshParts {
            positions,
            corners,
            ..MeshParts::default()
        })
        .unwrap();
        // A problem in each shell: only the thin one goes, all twelve of its faces.
        let (shells, gone) = thin_shells(&mesh, &[0, 8], tolerance);
        assert_eq!((shells, gone), (1, (0..12).collect::<Vec<u32>>()));
        // Without a problem in it, a thin shell stays.
        assert_eq!(thin_shells(&mesh, &[8], tolerance), (0, vec![]));
        assert_eq!(faces, 24);
    }

    #[test]
    fn only_closed_thin_pockets_hanging_on_an_edge_go() {
        // The unit cube, and a tetrahedron on its edge from (0, 0, 0) to (1, 0, 0): that edge
        // has four uses, so the tetrahedron is a piece of its own, closed by itself, whose
        // fourth corner lies `height` above the plane of the other three.
        let tolerance = grid_step(&[[1.0; 3]], THIN_SHELL_LEVEL, Precision::F64);
        let with_pocket = |height: f64, faces: usize| {
            let cube = cube(0.0, 1.0);
            let at = |p: Point3| (cube.positions().iter()).position(|&q| q == p).unwrap() as u32;
            let (a, b) = (at([0.0; 3]), at([1.0, 0.0, 0.0]));
            let (c, d) = (8, 9);
            let mut positions = cube.positions().to_vec();
            positions.extend([[0.5, -0.5, 0.0], [0.5, -0.25, height]]);
            let mut corners = cube.corners().to_vec();
            let pocket = [[a, c, b], [a, b, d], [b, c, d], [a, d, c]];
            corners.extend(pocket[..faces].iter().flatten());
            Mesh::from_parts(MeshParts {
                positions,
                corners,
                ..MeshParts::default()
            })
            .unwrap()
        };
        let pocket_faces: Vec<u32> = (12..16).collect();
        // A problem at its corner: the thin pocket goes, its four faces and nothing else.
        let thin = with_pocket(tolerance, 4);
        assert_eq!(thin_pockets(&thin, &[8], tolerance), (1, pocket_faces));
        // A problem only on the cube, whose piece is thick: nothing goes.
        let far_corner = (thin.positions().iter())
            .position(|&p| p == [1.0; 3])
            .unwrap();
        assert_eq!(
            thin_pockets(&thin, &[far_corner as u32], tolerance),
            (0, vec![])
        );
        // A thick pocket stays, and so does a thin one that is not closed by itself.
        assert_eq!(
            thin_pockets(&with_pocket(100.0 * tolerance, 4), &[8], tolerance),
            (0, vec![])
        );
        assert_eq!(
            thin_pockets(&with_pocket(tolerance, 3), &[8], tolerance),
            (0, vec![])
        );
    }

    #[test]
    fn a_valid_thin_shell_through_a_moved_vertex_goes_inside_out_or_not() {
        // A cube with a box a quarter of the tolerance high beside it, inside out (as a slab
        // rounding turned over): no problem, a negative volume. Only with a moved vertex in
        // the thin box does it go.
        let tolerance = grid_step(&[[4.0; 3]], THIN_SHELL_LEVEL, Precision::F64);
        let (mut positions, mut corners) = flat_box(tolerance / 4.0, 0);
        corners.chunks_exact_mut(3).for_each(|c| c.swap(1, 2));
        let thick = cube(5.0, 6.0);
        corners.extend(thick.corners().iter().map(|&v| v + 8));
        positions.extend_from_slice(thick.positions());
        let mesh = Mesh::from_parts(MeshParts {
            positions,
            corners,
            ..MeshParts::default()
        })
        .unwrap();
        assert!(mesh.report().measures.volume < 1.0);
        let mut moved = vec![false; 16];
        moved[12] = true;
        let mut certificate = Certificate::default();
        let (kept, _) = certify(
            Rounded {
                mesh: mesh.clone(),
                moved: moved.clone(),
                rounded: 1,
            },
            Precision::F64,
            false,
            &Progress::default(),
            |_, _| None,
        )
        .unwrap();
        assert_eq!(kept.face_count(), 24, "no moved vertex in the thin box");
        moved[3] = true;
        let without = without_thin_shells(mesh, &moved, Precision::F64, &mut certificate);
        assert_eq!(without.face_count(), 12);
        assert_eq!(certificate.removed_shells, 1);
        assert_eq!(without.report().measures.volume, 1.0);
    }

    #[test]
    fn near_vertices_merge_onto_the_lowest_in_clusters() {
        // Two triangles whose corners 3 and 4 lie a step from 0 and 1: with 3 a problem
        // vertex, 3 goes onto 0; 4 is no problem's and stays; corner 2 is far and stays.
        let up = |x: f64| Precision::F64.step_by(x, 1);
        let positions = vec![
            [0.5, 0.5, 0.5],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, up(0.5), 0.5],
            [up(1.0), 0.0, 0.0],
        ];
        let mut mesh = Mesh::from_triangles(positions.clone(), &[[0, 1, 2], [3, 4, 2]]).unwrap();
        let tolerance = grid_step(mesh.positions(), NEAR_LEVEL, Precision::F64);
        let (count, displacement) = merge_near(&mut mesh, &[3], tolerance);
        assert_eq!(count, 1);
        assert!(displacement > 0.0);
        let after = mesh.positions();
        assert_eq!(after[3], positions[0]);
        assert_eq!(
            [after[0], after[1], after[2], after[4]],
            [0, 1, 2, 4].map(|v| positions[v])
        );
        // Nothing within the tolerance of a problem vertex: nothing moves.
        let (count, _) = merge_near(&mut mesh, &[2], tolerance);
        assert_eq!(count, 0);
    }

    #[test]
    fn exact_meshes_have_no_problem() {
        let mesh = cube(0.0, 1.0);
        let moved = vec![true; mesh.vertex_count()];
        assert!(find_problems(&mesh, &moved).is_empty());
    }

    #[test]
    fn a_crossing_near_a_moved_vertex_is_found() {
        // Two cubes in one mesh, overlapping: every crossing involves a moved vertex of the
        // second one.
        let (a, b) = (cube(0.0, 1.0), cube(0.5, 1.5));
        let mut positions = a.positions().to_vec();
        positions.extend_from_slice(b.positions());
        let triangles: Vec<[u32; 3]> = (a.faces().map(|f| [f[0], f[1], f[2]]))
            .chain(b.faces().map(|f| [f[0] + 8, f[1] + 8, f[2] + 8]))
            .collect();
        let mesh = Mesh::from_triangles(positions, &triangles).expect("indices below 16");
        let mut moved = vec![false; 16];
        moved[8..].iter_mut().for_each(|m| *m = true);
        let problems = find_problems(&mesh, &moved);
        assert!(!problems.pairs.is_empty());
        assert!(
            problems.to_snap.iter().any(|&v| v < 8) && problems.to_snap.iter().any(|&v| v >= 8)
        );
        // Nothing moved: nothing to look at.
        assert!(find_problems(&mesh, &[false; 16]).is_empty());
    }

    #[test]
    fn collinear_and_coincident_vertices_are_found() {
        let positions = vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let mesh = Mesh::from_triangles(positions, &[[0, 1, 2], [0, 3, 4]]).expect("in range");
        let problems = find_problems(&mesh, &[false, true, false, true, false]);
        assert_eq!(problems.degenerate_faces, 1);
        assert_eq!(problems.coincident.len(), 1);
    }

    #[test]
    fn a_corner_rounded_across_an_edge_is_rounded_back() {
        // Two triangles on one side of their common edge: the second's corner, rounded to
        // the smallest positive y, folds it over the first. A step of one ulp unfolds it.
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, f64::from_bits(1), 0.0],
        ];
        let mut mesh = Mesh::from_triangles(positions, &[[0, 1, 2], [1, 0, 3]]).expect("in range");
        let moved = [false, false, false, true];
        let problems = find_problems(&mesh, &moved);
        assert_eq!(problems.pairs.len(), 1);
        let work = std::cell::Cell::new(0);
        let (count, displacement) = reround(
            &mut mesh,
            &REROUND_PASSES[0],
            Precision::F64,
            &moved,
            &problems,
            &work,
        );
        assert_eq!(count, 1);
        assert!(displacement > 0.0 && displacement < 1e-15);
        assert!(find_problems(&mesh, &moved).is_empty());
    }

    #[test]
    fn re_rounding_makes_no_coordinate_subnormal() {
        let around_zero = neighbours([0.0, 1.0, 2.0], 2, Precision::F64);
        assert!(around_zero.iter().all(|q| !q[0].is_subnormal()));
        // 0 stays; the other two coordinates take their five values each.
        assert_eq!(around_zero.len(), 5 * 5 - 1);
        // A coordinate that is subnormal already may step on.
        let tiny = f64::from_bits(1);
        assert!(
            neighbours([tiny, 1.0, 2.0], 1, Precision::F64)
                .iter()
                .any(|q| q[0] == 2.0 * tiny)
        );
    }

    #[test]
    fn coincident_vertices_merge_and_collapsed_faces_go() {
        let positions = vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let mesh = Mesh::from_triangles(positions, &[[0, 1, 2], [0, 2, 3]]).expect("in range");
        let (merged, moved) = merge_coincident(mesh, &[false, false, true, false]);
        assert_eq!(merged.vertex_count(), 3);
        assert_eq!(merged.face_count(), 1);
        assert_eq!(moved, [false, true, false]);
    }

    #[test]
    fn snapping_is_exact_and_bounded() {
        let mut mesh = Mesh::from_triangles(
            vec![[0.1, 0.2, 0.3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[[0, 1, 2]],
        )
        .expect("in range");
        let d = snap(&mut mesh, &[0], MAX_SNAP_LEVEL, Precision::F64);
        let step = 2f64.powi(MAX_SNAP_LEVEL - 52);
        for x in mesh.positions()[0] {
            assert_eq!((x / step).fract(), 0.0, "{x} is on the grid");
        }
        assert!(d > 0.0 && d <= step * 3f64.sqrt() / 2.0 / 2f64.sqrt());
    }

    #[test]
    fn provenance_is_carried_through_a_re_refinement() {
        let mut soup = cube(0.0, 1.0).into_parts();
        let source: Vec<Provenance> = (0..12)
            .map(|f| Provenance {
                operand: OperandId::new(1),
                face: FaceId::new(100 + f),
            })
            .collect();
        soup.face_provenance = Some(source);
        let soup = Mesh::from_parts(soup).expect("one provenance per face");
        let mut refined = cube(0.0, 1.0).into_parts();
        refined.face_provenance = Some(
            (0..12)
                .map(|f| Provenance {
                    operand: OperandId::new(0),
                    face: FaceId::new(11 - f),
                })
                .collect(),
        );
        let refined = Mesh::from_parts(refined).expect("one provenance per face");
        let carried = with_source_provenance(refined, &soup);
        let first = carried.parts().face_provenance.as_ref().expect("kept")[0];
        assert_eq!(first.operand, OperandId::new(1));
        assert_eq!(first.face, FaceId::new(111));
    }
}
