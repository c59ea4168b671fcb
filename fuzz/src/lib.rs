//! What the fuzz targets check, shared so that each target is one line and the regression
//! tests in `crates/csgkit/tests/fuzz_regressions.rs` replay the same checks on the inputs
//! the fuzzer found.
//!
//! A reader must return `Ok` or `Err` for any bytes, never panic, hang or exhaust memory. On
//! `Ok`, the mesh must hold its invariants, have finite coordinates, and survive a round trip
//! through its own format: written and read again it has the same faces, and (for the
//! formats that store f64 text or whose reader keeps what it read) bit-identical positions.

use std::path::Path;

use csgkit::csg::openscad::parse_openscad_csg;
use csgkit::csg::scene::parse_scene;
use csgkit::csg::{Node, flatten};
use csgkit::exact::BooleanOptions;
use csgkit::ortho::{MeshOptions, VoxOptions, box_union_mesh, parse_boxes, read_vox};
use csgkit::{
    Encoding, Format, LoadedMesh, Mesh, Progress, read_mesh_from_bytes, write_mesh_to_bytes,
};

pub mod solids;

/// Reads `data` as the format `hint` names (content that says otherwise wins, as for files)
/// and checks the result.
pub fn check_reader(data: &[u8], hint: Format) {
    let Ok(loaded) = read_mesh_from_bytes(data, Some(hint)) else {
        return;
    };
    check_loaded(&loaded);
}

/// The invariants of a mesh a reader returned, and its round trip.
pub fn check_loaded(loaded: &LoadedMesh) {
    let mesh = &loaded.mesh;
    mesh.check_invariants()
        .unwrap_or_else(|e| panic!("{} reader broke an invariant: {e}", loaded.format));
    assert!(
        mesh.positions().iter().flatten().all(|c| c.is_finite()),
        "{} reader returned a non-finite coordinate",
        loaded.format
    );
    // glTF stores f32 and applies node transforms on reading: the round trip is checked for
    // faces only. STL readers weld, so positions come back in welding order.
    let same_positions = matches!(
        loaded.format,
        Format::Obj | Format::Ply | Format::Off | Format::ThreeMf
    );
    let encoding = match loaded.format {
        // Binary STL stores f32: write what was read as text as text.
        Format::Stl => loaded.encoding,
        _ => Encoding::Binary,
    };
    let bytes = match write_mesh_to_bytes(mesh, loaded.format, encoding) {
        Ok(bytes) => bytes,
        // A polygon that cannot be triangulated exactly for a triangles-only format, or a
        // mesh too large for the format: a clear error is the contract.
        Err(_) if !mesh.is_triangle_mesh() || mesh.face_count() > u32::MAX as usize / 4 => return,
        Err(e) => panic!(
            "{} writer failed on what its reader read: {e}",
            loaded.format
        ),
    };
    let again = read_mesh_from_bytes(&bytes, Some(loaded.format)).unwrap_or_else(|e| {
        panic!(
            "{} reader rejected what its writer wrote: {e}",
            loaded.format
        )
    });
    assert_eq!(
        again.format, loaded.format,
        "written {} read back as another format",
        loaded.format
    );
    if mesh.is_triangle_mesh() || same_positions {
        assert_eq!(
            again.mesh.face_count(),
            mesh.face_count(),
            "{} round trip changed the face count; written:\n{}",
            loaded.format,
            String::from_utf8_lossy(&bytes[..bytes.len().min(4000)])
        );
    }
    if same_positions {
        assert!(
            same_bits(again.mesh.positions(), mesh.positions()),
            "{} round trip changed a position",
            loaded.format
        );
        assert_eq!(
            again.mesh.corners(),
            mesh.corners(),
            "{} round trip changed a face",
            loaded.format
        );
    }
}

fn same_bits(a: &[[f64; 3]], b: &[[f64; 3]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| (0..3).all(|k| p[k].to_bits() == q[k].to_bits()))
}

