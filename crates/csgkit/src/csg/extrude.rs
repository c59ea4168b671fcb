//! 2D shapes and the solids made from them (OpenSCAD's `linear_extrude` and
//! `rotate_extrude`).
//!
//! # 2D shapes are prisms
//! A 2D shape travels through the tree as its *prism*: each outline extruded from −h to h,
//! with a ring of vertices at z = 0 ([`prism`]). Prism walls are vertical, so the cross
//! section at z = 0 of `prism(A) op prism(B)` is exactly `A op B`: 2D booleans are 3D
//! booleans of prisms, computed by the exact engine with its guarantees (exact decisions,
//! every point rounded once), and no second clipping code with its own rounding exists.
//! Every outline gets its own height h, so no two caps are coplanar and the engine never
//! overlays two cap triangulations (which costs the product of their sizes); only walls meet.
//! [`Profile::of_prisms`] reads the region back from the result's edges in z = 0, where
//! intersection points lie exactly (z = 0 rounds to itself).
//!
//! # Extrusions
//! An [`Extrusion`] sweeps a [`Profile`] through rings of moved copies of its points:
//! translated, turned and scaled copies for `linear_extrude`, copies turned about the z axis
//! for `rotate_extrude`. Each boundary side of the profile becomes a band of faces between
//! consecutive rings, and the profile's own triangles close the ends. Points that rings map
//! to one position (a point on the axis of a revolution, the apex of a cone scaled to 0)
//! become one vertex, and faces that lose area that way are dropped, so the solid is closed.
//! The rings and the diagonals of the twisted bands follow OpenSCAD 2021 (`src/
//! GeometryEvaluator.cc`, `rotateextrude`), so volumes compare with OpenSCAD's renders.

use std::collections::HashMap;

use crate::kernel::{Sign, orient2d};
use crate::mesh::{Mesh, measure, triangulate_faces, triangulate_planar};
use crate::primitives::{Fragments, cos_degrees, sin_degrees};

/// The prism of a 2D shape bounded by `outlines` (closed loops of points, any orientation):
/// the region inside an odd number of them (the even-odd rule, as OpenSCAD fills
/// polygons), each loop extruded from `−heights(i)` to `heights(i)` (positive and different
/// for every loop of every prism that meets this one, see the module docs).
///
/// Each loop becomes one closed shell, oriented outward when it is nested in an even number
/// of the other loops and inward otherwise, so under the non-zero winding rule the prism's
/// section is the even-odd region of loops that do not cross. A loop's orientation and
/// nesting are decided by exact orientations.
pub fn prism(outlines: &[Vec<[f64; 2]>], mut heights: impl FnMut(usize) -> f64) -> Mesh {
    let loops: Vec<Vec<[f64; 2]>> = (outlines.iter())
        .map(|l| without_repeats(l))
        .filter(|l| l.len() >= 3)
        .collect();
    let mut positions = Vec::new();
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for (i, points) in loops.iter().enumerate() {
        let depth = (loops.iter().enumerate())
            .filter(|&(j, other)| j != i && contains(other, points[0]))
            .count();
        let outward = (depth % 2 == 0) == (orientation(points) == Sign::Positive);
        let h = heights(i);
        let n = points.len() as u32;
        let base = positions.len() as u32;
        for z in [-h, 0.0, h] {
            positions.extend(points.iter().map(|p| [p[0], p[1], z]));
        }
        let at = |level: u32, j: u32| base + level * n + j % n;
        let mut shell: Vec<Vec<u32>> = vec![
            (0..n).rev().map(|j| at(0, j)).collect(),
            (0..n).map(|j| at(2, j)).collect(),
        ];
        for level in 0..2 {
            shell.extend((0..n).map(|j| {
                vec![
                    at(level, j),
                    at(level, j + 1),
                    at(level + 1, j + 1),
                    at(level + 1, j),
                ]
            }));
        }
        if !outward {
            shell.iter_mut().for_each(|f| f.reverse());
        }
        faces.extend(shell);
    }
    Mesh::from_polygons(positions, &faces).expect("prism faces index its loops")
}

