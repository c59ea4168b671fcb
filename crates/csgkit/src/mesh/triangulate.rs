//! The one triangulator of polygons: every face of a [`Mesh`] as triangles over the mesh's own
//! vertex ids, decided exactly.
//!
//! # Contract
//! [`triangulate_faces`] gives a [`Triangulation`]: for every face, in face order, triangles
//! whose corners are corners of that face, wound as the face is, each with its [`FaceId`] and
//! an edge mask saying which of its sides are edges of the polygon (the others are diagonals).
//! - A face of three corners is its own triangle, degenerate or not (consumers decide what a
//!   degenerate triangle means to them).
//! - A polygon of n corners whose projection (below) is simple gives exactly n − 2 triangles,
//!   none of zero area: no Steiner point, no dropped corner, collinear corners kept.
//! - Consecutive corners at one position (bit-identical, `-0.0` equal to `0.0`) are one corner:
//!   the zero-length edge between them is no edge. A polygon with m corners left gives m − 2
//!   triangles; which of the equal corners is kept is unspecified.
//! - Any other polygon gets a [`PolygonError`] naming the face: its projection overlaps itself
//!   ([`PolygonError::SelfOverlapping`]: two corners at one point, two edges crossing, or a
//!   corner on another edge), all its corners lie on one line ([`PolygonError::ZeroArea`]), a
//!   coordinate is not finite, or its coordinates span too many binades for the triangulator
//!   ([`PolygonError::OutOfRange`]). No input panics.
//!
//! A polygon need not be planar: it is triangulated in its projection, and because each
//! triangle has positive area there, each is the graph of an affine map over its projection,
//! so two triangles of one face meet only in their shared corners and sides.
//!
//! # Algorithm
//! Per face, in parallel over blocks of faces and concatenated in face order:
//! 1. Three corners: the triangle, unchanged. A triangle mesh is read in place: no copy and
//!    no allocation at all.
//! 2. Choose the projection: drop the axis of the largest component of the Newell normal
//!    (an f64 estimate, which only orders the axes), keeping the other two coordinates. A
//!    projection in which every corner is exactly collinear is skipped for the next axis, so a
//!    rounded normal cannot make a polygon degenerate; when all three are, so is the polygon.
//! 3. Strictly convex in the projection — every turn (`orient2d` of consecutive corners) of
//!    one non-zero sign and the edge directions winding once (the first coordinate's
//!    differences change sign exactly twice; all turns of one sign alone also admit
//!    pentagrams) — keeps the fan from the first corner, with no allocation, up to five
//!    corners, and above that gets a strip (zigzag), whose near-parallel diagonals keep the
//!    overlay of coplanar faces small.
//! 4. Otherwise merge consecutive equal corners and build the constrained Delaunay
//!    triangulation of the projected corners with every polygon edge a constraint (`planar`,
//!    on spade's bulk loader). The projection is simple exactly when the corners are distinct,
//!    no two edges cross, and every polygon edge is an edge of the triangulation (a corner on
//!    an edge would split it); otherwise the polygon overlaps itself.
//! 5. Flood fill from the outer face, flipping inside and outside across constraint edges;
//!    keep the inside triangles, turned to the polygon's orientation (the side of its first
//!    edge the inside lies on).
//!
//! `planar` is also how the orthogonal engine triangulates its faces with holes
//! (`ortho::triangulate`): one triangulator of polygons in the crate.
//!
//! # Numeric model
//! Only exact predicates decide: the kernel's [`orient2d`] (exact for every finite input) in
//! steps 2–3, spade's (Shewchuk's, through `robust`) in step 4. spade accepts coordinate
//! magnitudes in [2^-142, 2^201] and zero; `planar` multiplies a loop's coordinates by one power
//! of two when they lie outside, which is exact because every product is a normal number and
//! changes no predicate's sign. That fails only when a loop's nonzero magnitudes span more than
//! 2^342 ([`PolygonError::OutOfRange`]).
//!
//! # Complexity
//! O(n) per triangle or strictly convex polygon of n corners, O(n log n) per other polygon.

