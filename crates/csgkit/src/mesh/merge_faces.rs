//! Output faces from an engine's triangles: the triangles that came from one source face
//! (equal [`Provenance`]) merged back into polygons, or paired into convex quads.
//!
//! # Contract
//! In: a triangle mesh whose only attribute is its provenance (what an engine has before
//! [`inherit_attributes`](super::inherit_attributes)), and the source meshes the provenance
//! names. Out, by [`FaceMode`]:
//! - [`FaceMode::Triangles`]: the mesh unchanged;
//! - [`FaceMode::Polygons`]: every face a simple polygon (no corner repeated) that is a union
//!   of the input's triangles of one provenance and that the fan from its first corner
//!   triangulates (so readers that fan polygons, as many do, read it right); a region with
//!   holes, or that no corner sees whole, is cut into few such pieces along existing
//!   triangle sides; a piece stays as its triangles unless the one triangulator
//!   ([`triangulate_faces`](super::triangulate_faces)), which readers of the written face
//!   apply, gives back its triangles or the piece is exactly flat (corners an ulp apart can
//!   turn a side in the polygon's own projection, and other diagonals of a polygon flat only
//!   to its corners' rounding can cross a neighbour);
//! - [`FaceMode::Quads`]: triangles and strictly convex quads, each quad two triangles of one
//!   provenance, written from a corner of the side they share, so that the fan from its first
//!   corner gives back those two triangles.
//!
//! A face whose merged boundary has the corners of its source face, at the same positions
//! (a face nothing cut), is written with the source's corners in the source's cyclic order,
//! starting at the same corner: it comes back as it was read.
//!
//! Only triangle sides used by exactly two triangles, once in each direction, both of one
//! provenance, are dissolved, so edges where more faces meet stay, and the polygons conform
//! to their neighbours exactly as the triangles did; the sides at a vertex inside the region
//! that other faces also use (a solid touching the face at one point) stay too, so that
//! vertex remains a corner. Every decision is combinatorial, except
//! the convexity of quads and the apex's view of a piece (exact `orient2d` of the f64 corners
//! projected along the dominant axis of the first triangle's or the region's normal).
//! Because every face is a union of the input's triangles, the input's triangulation, which
//! the engine certified, is one triangulation of each face without new vertices; the fan from
//! the first corner is another, valid in the face's projection, and what the one triangulator
//! reads is the certified one or lies in one plane with it, so a written polygon is read as a
//! surface the engine certified.
//!
//! # Algorithm
//! A provenance with one triangle is that triangle (counted per source face, so nearly all
//! of a large result passes through in one linear scan). The others are sorted by
//! provenance, and for each: the sides to dissolve (their uses counted over the whole
//! mesh), the connected regions across them, and per region:
//! - polygons: pieces grown breadth-first across dissolved sides from the lowest free
//!   triangle, with each of its corners as apex in turn (the largest piece kept): a triangle
//!   joins when its third corner is not yet in the piece (so the piece stays a disk with a
//!   simple boundary) and the apex sees both its new boundary sides (exact `orient2d` in the
//!   region's projection: the fan triangle turns like the region, so the fan tiles the
//!   piece); then neighbouring pieces are joined while they share only the side between them
//!   and the apex of one sees the other's whole boundary; each piece's boundary is traced by
//!   turning around its corners through its triangles and starts at the apex;
//! - quads: triangles paired greedily across dissolved sides where the pair is strictly
//!   convex, those with fewest choices first; each quad's boundary starts at a corner of the
//!   side it dissolved.
//!
//! Faces keep the order of their lowest triangle.

use crate::par::*;
use rustc_hash::{FxHashMap, FxHashSet};

use crate::kernel::{Axis, Sign, orient2d, orient3d};

use super::numbering::FaceNumbering;
use super::triangulate::polygon_triangles;
use super::vector::triangle_normal;
use super::{Mesh, MeshParts, Provenance};

