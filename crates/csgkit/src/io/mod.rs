//! Mesh file readers and writers: OBJ, STL (ASCII and binary), PLY (ASCII and binary), OFF
//! (ASCII and binary), 3MF, and glTF 2.0 (`.gltf` and `.glb`).
//!
//! [`read_mesh`] loads a file whole into memory and parses it with the reader of its format;
//! [`write_mesh`] renders the mesh into memory and writes it to a temporary file in the
//! destination folder that is renamed over the destination when complete, so an output file
//! is written whole or not at all. Every reader and writer works on bytes in memory
//! ([`read_meshes_from_bytes`], [`write_mesh_to_bytes`]); only the path-based functions touch
//! the file system, so the module runs where there is none (WebAssembly).
//!
//! # Files of several parts
//! A 3MF file places objects as build items, a glTF file places meshes at the nodes of its
//! scene. [`read_meshes`] gives each such part as its own mesh ([`LoadedMeshes`]), in its
//! place; [`read_mesh`] gives them merged into one ([`concatenate`]). The other formats
//! hold one part.
//!
//! ```
//! use csgkit::{Encoding, Format, Mesh, read_mesh_from_bytes, write_mesh_to_bytes};
//!
//! let positions = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.1, 0.0]];
//! let triangle = Mesh::from_triangles(positions, &[[0, 1, 2]])?;
//! let bytes = write_mesh_to_bytes(&triangle, Format::Obj, Encoding::Ascii)?;
//! let loaded = read_mesh_from_bytes(&bytes, None)?; // recognised by its content
//! assert_eq!(loaded.format, Format::Obj);
//! assert_eq!(loaded.mesh.positions(), triangle.positions()); // bit-identical
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Format detection
//! The extension chooses the format, but content that unambiguously says otherwise wins, in
//! this order: a zip archive (`PK\x03\x04`: 3MF, the one zip-based format; its reader says
//! when the archive holds no 3D model), the `glTF` magic of a GLB, a JSON object with an
//! `"asset"` key (a `.gltf`), a `ply` magic line, an `OFF` header (text or `OFF BINARY`), a
//! binary STL whose size is exactly `84 + 50 * triangle count`, text starting with `solid` (ASCII STL), and text whose first
//! statement after comments is an OBJ keyword. Within STL, binary versus ASCII is decided by
//! the size check first, because binary files whose 80-byte header begins with `solid` are
//! common. A file of comments only is OBJ when the extension says nothing.
//!
//! # Why hand-written readers
//! 3MF is read with `zip` and `quick-xml`, glTF with `gltf` (the document model and its
//! validation); their modules say why no 3MF crate is used and which part of `gltf` is not.
//! The mesh formats are hand-written byte scanners; each module says which crate it was
//! compared with. In short: `tobj` splits the file
//! into models with one material each and stores f32 by default, `stl_io` returns f32
//! positions (csgkit keeps the exact f64 values of ASCII files), and `ply-rs` builds a hash map
//! of named properties for every vertex and face. These crates were judged from their
//! documented data model, not benchmarked. The formats are small, and one scanner shares its
//! error reporting.
//!
//! # Errors
//! Every reader error names the file (added here), the line or byte offset, and the vertex or
//! face at fault; see [`ParseError`]. A file that parses but holds no face is an empty mesh.

mod builder;
mod error;
mod gltf;
mod obj;
mod off;
mod ply;
mod stl;
mod text;
mod threemf;

use std::fmt;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

pub use error::{Location, ParseError, ReadError, WriteError};

use crate::kernel::Precision;
use crate::mesh::{Mesh, concatenate};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// STL, ASCII or binary.
    Stl,
    /// Stanford PLY, ASCII or binary.
    Ply,
    /// Object File Format, ASCII or binary.
    Off,
    /// 3D Manufacturing Format: a zip archive of XML parts.
    ThreeMf,
    /// glTF 2.0 as JSON (`.gltf`), buffers embedded as base64 or in files beside it.
    Gltf,
    /// glTF 2.0 as one binary file (`.glb`).
    Glb,
}

impl Format {
    /// The format a file extension names (case-insensitive), if any.
    pub fn from_extension(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Format::Obj),
            "stl" => Some(Format::Stl),
            "ply" => Some(Format::Ply),
            "off" => Some(Format::Off),
            "3mf" => Some(Format::ThreeMf),
            "gltf" => Some(Format::Gltf),
            "glb" => Some(Format::Glb),
            _ => None,
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::Stl => "STL",
            Format::Ply => "PLY",
            Format::Off => "OFF",
            Format::ThreeMf => "3MF",
            Format::Gltf => "glTF",
            Format::Glb => "GLB",
        })
    }
}

