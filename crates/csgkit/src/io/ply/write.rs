//! The PLY writer.

use super::{CHANNELS, SOURCE_FACE, SOURCE_OPERAND};
use crate::io::Encoding;
use crate::mesh::Mesh;

/// Appends `mesh` as PLY (binary little-endian or ASCII) to `out`.
pub(crate) fn write(mesh: &Mesh, encoding: Encoding, out: &mut Vec<u8>) {
    let ascii = encoding == Encoding::Ascii;
    let wide = mesh.faces().any(|f| f.len() > 255);
    write_header(mesh, ascii, wide, out);
    let mut w = Writer {
        out,
        ascii,
        f: ryu::Buffer::new(),
        int: itoa::Buffer::new(),
    };
    let colors = mesh.vertex_colors();
    for (v, p) in mesh.positions().iter().enumerate() {
        for (k, &c) in p.iter().enumerate() {
            w.double(c, k == 0);
        }
        for &c in colors.map(|c| &c[v][..]).unwrap_or_default() {
            w.uint(u32::from(c), 1, false);
        }
        w.end();
    }
    for (face, corners) in mesh.faces().enumerate() {
        w.uint(corners.len() as u32, if wide { 4 } else { 1 }, true);
        for &v in corners {
            w.uint(v, 4, false);
        }
        if let Some(materials) = mesh.face_materials() {
            w.uint(materials[face], 4, false);
        }
        for &c in mesh.face_colors().map(|c| &c[face][..]).unwrap_or_default() {
            w.uint(u32::from(c), 1, false);
        }
        if let Some(provenance) = mesh.face_provenance() {
            w.uint(provenance[face].operand.get(), 4, false);
            w.uint(provenance[face].face.get(), 4, false);
        }
        w.end();
    }
}

fn write_header(mesh: &Mesh, ascii: bool, wide: bool, out: &mut Vec<u8>) {
    let mut h = String::from("ply\n");
    h += if ascii {
        "format ascii 1.0\n"
    } else {
        "format binary_little_endian 1.0\n"
    };
    h += "comment written by csgkit\n";
    h += &format!("element vertex {}\n", mesh.vertex_count());
    h += "property double x\nproperty double y\nproperty double z\n";
    let channels = |h: &mut String| {
        CHANNELS
            .iter()
            .for_each(|c| *h += &format!("property uchar {c}\n"))
    };
    if mesh.vertex_colors().is_some() {
        channels(&mut h);
    }
    h += &format!("element face {}\n", mesh.face_count());
    h += if wide {
        "property list uint int vertex_indices\n"
    } else {
        "property list uchar int vertex_indices\n"
    };
    if mesh.face_materials().is_some() {
        h += "property int material_index\n";
    }
    if mesh.face_colors().is_some() {
        channels(&mut h);
    }
    if mesh.face_provenance().is_some() {
        h += &format!("property int {SOURCE_OPERAND}\nproperty int {SOURCE_FACE}\n");
    }
    h += "end_header\n";
    out.extend_from_slice(h.as_bytes());
}

/// Writes values as little-endian binary or as space-separated ASCII lines.
struct Writer<'a> {
    out: &'a mut Vec<u8>,
    ascii: bool,
    f: ryu::Buffer,
    int: itoa::Buffer,
}

impl Writer<'_> {
    fn separate(&mut self, first: bool) {
        if self.ascii && !first {
            self.out.push(b' ');
        }
    }

    fn double(&mut self, value: f64, first: bool) {
        self.separate(first);
        if self.ascii {
            self.out.extend_from_slice(self.f.format(value).as_bytes());
        } else {
            self.out.extend_from_slice(&value.to_le_bytes());
        }
    }

    /// Writes `value` as a `width`-byte integer (1 or 4) in binary.
    fn uint(&mut self, value: u32, width: usize, first: bool) {
        self.separate(first);
        if self.ascii {
            self.out
                .extend_from_slice(self.int.format(value).as_bytes());
        } else {
            self.out.extend_from_slice(&value.to_le_bytes()[..width]);
        }
    }

    fn end(&mut self) {
        if self.ascii {
            self.out.push(b'\n');
        }
    }
}