/// The faces an engine writes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FaceMode {
    /// Simple polygons without holes, each from one source face (`--polygons`).
    Polygons,
    /// Triangles and strictly convex quads (`--quads`), as Freixas et al. output.
    Quads,
    /// Triangles (`--triangles`): per merged face, a triangulation without new vertices.
    #[default]
    Triangles,
}

/// The faces of `mesh` merged by provenance as `mode` asks (see the module docs).
/// `sources` are the meshes the provenance names (operand `k` is `sources[k]`).
///
/// # Panics
/// If `mesh` has polygons or attributes other than provenance (engines call this before
/// their results inherit attributes), or a provenance names no face of `sources`.
pub fn merge_faces(mesh: Mesh, mode: FaceMode, sources: &[&Mesh]) -> Mesh {
    let Some(provenance) = mesh.face_provenance() else {
        return mesh;
    };
    if mode == FaceMode::Triangles {
        return mesh;
    }
    assert!(mesh.is_triangle_mesh(), "merge_faces takes triangles");
    debug_assert_eq!(
        MeshParts {
            positions: Vec::new(),
            corners: Vec::new(),
            face_provenance: None,
            ..mesh.parts().clone()
        },
        MeshParts::default(),
        "merge_faces takes a mesh whose only attribute is provenance"
    );
    // Source faces numbered densely; most keep one triangle and pass through untouched.
    let numbering = FaceNumbering::new(sources);
    let dense = |f: u32| numbering.of(provenance[f as usize]);
    let mut uses = vec![0u32; numbering.total() as usize];
    for f in 0..mesh.face_count() as u32 {
        uses[dense(f) as usize] += 1;
    }
    let mut shared: Vec<u32> = (0..mesh.face_count() as u32)
        .filter(|&f| uses[dense(f) as usize] > 1)
        .collect();
    shared.par_sort_unstable_by_key(|&f| (dense(f), f));
    let runs: Vec<&[u32]> = shared.chunk_by(|&f, &g| dense(f) == dense(g)).collect();
    let corners = mesh.corners();
    let triangle = |f: u32| -> [u32; 3] {
        let f = 3 * f as usize;
        [corners[f], corners[f + 1], corners[f + 2]]
    };
    let dissolved = dissolved_sides(&mesh, &runs);
    let merged: Vec<(u32, Vec<u32>)> = (runs.par_iter())
        .flat_map_iter(|run| {
            let region = Region::new(run, &triangle, &dissolved);
            let source = provenance[run[0] as usize];
            region.faces(mode, mesh.positions(), source_corners(sources, source))
        })
        .collect();
    // Each merged face takes the place of its lowest triangle; its other triangles go.
    let mut slot = vec![u32::MAX; mesh.face_count()];
    for (i, (first, _)) in merged.iter().enumerate() {
        slot[*first as usize] = i as u32;
    }
    let mut out_corners = Vec::with_capacity(corners.len());
    let mut starts = Vec::with_capacity(mesh.face_count() + 1);
    let mut out_provenance = Vec::with_capacity(mesh.face_count());
    for f in 0..mesh.face_count() as u32 {
        let polygon: &[u32] = if uses[dense(f) as usize] == 1 {
            &corners[3 * f as usize..3 * f as usize + 3]
        } else if slot[f as usize] != u32::MAX {
            &merged[slot[f as usize] as usize].1
        } else {
            continue;
        };
        starts.push(out_corners.len() as u32);
        out_corners.extend_from_slice(polygon);
        out_provenance.push(provenance[f as usize]);
    }
    starts.push(out_corners.len() as u32);
    let polygons = out_corners.len() != 3 * out_provenance.len();
    let parts = MeshParts {
        corners: out_corners,
        face_starts: polygons.then_some(starts),
        face_provenance: Some(out_provenance),
        ..mesh.into_parts()
    };
    Mesh::from_parts(parts).expect("merged faces use the mesh's own vertices")
}

/// The corners' positions of the face `source` names.
fn source_corners(sources: &[&Mesh], source: Provenance) -> Vec<[f64; 3]> {
    let mesh = sources[source.operand.index()];
    (mesh.face(source.face).iter())
        .map(|&v| mesh.positions()[v as usize])
        .collect()
}

