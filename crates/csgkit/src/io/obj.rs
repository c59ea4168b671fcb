//! Wavefront OBJ: reader and writer.
//!
//! The reader takes `v` (with an optional `w`, or an `r g b` vertex colour after `x y z`),
//! `vt`, `vn`, and `f` in every index form (`v`, `v/vt`, `v//vn`, `v/vt/vn`, negative indices
//! counting back from the last element defined). `o` and `g` set the face group, `usemtl` the
//! material, `mtllib` names are kept. Lines continue after a trailing `\`; comments, `s`, `l`,
//! `p` and unknown statements are skipped.
//!
//! Hand-written rather than `tobj`: `tobj` returns one model per `o`/`g`/`usemtl` run, each
//! with its own re-indexed vertices and a single material, so the per-face group and material
//! ids over one shared vertex set that csgkit keeps would have to be rebuilt, and it stores
//! f32 unless its `use_f64` feature is on; a byte-slice scanner is also faster.
//!
//! The writer prints coordinates in shortest round-trip form (`ryu`), so reading back gives
//! bit-identical positions, and groups faces by material under `usemtl` (a stable sort, so a
//! file already grouped keeps its face order).

use super::builder::{FaceAttributes, MeshBuilder};
use super::error::{Location, ParseError, malformed};
use super::text::{Lines, Tokens, channel, check_finite, next_f64, parse_f32, parse_i64};
use super::{Encoding, Format, LoadedMesh};
use crate::mesh::{FaceId, Mesh, Rgba};

/// Reads an OBJ file held in memory.
pub(crate) fn read(data: &[u8]) -> Result<LoadedMesh, ParseError> {
    // About 30 bytes per vertex line and 2 faces per vertex in typical meshes.
    let mut reader = Reader {
        builder: MeshBuilder::with_capacity(data.len() / 90, data.len() / 45),
        uvs: Vec::new(),
        normals: Vec::new(),
        material: None,
        group: None,
    };
    let mut lines = Lines::new(data);
    let mut joined = Vec::new();
    while let Some((number, line)) = lines.next() {
        let at = Location::Line(number);
        if line.ends_with(b"\\") {
            joined.clear();
            join_continued(line, &mut lines, &mut joined);
            reader.statement(&joined, at)?;
        } else {
            reader.statement(line, at)?;
        }
    }
    let raw_vertex_count = reader.builder.vertex_count();
    Ok(LoadedMesh {
        mesh: reader.builder.finish()?,
        format: Format::Obj,
        encoding: Encoding::Ascii,
        raw_vertex_count,
    })
}

/// Joins `first` (ending in `\`) with the lines it continues into `out`.
fn join_continued(first: &[u8], lines: &mut Lines<'_>, out: &mut Vec<u8>) {
    let mut line = first;
    while let Some(head) = line.strip_suffix(b"\\") {
        out.extend_from_slice(head);
        out.push(b' ');
        match lines.next() {
            Some((_, next)) => line = next,
            None => return,
        }
    }
    out.extend_from_slice(line);
}

struct Reader {
    builder: MeshBuilder,
    uvs: Vec<[f32; 2]>,
    normals: Vec<[f32; 3]>,
    material: Option<String>,
    group: Option<String>,
}

