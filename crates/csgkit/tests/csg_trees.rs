//! CSG trees in one exact pass: JSON scenes against chains of binary booleans, trees whose
//! leaves touch and coincide, and random trees of moved primitives.

use std::path::Path;

use csgkit::csg::scene::read_scene;
use csgkit::csg::{Affine, Node, NodeKind, evaluate};
use csgkit::exact::{BooleanOptions, boolean};
use csgkit::mesh::FaceMode;
use csgkit::primitives::{cuboid, icosphere};
use csgkit::{Mesh, Operation, Progress};

use crate::util::{assert_close, assert_no_self_intersection, rotation};

/// The tree's value computed the long way: every leaf placed alone, then each operation as a
/// chain of binary booleans, each rounded (transforms only on leaves).
fn chained(node: &Node) -> Mesh {
    match &node.kind {
        NodeKind::Mesh { .. } | NodeKind::Extrude { .. } => {
            evaluate(node, &BooleanOptions::default(), &Progress::default())
                .unwrap()
                .result
                .mesh
        }
        NodeKind::Apply(op, children) => {
            let mut values = children.iter().map(chained);
            let first = values.next().expect("a child");
            values.fold(first, |acc, next| {
                boolean(*op, &[&acc, &next], &BooleanOptions::default())
                    .unwrap()
                    .mesh
            })
        }
    }
}

fn one_pass(node: &Node) -> Mesh {
    let mesh = evaluate(node, &BooleanOptions::default(), &Progress::default())
        .unwrap()
        .result
        .mesh;
    assert!(mesh.report().is_valid_solid());
    assert_no_self_intersection(&mesh, "one pass");
    mesh
}

fn volume(mesh: &Mesh) -> f64 {
    mesh.report().measures.volume
}

#[test]
fn a_json_scene_matches_the_chain_of_binary_booleans() {
    let dir = tempfile::TempDir::new().unwrap();
    let part = dir.path().join("part.obj");
    csgkit::write_mesh(
        &part,
        &icosphere([0.0; 3], 0.7, 2),
        csgkit::WriteOptions::default(),
    )
    .unwrap();
    let scene = dir.path().join("scene.json");
    std::fs::write(
        &scene,
        r#"{"difference": [
            {"union": [
                {"cube": {"size": [2, 1.5, 1], "center": true}},
                {"mesh": "part.obj", "transform": [[1, 0, 0, 0.9], [0, 1, 0, 0.1], [0, 0, 1, 0.2]]},
                {"sphere": {"r": 0.5, "segments": 20}, "transform": [[0.8, -0.6, 0, -0.9], [0.6, 0.8, 0, 0], [0, 0, 1, 0.3]]}
            ]},
            {"intersection": [
                {"cylinder": {"r": 0.35, "h": 4, "segments": 24, "center": true}},
                {"cube": {"size": 3, "center": true}, "transform": [[1, 0, 0, 0], [0, 0.6, -0.8, 0], [0, 0.8, 0.6, 0.4]]}
            ]}
        ]}"#,
    )
    .unwrap();
    let tree = read_scene(&scene).unwrap();
    let once = one_pass(&tree);
    let chain = chained(&tree);
    assert!(volume(&once) > 1.0);
    assert_close(volume(&once), volume(&chain), 1e-9, 1.0, "scene volume");
    let evaluation = evaluate(&tree, &BooleanOptions::default(), &Progress::default()).unwrap();
    assert_eq!((evaluation.leaves, evaluation.operations), (5, 3));
}

/// 27 unit cubes touching face to face make the 3 × 3 × 3 cube exactly; with coplanar
/// merging its polygons are the 6 squares over its 8 corners, every inner face gone.
#[test]
fn a_union_of_27_touching_cubes_is_one_cube() {
    let cubes: Vec<Node> = (0..27)
        .map(|i| {
            let p = [i % 3, i / 3 % 3, i / 9].map(f64::from);
            Node::mesh(cuboid(p, p.map(|x| x + 1.0)), format!("cube {i}"))
        })
        .collect();
    let tree = Node::apply(Operation::Union, cubes);
    let mesh = one_pass(&tree);
    assert_eq!(volume(&mesh), 27.0);
    let options = BooleanOptions {
        faces: FaceMode::Polygons,
        merge_coplanar: true,
        ..BooleanOptions::default()
    };
    let merged = evaluate(&tree, &options, &Progress::default())
        .unwrap()
        .result
        .mesh;
    assert_eq!((merged.face_count(), merged.vertex_count()), (6, 8));
    assert!(merged.report().is_valid_solid());
}