/// The undirected sides, as `(low, high)` vertex pairs, that two triangles of one run use in
/// opposite directions and no other triangle uses, except around a pinch: a vertex inside a
/// run's region (every side of the run at it dissolved) that other faces also use, where a
/// solid touches the face at one point. Dissolved, its sides would leave the vertex inside a
/// polygon that does not have it as a corner, and the faces at it would touch the polygon's
/// interior: its sides stay.
fn dissolved_sides(mesh: &Mesh, runs: &[&[u32]]) -> FxHashSet<(u32, u32)> {
    let mut dissolved = shared_sides(mesh, runs);
    let corners = mesh.corners();
    let mut faces_at = vec![0u32; mesh.vertex_count()];
    for &v in corners {
        faces_at[v as usize] += 1;
    }
    let pinched: Vec<(u32, u32)> = (runs.par_iter())
        .filter(|run| run.len() > 1)
        .flat_map_iter(|run| {
            // Per vertex: the run's triangles at it, and its dissolved sides at it.
            let mut own: FxHashMap<u32, (u32, u32)> = FxHashMap::default();
            let mut sides = Vec::new();
            for &f in run.iter() {
                let c = &corners[3 * f as usize..3 * f as usize + 3];
                for i in 0..3 {
                    let (a, b) = (c[i], c[(i + 1) % 3]);
                    own.entry(a).or_default().0 += 1;
                    if a < b && dissolved.contains(&(a, b)) {
                        sides.push((a, b));
                        own.entry(a).or_default().1 += 1;
                        own.entry(b).or_default().1 += 1;
                    }
                }
            }
            let pinch = |v: u32| {
                let (triangles, inner) = own[&v];
                inner == triangles && faces_at[v as usize] > triangles
            };
            (sides.into_iter())
                .filter(|&(a, b)| pinch(a) || pinch(b))
                .collect::<Vec<_>>()
        })
        .collect();
    for side in pinched {
        dissolved.remove(&side);
    }
    dissolved
}

/// The undirected sides, as `(low, high)` vertex pairs, that two triangles of one run use in
/// opposite directions and no other triangle uses.
fn shared_sides(mesh: &Mesh, runs: &[&[u32]]) -> FxHashSet<(u32, u32)> {
    let corners = mesh.corners();
    let side = |f: u32, i: usize| {
        let f = 3 * f as usize;
        (corners[f + i], corners[f + (i + 1) % 3])
    };
    let candidates: Vec<(u32, u32)> = (runs.par_iter())
        .filter(|run| run.len() > 1)
        .flat_map_iter(|run| {
            let directed: FxHashSet<(u32, u32)> = (run.iter())
                .flat_map(|&f| (0..3).map(move |i| side(f, i)))
                .collect();
            let mut inner: Vec<(u32, u32)> = (directed.iter())
                .filter(|&&(a, b)| a < b && directed.contains(&(b, a)))
                .copied()
                .collect();
            inner.sort_unstable();
            inner
        })
        .collect();
    let mut uses: FxHashMap<(u32, u32), u32> = candidates.iter().map(|&e| (e, 0)).collect();
    let mut marked = vec![false; mesh.vertex_count()];
    for &(a, b) in &candidates {
        marked[a as usize] = true;
        marked[b as usize] = true;
    }
    for f in 0..mesh.face_count() as u32 {
        for i in 0..3 {
            let (a, b) = side(f, i);
            if marked[a as usize] && marked[b as usize] {
                if let Some(count) = uses.get_mut(&(a.min(b), a.max(b))) {
                    *count += 1;
                }
            }
        }
    }
    (uses.into_iter())
        .filter(|&(_, count)| count == 2)
        .map(|(e, _)| e)
        .collect()
}

/// The triangles of one provenance, with their neighbours across dissolved sides.
struct Region {
    /// Mesh face index of each triangle, ascending.
    faces: Vec<u32>,
    /// Corners of each triangle.
    triangles: Vec<[u32; 3]>,
    /// Per triangle and side (from corner `i` to `i + 1`): the triangle across it, if the
    /// side is dissolved.
    across: Vec<[Option<u32>; 3]>,
}

