//! Stanford PLY, ASCII and binary (little- and big-endian): reader and writer.
//!
//! The reader takes the `vertex` element's `x y z` (any scalar type) and `red green blue
//! alpha` (integers 0–255 or floats 0–1), and the `face` element's `vertex_indices` (or
//! `vertex_index`) list with any count and index types, a `material_index` (or `material_id`,
//! `material`) number and a face colour. Every other element and property, lists included,
//! is skipped. Material numbers become ids into names `material_N`, sorted by `N`.
//! The elements may come in any order (a few writers put `face` first): face indices are
//! checked against the count the header gives the `vertex` element.
//!
//! Every PLY scalar type (at most 32-bit integers, `float`, `double`) is exact in f64, so one
//! value path serves all types. Header counts are checked against the body's size before any
//! allocation.
//!
//! Hand-written rather than `ply-rs`: it stores each element as a hash map of named
//! properties, an allocation per vertex and face, and has no error locations.
//!
//! The writer emits binary little-endian by default (ASCII on request), `double` coordinates,
//! `uchar` colours, a `list uchar int vertex_indices` (`uint` counts past 255 corners) and an
//! `int material_index`. PLY has no material names: a round trip renames them `material_N`.
//! A face's provenance (the source face an engine's output face lies on) is written as `int
//! source_operand` and `int source_face` and read back, so the faces a boolean cut from one
//! source face merge again in the next boolean on the file. Groups, UVs and normals are not
//! written.

mod header;
mod write;

use super::builder::{FaceAttributes, MeshBuilder};
use super::error::{Location, ParseError, malformed};
use super::text::{Lines, Tokens, channel, check_finite, parse_f64};
use super::{Encoding, Format, LoadedMesh};
use crate::mesh::{FaceId, Mesh, OperandId, Provenance};

use header::{Body, Element, Header, Property, Scalar, read_header};
pub(crate) use write::write;

/// Reads a PLY file held in memory.
pub(crate) fn read(data: &[u8]) -> Result<LoadedMesh, ParseError> {
    if data.is_empty() {
        return Err(ParseError::Empty {
            format: Format::Ply,
        });
    }
    let header = read_header(data)?;
    let binary = header.body != Body::Ascii;
    let room = data.len() - header.body_start;
    let mut needed = 0usize;
    for element in &header.elements {
        needed = needed.saturating_add(element.count.saturating_mul(element.min_size(binary)));
        if needed > room {
            let reason = "the rest of the file cannot hold that many";
            return Err(ParseError::CountTooLarge {
                what: "PLY element",
                count: element.count as u64,
                reason,
            });
        }
    }
    let (mesh, raw_vertex_count) = match header.body {
        Body::Ascii => {
            let lines = Lines::new(&data[header.body_start..]);
            let tokens = Tokens::new(b"");
            read_body(
                &header,
                Ascii {
                    lines,
                    tokens,
                    line: header.lines,
                },
            )?
        }
        Body::Little => read_body(
            &header,
            Binary::<false> {
                data,
                pos: header.body_start,
            },
        )?,
        Body::Big => read_body(
            &header,
            Binary::<true> {
                data,
                pos: header.body_start,
            },
        )?,
    };
    let encoding = if binary {
        Encoding::Binary
    } else {
        Encoding::Ascii
    };
    Ok(LoadedMesh {
        mesh,
        format: Format::Ply,
        encoding,
        raw_vertex_count,
    })
}

/// A stream of PLY values, binary or ASCII.
trait Source {
    /// The next value, of type `ty` (exact in f64 for every PLY type).
    fn value(&mut self, ty: Scalar) -> Result<f64, ParseError>;
    /// Where the next value starts.
    fn at(&mut self) -> Location;
    /// Appends the next `n` values of type `ty` to `out` as integers; a value that is not an
    /// integer becomes -1 (an invalid index).
    fn integers(&mut self, ty: Scalar, n: usize, out: &mut Vec<i64>) -> Result<(), ParseError> {
        for _ in 0..n {
            out.push(integer(self.value(ty)?));
        }
        Ok(())
    }
}

/// `value` as an integer, or -1 if it is not one.
fn integer(value: f64) -> i64 {
    let int = value as i64;
    if int as f64 == value { int } else { -1 }
}

