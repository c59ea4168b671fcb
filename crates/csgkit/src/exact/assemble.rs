//! The **assemble** stage (`design/exact.md`, stage 8): the output mesh.
//!
//! Vertices the kept sub-triangles use keep their relative order (input vertices first); an intersection
//! point is rounded to the nearest f64 here, once (exact big-integer division), and every
//! coordinate is scaled back by the inverse of the ingest power of two (exact). Each face
//! records its provenance: the operand and the original face it lies on.
//!
//! Rounding moves intersection points by up to half an ulp, which in rare near-degenerate
//! configurations makes two output faces cross. The faces around rounded vertices are checked
//! exactly and the number of crossing pairs is reported ([`BooleanStats`]), never hidden;
//! repairing them (snap rounding) is not done yet.
//!
//! [`BooleanStats`]: super::BooleanStats

use rayon::prelude::*;

use crate::kernel::round_point;
use crate::mesh::{Mesh, MeshParts, OperandId, Provenance};

use super::ingest::Input;
use super::select::Kept;
use super::subdivide::Arrangement;

/// The output mesh, and how many of its face pairs intersect because of rounding.
pub(crate) struct Assembled {
    pub mesh: Mesh,
    pub rounding_folds: usize,
}

/// The mesh of the kept sub-triangles, checked for folds that rounding created.
pub(crate) fn assemble(input: &Input, arr: &Arrangement, kept: &Kept) -> Assembled {
    let (mesh, rounded) = build_mesh(input, arr, kept);
    let rounding_folds = folds_after_rounding(&mesh, &rounded);
    Assembled {
        mesh,
        rounding_folds,
    }
}

/// Counts the face pairs of `mesh` that intersect other than along what they share, among
/// the faces around rounded vertices (`rounded[v]`): the faces with a vertex on a face that
/// has a rounded vertex. The exact arrangement has no such pair, so any found is a fold that
/// rounding made (design/exact.md: reported, never silent). Faces farther away would have
/// to lie within half an ulp of a rounded point without sharing a vertex with its faces.
fn folds_after_rounding(mesh: &Mesh, rounded: &[bool]) -> usize {
    let corners = mesh.corners();
    let face = |f: usize| &corners[3 * f..3 * f + 3];
    let mut ring = vec![false; mesh.vertex_count()];
    for f in 0..mesh.face_count() {
        if face(f).iter().any(|&v| rounded[v as usize]) {
            face(f).iter().for_each(|&v| ring[v as usize] = true);
        }
    }
    let near: Vec<usize> = (0..mesh.face_count())
        .into_par_iter()
        .filter(|&f| face(f).iter().any(|&v| ring[v as usize]))
        .collect();
    if near.is_empty() {
        return 0;
    }
    // A small mesh of those faces, so the check welds and indexes only them.
    let mut local = vec![u32::MAX; mesh.vertex_count()];
    let mut positions = Vec::new();
    let triangles: Vec<[u32; 3]> = (near.iter())
        .map(|&f| {
            [0, 1, 2].map(|i| {
                let v = face(f)[i] as usize;
                if local[v] == u32::MAX {
                    local[v] = positions.len() as u32;
                    positions.push(mesh.positions()[v]);
                }
                local[v]
            })
        })
        .collect();
    let around =
        Mesh::from_triangles(positions, &triangles).expect("the faces index their vertices");
    super::self_intersect::self_intersections(&around)
        .pairs
        .len()
}

/// The mesh of the kept sub-triangles, and which of its vertices are rounded points.
fn build_mesh(input: &Input, arr: &Arrangement, kept: &Kept) -> (Mesh, Vec<bool>) {
    // Used vertices keep their relative order (input vertices, then intersection points), so
    // the numbering is deterministic and every step but the marking runs in parallel.
    let mut new_id = vec![u32::MAX; arr.vertex_count(input)];
    for &(s, _) in kept {
        for v in arr.triangles[s as usize] {
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
    let rounded: Vec<bool> = used.iter().map(|&v| v >= explicit_count).collect();
    let corners: Vec<u32> = (kept.par_iter())
        .flat_map_iter(|&(s, reverse)| {
            let [a, b, c] = arr.triangles[s as usize].map(|v| new_id[v as usize]);
            if reverse { [a, c, b] } else { [a, b, c] }
        })
        .collect();
    let provenance: Vec<Provenance> = (kept.par_iter())
        .map(|&(s, _)| {
            let t = arr.source[s as usize] as usize;
            Provenance {
                operand: OperandId::new(input.operand[t] as usize),
                face: input.face[t],
            }
        })
        .collect();
    let mesh = Mesh::from_parts(MeshParts {
        positions,
        corners,
        face_provenance: Some(provenance),
        ..MeshParts::default()
    })
    .expect("kept sub-triangles index their own vertices");
    (mesh, rounded)
}