impl Region {
    fn new(
        run: &[u32],
        triangle: &impl Fn(u32) -> [u32; 3],
        dissolved: &FxHashSet<(u32, u32)>,
    ) -> Self {
        let faces = run.to_vec();
        let triangles: Vec<[u32; 3]> = faces.iter().map(|&f| triangle(f)).collect();
        let mut by_side: FxHashMap<(u32, u32), u32> = FxHashMap::default();
        for (i, t) in triangles.iter().enumerate() {
            for j in 0..3 {
                by_side.insert((t[j], t[(j + 1) % 3]), i as u32);
            }
        }
        let across = (triangles.iter())
            .map(|t| {
                std::array::from_fn(|j| {
                    let (a, b) = (t[j], t[(j + 1) % 3]);
                    if dissolved.contains(&(a.min(b), a.max(b))) {
                        by_side.get(&(b, a)).copied()
                    } else {
                        None
                    }
                })
            })
            .collect();
        Self {
            faces,
            triangles,
            across,
        }
    }

    /// The output faces of the region, each with the mesh index of its lowest triangle.
    fn faces(
        &self,
        mode: FaceMode,
        positions: &[[f64; 3]],
        source: Vec<[f64; 3]>,
    ) -> Vec<(u32, Vec<u32>)> {
        let first = self
            .faces
            .iter()
            .copied()
            .min()
            .expect("a region has a triangle");
        if let Some(polygon) = self.as_read(positions, &source) {
            return vec![(first, polygon)];
        }
        let frame = Frame::of(&self.triangles, positions);
        let pieces: Vec<(Vec<u32>, Option<u32>)> = match mode {
            FaceMode::Polygons => (self.fans(&frame, positions).into_iter())
                .map(|(piece, apex)| (piece, Some(apex)))
                .collect(),
            FaceMode::Quads => (self.quads(positions).into_iter())
                .map(|piece| {
                    let apex = self.shared_corner(&piece);
                    (piece, apex)
                })
                .collect(),
            FaceMode::Triangles => (0..self.triangles.len() as u32)
                .map(|i| (vec![i], None))
                .collect(),
        };
        (pieces.into_iter())
            .flat_map(|(piece, apex)| {
                let mut polygon = self.boundary(&piece);
                if let Some(at) = apex.and_then(|a| polygon.iter().position(|&v| v == a)) {
                    polygon.rotate_left(at);
                }
                if polygon.len() > 3 && !self.reads_as_certified(positions, &piece, &polygon) {
                    return (piece.iter())
                        .map(|&i| (self.faces[i as usize], self.triangles[i as usize].to_vec()))
                        .collect();
                }
                let first = piece.iter().map(|&i| self.faces[i as usize]).min();
                vec![(first.expect("a piece has a triangle"), polygon)]
            })
            .collect()
    }

    /// Whether a reader that triangulates `polygon` (the boundary of `piece`) with the one
    /// triangulator gets a surface the engine certified: the piece's own triangles, or any
    /// triangles when every corner lies exactly in one plane (they tile the same flat
    /// region). Otherwise its triangles are written instead. A piece is valid in the region's
    /// projection, where it is grown, but a polygon of rounded corners is flat only to an
    /// ulp: in its own projection (its Newell normal's) corners an ulp apart can turn a side
    /// the other way, so the triangulator rejects it, and from six corners on it is cut
    /// along other diagonals (a strip), whose triangles, tilted by the corners' rounding,
    /// can cross a neighbour's.
    fn reads_as_certified(&self, positions: &[[f64; 3]], piece: &[u32], polygon: &[u32]) -> bool {
        let Some(mut read) = polygon_triangles(positions, polygon) else {
            return false;
        };
        let mut certified: Vec<[u32; 3]> = (piece.iter())
            .map(|&i| self.triangles[i as usize])
            .collect();
        for triangles in [&mut read, &mut certified] {
            for t in triangles.iter_mut() {
                let first = (0..3).min_by_key(|&k| t[k]).expect("three corners");
                t.rotate_left(first);
            }
            triangles.sort_unstable();
        }
        if read == certified {
            return true;
        }
        let [a, b, c] = certified[0].map(|v| positions[v as usize]);
        (polygon.iter()).all(|&v| orient3d(a, b, c, positions[v as usize]) == Sign::Zero)
    }

