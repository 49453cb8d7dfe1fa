//! Typed indices into a [`Mesh`](super::Mesh) and its [`Topology`](super::Topology).
//!
//! Every element kind gets its own newtype over `u32` so that a face index can never be
//! passed where a vertex index is expected. `u32` halves the memory of the connectivity
//! tables compared with `usize`; [`Mesh::new`](super::Mesh::new) rejects meshes too
//! large for it.

/// Index of a vertex (a position) in a [`Mesh`](super::Mesh).
///
/// Public so that callers can name vertices they put into a mesh themselves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VertexId(pub u32);

/// Index of a face in a [`Mesh`](super::Mesh).
///
/// Public so that callers can name faces, for example when declaring a group.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FaceId(pub u32);

/// Index of an undirected edge (an unordered vertex pair) in a
/// [`Topology`](super::Topology).
///
/// Only a topology hands these out: edge numbering is an artefact of how the topology
/// was built, so the field is private. Ids are ordered by their sorted vertex pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct EdgeId(pub(crate) u32);

/// Index of a half-edge (one side of one face, directed along the face's winding) in a
/// [`Topology`](super::Topology).
///
/// Only a topology hands these out, so the field is private. The half-edges of face `f`
/// are numbered consecutively, in the face's vertex order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct HalfEdgeId(pub(crate) u32);

macro_rules! index_impl {
    ($($t:ty),*) => {$(
        impl $t {
            /// The index as a `usize`, for indexing slices.
            #[inline]
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }
    )*};
}

index_impl!(VertexId, FaceId, EdgeId, HalfEdgeId);

impl From<u32> for VertexId {
    fn from(i: u32) -> Self {
        VertexId(i)
    }
}

impl From<u32> for FaceId {
    fn from(i: u32) -> Self {
        FaceId(i)
    }
}

/// Converts a `usize` index that the caller knows to be below `u32::MAX` (because
/// [`Mesh::new`](super::Mesh::new) bounds every count) into `u32`.
#[inline]
pub(crate) fn to_u32(i: usize) -> u32 {
    debug_assert!(
        i <= u32::MAX as usize,
        "mesh counts are bounded by Mesh::new"
    );
    i as u32
}
