//! The **intersect** and **split** stages (`design/exact.md`, stages 4 and 5), the paper's
//! subdivision: every candidate pair is intersected exactly, and every triangle that meets
//! another operand is triangulated with the contact points and segments on it.
//!
//! # Contract
//! Out: an [`Arrangement`]: sub-triangles covering every input triangle exactly once, over
//! one global vertex numbering (input vertices keep their ids; each distinct intersection
//! point gets one id after them), such that
//! - every contact segment is a union of sub-triangle edges in every triangle it lies on;
//! - the same point gets the same id in every triangle (canonical [`PointKey`]s, plus the
//!   exact merges [`split_triangle`] reports for coincident points with different keys), so a
//!   point on an edge splits it on both sides and no T-junction appears.
//!
//! Coplanar overlapping triangles of different operands each receive the boundary of their
//! overlap as constraints, so each is cut along the other's edges; classification finds the
//! sub-triangles in the shared region and selection keeps that region once.
//!
//! # Complexity
//! Linear in the candidate pairs (each an O(1) exact test, in parallel) plus the splits, each
//! independent and run in parallel; results are sorted by triangle, so the output does not
//! depend on the thread count.

use std::borrow::Cow;

use crate::par::*;
use rustc_hash::FxHashMap;

use crate::index::Aabb;
use crate::kernel::{Point, Sign, compare_lex, orient2d_projected, simplify};
use crate::mesh::union_find::UnionFind;
use crate::progress::{Cancelled, Progress, Stage};

use super::ingest::Input;
use super::intersect::{Contact, Feature, Intersection, PointKey, Triangle, intersect_triangles};
use super::split::split_triangle;

/// Why a stage after the intersections (split, classify, winding) stopped without a result.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum StageError {
    /// A configuration the stage cannot handle; the message says which. The driver turns it
    /// into `BooleanError::Unsupported`, or, from classify, tries winding numbers instead.
    Unsupported(String),
    /// The caller cancelled the run.
    Cancelled(Cancelled),
}

impl From<Cancelled> for StageError {
    fn from(cancelled: Cancelled) -> Self {
        StageError::Cancelled(cancelled)
    }
}

/// What one intersecting pair puts on one of its triangles. A mark names points by key only
/// (a key is at most 20 bytes; a point is 32, and an implicit one's clone counts a reference
/// on its shared definition), and the marks of two triangles and the points of one pair are
/// kept apart ([`Contacts`]), so each point is stored once per pair that finds it, not once
/// per mark. On two cubes the marks were most of the operation's fresh memory, and first
/// touches of fresh pages cost a few microseconds each.
#[derive(Clone, Copy, Debug)]
enum Mark {
    /// A contact point: an input vertex, or one of the pair's [`Contacts::points`].
    Point(PointKey),
    /// A contact segment between two points, on the line where `Support` meets the triangle.
    Segment(PointKey, PointKey, Support),
}

/// What carries a contact segment on a triangle `t`: needed to build the point where two
/// segments on `t` cross.
#[derive(Clone, Copy, Debug)]
enum Support {
    /// The plane of another (not coplanar) triangle: the segment lies on its line with `t`,
    /// through that triangle's interior (one along its edge has [`Support::Edge`]).
    Plane(u32),
    /// An input edge lying in the plane of `t`, as its sorted vertex ids.
    Edge([u32; 2]),
}

/// The contacts of every intersecting candidate pair, grouped by triangle.
pub(crate) struct Contacts {
    /// How many candidate pairs touch or cross.
    pub intersecting_pairs: usize,
    /// `(triangle, mark)`, sorted by triangle, and within a triangle in pair order.
    marks: Vec<(u32, Mark)>,
    /// The contact points that are not input vertices, as found by each pair, in pair order
    /// over the lists (one per run of candidates): a point found by several pairs is here
    /// once for each. Kept in the lists they were found in: joined, they would be copied
    /// once more, to fresh memory.
    points: Vec<Vec<(PointKey, Point)>>,
}

