//! A box file as every front end reads it (the command line, the JSON scenes, the Python and
//! JavaScript bindings): a MagicaVoxel `.vox` model or a box text file, told apart by the
//! caller's name for it and by the `.vox` magic.

use super::{BoxesTextError, OrthoError, VoxOptions, parse_boxes, read_vox};
use crate::mesh::Rgba;

/// The boxes of a file and what a `.vox` model adds to them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BoxFile {
    /// Boxes `[x0, y0, z0, x1, y1, z1]` (voxel units for a `.vox` model).
    pub boxes: Vec<[f64; 6]>,
    /// The palette index of each box's voxels (a `.vox` model), `None` for box text.
    pub materials: Option<Vec<u32>>,
    /// The `.vox` palette, when the file has one.
    pub palette: Option<Vec<Rgba>>,
    /// The number of distinct voxels (a `.vox` model).
    pub voxel_count: Option<usize>,
}

/// Why a box file could not be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BoxFileError {
    /// A malformed `.vox` model, or a model index out of range.
    #[error(transparent)]
    Vox(#[from] OrthoError),
    /// A malformed line of box text.
    #[error(transparent)]
    Text(#[from] BoxesTextError),
    /// Bytes that are neither a `.vox` model nor UTF-8 text.
    #[error("neither a .vox model nor UTF-8 box text")]
    NotText,
    /// A model index given for box text, which has no models.
    #[error("a model index applies to .vox files only")]
    ModelOfText,
}

/// Reads `bytes` as a `.vox` model when `vox` says so (the file's extension, say) or they
/// start with the `VOX ` magic, taking model `model` alone when given; otherwise as box text.
///
/// # Errors
/// [`BoxFileError`] naming the byte offset of a malformed `.vox` chunk or the line of a
/// malformed box.
pub fn read_box_file(
    bytes: &[u8],
    vox: bool,
    model: Option<usize>,
) -> Result<BoxFile, BoxFileError> {
    if vox || bytes.starts_with(b"VOX ") {
        let read = read_vox(bytes, VoxOptions { model })?;
        return Ok(BoxFile {
            materials: Some(read.colors.iter().map(|&c| u32::from(c)).collect()),
            boxes: read.boxes,
            palette: read.palette,
            voxel_count: Some(read.voxel_count),
        });
    }
    if model.is_some() {
        return Err(BoxFileError::ModelOfText);
    }
    let text = std::str::from_utf8(bytes).map_err(|_| BoxFileError::NotText)?;
    Ok(BoxFile {
        boxes: parse_boxes(text)?,
        ..BoxFile::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_and_its_errors() {
        let file = read_box_file(b"0 0 0 1 1 1\n", false, None).unwrap();
        assert_eq!(file.boxes, vec![[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]]);
        assert_eq!(file.materials, None);
        assert_eq!(
            read_box_file(b"0 0 0 1 1 1\n", false, Some(0)),
            Err(BoxFileError::ModelOfText)
        );
        assert_eq!(
            read_box_file(&[0xff, 0xfe], false, None),
            Err(BoxFileError::NotText)
        );
        assert!(matches!(
            read_box_file(b"0 0 x\n", false, None),
            Err(BoxFileError::Text(_))
        ));
        // Named a .vox file, the bytes must be one.
        assert!(matches!(
            read_box_file(b"0 0 0 1 1 1\n", true, None),
            Err(BoxFileError::Vox(_))
        ));
    }
}
