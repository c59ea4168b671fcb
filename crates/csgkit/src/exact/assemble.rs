//! The **assemble** stage (`design/exact.md`, stage 8): the output mesh.
//!
//! Vertices the kept sub-triangles use keep their relative order (input vertices first); an intersection
//! point is rounded to the nearest f64 here, once (exact big-integer division), and every
//! coordinate is scaled back by the inverse of the ingest power of two (exact). Each face
//! records its provenance: the operand and the original face it lies on.
//!
//! Rounding moves intersection points by up to half an ulp, which in near-degenerate
//! configurations makes two output faces cross or a face collapse; the [`certify`] stage
//! finds and repairs those, starting from the vertices this stage marks as moved.
//!
//! [`certify`]: super::certify

use crate::par::*;

use crate::kernel::round_point;
use crate::mesh::{Mesh, MeshParts};

use super::ingest::Input;
use super::reconstruct::Reconstructed;
use super::subdivide::Arrangement;

/// The output mesh in f64, and which of its vertices need checking.
pub(crate) struct Rounded {
    pub mesh: Mesh,
    /// Per vertex: an intersection point rounded to f64 (the only vertices where the f64 mesh
    /// may differ from the exact result; the triangles reconstruct made tile the exact result
    /// too).
    pub moved: Vec<bool>,
    /// How many vertices are intersection points rounded to f64.
    pub rounded: usize,
}

/// The mesh of the reconstructed triangles, with its rounded vertices marked.
pub(crate) fn assemble(input: &Input, arr: &Arrangement, faces: Reconstructed) -> Rounded {
    // Used vertices keep their relative order (input vertices, then intersection points), so
    // the numbering is deterministic and every step but the marking runs in parallel.
    let mut new_id = vec![u32::MAX; arr.vertex_count(input)];
    for t in &faces.triangles {
        for &v in t {
            new_id[v as usize] = 0;
        }
    }
    let mut used = Vec::new();
    for (v, id) in new_id.iter_mut().enumerate() {
        if *id == 0 {
            *id = used.len() as u32;
            used.push(v as u32);
        }
    }
    let explicit_count = input.positions.len() as u32;
    let unscale = 1.0 / input.scale;
    let positions: Vec<[f64; 3]> = (used.par_iter())
        .map(|&v| round_point(&arr.point(input, v)).map(|x| x * unscale))
        .collect();
    // An intersection point the split stage simplified to an explicit one is exact.
    let moved: Vec<bool> = (used.par_iter())
        .map(|&v| v >= explicit_count && !arr.point(input, v).is_explicit())
        .collect();
    let rounded = moved.iter().filter(|&&m| m).count();
    let corners: Vec<u32> = (faces.triangles.par_iter())
        .flat_map_iter(|t| t.map(|v| new_id[v as usize]))
        .collect();
    let mesh = Mesh::from_parts(MeshParts {
        positions,
        corners,
        face_provenance: Some(faces.provenance),
        ..MeshParts::default()
    })
    .expect("reconstructed triangles index their own vertices");
    Rounded {
        mesh,
        moved,
        rounded,
    }
}
