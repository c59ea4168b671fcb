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
