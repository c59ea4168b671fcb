//! The orthogonal engine: the exact boundary of a union of axis-aligned boxes.
//!
//! Implements the method of López Monterde, Martínez, Vigo and Pla, "A practical and robust
//! method to compute the boundary of three-dimensional axis-aligned boxes", as specified and
//! corrected in `design/ortho.md` (the design note beside the code is the reference).
//!
//! # Contract
//! In: boxes `[x0, y0, z0, x1, y1, z1]` (f64, bounds of an axis in either order, any box
//! order, duplicates allowed); boxes of zero thickness are dropped and counted, non-finite
//! coordinates are an error. The solid is the regularised union (the closure of the union of
//! the interiors).
//! Out: a [`BRep`] — every boundary vertex with its octant code and six face degrees, and
//! every maximal planar face with one CCW outer loop and its CW hole loops (CCW seen from
//! outside) — which [`BRep::to_mesh`] turns into a closed, T-junction-free [`Mesh`].
//!
//! # Algorithm
//! 1. Rank the coordinates of each axis (`grid`); from here to triangulation only ranks are
//!    compared.
//! 2. Sweep z-planes in parallel; on each, scan the slabs below and above at once and
//!    classify every candidate point by its 8-bit octant code (`sweep`, `rect2d`, §A3–A4).
//! 3. Link the vertices into loops per face plane and assign holes (`brep`, §A5).
//! 4. Triangulate faces with holes without adding or dropping a boundary vertex, with exact
//!    predicates (`triangulate`, §A6), and index vertices by exact position.
//! 5. Optionally split non-manifold edges and vertices into a 2-manifold (`manifold`, §A6).
//!
//! # Variants and inputs
//! - [`box_union_with_materials`] gives each face the material of the box behind it
//!   (`materials`); [`box_union_per_material`] builds one solid per material.
//! - [`box_union_timed`] reports stage times and progress, and can be cancelled, through the
//!   crate's one [`Progress`] context.
//! - [`box_union_vertices`] gives the vertices under any [`DegreeConvention`], including the
//!   paper's; [`rect_union_corners`] is the 2D algorithm alone.
//! - [`parse_boxes`] reads the box text format, [`read_vox`] MagicaVoxel files.
//!
//! # Mesh output
//! [`Mesh`] holds simple polygons only, so [`BRep::to_mesh`] writes a face without
//! holes as one polygon and triangulates a face with holes (or a weakly simple outer loop);
//! [`BRep`] itself is the polygon-with-holes representation, for writers that can hold holes.
//!
//! # Numeric model
//! Steps 1–3 only compare input coordinates: they are exact for every finite f64. Step 4 uses
//! the exact orientation predicates of `spade` (Shewchuk's, through `robust`) on the input
//! coordinates and creates no coordinate; spade accepts absolute values up to 2^201 and
//! nonzero ones down to 2^-142, so a face's coordinates are first multiplied by a power of two
//! (exactly) when they lie outside; a face whose nonzero magnitudes span more than 2^342 is
//! reported as [`OrthoError::Triangulation`].
//!
//! # Complexity
//! Σ_planes O(m_k log m_k + runs) for the sweep, O(E log E) for the loops, and the
//! triangulation O(n log n) per face; the worst case is Θ(n³), the worst-case output size.

mod box_file;
mod boxes_text;
mod brep;
mod coverage;
mod grid;
mod manifold;
mod materials;
mod octant;
mod random;
mod rect2d;
mod sweep;
mod triangulate;
mod vox;

pub use box_file::{BoxFile, BoxFileError, read_box_file};
pub use boxes_text::{BoxesTextError, parse_boxes};
pub use brep::Orientation;
pub use octant::{DegreeConvention, OCTANT_TABLE, OctantInfo};
pub use random::random_grid_boxes;
pub use triangulate::{MeshOptions, MeshOutput, per_material_mesh};
pub use vox::{VoxBoxes, VoxOptions, read_vox, with_palette_colors};

use crate::par::*;
use grid::RankedBoxes;

use crate::mesh::{Mesh, analyze_topology, measure};
use crate::progress::{Cancelled, Progress, Stage, StageClock};

