//! Closed, outward-oriented meshes of simple solids, built in code.
//!
//! The demo, the tests and the benches need a few solids without reading files; these functions
//! are their one definition, so every caller meets the same vertices in the same order.
//!
//! # Conventions
//! - Every primitive is a **triangle mesh** ([`Mesh::from_triangles`]): the exact and discrete
//!   engines consume triangles, and a triangle mesh stores no face offsets. A caller that
//!   wants polygons can merge the documented triangle pairs back (each quad `a b c d` of a
//!   primitive becomes the consecutive triangles `a b c`, `a c d`).
//! - Triangles are wound counter-clockwise seen from outside, so the signed volume is
//!   positive; every primitive is closed, consistently oriented and edge-manifold, with no
//!   repeated positions.
//! - The output depends only on the arguments: vertex and triangle order are fixed.
//!
//! # Numeric model
//! [`cuboid`] copies its corner coordinates, so its faces lie exactly on the six planes and its
//! volume is exact. The curved primitives place vertices with `sin`, `cos` and `sqrt`, so a
//! vertex lies on the analytic surface only up to rounding; the mesh, not the analytic
//! surface, is the solid the engines see. [`cylinder`] keeps its caps exactly planar (every
//! cap vertex has the same z) and its side quads exactly planar (top and bottom rings share
//! x and y).

use crate::Mesh;

/// The triangles of the cuboid whose vertex `i` takes x from bit 0, y from bit 1 and z from
/// bit 2 of `i` (clear: min, set: max); each face's quad split along a diagonal, wound outward.
const CUBOID_TRIANGLES: [[u32; 3]; 12] = [
    [0, 2, 3],
    [0, 3, 1],
    [4, 5, 7],
    [4, 7, 6],
    [0, 1, 5],
    [0, 5, 4],
    [2, 6, 7],
    [2, 7, 3],
    [0, 4, 6],
    [0, 6, 2],
    [1, 3, 7],
    [1, 7, 5],
];

/// The axis-aligned box `[min, max]`: 8 vertices and 12 triangles (two per face).
///
/// Vertex `i` takes its x from bit 0 of `i`, y from bit 1 and z from bit 2 (bit clear: `min`,
/// set: `max`), so vertex 0 is `min` and vertex 7 is `max`. The coordinates are `min` and
/// `max` themselves, so the volume is exact. If `min[d] > max[d]` on an odd number of axes the
/// box is inside out (negative volume).
pub fn cuboid(min: [f64; 3], max: [f64; 3]) -> Mesh {
    let corner = |i: u32| [0, 1, 2].map(|d| if i >> d & 1 == 0 { min[d] } else { max[d] });
    Mesh::from_triangles((0..8).map(corner).collect(), &CUBOID_TRIANGLES)
        .expect("cuboid indices are below 8")
}

/// The 12 vertices of the regular icosahedron `(0, ±1, ±t)` and its cyclic permutations,
/// `t` the golden ratio.
fn icosahedron_vertices() -> Vec<[f64; 3]> {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
}

/// The 20 outward triangles of [`icosahedron_vertices`].
const ICOSAHEDRON_TRIANGLES: [[u32; 3]; 20] = [
    [0, 11, 5],
    [0, 5, 1],
    [0, 1, 7],
    [0, 7, 10],
    [0, 10, 11],
    [1, 5, 9],
    [5, 11, 4],
    [11, 10, 2],
    [10, 7, 6],
    [7, 1, 8],
    [3, 9, 4],
    [3, 4, 2],
    [3, 2, 6],
    [3, 6, 8],
    [3, 8, 9],
    [4, 9, 5],
    [2, 4, 11],
    [6, 2, 10],
    [8, 6, 7],
    [9, 8, 1],
];

/// A sphere of `radius` around `centre`: the regular icosahedron with each triangle split into
/// four `subdivisions` times, every vertex then projected onto the sphere.
///
/// It has `10·4^s + 2` vertices and `20·4^s` triangles for `s` subdivisions, all vertices on
/// the sphere up to rounding; the volume approaches `4/3·π·radius³` from below.
pub fn icosphere(centre: [f64; 3], radius: f64, subdivisions: u32) -> Mesh {
    let mut points = icosahedron_vertices();
    let mut triangles = ICOSAHEDRON_TRIANGLES.to_vec();
    for _ in 0..subdivisions {
        triangles = subdivide(&mut points, &triangles);
    }
    let positions = points
        .iter()
        .map(|p| {
            let norm = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            [0, 1, 2].map(|d| centre[d] + radius * p[d] / norm)
        })
        .collect();
    Mesh::from_triangles(positions, &triangles).expect("subdivision indexes pushed points")
}

