//! MagicaVoxel `.vox` input: voxels placed as MagicaVoxel places them, merged into boxes.
//!
//! Format (`design/ortho.md` §A9): `"VOX "`, a version, then a `MAIN` chunk whose children are
//! `PACK` (optional), `SIZE` + `XYZI` per model, `RGBA` (the palette), and the scene graph
//! (`nTRN` transforms, `nGRP` groups, `nSHP` shapes), plus chunks we skip (`LAYR`, `MATL`,
//! `MATT`, `rOBJ`, `IMAP`, …). Every chunk is `id, content size, children size, content,
//! children`, little-endian.
//!
//! 1. Parse the chunks, checking every length against the buffer (a truncated or malformed
//!    file is an error naming the byte offset, never a panic).
//! 2. Place the models. With a scene graph, every shape instance is placed by the composed
//!    transforms of its `nTRN` ancestors (frame 0): world = R·(v − pivot) + t, where the pivot
//!    is the model's size halved and rounded down, and a flipped axis maps the cell
//!    [v, v+1] to [−(v − pivot) − 1, −(v − pivot)]. Without a scene graph, several models are
//!    animation frames: the first is taken. [`VoxOptions::model`] picks one model alone, in
//!    its own coordinates.
//! 3. Merge voxels of the same colour into boxes: runs along z, then runs of equal z-runs
//!    along y.
//!
//! Complexity: O(v log v) for v voxels.

use std::collections::HashMap;

use super::OrthoError;
use crate::Rgba;
use crate::mesh::Mesh;

/// Options for [`read_vox`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VoxOptions {
    /// Take this model alone (by its index in the file), ignoring the scene graph.
    pub model: Option<usize>,
}

/// Boxes read from a `.vox` file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VoxBoxes {
    /// Boxes `[x0, y0, z0, x1, y1, z1]` in voxel units, disjoint.
    pub boxes: Vec<[f64; 6]>,
    /// The palette index (1–255) of each box's voxels.
    pub colors: Vec<u8>,
    /// The palette: `palette[i - 1]` is the colour of index i. MagicaVoxel's default palette
    /// is not built in: a file without `RGBA` gives `None`.
    pub palette: Option<Vec<Rgba>>,
    /// The number of distinct cells filled (voxels placed on the same cell count once).
    pub voxel_count: usize,
}

/// One model: its size and voxels `(x, y, z, colour index)`.
struct Model {
    size: [i64; 3],
    voxels: Vec<[u8; 4]>,
}

/// A scene-graph node.
enum Node {
    Transform {
        child: i32,
        rotation: [[i64; 3]; 3],
        translation: [i64; 3],
    },
    Group {
        children: Vec<i32>,
    },
    Shape {
        models: Vec<i32>,
    },
}

/// Reads a `.vox` file from memory (steps 1–3).
///
/// # Errors
/// [`OrthoError::Vox`] naming the byte offset of the first malformed chunk, or a model index
/// out of range.
pub fn read_vox(bytes: &[u8], options: VoxOptions) -> Result<VoxBoxes, OrthoError> {
    let file = parse(bytes)?;
    let voxels = match options.model {
        Some(m) => {
            let model = file.models.get(m).ok_or_else(|| OrthoError::Vox {
                offset: 0,
                reason: format!("model {m} requested but the file has {}", file.models.len()),
            })?;
            model
                .voxels
                .iter()
                .map(|v| ([0, 1, 2].map(|k| i64::from(v[k])), v[3]))
                .collect()
        }
        None if file.nodes.is_empty() => file.models.first().map_or_else(Vec::new, |m| {
            m.voxels
                .iter()
                .map(|v| ([0, 1, 2].map(|k| i64::from(v[k])), v[3]))
                .collect()
        }),
        None => place_scene(&file)?,
    };
    let (boxes, colors, voxel_count) = merge_runs(voxels);
    Ok(VoxBoxes {
        boxes,
        colors,
        palette: file.palette,
        voxel_count,
    })
}

/// Gives every face of a mesh built from a file's boxes the colour of its material in
/// `palette`: material `m` is palette index `m` (`palette[m - 1]`), as [`VoxBoxes::colors`]
/// are; a material outside the palette is white. A mesh without materials is returned as it
/// is.
pub fn with_palette_colors(mesh: Mesh, palette: &[Rgba]) -> Mesh {
    let Some(materials) = mesh.face_materials() else {
        return mesh;
    };
    let colors = (materials.iter())
        .map(|&m| {
            (palette.get((m as usize).wrapping_sub(1)))
                .copied()
                .unwrap_or([255; 4])
        })
        .collect();
    let mut parts = mesh.into_parts();
    parts.face_colors = Some(colors);
    Mesh::from_parts(parts).expect("one colour per face keeps the mesh valid")
}