/// What the intersecting pairs of one run of candidates found, in pair order: one record per
/// run rather than per pair, so the many small pairs do not each allocate.
#[derive(Default)]
struct FoundContacts {
    intersecting_pairs: usize,
    /// The marks on both triangles of each pair.
    marks: Vec<(u32, Mark)>,
    /// The contact points that are not input vertices.
    points: Vec<(PointKey, Point)>,
}

/// Intersects every candidate pair exactly, reporting pairs done to `progress`.
///
/// # Errors
/// [`Cancelled`] when the run was cancelled.
pub(crate) fn intersect_pairs(
    input: &Input,
    pairs: &[(u32, u32)],
    progress: &Progress,
) -> Result<Contacts, Cancelled> {
    let counter = progress.counter(Stage::Intersect, pairs.len());
    let found: Vec<FoundContacts> = counter.par_chunks(pairs, |chunk, out| {
        let mut found = FoundContacts::default();
        for &(s, t) in chunk {
            let (a, b) = (input.triangle(s as usize), input.triangle(t as usize));
            add_contacts(&a, &b, &intersect_triangles(&a, &b), &mut found);
        }
        out.push(found);
    });
    counter.finish()?;
    let intersecting_pairs = found.iter().map(|f| f.intersecting_pairs).sum();
    let (marks, points): (Vec<_>, Vec<_>) = found.into_iter().map(|f| (f.marks, f.points)).unzip();
    let marks = marks.concat();
    // Grouped by triangle, and within a triangle in pair order, which is deterministic: a
    // stable radix sort of (triangle, place in pair order) by triangle, which moves 8 bytes
    // an item where a mark is 64 and passes only over the bytes of the triangle ids that
    // differ (one pass on two unit cubes, where a comparison sort of the keys was 6 % of the
    // boolean, and the stable sort of the marks themselves 7 %). A place fits in 32 bits:
    // 2^32 marks would be 256 GiB.
    let mut order: Vec<(u32, u32)> = (marks.iter().enumerate())
        .map(|(place, &(t, _))| (t, place as u32))
        .collect();
    radsort::sort_by_key(&mut order, |&(t, _)| t);
    let marks = (order.iter())
        .map(|&(_, place)| marks[place as usize])
        .collect();
    Ok(Contacts {
        intersecting_pairs,
        marks,
        points,
    })
}

/// Adds what an intersection of triangles `a` and `b` puts on each of them to `found`.
fn add_contacts(
    a: &Triangle,
    b: &Triangle,
    intersection: &Intersection,
    found: &mut FoundContacts,
) {
    let contacts: &[Contact] = match intersection {
        Intersection::Disjoint => return,
        Intersection::TouchingPoint(c) => std::slice::from_ref(c),
        Intersection::TouchingSegment(ends) | Intersection::Crossing(ends) => ends,
        Intersection::CoplanarOverlap(corners) => corners,
    };
    found.intersecting_pairs += 1;
    found.points.extend(
        (contacts.iter())
            .filter(|c| !matches!(c.key, PointKey::Vertex(_)))
            .map(|c| (c.key, c.point.clone())),
    );
    add_marks(a, b, intersection, &mut found.marks);
}