/// `points` without consecutive repeats (the closing point included).
fn without_repeats(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(points.len());
    for &p in points {
        if out.last() != Some(&p) {
            out.push(p);
        }
    }
    while out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

/// The orientation of a simple loop: the turn at its lowest (then leftmost) point, where
/// the loop is convex.
fn orientation(points: &[[f64; 2]]) -> Sign {
    let n = points.len();
    let lowest = (0..n)
        .min_by(|&a, &b| {
            let (p, q) = (points[a], points[b]);
            (p[1], p[0])
                .partial_cmp(&(q[1], q[0]))
                .expect("finite points")
        })
        .expect("a loop has points");
    orient2d(
        points[(lowest + n - 1) % n],
        points[lowest],
        points[(lowest + 1) % n],
    )
}

/// Whether `p` lies inside the loop (crossing parity of a ray towards +x, exact; a point
/// on the loop counts as inside, which for loops that do not cross makes no difference).
fn contains(points: &[[f64; 2]], p: [f64; 2]) -> bool {
    let n = points.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        // The half-open rule counts a side when it spans p's height, lower end included.
        if (a[1] <= p[1]) != (b[1] <= p[1]) {
            let (lo, hi) = if a[1] <= b[1] { (a, b) } else { (b, a) };
            match orient2d(lo, hi, p) {
                Sign::Positive => {}
                Sign::Zero => return true,
                Sign::Negative => inside = !inside,
            }
        }
    }
    inside
}

/// A region of the plane: its triangles and its boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    points: Vec<[f64; 2]>,
    /// Counter-clockwise triangles over `points`.
    triangles: Vec<[u32; 3]>,
    /// Boundary sides with the region on their left.
    sides: Vec<Side>,
}

/// A boundary side of a profile.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Side {
    from: u32,
    to: u32,
    /// The side lies on a clockwise loop (a hole's outline).
    hole: bool,
}

impl Profile {
    /// The region whose prism is `mesh` (the result of booleans of [`prism`]s): the edges in
    /// z = 0, each directed with the region on its left (as the wall face above it runs),
    /// and the constrained triangulation of the loops they form.
    pub fn of_prisms(mesh: &Mesh) -> Profile {
        let triangulation = triangulate_faces(mesh).expect("the engine's output triangulates");
        let positions = mesh.positions();
        let mut ids: HashMap<u32, u32> = HashMap::new();
        let mut points = Vec::new();
        let mut edges = Vec::new();
        for (_, corners) in triangulation.iter() {
            let z = corners.map(|v| positions[v as usize][2]);
            for k in 0..3 {
                let (p, q, r) = (k, (k + 1) % 3, (k + 2) % 3);
                if z[p] == 0.0 && z[q] == 0.0 && z[r] > 0.0 {
                    let [a, b] = [corners[p], corners[q]].map(|v| {
                        *ids.entry(v).or_insert_with(|| {
                            let p = positions[v as usize];
                            points.push([p[0], p[1]]);
                            points.len() as u32 - 1
                        })
                    });
                    edges.push((a, b));
                }
            }
        }
        let sides = loops(&points, &edges);
        let triangles = if edges.is_empty() {
            Vec::new()
        } else {
            let constraints = edges
                .iter()
                .map(|&(a, b)| [a as usize, b as usize])
                .collect();
            triangulate_planar(points.clone(), constraints)
                .expect("the certified section is a set of simple loops")
                .triangles
                .into_iter()
                .map(|t| t.map(|i| i as u32))
                .collect()
        };
        Profile {
            points,
            triangles,
            sides,
        }
    }

    /// Whether the region is empty.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }
}

/// The boundary `edges` chained into loops, each side marked with its loop's orientation
/// (clockwise: a hole).
fn loops(points: &[[f64; 2]], edges: &[(u32, u32)]) -> Vec<Side> {
    let mut outgoing: HashMap<u32, Vec<u32>> = HashMap::new();
    for &(a, b) in edges {
        outgoing.entry(a).or_default().push(b);
    }
    // Follow outgoing sides until back at the start; a point where loops touch has several,
    // taken in turn.
    let mut sides = Vec::with_capacity(edges.len());
    for &(start, _) in edges {
        let mut chain = Vec::new();
        let mut at = start;
        while let Some(next) = outgoing.get_mut(&at).and_then(Vec::pop) {
            chain.push(at);
            at = next;
            if at == start {
                break;
            }
        }
        if chain.is_empty() {
            continue;
        }
        let loop_points: Vec<[f64; 2]> = chain.iter().map(|&v| points[v as usize]).collect();
        let hole = loop_points.len() >= 3 && orientation(&loop_points) == Sign::Negative;
        for (k, &from) in chain.iter().enumerate() {
            let to = chain[(k + 1) % chain.len()];
            sides.push(Side { from, to, hole });
        }
    }
    sides
}

