//! Convex hulls decided by exact orientations (OpenSCAD's `hull()`).
//!
//! Hand-written: the hull crates (`chull`, parry3d's, bindings to qhull) decide whether a
//! point sees a face with a tolerance, so a point an ulp outside a face may be dropped and a
//! flat cap of many points may fold. Here every such decision is the exact [`orient3d`]
//! (or [`orient2d`]), and the hull's vertices are input points: the result is exactly the
//! convex hull of the points given, a closed solid the exact engine takes as it is.

use rustc_hash::FxHashSet;

use super::Mesh;
use crate::kernel::{Sign, orient2d, orient3d};

/// The convex hull of `points`: a closed, outward triangle mesh over its corners (points
/// inside it are left out; one on a face or an edge of it stays a vertex where it came
/// before the corners around it, and coplanar triangles stay apart: the solid is the hull
/// exactly all the same). Empty when the points lie in one plane, so bound no volume.
///
/// Incremental: each point is tested against every face of the hull so far and, where it
/// sees some, replaces them by the fan from it to their horizon. A point that only lies in a
/// face's plane does not see it, and coplanar faces, over one plane, agree on every point,
/// so what a point sees is always whole flat facets. `O(n h)` for `n` points and `h` hull
/// faces: milliseconds on OpenSCAD's hulls of a few spheres or cylinders.
pub fn convex_hull(points: &[[f64; 3]]) -> Mesh {
    let mut points = points.to_vec();
    points.sort_by(lexicographic);
    points.dedup();
    let Some(simplex) = initial_simplex(&points) else {
        return Mesh::new();
    };
    let [a, b, c, d] = simplex.map(|i| i as u32);
    let mut faces = vec![[a, b, c], [a, d, b], [b, d, c], [c, d, a]];
    let mut alive = vec![true; 4];
    let at = |v: u32| points[v as usize];
    for p in 0..points.len() as u32 {
        if simplex.contains(&(p as usize)) {
            continue;
        }
        let seen: Vec<usize> = (0..faces.len())
            .filter(|&f| {
                let [a, b, c] = faces[f];
                alive[f] && orient3d(at(a), at(b), at(c), at(p)) == Sign::Negative
            })
            .collect();
        if seen.is_empty() {
            continue;
        }
        let sides: FxHashSet<(u32, u32)> = (seen.iter())
            .flat_map(|&f| {
                let [a, b, c] = faces[f];
                [(a, b), (b, c), (c, a)]
            })
            .collect();
        for &f in &seen {
            alive[f] = false;
            let [a, b, c] = faces[f];
            for (u, v) in [(a, b), (b, c), (c, a)] {
                // A side of the seen region whose other face is not seen: the horizon.
                if !sides.contains(&(v, u)) {
                    faces.push([u, v, p]);
                    alive.push(true);
                }
            }
        }
    }
    let kept: Vec<[u32; 3]> = (faces.iter().zip(&alive))
        .filter(|&(_, &alive)| alive)
        .map(|(f, _)| *f)
        .collect();
    let mut id = vec![u32::MAX; points.len()];
    let mut corners = Vec::new();
    let triangles: Vec<[u32; 3]> = (kept.iter())
        .map(|face| {
            face.map(|v| {
                if id[v as usize] == u32::MAX {
                    id[v as usize] = corners.len() as u32;
                    corners.push(points[v as usize]);
                }
                id[v as usize]
            })
        })
        .collect();
    Mesh::from_triangles(corners, &triangles).expect("indices of the kept corners")
}

/// The convex hull of `points` in the plane: its corners counterclockwise, from the
/// lexicographically smallest, without points on its sides; empty when the points lie on
/// one line. Andrew's monotone chain.
pub fn convex_hull_2d(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut points = points.to_vec();
    points.sort_by(lexicographic);
    points.dedup();
    if points.len() < 3 {
        return Vec::new();
    }
    // A chain keeps only left turns: the lower one forward, the upper one backward.
    let chain = |points: &mut dyn Iterator<Item = [f64; 2]>| {
        let mut chain: Vec<[f64; 2]> = Vec::new();
        for p in points {
            while let [.., a, b] = chain[..] {
                if orient2d(a, b, p) == Sign::Positive {
                    break;
                }
                chain.pop();
            }
            chain.push(p);
        }
        chain.pop();
        chain
    };
    let mut hull = chain(&mut points.iter().copied());
    hull.extend(chain(&mut points.iter().rev().copied()));
    if hull.len() < 3 { Vec::new() } else { hull }
}

