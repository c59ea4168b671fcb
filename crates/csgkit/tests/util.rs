//! Fixtures shared by the integration tests.

use std::path::PathBuf;

/// The shared data folder (`../shared/data` beside the repository, or `$CSGKIT_SHARED_DATA`
/// for a work tree kept elsewhere), or `None` with a message when it is absent, so tests that
/// need real data skip instead of failing.
pub fn shared_data() -> Option<PathBuf> {
    let dir = std::env::var_os("CSGKIT_SHARED_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
        PathBuf::from,
    );
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipping: shared data folder {} is absent", dir.display());
        None
    }
}

/// A file in the repository's own test data (`crates/csgkit/tests/data`).
pub fn repo_data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The rotation by `angle` radians about `axis` (any non-zero length), by Rodrigues' formula.
pub fn rotation(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let norm = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = axis.map(|a| a / norm);
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

/// `mesh` with every position `p` replaced by `rotation · p + translation` (rounded to f64);
/// faces and attributes are kept.
pub fn transformed(
    mesh: &csgkit::Mesh,
    rotation: &[[f64; 3]; 3],
    translation: [f64; 3],
) -> csgkit::Mesh {
    let mut parts = mesh.clone().into_parts();
    for p in &mut parts.positions {
        let q = *p;
        *p = std::array::from_fn(|i| {
            rotation[i][0] * q[0] + rotation[i][1] * q[1] + rotation[i][2] * q[2] + translation[i]
        });
    }
    csgkit::Mesh::from_parts(parts).expect("moving vertices keeps the invariants")
}

/// `mesh` moved by `offset` (rounded to f64).
pub fn translated(mesh: &csgkit::Mesh, offset: [f64; 3]) -> csgkit::Mesh {
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    transformed(mesh, &identity, offset)
}

/// The signed volume of `mesh`, exactly: the sum of its fan triangles' determinants, over 6,
/// in rational arithmetic on the f64 coordinates.
pub fn exact_volume(mesh: &csgkit::Mesh) -> num_rational::BigRational {
    use num_rational::BigRational as Q;
    use num_traits::Zero;
    let q = |x: f64| Q::from_float(x).expect("finite coordinate");
    let mut volume6 = Q::zero();
    for (_, corners) in mesh.fan_triangles() {
        let [a, b, c] = corners.map(|v| mesh.positions()[v as usize].map(q));
        volume6 += &a[0] * (&b[1] * &c[2] - &b[2] * &c[1])
            - &a[1] * (&b[0] * &c[2] - &b[2] * &c[0])
            + &a[2] * (&b[0] * &c[1] - &b[1] * &c[0]);
    }
    volume6 / Q::from_integer(6.into())
}

/// The area of `mesh`, exactly, when every triangle of its faces lies in an axis-aligned plane
/// (its normal has one non-zero component, whose absolute value is twice its area); otherwise
/// the first face that does not, with its corners, or the face that cannot be triangulated.
///
/// Boxes and their unions have only such faces. An output vertex that is a rounded
/// intersection point keeps the coordinate of its plane (any f64, an integer in particular, is
/// its own nearest f64) and moves only within it, which changes neither the area nor the
/// volume of the tiling.
pub fn axis_aligned_area(mesh: &csgkit::Mesh) -> Result<num_rational::BigRational, String> {
    use num_rational::BigRational as Q;
    use num_traits::{Signed, Zero};
    let q = |x: f64| Q::from_float(x).expect("finite coordinate");
    let mut area2 = Q::zero();
    let triangles = csgkit::mesh::triangulate_faces(mesh).map_err(|e| e.to_string())?;
    for (f, corners) in triangles.iter() {
        let [a, b, c] = corners.map(|v| mesh.positions()[v as usize].map(q));
        let u: [Q; 3] = std::array::from_fn(|i| &b[i] - &a[i]);
        let v: [Q; 3] = std::array::from_fn(|i| &c[i] - &a[i]);
        let n = [
            &u[1] * &v[2] - &u[2] * &v[1],
            &u[2] * &v[0] - &u[0] * &v[2],
            &u[0] * &v[1] - &u[1] * &v[0],
        ];
        if n.iter().filter(|x| !x.is_zero()).count() > 1 {
            return Err(format!(
                "face {} is not in an axis-aligned plane: corners {:?}",
                f.index(),
                corners.map(|v| mesh.positions()[v as usize])
            ));
        }
        for x in &n {
            area2 += x.abs();
        }
    }
    Ok(area2 / Q::from_integer(2.into()))
}

/// Reads `meshes/<name>` of the shared data folder `data`.
pub fn load(data: &std::path::Path, name: &str) -> csgkit::Mesh {
    csgkit::read_mesh(data.join("meshes").join(name))
        .unwrap_or_else(|e| panic!("{e}"))
        .mesh
}

/// The bounding box of a mesh with faces.
pub fn bbox(mesh: &csgkit::Mesh) -> csgkit::mesh::BoundingBox {
    mesh.report().measures.bbox.expect("the mesh has faces")
}

/// The length of the diagonal of `b`.
pub fn diagonal(b: &csgkit::mesh::BoundingBox) -> f64 {
    (0..3)
        .map(|i| (b.max[i] - b.min[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Asserts the exact self-intersection check finds nothing in `mesh` (every output of the
/// exact engine is certified so).
pub fn assert_no_self_intersection(mesh: &csgkit::Mesh, what: &str) {
    let found = csgkit::self_intersections(mesh);
    assert!(
        found.is_empty(),
        "{what}: {} self-intersecting face pairs, first {:?}",
        found.pair_count(),
        found.pairs.iter().take(5).collect::<Vec<_>>()
    );
}

/// `mesh` written to a file of `format` (STL: binary, f32) and read back, as the next
/// command of a chain reads it.
pub fn through_a_file(mesh: &csgkit::Mesh, format: csgkit::Format) -> csgkit::Mesh {
    let bytes = csgkit::write_mesh_to_bytes(mesh, format, csgkit::Encoding::Binary)
        .expect("a result writes");
    (csgkit::read_mesh_from_bytes(&bytes, Some(format)))
        .expect("a written file reads back")
        .mesh
}

/// Asserts `mesh` is a valid solid (closed, consistently oriented, of positive volume) in
/// which the exact self-intersection check finds nothing: a valid operand of the next boolean.
pub fn assert_valid_operand(mesh: &csgkit::Mesh, what: &str) {
    let report = mesh.report();
    assert!(report.is_valid_solid(), "{what}: {report:?}");
    assert_no_self_intersection(mesh, what);
}

/// Asserts `|x − y| ≤ tolerance · scale`: a volume compared with another to a relative
/// tolerance of the operands' volumes (`scale`).
pub fn assert_close(x: f64, y: f64, tolerance: f64, scale: f64, what: &str) {
    assert!(
        (x - y).abs() <= tolerance * scale,
        "{what}: {x} vs {y} (difference {:e}, allowed {:e})",
        (x - y).abs(),
        tolerance * scale
    );
}

/// The box `[min, max]` as six quads, material `materials[k]` on the two faces normal to axis
/// `k`.
pub fn box_of_quads(min: [f64; 3], max: [f64; 3], materials: [&str; 3]) -> csgkit::Mesh {
    let positions: Vec<[f64; 3]> = (0..8)
        .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { max[k] } else { min[k] }))
        .collect();
    // Outward quads: axis, side, corners (vertex index bit k = coordinate k at max).
    let quads = [
        (0, [0, 4, 6, 2]),
        (0, [1, 3, 7, 5]),
        (1, [0, 1, 5, 4]),
        (1, [2, 6, 7, 3]),
        (2, [0, 2, 3, 1]),
        (2, [4, 5, 7, 6]),
    ];
    let mut names: Vec<String> = Vec::new();
    let face_materials: Vec<u32> = (quads.iter())
        .map(|&(axis, _)| {
            let name = materials[axis].to_owned();
            let id = names.iter().position(|n| *n == name).unwrap_or_else(|| {
                names.push(name);
                names.len() - 1
            });
            id as u32
        })
        .collect();
    csgkit::Mesh::from_parts(csgkit::MeshParts {
        positions,
        corners: quads.iter().flat_map(|(_, q)| *q).collect(),
        face_starts: Some((0..=6).map(|f| 4 * f).collect()),
        face_materials: Some(face_materials),
        materials: names,
        ..Default::default()
    })
    .expect("a valid box")
}

/// The normal of a polygon (the sum over a fan of its corners), any length.
pub fn polygon_normal(p: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    for i in 1..p.len() - 1 {
        let (u, w) = (
            [0, 1, 2].map(|k| p[i][k] - p[0][k]),
            [0, 1, 2].map(|k| p[i + 1][k] - p[0][k]),
        );
        n[0] += u[1] * w[2] - u[2] * w[1];
        n[1] += u[2] * w[0] - u[0] * w[2];
        n[2] += u[0] * w[1] - u[1] * w[0];
    }
    n
}
