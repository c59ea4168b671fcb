//! 3MF (3D Manufacturing Format, Core Specification 1.3, with the Materials and Properties
//! Extension's base materials and colour groups): reader and writer.
//!
//! A 3MF file is a zip archive (OPC package); `_rels/.rels` names the 3D model part (usually
//! `3D/3dmodel.model`), an XML document of resources (objects and property groups) and a
//! build of items that place objects.
//!
//! # Reading
//! 1. The archive is opened ([`zip`]) and the model part found through the root relationship
//!    of type `…/3dmodel`, or at `3D/3dmodel.model` when there is none. An archive with
//!    neither is "not a 3MF file".
//! 2. The model is parsed as a stream of XML events ([`quick_xml`]), element names compared
//!    without their namespace prefix. `requiredextensions` naming an extension other than
//!    materials is an error, as the specification asks of a consumer that does not know it.
//! 3. Each `<object>` with a `<mesh>` becomes a [`Mesh`]: its vertices in file order (bit-exact
//!    f64 from the shortest decimal), its triangles with every index checked, and per triangle
//!    the property its `pid`/`p1` (or the object's `pid`/`pindex`) names: a base material
//!    gives the face material (its `name`) and the face colour (its `displaycolor`), a colour
//!    group entry gives the face colour. The rule for per-vertex properties is **p1 for the
//!    face**: `p2` and `p3` are ignored, since csgkit's colours and materials are per face.
//!    Properties of other groups (textures, composites, multi-properties) are left out.
//! 4. Every `<item>` of the build becomes one part ([`Part`]): its object, with its
//!    `<components>` placed recursively, moved by the item's `transform`
//!    ([`transformed`]: faces reversed under a mirror).
//!
//! **Units.** Coordinates are read in millimetres: a model whose `unit` is not `millimeter`
//! (3MF's default) is scaled to millimetres with its item transform (one rounding per
//! coordinate), and [`LoadedMeshes::unit`] reports the unit the file declared. The writer
//! writes millimetres. So every 3MF csgkit reads is in one unit, and a millimetre file, the
//! common case, round-trips bit-exactly.
//!
//! # Writing
//! One object with the mesh's vertices (shortest round-trip decimals, so no f64 is lost) and
//! its faces triangulated by [`triangulate_faces`] (3MF holds triangles only; a polygon that
//! cannot be triangulated is a [`WriteError::InvalidPolygon`]), one build item without
//! transform. A mesh with materials gets one `<basematerials>` entry per distinct (material,
//! colour) pair of its faces, named after the material, its display colour the face colour
//! (white without colours); a mesh with colours only gets a `<m:colorgroup>`. Reading back
//! gives the same positions, triangles, materials and colours; a mesh with materials but no
//! colours comes back with white faces, since a 3MF base material always has a colour.
//! Groups, UVs, normals, vertex colours and provenance are not written.
//!
//! # Why no 3MF crate
//! `threemf` (the one pure-Rust 3MF crate) reads and writes meshes and build items but
//! neither base materials nor colour groups, and `lib3mf` binds the C++ reference library;
//! `zip` and `quick-xml` are the well-kept parts a 3MF reader is made of.

use std::io::{Cursor, Read, Write};

use quick_xml::events::attributes::Attribute;
use quick_xml::events::{BytesStart, Event};
use rustc_hash::FxHashMap;

use super::builder::{FaceAttributes, MeshBuilder};
use super::error::{Location, ParseError, WriteError, malformed, within};
use super::text::{check_finite, parse_f64, parse_i64, trim};
use super::{Encoding, Format, LoadedMeshes, Part, Unit};
use crate::mesh::{
    Affine, IDENTITY, Mesh, Rgba, Triangulation, compose, concatenate, transformed,
    triangulate_faces,
};

/// The first bytes of a zip archive (a local file header).
pub(crate) const ZIP_MAGIC: &[u8] = b"PK\x03\x04";

/// The relationship type of the 3D model part.
const MODEL_RELATIONSHIP: &str = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel";

/// Where the model part is when no relationship names it.
const DEFAULT_MODEL: &str = "3D/3dmodel.model";

/// The namespaces of the model XML.
const CORE_NAMESPACE: &str = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02";
const MATERIAL_NAMESPACE: &str = "http://schemas.microsoft.com/3dmanufacturing/material/2015/02";