/// How a profile becomes a solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Extrusion {
    /// OpenSCAD's `linear_extrude`.
    Linear(LinearExtrude),
    /// OpenSCAD's `rotate_extrude`.
    Rotate(RotateExtrude),
}

/// A straight extrusion along z, turning and scaling on the way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearExtrude {
    /// The height (positive).
    pub height: f64,
    /// From −height/2 to height/2 instead of from 0 to height.
    pub center: bool,
    /// Degrees turned clockwise (seen from above) from bottom to top.
    pub twist: f64,
    /// Bands of faces from bottom to top (at least 1); by default OpenSCAD's count, from the
    /// twist, the scale and the profile's largest radius.
    pub slices: Option<u32>,
    /// The scale of the top against the bottom, per axis.
    pub scale: [f64; 2],
    /// The fragment rule the default slices follow.
    pub fragments: Fragments,
}

/// A revolution about the z axis of a profile in the half plane x ≥ 0 (its x becomes the
/// radius, its y the height).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotateExtrude {
    /// Degrees swept counter-clockwise from the x axis (360 is a closed ring).
    pub angle: f64,
    /// The fragment rule for the largest radius.
    pub fragments: Fragments,
}

/// Why an extrusion could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ExtrudeError {
    /// A revolved profile has points on both sides of the axis.
    #[error(
        "rotate_extrude: the profile has points on both sides of the y axis (x from {min} to {max})"
    )]
    AcrossTheAxis {
        /// The smallest x of the profile.
        min: f64,
        /// The largest x.
        max: f64,
    },
    /// A parameter is out of range.
    #[error("{0}")]
    Parameter(String),
}

impl Extrusion {
    /// The solid swept by `profile`.
    ///
    /// # Errors
    /// [`ExtrudeError`] for a non-positive height, no slices, or a revolved profile across
    /// the axis.
    pub fn solid(&self, profile: &Profile) -> Result<Mesh, ExtrudeError> {
        if profile.is_empty() {
            return Ok(Mesh::new());
        }
        match self {
            Extrusion::Linear(linear) => linear.solid(profile),
            Extrusion::Rotate(rotate) => rotate.solid(profile),
        }
    }
}