/// Why a box union failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OrthoError {
    /// A box has a NaN or infinite coordinate.
    ///
    /// *How to fix:* drop or repair the box; only finite coordinates describe a box.
    #[error("box {index} has a non-finite coordinate")]
    NonFinite {
        /// The box's index in the input.
        index: usize,
    },
    /// The vertex degrees do not describe a closed orthogonal boundary. The sweep never
    /// produces this; it signals a broken invariant.
    #[error("inconsistent vertex degrees on a {orientation:?} face plane: {reason}")]
    InconsistentDegrees {
        /// The face orientation being linked.
        orientation: Orientation,
        /// What went wrong.
        reason: &'static str,
    },
    /// A `.vox` file is malformed.
    #[error("malformed .vox data at byte {offset}: {reason}")]
    Vox {
        /// The byte offset in the file.
        offset: usize,
        /// What is wrong.
        reason: String,
    },
    /// The material list does not have one entry per box.
    #[error("{materials} materials given for {boxes} boxes")]
    MaterialCount {
        /// The number of boxes.
        boxes: usize,
        /// The number of materials.
        materials: usize,
    },
    /// A [`BRep`] given to [`BRep::to_mesh`] breaks its invariants (its fields are public, so
    /// a caller may have edited it).
    #[error("invalid B-rep: {reason}")]
    InvalidBRep {
        /// The first broken invariant, from [`BRep::check_invariants`].
        reason: String,
    },
    /// The run was cancelled through its [`Progress`].
    #[error(transparent)]
    Cancelled(#[from] Cancelled),
    /// The triangulation of a face failed, e.g. for coordinates spanning more binades than
    /// spade's range.
    #[error("face {face} cannot be triangulated: {reason}")]
    Triangulation {
        /// The face's index in the B-rep.
        face: usize,
        /// What went wrong.
        reason: String,
    },
}

/// A boundary vertex of the union.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BRepVertex {
    /// The position, made of input coordinates.
    pub position: [f64; 3],
    /// The octant code: bit `sx | sy << 1 | sz << 2` set iff that open octant is inside.
    pub code: u8,
    /// Face degrees in the order +x, −x, +y, −y, +z, −z (see [`DegreeConvention`]).
    pub degrees: [u8; 6],
}

/// A maximal planar face of the boundary.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Face {
    /// The outward normal.
    pub orientation: Orientation,
    /// The material of the solid behind the face (0 without materials).
    pub material: u32,
    /// Vertex indices of the outer loop, CCW seen from outside. It may be weakly simple,
    /// visiting a pinch vertex twice (a hole touching the outer boundary at a point).
    pub outer: Vec<u32>,
    /// Vertex indices of each hole loop, CW seen from outside.
    pub holes: Vec<Vec<u32>>,
}

/// The exact boundary representation of a union of boxes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BRep {
    /// Boundary vertices, sorted by (z, y, x).
    pub vertices: Vec<BRepVertex>,
    /// Faces, by orientation (+x, −x, +y, −y, +z, −z), then plane.
    pub faces: Vec<Face>,
    /// Input boxes dropped for zero thickness.
    pub dropped_boxes: usize,
    /// Whether faces carry the materials of their boxes ([`box_union_with_materials`]).
    pub has_materials: bool,
}

/// Computes the vertices of the union of `boxes` with their octant codes and degrees, sorted
/// by (z, y, x): steps 1–2 of the module docs.
///
/// # Errors
/// [`OrthoError::NonFinite`] naming the first box with a non-finite coordinate.
pub fn box_union_vertices(
    boxes: &[[f64; 6]],
    convention: DegreeConvention,
) -> Result<Vec<BRepVertex>, OrthoError> {
    let ranked = RankedBoxes::new(boxes)?;
    let progress = Progress::default();
    let counter = progress.counter(Stage::Sweep, ranked.coords[2].len());
    Ok(sweep::sweep_vertices(&ranked, convention, &counter)
        .into_iter()
        .map(|v| BRepVertex {
            position: ranked.position(v.rank),
            code: v.code,
            degrees: v.degrees,
        })
        .collect())
}