/// Components nested deeper than this are a cycle (or a file no printer would take).
const MAX_DEPTH: usize = 64;

/// Reads a 3MF archive held in memory: one part per build item.
pub(crate) fn read(data: &[u8]) -> Result<LoadedMeshes, ParseError> {
    let mut archive = zip::ZipArchive::new(Cursor::new(data))
        .map_err(|e| structure(format!("not a zip archive: {e}")))?;
    let part = model_part(&mut archive)?;
    let xml = read_part(&mut archive, &part)?;
    let model = Model::parse(&xml).map_err(|e| within(part.as_str(), e))?;
    let unit = model.unit;
    let scale = unit.millimeters();
    let mut scaled = IDENTITY;
    for (k, row) in scaled.iter_mut().enumerate() {
        row[k] = scale;
    }
    let mut parts = Vec::with_capacity(model.items.len());
    for (k, item) in model.items.iter().enumerate() {
        let name = || format!("{part}, build item {k} (object {})", item.object);
        let placement = compose(scaled, item.transform);
        let mut meshes = Vec::new();
        model
            .place(item.object, placement, 0, &mut meshes)
            .map_err(|e| within(name(), e))?;
        let mesh = concatenate(&meshes).map_err(|e| within(name(), e.into()))?;
        let object = &model.objects[&item.object];
        let name = object.name.clone().unwrap_or_else(|| format!("item {k}"));
        parts.push(Part { name, mesh });
    }
    Ok(LoadedMeshes {
        parts,
        format: Format::ThreeMf,
        encoding: Encoding::Binary,
        raw_vertex_count: model.vertices,
        unit: Some(unit),
    })
}

/// A [`ParseError::Structure`] of a 3MF file.
fn structure(reason: impl Into<String>) -> ParseError {
    ParseError::Structure {
        format: Format::ThreeMf,
        reason: reason.into(),
    }
}

/// The name of the model part: the target of the root `3dmodel` relationship, or
/// `3D/3dmodel.model`.
fn model_part(archive: &mut zip::ZipArchive<Cursor<&[u8]>>) -> Result<String, ParseError> {
    let rels = "_rels/.rels";
    if archive.index_for_name(rels).is_some() {
        let xml = read_part(archive, rels)?;
        if let Some(target) = model_target(&xml).map_err(|e| within(rels, e))? {
            let name = target.trim_start_matches('/').to_owned();
            return match archive.index_for_name(&name) {
                Some(_) => Ok(name),
                None => Err(structure(format!(
                    "the 3D model part {target} that {rels} names is not in the archive"
                ))),
            };
        }
    }
    match archive.index_for_name(DEFAULT_MODEL) {
        Some(_) => Ok(DEFAULT_MODEL.to_owned()),
        None => Err(structure(format!(
            "not a 3MF file: the zip archive has no 3D model part (no 3dmodel relationship in \
             {rels} and no {DEFAULT_MODEL})"
        ))),
    }
}

/// The target of the first relationship of the model type in a `.rels` part.
fn model_target(xml: &[u8]) -> Result<Option<String>, ParseError> {
    let mut reader = quick_xml::Reader::from_reader(xml);
    loop {
        match reader.read_event() {
            Ok(Event::Start(e) | Event::Empty(e)) if e.local_name().as_ref() == b"Relationship" => {
                let (mut target, mut kind) = (None, None);
                for attribute in e.attributes().with_checks(false).flatten() {
                    match attribute.key.local_name().as_ref() {
                        b"Target" => target = Some(text(&attribute)),
                        b"Type" => kind = Some(text(&attribute)),
                        _ => {}
                    }
                }
                if kind.as_deref() == Some(MODEL_RELATIONSHIP) {
                    return Ok(target);
                }
            }
            Ok(Event::Eof) => return Ok(None),
            Ok(_) => {}
            Err(e) => return Err(xml_error(xml, &reader, e)),
        }
    }
}