/// Adds the marks an intersection of triangles `a` and `b` puts on each of them to `marks`.
fn add_marks(
    a: &Triangle,
    b: &Triangle,
    intersection: &Intersection,
    marks: &mut Vec<(u32, Mark)>,
) {
    let (s, t) = (a.id(), b.id());
    let point = |c: &Contact| Mark::Point(c.key);
    let both = |mark: Mark| [(s, mark), (t, mark)];
    match intersection {
        Intersection::Disjoint => {}
        Intersection::TouchingPoint(c) => marks.extend(both(point(c))),
        Intersection::TouchingSegment([c, d]) | Intersection::Crossing([c, d]) => {
            marks.extend(both(point(c)));
            marks.extend(both(point(d)));
            // A segment along an edge of the other triangle is carried by that edge, so a
            // point where another segment crosses it gets the key the intersect stage gives
            // that point (edge × edge, edge × triangle), not a key naming the plane.
            let on_b =
                common_edge(c.on_b, d.on_b).map_or(Support::Plane(t), |i| Support::Edge(b.edge(i)));
            let on_a =
                common_edge(c.on_a, d.on_a).map_or(Support::Plane(s), |i| Support::Edge(a.edge(i)));
            marks.push((s, Mark::Segment(c.key, d.key, on_b)));
            marks.push((t, Mark::Segment(c.key, d.key, on_a)));
        }
        Intersection::CoplanarOverlap(corners) => {
            marks.extend(corners.iter().flat_map(|c| both(point(c))));
            for (i, c) in corners.iter().enumerate() {
                let d = &corners[(i + 1) % corners.len()];
                // Each side of the overlap lies along an edge of `b` or of `a`.
                let edge = match common_edge(c.on_b, d.on_b) {
                    Some(i) => b.edge(i),
                    None => a.edge(common_edge(c.on_a, d.on_a).unwrap_or(0)),
                };
                marks.extend(both(Mark::Segment(c.key, d.key, Support::Edge(edge))));
            }
        }
    }
}

/// The edge of a triangle containing two features of it, if any.
fn common_edge(f: Feature, g: Feature) -> Option<usize> {
    let edges = |x: Feature| match x {
        Feature::Vertex(i) => [Some(i), Some((i + 2) % 3)],
        Feature::Edge(i) => [Some(i), None],
        Feature::Face => [None, None],
    };
    let (ef, eg) = (edges(f), edges(g));
    ef.into_iter().flatten().find(|e| eg.contains(&Some(*e)))
}

/// The subdivided operands.
pub(crate) struct Arrangement {
    /// Intersection points; point `i` has vertex id `input.positions.len() + i`.
    pub points: Vec<Point>,
    /// Sub-triangles over global vertex ids, oriented like their source triangles, grouped
    /// by source: those of input triangle `t` are `sub_starts[t]..sub_starts[t + 1]`.
    pub triangles: Vec<[u32; 3]>,
    /// See `triangles`.
    pub sub_starts: Vec<u32>,
    /// The input triangle of each sub-triangle.
    pub source: Vec<u32>,
    /// Whether each input triangle has contacts (and was split, possibly into itself).
    pub touched: Vec<bool>,
    /// `(v, k)` for each input vertex `v` in a contact with a triangle of operand `k`
    /// (including `v`'s own operand), once per contact, in no order: classify sorts them
    /// only where a patch needs a ray, and most runs need none (on two unit cubes the sort
    /// here was 5 % of the boolean).
    pub contact_vertices: Vec<(u32, u32)>,
    /// How many input triangles were split.
    pub split_triangles: usize,
}

impl Arrangement {
    /// The number of vertex ids: input vertices, then intersection points.
    pub(crate) fn vertex_count(&self, input: &Input) -> usize {
        input.positions.len() + self.points.len()
    }

    /// The exact point of vertex `v`: an intersection point borrowed (a clone would count a
    /// reference on its shared definition, an atomic write that threads reading the same
    /// point contend on), an input vertex made from its coordinates.
    pub(crate) fn point(&self, input: &Input, v: u32) -> Cow<'_, Point> {
        let n = input.positions.len();
        match (v as usize).checked_sub(n) {
            Some(i) => Cow::Borrowed(&self.points[i]),
            None => Cow::Owned(Point::Explicit(input.positions[v as usize])),
        }
    }
}

