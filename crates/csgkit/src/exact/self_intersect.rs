//! The exact self-intersection check of one mesh.
//!
//! # Contract
//! [`self_intersections`] reports the pairs of faces that intersect and the faces involved,
//! with the semantics of libigl's CGAL-based `remesh_self_intersections` in detect-only mode
//! (the reference measured in the shared data's `manifest.json`):
//! - vertices with exactly equal positions are welded first ([`weld_positions`]: `-0.0`
//!   equals `0.0`);
//! - polygons are triangulated exactly ([`triangulate_faces_partial`]); exactly degenerate
//!   triangles (collinear corners) are left out, and so are polygons of zero area; a polygon
//!   that cannot be triangulated otherwise (its projection overlaps itself) is left out of the
//!   pairs and reported in [`SelfIntersections::invalid_polygons`];
//! - two triangles with no shared vertex count when they have any common point (touching
//!   counts);
//! - sharing one vertex: when they have a common point besides that vertex;
//! - sharing an edge: only when they are coplanar and overlap with positive area
//!   ([`Intersection::CoplanarOverlap`]);
//! - sharing three vertices (a duplicated triangle): never, as in libigl;
//! - **polygons** (a csgkit choice; the reference files with polygons have no
//!   self-intersection): two triangles of the same face never count against each other (they
//!   cannot overlap: the triangulation is exact), and a pair of faces counts once however many
//!   of their triangles meet. On triangle meshes the face pairs are exactly the triangle pairs
//!   of the reference.
//!
//! # Agreement with the reference
//! The counts equal the manifest's on every shared data mesh but two (checked in
//! `tests/self_intersection.rs`): on `block.obj` csgkit also counts 5 pairs of coplanar
//! neighbours sharing an edge that fold over each other as thin slivers — an exact positive
//! area overlap the reference misses; on `openscad-nonmanifold-crash.obj` csgkit finds 24
//! more pairs (7542 against 7518) among the same 1385 faces, not yet explained.
//!
//! # Algorithm
//! [`self_intersections`]:
//! 1. Weld, triangulate and drop degenerate triangles ([`Triangle::new`]), in parallel.
//! 2. `intersecting_pairs` on those triangles.
//! 3. Map the triangle pairs to face pairs, drop the pairs within one face, sort and
//!    deduplicate; the faces are the sorted union of their members.
//!
//! `intersecting_pairs`, which the boolean engine runs on each operand:
//! 1. A [`Bvh`] over the triangles' boxes, computed on demand ([`Bvh::build_with`]; closed
//!    boxes, so touching triangles are candidates), renumbered in its Morton order
//!    ([`Bvh::into_tree_order`]); the triangles are copied into that order with their planes
//!    prepared (`Prepared`), so the walk reads them almost sequentially.
//! 2. The self walk ([`Bvh::self_overlapping_filter_map`], parallel over subtrees) decides each
//!    candidate as it finds it (`counts`) and keeps only the hits: the candidate list is
//!    never stored (34.7 M candidates on `Generic_Twin_7081.1.t0_left.obj`, 7.9 M on a
//!    1.3 M-triangle sphere).
//! 3. Sort the hits.
//!
//! # Deciding a candidate
//! On a closed mesh nearly every candidate is a pair of neighbours (a sphere's are all of
//! them), and most of the others are far apart in at least one plane's direction, so
//! `counts` decides them with [`orient3d`] of input vertices against the other
//! triangle's plane, without intersection points: the sharing pattern of the vertex ids
//! says which vertices to test, and the sides decide (the cases are in `counts`).
//! `Prepared::side` evaluates those signs exactly but cheaply: a comparison for a plane
//! along an axis, CGAL's semi-static filter with per-plane minors otherwise, and the full
//! predicate only when the filter cannot tell. Where it cannot (nearly coplanar pairs:
//! pieces of one face of a boolean's result, cut apart and rounded, or coplanar faces of a
//! model), `separated_in_projection` first tries to show with `orient2d`'s filter alone
//! that the pair's projections meet only where the triangles share vertices. Only pairs
//! that cross or touch in a way neither settles (no shared vertex and each straddling the
//! other's plane, or degenerate contacts) reach [`intersect_triangles`].
//!
//! # Complexity
//! O(n log n) for the hierarchy plus O(1) exact predicates per candidate pair; for a mesh
//! without self-intersection the candidates are mostly neighbours (a few per triangle), so
//! the walk and the side tests cost about the same per triangle as building the tree. The
//! output is the same for every thread count.

use std::cell::OnceCell;

use crate::par::*;

use super::intersect::{Intersection, Triangle, intersect_triangles};
use crate::index::{Aabb, Bvh};
use crate::kernel::{
    Axis, PlaneFilter, Point3, Sign, orient2d, orient2d_filterable, orient2d_value_if_clear,
    orient3d, side_of_axis_plane,
};
use crate::mesh::{FaceId, Mesh, PolygonError, triangulate_faces_partial, weld_positions};

/// The self-intersections of a mesh (see [`self_intersections`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SelfIntersections {
    /// Intersecting face pairs, each as (smaller id, larger id), sorted, without repeats.
    pub pairs: Vec<(FaceId, FaceId)>,
    /// The faces in at least one pair, sorted, without repeats.
    pub faces: Vec<FaceId>,
    /// Polygons left out of the check because they cannot be triangulated (their projection
    /// overlaps itself, which is a self-intersection of its own), in face order. Polygons of
    /// zero area are left out silently, as degenerate triangles are.
    pub invalid_polygons: Vec<PolygonError>,
}