/// The bytes of the part `name`, decompressed.
fn read_part(
    archive: &mut zip::ZipArchive<Cursor<&[u8]>>,
    name: &str,
) -> Result<Vec<u8>, ParseError> {
    let mut file = archive
        .by_name(name)
        .map_err(|e| structure(format!("cannot open part {name}: {e}")))?;
    // The declared size is only a hint (the compressed stream decides), so it reserves no
    // more than 64 MiB up front.
    let mut bytes = Vec::with_capacity(file.size().min(1 << 26) as usize);
    file.read_to_end(&mut bytes)
        .map_err(|e| structure(format!("cannot read part {name}: {e}")))?;
    Ok(bytes)
}

/// An XML syntax error at the line where the parser stopped.
fn xml_error(xml: &[u8], reader: &quick_xml::Reader<&[u8]>, error: quick_xml::Error) -> ParseError {
    let at = line_at(xml, reader.error_position() as usize);
    malformed(Format::ThreeMf, at, format!("invalid XML: {error}"))
}

/// The line of byte `offset` of `xml`.
fn line_at(xml: &[u8], offset: usize) -> Location {
    let before = &xml[..offset.min(xml.len())];
    Location::Line(1 + memchr::memchr_iter(b'\n', before).count())
}

/// An attribute's value, unescaped (raw when it holds a malformed entity).
fn text(attribute: &Attribute<'_>) -> String {
    match attribute.normalized_value(quick_xml::XmlVersion::Implicit1_0) {
        Ok(value) => value.into_owned(),
        Err(_) => String::from_utf8_lossy(&attribute.value).into_owned(),
    }
}

/// A property group of the model's resources.
enum Group {
    /// Base materials: name and display colour.
    Base(Vec<(String, Rgba)>),
    /// A colour group.
    Colors(Vec<Rgba>),
    /// A group csgkit does not read (textures, composites, multi-properties).
    Other,
}

/// An object of the model's resources.
struct Object {
    name: Option<String>,
    mesh: Option<Mesh>,
    components: Vec<(u32, Affine)>,
}

/// A build item.
struct Item {
    object: u32,
    transform: Affine,
}

/// The parsed model part.
struct Model {
    unit: Unit,
    groups: FxHashMap<u32, Group>,
    objects: FxHashMap<u32, Object>,
    items: Vec<Item>,
    /// Vertices stored in all objects.
    vertices: usize,
}

/// The object being parsed.
struct Open {
    id: u32,
    name: Option<String>,
    /// The object's default property group and index.
    pid: Option<u32>,
    pindex: Option<u32>,
    builder: Option<MeshBuilder>,
    components: Vec<(u32, Affine)>,
}

/// The attributes of an element, found by local name.
struct Attributes<'a> {
    list: smallvec::SmallVec<[Attribute<'a>; 8]>,
}

impl<'a> Attributes<'a> {
    fn of(e: &'a BytesStart<'a>) -> Self {
        let list = e.attributes().with_checks(false).flatten().collect();
        Self { list }
    }

    fn get(&self, name: &[u8]) -> Option<&Attribute<'a>> {
        self.list.iter().find(|a| local(a.key.as_ref()) == name)
    }

    /// The raw value of attribute `name`, trimmed.
    fn raw(&self, name: &[u8]) -> Option<&[u8]> {
        self.get(name).map(|a| trim(&a.value))
    }
}

/// A qualified name without its prefix.
fn local(name: &[u8]) -> &[u8] {
    memchr::memchr(b':', name).map_or(name, |colon| &name[colon + 1..])
}

/// Parses the model XML; errors name the element and its line (the caller adds the part).
struct Parser<'x> {
    xml: &'x [u8],
    reader: quick_xml::Reader<&'x [u8]>,
}

impl<'x> Parser<'x> {
    /// The line of the element just read.
    fn at(&self) -> Location {
        line_at(self.xml, self.reader.buffer_position() as usize)
    }

    /// `error` in `element` at the current line.
    fn fail(&self, element: impl Into<String>, reason: impl Into<String>) -> ParseError {
        within(element, malformed(Format::ThreeMf, self.at(), reason))
    }

    /// The required attribute `name` of `element` as a number.
    fn number(
        &self,
        attrs: &Attributes<'_>,
        name: &str,
        element: &dyn Fn() -> String,
    ) -> Result<f64, ParseError> {
        let raw = attrs
            .raw(name.as_bytes())
            .ok_or_else(|| self.fail(element(), format!("missing attribute {name}")))?;
        parse_f64(raw, self.at()).map_err(|e| within(format!("{}, attribute {name}", element()), e))
    }

