//! The **reconstruct** stage (`design/exact.md`, stage 9), on exact points: which output face
//! every kept sub-triangle belongs to, and the removal of the vertices no face needs.
//!
//! # Faces
//! A kept sub-triangle belongs to the face of its input face: the sub-triangles of one
//! original polygon, however the split cut them, make one output face again. The polygons
//! themselves are traced after rounding and certification, by
//! [`merge_faces`](crate::mesh::merge_faces), from the provenance this stage writes. Two
//! things join faces further:
//! - **composition**: faces of an operand that share a provenance (the result of an earlier
//!   boolean, whose faces name the original face they lie on) are one face, so a chain of
//!   operations merges back what earlier steps split;
//! - **coplanar merging** (`BooleanOptions::merge_coplanar`, off by default): two faces that
//!   share an edge, lie exactly in one plane (exact `orient3d` of their input triangles) and
//!   have the same material, group and colour, and no corner attributes (UVs and normals are
//!   defined per source face), are one face.
//!
//! Every sub-triangle of a joined face records the provenance of its lowest member.
//!
//! # Vertices
//! An intersection point is needed where three or more faces meet, or where the boundary
//! between two faces turns. One that lies on a straight stretch of the boundary between
//! exactly two faces (where a curve crossed an input edge or a polygon diagonal that no
//! longer bounds anything), or inside one face, is not: it is removed by collapsing it onto a
//! neighbour along that boundary (any neighbour, inside a face), which replaces its fan in
//! each face by a fan from that neighbour. Every decision is exact:
//! - collinearity of the point and its two boundary neighbours is three projected
//!   orientations of the exact points, and the point must lie between them;
//! - a fan is replaced only where its input triangles are coplanar (exact `orient3d`);
//! - every new triangle must turn like its input triangle in that triangle's projection
//!   (exact `orient2d`); then the new fan tiles the old one exactly (its winding number is one
//!   on the old fan, and no triangle is negative).
//!
//! So the new triangles are part of an exact tiling of the result like the arrangement's own:
//! where all their corners are f64 numbers they cross nothing, and where one is rounded, that
//! corner is marked for certification like any rounded point. They need no check of their own.
//!
//! Of the two neighbours, the collapse keeps the fan whose worst triangle is fattest (an f64
//! shape measure: a choice, not a decision), so needles are avoided where there is a choice.
//! Input vertices are removed only with coplanar merging, where faces from different sources
//! join (27 touching cubes become one cube of 8 corners); otherwise a face that nothing cut
//! keeps its corners.
//!
//! # Complexity
//! Only sub-triangles of split input triangles hold intersection points, so removal looks at
//! those alone, in time linear in their number. Coplanar merging looks at every edge of the
//! kept sub-triangles once.

use crate::par::*;
use rustc_hash::FxHashMap;

use crate::kernel::{Axis, Point, Sign, approx_point, compare_along, orient2d_projected, orient3d};
use crate::mesh::numbering::FaceNumbering;
use crate::mesh::union_find::UnionFind;
use crate::mesh::vector::triangle_shape;
use crate::mesh::{FaceId, Mesh, OperandId, Provenance};

use super::ingest::Input;
use super::select::Kept;
use super::star::{self, Collapse};
use super::subdivide::Arrangement;

/// The kept sub-triangles after reconstruction.
pub(crate) struct Reconstructed {
    /// Triangles over arrangement vertex ids, oriented as in the result.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: the provenance of the face it belongs to.
    pub provenance: Vec<Provenance>,
    /// Per triangle: the input triangle it lies in (whose plane assemble rounds against).
    pub source: Vec<u32>,
    /// Intersection points removed.
    pub removed_vertices: usize,
}

/// What the stage does beyond grouping by source face.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Options {
    /// Join coplanar neighbouring faces that look alike.
    pub merge_coplanar: bool,
    /// Remove the intersection points no face needs.
    pub remove_vertices: bool,
}

