//! Splitting non-manifold edges and vertices apart by duplicating vertices, so that a closed
//! mesh becomes a combinatorial 2-manifold with the same surface.
//!
//! # Contract
//! [`split_non_manifold`] takes a closed, consistently oriented mesh (csgkit's *closed*: every
//! edge is used as often in each direction, so two cubes sharing an edge or a vertex qualify)
//! and returns the same surface in which every edge has exactly two uses, one in each
//! direction, and the corners at every vertex form a single fan: the 2-manifold that Manifold
//! (`elalish/manifold`) hands out for non-manifold results.
//! - Only vertices change. Equal positions are welded first ([`weld_positions`], `-0.0` equal
//!   to `0.0`), and a welded vertex whose corners form several fans gets one copy per extra
//!   fan, with the same position and vertex colour. Faces, their order, every face attribute
//!   (provenance, material, group, colour) and every corner attribute are kept, so welding the
//!   output again gives the welded input back: the split is a pure duplication.
//! - Vertex order: the welded vertices in first-occurrence order (as [`weld`](super::weld())),
//!   then the copies in the order of their first corner. A welded 2-manifold comes back equal
//!   to its input.
//! - Touching parts come apart: where several sheets of surface meet at an edge, the two faces
//!   bounding each solid wedge around it are joined, so two cubes sharing an edge become two
//!   separate cubes (the erosion view of Manifold, and of the orthogonal engine's `manifold`
//!   stage). One configuration cannot come apart by duplicating vertices: two sheets meeting
//!   at an edge whose ends each have a single fan (two pillars touching along an edge between
//!   two slabs). Separating them needs a second copy of the edge between the same two
//!   positions, which Manifold's `DedupeEdge` makes with two zero-area triangles and the
//!   orthogonal engine with a midpoint; both add faces. Here the two sheets are joined the
//!   other way across the edge instead (Manifold's `FormLoop` does the same when a collapse
//!   would make such an edge), which makes their ends two fans each and keeps the faces.
//! - Faces with fewer than three distinct welded vertices take no part (as in
//!   [`Topology`](super::Topology)); their corners keep the welded vertex.
//! - Any other mesh (open, misoriented) gives a valid mesh without panic: sides that cannot be
//!   paired stay unpaired, and the fans are computed all the same.
//!
//! # Algorithm
//! 1. **Weld** equal positions; everything below works on welded vertex indices.
//! 2. **Group face sides by edge**: one record per side (its origin corner, the edge's larger
//!    vertex and the direction), bucketed by smaller vertex with a counting sort and sorted
//!    within each bucket, as [`EdgeTable`](super::EdgeTable) does.
//! 3. **Pair sides** (`mate`). An edge with one use in each direction pairs them. An edge with
//!    more uses orders its faces around the edge exactly (`order_around_edge`) and matches
//!    them across the solid wedges (`match_wedges`); when a face there has no direction around
//!    the edge (zero area along it, or a polygon), the sides pair in index order instead, and
//!    step 5 still makes the result a 2-manifold.
//! 4. **Fans.** A paired side leads from one corner at a vertex to the next corner of the fan
//!    (`turn`); fans are the orbits of that step, labelled by walking them (`label_fan`).
//! 5. **Separate sheets.** At each non-manifold edge, two sheets with the same fans at both
//!    ends would be one edge used four times; they swap partners (`separate_sheets`), which
//!    splits the fan at each end in two.
//! 6. **Number**: the first fan at a vertex keeps the vertex, each later fan gets a copy.
//!
//! # Invariants
//! - `mate` is an involution on the sides it pairs, and pairs only opposite directions of one
//!   edge; every side of a closed input is paired after step 3.
//! - Every corner that takes part carries the label of its fan, and that label is a corner of
//!   the fan, so labels of different fans differ. Step 5 only ever splits fans, so an edge
//!   made distinct stays distinct.
//!
//! # Numeric model
//! Only the order of faces around a non-manifold edge looks at coordinates, through the
//! kernel's exact [`orient3d`] and [`orient2d`] on the input positions; no epsilon, no
//! constructed point. An edge with a non-finite coordinate among its faces pairs in index
//! order.
//!
//! # Complexity
//! O(V + C) for V vertices and C corners, plus O(k log k) predicates at each non-manifold edge
//! with k uses, plus a walk over the fans at both ends of an edge for each swap in step 5
//! (rare: it needs the configuration above). A mesh that is already a 2-manifold makes one
//! pass over its sides and fans and is returned as a copy. Memory: 16 bytes per side record
//! and about 20 per corner (welded vertex, mate, label, output vertex, fan numbers), 8 more
//! per corner for polygon meshes.

use std::borrow::Cow;

use super::topology::has_three_distinct;
use super::{FaceId, Mesh, MeshParts, weld_positions};
use crate::kernel::{Sign, orient2d, orient3d};

/// Marks an unpaired side, an unlabelled corner and an unnumbered fan.
const NONE: u32 = u32::MAX;