use crate::par::*;
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation as _};

use super::{FaceId, Mesh};
use crate::kernel::{Sign, orient2d};

/// The triangles of every face of a mesh (see the [module docs](self)).
///
/// Triangle `t` has corners [`triangle(t)`](Self::triangle) (vertex ids of the mesh), comes
/// from face [`face(t)`](Self::face), and its side `i`, from corner `i` to corner `i + 1`
/// (mod 3), is an edge of that face when bit `i` of [`edge_mask(t)`](Self::edge_mask) is set,
/// and a diagonal otherwise. Triangles are in face order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Triangulation<'m> {
    repr: Repr<'m>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Repr<'m> {
    /// A triangle mesh's corner buffer, read in place: triangle `t` is face `t`, all sides
    /// polygon edges.
    Triangles(&'m [u32]),
    /// Triangles of polygon faces.
    Polygons(Polygons),
}

/// Triangles with their faces and edge masks, one entry each.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
struct Polygons {
    triangles: Vec<[u32; 3]>,
    faces: Vec<FaceId>,
    edge_masks: Vec<u8>,
}

impl Polygons {
    fn with_capacity(n: usize) -> Polygons {
        Polygons {
            triangles: Vec::with_capacity(n),
            faces: Vec::with_capacity(n),
            edge_masks: Vec::with_capacity(n),
        }
    }

    fn push(&mut self, face: FaceId, triangle: [u32; 3], mask: u8) {
        self.triangles.push(triangle);
        self.faces.push(face);
        self.edge_masks.push(mask);
    }

    fn append(&mut self, mut other: Polygons) {
        self.triangles.append(&mut other.triangles);
        self.faces.append(&mut other.faces);
        self.edge_masks.append(&mut other.edge_masks);
    }
}

impl Triangulation<'_> {
    /// The edge mask of a triangle whose three sides are polygon edges, as every triangular
    /// face's.
    pub const ALL_SIDES: u8 = 0b111;

    /// The number of triangles.
    pub fn len(&self) -> usize {
        match &self.repr {
            Repr::Triangles(corners) => corners.len() / 3,
            Repr::Polygons(p) => p.triangles.len(),
        }
    }

    /// True when there is no triangle.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The corners of triangle `t`, vertex ids of the mesh.
    ///
    /// # Panics
    /// If `t` is not below [`len`](Self::len).
    pub fn triangle(&self, t: usize) -> [u32; 3] {
        match &self.repr {
            Repr::Triangles(corners) => [corners[3 * t], corners[3 * t + 1], corners[3 * t + 2]],
            Repr::Polygons(p) => p.triangles[t],
        }
    }

    /// The face triangle `t` comes from.
    ///
    /// # Panics
    /// If `t` is not below [`len`](Self::len).
    pub fn face(&self, t: usize) -> FaceId {
        match &self.repr {
            Repr::Triangles(corners) => {
                assert!(t < corners.len() / 3, "triangle {t} out of range");
                FaceId::new(t)
            }
            Repr::Polygons(p) => p.faces[t],
        }
    }

    /// Which sides of triangle `t` are polygon edges: bit `i` for the side from corner `i` to
    /// corner `i + 1` (mod 3); [`ALL_SIDES`](Self::ALL_SIDES) for a triangular face.
    ///
    /// # Panics
    /// If `t` is not below [`len`](Self::len).
    pub fn edge_mask(&self, t: usize) -> u8 {
        match &self.repr {
            Repr::Triangles(corners) => {
                assert!(t < corners.len() / 3, "triangle {t} out of range");
                Self::ALL_SIDES
            }
            Repr::Polygons(p) => p.edge_masks[t],
        }
    }

    /// Every triangle with its face, in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (FaceId, [u32; 3])> + '_ {
        (0..self.len()).map(|t| (self.face(t), self.triangle(t)))
    }

    /// [`iter`](Self::iter) in parallel.
    pub(crate) fn par_iter(&self) -> impl IndexedParallelIterator<Item = (FaceId, [u32; 3])> + '_ {
        (0..self.len())
            .into_par_iter()
            .map(|t| (self.face(t), self.triangle(t)))
    }
}