/// Splits every triangle with contacts, reporting triangles done to `progress`.
///
/// # Errors
/// [`StageError::Unsupported`] when a triangle's constraints cross away from the contact
/// points (needs three-plane points that pairs of operands do not produce);
/// [`StageError::Cancelled`].
pub(crate) fn split(
    input: &Input,
    contacts: Contacts,
    progress: &Progress,
) -> Result<Arrangement, StageError> {
    let marks = contacts.marks;
    let (ids, points) = number_points(input.positions.len(), &contacts.points);
    drop(contacts.points);
    let groups: Vec<&[(u32, Mark)]> = marks.chunk_by(|x, y| x.0 == y.0).collect();
    let counter = progress.counter(Stage::Split, groups.len());
    let splits: Vec<Result<TriangleSplit, StageError>> =
        counter.par_chunks(&groups, |chunk, out| {
            out.extend(
                chunk
                    .iter()
                    .map(|group| split_one(input, group, &ids, &points)),
            );
        });
    counter.finish()?;
    let mut splits: Vec<TriangleSplit> = splits.into_iter().collect::<Result<_, _>>()?;
    let points = number_crossings(input, points, &ids, &mut splits);

    // Each id's kept id, where coincident points with different keys were merged.
    let kept_ids = splits.iter().any(|s| !s.merged.is_empty()).then(|| {
        let mut merges = UnionFind::new(input.positions.len() + points.len());
        for s in &splits {
            for &[a, b] in &s.merged {
                merges.union(a, b);
            }
        }
        merges.roots()
    });
    let (triangles, source, sub_starts) = sub_triangles(input, &splits, kept_ids.as_deref());
    let mut touched = vec![false; input.triangles.len()];
    for s in &splits {
        touched[s.triangle as usize] = true;
    }
    let contact_vertices: Vec<(u32, u32)> = (marks.iter())
        .filter_map(|&(t, m)| match m {
            Mark::Point(PointKey::Vertex(v)) => Some((v, input.operand[t as usize])),
            _ => None,
        })
        .collect();
    Ok(Arrangement {
        points,
        triangles,
        sub_starts,
        source,
        touched,
        contact_vertices,
        split_triangles: splits.len(),
    })
}

/// The arrangement's sub-triangles, the input triangle of each, and where each input
/// triangle's sub-triangles begin (one past the last at the end): a split triangle's pieces
/// in its place, every other triangle as it is, vertex ids replaced by `kept_ids` where
/// points merged. Written on all threads, a block of input triangles each: two million
/// entries on two 1 M spheres, which written by one thread into fresh pages took 35–40 ms
/// of the split stage's 50.
fn sub_triangles(
    input: &Input,
    splits: &[TriangleSplit],
    kept_ids: Option<&[u32]>,
) -> (Vec<[u32; 3]>, Vec<u32>, Vec<u32>) {
    let count = input.triangles.len();
    // Sub-triangles of the split triangles before each split triangle, and of all of them.
    let mut split_subs_before = Vec::with_capacity(splits.len() + 1);
    let mut split_subs = 0;
    for s in splits {
        split_subs_before.push(split_subs);
        split_subs += s.triangles.len();
    }
    split_subs_before.push(split_subs);
    // Where input triangle `t` begins: after one sub-triangle per unsplit triangle before it
    // and the pieces of the split ones; with the first split triangle at `t` or after it.
    let first_sub = |t: usize| {
        let next = splits.partition_point(|s| (s.triangle as usize) < t);
        (t - next + split_subs_before[next], next)
    };
    let total = first_sub(count).0;
    let mut triangles = vec![[0u32; 3]; total];
    let mut source = vec![0u32; total];
    let mut sub_starts = vec![0u32; count + 1];
    sub_starts[count] = total as u32;
    // Per block of input triangles: its first triangle, its first split triangle, and its
    // parts of the three arrays.
    let mut blocks = Vec::with_capacity(count.div_ceil(SUB_TRIANGLE_BLOCK));
    let (mut rest_triangles, mut rest_source, mut rest_starts) = (
        &mut triangles[..],
        &mut source[..],
        &mut sub_starts[..count],
    );
    for first in (0..count).step_by(SUB_TRIANGLE_BLOCK) {
        let end = (first + SUB_TRIANGLE_BLOCK).min(count);
        let (base, next) = first_sub(first);
        let subs = first_sub(end).0 - base;
        let (block_triangles, block_source, block_starts);
        (block_triangles, rest_triangles) = rest_triangles.split_at_mut(subs);
        (block_source, rest_source) = rest_source.split_at_mut(subs);
        (block_starts, rest_starts) = rest_starts.split_at_mut(end - first);
        blocks.push((
            first,
            base,
            next,
            block_triangles,
            block_source,
            block_starts,
        ));
    }
    blocks.into_par_iter().for_each(
        |(first, base, mut next, block_triangles, block_source, block_starts)| {
            let mut sub = 0;
            for (i, start) in block_starts.iter_mut().enumerate() {
                let t = first + i;
                *start = (base + sub) as u32;
                if splits.get(next).is_some_and(|s| s.triangle as usize == t) {
                    let pieces = &splits[next].triangles;
                    block_triangles[sub..sub + pieces.len()].copy_from_slice(pieces);
                    block_source[sub..sub + pieces.len()].fill(t as u32);
                    sub += pieces.len();
                    next += 1;
                } else {
                    block_triangles[sub] = input.triangles[t].vertices();
                    block_source[sub] = t as u32;
                    sub += 1;
                }
            }
            if let Some(kept) = kept_ids {
                for tri in block_triangles.iter_mut() {
                    *tri = tri.map(|v| kept[v as usize]);
                }
            }
        },
    );
    (triangles, source, sub_starts)
}

