//! Algorithm 3 (`design/ortho.md` §A5): faces with an outer loop and holes, from the vertices
//! and their degrees alone.
//!
//! For each orientation o = (axis k, sign s), and each plane p[k] = c holding vertices:
//! 1. **Frame.** (a, b) = (k+1, k+2) mod 3 for s = +, else (k+2, k+1), so CCW in (a, b) is CCW
//!    seen from outside ([`Orientation::frame`]).
//! 2. **Copies.** Each vertex on the plane contributes `deg_o` copies of (p[a], p[b]).
//! 3. **Edges by pairing.** On each b-line, consecutive copies in a-order pair into a-edges;
//!    likewise b-edges. An odd count on a line is an error. Zero-length pairs (the two copies
//!    of a pass-through vertex on the line across the face) are discarded.
//! 4. **Orientation from the quadrants.** Each copy carries the quadrants around its vertex
//!    that the face covers (from the octant code, or from the material corner); an edge runs
//!    so that the face lies on its left, which its lower end's quadrants on the edge's side
//!    tell. (The paper sweeps the parity of the parallel edges instead: same answer, a
//!    log factor and a sort more.)
//! 5. **Linking.** Positions are numbered in (a, b) order and the half-edges counting-sorted
//!    by start; at a position with two outgoing half-edges, continue straight if possible,
//!    else turn left: the left turn hugs the occupied quadrant ("erosion semantics").
//! 6. **Cycles.** A cycle is an outer loop (CCW) iff it leaves its lexicographically smallest
//!    position along +a; otherwise it is a hole (CW).
//! 7. **Holes.** Each hole belongs to the face of the nearest b-edge on the left of its
//!    smallest position, found by an a-sweep over a "last writer wins" tree.
//!
//! Conventions fixed by the left-turn rule: two faces touching at a point are separate faces;
//! a hole touching its outer boundary at one point merges into the outer loop, which becomes
//! weakly simple and visits the pinch twice; two holes touching at a point make one loop.
//!
//! Invariant established: every loop edge is axis-parallel, loops alternate a- and b-edges
//! except through pass-through vertices, and every 3D edge lies in 2 or 4 loops with
//! cancelling directions (checked by the tests).
//! Numeric model: ranks and comparisons only. Complexity: O(E log E) per plane, planes of one
//! orientation in parallel.

use crate::par::*;

use crate::progress::{Progress, Stage};

use super::OrthoError;
use super::materials::FaceCorner;
use super::sweep::RankVertex;

/// The orientation of a face: its outward normal, one of the six axis directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Orientation {
    /// Outward normal +x.
    PosX,
    /// Outward normal −x.
    NegX,
    /// Outward normal +y.
    PosY,
    /// Outward normal −y.
    NegY,
    /// Outward normal +z.
    PosZ,
    /// Outward normal −z.
    NegZ,
}

impl Orientation {
    /// All six, in the degree order +x, −x, +y, −y, +z, −z.
    pub const ALL: [Self; 6] = [
        Self::PosX,
        Self::NegX,
        Self::PosY,
        Self::NegY,
        Self::PosZ,
        Self::NegZ,
    ];

    /// The index in the degree order (+x, −x, +y, −y, +z, −z).
    pub fn index(self) -> usize {
        self as usize
    }

    /// The normal's axis: 0, 1 or 2.
    pub fn axis(self) -> usize {
        self.index() / 2
    }

    /// True for +x, +y, +z.
    pub fn is_positive(self) -> bool {
        self.index() % 2 == 0
    }

    /// The in-plane axes (a, b) in which CCW is CCW as seen from outside the solid.
    pub fn frame(self) -> (usize, usize) {
        let k = self.axis();
        if self.is_positive() {
            ((k + 1) % 3, (k + 2) % 3)
        } else {
            ((k + 2) % 3, (k + 1) % 3)
        }
    }
}

/// A face loop before mapping to the B-rep: vertex indices in order.
pub(crate) struct PlaneFace {
    pub material: u32,
    pub outer: Vec<u32>,
    pub holes: Vec<Vec<u32>>,
}

/// One copy of a vertex on a face plane, in the face frame.
#[derive(Clone, Copy, Debug)]
struct Copy2 {
    /// (plane, material, b, a) packed high to low: sorting on it sorts the copies, and equal
    /// keys mean the same corner (a position holds one vertex).
    key: u128,
    vertex: u32,
    /// The quadrants around the vertex covered by the face, bit `sa | sb << 1`.
    quadrants: u8,
}