/// Returns `mesh` with its non-manifold edges and vertices split apart by duplicating vertices:
/// every edge has two uses, one in each direction, and every vertex a single fan.
///
/// The input should be closed and consistently oriented; non-manifold edges and vertices are
/// what it is for (two cubes sharing an edge or a vertex). Equal positions are welded first,
/// then a welded vertex whose corners form several fans gets one copy per extra fan, with the
/// same position and vertex colour. The output's vertices are the welded ones in
/// first-occurrence order (as [`weld`](super::weld())), then the copies; faces, their order
/// and every face and corner attribute are the input's. So welding the output gives the
/// welded input back, and a welded 2-manifold comes back unchanged.
///
/// Where surfaces touch, they come apart: around an edge with more than two uses the two faces
/// bounding each wedge of solid are joined, ordered by exact predicates (polygons there, which
/// may be non-convex, pair in index order: triangulate first to have them ordered too),
/// so two cubes sharing an edge come out as two separate cubes. The one exception is
/// two sheets meeting along an edge whose ends each have a single fan (two pillars touching
/// along an edge between two slabs): no duplication of vertices can separate them, so they are
/// joined the other way across that edge. Faces with fewer than three distinct welded
/// vertices keep their welded vertices. An open or misoriented mesh gives a valid mesh too,
/// without panic. The source file `mesh/manifold_split.rs` gives the algorithm.
///
/// # Example
/// ```
/// use csgkit::primitives::cuboid;
/// use csgkit::mesh::{analyze_topology, split_non_manifold, weld};
/// use csgkit::Mesh;
///
/// // Two unit cubes sharing the edge x = y = 1, as one mesh.
/// let (a, b) = (cuboid([0.0; 3], [1.0; 3]), cuboid([1.0, 1.0, 0.0], [2.0, 2.0, 1.0]));
/// let mut positions = a.positions().to_vec();
/// positions.extend_from_slice(b.positions());
/// let triangles: Vec<[u32; 3]> = (a.fan_triangles().map(|(_, t)| t))
///     .chain(b.fan_triangles().map(|(_, t)| t.map(|v| v + 8)))
///     .collect();
/// let (cubes, _) = weld(&Mesh::from_triangles(positions, &triangles)?);
/// assert_eq!(analyze_topology(&cubes).non_manifold_edges, 1);
///
/// let split = split_non_manifold(&cubes);
/// let topology = analyze_topology(&split);
/// assert!(topology.is_edge_manifold() && topology.is_vertex_manifold());
/// assert_eq!(topology.components, 2);
/// // Only the two vertices of the shared edge were duplicated.
/// assert_eq!(split.vertex_count(), cubes.vertex_count() + 2);
/// assert_eq!(weld(&split).0, cubes);
/// # Ok::<(), csgkit::InvalidMesh>(())
/// ```
pub fn split_non_manifold(mesh: &Mesh) -> Mesh {
    let welding = weld_positions(mesh.positions());
    let welded = welding.duplicate_count() > 0;
    let vertex: Cow<[u32]> = if welded {
        Cow::Owned(
            mesh.corners()
                .iter()
                .map(|&v| welding.remap[v as usize])
                .collect(),
        )
    } else {
        Cow::Borrowed(mesh.corners())
    };
    let positions: Cow<[[f64; 3]]> = if welded {
        let at = |&v: &u32| mesh.positions()[v as usize];
        Cow::Owned(welding.representatives.iter().map(at).collect())
    } else {
        Cow::Borrowed(mesh.positions())
    };
    let corners = Corners::new(mesh, &vertex, &positions);
    let mut pairing = corners.pair_sides();
    let mut label = corners.label_fans(&pairing.mate);
    corners.separate_sheets(&mut pairing, &mut label);
    let (numbered, copies) = corners.number_fans(&label);
    if copies.is_empty() && !welded {
        return mesh.clone();
    }
    let mut positions = positions.into_owned();
    for &v in &copies {
        positions.push(positions[v as usize]);
    }
    // Each welded vertex, and each copy, takes the colour of its first occurrence.
    let first_occurrences = (0..welding.welded_count() as u32).chain(copies);
    let input = mesh.parts();
    let vertex_colors = (input.vertex_colors.as_ref()).map(|colors| {
        (first_occurrences.map(|v| colors[welding.representatives[v as usize] as usize])).collect()
    });
    // Every buffer named, so that a new one cannot be forgotten here.
    let parts = MeshParts {
        positions,
        corners: numbered,
        face_starts: input.face_starts.clone(),
        face_materials: input.face_materials.clone(),
        materials: input.materials.clone(),
        face_groups: input.face_groups.clone(),
        groups: input.groups.clone(),
        face_colors: input.face_colors.clone(),
        face_provenance: input.face_provenance.clone(),
        corner_uvs: input.corner_uvs.clone(),
        corner_normals: input.corner_normals.clone(),
        vertex_colors,
        material_libraries: input.material_libraries.clone(),
    };
    let split = Mesh { parts };
    debug_assert!(
        split.check_invariants().is_ok(),
        "the split only renumbers corners and appends vertices"
    );
    split
}

