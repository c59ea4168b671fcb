//! Overlap queries: every pair of primitives whose boxes overlap.
//!
//! # Overview
//! 1. Descend both trees together from the roots, breadth first, keeping node pairs whose
//!    boxes overlap, until there are enough pairs to share among threads (a *frontier*).
//! 2. Finish each frontier pair by a depth-first descent on its own thread; at two leaves,
//!    test the primitive boxes directly.
//! 3. Concatenate the per-pair results in frontier order.
//!
//! Both descents take child pairs first to last, so the output is in the order of one
//! depth-first walk from the roots whatever the frontier: it does not depend on the thread
//! count, and on one thread that walk is all there is (no frontier: on two 1 k-triangle
//! spheres, building it was a fifth of the broad phase).
//!
//! The self query walks the one tree against itself and visits each unordered node pair
//! once: a node against itself expands to (left, left), (right, right) and (left, right).
//!
//! The `_filter_map` forms call a function on each pair as the descent finds it and keep
//! only what it returns, so a caller that rejects most candidates (the self-intersection
//! check keeps a handful of tens of millions) never stores the candidate list; the exact test
//! runs while the pair's boxes and triangles are still in cache. The order is the same as the
//! pair lists' order.

use smallvec::SmallVec;

use crate::par::*;

use super::bvh_build::LEAF_SIZE;
use super::{Aabb, Bvh};

/// Frontier size: enough pairs to balance uneven subtrees over many threads. It is fixed,
/// not scaled by the thread count, because the output order follows the frontier.
const FRONTIER_TARGET: usize = 1024;

/// Which two trees a traversal walks.
#[derive(Clone, Copy)]
struct Walk<'a> {
    a: &'a Bvh,
    b: &'a Bvh,
    /// `a` and `b` are the same tree and each unordered pair is wanted once.
    same_tree: bool,
}

impl Bvh {
    /// Every pair `(id in self, id in other)` whose primitive boxes overlap (touching counts).
    pub fn overlapping_pairs(&self, other: &Bvh) -> Vec<(u32, u32)> {
        self.overlapping_filter_map(other, |i, j| Some((i, j)))
    }

    /// Every unordered pair of distinct primitives of this tree whose boxes overlap, each
    /// once, as `(smaller id, larger id)`.
    pub fn self_overlapping_pairs(&self) -> Vec<(u32, u32)> {
        self.self_overlapping_filter_map(|i, j| Some((i, j)))
    }

    /// [`Bvh::overlapping_pairs`] passed through `f` as they are found: the `Some` values, in
    /// the order of the pairs. `f` runs on several threads at once.
    pub fn overlapping_filter_map<T: Send>(
        &self,
        other: &Bvh,
        f: impl Fn(u32, u32) -> Option<T> + Sync,
    ) -> Vec<T> {
        Walk {
            a: self,
            b: other,
            same_tree: false,
        }
        .run(f)
    }

    /// [`Bvh::self_overlapping_pairs`] passed through `f` as they are found (each unordered
    /// pair once, smaller id first): the `Some` values, in the order of the pairs. `f` runs on
    /// several threads at once.
    pub fn self_overlapping_filter_map<T: Send>(
        &self,
        f: impl Fn(u32, u32) -> Option<T> + Sync,
    ) -> Vec<T> {
        Walk {
            a: self,
            b: self,
            same_tree: true,
        }
        .run(f)
    }
}

impl Bvh {
    /// Calls `visit` with the id of every primitive whose box overlaps `query` (touching
    /// counts), in tree order. A ray along an axis is a box that is flat on two axes.
    pub fn visit_overlapping(&self, query: &Aabb, mut visit: impl FnMut(u32)) {
        self.any_overlapping(query, |id| {
            visit(id);
            false
        });
    }

    /// True when some primitive whose box overlaps `query` satisfies `wanted`; stops at the
    /// first one.
    pub fn any_overlapping(&self, query: &Aabb, mut wanted: impl FnMut(u32) -> bool) -> bool {
        if self.is_empty() {
            return false;
        }
        // A complete tree of at most 2^32 leaves: the depth-first stack holds at most one
        // pending sibling per level, so it never leaves the inline buffer (no allocation per
        // query; the broad phase asks one per triangle).
        let mut stack: SmallVec<[usize; 64]> = SmallVec::new();
        stack.push(0);
        while let Some(node) = stack.pop() {
            if !self.nodes[node].overlaps(query) {
                continue;
            }
            if self.is_leaf(node) {
                for p in self.leaf_primitives(node) {
                    if self.boxes[p].overlaps(query) && wanted(self.ids[p]) {
                        return true;
                    }
                }
            } else {
                stack.extend([2 * node + 2, 2 * node + 1]);
            }
        }
        false
    }
}