impl LinearExtrude {
    fn solid(&self, profile: &Profile) -> Result<Mesh, ExtrudeError> {
        // OpenSCAD makes nothing of a height that is not positive.
        if self.height <= 0.0 {
            return Ok(Mesh::new());
        }
        if !self.height.is_finite() {
            return Err(ExtrudeError::Parameter(format!(
                "linear_extrude needs a finite height (height {})",
                self.height
            )));
        }
        let slices = self.slices.unwrap_or_else(|| self.default_slices(profile));
        let (h1, h2) = if self.center {
            (-self.height / 2.0, self.height / 2.0)
        } else {
            (0.0, self.height)
        };
        let n = f64::from(slices);
        // Each expression as OpenSCAD writes it, so every position rounds the same way.
        let turn = |j: u32| self.twist * f64::from(j) / n;
        let scale = |j: u32| [0, 1].map(|k| 1.0 - (1.0 - self.scale[k]) * f64::from(j) / n);
        let ring = |j: u32, p: [f64; 2]| {
            let (s, c) = (sin_degrees(-turn(j)), cos_degrees(-turn(j)));
            let k = scale(j);
            [
                k[0] * (c * p[0] - s * p[1]),
                k[1] * (s * p[0] + c * p[1]),
                h1 + (h2 - h1) * f64::from(j) / n,
            ]
        };
        let mut sweep = Sweep::new(profile, slices, ring);
        sweep.cap(0, true);
        sweep.cap(slices, false);
        // Without twist or scale every band is a planar rectangle; otherwise OpenSCAD's
        // add_slice splits it along the shorter diagonal (in the plane).
        let straight = self.twist == 0.0 && self.scale == [1.0, 1.0];
        for j in 0..slices {
            let back_twist = turn(j + 1) <= turn(j);
            let top = scale(j + 1);
            let any_zero = top[0] == 0.0 || top[1] == 0.0;
            for side in &profile.sides {
                let (from, to) = (side.from, side.to);
                let [a, b, c, d] = [
                    sweep.vertex(j, from),
                    sweep.vertex(j, to),
                    sweep.vertex(j + 1, to),
                    sweep.vertex(j + 1, from),
                ];
                if straight {
                    sweep.face(vec![a, b, c, d]);
                    continue;
                }
                let at = |v: u32| {
                    let q = sweep.position(v);
                    [q[0], q[1]]
                };
                let flip = side.hole != back_twist;
                let first = match shorter(sub(at(a), at(c)), sub(at(b), at(d))) {
                    Some(first) => first,
                    None => !flip,
                };
                if first != any_zero {
                    sweep.face(vec![a, b, c]);
                    sweep.face(vec![a, c, d]);
                } else {
                    sweep.face(vec![a, b, d]);
                    sweep.face(vec![b, c, d]);
                }
            }
        }
        Ok(sweep.mesh())
    }

    /// OpenSCAD's slice count when none is given (`extrudePolygon` with
    /// `Calc::get_helix_slices`, `get_conical_helix_slices`, `get_diagonal_slices`).
    fn default_slices(&self, profile: &Profile) -> u32 {
        let Fragments { fn_, fa, fs } = self.fragments;
        let [sx, sy] = self.scale;
        let max_r_sqr = (profile.points.iter())
            .map(|p| p[0] * p[0] + p[1] * p[1])
            .fold(0.0, f64::max);
        let fine = 1.0 / f64::from(1u32 << 20);
        if self.twist != 0.0 {
            let twist = self.twist.abs();
            let min_slices = ((twist / 120.0).ceil() as i64).max(1);
            let slices = if max_r_sqr.sqrt() < fine || !fn_.is_finite() {
                min_slices
            } else if fn_ > 0.0 {
                ((twist * fn_ / 360.0).ceil() as i64).max(min_slices)
            } else {
                let length = if (sx == 1.0 && sy == 1.0) || sx != sy {
                    let turn = twist.to_radians();
                    let c = self.height / turn;
                    turn * (max_r_sqr + c * c).sqrt()
                } else {
                    let turn = twist.to_radians();
                    let end = if sx > 1.0 {
                        turn * sx / (sx - 1.0)
                    } else {
                        turn / (1.0 - sx)
                    };
                    let a = max_r_sqr.sqrt() / end;
                    let spiral = |t: f64| 0.5 * a * (t * (1.0 + t * t).sqrt() + t.asinh());
                    let flat = spiral(end) - spiral(end - turn);
                    (flat * flat + self.height * self.height).sqrt()
                };
                let by_fa = (twist / fa).ceil() as i64;
                let by_fs = (length / fs).ceil() as i64;
                by_fa.min(by_fs).max(min_slices)
            };
            return slices.clamp(1, i64::from(u32::MAX)) as u32;
        }
        if sx != sy {
            let max_delta_sqr = (profile.points.iter())
                .map(|p| {
                    let d = [p[0] - p[0] * sx, p[1] - p[1] * sy];
                    d[0] * d[0] + d[1] * d[1]
                })
                .fold(0.0, f64::max);
            if max_delta_sqr.sqrt() < fine || !fn_.is_finite() {
                return 1;
            }
            if fn_ > 0.0 {
                return (fn_ as u32).max(1);
            }
            let by_fs = ((max_delta_sqr + self.height * self.height).sqrt() / fs).ceil();
            return (by_fs as u32).max(1);
        }
        1
    }
}

