//! Face attributes (material, group, colour), the name tables they index, and corner
//! attributes (UV, normal): shared by the readers, which build them, and by the engines, whose
//! results inherit them from the faces they were cut from.

use super::vector::{dot, triangle_normal};
use rustc_hash::FxHashMap;

use super::{FaceId, InvalidMesh, Mesh, MeshParts, Rgba, triangulate_faces_partial};

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

/// `mesh` (any faces) with the attributes of the source face each of its faces came from, by
/// its provenance (operand `k` is `sources[k]`, its face the source face's index).
///
/// Face attributes (material, group, colour) are copied. Corner UVs and normals are
/// interpolated at each corner's position in the source face, barycentrically in the
/// triangle of the source face's triangulation that contains it (so an attribute that is
/// affine on a source triangle comes out exact up to f64 rounding, and normals up to their f32 storage); a face whose
/// orientation is reversed from its source's gets its normals negated. Each corner gets its
/// own values, so UV seams stay split. Vertex colours are interpolated the same way, each
/// vertex in the first face that uses it.
///
/// Name tables are merged by name across the sources, so "green" in one operand and "green"
/// in another are one material; a source without materials (or groups) gives its faces
/// `"default"`, one without colours gives white, while any source has them. Material
/// libraries are kept, each once. A mesh without provenance, or a provenance naming a face no
/// source has, comes back unchanged.
pub fn inherit_attributes(mesh: Mesh, sources: &[&Mesh]) -> Mesh {
    let has_any = sources.iter().any(|s| {
        let p = s.parts();
        p.face_materials.is_some()
            || p.face_groups.is_some()
            || p.face_colors.is_some()
            || p.corner_uvs.is_some()
            || p.corner_normals.is_some()
            || p.vertex_colors.is_some()
            || !p.material_libraries.is_empty()
    });
    if !has_any {
        return mesh;
    }
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
    let corner_and_vertex = interpolated(&mesh, &source_faces, sources);
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
        corner_uvs: corner_and_vertex.uvs,
        corner_normals: corner_and_vertex.normals,
        vertex_colors: corner_and_vertex.vertex_colors,
        material_libraries,
        ..mesh.into_parts()
    };
    Mesh::from_parts(parts).expect("one attribute per face, every id in its merged table")
}

/// The corner and vertex attributes of a result, each present or not.
struct Interpolated {
    uvs: Option<Vec<[f64; 2]>>,
    normals: Option<Vec<[f32; 3]>>,
    vertex_colors: Option<Vec<Rgba>>,
}

/// Per corner of `mesh` its UV and normal, and per vertex its colour,
/// interpolated in its source face; `None` for an attribute no source has (elements from
/// sources without it get zeros, or white). A vertex takes its colour from the first face
/// that uses it.
fn interpolated(mesh: &Mesh, source_faces: &[(usize, usize)], sources: &[&Mesh]) -> Interpolated {
    let has_uvs = sources.iter().any(|s| s.corner_uvs().is_some());
    let has_normals = sources.iter().any(|s| s.corner_normals().is_some());
    let has_colors = sources.iter().any(|s| s.vertex_colors().is_some());
    let mut out = Interpolated {
        uvs: has_uvs.then(|| Vec::with_capacity(mesh.corner_count())),
        normals: has_normals.then(|| Vec::with_capacity(mesh.corner_count())),
        vertex_colors: has_colors.then(|| vec![WHITE; mesh.vertex_count()]),
    };
    if !has_uvs && !has_normals && !has_colors {
        return out;
    }
    let pieces: Vec<Vec<Vec<[usize; 3]>>> = sources.iter().map(|s| source_triangles(s)).collect();
    let mut coloured = vec![false; mesh.vertex_count()];
    for (f, &(k, source_face)) in source_faces.iter().enumerate() {
        let corners = mesh.face(FaceId::new(f));
        let source = sources[k];
        let triangles = pieces[k].get(source_face).map_or(&[][..], Vec::as_slice);
        let at = |c: usize| source.positions()[source.corners()[c] as usize];
        let source_normal = (triangles.iter())
            .map(|t| triangle_normal(t.map(at)))
            .fold([0.0; 3], |n, m| [n[0] + m[0], n[1] + m[1], n[2] + m[2]]);
        // The polygon's own normal: the sum over a fan, right for non-convex faces too.
        let own = (1..corners.len() - 1)
            .map(|i| {
                triangle_normal(
                    [corners[0], corners[i], corners[i + 1]].map(|v| mesh.positions()[v as usize]),
                )
            })
            .fold([0.0; 3], |n, m| [n[0] + m[0], n[1] + m[1], n[2] + m[2]]);
        let sign = if dot(own, source_normal) < 0.0 {
            -1.0
        } else {
            1.0
        };
        for &v in corners {
            let p = mesh.positions()[v as usize];
            // The source triangle the corner is most inside of, and its weights there.
            let weights = (triangles.iter())
                .filter_map(|&t| barycentric(p, t.map(at), source_normal).map(|w| (t, w)))
                .max_by(|a, b| min3(a.1).total_cmp(&min3(b.1)));
            if let Some(uvs) = out.uvs.as_mut() {
                let uv = (source.corner_uvs()).map_or([0.0; 2], |s| blend(weights, |c| s[c]));
                uvs.push(uv);
            }
            if let Some(normals) = out.normals.as_mut() {
                let n = (source.corner_normals())
                    .map_or([0.0; 3], |s| blend(weights, |c| s[c].map(f64::from)));
                // At a source corner the normal is that corner's, as the file gave it; a
                // blend of several is made unit length again.
                let at_corner = weights.is_some_and(|(_, w)| w.contains(&1.0));
                let length = dot(n, n).sqrt();
                let scale = match (at_corner, length > 0.0) {
                    (true, _) => sign,
                    (false, true) => sign / length,
                    (false, false) => 0.0,
                };
                normals.push(n.map(|x| (x * scale) as f32));
            }
            if let (Some(colors), Some(source_colors)) =
                (out.vertex_colors.as_mut(), source.vertex_colors())
            {
                if !coloured[v as usize] {
                    coloured[v as usize] = true;
                    let vertex_of = |c: usize| source.corners()[c] as usize;
                    let rgba = blend(weights, |c| source_colors[vertex_of(c)].map(f64::from));
                    colors[v as usize] = rgba.map(|x| x.round().clamp(0.0, 255.0) as u8);
                }
            }
        }
    }
    out
}