/// Splits each triangle into four at its edge midpoints, appending each midpoint to `points`
/// once (keyed by its sorted edge, so neighbours share it and the mesh stays closed).
fn subdivide(points: &mut Vec<[f64; 3]>, triangles: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut midpoints = std::collections::HashMap::new();
    let mut next = Vec::with_capacity(4 * triangles.len());
    for &[a, b, c] in triangles {
        let mut mid = |i: u32, j: u32| {
            *midpoints.entry((i.min(j), i.max(j))).or_insert_with(|| {
                let (p, q) = (points[i as usize], points[j as usize]);
                points.push([0, 1, 2].map(|d| (p[d] + q[d]) / 2.0));
                points.len() as u32 - 1
            })
        };
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    next
}

/// A torus around the z axis through `centre`, with radii `major` (centre to tube centre) and
/// `minor` (tube), as a grid of `major_segments × minor_segments` quads, each split in two.
///
/// Vertex `i·minor_segments + j` is at angle `τ·i/major_segments` around the z axis and
/// `τ·j/minor_segments` around the tube (0 on the outer equator, rising towards +z). Quad
/// `(i, j)` has corners `(i, j)`, `(i+1, j)`, `(i+1, j+1)`, `(i, j+1)` (indices wrap) and
/// becomes the consecutive triangles `a b c`, `a c d`, in row-major order. The genus is 1 and
/// the volume approaches `2·π²·major·minor²` when `minor < major`.
///
/// # Panics
/// If either segment count is below 3 (the grid would not close into a torus).
pub fn torus(
    centre: [f64; 3],
    major: f64,
    minor: f64,
    major_segments: u32,
    minor_segments: u32,
) -> Mesh {
    let (n, m) = (major_segments, minor_segments);
    assert!(
        n >= 3 && m >= 3,
        "a torus needs at least 3 segments each way"
    );
    let angle = |k: u32, of: u32| std::f64::consts::TAU * f64::from(k) / f64::from(of);
    let mut positions = Vec::with_capacity((n * m) as usize);
    for i in 0..n {
        let (su, cu) = angle(i, n).sin_cos();
        for j in 0..m {
            let (sv, cv) = angle(j, m).sin_cos();
            let r = major + minor * cv;
            positions.push([
                centre[0] + r * cu,
                centre[1] + r * su,
                centre[2] + minor * sv,
            ]);
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + (j % m);
    let mut triangles = Vec::with_capacity(2 * (n * m) as usize);
    for i in 0..n {
        for j in 0..m {
            let [a, b, c, d] = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            triangles.extend([[a, b, c], [a, c, d]]);
        }
    }
    Mesh::from_triangles(positions, &triangles).expect("torus indices wrap below n·m")
}

/// A cylinder of `radius` along +z: the bottom cap's centre is `base`, the top's is `height`
/// above it; the circle is a regular polygon of `segments` sides.
///
/// Vertices: the bottom ring (`0..segments`, counter-clockwise seen from +z, vertex 0 on +x),
/// the top ring (`segments..2·segments`, same x and y), then the bottom and top cap centres.
/// Triangles: each side quad (bottom `i`, bottom `i+1`, top `i+1`, top `i`) split in two,
/// then the bottom fan, then the top fan. The volume is
/// `segments/2 · radius² · sin(τ/segments) · height`, approaching `π·radius²·height`.
///
/// # Panics
/// If `segments` is below 3.
pub fn cylinder(base: [f64; 3], radius: f64, height: f64, segments: u32) -> Mesh {
    let n = segments;
    assert!(n >= 3, "a cylinder needs at least 3 segments");
    let top = base[2] + height;
    let ring: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let (s, c) = (std::f64::consts::TAU * f64::from(i) / f64::from(n)).sin_cos();
            [base[0] + radius * c, base[1] + radius * s]
        })
        .collect();
    let mut positions: Vec<[f64; 3]> = ring.iter().map(|&[x, y]| [x, y, base[2]]).collect();
    positions.extend(ring.iter().map(|&[x, y]| [x, y, top]));
    positions.extend([base, [base[0], base[1], top]]);
    let (bottom_centre, top_centre) = (2 * n, 2 * n + 1);
    let mut triangles = Vec::with_capacity(4 * n as usize);
    for i in 0..n {
        let (a, b) = (i, (i + 1) % n);
        triangles.extend([[a, b, b + n], [a, b + n, a + n]]);
    }
    triangles.extend((0..n).map(|i| [bottom_centre, (i + 1) % n, i]));
    triangles.extend((0..n).map(|i| [top_centre, i + n, (i + 1) % n + n]));
    Mesh::from_triangles(positions, &triangles).expect("cylinder indices are below 2n + 2")
}

/// The sphere of `radius` about `centre` as OpenSCAD tessellates it with `fragments` points
/// per ring: `(fragments + 1) / 2` rings at polar angles `180° · (i + ½) / rings`, each with
/// `fragments` points from azimuth 0 counter-clockwise seen from +z (degree trigonometry as
/// OpenSCAD's); quads between rings and one polygon cap at each end (outward).
///
/// # Panics
/// If `fragments` is below 3.
pub fn uv_sphere(centre: [f64; 3], radius: f64, fragments: u32) -> Mesh {
    assert!(fragments >= 3, "a sphere needs at least 3 fragments");
    let n = fragments;
    let rings = n.div_ceil(2);
    let mut positions = Vec::with_capacity((rings * n) as usize);
    for i in 0..rings {
        let polar = 180.0 * (f64::from(i) + 0.5) / f64::from(rings);
        let (ring, z) = (radius * sin_degrees(polar), radius * cos_degrees(polar));
        positions.extend(
            (circle(ring, n).into_iter())
                .map(|[x, y]| [centre[0] + x, centre[1] + y, centre[2] + z]),
        );
    }
    let at = |i: u32, j: u32| i * n + j % n;
    let mut faces: Vec<Vec<u32>> = vec![(0..n).map(|j| at(0, j)).collect()];
    for i in 0..rings - 1 {
        faces.extend((0..n).map(|j| vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]));
    }
    faces.push((0..n).rev().map(|j| at(rings - 1, j)).collect());
    Mesh::from_polygons(positions, &faces).expect("sphere corners index its rings")
}