/// Text or binary encoding of a file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// Binary (STL, PLY); the default for writing where the format has it.
    #[default]
    Binary,
    /// Text.
    Ascii,
}

/// A mesh read from a file, with what was learned about the file.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct LoadedMesh {
    /// The mesh.
    pub mesh: Mesh,
    /// The format the content was parsed as.
    pub format: Format,
    /// The encoding the content was parsed as.
    pub encoding: Encoding,
    /// The number of vertices the file stores, before any welding: for STL three per facet,
    /// for the other formats equal to the mesh's vertex count.
    pub raw_vertex_count: usize,
}

/// The unit a file declares for its coordinates (3MF's `unit` attribute).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Unit {
    /// 10⁻⁶ m.
    Micron,
    /// 10⁻³ m, 3MF's default and the unit csgkit reads 3MF coordinates in.
    Millimeter,
    /// 10⁻² m.
    Centimeter,
    /// 25.4 mm.
    Inch,
    /// 304.8 mm.
    Foot,
    /// 1 m.
    Meter,
}

impl Unit {
    /// The unit a 3MF `unit` attribute names.
    pub fn from_name(name: &str) -> Option<Unit> {
        Some(match name {
            "micron" => Unit::Micron,
            "millimeter" => Unit::Millimeter,
            "centimeter" => Unit::Centimeter,
            "inch" => Unit::Inch,
            "foot" => Unit::Foot,
            "meter" => Unit::Meter,
            _ => return None,
        })
    }

    /// Its 3MF name.
    pub fn name(self) -> &'static str {
        match self {
            Unit::Micron => "micron",
            Unit::Millimeter => "millimeter",
            Unit::Centimeter => "centimeter",
            Unit::Inch => "inch",
            Unit::Foot => "foot",
            Unit::Meter => "meter",
        }
    }

    /// Millimetres per unit.
    pub fn millimeters(self) -> f64 {
        match self {
            Unit::Micron => 0.001,
            Unit::Millimeter => 1.0,
            Unit::Centimeter => 10.0,
            Unit::Inch => 25.4,
            Unit::Foot => 304.8,
            Unit::Meter => 1000.0,
        }
    }
}

/// One part of a file that places several (a 3MF build item, a glTF node with a mesh).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Part {
    /// The part's name in the file, or where it is (`"item 2"`, `"nodes[3]"`).
    pub name: String,
    /// Its mesh, in its place.
    pub mesh: Mesh,
}

/// The parts of a file, each its own mesh, with what was learned about the file.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct LoadedMeshes {
    /// The parts in file order (build items, nodes in depth-first order); formats that hold
    /// one mesh give one part, named after the format.
    pub parts: Vec<Part>,
    /// The format the content was parsed as.
    pub format: Format,
    /// The encoding the content was parsed as.
    pub encoding: Encoding,
    /// The number of vertices the file stores, summed over the parts, before any welding.
    pub raw_vertex_count: usize,
    /// The unit the file declares (3MF; its coordinates are scaled to millimetres on reading),
    /// `None` for formats without one.
    pub unit: Option<Unit>,
}

impl LoadedMeshes {
    /// One part read from a format that holds one mesh.
    fn single(loaded: LoadedMesh) -> LoadedMeshes {
        LoadedMeshes {
            parts: vec![Part {
                name: loaded.format.to_string(),
                mesh: loaded.mesh,
            }],
            format: loaded.format,
            encoding: loaded.encoding,
            raw_vertex_count: loaded.raw_vertex_count,
            unit: None,
        }
    }

    /// The parts as one mesh ([`concatenate`]).
    ///
    /// # Errors
    /// [`ParseError::Invalid`] if the merged mesh passes the `u32` limits.
    pub fn merge(mut self) -> Result<LoadedMesh, ParseError> {
        let mesh = if self.parts.len() == 1 {
            self.parts.pop().map(|part| part.mesh).unwrap_or_default()
        } else {
            let meshes: Vec<Mesh> = self.parts.into_iter().map(|part| part.mesh).collect();
            concatenate(&meshes)?
        };
        Ok(LoadedMesh {
            mesh,
            format: self.format,
            encoding: self.encoding,
            raw_vertex_count: self.raw_vertex_count,
        })
    }
}