/// The welded corners of a mesh, how they follow each other around their faces, and which of
/// them take part.
struct Corners<'a> {
    /// The welded vertex of each corner.
    vertex: &'a [u32],
    /// The welded positions.
    positions: &'a [[f64; 3]],
    /// The next and previous corner around the face, stored for polygon meshes only: a
    /// triangle's are found by arithmetic.
    rings: Option<(Vec<u32>, Vec<u32>)>,
    /// Whether each corner's face has three distinct welded vertices.
    active: Vec<bool>,
}

/// One face side, the directed use of an edge, named by the corner it leaves.
#[derive(Clone, Copy, Debug)]
struct Side {
    /// `(larger << 1) | forward`: the edge's larger vertex, and 1 when the side runs from the
    /// smaller vertex to the larger. The smaller vertex is the bucket the record sits in.
    key: u64,
    /// The corner the side leaves.
    corner: u32,
}

impl Side {
    fn is_forward(&self) -> bool {
        self.key & 1 == 1
    }
}

/// The paired sides, and the sheets of every non-manifold edge.
struct Pairing {
    /// The side paired with each side (sides are named by the corner they leave), or
    /// [`NONE`].
    mate: Vec<u32>,
    /// `[forward side, backward side]` of each pair at a non-manifold edge.
    sheets: Vec<[u32; 2]>,
    /// Each non-manifold edge's sheets are `sheets[edge_sheets[e]..edge_sheets[e + 1]]`.
    edge_sheets: Vec<u32>,
}

/// A face around a non-manifold edge `a → b` (`a` the smaller vertex), for the radial order.
#[derive(Clone, Copy, Debug)]
struct Spoke {
    /// The side's corner.
    corner: u32,
    /// The side runs `a → b`. Such a face closes a solid wedge when turning around the edge by
    /// the right-hand rule; a backward face opens one.
    forward: bool,
    /// The face's third vertex: the face is the half-plane from the edge through it.
    apex: [f64; 3],
    /// The signs of the components of `(b − a) × (apex − a)`, the face's normal direction.
    normal: [Sign; 3],
    /// The sector around the edge, measured from the first spoke: 0 on its half-plane, 1 up
    /// to the opposite half-plane, 2 on it, 3 beyond.
    sector: u8,
}

impl<'a> Corners<'a> {
    fn new(mesh: &Mesh, vertex: &'a [u32], positions: &'a [[f64; 3]]) -> Self {
        let mut active = Vec::with_capacity(vertex.len());
        let mut rings =
            (!mesh.is_triangle_mesh()).then(|| (vec![0; vertex.len()], vec![0; vertex.len()]));
        for f in 0..mesh.face_count() {
            let range = mesh.face_range(FaceId::new(f));
            let takes_part = has_three_distinct(&vertex[range.clone()]);
            active.extend(std::iter::repeat_n(takes_part, range.len()));
            if let Some((next, prev)) = &mut rings {
                let (first, last) = (range.start as u32, range.end as u32 - 1);
                for c in first..=last {
                    next[c as usize] = if c == last { first } else { c + 1 };
                    prev[c as usize] = if c == first { last } else { c - 1 };
                }
            }
        }
        Self {
            vertex,
            positions,
            rings,
            active,
        }
    }

    fn next(&self, c: u32) -> u32 {
        match &self.rings {
            Some((next, _)) => next[c as usize],
            None if c % 3 == 2 => c - 2,
            None => c + 1,
        }
    }

    fn prev(&self, c: u32) -> u32 {
        match &self.rings {
            Some((_, prev)) => prev[c as usize],
            None if c % 3 == 0 => c + 2,
            None => c - 1,
        }
    }

    fn position(&self, c: u32) -> [f64; 3] {
        self.positions[self.vertex[c as usize] as usize]
    }

    /// Whether the side leaving `c` joins two corners of one vertex (a repeated corner of a
    /// polygon): it belongs to no edge, and joins the two corners' fans.
    fn is_zero_length(&self, c: u32) -> bool {
        self.vertex[c as usize] == self.vertex[self.next(c) as usize]
    }

    /// Step 2: the sides of the active faces, bucketed by smaller vertex and sorted by key and
    /// corner within each bucket; bucket `v` is `sides[starts[v]..starts[v + 1]]`.
    fn sides_by_edge(&self) -> (Vec<Side>, Vec<u32>) {
        let sides = || {
            (0..self.vertex.len() as u32)
                .filter(|&c| self.active[c as usize] && !self.is_zero_length(c))
                .map(|c| {
                    (
                        c,
                        self.vertex[c as usize],
                        self.vertex[self.next(c) as usize],
                    )
                })
        };
        let mut starts = vec![0u32; self.positions.len() + 1];
        for (_, v, w) in sides() {
            starts[v.min(w) as usize + 1] += 1;
        }
        for v in 1..starts.len() {
            starts[v] += starts[v - 1];
        }
        let empty = Side { key: 0, corner: 0 };
        let mut sorted = vec![empty; *starts.last().expect("one entry per vertex + 1") as usize];
        let mut slot = starts.clone();
        for (corner, v, w) in sides() {
            let key = (u64::from(v.max(w)) << 1) | u64::from(v < w);
            sorted[slot[v.min(w) as usize] as usize] = Side { key, corner };
            slot[v.min(w) as usize] += 1;
        }
        for bucket in starts.windows(2) {
            sorted[bucket[0] as usize..bucket[1] as usize]
                .sort_unstable_by_key(|s| (s.key, s.corner));
        }
        (sorted, starts)
    }