/// The value at barycentric `weights` in a source triangle (corner indices) of the values
/// `value` gives its corners; zeros without a triangle.
fn blend<const N: usize>(
    weights: Option<([usize; 3], [f64; 3])>,
    value: impl Fn(usize) -> [f64; N],
) -> [f64; N] {
    let mut out = [0.0; N];
    if let Some((corners, w)) = weights {
        for (c, wi) in corners.into_iter().zip(w) {
            for (o, x) in out.iter_mut().zip(value(c)) {
                *o += wi * x;
            }
        }
    }
    out
}

/// Each face's triangles as corner indices of `source` (none when it has no corner
/// attributes, so nothing is interpolated from it).
fn source_triangles(source: &Mesh) -> Vec<Vec<[usize; 3]>> {
    if source.corner_uvs().is_none()
        && source.corner_normals().is_none()
        && source.vertex_colors().is_none()
    {
        return Vec::new();
    }
    let mut of_face = vec![Vec::new(); source.face_count()];
    for (face, triangle) in triangulate_faces_partial(source).0.iter() {
        let range = source.face_range(face);
        let corner = |v: u32| {
            (range.clone())
                .find(|&c| source.corners()[c] == v)
                .expect("a triangle of a face uses its corners")
        };
        of_face[face.index()].push(triangle.map(corner));
    }
    of_face
}

/// The barycentric weights of `p` in the triangle `t`, in its projection along the largest
/// component of `normal`; `None` when that projection is degenerate.
fn barycentric(p: [f64; 3], t: [[f64; 3]; 3], normal: [f64; 3]) -> Option<[f64; 3]> {
    let drop = (0..3)
        .max_by(|&i, &j| normal[i].abs().total_cmp(&normal[j].abs()))
        .unwrap_or(2);
    let (u, v) = ((drop + 1) % 3, (drop + 2) % 3);
    let twice_area = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        (b[u] - a[u]) * (c[v] - a[v]) - (b[v] - a[v]) * (c[u] - a[u])
    };
    let total = twice_area(t[0], t[1], t[2]);
    if total == 0.0 || !total.is_finite() {
        return None;
    }
    Some([
        twice_area(p, t[1], t[2]) / total,
        twice_area(t[0], p, t[2]) / total,
        twice_area(t[0], t[1], p) / total,
    ])
}

