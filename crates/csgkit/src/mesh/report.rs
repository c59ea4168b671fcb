//! One report gathering every validity check and measure of a mesh.
//!
//! [`analyze`] welds equal vertices (`-0.0` with `+0.0`) ([`super::weld`]), then runs the topology
//! ([`super::analyze_topology`]), the exact degeneracy checks ([`super::count_degenerate`]) and
//! the geometric measures ([`super::measure`]) on the welded mesh. The module docs of each
//! define its numbers; `shared/data/manifest.json` names the same quantities as follows:
//! `raw_verts` = `vertices`, `raw_faces` = `faces`, `ngons` = `polygons`,
//! `dup_verts` = `duplicate_vertices`, `unref_verts` = `unreferenced_vertices`,
//! `comb_degen` = `repeated_vertex_faces`, `zero_area` = `degenerate_faces`,
//! `dup_faces` = `duplicate_faces`, `boundary_e`, `boundary_loops`, `nonmanif_e`,
//! `nonmanif_v`, `misoriented_e`, `components`, `euler`, `genus`, `volume` and `bbox`
//! likewise; `edges` differs by the fan diagonals of polygons (see [`super::Topology`]).
//!
//! A mesh is a **valid solid** when it is closed (every edge balanced) and consistently
//! oriented. Non-manifold edges and vertices are allowed: two cubes sharing an edge bound a
//! solid, and the boolean engines must accept and produce such meshes.
//!
//! # Complexity
//! Linear in practice: hash maps for welding, bucketed sorts for edges, and one sort of the
//! faces for duplicates (O(F log F)). The topology, the degeneracy checks and the measures run
//! in parallel (rayon), each sequential inside.

use std::borrow::Cow;

use serde::Serialize;

use super::{Measures, Mesh, Topology};
use crate::par;

/// Every validity check and measure of a mesh, ready to print or serialize as JSON.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshReport {
    /// Vertices stored in the mesh, before welding.
    pub vertices: usize,
    /// Faces stored in the mesh.
    pub faces: usize,
    /// Faces with more than three corners.
    pub polygons: usize,
    /// Triangles of every face split without new vertices: n − 2 for a face of n corners, as a
    /// fan gives (the reference's count) and [`triangulate_faces`](super::triangulate_faces)
    /// gives for a simple polygon.
    pub triangles: usize,
    /// Stored vertices that repeat an earlier position (equal coordinates).
    pub duplicate_vertices: usize,
    /// Distinct positions after welding.
    pub welded_vertices: usize,
    /// Faces with a repeated vertex after welding.
    pub repeated_vertex_faces: usize,
    /// Faces with distinct but exactly collinear vertices.
    pub collinear_faces: usize,
    /// Faces of zero area: repeated-vertex and collinear faces together.
    pub degenerate_faces: usize,
    /// Faces whose vertex set repeats an earlier face's.
    pub duplicate_faces: usize,
    /// Edges, boundary, manifoldness, orientation, components, Euler characteristic, genus.
    #[serde(flatten)]
    pub topology: Topology,
    /// Closed: every edge has as many uses in each direction.
    pub closed: bool,
    /// No edge has three or more uses.
    pub edge_manifold: bool,
    /// No vertex has more than one fan.
    pub vertex_manifold: bool,
    /// Every two-use edge is traversed once in each direction.
    pub oriented: bool,
    /// Closed and oriented: a solid the boolean engines accept.
    pub valid_solid: bool,
    /// Signed volume, area and bounding box.
    #[serde(flatten)]
    pub measures: Measures,
}

impl MeshReport {
    /// Closed and consistently oriented (non-manifold edges allowed).
    pub fn is_valid_solid(&self) -> bool {
        self.valid_solid
    }

    /// Counts the vertices a file stored rather than those of the mesh read from it.
    ///
    /// Readers of formats without shared vertices (STL) weld on read, so the mesh has fewer
    /// vertices than the file; this sets [`vertices`](Self::vertices) to the file's count and
    /// counts the vertices welded away by the reader as duplicates too.
    pub fn count_file_vertices(&mut self, file_vertices: usize) {
        self.vertices = file_vertices;
        self.duplicate_vertices = file_vertices.saturating_sub(self.welded_vertices);
    }
}