impl Copy2 {
    fn plane_material(&self) -> u64 {
        (self.key >> 64) as u64
    }

    fn material(&self) -> u32 {
        (self.key >> 64) as u32
    }

    fn b(&self) -> u32 {
        (self.key >> 32) as u32
    }

    fn a(&self) -> u32 {
        self.key as u32
    }
}

/// Steps 1–8 for every orientation: (orientation, faces) in orientation then plane order.
///
/// Without `corners`, each vertex's degrees count copies on material 0; with them, the copies
/// are the given face corners, and faces are extracted per material as well. Each face plane
/// done is reported to `progress`.
///
/// # Errors
/// [`OrthoError::InconsistentDegrees`] (a broken invariant), [`OrthoError::Cancelled`].
pub(crate) fn extract_faces(
    vertices: &[RankVertex],
    corners: Option<&[FaceCorner]>,
    progress: &Progress,
) -> Result<Vec<(Orientation, PlaneFace)>, OrthoError> {
    let per_orientation: Vec<Vec<Copy2>> = Orientation::ALL
        .par_iter()
        .map(|&o| face_copies(vertices, corners, o))
        .collect();
    // Every (orientation, plane) is independent: one parallel task each, results in order.
    let planes: Vec<(Orientation, &[Copy2])> = Orientation::ALL
        .iter()
        .zip(&per_orientation)
        .flat_map(|(&o, copies)| {
            copies
                .chunk_by(|x, y| x.plane_material() == y.plane_material())
                .map(move |p| (o, p))
        })
        .collect();
    let counter = progress.counter(Stage::Loops, planes.len());
    let per_plane: Vec<Result<Vec<PlaneFace>, OrthoError>> = planes
        .par_iter()
        .map(|&(o, p)| {
            if counter.is_cancelled() {
                return Ok(Vec::new());
            }
            let faces = plane_faces(p, o);
            counter.advance(1);
            faces
        })
        .collect();
    counter.finish()?;
    let mut faces = Vec::new();
    for ((o, _), result) in planes.iter().zip(per_plane) {
        faces.extend(result?.into_iter().map(|f| (*o, f)));
    }
    Ok(faces)
}

/// Steps 1–2: the copies of every vertex for orientation `o`, sorted by
/// (plane, material, b, a).
fn face_copies(
    vertices: &[RankVertex],
    corners: Option<&[FaceCorner]>,
    o: Orientation,
) -> Vec<Copy2> {
    let (k, (a, b)) = (o.axis(), o.frame());
    let copy = |i: u32, material: u32, quadrants: u8| {
        let r = vertices[i as usize].rank;
        let key = [r[k], material, r[b], r[a]]
            .iter()
            .fold(0u128, |key, &x| key << 32 | u128::from(x));
        Copy2 {
            key,
            vertex: i,
            quadrants,
        }
    };
    let quadrants: [u8; 256] = std::array::from_fn(|code| face_quadrants(code as u8, o));
    let copies: Vec<Copy2> = match corners {
        None => (0..vertices.len() as u32)
            .flat_map(|i| {
                let v = &vertices[i as usize];
                let degree = v.degrees[o.index()];
                let quadrants = quadrants[usize::from(v.code)];
                std::iter::repeat_n(copy(i, 0, quadrants), degree.into())
            })
            .collect(),
        Some(corners) => corners
            .iter()
            .filter(|c| usize::from(c.orientation) == o.index())
            .flat_map(|c| {
                std::iter::repeat_n(copy(c.vertex, c.material, c.quadrants), c.degree.into())
            })
            .collect(),
    };
    sort_copies(copies)
}

/// Sorts copies by key: a stable counting sort by plane, then each plane in parallel. The
/// copies come in vertex order, (z, y, x), which already is (b, a) order within a plane for
/// +x, −y and +z, so half of the orientations only check their planes.
fn sort_copies(copies: Vec<Copy2>) -> Vec<Copy2> {
    let plane = |c: &Copy2| (c.key >> 96) as usize;
    let planes = copies.iter().map(|c| plane(c) + 1).max().unwrap_or(0);
    let mut start = vec![0usize; planes + 1];
    for c in &copies {
        start[plane(c) + 1] += 1;
    }
    for p in 0..planes {
        start[p + 1] += start[p];
    }
    let mut fill = start.clone();
    let mut sorted = copies.clone();
    for c in copies {
        sorted[fill[plane(&c)]] = c;
        fill[plane(&c)] += 1;
    }
    let segments = split_lengths_mut(&mut sorted, start.windows(2).map(|w| w[1] - w[0]));
    segments.into_par_iter().for_each(|s| {
        if !s.is_sorted_by_key(|c| c.key) {
            s.sort_unstable_by_key(|c| c.key);
        }
    });
    sorted
}