/// Why a polygon's projection is not simple.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Overlap {
    /// Two corners project to one point (and are not consecutive corners at one position,
    /// which count as one corner).
    CoincidentCorners,
    /// Two edges cross.
    CrossingEdges,
    /// A corner lies on an edge it does not end, or two edges overlap along a segment.
    CornerOnEdge,
}

impl std::fmt::Display for Overlap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Overlap::CoincidentCorners => "two corners coincide",
            Overlap::CrossingEdges => "two edges cross",
            Overlap::CornerOnEdge => "a corner lies on another edge",
        })
    }
}

/// A face that cannot be triangulated (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum PolygonError {
    /// The polygon's projection is not a simple polygon: it overlaps itself.
    ///
    /// *How to fix*: split the face into simple polygons, or triangulate it where it was made.
    #[error("face {face} overlaps itself in its projection ({overlap})")]
    SelfOverlapping {
        /// The face.
        face: FaceId,
        /// What overlaps.
        overlap: Overlap,
    },
    /// Every corner lies on one line: the polygon has no area.
    ///
    /// *How to fix*: remove the face; it bounds nothing.
    #[error("face {face} has zero area (its corners are collinear)")]
    ZeroArea {
        /// The face.
        face: FaceId,
    },
    /// A corner has a NaN or infinite coordinate.
    ///
    /// *How to fix*: repair or remove the vertex.
    #[error("face {face} has a corner with a non-finite coordinate")]
    NonFinite {
        /// The face.
        face: FaceId,
    },
    /// The polygon's nonzero coordinate magnitudes span more than 2^342, more than the
    /// constrained triangulation's exact predicates accept after any scaling.
    ///
    /// *How to fix*: snap coordinates that are almost zero to zero, or triangulate the face.
    #[error("face {face} has coordinates too far apart in magnitude to triangulate")]
    OutOfRange {
        /// The face.
        face: FaceId,
    },
}

impl PolygonError {
    /// The face at fault.
    pub fn face(&self) -> FaceId {
        match *self {
            PolygonError::SelfOverlapping { face, .. }
            | PolygonError::ZeroArea { face }
            | PolygonError::NonFinite { face }
            | PolygonError::OutOfRange { face } => face,
        }
    }
}

/// Triangulates every face of `mesh` (see the [module docs](self)).
///
/// # Errors
/// The [`PolygonError`] of the first face that cannot be triangulated.
///
/// # Example
/// ```
/// use csgkit::mesh::triangulate_faces;
/// use csgkit::{Mesh, MeshParts};
///
/// // An L-shaped hexagon starting at (2, 0): its fan would leave it, as the fan triangle
/// // (2, 0), (1, 1), (1, 2) is clockwise.
/// let positions = vec![
///     [0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0],
///     [1.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 2.0, 0.0],
/// ];
/// let mesh = Mesh::from_parts(MeshParts {
///     positions,
///     corners: vec![1, 2, 3, 4, 5, 0],
///     face_starts: Some(vec![0, 6]),
///     ..MeshParts::default()
/// })?;
/// let triangles = triangulate_faces(&mesh)?;
/// assert_eq!(triangles.len(), 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn triangulate_faces(mesh: &Mesh) -> Result<Triangulation<'_>, PolygonError> {
    let (triangulation, errors) = triangulate_faces_partial(mesh);
    match errors.first() {
        Some(&error) => Err(error),
        None => Ok(triangulation),
    }
}

