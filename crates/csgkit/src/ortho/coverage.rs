//! A segment tree of rectangle coverage counts over elementary x-intervals.
//!
//! Leaf `i` is the elementary interval between the `i`-th and `(i+1)`-th distinct
//! x-coordinate of a plane. Each node keeps `count` (rectangles covering the whole node),
//! `full` (every leaf below is covered) and `any` (some leaf below is covered); a leaf is
//! covered iff some node on its root path has a positive count (`design/ortho.md` §A3 step 1).
//! The leaves are padded to a power of two, so updates run bottom-up without recursion; the
//! padding is never covered, so a run reaching it ends at leaf `leaves`.
//!
//! Runs are maximal sequences of covered leaves, reported **unclipped** as half-open leaf
//! ranges `[start, end)`, i.e. from x-point `start` to x-point `end`.
//!
//! Complexity: range update O(log m); the runs overlapping a query range cost
//! O((1 + runs) log m).

/// Coverage counts over `leaves` elementary intervals.
pub(crate) struct Coverage {
    leaves: usize,
    /// The padded leaf count, a power of two: leaf `i` is node `size + i`.
    size: usize,
    /// The nodes, heap-ordered from 1; one array of structs so a visit touches one line.
    nodes: Vec<Node>,
}

#[derive(Clone, Copy, Default)]
struct Node {
    count: i32,
    full: bool,
    any: bool,
}

impl Coverage {
    /// An uncovered tree over `leaves` elementary intervals.
    pub(crate) fn new(leaves: usize) -> Self {
        let size = leaves.max(1).next_power_of_two();
        Self {
            leaves,
            size,
            nodes: vec![Node::default(); 2 * size],
        }
    }

    /// Adds `delta` to the coverage of leaves `[l, r)`.
    pub(crate) fn add(&mut self, l: usize, r: usize, delta: i32) {
        if l >= r {
            return;
        }
        let (first, last) = (self.size + l, self.size + r - 1);
        // The canonical cover of [l, r): the nodes hanging off the two boundary paths.
        let (mut lo, mut hi) = (first, last + 1);
        while lo < hi {
            if lo & 1 == 1 {
                self.nodes[lo].count += delta;
                self.pull(lo);
                lo += 1;
            }
            if hi & 1 == 1 {
                hi -= 1;
                self.nodes[hi].count += delta;
                self.pull(hi);
            }
            (lo, hi) = (lo >> 1, hi >> 1);
        }
        // Every ancestor of a changed node lies on a boundary path; refresh them bottom-up.
        let (mut a, mut b) = (first >> 1, last >> 1);
        while a > 0 {
            self.pull(a);
            self.pull(b);
            (a, b) = (a >> 1, b >> 1);
        }
    }

    fn pull(&mut self, node: usize) {
        let (full, any) = if self.nodes[node].count > 0 {
            (true, true)
        } else if node >= self.size {
            (false, false)
        } else {
            let (l, r) = (self.nodes[2 * node], self.nodes[2 * node + 1]);
            (l.full && r.full, l.any || r.any)
        };
        (self.nodes[node].full, self.nodes[node].any) = (full, any);
    }

    /// The first leaf `>= i` that is covered (`want`) or uncovered (`!want`).
    fn first_from(&self, i: usize, want: bool) -> Option<usize> {
        self.find_first(1, 0, self.size, i, want)
    }

    fn find_first(&self, node: usize, nl: usize, nr: usize, i: usize, want: bool) -> Option<usize> {
        let n = self.nodes[node];
        if nr <= i || nl >= nr || (want && !n.any) || (!want && n.full) {
            return None;
        }
        if n.count > 0 {
            // The whole node is covered; `want` is true here because `full` is.
            return Some(nl.max(i));
        }
        if nr - nl == 1 {
            return Some(nl);
        }
        let mid = (nl + nr) / 2;
        self.find_first(2 * node, nl, mid, i, want)
            .or_else(|| self.find_first(2 * node + 1, mid, nr, i, want))
    }

