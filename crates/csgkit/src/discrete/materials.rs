//! Materials through the discrete engine, in the face attribute model every engine shares:
//! a face of the result takes the material (name and colour) of the solid behind it.
//!
//! A solid of the discrete engine is a set of voxels with no attribute, so materials travel
//! as parts: one solid per material, pairwise disjoint up to their common faces.
//! - **In** ([`material_parts`]): a mesh whose faces of each material form a closed surface
//!   (one solid per material, as `csgkit boxes --per-material` writes a voxel model, or an
//!   operand of one material) gives one part per material; any other mesh is one part, of
//!   the material of its first face.
//! - **Through** ([`label`]): a voxel of the result belongs to the first part, in operand
//!   order and then material order, that contains it. For a union every voxel keeps the
//!   material of the first operand that has it; for a difference or intersection, the first
//!   operand's.
//! - **Out** ([`labelled_mesh`]): the parts' boxes go to the orthogonal engine with one
//!   material id per distinct name, so faces are maximal per material and interfaces between
//!   materials inside the solid are not faces; names and colours are those of the parts.

use super::discretize::{DiscretizeError, DiscretizeOptions, discretize_counted, triangle_count};
use super::grid::Grid;
use super::ops::OpError;
use super::tile::Solid;
use crate::mesh::attributes::DEFAULT_NAME;
use crate::mesh::{Mesh, Rgba, analyze_topology};
use crate::ortho::{MeshOptions, OrthoError, box_union_with_materials};
use crate::progress::{Counter, Progress, Stage};

/// The voxels of one material.
#[derive(Clone, Debug)]
pub struct MaterialSolid {
    /// The material's name (`"default"` for faces without one).
    pub material: String,
    /// The colour of the material's faces, if the source had face colours.
    pub color: Option<Rgba>,
    /// Its voxels.
    pub solid: Solid,
}

/// The faces of `mesh` by material, as closed meshes, when every material's faces are
/// closed; otherwise `mesh` whole, with the material and colour of its first face.
pub fn material_parts(mesh: &Mesh) -> Vec<(String, Option<Rgba>, Mesh)> {
    let name_of = |f: usize| {
        (mesh.face_materials())
            .map_or(DEFAULT_NAME, |ids| {
                mesh.materials()[ids[f] as usize].as_str()
            })
            .to_owned()
    };
    let color_of = |f: usize| mesh.face_colors().map(|c| c[f]);
    let whole = || vec![(name_of(0), color_of(0), mesh.clone())];
    let Some(ids) = mesh.face_materials() else {
        return whole();
    };
    let mut materials: Vec<u32> = ids.to_vec();
    materials.sort_unstable();
    materials.dedup();
    if materials.len() < 2 {
        return whole();
    }
    let mut parts = Vec::with_capacity(materials.len());
    for m in materials {
        let faces: Vec<usize> = (0..mesh.face_count()).filter(|&f| ids[f] == m).collect();
        let polygons: Vec<&[u32]> = (faces.iter())
            .map(|&f| mesh.face(crate::mesh::FaceId::new(f)))
            .collect();
        let sub = Mesh::from_polygons(mesh.positions().to_vec(), &polygons)
            .expect("faces of the mesh over its own vertices");
        if !analyze_topology(&sub).is_closed() {
            return whole();
        }
        parts.push((name_of(faces[0]), color_of(faces[0]), sub));
    }
    parts
}

/// [`material_parts`] of `mesh`, each discretised at `level` of `grid`.
///
/// # Errors
/// The [`DiscretizeError`] of a part.
pub fn discretize_parts(
    mesh: &Mesh,
    grid: Grid,
    level: u8,
    options: DiscretizeOptions,
) -> Result<Vec<MaterialSolid>, DiscretizeError> {
    let progress = Progress::default();
    let counter = progress.counter(Stage::Discretize, triangle_count(mesh));
    discretize_parts_counted(mesh, grid, level, options, &counter)
}

/// [`discretize_parts`], advancing `counter` by the triangles done.
///
/// # Errors
/// As [`discretize_parts`].
pub(crate) fn discretize_parts_counted(
    mesh: &Mesh,
    grid: Grid,
    level: u8,
    options: DiscretizeOptions,
    counter: &Counter,
) -> Result<Vec<MaterialSolid>, DiscretizeError> {
    (material_parts(mesh).into_iter())
        .map(|(material, color, part)| {
            Ok(MaterialSolid {
                material,
                color,
                solid: discretize_counted(&part, grid, level, options, counter)?,
            })
        })
        .collect()
}

/// The voxels of `result` by material: each voxel in the first part of `operands` (in
/// operand order, then part order) that contains it. Parts that get no voxel are left out.
///
/// # Errors
/// [`OpError`] if the solids are on different grids.
pub fn label(
    result: &Solid,
    operands: &[Vec<MaterialSolid>],
) -> Result<Vec<MaterialSolid>, OpError> {
    let mut left = result.clone();
    let mut out = Vec::new();
    for part in operands.iter().flatten() {
        if left.is_empty() {
            break;
        }
        let mine = left.intersection(&part.solid)?;
        if mine.is_empty() {
            continue;
        }
        left = left.difference(&part.solid)?;
        out.push(MaterialSolid {
            solid: mine,
            ..part.clone()
        });
    }
    Ok(out)
}

/// The boundary of the union of `parts` through the orthogonal engine, each face with the
/// material name (and colour, where parts have one) of the part behind it.
///
/// # Errors
/// The [`OrthoError`] of the orthogonal engine.
pub fn labelled_mesh(parts: &[MaterialSolid]) -> Result<Mesh, OrthoError> {
    let mut names: Vec<&str> = Vec::new();
    let mut colors: Vec<Option<Rgba>> = Vec::new();
    let mut boxes = Vec::new();
    let mut ids = Vec::new();
    for part in parts {
        let id = match names.iter().position(|&n| n == part.material) {
            Some(id) => id,
            None => {
                names.push(&part.material);
                colors.push(part.color);
                names.len() - 1
            }
        };
        let own = part.solid.to_boxes();
        ids.extend(std::iter::repeat_n(id as u32, own.len()));
        boxes.extend(own);
    }
    let brep = box_union_with_materials(&boxes, &ids)?;
    let mut mesh = brep.to_mesh(MeshOptions::default())?.mesh.into_parts();
    // The engine names material m `material_m`; give the ids their parts' names.
    let count = mesh.materials.len();
    mesh.materials = (0..count).map(|m| names[m].to_owned()).collect();
    if colors.iter().any(Option::is_some) {
        mesh.face_colors = (mesh.face_materials.as_ref()).map(|ids| {
            (ids.iter())
                .map(|&m| colors[m as usize].unwrap_or(crate::mesh::attributes::WHITE))
                .collect()
        });
    }
    Ok(Mesh::from_parts(mesh).expect("one name per material id, one colour per face"))
}