/// Reconstructs the faces of `kept` (see the module docs). `operands` are the meshes the
/// input was made from, for their provenance and face attributes.
pub(crate) fn reconstruct(
    input: &Input,
    arr: &Arrangement,
    kept: &Kept,
    operands: &[&Mesh],
    options: Options,
) -> Reconstructed {
    let triangles: Vec<[u32; 3]> = (kept.par_iter())
        .map(|&(s, reverse)| {
            let [a, b, c] = arr.triangles[s as usize];
            if reverse { [a, c, b] } else { [a, b, c] }
        })
        .collect();
    let source: Vec<u32> = (kept.par_iter())
        .map(|&(s, _)| arr.source[s as usize])
        .collect();
    let mut faces = FaceGroups::new(input, operands);
    if options.merge_coplanar {
        faces.join_coplanar(input, operands, &triangles, &source);
    }
    // Joining faces across sources can leave input vertices that no face needs.
    let first = if options.merge_coplanar {
        0
    } else {
        input.positions.len() as u32
    };
    let mut fans = Fans::new(input, arr, kept, &triangles, &source, &mut faces, first);
    let removed_vertices = if options.remove_vertices {
        fans.remove_unneeded(input, arr)
    } else {
        0
    };

    // The kept sub-triangles the removal replaced, in order: the others close up over them
    // in place (on two 1 M spheres, copies of all 1.3 M took 13–15 ms of this stage's 31–36).
    let mut replaced: Vec<u32> = (fans.origin.iter().zip(&fans.alive))
        .filter_map(|(&origin, &alive)| origin.filter(|_| !alive))
        .collect();
    replaced.sort_unstable();
    replaced.dedup();
    let (mut out_triangles, mut out_source) = (triangles, source);
    if let Some(&first) = replaced.first() {
        let mut write = first as usize;
        let mut next_replaced = replaced.iter().peekable();
        for k in first as usize..out_triangles.len() {
            if next_replaced.next_if(|&&r| r as usize == k).is_none() {
                out_triangles[write] = out_triangles[k];
                out_source[write] = out_source[k];
                write += 1;
            }
        }
        out_triangles.truncate(write);
        out_source.truncate(write);
    }
    for l in 0..fans.triangles.len() {
        if fans.alive[l] && fans.origin[l].is_none() {
            out_triangles.push(fans.triangles[l]);
            out_source.push(fans.source[l]);
        }
    }
    let roots = faces.roots();
    let provenance = (out_source.par_iter())
        .map(|&t| faces.provenance(input, roots.as_deref(), t))
        .collect();
    Reconstructed {
        triangles: out_triangles,
        provenance,
        source: out_source,
        removed_vertices,
    }
}

/// Which output face every input triangle's sub-triangles belong to.
struct FaceGroups {
    /// The source faces, numbered densely.
    numbering: FaceNumbering,
    /// Per dense face id: its group, where faces were joined (roots are the lowest member,
    /// whose provenance the group records); `None` while every face is its own group.
    groups: Option<UnionFind>,
}

impl FaceGroups {
    /// One group per input face, joined where an operand's faces share a provenance.
    fn new(input: &Input, operands: &[&Mesh]) -> Self {
        debug_assert_eq!(input.operand_count(), operands.len());
        let mut faces = Self {
            numbering: FaceNumbering::new(operands),
            groups: None,
        };
        for (k, mesh) in operands.iter().enumerate() {
            let Some(provenance) = mesh.face_provenance() else {
                continue;
            };
            let mut first: FxHashMap<Provenance, u32> = FxHashMap::default();
            for (f, p) in provenance.iter().enumerate() {
                let id = faces.numbering.id(k, FaceId::new(f));
                let root = *first.entry(*p).or_insert(id);
                if root != id {
                    faces.join(root, id);
                }
            }
        }
        faces
    }

    fn join(&mut self, a: u32, b: u32) {
        let total = self.numbering.total() as usize;
        (self.groups.get_or_insert_with(|| UnionFind::new(total))).union(a, b);
    }

    /// The dense id of input triangle `t`'s face.
    fn face(&self, input: &Input, t: u32) -> u32 {
        self.numbering.of(source_face(input, t))
    }

    /// The group of input triangle `t`.
    fn group(&mut self, input: &Input, t: u32) -> u32 {
        let face = self.face(input, t);
        match self.groups.as_mut() {
            Some(groups) => groups.find(face),
            None => face,
        }
    }

    /// Every dense face's group, if faces were joined.
    fn roots(&mut self) -> Option<Vec<u32>> {
        let total = self.numbering.total();
        let groups = self.groups.as_mut()?;
        Some((0..total).map(|f| groups.find(f)).collect())
    }

    /// The provenance of input triangle `t`'s group (that of its lowest member face), given
    /// the [`roots`](Self::roots).
    fn provenance(&self, input: &Input, roots: Option<&[u32]>, t: u32) -> Provenance {
        let face = self.face(input, t);
        self.numbering
            .provenance(roots.map_or(face, |roots| roots[face as usize]))
    }