/// The box `[x0, y0, z0, x1, y1, z1]` of `mesh` where the orthogonal engine can take it as a
/// box and lose nothing: its eight corners bound that box ([`bounded_box`]) and it carries no
/// face, corner or vertex attribute (material, group, colour, UV, normal), which the box's
/// faces, merged into maximal faces, would not keep. The test of the engine facade's operands
/// and of CSG trees' box leaves.
pub fn plain_box(mesh: &Mesh) -> Option<[f64; 6]> {
    let parts = mesh.parts();
    let bare = mesh.vertex_count() == 8
        && parts.face_materials.is_none()
        && parts.face_groups.is_none()
        && parts.face_colors.is_none()
        && parts.corner_uvs.is_none()
        && parts.corner_normals.is_none()
        && parts.vertex_colors.is_none();
    bare.then(|| bounded_box(mesh)).flatten()
}

/// The box `[x0, y0, z0, x1, y1, z1]` that `mesh` bounds, if it bounds one: every face lies
/// in a plane of its bounding box and the surface is closed with positive volume, so it covers
/// the box a whole number of times (the orthogonal engine's operands, and the box leaves of CSG
/// trees). The decisions are comparisons of input coordinates, and the count of
/// times the surface covers the box, an integer, is the volume over the box's volume rounded
/// to the nearest one; f64 sums of a box's faces are far closer than ½ to it.
pub fn bounded_box(mesh: &Mesh) -> Option<[f64; 6]> {
    let measures = measure(mesh);
    let bbox = measures.bbox?;
    let (min, max) = (bbox.min, bbox.max);
    let in_a_plane = |face: &[u32]| {
        (0..3).any(|k| {
            [min[k], max[k]].iter().any(|&plane| {
                face.iter()
                    .all(|&v| mesh.positions()[v as usize][k] == plane)
            })
        })
    };
    let box_volume = (0..3).map(|k| max[k] - min[k]).product::<f64>();
    let covers = (measures.volume / box_volume).round();
    let is_box = box_volume > 0.0
        && mesh.faces().all(in_a_plane)
        && analyze_topology(mesh).is_closed()
        && covers >= 1.0;
    is_box.then_some([min[0], min[1], min[2], max[0], max[1], max[2]])
}

/// Computes the B-rep of the union of `boxes` (conforming degrees): steps 1–3.
///
/// # Errors
/// [`OrthoError::NonFinite`] naming the first box with a non-finite coordinate.
pub fn box_union(boxes: &[[f64; 6]]) -> Result<BRep, OrthoError> {
    box_union_timed(boxes, None, &Progress::default()).map(|(brep, _)| brep)
}

/// [`box_union`] (`materials: None`) or [`box_union_with_materials`], with the seconds of
/// each stage ([`Stage::Rank`], [`Stage::Sweep`], [`Stage::Loops`]), reporting every z-plane
/// swept and every face plane linked to `progress`, which can cancel the run.
///
/// # Errors
/// As [`box_union_with_materials`], and [`OrthoError::Cancelled`] once `progress` is
/// cancelled.
pub fn box_union_timed(
    boxes: &[[f64; 6]],
    materials: Option<&[u32]>,
    progress: &Progress,
) -> Result<(BRep, Vec<(Stage, f64)>), OrthoError> {
    // A few boxes (a Menger sponge's bars before the exact engine meets them) run on this
    // thread, as a small exact boolean does: their loops are too short to pay for handing
    // jobs to the pool, and where other processes keep both cores busy each hand-over waits
    // for a worker to be scheduled.
    crate::par::on_pool_or_inline(BOX_SIZE * boxes.len(), || {
        sweep_and_link(boxes, materials, progress)
    })
}

/// The size of one box in [`crate::par::on_pool_or_inline`]'s unit (input faces of the exact
/// engine), so that a union of up to 32 boxes runs inline. Fresh CLI runs, op medians of 11
/// to 15 interleaved runs (pool → inline): Menger level 1 (3 boxes, then the exact
/// difference) 1.33 → 1.15 ms, and with two other processes keeping both cores busy 3.3 →
/// 0.88 ms (level 2, 30 boxes: 37.7 → 14.9). At 12 per box (a box's triangles), level 3's
/// 273 boxes ran inline too, and its op went 84 → 90 ms: the union's own stages took the
/// same time, the exact stages after it (on the pool) longer.
const BOX_SIZE: usize = 128;