impl SelfIntersections {
    /// The number of intersecting face pairs.
    pub fn pair_count(&self) -> usize {
        self.pairs.len()
    }

    /// The number of faces involved.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// True when the mesh does not intersect itself: no pair and no invalid polygon.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty() && self.invalid_polygons.is_empty()
    }
}

/// The exact self-intersections of `mesh` (semantics and algorithm in the
/// [module docs](self)).
pub fn self_intersections(mesh: &Mesh) -> SelfIntersections {
    let (faces, triangles, invalid_polygons) = triangles(mesh);
    // Triangles of one face never count against each other: the pair is dropped here rather
    // than in `intersecting_pairs`, which knows nothing of faces.
    let mut pairs: Vec<(FaceId, FaceId)> = intersecting_pairs(triangles.len(), |i| triangles[i])
        .into_iter()
        .filter_map(|(i, j)| {
            let (f, g) = (faces[i as usize], faces[j as usize]);
            (f != g).then(|| (f.min(g), f.max(g)))
        })
        .collect();
    pairs.par_sort_unstable();
    pairs.dedup();
    let mut faces: Vec<FaceId> = pairs.iter().flat_map(|&(f, g)| [f, g]).collect();
    faces.par_sort_unstable();
    faces.dedup();
    SelfIntersections {
        pairs,
        faces,
        invalid_polygons,
    }
}

/// Pairs `(i, j)`, `i < j`, of the `count` triangles `triangle(0..count)` that intersect
/// other than along what they share: exactly the pairs [`self_intersections`] counts (the
/// rules of the [module docs](self), without the face grouping of polygons). Sorted,
/// deduplicated.
///
/// The exact boolean engine runs it on each operand's prepared triangles, which it keeps by
/// vertex ids (`triangle` looks their positions up), so it takes them as they are: vertex ids
/// must be welded (equal positions have equal ids), because the shared vertices of a pair
/// are found by id; [`Triangle::id`] is not used.
pub(crate) fn intersecting_pairs(
    count: usize,
    triangle: impl Fn(usize) -> Triangle + Sync,
) -> Vec<(u32, u32)> {
    intersecting_pairs_and_tree(count, triangle).0
}

/// [`intersecting_pairs`], and the tree over the triangles' boxes it walked (ids are indices
/// of `triangle`), for callers that query the same triangles again.
pub(crate) fn intersecting_pairs_and_tree(
    count: usize,
    triangle: impl Fn(usize) -> Triangle + Sync,
) -> (Vec<(u32, u32)>, Bvh) {
    pairs_from_one_walk(count, triangle, None)
}

/// The pairs of [`intersecting_pairs`] with at least one triangle in `marked` (indices of
/// `triangle`'s). For a mesh known to be free of self-intersections except near a few
/// triangles (the certify stage's moved faces and those around them), at a fraction of the
/// cost of the whole check: the pairs of two unmarked triangles are passed over before any
/// test, by the self walk where most triangles are marked, and where fewer than half are by
/// walking a tree of the marked ones against the whole tree, which never meets those pairs.
/// (A query of the tree from each marked triangle instead descends from the root every
/// time, and cost more than the walk's extra box tests.)
pub(crate) fn intersecting_pairs_of(
    count: usize,
    triangle: impl Fn(usize) -> Triangle + Sync,
    marked: &[u32],
) -> Vec<(u32, u32)> {
    pairs_from_one_walk(count, triangle, Some(marked)).0
}

/// One walk of a tree over the triangles against itself, testing every overlapping pair that
/// has a triangle in `marked` (every pair when `None`); the pairs found, sorted, and the tree.
fn pairs_from_one_walk(
    count: usize,
    triangle: impl Fn(usize) -> Triangle + Sync,
    marked: Option<&[u32]>,
) -> (Vec<(u32, u32)>, Bvh) {
    let box_of = |i: usize| Aabb::from_points(triangle(i).positions().iter());
    let (bvh, order) = Bvh::build_with(count, box_of).into_tree_order();
    // Triangles in the tree's order, so that the walk reads them almost sequentially.
    let sorted: Vec<Prepared> = (order.par_iter())
        .map(|&i| Prepared::new(&triangle(i as usize)))
        .collect();
    // By place in the tree's order, apart from the records: a flag in each would widen all
    // of them, on the whole check too.
    let is_marked = marked.map(|marked| {
        let mut place = vec![0u32; count];
        for (x, &i) in order.iter().enumerate() {
            place[i as usize] = x as u32;
        }
        let mut is_marked = vec![false; count];
        for &i in marked {
            is_marked[place[i as usize] as usize] = true;
        }
        is_marked
    });
    let test = |x: u32, y: u32| {
        let (i, j) = (order[x as usize], order[y as usize]);
        let full = || (triangle(i as usize), triangle(j as usize));
        counts(&sorted[x as usize], &sorted[y as usize], full).then(|| (i.min(j), i.max(j)))
    };
    let few_marked = marked.is_some_and(|marked| 2 * marked.len() < count);
    let mut pairs = match &is_marked {
        // Few marked among many: a tree of the marked walked against the whole one passes by
        // the pairs of two unmarked triangles, which the self walk meets and then skips. On a
        // CAD model whose fans of long triangles cross the whole part, the self walk met 34
        // million box pairs to test 8 million.
        Some(is_marked) if few_marked => {
            let places: Vec<u32> = (0..count as u32)
                .filter(|&x| is_marked[x as usize])
                .collect();
            let marked_tree =
                Bvh::build_over(places, |x| Aabb::from_points(sorted[x].corners.iter()));
            // A pair of two marked triangles is met both ways round: kept once.
            marked_tree.overlapping_filter_map(&bvh, |x, y| {
                let once = x != y && (x < y || !is_marked[y as usize]);
                once.then(|| test(x, y)).flatten()
            })
        }
        _ => bvh.self_overlapping_filter_map(|x, y| {
            let tested = (is_marked.as_ref()).is_none_or(|m| m[x as usize] || m[y as usize]);
            tested.then(|| test(x, y)).flatten()
        }),
    };
    pairs.par_sort_unstable();
    pairs.dedup();
    (pairs, bvh.with_ids(order))
}