/// Triangulates every face of `mesh` that can be, and gives the error of each face that
/// cannot, in face order; those faces have no triangle.
///
/// For checks that report every problem of a mesh rather than stop at the first.
pub fn triangulate_faces_partial(mesh: &Mesh) -> (Triangulation<'_>, Vec<PolygonError>) {
    if mesh.is_triangle_mesh() {
        let repr = Repr::Triangles(mesh.corners());
        return (Triangulation { repr }, Vec::new());
    }
    // Faces per parallel task: enough to amortise the task, small enough to balance.
    const BLOCK: usize = 1 << 12;
    let faces = mesh.face_count();
    let ranges: Vec<std::ops::Range<usize>> = block_ranges(faces, BLOCK).collect();
    let blocks: Vec<(Polygons, Vec<PolygonError>)> = (ranges.into_par_iter())
        .map(|range| {
            let corners = mesh.face_range(FaceId::new(range.start)).start
                ..mesh.face_range(FaceId::new(range.end - 1)).end;
            // n - 2 triangles per face of n corners, fewer only for merged corners or errors.
            let mut out = Polygons::with_capacity(corners.len() - 2 * range.len());
            let mut errors = Vec::new();
            for f in range.map(FaceId::new) {
                if let Err(e) = triangulate_face(mesh.positions(), mesh.face(f), f, &mut out) {
                    errors.push(e);
                }
            }
            (out, errors)
        })
        .collect();
    let mut all = Polygons::with_capacity(blocks.iter().map(|(b, _)| b.triangles.len()).sum());
    let mut errors = Vec::new();
    for (block, block_errors) in blocks {
        all.append(block);
        errors.extend(block_errors);
    }
    debug_assert!(all.faces.windows(2).all(|w| w[0] <= w[1]));
    let repr = Repr::Polygons(all);
    (Triangulation { repr }, errors)
}

/// The triangles this triangulator makes of the polygon `corners`, or `None` where it rejects
/// it: what a reader of the written face gets (`csgkit check` and csgkit's own operands
/// among them), for a writer that must not write a face it rejects or reads otherwise.
pub(crate) fn polygon_triangles(positions: &[[f64; 3]], corners: &[u32]) -> Option<Vec<[u32; 3]>> {
    let mut scratch = Polygons::with_capacity(corners.len().saturating_sub(2));
    triangulate_face(positions, corners, FaceId::new(0), &mut scratch).ok()?;
    Some(scratch.triangles)
}

/// Appends the triangles of one face (steps 1–5); on error, appends nothing.
fn triangulate_face(
    positions: &[[f64; 3]],
    corners: &[u32],
    face: FaceId,
    out: &mut Polygons,
) -> Result<(), PolygonError> {
    if let &[a, b, c] = corners {
        out.push(face, [a, b, c], Triangulation::ALL_SIDES);
        return Ok(());
    }
    let point = |i: usize| positions[corners[i] as usize];
    if !(0..corners.len()).all(|i| point(i).iter().all(|x| x.is_finite())) {
        return Err(PolygonError::NonFinite { face });
    }
    for axis in projection_order(&point, corners.len()) {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let projected = |i: usize| {
            let p = point(i);
            [p[u], p[v]]
        };
        if is_strictly_convex(&projected, corners.len()) {
            if corners.len() <= FAN_CORNERS {
                push_fan(corners, face, out);
            } else {
                push_strip(corners, face, out);
            }
            return Ok(());
        }
        if !all_collinear(&projected, corners.len()) {
            return triangulate_simple(positions, corners, (u, v), face, out);
        }
    }
    Err(PolygonError::ZeroArea { face })
}

/// The axes to drop, by decreasing magnitude of the Newell normal's components.
fn projection_order(point: &impl Fn(usize) -> [f64; 3], n: usize) -> [usize; 3] {
    // Shifted to the first corner, so far-off polygons lose less to cancellation.
    let o = point(0);
    let shifted = |i: usize| {
        let p = point(i);
        [p[0] - o[0], p[1] - o[1], p[2] - o[2]]
    };
    let mut normal = [0.0f64; 3];
    for i in 1..n - 1 {
        let (a, b) = (shifted(i), shifted(i + 1));
        normal[0] += a[1] * b[2] - a[2] * b[1];
        normal[1] += a[2] * b[0] - a[0] * b[2];
        normal[2] += a[0] * b[1] - a[1] * b[0];
    }
    // NaN (overflowed sums) orders as zero: every axis is tried anyway.
    let size = |k: usize| {
        let m = normal[k].abs();
        if m.is_nan() { 0.0 } else { m }
    };
    let mut order = [2, 0, 1];
    order.sort_by(|&a, &b| size(b).total_cmp(&size(a)));
    order
}