/// `Some(true)` when `u` is clearly shorter than `v`, `Some(false)` when clearly longer, and
/// `None` when their lengths agree to 10 ppm (OpenSCAD's `sgn_vdiff`). The choice is between
/// two valid triangulations of a band, so f64 decides it.
fn shorter(u: [f64; 2], v: [f64; 2]) -> Option<bool> {
    let (lu, lv) = (u[0].hypot(u[1]), v[0].hypot(v[1]));
    (2.0 * (lu - lv).abs() * 1e5 > lu + lv).then_some(lu < lv)
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

impl RotateExtrude {
    fn solid(&self, profile: &Profile) -> Result<Mesh, ExtrudeError> {
        let xs = profile.points.iter().map(|p| p[0]);
        let (min, max) = xs.fold((0.0f64, 0.0f64), |(lo, hi), x| (lo.min(x), hi.max(x)));
        if max - min > max && max - min > min.abs() {
            return Err(ExtrudeError::AcrossTheAxis { min, max });
        }
        let angle = self.angle;
        if angle == 0.0 || !angle.is_finite() || angle.abs() > 360.0 {
            return Err(ExtrudeError::Parameter(format!(
                "rotate_extrude needs an angle in [-360, 360] other than 0 (angle {angle})"
            )));
        }
        let full = angle == 360.0;
        let steps =
            (f64::from(self.fragments.count(max - min)) * angle.abs() / 360.0).max(1.0) as u32;
        let n = f64::from(steps);
        // OpenSCAD's rings (`fill_ring`): a full turn starts on the −x axis, a partial one
        // on the +x axis, turning by −angle/steps in its parameter.
        let ring = |j: u32, p: [f64; 2]| {
            let a = if full {
                -90.0 + f64::from(j % steps) * 360.0 / n
            } else {
                90.0 - f64::from(j) * angle / n
            };
            [p[0] * sin_degrees(a), p[0] * cos_degrees(a), p[1]]
        };
        let mut sweep = Sweep::new(profile, steps, ring);
        if !full {
            sweep.cap(0, true);
            sweep.cap(steps, false);
        }
        // OpenSCAD's bands split along the diagonal from a side's first point to the next
        // ring's second (on a profile left of the axis, whose outlines it reverses, the other).
        let left = min < 0.0;
        for j in 0..steps {
            for side in &profile.sides {
                let [a, b, c, d] = [
                    sweep.vertex(j, side.from),
                    sweep.vertex(j, side.to),
                    sweep.vertex(j + 1, side.to),
                    sweep.vertex(j + 1, side.from),
                ];
                if left {
                    sweep.face(vec![a, b, d]);
                    sweep.face(vec![b, c, d]);
                } else {
                    sweep.face(vec![a, b, c]);
                    sweep.face(vec![a, c, d]);
                }
            }
        }
        // The sweep's faces are consistently oriented; which way round depends on the
        // direction of the turn and the side of the axis, so the volume's sign decides.
        Ok(sweep.mesh_outward())
    }
}

/// Rings of moved copies of a profile's points and the faces between them; copies that
/// land on one position are one vertex.
struct Sweep<'a> {
    profile: &'a Profile,
    /// `ids[j · n + i]`: the vertex of point `i` in ring `j`.
    ids: Vec<u32>,
    positions: Vec<[f64; 3]>,
    faces: Vec<Vec<u32>>,
}

impl<'a> Sweep<'a> {
    fn new(profile: &'a Profile, steps: u32, place: impl Fn(u32, [f64; 2]) -> [f64; 3]) -> Self {
        let mut at: HashMap<[u64; 3], u32> = HashMap::new();
        let mut positions = Vec::new();
        let mut ids = Vec::new();
        for j in 0..=steps {
            for &p in &profile.points {
                let q = place(j, p).map(|x| if x == 0.0 { 0.0 } else { x });
                let id = *at.entry(q.map(f64::to_bits)).or_insert_with(|| {
                    positions.push(q);
                    positions.len() as u32 - 1
                });
                ids.push(id);
            }
        }
        Sweep {
            profile,
            ids,
            positions,
            faces: Vec::new(),
        }
    }

    fn vertex(&self, ring: u32, point: u32) -> u32 {
        self.ids[ring as usize * self.profile.points.len() + point as usize]
    }