impl Walk<'_> {
    fn run<T: Send>(self, f: impl Fn(u32, u32) -> Option<T> + Sync) -> Vec<T> {
        if self.a.is_empty() || self.b.is_empty() {
            return Vec::new();
        }
        // One thread has nothing to share: its frontier is the roots' pair alone.
        let target = if current_num_threads() == 1 {
            1
        } else {
            FRONTIER_TARGET
        };
        let frontier = self.frontier(target);
        let parts: Vec<Vec<T>> = frontier
            .par_iter()
            .map(|&pair| {
                let mut out = Vec::new();
                self.descend(pair, &mut |i, j| out.extend(f(i, j)));
                out
            })
            .collect();
        let mut all = Vec::with_capacity(parts.iter().map(Vec::len).sum());
        parts.into_iter().for_each(|part| all.extend(part));
        all
    }

    /// Node pairs whose subtrees together hold every overlapping primitive pair, expanded
    /// breadth first until there are at least `target` of them or nothing is left to expand.
    fn frontier(self, target: usize) -> Vec<(usize, usize)> {
        let mut frontier = vec![(0, 0)];
        if !self.nodes_overlap(0, 0) {
            return Vec::new();
        }
        while frontier.len() < target {
            let mut next = Vec::with_capacity(frontier.len() * 4);
            let mut expanded = false;
            for &pair in &frontier {
                let (children, count) = self.children(pair);
                if count == 0 && self.is_leaf_pair(pair) {
                    next.push(pair);
                } else {
                    next.extend_from_slice(&children[..count]);
                    expanded = true;
                }
            }
            frontier = next;
            if !expanded {
                break;
            }
        }
        frontier
    }

    /// Depth-first descent below one node pair, calling `visit` on overlapping primitive
    /// pairs, child pairs first to last.
    fn descend(self, root: (usize, usize), visit: &mut impl FnMut(u32, u32)) {
        // On the call stack: a walk runs one descent per frontier pair, up to
        // `FRONTIER_TARGET` of them, and each heap buffer cost as much as a small walk.
        let mut stack: SmallVec<[(usize, usize); 64]> = SmallVec::new();
        stack.push(root);
        while let Some(pair) = stack.pop() {
            if self.is_leaf_pair(pair) {
                self.leaf_pairs(pair, visit);
            } else {
                // Pushed last to first, so they come off first to last; a `push` each, where
                // `SmallVec::extend` (a reservation, then its iterator) took 68 instructions a
                // node pair, about 1 % of a boolean of two 1 k spheres.
                let (children, count) = self.children(pair);
                for &child in children[..count].iter().rev() {
                    stack.push(child);
                }
            }
        }
    }

    fn is_leaf_pair(self, (a, b): (usize, usize)) -> bool {
        self.a.is_leaf(a) && self.b.is_leaf(b)
    }

    fn nodes_overlap(self, a: usize, b: usize) -> bool {
        self.a.nodes[a].overlaps(&self.b.nodes[b])
    }

    /// The overlapping child pairs of an inner pair, first to last, and how many there are
    /// (none for a leaf pair): of two inner nodes (left, left), (left, right), (right, left),
    /// (right, right); of a leaf and an inner node, the leaf against each child.
    ///
    /// Written out case by case: the walk spends about as long here as in the leaf tests.
    fn children(self, (a, b): (usize, usize)) -> ([(usize, usize); 4], usize) {
        let (na, nb) = (&self.a.nodes, &self.b.nodes);
        let mut children = [(0, 0); 4];
        let mut count = 0;
        let mut keep = |overlap: bool, child: (usize, usize)| {
            children[count] = child;
            count += usize::from(overlap);
        };
        match (self.a.is_leaf(a), self.b.is_leaf(b)) {
            (true, true) => {}
            (false, false) => {
                let (a0, a1, b0, b1) = (2 * a + 1, 2 * a + 2, 2 * b + 1, 2 * b + 2);
                keep(na[a0].overlaps(&nb[b0]), (a0, b0));
                keep(na[a0].overlaps(&nb[b1]), (a0, b1));
                // On the diagonal of the self query, (right, left) repeats (left, right).
                let diagonal = self.same_tree && a == b;
                keep(!diagonal && na[a1].overlaps(&nb[b0]), (a1, b0));
                keep(na[a1].overlaps(&nb[b1]), (a1, b1));
            }
            (true, false) => {
                for child in [2 * b + 1, 2 * b + 2] {
                    keep(na[a].overlaps(&nb[child]), (a, child));
                }
            }
            (false, true) => {
                for child in [2 * a + 1, 2 * a + 2] {
                    keep(na[child].overlaps(&nb[b]), (child, b));
                }
            }
        }
        (children, count)
    }

    /// Calls `visit` on the overlapping primitive pairs of two leaves.
    ///
    /// All box tests of the two leaves run first, into a bit mask, and only the hits are
    /// then visited: whether two neighbouring boxes overlap is a coin toss for the branch
    /// predictor, so the tests are kept free of branches.
    fn leaf_pairs(self, (a, b): (usize, usize), visit: &mut impl FnMut(u32, u32)) {
        const _: () = assert!(LEAF_SIZE * LEAF_SIZE <= 64, "leaf pair masks are u64");
        let (ra, rb) = (self.a.leaf_primitives(a), self.b.leaf_primitives(b));
        let (boxes_a, boxes_b) = (&self.a.boxes[ra.clone()], &self.b.boxes[rb.clone()]);
        let mut hits = 0u64;
        for (x, box_a) in boxes_a.iter().enumerate() {
            for (y, box_b) in boxes_b.iter().enumerate() {
                hits |= u64::from(box_a.overlaps(box_b)) << (x * LEAF_SIZE + y);
            }
        }
        let diagonal = self.same_tree && a == b;
        if diagonal {
            // A leaf against itself: only y > x (each unordered pair once, no self pairs).
            hits &= UPPER_TRIANGLE;
        }
        while hits != 0 {
            let bit = hits.trailing_zeros() as usize;
            hits &= hits - 1;
            let (i, j) = (ra.start + bit / LEAF_SIZE, rb.start + bit % LEAF_SIZE);
            let (ia, ib) = (self.a.ids[i], self.b.ids[j]);
            if self.same_tree && ib < ia {
                visit(ib, ia);
            } else {
                visit(ia, ib);
            }
        }
    }
}

