//! The **ingest** stage (`design/exact.md`, stage 1): every operand becomes triangles over one
//! shared, welded vertex array, checked to bound a solid.
//!
//! # Contract
//! In: the operands, any polygon meshes. Out: [`Input`], in which
//! - positions of all operands are welded together (bit-identical coordinates, `-0.0` equal to
//!   `0.0`), so a vertex two operands share has one id and the intersect stage recognises
//!   shared vertices by id;
//! - every face is triangulated by the mesh module's exact triangulator
//!   ([`triangulate_faces`]: a polygon whose projection overlaps itself is an error), keeping
//!   its face id, and exactly degenerate triangles (collinear corners, by the exact orientation
//!   test) are dropped;
//! - the triangles of each operand are contiguous and each operand is closed and consistently
//!   oriented: every undirected edge is used as often in each direction (non-manifold but
//!   balanced edges, as in two cubes sharing an edge, are solids too), counting the dropped
//!   degenerate triangles (a flat triangle is a T-junction between its neighbours, which the
//!   arrangement resolves, not a hole), with a non-negative volume;
//! - two-sided sheets (triangles of one operand over the same three vertices in opposite
//!   orientations) are dropped: they add nothing to any winding number, and their faces have
//!   no inside for classification to sample. A triangle repeated in the same orientation
//!   doubles the winding number behind it ([`Input::has_repeats`] sends the operands to the
//!   winding classification), except where it unbalances edges: an operand whose only fault
//!   is a face written twice is closed without the repeat;
//! - coordinates are multiplied by [`Input::scale`], an exact power of two chosen so that the
//!   largest magnitude is near 1 when it is far from it, so predicate arithmetic on inputs
//!   like ±3.4e38 neither overflows nor leaves the fast filters. The scale is applied only
//!   when every coordinate stays a normal f64, which makes it exact.
//!
//! Errors name the operand and the first offending vertices or edges, in the operand's own
//! vertex numbering.
//!
//! [`self_intersecting_pairs`] (and [`self_intersecting_pairs_at`], for a mesh known to be
//! clean away from some vertices) find the triangle pairs of one operand that cross; the
//! driver adds them to the arrangement.
//!
//! # Complexity
//! One hash pass to weld, one parallel sort of the `3 n` half-edges for the edge checks and
//! the neighbour table that classification floods across.

use crate::par::*;

use crate::index::{Aabb, Bvh};
use crate::kernel::Point3;
use crate::mesh::vector::{cross, dot, sub};
use crate::mesh::weld_positions_by;
use crate::mesh::{FaceId, Mesh, PolygonError, coincident_triangles, triangulate_faces};
use crate::progress::{Cancelled, Progress, Stage};

use super::intersect::{IndexedTriangle, Triangle};

/// Why an operand cannot enter the exact engine: it is not a closed, outward solid of finite
/// coordinates. Every variant names the operand (its index in the order given) and where the
/// problem is.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum InvalidOperand {
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
}

impl InvalidOperand {
    /// The index of the operand at fault, in the order given.
    pub fn operand(&self) -> usize {
        match *self {
            InvalidOperand::NonFinite { operand, .. }
            | InvalidOperand::InvalidPolygon { operand, .. }
            | InvalidOperand::NotClosed { operand, .. }
            | InvalidOperand::Inverted { operand, .. } => operand,
        }
    }
}

fn format_edges(edges: &[[u32; 2]]) -> String {
    let list: Vec<String> = edges.iter().map(|[a, b]| format!("{a}–{b}")).collect();
    list.join(", ")
}

/// How many unbalanced edges [`InvalidOperand::NotClosed`] lists.
const ERROR_EXAMPLES: usize = 5;

/// "No neighbour" in [`Input::neighbours`].
pub(crate) const NO_NEIGHBOUR: u32 = u32::MAX;

