//! Exact classification of degenerate faces and detection of duplicate faces.
//!
//! # Definitions
//! - A face is **combinatorially degenerate** when two of its corners are the same welded
//!   vertex, and **collinear** when its vertices are distinct but all lie on one line.
//!   Both have zero area; the reference counts the first as `comb_degen` and both as
//!   `zero_area`.
//! - Collinearity is decided exactly: three points are collinear iff the cross product
//!   (b − a) × (c − a) vanishes, and its three components are the 2D orientation determinants
//!   of the projections on the yz, zx and xy planes. Each is decided by the kernel's
//!   [`orient2d`], whose sign is exact for every finite f64 input, subnormal coordinates
//!   included (Shewchuk's predicates alone underflow there, and would call a triangle with a
//!   corner at `y = -5e-324` flat); no epsilon takes part. A polygon is collinear when every corner is collinear with its first
//!   corner and the first corner at another position.
//! - **Duplicate faces**: faces whose sorted welded vertex lists equal an earlier face's,
//!   whatever their orientation or starting corner (the reference's "repeated vertex
//!   triples"). Degenerate faces count too.
//! - **Opposite pairs** ([`opposite_triangle_pairs`]): two triangles over the same three
//!   vertices in opposite orientations, a two-sided sheet. It adds nothing to any winding
//!   number off the sheet, so removing both faces leaves the solid, its volume and the balance
//!   of every edge as they were, while the sheet itself has no inside to sample and doubles
//!   the uses of its edges.
//! - **Repeats** ([`coincident_triangles`]): a triangle over the same three vertices, in the
//!   same orientation, as an earlier one that no opposite pair took.
//!
//! # Numeric model
//! Exact for finite coordinates. Non-finite coordinates (rejected by readers) give an
//! unspecified but panic-free answer.
//!
//! # Complexity
//! O(C) predicate calls for C corners; duplicate detection sorts the faces, O(F log F).

use crate::kernel::{Sign, orient2d};

use super::Mesh;

/// The shape of one face, decided exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FaceShape {
    /// At least three corners not on one line: positive area.
    Proper,
    /// Two corners are the same (welded) vertex.
    RepeatedVertex,
    /// Distinct vertices, all on one line.
    Collinear,
}

/// Classifies a face given its welded vertex indices and the mesh positions.
pub fn face_shape(positions: &[[f64; 3]], corners: &[u32]) -> FaceShape {
    if has_repeated_vertex(corners) {
        return FaceShape::RepeatedVertex;
    }
    if let [a, b, c] = *corners {
        let p = |v: u32| positions[v as usize];
        return if are_collinear(p(a), p(b), p(c)) {
            FaceShape::Collinear
        } else {
            FaceShape::Proper
        };
    }
    let first = positions[corners[0] as usize];
    let other = corners
        .iter()
        .map(|&v| positions[v as usize])
        .find(|p| *p != first);
    let Some(second) = other else {
        return FaceShape::Collinear;
    };
    let all_on_line = corners
        .iter()
        .all(|&v| are_collinear(first, second, positions[v as usize]));
    if all_on_line {
        FaceShape::Collinear
    } else {
        FaceShape::Proper
    }
}

/// Whether three points lie on one line (or coincide), decided exactly. A point with a
/// non-finite coordinate is on no line: false, without a test, as the exact predicates take
/// finite numbers (a report of a mesh with such a point then shows its volume as NaN).
pub fn are_collinear(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    if ![a, b, c].as_flattened().iter().all(|x| x.is_finite()) {
        return false;
    }
    // The cross product's components are the orientations of the three axis projections.
    [(1, 2), (2, 0), (0, 1)].iter().all(|&(i, j)| {
        let project = |p: [f64; 3]| [p[i], p[j]];
        orient2d(project(a), project(b), project(c)) == Sign::Zero
    })
}

/// Whether a face uses one vertex index twice.
fn has_repeated_vertex(corners: &[u32]) -> bool {
    if let [a, b, c] = corners {
        return a == b || b == c || a == c;
    }
    let mut sorted = corners.to_vec();
    sorted.sort_unstable();
    sorted.windows(2).any(|w| w[0] == w[1])
}

