//! Binary OFF (Geomview's `OFF BINARY`): big-endian `int32` counts and indices, `float32`
//! values.
//!
//! After the header line come `vertices faces edges`, then per vertex `x y z` with, as the
//! header's prefixes ask, a normal (3 floats, skipped), a colour (4 floats 0–1) and texture
//! coordinates (2 floats, skipped); then per face its corner count, the indices, a colour
//! component count (0–4) and that many floats: 3 or 4 are a colour, 1 (a colour-map index)
//! and 0 are none. Geomview's `off(5)` manual page is the reference.

use super::super::builder::{FaceAttributes, MeshBuilder};
use super::super::error::{Location, ParseError, malformed};
use super::super::text::{channel, check_finite};
use super::super::{Encoding, Format, LoadedMesh};

/// What the header's prefixes add to each vertex.
pub(super) struct VertexLayout {
    pub(super) colors: bool,
    pub(super) normals: bool,
    pub(super) texture: bool,
}

/// A big-endian cursor over the body.
struct Body<'a> {
    data: &'a [u8],
    pos: usize,
}

impl Body<'_> {
    fn word(&mut self, what: &'static str) -> Result<[u8; 4], ParseError> {
        let end = self.pos + 4;
        let bytes = self.data.get(self.pos..end).ok_or(ParseError::Truncated {
            what,
            expected: end,
            actual: self.data.len(),
        })?;
        self.pos = end;
        Ok(bytes.try_into().unwrap_or([0; 4]))
    }

    fn int(&mut self, what: &'static str) -> Result<i32, ParseError> {
        self.word(what).map(i32::from_be_bytes)
    }

    fn float(&mut self, what: &'static str) -> Result<f64, ParseError> {
        self.word(what).map(|w| f64::from(f32::from_be_bytes(w)))
    }
}

/// Reads the binary body starting at byte `start` of `data`.
pub(super) fn read(
    data: &[u8],
    start: usize,
    layout: &VertexLayout,
) -> Result<LoadedMesh, ParseError> {
    let mut body = Body { data, pos: start };
    let counts = [
        body.int("binary OFF counts")?,
        body.int("binary OFF counts")?,
    ];
    body.int("binary OFF counts")?;
    let floats = 3
        + 3 * usize::from(layout.normals)
        + 4 * usize::from(layout.colors)
        + 2 * usize::from(layout.texture);
    let room = data.len() - body.pos;
    let [nv, nf] =
        [("vertex", counts[0], 4 * floats), ("face", counts[1], 12)].map(|(what, count, size)| {
            match usize::try_from(count) {
                Ok(n) if n.saturating_mul(size) <= room => Ok(n),
                _ => Err(ParseError::CountTooLarge {
                    what,
                    count: i64::from(count).unsigned_abs(),
                    reason: "negative, or more than the rest of the file can hold",
                }),
            }
        });
    let (nv, nf) = (nv?, nf?);
    let mut builder = MeshBuilder::with_capacity(nv, nf);
    for v in 0..nv {
        let at = Location::Byte(body.pos);
        let mut p = [0.0; 3];
        for c in &mut p {
            *c = body.float("binary OFF vertices")?;
        }
        check_finite(p, v, at)?;
        for _ in 0..3 * usize::from(layout.normals) {
            body.float("binary OFF vertices")?;
        }
        let mut color = None;
        if layout.colors {
            let mut rgba = [0u8; 4];
            for c in &mut rgba {
                *c = channel(body.float("binary OFF vertices")?, true);
            }
            color = Some(rgba);
        }
        for _ in 0..2 * usize::from(layout.texture) {
            body.float("binary OFF vertices")?;
        }
        builder.push_vertex(p, color);
    }
    for face in 0..nf {
        let at = Location::Byte(body.pos);
        let corners = body.int("binary OFF faces")?;
        if corners < 3 {
            let corners = corners.max(0) as usize;
            return Err(ParseError::TooFewCorners { face, corners, at });
        }
        for _ in 0..corners {
            let at = Location::Byte(body.pos);
            let index = body.int("binary OFF faces")?;
            if index < 0 || index as usize >= nv {
                return Err(ParseError::IndexOutOfRange {
                    face,
                    what: "vertex",
                    index: i64::from(index),
                    count: nv,
                    at,
                });
            }
            builder.push_corner(index as u32, None, None);
        }
        let at = Location::Byte(body.pos);
        let components = body.int("binary OFF faces")?;
        if !(0..=4).contains(&components) {
            let reason = format!("face {face} has {components} colour components; at most 4");
            return Err(malformed(Format::Off, at, reason));
        }
        let mut rgba = [255u8; 4];
        for c in rgba.iter_mut().take(components as usize) {
            *c = channel(body.float("binary OFF faces")?, true);
        }
        let color = (components >= 3).then_some(rgba);
        builder.end_face(FaceAttributes {
            color,
            ..FaceAttributes::default()
        })?;
    }
    Ok(LoadedMesh {
        raw_vertex_count: nv,
        mesh: builder.finish()?,
        format: Format::Off,
        encoding: Encoding::Binary,
    })
}
