//! STL, ASCII and binary: reader and writer.
//!
//! STL stores each facet with its own three vertices; the reader welds vertices whose f64
//! positions are bit-identical (a hash on the bit patterns, so `0.0` and `-0.0` stay apart)
//! and reports the unwelded count as [`LoadedMesh::raw_vertex_count`]. Binary float32
//! coordinates widen to f64 exactly.
//!
//! A file is binary when its size is exactly `84 + 50 * count` (count from bytes 80..84),
//! whatever its header says: many binary files begin with `solid`. Otherwise a file starting
//! with `solid` is ASCII; if the ASCII parse fails or finds no facet while the size can hold
//! the facets announced at bytes 80..84, the file is read as binary after all.
//! Facet normals and attribute bytes are ignored.
//!
//! Hand-written rather than `stl_io`: it welds in f32 and returns f32 positions, while csgkit
//! keeps the exact f64 values an ASCII file spells out.
//!
//! The writer triangulates polygons with the mesh module's exact triangulator
//! ([`triangulate_faces`]), so non-convex polygons are written as themselves; a polygon that
//! cannot be triangulated (its projection overlaps itself, or it has zero area) is a
//! [`WriteError::InvalidPolygon`].
//! Binary output rounds coordinates to f32; ASCII output prints shortest round-trip f64.
//! Only geometry is written: STL holds no attribute csgkit keeps.

use rustc_hash::FxHashMap;

use super::builder::{FaceAttributes, MeshBuilder};
use super::error::{Location, ParseError, WriteError, malformed};
use super::text::{Lines, Tokens, check_finite, next_f64};
use super::{Encoding, Format, LoadedMesh};
use crate::mesh::{Mesh, MeshParts, Triangulation, triangulate_faces};

/// Bytes before the first facet of a binary file: header and triangle count.
const HEADER: usize = 84;
/// Bytes per binary facet: normal, three vertices, attribute.
const FACET: usize = 50;

/// True when `data` has exactly the size of a binary STL with the count it announces.
pub(crate) fn is_binary(data: &[u8]) -> bool {
    announced_size(data) == Some(data.len())
}

/// The size a binary STL with the triangle count in `data` would have.
fn announced_size(data: &[u8]) -> Option<usize> {
    let count: [u8; 4] = data.get(80..HEADER)?.try_into().ok()?;
    (u32::from_le_bytes(count) as usize)
        .checked_mul(FACET)?
        .checked_add(HEADER)
}

/// True when `text` begins with `solid` in any case: the start of an ASCII STL.
pub(crate) fn starts_with_solid(text: &[u8]) -> bool {
    text.get(..5)
        .is_some_and(|word| word.eq_ignore_ascii_case(b"solid"))
}

/// Reads an STL file held in memory, deciding ASCII or binary as the module docs say.
pub(crate) fn read(data: &[u8]) -> Result<LoadedMesh, ParseError> {
    if data.is_empty() {
        return Err(ParseError::Empty {
            format: Format::Stl,
        });
    }
    if is_binary(data) {
        return read_binary(data);
    }
    let start = &data[data
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(0)..];
    if starts_with_solid(start) {
        let binary_fits =
            announced_size(data).is_some_and(|size| size > HEADER && size <= data.len());
        return match read_ascii(data) {
            Ok(loaded) if !(loaded.mesh.is_empty() && binary_fits) => Ok(loaded),
            Err(error) if !binary_fits => Err(error),
            _ => read_binary(data),
        };
    }
    read_binary(data)
}

/// Welds bit-identical positions: the index of `p`, adding it if new.
fn weld(map: &mut FxHashMap<[u64; 3], u32>, positions: &mut Vec<[f64; 3]>, p: [f64; 3]) -> u32 {
    let next = positions.len() as u32;
    *map.entry(p.map(f64::to_bits)).or_insert_with(|| {
        positions.push(p);
        next
    })
}

fn read_binary(data: &[u8]) -> Result<LoadedMesh, ParseError> {
    let Some(expected) = announced_size(data) else {
        return Err(ParseError::Truncated {
            what: "binary STL header",
            expected: HEADER,
            actual: data.len(),
        });
    };
    if expected > data.len() {
        return Err(ParseError::Truncated {
            what: "binary STL facets",
            expected,
            actual: data.len(),
        });
    }
    let count = (expected - HEADER) / FACET;
    let mut map = FxHashMap::with_capacity_and_hasher(count / 2 + 3, Default::default());
    let mut positions = Vec::with_capacity(count / 2 + 3);
    let mut corners = Vec::with_capacity(3 * count);
    for (t, facet) in data[HEADER..expected].chunks_exact(FACET).enumerate() {
        for k in 0..3 {
            let at = 12 + 12 * k;
            let p = [0, 4, 8].map(|c| {
                let bytes = [
                    facet[at + c],
                    facet[at + c + 1],
                    facet[at + c + 2],
                    facet[at + c + 3],
                ];
                f64::from(f32::from_le_bytes(bytes))
            });
            check_finite(p, 3 * t + k, Location::Byte(HEADER + FACET * t + at))?;
            corners.push(weld(&mut map, &mut positions, p));
        }
    }
    let mesh = Mesh::from_parts(MeshParts {
        positions,
        corners,
        ..MeshParts::default()
    })?;
    Ok(LoadedMesh {
        mesh,
        format: Format::Stl,
        encoding: Encoding::Binary,
        raw_vertex_count: 3 * count,
    })
}

