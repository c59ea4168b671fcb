//! The degenerate suite of `design/exact.md`: touching, coplanar, identical, nested and
//! disjoint operands, with exact volumes.

use csgkit::exact::{BooleanOptions, boolean};
use csgkit::mesh::FaceMode;
use csgkit::primitives::cuboid;
use csgkit::{Mesh, Operation};

use crate::util::{assert_no_self_intersection, box_of_quads, polygon_normal};

use Operation::{Difference, Intersection, Union, Xor};

/// Runs `op`, checks the result is a closed, oriented solid without self-intersection (the
/// certified output), and returns its volume.
fn volume_of(op: Operation, operands: &[&Mesh]) -> f64 {
    let result = boolean(op, operands, &BooleanOptions::default())
        .unwrap_or_else(|e| panic!("{op:?} failed: {e}"));
    let report = result.mesh.report();
    assert!(
        report.is_valid_solid(),
        "{op:?}: not a closed oriented solid: {report:?}"
    );
    assert_no_self_intersection(&result.mesh, &format!("{op:?}"));
    report.measures.volume
}

fn unit_cube_at(x: f64, y: f64, z: f64) -> Mesh {
    cuboid([x, y, z], [x + 1.0, y + 1.0, z + 1.0])
}

/// Asserts `actual` is `expected` up to the rounding of summing a volume.
fn assert_volume(actual: f64, expected: f64, what: &str) {
    let error = (actual - expected).abs();
    assert!(
        error <= 1e-12 * expected.abs().max(1.0),
        "{what}: volume {actual}, expected {expected}"
    );
}

/// Volumes of ∪, ∩, − for two operands, checked against the expected values, and of ⊕
/// against vol(A ∪ B) − vol(A ∩ B).
fn check_all(a: &Mesh, b: &Mesh, union: f64, intersection: f64, difference: f64) {
    assert_volume(volume_of(Union, &[a, b]), union, "union");
    assert_volume(
        volume_of(Intersection, &[a, b]),
        intersection,
        "intersection",
    );
    assert_volume(volume_of(Difference, &[a, b]), difference, "difference");
    assert_volume(volume_of(Xor, &[a, b]), union - intersection, "xor");
}

/// vol(A ⊕ B) = vol(A) + vol(B) − 2 vol(A ∩ B), where the cubes overlap in a corner, where
/// they touch along a coplanar face (the shared face bounds neither piece), and where they
/// overlap with four coplanar face pairs (coincident regions are kept once, or not at all).
/// The overlapping pieces A − B and B − A meet along edges only, which the result keeps as
/// non-manifold edges of a valid solid.
#[test]
fn xor_is_the_union_minus_the_intersection() {
    let cases = [
        (
            "overlapping",
            unit_cube_at(0.0, 0.0, 0.0),
            unit_cube_at(0.5, 0.5, 0.5),
        ),
        (
            "touching",
            unit_cube_at(0.0, 0.0, 0.0),
            unit_cube_at(1.0, 0.0, 0.0),
        ),
        (
            "coplanar",
            cuboid([0.0; 3], [2.0; 3]),
            cuboid([1.0, 0.0, 0.0], [3.0, 2.0, 2.0]),
        ),
    ];
    for (what, a, b) in cases {
        let (va, vb) = (volume_of(Union, &[&a]), volume_of(Union, &[&b]));
        let intersection = volume_of(Intersection, &[&a, &b]);
        let xor = volume_of(Xor, &[&a, &b]);
        assert_volume(xor, va + vb - 2.0 * intersection, what);
        assert_volume(volume_of(Xor, &[&b, &a]), xor, &format!("{what}, swapped"));
    }
    // Three operands: the points in one or in all three.
    let (a, b, c) = (
        unit_cube_at(0.0, 0.0, 0.0),
        unit_cube_at(0.5, 0.0, 0.0),
        unit_cube_at(0.25, 0.0, 0.0),
    );
    assert_volume(
        volume_of(Xor, &[&a, &b, &c]),
        0.25 + 0.25 + 0.5,
        "three in a row",
    );
}

#[test]
fn cubes_sharing_a_face() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(1.0, 0.0, 0.0),
        2.0,
        0.0,
        1.0,
    );
}

#[test]
fn cubes_sharing_part_of_a_face() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(1.0, 0.5, 0.5),
        2.0,
        0.0,
        1.0,
    );
}

#[test]
fn cubes_sharing_an_edge() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(1.0, 1.0, 0.0),
        2.0,
        0.0,
        1.0,
    );
}

#[test]
fn cubes_sharing_a_vertex() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(1.0, 1.0, 1.0),
        2.0,
        0.0,
        1.0,
    );
}