/// The parsed chunks.
#[derive(Default)]
struct VoxFile {
    models: Vec<Model>,
    nodes: HashMap<i32, Node>,
    palette: Option<Vec<Rgba>>,
}

/// A bounds-checked little-endian reader.
struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn fail(&self, reason: &str) -> OrthoError {
        OrthoError::Vox {
            offset: self.pos,
            reason: reason.to_string(),
        }
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], OrthoError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| self.fail("unexpected end of file"))?;
        let out = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(out)
    }

    fn u32(&mut self) -> Result<u32, OrthoError> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn i32(&mut self) -> Result<i32, OrthoError> {
        Ok(self.u32()? as i32)
    }

    fn string(&mut self) -> Result<String, OrthoError> {
        let n = self.u32()? as usize;
        Ok(String::from_utf8_lossy(self.take(n)?).into_owned())
    }

    fn dict(&mut self) -> Result<HashMap<String, String>, OrthoError> {
        let n = self.u32()?;
        let mut out = HashMap::new();
        for _ in 0..n {
            let key = self.string()?;
            out.insert(key, self.string()?);
        }
        Ok(out)
    }
}

/// Step 1.
fn parse(bytes: &[u8]) -> Result<VoxFile, OrthoError> {
    let mut r = Reader { bytes, pos: 0 };
    if r.take(4)? != b"VOX " {
        return Err(OrthoError::Vox {
            offset: 0,
            reason: "missing 'VOX ' magic".into(),
        });
    }
    r.u32()?;
    if r.take(4)? != b"MAIN" {
        return Err(r.fail("missing MAIN chunk"));
    }
    let (content, children) = (r.u32()? as usize, r.u32()? as usize);
    r.take(content)?;
    let end = r.pos;
    r.take(children)?;
    r.pos = end;
    let mut file = VoxFile::default();
    let mut size = None;
    while r.pos < end + children {
        let id: [u8; 4] = r.take(4)?.try_into().expect("4 bytes");
        let (n, children) = (r.u32()? as usize, r.u32()? as usize);
        let start = r.pos;
        let mut c = Reader {
            bytes: r.take(n)?,
            pos: 0,
        };
        r.take(children)?;
        let at = |e: OrthoError| match e {
            OrthoError::Vox { offset, reason } => OrthoError::Vox {
                offset: start + offset,
                reason,
            },
            other => other,
        };
        parse_chunk(&id, &mut c, &mut file, &mut size).map_err(at)?;
    }
    Ok(file)
}

fn parse_chunk(
    id: &[u8; 4],
    c: &mut Reader,
    file: &mut VoxFile,
    size: &mut Option<[i64; 3]>,
) -> Result<(), OrthoError> {
    match id {
        b"SIZE" => *size = Some([c.u32()?, c.u32()?, c.u32()?].map(i64::from)),
        b"XYZI" => {
            let n = c.u32()? as usize;
            let data = c.take(
                n.checked_mul(4)
                    .ok_or_else(|| c.fail("voxel count overflows"))?,
            )?;
            let size = size.take().ok_or_else(|| c.fail("XYZI without SIZE"))?;
            let voxels = data
                .chunks_exact(4)
                .map(|v| [v[0], v[1], v[2], v[3]])
                .collect();
            file.models.push(Model { size, voxels });
        }
        b"RGBA" => {
            let data = c.take(1024)?;
            file.palette = Some(
                data.chunks_exact(4)
                    .take(255)
                    .map(|p| [p[0], p[1], p[2], p[3]])
                    .collect(),
            );
        }
        b"nTRN" => {
            let node = c.i32()?;
            c.dict()?;
            let child = c.i32()?;
            c.i32()?;
            c.i32()?;
            let frames = c.u32()?;
            let frame = if frames > 0 {
                c.dict()?
            } else {
                HashMap::new()
            };
            let rotation = frame.get("_r").map_or(Ok(IDENTITY), |s| rotation(s, c))?;
            let translation = frame.get("_t").map_or(Ok([0; 3]), |s| translation(s, c))?;
            file.nodes.insert(
                node,
                Node::Transform {
                    child,
                    rotation,
                    translation,
                },
            );
        }
        b"nGRP" => {
            let node = c.i32()?;
            c.dict()?;
            let n = c.u32()?;
            let children = (0..n).map(|_| c.i32()).collect::<Result<_, _>>()?;
            file.nodes.insert(node, Node::Group { children });
        }
        b"nSHP" => {
            let node = c.i32()?;
            c.dict()?;
            let n = c.u32()?;
            let mut models = Vec::new();
            for _ in 0..n {
                models.push(c.i32()?);
                c.dict()?;
            }
            file.nodes.insert(node, Node::Shape { models });
        }
        _ => {}
    }
    Ok(())
}

const IDENTITY: [[i64; 3]; 3] = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];

