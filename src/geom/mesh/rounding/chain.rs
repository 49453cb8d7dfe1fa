//! The chain of sharp edges to round (paper 000, section 2, step 1): from a picked
//! node, the edges whose dihedral angle exceeds the feature angle θ are followed both
//! ways, until the mesh's boundary (or the chain's end) or back to the start.

use glam::DVec3;

use crate::geom::mesh::{EdgeId, Mesh, Topology, VertexId};

/// The feature angle a round defaults to (radians): an edge whose faces' normals turn
/// by more than this is sharp. 30 deg keeps a tessellated round's facets (a few deg
/// each at any fine tessellation) out of the chain, and takes any die shoulder modelled
/// sharp.
pub const DEFAULT_FEATURE_ANGLE: f64 = std::f64::consts::PI / 6.0;

/// How near `follow` (as the cosine of the angle) a sharp edge at a branch must run to
/// be followed: within 60 deg.
const FOLLOWS: f64 = 0.5;

/// A chain of sharp edges: its nodes in order and the edges between them (one fewer
/// than the nodes when open; as many when closed, the last edge back to the first
/// node).
#[derive(Debug, Clone, PartialEq)]
pub struct SharpChain {
    /// The nodes, in order along the chain.
    pub nodes: Vec<VertexId>,
    /// The edges, `edges[k]` from `nodes[k]` to the next node.
    pub edges: Vec<EdgeId>,
    /// Whether the chain runs back round to its first node.
    pub closed: bool,
}

impl SharpChain {
    /// Its length along its edges (mm).
    pub fn length(&self, mesh: &Mesh) -> f64 {
        let p = |k: usize| {
            mesh.position(self.nodes[k % self.nodes.len()])
                .unwrap_or_default()
        };
        (0..self.edges.len()).map(|k| p(k).distance(p(k + 1))).sum()
    }
}

/// Why no chain could be followed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ChainError {
    /// The picked node has no sharp edge.
    #[error("node {node} has no sharp edge (none turns by more than the feature angle)")]
    NotSharp { node: u32 },
    /// Three or more sharp edges meet at a node of the chain, and no direction to follow
    /// picks one (or the one given picks none within 60 deg).
    #[error("the chain branches at node {node}, where {edges} sharp edges meet")]
    Branch { node: u32, edges: usize },
    /// An edge at a node of the chain joins more than two faces, or two faces that
    /// disagree on orientation: the two sides of the chain cannot be told apart there.
    #[error("the mesh is not manifold and consistently oriented at node {node}")]
    NotManifold { node: u32 },
}

/// Which edges of `mesh` are sharp: joining two faces whose normals turn by more than
/// `theta` (radians), or more than two faces (a fin or a seam welded three ways is a
/// feature line too, so a chain reaches it and is refused there, naming the node).
/// Free edges are not sharp.
pub fn sharp_edges(mesh: &Mesh, topology: &Topology, theta: f64) -> Vec<bool> {
    topology
        .edges()
        .map(|e| {
            topology.edge_faces(e).count() > 2
                || topology
                    .dihedral_angle(mesh, e)
                    .is_some_and(|angle| angle > theta)
        })
        .collect()
}

/// The node of `mesh` nearest `point` that has a sharp edge, with its distance.
pub fn nearest_sharp_node(
    mesh: &Mesh,
    topology: &Topology,
    sharp: &[bool],
    point: DVec3,
) -> Option<(VertexId, f64)> {
    (0..mesh.vertex_count())
        .map(|i| VertexId(i as u32))
        .filter(|&v| topology.vertex_edges(v).iter().any(|e| sharp[e.index()]))
        .filter_map(|v| Some((v, mesh.position(v)?.distance(point))))
        .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
}

