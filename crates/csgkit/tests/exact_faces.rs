//! Reconstruction: the result's faces merged back by source face, in the three output modes,
//! with the fewest vertices; faces nothing cut come back as read; provenance composes
//! through chained booleans.

use csgkit::exact::{BooleanOptions, boolean};
use csgkit::mesh::FaceMode;
use csgkit::primitives::{cylinder, icosphere};
use csgkit::{Encoding, Format, Mesh, Operation};

use crate::util::{assert_close, assert_no_self_intersection, box_of_quads, polygon_normal};

use Operation::{Difference, Union};

fn compute(op: Operation, operands: &[&Mesh], faces: FaceMode) -> Mesh {
    let options = BooleanOptions {
        faces,
        ..BooleanOptions::default()
    };
    boolean(op, operands, &options)
        .unwrap_or_else(|e| panic!("{op:?} in {faces:?}: {e}"))
        .mesh
}

/// The corner counts of the faces, sorted.
fn face_sizes(mesh: &Mesh) -> Vec<usize> {
    let mut sizes: Vec<usize> = mesh.faces().map(<[u32]>::len).collect();
    sizes.sort_unstable();
    sizes
}

/// `count` copies of `size`, for expected face sizes.
fn sizes(groups: &[(usize, usize)]) -> Vec<usize> {
    let mut out: Vec<usize> = (groups.iter())
        .flat_map(|&(count, size)| std::iter::repeat_n(size, count))
        .collect();
    out.sort_unstable();
    out
}

/// A valid solid whose faces repeat no corner and whose triangulation crosses nothing.
fn assert_valid(mesh: &Mesh, what: &str) {
    let report = mesh.report();
    assert!(report.is_valid_solid(), "{what}: not a valid solid");
    for (f, face) in mesh.faces().enumerate() {
        let mut corners = face.to_vec();
        corners.sort_unstable();
        corners.dedup();
        assert_eq!(
            corners.len(),
            face.len(),
            "{what}: face {f} repeats a corner"
        );
    }
    assert_no_self_intersection(mesh, what);
    assert_fans_from_first_corner(mesh, what);
}

/// Every face is triangulated by the fan from its first corner, as readers that fan polygons
/// (many do) will triangulate it: every fan triangle turns like the face.
fn assert_fans_from_first_corner(mesh: &Mesh, what: &str) {
    for (f, p) in face_positions(mesh).iter().enumerate() {
        let normal = polygon_normal(p);
        for i in 1..p.len() - 1 {
            let fan = polygon_normal(&[p[0], p[i], p[i + 1]]);
            let along: f64 = (0..3).map(|k| fan[k] * normal[k]).sum();
            assert!(
                along > 0.0,
                "{what}: face {f} is no fan from its first corner: {p:?}"
            );
        }
    }
}

/// The corner positions of every face, in order.
fn face_positions(mesh: &Mesh) -> Vec<Vec<[f64; 3]>> {
    (mesh.faces())
        .map(|face| face.iter().map(|&v| mesh.positions()[v as usize]).collect())
        .collect()
}

/// Every face of `source` that `untouched` accepts is a face of `result` with the same
/// corners at the same positions in the same order, from the same first corner.
fn assert_untouched_faces_as_read(
    result: &Mesh,
    source: &Mesh,
    untouched: impl Fn(&[[f64; 3]]) -> bool,
    what: &str,
) -> usize {
    let written = face_positions(result);
    let mut checked = 0;
    for face in face_positions(source) {
        if untouched(&face) {
            assert!(
                written.contains(&face),
                "{what}: {face:?} did not come back as read"
            );
            checked += 1;
        }
    }
    checked
}

