//! Algorithm 2 (`design/ortho.md` §A4.3): the octant-code z-sweep giving every boundary
//! vertex with its six face degrees.
//!
//! 1. Sort the distinct z of all boxes (ranks `0..Z`); slab k lies between planes k and k+1.
//! 2. List the xy-rectangles of the boxes spanning each slab.
//! 3. For every plane k, independently and in parallel (rayon), run [`plane_scan`] on the slab
//!    below and the slab above; keep the candidates whose octant code is a vertex code, with
//!    the degrees of the chosen [`DegreeConvention`].
//! 4. Concatenate the planes in order: the vertices come out sorted by (z, y, x).
//!
//! This keeps the paper's structure (comparing the cross-sections below and above each event
//! plane) but classifies each point by its octant code instead of XOR-ing consecutive slices,
//! which loses the tripod (E7) and mis-signs some z-degrees (§A4.2). Each point is produced
//! exactly once, at its own z, y and x, so there is no merge step; the crossings the paper's
//! "closed slice" exists for are run ends of the other slab.
//!
//! Numeric model: ranks and comparisons only. Determinism: planes are independent and
//! concatenated in order, so the output does not depend on the thread count.
//! Complexity: Σ_k O(m_k log m_k + visited runs) time and O(Σ_k m_k) memory for the slab
//! lists, where m_k counts the boxes touching plane k; Θ(n³) in the worst case, the
//! worst-case size of the union's boundary.

use crate::par::*;

use crate::progress::Counter;

use super::grid::RankedBoxes;
use super::octant::{DegreeConvention, OCTANT_TABLE};
use super::rect2d::{Rect, plane_scan};

/// A boundary vertex in ranks with its octant code and degrees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RankVertex {
    /// `[x, y, z]` ranks.
    pub rank: [u32; 3],
    /// The octant code.
    pub code: u8,
    /// Face degrees in the order +x, −x, +y, −y, +z, −z.
    pub degrees: [u8; 6],
}

/// Every boundary vertex of the union of `boxes`, sorted by (z, y, x).
///
/// Each plane advances `counter`; once the run is cancelled, the remaining planes are skipped
/// and the result is incomplete (the caller's [`Counter::finish`] says so).
pub(crate) fn sweep_vertices(
    boxes: &RankedBoxes,
    convention: DegreeConvention,
    counter: &Counter,
) -> Vec<RankVertex> {
    let slabs = slab_rects(boxes);
    let planes = boxes.coords[2].len();
    for_each_plane(&slabs, planes, counter, |below, above, k| {
        plane_vertices(below, above, k, convention)
    })
    .concat()
}

/// Runs `plane` on every z-plane in parallel with the slabs just below and just above it
/// (empty beyond the ends), in plane order; each plane advances `counter`, and once the run is
/// cancelled the remaining planes give nothing.
pub(crate) fn for_each_plane<S: Sync, T: Send>(
    slabs: &[Vec<S>],
    planes: usize,
    counter: &Counter,
    plane: impl Fn(&[S], &[S], u32) -> Vec<T> + Sync,
) -> Vec<Vec<T>> {
    (0..planes)
        .into_par_iter()
        .map(|k| {
            if counter.is_cancelled() {
                return Vec::new();
            }
            let below = if k > 0 { &slabs[k - 1][..] } else { &[][..] };
            let above = slabs.get(k).map_or(&[][..], |s| &s[..]);
            let vertices = plane(below, above, k as u32);
            counter.advance(1);
            vertices
        })
        .collect()
}

/// Step 2: the rectangles spanning each slab `k` (between planes k and k+1).
fn slab_rects(boxes: &RankedBoxes) -> Vec<Vec<Rect>> {
    let mut slabs = vec![Vec::new(); boxes.coords[2].len().saturating_sub(1)];
    for b in &boxes.boxes {
        let rect = Rect {
            x0: b[0],
            x1: b[3],
            y0: b[1],
            y1: b[4],
        };
        for slab in &mut slabs[b[2] as usize..b[5] as usize] {
            slab.push(rect);
        }
    }
    slabs
}

/// Step 3 for one plane.
fn plane_vertices(
    below: &[Rect],
    above: &[Rect],
    z: u32,
    convention: DegreeConvention,
) -> Vec<RankVertex> {
    let mut out = Vec::new();
    plane_scan(below, above, |x, y, code| {
        let info = OCTANT_TABLE[code as usize];
        if info.is_vertex() {
            out.push(RankVertex {
                rank: [x, y, z],
                code,
                degrees: info.degrees(convention),
            });
        }
    });
    out
}