fn read_ascii(data: &[u8]) -> Result<LoadedMesh, ParseError> {
    // An ASCII facet takes about 250 bytes and adds about half a vertex.
    let mut builder = MeshBuilder::with_capacity(data.len() / 500, data.len() / 250);
    let mut map = FxHashMap::default();
    let mut positions = Vec::new();
    let mut raw = 0;
    for (number, line) in Lines::new(data) {
        let at = Location::Line(number);
        let mut tokens = Tokens::new(line);
        let mut lower = [0u8; 8];
        match tokens.next().map(|keyword| lowercase(keyword, &mut lower)) {
            None | Some(b"solid" | b"endsolid" | b"facet" | b"outer" | b"endfacet") => {}
            Some(b"vertex") => {
                let missing = || malformed(Format::Stl, at, "vertex needs 3 coordinates");
                let p = [
                    next_f64(&mut tokens, at, missing)?,
                    next_f64(&mut tokens, at, missing)?,
                    next_f64(&mut tokens, at, missing)?,
                ];
                check_finite(p, raw, at)?;
                raw += 1;
                builder.push_corner(weld(&mut map, &mut positions, p), None, None);
            }
            Some(b"endloop") => {
                let corners = builder.open_corners();
                if corners < 3 {
                    let face = builder.face_count();
                    return Err(ParseError::TooFewCorners { face, corners, at });
                }
                builder.end_face(FaceAttributes::default())?;
            }
            Some(other) => {
                let word = String::from_utf8_lossy(&other[..other.len().min(20)]).into_owned();
                return Err(malformed(
                    Format::Stl,
                    at,
                    format!("unexpected keyword {word:?}"),
                ));
            }
        }
    }
    if builder.open_corners() > 0 {
        let at = Location::Line(Lines::new(data).count());
        return Err(malformed(Format::Stl, at, "the last facet has no endloop"));
    }
    for p in positions {
        builder.push_vertex(p, None);
    }
    Ok(LoadedMesh {
        mesh: builder.finish()?,
        format: Format::Stl,
        encoding: Encoding::Ascii,
        raw_vertex_count: raw,
    })
}

/// `keyword` in lower case (keywords are at most 8 bytes long; longer tokens are returned as
/// they are), since some exporters write `FACET NORMAL`.
fn lowercase<'a>(keyword: &'a [u8], buffer: &'a mut [u8; 8]) -> &'a [u8] {
    match buffer.get_mut(..keyword.len()) {
        Some(lower) => {
            lower.copy_from_slice(keyword);
            lower.make_ascii_lowercase();
            lower
        }
        None => keyword,
    }
}

/// The unit normal of a triangle (zero for a degenerate triangle).
fn normal([a, b, c]: [[f64; 3]; 3]) -> [f64; 3] {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        n.map(|c| c / len)
    } else {
        [0.0; 3]
    }
}

/// Appends `mesh` as STL to `out`, triangulating polygons.
pub(crate) fn write(mesh: &Mesh, encoding: Encoding, out: &mut Vec<u8>) -> Result<(), WriteError> {
    let triangles = triangulate_faces(mesh).map_err(|error| WriteError::InvalidPolygon {
        format: Format::Stl,
        error,
    })?;
    match encoding {
        Encoding::Binary => write_binary(mesh, &triangles, out),
        Encoding::Ascii => {
            write_ascii(mesh, &triangles, out);
            Ok(())
        }
    }
}

fn write_binary(
    mesh: &Mesh,
    triangles: &Triangulation<'_>,
    out: &mut Vec<u8>,
) -> Result<(), WriteError> {
    let count = triangles.len();
    let count = u32::try_from(count).map_err(|_| WriteError::TooLarge {
        format: Format::Stl,
        reason: "binary STL holds at most u32::MAX triangles",
    })?;
    let mut header = [b' '; 80];
    let title = b"binary STL written by csgkit";
    header[..title.len()].copy_from_slice(title);
    out.extend_from_slice(&header);
    out.extend_from_slice(&count.to_le_bytes());
    out.reserve(FACET * count as usize);
    for (_, t) in triangles.iter() {
        let points = t.map(|v| mesh.positions()[v as usize]);
        let mut facet = [0u8; FACET];
        for (k, p) in std::iter::once(normal(points)).chain(points).enumerate() {
            for (c, value) in p.into_iter().enumerate() {
                let at = 12 * k + 4 * c;
                facet[at..at + 4].copy_from_slice(&(value as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&facet);
    }
    Ok(())
}

fn write_ascii(mesh: &Mesh, triangles: &Triangulation<'_>, out: &mut Vec<u8>) {
    let mut f = ryu::Buffer::new();
    let mut xyz = |out: &mut Vec<u8>, p: [f64; 3]| {
        for c in p {
            out.push(b' ');
            out.extend_from_slice(f.format(c).as_bytes());
        }
        out.push(b'\n');
    };
    out.extend_from_slice(b"solid csgkit\n");
    for (_, t) in triangles.iter() {
        out.extend_from_slice(b"facet normal");
        xyz(out, normal(t.map(|v| mesh.positions()[v as usize])));
        out.extend_from_slice(b"outer loop\n");
        for v in t {
            out.extend_from_slice(b"vertex");
            xyz(out, mesh.positions()[v as usize]);
        }
        out.extend_from_slice(b"endloop\nendfacet\n");
    }
    out.extend_from_slice(b"endsolid csgkit\n");
}

#[cfg(test)]
mod tests;