/// Whether two triangles of one mesh count as intersecting ([`intersecting_pairs`]'s rules,
/// for one pair).
pub(crate) fn pair_intersects(a: &Triangle, b: &Triangle) -> bool {
    counts(&Prepared::new(a), &Prepared::new(b), || (*a, *b))
}

/// The non-degenerate triangles of `mesh` with welded vertex ids, the face of each, and the
/// polygons that cannot be triangulated (except those of zero area).
fn triangles(mesh: &Mesh) -> (Vec<FaceId>, Vec<Triangle>, Vec<PolygonError>) {
    let positions = mesh.positions();
    // Each vertex becomes the first vertex at its position (`-0.0` equals `0.0`), so the
    // triangles keep input vertex ids and exactly equal positions share one.
    let welding = weld_positions(positions);
    let weld: Vec<u32> = (welding.remap.iter())
        .map(|&w| welding.representatives[w as usize])
        .collect();
    let (triangulation, mut invalid) = triangulate_faces_partial(mesh);
    invalid.retain(|e| !matches!(e, PolygonError::ZeroArea { .. }));
    let (faces, mut triangles): (Vec<FaceId>, Vec<Triangle>) = (triangulation.par_iter())
        .filter_map(|(face, corners)| {
            let ids = corners.map(|v| weld[v as usize]);
            let pts = ids.map(|v| positions[v as usize]);
            Triangle::new(0, ids, pts).map(|t| (face, t))
        })
        .unzip();
    // A triangle's id is its index (only intersection keys read it).
    (triangles.par_iter_mut().enumerate()).for_each(|(k, t)| *t = t.with_id(k as u32));
    (faces, triangles, invalid)
}

/// Whether a pair of triangles of one mesh counts as intersecting (libigl's rules).
///
/// Most candidate pairs are decided by the sides of one triangle's vertices against the
/// other's plane ([`Prepared::side`]), without building intersection points:
/// - sharing an edge: they count only when coplanar (one side test) and folded over
///   ([`folded_over`]);
/// - sharing one vertex: the other two vertices of either triangle strictly on one side of
///   the other's plane leave the shared vertex as the only common point; both on the plane:
///   coplanar, decided by [`wedges_overlap`]; one on it: [`in_corner`]; each straddling the
///   other's plane: [`chords_agree`];
/// - sharing nothing: all three vertices of either triangle strictly on one side of the
///   other's plane: disjoint.
///
/// The rest goes to [`intersect_triangles`].
///
/// `full` gives the two triangles, which only the rare cases read.
fn counts(a: &Prepared, b: &Prepared, full: impl FnOnce() -> (Triangle, Triangle)) -> bool {
    let (va, vb) = (a.vertices, b.vertices);
    // Bit i: vertex i of `b` is a vertex of `a`. Without branches: along a walk the sharing
    // pattern of consecutive pairs is unpredictable.
    let in_a = |v: u32| u8::from((v == va[0]) | (v == va[1]) | (v == va[2]));
    let shared = in_a(vb[0]) | in_a(vb[1]) << 1 | in_a(vb[2]) << 2;
    let (pa, pb) = (a.corners, b.corners);
    // Asked at most once, and only where exact work would follow.
    let separated = OnceCell::new();
    let is_separated = || *separated.get_or_init(|| separated_in_projection(a, b));
    let side = |t: &Prepared, p: Point3| t.side_unless(p, is_separated);
    match shared.count_ones() {
        3 => false,
        2 => {
            let k = (!shared & 7).trailing_zeros() as usize;
            side(a, pb[k]) == Some(Sign::Zero) && {
                let (ta, tb) = full();
                folded_over(&ta, &tb)
            }
        }
        1 => {
            // `b`'s corner at the shared vertex `vb[k]` is `vb[k], vb[k + 1], vb[k + 2]`.
            let k = shared.trailing_zeros() as usize;
            let (Some(s1), Some(s2)) = (side(a, pb[(k + 1) % 3]), side(a, pb[(k + 2) % 3])) else {
                return false;
            };
            if s1 == s2 {
                return s1 == Sign::Zero && {
                    let (ta, tb) = full();
                    wedges_overlap(&ta, &tb)
                };
            }
            let j = usize::from(va[1] == vb[k]) + 2 * usize::from(va[2] == vb[k]);
            if s1 == Sign::Zero || s2 == Sign::Zero {
                // `b` meets `a`'s plane only along its edge from the shared vertex to the
                // vertex on that plane.
                let on_plane = if s1 == Sign::Zero { 1 } else { 2 };
                return in_corner(a, j, pb[(k + on_plane) % 3]);
            }
            let (Some(t1), Some(t2)) = (side(b, pa[(j + 1) % 3]), side(b, pa[(j + 2) % 3])) else {
                return false;
            };
            if t1 == t2 {
                // Both strictly on one side: were both on `b`'s plane, `a` would lie in it and
                // `b` in `a`'s.
                return false;
            }
            if t1 == Sign::Zero || t2 == Sign::Zero {
                let on_plane = if t1 == Sign::Zero { 1 } else { 2 };
                return in_corner(b, k, pa[(j + on_plane) % 3]);
            }
            // Each straddles the other's plane.
            let corner = [pa[j], pa[(j + 1) % 3], pa[(j + 2) % 3]];
            chords_agree(corner, [pb[(k + 1) % 3], pb[(k + 2) % 3]], s1)
        }
        _ => {
            let one_side = |t: &Prepared, points: &[Point3; 3]| match t.one_side_if_clear(points) {
                Some(verdict) => verdict,
                None => is_separated() || t.strictly_one_side_exact(points),
            };
            !one_side(a, &pb) && !one_side(b, &pa) && !is_separated() && {
                let (ta, tb) = full();
                by_classification(&ta, &tb, 0)
            }
        }
    }
}