#[test]
fn overlapping_cubes() {
    check_all(
        &unit_cube_at(0.0, 0.0, 0.0),
        &unit_cube_at(0.5, 0.5, 0.5),
        1.875,
        0.125,
        0.875,
    );
}

#[test]
fn cube_with_itself() {
    let a = unit_cube_at(0.0, 0.0, 0.0);
    check_all(&a, &a.clone(), 1.0, 1.0, 0.0);
}

#[test]
fn cube_minus_a_flush_cube() {
    let a = cuboid([0.0; 3], [2.0; 3]);
    let b = cuboid([0.5, 0.5, 1.0], [1.5, 1.5, 2.0]);
    check_all(&a, &b, 8.0, 1.0, 7.0);
}

#[test]
fn nested_and_disjoint_cubes() {
    let outer = cuboid([0.0; 3], [3.0; 3]);
    let inner = unit_cube_at(1.0, 1.0, 1.0);
    check_all(&outer, &inner, 27.0, 1.0, 26.0);
    check_all(&inner, &outer, 27.0, 1.0, 0.0);
    let far = unit_cube_at(5.0, 0.0, 0.0);
    check_all(&inner, &far, 2.0, 0.0, 1.0);
}

/// An integer box `[min, max]`.
type IntBox = ([i32; 3], [i32; 3]);

/// The box as 12 triangles, with `cuboid`'s face diagonals or with the other ones (those of
/// the peers' OBJ files): coincident faces of several operands then cross differently.
fn box_mesh((min, max): IntBox, other_diagonals: bool) -> Mesh {
    let (lo, hi) = (min.map(f64::from), max.map(f64::from));
    if !other_diagonals {
        return cuboid(lo, hi);
    }
    let corner = |i: usize| {
        let [x, y] = [[0, 1, 1, 0][i % 4], [0, 0, 1, 1][i % 4]];
        [[lo[0], hi[0]][x], [lo[1], hi[1]][y], [lo[2], hi[2]][i / 4]]
    };
    let triangles = [
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    Mesh::from_triangles((0..8).map(corner).collect(), &triangles).expect("indices below 8")
}

/// The volume of `op` on integer boxes, by counting unit cells.
fn voxel_volume(op: Operation, boxes: &[IntBox]) -> f64 {
    let lo = [0, 1, 2].map(|k| boxes.iter().map(|b| b.0[k]).min().unwrap_or(0));
    let hi = [0, 1, 2].map(|k| boxes.iter().map(|b| b.1[k]).max().unwrap_or(0));
    let mut cells = 0;
    for x in lo[0]..hi[0] {
        for y in lo[1]..hi[1] {
            for z in lo[2]..hi[2] {
                let inside = |(min, max): &IntBox| {
                    [x, y, z]
                        .iter()
                        .enumerate()
                        .all(|(k, &c)| min[k] <= c && c < max[k])
                };
                cells += usize::from(op.contains(boxes.iter().map(inside)));
            }
        }
    }
    cells as f64
}

/// Checks `op` on `boxes` (both triangulations) against the voxel count.
fn check_boxes(op: Operation, boxes: &[IntBox]) {
    let expected = voxel_volume(op, boxes);
    for other_diagonals in [false, true] {
        let meshes: Vec<Mesh> = boxes
            .iter()
            .map(|&b| box_mesh(b, other_diagonals))
            .collect();
        let operands: Vec<&Mesh> = meshes.iter().collect();
        let what = format!("{op:?} of {boxes:?} (other diagonals: {other_diagonals})");
        let result = boolean(op, &operands, &BooleanOptions::default())
            .unwrap_or_else(|e| panic!("{what} failed: {e}"));
        let report = result.mesh.report();
        assert!(
            report.is_valid_solid(),
            "{what}: not a valid solid: {report:?}"
        );
        assert_no_self_intersection(&result.mesh, &what);
        let error = (report.measures.volume - expected).abs();
        assert!(
            error <= 1e-9 * expected.max(1.0),
            "{what}: volume {}, expected {expected}",
            report.measures.volume
        );
    }
}

/// Three operands with coincident faces, where two segments on one triangle cross at a
/// point that is also a contact point of two other triangles (it must get that point's id),
/// or cross a segment lying along another triangle's edge (the crossing is an edge × edge
/// or edge × triangle point, as the intersect stage keys it). Both left T-junctions.
#[test]
fn three_operands_with_coincident_faces() {
    let cases: [&[IntBox]; 2] = [
        &[
            ([4, 4, 4], [5, 6, 5]),
            ([5, 3, 4], [6, 6, 5]),
            ([4, 4, 4], [5, 5, 5]),
        ],
        &[
            ([3, 3, 2], [4, 4, 3]),
            ([3, 2, 2], [4, 4, 3]),
            ([3, 1, 2], [4, 4, 3]),
        ],
    ];
    for boxes in cases {
        for op in Operation::ALL {
            check_boxes(op, boxes);
        }
    }
}

/// n-ary operations on random integer boxes (many coincident faces, edges and vertices)
/// agree with a voxel count.
#[test]
fn random_integer_boxes_against_voxel_count() {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut random = |n: i32| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as i32
    };
    for _ in 0..60 {
        let count = 3 + random(3) as usize;
        let boxes: Vec<IntBox> = (0..count)
            .map(|_| {
                let (mut min, mut max) = ([0; 3], [0; 3]);
                for k in 0..3 {
                    min[k] = random(4);
                    max[k] = min[k] + 1 + random(4 - min[k]);
                }
                (min, max)
            })
            .collect();
        for op in Operation::ALL {
            check_boxes(op, &boxes);
        }
    }
}