/// OpenSCAD's rule for the number of fragments of a circle (`Calc::get_fragments_from_r` in
/// `src/calc.cc`): `$fn` when set, otherwise what the smallest angle `$fa` and the smallest
/// side `$fs` allow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragments {
    /// `$fn`: the fragment count when positive (at least 3).
    pub fn_: f64,
    /// `$fa`: the smallest angle of a fragment, in degrees.
    pub fa: f64,
    /// `$fs`: the smallest side of a fragment.
    pub fs: f64,
}

impl Default for Fragments {
    /// OpenSCAD's defaults: `$fn = 0`, `$fa = 12`, `$fs = 2`.
    fn default() -> Self {
        Fragments {
            fn_: 0.0,
            fa: 12.0,
            fs: 2.0,
        }
    }
}

impl Fragments {
    /// The fragments of a circle of radius `r`: 3 below 2^-20, `max($fn, 3)` when `$fn` > 0,
    /// otherwise `ceil(max(min(360 / $fa, 2πr / $fs), 5))`.
    pub fn count(&self, r: f64) -> u32 {
        if r < 1.0 / f64::from(1u32 << 20) {
            return 3;
        }
        if self.fn_ > 0.0 {
            return if self.fn_ >= 3.0 { self.fn_ as u32 } else { 3 };
        }
        (360.0 / self.fa)
            .min(r * 2.0 * std::f64::consts::PI / self.fs)
            .max(5.0)
            .ceil() as u32
    }
}

/// `sin` of `x` degrees with OpenSCAD's exact values at multiples of 30° and 45°
/// (`src/degree_trig.cc`), so tessellations match OpenSCAD's.
pub(crate) fn sin_degrees(x: f64) -> f64 {
    let mut x = x.rem_euclid(360.0);
    let oppose = x >= 180.0;
    if oppose {
        x -= 180.0;
    }
    if x > 90.0 {
        x = 180.0 - x;
    }
    let s = if x == 0.0 {
        0.0
    } else if x == 30.0 {
        0.5
    } else if x == 45.0 {
        std::f64::consts::FRAC_1_SQRT_2
    } else if x == 60.0 {
        3f64.sqrt() / 2.0
    } else if x == 90.0 {
        1.0
    } else {
        x.to_radians().sin()
    };
    if oppose { -s } else { s }
}

pub(crate) fn cos_degrees(x: f64) -> f64 {
    sin_degrees(x + 90.0)
}