/// [`box_union_timed`]'s stages, on the thread [`crate::par::on_pool_or_inline`] chose.
fn sweep_and_link(
    boxes: &[[f64; 6]],
    materials: Option<&[u32]>,
    progress: &Progress,
) -> Result<(BRep, Vec<(Stage, f64)>), OrthoError> {
    let mut clock = StageClock::new(progress);
    let ranked = RankedBoxes::with_materials(boxes, materials)?;
    clock.end(Stage::Rank)?;
    let counter = progress.counter(Stage::Sweep, ranked.coords[2].len());
    let (vertices, corners) = match materials {
        None => (
            sweep::sweep_vertices(&ranked, DegreeConvention::Conforming, &counter),
            None,
        ),
        Some(_) => {
            let (v, c) = materials::sweep_material_vertices(&ranked, &counter);
            (v, Some(c))
        }
    };
    counter.finish()?;
    clock.record(Stage::Sweep);
    let faces = brep::extract_faces(&vertices, corners.as_deref(), progress)?;
    let brep = assemble(&ranked, &vertices, faces, materials.is_some());
    clock.record(Stage::Loops);
    Ok((brep, clock.into_seconds()))
}

/// [`box_union_timed`], then the B-rep as a mesh ([`BRep::to_mesh`] with `options`), timed
/// and reported as [`Stage::Triangulate`]: the orthogonal engine from boxes to a mesh, as
/// the engine facade's `OrthoEngine` and the Python package's `boxes` run it.
///
/// # Errors
/// As [`box_union_timed`] and [`BRep::to_mesh`].
pub fn box_union_mesh(
    boxes: &[[f64; 6]],
    materials: Option<&[u32]>,
    options: MeshOptions,
    progress: &Progress,
) -> Result<(MeshOutput, Vec<(Stage, f64)>), OrthoError> {
    // One entry for the whole run, the union and its mesh: a run on the pool is handed over
    // once, as the exact boolean is.
    crate::par::on_pool_or_inline(BOX_SIZE * boxes.len(), || {
        let (brep, mut stage_seconds) = sweep_and_link(boxes, materials, progress)?;
        let mut clock = StageClock::new(progress);
        let out = brep.to_mesh(options)?;
        clock.end(Stage::Triangulate)?;
        stage_seconds.extend(clock.into_seconds());
        Ok((out, stage_seconds))
    })
}

/// Computes the B-rep of the union of `boxes`, box `i` being made of material
/// `materials[i]`: each face takes the material of the box behind it (the smallest id where
/// boxes of different materials overlap), faces are maximal per material, and interfaces
/// between materials inside the union are not faces (`materials` stage).
///
/// # Errors
/// [`OrthoError::NonFinite`], or [`OrthoError::MaterialCount`] if the lengths differ.
pub fn box_union_with_materials(boxes: &[[f64; 6]], materials: &[u32]) -> Result<BRep, OrthoError> {
    box_union_timed(boxes, Some(materials), &Progress::default()).map(|(brep, _)| brep)
}

/// Computes one B-rep per material, each the union of that material's boxes alone, in
/// increasing material order: where two materials touch, both solids have a face, with
/// opposite orientations.
///
/// # Errors
/// [`OrthoError::NonFinite`], or [`OrthoError::MaterialCount`] if the lengths differ.
pub fn box_union_per_material(
    boxes: &[[f64; 6]],
    materials: &[u32],
) -> Result<Vec<(u32, BRep)>, OrthoError> {
    if materials.len() != boxes.len() {
        return Err(OrthoError::MaterialCount {
            boxes: boxes.len(),
            materials: materials.len(),
        });
    }
    let mut ids: Vec<u32> = materials.to_vec();
    ids.sort_unstable();
    ids.dedup();
    ids.into_iter()
        .map(|m| {
            let own: Vec<[f64; 6]> = boxes
                .iter()
                .zip(materials)
                .filter(|&(_, &b)| b == m)
                .map(|(b, _)| *b)
                .collect();
            let mut brep = box_union(&own)?;
            brep.has_materials = true;
            brep.faces.iter_mut().for_each(|f| f.material = m);
            Ok((m, brep))
        })
        .collect()
}

