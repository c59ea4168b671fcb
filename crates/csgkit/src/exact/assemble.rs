//! The **assemble** stage (`design/exact.md`, stage 8): the output mesh.
//!
//! Vertices the kept sub-triangles use are numbered in order of first use; an intersection
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

use crate::index::{Aabb, Bvh};
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
/// the faces near a rounded vertex (`rounded[v]`): the exact arrangement has none, so any
/// found is a fold that rounding made (design/exact.md: reported, never silent).
fn folds_after_rounding(mesh: &Mesh, rounded: &[bool]) -> usize {
    let corners = mesh.corners();
    let face_box = |f: usize| {
        Aabb::from_points(
            corners[3 * f..3 * f + 3]
                .iter()
                .map(|&v| &mesh.positions()[v as usize]),
        )
    };
    let moved: Vec<Aabb> = (0..mesh.face_count())
        .filter(|&f| {
            corners[3 * f..3 * f + 3]
                .iter()
                .any(|&v| rounded[v as usize])
        })
        .map(face_box)
        .collect();
    if moved.is_empty() {
        return 0;
    }
    let tree = Bvh::build(&moved);
    let near: Vec<[u32; 3]> = (0..mesh.face_count())
        .into_par_iter()
        .filter(|&f| tree.any_overlapping(&face_box(f), |_| true))
        .map(|f| [corners[3 * f], corners[3 * f + 1], corners[3 * f + 2]])
        .collect();
    let around = Mesh::from_triangles(mesh.positions().to_vec(), &near)
        .expect("the faces index the mesh's vertices");
    super::self_intersect::self_intersections(&around)
        .pairs
        .len()
}

/// The mesh of the kept sub-triangles, and which of its vertices are rounded points.
fn build_mesh(input: &Input, arr: &Arrangement, kept: &Kept) -> (Mesh, Vec<bool>) {
    let mut new_id = vec![u32::MAX; arr.vertex_count(input)];
    let mut positions = Vec::new();
    let mut corners = Vec::with_capacity(3 * kept.len());
    let mut provenance = Vec::with_capacity(kept.len());
    let mut rounded = Vec::new();
    let explicit_count = input.positions.len() as u32;
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
                rounded.push(v >= explicit_count);
            }
            corners.push(new_id[v as usize]);
        }
        let t = arr.source[s as usize] as usize;
        provenance.push(Provenance {
            operand: OperandId::new(input.operand[t] as usize),
            face: input.face[t],
        });
    }
    let mesh = Mesh::from_parts(MeshParts {
        positions,
        corners,
        face_provenance: Some(provenance),
        ..MeshParts::default()
    })
    .expect("kept sub-triangles index their own vertices");
    (mesh, rounded)
}