/// Counts of degenerate and duplicate faces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DegenerateCounts {
    /// Faces with a repeated vertex.
    pub repeated_vertex: usize,
    /// Faces with distinct but collinear vertices.
    pub collinear: usize,
    /// Faces whose vertex set repeats an earlier face's.
    pub duplicate: usize,
}

/// Classifies every face of a welded mesh and counts duplicate faces.
pub fn count_degenerate(mesh: &Mesh) -> DegenerateCounts {
    let mut counts = DegenerateCounts::default();
    for corners in mesh.faces() {
        match face_shape(mesh.positions(), corners) {
            FaceShape::Proper => {}
            FaceShape::RepeatedVertex => counts.repeated_vertex += 1,
            FaceShape::Collinear => counts.collinear += 1,
        }
    }
    counts.duplicate = count_duplicate_faces(mesh);
    counts
}

/// The number of faces whose sorted vertex list equals an earlier face's.
///
/// Sorting the keys and counting equal neighbours is faster than hashing on large meshes.
/// A triangle never equals a larger face, so the two kinds are counted apart.
fn count_duplicate_faces(mesh: &Mesh) -> usize {
    let mut triangles = Vec::new();
    let mut polygons = Vec::new();
    for corners in mesh.faces() {
        if let [a, b, c] = *corners {
            let mut key = [a, b, c];
            key.sort_unstable();
            triangles.push(key);
        } else {
            let mut key = corners.to_vec();
            key.sort_unstable();
            polygons.push(key);
        }
    }
    triangles.sort_unstable();
    polygons.sort_unstable();
    let repeats = |n: usize, same: &dyn Fn(usize) -> bool| (1..n).filter(|&i| same(i)).count();
    repeats(triangles.len(), &|i| triangles[i] == triangles[i - 1])
        + repeats(polygons.len(), &|i| polygons[i] == polygons[i - 1])
}

/// The pairs of `triangles` (each an id and its welded corners) over the same three vertices
/// in opposite orientations (see the module docs), each triangle in at most one pair, a
/// triangle of one orientation paired with one of the other in id order; triangles with a
/// repeated corner are in none.
///
/// # Complexity
/// One sort of the triangles given, O(T log T).
pub fn opposite_triangle_pairs(
    triangles: impl IntoIterator<Item = (u32, [u32; 3])>,
) -> Vec<[u32; 2]> {
    coincident_triangles(triangles).0
}

