//! Building the BVH: Morton order, then a complete binary tree over it.
//!
//! # Overview
//! 1. Compute the 63-bit Morton code of every box centre, scaled into the box of all centres.
//! 2. Sort primitive ids by (code, id): one parallel sort, deterministic because ids break
//!    ties.
//! 3. Cut the sorted order into leaves of [`LEAF_SIZE`] primitives and pad the leaf count to a
//!    power of two, so the tree is complete and stored implicitly in heap order (node `i` has
//!    children `2i + 1` and `2i + 2`): no child pointers, and the depth of every leaf is equal.
//! 4. Fill the node boxes bottom-up, one level at a time, each level in parallel.
//!
//! Padding leaves hold [`Aabb::EMPTY`], which overlaps nothing, so queries prune them at once.
//!
//! # Complexity
//! O(n log n) for the sort, O(n) for the boxes; memory is at most four node boxes per leaf.

use crate::par::*;

use super::Aabb;

/// Primitives per leaf. Small leaves keep leaf–leaf tests cheap; 4 is what Manifold's
/// collider and most LBVH builders settle on.
pub const LEAF_SIZE: usize = 4;

/// Below this many nodes a level is filled serially: threads cost more than they save.
const PARALLEL_LEVEL_MIN: usize = 4096;

/// A bounding-volume hierarchy over a set of boxes, answering overlap queries.
///
/// **Invariant:** `nodes.len() == 2 * leaf_count - 1` with `leaf_count` a power of two; every
/// node's box holds the boxes of its children; leaf `j` (node `leaf_count - 1 + j`) holds the
/// sorted primitives `j * LEAF_SIZE .. min((j + 1) * LEAF_SIZE, len)`.
#[derive(Clone, Debug)]
pub struct Bvh {
    /// Node boxes in heap order.
    pub(super) nodes: Vec<Aabb>,
    /// Primitive boxes in Morton order.
    pub(super) boxes: Vec<Aabb>,
    /// The caller's id of each primitive, in Morton order.
    pub(super) ids: Vec<u32>,
    /// Number of leaves (a power of two).
    pub(super) leaf_count: usize,
}

impl Bvh {
    /// Builds a tree over `boxes`; a primitive's id is its index in `boxes`.
    ///
    /// # Panics
    /// If there are more than `u32::MAX` boxes (meshes never have that many faces).
    pub fn build(boxes: &[Aabb]) -> Bvh {
        Self::build_where(boxes.len(), |i| boxes[i], |_| true)
    }

    /// Builds a tree over the boxes `box_of(0) .. box_of(len - 1)`; a primitive's id is its
    /// index. The same tree as [`Bvh::build`] on the collected boxes, without the caller
    /// storing them: `box_of` is called a few times per primitive, so it should be cheap
    /// (the box of a triangle from its corners). On a million triangles the list of boxes
    /// would be 48 MB that are written once and read twice.
    ///
    /// # Panics
    /// If `len` exceeds `u32::MAX`.
    pub fn build_with(len: usize, box_of: impl Fn(usize) -> Aabb + Sync) -> Bvh {
        Self::build_where(len, box_of, |_| true)
    }

    /// Builds a tree over the boxes `box_of(0) .. box_of(len - 1)` that overlap `region`,
    /// keeping their indices as ids (`box_of` as in [`Bvh::build_with`]). The broad phase uses
    /// it to index only the part of each operand that lies in the overlap of both operands'
    /// boxes.
    ///
    /// # Panics
    /// If `len` exceeds `u32::MAX`.
    pub fn build_in(len: usize, box_of: impl Fn(usize) -> Aabb + Sync, region: &Aabb) -> Bvh {
        Self::build_where(len, box_of, |b| b.overlaps(region))
    }

    fn build_where(
        len: usize,
        box_of: impl Fn(usize) -> Aabb + Sync,
        keep: impl Fn(&Aabb) -> bool + Sync,
    ) -> Bvh {
        assert!(
            u32::try_from(len).is_ok(),
            "a BVH holds at most u32::MAX primitives"
        );
        let ids: Vec<u32> = (0..len as u32)
            .into_par_iter()
            .filter(|&i| keep(&box_of(i as usize)))
            .collect();
        Self::build_over(ids, box_of)
    }