    /// Step 3: pairs the sides of every edge.
    fn pair_sides(&self) -> Pairing {
        let (sides, starts) = self.sides_by_edge();
        let mut pairing = Pairing {
            mate: vec![NONE; self.vertex.len()],
            sheets: Vec::new(),
            edge_sheets: vec![0],
        };
        for bucket in starts.windows(2) {
            let bucket = &sides[bucket[0] as usize..bucket[1] as usize];
            for uses in bucket.chunk_by(|s, t| s.key >> 1 == t.key >> 1) {
                match uses {
                    [s, t] if s.is_forward() != t.is_forward() => {
                        pairing.link(s.corner, t.corner);
                    }
                    [_, _, _, ..] => {
                        self.pair_around_edge(uses, &mut pairing);
                        pairing.edge_sheets.push(pairing.sheets.len() as u32);
                    }
                    // A boundary or misoriented edge: nothing to pair.
                    _ => {}
                }
            }
        }
        pairing
    }

    /// Pairs the sides of one non-manifold edge (`uses`, sorted by direction then corner):
    /// across the solid wedges when every face has a direction around the edge, in index
    /// order otherwise.
    fn pair_around_edge(&self, uses: &[Side], pairing: &mut Pairing) {
        let first = uses[0].corner;
        let (a, b) = if uses[0].is_forward() {
            (self.position(first), self.position(self.next(first)))
        } else {
            (self.position(self.next(first)), self.position(first))
        };
        let spokes: Option<Vec<Spoke>> = uses.iter().map(|s| self.spoke(a, b, s)).collect();
        match spokes {
            Some(mut spokes) => {
                order_around_edge(a, b, &mut spokes);
                match_wedges(&spokes, pairing);
            }
            None => {
                // Backward sides sort first (their key ends in 0).
                let split = uses.partition_point(|s| !s.is_forward());
                for (g, f) in uses[..split].iter().zip(&uses[split..]) {
                    pairing.link(f.corner, g.corner);
                    pairing.sheets.push([f.corner, g.corner]);
                }
            }
        }
    }

    /// The spoke of a side on the edge `a → b`, or `None` when its face has no direction
    /// around the edge: not a triangle (a polygon's next corner need not lie on its side of
    /// the edge), zero area, or a non-finite coordinate.
    fn spoke(&self, a: [f64; 3], b: [f64; 3], side: &Side) -> Option<Spoke> {
        let opposite = self.next(self.next(side.corner));
        if self.next(opposite) != side.corner {
            return None;
        }
        let apex = self.position(opposite);
        if !a.iter().chain(&b).chain(&apex).all(|x| x.is_finite()) {
            return None;
        }
        let normal = normal_signs(a, b, apex);
        (normal != [Sign::Zero; 3]).then_some(Spoke {
            corner: side.corner,
            forward: side.is_forward(),
            apex,
            normal,
            sector: 0,
        })
    }

    /// σ: the corner that follows `c` in its fan, leaving `c`'s face through the side that
    /// leaves `c` and entering the paired face at the same vertex. `None` at an unpaired side.
    fn turn(&self, mate: &[u32], c: u32) -> Option<u32> {
        if self.is_zero_length(c) {
            return Some(self.next(c));
        }
        let m = mate[c as usize];
        (m != NONE).then(|| self.next(m))
    }

    /// σ⁻¹: the corner that `c` follows in its fan.
    fn turn_back(&self, mate: &[u32], c: u32) -> Option<u32> {
        let p = self.prev(c);
        if self.is_zero_length(p) {
            return Some(p);
        }
        let m = mate[p as usize];
        (m != NONE).then_some(m)
    }

    /// Step 4: the fan label of every active corner ([`NONE`] for the others).
    fn label_fans(&self, mate: &[u32]) -> Vec<u32> {
        let mut label = vec![NONE; self.vertex.len()];
        for c in 0..self.vertex.len() as u32 {
            if self.active[c as usize] && label[c as usize] == NONE {
                self.label_fan(mate, &mut label, c);
            }
        }
        label
    }

    /// Labels the fan of `start` with `start`.
    ///
    /// σ is injective (`mate` is an involution, and zero-length sides are never paired), so a
    /// fan is a cycle or, around an unpaired side, a path: walk forward until back at `start`,
    /// and from a dead end walk backward from `start` too.
    fn label_fan(&self, mate: &[u32], label: &mut [u32], start: u32) {
        let mut c = start;
        loop {
            label[c as usize] = start;
            match self.turn(mate, c) {
                Some(n) if n == start => return,
                Some(n) => c = n,
                None => break,
            }
        }
        let mut c = start;
        while let Some(p) = self.turn_back(mate, c) {
            label[p as usize] = start;
            c = p;
        }
    }