/// The operands, ready for the pipeline.
pub(crate) struct Input {
    /// Welded, scaled positions of all operands.
    pub positions: Vec<Point3>,
    /// The exact power of two every coordinate was multiplied by.
    pub scale: f64,
    /// All triangles, by vertex ids into `positions` ([`Input::triangle`] gives one whole,
    /// its [`Triangle::id`] being its index here).
    pub triangles: Vec<IndexedTriangle>,
    /// The operand of each triangle.
    pub operand: Vec<u32>,
    /// The original face of each triangle, in its operand.
    pub face: Vec<FaceId>,
    /// The triangles of operand `k`: `operand_starts[k]..operand_starts[k + 1]`.
    pub operand_starts: Vec<u32>,
    /// The bounding box of each operand's vertices (scaled), which holds its triangles.
    pub operand_boxes: Vec<Aabb>,
    /// For each triangle side `3 t + i` (from corner `i` to `i + 1`), the triangle across it
    /// when that edge has exactly two uses, both in this operand, in opposite directions;
    /// [`NO_NEIGHBOUR`] otherwise.
    pub neighbours: Vec<u32>,
    /// Whether an operand holds a triangle twice over the same vertices in the same
    /// orientation, its edges balanced (a shell written twice, or nested shells sharing a
    /// face): such coincident faces double the winding number behind them, which only the
    /// winding classification counts.
    pub has_repeats: bool,
}

impl Input {
    /// The number of operands.
    pub(crate) fn operand_count(&self) -> usize {
        self.operand_starts.len() - 1
    }

    /// The triangle index range of operand `k`.
    pub(crate) fn operand_triangles(&self, k: usize) -> std::ops::Range<usize> {
        self.operand_starts[k] as usize..self.operand_starts[k + 1] as usize
    }

    /// Triangle `t`, with its positions and its index as id.
    #[inline]
    pub(crate) fn triangle(&self, t: usize) -> Triangle {
        self.triangles[t].with_positions(t as u32, &self.positions)
    }

    /// The corner positions of triangle `t`.
    #[inline]
    pub(crate) fn triangle_positions(&self, t: usize) -> [Point3; 3] {
        self.triangles[t]
            .vertices()
            .map(|v| self.positions[v as usize])
    }

    /// The box of triangle `t`.
    #[inline]
    pub(crate) fn triangle_box(&self, t: usize) -> Aabb {
        Aabb::from_points(self.triangle_positions(t).iter())
    }
}