/// A `N`-byte word from a slice of exactly `N` bytes, in native order.
#[inline]
fn word<const N: usize, const BIG: bool>(bytes: &[u8]) -> [u8; N] {
    let mut word: [u8; N] = bytes.try_into().unwrap_or([0; N]);
    if BIG {
        word.reverse();
    }
    word
}

struct Binary<'a, const BIG: bool> {
    data: &'a [u8],
    pos: usize,
}

impl<const BIG: bool> Binary<'_, BIG> {
    #[inline]
    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], ParseError> {
        let end = self.pos + N;
        let slice = self.data.get(self.pos..end).ok_or(ParseError::Truncated {
            what: "PLY body",
            expected: end,
            actual: self.data.len(),
        })?;
        let mut bytes: [u8; N] = slice.try_into().unwrap_or([0; N]);
        if BIG {
            bytes.reverse();
        }
        self.pos = end;
        Ok(bytes)
    }
}

impl<const BIG: bool> Source for Binary<'_, BIG> {
    #[inline]
    fn value(&mut self, ty: Scalar) -> Result<f64, ParseError> {
        Ok(match ty {
            Scalar::I8 => f64::from(i8::from_le_bytes(self.bytes()?)),
            Scalar::U8 => f64::from(u8::from_le_bytes(self.bytes()?)),
            Scalar::I16 => f64::from(i16::from_le_bytes(self.bytes()?)),
            Scalar::U16 => f64::from(u16::from_le_bytes(self.bytes()?)),
            Scalar::I32 => f64::from(i32::from_le_bytes(self.bytes()?)),
            Scalar::U32 => f64::from(u32::from_le_bytes(self.bytes()?)),
            Scalar::F32 => f64::from(f32::from_le_bytes(self.bytes()?)),
            Scalar::F64 => f64::from_le_bytes(self.bytes()?),
        })
    }

    fn at(&mut self) -> Location {
        Location::Byte(self.pos)
    }

    /// Decodes integer lists from one bounds-checked slice: the hot loop of face reading.
    fn integers(&mut self, ty: Scalar, n: usize, out: &mut Vec<i64>) -> Result<(), ParseError> {
        let len = n.saturating_mul(ty.size());
        let end = self.pos.saturating_add(len);
        let Some(bytes) = self.data.get(self.pos..end) else {
            let actual = self.data.len();
            return Err(ParseError::Truncated {
                what: "PLY body",
                expected: end,
                actual,
            });
        };
        self.pos = end;
        let chunks = bytes.chunks_exact(ty.size());
        match ty {
            Scalar::I8 => {
                out.extend(chunks.map(|c| i64::from(i8::from_le_bytes(word::<1, BIG>(c)))))
            }
            Scalar::U8 => out.extend(bytes.iter().map(|&b| i64::from(b))),
            Scalar::I16 => {
                out.extend(chunks.map(|c| i64::from(i16::from_le_bytes(word::<2, BIG>(c)))))
            }
            Scalar::U16 => {
                out.extend(chunks.map(|c| i64::from(u16::from_le_bytes(word::<2, BIG>(c)))))
            }
            Scalar::I32 => {
                out.extend(chunks.map(|c| i64::from(i32::from_le_bytes(word::<4, BIG>(c)))))
            }
            Scalar::U32 => {
                out.extend(chunks.map(|c| i64::from(u32::from_le_bytes(word::<4, BIG>(c)))))
            }
            Scalar::F32 => out
                .extend(chunks.map(|c| integer(f64::from(f32::from_le_bytes(word::<4, BIG>(c)))))),
            Scalar::F64 => {
                out.extend(chunks.map(|c| integer(f64::from_le_bytes(word::<8, BIG>(c)))))
            }
        }
        Ok(())
    }
}

struct Ascii<'a> {
    lines: Lines<'a>,
    tokens: Tokens<'a>,
    /// Lines before the body start, plus the body lines read so far.
    line: usize,
}

impl Ascii<'_> {
    /// Moves to the line holding the next token; false at the end of the file.
    fn fill(&mut self) -> bool {
        while self.tokens.clone().next().is_none() {
            match self.lines.next() {
                Some((_, line)) => {
                    self.tokens = Tokens::new(line);
                    self.line += 1;
                }
                None => return false,
            }
        }
        true
    }
}