/// Options for [`write_mesh`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WriteOptions {
    /// The format to write; `None` chooses by the destination's extension.
    pub format: Option<Format>,
    /// Binary (the default) or ASCII, for STL and PLY; the other formats ignore it (OBJ and
    /// OFF are written as text, 3MF as XML, glTF as `.gltf` or `.glb` by the format).
    pub encoding: Encoding,
}

/// What [`write_mesh`] did besides writing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct Written {
    /// The coordinates the format could not hold exactly and rounded to f32 (glTF, binary
    /// STL); zero for the formats that store f64.
    pub rounded_coordinates: usize,
}

/// Where the external files of a file come from (a `.gltf`'s buffers given by relative URI):
/// the bytes of the file a URI names, or why there are none.
pub type External<'a> = &'a dyn Fn(&str) -> std::io::Result<Vec<u8>>;

/// An [`External`] for bytes that have no folder around them: every external file is missing.
pub fn no_external_files(uri: &str) -> std::io::Result<Vec<u8>> {
    Err(std::io::Error::new(
        std::io::ErrorKind::NotFound,
        format!("{uri} is not in memory (only a file read from a folder has neighbours)"),
    ))
}

/// Reads a mesh file, choosing the format by extension and content; the parts of a file that
/// holds several are merged into one mesh.
///
/// # Errors
/// [`ReadError::Io`] if the file cannot be read, [`ReadError::Parse`] naming the file and the
/// [`ParseError`] if its content is not a valid mesh.
pub fn read_mesh(path: impl AsRef<Path>) -> Result<LoadedMesh, ReadError> {
    let path = path.as_ref();
    let parse_error = |error| ReadError::Parse {
        path: Some(path.to_owned()),
        error,
    };
    read_meshes(path)?.merge().map_err(parse_error)
}

/// Reads a mesh file with each of its parts as its own mesh (see the module docs); external
/// files it names (a `.gltf`'s buffers) are read from its folder.
///
/// # Errors
/// As [`read_mesh`].
pub fn read_meshes(path: impl AsRef<Path>) -> Result<LoadedMeshes, ReadError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| ReadError::Io {
        path: path.to_owned(),
        source,
    })?;
    let folder = path.parent().unwrap_or(Path::new(""));
    let external = |uri: &str| std::fs::read(folder.join(uri));
    parse(&bytes, Format::from_extension(path), &external).map_err(|error| ReadError::Parse {
        path: Some(path.to_owned()),
        error,
    })
}

/// Reads a mesh from bytes in memory, parts merged; `hint` plays the role of the file
/// extension. A `.gltf` whose buffers are external files is an error: use
/// [`read_meshes_from_bytes`] with an [`External`].
///
/// # Errors
/// [`ReadError::Parse`] (with no path) if the bytes are not a valid mesh.
pub fn read_mesh_from_bytes(bytes: &[u8], hint: Option<Format>) -> Result<LoadedMesh, ReadError> {
    read_meshes_from_bytes(bytes, hint, &no_external_files)?
        .merge()
        .map_err(|error| ReadError::Parse { path: None, error })
}

/// Reads the parts of a mesh file from bytes in memory; `external` gives the files it names.
///
/// # Errors
/// [`ReadError::Parse`] (with no path) if the bytes are not a valid mesh.
pub fn read_meshes_from_bytes(
    bytes: &[u8],
    hint: Option<Format>,
    external: External<'_>,
) -> Result<LoadedMeshes, ReadError> {
    parse(bytes, hint, external).map_err(|error| ReadError::Parse { path: None, error })
}

/// Decides the format and runs its reader.
fn parse(
    bytes: &[u8],
    hint: Option<Format>,
    external: External<'_>,
) -> Result<LoadedMeshes, ParseError> {
    let format = detect(bytes, hint).ok_or(ParseError::UnknownFormat)?;
    match format {
        Format::Obj => obj::read(bytes).map(LoadedMeshes::single),
        Format::Stl => stl::read(bytes).map(LoadedMeshes::single),
        Format::Ply => ply::read(bytes).map(LoadedMeshes::single),
        Format::Off => off::read(bytes).map(LoadedMeshes::single),
        Format::ThreeMf => threemf::read(bytes),
        Format::Gltf | Format::Glb => gltf::read(bytes, external),
    }
}