    /// The attribute `name` of `element` as a `u32`, if present.
    fn index(
        &self,
        attrs: &Attributes<'_>,
        name: &str,
        element: &dyn Fn() -> String,
    ) -> Result<Option<u32>, ParseError> {
        let Some(raw) = attrs.raw(name.as_bytes()) else {
            return Ok(None);
        };
        let value = parse_i64(raw, self.at())
            .map_err(|e| within(format!("{}, attribute {name}", element()), e))?;
        u32::try_from(value).map(Some).map_err(|_| {
            self.fail(
                element(),
                format!("attribute {name} is {value}, not an index"),
            )
        })
    }

    /// The required attribute `name` of `element` as a `u32`.
    fn required_index(
        &self,
        attrs: &Attributes<'_>,
        name: &str,
        element: &dyn Fn() -> String,
    ) -> Result<u32, ParseError> {
        self.index(attrs, name, element)?
            .ok_or_else(|| self.fail(element(), format!("missing attribute {name}")))
    }

    /// The optional `transform` attribute of `element`: 12 numbers, 3MF's row-vector matrix.
    fn transform(
        &self,
        attrs: &Attributes<'_>,
        element: &dyn Fn() -> String,
    ) -> Result<Affine, ParseError> {
        let Some(raw) = attrs.raw(b"transform") else {
            return Ok(IDENTITY);
        };
        let mut values = [0.0; 12];
        let mut count = 0;
        for token in super::text::Tokens::new(raw) {
            let value = parse_f64(token, self.at())
                .map_err(|e| within(format!("{}, attribute transform", element()), e))?;
            if count < 12 {
                values[count] = value;
            }
            count += 1;
        }
        if count != 12 {
            return Err(self.fail(
                element(),
                format!("transform has {count} numbers; it needs 12"),
            ));
        }
        // 3MF multiplies row vectors: x' = x·m00 + y·m10 + z·m20 + m30.
        Ok([0, 1, 2].map(|i| [values[i], values[3 + i], values[6 + i], values[9 + i]]))
    }
}

/// The elements that open a property group.
fn is_group(name: &[u8]) -> bool {
    matches!(
        name,
        b"basematerials"
            | b"colorgroup"
            | b"texture2dgroup"
            | b"compositematerials"
            | b"multiproperties"
    )
}

impl Model {
    fn parse(xml: &[u8]) -> Result<Model, ParseError> {
        let mut p = Parser {
            xml,
            reader: quick_xml::Reader::from_reader(xml),
        };
        let mut model = Model {
            unit: Unit::Millimeter,
            groups: FxHashMap::default(),
            objects: FxHashMap::default(),
            items: Vec::new(),
            vertices: 0,
        };
        let mut object: Option<Open> = None;
        let mut group: Option<(u32, Group)> = None;
        let mut seen_model = false;
        loop {
            let (e, empty) = match p.reader.read_event() {
                Ok(Event::Start(e)) => (e, false),
                Ok(Event::Empty(e)) => (e, true),
                Ok(Event::End(e)) => {
                    let name = local(e.name().into_inner()).to_vec();
                    model.close(&p, &name, &mut object, &mut group)?;
                    continue;
                }
                Ok(Event::Eof) => break,
                Ok(_) => continue,
                Err(e) => return Err(xml_error(xml, &p.reader, e)),
            };
            let name = local(e.name().into_inner()).to_vec();
            let attrs = Attributes::of(&e);
            match name.as_slice() {
                b"model" => {
                    seen_model = true;
                    model.unit = model_unit(&p, &attrs)?;
                }
                _ if !seen_model => {
                    let found = String::from_utf8_lossy(&name).into_owned();
                    return Err(structure(format!(
                        "the root element is <{found}>, not <model>"
                    )));
                }
                b"object" => object = Some(open_object(&p, &attrs)?),
                b"mesh" => {
                    if let Some(open) = object.as_mut() {
                        open.builder = Some(MeshBuilder::with_capacity(0, 0));
                    }
                }
                b"vertex" => model.vertex(&p, &attrs, object.as_mut())?,
                b"triangle" => model.triangle(&p, &attrs, object.as_mut())?,
                b"component" => component(&p, &attrs, object.as_mut())?,
                b"item" => {
                    let element = || format!("build item {}", model.items.len());
                    let id = p.required_index(&attrs, "objectid", &element)?;
                    if attrs.get(b"path").is_some() {
                        return Err(production(element()));
                    }
                    let transform = p.transform(&attrs, &element)?;
                    model.items.push(Item {
                        object: id,
                        transform,
                    });
                }
                _ if is_group(&name) => {
                    let kind = String::from_utf8_lossy(&name).into_owned();
                    let id = p.required_index(&attrs, "id", &|| kind.clone())?;
                    let entries = match name.as_slice() {
                        b"basematerials" => Group::Base(Vec::new()),
                        b"colorgroup" => Group::Colors(Vec::new()),
                        _ => Group::Other,
                    };
                    group = Some((id, entries));
                }
                b"base" | b"color" => group_entry(&p, &name, &attrs, group.as_mut())?,
                _ => {}
            }
            if empty {
                model.close(&p, &name, &mut object, &mut group)?;
            }
        }
        if !seen_model {
            return Err(structure("the model part has no <model> element"));
        }
        Ok(model)
    }