/// Input triangles per block of [`sub_triangles`].
const SUB_TRIANGLE_BLOCK: usize = 1 << 15;

/// Global vertex ids of the contact points: an input vertex keeps its id; every other key
/// gets the next id, in key order (deterministic).
fn number_points(
    vertex_count: usize,
    found: &[Vec<(PointKey, Point)>],
) -> (FxHashMap<PointKey, u32>, Vec<Point>) {
    // Keys with references to their points: the sort moves small tuples, not the points.
    // Triangle pairs that find one point may define it differently (an edge's line from
    // either end, a plane from either triangle of a planar quad), and the definition kept
    // decides how often the kernel's filter can answer for it: each key keeps the one whose
    // filter encloses the point in the smallest box (on rotated_z_union, 23 M instructions
    // against 33 M with the first found), then the first found. A total order, so every
    // build keeps the same one (rayon's and the standard library's unstable sorts order ties
    // differently).
    let mut keyed: Vec<(PointKey, f64, usize, &Point)> = (found.iter().flatten().enumerate())
        .map(|(index, (key, point))| (*key, enclosure_size(point), index, point))
        .collect();
    keyed.par_sort_unstable_by(|x, y| {
        (x.0.cmp(&y.0))
            .then(x.1.total_cmp(&y.1))
            .then(x.2.cmp(&y.2))
    });
    keyed.dedup_by(|x, y| x.0 == y.0);
    let n = vertex_count as u32;
    let ids = (keyed.iter().enumerate())
        .map(|(i, (key, ..))| (*key, n + i as u32))
        .collect();
    let points: Vec<Point> = (keyed.into_par_iter())
        .map(|(.., p)| simplify(p.clone()))
        .collect();
    (ids, points)
}

/// The largest side of the box the kernel's filter encloses `point` in (infinite when it
/// cannot bound it).
fn enclosure_size(point: &Point) -> f64 {
    let (lo, hi) = point.enclosure();
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    if size.is_nan() { f64::INFINITY } else { size }
}

/// The global id of a key.
fn global_id(key: &PointKey, ids: &FxHashMap<PointKey, u32>) -> u32 {
    match key {
        PointKey::Vertex(v) => *v,
        other => ids[other],
    }
}

/// Marks a vertex id in a [`TriangleSplit`] as an index into its `crossings`, until
/// [`number_crossings`] gives crossing points their global ids.
const CROSSING: u32 = 1 << 31;