impl Source for Ascii<'_> {
    fn value(&mut self, _ty: Scalar) -> Result<f64, ParseError> {
        if !self.fill() {
            let at = Location::Line(self.line);
            return Err(malformed(
                Format::Ply,
                at,
                "the file ends inside the element data",
            ));
        }
        let token = self.tokens.next().unwrap_or_default();
        parse_f64(token, Location::Line(self.line))
    }

    fn at(&mut self) -> Location {
        self.fill();
        Location::Line(self.line)
    }
}

/// A list length or index read as f64: a non-negative integer, or `None`.
fn whole(value: f64) -> Option<usize> {
    // The round trip through u32 tests integrality without a call to `trunc`.
    let int = value as u32;
    (f64::from(int) == value).then_some(int as usize)
}

/// Reads and drops one property value.
fn skip<S: Source>(src: &mut S, property: &Property) -> Result<(), ParseError> {
    let Some(count_type) = property.list else {
        return src.value(property.item).map(drop);
    };
    let at = src.at();
    let count = whole(src.value(count_type)?)
        .ok_or_else(|| malformed(Format::Ply, at, "bad list length"))?;
    for _ in 0..count {
        src.value(property.item)?;
    }
    Ok(())
}

/// Reads every element; returns the mesh and the vertex count.
fn read_body<S: Source>(header: &Header, mut src: S) -> Result<(Mesh, usize), ParseError> {
    let count = |name: &str| {
        header
            .elements
            .iter()
            .find(|e| e.name == name)
            .map_or(0, |e| e.count)
    };
    // `read` checked every count against the body's size, so these reservations are bounded.
    let mut builder = MeshBuilder::with_capacity(count("vertex"), count("face"));
    let mut materials = Vec::new();
    let (mut seen_vertex, mut seen_face) = (false, false);
    for element in &header.elements {
        match element.name.as_str() {
            "vertex" if !seen_vertex => {
                seen_vertex = true;
                read_vertices(&mut src, element, &mut builder)?;
            }
            "face" if !seen_face => {
                seen_face = true;
                let vertices = count("vertex");
                read_faces(&mut src, element, vertices, &mut builder, &mut materials)?;
            }
            // An element without properties takes no byte, whatever its count.
            _ if element.properties.is_empty() => {}
            _ => {
                for _ in 0..element.count {
                    for property in &element.properties {
                        skip(&mut src, property)?;
                    }
                }
            }
        }
    }
    if !materials.is_empty() {
        set_materials(&mut builder, &materials);
    }
    let vertices = builder.vertex_count();
    Ok((builder.finish()?, vertices))
}

/// What a property of a vertex or face means to csgkit.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Coordinate(usize),
    Color(usize),
    Indices,
    Material,
    SourceOperand,
    SourceFace,
    Skip,
}

/// The face properties that hold provenance.
const SOURCE_OPERAND: &str = "source_operand";
const SOURCE_FACE: &str = "source_face";

/// PLY's colour property names.
const CHANNELS: [&str; 4] = ["red", "green", "blue", "alpha"];

fn vertex_role(property: &Property) -> Role {
    let coordinate = ["x", "y", "z"].iter().position(|&n| n == property.name);
    let color = CHANNELS.iter().position(|&n| n == property.name);
    match (property.list, coordinate, color) {
        (None, Some(k), _) => Role::Coordinate(k),
        (None, _, Some(k)) => Role::Color(k),
        _ => Role::Skip,
    }
}

fn read_vertices<S: Source>(
    src: &mut S,
    element: &Element,
    builder: &mut MeshBuilder,
) -> Result<(), ParseError> {
    let roles: Vec<Role> = element.properties.iter().map(vertex_role).collect();
    let at = Location::Line(element.line);
    for k in 0..3 {
        if !roles.contains(&Role::Coordinate(k)) {
            return Err(malformed(
                Format::Ply,
                at,
                "the vertex element lacks x, y or z",
            ));
        }
    }
    let has_color = roles.iter().any(|r| matches!(r, Role::Color(_)));
    for v in 0..element.count {
        let at = src.at();
        let (mut p, mut color) = ([0.0; 3], [255u8; 4]);
        for (property, role) in element.properties.iter().zip(&roles) {
            match *role {
                Role::Coordinate(k) => p[k] = src.value(property.item)?,
                Role::Color(k) => {
                    color[k] = channel(src.value(property.item)?, property.item.is_float())
                }
                _ => skip(src, property)?,
            }
        }
        check_finite(p, v, at)?;
        builder.push_vertex(p, has_color.then_some(color));
    }
    Ok(())
}