    /// The source polygon, in its own order from its own first corner, when the region is
    /// exactly that polygon again: one boundary loop with the source's corners at the same
    /// positions (a face nothing cut).
    fn as_read(&self, positions: &[[f64; 3]], source: &[[f64; 3]]) -> Option<Vec<u32>> {
        let boundary_sides = (self.across.iter())
            .map(|sides| sides.iter().filter(|k| k.is_none()).count())
            .sum::<usize>();
        if boundary_sides != source.len() {
            return None;
        }
        let all: Vec<u32> = (0..self.triangles.len() as u32).collect();
        let mut polygon = self.boundary(&all);
        let n = polygon.len();
        let at = |v: u32| positions[v as usize];
        if n != source.len() {
            return None;
        }
        let start = (0..n).find(|&r| at(polygon[r]) == source[0])?;
        (0..n)
            .all(|m| at(polygon[(start + m) % n]) == source[m])
            .then(|| {
                polygon.rotate_left(start);
                polygon
            })
    }

    /// Pieces covering the region, each a simple polygon that the fan from one of its corners
    /// (its apex) triangulates (see the module docs), as lists of triangles with the apex.
    fn fans(&self, frame: &Frame, positions: &[[f64; 3]]) -> Vec<(Vec<u32>, u32)> {
        let n = self.triangles.len();
        let mut piece_of = vec![u32::MAX; n];
        let mut pieces: Vec<(Vec<u32>, u32)> = Vec::new();
        for seed in 0..n as u32 {
            if piece_of[seed as usize] != u32::MAX {
                continue;
            }
            let best = (self.triangles[seed as usize].into_iter())
                .map(|apex| (self.grow(seed, apex, &piece_of, frame, positions), apex))
                .max_by_key(|(members, _)| members.len())
                .expect("a triangle has corners");
            for &i in &best.0 {
                piece_of[i as usize] = pieces.len() as u32;
            }
            pieces.push(best);
        }
        // Join neighbouring pieces that share only the side between them, where the apex of
        // one sees the whole boundary of the other.
        let mut changed = true;
        while changed {
            changed = false;
            for i in 0..n {
                for j in 0..3 {
                    let Some(k) = self.across[i][j] else { continue };
                    let (p, q) = (piece_of[i] as usize, piece_of[k as usize] as usize);
                    if p == q {
                        continue;
                    }
                    let Some(apex) = self.joined_apex(&pieces[p], &pieces[q], frame, positions)
                    else {
                        continue;
                    };
                    let (keep, gone) = (p.min(q), p.max(q));
                    let moved = std::mem::take(&mut pieces[gone].0);
                    for &t in &moved {
                        piece_of[t as usize] = keep as u32;
                    }
                    pieces[keep].0.extend(moved);
                    pieces[keep].1 = apex;
                    changed = true;
                }
            }
        }
        pieces.retain(|(members, _)| !members.is_empty());
        for (members, _) in &mut pieces {
            members.sort_unstable();
        }
        pieces.sort_unstable_by_key(|(members, _)| members[0]);
        pieces
    }

