//! Each node's star: the faces round it, as a list per node threaded through the
//! faces' corners, built in one pass over the faces, with no edge numbering.
//!
//! This is the light connectivity that work round a few places of a large mesh needs
//! (a hole's rim, the faces round it): a node's faces, and how they run round it. It
//! costs a fraction of the half-edge [`Topology`](super::Topology), which numbers every
//! edge of the mesh and is worth building only when the whole mesh is walked.
//!
//! Every face has four corner slots (`4 * face + corner`, a triangle leaving its fourth
//! unused); each node holds its first corner, and each corner the node's next. The
//! faces are taken last to first and each corner put at the head of its node's list, so
//! every list runs in face order: one write per corner, where a table of rows (counted,
//! summed, then filled) takes two passes and twice the scattered writes. Work round a
//! hole reads a few thousand stars; the build touches every face, so it is the build
//! that is made cheap.
//!
//! The same pass also sums, per node, a *balance*: for each face at the node, a hash
//! of the node the face runs to from it less a hash of the node it runs in from. Where
//! the faces close round the node, each neighbour is run to once and in from once and
//! the balance is zero; on a free edge, or where an edge has more than two faces or
//! faces wound both ways, it is not. So the nodes worth looking at come out of the pass
//! that builds the stars. (A node that is not closed could sum to zero only by a
//! collision of 64-bit hashes, about one chance in 2^64.)

use super::{FaceId, Mesh, VertexId};

/// The end of a node's list of corners. No corner slot is numbered so: a mesh has at
/// most `MAX_FACES` faces, so its last slot is `4 * MAX_FACES - 1 < u32::MAX`.
const END: u32 = u32::MAX;

/// One node's star: its first corner and its balance, side by side so the build
/// touches one place per corner.
#[derive(Debug, Clone, Copy)]
struct Star {
    /// The slot of the node's corner in its first face, or [`END`].
    first: u32,
    /// The balance of the sides into and out of it (see the module notes).
    balance: u64,
}

/// The faces at each node of a mesh, and whether they close round it.
#[derive(Debug, Clone)]
pub struct VertexStars<'m> {
    mesh: &'m Mesh,
    /// Per node, its star.
    stars: Vec<Star>,
    /// Per corner slot (`4 * face + corner`), the slot of the node's corner in its next
    /// face, or [`END`].
    next: Vec<u32>,
}

/// A node's hash in the balance: a fixed mixing of its index (SplitMix64's finaliser),
/// so that no small set of neighbours cancels out by arithmetic.
fn node_hash(v: u32) -> u64 {
    let mut z = u64::from(v).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// How one face runs at one of its nodes: the node it runs in from and the node it
/// runs on to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Corner {
    /// The face.
    pub face: FaceId,
    /// The node before this corner in the face's winding.
    pub from: VertexId,
    /// The node after it.
    pub to: VertexId,
}

impl<'m> VertexStars<'m> {
    /// The stars of every node of `mesh`.
    pub fn build(mesh: &'m Mesh) -> VertexStars<'m> {
        let mut stars = vec![
            Star {
                first: END,
                balance: 0,
            };
            mesh.vertex_count()
        ];
        let mut next = vec![END; 4 * mesh.face_count()];
        // Mesh::new checked every index against the positions, and the face count
        // against MAX_FACES (so every slot fits a u32 below END).
        let mut add = |v: u32, slot: usize, to: u64, from: u64| {
            let star = &mut stars[v as usize];
            next[slot] = star.first;
            star.first = slot as u32;
            star.balance = star.balance.wrapping_add(to.wrapping_sub(from));
        };
        for (f, face) in mesh.faces().iter().enumerate().rev() {
            let slot = 4 * f;
            match *face.indices() {
                [a, b, c] => {
                    let (ha, hb, hc) = (node_hash(a), node_hash(b), node_hash(c));
                    add(a, slot, hb, hc);
                    add(b, slot + 1, hc, ha);
                    add(c, slot + 2, ha, hb);
                }
                ref corners => {
                    let k = corners.len();
                    for i in 0..k {
                        add(
                            corners[i],
                            slot + i,
                            node_hash(corners[(i + 1) % k]),
                            node_hash(corners[(i + k - 1) % k]),
                        );
                    }
                }
            }
        }
        VertexStars { mesh, stars, next }
    }

    /// The mesh the stars are of.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// The corner slots of node `v`, in face order; none for an unused or out-of-range
    /// node.
    fn slots(&self, v: VertexId) -> impl Iterator<Item = u32> + '_ {
        let first = self.stars.get(v.index()).map_or(END, |s| s.first);
        std::iter::successors((first != END).then_some(first), |&slot| {
            let next = self.next[slot as usize];
            (next != END).then_some(next)
        })
    }

    /// The faces using node `v`, in id order; none for an unused or out-of-range node.
    pub fn faces(&self, v: VertexId) -> impl Iterator<Item = FaceId> + '_ {
        self.slots(v).map(|slot| FaceId(slot / 4))
    }

    /// Whether the faces at `v` close round it: every neighbour run to once and in from
    /// once by them (an inner node of a sound mesh, or an unused one). `false` on a free
    /// edge, at an edge of more than two faces, or where faces are wound both ways.
    pub fn closes(&self, v: VertexId) -> bool {
        self.stars.get(v.index()).is_none_or(|s| s.balance == 0)
    }

    /// The nodes whose faces do not close round them, in id order: every node on a free
    /// edge among them.
    pub fn open_nodes(&self) -> impl Iterator<Item = VertexId> + '_ {
        (0..self.stars.len() as u32)
            .map(VertexId)
            .filter(|&v| !self.closes(v))
    }

    /// How each face at `v` runs there, in face order.
    pub fn corners(&self, v: VertexId) -> impl Iterator<Item = Corner> + '_ {
        self.slots(v).map(move |slot| {
            let face = FaceId(slot / 4);
            // A slot is only threaded for a corner its face has.
            let corners = self.mesh.faces()[face.index()].indices();
            let k = corners.len();
            let i = (slot % 4) as usize;
            Corner {
                face,
                from: VertexId(corners[(i + k - 1) % k]),
                to: VertexId(corners[(i + 1) % k]),
            }
        })
    }
}