/// The level-2 Menger sponge as one n-ary difference: the cube `[0, 9]³` minus 30 bars.
#[test]
fn menger_sponge_level_2() {
    let mut boxes: Vec<IntBox> = vec![([0; 3], [9; 3])];
    for (size, blocks) in [(3, 1), (1, 3)] {
        for axis in 0..3 {
            for i in 0..blocks {
                for j in 0..blocks {
                    let (u, v) = ((3 * i + 1) * size, (3 * j + 1) * size);
                    let (mut min, mut max) = ([-1; 3], [10; 3]);
                    let (p, q) = ((axis + 1) % 3, (axis + 2) % 3);
                    (min[p], max[p], min[q], max[q]) = (u, u + size, v, v + size);
                    boxes.push((min, max));
                }
            }
        }
    }
    assert_eq!(boxes.len(), 31);
    assert_eq!(voxel_volume(Difference, &boxes), 400.0);
    check_boxes(Difference, &boxes);
}

/// Every face of a result keeps the material of the face it was cut from, and one name in
/// two operands is one material: the cube's faces are red (z), green (y) and blue (x); the
/// box pushed into its top face is green all over, so the pocket it leaves is green.
#[test]
fn faces_keep_their_source_materials_merged_by_name() {
    let cube = box_of_quads([-1.0; 3], [1.0; 3], ["blue", "green", "red"]);
    let pushed = box_of_quads([0.0, 0.0, 0.5], [2.0, 2.0, 2.0], ["green"; 3]);
    let result = boolean(Difference, &[&cube, &pushed], &BooleanOptions::default())
        .expect("a difference")
        .mesh;
    assert_eq!(result.report().measures.volume, 8.0 - 0.5);
    let materials = result.materials();
    assert_eq!(
        materials.iter().filter(|n| *n == "green").count(),
        1,
        "{materials:?}"
    );
    let ids = result.parts().face_materials.as_ref().expect("materials");
    for (f, face) in result.faces().enumerate() {
        let p: Vec<[f64; 3]> = face
            .iter()
            .map(|&v| result.positions()[v as usize])
            .collect();
        // The axis the face is normal to, and the coordinate of its plane.
        let axis = (0..3)
            .find(|&k| p.iter().all(|q| q[k] == p[0][k]))
            .expect("every face is axis-aligned");
        let on_cube = p[0][axis].abs() == 1.0;
        let expected = match (axis, on_cube) {
            (0, true) => "blue",
            (2, true) => "red",
            _ => "green",
        };
        assert_eq!(materials[ids[f] as usize], expected, "face {f}: {p:?}");
    }
}

/// The UV a face of [`box_of_quads`] gives a point: an affine function of position, a
/// different one for each face (`q` is the face's index in its box).
fn affine_uv(p: [f64; 3], q: usize) -> [f64; 2] {
    let q = q as f64;
    [p[0] + 2.0 * p[1] + 3.0 * p[2] + q, q * p[0] - p[2] + 0.5]
}