    /// The last leaf `< i` that is uncovered.
    fn last_uncovered_before(&self, i: usize) -> Option<usize> {
        self.find_last_uncovered(1, 0, self.size, i)
    }

    fn find_last_uncovered(&self, node: usize, nl: usize, nr: usize, i: usize) -> Option<usize> {
        if nl >= i || nl >= nr || self.nodes[node].full {
            return None;
        }
        if nr - nl == 1 {
            return Some(nl);
        }
        let mid = (nl + nr) / 2;
        self.find_last_uncovered(2 * node + 1, mid, nr, i)
            .or_else(|| self.find_last_uncovered(2 * node, nl, mid, i))
    }

    /// Appends to `out` the maximal covered runs that overlap leaves `[lo, hi)`, unclipped.
    pub(crate) fn runs_overlapping(&self, lo: usize, hi: usize, out: &mut Vec<(u32, u32)>) {
        let first = out.len();
        self.covered_spans(1, 0, self.size, (lo, hi), first, out);
        // Only the first and last runs can be clipped by the range: extend them outwards.
        if let Some(run) = out.get_mut(first).filter(|r| r.0 as usize == lo) {
            run.0 = self.last_uncovered_before(lo).map_or(0, |u| u + 1) as u32;
        }
        if let Some(run) = out[first..].last_mut().filter(|r| r.1 as usize == hi) {
            run.1 = self.first_from(hi, false).unwrap_or(self.leaves) as u32;
        }
    }

    /// Appends the covered leaves of `range` below `node`, merging adjacent spans from
    /// `out[first..]`: one descent for all runs instead of one per run end.
    fn covered_spans(
        &self,
        node: usize,
        nl: usize,
        nr: usize,
        range: (usize, usize),
        first: usize,
        out: &mut Vec<(u32, u32)>,
    ) {
        let n = self.nodes[node];
        if nr <= range.0 || range.1 <= nl || nl >= nr || !n.any {
            return;
        }
        if n.full {
            let (s, e) = (nl.max(range.0) as u32, nr.min(range.1) as u32);
            match out[first..].last_mut() {
                Some(last) if last.1 == s => last.1 = e,
                _ => out.push((s, e)),
            }
            return;
        }
        let mid = (nl + nr) / 2;
        self.covered_spans(2 * node, nl, mid, range, first, out);
        self.covered_spans(2 * node + 1, mid, nr, range, first, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs by brute force from per-leaf counts.
    fn brute_runs(counts: &[i32], lo: usize, hi: usize) -> Vec<(u32, u32)> {
        let mut runs = Vec::new();
        let mut i = 0;
        while i < counts.len() {
            if counts[i] > 0 {
                let s = i;
                while i < counts.len() && counts[i] > 0 {
                    i += 1;
                }
                if s < hi && i > lo {
                    runs.push((s as u32, i as u32));
                }
            } else {
                i += 1;
            }
        }
        runs
    }

    #[test]
    fn runs_match_brute_force_under_random_updates() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |m: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % m) as usize
        };
        for leaves in 1..12 {
            let mut tree = Coverage::new(leaves);
            let mut counts = vec![0; leaves];
            let mut added = Vec::new();
            for _ in 0..200 {
                if !added.is_empty() && next(3) == 0 {
                    let (l, r) = added.swap_remove(next(added.len() as u64));
                    tree.add(l, r, -1);
                    counts[l..r].iter_mut().for_each(|c| *c -= 1);
                } else {
                    let l = next(leaves as u64);
                    let r = l + 1 + next((leaves - l) as u64);
                    tree.add(l, r, 1);
                    counts[l..r].iter_mut().for_each(|c| *c += 1);
                    added.push((l, r));
                }
                let lo = next(leaves as u64);
                let hi = lo + 1 + next((leaves - lo) as u64);
                let mut runs = Vec::new();
                tree.runs_overlapping(lo, hi, &mut runs);
                assert_eq!(runs, brute_runs(&counts, lo, hi), "{counts:?} [{lo},{hi})");
            }
        }
    }
}
