//! Each node's star: the faces round it, as one compressed table built in two passes
//! over the faces (a counting sort), with no edge numbering.
//!
//! This is the light connectivity that work round a few places of a large mesh needs
//! (a hole's rim, the faces round it): a node's faces, and how they run round it. It costs a fraction of the
//! half-edge [`Topology`](super::Topology), which numbers every edge of the mesh and is
//! worth building only when the whole mesh is walked.
//!
//! The first pass also sums, per node, a *balance*: for each face at the node, a hash
//! of the node the face runs to from it less a hash of the node it runs in from. Where
//! the faces close round the node, each neighbour is run to once and in from once and
//! the balance is zero; on a free edge, or where an edge has more than two faces or
//! faces wound both ways, it is not. So the nodes worth looking at come out of the pass
//! that counts the stars. (A node that is not closed could sum to zero only by a
//! collision of 64-bit hashes, about one chance in 2^64.)

use super::{FaceId, Mesh, VertexId};

/// The faces at each node of a mesh, and whether they close round it.
#[derive(Debug, Clone)]
pub struct VertexStars<'m> {
    mesh: &'m Mesh,
    /// Node `v`'s faces are `faces[offsets[v]..offsets[v + 1]]`, in id order.
    offsets: Vec<u32>,
    faces: Vec<FaceId>,
    /// Per node, the balance of the sides into and out of it (see the module notes).
    balance: Vec<u64>,
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
        let n = mesh.vertex_count();
        let mut offsets = vec![0u32; n + 1];
        let mut balance = vec![0u64; n];
        let mut add = |v: u32, to: u64, from: u64| {
            // Mesh::new checked every index against the positions.
            offsets[v as usize + 1] += 1;
            let b = &mut balance[v as usize];
            *b = b.wrapping_add(to.wrapping_sub(from));
        };
        for face in mesh.faces() {
            match *face.indices() {
                [a, b, c] => {
                    let (ha, hb, hc) = (node_hash(a), node_hash(b), node_hash(c));
                    add(a, hb, hc);
                    add(b, hc, ha);
                    add(c, ha, hb);
                }
                ref corners => {
                    let k = corners.len();
                    for i in 0..k {
                        add(
                            corners[i],
                            node_hash(corners[(i + 1) % k]),
                            node_hash(corners[(i + k - 1) % k]),
                        );
                    }
                }
            }
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        // Each node's next free slot: its row's start, moved on as faces are placed.
        let mut slot = offsets.clone();
        let mut faces = vec![FaceId(0); offsets[n] as usize];
        for (f, face) in mesh.faces().iter().enumerate() {
            for &v in face.indices() {
                let s = &mut slot[v as usize];
                faces[*s as usize] = FaceId(f as u32);
                *s += 1;
            }
        }
        VertexStars {
            mesh,
            offsets,
            faces,
            balance,
        }
    }

    /// The mesh the stars are of.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// The faces using node `v`, in id order; empty for an unused or out-of-range node.
    pub fn faces(&self, v: VertexId) -> &[FaceId] {
        match (self.offsets.get(v.index()), self.offsets.get(v.index() + 1)) {
            (Some(&start), Some(&end)) => &self.faces[start as usize..end as usize],
            _ => &[],
        }
    }

    /// Whether the faces at `v` close round it: every neighbour run to once and in from
    /// once by them (an inner node of a sound mesh, or an unused one). `false` on a free
    /// edge, at an edge of more than two faces, or where faces are wound both ways.
    pub fn closes(&self, v: VertexId) -> bool {
        self.balance.get(v.index()).is_none_or(|&b| b == 0)
    }

    /// The nodes whose faces do not close round them, in id order: every node on a free
    /// edge among them.
    pub fn open_nodes(&self) -> impl Iterator<Item = VertexId> + '_ {
        (0..self.balance.len() as u32)
            .map(VertexId)
            .filter(|&v| !self.closes(v))
    }

    /// How each face at `v` runs there, in face order.
    pub fn corners(&self, v: VertexId) -> impl Iterator<Item = Corner> + '_ {
        self.faces(v).iter().filter_map(move |&f| {
            let corners = self.mesh.faces().get(f.index())?.indices();
            let k = corners.len();
            let i = corners.iter().position(|&w| w == v.0)?;
            Some(Corner {
                face: f,
                from: VertexId(corners[(i + k - 1) % k]),
                to: VertexId(corners[(i + 1) % k]),
            })
        })
    }
}
