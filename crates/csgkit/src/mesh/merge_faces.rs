//! Output faces from an engine's triangles: the triangles that came from one source face
//! (equal [`Provenance`]) merged back into polygons, or paired into convex quads.
//!
//! # Contract
//! In: a triangle mesh whose only attribute is its provenance (what an engine has before
//! [`inherit_attributes`](super::inherit_attributes)), and the source meshes the provenance
//! names. Out, by [`FaceMode`]:
//! - [`FaceMode::Triangles`]: the mesh unchanged;
//! - [`FaceMode::Polygons`]: every face a simple polygon (no corner repeated) that is a union
//!   of the input's triangles of one provenance; a region with holes, or whose boundary
//!   touches itself, is cut into few such pieces along existing triangle sides;
//! - [`FaceMode::Quads`]: triangles and strictly convex quads, each quad two triangles of one
//!   provenance.
//!
//! A face whose merged boundary has the corners of its source face, at the same positions
//! (a face nothing cut), is written with the source's corners in the source's cyclic order,
//! starting at the same corner: it comes back as it was read.
//!
//! Only triangle sides used by exactly two triangles, once in each direction, both of one
//! provenance, are dissolved, so edges where more faces meet stay, and the polygons conform
//! to their neighbours exactly as the triangles did. Every decision is combinatorial, except
//! the convexity of quads (exact `orient2d` of the f64 corners projected along the dominant
//! axis of the first triangle's normal). Because every face is a union of the input's
//! triangles, the triangles certify every face: the triangulation the input had is one
//! triangulation of each face without new vertices.
//!
//! # Algorithm
//! A provenance with one triangle is that triangle (counted per source face, so nearly all
//! of a large result passes through in one linear scan). The others are sorted by
//! provenance, and for each: the sides to dissolve (their uses counted over the whole mesh), the connected
//! regions across them, and per region:
//! - polygons: pieces grown breadth-first across dissolved sides, a triangle joining when its
//!   third corner is not yet in the piece (so the piece stays a disk with a simple
//!   boundary), then adjacent pieces joined while they share only the side between them; a
//!   region that needs more than two pieces (a face with holes needs at least two) is grown
//!   again from up to [`PIECE_STARTS`] first triangles and the fewest pieces kept; each
//!   piece's boundary is traced by turning around its corners through its triangles;
//! - quads: triangles paired greedily across dissolved sides where the pair is strictly
//!   convex, those with fewest choices first.
//!
//! Faces keep the order of their lowest triangle.

use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};

use crate::kernel::{Axis, Sign, orient2d};

use super::vector::triangle_normal;
use super::{Mesh, MeshParts, Provenance};

/// How many first triangles piece growing tries in a region that needs more than two pieces.
const PIECE_STARTS: usize = 16;

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
    let mut base = Vec::with_capacity(sources.len());
    let mut total = 0u32;
    for source in sources {
        base.push(total);
        total += source.face_count() as u32;
    }
    let dense = |f: u32| {
        let p = provenance[f as usize];
        base[p.operand.index()] + p.face.get()
    };
    let mut uses = vec![0u32; total as usize];
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
/// opposite directions and no other triangle uses.
fn dissolved_sides(mesh: &Mesh, runs: &[&[u32]]) -> FxHashSet<(u32, u32)> {
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
        let pieces = match mode {
            FaceMode::Polygons => self.pieces(),
            FaceMode::Quads => self.quads(positions),
            FaceMode::Triangles => (0..self.triangles.len() as u32).map(|i| vec![i]).collect(),
        };
        let whole = pieces.len() == 1;
        (pieces.into_iter())
            .map(|piece| {
                let mut polygon = self.boundary(&piece);
                if whole {
                    as_read(&mut polygon, positions, &source);
                }
                let first = piece.iter().map(|&i| self.faces[i as usize]).min();
                (first.expect("a piece has a triangle"), polygon)
            })
            .collect()
    }

    /// Simple polygons covering the region (see the module docs), as lists of triangles: the
    /// fewest pieces found by growing from a few evenly spaced first triangles.
    fn pieces(&self) -> Vec<Vec<u32>> {
        let n = self.triangles.len();
        let mut best = self.pieces_from(0);
        let step = n.div_ceil(PIECE_STARTS).max(1);
        for start in (step..n).step_by(step) {
            if best.len() <= 2 {
                break;
            }
            let other = self.pieces_from(start);
            if other.len() < best.len() {
                best = other;
            }
        }
        best
    }

    /// Pieces grown from triangle `start` first, then from the lowest triangle left, then
    /// joined where neighbours share only the side between them.
    fn pieces_from(&self, start: usize) -> Vec<Vec<u32>> {
        let n = self.triangles.len();
        let mut piece_of = vec![u32::MAX; n];
        let mut corners: Vec<FxHashSet<u32>> = Vec::new();
        for seed in std::iter::once(start).chain(0..n) {
            if piece_of[seed] != u32::MAX {
                continue;
            }
            let p = corners.len() as u32;
            piece_of[seed] = p;
            let mut have: FxHashSet<u32> = self.triangles[seed].into_iter().collect();
            let mut queue = std::collections::VecDeque::from([seed as u32]);
            while let Some(i) = queue.pop_front() {
                for j in 0..3 {
                    let Some(k) = self.across[i as usize][j] else {
                        continue;
                    };
                    if piece_of[k as usize] != u32::MAX {
                        continue;
                    }
                    let third = self.third_corner(k, i, j);
                    if have.insert(third) {
                        piece_of[k as usize] = p;
                        queue.push_back(k);
                    }
                }
            }
            corners.push(have);
        }
        // Join neighbouring pieces that share only the side between them.
        let mut changed = true;
        while changed {
            changed = false;
            for i in 0..n {
                for j in 0..3 {
                    let Some(k) = self.across[i][j] else { continue };
                    let (p, q) = (piece_of[i], piece_of[k as usize]);
                    if p == q
                        || corners[p as usize]
                            .intersection(&corners[q as usize])
                            .count()
                            != 2
                    {
                        continue;
                    }
                    let (keep, gone) = (p.min(q), p.max(q));
                    let moved = std::mem::take(&mut corners[gone as usize]);
                    corners[keep as usize].extend(moved);
                    piece_of
                        .iter_mut()
                        .filter(|x| **x == gone)
                        .for_each(|x| *x = keep);
                    changed = true;
                }
            }
        }
        let mut pieces: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
        for (i, &p) in piece_of.iter().enumerate() {
            pieces.entry(p).or_default().push(i as u32);
        }
        let mut pieces: Vec<Vec<u32>> = pieces.into_values().collect();
        pieces.sort_unstable_by_key(|piece| piece[0]);
        pieces
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

/// Rotates `polygon` into its source face's cyclic order when it has the source's corners at
/// the same positions (a face nothing cut), so it starts at the source's first corner.
fn as_read(polygon: &mut [u32], positions: &[[f64; 3]], source: &[[f64; 3]]) {
    if polygon.len() != source.len() {
        return;
    }
    let at = |v: u32| positions[v as usize];
    let n = polygon.len();
    let Some(start) = (0..n).find(|&r| at(polygon[r]) == source[0]) else {
        return;
    };
    if (0..n).all(|m| at(polygon[(start + m) % n]) == source[m]) {
        polygon.rotate_left(start);
    }
}