/// Whether `a` and `b` meet only in what they share (no point, their common vertex, or their
/// common edge), shown by their projections along `a`'s drop axis with `orient2d`'s f64
/// filter alone; `false` where the filter cannot show it.
///
/// Why it holds: every common point of the triangles projects into both projections; if
/// those meet only in the projection of the shared part, the point projects there, and the
/// projection is one-to-one on `a`'s plane (`a`'s projected turn is never zero), so the point
/// is in the shared part. In the plane, the projections meet only there when an edge line of
/// one leaves every vertex of the other strictly on its outer side, but for vertices shared
/// with that edge (the other triangle then touches the line only in those, which lie in the
/// edge); the separating axis theorem gives such an edge for disjoint triangles, and for
/// triangles sharing a vertex or an edge whose corners there do not overlap.
///
/// Why: the pairs the plane filter cannot decide are mostly pieces of one face, cut apart by
/// the boolean and rounded (within rounding of each other's planes), or coplanar faces of a
/// model. Their sides would take `orient3d`'s exact stages, and their contacts the full
/// classification; in projection the same pairs are well shaped, and a few `orient2d`
/// filters decide.
fn separated_in_projection(a: &Prepared, b: &Prepared) -> bool {
    let project = |t: &Prepared| t.corners.map(|p| a.drop.project(p));
    let (pa, pb) = (project(a), project(b));
    if !orient2d_filterable(&[pa[0], pa[1], pa[2], pb[0], pb[1], pb[2]]) {
        return false;
    }
    let turn_b = (orient2d_value_if_clear(pb[0], pb[1], pb[2]).map(Sign::of))
        .filter(|&turn| turn != Sign::Zero);
    an_edge_separates((pa, a.vertices, a.turn), (pb, b.vertices))
        || turn_b.is_some_and(|turn| an_edge_separates((pb, b.vertices, turn), (pa, a.vertices)))
}

/// Whether an edge line of the projected triangle `t` (corners, vertex ids, turn) leaves
/// every vertex of `u` (corners, vertex ids) strictly on its outer side, except the vertices
/// of `u` that are ends of that edge. The coordinates are in the filter's range.
fn an_edge_separates(
    (t, t_ids, turn): ([[f64; 2]; 3], [u32; 3], Sign),
    (u, u_ids): ([[f64; 2]; 3], [u32; 3]),
) -> bool {
    (0..3).any(|i| {
        let (p, q) = (t[i], t[(i + 1) % 3]);
        let (e0, e1) = (t_ids[i], t_ids[(i + 1) % 3]);
        (0..3).all(|j| {
            u_ids[j] == e0
                || u_ids[j] == e1
                || orient2d_value_if_clear(p, q, u[j]).is_some_and(|d| Sign::of(d) == turn.flip())
        })
    })
}

/// Two non-coplanar triangles share one vertex `v` and each has its other two vertices
/// strictly on both sides of the other's plane: whether they meet beyond `v`.
///
/// `corner` is `v, a1, a2` (a rotation of the first triangle's corners, so of its
/// orientation), `[b1, b2]` the other vertices of the second triangle, and `side_b1` is
/// [`orient3d`]`(v, a1, a2, b1)`. The planes meet in a line `L` through `v`; each triangle
/// meets `L` in a segment from `v` (to a point inside its edge opposite `v`), and the two
/// meet beyond `v` exactly when those segments leave `v` in the same direction. The second
/// one ends at `y`, where `b1 b2` crosses the first plane, and it points into the first
/// triangle's corner at `v` (rather than away from it) exactly when `y` lies on the inner
/// side of the line `v a1`: `orient3d(b1, b2, v, a1)` is that side times the side of `b1`,
/// up to a fixed sign (expand `det(b2 - b1, v - b1, a1 - b1)` with `y` on `b1 b2`), and `y`
/// is never on that line, because `a1` is off the second plane. One exact [`orient3d`] on
/// input points, where the full classification would build and order intersection points.
fn chords_agree(corner: [Point3; 3], [b1, b2]: [Point3; 2], side_b1: Sign) -> bool {
    let [v, a1, _] = corner;
    orient3d(b1, b2, v, a1) == side_b1.flip()
}