/// The bits `x * LEAF_SIZE + y` with `y > x`: the pairs of a leaf against itself.
const UPPER_TRIANGLE: u64 = {
    let mut mask = 0u64;
    let mut x = 0;
    while x < LEAF_SIZE {
        let mut y = x + 1;
        while y < LEAF_SIZE {
            mask |= 1 << (x * LEAF_SIZE + y);
            y += 1;
        }
        x += 1;
    }
    mask
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::index::Aabb;
    use proptest::prelude::*;

    fn brute_pairs(a: &[Aabb], b: &[Aabb]) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        for (i, x) in a.iter().enumerate() {
            for (j, y) in b.iter().enumerate() {
                if x.overlaps(y) {
                    pairs.push((i as u32, j as u32));
                }
            }
        }
        pairs
    }

    fn boxes_strategy() -> impl Strategy<Value = Vec<Aabb>> {
        // Integer corners on a small grid make touching boxes common.
        let corner = (0i32..12, 0i32..12, 0i32..12);
        let extent = (0i32..4, 0i32..4, 0i32..4);
        proptest::collection::vec((corner, extent), 0..120).prop_map(|v| {
            v.into_iter()
                .map(|((x, y, z), (dx, dy, dz))| {
                    let min = [x as f64, y as f64, z as f64];
                    let max = [(x + dx) as f64, (y + dy) as f64, (z + dz) as f64];
                    Aabb::from_points(&[min, max])
                })
                .collect()
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

        #[test]
        fn pairs_match_brute_force(a in boxes_strategy(), b in boxes_strategy()) {
            let mut got = Bvh::build(&a).overlapping_pairs(&Bvh::build(&b));
            got.sort_unstable();
            prop_assert_eq!(got, brute_pairs(&a, &b));
        }

        #[test]
        fn self_pairs_match_brute_force(a in boxes_strategy()) {
            let mut got = Bvh::build(&a).self_overlapping_pairs();
            got.sort_unstable();
            let want: Vec<_> = brute_pairs(&a, &a).into_iter().filter(|(i, j)| i < j).collect();
            prop_assert_eq!(got, want);
        }
    }

    #[test]
    fn filter_map_keeps_the_order_of_the_pairs() {
        let boxes: Vec<Aabb> = (0..3000)
            .map(|i| {
                let p = [(i % 13) as f64, (i % 19) as f64, (i % 31) as f64];
                Aabb::from_points(&[p, [p[0] + 2.0, p[1] + 1.0, p[2] + 1.5]])
            })
            .collect();
        let (bvh, half) = (Bvh::build(&boxes), Bvh::build(&boxes[..1500]));
        let odd = |i: u32, j: u32| ((i + j) % 2 == 1).then_some((j, i));
        let want: Vec<_> = (bvh.self_overlapping_pairs().into_iter())
            .filter_map(|(i, j)| odd(i, j))
            .collect();
        assert!(!want.is_empty());
        assert_eq!(bvh.self_overlapping_filter_map(odd), want);
        let want: Vec<_> = (bvh.overlapping_pairs(&half).into_iter())
            .filter_map(|(i, j)| odd(i, j))
            .collect();
        assert_eq!(bvh.overlapping_filter_map(&half, odd), want);
    }

    #[test]
    fn result_order_is_independent_of_thread_count() {
        let boxes: Vec<Aabb> = (0..5000)
            .map(|i| {
                let p = [(i % 17) as f64, (i % 23) as f64, (i % 29) as f64];
                Aabb::from_points(&[p, [p[0] + 1.5, p[1] + 1.5, p[2] + 1.5]])
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        // One thread walks from the roots, four share a frontier.
        let one = pool(1).install(|| bvh.self_overlapping_pairs());
        let many = pool(4).install(|| Bvh::build(&boxes).self_overlapping_pairs());
        assert_eq!(one, many);
        let half = Bvh::build(&boxes[..2500]);
        let one = pool(1).install(|| bvh.overlapping_pairs(&half));
        let many = pool(4).install(|| bvh.overlapping_pairs(&half));
        assert!(!one.is_empty());
        assert_eq!(one, many);
    }
}