/// The invariants of a mesh the box-union engine built from `boxes`: a closed, oriented
/// solid whose volume is `volume` (the boxes' own, when they are disjoint), or nothing for
/// no boxes.
pub fn check_box_union(boxes: &[[f64; 6]], mesh: &Mesh, volume: Option<f64>) {
    if boxes.is_empty() {
        assert_eq!(mesh.face_count(), 0, "no boxes made faces");
        return;
    }
    let report = mesh.report();
    assert!(
        report.is_valid_solid(),
        "the union of {} boxes is not a valid solid",
        boxes.len()
    );
    if let Some(volume) = volume {
        let tolerance = 1e-9 * volume.abs().max(1.0);
        assert!(
            (report.measures.volume - volume).abs() <= tolerance,
            "the union of disjoint boxes has volume {} instead of {volume}",
            report.measures.volume
        );
    }
}

/// The largest box count a target unites: enough for every branch of the sweep, small enough
/// that an execution stays fast.
const MAX_FUZZ_BOXES: usize = 256;

/// A MagicaVoxel file: read, and when its boxes are few, united into a solid whose volume is
/// the number of distinct voxels.
pub fn check_vox(data: &[u8]) {
    let Ok(read) = read_vox(data, VoxOptions::default()) else {
        return;
    };
    assert_eq!(read.boxes.len(), read.colors.len(), "one colour per box");
    let cells: f64 = read
        .boxes
        .iter()
        .map(|b| (b[3] - b[0]) * (b[4] - b[1]) * (b[5] - b[2]))
        .sum();
    assert_eq!(
        cells, read.voxel_count as f64,
        "the boxes cover the voxels once each"
    );
    if read.boxes.len() <= MAX_FUZZ_BOXES {
        let materials: Vec<u32> = read.colors.iter().map(|&c| u32::from(c)).collect();
        let (out, _) = box_union_mesh(
            &read.boxes,
            Some(&materials),
            MeshOptions::default(),
            &Progress::default(),
        )
        .unwrap_or_else(|e| panic!("the boxes of a .vox file could not be united: {e}"));
        check_box_union(&read.boxes, &out.mesh, Some(cells));
    }
}

/// A box text file: parsed, and when its boxes are few, united into a solid.
pub fn check_boxes_text(data: &[u8]) {
    let Ok(boxes) = std::str::from_utf8(data)
        .map_err(drop)
        .and_then(|t| parse_boxes(t).map_err(drop))
    else {
        return;
    };
    if boxes.len() <= MAX_FUZZ_BOXES {
        // A clear error (a box that is flat or inverted, say) is allowed; a wrong solid is not.
        if let Ok((out, _)) =
            box_union_mesh(&boxes, None, MeshOptions::default(), &Progress::default())
        {
            check_box_union(&boxes, &out.mesh, None);
        }
    }
}

/// A JSON scene: parsed, and its tree flattened into leaf meshes (primitives built, files
/// named by it looked up in a folder that does not exist).
pub fn check_scene_json(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let missing = Path::new("/nonexistent-fuzz-folder");
    if let Ok(root) = parse_scene(text, Path::new("fuzz.json"), missing) {
        check_flatten(&root);
    }
}

/// An OpenSCAD `.csg` export: parsed, and its tree flattened into leaf meshes.
pub fn check_openscad_csg(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let missing = Path::new("/nonexistent-fuzz-folder");
    if let Ok(root) = parse_openscad_csg(text, missing) {
        check_flatten(&root);
    }
}

/// Flattening a parsed tree gives leaves that are valid meshes, or a clear error.
fn check_flatten(root: &Node) {
    if let Ok(flat) = flatten(root, &BooleanOptions::default(), &Progress::default()) {
        for leaf in &flat.leaves {
            leaf.check_invariants()
                .unwrap_or_else(|e| panic!("a leaf broke an invariant: {e}"));
        }
    }
}