/// The format of `bytes`: a content signature wins over `hint`, which wins over a file made
/// only of comments (OBJ when there is no hint).
fn detect(bytes: &[u8], hint: Option<Format>) -> Option<Format> {
    if bytes.starts_with(threemf::ZIP_MAGIC) {
        return Some(Format::ThreeMf);
    }
    if bytes.starts_with(gltf::GLB_MAGIC) {
        return Some(Format::Glb);
    }
    if gltf::is_gltf_json(bytes) {
        return Some(Format::Gltf);
    }
    if bytes.starts_with(b"ply") {
        return Some(Format::Ply);
    }
    if off::has_header(bytes) {
        return Some(Format::Off);
    }
    if stl::is_binary(bytes) {
        return Some(Format::Stl);
    }
    let start = text::trim(&bytes[..bytes.len().min(4096)]);
    if stl::starts_with_solid(start) {
        return Some(Format::Stl);
    }
    let first = text::Lines::new(start)
        .filter_map(|(_, line)| text::Tokens::new(line).next())
        .find(|token| !token.starts_with(b"#"));
    let obj_keywords: [&[u8]; 9] = [
        b"v", b"vt", b"vn", b"f", b"o", b"g", b"s", b"mtllib", b"usemtl",
    ];
    match first {
        Some(token) if obj_keywords.contains(&token) => Some(Format::Obj),
        None if hint.is_none() && !start.is_empty() => Some(Format::Obj),
        _ => hint,
    }
}

/// Renders `mesh` in `format`.
///
/// # Errors
/// [`WriteError::TooLarge`] if the mesh does not fit the format, [`WriteError::InvalidPolygon`]
/// if the format holds only triangles (STL, 3MF, glTF) and a polygon cannot be triangulated.
pub fn write_mesh_to_bytes(
    mesh: &Mesh,
    format: Format,
    encoding: Encoding,
) -> Result<Vec<u8>, WriteError> {
    let mut out = Vec::with_capacity(64 * mesh.vertex_count() + 32 * mesh.face_count());
    match format {
        Format::Obj => obj::write(mesh, &mut out),
        Format::Stl => stl::write(mesh, encoding, &mut out)?,
        Format::Ply => ply::write(mesh, encoding, &mut out),
        Format::Off => off::write(mesh, &mut out),
        Format::ThreeMf => threemf::write(mesh, &mut out)?,
        Format::Gltf | Format::Glb => gltf::write(mesh, format, &mut out)?,
    }
    Ok(out)
}

impl Format {
    /// The numbers this format stores coordinates in with `encoding`: f32 in glTF, GLB and
    /// binary STL, f64 (shortest round-trip decimals, or doubles) in the others. A boolean
    /// whose result goes to such a file is certified in that precision
    /// ([`BooleanOptions::precision`](crate::exact::BooleanOptions::precision)).
    pub fn precision(self, encoding: Encoding) -> Precision {
        match self {
            Format::Gltf | Format::Glb => Precision::F32,
            Format::Stl if encoding == Encoding::Binary => Precision::F32,
            Format::Stl | Format::Obj | Format::Ply | Format::Off | Format::ThreeMf => {
                Precision::F64
            }
        }
    }
}

/// How many coordinates of `mesh` writing it in `format` and `encoding` rounds: those that
/// are not numbers of its [`Format::precision`] (f32 in glTF, GLB and binary STL); zero for
/// the others.
pub fn rounded_coordinates(mesh: &Mesh, format: Format, encoding: Encoding) -> usize {
    let precision = format.precision(encoding);
    (mesh.positions().iter().flatten())
        .filter(|&&c| !precision.holds(c))
        .count()
}

/// Writes `mesh` to `path` atomically: to a temporary file beside it, then renamed over it;
/// says how many coordinates the format rounded ([`rounded_coordinates`]).
///
/// # Errors
/// [`WriteError::UnknownFormat`] if neither `options.format` nor the extension names a format,
/// [`WriteError::TooLarge`] if the mesh does not fit it, [`WriteError::InvalidPolygon`] if it
/// holds only triangles and a polygon cannot be triangulated, [`WriteError::Io`] if the file system
/// refuses; the destination is then left as it was.
pub fn write_mesh(
    path: impl AsRef<Path>,
    mesh: &Mesh,
    options: WriteOptions,
) -> Result<Written, WriteError> {
    let path = path.as_ref();
    let format = options
        .format
        .or_else(|| Format::from_extension(path))
        .ok_or_else(|| WriteError::UnknownFormat {
            path: path.to_owned(),
        })?;
    let bytes = write_mesh_to_bytes(mesh, format, options.encoding)?;
    write_atomic(path, &bytes).map_err(|source| WriteError::Io {
        path: path.to_owned(),
        source,
    })?;
    Ok(Written {
        rounded_coordinates: rounded_coordinates(mesh, format, options.encoding),
    })
}