fn min3(w: [f64; 3]) -> f64 {
    w[0].min(w[1]).min(w[2])
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

/// The meshes as one: vertices and faces one mesh after the other, as the readers of files
/// that hold several parts (3MF build items, glTF nodes) merge them.
///
/// Each attribute is present when any mesh has it; faces of meshes without it get the
/// material or group `"default"`, white, UV `[0, 0]` or normal `[0, 0, 0]`, as the readers
/// fill attributes a file gives only some elements. Name tables are merged by name, material
/// libraries kept once each; provenance is dropped, since it names faces of the parts.
///
/// # Errors
/// [`InvalidMesh`] when the result passes the `u32` limits on vertices or corners.
pub fn concatenate(meshes: &[Mesh]) -> Result<Mesh, InvalidMesh> {
    let any = |has: fn(&MeshParts) -> bool| meshes.iter().any(|m| has(m.parts()));
    fn start<T>(has: bool) -> Option<Vec<T>> {
        has.then(Vec::new)
    }
    let mut out = MeshParts {
        face_starts: (!meshes.iter().all(Mesh::is_triangle_mesh)).then(|| vec![0]),
        face_materials: start(any(|p| p.face_materials.is_some())),
        face_groups: start(any(|p| p.face_groups.is_some())),
        face_colors: start(any(|p| p.face_colors.is_some())),
        corner_uvs: start(any(|p| p.corner_uvs.is_some())),
        corner_normals: start(any(|p| p.corner_normals.is_some())),
        vertex_colors: start(any(|p| p.vertex_colors.is_some())),
        ..MeshParts::default()
    };
    let (mut materials, mut groups) = (Names::default(), Names::default());
    for mesh in meshes {
        let p = mesh.parts();
        let offset = u32::try_from(out.positions.len()).map_err(|_| InvalidMesh::TooLarge {
            what: "vertices",
            count: out.positions.len(),
        })?;
        out.positions.extend_from_slice(&p.positions);
        out.corners
            .extend(p.corners.iter().map(|&v| v.wrapping_add(offset)));
        if let Some(starts) = out.face_starts.as_mut() {
            for face in mesh.faces() {
                let last = starts[starts.len() - 1];
                starts.push(last.wrapping_add(face.len() as u32));
            }
        }
        let faces = mesh.face_count();
        let named = |ids: Option<&[u32]>, names: &[String], table: &mut Names| match ids {
            Some(ids) => ids
                .iter()
                .map(|&id| table.id(&names[id as usize]))
                .collect(),
            None => vec![table.id(DEFAULT_NAME); faces],
        };
        if let Some(ids) = out.face_materials.as_mut() {
            ids.extend(named(
                p.face_materials.as_deref(),
                &p.materials,
                &mut materials,
            ));
        }
        if let Some(ids) = out.face_groups.as_mut() {
            ids.extend(named(p.face_groups.as_deref(), &p.groups, &mut groups));
        }
        extend(&mut out.face_colors, p.face_colors.as_deref(), WHITE, faces);
        let corners = mesh.corner_count();
        extend(
            &mut out.corner_uvs,
            p.corner_uvs.as_deref(),
            [0.0; 2],
            corners,
        );
        extend(
            &mut out.corner_normals,
            p.corner_normals.as_deref(),
            [0.0; 3],
            corners,
        );
        let vertices = mesh.vertex_count();
        extend(
            &mut out.vertex_colors,
            p.vertex_colors.as_deref(),
            WHITE,
            vertices,
        );
        for library in &p.material_libraries {
            if !out.material_libraries.contains(library) {
                out.material_libraries.push(library.clone());
            }
        }
    }
    out.materials = materials.into_names();
    out.groups = groups.into_names();
    Mesh::from_parts(out)
}

/// Appends `values`, or `n` copies of `default`, to a buffer that exists.
fn extend<T: Copy>(out: &mut Option<Vec<T>>, values: Option<&[T]>, default: T, n: usize) {
    if let Some(out) = out {
        match values {
            Some(values) => out.extend_from_slice(values),
            None => out.extend(std::iter::repeat_n(default, n)),
        }
    }
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
        let result = inherit_attributes(result, &[&a, &b, &c]);
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
        assert_eq!(inherit_attributes(triangle(), &[&a]), triangle());
    }

    #[test]
    fn concatenation_fills_missing_attributes_and_merges_names() {
        let triangle = |material: Option<&str>, color: Option<Rgba>| {
            Mesh::from_parts(MeshParts {
                positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                corners: vec![0, 1, 2],
                face_materials: material.map(|_| vec![0]),
                materials: material.into_iter().map(str::to_owned).collect(),
                face_colors: color.map(|c| vec![c]),
                ..MeshParts::default()
            })
            .unwrap()
        };
        let red = [255, 0, 0, 255];
        let parts = [
            triangle(Some("stone"), None),
            triangle(None, Some(red)),
            triangle(Some("stone"), None),
        ];
        let mesh = concatenate(&parts).unwrap();
        assert_eq!(mesh.vertex_count(), 9);
        assert_eq!(mesh.corners(), &[0, 1, 2, 3, 4, 5, 6, 7, 8]);
        assert_eq!(mesh.materials(), ["stone", "default"]);
        assert_eq!(mesh.face_materials(), Some(&[0, 1, 0][..]));
        assert_eq!(mesh.face_colors(), Some(&[WHITE, red, WHITE][..]));
        assert!(mesh.face_provenance().is_none());
        assert_eq!(concatenate(&parts[..1]).unwrap(), parts[0]);
    }
}