    /// Ends the element `name`: an object or a property group is complete.
    fn close(
        &mut self,
        p: &Parser<'_>,
        name: &[u8],
        object: &mut Option<Open>,
        group: &mut Option<(u32, Group)>,
    ) -> Result<(), ParseError> {
        if name == b"object" {
            if let Some(open) = object.take() {
                let element = format!("object {}", open.id);
                let mesh = match open.builder {
                    Some(builder) => {
                        Some(builder.finish().map_err(|e| within(element.clone(), e))?)
                    }
                    None => None,
                };
                let done = Object {
                    name: open.name,
                    mesh,
                    components: open.components,
                };
                if self.objects.insert(open.id, done).is_some() {
                    return Err(p.fail(element, "a second object has this id"));
                }
            }
        } else if is_group(name) {
            if let Some((id, entries)) = group.take() {
                if self.groups.insert(id, entries).is_some() {
                    return Err(
                        p.fail(format!("property group {id}"), "a second group has this id")
                    );
                }
            }
        }
        Ok(())
    }

    /// A `<vertex>` of the open object's mesh.
    fn vertex(
        &mut self,
        p: &Parser<'_>,
        attrs: &Attributes<'_>,
        object: Option<&mut Open>,
    ) -> Result<(), ParseError> {
        let (id, builder) = open_mesh(p, object, "vertex")?;
        let v = builder.vertex_count();
        let element = || format!("object {id}, vertex {v}");
        let position = [
            p.number(attrs, "x", &element)?,
            p.number(attrs, "y", &element)?,
            p.number(attrs, "z", &element)?,
        ];
        check_finite(position, v, p.at()).map_err(|e| within(format!("object {id}"), e))?;
        builder.push_vertex(position, None);
        self.vertices += 1;
        Ok(())
    }

    /// A `<triangle>` of the open object's mesh, with its property (p1 for the face).
    fn triangle(
        &mut self,
        p: &Parser<'_>,
        attrs: &Attributes<'_>,
        object: Option<&mut Open>,
    ) -> Result<(), ParseError> {
        // The object's default property, for triangles that name none.
        let (object_pid, pindex) = (object.as_deref()).map_or((None, None), |o| (o.pid, o.pindex));
        let (id, builder) = open_mesh(p, object, "triangle")?;
        let face = builder.face_count();
        let element = || format!("object {id}, triangle {face}");
        let count = builder.vertex_count();
        for name in ["v1", "v2", "v3"] {
            let index = p.required_index(attrs, name, &element)?;
            if index as usize >= count {
                let error = ParseError::IndexOutOfRange {
                    face,
                    what: "vertex",
                    index: i64::from(index),
                    count,
                    at: p.at(),
                };
                return Err(within(format!("object {id}"), error));
            }
            builder.push_corner(index, None, None);
        }
        let pid = p.index(attrs, "pid", &element)?;
        let p1 = p.index(attrs, "p1", &element)?;
        let property = match (pid, p1) {
            (Some(pid), Some(index)) => Some((pid, index)),
            (Some(pid), None) if Some(pid) == object_pid => pindex.map(|index| (pid, index)),
            (Some(_), None) => return Err(p.fail(element(), "pid without p1")),
            (None, Some(index)) => object_pid.map(|pid| (pid, index)),
            (None, None) => object_pid.zip(pindex),
        };
        let mut attributes = FaceAttributes::default();
        if let Some((pid, index)) = property {
            let Some(group) = self.groups.get(&pid) else {
                return Err(p.fail(
                    element(),
                    format!("pid {pid} names no property group defined before it"),
                ));
            };
            let out_of_range = || {
                p.fail(
                    element(),
                    format!("p1 {index} is past the end of property group {pid}"),
                )
            };
            match group {
                Group::Base(entries) => {
                    let (name, color) = entries.get(index as usize).ok_or_else(out_of_range)?;
                    attributes.material = Some(name.as_str());
                    attributes.color = Some(*color);
                }
                Group::Colors(entries) => {
                    attributes.color = Some(*entries.get(index as usize).ok_or_else(out_of_range)?);
                }
                Group::Other => {}
            }
        }
        builder
            .end_face(attributes)
            .map_err(|e| within(element(), e))
    }

