//! Errors of the readers and writers.
//!
//! A [`ReadError`] says which file failed and, through [`ParseError`], what is wrong and where:
//! a line number in text files, a byte offset in binary ones, and the vertex or face index at
//! fault. Parsers produce a [`ParseError`] without knowing the path; [`read_mesh`] attaches it.
//!
//! [`read_mesh`]: super::read_mesh

use std::fmt;
use std::path::{Path, PathBuf};

use super::Format;
use crate::mesh::{InvalidMesh, PolygonError};

/// Where in a file a problem lies: a 1-based line of a text file or a byte offset of a binary one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// A 1-based line number.
    Line(usize),
    /// A 0-based byte offset.
    Byte(usize),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(line) => write!(f, "line {line}"),
            Location::Byte(offset) => write!(f, "byte offset {offset}"),
        }
    }
}

/// What is wrong with the content of a mesh file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParseError {
    /// The file has no byte at all, but the format needs a header.
    #[error("empty file: {format} needs a header")]
    Empty {
        /// The format the file was read as.
        format: Format,
    },
    /// The content matches no supported format.
    #[error(
        "unknown format: the extension and the content match none of OBJ, STL, PLY, OFF, 3MF, \
         glTF, GLB"
    )]
    UnknownFormat,
    /// A vertex coordinate is NaN or infinite.
    #[error("{at}: vertex {vertex} has a non-finite coordinate {value}")]
    NonFinite {
        /// The vertex in file order (for STL: 3 per facet, before welding).
        vertex: usize,
        /// The offending value.
        value: f64,
        /// Where it is.
        at: Location,
    },
    /// A face refers to a vertex, texture coordinate or normal that does not exist.
    #[error("{at}: face {face} refers to {what} {index}, but {count} are defined")]
    IndexOutOfRange {
        /// The face in file order.
        face: usize,
        /// "vertex", "texture coordinate" or "normal".
        what: &'static str,
        /// The index as written in the file (1-based or negative in OBJ, 0-based elsewhere).
        index: i64,
        /// How many the file defines at that point.
        count: usize,
        /// Where it is.
        at: Location,
    },
    /// A face has fewer than three corners.
    #[error("{at}: face {face} has {corners} corners; a face needs at least 3")]
    TooFewCorners {
        /// The face in file order.
        face: usize,
        /// Its corner count.
        corners: usize,
        /// Where it is.
        at: Location,
    },
    /// The file ends before the data its header announces.
    #[error("truncated file: {what} needs {expected} bytes, the file has {actual}")]
    Truncated {
        /// What was being read.
        what: &'static str,
        /// Bytes needed.
        expected: usize,
        /// Bytes present.
        actual: usize,
    },
    /// A token that should be a number is not one.
    #[error("{at}: malformed number {token:?}")]
    MalformedNumber {
        /// The token (cut to 40 bytes).
        token: String,
        /// Where it is.
        at: Location,
    },
    /// The file breaks the format's grammar.
    #[error("{at}: malformed {format} file: {reason}")]
    Malformed {
        /// The format the file was read as.
        format: Format,
        /// What was expected.
        reason: String,
        /// Where it is.
        at: Location,
    },
    /// The file uses a feature of the format that csgkit does not read.
    #[error("{at}: unsupported {format} feature: {feature}")]
    Unsupported {
        /// The format the file was read as.
        format: Format,
        /// The feature.
        feature: String,
        /// Where it is.
        at: Location,
    },
    /// A count is larger than the file could hold or than `u32` indices allow.
    #[error("{what} count {count} is too large: {reason}")]
    CountTooLarge {
        /// What is counted.
        what: &'static str,
        /// The count.
        count: u64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A file of parts (3MF, glTF) breaks its specification, in a way no line or byte offset
    /// locates (the element is named by [`ParseError::In`] around it).
    #[error("malformed {format} file: {reason}")]
    Structure {
        /// The format the file was read as.
        format: Format,
        /// What is wrong.
        reason: String,
    },
    /// A file of parts (3MF, glTF) uses a feature csgkit does not read.
    #[error("unsupported {format} feature: {feature}")]
    Feature {
        /// The format the file was read as.
        format: Format,
        /// The feature.
        feature: String,
    },
    /// An error inside one part or element of a file of parts: the 3MF part and object, the
    /// glTF element (`meshes[0].primitives[1]`).
    #[error("{element}: {error}")]
    In {
        /// Where: the part, the element, the object.
        element: String,
        /// What is wrong there.
        error: Box<ParseError>,
    },
    /// The assembled mesh breaks a mesh invariant (in practice: a `u32` size limit).
    #[error("the file's mesh is invalid: {0}")]
    Invalid(#[from] InvalidMesh),
}

/// A mesh file could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadError {
    /// The file could not be opened or read.
    #[error("cannot read {}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file's content is not a valid mesh.
    #[error("{}: {error}", show_path(.path.as_deref()))]
    Parse {
        /// The file, or `None` for bytes read from memory.
        path: Option<PathBuf>,
        /// What is wrong and where.
        error: ParseError,
    },
}

impl ReadError {
    /// The parse error, if the content (not the file system) is at fault.
    pub fn parse_error(&self) -> Option<&ParseError> {
        match self {
            ReadError::Parse { error, .. } => Some(error),
            ReadError::Io { .. } => None,
        }
    }
}

fn show_path(path: Option<&Path>) -> String {
    path.map_or_else(|| "<memory>".to_owned(), |p| p.display().to_string())
}

/// A mesh could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WriteError {
    /// The file system refused the temporary file, the write or the rename.
    #[error("cannot write {}: {source}", .path.display())]
    Io {
        /// The destination file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The extension names no supported format and no format was given.
    #[error(
        "cannot write {}: unknown extension (use .obj, .stl, .ply, .off, .3mf, .gltf or .glb)",
        .path.display()
    )]
    UnknownFormat {
        /// The destination file.
        path: PathBuf,
    },
    /// The mesh does not fit the format (e.g. more than `u32::MAX` STL triangles).
    #[error("cannot write {format}: {reason}")]
    TooLarge {
        /// The format.
        format: Format,
        /// What does not fit.
        reason: &'static str,
    },
    /// The format holds triangles only, and a polygon cannot be triangulated.
    ///
    /// *How to fix*: split the face into simple polygons, or remove it if it has no area.
    #[error("cannot write {format}: {error}")]
    InvalidPolygon {
        /// The format.
        format: Format,
        /// The face and what is wrong with it.
        error: PolygonError,
    },
}

/// A [`ParseError::MalformedNumber`] for `token` at `at`, cutting long tokens.
pub(crate) fn malformed_number(token: &[u8], at: Location) -> ParseError {
    let cut = &token[..token.len().min(40)];
    ParseError::MalformedNumber {
        token: String::from_utf8_lossy(cut).into_owned(),
        at,
    }
}

/// A [`ParseError::Malformed`].
pub(crate) fn malformed(format: Format, at: Location, reason: impl Into<String>) -> ParseError {
    ParseError::Malformed {
        format,
        reason: reason.into(),
        at,
    }
}

/// `error` inside `element` ([`ParseError::In`]).
pub(crate) fn within(element: impl Into<String>, error: ParseError) -> ParseError {
    ParseError::In {
        element: element.into(),
        error: Box::new(error),
    }
}