    /// The triangles of a piece grown breadth-first from `seed` across dissolved sides, among
    /// triangles in no piece yet, while it stays simple (each new triangle brings a new
    /// corner) and `apex` sees every side of its boundary.
    fn grow(
        &self,
        seed: u32,
        apex: u32,
        piece_of: &[u32],
        frame: &Frame,
        positions: &[[f64; 3]],
    ) -> Vec<u32> {
        let mut members = vec![seed];
        let mut corners: FxHashSet<u32> = self.triangles[seed as usize].into_iter().collect();
        let mut queue = std::collections::VecDeque::from([seed]);
        while let Some(i) = queue.pop_front() {
            let t = self.triangles[i as usize];
            for j in 0..3 {
                let Some(k) = self.across[i as usize][j] else {
                    continue;
                };
                if piece_of[k as usize] != u32::MAX || members.contains(&k) {
                    continue;
                }
                let (a, b) = (t[j], t[(j + 1) % 3]);
                let c = self.third_corner(k, i, j);
                if corners.contains(&c)
                    || !frame.sees(apex, a, c, positions)
                    || !frame.sees(apex, c, b, positions)
                {
                    continue;
                }
                corners.insert(c);
                members.push(k);
                queue.push_back(k);
            }
        }
        members
    }

    /// The apex of pieces `p` and `q` joined, if they share only the side between them and
    /// the apex of one sees every boundary side of the other.
    fn joined_apex(
        &self,
        p: &(Vec<u32>, u32),
        q: &(Vec<u32>, u32),
        frame: &Frame,
        positions: &[[f64; 3]],
    ) -> Option<u32> {
        let corners = |piece: &[u32]| -> FxHashSet<u32> {
            (piece.iter())
                .flat_map(|&i| self.triangles[i as usize])
                .collect()
        };
        if corners(&p.0).intersection(&corners(&q.0)).count() != 2 {
            return None;
        }
        let sees_all = |apex: u32, other: &[u32], own: &[u32]| {
            other.iter().all(|&i| {
                let t = self.triangles[i as usize];
                (0..3).all(|j| {
                    let inner = (self.across[i as usize][j])
                        .is_some_and(|k| other.contains(&k) || own.contains(&k));
                    inner || frame.sees(apex, t[j], t[(j + 1) % 3], positions)
                })
            })
        };
        if sees_all(p.1, &q.0, &p.0) {
            Some(p.1)
        } else if sees_all(q.1, &p.0, &q.0) {
            Some(q.1)
        } else {
            None
        }
    }

    /// The corner of triangle `k` that is not on the side it shares with side `j` of `i`.
    fn third_corner(&self, k: u32, i: u32, j: usize) -> u32 {
        let t = self.triangles[i as usize];
        let (a, b) = (t[j], t[(j + 1) % 3]);
        (self.triangles[k as usize].into_iter())
            .find(|&c| c != a && c != b)
            .expect("a triangle has a corner off each side")
    }

    /// Triangles and strictly convex quads covering the region, as lists of triangles.
    fn quads(&self, positions: &[[f64; 3]]) -> Vec<Vec<u32>> {
        let n = self.triangles.len();
        let partners: Vec<Vec<u32>> = (0..n)
            .map(|i| {
                (0..3)
                    .filter_map(|j| {
                        let k = self.across[i][j]?;
                        self.is_convex_pair(i as u32, j, k, positions).then_some(k)
                    })
                    .collect()
            })
            .collect();
        let mut by_choices: Vec<u32> = (0..n as u32).collect();
        by_choices.sort_by_key(|&i| (partners[i as usize].len(), i));
        let mut paired = vec![false; n];
        let mut pieces = Vec::with_capacity(n);
        for i in by_choices {
            if paired[i as usize] {
                continue;
            }
            paired[i as usize] = true;
            let partner = (partners[i as usize].iter())
                .copied()
                .filter(|&k| !paired[k as usize])
                .min_by_key(|&k| (partners[k as usize].len(), k));
            match partner {
                Some(k) => {
                    paired[k as usize] = true;
                    pieces.push(vec![i.min(k), i.max(k)]);
                }
                None => pieces.push(vec![i]),
            }
        }
        pieces.sort_unstable_by_key(|piece| piece[0]);
        pieces
    }

    /// For a quad (two triangles), a corner of the side its triangles share: written from it,
    /// the quad is fanned across that side. Its four corners need not lie in one plane (a cut
    /// face after rounding), and across the other diagonal it would be another surface, which
    /// can cross its neighbours where the certified triangles do not.
    fn shared_corner(&self, piece: &[u32]) -> Option<u32> {
        let [i, k] = piece else { return None };
        let other = self.triangles[*k as usize];
        (self.triangles[*i as usize].into_iter()).find(|v| other.contains(v))
    }