fn face_role(property: &Property) -> Role {
    let name = property.name.as_str();
    match property.list {
        Some(_) if matches!(name, "vertex_indices" | "vertex_index") => Role::Indices,
        None if matches!(name, "material_index" | "material_id" | "material") => Role::Material,
        None if name == SOURCE_OPERAND => Role::SourceOperand,
        None if name == SOURCE_FACE => Role::SourceFace,
        None => CHANNELS
            .iter()
            .position(|&n| n == name)
            .map_or(Role::Skip, Role::Color),
        Some(_) => Role::Skip,
    }
}

fn read_faces<S: Source>(
    src: &mut S,
    element: &Element,
    vertices: usize,
    builder: &mut MeshBuilder,
    materials: &mut Vec<f64>,
) -> Result<(), ParseError> {
    let roles: Vec<Role> = element.properties.iter().map(face_role).collect();
    if !roles.contains(&Role::Indices) {
        let at = Location::Line(element.line);
        return Err(malformed(
            Format::Ply,
            at,
            "the face element lacks a vertex_indices list",
        ));
    }
    let has_color = roles.iter().any(|r| matches!(r, Role::Color(_)));
    let has_provenance = roles.contains(&Role::SourceOperand) && roles.contains(&Role::SourceFace);
    let mut scratch = Vec::new();
    for face in 0..element.count {
        let mut color = [255u8; 4];
        let mut source = [0u32; 2];
        for (property, role) in element.properties.iter().zip(&roles) {
            match *role {
                Role::Indices => {
                    read_indices(src, property, face, vertices, builder, &mut scratch)?
                }
                Role::Material => materials.push(src.value(property.item)?),
                Role::Color(k) => {
                    color[k] = channel(src.value(property.item)?, property.item.is_float())
                }
                Role::SourceOperand | Role::SourceFace => {
                    let at = src.at();
                    let value = whole(src.value(property.item)?)
                        .and_then(|v| u32::try_from(v).ok())
                        .ok_or_else(|| {
                            malformed(Format::Ply, at, "a source index is not a count")
                        })?;
                    source[usize::from(*role == Role::SourceFace)] = value;
                }
                _ => skip(src, property)?,
            }
        }
        let attributes = FaceAttributes {
            color: has_color.then_some(color),
            provenance: has_provenance.then(|| Provenance {
                operand: OperandId::from(source[0]),
                face: FaceId::from(source[1]),
            }),
            ..FaceAttributes::default()
        };
        builder.end_face(attributes)?;
    }
    Ok(())
}

fn read_indices<S: Source>(
    src: &mut S,
    property: &Property,
    face: usize,
    vertices: usize,
    builder: &mut MeshBuilder,
    scratch: &mut Vec<i64>,
) -> Result<(), ParseError> {
    let at = src.at();
    let count_type = property.list.unwrap_or(Scalar::U8);
    let count = src.value(count_type)?;
    let corners = whole(count).ok_or_else(|| malformed(Format::Ply, at, "bad list length"))?;
    if corners < 3 {
        return Err(ParseError::TooFewCorners { face, corners, at });
    }
    scratch.clear();
    src.integers(property.item, corners, scratch)?;
    let count = vertices;
    if let Some(&index) = scratch.iter().find(|&&i| i < 0 || i >= count as i64) {
        let what = "vertex";
        return Err(ParseError::IndexOutOfRange {
            face,
            what,
            index,
            count,
            at,
        });
    }
    // Every index is below the vertex element's count, which `read` bounded by the file size.
    builder.push_corners(scratch.iter().map(|&i| i as u32));
    Ok(())
}

/// Turns the material numbers of the faces into ids of names `material_N`, sorted by `N`.
fn set_materials(builder: &mut MeshBuilder, numbers: &[f64]) {
    let mut distinct: Vec<f64> = numbers.to_vec();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    let ids = numbers
        .iter()
        .map(|n| distinct.partition_point(|d| d.total_cmp(n).is_lt()) as u32)
        .collect();
    let names = distinct.iter().map(|n| format!("material_{n}")).collect();
    builder.set_materials(ids, names);
}

#[cfg(test)]
mod tests;