    /// Appends the meshes of object `id`, placed by `transform`, to `out`.
    fn place(
        &self,
        id: u32,
        transform: Affine,
        depth: usize,
        out: &mut Vec<Mesh>,
    ) -> Result<(), ParseError> {
        let Some(object) = self.objects.get(&id) else {
            return Err(structure(format!("object {id} is not defined")));
        };
        if depth > MAX_DEPTH {
            return Err(structure(format!(
                "components nest deeper than {MAX_DEPTH} levels at object {id} (a cycle?)"
            )));
        }
        if let Some(mesh) = &object.mesh {
            let moved = transformed(mesh, &transform).ok_or_else(|| {
                structure(format!(
                    "object {id} is placed by a singular or non-finite transform"
                ))
            })?;
            out.push(moved);
        }
        for &(child, own) in &object.components {
            self.place(child, compose(transform, own), depth + 1, out)
                .map_err(|e| within(format!("object {id}, component object {child}"), e))?;
        }
        Ok(())
    }
}

/// The id and mesh of the open object, for one of its `what` elements (vertex, triangle).
fn open_mesh<'o>(
    p: &Parser<'_>,
    object: Option<&'o mut Open>,
    what: &str,
) -> Result<(u32, &'o mut MeshBuilder), ParseError> {
    let Some(open) = object else {
        return Err(p.fail("the resources", format!("a {what} outside any object")));
    };
    let id = open.id;
    match open.builder.as_mut() {
        Some(builder) => Ok((id, builder)),
        None => Err(p.fail(format!("object {id}"), format!("a {what} outside its mesh"))),
    }
}

/// The error for a reference into another model part (the Production extension).
fn production(element: String) -> ParseError {
    within(
        element,
        ParseError::Feature {
            format: Format::ThreeMf,
            feature: "a path to another model part (production extension)".to_owned(),
        },
    )
}

/// The `<model>` element: its unit and required extensions.
fn model_unit(p: &Parser<'_>, attrs: &Attributes<'_>) -> Result<Unit, ParseError> {
    if let Some(required) = attrs.get(b"requiredextensions") {
        let required = text(required);
        for prefix in required.split_ascii_whitespace() {
            let key = format!("xmlns:{prefix}");
            let namespace = attrs
                .list
                .iter()
                .find(|a| a.key.as_ref() == key.as_bytes())
                .map(text)
                .unwrap_or_else(|| prefix.to_owned());
            if namespace != MATERIAL_NAMESPACE && namespace != CORE_NAMESPACE {
                return Err(within(
                    "model",
                    ParseError::Feature {
                        format: Format::ThreeMf,
                        feature: format!("required extension {namespace}"),
                    },
                ));
            }
        }
    }
    match attrs.get(b"unit") {
        None => Ok(Unit::Millimeter),
        Some(unit) => {
            let name = text(unit);
            Unit::from_name(name.trim())
                .ok_or_else(|| p.fail("model", format!("unknown unit {name:?}")))
        }
    }
}

