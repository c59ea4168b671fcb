//! The 2-manifold option (`design/ortho.md` §A6): split non-manifold edges and vertices of the
//! shared triangle mesh so that every index-edge carries exactly two triangles.
//!
//! 1. **Pair half-edges.** A manifold edge pairs its two half-edges. At a 4-triangle edge with
//!    direction d, the half-edge of triangle F (outward normal n_F, in-face direction
//!    t_F = n_F × d) pairs with the reverse half-edge of the triangle G with n_G = −t_F: the
//!    two faces bounding the same solid wedge ("erosion", consistent with the left-turn rule
//!    of the loops).
//! 2. **Split vertices** into one copy per fan: union-find over the triangle corners glued by
//!    the paired half-edges.
//! 3. **Split sheets.** An index-edge still carrying 4 triangles (both endpoints single-fan,
//!    e.g. between two class-25 vertices) gets one midpoint vertex per sheet (pair), and the
//!    sheet's two triangles are split there. If f64 has no value strictly between the
//!    endpoints, the edge stays shared and is counted in [`MeshOutput::unsplit_edges`].
//!
//! The result may have coincident positions; STL cannot carry it (its vertices are positions),
//! so prefer OBJ, PLY or OFF for this mode.
//! Numeric model: comparisons and signs of coordinate differences; the only arithmetic is the
//! midpoint, checked to lie strictly between its endpoints.
//! Complexity: O(T log T) for T triangles.

use super::Orientation;

/// A triangle mesh being split, with one source index and normal per triangle.
pub(crate) struct TriangleSoup {
    pub positions: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    pub normals: Vec<Orientation>,
    pub sources: Vec<u32>,
}

/// One half-edge: (triangle, corner index of its origin).
type Half = (u32, u8);

impl TriangleSoup {
    fn half_ends(&self, (t, i): Half) -> (u32, u32) {
        let tri = self.triangles[t as usize];
        (tri[i as usize], tri[(i as usize + 1) % 3])
    }

    /// Runs steps 1–3 and returns the number of edges left shared.
    pub(crate) fn make_manifold(&mut self) -> usize {
        let pairs = self.pair_half_edges();
        self.split_vertices(&pairs);
        self.split_sheets(&pairs)
    }

    /// Step 1.
    fn pair_half_edges(&self) -> Vec<(Half, Half)> {
        let mut halves: Vec<((u32, u32), Half)> = (0..self.triangles.len() as u32)
            .flat_map(|t| (0..3u8).map(move |i| (t, i)))
            .map(|h| {
                let (u, v) = self.half_ends(h);
                ((u.min(v), u.max(v)), h)
            })
            .collect();
        halves.sort_unstable();
        let mut pairs = Vec::with_capacity(halves.len() / 2);
        for group in halves.chunk_by(|a, b| a.0 == b.0) {
            let (fwd, rev): (Vec<Half>, Vec<Half>) = group
                .iter()
                .map(|g| g.1)
                .partition(|&h| self.half_ends(h).0 == group[0].0.0);
            for &f in &fwd {
                let g = if rev.len() == 1 {
                    Some(rev[0])
                } else {
                    let want = neg(self.in_face(f));
                    rev.iter()
                        .copied()
                        .find(|&g| unit(self.normals[g.0 as usize]) == want)
                };
                pairs.extend(g.map(|g| (f, g)));
            }
        }
        pairs
    }

    /// t_F = n_F × d for half-edge `h`.
    fn in_face(&self, h: Half) -> [i8; 3] {
        let (u, v) = self.half_ends(h);
        let (p, q) = (self.positions[u as usize], self.positions[v as usize]);
        let d: [i8; 3] = std::array::from_fn(|k| (q[k] > p[k]) as i8 - (q[k] < p[k]) as i8);
        let n = unit(self.normals[h.0 as usize]);
        [
            n[1] * d[2] - n[2] * d[1],
            n[2] * d[0] - n[0] * d[2],
            n[0] * d[1] - n[1] * d[0],
        ]
    }

