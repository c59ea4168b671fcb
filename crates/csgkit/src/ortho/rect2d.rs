//! Algorithm 1 (`design/ortho.md` §A3, §A4.3): the vertices of a union of rectangles, and of
//! two stacked unions at once.
//!
//! [`plane_scan`] sweeps a line in y over two rectangle sets, `below` (the slab under a sweep
//! plane) and `above` (the slab over it), each with its own [`Coverage`] tree:
//! 1. compress the x-coordinates of the plane's rectangles; build one tree per set;
//! 2. group the rectangles' bottom (+1) and top (−1) edges by y, ascending;
//! 3. at each y: `X_y` = the union of the closed x-extents of the edges on y, from both sets;
//! 4. read the covered runs of both trees that overlap `X_y` (`B−`, `A−`), apply every event
//!    at y, read them again (`B+`, `A+`);
//! 5. the candidates are the run ends lying in `X_y`; each gets the 8-bit octant code read
//!    from the four run lists (half-open run ends) and is reported to the caller.
//!
//! Every vertex of the union is a candidate: its code is symmetric neither in y (so an edge on
//! y covers it: it lies in `X_y`) nor in x (so it is a run end). Ties are grouped, never
//! ordered: duplicate rectangles are counts, shared edges merge through the counts.
//!
//! Numeric model: coordinates are ranks (`u32`); only comparisons happen here.
//! Complexity: O(m log m + Σ_y runs overlapping `X_y`) for m rectangles; Θ(m²) in the worst
//! case, which is also the worst-case output size.

use super::coverage::Coverage;

/// An axis-aligned rectangle `[x0, x1) × [y0, y1)` in coordinate ranks, with `x0 < x1` and
/// `y0 < y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Rect {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

/// One rectangle edge on a scan line, in local x indices.
#[derive(Clone, Copy)]
struct Event {
    y: u32,
    layer: usize,
    l: u32,
    r: u32,
    delta: i32,
}

/// Calls `emit(x, y, code)` for every candidate point of the plane between the slabs `below`
/// and `above`, in (y, x) order, with its octant code (bit `sx | sy << 1 | sz << 2`, where
/// `sz = 0` reads `below`). The caller filters the codes through the octant table.
pub(crate) fn plane_scan(below: &[Rect], above: &[Rect], mut emit: impl FnMut(u32, u32, u8)) {
    scan_layers(&[below, above], |x, y, masks| {
        emit(x, y, masks[0] | masks[1] << 4)
    });
}

/// The scan over any number of rectangle layers, each with its own coverage tree. For every
/// candidate (a run end of some layer lying in `X_y`) `emit` receives one 4-bit mask per
/// layer: bit `sx | sy << 1` set iff the quadrant on side (sx, sy) of the point is covered by
/// that layer.
pub(crate) fn scan_layers(layers: &[&[Rect]], mut emit: impl FnMut(u32, u32, &[u8])) {
    let mut xs: Vec<u32> = layers
        .iter()
        .flat_map(|l| l.iter())
        .flat_map(|r| [r.x0, r.x1])
        .collect();
    xs.sort_unstable();
    xs.dedup();
    let local = |x: u32| xs.partition_point(|&v| v < x) as u32;
    let mut events = Vec::with_capacity(2 * layers.iter().map(|l| l.len()).sum::<usize>());
    for (layer, rects) in layers.iter().enumerate() {
        for r in rects.iter() {
            let (l, rr) = (local(r.x0), local(r.x1));
            for (y, delta) in [(r.y0, 1), (r.y1, -1)] {
                events.push(Event {
                    y,
                    layer,
                    l,
                    r: rr,
                    delta,
                });
            }
        }
    }
    events.sort_unstable_by_key(|e| (e.y, e.l, e.r));
    let leaves = xs.len().saturating_sub(1);
    let mut trees: Vec<Coverage> = layers.iter().map(|_| Coverage::new(leaves)).collect();
    let mut line = ScanLine::default();
    for group in events.chunk_by(|a, b| a.y == b.y) {
        line.process(group, &mut trees, leaves);
        for (x, masks) in line
            .candidates
            .iter()
            .zip(line.masks.chunks_exact(layers.len()))
        {
            emit(xs[*x as usize], group[0].y, masks);
        }
    }
}

/// Buffers reused from one scan line to the next.
#[derive(Default)]
struct ScanLine {
    intervals: Vec<(u32, u32)>,
    /// Runs per (interval, list): list `2t` is layer t before the line's events, `2t + 1`
    /// after.
    runs: Vec<Vec<Vec<(u32, u32)>>>,
    candidates: Vec<u32>,
    /// One mask per (candidate, layer).
    masks: Vec<u8>,
}

