//! The PLY header: format line, elements and their properties.

use super::super::error::{Location, ParseError, malformed};
use super::super::text::{Lines, Tokens, parse_i64};
use super::Format;

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    pub(super) fn parse(name: &[u8]) -> Option<Scalar> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    pub(super) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub(super) fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// A property: a scalar, or a list with a count type and an item type.
#[derive(Clone, Debug)]
pub(super) struct Property {
    pub(super) name: String,
    /// `Some(count type)` for a list.
    pub(super) list: Option<Scalar>,
    pub(super) item: Scalar,
}

#[derive(Clone, Debug)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) count: usize,
    pub(super) properties: Vec<Property>,
    pub(super) line: usize,
}

impl Element {
    /// The fewest bytes one instance can take: in binary its scalars and list counts; in ASCII
    /// one digit and a separator per property.
    pub(super) fn min_size(&self, binary: bool) -> usize {
        let sizes = self
            .properties
            .iter()
            .map(|p| p.list.unwrap_or(p.item).size());
        if binary {
            sizes.sum()
        } else {
            2 * self.properties.len()
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Body {
    Ascii,
    Little,
    Big,
}

pub(super) struct Header {
    pub(super) body: Body,
    pub(super) elements: Vec<Element>,
    /// Byte offset of the body and number of the header's last line.
    pub(super) body_start: usize,
    pub(super) lines: usize,
}

pub(super) fn read_header(data: &[u8]) -> Result<Header, ParseError> {
    let mut lines = Lines::new(data);
    let first = lines.next().map(|(_, line)| line);
    if first != Some(b"ply") {
        return Err(malformed(
            Format::Ply,
            Location::Line(1),
            "the first line must be \"ply\"",
        ));
    }
    let mut body = None;
    let mut elements: Vec<Element> = Vec::new();
    while let Some((number, line)) = lines.next() {
        let at = Location::Line(number);
        let mut tokens = Tokens::new(line);
        match tokens.next() {
            Some(b"format") => body = Some(body_format(tokens, at)?),
            Some(b"element") => elements.push(element(tokens, at, number)?),
            Some(b"property") => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| malformed(Format::Ply, at, "property before any element"))?;
                element.properties.push(property(tokens, at)?);
            }
            Some(b"end_header") => {
                let body = body.ok_or_else(|| malformed(Format::Ply, at, "no format line"))?;
                let body_start = data.len() - lines.rest().len();
                return Ok(Header {
                    body,
                    elements,
                    body_start,
                    lines: number,
                });
            }
            None | Some(b"comment" | b"obj_info") => {}
            Some(_) => return Err(malformed(Format::Ply, at, "unknown header line")),
        }
    }
    let at = Location::Line(data.split(|&b| b == b'\n').count());
    Err(malformed(Format::Ply, at, "the header has no end_header"))
}

fn body_format(mut tokens: Tokens<'_>, at: Location) -> Result<Body, ParseError> {
    match tokens.next() {
        Some(b"ascii") => Ok(Body::Ascii),
        Some(b"binary_little_endian") => Ok(Body::Little),
        Some(b"binary_big_endian") => Ok(Body::Big),
        other => {
            let feature = format!(
                "format {}",
                String::from_utf8_lossy(other.unwrap_or_default())
            );
            Err(ParseError::Unsupported {
                format: Format::Ply,
                feature,
                at,
            })
        }
    }
}

fn element(mut tokens: Tokens<'_>, at: Location, line: usize) -> Result<Element, ParseError> {
    let (Some(name), Some(count)) = (tokens.next(), tokens.next()) else {
        return Err(malformed(
            Format::Ply,
            at,
            "element needs a name and a count",
        ));
    };
    let count = parse_i64(count, at)?;
    let count =
        usize::try_from(count).map_err(|_| malformed(Format::Ply, at, "negative element count"))?;
    let name = String::from_utf8_lossy(name).into_owned();
    Ok(Element {
        name,
        count,
        properties: Vec::new(),
        line,
    })
}

fn property(mut tokens: Tokens<'_>, at: Location) -> Result<Property, ParseError> {
    let scalar = |token: Option<&[u8]>| {
        let token = token.unwrap_or_default();
        Scalar::parse(token).ok_or_else(|| {
            let feature = format!("property type {:?}", String::from_utf8_lossy(token));
            ParseError::Unsupported {
                format: Format::Ply,
                feature,
                at,
            }
        })
    };
    let first = tokens.next();
    let (list, item) = if first == Some(b"list") {
        (Some(scalar(tokens.next())?), scalar(tokens.next())?)
    } else {
        (None, scalar(first)?)
    };
    let name = tokens
        .next()
        .ok_or_else(|| malformed(Format::Ply, at, "property needs a name"))?;
    Ok(Property {
        name: String::from_utf8_lossy(name).into_owned(),
        list,
        item,
    })
}
