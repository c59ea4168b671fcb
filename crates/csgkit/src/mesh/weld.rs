//! Welding of vertices whose positions are identical.
//!
//! STL stores no shared vertices and many files repeat vertices on purpose (UV seams), so every
//! topological measure runs on welded vertices.
//! Two vertices weld when their three coordinates are equal as numbers: no epsilon takes part,
//! so welding never merges vertices that a file keeps apart on purpose.
//!
//! # Definitions
//! - Coordinates are compared by their IEEE 754 bit patterns after mapping `-0.0` to `+0.0`.
//!   The two zeros are the same number, and the reference measurements in
//!   `shared/data/manifest.json` weld them: `teapot.obj` and `capsule.obj` store seam vertices
//!   as `0` and `-0`, and only welding them gives the reference's 403 and 250 duplicates (and
//!   a closed capsule). Bit-exact welding would leave 319 and 194.
//! - A NaN welds only with a NaN of the same bit pattern; readers reject non-finite
//!   coordinates anyway.
//! - The surviving vertex of each class is its first occurrence, and welded vertices keep the
//!   order of first occurrence, so welding is deterministic.
//!
//! # Complexity
//! One parallel sort of the vertices by their coordinate bits: O(V log V) work spread over
//! every core, O(V) memory.

use crate::par::*;

use super::Mesh;

/// How the vertices of a mesh weld: a map from each vertex to its welded index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Welding {
    /// For each input vertex, the index of its welded vertex (first-occurrence order).
    pub remap: Vec<u32>,
    /// For each welded vertex, the input vertex that represents it (its first occurrence).
    pub representatives: Vec<u32>,
}

impl Welding {
    /// The number of welded (distinct) positions.
    pub fn welded_count(&self) -> usize {
        self.representatives.len()
    }

    /// The number of input vertices that repeat an earlier position.
    pub fn duplicate_count(&self) -> usize {
        self.remap.len() - self.representatives.len()
    }
}

/// Computes the welding of equal positions.
///
/// Sorts the vertices by their coordinate bits (in parallel) and takes the first vertex of
/// each run of equal keys: the same result as a first-occurrence hash pass, faster on large
/// meshes because the sort runs on every core.
pub fn weld_positions(positions: &[[f64; 3]]) -> Welding {
    let mut order: Vec<([u64; 3], u32)> = (positions.par_iter().enumerate())
        .map(|(v, p)| (p.map(canonical_bits), v as u32))
        .collect();
    order.par_sort_unstable();
    // The first vertex of each run of equal keys represents it.
    let mut first_of = vec![0u32; positions.len()];
    let mut is_first = vec![false; positions.len()];
    for run in order.chunk_by(|x, y| x.0 == y.0) {
        let first = run[0].1;
        is_first[first as usize] = true;
        for &(_, v) in run {
            first_of[v as usize] = first;
        }
    }
    // Welded ids in order of first occurrence.
    let mut id_of_first = vec![0u32; positions.len()];
    let mut representatives = Vec::new();
    for (v, &first) in is_first.iter().enumerate() {
        if first {
            id_of_first[v] = representatives.len() as u32;
            // Lossless: `Mesh` guarantees fewer than u32::MAX vertices.
            representatives.push(v as u32);
        }
    }
    let remap = first_of.iter().map(|&f| id_of_first[f as usize]).collect();
    Welding {
        remap,
        representatives,
    }
}

/// The bits of a coordinate, with `-0.0` mapped to `+0.0`.
fn canonical_bits(x: f64) -> u64 {
    if x == 0.0 { 0 } else { x.to_bits() }
}

/// Returns `mesh` with equal vertices welded, and the welding that was applied.
///
/// Faces, face attributes and corner attributes are kept as they are; corners point to the
/// welded vertices. A per-vertex colour is the colour of the vertex's first occurrence.
pub fn weld(mesh: &Mesh) -> (Mesh, Welding) {
    let welding = weld_positions(mesh.positions());
    (apply_welding(mesh, &welding), welding)
}

/// Returns `mesh` with its vertices merged as `welding` says.
///
/// # Panics
/// If `welding` was not computed from this mesh's positions.
pub fn apply_welding(mesh: &Mesh, welding: &Welding) -> Mesh {
    assert_eq!(
        welding.remap.len(),
        mesh.vertex_count(),
        "welding belongs to this mesh"
    );
    let parts = mesh.parts();
    let mut welded = parts.clone();
    welded.positions = (welding.representatives.iter())
        .map(|&v| parts.positions[v as usize])
        .collect();
    for corner in &mut welded.corners {
        *corner = welding.remap[*corner as usize];
    }
    if let Some(colors) = &parts.vertex_colors {
        let first = |&v: &u32| colors[v as usize];
        welded.vertex_colors = Some(welding.representatives.iter().map(first).collect());
    }
    let mesh = Mesh { parts: welded };
    debug_assert!(
        mesh.check_invariants().is_ok(),
        "welding keeps every invariant"
    );
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welds_equal_positions_and_both_zeros() {
        let next_after_one = f64::from_bits(1.0f64.to_bits() + 1);
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [-0.0, 0.0, -0.0],
            [1.0, 0.0, 0.0],
            [next_after_one, 0.0, 0.0],
        ];
        let welding = weld_positions(&positions);
        assert_eq!(welding.remap, vec![0, 1, 0, 0, 1, 2]);
        assert_eq!(welding.representatives, vec![0, 1, 5]);
        assert_eq!(welding.duplicate_count(), 3);
        assert_eq!(welding.welded_count(), 3);
    }

    #[test]
    fn weld_remaps_corners_and_keeps_faces() {
        // Two triangles of a square stored STL-style, with no shared vertex.
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let mesh = Mesh::from_triangles(positions, &[[0, 1, 2], [3, 4, 5]]).unwrap();
        let (welded, welding) = weld(&mesh);
        assert_eq!(welding.duplicate_count(), 2);
        assert_eq!(welded.vertex_count(), 4);
        assert_eq!(welded.corners(), &[0, 1, 2, 0, 2, 3]);
        welded.check_invariants().unwrap();
    }
}