/// Welds the mesh and computes every check and measure.
///
/// # Example
/// ```
/// use csgkit::Mesh;
///
/// // A tetrahedron wound outward.
/// let positions = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let mesh = Mesh::from_triangles(positions, &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])?;
/// let report = csgkit::mesh::analyze(&mesh);
/// assert!(report.is_valid_solid());
/// assert_eq!(report.topology.genus, Some(0));
/// assert_eq!(report.measures.volume, 1.0 / 6.0);
/// # Ok::<(), csgkit::InvalidMesh>(())
/// ```
pub fn analyze(mesh: &Mesh) -> MeshReport {
    let welding = super::weld_positions(mesh.positions());
    // Most meshes other than STL have nothing to weld: skip the copy then.
    let welded = if welding.duplicate_count() == 0 {
        Cow::Borrowed(mesh)
    } else {
        Cow::Owned(super::apply_welding(mesh, &welding))
    };
    // The three analyses are independent; run them side by side (the answer does not depend
    // on the thread count).
    let (topology, (degenerate, measures)) = par::join(
        || super::analyze_topology(&welded),
        || {
            par::join(
                || super::count_degenerate(&welded),
                || super::measure(&welded),
            )
        },
    );
    let polygons = mesh.faces().filter(|f| f.len() > 3).count();
    let closed = topology.is_closed();
    let oriented = topology.is_oriented();
    MeshReport {
        vertices: mesh.vertex_count(),
        faces: mesh.face_count(),
        polygons,
        triangles: mesh.corner_count() - 2 * mesh.face_count(),
        duplicate_vertices: welding.duplicate_count(),
        welded_vertices: welding.welded_count(),
        repeated_vertex_faces: degenerate.repeated_vertex,
        collinear_faces: degenerate.collinear,
        degenerate_faces: degenerate.repeated_vertex + degenerate.collinear,
        duplicate_faces: degenerate.duplicate,
        closed,
        edge_manifold: topology.is_edge_manifold(),
        vertex_manifold: topology.is_vertex_manifold(),
        oriented,
        valid_solid: closed && oriented,
        topology,
        measures,
    }
}