/// Whether `p`, a point of the plane of `t` other than its corner `c`, lies in the closed
/// corner of `t` at `c` (the cone from that corner over the triangle): then a segment from
/// the corner to `p` runs into `t`. Exact [`orient2d`] in `t`'s projection, which is one to
/// one on its plane: `p - v = α (x - v) + β (y - v)` for the corner `v, x, y`, and the two
/// orientations below are `β` and `α` times the corner's turn.
///
/// Why: a triangle that shares a vertex with another and has its second vertex on the other's
/// plane (the third off it) meets that plane only along the edge between them; the two meet
/// beyond the shared vertex exactly when that edge runs into the other's corner. Pieces of
/// one face, cut apart by a boolean and rounded, are full of such pairs, which the full
/// classification would decide by building and ordering intersection points.
fn in_corner(t: &Prepared, c: usize, p: Point3) -> bool {
    let project = |x: Point3| t.drop.project(x);
    let [v, x, y] = [0, 1, 2].map(|i| project(t.corners[(c + i) % 3]));
    let p = project(p);
    orient2d(v, x, p) != t.turn.flip() && orient2d(v, p, y) != t.turn.flip()
}

/// A triangle `p, q, r` with its plane, prepared for side tests of points.
///
/// [`Prepared::side`] is [`orient3d`]`(p, q, r, s)`, exactly; most tests are decided by a few
/// multiplications:
/// - **aligned**: the three vertices share a coordinate (a face of a CAD model along an axis
///   plane). The plane is `x_k = p_k`, and the side of `s` is the comparison of `s_k` with
///   `p_k` times the triangle's turn in the plane (expand the determinant along column `k`),
///   computed once; exact, with no rounding at all. It also keeps coplanar points, common on
///   such models, away from the slow exact stages [`orient3d`] needs for a zero.
/// - **filtered**: CGAL's semi-static filter for `orient3d` ([`PlaneFilter`]), whose 2 × 2
///   minors involve only `q - p` and `r - p` and are computed once per plane. When the
///   filter cannot decide, [`orient3d`] does.
#[derive(Clone, Copy, Debug)]
struct Prepared {
    corners: [Point3; 3],
    plane: PlaneFilter,
    vertices: [u32; 3],
    /// The axis `k` whose coordinate all three corners share, if any, and the turn of the
    /// corners projected along it ([`orient2d`] of coordinates `k + 1`, `k + 2`).
    aligned: Option<(u8, Sign)>,
    /// The triangle's [`Triangle::drop_axis`] and [`Triangle::turn`], for
    /// `separated_in_projection`.
    drop: Axis,
    turn: Sign,
}

impl Prepared {
    /// The plane of `triangle`.
    fn new(triangle: &Triangle) -> Prepared {
        let [p, q, r] = triangle.positions();
        let aligned =
            (triangle.axis_level()).map(|_| (triangle.drop_axis().index() as u8, triangle.turn()));
        Prepared {
            corners: [p, q, r],
            plane: PlaneFilter::new(&[p, q, r]),
            vertices: triangle.vertices(),
            aligned,
            drop: triangle.drop_axis(),
            turn: triangle.turn(),
        }
    }

    /// The side of `s`: [`orient3d`] of the triangle's corners and `s`.
    #[inline]
    fn side(&self, s: Point3) -> Sign {
        self.side_if_clear(s).unwrap_or_else(|| self.side_exact(s))
    }

    /// The side of `s` where a comparison or the filter decides it, `None` elsewhere.
    #[inline]
    fn side_if_clear(&self, s: Point3) -> Option<Sign> {
        if let Some((axis, turn)) = self.aligned {
            let axis = usize::from(axis);
            return Some(side_of_axis_plane(self.corners[0][axis], s[axis], turn));
        }
        self.plane.side_if_clear(s)
    }

    /// The side of `s`, unless the filter cannot decide it and `separated` (asked only then)
    /// holds: the caller's way out of exact arithmetic.
    #[inline]
    fn side_unless(&self, s: Point3, separated: impl FnOnce() -> bool) -> Option<Sign> {
        match self.side_if_clear(s) {
            Some(sign) => Some(sign),
            None if separated() => None,
            None => Some(self.side_exact(s)),
        }
    }

    /// The side of `s` by the full predicate.
    fn side_exact(&self, s: Point3) -> Sign {
        let [p, q, r] = self.corners;
        orient3d(p, q, r, s)
    }

