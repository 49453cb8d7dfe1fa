//! Free edges chained into boundary loops: the outlines that hole filling closes and
//! that trimming and flange generation follow.
//!
//! Each free edge has exactly one half-edge; the chains follow those half-edges, so a
//! loop runs the way its faces are wound: counter-clockwise around the outer rim of a
//! patch (seen from the normal side) and clockwise around a hole.

use super::{HalfEdgeId, Topology, VertexId};

/// A chain of consecutive free half-edges, each ending where the next starts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BoundaryChain {
    /// The free half-edges in order along the chain.
    pub half_edges: Vec<HalfEdgeId>,
    /// The vertices in order: the origin of every half-edge, and for an open chain
    /// also the end of the last one (so one more vertex than half-edges). A closed
    /// loop does not repeat its first vertex.
    pub vertices: Vec<VertexId>,
}

/// All free edges of a mesh, chained by [`Topology::boundary_loops`]. Every free
/// half-edge is in exactly one chain.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct BoundaryLoops {
    /// Closed loops, ordered by their lowest-numbered half-edge, each starting there.
    pub loops: Vec<BoundaryChain>,
    /// Chains that could not be closed, ordered like the loops; each starts at the
    /// end of the chain opposite to where its free half-edges point.
    pub open_chains: Vec<BoundaryChain>,
}

impl Topology {
    /// Chains the free edges into closed loops (and open chains where they do not
    /// close), following the faces' winding. Deterministic: same mesh, same loops,
    /// same order.
    ///
    /// At a *bowtie* vertex two loops touch (or one loop touches itself) and several
    /// free half-edges leave the same vertex. The continuation is then the free
    /// half-edge reached by turning around the vertex inside the fan of faces that the
    /// incoming half-edge belongs to, so each loop hugs its own faces instead of
    /// crossing into the neighbouring wedge (hole filling needs each loop to bound one
    /// hole). Where that fan walk is blocked (a non-manifold edge or a winding flip
    /// around the vertex), the loop's start is taken if it closes the loop, else the
    /// lowest-numbered free half-edge. Free edges that do not close up (possible only
    /// with non-manifold edges or inconsistent winding) come back as open chains.
    pub fn boundary_loops(&self) -> BoundaryLoops {
        let mut used = vec![false; self.half_edge_count()];
        let mut result = BoundaryLoops::default();
        for start in self.half_edges().filter(|&h| self.is_free(h)) {
            if used[start.index()] {
                continue;
            }
            used[start.index()] = true;
            let mut chain = vec![start];
            if self.extend_forward(&mut chain, &mut used) {
                let vertices = chain.iter().map(|&h| self.origin(h)).collect();
                result.loops.push(BoundaryChain { half_edges: chain, vertices });
            } else {
                let mut full = self.extend_backward(start, &mut used);
                full.reverse();
                full.extend(chain);
                result.open_chains.push(self.open_chain(full));
            }
        }
        result
    }

    /// Whether half-edge `h` lies on a free edge.
    fn is_free(&self, h: HalfEdgeId) -> bool {
        self.is_boundary_edge(self.edge(h))
    }

    /// Appends continuations to `chain` until it closes (returns `true`) or runs out.
    fn extend_forward(&self, chain: &mut Vec<HalfEdgeId>, used: &mut [bool]) -> bool {
        let start = chain[0];
        // Each step marks a half-edge used, so this ends after at most every half-edge.
        loop {
            let last = chain[chain.len() - 1];
            match self.successor(last, start, used) {
                Some(next) if next == start => return true,
                Some(next) => {
                    used[next.index()] = true;
                    chain.push(next);
                }
                None => return false,
            }
        }
    }

    /// The unused free half-edges that lead into `start`, nearest first.
    fn extend_backward(&self, start: HalfEdgeId, used: &mut [bool]) -> Vec<HalfEdgeId> {
        let mut before = Vec::new();
        let mut first = start;
        while let Some(p) = self.predecessor(first, used) {
            used[p.index()] = true;
            before.push(p);
            first = p;
        }
        before
    }

    /// The free half-edge continuing the boundary after `h`: unused or the chain's
    /// `start` (which closes the loop). Prefers the fan walk, then `start`, then the
    /// lowest id.
    fn successor(&self, h: HalfEdgeId, start: HalfEdgeId, used: &[bool]) -> Option<HalfEdgeId> {
        let available = |g: HalfEdgeId| self.is_free(g) && (g == start || !used[g.index()]);
        if let Some(g) = self.fan_successor(h).filter(|&g| available(g)) {
            return Some(g);
        }
        let v = self.destination(h);
        let mut candidates = self.vertex_half_edges(v).iter().copied().filter(|&g| available(g));
        let first = candidates.next()?;
        if first == start || candidates.any(|g| g == start) {
            Some(start)
        } else {
            Some(first)
        }
    }

    /// The unused free half-edge leading into `h`'s origin that precedes `h`: the fan
    /// walk's answer, else the lowest id.
    fn predecessor(&self, h: HalfEdgeId, used: &[bool]) -> Option<HalfEdgeId> {
        let available = |p: HalfEdgeId| self.is_free(p) && !used[p.index()];
        if let Some(p) = self.fan_predecessor(h).filter(|&p| available(p)) {
            return Some(p);
        }
        let u = self.origin(h);
        // prev(g) of every half-edge g leaving u is a half-edge entering u.
        self.vertex_half_edges(u).iter().map(|&g| self.prev(g)).filter(|&p| available(p)).min()
    }

    /// Turns around `h`'s end vertex through the faces of its fan, starting in `h`'s
    /// face, until a free half-edge leaves the vertex. `None` if a non-manifold edge or
    /// a winding flip blocks the way.
    fn fan_successor(&self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        let v = self.destination(h);
        let mut g = self.next(h);
        for _ in 0..=self.vertex_half_edges(v).len() {
            if self.is_free(g) {
                return Some(g);
            }
            let t = self.twin(g)?;
            if self.origin(t) == v {
                return None;
            }
            g = self.next(t);
        }
        None
    }

    /// The mirror of [`Topology::fan_successor`]: turns around `h`'s origin the other
    /// way until a free half-edge enters it.
    fn fan_predecessor(&self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        let u = self.origin(h);
        let mut p = self.prev(h);
        for _ in 0..=self.vertex_half_edges(u).len() {
            if self.is_free(p) {
                return Some(p);
            }
            let t = self.twin(p)?;
            if self.origin(t) != u {
                return None;
            }
            p = self.prev(t);
        }
        None
    }

    /// An open chain from its half-edges (non-empty), listing the last end vertex too.
    fn open_chain(&self, half_edges: Vec<HalfEdgeId>) -> BoundaryChain {
        let mut vertices: Vec<VertexId> = half_edges.iter().map(|&h| self.origin(h)).collect();
        if let Some(&last) = half_edges.last() {
            vertices.push(self.destination(last));
        }
        BoundaryChain { half_edges, vertices }
    }
}