impl Mesh {
    /// Every validity check and measure of this mesh; see [`analyze`].
    pub fn report(&self) -> MeshReport {
        analyze(self)
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh::test_meshes::{cube, open_box, tetrahedron, torus, two_cubes_sharing_an_edge};
    use crate::mesh::{Mesh, MeshParts};

    #[test]
    fn cube_is_a_valid_genus_0_solid() {
        let report = cube([0.0; 3], 1.0).report();
        assert!(report.is_valid_solid());
        assert!(report.edge_manifold && report.vertex_manifold);
        let t = &report.topology;
        assert_eq!(
            (t.edges, t.components, t.euler, t.genus),
            (18, 1, 2, Some(0))
        );
        assert_eq!(report.measures.volume, 1.0);
    }

    #[test]
    fn two_cubes_sharing_an_edge_are_a_valid_solid() {
        let report = two_cubes_sharing_an_edge().report();
        assert_eq!(report.duplicate_vertices, 2);
        assert!(report.closed && report.oriented && report.valid_solid);
        assert!(!report.edge_manifold);
        let t = &report.topology;
        assert_eq!(t.non_manifold_edges, 1);
        assert_eq!(t.non_manifold_vertices, 0);
        assert_eq!(t.components, 1);
        assert_eq!(t.genus, None, "genus needs an edge-manifold mesh");
        assert_eq!(report.measures.volume, 2.0);
    }

    #[test]
    fn flipped_face_breaks_orientation_and_balance() {
        let good = tetrahedron(false).report();
        assert!(good.valid_solid);
        assert!((good.measures.volume - 1.0 / 6.0).abs() < 1e-15);
        let bad = tetrahedron(true).report();
        assert!(!bad.oriented && !bad.closed && !bad.valid_solid);
        assert_eq!(bad.topology.misoriented_edges, 3);
        assert_eq!(bad.topology.unbalanced_edges, 3);
        assert_eq!(bad.topology.boundary_edges, 0);
    }

    #[test]
    fn open_box_has_one_boundary_loop_of_four_edges() {
        let report = open_box().report();
        assert!(!report.closed && !report.valid_solid);
        let t = &report.topology;
        assert_eq!((t.boundary_edges, t.boundary_loops), (4, 1));
        assert_eq!((t.euler, t.genus), (1, None));
    }

    #[test]
    fn torus_has_genus_1_as_triangles_and_as_quads() {
        for split in [true, false] {
            let report = torus(4, split).report();
            assert!(report.valid_solid, "split = {split}");
            assert_eq!(report.topology.euler, 0);
            assert_eq!(report.topology.genus, Some(1));
            assert!(report.measures.volume > 0.0);
        }
        assert_eq!(torus(4, false).report().topology.edges, 32);
    }

    #[test]
    fn degenerate_faces_are_counted_and_left_out_of_the_topology() {
        // A cube plus a sliver (0, 1, 1) and a collinear triangle on the cube's bottom edge.
        let mut parts = cube([0.0; 3], 1.0).into_parts();
        parts.positions.push([0.5, 0.0, 0.0]);
        parts.corners.extend([0, 1, 1, 0, 8, 1]);
        let report = Mesh::from_parts(parts).unwrap().report();
        assert_eq!(report.repeated_vertex_faces, 1);
        assert_eq!(report.collinear_faces, 1);
        assert_eq!(report.degenerate_faces, 2);
        assert_eq!(report.topology.excluded_faces, 1);
        // The collinear face takes part: its two new edges are boundary edges, and the cube
        // edge 0-1 gets a third use.
        assert_eq!(report.topology.boundary_edges, 2);
        assert_eq!(report.topology.non_manifold_edges, 1);
        assert_eq!(report.topology.boundary_loops, 1);
    }

    #[test]
    fn pinched_vertex_is_non_manifold() {
        // Two tetrahedra sharing only vertex 0.
        let mut parts: MeshParts = tetrahedron(false).into_parts();
        parts
            .positions
            .extend([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
        parts.corners.extend([0, 4, 5, 0, 6, 4, 0, 5, 6, 4, 6, 5]);
        let report = Mesh::from_parts(parts).unwrap().report();
        assert!(report.valid_solid && report.edge_manifold);
        assert_eq!(report.measures.volume, 2.0 / 6.0);
        let t = &report.topology;
        assert_eq!(t.non_manifold_vertices, 1);
        assert_eq!((t.components, t.vertex_components), (2, 1));
        assert_eq!(t.genus, None);
    }

    #[test]
    fn json_report_is_flat_and_writes_non_finite_as_null() {
        let mut report = cube([0.0; 3], 1.0).report();
        report.measures.volume = f64::INFINITY;
        let json = serde_json::to_value(&report).unwrap();
        assert_eq!(json["boundary_loops"], 0);
        assert_eq!(json["genus"], 0);
        assert_eq!(json["valid_solid"], true);
        assert_eq!(json["bbox"]["max"][2], 1.0);
        assert!(json["volume"].is_null());
    }

    #[test]
    fn file_vertices_count_as_duplicates() {
        let mut report = cube([0.0; 3], 1.0).report();
        report.count_file_vertices(36);
        assert_eq!((report.vertices, report.duplicate_vertices), (36, 28));
    }

    #[test]
    fn non_finite_coordinates_do_not_panic() {
        let mut parts = cube([0.0; 3], 1.0).into_parts();
        parts.positions[0] = [f64::NAN, 0.0, 0.0];
        parts.positions[7] = [f64::INFINITY, f64::NEG_INFINITY, 1.0];
        let report = Mesh::from_parts(parts).unwrap().report();
        // Topology needs no coordinate: the cube is still a closed genus-0 surface.
        assert!(report.valid_solid);
        assert_eq!(report.topology.genus, Some(0));
        assert!(report.measures.volume.is_nan());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]

        /// Any buffers either fail validation with an error or analyse without a panic.
        #[test]
        fn arbitrary_buffers_never_panic(
            positions in proptest::collection::vec(
                proptest::array::uniform3(proptest::prelude::any::<f64>()), 0..8),
            corners in proptest::collection::vec(0u32..10, 0..24),
            face_starts in proptest::option::of(proptest::collection::vec(0u32..26, 0..8)),
        ) {
            let parts = MeshParts { positions, corners, face_starts, ..MeshParts::default() };
            if let Ok(mesh) = Mesh::from_parts(parts) {
                let report = mesh.report();
                proptest::prop_assert!(report.topology.edges <= mesh.corner_count());
            }
        }
    }

    #[test]
    fn empty_mesh_reports_zeros() {
        let report = Mesh::new().report();
        assert!(report.closed && report.oriented);
        assert_eq!(report.topology.components, 0);
        assert_eq!(report.topology.genus, Some(0));
        assert_eq!(report.measures.bbox, None);
    }
}
