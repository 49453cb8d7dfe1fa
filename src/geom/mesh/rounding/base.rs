//! The base meshes of a round (paper 000, section 2, step 1): the faces within reach of
//! the chain, split by it into the two groups the ball rolls on, one on each side.

use std::cell::Cell;
use std::collections::BTreeSet;

use glam::DVec3;

use super::chain::SharpChain;
use super::chain_polyline;
use super::index::PolylineIndex;
use crate::geom::mesh::{FaceId, Mesh, Topology, VertexId};

/// How far from the chain base faces are taken, in ball radii: the paper's 3R.
pub const BASE_REACH: f64 = 3.0;

/// The two base meshes of a chain: the faces on its left (the side of the faces whose
/// winding runs along the chain) and on its right, each within reach of it.
#[derive(Debug, Clone, PartialEq)]
pub struct BaseMeshes {
    /// The faces on the chain's left, ascending.
    pub left: Vec<FaceId>,
    /// The faces on its right, ascending.
    pub right: Vec<FaceId>,
}

/// Why the base meshes could not be split.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BaseError {
    /// The faces on the two sides of the chain join round it within reach (an open
    /// chain that ends inside the mesh, short of its boundary): the ball has no one
    /// side to roll on.
    #[error(
        "the chain does not split the mesh near it in two: its two sides join round face {face}"
    )]
    NotSplit { face: u32 },
    /// A chain edge does not have two faces.
    #[error("a chain edge has not two faces")]
    NotTwoFaces,
}

/// The base meshes of `chain` for a ball of radius `radius` (the mean radius, for a
/// variable one): from the faces beside each chain edge, every face reached across an
/// edge not on the chain with a corner within [`BASE_REACH`] `radius` of the chain.
/// Refused when the two sides meet.
pub fn base_meshes(
    mesh: &Mesh,
    topology: &Topology,
    chain: &SharpChain,
    radius: f64,
) -> Result<BaseMeshes, BaseError> {
    let on_chain: BTreeSet<_> = chain.edges.iter().copied().collect();
    let reach = BASE_REACH * radius;
    let line = chain_polyline(mesh, chain);
    let within = Reach::new(mesh, &line, reach);
    let near = |f: FaceId| within.face(f);
    // The seeds: each chain edge's face whose side runs along the chain, and the other.
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for (k, &e) in chain.edges.iter().enumerate() {
        let from = chain.nodes[k];
        let halves = topology.edge_half_edges(e);
        let [a, b] = *halves else {
            return Err(BaseError::NotTwoFaces);
        };
        let (along, against) = if topology.origin(a) == from {
            (a, b)
        } else {
            (b, a)
        };
        left.push(topology.face(along));
        right.push(topology.face(against));
    }
    let flood = |seeds: &[FaceId]| -> BTreeSet<FaceId> {
        let mut seen: BTreeSet<FaceId> = seeds.iter().copied().collect();
        let mut queue: Vec<FaceId> = seeds.to_vec();
        while let Some(f) = queue.pop() {
            for h in topology.face_half_edges(f) {
                let e = topology.edge(h);
                if on_chain.contains(&e) {
                    continue;
                }
                for g in topology.edge_faces(e) {
                    if near(g) && seen.insert(g) {
                        queue.push(g);
                    }
                }
            }
        }
        seen
    };
    let (left, right) = (flood(&left), flood(&right));
    if let Some(&f) = left.intersection(&right).next() {
        return Err(BaseError::NotSplit { face: f.0 });
    }
    Ok(BaseMeshes {
        left: left.into_iter().collect(),
        right: right.into_iter().collect(),
    })
}

/// Which faces of a mesh have a corner within a reach of a polyline (the chain, or an
/// existing round's middle line): what the base meshes' flood asks of every face it
/// meets. Each node's answer is worked out once, as the flood asks it from every face
/// round the node and each answer walks the whole line.
pub(super) struct Reach<'a> {
    mesh: &'a Mesh,
    line: PolylineIndex,
    reach: f64,
    within: Vec<Cell<Option<bool>>>,
}

impl<'a> Reach<'a> {
    /// The faces of `mesh` within `reach` of `line`.
    pub(super) fn new(mesh: &'a Mesh, line: &[DVec3], reach: f64) -> Reach<'a> {
        Reach {
            mesh,
            line: PolylineIndex::new(line),
            reach,
            within: (0..mesh.vertex_count()).map(|_| Cell::new(None)).collect(),
        }
    }

    /// Whether node `v` lies within reach.
    fn node(&self, v: VertexId) -> bool {
        let slot = &self.within[v.index()];
        slot.get().unwrap_or_else(|| {
            let near = self
                .mesh
                .position(v)
                .is_some_and(|p| self.line.nearest(p).0 <= self.reach);
            slot.set(Some(near));
            near
        })
    }

    /// Whether face `f` has a corner within reach.
    pub(super) fn face(&self, f: FaceId) -> bool {
        self.mesh
            .face(f)
            .is_some_and(|face| face.vertices().any(|v| self.node(v)))
    }
}
