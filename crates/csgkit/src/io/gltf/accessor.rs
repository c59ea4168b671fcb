//! Buffers and accessors of a glTF document, read with every range checked.

use std::borrow::Cow;

use gltf::accessor::{DataType, Dimensions};

use super::super::error::{Location, ParseError, within};
use super::super::{External, Format};
use super::{data_uri, percent_decoded, structure};

/// The bytes of every buffer of a document, by buffer index.
pub(super) struct Buffers<'a> {
    data: Vec<Cow<'a, [u8]>>,
}

impl<'a> Buffers<'a> {
    /// Loads every buffer: the GLB binary chunk, a `data:` URI, or an external file.
    pub(super) fn load(
        document: &gltf::Document,
        bin: Option<&'a [u8]>,
        external: External<'_>,
        format: Format,
    ) -> Result<Buffers<'a>, ParseError> {
        let mut data = Vec::new();
        for buffer in document.buffers() {
            let element = || format!("buffers[{}]", buffer.index());
            let fail = |reason: String| within(element(), structure(format, reason));
            let bytes: Cow<'a, [u8]> = match buffer.source() {
                gltf::buffer::Source::Bin => match bin {
                    Some(bin) => Cow::Borrowed(bin),
                    None => {
                        return Err(fail(
                            "it is the GLB binary chunk, which the file lacks".into(),
                        ));
                    }
                },
                gltf::buffer::Source::Uri(uri) => match data_uri(uri) {
                    Some(decoded) => Cow::Owned(decoded.map_err(fail)?),
                    None => {
                        let name = percent_decoded(uri);
                        Cow::Owned(
                            external(&name)
                                .map_err(|e| fail(format!("cannot read {name}: {e}")))?,
                        )
                    }
                },
            };
            if bytes.len() < buffer.length() {
                let (held, declared) = (bytes.len(), buffer.length());
                return Err(fail(format!(
                    "it holds {held} bytes, byteLength says {declared}"
                )));
            }
            data.push(bytes);
        }
        Ok(Buffers { data })
    }
}

/// Where an accessor's elements lie in its buffer.
struct Layout<'b> {
    buffer: &'b [u8],
    /// Byte offset of the first element in the buffer.
    start: usize,
    stride: usize,
    count: usize,
}

impl Layout<'_> {
    /// The bytes of element `i` from component byte `offset`, `len` bytes long.
    fn bytes<const L: usize>(&self, i: usize, offset: usize) -> [u8; L] {
        let at = self.start + i * self.stride + offset;
        // In range: `layout` checked the last element's end against the buffer.
        self.buffer[at..at + L].try_into().unwrap_or([0; L])
    }
}

/// The layout of `accessor`, every byte of it checked to lie in its view and buffer.
fn layout<'b>(
    buffers: &'b Buffers<'_>,
    accessor: &gltf::Accessor<'_>,
    format: Format,
) -> Result<Layout<'b>, ParseError> {
    let element = || format!("accessors[{}]", accessor.index());
    let fail = |reason: String| within(element(), structure(format, reason));
    if accessor.sparse().is_some() {
        let feature = "sparse accessors".to_owned();
        return Err(within(element(), ParseError::Feature { format, feature }));
    }
    let Some(view) = accessor.view() else {
        return Err(fail("it has no bufferView".into()));
    };
    let buffer = buffers
        .data
        .get(view.buffer().index())
        .map(AsRef::as_ref)
        .unwrap_or_default();
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(fail(format!(
            "byteStride {stride} is less than its element size {size}"
        )));
    }
    let view_end = view.offset().saturating_add(view.length());
    if view_end > buffer.len() {
        return Err(fail(format!(
            "bufferViews[{}] ends at byte {view_end}, past the end of buffers[{}] ({} bytes)",
            view.index(),
            view.buffer().index(),
            buffer.len()
        )));
    }
    let start = view.offset().saturating_add(accessor.offset());
    let count = accessor.count();
    if count > 0 {
        let end = (count - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(start))
            .and_then(|x| x.checked_add(size))
            .unwrap_or(usize::MAX);
        if end > view_end {
            return Err(fail(format!(
                "its {count} elements end at byte {end}, past the end of bufferViews[{}] at {view_end}",
                view.index()
            )));
        }
    }
    Ok(Layout {
        buffer,
        start,
        stride,
        count,
    })
}