impl ScanLine {
    /// Steps 3–5 at one y: fills `candidates` (local x) and their `masks`.
    fn process(&mut self, group: &[Event], trees: &mut [Coverage], leaves: usize) {
        self.merge_extents(group);
        let lists = 2 * trees.len();
        if self.runs.len() < self.intervals.len() {
            self.runs.resize_with(self.intervals.len(), Vec::new);
        }
        self.runs
            .iter_mut()
            .for_each(|r| r.resize_with(lists, Vec::new));
        self.read_runs(trees, leaves, 0);
        for e in group {
            trees[e.layer].add(e.l as usize, e.r as usize, e.delta);
        }
        self.read_runs(trees, leaves, 1);
        self.candidates.clear();
        self.masks.clear();
        for (i, &(a, b)) in self.intervals.iter().enumerate() {
            let runs = &self.runs[i][..lists];
            let first = self.candidates.len();
            for &(s, e) in runs.iter().flatten() {
                self.candidates
                    .extend([s, e].into_iter().filter(|x| (a..=b).contains(x)));
            }
            self.candidates[first..].sort_unstable();
            let mut kept = first;
            for j in first..self.candidates.len() {
                if j == first || self.candidates[j] != self.candidates[kept - 1] {
                    self.candidates[kept] = self.candidates[j];
                    kept += 1;
                }
            }
            self.candidates.truncate(kept);
            for &x in &self.candidates[first..] {
                self.masks
                    .extend(runs.chunks_exact(2).map(|pair| quadrant_mask(pair, x)));
            }
        }
    }

    /// `X_y`: the union of the closed extents of the edges on this line.
    fn merge_extents(&mut self, group: &[Event]) {
        self.intervals.clear();
        // `group` is sorted by (l, r).
        for e in group {
            match self.intervals.last_mut() {
                Some(last) if e.l <= last.1 => last.1 = last.1.max(e.r),
                _ => self.intervals.push((e.l, e.r)),
            }
        }
    }

    /// Reads the runs of every tree overlapping each interval into lists `2t + after`.
    fn read_runs(&mut self, trees: &[Coverage], leaves: usize, after: usize) {
        for (i, &(a, b)) in self.intervals.iter().enumerate() {
            // Leaves a−1 ..= b hold every run with an end in [a, b].
            let (lo, hi) = ((a as usize).saturating_sub(1), (b as usize + 1).min(leaves));
            for (t, tree) in trees.iter().enumerate() {
                let list = &mut self.runs[i][2 * t + after];
                list.clear();
                tree.runs_overlapping(lo, hi, list);
            }
        }
    }
}

/// Whether leaf `leaf` lies in a run of the sorted, disjoint `runs`.
fn in_runs(runs: &[(u32, u32)], leaf: i64) -> bool {
    let i = runs.partition_point(|&(s, _)| i64::from(s) <= leaf);
    i > 0 && i64::from(runs[i - 1].1) > leaf
}

/// The 4-bit quadrant mask at point x from one layer's run lists (before, after the line).
fn quadrant_mask(pair: &[Vec<(u32, u32)>], x: u32) -> u8 {
    let x = i64::from(x);
    let mut mask = 0u8;
    for (sy, list) in pair.iter().enumerate() {
        for (sx, leaf) in [(0, x - 1), (1, x)] {
            if in_runs(list, leaf) {
                mask |= 1 << (sx | sy << 1);
            }
        }
    }
    mask
}

/// The 2D corner records of a 4-bit quadrant code (bit `sx | sy << 1`), as outward-normal
/// flags (+x, −x, +y, −y) of the corner's two edges (§A3 steps 4 and 6): a convex corner
/// occupying quadrant q points away from q, a reflex corner towards its empty quadrant, and a
/// pinch gives two convex records.
pub(crate) fn corner_records(q: u8) -> Vec<[bool; 4]> {
    let normals = |quad: u32, toward: bool| {
        let (px, py) = (quad & 1 == 1, quad >> 1 == 1);
        [px == toward, px != toward, py == toward, py != toward]
    };
    match q.count_ones() {
        1 => vec![normals(q.trailing_zeros(), false)],
        3 => vec![normals((!q & 15).trailing_zeros(), true)],
        2 if q == 0b1001 || q == 0b0110 => {
            let lo = q.trailing_zeros();
            vec![normals(lo, false), normals(3 - lo, false)]
        }
        _ => Vec::new(),
    }
}