    /// Whether triangle `i` and triangle `k` across its side `j` make a strictly convex quad.
    fn is_convex_pair(&self, i: u32, j: usize, k: u32, positions: &[[f64; 3]]) -> bool {
        let t = self.triangles[i as usize];
        let (a, b, c) = (t[j], t[(j + 1) % 3], t[(j + 2) % 3]);
        let d = self.third_corner(k, i, j);
        let p = |v: u32| positions[v as usize];
        let normal = triangle_normal([p(a), p(b), p(c)]);
        let drop = Axis::of_largest(normal).index();
        let (u, w) = ((drop + 1) % 3, (drop + 2) % 3);
        let flat = |v: u32| [p(v)[u], p(v)[w]];
        let turn = orient2d(flat(a), flat(b), flat(c));
        let quad = [a, d, b, c];
        turn != Sign::Zero
            && (0..4).all(|m| {
                orient2d(
                    flat(quad[m]),
                    flat(quad[(m + 1) % 4]),
                    flat(quad[(m + 2) % 4]),
                ) == turn
            })
    }

    /// The boundary loop of `piece` (a disk with a simple boundary), traced by turning around
    /// each corner through the piece's triangles.
    fn boundary(&self, piece: &[u32]) -> Vec<u32> {
        let inside: FxHashSet<u32> = piece.iter().copied().collect();
        let is_boundary =
            |i: u32, j: usize| self.across[i as usize][j].is_none_or(|k| !inside.contains(&k));
        let (first, first_side) = (piece.iter())
            .find_map(|&i| (0..3).find(|&j| is_boundary(i, j)).map(|j| (i, j)))
            .expect("a piece has a boundary");
        let mut polygon = Vec::with_capacity(piece.len() + 2);
        let (mut i, mut j) = (first, first_side);
        loop {
            polygon.push(self.triangles[i as usize][j]);
            // The next boundary side starts at the end of this one: turn around that corner.
            let mut next = (j + 1) % 3;
            while !is_boundary(i, next) {
                let k = self.across[i as usize][next].expect("an inner side has a triangle");
                let corner = self.triangles[i as usize][(next + 1) % 3];
                let back = (0..3)
                    .find(|&m| self.triangles[k as usize][m] == corner)
                    .expect("the triangle across shares the side");
                i = k;
                next = (back + 1) % 3;
            }
            j = next;
            if (i, j) == (first, first_side) || polygon.len() > 3 * piece.len() {
                break;
            }
        }
        polygon
    }
}

/// The projection of a region for 2D orientation tests: the coordinates kept when the
/// dominant axis of its summed normal is dropped, and the turn of its triangles there.
struct Frame {
    u: usize,
    v: usize,
    turn: Sign,
}

impl Frame {
    fn of(triangles: &[[u32; 3]], positions: &[[f64; 3]]) -> Self {
        let p = |v: u32| positions[v as usize];
        let normal = (triangles.iter())
            .map(|t| triangle_normal(t.map(p)))
            .fold([0.0; 3], |n, m| [n[0] + m[0], n[1] + m[1], n[2] + m[2]]);
        let drop = Axis::of_largest(normal).index();
        let turn = if normal[drop] < 0.0 {
            Sign::Negative
        } else {
            Sign::Positive
        };
        Self {
            u: (drop + 1) % 3,
            v: (drop + 2) % 3,
            turn,
        }
    }

    /// Whether the fan triangle from `apex` over the side from `a` to `b` turns like the
    /// region (exact `orient2d` of the projected f64 corners), or is no triangle (the side
    /// ends at the apex).
    fn sees(&self, apex: u32, a: u32, b: u32, positions: &[[f64; 3]]) -> bool {
        if apex == a || apex == b {
            return true;
        }
        let flat = |x: u32| [positions[x as usize][self.u], positions[x as usize][self.v]];
        orient2d(flat(apex), flat(a), flat(b)) == self.turn
    }
}