/// A cube of quads minus a box pushed into its top face: the top keeps a square hole, the
/// pocket has four walls and a floor, the other five faces are untouched. Exactly 16
/// vertices in every mode (the points where the box's walls cross the quads' diagonals are
/// gone); polygons: the top in two hole-free hexagons, each a fan from its first corner, 12
/// faces;
/// quads: the top as four trapezoids, 14 strictly convex quads; triangles: 28, which is
/// n + 2h − 2 per face (8 for the top, 2 for each quad).
#[test]
fn a_quad_cube_minus_a_pushed_box_has_exact_counts_in_every_mode() {
    let cube = box_of_quads([0.0; 3], [2.0; 3], ["a"; 3]);
    let pushed = box_of_quads([0.5, 0.5, 1.5], [1.5, 1.5, 3.0], ["b"; 3]);
    let cases = [
        (FaceMode::Polygons, sizes(&[(10, 4), (2, 6)])),
        (FaceMode::Quads, sizes(&[(14, 4)])),
        (FaceMode::Triangles, sizes(&[(28, 3)])),
    ];
    for (mode, expected) in cases {
        let what = format!("{mode:?}");
        let result = compute(Difference, &[&cube, &pushed], mode);
        assert_valid(&result, &what);
        assert_eq!(result.report().measures.volume, 7.5, "{what}");
        assert_eq!(result.vertex_count(), 16, "{what}: vertices");
        assert_eq!(face_sizes(&result), expected, "{what}: face sizes");
        if mode != FaceMode::Triangles {
            let below_top = |face: &[[f64; 3]]| face.iter().any(|p| p[2] < 2.0);
            let checked = assert_untouched_faces_as_read(&result, &cube, below_top, &what);
            assert_eq!(checked, 5, "{what}");
        }
    }
}

/// The seed's Table 6: two cubes sharing part of a face. The union is sewn with the fewest
/// vertices: the 16 corners and the 2 points where an edge of one meets a face of the other,
/// nothing else. Polygons: each cube keeps its far faces as quads, two side faces with a
/// fifth corner where the other cube's edge meets them, and an L-shaped hexagon where they
/// touch: 12 faces; triangles: 32.
#[test]
fn two_cubes_sharing_part_of_a_face_unite_with_the_fewest_vertices() {
    let a = box_of_quads([0.0; 3], [1.0; 3], ["a"; 3]);
    let b = box_of_quads([0.5, 0.5, 1.0], [1.5, 1.5, 2.0], ["b"; 3]);
    let cases = [
        (FaceMode::Polygons, sizes(&[(6, 4), (4, 5), (2, 6)])),
        (FaceMode::Triangles, sizes(&[(32, 3)])),
    ];
    for (mode, expected) in cases {
        let what = format!("{mode:?}");
        let result = compute(Union, &[&a, &b], mode);
        assert_valid(&result, &what);
        assert_eq!(result.report().measures.volume, 2.0, "{what}");
        assert_eq!(result.vertex_count(), 18, "{what}: vertices");
        assert_eq!(face_sizes(&result), expected, "{what}: face sizes");
    }
}

