//! A disjoint-set forest over `u32` indices, for components, fans and boundary loops.
//!
//! Path halving keeps the trees shallow; roots are the smallest index of their set, which
//! makes the structure deterministic without a rank array. Amortized near-constant time per
//! operation in practice (O(log n) worst case without ranks), 4 bytes per element.
//!
//! The forest can also be built by many threads at once ([`UnionFind::union_shared`]), for
//! the passes over every triangle of a million-triangle mesh (the patches of the arrangement,
//! the shells of a result): a root is only ever linked below a smaller root, by a
//! compare-and-swap that fails if another thread linked it first, and path halving only
//! moves a parent pointer to an ancestor, so the sets, and with them the roots, are those of
//! the same unions made one by one, in any order.

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use crate::par::*;

/// Disjoint sets of the indices `0..len`.
#[derive(Debug)]
pub(crate) struct UnionFind {
    /// Each index's parent; a root is its own. Atomic so that threads can link sets at once;
    /// the `&mut self` methods read and write it as plain integers.
    parent: Vec<AtomicU32>,
}

impl UnionFind {
    /// `len` singleton sets.
    pub(crate) fn new(len: usize) -> Self {
        Self {
            parent: (0..len as u32).map(AtomicU32::new).collect(),
        }
    }

    /// The root of every index's set, in index order.
    pub(crate) fn roots(mut self) -> Vec<u32> {
        if self.parent.len() < PARALLEL_ROOTS_FROM {
            for x in 0..self.parent.len() {
                // Roots are the smallest index of their set: a parent below x is final already.
                let parent = *self.parent[x].get_mut();
                *self.parent[x].get_mut() = *self.parent[parent as usize].get_mut();
            }
        } else {
            (0..self.parent.len() as u32)
                .into_par_iter()
                .for_each(|x| self.parent[x as usize].store(self.find(x), Relaxed));
        }
        (self.parent.into_iter())
            .map(AtomicU32::into_inner)
            .collect()
    }

    /// Merges the sets of `a` and `b`.
    pub(crate) fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra < rb {
            *self.parent[rb as usize].get_mut() = ra;
        } else if rb < ra {
            *self.parent[ra as usize].get_mut() = rb;
        }
    }

    /// [`Self::union`] while other threads may be making unions too.
    pub(crate) fn union_shared(&self, mut a: u32, mut b: u32) {
        loop {
            let (ra, rb) = (self.find(a), self.find(b));
            let (low, high) = match ra.cmp(&rb) {
                std::cmp::Ordering::Equal => return,
                std::cmp::Ordering::Less => (ra, rb),
                std::cmp::Ordering::Greater => (rb, ra),
            };
            // Linked only while `high` is still a root; else another thread linked it, and
            // the roots are found again.
            let linked = self.parent[high as usize].compare_exchange(high, low, Relaxed, Relaxed);
            if linked.is_ok() {
                return;
            }
            (a, b) = (high, low);
        }
    }

    /// The root of `x`'s set, also while other threads make unions (relaxed atomic reads and
    /// writes are plain ones on the targets built for). A parent read late is still an
    /// ancestor, so the walk ends at the root or at a root another thread is linking, which
    /// [`Self::union_shared`]'s compare-and-swap then finds out.
    pub(crate) fn find(&self, mut x: u32) -> u32 {
        loop {
            let parent = self.parent[x as usize].load(Relaxed);
            if parent == x {
                return x;
            }
            let grandparent = self.parent[parent as usize].load(Relaxed);
            if grandparent != parent {
                self.parent[x as usize].store(grandparent, Relaxed);
            }
            x = grandparent;
        }
    }
}

/// The indices from which [`UnionFind::roots`] finds them on many threads: below, one pass in
/// index order (each parent's root already final) takes less than handing the work out.
const PARALLEL_ROOTS_FROM: usize = 1 << 16;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unions_are_transitive_and_roots_are_smallest() {
        let mut sets = UnionFind::new(5);
        sets.union(4, 2);
        sets.union(2, 3);
        assert_eq!(sets.find(4), 2);
        assert_eq!(sets.find(3), 2);
        assert_eq!(sets.find(0), 0);
        sets.union(3, 0);
        assert_eq!(sets.find(4), 0);
    }

    /// Unions made by many threads give the roots the same unions give one by one.
    #[test]
    fn shared_unions_give_the_roots_of_serial_ones() {
        let len = 210_000u32;
        // A path through each residue class mod 7, its links in scrambled order, and two
        // links joining classes 0 and 1, 2 and 3: five sets.
        let mut pairs: Vec<(u32, u32)> = (0..len)
            .map(|i| (u64::from(i) * 2_654_435_761 % u64::from(len)) as u32)
            .filter(|&a| a + 7 < len)
            .map(|a| (a + 7, a))
            .collect();
        pairs.extend([(7_001, 0), (2, 14_003)]);
        let mut serial = UnionFind::new(len as usize);
        for &(a, b) in &pairs {
            serial.union(a, b);
        }
        let shared = UnionFind::new(len as usize);
        pairs
            .par_iter()
            .for_each(|&(a, b)| shared.union_shared(a, b));
        let roots = shared.roots();
        assert_eq!(roots, serial.roots());
        let mut distinct = roots.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct, [0, 2, 4, 5, 6]);
    }
}