/// The sub-triangles of one input triangle.
struct TriangleSplit {
    triangle: u32,
    triangles: Vec<[u32; 3]>,
    /// `[merged, kept]` ids of coincident points with different keys.
    merged: Vec<[u32; 2]>,
    /// Points where two segments cross inside the triangle; id `CROSSING | i` is `i`.
    crossings: Vec<(PointKey, Point)>,
}

/// Gives the crossing points found by the splits global ids, and rewrites the splits'
/// placeholder ids: a crossing whose key is already a contact point's (two edges that cross
/// inside a triangle of a third operand also meet in their own triangles) takes that
/// point's id; the others get ids after the contact points, in key order. Returns all
/// intersection points.
fn number_crossings(
    input: &Input,
    mut points: Vec<Point>,
    ids: &FxHashMap<PointKey, u32>,
    splits: &mut [TriangleSplit],
) -> Vec<Point> {
    if splits.iter().all(|s| s.crossings.is_empty()) {
        return points;
    }
    let mut found: Vec<(PointKey, Point)> = (splits.iter())
        .flat_map(|s| s.crossings.iter().cloned())
        .filter(|(key, _)| !ids.contains_key(key))
        .collect();
    found.sort_unstable_by_key(|x| x.0);
    found.dedup_by(|x, y| x.0 == y.0);
    let first = (input.positions.len() + points.len()) as u32;
    let id_of = |key: &PointKey| match ids.get(key) {
        Some(&id) => id,
        None => {
            first
                + found
                    .binary_search_by(|x| x.0.cmp(key))
                    .expect("every crossing was found") as u32
        }
    };
    for s in splits.iter_mut() {
        if s.crossings.is_empty() {
            continue;
        }
        let global: Vec<u32> = s.crossings.iter().map(|(key, _)| id_of(key)).collect();
        let fix = |v: u32| {
            if v & CROSSING != 0 {
                global[(v & !CROSSING) as usize]
            } else {
                v
            }
        };
        for tri in &mut s.triangles {
            *tri = tri.map(fix);
        }
        for m in &mut s.merged {
            *m = m.map(fix);
        }
    }
    points.extend(found.into_iter().map(|(_, p)| p));
    points
}

/// Splits the triangle the marks of `group` are on.
fn split_one(
    input: &Input,
    group: &[(u32, Mark)],
    ids: &FxHashMap<PointKey, u32>,
    contact_points: &[Point],
) -> Result<TriangleSplit, StageError> {
    let t = group[0].0;
    let tri = input.triangle(t as usize);
    // Local ids: corners 0..3, then points in first-seen order; `global` holds their ids.
    let mut global: Vec<u32> = tri.vertices().to_vec();
    let mut local_of: FxHashMap<u32, u32> = (global.iter().enumerate())
        .map(|(i, &g)| (g, i as u32))
        .collect();
    let mut points = Vec::new();
    for (_, mark) in group {
        if let Mark::Point(key) = mark {
            let g = global_id(key, ids);
            local_of.entry(g).or_insert_with(|| {
                global.push(g);
                // The numbered point: an implicit one may have become explicit.
                let n = input.positions.len();
                points.push(match (g as usize).checked_sub(n) {
                    Some(i) => contact_points[i].clone(),
                    None => Point::Explicit(input.positions[g as usize]),
                });
                (global.len() - 1) as u32
            });
        }
    }
    let mut segments: Vec<([u32; 2], Support)> = Vec::new();
    for (_, mark) in group {
        if let Mark::Segment(a, b, support) = mark {
            let (a, b) = (local_of[&global_id(a, ids)], local_of[&global_id(b, ids)]);
            if a != b {
                segments.push(([a.min(b), a.max(b)], *support));
            }
        }
    }
    // Of the supports of one segment, keep an edge if there is one (see `add_marks`); the
    // sort is stable, so the choice does not depend on the thread count.
    segments.sort_by_key(|s| (s.0, matches!(s.1, Support::Plane(_))));
    segments.dedup_by_key(|s| s.0);
    let crossings = cut_crossing_segments(input, t, &mut points, &mut segments);
    for i in 0..crossings.len() {
        global.push(CROSSING | i as u32);
    }
    let segments: Vec<[u32; 2]> = segments.iter().map(|s| s.0).collect();
    let split = split_triangle(tri.positions(), &points, &segments).map_err(|e| {
        StageError::Unsupported(format!(
            "splitting face {} of operand {}: {e}",
            input.face[t as usize].index(),
            input.operand[t as usize]
        ))
    })?;
    let to_global = |v: u32| global[v as usize];
    Ok(TriangleSplit {
        triangle: t,
        triangles: split.triangles.iter().map(|s| s.map(to_global)).collect(),
        merged: split.merged.iter().map(|m| m.map(to_global)).collect(),
        crossings,
    })
}

