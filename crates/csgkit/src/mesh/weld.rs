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
//! One parallel sort of the vertices by a hash of their coordinate bits: O(V log V) work
//! spread over every core, O(V) memory.

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
/// Sorts the vertices by a hash of their coordinate bits (in parallel), splits each run of
/// equal hashes by the bits themselves, and takes the first vertex of each class: the same
/// result as a first-occurrence hash pass, faster on large meshes because the sort runs on
/// every core. Sorting 8-byte (hash, vertex) keys rather than 32-byte (bits, vertex) records
/// moves a quarter of the bytes, the same welding.
pub fn weld_positions(positions: &[[f64; 3]]) -> Welding {
    weld_positions_by(positions.len(), |v| positions[v as usize])
}

/// [`weld_positions`] of the `count` positions `position(0..count)`, for a caller whose
/// positions lie in several arrays (the exact engine's operands): copying them into one first
/// cost the engine's ingest 13 ms of its 210 on two 1 M-triangle spheres, most of it the first
/// touch of the 24 MB copy.
pub(crate) fn weld_positions_by(
    count: usize,
    position: impl Fn(u32) -> [f64; 3] + Sync,
) -> Welding {
    let bits = |v: u32| position(v).map(canonical_bits);
    // (High half of the hash, vertex) in one 8-byte key: the sort moves and compares half
    // what (hash, vertex) pairs took (two 1 M-triangle spheres: 36–42 → 25–26 ms); the few
    // positions whose hashes share a high half are told apart by their bits below.
    let vertex = |key: u64| key as u32;
    let mut order: Vec<u64> = (0..count as u32)
        .into_par_iter()
        .map(|v| position_hash(&position(v)) & !u64::from(u32::MAX) | u64::from(v))
        .collect();
    order.par_sort_unstable();
    // Each vertex is the first of its class unless a run says otherwise.
    let mut first_of: Vec<u32> = (0..count as u32).into_par_iter().collect();
    for run in order.chunk_by_mut(|x, y| x >> 32 == y >> 32) {
        if run.len() == 1 {
            continue;
        }
        // Equal bits are together, each class in vertex order.
        run.sort_unstable_by_key(|&key| (bits(vertex(key)), vertex(key)));
        for class in run.chunk_by(|&x, &y| bits(vertex(x)) == bits(vertex(y))) {
            for &key in &class[1..] {
                first_of[vertex(key) as usize] = vertex(class[0]);
            }
        }
    }
    // Welded ids in order of first occurrence.
    let mut id_of_first = vec![0u32; count];
    let mut representatives = Vec::new();
    for (v, &first) in first_of.iter().enumerate() {
        if first as usize == v {
            id_of_first[v] = representatives.len() as u32;
            // Lossless: `Mesh` guarantees fewer than u32::MAX vertices.
            representatives.push(v as u32);
        }
    }
    let remap = (first_of.par_iter())
        .map(|&f| id_of_first[f as usize])
        .collect();
    Welding {
        remap,
        representatives,
    }
}

/// A hash of a position's canonical coordinate bits: equal positions hash equal.
fn position_hash(p: &[f64; 3]) -> u64 {
    let [a, b, c] = p.map(canonical_bits);
    // Odd multipliers and rotations spread every bit of each coordinate (grid coordinates
    // differ only in high bits), then a final avalanche (splitmix64's).
    let mut h = a.wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ b.rotate_left(21).wrapping_mul(0xc2b2_ae3d_27d4_eb4f)
        ^ c.rotate_left(43).wrapping_mul(0x1656_67b1_9e37_79f9);
    h ^= h >> 30;
    h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h ^= h >> 27;
    h
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

    /// Against a first-occurrence pass with a hash map, on positions drawn from a small pool
    /// (long runs of equal positions, both zeros).
    #[test]
    fn agrees_with_a_first_occurrence_pass() {
        let pool = [0.0, -0.0, 1.0, 0.5, -2.0, 1e-300, 3.0e10];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            pool[(state % pool.len() as u64) as usize]
        };
        let positions: Vec<[f64; 3]> = (0..5000).map(|_| [next(), next(), next()]).collect();
        let mut id_of = std::collections::HashMap::new();
        let mut representatives = Vec::new();
        let remap: Vec<u32> = (positions.iter().enumerate())
            .map(|(v, p)| {
                *id_of.entry(p.map(canonical_bits)).or_insert_with(|| {
                    representatives.push(v as u32);
                    representatives.len() as u32 - 1
                })
            })
            .collect();
        let welding = weld_positions(&positions);
        assert!(welding.duplicate_count() > 4000);
        assert_eq!(welding.remap, remap);
        assert_eq!(welding.representatives, representatives);
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