/// The dimension count glTF's `type` names.
fn dimensions(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 | Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// The elements of a `VEC{N}` attribute accessor: floats, or normalised integers.
pub(super) fn read_f32s<const N: usize>(
    buffers: &Buffers<'_>,
    accessor: &gltf::Accessor<'_>,
    name: &str,
    format: Format,
) -> Result<Vec<[f32; N]>, ParseError> {
    let element = || format!("accessors[{}]", accessor.index());
    let kind = (accessor.data_type(), accessor.normalized());
    let usable = matches!(
        kind,
        (DataType::F32, _)
            | (
                DataType::U8 | DataType::U16 | DataType::I8 | DataType::I16,
                true
            )
    );
    if dimensions(accessor.dimensions()) != N || !usable {
        let reason = format!(
            "{name} is {:?} of {:?}{}; csgkit reads VEC{N} of floats or normalized integers",
            accessor.dimensions(),
            accessor.data_type(),
            if accessor.normalized() {
                " (normalized)"
            } else {
                ""
            }
        );
        return Err(within(element(), structure(format, reason)));
    }
    let layout = layout(buffers, accessor, format)?;
    let size = accessor.data_type().size();
    let value = |i: usize, k: usize| -> f32 {
        let offset = k * size;
        match accessor.data_type() {
            DataType::F32 => f32::from_le_bytes(layout.bytes(i, offset)),
            DataType::U8 => f32::from(layout.bytes::<1>(i, offset)[0]) / 255.0,
            DataType::U16 => f32::from(u16::from_le_bytes(layout.bytes(i, offset))) / 65535.0,
            DataType::I8 => (f32::from(layout.bytes::<1>(i, offset)[0] as i8) / 127.0).max(-1.0),
            DataType::I16 => {
                (f32::from(i16::from_le_bytes(layout.bytes(i, offset))) / 32767.0).max(-1.0)
            }
            DataType::U32 => 0.0,
        }
    };
    Ok((0..layout.count)
        .map(|i| std::array::from_fn(|k| value(i, k)))
        .collect())
}

/// The elements of an index accessor and where each lies.
pub(super) struct Indices {
    pub(super) values: Vec<u32>,
    start: usize,
    stride: usize,
}

impl Indices {
    /// The byte offset of index `i` in its buffer.
    pub(super) fn at(&self, i: usize) -> Location {
        Location::Byte(self.start + i * self.stride)
    }
}

/// The elements of a `SCALAR` accessor of unsigned integers (a primitive's `indices`).
pub(super) fn read_indices(
    buffers: &Buffers<'_>,
    accessor: &gltf::Accessor<'_>,
    format: Format,
) -> Result<Indices, ParseError> {
    let element = || format!("accessors[{}]", accessor.index());
    let unsigned = matches!(
        accessor.data_type(),
        DataType::U8 | DataType::U16 | DataType::U32
    );
    if accessor.dimensions() != Dimensions::Scalar || !unsigned {
        let reason = format!(
            "indices are {:?} of {:?}; glTF indices are SCALAR unsigned integers",
            accessor.dimensions(),
            accessor.data_type()
        );
        return Err(within(element(), structure(format, reason)));
    }
    let layout = layout(buffers, accessor, format)?;
    let values = (0..layout.count)
        .map(|i| match accessor.data_type() {
            DataType::U8 => u32::from(layout.bytes::<1>(i, 0)[0]),
            DataType::U16 => u32::from(u16::from_le_bytes(layout.bytes(i, 0))),
            _ => u32::from_le_bytes(layout.bytes(i, 0)),
        })
        .collect();
    Ok(Indices {
        values,
        start: layout.start,
        stride: layout.stride,
    })
}