/// Maps ranks back to positions and builds the [`BRep`].
fn assemble(
    ranked: &RankedBoxes,
    vertices: &[sweep::RankVertex],
    faces: Vec<(Orientation, brep::PlaneFace)>,
    has_materials: bool,
) -> BRep {
    let brep = BRep {
        vertices: vertices
            .par_iter()
            .map(|v| BRepVertex {
                position: ranked.position(v.rank),
                code: v.code,
                degrees: v.degrees,
            })
            .collect(),
        faces: faces
            .into_par_iter()
            .map(|(orientation, f)| Face {
                orientation,
                material: f.material,
                outer: f.outer,
                holes: f.holes,
            })
            .collect(),
        dropped_boxes: ranked.dropped,
        has_materials,
    };
    debug_assert_eq!(brep.check_invariants(), Ok(()));
    brep
}

/// A 2D corner record of a union of rectangles (§A3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectCorner {
    /// The corner's position.
    pub position: [f64; 2],
    /// The outward normals of its two boundary edges, as flags (+x, −x, +y, −y).
    pub dirs: [bool; 4],
}

/// The corners of the union of rectangles `[x0, y0, x1, y1]`, in (y, x) order (§A3). A pinch
/// point (two diagonal quadrants) gives two records.
///
/// # Errors
/// [`OrthoError::NonFinite`] naming the first rectangle with a non-finite coordinate.
pub fn rect_union_corners(rects: &[[f64; 4]]) -> Result<Vec<RectCorner>, OrthoError> {
    let boxes: Vec<[f64; 6]> = rects
        .iter()
        .map(|r| [r[0], r[1], 0.0, r[2], r[3], 1.0])
        .collect();
    let ranked = RankedBoxes::new(&boxes)?;
    let rects: Vec<rect2d::Rect> = ranked
        .boxes
        .iter()
        .map(|b| rect2d::Rect {
            x0: b[0],
            x1: b[3],
            y0: b[1],
            y1: b[4],
        })
        .collect();
    let mut out = Vec::new();
    rect2d::plane_scan(&[], &rects, |x, y, code| {
        let position = ranked.position([x, y, 0]);
        for dirs in rect2d::corner_records(code >> 4) {
            out.push(RectCorner {
                position: [position[0], position[1]],
                dirs,
            });
        }
    });
    Ok(out)
}

impl BRep {
    /// Checks the structural invariants: every loop index is a vertex, every loop has at least
    /// four positions and alternates axis-parallel edges lying in its face's plane.
    ///
    /// # Errors
    /// A description of the first broken invariant.
    pub fn check_invariants(&self) -> Result<(), String> {
        // Faces are independent; `find_map_first` reports the first broken face.
        match self
            .faces
            .par_iter()
            .enumerate()
            .find_map_first(|(f, face)| self.face_invariant(face).map(|e| format!("face {f} {e}")))
        {
            Some(reason) => Err(reason),
            None => Ok(()),
        }
    }

    /// The first broken invariant of one face, completing "face {f} …".
    fn face_invariant(&self, face: &Face) -> Option<String> {
        let k = face.orientation.axis();
        for lp in std::iter::once(&face.outer).chain(&face.holes) {
            if lp.len() < 4 {
                return Some(format!("has a loop of {} positions", lp.len()));
            }
            if lp.iter().any(|&v| v as usize >= self.vertices.len()) {
                return Some("refers to a missing vertex".into());
            }
            let position = |v: u32| self.vertices[v as usize].position;
            let mut prev = position(lp[lp.len() - 1]);
            for &v in lp {
                let p = position(v);
                let differ = (0..3).filter(|&j| p[j] != prev[j]).count();
                if p[k] != prev[k] || differ != 1 {
                    return Some("has a loop edge that is not axis-parallel in its plane".into());
                }
                prev = p;
            }
        }
        None
    }
}
