//! The **assemble** stage (`design/exact.md`, stage 8): the output mesh.
//!
//! Vertices the kept sub-triangles use are numbered in order of first use; an intersection
//! point is rounded to the nearest f64 here, once (exact big-integer division), and every
//! coordinate is scaled back by the inverse of the ingest power of two (exact). Each face
//! records its provenance: the operand and the original face it lies on.

use crate::kernel::round_point;
use crate::mesh::{Mesh, MeshParts, OperandId, Provenance};

use super::ingest::Input;
use super::select::Kept;
use super::subdivide::Arrangement;

/// The mesh of the kept sub-triangles.
pub(crate) fn assemble(input: &Input, arr: &Arrangement, kept: &Kept) -> Mesh {
    let mut new_id = vec![u32::MAX; arr.vertex_count(input)];
    let mut positions = Vec::new();
    let mut corners = Vec::with_capacity(3 * kept.len());
    let mut provenance = Vec::with_capacity(kept.len());
    let unscale = 1.0 / input.scale;
    for &(s, reverse) in kept {
        let mut tri = arr.triangles[s as usize];
        if reverse {
            tri.swap(1, 2);
        }
        for v in tri {
            if new_id[v as usize] == u32::MAX {
                new_id[v as usize] = positions.len() as u32;
                positions.push(round_point(&arr.point(input, v)).map(|x| x * unscale));
            }
            corners.push(new_id[v as usize]);
        }
        let t = arr.source[s as usize] as usize;
        provenance.push(Provenance {
            operand: OperandId::new(input.operand[t] as usize),
            face: input.face[t],
        });
    }
    Mesh::from_parts(MeshParts {
        positions,
        corners,
        face_provenance: Some(provenance),
        ..MeshParts::default()
    })
    .expect("kept sub-triangles index their own vertices")
}
