//! The **broad** stage (`design/exact.md`, stage 2): the pairs of triangles of different
//! operands whose bounding boxes overlap, less those that the plane of one triangle has
//! strictly on one side (exact, the first test of the intersect stage, answered by the
//! orientation filter almost always): the sliver triangles of CAD exports have boxes that
//! overlap thousands of triangles they cannot touch, and such pairs are not worth a place in
//! the list, its sort and the intersect stage's loop.
//!
//! Two operands whose trees the self-intersection check built ([`TriangleTrees`], one over
//! each operand's triangles) are walked against each other ([`Bvh::overlapping_filter_map`]),
//! which drops whole subtrees of either side at once: the trees are there, as a constructed
//! solid's collider is in manifold3d, and the walk of the whole trees costs less than the
//! restriction below (two 1 M-triangle spheres: broad 56 → 13 ms of op; two 1 k-triangle
//! ones 0.30 → 0.24 ms, pair_ball_union 0.42 → 0.21). Where the check did not run, whole
//! trees built for the broad phase alone would cost more than the restriction saves them:
//! 50 → 180 ms on the 1 M spheres.
//!
//! Otherwise only triangles near where operands meet are indexed. Two operands: in the
//! overlap of both operand boxes, each operand marks the cells of a coarse grid its
//! triangles' boxes overlap ([`Occupancy`], cells about as large as the triangles), and a
//! [`Bvh`] is built over each operand's triangles there that touch a cell the other marked
//! (a pair whose boxes overlap shares such a cell); the two trees are walked against each
//! other. On two offset 1 M-triangle spheres the overlap of the boxes holds 750 k triangles
//! of each, of which the grid keeps the few near the intersection curve. More operands: one
//! tree over every triangle that meets another operand's box, queried against itself,
//! keeping pairs of different operands. Output order is deterministic (the BVH walks are),
//! then sorted.

use crate::par::*;

use crate::index::{Aabb, Bvh, CellSpan, Occupancy};

use super::ingest::{Input, TriangleTrees};
use super::intersect::planes_separate;

/// Every pair `(s, t)` with `s < t` of triangles of different operands whose boxes overlap
/// and whose planes do not separate them, sorted. `trees` serve where both of two operands'
/// exist.
pub(crate) fn candidate_pairs(input: &Input, trees: &TriangleTrees) -> Vec<(u32, u32)> {
    let mut pairs = if input.operand_count() == 2 {
        let region = input.operand_boxes[0].intersection(&input.operand_boxes[1]);
        if region.is_empty() {
            return Vec::new();
        }
        // Both trees number each operand's triangles from its first.
        let (first_a, first_b) = (input.operand_starts[0], input.operand_starts[1]);
        let walk = |tree_a: &Bvh, tree_b: &Bvh| {
            tree_a.overlapping_filter_map(tree_b, |s, t| {
                let (s, t) = (s + first_a, t + first_b);
                let (x, y) = (input.triangle(s as usize), input.triangle(t as usize));
                (!planes_separate(&x, &y)).then_some((s, t))
            })
        };
        match (trees.built(0), trees.built(1)) {
            (Some(tree_a), Some(tree_b)) => walk(tree_a, tree_b),
            _ => {
                let (tree_a, tree_b) = trees_near(input, &region);
                walk(&tree_a, &tree_b)
            }
        }
    } else {
        let operand_tree = Bvh::build(&input.operand_boxes);
        let near_other: Vec<Aabb> = (0..input.triangles.len())
            .into_par_iter()
            .map(|t| {
                let (mine, own) = (input.operand[t], input.triangle_box(t));
                let near = operand_tree.any_overlapping(&own, |k| k != mine);
                if near { own } else { Aabb::EMPTY }
            })
            .collect();
        let tree = Bvh::build_in(near_other.len(), |t| near_other[t], &operand_tree.bounds());
        let mut pairs: Vec<(u32, u32)> = (tree.self_overlapping_pairs().into_par_iter())
            .filter(|&(s, t)| {
                input.operand[s as usize] != input.operand[t as usize] && {
                    let (a, b) = (input.triangle(s as usize), input.triangle(t as usize));
                    !planes_separate(&a, &b)
                }
            })
            .collect();
        pairs
            .par_iter_mut()
            .for_each(|p| *p = (p.0.min(p.1), p.0.max(p.1)));
        pairs
    };
    pairs.par_sort_unstable();
    pairs
}