    /// Builds a tree over the primitives `ids` (distinct), whose boxes are `box_of(id)` (as
    /// in [`Bvh::build_with`]): for a caller that chose them without their boxes.
    pub fn build_over(ids: Vec<u32>, box_of: impl Fn(usize) -> Aabb + Sync) -> Bvh {
        let ids = morton_order(&box_of, ids);
        let sorted: Vec<Aabb> = ids.par_iter().map(|&i| box_of(i as usize)).collect();
        let leaf_count = sorted.len().div_ceil(LEAF_SIZE).max(1).next_power_of_two();
        let nodes = fill_nodes(&sorted, leaf_count);
        let bvh = Bvh {
            nodes,
            boxes: sorted,
            ids,
            leaf_count,
        };
        debug_assert!(bvh.check_invariants().is_ok());
        bvh
    }

    /// Number of primitives in the tree.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True when the tree holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// The box of everything in the tree.
    pub fn bounds(&self) -> Aabb {
        self.nodes[0]
    }

    /// The same tree with each primitive renumbered by its position in the tree's (Morton)
    /// order, and the old id of each position.
    ///
    /// Queries on the renumbered tree report positions. A caller that copies its per-primitive
    /// data into that order then reads it almost sequentially, as the queries walk the tree,
    /// instead of jumping through the whole array: on a million triangles the jumps cost more
    /// than the exact tests of the self-intersection check.
    pub fn into_tree_order(mut self) -> (Bvh, Vec<u32>) {
        let positions = (0..self.ids.len() as u32).collect();
        let ids = std::mem::replace(&mut self.ids, positions);
        (self, ids)
    }

    /// Undoes [`Bvh::into_tree_order`]: the same tree answering with the caller's ids again,
    /// `ids` being the list that call returned.
    ///
    /// # Panics
    /// If `ids` is not as long as the tree has primitives.
    pub fn with_ids(mut self, ids: Vec<u32>) -> Bvh {
        assert_eq!(ids.len(), self.ids.len(), "one id per primitive");
        self.ids = ids;
        self
    }

    /// Range of sorted primitives in leaf node `node`.
    pub(super) fn leaf_primitives(&self, node: usize) -> std::ops::Range<usize> {
        let leaf = node + 1 - self.leaf_count;
        let start = (leaf * LEAF_SIZE).min(self.boxes.len());
        start..(start + LEAF_SIZE).min(self.boxes.len())
    }

    /// True when `node` is a leaf.
    pub(super) fn is_leaf(&self, node: usize) -> bool {
        node + 1 >= self.leaf_count
    }

    /// Checks the invariant of the type docs.
    ///
    /// # Errors
    /// A description of the first violation.
    pub fn check_invariants(&self) -> Result<(), String> {
        if !self.leaf_count.is_power_of_two() || self.nodes.len() != 2 * self.leaf_count - 1 {
            return Err(format!(
                "{} nodes for {} leaves",
                self.nodes.len(),
                self.leaf_count
            ));
        }
        for node in 0..self.nodes.len() {
            let expected = if self.is_leaf(node) {
                let range = self.leaf_primitives(node);
                self.boxes[range]
                    .iter()
                    .fold(Aabb::EMPTY, |b, p| b.union(p))
            } else {
                self.nodes[2 * node + 1].union(&self.nodes[2 * node + 2])
            };
            if expected != self.nodes[node] {
                return Err(format!("node {node} does not bound its children"));
            }
        }
        Ok(())
    }
}

/// Sorts `ids` by the Morton code of their box centres, ties broken by id.
fn morton_order(box_of: &(impl Fn(usize) -> Aabb + Sync), mut ids: Vec<u32>) -> Vec<u32> {
    let centres = ids
        .par_iter()
        .map(|&i| Aabb::EMPTY.union_point(&box_of(i as usize).centre()))
        .reduce_with(|a, b| a.union(&b))
        .unwrap_or(Aabb::EMPTY);
    let mut keyed: Vec<(u64, u32)> = ids
        .par_iter()
        .map(|&i| (morton_code(&box_of(i as usize).centre(), &centres), i))
        .collect();
    keyed.par_sort_unstable();
    ids.clear();
    ids.extend(keyed.into_iter().map(|(_, i)| i));
    ids
}

/// The 63-bit Morton code (21 bits per axis) of `p` scaled into `frame`.
fn morton_code(p: &[f64; 3], frame: &Aabb) -> u64 {
    const CELLS: f64 = ((1u64 << 21) - 1) as f64;
    (0..3).fold(0, |code, k| {
        let extent = frame.max[k] - frame.min[k];
        let t = if extent > 0.0 {
            (p[k] - frame.min[k]) / extent
        } else {
            0.0
        };
        // `as` saturates, so a NaN or out-of-range t cannot produce a wild cell.
        code | spread_bits((t * CELLS) as u64) << k
    })
}