    /// Step 5: at each non-manifold edge, while two sheets have the same fans at both ends,
    /// swaps their backward sides and relabels the fans at the ends.
    ///
    /// Sheets `(f, g)` and `(f', g')` on one fan at end `a` lie on its cycle as
    /// `f → g … f' → g' …` (σ steps from a forward side's corner to its partner's); pairing
    /// `(f, g')` and `(f', g)` instead cuts it into `f → g' … f` and `f' → g … f'`, and
    /// likewise at `b`. So each swap splits one fan at each end, the two new sheets end on
    /// different fans, and fans elsewhere only get finer: at most k − 1 swaps for k sheets.
    fn separate_sheets(&self, pairing: &mut Pairing, label: &mut [u32]) {
        for e in 0..pairing.edge_sheets.len() - 1 {
            let range = pairing.edge_sheets[e] as usize..pairing.edge_sheets[e + 1] as usize;
            for _ in 1..range.len() {
                let Some((i, j)) = self.shared_ends(&pairing.sheets[range.clone()], label) else {
                    break;
                };
                let ([f, g], [f2, g2]) = (
                    pairing.sheets[range.start + i],
                    pairing.sheets[range.start + j],
                );
                pairing.link(f, g2);
                pairing.link(f2, g);
                pairing.sheets[range.start + i] = [f, g2];
                pairing.sheets[range.start + j] = [f2, g];
                for start in [f, f2, self.next(f), self.next(f2)] {
                    self.label_fan(&pairing.mate, label, start);
                }
            }
        }
    }