/// Builds the [`Input`] of `operands`.
///
/// # Errors
/// [`InvalidOperand::NonFinite`], [`InvalidOperand::InvalidPolygon`], [`InvalidOperand::NotClosed`]
/// or [`InvalidOperand::Inverted`], naming the first operand that fails.
pub(crate) fn ingest(operands: &[&Mesh]) -> Result<Input, InvalidOperand> {
    let (scale, operand_boxes) = scale_and_boxes(operands)?;
    // Vertex `v` of the operands' positions one after another, read where each operand keeps
    // them rather than copied into one array.
    let offsets = vertex_offsets(operands);
    let raw = |v: u32| {
        let k = offsets.partition_point(|&start| start <= v as usize) - 1;
        operands[k].positions()[v as usize - offsets[k]]
    };
    let welding = weld_positions_by(offsets[operands.len()], raw);
    let positions: Vec<Point3> = (welding.representatives.par_iter())
        .map(|&v| raw(v).map(|x| x * scale))
        .collect();

    // Each operand's triangles are written once, in place (an indexed parallel extend); the
    // exactly degenerate ones, rare, stay `None` until one in-place pass takes them out.
    let triangulations = (operands.iter().enumerate())
        .map(|(k, mesh)| {
            triangulate_faces(mesh)
                .map_err(|error| InvalidOperand::InvalidPolygon { operand: k, error })
        })
        .collect::<Result<Vec<_>, _>>()?;
    // Sized for all operands at once: grown operand by operand, the second one's triangles
    // moved the first one's to a new block (two 100 k-triangle spheres: 4.3 ms for the
    // second against 2.6 for the first).
    let total: usize = triangulations.iter().map(|t| t.len()).sum();
    let mut made_faces: (Vec<FaceId>, Vec<Option<IndexedTriangle>>) =
        (Vec::with_capacity(total), Vec::with_capacity(total));
    let mut operand = Vec::with_capacity(total);
    let mut degenerate = Vec::new();
    let mut vertex_offset = 0usize;
    for (k, (mesh, triangulation)) in operands.iter().zip(&triangulations).enumerate() {
        let remap = &welding.remap[vertex_offset..vertex_offset + mesh.vertex_count()];
        let welded = |corners: [u32; 3]| corners.map(|v| remap[v as usize]);
        let own_positions = mesh.positions();
        let start = made_faces.1.len();
        made_faces.par_extend(triangulation.par_iter().map(|(f, corners)| {
            // The corners' positions read from the operand's own array, not the welded one
            // through the welded ids: the same numbers (scaled exactly; only a zero's sign
            // may differ, which no orientation sees), and the reads do not wait for the
            // ids' (two 1 M spheres, whose vertex numbering scatters each face's corners
            // through memory: ingest 415 → 370 ms, medians of seven runs).
            let corner_positions = corners.map(|v| own_positions[v as usize].map(|x| x * scale));
            let made = Triangle::new(0, welded(corners), corner_positions);
            (f, made.map(|t| t.indexed()))
        }));
        let made = &made_faces.1;
        let flat = (made[start..].par_iter().zip(triangulation.par_iter()))
            .filter(|(made, _)| made.is_none())
            .map(|(_, (_, corners))| (k as u32, welded(corners)));
        degenerate.par_extend(flat);
        // On every thread, as the records were: a fill on one first touched its pages alone.
        let count = made.len() - operand.len();
        operand.par_extend((0..count).into_par_iter().map(|_| k as u32));
        vertex_offset += mesh.vertex_count();
    }
    let (mut face, made) = made_faces;
    if !degenerate.is_empty() {
        operand = of_made(operand, &made);
        face = of_made(face, &made);
    }
    // `filter_map` rather than `flatten`: the standard library collects it in place, in the
    // allocation of `made`, where `flatten` would copy every triangle to a new one.
    #[allow(clippy::filter_map_identity)]
    let triangles: Vec<IndexedTriangle> = made.into_iter().filter_map(|t| t).collect();
    let operand_starts: Vec<u32> = (0..=operands.len())
        .map(|k| operand.partition_point(|&o| (o as usize) < k) as u32)
        .collect();
    let mut input = Input {
        positions,
        scale,
        triangles,
        operand,
        face,
        operand_starts,
        operand_boxes,
        neighbours: Vec::new(),
        has_repeats: false,
    };
    let link = |input: &Input| link_edges(input, &degenerate, operands, &welding.remap, &offsets);
    let dropped = match link(&input) {
        Ok(neighbours) => {
            input.neighbours = neighbours;
            let (sheets, repeats) =
                coincident_within_operands(&input, &coincidence_candidates(&input));
            input.has_repeats = !repeats.is_empty();
            sheets
        }
        // A face a file holds twice unbalances its edges: the operand may close without the
        // repeat (and without any sheet).
        Err(error) => {
            let all: Vec<u32> = (0..input.triangles.len() as u32).collect();
            let (mut sheets, repeats) = coincident_within_operands(&input, &all);
            if repeats.is_empty() {
                return Err(error);
            }
            sheets.extend(repeats);
            sheets.sort_unstable();
            sheets
        }
    };
    if !dropped.is_empty() {
        input = without_triangles(input, &dropped);
        input.neighbours = link(&input)?;
    }
    for k in 0..operands.len() {
        let volume = signed_volume(&input, k);
        if volume < 0.0 {
            return Err(InvalidOperand::Inverted {
                operand: k,
                volume: volume / (input.scale * input.scale * input.scale),
            });
        }
    }
    Ok(input)
}

/// The entries of `per_triangle` whose triangle was made (is not degenerate).
fn of_made<T>(per_triangle: Vec<T>, made: &[Option<IndexedTriangle>]) -> Vec<T> {
    (per_triangle.into_iter().zip(made))
        .filter_map(|(x, t)| t.is_some().then_some(x))
        .collect()
}