/// Finds the segments on triangle `t` that cross each other at a point inside both (only
/// with three or more operands: each segment comes from another triangle), adds each
/// crossing point to `points` and cuts the segments there. Returns the crossing points
/// with their keys, in the order they were added.
fn cut_crossing_segments(
    input: &Input,
    t: u32,
    points: &mut Vec<Point>,
    segments: &mut Vec<([u32; 2], Support)>,
) -> Vec<(PointKey, Point)> {
    if segments.len() < 2 {
        return Vec::new();
    }
    let tri = input.triangle(t as usize);
    let corners = tri.positions().map(Point::Explicit);
    let drop = tri.drop_axis();
    // Boxes certain to contain each segment: an approximation of an implicit point can be far
    // off when its definition is nearly degenerate, so only enclosures may reject a pair.
    let boxes: Vec<Aabb> = (segments.iter())
        .map(|(s, _)| {
            let (a, b) = (
                local_point(&corners, points, s[0]).enclosure(),
                local_point(&corners, points, s[1]).enclosure(),
            );
            Aabb::from_points([a.0, a.1, b.0, b.1].iter())
        })
        .collect();
    let mut cuts: Vec<(usize, u32)> = Vec::new(); // (segment, local point id)
    let mut crossings: Vec<(PointKey, Point)> = Vec::new();
    for i in 0..segments.len() {
        for j in i + 1..segments.len() {
            let ([a, b], sa) = segments[i];
            let ([c, d], sb) = segments[j];
            if a == c || a == d || b == c || b == d || !boxes[i].overlaps(&boxes[j]) {
                continue;
            }
            let [pa, pb, pc, pd] = [a, b, c, d].map(|v| local_point(&corners, points, v));
            let opposite = |x: Sign, y: Sign| x != Sign::Zero && x == y.flip();
            if !opposite(
                orient2d_projected(pa, pb, pc, drop),
                orient2d_projected(pa, pb, pd, drop),
            ) || !opposite(
                orient2d_projected(pc, pd, pa, drop),
                orient2d_projected(pc, pd, pb, drop),
            ) {
                continue;
            }
            let Some((key, x)) = crossing_point(input, t, sa, sb).map(|(k, x)| (k, simplify(x)))
            else {
                continue;
            };
            let id = match crossings.iter().position(|c| c.0 == key) {
                Some(k) => 3 + (points.len() - crossings.len() + k) as u32,
                None => {
                    crossings.push((key, x.clone()));
                    points.push(x);
                    (2 + points.len()) as u32
                }
            };
            cuts.push((i, id));
            cuts.push((j, id));
        }
    }
    if cuts.is_empty() {
        return crossings;
    }
    cuts.sort_unstable();
    let mut cut_segments = Vec::with_capacity(segments.len() + cuts.len());
    for (i, &([a, b], support)) in segments.iter().enumerate() {
        let start = cuts.partition_point(|c| c.0 < i);
        let mut on: Vec<u32> = cuts[start..]
            .iter()
            .take_while(|c| c.0 == i)
            .map(|c| c.1)
            .collect();
        let at = |v: u32| local_point(&corners, points, v);
        on.sort_by(|&x, &y| compare_lex(at(x), at(y)));
        let mut chain = vec![a];
        if compare_lex(at(a), at(b)) == std::cmp::Ordering::Greater {
            on.reverse();
        }
        chain.extend(on);
        chain.push(b);
        for w in chain.windows(2) {
            cut_segments.push(([w[0].min(w[1]), w[0].max(w[1])], support));
        }
    }
    cut_segments.sort_unstable_by_key(|s| s.0);
    cut_segments.dedup_by_key(|s| s.0);
    *segments = cut_segments;
    crossings
}