/// An `<object>` start tag.
fn open_object(p: &Parser<'_>, attrs: &Attributes<'_>) -> Result<Open, ParseError> {
    let id = p.required_index(attrs, "id", &|| "object".to_owned())?;
    let element = || format!("object {id}");
    Ok(Open {
        id,
        name: attrs.get(b"name").map(text),
        pid: p.index(attrs, "pid", &element)?,
        pindex: p.index(attrs, "pindex", &element)?,
        builder: None,
        components: Vec::new(),
    })
}

/// A `<component>` of the open object.
fn component(
    p: &Parser<'_>,
    attrs: &Attributes<'_>,
    object: Option<&mut Open>,
) -> Result<(), ParseError> {
    let Some(open) = object else {
        return Err(p.fail("the resources", "a component outside any object"));
    };
    let k = open.components.len();
    let element = || format!("object {}, component {k}", open.id);
    let child = p.required_index(attrs, "objectid", &element)?;
    if attrs.get(b"path").is_some() {
        return Err(production(element()));
    }
    let transform = p.transform(attrs, &element)?;
    open.components.push((child, transform));
    Ok(())
}

/// A `<base>` or `<color>` entry of the open property group.
fn group_entry(
    p: &Parser<'_>,
    name: &[u8],
    attrs: &Attributes<'_>,
    group: Option<&mut (u32, Group)>,
) -> Result<(), ParseError> {
    let Some((id, entries)) = group else {
        return Ok(());
    };
    let element = |k: usize| format!("property group {id}, entry {k}");
    let color_of = |key: &str, k: usize| -> Result<Rgba, ParseError> {
        let raw = attrs
            .raw(key.as_bytes())
            .ok_or_else(|| p.fail(element(k), format!("missing attribute {key}")))?;
        parse_color(raw).ok_or_else(|| {
            let shown = String::from_utf8_lossy(raw);
            p.fail(
                element(k),
                format!("{key} {shown:?} is not #RRGGBB or #RRGGBBAA"),
            )
        })
    };
    match (name, entries) {
        (b"base", Group::Base(list)) => {
            let k = list.len();
            let label = attrs
                .get(b"name")
                .map(text)
                .unwrap_or_else(|| format!("material {k}"));
            list.push((label, color_of("displaycolor", k)?));
        }
        (b"color", Group::Colors(list)) => {
            let k = list.len();
            list.push(color_of("color", k)?);
        }
        _ => {}
    }
    Ok(())
}

/// `#RRGGBB` or `#RRGGBBAA`.
fn parse_color(raw: &[u8]) -> Option<Rgba> {
    let hex = raw.strip_prefix(b"#")?;
    if hex.len() != 6 && hex.len() != 8 {
        return None;
    }
    let mut rgba = [255u8; 4];
    for (k, pair) in hex.chunks_exact(2).enumerate() {
        let digits = std::str::from_utf8(pair).ok()?;
        rgba[k] = u8::from_str_radix(digits, 16).ok()?;
    }
    Some(rgba)
}

/// Appends `mesh` as a 3MF archive (see the module docs) to `out`.
pub(crate) fn write(mesh: &Mesh, out: &mut Vec<u8>) -> Result<(), WriteError> {
    let triangles = triangulate_faces(mesh).map_err(|error| WriteError::InvalidPolygon {
        format: Format::ThreeMf,
        error,
    })?;
    let model = model_xml(mesh, &triangles);
    let too_large = |_| WriteError::TooLarge {
        format: Format::ThreeMf,
        reason: "the zip archive could not be written",
    };
    let mut zip = zip::ZipWriter::new(Cursor::new(out));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .large_file(model.len() >= u32::MAX as usize);
    let files: [(&str, &[u8]); 3] = [
        ("[Content_Types].xml", CONTENT_TYPES.as_bytes()),
        ("_rels/.rels", RELATIONSHIPS.as_bytes()),
        (DEFAULT_MODEL, &model),
    ];
    for (name, bytes) in files {
        zip.start_file(name, options).map_err(too_large)?;
        zip.write_all(bytes).map_err(|_| WriteError::TooLarge {
            format: Format::ThreeMf,
            reason: "the zip archive could not be written",
        })?;
    }
    zip.finish().map_err(too_large)?;
    Ok(())
}

const CONTENT_TYPES: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">\
<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>\
<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>\
</Types>\n";