/// OpenSCAD's circle of `n` points of radius `r`, from angle 0 counter-clockwise.
pub(crate) fn circle(r: f64, n: u32) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let phi = 360.0 * f64::from(i) / f64::from(n);
            [r * cos_degrees(phi), r * sin_degrees(phi)]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::mesh::{MeshReport, analyze};

    #[test]
    fn a_uv_sphere_is_a_closed_solid_inside_its_ball() {
        let sphere = uv_sphere([1.0, 2.0, 3.0], 2.0, 30);
        let report = solid(&sphere, 0);
        assert_eq!(sphere.face_count(), 2 + 14 * 30);
        let volume = report.measures.volume;
        assert!(volume < 4.0 / 3.0 * PI * 8.0 && volume > 0.95 * 4.0 / 3.0 * PI * 8.0);
    }

    /// Analyses `mesh` and asserts it is a closed, oriented, edge-manifold solid of `genus`
    /// with no repeated position.
    fn solid(mesh: &Mesh, genus: i64) -> MeshReport {
        let report = analyze(mesh);
        assert!(report.closed && report.oriented, "{report:?}");
        assert!(report.edge_manifold && report.valid_solid, "{report:?}");
        assert_eq!(report.duplicate_vertices, 0);
        assert_eq!(report.topology.components, 1);
        assert_eq!(report.topology.genus, Some(genus));
        report
    }

    fn assert_close(measured: f64, exact: f64, relative: f64) {
        let error = (measured - exact).abs() / exact;
        assert!(error < relative, "{measured} vs {exact}: {error:e}");
    }

    #[test]
    fn cuboid_is_an_exact_box() {
        let report = solid(&cuboid([-1.0, 2.0, 0.5], [3.0, 2.5, 4.0]), 0);
        assert_eq!((report.vertices, report.faces), (8, 12));
        assert_eq!(report.measures.volume, 4.0 * 0.5 * 3.5);
        assert_eq!(
            report.measures.area,
            2.0 * (4.0 * 0.5 + 4.0 * 3.5 + 0.5 * 3.5)
        );
        let bbox = report.measures.bbox.expect("not empty");
        assert_eq!((bbox.min, bbox.max), ([-1.0, 2.0, 0.5], [3.0, 2.5, 4.0]));
    }

    #[test]
    fn inverted_cuboid_has_negative_volume() {
        let report = analyze(&cuboid([1.0, 0.0, 0.0], [0.0, 1.0, 1.0]));
        assert!(report.closed && report.oriented);
        assert_eq!(report.measures.volume, -1.0);
    }

    #[test]
    fn icosphere_converges_to_the_ball() {
        let ball = 4.0 / 3.0 * PI * 8.0;
        let mut previous = 0.0;
        for s in 0..5 {
            let report = solid(&icosphere([1.0, -2.0, 3.0], 2.0, s), 0);
            let four_s = 4usize.pow(s);
            assert_eq!(
                (report.vertices, report.faces),
                (10 * four_s + 2, 20 * four_s)
            );
            let volume = report.measures.volume;
            assert!(
                previous < volume && volume < ball,
                "inscribed, growing: s = {s}"
            );
            previous = volume;
        }
        assert_close(previous, ball, 5e-3);
    }

    #[test]
    fn torus_has_genus_one_and_converges() {
        let report = solid(&torus([0.5, 0.0, -1.0], 3.0, 1.0, 5, 3), 1);
        assert_eq!((report.vertices, report.faces), (15, 30));
        let report = solid(&torus([0.5, 0.0, -1.0], 3.0, 1.0, 256, 128), 1);
        assert_close(report.measures.volume, 2.0 * PI * PI * 3.0, 1e-3);
    }

    #[test]
    fn cylinder_volume_is_the_prism_and_converges() {
        let report = solid(&cylinder([1.0, 2.0, -0.5], 2.0, 3.0, 3), 0);
        assert_eq!((report.vertices, report.faces), (8, 12));
        for n in [3u32, 16, 1024] {
            let report = solid(&cylinder([1.0, 2.0, -0.5], 2.0, 3.0, n), 0);
            let prism = f64::from(n) / 2.0 * 4.0 * (std::f64::consts::TAU / f64::from(n)).sin();
            assert_close(report.measures.volume, prism * 3.0, 1e-12);
        }
        let report = analyze(&cylinder([0.0; 3], 2.0, 3.0, 1024));
        assert_close(report.measures.volume, PI * 4.0 * 3.0, 1e-4);
        let bbox = report.measures.bbox.expect("not empty");
        assert_eq!((bbox.min[2], bbox.max[2]), (0.0, 3.0));
    }
}
