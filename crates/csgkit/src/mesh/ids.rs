//! Index newtypes.
//!
//! Vertex, face and operand indices are `u32` newtypes, as in regex-automata: half the memory
//! of `usize` in the large index buffers, no casts scattered around, and no way to pass a face
//! index where a vertex index is expected. Meshes are limited to `u32::MAX` vertices, corners
//! and faces; readers reject larger counts with an error.

macro_rules! index_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(u32);

        impl $name {
            /// Wraps an index.
            ///
            /// # Panics
            /// If `index` does not fit in a `u32`; readers check counts before building.
            pub fn new(index: usize) -> Self {
                Self(u32::try_from(index).expect("mesh indices fit in u32 (checked by readers)"))
            }

            /// The index as a `usize`, for indexing buffers.
            pub fn index(self) -> usize {
                self.0 as usize
            }

            /// The raw `u32`.
            pub fn get(self) -> u32 {
                self.0
            }
        }

        impl From<u32> for $name {
            fn from(raw: u32) -> Self {
                Self(raw)
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                self.0.fmt(f)
            }
        }
    };
}

index_type!(
    /// Index of a vertex in [`Mesh::positions`](super::Mesh::positions).
    VertexId
);
index_type!(
    /// Index of a face of a [`Mesh`](super::Mesh).
    FaceId
);
index_type!(
    /// Index of an operand of an operation, in the order the operation received them.
    OperandId
);
