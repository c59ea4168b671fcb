//! Structural invariants of [`Mesh`](super::Mesh) buffers.
//!
//! This checks the storage contract only (indices in range, buffer lengths, face sizes).
//! Whether a mesh is a valid *solid* (closed, oriented, manifold) is a measure, not an
//! invariant: an open mesh is still a mesh.

use super::MeshParts;

/// A broken structural invariant of a mesh's buffers.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum InvalidMesh {
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but the mesh has {vertex_count} vertices")]
    VertexOutOfRange {
        /// The face at fault.
        face: usize,
        /// The index it uses.
        vertex: u32,
        /// The number of vertices.
        vertex_count: usize,
    },
    /// A face has fewer than three corners.
    #[error("face {face} has {corners} corners; a face needs at least 3")]
    TooFewCorners {
        /// The face at fault.
        face: usize,
        /// Its corner count.
        corners: usize,
    },
    /// The face offsets are not a valid partition of the corner buffer.
    #[error("face offsets are malformed: {reason}")]
    MalformedOffsets {
        /// What is wrong with them.
        reason: &'static str,
    },
    /// An attribute buffer has the wrong length.
    #[error("{attribute} has {actual} entries; expected {expected}")]
    AttributeLength {
        /// The attribute's name.
        attribute: &'static str,
        /// Its length.
        actual: usize,
        /// One per face, corner or vertex.
        expected: usize,
    },
    /// A face's material or group id has no name.
    #[error("face {face} has {table} id {id}, but only {table_len} names exist")]
    NameOutOfRange {
        /// "material" or "group".
        table: &'static str,
        /// The face at fault.
        face: usize,
        /// Its id.
        id: u32,
        /// The table's length.
        table_len: usize,
    },
    /// The mesh is too large for `u32` indices.
    #[error("{what} count {count} exceeds the limit of {limit}", limit = u32::MAX)]
    TooLarge {
        /// What overflowed.
        what: &'static str,
        /// The count.
        count: usize,
    },
}

/// Checks the invariants listed in the [module docs of `mesh`](super).
pub(super) fn check_parts(parts: &MeshParts) -> Result<(), InvalidMesh> {
    check_sizes(parts)?;
    let face_count = check_faces(parts)?;
    check_attributes(parts, face_count)
}

fn check_sizes(parts: &MeshParts) -> Result<(), InvalidMesh> {
    for (what, count) in [
        ("vertex", parts.positions.len()),
        ("corner", parts.corners.len()),
    ] {
        if count > u32::MAX as usize {
            return Err(InvalidMesh::TooLarge { what, count });
        }
    }
    Ok(())
}

/// Checks face sizes and corner indices; returns the face count.
fn check_faces(parts: &MeshParts) -> Result<usize, InvalidMesh> {
    let vertex_count = parts.positions.len();
    let check_face = |face: usize, corners: &[u32]| {
        if corners.len() < 3 {
            return Err(InvalidMesh::TooFewCorners {
                face,
                corners: corners.len(),
            });
        }
        match corners.iter().find(|&&v| v as usize >= vertex_count) {
            Some(&vertex) => Err(InvalidMesh::VertexOutOfRange {
                face,
                vertex,
                vertex_count,
            }),
            None => Ok(()),
        }
    };
    match &parts.face_starts {
        None => {
            if parts.corners.len() % 3 != 0 {
                return Err(InvalidMesh::MalformedOffsets {
                    reason: "a triangle mesh's corner count must be a multiple of 3",
                });
            }
            for (face, corners) in parts.corners.chunks_exact(3).enumerate() {
                check_face(face, corners)?;
            }
            Ok(parts.corners.len() / 3)
        }
        Some(starts) => {
            if starts.first() != Some(&0) {
                return Err(InvalidMesh::MalformedOffsets {
                    reason: "the first offset must be 0",
                });
            }
            if *starts.last().expect("not empty: first exists") as usize != parts.corners.len() {
                return Err(InvalidMesh::MalformedOffsets {
                    reason: "the last offset must equal the corner count",
                });
            }
            for (face, pair) in starts.windows(2).enumerate() {
                // The last offset equals the corner count, so one past it must decrease later;
                // checking it here keeps the slice below in bounds.
                if pair[1] < pair[0] || pair[1] as usize > parts.corners.len() {
                    return Err(InvalidMesh::MalformedOffsets {
                        reason: "offsets must not decrease",
                    });
                }
                check_face(face, &parts.corners[pair[0] as usize..pair[1] as usize])?;
            }
            Ok(starts.len() - 1)
        }
    }
}