impl Reader {
    fn statement(&mut self, line: &[u8], at: Location) -> Result<(), ParseError> {
        let line = match memchr::memchr(b'#', line) {
            Some(hash) => &line[..hash],
            None => line,
        };
        let mut tokens = Tokens::new(line);
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        match keyword {
            b"v" => self.vertex(tokens, at),
            b"vt" => {
                let [u] = floats::<1>(&mut tokens, at, "vt needs a coordinate")?;
                let v = tokens.next().map_or(Ok(0.0), |t| parse_f32(t, at))?;
                self.uvs.push([u, v]);
                Ok(())
            }
            b"vn" => {
                let n = floats::<3>(&mut tokens, at, "vn needs 3 coordinates")?;
                self.normals.push(n);
                Ok(())
            }
            b"f" => self.face(tokens, at),
            b"o" | b"g" => {
                self.group = Some(name(tokens.remainder()));
                Ok(())
            }
            b"usemtl" => {
                self.material = Some(name(tokens.remainder()));
                Ok(())
            }
            b"mtllib" => {
                for library in tokens {
                    self.builder
                        .push_material_library(&String::from_utf8_lossy(library));
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    fn vertex(&mut self, mut tokens: Tokens<'_>, at: Location) -> Result<(), ParseError> {
        let missing = || malformed(Format::Obj, at, "v needs 3 coordinates");
        let p = [
            next_f64(&mut tokens, at, missing)?,
            next_f64(&mut tokens, at, missing)?,
            next_f64(&mut tokens, at, missing)?,
        ];
        let vertex = self.builder.vertex_count();
        check_finite(p, vertex, at)?;
        if vertex == u32::MAX as usize {
            return Err(ParseError::CountTooLarge {
                what: "vertex",
                count: vertex as u64 + 1,
                reason: "meshes are limited to u32::MAX vertices",
            });
        }
        let mut extra = [0.0f64; 3];
        let mut count = 0;
        for token in tokens {
            let value = super::text::parse_f64(token, at)?;
            if count < 3 {
                extra[count] = value;
            }
            count += 1;
        }
        // One extra value is the homogeneous w, which csgkit ignores; three or more are a colour.
        let color: Option<Rgba> = (count >= 3).then(|| {
            let [r, g, b] = extra.map(|c| channel(c, true));
            [r, g, b, 255]
        });
        self.builder.push_vertex(p, color);
        Ok(())
    }

    fn face(&mut self, tokens: Tokens<'_>, at: Location) -> Result<(), ParseError> {
        let face = self.builder.face_count();
        for token in tokens {
            let mut parts = token.split(|&b| b == b'/');
            let v = parts.next().unwrap_or_default();
            let vertex = resolve(v, self.builder.vertex_count(), "vertex", face, at)?;
            let uv = match parts.next().filter(|t| !t.is_empty()) {
                Some(t) => Some(
                    self.uvs[resolve(t, self.uvs.len(), "texture coordinate", face, at)? as usize],
                ),
                None => None,
            };
            let normal = match parts.next().filter(|t| !t.is_empty()) {
                Some(t) => {
                    Some(self.normals[resolve(t, self.normals.len(), "normal", face, at)? as usize])
                }
                None => None,
            };
            self.builder.push_corner(vertex, uv, normal);
        }
        let corners = self.builder.open_corners();
        if corners < 3 {
            return Err(ParseError::TooFewCorners { face, corners, at });
        }
        self.builder.end_face(FaceAttributes {
            material: self.material.as_deref(),
            group: self.group.as_deref(),
            color: None,
        })
    }
}

/// Parses `N` floats from `tokens`; extra tokens (a `w`) are ignored.
fn floats<const N: usize>(
    tokens: &mut Tokens<'_>,
    at: Location,
    missing: &str,
) -> Result<[f32; N], ParseError> {
    let mut out = [0.0f32; N];
    for value in &mut out {
        let token = tokens
            .next()
            .ok_or_else(|| malformed(Format::Obj, at, missing))?;
        *value = parse_f32(token, at)?;
    }
    Ok(out)
}

/// A statement's name argument (`o`, `g`, `usemtl`), `"default"` when absent.
fn name(rest: &[u8]) -> String {
    if rest.is_empty() {
        "default".to_owned()
    } else {
        String::from_utf8_lossy(rest).into_owned()
    }
}

/// Turns a 1-based or negative (relative) OBJ index into a 0-based index below `count`.
fn resolve(
    token: &[u8],
    count: usize,
    what: &'static str,
    face: usize,
    at: Location,
) -> Result<u32, ParseError> {
    let index = parse_i64(token, at)?;
    let resolved = match index {
        i if i > 0 => i - 1,
        i => count as i64 + i,
    };
    if index == 0 || resolved < 0 || resolved >= count as i64 {
        return Err(ParseError::IndexOutOfRange {
            face,
            what,
            index,
            count,
            at,
        });
    }
    // Below `count`, which the builder keeps within u32.
    Ok(resolved as u32)
}

/// Appends `mesh` as OBJ text to `out`.
pub(crate) fn write(mesh: &Mesh, out: &mut Vec<u8>) {
    let mut f = ryu::Buffer::new();
    out.extend_from_slice(b"# written by csgkit\n");
    for library in mesh.material_libraries() {
        line(out, &[b"mtllib ", library.as_bytes()]);
    }
    let colors = mesh.vertex_colors();
    for (v, p) in mesh.positions().iter().enumerate() {
        out.push(b'v');
        for c in p {
            out.push(b' ');
            out.extend_from_slice(f.format(*c).as_bytes());
        }
        if let Some(colors) = colors {
            for &c in &colors[v][..3] {
                out.push(b' ');
                out.extend_from_slice(f.format(f64::from(c) / 255.0).as_bytes());
            }
        }
        out.push(b'\n');
    }
    for uv in mesh.corner_uvs().unwrap_or_default() {
        write_floats(out, b"vt", uv, &mut f);
    }
    for n in mesh.corner_normals().unwrap_or_default() {
        write_floats(out, b"vn", n, &mut f);
    }
    write_faces(mesh, out);
}

/// Writes one line made of `pieces`.
fn line(out: &mut Vec<u8>, pieces: &[&[u8]]) {
    for piece in pieces {
        out.extend_from_slice(piece);
    }
    out.push(b'\n');
}

fn write_floats(out: &mut Vec<u8>, keyword: &[u8], values: &[f32], f: &mut ryu::Buffer) {
    out.extend_from_slice(keyword);
    for &value in values {
        out.push(b' ');
        out.extend_from_slice(f.format(value).as_bytes());
    }
    out.push(b'\n');
}

/// Writes the `f` lines, grouped by material, with `usemtl` and `g` where the name changes.
fn write_faces(mesh: &Mesh, out: &mut Vec<u8>) {
    let mut order: Vec<usize> = (0..mesh.face_count()).collect();
    if let Some(materials) = mesh.face_materials() {
        order.sort_by_key(|&f| materials[f]);
    }
    let (has_uv, has_normal) = (mesh.corner_uvs().is_some(), mesh.corner_normals().is_some());
    let mut int = itoa::Buffer::new();
    let (mut material, mut group) = (None, None);
    for f in order {
        if let Some(id) = mesh
            .face_materials()
            .map(|m| m[f])
            .filter(|&id| material != Some(id))
        {
            material = Some(id);
            line(out, &[b"usemtl ", mesh.materials()[id as usize].as_bytes()]);
        }
        if let Some(id) = mesh
            .face_groups()
            .map(|g| g[f])
            .filter(|&id| group != Some(id))
        {
            group = Some(id);
            line(out, &[b"g ", mesh.groups()[id as usize].as_bytes()]);
        }
        out.push(b'f');
        let range = mesh.face_range(FaceId::new(f));
        for (corner, &v) in range.clone().zip(&mesh.corners()[range]) {
            out.push(b' ');
            out.extend_from_slice(int.format(v + 1).as_bytes());
            if has_uv || has_normal {
                out.push(b'/');
                if has_uv {
                    out.extend_from_slice(int.format(corner + 1).as_bytes());
                }
            }
            if has_normal {
                out.push(b'/');
                out.extend_from_slice(int.format(corner + 1).as_bytes());
            }
        }
        out.push(b'\n');
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::MeshParts;

    fn read_str(text: &str) -> Result<Mesh, ParseError> {
        read(text.as_bytes()).map(|loaded| loaded.mesh)
    }

    #[test]
    fn reads_every_index_form_and_negative_indices() {
        let mesh = read_str(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n\
             f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf -4/-3/-1 -3/-2/-1 -1/-1/-1 \\\n -2/1/1\n",
        )
        .unwrap();
        assert_eq!(mesh.face_count(), 4);
        assert_eq!(mesh.face(FaceId::new(3)), &[0, 1, 3, 2]);
        let uvs = mesh.corner_uvs().unwrap();
        assert_eq!(uvs[0], [0.0, 0.0]);
        assert_eq!(uvs[4], [1.0, 0.0]);
        assert_eq!(mesh.corner_normals().unwrap()[6], [0.0, 0.0, 1.0]);
    }

    #[test]
    fn groups_materials_colours_and_crlf() {
        let mesh = read_str(
            "mtllib a.mtl b.mtl\r\nv 0 0 0 1 0 0\r\nv 1 0 0\r\nv 0 1 0 # c\r\no part\r\n\
             usemtl red\r\nf 1 2 3\r\ns off\r\nl 1 2\r\ng other\r\nusemtl blue\r\nf 3 2 1\r\n",
        )
        .unwrap();
        assert_eq!(mesh.material_libraries(), ["a.mtl", "b.mtl"]);
        assert_eq!(mesh.materials(), ["red", "blue"]);
        assert_eq!(mesh.face_materials(), Some(&[0, 1][..]));
        assert_eq!(mesh.groups(), ["part", "other"]);
        assert_eq!(mesh.vertex_colors().unwrap()[0], [255, 0, 0, 255]);
        assert_eq!(mesh.vertex_colors().unwrap()[1], [255; 4]);
    }

    #[test]
    fn round_trip_keeps_positions_faces_and_attributes() {
        let parts = MeshParts {
            positions: vec![
                [0.1, -1e-300, 3.0e10],
                [1.0 / 3.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [2.0; 3],
            ],
            corners: vec![0, 1, 2, 3, 0, 2, 1],
            face_starts: Some(vec![0, 4, 7]),
            face_materials: Some(vec![0, 1]),
            materials: vec!["a".into(), "b".into()],
            face_groups: Some(vec![0, 1]),
            groups: vec!["g0".into(), "g1".into()],
            corner_uvs: Some((0..7).map(|i| [i as f32 * 0.1, 0.5]).collect()),
            corner_normals: Some(vec![[0.0, 0.0, 1.0]; 7]),
            vertex_colors: Some(vec![[1, 2, 3, 255]; 4]),
            material_libraries: vec!["m.mtl".into()],
            ..MeshParts::default()
        };
        let mesh = Mesh::from_parts(parts).unwrap();
        let mut out = Vec::new();
        write(&mesh, &mut out);
        assert_eq!(read(&out).unwrap().mesh, mesh);
    }

    #[test]
    fn errors_name_the_line_face_and_vertex() {
        assert!(matches!(
            read_str("v 0 0 0\nv 1 nan 0\n"),
            Err(ParseError::NonFinite { vertex: 1, at: Location::Line(2), value }) if value.is_nan()
        ));
        assert!(matches!(
            read_str("v 0 0 0\nv inf 0 0\n"),
            Err(ParseError::NonFinite {
                vertex: 1,
                at: Location::Line(2),
                ..
            })
        ));
        assert_eq!(
            read_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n"),
            Err(ParseError::IndexOutOfRange {
                face: 1,
                what: "vertex",
                index: 4,
                count: 3,
                at: Location::Line(5)
            })
        );
        assert_eq!(
            read_str("v 0 0 0\nv 1 0 0\nf 1 2\n"),
            Err(ParseError::TooFewCorners {
                face: 0,
                corners: 2,
                at: Location::Line(3)
            })
        );
        assert!(matches!(
            read_str("v 0 0 0\nf 0 1 1\n"),
            Err(ParseError::IndexOutOfRange { index: 0, .. })
        ));
        assert!(matches!(
            read_str("v 0 x 0\n"),
            Err(ParseError::MalformedNumber { .. })
        ));
    }

    #[test]
    fn empty_and_face_free_files_are_empty_meshes() {
        assert!(read_str("").unwrap().is_empty());
        assert_eq!(read_str("# nothing\nv 1 2 3\n").unwrap().vertex_count(), 1);
    }
}