/// The quadrants (bit `sa | sb << 1` in the frame of `o`) around a vertex of octant code
/// `code` that a face of orientation `o` covers: inside behind the plane, outside in front.
fn face_quadrants(code: u8, o: Orientation) -> u8 {
    let (k, (a, b)) = (o.axis(), o.frame());
    let (inner, outer) = if o.is_positive() {
        (0, 1 << k)
    } else {
        (1 << k, 0)
    };
    (0..4u8)
        .filter(|&q| {
            let s = usize::from(q & 1) << a | usize::from(q >> 1) << b;
            code >> (s | inner) & 1 == 1 && code >> (s | outer) & 1 == 0
        })
        .fold(0, |mask, q| mask | 1 << q)
}

/// A directed boundary edge in the face frame. `dir`: 0 = +a, 1 = +b, 2 = −a, 3 = −b.
/// `from_pos`/`to_pos` number the plane's positions in (a, b) order.
#[derive(Clone, Copy, Debug)]
struct HalfEdge {
    from: (u32, u32),
    to: (u32, u32),
    from_pos: u32,
    to_pos: u32,
    dir: u8,
    v_from: u32,
}

/// Steps 3–7 on one plane; `copies` are sorted by (b, a).
fn plane_faces(copies: &[Copy2], o: Orientation) -> Result<Vec<PlaneFace>, OrthoError> {
    // The copies in (a, b) order, and each copy's position number in that order.
    let mut by_a: Vec<(u64, u32)> = (0..copies.len() as u32)
        .map(|i| {
            let c = &copies[i as usize];
            (u64::from(c.a()) << 32 | u64::from(c.b()), i)
        })
        .collect();
    by_a.sort_unstable();
    let mut pos = vec![0u32; copies.len()];
    let mut positions = 0u32;
    for (j, &(key, i)) in by_a.iter().enumerate() {
        if j > 0 && by_a[j - 1].0 != key {
            positions += 1;
        }
        pos[i as usize] = positions;
    }
    let a_edges = pair_lines(0..copies.len() as u32, copies, Copy2::b, Copy2::a, o)?;
    let b_edges = pair_lines(by_a.iter().map(|p| p.1), copies, Copy2::a, Copy2::b, o)?;
    let mut half = Vec::with_capacity(a_edges.len() + b_edges.len());
    for (edges, along_b) in [(a_edges, false), (b_edges, true)] {
        for (lo, hi) in edges {
            half.push(half_edge(copies, &pos, lo, hi, along_b, o)?);
        }
    }
    let (half, start) = sort_by_start(half, positions as usize + 1, o)?;
    let next = link(&half, &start, o)?;
    let (order, starts) = cycles(&next);
    let cycles: Vec<&[u32]> = starts
        .windows(2)
        .map(|w| &order[w[0] as usize..w[1] as usize])
        .collect();
    let mut faces = assemble_faces(&half, &cycles, o)?;
    faces
        .iter_mut()
        .for_each(|f| f.material = copies[0].material());
    Ok(faces)
}

/// Step 3: pairs consecutive copies (indices into `copies`, sorted by `line` then `along`)
/// on each line into edges `(lo, hi)`, dropping zero-length pairs.
fn pair_lines(
    order: impl Iterator<Item = u32>,
    copies: &[Copy2],
    line: fn(&Copy2) -> u32,
    along: fn(&Copy2) -> u32,
    o: Orientation,
) -> Result<Vec<(u32, u32)>, OrthoError> {
    let odd = OrthoError::InconsistentDegrees {
        orientation: o,
        reason: "odd number of vertex copies on a line",
    };
    let mut edges = Vec::with_capacity(copies.len() / 2);
    let mut open = None;
    for i in order {
        let Some(j) = open.take() else {
            open = Some(i);
            continue;
        };
        // A pair across two lines means the first line had an odd count.
        let (p, q) = (&copies[j as usize], &copies[i as usize]);
        if line(p) != line(q) {
            return Err(odd);
        }
        if along(p) != along(q) {
            edges.push((j, i));
        }
    }
    match open {
        Some(_) => Err(odd),
        None => Ok(edges),
    }
}