/// The triangles that can be coincident with another of their operand, sorted: those with a
/// side that links no neighbour, or whose three sides link one neighbour. A two-sided sheet
/// or a repeated triangle makes its edges non-manifold (four uses), and those link nothing;
/// a triangle whose reverse is the only other use of its edges links it across all three
/// sides. Read from the links alone (the triangles' vertices only where they are needed), so
/// a clean operand costs one sequential pass over its sides.
fn coincidence_candidates(input: &Input) -> Vec<u32> {
    (input.neighbours.par_chunks(3).enumerate())
        .filter(|(_, links)| {
            links.contains(&NO_NEIGHBOUR) || (links[0] == links[1] && links[1] == links[2])
        })
        .map(|(t, _)| t as u32)
        .collect()
}

/// Among `candidates` (sorted), the coincident triangles of one operand
/// ([`coincident_triangles`]), each list sorted:
/// - both triangles of every two-sided sheet (a pair over the same three vertices in
///   opposite orientations), which files written by other tools (and rounded results) carry
///   where a sliver collapsed flat. A sheet adds nothing to any winding number, so without it
///   the operand is the same solid, and its faces have no inside to sample: it is dropped;
/// - every repeat of a triangle in the same orientation, which files carry where geometry was
///   written twice or where nested shells share a face. A repeat doubles the winding number
///   behind its face; it is dropped only where it leaves edges unbalanced (a face written
///   twice), and otherwise sends the operand to the winding classification.
fn coincident_within_operands(input: &Input, candidates: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let (mut sheets, mut repeats) = (Vec::new(), Vec::new());
    let mut rest = candidates;
    for k in 0..input.operand_count() {
        let end = input.operand_starts[k + 1];
        let (own, tail) = rest.split_at(rest.partition_point(|&t| t < end));
        let triangles = own
            .iter()
            .map(|&t| (t, input.triangles[t as usize].vertices()));
        let (pairs, repeated) = coincident_triangles(triangles);
        sheets.extend(pairs.into_iter().flatten());
        repeats.extend(repeated);
        rest = tail;
    }
    sheets.sort_unstable();
    repeats.sort_unstable();
    (sheets, repeats)
}

/// `input` without the triangles `removed` (sorted), renumbered; the neighbour links are
/// left for the caller to rebuild.
fn without_triangles(input: Input, removed: &[u32]) -> Input {
    let kept = |t: &usize| removed.binary_search(&(*t as u32)).is_err();
    let all = 0..input.triangles.len();
    let triangles: Vec<IndexedTriangle> = all
        .clone()
        .filter(kept)
        .map(|t| input.triangles[t])
        .collect();
    let operand: Vec<u32> = all.clone().filter(kept).map(|t| input.operand[t]).collect();
    let face: Vec<FaceId> = all.filter(kept).map(|t| input.face[t]).collect();
    let operand_starts = (input.operand_starts.iter())
        .map(|&start| start - removed.partition_point(|&t| t < start) as u32)
        .collect();
    Input {
        triangles,
        operand,
        face,
        operand_starts,
        neighbours: Vec::new(),
        ..input
    }
}

/// The first vertex index of each operand in the concatenated positions.
fn vertex_offsets(operands: &[&Mesh]) -> Vec<usize> {
    let mut offsets = vec![0];
    for mesh in operands {
        offsets.push(offsets.last().copied().unwrap_or(0) + mesh.vertex_count());
    }
    offsets
}