/// Whether the projected polygon is strictly convex: every turn has one non-zero sign and
/// the edge directions turn around once.
fn is_strictly_convex(p: &impl Fn(usize) -> [f64; 2], n: usize) -> bool {
    let turn = |i: usize| orient2d(p((i + n - 1) % n), p(i), p((i + 1) % n));
    let first = turn(0);
    if first == Sign::Zero || !(1..n).all(|i| turn(i) == first) {
        return false;
    }
    // With all turns of one sign the direction angle grows monotonically by 2π w in total,
    // and the first coordinate's difference changes sign 2 w times; convex means w = 1.
    let mut steps = (0..n).filter_map(|i| {
        let (a, b) = (p(i)[0], p((i + 1) % n)[0]);
        (a != b).then_some(b > a)
    });
    let Some(start) = steps.next() else {
        return false;
    };
    let (mut last, mut changes) = (start, 0);
    for up in steps {
        changes += usize::from(up != last);
        last = up;
    }
    changes += usize::from(last != start);
    changes == 2
}

/// Whether every projected corner lies on one line (or all coincide).
fn all_collinear(p: &impl Fn(usize) -> [f64; 2], n: usize) -> bool {
    let a = p(0);
    let Some(b) = (1..n).map(p).find(|&q| q != a) else {
        return true;
    };
    (1..n).all(|i| orient2d(a, b, p(i)) == Sign::Zero)
}

/// Strictly convex polygons with up to this many corners keep their fan; larger ones get a
/// strip.
const FAN_CORNERS: usize = 5;

/// The strip (zigzag) triangulation of a strictly convex polygon: corners taken alternately
/// from both sides of the first, `0, 1, n−1, 2, n−2, …`, each three consecutive ones a
/// triangle. Its diagonals are near-parallel chords, where a fan's all meet in one corner as
/// slivers; two coplanar discs (the caps of a tube's two cylinders) then cross in O(n)
/// points instead of O(n²), which is what the exact engine pays to overlay them.
fn push_strip(corners: &[u32], face: FaceId, out: &mut Polygons) {
    let n = corners.len();
    let order: Vec<usize> = std::iter::once(0)
        .chain((1..n).map(|k| if k % 2 == 1 { k.div_ceil(2) } else { n - k / 2 }))
        .collect();
    let is_side = |a: usize, b: usize| (a + 1) % n == b || (b + 1) % n == a;
    for w in order.windows(3) {
        // Corners in their cyclic order are counter-clockwise like the polygon.
        let mut t = [w[0], w[1], w[2]];
        t.sort_unstable();
        let mask = (0..3)
            .map(|i| u8::from(is_side(t[i], t[(i + 1) % 3])) << i)
            .sum();
        out.push(face, t.map(|i| corners[i]), mask);
    }
}

/// The fan from the first corner of a strictly convex polygon.
fn push_fan(corners: &[u32], face: FaceId, out: &mut Polygons) {
    let n = corners.len();
    for k in 1..n - 1 {
        // Side 0 (first corner to corner k) is an edge only for the first triangle, side 2
        // (corner k + 1 back to the first) only for the last.
        let mask = 0b010 | u8::from(k == 1) | u8::from(k + 2 == n) << 2;
        out.push(face, [corners[0], corners[k], corners[k + 1]], mask);
    }
}

