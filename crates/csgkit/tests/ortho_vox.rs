//! The orthogonal engine on the MagicaVoxel models of `../shared/data/voxels`: every model
//! gives a closed mesh without T-junctions whose volume equals its voxel count.

use std::collections::HashMap;

use csgkit::ortho::{MeshOptions, VoxOptions, box_union, box_union_with_materials, read_vox};

use crate::util::shared_data;

#[test]
fn every_shared_vox_model_gives_a_closed_mesh_of_the_right_volume() {
    let Some(data) = shared_data() else { return };
    let mut paths: Vec<_> = std::fs::read_dir(data.join("voxels"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vox"))
        .collect();
    paths.sort();
    assert!(!paths.is_empty());
    for path in paths {
        let read = read_vox(&std::fs::read(&path).unwrap(), VoxOptions::default()).unwrap();
        let materials: Vec<u32> = read.colors.iter().map(|&c| u32::from(c)).collect();
        let plain = box_union(&read.boxes).unwrap();
        let coloured = box_union_with_materials(&read.boxes, &materials).unwrap();
        let manifold = MeshOptions {
            triangles: true,
            manifold: true,
        };
        for (brep, options) in [
            (&plain, MeshOptions::default()),
            (&plain, manifold),
            (&coloured, MeshOptions::default()),
        ] {
            brep.check_invariants().unwrap();
            let mesh = brep.to_mesh(options).unwrap().mesh;
            // Every directed edge has its reverse: closed, and no T-junction (a vertex inside
            // an edge on one side only would leave that edge unbalanced).
            let mut balance: HashMap<(u32, u32), i64> = HashMap::new();
            for face in mesh.faces() {
                for i in 0..face.len() {
                    let (u, v) = (face[i], face[(i + 1) % face.len()]);
                    *balance.entry((u.min(v), u.max(v))).or_insert(0) += if u < v { 1 } else { -1 };
                }
            }
            assert!(
                balance.values().all(|&b| b == 0),
                "{} is not closed",
                path.display()
            );
            let p = mesh.positions();
            let six_volume: f64 = mesh
                .fan_triangles()
                .map(|(_, [a, b, c])| {
                    let (a, b, c) = (p[a as usize], p[b as usize], p[c as usize]);
                    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                        + a[2] * (b[0] * c[1] - b[1] * c[0])
                })
                .sum();
            assert_eq!(
                six_volume,
                6.0 * read.voxel_count as f64,
                "{}",
                path.display()
            );
        }
    }
}

/// A voxel model's palette survives the discrete engine: T-Rex as one solid per colour
/// (`csgkit boxes --per-material`), discretised on its own unit grid and united with a bar
/// through it, keeps every colour of the model with its voxel count, and the bar adds voxels
/// of its own material only outside the model.
#[test]
fn a_vox_palette_survives_a_discrete_union() {
    use csgkit::Operation;
    use csgkit::discrete::{DiscretizeOptions, Grid, Solid, discretize_parts, label};
    let Some(data) = shared_data() else { return };
    let read = read_vox(
        &std::fs::read(data.join("voxels/T-Rex.vox")).unwrap(),
        VoxOptions::default(),
    )
    .unwrap();
    let materials: Vec<u32> = read.colors.iter().map(|&c| u32::from(c)).collect();
    let solids = csgkit::ortho::box_union_per_material(&read.boxes, &materials).unwrap();
    let model = csgkit::ortho::per_material_mesh(&solids, MeshOptions::default())
        .unwrap()
        .mesh;
    let bar = csgkit::primitives::cuboid([10.0, 10.0, 10.0], [14.0, 14.0, 30.0]);
    let (grid, _) = Grid::for_cells(&[1.0]).unwrap();
    let options = DiscretizeOptions::default();
    let operands = [
        discretize_parts(&model, grid, 0, options).unwrap(),
        discretize_parts(&bar, grid, 0, options).unwrap(),
    ];
    assert_eq!(operands[0].len(), solids.len(), "one part per colour");
    let whole = |parts: &[csgkit::discrete::MaterialSolid]| {
        let solids: Vec<Solid> = parts.iter().map(|p| p.solid.clone()).collect();
        Solid::op_all(&solids, Operation::Union).unwrap().unwrap()
    };
    let (a, b) = (whole(&operands[0]), whole(&operands[1]));
    let union = label(&a.union(&b).unwrap(), &operands).unwrap();
    for (part, (m, brep)) in union.iter().zip(&solids) {
        assert_eq!(part.material, format!("material_{m}"));
        let voxels: f64 = brep
            .to_mesh(MeshOptions::default())
            .unwrap()
            .mesh
            .report()
            .measures
            .volume;
        assert_eq!(part.solid.voxel_count() as f64, voxels, "{}", part.material);
    }
    let added = union.last().expect("the bar's part");
    assert_eq!(added.material, "default");
    assert_eq!(
        added.solid.voxel_count(),
        b.difference(&a).unwrap().voxel_count()
    );
    let mesh = csgkit::discrete::labelled_mesh(&union).unwrap();
    assert!(mesh.report().is_valid_solid());
    assert_eq!(mesh.materials().len(), solids.len() + 1);
}