/// A power of two that brings the largest magnitude of the operands' coordinates near 1
/// when it lies outside `[2^-64, 2^64]`, if every coordinate stays a normal number (so the
/// scaling is exact); otherwise 1. With it, each operand's bounding box, scaled.
///
/// The box is of the operand's vertices, a superset of its triangles' corners where a file
/// has unused vertices: the broad phase, its one reader, only asks where operands' boxes
/// overlap before it tests triangles. Taken in this pass over the positions in order, where
/// a pass over the triangles read three scattered corners each (two 1 M-triangle spheres:
/// 8–12 ms).
///
/// # Errors
/// [`InvalidOperand::NonFinite`] for the first vertex with a NaN or infinite coordinate.
fn scale_and_boxes(operands: &[&Mesh]) -> Result<(f64, Vec<Aabb>), InvalidOperand> {
    // The largest and the smallest nonzero magnitude, and whether all are finite, in one
    // pass on every core (one sequential pass took 12 ms on the million vertices of two 1 M
    // triangle spheres, and the finiteness check another 3).
    let (mut largest, mut smallest) = (0.0f64, f64::INFINITY);
    let mut boxes = Vec::with_capacity(operands.len());
    for (k, mesh) in operands.iter().enumerate() {
        let (high, low, all_finite, bounds) = (mesh.positions().par_chunks(4096))
            .map(|chunk| {
                let (mut high, mut low, mut all_finite) = (0.0f64, f64::INFINITY, true);
                for x in chunk.iter().flatten().map(|x| x.abs()) {
                    all_finite &= x.is_finite();
                    high = if x > high { x } else { high };
                    low = if x > 0.0 && x < low { x } else { low };
                }
                (high, low, all_finite, Aabb::from_points(chunk))
            })
            .reduce_with(|a, b| (a.0.max(b.0), a.1.min(b.1), a.2 && b.2, a.3.union(&b.3)))
            .unwrap_or((0.0, f64::INFINITY, true, Aabb::EMPTY));
        if !all_finite {
            let vertex = (mesh.positions().iter())
                .position(|p| !p.iter().all(|x| x.is_finite()))
                .unwrap_or(0);
            return Err(InvalidOperand::NonFinite {
                operand: k,
                vertex: vertex as u32,
            });
        }
        (largest, smallest) = (largest.max(high), smallest.min(low));
        boxes.push(bounds);
    }
    let scale = if largest == 0.0 || (2f64.powi(-64)..=2f64.powi(64)).contains(&largest) {
        1.0
    } else {
        let exponent = -(largest.log2().floor() as i32);
        let scale = 2f64.powi(exponent);
        let exact = smallest * scale >= f64::MIN_POSITIVE && (largest * scale).is_finite();
        if exact { scale } else { 1.0 }
    };
    // Exact, as the scaling of every coordinate is.
    let scaled = |b: Aabb| Aabb {
        min: b.min.map(|x| x * scale),
        max: b.max.map(|x| x * scale),
    };
    Ok((scale, boxes.into_iter().map(scaled).collect()))
}

/// Checks that every edge of every operand is balanced, and links each triangle side to the
/// triangle across it where the edge is a plain two-sided edge of one operand. Operands are
/// linked side by side, each into its own part of the one table returned: an edge's uses are
/// counted within its operand only.
fn link_edges(
    input: &Input,
    degenerate: &[(u32, [u32; 3])],
    operands: &[&Mesh],
    remap: &[u32],
    offsets: &[usize],
) -> Result<Vec<u32>, InvalidOperand> {
    // Zeroed pages cost nothing until touched: each operand's part is filled on its own
    // thread, where one fill of the whole 24 MB table came first on one (two 1 M-triangle
    // spheres: the linking 75 → 63 ms, medians of five runs).
    let mut neighbours = vec![0; 3 * input.triangles.len()];
    let parts = split_lengths_mut(
        &mut neighbours,
        (0..operands.len()).map(|k| 3 * input.operand_triangles(k).len()),
    );
    let unbalanced: Vec<Unbalanced> = (parts.into_par_iter().enumerate())
        .map(|(k, own)| {
            // The sides of the operand's degenerate triangles count for balance but link
            // nothing. A side from a vertex to itself is no edge.
            let flat: Vec<[u32; 2]> = (degenerate.iter())
                .filter(|&&(owner, _)| owner as usize == k)
                .flat_map(|&(_, t)| (0..3).map(move |i| [t[i], t[(i + 1) % 3]]))
                .filter(|&[a, b]| a != b)
                .collect();
            // The welded ids of the operand's own vertices bound the ids its sides use,
            // read from its vertices rather than from three times as many sides.
            let ids = remap[offsets[k]..offsets[k + 1]].iter().copied();
            let (lowest, highest) = ids.fold((u32::MAX, 0), |(lo, hi), v| (lo.min(v), hi.max(v)));
            link_operand(input, k, &flat, (lowest, highest), own)
        })
        .collect();
    if let Some(k) = unbalanced.iter().position(|u| u.count > 0) {
        // The operand's own index of a welded vertex (the welded representative may belong
        // to another operand). Only on this error path, so a scan is fine.
        let local = |v: u32| {
            let own = offsets[k]..offsets[k + 1];
            let raw = own.clone().find(|&r| remap[r] == v).unwrap_or(own.start);
            (raw - offsets[k]) as u32
        };
        return Err(InvalidOperand::NotClosed {
            operand: k,
            count: unbalanced[k].count,
            first: (unbalanced[k].first.iter())
                .map(|&[a, b]| [local(a), local(b)])
                .collect(),
        });
    }
    Ok(neighbours)
}