/// Steps 4–5 for a polygon that is neither strictly convex nor collinear in the projection
/// `(u, v)`.
fn triangulate_simple(
    positions: &[[f64; 3]],
    corners: &[u32],
    (u, v): (usize, usize),
    face: FaceId,
    out: &mut Polygons,
) -> Result<(), PolygonError> {
    let n = corners.len();
    let position = |i: usize| positions[corners[i] as usize];
    // A corner is kept unless it repeats the previous corner's position (`==` makes -0.0
    // equal to 0.0, as welding does).
    let kept: Vec<u32> = (0..n)
        .filter(|&i| position(i) != position((i + n - 1) % n))
        .map(|i| corners[i])
        .collect();
    let m = kept.len();
    if m == 3 {
        // Not collinear (the caller checked the same point set): the triangle itself.
        out.push(face, [kept[0], kept[1], kept[2]], Triangulation::ALL_SIDES);
        return Ok(());
    }
    let points = (kept.iter())
        .map(|&c| {
            let p = positions[c as usize];
            [p[u], p[v]]
        })
        .collect();
    let edges = (0..m).map(|i| [i, (i + 1) % m]).collect();
    let planar = triangulate_planar(points, edges).map_err(|fault| match fault {
        PlanarFault::OutOfRange => PolygonError::OutOfRange { face },
        PlanarFault::CoincidentPoints => PolygonError::SelfOverlapping {
            face,
            overlap: Overlap::CoincidentCorners,
        },
        PlanarFault::CrossingEdges => PolygonError::SelfOverlapping {
            face,
            overlap: Overlap::CrossingEdges,
        },
    })?;
    if !planar.edges_whole {
        return Err(PolygonError::SelfOverlapping {
            face,
            overlap: Overlap::CornerOnEdge,
        });
    }
    // A simple polygon of m corners has exactly m - 2 triangles in any triangulation without
    // Steiner points (and the constrained one makes none of zero area).
    debug_assert_eq!(planar.triangles.len(), m - 2, "face {face}");
    let clockwise = is_clockwise(&planar);
    for (t, &mask) in planar.triangles.iter().zip(&planar.edge_masks) {
        let ids = t.map(|i| kept[i]);
        if clockwise {
            // Corners a, c, b: the sides become (a c, c b, b a) = (old 2, old 1, old 0).
            let mask = (mask & 0b010) | (mask >> 2 & 1) | (mask & 1) << 2;
            out.push(face, [ids[0], ids[2], ids[1]], mask);
        } else {
            out.push(face, ids, mask);
        }
    }
    Ok(())
}

/// Whether the loop `0, 1, …` runs clockwise in the plane: the inside lies right of its edge
/// from point 0 to point 1 (the inside triangles are counter-clockwise).
fn is_clockwise(planar: &PlanarTriangles) -> bool {
    !(planar.triangles.iter()).any(|t| (0..3).any(|i| t[i] == 0 && t[(i + 1) % 3] == 1))
}

/// The constrained triangulation of loops in the plane (`planar` in the module docs): what the
/// mesh polygons and the orthogonal engine's faces share.
pub(crate) struct PlanarTriangles {
    /// The triangles inside the loops, counter-clockwise, as indices of the input points.
    pub triangles: Vec<[usize; 3]>,
    /// Per triangle, bit `i` set when its side from corner `i` to `i + 1` is a constraint.
    pub edge_masks: Vec<u8>,
    /// Whether every input edge is an edge of the triangulation, that is, no input point lies
    /// inside an input edge (which splits it).
    pub edges_whole: bool,
}

/// Why [`triangulate_planar`] failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PlanarFault {
    /// A coordinate is not finite, or the magnitudes span more than 2^342.
    OutOfRange,
    /// Two input points are equal.
    CoincidentPoints,
    /// Two input edges cross.
    CrossingEdges,
}