fn check_attributes(parts: &MeshParts, face_count: usize) -> Result<(), InvalidMesh> {
    fn check_len<T>(
        attribute: &'static str,
        values: &Option<Vec<T>>,
        expected: usize,
    ) -> Result<(), InvalidMesh> {
        match values {
            Some(values) if values.len() != expected => Err(InvalidMesh::AttributeLength {
                attribute,
                actual: values.len(),
                expected,
            }),
            _ => Ok(()),
        }
    }
    fn check_names(
        table: &'static str,
        ids: &Option<Vec<u32>>,
        names: &[String],
    ) -> Result<(), InvalidMesh> {
        let bad = ids
            .iter()
            .flatten()
            .enumerate()
            .find(|&(_, &id)| id as usize >= names.len());
        match bad {
            Some((face, &id)) => Err(InvalidMesh::NameOutOfRange {
                table,
                face,
                id,
                table_len: names.len(),
            }),
            None => Ok(()),
        }
    }
    let corners = parts.corners.len();
    check_len("face materials", &parts.face_materials, face_count)?;
    check_len("face groups", &parts.face_groups, face_count)?;
    check_len("face colours", &parts.face_colors, face_count)?;
    check_len("face provenance", &parts.face_provenance, face_count)?;
    check_len("corner UVs", &parts.corner_uvs, corners)?;
    check_len("corner normals", &parts.corner_normals, corners)?;
    check_len(
        "vertex colours",
        &parts.vertex_colors,
        parts.positions.len(),
    )?;
    check_names("material", &parts.face_materials, &parts.materials)?;
    check_names("group", &parts.face_groups, &parts.groups)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn rejects_out_of_range_corner() {
        let err = Mesh::from_triangles(vec![[0.0; 3]; 3], &[[0, 1, 3]]).unwrap_err();
        assert_eq!(
            err,
            InvalidMesh::VertexOutOfRange {
                face: 0,
                vertex: 3,
                vertex_count: 3
            }
        );
    }

    #[test]
    fn rejects_two_corner_face() {
        let err = Mesh::from_parts(MeshParts {
            positions: vec![[0.0; 3]; 3],
            corners: vec![0, 1, 2, 0, 1],
            face_starts: Some(vec![0, 3, 5]),
            ..MeshParts::default()
        })
        .unwrap_err();
        assert_eq!(
            err,
            InvalidMesh::TooFewCorners {
                face: 1,
                corners: 2
            }
        );
    }

    #[test]
    fn rejects_malformed_offsets_with_the_exact_reason() {
        let parts = |corners: Vec<u32>, face_starts: Option<Vec<u32>>| MeshParts {
            positions: vec![[0.0; 3]; 4],
            corners,
            face_starts,
            ..MeshParts::default()
        };
        let reason = |parts| match Mesh::from_parts(parts) {
            Err(InvalidMesh::MalformedOffsets { reason }) => reason,
            other => panic!("expected malformed offsets, got {other:?}"),
        };
        assert_eq!(
            reason(parts(vec![0, 1, 2, 3], None)),
            "a triangle mesh's corner count must be a multiple of 3"
        );
        let quad = vec![0, 1, 2, 3];
        assert_eq!(
            reason(parts(quad.clone(), Some(vec![1, 4]))),
            "the first offset must be 0"
        );
        assert_eq!(
            reason(parts(quad.clone(), Some(vec![0, 3]))),
            "the last offset must equal the corner count"
        );
        assert_eq!(
            reason(parts(quad, Some(vec![0, 5, 4]))),
            "offsets must not decrease"
        );
    }

    #[test]
    fn rejects_short_attribute_and_unnamed_material() {
        let base = MeshParts {
            positions: vec![[0.0; 3]; 3],
            corners: vec![0, 1, 2],
            ..MeshParts::default()
        };
        let short = MeshParts {
            face_colors: Some(vec![]),
            ..base.clone()
        };
        assert!(matches!(
            Mesh::from_parts(short),
            Err(InvalidMesh::AttributeLength { .. })
        ));
        let unnamed = MeshParts {
            face_materials: Some(vec![0]),
            ..base
        };
        assert!(matches!(
            Mesh::from_parts(unnamed),
            Err(InvalidMesh::NameOutOfRange { .. })
        ));
    }
}