/// The unbalanced edges [`link_operand`] finds in one operand.
struct Unbalanced {
    /// How many edges are unbalanced.
    count: usize,
    /// The first [`ERROR_EXAMPLES`] of them (welded vertex ids, smaller first), in that order.
    first: Vec<[u32; 2]>,
}

/// Counts the uses of every edge of operand `k` in each direction, its triangles' sides and
/// then the `flat` sides of its degenerate triangles, and links the sides of each edge used
/// exactly twice, once each way: `neighbours[3 t + i]` (`t` counted from the operand's first
/// triangle) becomes the triangle across side `i` of `t`, every other entry [`NO_NEIGHBOUR`].
/// Every side's ends lie in `lowest..=highest`.
fn link_operand(
    input: &Input,
    k: usize,
    flat: &[[u32; 2]],
    (lowest, highest): (u32, u32),
    neighbours: &mut [u32],
) -> Unbalanced {
    /// Buckets per parallel task when sorting them.
    const BLOCK: usize = 1 << 12;
    neighbours.fill(NO_NEIGHBOUR);
    let range = input.operand_triangles(k);
    let triangles = &input.triangles[range.clone()];
    let side_count = 3 * triangles.len();
    let ends = |side: usize| match side.checked_sub(side_count) {
        Some(i) => flat[i],
        None => {
            let v = triangles[side / 3].vertices();
            [v[side % 3], v[(side % 3 + 1) % 3]]
        }
    };
    // One record per side, bucketed by its smaller vertex (a counting sort: linear, unlike one
    // sort of all sides), then each small bucket sorted by its larger vertex. Buckets span the
    // operand's own vertex ids only (each operand's vertices are mostly a range of the
    // welded ids, so two operands do not each pass over all of them). `bounds[b + 1]` counts
    // bucket `b`, then (summed) is where it starts; placing a side moves its bucket's start
    // one on, so that afterwards `bounds[b]` is where bucket `b` ends.
    let all_sides = side_count + flat.len();
    let bucket_count = (highest as usize + 1).saturating_sub(lowest as usize);
    let mut bounds = vec![0u32; bucket_count + 1];
    for side in 0..all_sides {
        let [a, b] = ends(side);
        bounds[(a.min(b) - lowest) as usize + 1] += 1;
    }
    for b in 1..bounds.len() {
        bounds[b] += bounds[b - 1];
    }
    // (larger vertex, side << 1 | forward).
    let mut sides = vec![(0u32, 0u32); all_sides];
    for side in 0..all_sides {
        let [a, b] = ends(side);
        let slot = &mut bounds[(a.min(b) - lowest) as usize];
        sides[*slot as usize] = (a.max(b), (side as u32) << 1 | u32::from(a < b));
        *slot += 1;
    }
    let bucket = |b: usize| {
        let start = if b == 0 { 0 } else { bounds[b - 1] };
        start as usize..bounds[b] as usize
    };
    let block_buckets: Vec<std::ops::Range<usize>> = block_ranges(bucket_count, BLOCK).collect();
    let block_sides = (block_buckets.iter()).map(|b| bucket(b.end - 1).end - bucket(b.start).start);
    let blocks = split_lengths_mut(&mut sides, block_sides);
    (blocks.into_par_iter().zip(block_buckets)).for_each(|(block, buckets)| {
        let base = bucket(buckets.start).start;
        for b in buckets {
            let own = bucket(b);
            block[own.start - base..own.end - base].sort_unstable();
        }
    });
    let mut unbalanced = Unbalanced {
        count: 0,
        first: Vec::new(),
    };
    for b in 0..bucket_count {
        for run in sides[bucket(b)].chunk_by(|s, t| s.0 == t.0) {
            let forward = run.iter().filter(|s| s.1 & 1 == 1).count();
            if 2 * forward != run.len() {
                unbalanced.count += 1;
                if unbalanced.first.len() < ERROR_EXAMPLES {
                    unbalanced.first.push([lowest + b as u32, run[0].0]);
                }
            } else if let [r, s] = run {
                let (p, q) = ((r.1 >> 1) as usize, (s.1 >> 1) as usize);
                if p < side_count && q < side_count {
                    neighbours[p] = (q / 3 + range.start) as u32;
                    neighbours[q] = (p / 3 + range.start) as u32;
                }
            }
        }
    }
    unbalanced
}

