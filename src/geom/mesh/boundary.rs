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
    /// Closed loops, each starting at its lowest-numbered half-edge and ordered by
    /// it. No loop visits a vertex twice.
    pub loops: Vec<BoundaryChain>,
    /// Chains that could not be closed, ordered by their lowest-numbered half-edge;
    /// each starts at the end its half-edges point away from.
    pub open_chains: Vec<BoundaryChain>,
}

impl Topology {
    /// Chains the free edges into closed loops (and open chains where they do not
    /// close), following the faces' winding. Deterministic: same mesh, same loops,
    /// same order.
    ///
    /// At a *bowtie* vertex several free half-edges leave the same vertex and two
    /// loops touch (or one loop touches itself). Two rules keep the loops fit for hole
    /// filling, which needs every loop to be a simple polygon:
    ///
    /// 1. The continuation after a free half-edge is the free half-edge reached by
    ///    turning around the vertex inside the fan of faces the incoming half-edge
    ///    belongs to, so a loop hugs its own faces: two patches touching at a corner
    ///    get one loop each. Where that fan walk is blocked (a non-manifold edge or a
    ///    winding flip around the vertex) the lowest-numbered unused free half-edge
    ///    leaving the vertex is taken.
    /// 2. Whenever the walk comes back to a vertex it already passed, the part walked
    ///    since is cut off as a loop of its own. Two holes touching at a corner thus
    ///    come back as two loops, not as one figure-of-eight, and no loop visits a
    ///    vertex twice.
    ///
    /// Free edges that do not close up (possible only with non-manifold edges or
    /// inconsistent winding) come back as open chains; those are not cut at repeated
    /// vertices.
    pub fn boundary_loops(&self) -> BoundaryLoops {
        let mut tracer = Tracer {
            topo: self,
            used: vec![false; self.half_edge_count()],
            position: vec![NOT_ON_PATH; self.vertex_count()],
            loops: Vec::new(),
            open: Vec::new(),
        };
        for start in self.half_edges().filter(|&h| self.is_free(h)) {
            if !tracer.used[start.index()] {
                tracer.trace(start);
            }
        }
        let mut loops: Vec<BoundaryChain> = tracer
            .loops
            .into_iter()
            .map(|l| self.closed_chain(l))
            .collect();
        loops.sort_by_key(|l| l.half_edges[0]);
        let mut open_chains: Vec<BoundaryChain> = tracer
            .open
            .into_iter()
            .map(|c| self.open_chain(c))
            .collect();
        open_chains.sort_by_key(|c| c.half_edges.iter().min().copied());
        BoundaryLoops { loops, open_chains }
    }

    /// Whether half-edge `h` lies on a free edge.
    fn is_free(&self, h: HalfEdgeId) -> bool {
        self.is_boundary_edge(self.edge(h))
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

    /// A closed loop from its half-edges (non-empty), rotated to start at the lowest.
    fn closed_chain(&self, mut half_edges: Vec<HalfEdgeId>) -> BoundaryChain {
        let lowest = (0..half_edges.len())
            .min_by_key(|&i| half_edges[i])
            .unwrap_or(0);
        half_edges.rotate_left(lowest);
        let vertices = half_edges.iter().map(|&h| self.origin(h)).collect();
        BoundaryChain {
            half_edges,
            vertices,
        }
    }

    /// An open chain from its half-edges (non-empty), listing the last end vertex too.
    fn open_chain(&self, half_edges: Vec<HalfEdgeId>) -> BoundaryChain {
        let mut vertices: Vec<VertexId> = half_edges.iter().map(|&h| self.origin(h)).collect();
        if let Some(&last) = half_edges.last() {
            vertices.push(self.destination(last));
        }
        BoundaryChain {
            half_edges,
            vertices,
        }
    }
}

/// Marks a vertex that is not the origin of a half-edge on the current path.
const NOT_ON_PATH: usize = usize::MAX;

/// The working state of one [`Topology::boundary_loops`] call.
struct Tracer<'t> {
    topo: &'t Topology,
    /// Per half-edge: already put on a path.
    used: Vec<bool>,
    /// Per vertex: the index on the current path of the half-edge starting there, or
    /// [`NOT_ON_PATH`].
    position: Vec<usize>,
    loops: Vec<Vec<HalfEdgeId>>,
    open: Vec<Vec<HalfEdgeId>>,
}

impl Tracer<'_> {
    /// Walks the boundary from the unused free half-edge `start`, cutting off a loop
    /// each time the walk returns to a vertex on its path, until the path is used up
    /// (all loops) or gets stuck (the rest is an open chain).
    fn trace(&mut self, start: HalfEdgeId) {
        let mut path = Vec::new();
        self.push(&mut path, start);
        // Every push uses up a free half-edge and every pass either pushes, cuts off a
        // loop (shortening the path) or stops, so this terminates.
        while let Some(&last) = path.last() {
            let w = self.topo.destination(last);
            if let Some(&i) = self.position.get(w.index()).filter(|&&i| i != NOT_ON_PATH) {
                let cycle = path.split_off(i);
                self.forget(&cycle);
                self.loops.push(cycle);
                continue;
            }
            match self.successor(last) {
                Some(g) => self.push(&mut path, g),
                None => {
                    self.forget(&path);
                    let mut chain = self.extend_backward(path[0]);
                    chain.reverse();
                    chain.append(&mut path);
                    self.open.push(chain);
                }
            }
        }
    }

    /// Appends `h` to the path, recording where its origin sits on it.
    fn push(&mut self, path: &mut Vec<HalfEdgeId>, h: HalfEdgeId) {
        self.used[h.index()] = true;
        if let Some(slot) = self.position.get_mut(self.topo.origin(h).index()) {
            *slot = path.len();
        }
        path.push(h);
    }

    /// Clears the path positions of the origins of `half_edges`.
    fn forget(&mut self, half_edges: &[HalfEdgeId]) {
        for &h in half_edges {
            if let Some(slot) = self.position.get_mut(self.topo.origin(h).index()) {
                *slot = NOT_ON_PATH;
            }
        }
    }

    /// Whether `h` is free and not yet on any path.
    fn available(&self, h: HalfEdgeId) -> bool {
        self.topo.is_free(h) && !self.used[h.index()]
    }

    /// The unused free half-edge continuing the boundary after `h`: the fan walk's
    /// answer, else the lowest-numbered one leaving `h`'s end.
    fn successor(&self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        if let Some(g) = self.topo.fan_successor(h).filter(|&g| self.available(g)) {
            return Some(g);
        }
        let v = self.topo.destination(h);
        self.topo
            .vertex_half_edges(v)
            .iter()
            .copied()
            .find(|&g| self.available(g))
    }

    /// The unused free half-edge leading into `h`'s origin before `h`: the fan walk's
    /// answer, else the lowest-numbered one.
    fn predecessor(&self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        if let Some(p) = self.topo.fan_predecessor(h).filter(|&p| self.available(p)) {
            return Some(p);
        }
        let u = self.topo.origin(h);
        // prev(g) of every half-edge g leaving u is a half-edge entering u.
        self.topo
            .vertex_half_edges(u)
            .iter()
            .map(|&g| self.topo.prev(g))
            .filter(|&p| self.available(p))
            .min()
    }

    /// The unused free half-edges that lead into `start`, nearest first.
    fn extend_backward(&mut self, start: HalfEdgeId) -> Vec<HalfEdgeId> {
        let mut before = Vec::new();
        let mut first = start;
        while let Some(p) = self.predecessor(first) {
            self.used[p.index()] = true;
            before.push(p);
            first = p;
        }
        before
    }
}