/// Decodes MagicaVoxel's packed rotation byte: bits 0–1 and 2–3 give the column of the
/// non-zero entry of rows 0 and 1, bits 4–6 the signs of rows 0–2 (1 = negative).
fn rotation(s: &str, c: &Reader) -> Result<[[i64; 3]; 3], OrthoError> {
    let bits: u8 = s.trim().parse().map_err(|_| c.fail("malformed rotation"))?;
    let (c0, c1) = ((bits & 3) as usize, ((bits >> 2) & 3) as usize);
    if c0 > 2 || c1 > 2 || c0 == c1 {
        return Err(c.fail("rotation is not a permutation"));
    }
    let c2 = 3 - c0 - c1;
    let mut m = [[0i64; 3]; 3];
    for (row, col) in [c0, c1, c2].into_iter().enumerate() {
        m[row][col] = if bits >> (4 + row) & 1 == 1 { -1 } else { 1 };
    }
    Ok(m)
}

fn translation(s: &str, c: &Reader) -> Result<[i64; 3], OrthoError> {
    let parts: Vec<i64> = s
        .split_whitespace()
        .map(|p| p.parse().map_err(|_| c.fail("malformed translation")))
        .collect::<Result<_, _>>()?;
    parts
        .try_into()
        .map_err(|_| c.fail("translation needs three values"))
}

/// Step 2 with a scene graph: every voxel of every shape instance, placed.
fn place_scene(file: &VoxFile) -> Result<Vec<([i64; 3], u8)>, OrthoError> {
    let mut out = Vec::new();
    // (node, rotation, translation, depth); the depth bound rejects cyclic graphs.
    let mut stack = vec![(0i32, IDENTITY, [0i64; 3], 0usize)];
    while let Some((id, rot, t, depth)) = stack.pop() {
        let bad = |reason: String| OrthoError::Vox { offset: 0, reason };
        if depth > file.nodes.len() {
            return Err(bad("the scene graph has a cycle".into()));
        }
        match file.nodes.get(&id) {
            Some(Node::Transform {
                child,
                rotation,
                translation,
            }) => {
                let r = mul(&rot, rotation);
                let tt: [i64; 3] = std::array::from_fn(|i| {
                    t[i] + (0..3).map(|j| rot[i][j] * translation[j]).sum::<i64>()
                });
                stack.push((*child, r, tt, depth + 1));
            }
            Some(Node::Group { children }) => {
                stack.extend(children.iter().rev().map(|&c| (c, rot, t, depth + 1)));
            }
            Some(Node::Shape { models }) => {
                for &m in models {
                    let model = usize::try_from(m).ok().and_then(|m| file.models.get(m));
                    let model = model
                        .ok_or_else(|| bad(format!("shape node {id} names missing model {m}")))?;
                    place_model(model, &rot, &t, &mut out);
                }
            }
            None => return Err(bad(format!("scene graph names missing node {id}"))),
        }
    }
    Ok(out)
}