/// Step 4: the edge from copy `lo` to copy `hi` (along b or a), directed so that the face
/// lies on its left: read from the quadrants the face covers at `lo` on the edge's side.
fn half_edge(
    copies: &[Copy2],
    pos: &[u32],
    lo: u32,
    hi: u32,
    along_b: bool,
    o: Orientation,
) -> Result<HalfEdge, OrthoError> {
    let (l, h) = (&copies[lo as usize], &copies[hi as usize]);
    // Quadrant bits beside the edge at `lo`: (forward when the face is there, backward).
    let (fwd_bit, back_bit, dir) = if along_b { (2, 3, 1) } else { (3, 1, 0) };
    let (fwd, back) = (
        l.quadrants >> fwd_bit & 1 == 1,
        l.quadrants >> back_bit & 1 == 1,
    );
    let ends = [(l, pos[lo as usize]), (h, pos[hi as usize])];
    let ((f, fp), (t, tp)) = match (fwd, back) {
        (true, false) => (ends[0], ends[1]),
        (false, true) => (ends[1], ends[0]),
        _ => {
            return Err(OrthoError::InconsistentDegrees {
                orientation: o,
                reason: "an edge has the face on both or neither side",
            });
        }
    };
    Ok(HalfEdge {
        from: (f.a(), f.b()),
        to: (t.a(), t.b()),
        from_pos: fp,
        to_pos: tp,
        dir: if fwd { dir } else { dir + 2 },
        v_from: f.vertex,
    })
}

/// Sorts the half-edges by (from, dir) with a counting sort on the start position; also
/// returns where each position's outgoing half-edges start (at most two each).
fn sort_by_start(
    half: Vec<HalfEdge>,
    positions: usize,
    o: Orientation,
) -> Result<(Vec<HalfEdge>, Vec<u32>), OrthoError> {
    let mut start = vec![0u32; positions + 1];
    for h in &half {
        start[h.from_pos as usize + 1] += 1;
    }
    if start.iter().any(|&c| c > 2) {
        return Err(OrthoError::InconsistentDegrees {
            orientation: o,
            reason: "a loop position cannot be linked",
        });
    }
    for p in 0..positions {
        start[p + 1] += start[p];
    }
    let mut fill = start.clone();
    let mut order = vec![0u32; half.len()];
    for (i, h) in half.iter().enumerate() {
        order[fill[h.from_pos as usize] as usize] = i as u32;
        fill[h.from_pos as usize] += 1;
    }
    let mut sorted: Vec<HalfEdge> = order.iter().map(|&i| half[i as usize]).collect();
    for p in 0..positions {
        let s = start[p] as usize;
        if start[p + 1] as usize == s + 2 && sorted[s].dir > sorted[s + 1].dir {
            sorted.swap(s, s + 1);
        }
    }
    Ok((sorted, start))
}

/// Step 5: the successor of every half-edge (`half` sorted by (from, dir), `start` indexing
/// each position's outgoing half-edges).
fn link(half: &[HalfEdge], start: &[u32], o: Orientation) -> Result<Vec<u32>, OrthoError> {
    let mut used = vec![false; half.len()];
    let mut next = Vec::with_capacity(half.len());
    for h in half {
        let first = start[h.to_pos as usize] as usize;
        let out = &half[first..start[h.to_pos as usize + 1] as usize];
        let pick = match out.len() {
            1 => Some(0),
            2 => [h.dir, (h.dir + 1) % 4]
                .iter()
                .find_map(|&d| out.iter().position(|g| g.dir == d)),
            _ => None,
        };
        let Some(j) = pick.map(|p| first + p).filter(|&j| !used[j]) else {
            return Err(OrthoError::InconsistentDegrees {
                orientation: o,
                reason: "a loop position cannot be linked",
            });
        };
        used[j] = true;
        next.push(j as u32);
    }
    Ok(next)
}

/// Step 6 (first half): the cycles of the successor permutation, in order of their first
/// half-edge, concatenated (one buffer, not one per cycle), with each cycle's start and the
/// end.
fn cycles(next: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let mut seen = vec![false; next.len()];
    let (mut order, mut starts) = (Vec::with_capacity(next.len()), vec![0]);
    for s in 0..next.len() {
        if seen[s] {
            continue;
        }
        let mut h = s;
        while !seen[h] {
            seen[h] = true;
            order.push(h as u32);
            h = next[h] as usize;
        }
        starts.push(order.len() as u32);
    }
    (order, starts)
}

