//! Face attributes (material, group, colour) and the name tables they index: shared by the
//! readers, which build them, and by the engines, whose results inherit them from the faces
//! they were cut from.

use rustc_hash::FxHashMap;

use super::{Mesh, MeshParts, Rgba};

/// The colour of elements that have none when others do.
pub(crate) const WHITE: Rgba = [255, 255, 255, 255];

/// The name of the material or group of faces that have none when others do.
pub(crate) const DEFAULT_NAME: &str = "default";

/// A name table with lookup by name.
#[derive(Default)]
pub(crate) struct Names {
    names: Vec<String>,
    ids: FxHashMap<String, u32>,
}

impl Names {
    /// The id of `name`, adding it to the table if it is new.
    pub(crate) fn id(&mut self, name: &str) -> u32 {
        if let Some(&id) = self.ids.get(name) {
            return id;
        }
        let id = u32::try_from(self.names.len()).unwrap_or(u32::MAX);
        self.names.push(name.to_owned());
        self.ids.insert(name.to_owned(), id);
        id
    }

    /// The names, in id order.
    pub(crate) fn into_names(self) -> Vec<String> {
        self.names
    }
}

/// `mesh` with the material, group and colour of the source face each of its faces came
/// from, by its provenance (operand `k` is `sources[k]`, its face the source face's index).
///
/// Name tables are merged by name across the sources, so "green" in one operand and "green"
/// in another are one material; a source without materials (or groups) gives its faces
/// [`DEFAULT_NAME`], one without colours gives [`WHITE`], while any source has them. Material
/// libraries are kept, each once. A mesh without provenance, or a provenance naming a face no
/// source has, comes back unchanged.
pub fn inherit_face_attributes(mesh: Mesh, sources: &[&Mesh]) -> Mesh {
    let Some(provenance) = mesh.parts().face_provenance.as_deref() else {
        return mesh;
    };
    let in_range = provenance
        .iter()
        .all(|p| (sources.get(p.operand.index())).is_some_and(|s| p.face.index() < s.face_count()));
    if !in_range {
        return mesh;
    }
    let source_faces: Vec<(usize, usize)> = (provenance.iter())
        .map(|p| (p.operand.index(), p.face.index()))
        .collect();
    let (face_materials, materials) = merged_names(&source_faces, sources, |parts| {
        (parts.face_materials.as_deref(), parts.materials.as_slice())
    });
    let (face_groups, groups) = merged_names(&source_faces, sources, |parts| {
        (parts.face_groups.as_deref(), parts.groups.as_slice())
    });
    let face_colors = (sources.iter().any(|s| s.parts().face_colors.is_some())).then(|| {
        (source_faces.iter())
            .map(|&(k, f)| {
                sources[k]
                    .parts()
                    .face_colors
                    .as_ref()
                    .map_or(WHITE, |c| c[f])
            })
            .collect()
    });
    let mut material_libraries: Vec<String> = Vec::new();
    for library in sources.iter().flat_map(|s| &s.parts().material_libraries) {
        if !material_libraries.contains(library) {
            material_libraries.push(library.clone());
        }
    }
    let parts = MeshParts {
        face_materials,
        materials,
        face_groups,
        groups,
        face_colors,
        material_libraries,
        ..mesh.into_parts()
    };
    Mesh::from_parts(parts).expect("one attribute per face, every id in its merged table")
}

/// Per face, the id of its source face's name (through `table` of the source's parts) in one
/// table merged by name; `None` when no source has that attribute.
fn merged_names<'a>(
    source_faces: &[(usize, usize)],
    sources: &[&'a Mesh],
    table: impl Fn(&'a MeshParts) -> (Option<&'a [u32]>, &'a [String]),
) -> (Option<Vec<u32>>, Vec<String>) {
    let tables: Vec<_> = sources.iter().map(|s| table(s.parts())).collect();
    if tables.iter().all(|(ids, _)| ids.is_none()) {
        return (None, Vec::new());
    }
    let mut names = Names::default();
    // Each source's ids, renumbered into the merged table in the sources' order.
    let renumbered: Vec<Option<Vec<u32>>> = (tables.iter())
        .map(|(ids, own)| ids.map(|_| own.iter().map(|name| names.id(name)).collect()))
        .collect();
    let ids = (source_faces.iter())
        .map(|&(k, f)| match (tables[k].0, &renumbered[k]) {
            (Some(ids), Some(to)) => to[ids[f] as usize],
            _ => names.id(DEFAULT_NAME),
        })
        .collect();
    (Some(ids), names.into_names())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{FaceId, OperandId, Provenance};

    fn with_materials(mesh: Mesh, ids: Vec<u32>, names: &[&str]) -> Mesh {
        let parts = MeshParts {
            face_materials: Some(ids),
            materials: names.iter().map(|n| n.to_string()).collect(),
            ..mesh.into_parts()
        };
        Mesh::from_parts(parts).expect("one material per face")
    }

    fn triangle() -> Mesh {
        Mesh::from_triangles(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[[0, 1, 2], [0, 2, 1]],
        )
        .expect("in range")
    }

    #[test]
    fn names_merge_across_sources_and_missing_ones_are_default() {
        let a = with_materials(triangle(), vec![0, 1], &["green", "red"]);
        let b = with_materials(triangle(), vec![0, 0], &["green"]);
        let c = triangle();
        let provenance = [(0, 1), (1, 0), (2, 1), (0, 0)]
            .map(|(operand, face)| Provenance {
                operand: OperandId::new(operand),
                face: FaceId::new(face),
            })
            .to_vec();
        let positions = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let result = Mesh::from_parts(MeshParts {
            positions,
            corners: [[0, 1, 2]; 4].concat(),
            face_provenance: Some(provenance),
            ..MeshParts::default()
        })
        .expect("in range");
        let result = inherit_face_attributes(result, &[&a, &b, &c]);
        let names: Vec<&str> = (result.parts().face_materials.as_ref().expect("materials"))
            .iter()
            .map(|&id| result.materials()[id as usize].as_str())
            .collect();
        assert_eq!(names, ["red", "green", "default", "green"]);
        assert_eq!(result.materials(), ["green", "red", "default"]);
        assert!(result.parts().face_groups.is_none());
        assert!(result.parts().face_colors.is_none());
    }

    #[test]
    fn a_mesh_without_provenance_is_unchanged() {
        let a = with_materials(triangle(), vec![0, 1], &["green", "red"]);
        assert_eq!(inherit_face_attributes(triangle(), &[&a]), triangle());
    }
}