/// Spreads the low 21 bits of `x` so that two zero bits separate each pair.
fn spread_bits(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    (x | x << 2) & 0x1249_2492_4924_9249
}

/// Node boxes in heap order: leaves first, then each level above from its children.
fn fill_nodes(sorted: &[Aabb], leaf_count: usize) -> Vec<Aabb> {
    let mut nodes = vec![Aabb::EMPTY; 2 * leaf_count - 1];
    let first_leaf = leaf_count - 1;
    nodes[first_leaf..]
        .par_iter_mut()
        .enumerate()
        .for_each(|(leaf, node)| {
            let start = (leaf * LEAF_SIZE).min(sorted.len());
            let end = (start + LEAF_SIZE).min(sorted.len());
            *node = sorted[start..end]
                .iter()
                .fold(Aabb::EMPTY, |b, p| b.union(p));
        });
    let mut level_start = first_leaf;
    while level_start > 0 {
        let parent_start = (level_start - 1) / 2;
        let (parents, children) = nodes.split_at_mut(level_start);
        let parents = &mut parents[parent_start..];
        let fill = |(i, parent): (usize, &mut Aabb)| {
            *parent = children[2 * i].union(&children[2 * i + 1]);
        };
        if parents.len() >= PARALLEL_LEVEL_MIN {
            parents.par_iter_mut().enumerate().for_each(fill);
        } else {
            parents.iter_mut().enumerate().for_each(fill);
        }
        level_start = parent_start;
    }
    nodes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_bits_interleaves() {
        assert_eq!(spread_bits(0b1), 0b1);
        assert_eq!(spread_bits(0b11), 0b1001);
        assert_eq!(spread_bits(0x1f_ffff).count_ones(), 21);
    }

    #[test]
    fn tree_over_many_sizes_keeps_its_invariants() {
        for n in [0, 1, 3, 4, 5, 17, 100, 1000] {
            let boxes: Vec<Aabb> = (0..n)
                .map(|i| {
                    let x = (i * 7 % 13) as f64;
                    Aabb::from_points(&[[x, i as f64, 0.0], [x + 1.0, i as f64 + 2.0, 1.0]])
                })
                .collect();
            let bvh = Bvh::build(&boxes);
            assert_eq!(bvh.len(), n);
            bvh.check_invariants().unwrap();
            let mut ids = bvh.ids.clone();
            ids.sort_unstable();
            assert_eq!(ids, (0..n as u32).collect::<Vec<_>>());
        }
    }

    #[test]
    fn build_with_builds_the_same_tree() {
        let boxes: Vec<Aabb> = (0..300)
            .map(|i| {
                let p = [(i * 5 % 19) as f64, (i % 7) as f64, (i * 3 % 13) as f64];
                Aabb::from_points(&[p, [p[0] + 1.0, p[1] + 2.5, p[2] + 0.5]])
            })
            .collect();
        let (built, with) = (Bvh::build(&boxes), Bvh::build_with(300, |i| boxes[i]));
        assert_eq!((&built.ids, &built.boxes), (&with.ids, &with.boxes));
        assert_eq!(built.nodes, with.nodes);
    }

    #[test]
    fn tree_order_renumbers_query_results() {
        let boxes: Vec<Aabb> = (0..500)
            .map(|i| {
                let p = [(i * 7 % 23) as f64, (i % 11) as f64, (i * 3 % 17) as f64];
                Aabb::from_points(&[p, [p[0] + 1.5, p[1] + 1.0, p[2] + 2.0]])
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        let want = bvh.self_overlapping_pairs();
        let (renumbered, ids) = bvh.clone().into_tree_order();
        assert_eq!(ids, bvh.ids);
        renumbered.check_invariants().unwrap();
        let got: Vec<(u32, u32)> = (renumbered.self_overlapping_pairs().into_iter())
            .map(|(x, y)| {
                let (i, j) = (ids[x as usize], ids[y as usize]);
                (i.min(j), i.max(j))
            })
            .collect();
        assert_eq!(got, want);
    }

    #[test]
    fn build_in_keeps_only_boxes_in_region() {
        let boxes: Vec<Aabb> = (0..10)
            .map(|i| Aabb::from_points(&[[i as f64; 3], [i as f64 + 0.5; 3]]))
            .collect();
        let region = Aabb::from_points(&[[2.5; 3], [5.0; 3]]);
        let bvh = Bvh::build_in(boxes.len(), |i| boxes[i], &region);
        let mut ids = bvh.ids.clone();
        ids.sort_unstable();
        assert_eq!(ids, vec![2, 3, 4, 5]);
    }
}
