//! OFF (Object File Format): reader and writer.
//!
//! The header keyword is `OFF` with optional prefixes: `C` (vertex colours after the
//! coordinates), `N` (vertex normals, skipped) and `ST` (texture coordinates, skipped); the
//! counts `vertices faces [edges]` may follow on the same line. Each face line is a corner count,
//! the indices, and an optional colour: 3 or 4 integers 0–255, or floats 0–1 when a value has a
//! decimal point. `#` starts a comment anywhere. `OFF BINARY` (Geomview's binary form,
//! big-endian) is read by [`binary`]; the `4OFF`/`nOFF` dimensions are not supported. Records
//! are read one per line, as every OFF writer in use emits them.
//!
//! No crate reads OFF with colours and error locations, so this reader is hand-written.
//! The writer emits `OFF` (`COFF` with vertex colours) and integer RGBA face colours; materials,
//! groups, UVs, normals and provenance are not written. It writes text only: few programs read
//! binary OFF, and binary is [`Encoding`]'s default, so every `.off` output would become one.

mod binary;

use super::builder::{FaceAttributes, MeshBuilder};
use super::error::{Location, ParseError, malformed};
use super::text::{
    Lines, Tokens, append_blocks, channel, check_finite, next_f64, parse_f64, parse_i64,
};
use super::{Encoding, Format, LoadedMesh};
use crate::mesh::{FaceId, Mesh, Rgba};

/// True when the first token after comments is an OFF header keyword.
pub(crate) fn has_header(data: &[u8]) -> bool {
    let mut records = Records::new(&data[..data.len().min(4096)]);
    records
        .next()
        .and_then(|(_, mut tokens)| tokens.next())
        .is_some_and(|k| keyword(k).is_some())
}

/// The flags of a header keyword: (vertex colours, vertex normals, texture coordinates).
fn keyword(token: &[u8]) -> Option<(bool, bool, bool)> {
    let prefix = token.strip_suffix(b"OFF")?;
    let (st, rest) = match prefix.strip_prefix(b"ST") {
        Some(rest) => (true, rest),
        None => (false, prefix),
    };
    let (c, rest) = rest.strip_prefix(b"C").map_or((false, rest), |r| (true, r));
    let (n, rest) = rest.strip_prefix(b"N").map_or((false, rest), |r| (true, r));
    rest.is_empty().then_some((c, n, st))
}

/// Non-blank lines with comments removed, as token streams.
struct Records<'a> {
    lines: Lines<'a>,
    last: usize,
}

impl<'a> Records<'a> {
    fn new(data: &'a [u8]) -> Self {
        Self {
            lines: Lines::new(data),
            last: 0,
        }
    }

    /// The next record, or a malformed-file error saying what was missing.
    fn expect(
        &mut self,
        what: impl FnOnce() -> String,
    ) -> Result<(Location, Tokens<'a>), ParseError> {
        let last = Location::Line(self.last.max(1));
        self.next()
            .ok_or_else(|| malformed(Format::Off, last, format!("file ends before {}", what())))
    }
}

impl<'a> Iterator for Records<'a> {
    type Item = (Location, Tokens<'a>);

    fn next(&mut self) -> Option<Self::Item> {
        for (number, line) in self.lines.by_ref() {
            self.last = number;
            let line = memchr::memchr(b'#', line).map_or(line, |hash| &line[..hash]);
            let tokens = Tokens::new(line);
            if tokens.clone().next().is_some() {
                return Some((Location::Line(number), tokens));
            }
        }
        None
    }
}

/// Reads an OFF file held in memory.
pub(crate) fn read(data: &[u8]) -> Result<LoadedMesh, ParseError> {
    if data.is_empty() {
        return Err(ParseError::Empty {
            format: Format::Off,
        });
    }
    let mut records = Records::new(data);
    let (at, mut tokens) = records.expect(|| "the OFF header".to_owned())?;
    let flags = tokens.next().and_then(keyword);
    let Some((colors, normals, texture)) = flags else {
        return Err(malformed(Format::Off, at, "expected an OFF header"));
    };
    if tokens.clone().next() == Some(b"BINARY") {
        let layout = binary::VertexLayout {
            colors,
            normals,
            texture,
        };
        return binary::read(data, data.len() - records.lines.rest().len(), &layout);
    }
    let (at, counts) = match tokens.clone().next() {
        Some(_) => (at, tokens),
        None => records.expect(|| "the vertex and face counts".to_owned())?,
    };
    let (nv, nf) = read_counts(counts, at, records.lines.rest().len())?;
    let skip = 3 * usize::from(normals) + 2 * usize::from(texture);
    // A vertex line takes at least 6 bytes ("0 0 0\n"), a face line at least 8.
    let room = records.lines.rest().len();
    let mut builder = MeshBuilder::with_capacity(nv.min(room / 6), nf.min(room / 8));
    for v in 0..nv {
        let (at, tokens) = records.expect(|| format!("vertex {v} of {nv}"))?;
        read_vertex(&mut builder, tokens, at, skip, colors)?;
    }
    for f in 0..nf {
        let (at, tokens) = records.expect(|| format!("face {f} of {nf}"))?;
        read_face(&mut builder, tokens, at)?;
    }
    Ok(LoadedMesh {
        raw_vertex_count: nv,
        mesh: builder.finish()?,
        format: Format::Off,
        encoding: Encoding::Ascii,
    })
}

/// Parses `vertices faces [edges]`, rejecting counts the rest of the file cannot hold.
fn read_counts(
    mut tokens: Tokens<'_>,
    at: Location,
    room: usize,
) -> Result<(usize, usize), ParseError> {
    let mut count = |what: &'static str| -> Result<usize, ParseError> {
        let token = tokens
            .next()
            .ok_or_else(|| malformed(Format::Off, at, format!("missing {what} count")))?;
        let value = parse_i64(token, at)?;
        let reason = match value {
            v if v < 0 => "negative",
            v if v > i64::from(u32::MAX) => "meshes are limited to u32::MAX elements",
            v if v as usize > room => "the rest of the file cannot hold that many lines",
            v => return Ok(v as usize),
        };
        Err(ParseError::CountTooLarge {
            what,
            count: value.unsigned_abs(),
            reason,
        })
    };
    Ok((count("vertex")?, count("face")?))
}