/// A tower minus a stack of three boxes flush with its sides and each other: every cut face
/// coincides with another; the volume is exact.
#[test]
fn a_difference_of_coplanar_stacks_is_exact() {
    let tower = Node::mesh(cuboid([0.0; 3], [2.0, 2.0, 6.0]), "tower");
    let stack: Vec<Node> = (0..3)
        .map(|k| {
            let z = 1.0 + 1.5 * f64::from(k);
            Node::mesh(
                cuboid([0.0, 0.0, z], [1.0, 2.0, z + 1.5]),
                format!("slab {k}"),
            )
        })
        .collect();
    let tree = Node::apply(
        Operation::Difference,
        vec![tower, Node::apply(Operation::Union, stack)],
    );
    let mesh = one_pass(&tree);
    assert_eq!(volume(&mesh), 24.0 - 9.0);
    assert_close(
        volume(&mesh),
        volume(&chained(&tree)),
        1e-12,
        24.0,
        "stacks",
    );
}

/// A leaf moved by a rotation about a random axis and a translation.
fn moved(mesh: Mesh, name: String, seed: &mut u64) -> Node {
    let mut next = || {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let axis = [next() - 0.5, next() - 0.5, next() - 0.5 + 1e-3];
    let r = rotation(axis, 6.0 * next());
    let t = [next() - 0.5, next() - 0.5, next() - 0.5];
    let transform: Affine = std::array::from_fn(|i| [r[i][0], r[i][1], r[i][2], t[i]]);
    Node {
        transform: Some(transform),
        ..Node::mesh(mesh, name)
    }
}

/// Random trees of rigidly moved boxes and spheres: the one-pass result is a valid solid
/// whose volume equals the chain of binary booleans' to 1e-9.
#[test]
fn random_trees_in_one_pass_match_their_chains() {
    let ops = [
        Operation::Union,
        Operation::Intersection,
        Operation::Difference,
    ];
    for tree_seed in 0..6u64 {
        let mut seed = 0x9e37_79b9_7f4a_7c15 ^ tree_seed;
        let leaf = |k: usize, seed: &mut u64| {
            let mesh = if k % 2 == 0 {
                cuboid([-0.5, -0.4, -0.3], [0.5, 0.4, 0.3])
            } else {
                icosphere([0.0; 3], 0.45, 2)
            };
            moved(mesh, format!("leaf {k}"), seed)
        };
        let inner: Vec<Node> = (0..2)
            .map(|g| {
                let children = vec![leaf(2 * g, &mut seed), leaf(2 * g + 1, &mut seed)];
                Node::apply(ops[(tree_seed as usize + g) % 3], children)
            })
            .collect();
        let tree = Node::apply(
            ops[(tree_seed as usize / 3) % 2],
            [inner, vec![leaf(4, &mut seed)]].concat(),
        );
        let once = one_pass(&tree);
        let chain = chained(&tree);
        assert_close(
            volume(&once),
            volume(&chain),
            1e-9,
            1.0,
            &format!("tree {tree_seed}"),
        );
    }
}

/// OpenSCAD's `CSG.scad` example as `openscad -o CSG.csg` exports it: its volume is the one
/// OpenSCAD 2021 renders from that file (7773.408926, read from its OFF export, which prints
/// about 7 significant digits), so the sphere's tessellation is OpenSCAD's.
#[test]
fn an_openscad_csg_export_has_the_volume_openscad_renders() {
    let text = "\
multmatrix([[1, 0, 0, -24], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {
	union() {
		cube(size = [15, 15, 15], center = true);
		sphere($fn = 0, $fa = 12, $fs = 2, r = 10);
	}
}
intersection() {
	cube(size = [15, 15, 15], center = true);
	sphere($fn = 0, $fa = 12, $fs = 2, r = 10);
}
multmatrix([[1, 0, 0, 24], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {
	difference() {
		cube(size = [15, 15, 15], center = true);
		sphere($fn = 0, $fa = 12, $fs = 2, r = 10);
	}
}
";
    let tree = csgkit::csg::openscad::parse_openscad_csg(text, Path::new(".")).unwrap();
    let mesh = one_pass(&tree);
    assert_close(volume(&mesh), 7773.408926, 1e-6, 7773.4, "CSG.scad");
}

/// Every OpenSCAD example the Debian package ships that uses only the nodes csgkit reads
/// gives a valid solid whose volume is OpenSCAD's own render of the same `.csg` export, to
/// the 7 significant digits OpenSCAD's OFF export prints (and the 2^-20 grid OpenSCAD snaps
/// to); the others are refused with an error naming their first unsupported node (an
/// imported 2D drawing by its kind). Skipped, saying so, where `openscad` is not installed.
#[test]
fn openscad_examples_match_openscad_renders() {
    let examples = std::path::Path::new("/usr/share/openscad/examples");
    let has_openscad = std::process::Command::new("openscad")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !examples.is_dir() || !has_openscad {
        eprintln!(
            "skipped: OpenSCAD and its examples are not installed (apt-get install openscad)"
        );
        return;
    }
    let dir = tempfile::TempDir::new().unwrap();
    let mut compared = 0;
    for name in [
        "Basics/CSG.scad",
        "Old/example002.scad",
        "Old/example003.scad",
        "Old/example004.scad",
        "Old/example014.scad",
        // example024 (a turned Menger sponge) and example006 (a hull of spheres, drilled)
        // evaluate too, but OpenSCAD takes 30 and 42 s to render them: they are compared in
        // benches/openscad_trees.py, and csg::tree's and mesh::hull's tests cover the same.
        // 2D shapes, their booleans and extrusions; example023's polygon goes through
        // OpenSCAD's 2^-16 grid (Clipper), which moves its volume by 3e-6.
        "Basics/linear_extrude.scad",
        "Old/example017.scad",
        "Old/example020.scad",
        "Old/example023.scad",
        // Imported STL parts: a part cut from a sphere, and a part cut by three bars. The
        // export names them relative to the model, as the `.csg` beside them reads them.
        "Old/example012.scad",
        "Old/example016.scad",
    ] {
        let scad = examples.join(name);
        if !scad.exists() {
            continue;
        }
        for part in std::fs::read_dir(scad.parent().unwrap()).unwrap() {
            let part = part.unwrap().path();
            if part.extension().is_some_and(|e| e == "stl") {
                std::fs::copy(&part, dir.path().join(part.file_name().unwrap())).unwrap();
            }
        }
        let csg = dir.path().join("model.csg");
        let off = dir.path().join("model.off");
        let export = |out: &std::path::Path, input: &std::path::Path| {
            std::process::Command::new("openscad")
                .arg("-o")
                .arg(out)
                .arg(input)
                .output()
                .unwrap()
        };
        assert!(
            export(&csg, &scad).status.success(),
            "{name}: openscad export"
        );
        assert!(
            export(&off, &csg).status.success(),
            "{name}: openscad render"
        );
        let text = std::fs::read_to_string(&csg).unwrap();
        let tree = csgkit::csg::openscad::parse_openscad_csg(&text, dir.path())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let mine = volume(&one_pass(&tree));
        let theirs = volume(&csgkit::read_mesh(&off).unwrap().mesh);
        assert_close(mine, theirs, 1e-5, theirs.abs(), name);
        compared += 1;
    }
    assert!(compared > 0, "no example found");
    let unsupported = |node: &str| format!("{node}() is not supported by csgkit's .csg reader");
    for (name, message) in [
        (
            "Old/example013.scad",
            "2D drawings (DXF, SVG) are not supported by csgkit's .csg reader".to_owned(),
        ),
        ("Advanced/offset.scad", unsupported("offset")),
        ("Basics/text_on_cube.scad", unsupported("text")),
        ("Old/example010.scad", unsupported("surface")),
        ("Old/example021.scad", unsupported("projection")),
    ] {
        let scad = examples.join(name);
        let csg = dir.path().join("unsupported.csg");
        let export = std::process::Command::new("openscad")
            .arg("-o")
            .arg(&csg)
            .arg(&scad)
            .output()
            .unwrap();
        assert!(export.status.success(), "{name}: openscad export");
        let text = std::fs::read_to_string(&csg).unwrap();
        let err = csgkit::csg::openscad::parse_openscad_csg(&text, dir.path()).unwrap_err();
        assert!(err.to_string().ends_with(&message), "{name}: {err}");
    }
}