    /// Two sheets of one edge with the same fans at both ends (the first two in sheet order),
    /// if any.
    fn shared_ends(&self, sheets: &[[u32; 2]], label: &[u32]) -> Option<(usize, usize)> {
        let mut ends: Vec<(u32, u32, usize)> = (sheets.iter().enumerate())
            .map(|(i, &[f, _])| (label[f as usize], label[self.next(f) as usize], i))
            .collect();
        ends.sort_unstable();
        ends.windows(2)
            .find(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
            .map(|w| (w[0].2, w[1].2))
    }

    /// Step 6: the output vertex of every corner, and the welded vertex each copy duplicates.
    ///
    /// Corners are visited in order, so the first fan met at a vertex keeps it and the copies
    /// are numbered by their first corner. Corners of faces that take no part keep their
    /// welded vertex.
    fn number_fans(&self, label: &[u32]) -> (Vec<u32>, Vec<u32>) {
        let vertex_count = self.positions.len();
        let mut fan_vertex = vec![NONE; self.vertex.len()];
        let mut claimed = vec![false; vertex_count];
        let mut copies = Vec::new();
        let numbered = (self.vertex.iter().zip(label))
            .map(|(&v, &fan)| {
                if fan == NONE {
                    return v;
                }
                let id = &mut fan_vertex[fan as usize];
                if *id == NONE {
                    *id = if claimed[v as usize] {
                        copies.push(v);
                        (vertex_count + copies.len() - 1) as u32
                    } else {
                        claimed[v as usize] = true;
                        v
                    };
                }
                *id
            })
            .collect();
        (numbered, copies)
    }
}

impl Pairing {
    fn link(&mut self, s: u32, t: u32) {
        self.mate[s as usize] = t;
        self.mate[t as usize] = s;
    }
}

/// Sorts the spokes of the edge `a → b` by angle around it (right-hand rule about `b − a`),
/// from the first spoke's half-plane; faces on one half-plane put the closing (forward) ones
/// first, so the zero-width wedges between touching faces count as outside.
///
/// The angle θ of a spoke is compared exactly: `orient3d(a, b, p, q)` is negative exactly
/// when θ_q − θ_p lies in (0, π). With the first spoke `r` at θ = 0, that sign against `r`
/// puts every spoke in (0, π) or (π, 2π), or on the plane of `r`; there the normal's signs
/// tell `r`'s half-plane (same normal) from the opposite one. Within a sector the angles
/// differ by less than π, so the same sign orders them: a total order, as sorting needs.
fn order_around_edge(a: [f64; 3], b: [f64; 3], spokes: &mut [Spoke]) {
    let (r, r_normal) = (spokes[0].apex, spokes[0].normal);
    for spoke in spokes.iter_mut() {
        spoke.sector = match orient3d(a, b, r, spoke.apex) {
            Sign::Negative => 1,
            Sign::Positive => 3,
            Sign::Zero if spoke.normal == r_normal => 0,
            Sign::Zero => 2,
        };
    }
    // Tied faces: closers before openers; closers by increasing corner and openers by
    // decreasing corner, so that the wedges of coincident copies of one surface nest with
    // the first copy innermost: each copy's faces pair with the same copy's.
    let tie = |s: &Spoke| {
        let corner = i64::from(s.corner);
        (!s.forward, if s.forward { corner } else { -corner })
    };
    spokes.sort_by(|p, q| {
        (p.sector.cmp(&q.sector))
            .then_with(|| orient3d(a, b, p.apex, q.apex).to_ordering())
            .then_with(|| tie(p).cmp(&tie(q)))
    });
}

/// Pairs the spokes, sorted around their edge, across the solid wedges.
///
/// Turning by increasing angle, a backward face opens a wedge of solid and a forward face
/// closes one (its outward normal points ahead). Matching them like parentheses, from just
/// after the lowest nesting depth, pairs the two faces that bound each solid wedge; where
/// solids overlap (depth 2 and more) the wedges nest. An unbalanced edge leaves the extra
/// sides unpaired.
fn match_wedges(spokes: &[Spoke], pairing: &mut Pairing) {
    let (mut depth, mut lowest, mut start) = (0i64, 0i64, 0);
    for (i, spoke) in spokes.iter().enumerate() {
        depth += if spoke.forward { -1 } else { 1 };
        if depth < lowest {
            (lowest, start) = (depth, i + 1);
        }
    }
    let mut open = Vec::new();
    for k in 0..spokes.len() {
        let spoke = spokes[(start + k) % spokes.len()];
        if !spoke.forward {
            open.push(spoke.corner);
        } else if let Some(g) = open.pop() {
            pairing.link(spoke.corner, g);
            pairing.sheets.push([spoke.corner, g]);
        }
    }
}

/// The signs of the components of `(b − a) × (p − a)`: component k is the orientation of the
/// triangle projected along axis k, its other coordinates taken in cyclic order.
fn normal_signs(a: [f64; 3], b: [f64; 3], p: [f64; 3]) -> [Sign; 3] {
    std::array::from_fn(|k| {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        orient2d([a[u], a[v]], [b[u], b[v]], [p[u], p[v]])
    })
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::mesh::{MeshParts, OperandId, Topology, analyze_topology, measure, weld};
    use crate::ortho::{MeshOptions, box_union};
    use crate::primitives::{cuboid, icosphere, torus};

    /// The unit cube with its minimum corner at `at`.
    fn unit_cube(at: [f64; 3]) -> Mesh {
        cuboid(at, at.map(|x| x + 1.0))
    }

    /// The meshes side by side in one mesh, without welding: a closed face soup.
    fn soup(meshes: &[Mesh]) -> Mesh {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for mesh in meshes {
            let offset = positions.len() as u32;
            positions.extend_from_slice(mesh.positions());
            triangles.extend(mesh.fan_triangles().map(|(_, t)| t.map(|v| v + offset)));
        }
        Mesh::from_triangles(positions, &triangles).unwrap()
    }

    fn cubes(corners: &[[f64; 3]]) -> Mesh {
        soup(&corners.iter().map(|&at| unit_cube(at)).collect::<Vec<_>>())
    }

    /// The union of unit grid cubes, as the orthogonal engine's triangle or polygon mesh.
    fn box_union_mesh(cells: &[[f64; 3]], triangles: bool) -> Mesh {
        let boxes: Vec<[f64; 6]> = (cells.iter())
            .map(|c| [c[0], c[1], c[2], c[0] + 1.0, c[1] + 1.0, c[2] + 1.0])
            .collect();
        let options = MeshOptions {
            triangles,
            manifold: false,
        };
        box_union(&boxes).unwrap().to_mesh(options).unwrap().mesh
    }

    /// Splits `input` and checks the whole contract: a closed, oriented 2-manifold with the
    /// same faces and attributes, whose welding is the welded input. Returns the output and
    /// its topology.
    fn split_checked(input: &Mesh) -> (Mesh, Topology) {
        let output = split_non_manifold(input);
        output.check_invariants().unwrap();
        // No welding here: `analyze` would merge the copies back.
        let topology = analyze_topology(&output);
        assert!(
            topology.is_closed() && topology.is_oriented(),
            "{topology:?}"
        );
        assert!(topology.is_edge_manifold(), "{topology:?}");
        assert!(topology.is_vertex_manifold(), "{topology:?}");
        let (welded_input, _) = weld(input);
        assert_eq!(
            weld(&output).0,
            welded_input,
            "the split is only a duplication"
        );
        assert_eq!(output.face_count(), input.face_count());
        assert_eq!(measure(&output), measure(input));
        (output, topology)
    }

    /// The number of vertices added to the welded input.
    fn added_vertices(input: &Mesh, output: &Mesh) -> usize {
        output.vertex_count() - weld(input).1.welded_count()
    }

    #[test]
    fn a_welded_two_manifold_comes_back_unchanged() {
        for mesh in [
            unit_cube([0.0; 3]),
            icosphere([1.0, 2.0, 3.0], 2.0, 2),
            torus([0.0; 3], 3.0, 1.0, 8, 6),
        ] {
            assert_eq!(split_non_manifold(&mesh), mesh);
        }
    }

    #[test]
    fn a_two_manifold_soup_is_only_welded() {
        // Two cubes apart, then every triangle stored with its own corners (STL-style).
        let apart = cubes(&[[0.0; 3], [3.0, 0.0, 0.0]]);
        let positions: Vec<[f64; 3]> = apart
            .corners()
            .iter()
            .map(|&v| apart.positions()[v as usize])
            .collect();
        let triangles: Vec<[u32; 3]> = (0..apart.face_count() as u32)
            .map(|f| [3 * f, 3 * f + 1, 3 * f + 2])
            .collect();
        let stl = Mesh::from_triangles(positions, &triangles).unwrap();
        let (output, topology) = split_checked(&stl);
        assert_eq!(output, weld(&stl).0);
        assert_eq!((output.vertex_count(), topology.components), (16, 2));
    }

    #[test]
    fn two_cubes_sharing_an_edge_come_apart() {
        let input = cubes(&[[0.0; 3], [1.0, 1.0, 0.0]]);
        assert_eq!(analyze_topology(&weld(&input).0).non_manifold_edges, 1);
        let (output, topology) = split_checked(&input);
        assert_eq!(added_vertices(&input, &output), 2);
        assert_eq!((topology.components, topology.genus), (2, Some(0)));
        assert_eq!(measure(&output).volume, 2.0);
    }

    #[test]
    fn two_cubes_sharing_a_vertex_come_apart() {
        // No non-manifold edge: only the fans at the shared vertex tell the cubes apart.
        let input = cubes(&[[0.0; 3], [1.0; 3]]);
        let before = analyze_topology(&weld(&input).0);
        assert_eq!(
            (before.non_manifold_edges, before.non_manifold_vertices),
            (0, 1)
        );
        let (output, topology) = split_checked(&input);
        assert_eq!(added_vertices(&input, &output), 1);
        assert_eq!((topology.components, topology.genus), (2, Some(0)));
    }

    #[test]
    fn cubes_touching_around_one_edge_come_apart() {
        // Three and four cubes of a 2 × 2 × 1 block, and the two diagonal pairs of a 2 × 2 × 2
        // block (a 3D checkerboard): as soups, each cube's faces touch its neighbours' faces,
        // edges or vertices, and every cube comes out on its own.
        for corners in [
            &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]][..],
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            &[
                [0.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [1.0, 0.0, 1.0],
                [0.0, 1.0, 1.0],
            ],
        ] {
            let (output, topology) = split_checked(&cubes(corners));
            assert_eq!(output.vertex_count(), 8 * corners.len());
            assert_eq!(topology.components, corners.len());
        }
    }

