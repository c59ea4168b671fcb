//! Face materials: the octant-code sweep with one material per octant.
//!
//! Each box carries a material id. A boundary face piece (a quadrant between an occupied and
//! an empty octant) takes the material of its occupied octant; where boxes overlap, the
//! smallest material id wins. Faces are then maximal per material: a face of the union is
//! split along the lines where the material beside it changes, and the interfaces between
//! materials inside the union are not faces.
//!
//! 1. Per plane, one coverage layer per (slab, material) present ([`scan_layers`]); the
//!    candidates are the run ends of every layer, so material changes are found as well as
//!    the union's vertices.
//! 2. At each candidate, read the material of the 8 octants; for each orientation and
//!    material, the quadrants whose inner octant has that material and whose outer octant is
//!    empty give a corner multiplicity and pass-through flag as in `octant`.
//! 3. A point is a vertex iff some multiplicity is positive; its degree per (orientation,
//!    material) is the conforming m + 2·pt, so faces of different materials meet without
//!    T-junctions.
//!
//! With one material this gives exactly the vertices and faces of the plain sweep (tested).
//! Complexity: the plain sweep's, times the number of materials present on a plane.

use crate::progress::Counter;

use super::grid::RankedBoxes;
use super::octant::{DegreeConvention, OCTANT_TABLE, classify_quadrants};
use super::rect2d::{Rect, scan_layers};
use super::sweep::{RankVertex, for_each_plane};

/// An octant with no material.
const EMPTY: u32 = u32::MAX;

/// One face corner of a vertex: `degree` copies on faces of `orientation` and `material`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct FaceCorner {
    pub vertex: u32,
    pub orientation: u8,
    pub material: u32,
    pub degree: u8,
    /// The quadrants around the vertex covered by the face, bit `sa | sb << 1` in the face
    /// frame: they orient the face's edges (`brep`).
    pub quadrants: u8,
}

/// Every vertex of the material boundary (sorted by (z, y, x)) and its face corners.
pub(crate) fn sweep_material_vertices(
    boxes: &RankedBoxes,
    counter: &Counter,
) -> (Vec<RankVertex>, Vec<FaceCorner>) {
    let slabs = material_slabs(boxes);
    let planes = boxes.coords[2].len();
    let per_plane = for_each_plane(&slabs, planes, counter, plane_vertices);
    let mut vertices = Vec::new();
    let mut corners = Vec::new();
    for (v, mut c) in per_plane.into_iter().flatten() {
        c.iter_mut().for_each(|c| c.vertex = vertices.len() as u32);
        vertices.push(v);
        corners.extend(c);
    }
    (vertices, corners)
}

/// The rectangles of each slab grouped by material: `(material, rects)` sorted by material.
fn material_slabs(boxes: &RankedBoxes) -> Vec<Vec<(u32, Vec<Rect>)>> {
    let mut slabs: Vec<Vec<(u32, Rect)>> =
        vec![Vec::new(); boxes.coords[2].len().saturating_sub(1)];
    for (b, &m) in boxes.boxes.iter().zip(&boxes.materials) {
        let rect = Rect {
            x0: b[0],
            x1: b[3],
            y0: b[1],
            y1: b[4],
        };
        for slab in &mut slabs[b[2] as usize..b[5] as usize] {
            slab.push((m, rect));
        }
    }
    slabs
        .into_iter()
        .map(|mut slab| {
            slab.sort_by_key(|&(m, _)| m);
            slab.chunk_by(|a, b| a.0 == b.0)
                .map(|g| (g[0].0, g.iter().map(|&(_, r)| r).collect()))
                .collect()
        })
        .collect()
}

/// Steps 1–3 on one plane.
fn plane_vertices(
    below: &[(u32, Vec<Rect>)],
    above: &[(u32, Vec<Rect>)],
    z: u32,
) -> Vec<(RankVertex, Vec<FaceCorner>)> {
    let layers: Vec<&[Rect]> = below.iter().chain(above).map(|(_, r)| &r[..]).collect();
    let material: Vec<u32> = below.iter().chain(above).map(|&(m, _)| m).collect();
    let split = below.len();
    let mut out = Vec::new();
    scan_layers(&layers, |x, y, masks| {
        // Step 2: the material of each octant, smallest id first (layers are sorted).
        let octants: [u32; 8] = std::array::from_fn(|o| {
            let (q, sz) = (o & 3, o >> 2);
            let range = if sz == 0 {
                0..split
            } else {
                split..masks.len()
            };
            range
                .into_iter()
                .find(|&t| masks[t] >> q & 1 == 1)
                .map_or(EMPTY, |t| material[t])
        });
        let corners = face_corners(&octants);
        if !corners.is_empty() {
            let code = octants
                .iter()
                .enumerate()
                .fold(0u8, |c, (o, &m)| c | u8::from(m != EMPTY) << o);
            let vertex = RankVertex {
                rank: [x, y, z],
                code,
                degrees: OCTANT_TABLE[code as usize].degrees(DegreeConvention::Conforming),
            };
            out.push((vertex, corners));
        }
    });
    out
}

/// Steps 2–3: the conforming degree per (orientation, material), or nothing if the point is
/// not a vertex.
fn face_corners(octants: &[u32; 8]) -> Vec<FaceCorner> {
    let mut quads: Vec<(u8, u32, u8)> = Vec::new(); // (orientation, material, quadrant mask)
    for k in 0..3 {
        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
        for q in 0..4 {
            let mut s = [0usize; 3];
            s[a] = q & 1;
            s[b] = q >> 1;
            let lo = octants[s[0] | s[1] << 1 | s[2] << 2];
            s[k] = 1;
            let hi = octants[s[0] | s[1] << 1 | s[2] << 2];
            let piece = match (lo != EMPTY, hi != EMPTY) {
                (true, false) => Some((2 * k as u8, lo)),
                (false, true) => Some((2 * k as u8 + 1, hi)),
                _ => None,
            };
            if let Some((o, m)) = piece {
                match quads.iter_mut().find(|e| e.0 == o && e.1 == m) {
                    Some(e) => e.2 |= 1 << q,
                    None => quads.push((o, m, 1 << q)),
                }
            }
        }
    }
    let classified: Vec<(u8, u32, u8, bool, u8)> = quads
        .into_iter()
        .map(|(o, m, q)| {
            let (mult, pass) = classify_quadrants(q);
            (o, m, mult, pass, q)
        })
        .collect();
    if classified.iter().all(|c| c.2 == 0) {
        return Vec::new();
    }
    classified
        .into_iter()
        .map(|(orientation, material, mult, pass, q)| FaceCorner {
            vertex: 0,
            orientation,
            material,
            degree: mult + 2 * u8::from(pass),
            quadrants: in_face_frame(q, orientation % 2 == 1),
        })
        .filter(|c| c.degree > 0)
        .collect()
}

/// A quadrant mask in the frame (k+1, k+2) as a mask in the face frame, which swaps the axes
/// on negative faces ([`Orientation::frame`](super::Orientation::frame)).
fn in_face_frame(q: u8, negative: bool) -> u8 {
    if negative {
        (q & 0b1001) | (q & 0b0010) << 1 | (q & 0b0100) >> 1
    } else {
        q
    }
}