fn read_vertex(
    builder: &mut MeshBuilder,
    mut tokens: Tokens<'_>,
    at: Location,
    skip: usize,
    colors: bool,
) -> Result<(), ParseError> {
    let missing = || malformed(Format::Off, at, "a vertex needs 3 coordinates");
    let p = [
        next_f64(&mut tokens, at, missing)?,
        next_f64(&mut tokens, at, missing)?,
        next_f64(&mut tokens, at, missing)?,
    ];
    check_finite(p, builder.vertex_count(), at)?;
    for _ in 0..skip {
        tokens.next();
    }
    let color = if colors { color(tokens, at)? } else { None };
    builder.push_vertex(p, color);
    Ok(())
}

fn read_face(
    builder: &mut MeshBuilder,
    mut tokens: Tokens<'_>,
    at: Location,
) -> Result<(), ParseError> {
    let face = builder.face_count();
    let count_token = tokens.next().unwrap_or_default();
    let corners = parse_i64(count_token, at)?;
    if corners < 3 {
        let corners = corners.max(0) as usize;
        return Err(ParseError::TooFewCorners { face, corners, at });
    }
    let vertex_count = builder.vertex_count();
    for _ in 0..corners {
        let token = tokens.next().ok_or_else(|| {
            malformed(
                Format::Off,
                at,
                format!("face {face} lists fewer than {corners} indices"),
            )
        })?;
        let index = parse_i64(token, at)?;
        if index < 0 || index >= vertex_count as i64 {
            let what = "vertex";
            return Err(ParseError::IndexOutOfRange {
                face,
                what,
                index,
                count: vertex_count,
                at,
            });
        }
        builder.push_corner(index as u32, None, None);
    }
    let color = color(tokens, at)?;
    builder.end_face(FaceAttributes {
        color,
        ..FaceAttributes::default()
    })
}

/// An optional trailing colour: 3 or 4 values, integers 0–255 or floats 0–1.
/// One value (a colour-map index) or none gives no colour.
fn color(tokens: Tokens<'_>, at: Location) -> Result<Option<Rgba>, ParseError> {
    let mut values = [255.0f64; 4];
    let mut count = 0;
    let mut is_float = false;
    for token in tokens {
        if count < 4 {
            values[count] = parse_f64(token, at)?;
        }
        is_float |= token.contains(&b'.');
        count += 1;
    }
    if count < 3 {
        return Ok(None);
    }
    if count == 3 {
        values[3] = if is_float { 1.0 } else { 255.0 };
    }
    Ok(Some(values.map(|c| channel(c, is_float))))
}

/// Appends `mesh` as OFF text (`COFF` when it has vertex colours) to `out`.
pub(crate) fn write(mesh: &Mesh, out: &mut Vec<u8>) {
    let mut int = itoa::Buffer::new();
    let vertex_colors = mesh.vertex_colors();
    out.extend_from_slice(if vertex_colors.is_some() {
        b"COFF\n"
    } else {
        b"OFF\n"
    });
    for n in [mesh.vertex_count(), mesh.face_count(), 0] {
        out.extend_from_slice(int.format(n).as_bytes());
        out.push(b' ');
    }
    out.push(b'\n');
    append_blocks(out, mesh.vertex_count(), |vertices, out| {
        let (mut f, mut int) = (ryu::Buffer::new(), itoa::Buffer::new());
        for v in vertices {
            for (k, c) in mesh.positions()[v].iter().enumerate() {
                if k > 0 {
                    out.push(b' ');
                }
                out.extend_from_slice(f.format(*c).as_bytes());
            }
            write_color(out, vertex_colors.map(|c| c[v]), &mut int);
        }
    });
    append_blocks(out, mesh.face_count(), |faces, out| {
        let mut int = itoa::Buffer::new();
        for face in faces {
            let corners = mesh.face(FaceId::new(face));
            out.extend_from_slice(int.format(corners.len()).as_bytes());
            for &v in corners {
                out.push(b' ');
                out.extend_from_slice(int.format(v).as_bytes());
            }
            write_color(out, mesh.face_colors().map(|c| c[face]), &mut int);
        }
    });
}

/// Ends a record with an optional integer RGBA colour and a newline.
fn write_color(out: &mut Vec<u8>, color: Option<Rgba>, int: &mut itoa::Buffer) {
    for channel in color.into_iter().flatten() {
        out.push(b' ');
        out.extend_from_slice(int.format(channel).as_bytes());
    }
    out.push(b'\n');
}

#[cfg(test)]
mod tests;
