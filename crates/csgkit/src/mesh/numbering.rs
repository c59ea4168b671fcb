//! The faces of an operation's source meshes numbered densely, operand after operand, so a
//! [`Provenance`] indexes a flat table (face groups, counts per source face).

use super::{FaceId, Mesh, OperandId, Provenance};

/// Dense ids of the faces of several meshes: operand `k`'s face `f` is `start[k] + f`.
#[derive(Clone, Debug)]
pub(crate) struct FaceNumbering {
    /// The first id of each operand, and the total at the end.
    start: Vec<u32>,
}

impl FaceNumbering {
    pub(crate) fn new(sources: &[&Mesh]) -> Self {
        let mut start = Vec::with_capacity(sources.len() + 1);
        let mut total = 0u32;
        for mesh in sources {
            start.push(total);
            total += mesh.face_count() as u32;
        }
        start.push(total);
        Self { start }
    }

    /// How many faces all sources have.
    pub(crate) fn total(&self) -> u32 {
        *self.start.last().expect("a total")
    }

    /// The id of face `face` of operand `operand`.
    pub(crate) fn id(&self, operand: usize, face: FaceId) -> u32 {
        self.start[operand] + face.get()
    }

    /// The id of the source face `p` names.
    pub(crate) fn of(&self, p: Provenance) -> u32 {
        self.id(p.operand.index(), p.face)
    }

    /// The source face with id `id`.
    pub(crate) fn provenance(&self, id: u32) -> Provenance {
        let k = self.start.partition_point(|&b| b <= id) - 1;
        Provenance {
            operand: OperandId::new(k),
            face: FaceId::new((id - self.start[k]) as usize),
        }
    }
}
