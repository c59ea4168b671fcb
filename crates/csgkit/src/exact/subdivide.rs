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

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use crate::kernel::Point;
use crate::mesh::union_find::UnionFind;

use super::boolean::BooleanError;
use super::ingest::Input;
use super::intersect::{Contact, Intersection, PointKey, intersect_triangles};
use super::split::split_triangle;

/// What one intersecting pair puts on one of its triangles.
#[derive(Clone, Copy, Debug)]
enum Mark {
    /// A contact point.
    Point(PointKey, Point),
    /// A contact segment between two points.
    Segment(PointKey, PointKey),
}

/// The contacts of every intersecting candidate pair, grouped by triangle.
pub(crate) struct Contacts {
    /// How many candidate pairs touch or cross.
    pub intersecting_pairs: usize,
    /// `(triangle, mark)`, sorted by triangle.
    marks: Vec<(u32, Mark)>,
}

/// Intersects every candidate pair exactly.
pub(crate) fn intersect_pairs(input: &Input, pairs: &[(u32, u32)]) -> Contacts {
    let found: Vec<Vec<(u32, Mark)>> = pairs
        .par_iter()
        .filter_map(|&(s, t)| {
            let (a, b) = (&input.triangles[s as usize], &input.triangles[t as usize]);
            let marks = marks_of(s, t, intersect_triangles(a, b));
            (!marks.is_empty()).then_some(marks)
        })
        .collect();
    let intersecting_pairs = found.len();
    let mut marks: Vec<(u32, Mark)> = found.into_iter().flatten().collect();
    // Stable: within a triangle, marks keep pair order, which is deterministic.
    marks.par_sort_by_key(|m| m.0);
    Contacts {
        intersecting_pairs,
        marks,
    }
}

/// The marks an intersection puts on its two triangles `s` (the `a` of the test) and `t`.
fn marks_of(s: u32, t: u32, intersection: Intersection) -> Vec<(u32, Mark)> {
    let point = |c: &Contact| Mark::Point(c.key, c.point);
    let both = |mark: Mark| [(s, mark), (t, mark)];
    match intersection {
        Intersection::Disjoint => Vec::new(),
        Intersection::TouchingPoint(c) => both(point(&c)).to_vec(),
        Intersection::TouchingSegment([c, d]) | Intersection::Crossing([c, d]) => {
            let mut marks = both(point(&c)).to_vec();
            marks.extend(both(point(&d)));
            marks.extend(both(Mark::Segment(c.key, d.key)));
            marks
        }
        Intersection::CoplanarOverlap(corners) => {
            let mut marks: Vec<(u32, Mark)> = corners.iter().flat_map(|c| both(point(c))).collect();
            for (i, c) in corners.iter().enumerate() {
                let d = &corners[(i + 1) % corners.len()];
                marks.extend(both(Mark::Segment(c.key, d.key)));
            }
            marks
        }
    }
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
    /// Input vertices that lie on another operand's surface, sorted.
    pub contact_vertices: Vec<u32>,
    /// How many input triangles were split.
    pub split_triangles: usize,
}

impl Arrangement {
    /// The number of vertex ids: input vertices, then intersection points.
    pub(crate) fn vertex_count(&self, input: &Input) -> usize {
        input.positions.len() + self.points.len()
    }

    /// The exact point of vertex `v`.
    pub(crate) fn point(&self, input: &Input, v: u32) -> Point {
        let n = input.positions.len();
        match (v as usize).checked_sub(n) {
            Some(i) => self.points[i],
            None => Point::Explicit(input.positions[v as usize]),
        }
    }
}