/// A UV sphere of quads (triangles at the poles), rings of `rings` and `segments` sides.
fn uv_sphere(rings: usize, segments: usize) -> Mesh {
    let mut positions = vec![[0.0, 0.0, 1.0]];
    for i in 1..rings {
        let polar = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let azimuth = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
            positions.push([
                polar.sin() * azimuth.cos(),
                polar.sin() * azimuth.sin(),
                polar.cos(),
            ]);
        }
    }
    positions.push([0.0, 0.0, -1.0]);
    let south = (positions.len() - 1) as u32;
    let at = |i: usize, j: usize| (1 + (i - 1) * segments + j % segments) as u32;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for j in 0..segments {
        faces.push(vec![0, at(1, j), at(1, j + 1)]);
        for i in 1..rings - 1 {
            faces.push(vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
        faces.push(vec![at(rings - 1, j + 1), at(rings - 1, j), south]);
    }
    Mesh::from_polygons(positions, &faces).expect("a valid sphere")
}

/// A UV sphere of quads united with a box through its side: every quad away from the box
/// comes back unchanged, and every face stays a simple polygon.
#[test]
fn a_quad_sphere_united_with_a_box_keeps_every_untouched_quad() {
    let sphere = uv_sphere(12, 16);
    let cube = box_of_quads([0.5, -0.2, -0.2], [1.5, 0.2, 0.2], ["b"; 3]);
    let result = compute(Union, &[&sphere, &cube], FaceMode::Polygons);
    assert_valid(&result, "sphere ∪ box");
    let away = |face: &[[f64; 3]]| face.iter().all(|p| p[0] < 0.45 || p[1].abs() > 0.3);
    let checked = assert_untouched_faces_as_read(&result, &sphere, away, "sphere ∪ box");
    assert!(checked > 150, "only {checked} faces checked");
}

/// The faces of a triangles-mode result, grouped by provenance, have no vertex inside: every
/// vertex a group uses is on a side only one of the group's triangles has, so each merged
/// face is triangulated without extra vertices.
#[test]
fn triangles_mode_adds_no_vertex_inside_a_face() {
    let sphere = icosphere([0.0; 3], 1.0, 3);
    let drill = cylinder([0.1, 0.2, -2.0], 0.4, 4.0, 24);
    let result = compute(Difference, &[&sphere, &drill], FaceMode::Triangles);
    assert_valid(&result, "sphere − cylinder");
    let provenance = result.face_provenance().expect("provenance");
    let mut groups: std::collections::BTreeMap<_, Vec<usize>> = Default::default();
    for (f, p) in provenance.iter().enumerate() {
        groups.entry(*p).or_default().push(f);
    }
    for (p, faces) in groups {
        let mut sides = std::collections::HashMap::new();
        for &f in &faces {
            let t = &result.corners()[3 * f..3 * f + 3];
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                *sides.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let on_boundary: std::collections::HashSet<u32> = (sides.iter())
            .filter(|&(_, &uses)| uses == 1)
            .flat_map(|(&(a, b), _)| [a, b])
            .collect();
        for &f in &faces {
            for &v in &result.corners()[3 * f..3 * f + 3] {
                assert!(
                    on_boundary.contains(&v),
                    "{p:?}: vertex {v} is inside its face"
                );
            }
        }
    }
}

/// Two drills through a cube, one boolean after the other, give the vertices and the
/// triangles of one n-ary difference: in the library the second step joins the pieces the
/// first cut (they share a provenance), through a PLY file (which keeps provenance) so does
/// the file's, and through an OBJ file (which does not) coplanar merging does the same.
#[test]
fn chained_differences_have_the_faces_of_one_n_ary_difference() {
    let cube = box_of_quads([-1.0; 3], [1.0; 3], ["a"; 3]);
    let drills = [
        box_of_quads([-0.7, -0.2, -2.0], [-0.3, 0.2, 2.0], ["d"; 3]),
        box_of_quads([0.3, -0.9, -2.0], [0.6, 0.8, 2.0], ["d"; 3]),
    ];
    let first = compute(Difference, &[&cube, &drills[0]], FaceMode::Polygons);
    let bytes =
        csgkit::write_mesh_to_bytes(&first, Format::Obj, Encoding::default()).expect("an OBJ");
    let read = csgkit::read_mesh_from_bytes(&bytes, Some(Format::Obj))
        .expect("the OBJ reads back")
        .mesh;
    assert!(
        read.face_provenance().is_none(),
        "OBJ files carry no provenance"
    );
    let ply = csgkit::write_mesh_to_bytes(&first, Format::Ply, Encoding::default()).expect("a PLY");
    let read_ply = csgkit::read_mesh_from_bytes(&ply, Some(Format::Ply))
        .expect("the PLY reads back")
        .mesh;
    assert_eq!(
        read_ply.face_provenance(),
        first.face_provenance(),
        "PLY keeps provenance"
    );

    for mode in [FaceMode::Polygons, FaceMode::Triangles] {
        let once = compute(Difference, &[&cube, &drills[0], &drills[1]], mode);
        assert_valid(&once, "one difference");
        let run = |operand: &Mesh, merge_coplanar: bool| {
            let options = BooleanOptions {
                faces: mode,
                merge_coplanar,
                ..BooleanOptions::default()
            };
            let mesh = (boolean(Difference, &[operand, &drills[1]], &options))
                .expect("a difference")
                .mesh;
            assert_valid(&mesh, "a chained difference");
            mesh
        };
        let chained = run(&first, false);
        let through_file = run(&read, true);
        let through_ply = run(&read_ply, false);
        let cases = [
            (&chained, "library"),
            (&through_file, "OBJ file, coplanar merging"),
            (&through_ply, "PLY file, its provenance"),
        ];
        for (mesh, what) in cases {
            let what = format!("{mode:?}, {what}");
            let volume = mesh.report().measures.volume;
            assert_close(volume, once.report().measures.volume, 1e-12, 8.0, &what);
            assert_eq!(mesh.vertex_count(), once.vertex_count(), "{what}: vertices");
            if mode == FaceMode::Triangles {
                assert_eq!(mesh.face_count(), once.face_count(), "{what}: triangles");
            }
        }
    }
}

/// A chain through a file, where the first result's faces come back flat only to an ulp:
/// exactly, the second cut must keep every point where it crosses a side between two of
/// those triangles, so the chained result has more vertices than one n-ary difference; with
/// `simplify`, it has no more, its volume is the n-ary difference's to within the
/// tolerance's effect, and it is still a certified solid. (Every difference merges coplanar
/// faces, so the cube's square faces are one face each.)
#[test]
fn simplify_keeps_a_chain_through_files_as_small_as_one_difference() {
    let cube = csgkit::primitives::cuboid([-1.0; 3], [1.0; 3]);
    let tilted = |axis: [f64; 3], angle: f64, offset: [f64; 3]| {
        let drill = cylinder([0.0, 0.0, -2.0], 0.3, 4.0, 24);
        crate::util::transformed(&drill, &crate::util::rotation(axis, angle), offset)
    };
    let drills = [
        tilted([1.0, 0.3, 0.0], 0.5, [0.1, -0.2, 0.0]),
        tilted([0.2, 1.0, 0.5], 0.9, [-0.15, 0.25, 0.1]),
    ];
    let merged = BooleanOptions {
        faces: FaceMode::Triangles,
        merge_coplanar: true,
        ..BooleanOptions::default()
    };
    let once = (boolean(Difference, &[&cube, &drills[0], &drills[1]], &merged))
        .expect("a difference")
        .mesh;
    let first = (boolean(Difference, &[&cube, &drills[0]], &merged))
        .expect("a difference")
        .mesh;
    let bytes =
        csgkit::write_mesh_to_bytes(&first, Format::Obj, Encoding::default()).expect("an OBJ");
    let read = csgkit::read_mesh_from_bytes(&bytes, Some(Format::Obj))
        .expect("the OBJ reads back")
        .mesh;
    let run = |simplify: Option<f64>| {
        let options = BooleanOptions {
            faces: FaceMode::Triangles,
            merge_coplanar: true,
            simplify,
            ..BooleanOptions::default()
        };
        let mesh = (boolean(Difference, &[&read, &drills[1]], &options))
            .expect("a difference")
            .mesh;
        assert_valid(&mesh, "a chained difference");
        mesh
    };
    let (exact, simplified) = (run(None), run(Some(1e-9)));
    assert!(
        exact.vertex_count() > once.vertex_count(),
        "exact chain: {} vertices, one difference {}",
        exact.vertex_count(),
        once.vertex_count()
    );
    assert!(
        simplified.vertex_count() <= once.vertex_count(),
        "simplified chain: {} vertices, one difference {}",
        simplified.vertex_count(),
        once.vertex_count()
    );
    let volume = |m: &Mesh| m.report().measures.volume;
    assert_close(volume(&simplified), volume(&once), 1e-8, 8.0, "volume");
}