/// `mesh` (a box of quads) with corner UVs from [`affine_uv`] and corner normals along the
/// outward normal of each face.
fn with_affine_uvs_and_normals(mesh: Mesh) -> Mesh {
    let mut uvs = Vec::new();
    let mut normals = Vec::new();
    for (q, face) in mesh.faces().enumerate() {
        let p: Vec<[f64; 3]> = face.iter().map(|&v| mesh.positions()[v as usize]).collect();
        let (u, w) = (
            [0, 1, 2].map(|k| p[1][k] - p[0][k]),
            [0, 1, 2].map(|k| p[2][k] - p[0][k]),
        );
        let n = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        let length = n.iter().map(|x| x * x).sum::<f64>().sqrt();
        for point in p {
            let uv = affine_uv(point, q);
            uvs.push(uv);
            normals.push(n.map(|x| (x / length) as f32));
        }
    }
    Mesh::from_parts(csgkit::MeshParts {
        corner_uvs: Some(uvs),
        corner_normals: Some(normals),
        ..mesh.into_parts()
    })
    .expect("one UV and normal per corner")
}

/// Every corner of a result carries the UV its source face gives its position (an affine
/// function, different on each face, reproduced to 1e-9) and the normal of the result's
/// surface there: the pocket's faces, cut from the subtracted box, point the other way from
/// their source's normals. The same holds whichever faces the result is written with.
#[test]
fn corners_keep_uvs_interpolated_in_their_source_face_and_normals_follow_orientation() {
    let cube = with_affine_uvs_and_normals(box_of_quads([-1.0; 3], [1.0; 3], ["a"; 3]));
    let pushed =
        with_affine_uvs_and_normals(box_of_quads([0.0, 0.0, 0.5], [2.0, 2.0, 2.0], ["b"; 3]));
    for faces in [FaceMode::Triangles, FaceMode::Polygons, FaceMode::Quads] {
        let options = BooleanOptions {
            faces,
            ..BooleanOptions::default()
        };
        let result = boolean(Difference, &[&cube, &pushed], &options)
            .expect("a difference")
            .mesh;
        let uvs = result.corner_uvs().expect("UVs");
        let normals = result.corner_normals().expect("normals");
        let provenance = result.face_provenance().expect("provenance");
        for (f, range) in
            (0..result.face_count()).map(|f| (f, result.face_range(csgkit::FaceId::new(f))))
        {
            let p: Vec<[f64; 3]> = (result.corners()[range.clone()].iter())
                .map(|&v| result.positions()[v as usize])
                .collect();
            let n = polygon_normal(&p);
            let q = provenance[f].face.index();
            for (c, point) in range.zip(&p) {
                let expected = affine_uv(*point, q);
                for k in 0..2 {
                    assert!(
                        (uvs[c][k] - expected[k]).abs() <= 1e-9 * expected[k].abs().max(1.0),
                        "{faces:?}: face {f} corner {c}: UV {:?}, expected {expected:?}",
                        uvs[c]
                    );
                }
                let along: f64 = (0..3).map(|k| f64::from(normals[c][k]) * n[k]).sum();
                assert!(
                    along > 0.0,
                    "{faces:?}: face {f}: normal {:?} against {n:?}",
                    normals[c]
                );
            }
        }
    }
}

/// A vertex colour that is an affine function of position.
fn affine_color(p: [f64; 3]) -> [f64; 4] {
    [
        128.0 + 40.0 * p[0],
        128.0 + 30.0 * p[1] - 10.0 * p[2],
        100.0 + 50.0 * p[2],
        255.0,
    ]
}

/// Every vertex of a union of two boxes coloured by one affine function of position carries
/// that function's colour, to the rounding of 8-bit channels: new vertices interpolate it.
#[test]
fn vertex_colours_are_interpolated_in_their_source_faces() {
    let coloured = |mesh: Mesh| {
        let colors = (mesh.positions().iter())
            .map(|&p| affine_color(p).map(|x| x.round() as u8))
            .collect();
        Mesh::from_parts(csgkit::MeshParts {
            vertex_colors: Some(colors),
            ..mesh.into_parts()
        })
        .expect("one colour per vertex")
    };
    let a = coloured(box_of_quads([-1.0; 3], [1.0; 3], ["a"; 3]));
    let b = coloured(box_of_quads([0.25, 0.5, -0.5], [1.5, 1.75, 0.75], ["a"; 3]));
    let result = boolean(Union, &[&a, &b], &BooleanOptions::default())
        .expect("a union")
        .mesh;
    let colors = result.vertex_colors().expect("vertex colours");
    let mut interpolated = 0;
    for (v, &p) in result.positions().iter().enumerate() {
        let expected = affine_color(p);
        for k in 0..4 {
            // Each corner's channel rounds by half a unit, and so does the blend.
            assert!(
                (f64::from(colors[v][k]) - expected[k]).abs() <= 1.0,
                "vertex {v} at {p:?}: {:?}, expected {expected:?}",
                colors[v]
            );
        }
        interpolated += usize::from(a.positions().iter().chain(b.positions()).all(|&q| q != p));
    }
    assert!(interpolated > 0);
}