    /// The profile's triangles at `ring`, reversed when `reversed`.
    fn cap(&mut self, ring: u32, reversed: bool) {
        for t in &self.profile.triangles {
            let mut face = t.map(|p| self.vertex(ring, p)).to_vec();
            if reversed {
                face.reverse();
            }
            self.face(face);
        }
    }

    /// Adds a face, without the corners that repeat their predecessor; a face left with
    /// fewer than three corners is dropped.
    fn face(&mut self, mut corners: Vec<u32>) {
        corners.dedup();
        while corners.len() > 1 && corners.first() == corners.last() {
            corners.pop();
        }
        if corners.len() >= 3 {
            self.faces.push(corners);
        }
    }

    fn position(&self, vertex: u32) -> [f64; 3] {
        self.positions[vertex as usize]
    }

    /// The mesh, with every face reversed when its signed volume is negative.
    fn mesh_outward(mut self) -> Mesh {
        let mesh = Mesh::from_polygons(self.positions.clone(), &self.faces)
            .expect("sweep faces index its rings");
        if measure(&mesh).volume >= 0.0 {
            return mesh;
        }
        self.faces.iter_mut().for_each(|f| f.reverse());
        self.mesh()
    }

    fn mesh(self) -> Mesh {
        Mesh::from_polygons(self.positions, &self.faces).expect("sweep faces index its rings")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Operation;
    use crate::csg::{Node, evaluate};
    use crate::exact::BooleanOptions;
    use crate::progress::Progress;

    fn square(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<[f64; 2]> {
        vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    }

    /// The region of a tree of prisms, each outline at its own height.
    fn profile(op: Operation, shapes: &[Vec<Vec<[f64; 2]>>]) -> Profile {
        let mut made = 0.0;
        let leaves = (shapes.iter())
            .map(|outlines| {
                let prism = prism(outlines, |_| {
                    made += 1.0;
                    made
                });
                Node::mesh(prism, "shape")
            })
            .collect();
        let result = evaluate(
            &Node::apply(op, leaves),
            &BooleanOptions::default(),
            &Progress::default(),
        )
        .unwrap();
        Profile::of_prisms(&result.result.mesh)
    }

    fn area(profile: &Profile) -> f64 {
        (profile.triangles.iter())
            .map(|t| {
                let [a, b, c] = t.map(|i| profile.points[i as usize]);
                ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2.0
            })
            .sum()
    }

    fn solid(extrusion: Extrusion, profile: &Profile) -> Mesh {
        let mesh = extrusion.solid(profile).unwrap();
        let report = mesh.report();
        assert!(report.is_valid_solid(), "{report:?}");
        mesh
    }

    #[test]
    fn nested_outlines_fill_by_the_even_odd_rule_in_either_orientation() {
        let outer = square(0.0, 0.0, 4.0, 4.0);
        let mut hole = square(1.0, 1.0, 3.0, 3.0);
        let island = square(1.5, 1.5, 2.5, 2.5);
        for _ in 0..2 {
            let p = profile(
                Operation::Union,
                &[vec![outer.clone(), hole.clone(), island.clone()]],
            );
            assert_eq!(area(&p), 16.0 - 4.0 + 1.0);
            // Two loops are holes (clockwise after the boolean): the hole and none else.
            let holes = p.sides.iter().filter(|s| s.hole).count();
            assert_eq!(holes, 4);
            hole.reverse();
        }
    }

    #[test]
    fn two_dimensional_booleans_are_booleans_of_prisms() {
        let (a, b) = (square(0.0, 0.0, 2.0, 2.0), square(1.0, 1.0, 3.0, 3.0));
        let shapes = [vec![a], vec![b]];
        assert_eq!(area(&profile(Operation::Union, &shapes)), 7.0);
        assert_eq!(area(&profile(Operation::Intersection, &shapes)), 1.0);
        assert_eq!(area(&profile(Operation::Difference, &shapes)), 3.0);
        // Shapes that share an edge merge into one region with no seam.
        let side_by_side = [
            vec![square(0.0, 0.0, 1.0, 1.0)],
            vec![square(1.0, 0.0, 2.0, 1.0)],
        ];
        let p = profile(Operation::Union, &side_by_side);
        assert_eq!(area(&p), 2.0);
        assert!(p.sides.iter().all(|s| !s.hole));
    }

    #[test]
    fn straight_extrusions_have_exact_volumes() {
        let p = profile(Operation::Union, &[vec![square(0.0, 0.0, 2.0, 3.0)]]);
        let linear = |twist: f64, scale: [f64; 2], slices: Option<u32>| {
            Extrusion::Linear(LinearExtrude {
                height: 5.0,
                center: true,
                twist,
                slices,
                scale,
                fragments: Fragments::default(),
            })
        };
        let prism = solid(linear(0.0, [1.0; 2], None), &p);
        assert_eq!(prism.report().measures.volume, 30.0);
        assert_eq!(prism.face_count(), 2 * 2 + 4);
        // Scaled to a point: a pyramid, one slice, the top a single vertex.
        let pyramid = solid(linear(0.0, [0.0; 2], None), &p);
        assert!((pyramid.report().measures.volume - 10.0).abs() < 1e-12);
        assert_eq!(pyramid.vertex_count(), 5);
        // Explicit slices stack rings without changing the volume.
        let stacked = solid(linear(0.0, [1.0; 2], Some(4)), &p);
        assert_eq!(stacked.report().measures.volume, 30.0);
    }

    #[test]
    fn twisted_extrusions_follow_openscad_slices_and_stay_valid() {
        let p = profile(Operation::Union, &[vec![square(-1.0, -1.0, 1.0, 1.0)]]);
        let twisted = LinearExtrude {
            height: 10.0,
            center: false,
            twist: 90.0,
            slices: None,
            scale: [1.0; 2],
            fragments: Fragments::default(),
        };
        // get_helix_slices: min(ceil(90 / 12), ceil(helix length / 2)) = min(8, 6) = 6.
        assert_eq!(twisted.default_slices(&p), 6);
        let mesh = solid(Extrusion::Linear(twisted), &p);
        assert_eq!(mesh.vertex_count(), 4 * 7);
        // OpenSCAD 2021 renders `linear_extrude(height=10, twist=90) square(2, center=true)`
        // with 42.99657 (its OFF's 6 digits): the diagonals it picks bulge the sides out,
        // where the other diagonals would cut them in below 40.
        let volume = mesh.report().measures.volume;
        assert!((volume - 42.99657).abs() < 1e-4, "{volume}");
    }

    #[test]
    fn revolutions_are_polygonal_rings() {
        let p = profile(Operation::Union, &[vec![square(1.0, 0.0, 2.0, 1.0)]]);
        let fragments = Fragments {
            fn_: 12.0,
            ..Fragments::default()
        };
        let ring = |angle: f64| Extrusion::Rotate(RotateExtrude { angle, fragments });
        // A regular 12-gon of circumradius r has area 3 r².
        let full = solid(ring(360.0), &p).report().measures.volume;
        assert!((full - 3.0 * (4.0 - 1.0)).abs() < 1e-12, "{full}");
        // A quarter turn has 3 of the 12 sectors and two caps; clockwise the same.
        for angle in [90.0, -90.0] {
            let quarter = solid(ring(angle), &p).report().measures.volume;
            assert!(
                (quarter - 3.0 * 3.0 / 4.0).abs() < 1e-12,
                "{angle}: {quarter}"
            );
        }
        // Left of the axis the profile revolves the same way.
        let left = profile(Operation::Union, &[vec![square(-2.0, 0.0, -1.0, 1.0)]]);
        let mirrored = solid(ring(360.0), &left).report().measures.volume;
        assert!((mirrored - 9.0).abs() < 1e-12, "{mirrored}");
    }

    #[test]
    fn a_profile_across_the_axis_is_refused() {
        let p = profile(Operation::Union, &[vec![square(-1.0, 0.0, 1.0, 1.0)]]);
        let ring = Extrusion::Rotate(RotateExtrude {
            angle: 360.0,
            fragments: Fragments::default(),
        });
        let err = ring.solid(&p).unwrap_err();
        assert_eq!(
            err.to_string(),
            "rotate_extrude: the profile has points on both sides of the y axis (x from -1 to 1)"
        );
    }
}