/// [`opposite_triangle_pairs`], and the **repeats** left over: among the triangles over the
/// same three vertices that no pair took, which all have one orientation, every one but the
/// first (by id). A repeat is geometry a file holds twice, or a face that nested shells
/// share; it doubles the winding number behind it and the uses of its edges.
///
/// # Complexity
/// One sort of the triangles given, O(T log T).
pub fn coincident_triangles(
    triangles: impl IntoIterator<Item = (u32, [u32; 3])>,
) -> (Vec<[u32; 2]>, Vec<u32>) {
    // Key: the corners rotated so that the smallest is first, then the other two in increasing
    // order; the flag says whether that took a reflection, so opposite triangles share a key
    // and differ in the flag.
    let mut keyed: Vec<([u32; 3], bool, u32)> = (triangles.into_iter())
        .filter(|(_, c)| c[0] != c[1] && c[1] != c[2] && c[2] != c[0])
        .map(|(id, c)| {
            let first = (0..3).min_by_key(|&i| c[i]).unwrap_or(0);
            let (a, b, d) = (c[first], c[(first + 1) % 3], c[(first + 2) % 3]);
            if b < d {
                ([a, b, d], false, id)
            } else {
                ([a, d, b], true, id)
            }
        })
        .collect();
    keyed.sort_unstable();
    let mut pairs = Vec::new();
    let mut repeats = Vec::new();
    for group in keyed.chunk_by(|x, y| x.0 == y.0) {
        let (forward, reflected) = group.split_at(group.partition_point(|x| !x.1));
        pairs.extend((forward.iter().zip(reflected)).map(|(f, r)| [f.2, r.2]));
        let paired = forward.len().min(reflected.len());
        let unpaired = if forward.len() > paired {
            &forward[paired..]
        } else {
            &reflected[paired..]
        };
        repeats.extend(unpaired.iter().skip(1).map(|x| x.2));
    }
    (pairs, repeats)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collinearity_is_exact() {
        let a = [0.0, 0.0, 0.0];
        let b = [1.0, 1.0, 1.0];
        assert!(are_collinear(a, b, [3.0, 3.0, 3.0]));
        // One ulp off the line is not collinear.
        let off = [3.0, 3.0, f64::from_bits(3.0f64.to_bits() + 1)];
        assert!(!are_collinear(a, b, off));
        // The doubles nearest 0.1, 0.2, 0.3 (and 0.3, 0.6, 0.9) are not exactly on a line:
        // the exact determinant is 2^-56.
        assert!(!are_collinear(
            [0.1, 0.3, 0.0],
            [0.2, 0.6, 0.0],
            [0.3, 0.9, 0.0]
        ));
        assert!(are_collinear(
            [0.5, 0.25, 0.0],
            [1.0, 0.5, 0.0],
            [1e10, 5e9, 0.0]
        ));
        // A corner one subnormal step off the x axis: every product in Shewchuk's formula
        // underflows to zero, but the triangle has an area.
        let tiny = -f64::from_bits(1);
        assert!(!are_collinear(
            [0.0, 0.0, 0.0],
            [3.4e-18, tiny, 0.0],
            [0.25, 0.0, 0.0]
        ));
        assert!(are_collinear(
            [0.0, tiny, 0.0],
            [3.4e-18, tiny, 0.0],
            [0.25, tiny, 0.0]
        ));
        // Non-finite coordinates: on no line, even where the finite ones would be.
        assert!(!are_collinear(a, b, [f64::NAN, 3.0, 3.0]));
        assert!(!are_collinear(a, [f64::INFINITY; 3], [3.0; 3]));
    }

    #[test]
    fn classifies_faces() {
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(face_shape(&positions, &[0, 1, 3]), FaceShape::Proper);
        assert_eq!(face_shape(&positions, &[0, 1, 2]), FaceShape::Collinear);
        assert_eq!(
            face_shape(&positions, &[0, 1, 1]),
            FaceShape::RepeatedVertex
        );
        assert_eq!(face_shape(&positions, &[0, 1, 2, 3]), FaceShape::Proper);
        assert_eq!(
            face_shape(&positions, &[2, 1, 0, 1]),
            FaceShape::RepeatedVertex
        );
    }

    #[test]
    fn coincident_triangles_pair_opposites_and_keep_one_of_each_repeat() {
        // Ids 0, 1, 2 go one way round {0, 1, 2}, 3 and 4 the other; 5 and 6 repeat {0, 1, 3};
        // 7 has a repeated corner and is no triangle.
        let triangles = [
            (0, [0, 1, 2]),
            (1, [1, 2, 0]),
            (2, [2, 0, 1]),
            (3, [2, 1, 0]),
            (4, [0, 2, 1]),
            (5, [0, 1, 3]),
            (6, [3, 0, 1]),
            (7, [0, 0, 1]),
        ];
        let (pairs, repeats) = coincident_triangles(triangles);
        assert_eq!(pairs, vec![[0, 3], [1, 4]]);
        // Of {0, 1, 2}, triangle 2 is left unpaired and is the first of its kind: kept.
        assert_eq!(repeats, vec![6]);
    }

    #[test]
    fn counts_duplicates_in_any_orientation() {
        let positions = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mesh =
            Mesh::from_triangles(positions, &[[0, 1, 2], [2, 1, 0], [1, 2, 0], [0, 1, 3]]).unwrap();
        let counts = count_degenerate(&mesh);
        assert_eq!(counts.duplicate, 2);
        assert_eq!(counts.repeated_vertex + counts.collinear, 0);
    }

    #[test]
    fn pairs_triangles_of_opposite_orientation_only() {
        // 0 and 1 are opposite; 2 repeats 0's orientation from another corner and has no
        // partner left; 3 is opposite to 2; 4 shares only two corners; 5 repeats a corner.
        let triangles = [
            [0, 1, 2],
            [2, 1, 0],
            [1, 2, 0],
            [0, 2, 1],
            [0, 1, 3],
            [0, 0, 1],
        ];
        let pairs = opposite_triangle_pairs((0..).zip(triangles));
        assert_eq!(pairs, vec![[0, 1], [2, 3]]);
        let unpaired = [[0, 1, 2], [1, 2, 0], [2, 1, 3]];
        assert!(opposite_triangle_pairs((0..).zip(unpaired)).is_empty());
    }
}
