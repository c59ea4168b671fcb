//! The **broad** stage (`design/exact.md`, stage 2): the pairs of triangles of different
//! operands whose bounding boxes overlap.
//!
//! Only triangles inside the region where operands overlap are indexed. Two operands: one
//! [`Bvh`] over the smaller operand's triangles in the overlap of both operand boxes, queried
//! by each of the other operand's triangles there, in parallel. More: one tree over every triangle that meets another operand's box,
//! queried against itself, keeping pairs of different operands. Output order is
//! deterministic (the BVH queries are), then sorted.

use crate::par::*;

use crate::index::{Aabb, Bvh};

use super::ingest::Input;

/// The box of triangle `t`.
pub(crate) fn triangle_box(input: &Input, t: usize) -> Aabb {
    Aabb::from_points(input.triangles[t].positions().iter())
}

/// Every pair `(s, t)` with `s < t` of triangles of different operands whose boxes overlap,
/// sorted.
pub(crate) fn candidate_pairs(input: &Input) -> Vec<(u32, u32)> {
    let mut pairs = if input.operand_count() == 2 {
        let region = input.operand_boxes[0].intersection(&input.operand_boxes[1]);
        if region.is_empty() {
            return Vec::new();
        }
        // One tree over the smaller operand, queried by each triangle of the other in the
        // region: cheaper than building a second tree for a one-shot query. Boxes are
        // computed where they are used, not stored for every triangle: most of a large
        // operand lies outside the region.
        let (a, b) = (input.operand_triangles(0), input.operand_triangles(1));
        let (small, large) = if a.len() <= b.len() { (a, b) } else { (b, a) };
        let offset = small.start;
        let tree = Bvh::build_in(small.len(), |s| triangle_box(input, s + offset), &region);
        (large.into_par_iter())
            .flat_map_iter(|t| {
                let query = triangle_box(input, t);
                let mut hits = Vec::new();
                if query.overlaps(&region) {
                    tree.visit_overlapping(&query, |s| {
                        let s = s + offset as u32;
                        hits.push((s.min(t as u32), s.max(t as u32)));
                    });
                }
                hits
            })
            .collect()
    } else {
        let operand_tree = Bvh::build(&input.operand_boxes);
        let near_other: Vec<Aabb> = (0..input.triangles.len())
            .into_par_iter()
            .map(|t| {
                let (mine, own) = (input.operand[t], triangle_box(input, t));
                let near = operand_tree.any_overlapping(&own, |k| k != mine);
                if near { own } else { Aabb::EMPTY }
            })
            .collect();
        let tree = Bvh::build_in(near_other.len(), |t| near_other[t], &operand_tree.bounds());
        let mut pairs: Vec<(u32, u32)> = (tree.self_overlapping_pairs().into_par_iter())
            .filter(|&(s, t)| input.operand[s as usize] != input.operand[t as usize])
            .collect();
        pairs
            .par_iter_mut()
            .for_each(|p| *p = (p.0.min(p.1), p.0.max(p.1)));
        pairs
    };
    pairs.par_sort_unstable();
    pairs
}