/// The constrained Delaunay triangulation of distinct `points` with constraint `edges` (pairs
/// of point indices forming closed loops), and the triangles inside the loops: those reached
/// from the outer face by crossing an odd number of constraints.
pub(crate) fn triangulate_planar(
    points: Vec<[f64; 2]>,
    edges: Vec<[usize; 2]>,
) -> Result<PlanarTriangles, PlanarFault> {
    let count = points.len();
    let scale = spade_scale(&points).ok_or(PlanarFault::OutOfRange)?;
    let points = (points.iter())
        .map(|p| Point2::new(p[0] * scale, p[1] * scale))
        .collect();
    let mut crossings = 0usize;
    let cdt = Cdt::try_bulk_load_cdt(points, edges.clone(), |_| crossings += 1)
        .map_err(|_| PlanarFault::OutOfRange)?;
    // spade keeps one of equal points; without duplicates its vertex i is input point i.
    if cdt.num_vertices() != count {
        return Err(PlanarFault::CoincidentPoints);
    }
    if crossings > 0 {
        return Err(PlanarFault::CrossingEdges);
    }
    let edges_whole = (edges.iter()).all(|&[a, b]| {
        cdt.exists_constraint(
            FixedVertexHandle::from_index(a),
            FixedVertexHandle::from_index(b),
        )
    });
    let inside = flood_fill(&cdt);
    let mut triangles = Vec::new();
    let mut edge_masks = Vec::new();
    for t in cdt.inner_faces().filter(|t| inside[t.fix().index()]) {
        // Side i runs from corner i to corner i + 1: the edges come counter-clockwise.
        let sides = t.adjacent_edges();
        triangles.push(sides.map(|e| e.from().fix().index()));
        let mask = (sides.iter().enumerate())
            .map(|(i, e)| u8::from(e.is_constraint_edge()) << i)
            .sum();
        edge_masks.push(mask);
    }
    Ok(PlanarTriangles {
        triangles,
        edge_masks,
        edges_whole,
    })
}

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Whether each face of `cdt` (by index) lies inside the loops.
fn flood_fill(cdt: &Cdt) -> Vec<bool> {
    let mut inside = vec![false; cdt.num_all_faces()];
    let mut seen = vec![false; cdt.num_all_faces()];
    let mut stack = Vec::new();
    for e in cdt.directed_edges() {
        if e.face().is_outer() {
            if let Some(t) = e.rev().face().as_inner() {
                stack.push((t, e.is_constraint_edge()));
            }
        }
    }
    while let Some((t, state)) = stack.pop() {
        let i = t.fix().index();
        if seen[i] {
            continue;
        }
        seen[i] = true;
        inside[i] = state;
        for e in t.adjacent_edges() {
            if let Some(u) = e.rev().face().as_inner() {
                if !seen[u.fix().index()] {
                    stack.push((u, state ^ e.is_constraint_edge()));
                }
            }
        }
    }
    inside
}

/// spade's accepted magnitudes: `[2^-142, 2^201]` and zero, as binary exponents.
const SPADE_MIN_EXPONENT: i32 = -142;
/// Values below `2^201`, that is with exponent at most 200, are accepted.
const SPADE_MAX_EXPONENT: i32 = 200;

/// A power of two that brings every nonzero magnitude of `points` into spade's range (1 when
/// they already are), or `None` when no power of two does or a coordinate is not finite.
/// Every scaled value is a normal number, so the scaling is exact.
fn spade_scale(points: &[[f64; 2]]) -> Option<f64> {
    let mut range: Option<(i32, i32)> = None;
    for &x in points.as_flattened() {
        if !x.is_finite() {
            return None;
        }
        if x != 0.0 {
            let e = exponent(x);
            range = Some(range.map_or((e, e), |(lo, hi)| (lo.min(e), hi.max(e))));
        }
    }
    let Some((lo, hi)) = range else {
        return Some(1.0);
    };
    // Feasible shifts s: lo + s >= MIN and hi + s <= MAX; the one closest to 0.
    let (least, most) = (SPADE_MIN_EXPONENT - lo, SPADE_MAX_EXPONENT - hi);
    if least > most {
        return None;
    }
    let shift = 0.clamp(least, most);
    // lo >= -1074 and hi <= 1023 keep the shift in [-823, 932]: a normal power of two.
    Some(power_of_two(shift))
}

/// `2^e` for `e` in `[-1022, 1023]`.
fn power_of_two(e: i32) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

/// The binary exponent of a finite nonzero `x`: `floor(log2 |x|)`, subnormals included.
fn exponent(x: f64) -> i32 {
    let bits = x.to_bits() & !(1 << 63);
    let biased = (bits >> 52) as i32;
    if biased == 0 {
        // Subnormal: the value is mantissa * 2^-1074.
        63 - bits.leading_zeros() as i32 - 1074
    } else {
        biased - 1023
    }
}

#[cfg(test)]
mod tests;