/// Steps 6–7: classifies the cycles, assigns each hole to its face and emits the faces.
fn assemble_faces(
    half: &[HalfEdge],
    cycles: &[&[u32]],
    o: Orientation,
) -> Result<Vec<PlaneFace>, OrthoError> {
    let mut cycle_of = vec![0u32; half.len()];
    // Cycles start at their smallest half-edge, whose `from` is their smallest position
    // because `half` is sorted by (from, dir).
    let mut face_of: Vec<Option<usize>> = vec![None; cycles.len()];
    let mut faces = Vec::new();
    let mut holes = Vec::new();
    for (c, cycle) in cycles.iter().enumerate() {
        for &h in cycle.iter() {
            cycle_of[h as usize] = c as u32;
        }
        let first = half[cycle[0] as usize];
        let vertices = cycle.iter().map(|&h| half[h as usize].v_from).collect();
        if first.dir == 0 {
            face_of[c] = Some(faces.len());
            faces.push(PlaneFace {
                material: 0,
                outer: vertices,
                holes: Vec::new(),
            });
        } else {
            holes.push((first.from, c, vertices));
        }
    }
    let owners = hole_owners(half, &holes);
    for ((_, c, vertices), owner) in holes.into_iter().zip(owners) {
        let face = owner.and_then(|e| face_of[cycle_of[e] as usize]);
        let Some(face) = face else {
            return Err(OrthoError::InconsistentDegrees {
                orientation: o,
                reason: "a hole lies in no face",
            });
        };
        face_of[c] = Some(face);
        faces[face].holes.push(vertices);
    }
    Ok(faces)
}

/// Step 7: for each hole (given by its smallest position, sorted), the b-half-edge nearest on
/// its left: the largest a < a_h whose span [b0, b1) holds b_h.
fn hole_owners(half: &[HalfEdge], holes: &[((u32, u32), usize, Vec<u32>)]) -> Vec<Option<usize>> {
    let mut bs: Vec<u32> = half.iter().flat_map(|h| [h.from.1, h.to.1]).collect();
    bs.sort_unstable();
    bs.dedup();
    let index = |b: u32| bs.partition_point(|&x| x < b);
    let mut b_edges: Vec<usize> = (0..half.len()).filter(|&h| half[h].dir % 2 == 1).collect();
    b_edges.sort_by_key(|&h| half[h].from.0);
    let mut order: Vec<usize> = (0..holes.len()).collect();
    order.sort_by_key(|&i| holes[i].0);
    let mut tree = LastWriter::new(bs.len());
    let mut owners = vec![None; holes.len()];
    let mut e = 0;
    for i in order {
        let (a_h, b_h) = holes[i].0;
        while e < b_edges.len() && half[b_edges[e]].from.0 < a_h {
            let h = half[b_edges[e]];
            let (b0, b1) = (h.from.1.min(h.to.1), h.from.1.max(h.to.1));
            tree.assign(index(b0), index(b1), b_edges[e]);
            e += 1;
        }
        owners[i] = tree.query(index(b_h));
    }
    owners
}

/// Range assignment and point query, "last writer wins", by timestamps on the covering nodes.
struct LastWriter {
    leaves: usize,
    nodes: Vec<(u32, usize)>,
    time: u32,
}

impl LastWriter {
    fn new(leaves: usize) -> Self {
        Self {
            leaves,
            nodes: vec![(0, usize::MAX); 4 * leaves.max(1)],
            time: 0,
        }
    }

    fn assign(&mut self, l: usize, r: usize, value: usize) {
        self.time += 1;
        self.assign_at(1, 0, self.leaves, l, r, value);
    }

    fn assign_at(&mut self, node: usize, nl: usize, nr: usize, l: usize, r: usize, value: usize) {
        if r <= nl || nr <= l || nl >= nr {
            return;
        }
        if l <= nl && nr <= r {
            self.nodes[node] = (self.time, value);
            return;
        }
        let mid = (nl + nr) / 2;
        self.assign_at(2 * node, nl, mid, l, r, value);
        self.assign_at(2 * node + 1, mid, nr, l, r, value);
    }

    fn query(&self, i: usize) -> Option<usize> {
        let (mut node, mut nl, mut nr) = (1, 0, self.leaves);
        let mut best = (0, usize::MAX);
        while nl < nr {
            best = best.max(self.nodes[node]);
            if nr - nl == 1 {
                break;
            }
            let mid = (nl + nr) / 2;
            if i < mid {
                (node, nr) = (2 * node, mid);
            } else {
                (node, nl) = (2 * node + 1, mid);
            }
        }
        (best.0 > 0).then_some(best.1)
    }
}