const RELATIONSHIPS: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">\
<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" \
Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/>\
</Relationships>\n";

/// The property of each face: an index into the written group, or `None` without one.
fn face_properties(mesh: &Mesh) -> (Vec<(Option<u32>, Rgba)>, Vec<u32>) {
    let materials = mesh.face_materials();
    let colors = mesh.face_colors();
    let mut entries: Vec<(Option<u32>, Rgba)> = Vec::new();
    let mut index: FxHashMap<(Option<u32>, Rgba), u32> = FxHashMap::default();
    let mut of_face = Vec::with_capacity(mesh.face_count());
    for face in 0..mesh.face_count() {
        let key = (
            materials.map(|m| m[face]),
            colors.map_or([255; 4], |c| c[face]),
        );
        let k = *index.entry(key).or_insert_with(|| {
            entries.push(key);
            entries.len() as u32 - 1
        });
        of_face.push(k);
    }
    (entries, of_face)
}

/// The model part of `mesh`.
fn model_xml(mesh: &Mesh, triangles: &Triangulation<'_>) -> Vec<u8> {
    let mut out = Vec::with_capacity(80 * mesh.vertex_count() + 60 * triangles.len() + 1024);
    out.extend_from_slice(
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" \
             xml:lang=\"en-US\" xmlns=\"{CORE_NAMESPACE}\" xmlns:m=\"{MATERIAL_NAMESPACE}\">\n\
             <metadata name=\"Application\">csgkit</metadata>\n<resources>\n"
        )
        .as_bytes(),
    );
    let has_properties = mesh.face_materials().is_some() || mesh.face_colors().is_some();
    let (entries, of_face) = if has_properties {
        face_properties(mesh)
    } else {
        (Vec::new(), Vec::new())
    };
    let hex = |c: Rgba| format!("#{:02X}{:02X}{:02X}{:02X}", c[0], c[1], c[2], c[3]);
    if mesh.face_materials().is_some() {
        out.extend_from_slice(b"<basematerials id=\"1\">\n");
        for &(material, color) in &entries {
            let name = &mesh.materials()[material.unwrap_or(0) as usize];
            let name = quick_xml::escape::escape(name.as_str());
            let line = format!("<base name=\"{name}\" displaycolor=\"{}\"/>\n", hex(color));
            out.extend_from_slice(line.as_bytes());
        }
        out.extend_from_slice(b"</basematerials>\n");
    } else if has_properties {
        out.extend_from_slice(b"<m:colorgroup id=\"1\">\n");
        for &(_, color) in &entries {
            out.extend_from_slice(format!("<m:color color=\"{}\"/>\n", hex(color)).as_bytes());
        }
        out.extend_from_slice(b"</m:colorgroup>\n");
    }
    out.extend_from_slice(b"<object id=\"2\" type=\"model\">\n<mesh>\n<vertices>\n");
    let mut f = ryu::Buffer::new();
    for p in mesh.positions() {
        out.extend_from_slice(b"<vertex");
        for (name, c) in [" x=\"", " y=\"", " z=\""].into_iter().zip(p) {
            out.extend_from_slice(name.as_bytes());
            out.extend_from_slice(f.format(*c).as_bytes());
            out.push(b'"');
        }
        out.extend_from_slice(b"/>\n");
    }
    out.extend_from_slice(b"</vertices>\n<triangles>\n");
    let mut int = itoa::Buffer::new();
    for (face, t) in triangles.iter() {
        out.extend_from_slice(b"<triangle");
        for (name, v) in [" v1=\"", " v2=\"", " v3=\""].into_iter().zip(t) {
            out.extend_from_slice(name.as_bytes());
            out.extend_from_slice(int.format(v).as_bytes());
            out.push(b'"');
        }
        if has_properties {
            out.extend_from_slice(b" pid=\"1\" p1=\"");
            out.extend_from_slice(int.format(of_face[face.index()]).as_bytes());
            out.push(b'"');
        }
        out.extend_from_slice(b"/>\n");
    }
    out.extend_from_slice(
        b"</triangles>\n</mesh>\n</object>\n</resources>\n<build>\n<item objectid=\"2\"/>\n</build>\n</model>\n",
    );
    out
}

#[cfg(test)]
mod tests;