fn mul(a: &[[i64; 3]; 3], b: &[[i64; 3]; 3]) -> [[i64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// world cell min = R·(v − pivot) + t, shifted by −1 on flipped axes.
fn place_model(model: &Model, rot: &[[i64; 3]; 3], t: &[i64; 3], out: &mut Vec<([i64; 3], u8)>) {
    let pivot = model.size.map(|s| s / 2);
    for v in &model.voxels {
        let local: [i64; 3] = std::array::from_fn(|k| i64::from(v[k]) - pivot[k]);
        let world = std::array::from_fn(|i| {
            let s: i64 = (0..3).map(|j| rot[i][j] * local[j]).sum();
            let flipped = (0..3).any(|j| rot[i][j] < 0);
            s + t[i] - i64::from(flipped)
        });
        out.push((world, v[3]));
    }
}

/// Step 3: voxels → disjoint boxes of one colour each. A later voxel at the same cell wins.
/// Returns the boxes, their colours and the number of distinct cells.
fn merge_runs(voxels: Vec<([i64; 3], u8)>) -> (Vec<[f64; 6]>, Vec<u8>, usize) {
    let mut cells: HashMap<[i64; 3], u8> = HashMap::with_capacity(voxels.len());
    for (p, c) in voxels {
        cells.insert(p, c);
    }
    // z-runs keyed by (colour, x, y).
    let mut sorted: Vec<(u8, i64, i64, i64)> =
        cells.iter().map(|(p, &c)| (c, p[0], p[1], p[2])).collect();
    sorted.sort_unstable();
    let mut runs: Vec<(u8, i64, i64, i64, i64)> = Vec::new(); // (colour, x, z0, z1, y)
    for v in sorted {
        match runs.last_mut() {
            Some(r) if (r.0, r.1, r.4, r.3) == (v.0, v.1, v.2, v.3) => r.3 += 1,
            _ => runs.push((v.0, v.1, v.3, v.3 + 1, v.2)),
        }
    }
    // y-runs of equal z-runs, keyed by (colour, x, z0, z1).
    runs.sort_unstable();
    let mut boxes = Vec::new();
    let mut colors = Vec::new();
    for group in runs.chunk_by(|a, b| (a.0, a.1, a.2, a.3) == (b.0, b.1, b.2, b.3)) {
        let (c, x, z0, z1, _) = group[0];
        for ys in group.chunk_by(|a, b| b.4 == a.4 + 1) {
            let (y0, y1) = (ys[0].4, ys[ys.len() - 1].4 + 1);
            boxes.push([x, y0, z0, x + 1, y1, z1].map(|v| v as f64));
            colors.push(c);
        }
    }
    (boxes, colors, cells.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_take_the_palette_colour_of_their_material() {
        let boxes = [
            [0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            [1.0, 0.0, 0.0, 2.0, 1.0, 1.0],
        ];
        let brep = crate::ortho::box_union_with_materials(&boxes, &[1, 3]).unwrap();
        let mesh = brep
            .to_mesh(crate::ortho::MeshOptions::default())
            .unwrap()
            .mesh;
        let (red, green) = ([255, 0, 0, 255], [0, 255, 0, 255]);
        let painted = with_palette_colors(mesh.clone(), &[red, green]);
        let materials = painted.face_materials().unwrap();
        let expected: Vec<Rgba> = (materials.iter())
            .map(|&m| match m {
                1 => red,
                _ => [255; 4], // palette index 3 is past the two colours given
            })
            .collect();
        assert_eq!(painted.face_colors().unwrap(), &expected[..]);
        assert!(materials.contains(&1) && materials.contains(&3));
        let plain = crate::ortho::box_union(&boxes).unwrap();
        let plain = plain
            .to_mesh(crate::ortho::MeshOptions::default())
            .unwrap()
            .mesh;
        assert_eq!(with_palette_colors(plain.clone(), &[red]), plain);
    }

    /// A minimal file: one model of the given size and voxels, no palette, no scene graph.
    fn vox_bytes(size: [u32; 3], voxels: &[[u8; 4]]) -> Vec<u8> {
        let mut children = Vec::new();
        let mut chunk = |id: &[u8], content: Vec<u8>| {
            children.extend_from_slice(id);
            children.extend_from_slice(&(content.len() as u32).to_le_bytes());
            children.extend_from_slice(&0u32.to_le_bytes());
            children.extend(content);
        };
        chunk(b"SIZE", size.iter().flat_map(|s| s.to_le_bytes()).collect());
        let mut xyzi = (voxels.len() as u32).to_le_bytes().to_vec();
        xyzi.extend(voxels.iter().flatten());
        chunk(b"XYZI", xyzi);
        let mut out = b"VOX ".to_vec();
        out.extend_from_slice(&150u32.to_le_bytes());
        out.extend_from_slice(b"MAIN");
        out.extend_from_slice(&0u32.to_le_bytes());
        out.extend_from_slice(&(children.len() as u32).to_le_bytes());
        out.extend(children);
        out
    }

    #[test]
    fn runs_merge_along_z_then_y_by_colour() {
        let voxels = [
            [0, 0, 0, 1],
            [0, 0, 1, 1],
            [0, 1, 0, 1],
            [0, 1, 1, 1],
            [1, 0, 0, 2],
        ];
        let read = read_vox(&vox_bytes([2, 2, 2], &voxels), VoxOptions::default()).unwrap();
        assert_eq!(read.voxel_count, 5);
        assert_eq!(
            read.boxes,
            [
                [0.0, 0.0, 0.0, 1.0, 2.0, 2.0],
                [1.0, 0.0, 0.0, 2.0, 1.0, 1.0]
            ]
        );
        assert_eq!(read.colors, [1, 2]);
    }

    #[test]
    fn truncated_files_name_the_offset() {
        let bytes = vox_bytes([2, 2, 2], &[[0, 0, 0, 1]]);
        for cut in 0..bytes.len() {
            assert!(
                read_vox(&bytes[..cut], VoxOptions::default()).is_err(),
                "cut at {cut}"
            );
        }
        let err = read_vox(&bytes, VoxOptions { model: Some(3) }).unwrap_err();
        assert!(err.to_string().contains("model 3"));
    }

    #[test]
    fn rotation_bytes_decode_to_signed_permutations() {
        let r = Reader { bytes: &[], pos: 0 };
        assert_eq!(rotation("4", &r).unwrap(), IDENTITY);
        // Row 0 → column 1, row 1 → column 0, row 2 negative.
        assert_eq!(
            rotation(&(1 | 1 << 6).to_string(), &r).unwrap(),
            [[0, 1, 0], [1, 0, 0], [0, 0, -1]]
        );
        assert!(rotation("15", &r).is_err());
    }
}