    /// Joins the groups of faces that share an edge, lie in one plane and look alike (see
    /// the module docs).
    fn join_coplanar(
        &mut self,
        input: &Input,
        operands: &[&Mesh],
        triangles: &[[u32; 3]],
        source: &[u32],
    ) {
        for (k, l) in star::side_neighbours(triangles) {
            let (s, t) = (source[k as usize], source[l as usize]);
            let (g, h) = (self.group(input, s), self.group(input, t));
            let alike = faces_look_alike(operands, source_face(input, s), source_face(input, t));
            if g != h && alike && coplanar(input, s, t) {
                self.join(g, h);
            }
        }
    }
}

/// Whether source faces `p` and `q` have the same material, group and colour names or
/// values, and neither operand has corner attributes (UVs and normals are defined per source
/// face, so faces that have them are never joined).
pub(crate) fn faces_look_alike(operands: &[&Mesh], p: Provenance, q: Provenance) -> bool {
    let side = |p: Provenance| (operands[p.operand.index()], p.face.index());
    let ((m, f), (n, g)) = (side(p), side(q));
    let corner_free = |mesh: &Mesh| mesh.corner_uvs().is_none() && mesh.corner_normals().is_none();
    fn material(mesh: &Mesh, f: usize) -> Option<&str> {
        (mesh.face_materials()).map(|ids| mesh.materials()[ids[f] as usize].as_str())
    }
    fn group(mesh: &Mesh, f: usize) -> Option<&str> {
        (mesh.face_groups()).map(|ids| mesh.groups()[ids[f] as usize].as_str())
    }
    let colour = |mesh: &Mesh, f: usize| mesh.face_colors().map(|c| c[f]);
    corner_free(m)
        && corner_free(n)
        && material(m, f) == material(n, g)
        && group(m, f) == group(n, g)
        && colour(m, f) == colour(n, g)
}

/// The source face of input triangle `t`.
fn source_face(input: &Input, t: u32) -> Provenance {
    Provenance {
        operand: OperandId::new(input.operand[t as usize] as usize),
        face: input.face[t as usize],
    }
}

/// Whether input triangles `s` and `t` lie in one plane, exactly.
fn coplanar(input: &Input, s: u32, t: u32) -> bool {
    let [a, b, c] = input.triangle_positions(s as usize);
    (input.triangle_positions(t as usize))
        .into_iter()
        .all(|d| orient3d(a, b, c, d) == Sign::Zero)
}

/// The kept sub-triangles around intersection points, with the fans of those points, as the
/// removal edits them.
struct Fans {
    /// Triangles over arrangement vertex ids, oriented as in the result.
    triangles: Vec<[u32; 3]>,
    /// Per triangle: its input triangle.
    source: Vec<u32>,
    /// Per triangle: whether it faces against its input triangle.
    reversed: Vec<bool>,
    /// Per triangle: its face group.
    group: Vec<u32>,
    /// Per triangle: whether it is still in the result.
    alive: Vec<bool>,
    /// Per triangle: its index among the kept sub-triangles, or `None` for a triangle the
    /// removal made.
    origin: Vec<Option<u32>>,
    /// The lowest vertex id that may be removed: the first intersection point, or 0 when
    /// faces are merged across sources (coplanar merging), where input vertices inside a
    /// merged face or on a straight stretch of its boundary are not needed either.
    first: u32,
    /// Per removable vertex (vertex id minus `first`): the triangles that use it, dead ones
    /// included.
    incident: Vec<Vec<u32>>,
}

impl Fans {
    /// The kept sub-triangles that use a vertex from `first` on (with intersection points
    /// only, those of split input triangles).
    fn new(
        input: &Input,
        arr: &Arrangement,
        kept: &Kept,
        triangles: &[[u32; 3]],
        source: &[u32],
        faces: &mut FaceGroups,
        first: u32,
    ) -> Self {
        let mut fans = Fans {
            triangles: Vec::new(),
            source: Vec::new(),
            reversed: Vec::new(),
            group: Vec::new(),
            alive: Vec::new(),
            origin: Vec::new(),
            first,
            incident: vec![Vec::new(); arr.vertex_count(input) - first as usize],
        };
        let around: Vec<usize> = (0..triangles.len())
            .into_par_iter()
            .filter(|&k| triangles[k].iter().any(|&v| v >= first))
            .collect();
        for k in around {
            let t = triangles[k];
            let group = faces.group(input, source[k]);
            fans.push(t, source[k], kept[k].1, group, Some(k as u32));
        }
        fans
    }

    fn push(&mut self, t: [u32; 3], source: u32, reversed: bool, group: u32, origin: Option<u32>) {
        let l = self.triangles.len() as u32;
        self.triangles.push(t);
        self.source.push(source);
        self.reversed.push(reversed);
        self.group.push(group);
        self.alive.push(true);
        self.origin.push(origin);
        for v in t {
            if let Some(p) = v.checked_sub(self.first) {
                self.incident[p as usize].push(l);
            }
        }
    }

