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
//! file already grouped keeps its face order). It writes one `vt`/`vn` per distinct value
//! (bit-identical values share a line; a seam keeps its two values), vertex
//! colours as `r g b` floats (alpha is dropped), `g` lines where the group changes, and no
//! face colours or provenance, which OBJ cannot hold. Name tables are rebuilt in order of first
//! use on reading, so their order may change in a round trip.

use super::builder::{FaceAttributes, MeshBuilder};
use super::error::{Location, ParseError, malformed};
use super::text::{
    Lines, Tokens, append_blocks, channel, check_finite, next_f64, parse_f32, parse_f64, parse_i64,
};
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
    uvs: Vec<[f64; 2]>,
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
                let token = (tokens.next())
                    .ok_or_else(|| malformed(Format::Obj, at, "vt needs a coordinate"))?;
                let u = parse_f64(token, at)?;
                let v = tokens.next().map_or(Ok(0.0), |t| parse_f64(t, at))?;
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
            let value = parse_f64(token, at)?;
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
            let uv = lookup(parts.next(), &self.uvs, "texture coordinate", face, at)?;
            let normal = lookup(parts.next(), &self.normals, "normal", face, at)?;
            self.builder.push_corner(vertex, uv, normal);
        }
        let corners = self.builder.open_corners();
        if corners < 3 {
            return Err(ParseError::TooFewCorners { face, corners, at });
        }
        self.builder.end_face(FaceAttributes {
            material: self.material.as_deref(),
            group: self.group.as_deref(),
            ..FaceAttributes::default()
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

/// The value an optional `vt` or `vn` index of a corner refers to.
fn lookup<T: Copy>(
    token: Option<&[u8]>,
    values: &[T],
    what: &'static str,
    face: usize,
    at: Location,
) -> Result<Option<T>, ParseError> {
    match token.filter(|t| !t.is_empty()) {
        Some(t) => Ok(Some(
            values[resolve(t, values.len(), what, face, at)? as usize],
        )),
        None => Ok(None),
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
    out.extend_from_slice(b"# written by csgkit\n");
    for library in mesh.material_libraries() {
        line(out, &[b"mtllib ", &statement_name(library)]);
    }
    let colors = mesh.vertex_colors();
    append_blocks(out, mesh.vertex_count(), |vertices, out| {
        let mut f = ryu::Buffer::new();
        for v in vertices {
            out.push(b'v');
            for c in mesh.positions()[v] {
                out.push(b' ');
                out.extend_from_slice(f.format(c).as_bytes());
            }
            if let Some(colors) = colors {
                for &c in &colors[v][..3] {
                    out.push(b' ');
                    out.extend_from_slice(f.format(f64::from(c) / 255.0).as_bytes());
                }
            }
            out.push(b'\n');
        }
    });
    let uv_of = write_distinct(out, b"vt", mesh.corner_uvs().unwrap_or_default(), |uv| {
        uv.map(f64::to_bits)
    });
    let normal_of = write_distinct(out, b"vn", mesh.corner_normals().unwrap_or_default(), |n| {
        n.map(f32::to_bits)
    });
    write_faces(mesh, &uv_of, &normal_of, out);
}

/// Writes each distinct corner attribute value once, as a `keyword` line, and returns every
/// corner's index among those lines: bit-identical values share one `vt` or `vn` line, so
/// only seams (different values at one vertex) repeat a vertex's attribute.
fn write_distinct<T: ryu::Float, const N: usize, K: std::hash::Hash + Eq>(
    out: &mut Vec<u8>,
    keyword: &[u8],
    values: &[[T; N]],
    key: impl Fn(&[T; N]) -> K,
) -> Vec<u32> {
    let mut f = ryu::Buffer::new();
    let mut index: rustc_hash::FxHashMap<K, u32> = rustc_hash::FxHashMap::default();
    (values.iter())
        .map(|value| {
            let next = index.len() as u32;
            *index.entry(key(value)).or_insert_with(|| {
                write_floats(out, keyword, value, &mut f);
                next
            })
        })
        .collect()
}

/// Writes one line made of `pieces`.
fn line(out: &mut Vec<u8>, pieces: &[&[u8]]) {
    for piece in pieces {
        out.extend_from_slice(piece);
    }
    out.push(b'\n');
}

fn write_floats<T: ryu::Float>(
    out: &mut Vec<u8>,
    keyword: &[u8],
    values: &[T],
    f: &mut ryu::Buffer,
) {
    out.extend_from_slice(keyword);
    for &value in values {
        out.push(b' ');
        out.extend_from_slice(f.format(value).as_bytes());
    }
    out.push(b'\n');
}

/// `name` as the rest of a statement that reads back as one name: a line break, a control
/// character or `#` (a comment) inside it becomes `_`, and a trailing `\` (which would join
/// the next line) gets a `_` after it. Names from OBJ files come back as they were.
fn statement_name(name: &str) -> Vec<u8> {
    let mut bytes: Vec<u8> = (name.trim().bytes())
        .map(|b| {
            if b == b'#' || (b.is_ascii_control() && b != b'\t') {
                b'_'
            } else {
                b
            }
        })
        .collect();
    if bytes.ends_with(b"\\") {
        bytes.push(b'_');
    }
    bytes
}

/// Writes the `f` lines, grouped by material, with `usemtl` and `g` where the name changes.
/// `uv_of` and `normal_of` give each corner's `vt` and `vn` index (empty without them).
fn write_faces(mesh: &Mesh, uv_of: &[u32], normal_of: &[u32], out: &mut Vec<u8>) {
    let mut order: Vec<usize> = (0..mesh.face_count()).collect();
    if let Some(materials) = mesh.face_materials() {
        order.sort_by_key(|&f| materials[f]);
    }
    let (has_uv, has_normal) = (mesh.corner_uvs().is_some(), mesh.corner_normals().is_some());
    append_blocks(out, order.len(), |lines, out| {
        let mut int = itoa::Buffer::new();
        // The material and group that the lines before this block left set.
        let before = lines.start.checked_sub(1).map(|line| order[line]);
        let mut material = before.and_then(|f| mesh.face_materials().map(|m| m[f]));
        let mut group = before.and_then(|f| mesh.face_groups().map(|g| g[f]));
        for &f in &order[lines] {
            if let Some(id) = mesh
                .face_materials()
                .map(|m| m[f])
                .filter(|&id| material != Some(id))
            {
                material = Some(id);
                line(
                    out,
                    &[b"usemtl ", &statement_name(&mesh.materials()[id as usize])],
                );
            }
            if let Some(id) = mesh
                .face_groups()
                .map(|g| g[f])
                .filter(|&id| group != Some(id))
            {
                group = Some(id);
                line(out, &[b"g ", &statement_name(&mesh.groups()[id as usize])]);
            }
            out.push(b'f');
            let range = mesh.face_range(FaceId::new(f));
            for (corner, &v) in range.clone().zip(&mesh.corners()[range]) {
                out.push(b' ');
                out.extend_from_slice(int.format(v + 1).as_bytes());
                if has_uv || has_normal {
                    out.push(b'/');
                    if has_uv {
                        out.extend_from_slice(int.format(uv_of[corner] + 1).as_bytes());
                    }
                }
                if has_normal {
                    out.push(b'/');
                    out.extend_from_slice(int.format(normal_of[corner] + 1).as_bytes());
                }
            }
            out.push(b'\n');
        }
    });
}

#[cfg(test)]
mod tests;