    /// Whether the three points are strictly on one side of the plane, where the comparison
    /// or the filter decides it (it judges all three at once); `None` elsewhere.
    fn one_side_if_clear(&self, points: &[Point3; 3]) -> Option<bool> {
        if self.aligned.is_some() {
            return Some(self.strictly_one_side_exact(points));
        }
        let [x, y, z] = points.map(|s| self.plane.verdict(s));
        if (x.0 & y.0 & z.0) | (x.1 & y.1 & z.1) {
            return Some(true);
        }
        if (x.0 | y.0 | z.0) & (x.1 | y.1 | z.1) {
            return Some(false);
        }
        None
    }

    /// Whether the three points are strictly on one side of the plane, by exact sides.
    fn strictly_one_side_exact(&self, points: &[Point3; 3]) -> bool {
        let first = self.side(points[0]);
        first != Sign::Zero && self.side(points[1]) == first && self.side(points[2]) == first
    }
}

/// libigl's rules applied to the full classification (for pairs sharing no edge).
fn by_classification(a: &Triangle, b: &Triangle, shared: usize) -> bool {
    let found = intersect_triangles(a, b);
    match shared {
        0 => !matches!(found, Intersection::Disjoint),
        // The shared vertex is common; anything more counts.
        1 => !matches!(
            found,
            Intersection::Disjoint | Intersection::TouchingPoint(_)
        ),
        2 => matches!(found, Intersection::CoplanarOverlap(_)),
        _ => false,
    }
}

/// `a` and `b` share one vertex `v` and are coplanar: whether they meet beyond `v`. Both are
/// convex, so they do exactly when one's corner at `v` contains a ray along an edge of the
/// other (two angular sectors below 180° overlap only so).
fn wedges_overlap(a: &Triangle, b: &Triangle) -> bool {
    let project = |p| a.drop_axis().project(p);
    let corner = |t: &Triangle, other: &Triangle| {
        let (v, p) = (t.vertices(), t.positions().map(project));
        let k = (0..3)
            .find(|&i| other.vertices().contains(&v[i]))
            .unwrap_or(0);
        [p[k], p[(k + 1) % 3], p[(k + 2) % 3]]
    };
    let contains = |[v, u, w]: [[f64; 2]; 3], d: [f64; 2]| {
        let turn = orient2d(v, u, w);
        orient2d(v, u, d).times(turn) != Sign::Negative
            && orient2d(v, d, w).times(turn) != Sign::Negative
    };
    let (ca, cb) = (corner(a, b), corner(b, a));
    contains(ca, cb[1]) || contains(ca, cb[2]) || contains(cb, ca[1]) || contains(cb, ca[2])
}