    /// Removes every vertex from `first` on that no face needs, in vertex order; returns how
    /// many.
    fn remove_unneeded(&mut self, input: &Input, arr: &Arrangement) -> usize {
        let mut removed = 0;
        for v in self.first..arr.vertex_count(input) as u32 {
            if self.remove(input, arr, v) {
                removed += 1;
            }
        }
        removed
    }

    /// Removes vertex `v` if no face needs it (see the module docs); whether it did.
    fn remove(&mut self, input: &Input, arr: &Arrangement, v: u32) -> bool {
        let fan: Vec<u32> = (self.incident[(v - self.first) as usize].iter())
            .copied()
            .filter(|&l| self.alive[l as usize])
            .collect();
        if fan.is_empty() {
            return false;
        }
        let Some(spokes) = star::disk(&self.triangles, v, &fan) else {
            return false;
        };
        let bounding = star::bounding(&spokes, |l| self.group[l as usize]);
        let point = |v: u32| arr.point(input, v);
        let targets: Vec<u32> = match bounding[..] {
            [] => spokes.iter().map(|s| s.to).collect(),
            [u, w] if is_between(&point(u), &point(v), &point(w)) => vec![u, w],
            _ => return false,
        };
        if !self.fans_are_planar(input, &fan) {
            return false;
        }
        let mut best: Option<Collapse> = None;
        for z in targets {
            let Some((shape, new)) = self.collapse(input, arr, v, z, &fan) else {
                continue;
            };
            if best.as_ref().is_none_or(|(s, _)| shape > *s) {
                best = Some((shape, new));
            }
        }
        let Some((_, new)) = best else {
            return false;
        };
        for &l in &fan {
            self.alive[l as usize] = false;
        }
        for (l, t) in new {
            let l = l as usize;
            let (source, reversed, group) = (self.source[l], self.reversed[l], self.group[l]);
            self.push(t, source, reversed, group, None);
        }
        true
    }

    /// Whether the input triangles of each face's part of `fan` lie in one plane.
    fn fans_are_planar(&self, input: &Input, fan: &[u32]) -> bool {
        let mut first_of_group: Vec<(u32, u32)> = Vec::with_capacity(2);
        for &l in fan {
            let (group, source) = (self.group[l as usize], self.source[l as usize]);
            match first_of_group.iter().find(|(g, _)| *g == group) {
                Some(&(_, first)) => {
                    if first != source && !coplanar(input, first, source) {
                        return false;
                    }
                }
                None => first_of_group.push((group, source)),
            }
        }
        true
    }

    /// The triangles that replace `fan` when `v` collapses onto `z`, each with the triangle
    /// it replaces, and the shape of the worst; `None` if one of them does not turn like its
    /// input triangle.
    fn collapse(
        &self,
        input: &Input,
        arr: &Arrangement,
        v: u32,
        z: u32,
        fan: &[u32],
    ) -> Option<Collapse> {
        let mut new = Vec::with_capacity(fan.len());
        let mut worst = f64::INFINITY;
        for &l in fan {
            let t = self.triangles[l as usize];
            if t.contains(&z) {
                continue;
            }
            let moved = t.map(|x| if x == v { z } else { x });
            let [a, b, c] = moved.map(|x| arr.point(input, x));
            let source = input.triangle(self.source[l as usize] as usize);
            let want = if self.reversed[l as usize] {
                source.turn().flip()
            } else {
                source.turn()
            };
            if orient2d_projected(&a, &b, &c, source.drop_axis()) != want {
                return None;
            }
            worst = worst.min(triangle_shape([a, b, c].map(|p| approx_point(&p))));
            new.push((l, moved));
        }
        Some((worst, new))
    }
}

/// Whether `v` lies on the segment from `u` to `w`, strictly between them (exact).
fn is_between(u: &Point, v: &Point, w: &Point) -> bool {
    let collinear = [Axis::X, Axis::Y, Axis::Z]
        .into_iter()
        .all(|axis| orient2d_projected(u, v, w, axis) == Sign::Zero);
    if !collinear {
        return false;
    }
    let (pu, pw) = (approx_point(u), approx_point(w));
    let axis = Axis::of_largest([pw[0] - pu[0], pw[1] - pu[1], pw[2] - pu[2]]);
    let before = compare_along(u, v, axis);
    before != std::cmp::Ordering::Equal && before == compare_along(v, w, axis)
}