/// Splits every triangle with contacts.
///
/// # Errors
/// [`BooleanError::Unsupported`] when a triangle's constraints cross away from the contact
/// points (needs three-plane points that pairs of operands do not produce).
pub(crate) fn split(input: &Input, contacts: Contacts) -> Result<Arrangement, BooleanError> {
    let marks = contacts.marks;
    let (ids, points) = number_points(input, &marks);
    let groups: Vec<&[(u32, Mark)]> = marks.chunk_by(|x, y| x.0 == y.0).collect();
    let splits: Vec<Result<TriangleSplit, BooleanError>> = groups
        .par_iter()
        .map(|group| split_one(input, group, &ids))
        .collect();
    let splits: Vec<TriangleSplit> = splits.into_iter().collect::<Result<_, _>>()?;

    let mut merges = UnionFind::new(input.positions.len() + points.len());
    let mut any_merge = false;
    for s in &splits {
        for &[a, b] in &s.merged {
            merges.union(a, b);
            any_merge = true;
        }
    }
    let mut triangles = Vec::with_capacity(input.triangles.len() + splits.len() * 4);
    let mut source = Vec::with_capacity(triangles.capacity());
    let mut sub_starts = Vec::with_capacity(input.triangles.len() + 1);
    let mut next_split = splits.iter().peekable();
    for (t, tri) in input.triangles.iter().enumerate() {
        sub_starts.push(triangles.len() as u32);
        match next_split.next_if(|s| s.triangle as usize == t) {
            Some(s) => {
                source.extend(std::iter::repeat_n(t as u32, s.triangles.len()));
                triangles.extend_from_slice(&s.triangles);
            }
            None => {
                source.push(t as u32);
                triangles.push(tri.vertices());
            }
        }
    }
    sub_starts.push(triangles.len() as u32);
    if any_merge {
        for tri in &mut triangles {
            *tri = tri.map(|v| merges.find(v));
        }
    }
    let mut touched = vec![false; input.triangles.len()];
    for s in &splits {
        touched[s.triangle as usize] = true;
    }
    let mut contact_vertices: Vec<u32> = (marks.iter())
        .filter_map(|&(_, m)| match m {
            Mark::Point(PointKey::Vertex(v), _) => Some(v),
            _ => None,
        })
        .collect();
    contact_vertices.par_sort_unstable();
    contact_vertices.dedup();
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

/// Global vertex ids of the contact points: an input vertex keeps its id; every other key
/// gets the next id, in key order (deterministic).
fn number_points(input: &Input, marks: &[(u32, Mark)]) -> (FxHashMap<PointKey, u32>, Vec<Point>) {
    let mut keyed: Vec<(PointKey, Point)> = (marks.iter())
        .filter_map(|&(_, m)| match m {
            Mark::Point(key, point) if !matches!(key, PointKey::Vertex(_)) => Some((key, point)),
            _ => None,
        })
        .collect();
    keyed.par_sort_unstable_by(|x, y| x.0.cmp(&y.0));
    keyed.dedup_by(|x, y| x.0 == y.0);
    let n = input.positions.len() as u32;
    let ids = (keyed.iter().enumerate())
        .map(|(i, (key, _))| (*key, n + i as u32))
        .collect();
    (ids, keyed.into_iter().map(|(_, p)| p).collect())
}

/// The global id of a key.
fn global_id(key: &PointKey, ids: &FxHashMap<PointKey, u32>) -> u32 {
    match key {
        PointKey::Vertex(v) => *v,
        other => ids[other],
    }
}

/// The sub-triangles of one input triangle.
struct TriangleSplit {
    triangle: u32,
    triangles: Vec<[u32; 3]>,
    /// `[merged, kept]` global ids of coincident points with different keys.
    merged: Vec<[u32; 2]>,
}

/// Splits the triangle the marks of `group` are on.
fn split_one(
    input: &Input,
    group: &[(u32, Mark)],
    ids: &FxHashMap<PointKey, u32>,
) -> Result<TriangleSplit, BooleanError> {
    let t = group[0].0;
    let tri = &input.triangles[t as usize];
    // Local ids: corners 0..3, then points in first-seen order.
    let mut local: Vec<u32> = tri.vertices().to_vec();
    let mut points = Vec::new();
    let mut local_of = |key: &PointKey, point: Option<&Point>, points: &mut Vec<Point>| {
        let g = global_id(key, ids);
        match local.iter().position(|&x| x == g) {
            Some(i) => i as u32,
            None => {
                local.push(g);
                points.push(*point.expect("every segment end is also a point mark"));
                (local.len() - 1) as u32
            }
        }
    };
    for (_, mark) in group {
        if let Mark::Point(key, point) = mark {
            local_of(key, Some(point), &mut points);
        }
    }
    let mut segments = Vec::new();
    for (_, mark) in group {
        if let Mark::Segment(a, b) = mark {
            let (a, b) = (local_of(a, None, &mut points), local_of(b, None, &mut points));
            if a != b {
                segments.push([a.min(b), a.max(b)]);
            }
        }
    }
    segments.sort_unstable();
    segments.dedup();
    let split = split_triangle(tri.positions(), &points, &segments).map_err(|e| {
        BooleanError::Unsupported(format!(
            "splitting face {} of operand {}: {e}",
            input.face[t as usize].index(),
            input.operand[t as usize]
        ))
    })?;
    let to_global = |v: u32| local[v as usize];
    Ok(TriangleSplit {
        triangle: t,
        triangles: split.triangles.iter().map(|s| s.map(to_global)).collect(),
        merged: split.merged.iter().map(|m| m.map(to_global)).collect(),
    })
}