    /// Step 2.
    fn split_vertices(&mut self, pairs: &[(Half, Half)]) {
        let corner = |(t, i): Half, k: u8| 3 * t as usize + ((i + k) % 3) as usize;
        let mut uf = UnionFind::new(3 * self.triangles.len());
        for &(f, g) in pairs {
            uf.union(corner(f, 0), corner(g, 1));
            uf.union(corner(f, 1), corner(g, 0));
        }
        let mut new_index = vec![u32::MAX; 3 * self.triangles.len()];
        let mut positions = Vec::new();
        for t in 0..self.triangles.len() {
            for i in 0..3 {
                let root = uf.find(3 * t + i);
                if new_index[root] == u32::MAX {
                    new_index[root] = positions.len() as u32;
                    positions.push(self.positions[self.triangles[t][i] as usize]);
                }
                self.triangles[t][i] = new_index[root];
            }
        }
        self.positions = positions;
    }

    /// Step 3; returns the number of edges left shared.
    fn split_sheets(&mut self, pairs: &[(Half, Half)]) -> usize {
        let mut count = std::collections::HashMap::new();
        for t in 0..self.triangles.len() as u32 {
            for i in 0..3 {
                let (u, v) = self.half_ends((t, i));
                *count.entry((u.min(v), u.max(v))).or_insert(0usize) += 1;
            }
        }
        let mut cuts: Vec<(u32, u8, u32)> = Vec::new();
        let mut unsplit = std::collections::BTreeSet::new();
        for &(f, g) in pairs {
            let (u, v) = self.half_ends(f);
            if count[&(u.min(v), u.max(v))] <= 2 {
                continue;
            }
            let (p, q) = (self.positions[u as usize], self.positions[v as usize]);
            let m: [f64; 3] = std::array::from_fn(|k| p[k] * 0.5 + q[k] * 0.5);
            let between = (0..3).all(|k| p[k] == q[k] || (m[k] - p[k]) * (q[k] - m[k]) > 0.0);
            if !between {
                unsplit.insert((u.min(v), u.max(v)));
                continue;
            }
            let id = self.positions.len() as u32;
            self.positions.push(m);
            cuts.extend([(f.0, f.1, id), (g.0, g.1, id)]);
        }
        self.apply_cuts(cuts);
        unsplit.len()
    }

    /// Replaces every cut triangle by a fan from its first midpoint.
    fn apply_cuts(&mut self, mut cuts: Vec<(u32, u8, u32)>) {
        cuts.sort_unstable();
        for per_triangle in cuts.chunk_by(|a, b| a.0 == b.0) {
            let t = per_triangle[0].0 as usize;
            let tri = self.triangles[t];
            let mut polygon = Vec::with_capacity(6);
            for i in 0..3u8 {
                polygon.push(tri[i as usize]);
                polygon.extend(per_triangle.iter().filter(|c| c.1 == i).map(|c| c.2));
            }
            let start = polygon
                .iter()
                .position(|&v| v == per_triangle[0].2)
                .expect("cut in polygon");
            polygon.rotate_left(start);
            self.triangles[t] = [polygon[0], polygon[1], polygon[2]];
            for k in 2..polygon.len() - 1 {
                self.triangles
                    .push([polygon[0], polygon[k], polygon[k + 1]]);
                self.normals.push(self.normals[t]);
                self.sources.push(self.sources[t]);
            }
        }
    }
}

/// The outward unit normal of an orientation.
fn unit(o: Orientation) -> [i8; 3] {
    let mut n = [0i8; 3];
    n[o.axis()] = if o.is_positive() { 1 } else { -1 };
    n
}

fn neg(v: [i8; 3]) -> [i8; 3] {
    v.map(|c| -c)
}

/// Union-find with path halving.
struct UnionFind(Vec<usize>);

impl UnionFind {
    fn new(n: usize) -> Self {
        Self((0..n).collect())
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] != x {
            self.0[x] = self.0[self.0[x]];
            x = self.0[x];
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        // The smaller root wins, so the result does not depend on the union order.
        self.0[ra.max(rb)] = ra.min(rb);
    }
}