/// Writes `bytes` to a new temporary file beside `path`, then renames it over `path`; on
/// failure the temporary file is removed and `path` is untouched.
fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
    let temp = path.with_file_name(format!(".{name}.{}-{unique}.tmp", std::process::id()));
    let result = std::fs::File::create_new(&temp)
        .and_then(|mut file| {
            file.write_all(bytes)?;
            file.sync_all()
        })
        .and_then(|()| std::fs::rename(&temp, path));
    if result.is_err() {
        // The temporary file may never have been created; the first error is the one to report.
        let _ = std::fs::remove_file(&temp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_signatures_beat_the_extension() {
        assert_eq!(
            detect(b"ply\nformat ascii 1.0\n", Some(Format::Stl)),
            Some(Format::Ply)
        );
        assert_eq!(
            detect(b"# c\nOFF\n0 0 0\n", Some(Format::Stl)),
            Some(Format::Off)
        );
        assert_eq!(detect(b"solid x\nendsolid\n", None), Some(Format::Stl));
        assert_eq!(detect(b"v 1 2 3\n", None), Some(Format::Obj));
        assert_eq!(
            detect(b"# c\n\nv 1 2 3\n", Some(Format::Stl)),
            Some(Format::Obj)
        );
        assert_eq!(detect(b"# only a comment\n", None), Some(Format::Obj));
        assert_eq!(
            detect(b"# only a comment\n", Some(Format::Off)),
            Some(Format::Off)
        );
        assert_eq!(detect(b"", Some(Format::Ply)), Some(Format::Ply));
        assert_eq!(detect(b"\x00\x01garbage", None), None);
        let mut binary = b"solid but binary".to_vec();
        binary.resize(84, 0);
        assert_eq!(detect(&binary, Some(Format::Obj)), Some(Format::Stl));
        assert_eq!(detect(&binary, Some(Format::Off)), Some(Format::Stl));
    }

    #[test]
    fn unknown_content_is_an_error_naming_no_path() {
        let err = read_mesh_from_bytes(b"\x00\x01", None).unwrap_err();
        assert!(matches!(err.parse_error(), Some(ParseError::UnknownFormat)));
        assert!(err.to_string().starts_with("<memory>: unknown format"));
    }

    #[test]
    fn zero_byte_files_name_the_path_and_the_format() {
        let dir = tempfile::tempdir().unwrap();
        for (name, format) in [
            ("e.stl", Format::Stl),
            ("e.ply", Format::Ply),
            ("e.off", Format::Off),
        ] {
            let path = dir.path().join(name);
            std::fs::write(&path, b"").unwrap();
            let err = read_mesh(&path).unwrap_err();
            assert_eq!(err.parse_error(), Some(&ParseError::Empty { format }));
            let message = format!("{}: empty file: {format} needs a header", path.display());
            assert_eq!(err.to_string(), message);
        }
        let path = dir.path().join("e.obj");
        std::fs::write(&path, b"").unwrap();
        assert!(read_mesh(&path).unwrap().mesh.is_empty());
        let path = dir.path().join("bad.obj");
        std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").unwrap();
        let message = "line 4: face 0 refers to vertex 4, but 3 are defined";
        assert_eq!(
            read_mesh(&path).unwrap_err().to_string(),
            format!("{}: {message}", path.display())
        );
        let missing = read_mesh(dir.path().join("missing.obj")).unwrap_err();
        assert!(matches!(missing, ReadError::Io { .. }));
    }

    #[test]
    fn write_is_atomic_and_chooses_format_by_extension() {
        let dir = tempfile::tempdir().unwrap();
        let mesh = Mesh::from_triangles(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[[0, 1, 2]],
        )
        .unwrap();
        for name in ["a.obj", "a.stl", "a.ply", "a.off"] {
            let path = dir.path().join(name);
            write_mesh(&path, &mesh, WriteOptions::default()).unwrap();
            let loaded = read_mesh(&path).unwrap();
            assert_eq!(Some(loaded.format), Format::from_extension(&path));
            assert_eq!(loaded.mesh.positions(), mesh.positions());
        }
        let err = write_mesh(dir.path().join("a.xyz"), &mesh, WriteOptions::default());
        assert!(matches!(err, Err(WriteError::UnknownFormat { .. })));
        let err = write_mesh(
            dir.path().join("missing/a.obj"),
            &mesh,
            WriteOptions::default(),
        );
        assert!(matches!(err, Err(WriteError::Io { .. })));
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 4);
    }
}