/// The signed volume of operand `k` (scaled), by the divergence theorem: the cones over its
/// triangles from the centre of its box. Any apex gives a closed operand's volume; one inside
/// the box keeps the products to the operand's own size. From the origin, a small part far
/// from it (a cube of side 0.5 at 10^6) cancelled to noise larger than its volume, and a valid
/// part read as inverted. Summed per block of triangles, then over the blocks in order, so the
/// sum does not depend on the thread count.
fn signed_volume(input: &Input, k: usize) -> f64 {
    /// Triangles per parallel task.
    const BLOCK: usize = 1 << 14;
    let bounds = &input.operand_boxes[k];
    let apex: Point3 = std::array::from_fn(|i| bounds.min[i] / 2.0 + bounds.max[i] / 2.0);
    let triangles = input.operand_triangles(k);
    let blocks: Vec<std::ops::Range<usize>> = block_ranges(triangles.len(), BLOCK).collect();
    let sums: Vec<f64> = (blocks.into_par_iter())
        .map(|block| {
            (block.map(|i| input.triangle_positions(triangles.start + i)))
                .map(|corners| {
                    let [a, b, c] = corners.map(|p| sub(p, apex));
                    dot(a, cross(b, c))
                })
                .sum::<f64>()
        })
        .collect();
    sums.iter().sum::<f64>() / 6.0
}

/// Every pair of triangles of one operand that intersect other than along what they share
/// (global triangle ids, `(smaller, larger)`), operand by operand: the exact check of
/// [`self_intersections`](super::self_intersections), whose pairs the driver adds to the
/// arrangement. Each operand checked is reported to `progress`.
///
/// Also returns the trees over each operand's triangles that the check walked where they
/// will serve again ([`TriangleTrees`]): both of two operands, which the broad phase walks
/// against each other, and otherwise those from the first operand found to intersect itself
/// on (or all, for operands with repeated faces), which the winding classification queries.
/// The others go, so that a check of many large simple operands holds one tree at a time.
///
/// # Errors
/// [`Cancelled`] when the run was cancelled.
pub(crate) fn self_intersecting_pairs<'a>(
    input: &'a Input,
    progress: &Progress,
) -> Result<(Vec<(u32, u32)>, TriangleTrees<'a>), Cancelled> {
    let counter = progress.counter(Stage::Validate, input.operand_count());
    let mut all = Vec::new();
    let trees = TriangleTrees::on_demand(input);
    for k in 0..input.operand_count() {
        let range = input.operand_triangles(k);
        let offset = range.start as u32;
        let (pairs, tree) = super::self_intersect::intersecting_pairs_and_tree(range.len(), |i| {
            input.triangle(range.start + i)
        });
        all.extend(pairs.into_iter().map(|(s, t)| (s + offset, t + offset)));
        if input.operand_count() == 2 || input.has_repeats || !all.is_empty() {
            trees.keep(k, tree);
        }
        counter.advance(1);
        progress.check()?;
    }
    counter.finish()?;
    Ok((all, trees))
}