/// `a` and `b` share an edge and are coplanar: whether their third vertices lie on the same
/// side of the shared edge, so that they overlap with positive area.
fn folded_over(a: &Triangle, b: &Triangle) -> bool {
    let project = |p| a.drop_axis().project(p);
    let (v, p) = (a.vertices(), a.positions().map(project));
    let Some(k) = (0..3).find(|&i| !b.vertices().contains(&v[i])) else {
        return false;
    };
    let (s0, s1) = (p[(k + 1) % 3], p[(k + 2) % 3]);
    let third = (0..3)
        .find(|&i| !v.contains(&b.vertices()[i]))
        .map(|i| project(b.positions()[i]));
    third.is_some_and(|q| orient2d(s0, s1, p[k]) == orient2d(s0, s1, q))
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    fn small_point() -> impl Strategy<Value = Point3> {
        [-2i32..=2, -2i32..=2, -2i32..=1].prop_map(|p| p.map(f64::from))
    }

    /// Triangles `a` and `b` (ids 0–2 and 3–5), with `share` (0–2) of `b`'s vertices replaced
    /// by `a`'s; `None` when either is degenerate, or when `welded` and an unshared vertex of
    /// `b` sits on a vertex of `a` (distinct ids must then mean distinct positions).
    fn sharing_pair(
        a: [Point3; 3],
        b: [Point3; 3],
        share: usize,
        welded: bool,
    ) -> Option<(Triangle, Triangle)> {
        let ids_b = [[3, 4, 5], [0, 4, 5], [1, 0, 5]][share];
        let mut pb = b;
        for (k, &id) in ids_b.iter().enumerate() {
            if id < 3 {
                pb[k] = a[id as usize];
            }
        }
        if welded && (0..3).any(|k| ids_b[k] >= 3 && a.contains(&pb[k])) {
            return None;
        }
        Some((
            Triangle::new(0, [0, 1, 2], a)?,
            Triangle::new(1, ids_b, pb)?,
        ))
    }

    /// `counts` of the pair, both ways round, is what the classification says (`share` of
    /// `b`'s vertices are `a`'s).
    fn counts_agree_with_classification(
        ta: &Triangle,
        tb: &Triangle,
        share: usize,
    ) -> Result<(), TestCaseError> {
        let (pa, pb) = (Prepared::new(ta), Prepared::new(tb));
        prop_assert_eq!(
            counts(&pa, &pb, || (*ta, *tb)),
            by_classification(ta, tb, share)
        );
        prop_assert_eq!(
            counts(&pb, &pa, || (*tb, *ta)),
            by_classification(tb, ta, share)
        );
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        /// The shortcuts for neighbours agree with the rules applied to the classification.
        #[test]
        fn shortcuts_agree_with_classification(
            a in [small_point(), small_point(), small_point()],
            b in [small_point(), small_point(), small_point()],
            share in 0usize..=2,
        ) {
            let Some((ta, tb)) = sharing_pair(a, b, share, false) else {
                return Ok(());
            };
            counts_agree_with_classification(&ta, &tb, share)?;
        }
    }

    fn wide_point() -> impl Strategy<Value = Point3> {
        [-6i32..=6, -6i32..=6, -6i32..=6].prop_map(|p| p.map(f64::from))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4000))]

        /// Pairs sharing one vertex, with the shared vertex at any corner of either triangle
        /// and either orientation: the shortcuts (one side, coplanar wedges, straddling
        /// chords) agree with the classification.
        #[test]
        fn vertex_neighbours_agree_with_classification(
            v in wide_point(),
            others in [wide_point(), wide_point(), wide_point(), wide_point()],
            at in (0usize..3, 0usize..3),
            flip in (any::<bool>(), any::<bool>()),
        ) {
            let [a1, a2, b1, b2] = others;
            let place = |v: Point3, p: Point3, q: Point3, at: usize, flip: bool, ids: [u32; 3]| {
                let (p, q, ip, iq) = if flip { (q, p, ids[2], ids[1]) } else { (p, q, ids[1], ids[2]) };
                let mut pts = [v, p, q];
                let mut vs = [ids[0], ip, iq];
                pts.rotate_right(at);
                vs.rotate_right(at);
                Triangle::new(0, vs, pts)
            };
            let (Some(ta), Some(tb)) = (
                place(v, a1, a2, at.0, flip.0, [0, 1, 2]),
                place(v, b1, b2, at.1, flip.1, [0, 3, 4]),
            ) else {
                return Ok(());
            };
            // Distinct ids must mean distinct positions (welded input).
            if [a1, a2].iter().any(|p| [b1, b2].contains(p)) {
                return Ok(());
            }
            counts_agree_with_classification(&ta, &tb, 1)?;
        }
    }

    /// A point of the plane `z = 0.1 x + 0.3 y` rounded to f64: points of it are within
    /// rounding of each other's planes, as the pieces of one rounded face are.
    fn nearly_planar_point() -> impl Strategy<Value = Point3> {
        [-4i32..=4, -4i32..=4].prop_map(|[x, y]| {
            let (x, y) = (f64::from(x), f64::from(y));
            [x, y, 0.1 * x + 0.3 * y]
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        /// Pairs within rounding of one plane, which the plane filter cannot decide: the
        /// projected separation only ever claims pairs the classification does not count,
        /// and the whole test agrees with the classification.
        #[test]
        fn nearly_coplanar_pairs_agree_with_classification(
            a in [nearly_planar_point(), nearly_planar_point(), nearly_planar_point()],
            b in [nearly_planar_point(), nearly_planar_point(), nearly_planar_point()],
            share in 0usize..=2,
        ) {
            let Some((ta, tb)) = sharing_pair(a, b, share, true) else {
                return Ok(());
            };
            if separated_in_projection(&Prepared::new(&ta), &Prepared::new(&tb)) {
                prop_assert!(!by_classification(&ta, &tb, share));
            }
            counts_agree_with_classification(&ta, &tb, share)?;
        }
    }

    /// Asserts that `Prepared::side` is `orient3d`.
    fn check_sides(corners: [Point3; 3], points: &[Point3]) -> Result<(), TestCaseError> {
        let Some(t) = Triangle::new(0, [0, 1, 2], corners) else {
            return Ok(());
        };
        let plane = Prepared::new(&t);
        for &s in points {
            let exact = orient3d(corners[0], corners[1], corners[2], s);
            prop_assert_eq!(plane.side(s), exact, "{:?} {:?}", corners, s);
        }
        Ok(())
    }

    /// A point near the plane of `c`: `c[0] + u (c[1] - c[0]) + v (c[2] - c[0])` in f64,
    /// nudged by `ulps` units in the last place, so that the filter often cannot decide.
    fn near_plane(c: [Point3; 3], u: f64, v: f64, ulps: i64) -> Point3 {
        std::array::from_fn(|k| {
            let x = c[0][k] + u * (c[1][k] - c[0][k]) + v * (c[2][k] - c[0][k]);
            f64::from_bits((x.to_bits() as i64 + ulps) as u64)
        })
    }

    fn scaled_point(scale: f64) -> impl Strategy<Value = Point3> {
        [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64].prop_map(move |p| p.map(|x| x * scale))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Grid points: aligned planes, coplanar points and exact zeros are common.
        #[test]
        fn plane_sides_on_a_grid(
            c in [small_point(), small_point(), small_point()],
            points in proptest::collection::vec(small_point(), 1..20),
        ) {
            check_sides(c, &points)?;
        }

        /// Points on and next to the plane at every scale, including scales outside the
        /// filter's range (1e-100 and 1e110), where `orient3d` decides.
        #[test]
        fn plane_sides_near_the_plane(
            scale in prop::sample::select(vec![1e-100, 1e-3, 1.0, 1e5, 1e110]),
            c in [scaled_point(1.0), scaled_point(1.0), scaled_point(1.0)],
            offset in scaled_point(1.0),
            near in proptest::collection::vec((-2.0..2.0f64, -2.0..2.0f64, -3i64..=3), 1..20),
        ) {
            let c = c.map(|p| std::array::from_fn(|k| (p[k] + offset[k] * 100.0) * scale));
            let points: Vec<Point3> = near.iter().map(|&(u, v, d)| near_plane(c, u, v, d)).collect();
            check_sides(c, &points)?;
        }
    }

    /// Triangles on a small grid with ids welded by position, so that neighbours, shared
    /// edges, coplanar pairs and touching contacts are common.
    fn welded_soup() -> impl Strategy<Value = Vec<Triangle>> {
        proptest::collection::vec([small_point(), small_point(), small_point()], 0..40).prop_map(
            |corners| {
                let mut points: Vec<Point3> = Vec::new();
                let mut id = |p: Point3| {
                    let k = points.iter().position(|&q| q == p).unwrap_or_else(|| {
                        points.push(p);
                        points.len() - 1
                    });
                    k as u32
                };
                corners
                    .into_iter()
                    .filter_map(|pts| Triangle::new(0, pts.map(&mut id), pts))
                    .collect()
            },
        )
    }

    /// Every pair of `triangles` decided by libigl's rules on the full classification.
    fn brute_force_pairs(triangles: &[Triangle]) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        for (i, a) in triangles.iter().enumerate() {
            for (j, b) in triangles.iter().enumerate().skip(i + 1) {
                let shared = (a.vertices().iter())
                    .filter(|v| b.vertices().contains(v))
                    .count();
                if by_classification(a, b, shared) {
                    pairs.push((i as u32, j as u32));
                }
            }
        }
        pairs
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(500))]

        /// The broad phase and the shortcuts lose no pair and add none.
        #[test]
        fn intersecting_pairs_match_brute_force(triangles in welded_soup()) {
            prop_assert_eq!(
                intersecting_pairs(triangles.len(), |i| triangles[i]),
                brute_force_pairs(&triangles)
            );
        }

        /// With marked triangles, few (a tree of them against the whole one) or many (the
        /// self walk), exactly the pairs with a marked triangle.
        #[test]
        fn pairs_of_marked_triangles_match_brute_force(
            triangles in welded_soup(),
            marks in proptest::collection::vec(any::<bool>(), 40),
            few in any::<bool>(),
        ) {
            let marked: Vec<u32> = (0..triangles.len() as u32)
                .filter(|&i| marks[i as usize] && (!few || i % 4 == 0))
                .collect();
            let mut want = brute_force_pairs(&triangles);
            want.retain(|(i, j)| marked.contains(i) || marked.contains(j));
            prop_assert_eq!(
                intersecting_pairs_of(triangles.len(), |i| triangles[i], &marked),
                want
            );
        }
    }

    /// CGAL writes the bound `5.1107127829973299e-15`; the constant is the same f64 in its
    /// shortest form.
    #[test]
    fn polygon_fans_and_duplicates_do_not_count() {
        // Face 0: a square; its two triangles share an edge (one face: no pair). Face 1: a
        // triangle crossing the square. Face 2: a copy of face 1 (three shared vertices: never
        // counted). Welding makes vertex 7 the same as vertex 4.
        let positions = vec![
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [4.0, 4.0, 0.0],
            [0.0, 4.0, 0.0],
            [3.0, 0.5, -1.0],
            [3.0, 0.5, 1.0],
            [3.5, 0.1, 1.0],
            [3.0, 0.5, -1.0],
        ];
        let parts = crate::MeshParts {
            positions,
            corners: vec![0, 1, 2, 3, 4, 5, 6, 7, 5, 6],
            face_starts: Some(vec![0, 4, 7, 10]),
            ..crate::MeshParts::default()
        };
        let mesh = Mesh::from_parts(parts).expect("valid mesh");
        let found = self_intersections(&mesh);
        let ids = |f: &[usize]| f.iter().map(|&i| FaceId::new(i)).collect::<Vec<_>>();
        assert_eq!(found.faces, ids(&[0, 1, 2]));
        assert_eq!(
            found.pairs,
            vec![
                (FaceId::new(0), FaceId::new(1)),
                (FaceId::new(0), FaceId::new(2))
            ]
        );
    }

    #[test]
    fn self_overlapping_polygons_are_reported_and_zero_area_ones_left_out() {
        // Face 0: an L hexagon starting at (2, 0), whose fan would overlap itself. Face 1: a
        // bow tie. Face 2: four collinear corners.
        let positions = vec![
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 0.0],
            [5.0, 0.0, 0.0],
            [7.0, 2.0, 0.0],
            [7.0, 0.0, 0.0],
            [5.0, 2.0, 0.0],
            [0.0, 0.0, 5.0],
            [1.0, 0.0, 5.0],
            [2.0, 0.0, 5.0],
        ];
        let parts = crate::MeshParts {
            positions,
            corners: vec![0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 11],
            face_starts: Some(vec![0, 6, 10, 14]),
            ..crate::MeshParts::default()
        };
        let found = self_intersections(&Mesh::from_parts(parts).expect("valid mesh"));
        assert!(found.pairs.is_empty());
        let face = FaceId::new(1);
        let overlap = crate::mesh::Overlap::CrossingEdges;
        assert_eq!(
            found.invalid_polygons,
            vec![PolygonError::SelfOverlapping { face, overlap }]
        );
        assert!(!found.is_empty());
    }
}