/// Local point `v` of a triangle being cut: its corners 0..3, then `points`.
fn local_point<'a>(corners: &'a [Point; 3], points: &'a [Point], v: u32) -> &'a Point {
    match (v as usize).checked_sub(3) {
        Some(i) => &points[i],
        None => &corners[v as usize],
    }
}

/// The point where segments carried by `sa` and `sb` cross inside triangle `t`, with its
/// canonical key; `None` for two segments on the same edge line (no single point).
fn crossing_point(input: &Input, t: u32, sa: Support, sb: Support) -> Option<(PointKey, Point)> {
    let tri = input.triangle(t as usize);
    let corners = |u: u32| input.triangle_positions(u as usize);
    let pos = |e: [u32; 2]| e.map(|v| input.positions[v as usize]);
    match (sa, sb) {
        (Support::Plane(u), Support::Plane(w)) => {
            let mut ids = [t, u, w];
            ids.sort_unstable();
            let point = Point::tpi(ids.map(corners))?;
            Some((PointKey::Triple { triangles: ids }, point))
        }
        (Support::Plane(u), Support::Edge(e)) | (Support::Edge(e), Support::Plane(u)) => {
            let [p, q] = pos(e);
            let [r, s, v] = corners(u);
            Some((
                PointKey::EdgeTriangle {
                    edge: e,
                    triangle: u,
                },
                Point::lpi(p, q, r, s, v)?,
            ))
        }
        (Support::Edge(e), Support::Edge(f)) => {
            let edges = [e.min(f), e.max(f)];
            let point = Point::edge_crossing(
                tri.positions(),
                pos(edges[0]),
                pos(edges[1]),
                tri.drop_axis(),
            )?;
            Some((PointKey::EdgeEdge { edges }, point))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One crossing found twice, its edge's line taken from either end: both orders of the
    /// finds keep the same definition, the one the filter encloses tighter.
    #[test]
    fn a_point_keeps_one_definition_whatever_order_it_is_found_in() {
        let plane = [[0.0, 0.0, 0.1], [1.0, 0.0, 0.3], [0.0, 1.0, 0.2]];
        let (s, t) = ([0.3, 0.2, -1.0], [0.35, 0.21, 1.7]);
        let crossing = |p, q| Point::lpi(p, q, plane[0], plane[1], plane[2]).expect("crosses");
        let (forward, backward) = (crossing(s, t), crossing(t, s));
        assert_ne!(
            enclosure_size(&forward),
            enclosure_size(&backward),
            "the two definitions are not equally tight"
        );
        let key = PointKey::EdgeTriangle {
            edge: [3, 4],
            triangle: 7,
        };
        // Found by two runs of pairs, in either order.
        let (ids, kept) = number_points(
            5,
            &[vec![(key, forward.clone())], vec![(key, backward.clone())]],
        );
        let (ids_reversed, kept_reversed) = number_points(
            5,
            &[vec![(key, backward.clone())], vec![(key, forward.clone())]],
        );
        assert_eq!((ids[&key], ids_reversed[&key]), (5, 5));
        assert_eq!((kept.len(), kept_reversed.len()), (1, 1));
        assert_eq!(format!("{:?}", kept[0]), format!("{:?}", kept_reversed[0]));
        let tighter = enclosure_size(&forward).min(enclosure_size(&backward));
        assert_eq!(enclosure_size(&kept[0]), tighter);
    }
}