    #[test]
    fn coincident_copies_of_a_surface_nest_in_index_order() {
        // The same cube twice: every edge has four uses on two half-planes.
        let input = cubes(&[[0.0; 3], [0.0; 3]]);
        let (output, topology) = split_checked(&input);
        assert_eq!((output.vertex_count(), topology.components), (16, 2));
        // Each copy keeps its own faces together: the first cube's faces use the first eight
        // vertices.
        assert!(output.corners()[..36].iter().all(|&v| v < 8));
    }

    #[test]
    fn pillars_touching_between_two_slabs_are_joined_across_their_edge() {
        // Two diagonal unit pillars between two 2 × 2 slabs: the pillars touch along the
        // segment x = y = 1, 0 ≤ z ≤ 1, whose ends each have one fan. Separating the pillars
        // would need a second edge between the same two vertices, so they are joined the
        // other way across it: each end splits in two, and the solid is a ball.
        let mut boxes = vec![[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            boxes.extend([[x, y, -1.0], [x, y, 1.0]]);
        }
        let input = box_union_mesh(&boxes, true);
        assert_eq!(analyze_topology(&input).non_manifold_edges, 1);
        let (output, topology) = split_checked(&input);
        assert_eq!(added_vertices(&input, &output), 2);
        assert_eq!((topology.components, topology.genus), (1, Some(0)));
        assert_eq!(measure(&output).volume, 10.0);
    }

    #[test]
    fn faces_of_zero_area_on_the_edge_pair_in_index_order() {
        // Two cubes sharing the edge a–b (the first cube's vertices 3 and 7), and a closed pair
        // of needles a, b, m with m on the line beyond b: they have no direction around a–b.
        let mut parts = cubes(&[[0.0; 3], [1.0, 1.0, 0.0]]).into_parts();
        let (a, b, m) = (3, 7, parts.positions.len() as u32);
        parts.positions.push([1.0, 1.0, 2.0]);
        parts.corners.extend([a, b, m, a, m, b]);
        let input = Mesh::from_parts(parts).unwrap();
        assert_eq!(
            input.position(crate::VertexId::new(a as usize)),
            [1.0, 1.0, 0.0]
        );
        split_checked(&input);
    }

    #[test]
    fn polygon_faces_are_split_too() {
        // The orthogonal engine's quads; at the shared edge they pair in index order.
        let input = box_union_mesh(&[[0.0; 3], [1.0, 1.0, 0.0]], false);
        assert!(!input.is_triangle_mesh());
        let (output, topology) = split_checked(&input);
        assert_eq!(added_vertices(&input, &output), 2);
        assert_eq!(topology.components, 2);
    }

    #[test]
    fn attributes_are_kept() {
        let mut input = cubes(&[[0.0; 3], [1.0, 1.0, 0.0]]);
        input.set_operand(OperandId::new(2));
        let (faces, corners, vertices) = (
            input.face_count(),
            input.corner_count(),
            input.vertex_count(),
        );
        let input = Mesh::from_parts(MeshParts {
            face_materials: Some((0..faces as u32).map(|f| f % 2).collect()),
            materials: vec!["red".into(), "blue".into()],
            face_groups: Some(vec![0; faces]),
            groups: vec!["cubes".into()],
            face_colors: Some((0..faces).map(|f| [f as u8, 0, 0, 255]).collect()),
            corner_uvs: Some((0..corners).map(|c| [c as f64, 0.5]).collect()),
            corner_normals: Some(vec![[0.0, 0.0, 1.0]; corners]),
            vertex_colors: Some((0..vertices).map(|v| [0, v as u8, 0, 255]).collect()),
            material_libraries: vec!["cubes.mtl".into()],
            ..input.into_parts()
        })
        .unwrap();
        let (output, _) = split_checked(&input);
        let (before, after) = (input.parts(), output.parts());
        let face_and_corner_attributes = |p: &MeshParts| {
            (
                p.face_materials.clone(),
                p.materials.clone(),
                p.face_groups.clone(),
                p.groups.clone(),
                p.face_colors.clone(),
                p.face_provenance.clone(),
                p.corner_uvs.clone(),
                p.corner_normals.clone(),
                p.material_libraries.clone(),
            )
        };
        assert_eq!(
            face_and_corner_attributes(before),
            face_and_corner_attributes(after)
        );
        // Every corner shows the colour of its input vertex's first occurrence.
        let first = weld_positions(input.positions());
        let colors_in = before.vertex_colors.as_ref().unwrap();
        let colors_out = after.vertex_colors.as_ref().unwrap();
        for (&v_in, &v_out) in before.corners.iter().zip(&after.corners) {
            let representative = first.representatives[first.remap[v_in as usize] as usize];
            assert_eq!(
                colors_out[v_out as usize],
                colors_in[representative as usize]
            );
        }
    }

    #[test]
    fn open_and_misoriented_meshes_do_not_panic() {
        let cube = unit_cube([0.0; 3]);
        let mut triangles: Vec<[u32; 3]> = cube.fan_triangles().map(|(_, t)| t).collect();
        triangles.pop();
        triangles[0].swap(1, 2);
        // Three faces on one edge, unbalanced.
        triangles.push(triangles[1]);
        let mesh = Mesh::from_triangles(cube.positions().to_vec(), &triangles).unwrap();
        let output = split_non_manifold(&mesh);
        output.check_invariants().unwrap();
        assert_eq!(weld(&output).0, mesh);
    }

    /// The unit cells of a 3 × 3 × 3 grid that `mask` selects.
    fn cells(mask: u32) -> Vec<[f64; 3]> {
        (0..27)
            .filter(|i| mask >> i & 1 == 1)
            .map(|i| [i % 3, i / 3 % 3, i / 9].map(f64::from))
            .collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Any union of grid cubes splits into a closed oriented 2-manifold of the same volume,
        /// as triangles (ordered around edges) or polygons (paired in index order).
        #[test]
        fn unions_of_grid_cubes_split_into_two_manifolds(mask in 1u32..1 << 27) {
            let cells = cells(mask);
            for triangles in [true, false] {
                let input = box_union_mesh(&cells, triangles);
                let (output, _) = split_checked(&input);
                prop_assert_eq!(measure(&output).volume, cells.len() as f64);
            }
        }

        /// Soups of grid cubes, repeats allowed, overlap and touch in every way; the split
        /// keeps every cube on its own.
        #[test]
        fn soups_of_grid_cubes_come_apart_into_cubes(
            picks in prop::collection::vec(0u32..27, 1..8),
        ) {
            let corners: Vec<[f64; 3]> = picks.iter().map(|&i| cells(1 << i)[0]).collect();
            let (output, topology) = split_checked(&cubes(&corners));
            prop_assert_eq!(topology.components, corners.len());
            prop_assert_eq!(output.vertex_count(), 8 * corners.len());
        }

        /// The same with distinct cubes and their faces in random order, so that index order
        /// says nothing: only the order around each edge keeps the cubes apart.
        #[test]
        fn shuffled_soups_of_grid_cubes_come_apart_into_cubes(
            mask in 1u32..1 << 27,
            seed in any::<u64>(),
        ) {
            let corners = cells(mask);
            let input = shuffled(&cubes(&corners), seed);
            let (output, topology) = split_checked(&input);
            prop_assert_eq!(topology.components, corners.len());
            prop_assert_eq!(output.vertex_count(), 8 * corners.len());
        }
    }

    /// `mesh`'s triangles in an order drawn from `seed` (Fisher–Yates on xorshift64*).
    fn shuffled(mesh: &Mesh, seed: u64) -> Mesh {
        let mut triangles: Vec<[u32; 3]> = mesh.fan_triangles().map(|(_, t)| t).collect();
        let mut state = seed | 1;
        for i in (1..triangles.len()).rev() {
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            let j = (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 33) as usize % (i + 1);
            triangles.swap(i, j);
        }
        Mesh::from_triangles(mesh.positions().to_vec(), &triangles).unwrap()
    }
}