/// Coordinates compared in order (the points are finite).
fn lexicographic<const N: usize>(a: &[f64; N], b: &[f64; N]) -> std::cmp::Ordering {
    (a.iter().zip(b))
        .map(|(x, y)| x.total_cmp(y))
        .find(|o| o.is_ne())
        .unwrap_or(std::cmp::Ordering::Equal)
}

/// Four of `points` (sorted, distinct) not in one plane, ordered so that the fourth lies
/// below the plane of the first three, which then face outward counterclockwise; `None` when
/// all lie in one plane.
fn initial_simplex(points: &[[f64; 3]]) -> Option<[usize; 4]> {
    let (a, b) = (0, points.len().checked_sub(1).filter(|&b| b > 0)?);
    let (pa, pb) = (points[a], points[b]);
    // Three points are collinear when every axis projection of them is.
    let collinear = |p: [f64; 3]| {
        [(0, 1), (1, 2), (0, 2)]
            .iter()
            .all(|&(u, v)| orient2d([pa[u], pa[v]], [pb[u], pb[v]], [p[u], p[v]]) == Sign::Zero)
    };
    let c = (0..points.len()).find(|&c| !collinear(points[c]))?;
    let pc = points[c];
    let (d, side) = (0..points.len())
        .map(|d| (d, orient3d(pa, pb, pc, points[d])))
        .find(|&(_, side)| side != Sign::Zero)?;
    Some(if side == Sign::Positive {
        [a, b, c, d]
    } else {
        [a, c, b, d]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_corners(min: f64, max: f64) -> Vec<[f64; 3]> {
        (0..8)
            .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { max } else { min }))
            .collect()
    }

    #[test]
    fn the_hull_of_a_cube_and_points_inside_and_on_it_is_the_cube() {
        let mut points = cube_corners(-1.0, 1.0);
        // Inside, at face centres, on edges: none is a corner of the hull.
        points.extend([
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.5],
            [1.0, 1.0, 0.25],
        ]);
        points.extend(cube_corners(-0.5, 0.5));
        let hull = convex_hull(&points);
        let report = hull.report();
        assert!(report.is_valid_solid());
        assert_eq!(report.measures.volume, 8.0);
        for corner in cube_corners(-1.0, 1.0) {
            assert!(hull.positions().contains(&corner));
        }
        // The points inside are not vertices.
        assert!(
            hull.positions()
                .iter()
                .all(|p| p.iter().all(|x| x.abs() == 1.0)
                    || [[1.0, 0.0, 0.0], [0.0, -1.0, 0.5], [1.0, 1.0, 0.25]].contains(p))
        );
        assert!(crate::exact::self_intersections(&hull).is_empty());
    }

    #[test]
    fn points_in_one_plane_have_no_hull() {
        let flat: Vec<[f64; 3]> = (0..10)
            .map(|i| [f64::from(i), f64::from(i * i % 7), 0.0])
            .collect();
        assert!(convex_hull(&flat).is_empty());
        let line: Vec<[f64; 3]> = (0..5).map(|i| [f64::from(i); 3]).collect();
        assert!(convex_hull(&line).is_empty());
        assert!(convex_hull(&[[1.0; 3]]).is_empty());
    }

    #[test]
    fn the_hull_of_two_spheres_is_a_valid_capsule() {
        let mut points = Vec::new();
        for centre in [[0.0; 3], [3.0, 1.0, 0.5]] {
            let sphere = crate::primitives::uv_sphere(centre, 1.0, 24);
            points.extend_from_slice(sphere.positions());
        }
        let hull = convex_hull(&points);
        let report = hull.report();
        assert!(report.is_valid_solid());
        assert!(crate::exact::self_intersections(&hull).is_empty());
        // Every input point is inside or on the hull: no face sees any.
        for p in &points {
            for face in hull.faces() {
                let [a, b, c] = [0, 1, 2].map(|i| hull.positions()[face[i] as usize]);
                assert_ne!(orient3d(a, b, c, *p), Sign::Negative);
            }
        }
    }

    #[test]
    fn the_planar_hull_is_counterclockwise_without_points_on_its_sides() {
        let points = [
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [2.0, 2.0],
        ];
        assert_eq!(
            convex_hull_2d(&points),
            vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
        );
        assert!(convex_hull_2d(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_empty());
    }
}