/// Trees over the triangles of each of two operands that lie in `region` (the overlap of
/// their boxes) near the other operand's: in grid cells the other's triangles also occupy.
/// Ids count from each operand's first triangle.
fn trees_near(input: &Input, region: &Aabb) -> (Bvh, Bvh) {
    let (a, b) = (input.operand_triangles(0), input.operand_triangles(1));
    let box_a = |s: usize| input.triangle_box(s + a.start);
    let box_b = |t: usize| input.triangle_box(t + b.start);
    // The triangles' size, from a few thousand of them spread over each operand.
    let samples = (Occupancy::size_samples(a.len()).map(box_a))
        .chain(Occupancy::size_samples(b.len()).map(box_b));
    let side = Occupancy::side_for(region, samples);
    let ((cells_a, spans_a), (cells_b, spans_b)) = join(
        || Occupancy::of(region, side, a.len(), box_a),
        || Occupancy::of(region, side, b.len(), box_b),
    );
    let near = |spans: &[CellSpan], other: &Occupancy| -> Vec<u32> {
        (0..spans.len() as u32)
            .into_par_iter()
            .filter(|&i| other.touches(spans[i as usize]))
            .collect()
    };
    (
        Bvh::build_over(near(&spans_a, &cells_b), box_a),
        Bvh::build_over(near(&spans_b, &cells_a), box_b),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::ingest::ingest;
    use crate::exact::intersect::{Intersection, intersect_triangles};
    use crate::primitives::{cuboid, icosphere};

    #[test]
    fn pairs_are_the_overlapping_boxes_that_no_plane_separates() {
        let sphere = icosphere([0.0; 3], 1.0, 1);
        // Inside the sphere's box, outside the sphere: boxes overlap, planes separate.
        let outside = cuboid([0.6; 3], [0.75; 3]);
        let crossing = cuboid([0.5, -0.2, -0.2], [1.5, 0.2, 0.2]);
        let sets = [
            vec![&sphere, &outside],
            vec![&sphere, &crossing],
            vec![&sphere, &outside, &crossing],
        ];
        let (mut separated, mut kept) = (0, 0);
        for operands in sets {
            let input = ingest(&operands).expect("valid operands");
            let n = input.triangles.len() as u32;
            let (mut expected, mut overlapping) = (Vec::new(), 0);
            for s in 0..n {
                for t in s + 1..n {
                    let (a, b) = (input.triangle(s as usize), input.triangle(t as usize));
                    let boxes = input
                        .triangle_box(s as usize)
                        .overlaps(&input.triangle_box(t as usize));
                    if !boxes || input.operand[s as usize] == input.operand[t as usize] {
                        continue;
                    }
                    overlapping += 1;
                    if planes_separate(&a, &b) {
                        // What the list leaves out cannot touch.
                        assert!(matches!(
                            intersect_triangles(&a, &b),
                            Intersection::Disjoint
                        ));
                    } else {
                        expected.push((s, t));
                    }
                }
            }
            // Without trees (the grid's restriction), and walking the operands' whole trees
            // where they exist.
            let trees = TriangleTrees::on_demand(&input);
            assert_eq!(candidate_pairs(&input, &trees), expected);
            trees.build_missing();
            assert_eq!(candidate_pairs(&input, &trees), expected);
            separated += overlapping - expected.len();
            kept += expected.len();
        }
        // Both kinds were met: the cube outside the sphere only has separated pairs.
        assert!(
            separated > 0 && kept > 0,
            "{separated} separated, {kept} kept"
        );
    }
}