/// The chain of sharp edges (`sharp`, per edge) through node `start`, followed both
/// ways to its ends or round to `start`. Where three or more sharp edges meet, the
/// chain goes on along the one running nearest `follow` (within 60 deg of it; against
/// it on the way back from the start), and is refused naming the node when no `follow`
/// is given or none runs near it. An edge at a node of the chain that joins three
/// faces or more, or two that disagree on orientation, refuses the chain there.
pub fn chain_through(
    mesh: &Mesh,
    topology: &Topology,
    sharp: &[bool],
    start: VertexId,
    follow: Option<DVec3>,
) -> Result<SharpChain, ChainError> {
    let sharp_at = |v: VertexId| -> Result<Vec<EdgeId>, ChainError> {
        let edges = topology.vertex_edges(v);
        if edges.iter().any(|&e| {
            topology.edge_face_count(e) > 2
                || (sharp[e.index()] && topology.signed_dihedral_angle(mesh, e).is_none())
        }) {
            return Err(ChainError::NotManifold { node: v.0 });
        }
        Ok(edges.iter().copied().filter(|e| sharp[e.index()]).collect())
    };
    let other_end = |e: EdgeId, v: VertexId| {
        let [a, b] = topology.edge_vertices(e);
        if a == v {
            b
        } else {
            a
        }
    };
    let direction = |e: EdgeId, from: VertexId| -> DVec3 {
        let to = other_end(e, from);
        match (mesh.position(from), mesh.position(to)) {
            (Some(p), Some(q)) => (q - p).normalize_or_zero(),
            _ => DVec3::ZERO,
        }
    };
    // Of the sharp edges `candidates` leaving `at`, the one to go on along.
    let choose = |at: VertexId,
                  candidates: &[EdgeId],
                  total: usize,
                  follow: Option<DVec3>|
     -> Result<EdgeId, ChainError> {
        if let [only] = candidates {
            return Ok(*only);
        }
        let Some(follow) = follow.and_then(DVec3::try_normalize) else {
            return Err(ChainError::Branch {
                node: at.0,
                edges: total,
            });
        };
        candidates
            .iter()
            .copied()
            .map(|e| (direction(e, at).dot(follow), e))
            .filter(|&(cos, _)| cos >= FOLLOWS)
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
            .map(|(_, e)| e)
            .ok_or(ChainError::Branch {
                node: at.0,
                edges: total,
            })
    };
    let first = sharp_at(start)?;
    if first.is_empty() {
        return Err(ChainError::NotSharp { node: start.0 });
    }
    // The first edge: along `follow` where there is a choice, else the one of lowest
    // id; the other way from the start, the edge left after it (if any).
    let ahead = if first.len() == 1 {
        first[0]
    } else if first.len() == 2 {
        first[0].min(first[1])
    } else {
        choose(start, &first, first.len(), follow)?
    };
    // Walks from `start` along `edge` (at branches towards `follow`), returning the
    // nodes and edges passed and whether it came back to `start`.
    let walk = |edge: EdgeId,
                follow: Option<DVec3>|
     -> Result<(Vec<VertexId>, Vec<EdgeId>, bool), ChainError> {
        let (mut nodes, mut edges) = (vec![start], vec![edge]);
        let mut at = other_end(edge, start);
        let mut came = edge;
        loop {
            if at == start {
                return Ok((nodes, edges, true));
            }
            if nodes.contains(&at) {
                // Back on itself away from the start: a lasso, which no ball rolls.
                return Err(ChainError::Branch {
                    node: at.0,
                    edges: sharp_at(at)?.len(),
                });
            }
            nodes.push(at);
            let here = sharp_at(at)?;
            let onward: Vec<EdgeId> = here.iter().copied().filter(|&e| e != came).collect();
            if onward.is_empty() {
                return Ok((nodes, edges, false));
            }
            let next = choose(at, &onward, here.len(), follow)?;
            edges.push(next);
            at = other_end(next, at);
            came = next;
        }
    };
    let (nodes, edges, closed) = walk(ahead, follow)?;
    if closed {
        return Ok(SharpChain {
            nodes,
            edges,
            closed,
        });
    }
    // Open: the other way from the start, if a sharp edge goes that way (where the
    // start is a branch, the one running nearest back against the first edge).
    let back: Vec<EdgeId> = first.iter().copied().filter(|&e| e != ahead).collect();
    let against = -direction(ahead, start);
    let behind = match back.len() {
        0 => None,
        1 => Some(back[0]),
        _ => choose(start, &back, first.len(), Some(against)).ok(),
    };
    let Some(behind) = behind else {
        return Ok(SharpChain {
            nodes,
            edges,
            closed: false,
        });
    };
    let (back_nodes, back_edges, _) = walk(behind, follow.map(|f| -f))?;
    // The far end first: the walk behind reversed, then the walk ahead.
    let mut all_nodes: Vec<VertexId> = back_nodes[1..].iter().rev().copied().collect();
    all_nodes.extend(nodes);
    let mut all_edges: Vec<EdgeId> = back_edges.into_iter().rev().collect();
    all_edges.extend(edges);
    Ok(SharpChain {
        nodes: all_nodes,
        edges: all_edges,
        closed: false,
    })
}
