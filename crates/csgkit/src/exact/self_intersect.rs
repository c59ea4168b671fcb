//! The exact self-intersection check of one mesh.
//!
//! # Contract
//! [`self_intersections`] reports the pairs of faces that intersect and the faces involved,
//! with the semantics of libigl's CGAL-based `remesh_self_intersections` in detect-only mode
//! (the reference measured in the shared data's `manifest.json`):
//! - vertices with exactly equal positions are welded first (`-0.0` equals `0.0`);
//! - polygons are fan-triangulated ([`Mesh::fan_triangles`]); exactly degenerate triangles
//!   (collinear corners) are left out;
//! - two triangles with no shared vertex count when they have any common point (touching
//!   counts);
//! - sharing one vertex: when they have a common point besides that vertex;
//! - sharing an edge: only when they are coplanar and overlap with positive area
//!   ([`Intersection::CoplanarOverlap`]);
//! - sharing three vertices (a duplicated triangle): never, as in libigl;
//! - **polygons** (a csgkit choice; the reference files with polygons have no
//!   self-intersection): two fan triangles of the same face never count against each other,
//!   and a pair of faces counts once however many of their triangles meet. On triangle
//!   meshes the face pairs are exactly the triangle pairs of the reference.
//!
//! # Algorithm
//! 1. Weld, fan-triangulate and drop degenerate triangles ([`Triangle::new`]).
//! 2. Candidate pairs: [`Bvh::self_overlapping_pairs`] on the triangles' boxes (closed boxes,
//!    so touching triangles are candidates).
//! 3. In parallel (rayon), count the shared vertices of each pair and classify it with
//!    [`intersect_triangles`] by the rules above.
//! 4. Sort and deduplicate the face pairs; the faces are the sorted union of their members.
//!
//! # Complexity
//! O(n log n) for the hierarchy plus O(1) exact predicates per candidate pair; for a mesh
//! without self-intersection the candidates are mostly neighbours (a few per triangle).
//! The output is the same for every thread count.

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::intersect::{Intersection, Triangle, intersect_triangles};
use crate::index::{Aabb, Bvh};
use crate::mesh::{FaceId, Mesh};

/// The self-intersections of a mesh (see [`self_intersections`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SelfIntersections {
    /// Intersecting face pairs, each as (smaller id, larger id), sorted, without repeats.
    pub pairs: Vec<(FaceId, FaceId)>,
    /// The faces in at least one pair, sorted, without repeats.
    pub faces: Vec<FaceId>,
}

impl SelfIntersections {
    /// The number of intersecting face pairs.
    pub fn pair_count(&self) -> usize {
        self.pairs.len()
    }

    /// The number of faces involved.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// True when the mesh does not intersect itself.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }
}

/// The exact self-intersections of `mesh` (semantics and algorithm in the
/// [module docs](self)).
pub fn self_intersections(mesh: &Mesh) -> SelfIntersections {
    let triangles = triangles(mesh);
    let boxes: Vec<Aabb> = triangles
        .iter()
        .map(|(_, t)| Aabb::from_points(t.positions().iter()))
        .collect();
    let candidates = Bvh::build(&boxes).self_overlapping_pairs();
    let mut pairs: Vec<(FaceId, FaceId)> = candidates
        .par_iter()
        .filter_map(|&(i, j)| {
            let ((fa, a), (fb, b)) = (&triangles[i as usize], &triangles[j as usize]);
            (fa != fb && counts(a, b)).then(|| (*fa.min(fb), *fa.max(fb)))
        })
        .collect();
    pairs.par_sort_unstable();
    pairs.dedup();
    let mut faces: Vec<FaceId> = pairs.iter().flat_map(|&(f, g)| [f, g]).collect();
    faces.par_sort_unstable();
    faces.dedup();
    SelfIntersections { pairs, faces }
}

/// The non-degenerate fan triangles of `mesh` with welded vertex ids, tagged with their face.
fn triangles(mesh: &Mesh) -> Vec<(FaceId, Triangle)> {
    let positions = mesh.positions();
    let mut first: FxHashMap<[u64; 3], u32> = FxHashMap::default();
    let weld: Vec<u32> = positions
        .iter()
        .enumerate()
        .map(|(v, p)| {
            // `+ 0.0` turns `-0.0` into `0.0`, so exactly equal positions weld.
            let bits = p.map(|x| (x + 0.0).to_bits());
            *first.entry(bits).or_insert(v as u32)
        })
        .collect();
    mesh.fan_triangles()
        .filter_map(|(face, corners)| {
            let ids = corners.map(|v| weld[v as usize]);
            let pts = ids.map(|v| positions[v as usize]);
            Triangle::new(0, ids, pts).map(|t| (face, t))
        })
        .enumerate()
        .map(|(k, (face, t))| (face, t.with_id(k as u32)))
        .collect()
}

/// Whether a pair of triangles of one mesh counts as intersecting (libigl's rules).
fn counts(a: &Triangle, b: &Triangle) -> bool {
    let shared = a
        .vertices()
        .iter()
        .filter(|v| b.vertices().contains(v))
        .count();
    let found = intersect_triangles(a, b);
    match shared {
        0 => !matches!(found, Intersection::Disjoint),
        // The shared vertex is common; anything more counts.
        1 => !matches!(
            found,
            Intersection::Disjoint | Intersection::TouchingPoint(_)
        ),
        2 => matches!(found, Intersection::CoplanarOverlap(_)),
        _ => false,
    }
}