/// A tree over the boxes of each operand's triangles, for queries over every triangle (the
/// winding classification's rays, one per patch, and the broad phase of two operands, where
/// both exist). The self-intersection check keeps the
/// trees it built when they will serve ([`self_intersecting_pairs`]); the first query builds
/// the others. Classification building a tree of its own over all triangles cost as much as
/// the rest of its work on dragon − offset (200 k triangles, 100 rays).
pub(crate) struct TriangleTrees<'a> {
    input: &'a Input,
    /// Per operand, a tree whose ids count from the operand's first triangle.
    trees: Vec<std::sync::OnceLock<Bvh>>,
}

impl<'a> TriangleTrees<'a> {
    /// No tree yet: each is built at the first query.
    pub(crate) fn on_demand(input: &'a Input) -> Self {
        let trees = (0..input.operand_count())
            .map(|_| Default::default())
            .collect();
        TriangleTrees { input, trees }
    }

    /// Keeps operand `k`'s tree, built by the caller.
    fn keep(&self, k: usize, tree: Bvh) {
        // A tree that is already there is the same tree.
        let _ = self.trees[k].set(tree);
    }

    /// Operand `k`'s tree if it exists, without building it.
    pub(crate) fn built(&self, k: usize) -> Option<&Bvh> {
        self.trees.get(k).and_then(std::sync::OnceLock::get)
    }

    /// Whether every tree exists (a query costs no build).
    pub(crate) fn are_built(&self) -> bool {
        self.trees.iter().all(|tree| tree.get().is_some())
    }

    /// Builds the trees not kept. Called before the parallel loops that query them: a tree
    /// built inside one, on its first query, could be asked for again by a job its own
    /// build's thread picks up while it waits, which a `OnceLock` does not allow.
    pub(crate) fn build_missing(&self) {
        for k in 0..self.trees.len() {
            self.tree(k);
        }
    }

    /// Operand `k`'s tree, built if it is missing.
    fn tree(&self, k: usize) -> &Bvh {
        self.trees[k].get_or_init(|| {
            let range = self.input.operand_triangles(k);
            Bvh::build_with(range.len(), |i| self.input.triangle_box(range.start + i))
        })
    }

    /// Calls `visit` with every triangle whose box overlaps `query`.
    pub(crate) fn visit_overlapping(&self, query: &Aabb, mut visit: impl FnMut(u32)) {
        for k in 0..self.trees.len() {
            let first = self.input.operand_starts[k];
            self.tree(k).visit_overlapping(query, |i| visit(first + i));
        }
    }
}

/// The pairs of [`self_intersecting_pairs`] that involve a triangle with a vertex at one of
/// `suspects` (unscaled positions): for operands known to be free of self-intersections away
/// from those vertices (a result whose vertices the certify stage moved).
pub(crate) fn self_intersecting_pairs_at(input: &Input, suspects: &[Point3]) -> Vec<(u32, u32)> {
    let key = |p: Point3| p.map(|x| (x + 0.0).to_bits());
    let at: rustc_hash::FxHashSet<[u64; 3]> = (suspects.iter())
        .map(|p| key(p.map(|x| x * input.scale)))
        .collect();
    let mut all = Vec::new();
    for k in 0..input.operand_count() {
        let range = input.operand_triangles(k);
        let offset = range.start as u32;
        let marked: Vec<u32> = (range.clone())
            .filter(|&t| {
                input
                    .triangle_positions(t)
                    .iter()
                    .any(|&p| at.contains(&key(p)))
            })
            .map(|t| (t - range.start) as u32)
            .collect();
        let triangle = |i: usize| input.triangle(range.start + i);
        let pairs = super::self_intersect::intersecting_pairs_of(range.len(), triangle, &marked);
        all.extend(pairs.into_iter().map(|(s, t)| (s + offset, t + offset)));
    }
    all
}
