//! The boundary representation of the solid a sheet model becomes: half-edges, edges,
//! vertices, loops and faces, changed only by Euler operators, with the twin relations
//! of a sheet (paper 003, sections 2-3).
//!
//! The data structure is the half-edge structure of Mantyla (*An Introduction to Solid
//! Modeling*, 1988, ch. 10-11): every face has loops (the first its outer boundary, the
//! others rings), every loop a cycle of half-edges, every edge two half-edges (one in
//! each loop it borders, running opposite ways). The Euler operators are his low-level
//! ones (`mvfs`, `lmev`, `lmef`, `lkemr`, `lkfmrh` and the inverses `lkev`, `lkef`):
//! each keeps the Euler-Poincare formula `V - E + F - R = 2 (S - G)` (R rings, S shells,
//! G genus), which [`Brep::check`] verifies with every link.
//!
//! A [`Sheet`] adds what makes the solid a sheet's: every face but the thickness faces
//! has a twin (the other side), every edge but the zero-length ones has a twin, every
//! vertex has a twin joined to it by a zero-length edge. [`Sheet::initial`] builds the
//! first sheet of a model, a slab of zero thickness over an n-sided outline.
//!
//! Elements are never reused once killed: ids stay stable through an operation, so
//! what a designer picked (by name or by a point near it) can be followed.

use std::collections::BTreeSet;

/// A half-edge: one side of an edge, in one loop, running from its vertex to the next
/// half-edge's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct HalfEdgeId(pub u32);

/// An edge: two half-edges running opposite ways.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct EdgeId(pub u32);

/// A vertex.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VertexId(pub u32);

/// A loop: a cycle of half-edges bounding a face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LoopId(pub u32);

/// A face: an outer loop and any rings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FaceId(pub u32);

macro_rules! index_of {
    ($($t:ty),*) => {$(
        impl $t {
            /// The id as an index into its table.
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }
    )*};
}
index_of!(HalfEdgeId, EdgeId, VertexId, LoopId, FaceId);

/// One half-edge's links.
#[derive(Debug, Clone, Copy, PartialEq)]
struct HalfEdge {
    /// Its edge; `None` only for the lone half-edge of a loop that is a single vertex
    /// (the face of [`Brep::mvfs`] before any edge).
    edge: Option<EdgeId>,
    /// Where it starts.
    vertex: VertexId,
    /// The loop it runs in.
    lp: LoopId,
    next: HalfEdgeId,
    prev: HalfEdgeId,
}

/// One edge's two half-edges: `plus` and `minus` run opposite ways.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Edge {
    plus: HalfEdgeId,
    minus: HalfEdgeId,
}

/// One vertex: a half-edge that starts there (`None` when none does).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Vertex {
    half: Option<HalfEdgeId>,
}

/// One loop: a half-edge in it, and its face.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Loop {
    half: HalfEdgeId,
    face: FaceId,
}

/// One face: its loops, the outer one first.
#[derive(Debug, Clone, PartialEq)]
struct Face {
    loops: Vec<LoopId>,
}

/// Why a topology is not valid, or why an operator cannot be applied.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TopologyError {
    /// An id that names no live element.
    Dead(String),
    /// The operator's arguments do not stand in the relation it needs.
    NotApplicable(String),
    /// A broken link or a violated invariant (a bug in an operator).
    Invalid(String),
}

impl std::fmt::Display for TopologyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TopologyError::Dead(what) => write!(f, "{what} no longer exists"),
            TopologyError::NotApplicable(why) => write!(f, "{why}"),
            TopologyError::Invalid(why) => write!(f, "invalid topology: {why}"),
        }
    }
}

impl std::error::Error for TopologyError {}

/// Result of the topology's operations.
pub type Result<T> = std::result::Result<T, TopologyError>;

/// Element counts and the Euler-Poincare terms of a topology.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts {
    /// Vertices.
    pub vertices: usize,
    /// Edges.
    pub edges: usize,
    /// Faces.
    pub faces: usize,
    /// Loops that are not a face's outer loop.
    pub rings: usize,
    /// Connected shells.
    pub shells: usize,
    /// Genus (through holes), as the operators made it.
    pub genus: usize,
}

impl Counts {
    /// `V - E + F - R - 2 (S - G)`: zero for a valid topology.
    pub fn euler_poincare(&self) -> i64 {
        self.vertices as i64 - self.edges as i64 + self.faces as i64
            - self.rings as i64
            - 2 * (self.shells as i64 - self.genus as i64)
    }
}

/// A boundary representation changed only by Euler operators.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Brep {
    halves: Vec<Option<HalfEdge>>,
    edges: Vec<Option<Edge>>,
    vertices: Vec<Option<Vertex>>,
    loops: Vec<Option<Loop>>,
    faces: Vec<Option<Face>>,
    /// Through holes made by [`Brep::lkfmrh`] within one shell, less those closed.
    genus: usize,
}

impl Brep {
    /// An empty topology.
    pub fn new() -> Self {
        Self::default()
    }

    fn half(&self, h: HalfEdgeId) -> Result<&HalfEdge> {
        self.halves
            .get(h.index())
            .and_then(Option::as_ref)
            .ok_or_else(|| TopologyError::Dead(format!("half-edge {}", h.0)))
    }

    fn half_mut(&mut self, h: HalfEdgeId) -> &mut HalfEdge {
        self.halves[h.index()]
            .as_mut()
            .expect("operators link only live half-edges, checked on entry")
    }

    fn edge_of(&self, e: EdgeId) -> Result<&Edge> {
        self.edges
            .get(e.index())
            .and_then(Option::as_ref)
            .ok_or_else(|| TopologyError::Dead(format!("edge {}", e.0)))
    }

    fn loop_of(&self, l: LoopId) -> Result<&Loop> {
        self.loops
            .get(l.index())
            .and_then(Option::as_ref)
            .ok_or_else(|| TopologyError::Dead(format!("loop {}", l.0)))
    }

    fn face_of(&self, f: FaceId) -> Result<&Face> {
        self.faces
            .get(f.index())
            .and_then(Option::as_ref)
            .ok_or_else(|| TopologyError::Dead(format!("face {}", f.0)))
    }

    fn new_half(&mut self, h: HalfEdge) -> HalfEdgeId {
        self.halves.push(Some(h));
        HalfEdgeId(self.halves.len() as u32 - 1)
    }

    fn new_vertex(&mut self) -> VertexId {
        self.vertices.push(Some(Vertex { half: None }));
        VertexId(self.vertices.len() as u32 - 1)
    }

    fn new_loop(&mut self, half: HalfEdgeId, face: FaceId) -> LoopId {
        self.loops.push(Some(Loop { half, face }));
        LoopId(self.loops.len() as u32 - 1)
    }

    fn new_face(&mut self) -> FaceId {
        self.faces.push(Some(Face { loops: Vec::new() }));
        FaceId(self.faces.len() as u32 - 1)
    }

    /// The half-edge after `h` in its loop.
    pub fn next(&self, h: HalfEdgeId) -> Result<HalfEdgeId> {
        Ok(self.half(h)?.next)
    }

    /// The half-edge before `h` in its loop.
    pub fn prev(&self, h: HalfEdgeId) -> Result<HalfEdgeId> {
        Ok(self.half(h)?.prev)
    }

    /// Where `h` starts.
    pub fn vertex(&self, h: HalfEdgeId) -> Result<VertexId> {
        Ok(self.half(h)?.vertex)
    }

    /// The edge of `h` (`None` for a loop that is a single vertex).
    pub fn edge(&self, h: HalfEdgeId) -> Result<Option<EdgeId>> {
        Ok(self.half(h)?.edge)
    }

    /// The loop `h` runs in.
    pub fn loop_with(&self, h: HalfEdgeId) -> Result<LoopId> {
        Ok(self.half(h)?.lp)
    }

    /// The face of loop `l`.
    pub fn face_with(&self, l: LoopId) -> Result<FaceId> {
        Ok(self.loop_of(l)?.face)
    }

    /// The other half of `h`'s edge.
    pub fn mate(&self, h: HalfEdgeId) -> Result<HalfEdgeId> {
        let e = self
            .half(h)?
            .edge
            .ok_or_else(|| TopologyError::NotApplicable("a lone vertex has no mate".into()))?;
        let edge = self.edge_of(e)?;
        Ok(if edge.plus == h {
            edge.minus
        } else {
            edge.plus
        })
    }

    /// The two half-edges of `e` (plus, minus).
    pub fn halves_of(&self, e: EdgeId) -> Result<(HalfEdgeId, HalfEdgeId)> {
        let edge = self.edge_of(e)?;
        Ok((edge.plus, edge.minus))
    }

    /// The loops of `f`, the outer one first.
    pub fn loops_of(&self, f: FaceId) -> Result<&[LoopId]> {
        Ok(&self.face_of(f)?.loops)
    }

    /// The half-edges of loop `l`, in order from its first.
    pub fn loop_halves(&self, l: LoopId) -> Result<Vec<HalfEdgeId>> {
        let first = self.loop_of(l)?.half;
        let mut out = vec![first];
        let mut h = self.half(first)?.next;
        while h != first {
            if out.len() > self.halves.len() {
                return Err(TopologyError::Invalid(format!("loop {} never closes", l.0)));
            }
            out.push(h);
            h = self.half(h)?.next;
        }
        Ok(out)
    }

    /// The live faces, in id order.
    pub fn faces(&self) -> impl Iterator<Item = FaceId> + '_ {
        ids(&self.faces).map(|i| FaceId(i as u32))
    }

    /// The live edges, in id order.
    pub fn edges(&self) -> impl Iterator<Item = EdgeId> + '_ {
        ids(&self.edges).map(|i| EdgeId(i as u32))
    }

    /// The live vertices, in id order.
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        ids(&self.vertices).map(|i| VertexId(i as u32))
    }

    /// The live loops, in id order.
    pub fn loops(&self) -> impl Iterator<Item = LoopId> + '_ {
        ids(&self.loops).map(|i| LoopId(i as u32))
    }

    /// Makes a new shell of one vertex and one face whose loop is that vertex alone.
    pub fn mvfs(&mut self) -> (VertexId, FaceId, HalfEdgeId) {
        let v = self.new_vertex();
        let f = self.new_face();
        let h = HalfEdgeId(self.halves.len() as u32);
        let l = self.new_loop(h, f);
        let made = self.new_half(HalfEdge {
            edge: None,
            vertex: v,
            lp: l,
            next: h,
            prev: h,
        });
        debug_assert_eq!(made, h);
        self.faces[f.index()]
            .as_mut()
            .expect("made above")
            .loops
            .push(l);
        self.vertices[v.index()] = Some(Vertex { half: Some(h) });
        (v, f, h)
    }

    /// Puts a half-edge of `e` starting at `v` into the loop of `at`, just before it (or
    /// `at` itself when it is a lone vertex's half-edge); `plus` says which half.
    fn add_half(&mut self, e: EdgeId, v: VertexId, at: HalfEdgeId, plus: bool) -> HalfEdgeId {
        let where_ = *self.half(at).expect("operators pass live half-edges");
        let h = if where_.edge.is_none() {
            let w = self.half_mut(at);
            w.edge = Some(e);
            w.vertex = v;
            at
        } else {
            let h = self.new_half(HalfEdge {
                edge: Some(e),
                vertex: v,
                lp: where_.lp,
                next: at,
                prev: where_.prev,
            });
            self.half_mut(where_.prev).next = h;
            self.half_mut(at).prev = h;
            h
        };
        let edge = self.edges[e.index()]
            .as_mut()
            .expect("the operator made it");
        if plus {
            edge.plus = h;
        } else {
            edge.minus = h;
        }
        h
    }

    /// Takes half-edge `h` out of its loop; returns the half-edge that now stands in its
    /// place (its predecessor, or `h` itself made a lone vertex's half-edge when it was
    /// the loop's only one).
    fn delete_half(&mut self, h: HalfEdgeId) -> HalfEdgeId {
        let he = *self.half(h).expect("operators pass live half-edges");
        if he.next == h {
            self.half_mut(h).edge = None;
            h
        } else {
            self.half_mut(he.prev).next = he.next;
            self.half_mut(he.next).prev = he.prev;
            self.halves[h.index()] = None;
            he.prev
        }
    }

    fn new_edge(&mut self) -> EdgeId {
        // Both halves are set by `add_half` right after.
        self.edges.push(Some(Edge {
            plus: HalfEdgeId(u32::MAX),
            minus: HalfEdgeId(u32::MAX),
        }));
        EdgeId(self.edges.len() as u32 - 1)
    }

    /// Make edge, vertex: splits the vertex where `h1` and `h2` start (the half-edges
    /// from `h1` round to `h2` move to the new vertex) by a new edge from the old vertex
    /// to the new one. With `h1 == h2`, a new edge dangles from the vertex into the loop
    /// of `h1`, just before it.
    pub fn lmev(&mut self, h1: HalfEdgeId, h2: HalfEdgeId) -> Result<(EdgeId, VertexId)> {
        let v = self.half(h1)?.vertex;
        if self.half(h2)?.vertex != v {
            return Err(TopologyError::NotApplicable(
                "lmev: the two half-edges must start at the same vertex".into(),
            ));
        }
        // The half-edges from h1 round the vertex to h2 (mate, next) must reach h2.
        let mut h = h1;
        let mut moved = Vec::new();
        while h != h2 {
            moved.push(h);
            if moved.len() > self.halves.len() {
                return Err(TopologyError::NotApplicable(
                    "lmev: h2 is not reached from h1 round their vertex".into(),
                ));
            }
            h = self.half(self.mate(h)?)?.next;
        }
        let e = self.new_edge();
        let nv = self.new_vertex();
        for h in moved {
            self.half_mut(h).vertex = nv;
        }
        self.add_half(e, v, h1, false);
        self.add_half(e, nv, h2, true);
        let nv_half = self.half(h2)?.prev;
        self.vertices[nv.index()] = Some(Vertex {
            half: Some(nv_half),
        });
        self.vertices[v.index()] = Some(Vertex { half: Some(h2) });
        Ok((e, nv))
    }

    /// Make edge, face: a new edge from the vertex of `h1` to the vertex of `h2` (both in
    /// one loop) splits that loop in two; the half-edges from `h1` up to `h2` go with
    /// the new edge into the outer loop of a new face.
    pub fn lmef(&mut self, h1: HalfEdgeId, h2: HalfEdgeId) -> Result<(EdgeId, FaceId)> {
        let lp = self.half(h1)?.lp;
        if self.half(h2)?.lp != lp {
            return Err(TopologyError::NotApplicable(
                "lmef: the two half-edges must be in one loop".into(),
            ));
        }
        if h1 == h2 {
            return Err(TopologyError::NotApplicable(
                "lmef: the two half-edges must differ".into(),
            ));
        }
        let face = self.new_face();
        let new_loop = self.new_loop(h1, face);
        self.faces[face.index()]
            .as_mut()
            .expect("made above")
            .loops
            .push(new_loop);
        let e = self.new_edge();
        let mut h = h1;
        while h != h2 {
            self.half_mut(h).lp = new_loop;
            h = self.half(h)?.next;
        }
        let v1 = self.half(h1)?.vertex;
        let v2 = self.half(h2)?.vertex;
        let n1 = self.add_half(e, v2, h1, false);
        let n2 = self.add_half(e, v1, h2, true);
        let (p1, p2) = (self.half(n1)?.prev, self.half(n2)?.prev);
        self.half_mut(p1).next = n2;
        self.half_mut(p2).next = n1;
        self.half_mut(n1).prev = p2;
        self.half_mut(n2).prev = p1;
        self.loops[new_loop.index()] = Some(Loop { half: n1, face });
        let old_face = self.loop_of(lp)?.face;
        self.loops[lp.index()] = Some(Loop {
            half: n2,
            face: old_face,
        });
        Ok((e, face))
    }

    /// Kill edge, make ring: removes the edge of `h`, whose two half-edges run in one
    /// loop, splitting that loop into two; the part that follows `h` becomes a new ring
    /// of the same face, the part that follows its mate stays the loop it was.
    pub fn lkemr(&mut self, h: HalfEdgeId) -> Result<LoopId> {
        let e = self.half(h)?.edge.ok_or_else(|| {
            TopologyError::NotApplicable("lkemr: a lone vertex has no edge".into())
        })?;
        let (h1, h2) = (h, self.mate(h)?);
        let old = self.half(h1)?.lp;
        if self.half(h2)?.lp != old {
            return Err(TopologyError::NotApplicable(
                "lkemr: the edge must run twice in one loop".into(),
            ));
        }
        let face = self.loop_of(old)?.face;
        let h3 = self.half(h1)?.next;
        let h2_next = self.half(h2)?.next;
        self.half_mut(h1).next = h2_next;
        self.half_mut(h2_next).prev = h1;
        self.half_mut(h2).next = h3;
        self.half_mut(h3).prev = h2;
        let ring = self.new_loop(h2, face);
        let mut h = h2;
        loop {
            self.half_mut(h).lp = ring;
            h = self.half(h)?.next;
            if h == h2 {
                break;
            }
        }
        let (p, q) = (self.half(h1)?.vertex, self.half(h2)?.vertex);
        let a = self.delete_half(h1);
        let b = self.delete_half(h2);
        self.loops[old.index()] = Some(Loop { half: a, face });
        self.loops[ring.index()] = Some(Loop { half: b, face });
        self.faces[face.index()]
            .as_mut()
            .expect("the loop's face is live")
            .loops
            .push(ring);
        // Each end keeps the half-edge that now follows the one before the deleted half.
        let (pa, qb) = (self.leaving_after(a)?, self.leaving_after(b)?);
        self.vertices[p.index()] = Some(Vertex { half: Some(pa) });
        self.vertices[q.index()] = Some(Vertex { half: Some(qb) });
        self.edges[e.index()] = None;
        Ok(ring)
    }

    /// Make edge, kill ring: the inverse of [`Brep::lkemr`]: a new edge from the vertex
    /// of `h1` to the vertex of `h2`, which run in two loops of one face, joins the two
    /// loops into the loop of `h1`; the loop of `h2` is gone.
    pub fn lmekr(&mut self, h1: HalfEdgeId, h2: HalfEdgeId) -> Result<EdgeId> {
        let (l1, l2) = (self.half(h1)?.lp, self.half(h2)?.lp);
        if l1 == l2 {
            return Err(TopologyError::NotApplicable(
                "lmekr: the two half-edges must run in two loops".into(),
            ));
        }
        let face = self.loop_of(l1)?.face;
        if self.loop_of(l2)?.face != face {
            return Err(TopologyError::NotApplicable(
                "lmekr: the two loops must bound one face".into(),
            ));
        }
        let cycle = self.loop_halves(l2)?;
        for &h in &cycle {
            self.half_mut(h).lp = l1;
        }
        let (v1, v2) = (self.half(h1)?.vertex, self.half(h2)?.vertex);
        let e = self.new_edge();
        // Each new half goes in before `h1` and `h2` (taking over a lone vertex's
        // half-edge), then the cycles are crossed over: n1 (v1 -> v2) runs on into the
        // loop of `h2`, n2 (v2 -> v1) back into the loop of `h1`.
        let n1 = self.add_half(e, v1, h1, true);
        let n2 = self.add_half(e, v2, h2, false);
        self.cross(n1, n2)?;
        let outer_was_l2 = self.face_of(face)?.loops[0] == l2;
        let loops = &mut self.faces[face.index()]
            .as_mut()
            .expect("checked above")
            .loops;
        loops.retain(|&l| l != l2);
        if outer_was_l2 {
            // The joined loop takes the outer loop's place.
            loops.retain(|&l| l != l1);
            loops.insert(0, l1);
        }
        self.loops[l2.index()] = None;
        self.loops[l1.index()] = Some(Loop { half: n1, face });
        Ok(e)
    }

    /// Crosses two half-edges' successors over: `a` continues with what followed `b`
    /// and `b` with what followed `a` (joins two cycles into one, or splits one in two).
    fn cross(&mut self, a: HalfEdgeId, b: HalfEdgeId) -> Result<()> {
        let (na, nb) = (self.half(a)?.next, self.half(b)?.next);
        self.half_mut(a).next = nb;
        self.half_mut(nb).prev = a;
        self.half_mut(b).next = na;
        self.half_mut(na).prev = b;
        Ok(())
    }

    /// Kill face, make ring (and hole): face `f2`, which has only an outer loop, is
    /// removed and its loop becomes a ring of `f1`. Within one shell this makes a
    /// through hole (the genus grows); across two shells it joins them.
    pub fn lkfmrh(&mut self, f1: FaceId, f2: FaceId) -> Result<LoopId> {
        if f1 == f2 {
            return Err(TopologyError::NotApplicable(
                "lkfmrh: a face cannot become a ring of itself".into(),
            ));
        }
        self.face_of(f1)?;
        let loops = self.face_of(f2)?.loops.clone();
        if loops.len() != 1 {
            return Err(TopologyError::NotApplicable(
                "lkfmrh: the face to kill must have only its outer loop".into(),
            ));
        }
        let same_shell = self.shell_of_face(f1)? == self.shell_of_face(f2)?;
        let l = loops[0];
        let lp = self.loops[l.index()]
            .as_mut()
            .expect("a face's loop is live");
        lp.face = f1;
        self.faces[f1.index()]
            .as_mut()
            .expect("checked above")
            .loops
            .push(l);
        self.faces[f2.index()] = None;
        if same_shell {
            self.genus += 1;
        }
        Ok(l)
    }

    /// Make face, kill ring (and hole): the inverse of [`Brep::lkfmrh`]: ring `ring` of
    /// face `f` becomes the outer loop of a new face. Where the two faces stay in one
    /// shell a through hole closes (the genus falls); where they do not, the shell
    /// falls apart in two (a strip cut across a sheet).
    pub fn lmfkrh(&mut self, f: FaceId, ring: LoopId) -> Result<FaceId> {
        let loops = self.face_of(f)?.loops.clone();
        if loops[0] == ring || !loops.contains(&ring) {
            return Err(TopologyError::NotApplicable(
                "lmfkrh: the loop must be a ring of the face".into(),
            ));
        }
        let g = self.new_face();
        self.faces[g.index()]
            .as_mut()
            .expect("just made")
            .loops
            .push(ring);
        self.faces[f.index()]
            .as_mut()
            .expect("checked above")
            .loops
            .retain(|&l| l != ring);
        self.loops[ring.index()]
            .as_mut()
            .expect("a face's loop is live")
            .face = g;
        if self.shell_of_face(f)? == self.shell_of_face(g)? {
            self.genus = self.genus.checked_sub(1).ok_or_else(|| {
                TopologyError::Invalid("lmfkrh: a ring closed on a shell of genus 0".into())
            })?;
        }
        Ok(g)
    }

    /// [`Brep::lkev`] killing vertex `gone`, one of the ends of edge `e`: the edge's two
    /// halves are named the other way round first when `gone` is where its minus half
    /// starts (which half is `plus` is only a name).
    pub fn lkev_at(&mut self, e: EdgeId, gone: VertexId) -> Result<VertexId> {
        let Edge { plus, minus } = *self.edge_of(e)?;
        if self.half(plus)?.vertex != gone {
            if self.half(minus)?.vertex != gone {
                return Err(TopologyError::NotApplicable(format!(
                    "lkev: vertex {} is not an end of edge {}",
                    gone.0, e.0
                )));
            }
            self.edges[e.index()] = Some(Edge {
                plus: minus,
                minus: plus,
            });
        }
        self.lkev(e)
    }

    /// The vertices of face `f`'s outer loop, in order.
    pub fn outer_vertices(&self, f: FaceId) -> Result<Vec<VertexId>> {
        self.loop_halves(self.loops_of(f)?[0])?
            .into_iter()
            .map(|h| self.vertex(h))
            .collect()
    }

    /// The edges at vertex `v`, round it (by mate, next).
    pub fn edges_at(&self, v: VertexId) -> Result<Vec<EdgeId>> {
        let vertex = self
            .vertices
            .get(v.index())
            .and_then(Option::as_ref)
            .ok_or_else(|| TopologyError::Dead(format!("vertex {}", v.0)))?;
        let Some(first) = vertex.half else {
            return Ok(Vec::new());
        };
        let mut out = Vec::new();
        let mut h = first;
        while let Some(e) = self.half(h)?.edge {
            out.push(e);
            h = self.half(self.mate(h)?)?.next;
            if h == first {
                break;
            }
            if out.len() > self.halves.len() {
                return Err(TopologyError::Invalid(format!(
                    "the star of vertex {} never closes",
                    v.0
                )));
            }
        }
        Ok(out)
    }

    /// Kill edge, vertex: the inverse of [`Brep::lmev`]: removes edge `e` and the
    /// vertex its `plus` half starts at; the half-edges leaving that vertex move to the
    /// vertex its `minus` half starts at.
    pub fn lkev(&mut self, e: EdgeId) -> Result<VertexId> {
        let Edge {
            plus: h1,
            minus: h2,
        } = *self.edge_of(e)?;
        let (gone, kept) = (self.half(h1)?.vertex, self.half(h2)?.vertex);
        if gone == kept {
            return Err(TopologyError::NotApplicable(
                "lkev: the edge is a loop at one vertex".into(),
            ));
        }
        // Every half-edge leaving `gone` moves to `kept` (round the vertex by mate, next).
        let mut h = self.half(h2)?.next;
        let mut guard = 0;
        while h != h1 {
            self.half_mut(h).vertex = kept;
            h = self.half(self.mate(h)?)?.next;
            guard += 1;
            if guard > self.halves.len() {
                return Err(TopologyError::Invalid(
                    "lkev: the star of the vertex never closes".into(),
                ));
            }
        }
        let lp1 = self.half(h1)?.lp;
        let a = self.delete_half(h1);
        self.set_loop_half(lp1, a);
        let lp2 = self.half(h2)?.lp;
        let b = self.delete_half(h2);
        self.set_loop_half(lp2, b);
        self.vertices[gone.index()] = None;
        self.edges[e.index()] = None;
        let half = self.leaving_after(b)?;
        self.vertices[kept.index()] = Some(Vertex { half: Some(half) });
        Ok(gone)
    }

    /// Kill edge, face: the inverse of [`Brep::lmef`]: removes edge `e` between two
    /// different faces and merges the face on its `plus` half's side into the face on
    /// its `minus` half's side (its loops move there).
    pub fn lkef(&mut self, e: EdgeId) -> Result<FaceId> {
        let Edge {
            plus: h1,
            minus: h2,
        } = *self.edge_of(e)?;
        let (l1, l2) = (self.half(h1)?.lp, self.half(h2)?.lp);
        let (f1, f2) = (self.loop_of(l1)?.face, self.loop_of(l2)?.face);
        if f1 == f2 {
            return Err(TopologyError::NotApplicable(
                "lkef: the edge must lie between two faces".into(),
            ));
        }
        if self.face_of(f1)?.loops[0] != l1 || self.face_of(f2)?.loops[0] != l2 {
            return Err(TopologyError::NotApplicable(
                "lkef: the edge must lie on both faces' outer loops".into(),
            ));
        }
        // Every half-edge of l1 joins l2.
        let mut h = h1;
        loop {
            self.half_mut(h).lp = l2;
            h = self.half(h)?.next;
            if h == h1 {
                break;
            }
        }
        // One cycle through both halves (Mantyla's splice), then each half deleted.
        let (p1, p2) = (self.half(h1)?.prev, self.half(h2)?.prev);
        self.half_mut(p1).next = h2;
        self.half_mut(p2).next = h1;
        self.half_mut(h2).prev = p1;
        self.half_mut(h1).prev = p2;
        let (a, b) = (self.half(h1)?.vertex, self.half(h2)?.vertex);
        let r2 = self.delete_half(h2);
        let r1 = self.delete_half(h1);
        // What stood before `h2` in the spliced cycle ended at a (where `h1` started),
        // what stood before `h1` ended at b; for an edge closing on itself (a = b) the
        // first was `h1`, and the deletions leave a lone vertex's half-edge.
        if self.half(r2).is_ok() {
            let leaving = self.leaving_after(r2)?;
            self.vertices[a.index()] = Some(Vertex {
                half: Some(leaving),
            });
        }
        let leaving = self.leaving_after(r1)?;
        self.vertices[b.index()] = Some(Vertex {
            half: Some(leaving),
        });
        self.loops[l2.index()] = Some(Loop { half: r1, face: f2 });
        self.loops[l1.index()] = None;
        let rings: Vec<LoopId> = self.face_of(f1)?.loops[1..].to_vec();
        for r in &rings {
            self.loops[r.index()]
                .as_mut()
                .expect("a face's loop is live")
                .face = f2;
        }
        self.faces[f2.index()]
            .as_mut()
            .expect("checked above")
            .loops
            .extend(rings);
        self.faces[f1.index()] = None;
        self.edges[e.index()] = None;
        Ok(f1)
    }

    /// Makes `h` the first half-edge of loop `lp`.
    fn set_loop_half(&mut self, lp: LoopId, h: HalfEdgeId) {
        if let Some(l) = self.loops[lp.index()].as_mut() {
            l.half = h;
        }
    }

    /// The half-edge leaving the vertex where `h` (what [`Brep::delete_half`] returned)
    /// ends: `h` itself when it is a lone vertex's half-edge, else the one after it.
    fn leaving_after(&self, h: HalfEdgeId) -> Result<HalfEdgeId> {
        let he = self.half(h)?;
        Ok(if he.edge.is_none() { h } else { he.next })
    }

    /// The shell (smallest face id of its connected component) of face `f`.
    fn shell_of_face(&self, f: FaceId) -> Result<FaceId> {
        let shells = self.shells()?;
        shells
            .into_iter()
            .find(|s| s.contains(&f))
            .and_then(|s| s.into_iter().next())
            .ok_or_else(|| TopologyError::Dead(format!("face {}", f.0)))
    }

    /// The faces of each connected shell (faces joined across edges or sharing a
    /// vertex), each set in id order, the shells by their smallest face.
    pub fn shells(&self) -> Result<Vec<BTreeSet<FaceId>>> {
        let faces: Vec<FaceId> = self.faces().collect();
        let mut parent: Vec<usize> = (0..self.faces.len()).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        // Faces meeting at a vertex are in one shell.
        let mut at_vertex: Vec<Option<usize>> = vec![None; self.vertices.len()];
        for h in ids(&self.halves) {
            let he = self.halves[h].expect("ids lists live slots");
            let f = self.loop_of(he.lp)?.face.index();
            match at_vertex[he.vertex.index()] {
                None => at_vertex[he.vertex.index()] = Some(f),
                Some(g) => {
                    let (a, b) = (root(&mut parent, f), root(&mut parent, g));
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        let mut out: Vec<BTreeSet<FaceId>> = Vec::new();
        let mut index_of_root = std::collections::BTreeMap::new();
        for f in faces {
            let r = root(&mut parent, f.index());
            let k = *index_of_root.entry(r).or_insert_with(|| {
                out.push(BTreeSet::new());
                out.len() - 1
            });
            out[k].insert(f);
        }
        Ok(out)
    }

    /// The element counts and Euler-Poincare terms.
    pub fn counts(&self) -> Result<Counts> {
        let faces = self.faces().count();
        let loops = self.loops().count();
        Ok(Counts {
            vertices: self.vertices().count(),
            edges: self.edges().count(),
            faces,
            rings: loops - faces,
            shells: self.shells()?.len(),
            genus: self.genus,
        })
    }

    /// Checks every link and the Euler-Poincare formula: each half-edge's next and prev
    /// agree, its loop's cycle holds it, its edge names it, and the half-edge after it
    /// starts where its mate does (so edges join the vertices they claim); each loop's
    /// face lists it, each face's loops point back, each vertex's half-edge leaves it.
    pub fn check(&self) -> Result<Counts> {
        let bad = |why: String| Err(TopologyError::Invalid(why));
        for h in ids(&self.halves).map(|i| HalfEdgeId(i as u32)) {
            let he = self.half(h)?;
            if self.half(he.next)?.prev != h || self.half(he.prev)?.next != h {
                return bad(format!("half-edge {}: next and prev disagree", h.0));
            }
            if self.half(he.next)?.lp != he.lp {
                return bad(format!("half-edge {}: its next runs in another loop", h.0));
            }
            self.vertices
                .get(he.vertex.index())
                .and_then(Option::as_ref)
                .ok_or_else(|| TopologyError::Invalid(format!("half-edge {}: dead vertex", h.0)))?;
            match he.edge {
                None => {
                    if he.next != h {
                        return bad(format!("half-edge {}: no edge in a loop of many", h.0));
                    }
                }
                Some(e) => {
                    let edge = self.edge_of(e).map_err(|_| {
                        TopologyError::Invalid(format!("half-edge {}: dead edge", h.0))
                    })?;
                    if edge.plus != h && edge.minus != h {
                        return bad(format!("half-edge {}: its edge does not name it", h.0));
                    }
                    let mate = self.mate(h)?;
                    if self.half(mate)?.vertex != self.half(he.next)?.vertex {
                        return bad(format!(
                            "half-edge {}: it ends where its mate does not start",
                            h.0
                        ));
                    }
                }
            }
        }
        for e in self.edges() {
            let edge = self.edge_of(e)?;
            for h in [edge.plus, edge.minus] {
                if self
                    .half(h)
                    .map_err(|_| TopologyError::Invalid(format!("edge {}: dead half-edge", e.0)))?
                    .edge
                    != Some(e)
                {
                    return bad(format!("edge {}: its half-edge names another edge", e.0));
                }
            }
        }
        let mut in_loops = 0;
        for l in self.loops() {
            let lp = self.loop_of(l)?;
            let face = self
                .face_of(lp.face)
                .map_err(|_| TopologyError::Invalid(format!("loop {}: dead face", l.0)))?;
            if !face.loops.contains(&l) {
                return bad(format!("loop {}: its face does not list it", l.0));
            }
            let cycle = self.loop_halves(l)?;
            if cycle
                .iter()
                .any(|&h| self.halves[h.index()].map(|x| x.lp) != Some(l))
            {
                return bad(format!(
                    "loop {}: a half-edge of its cycle runs elsewhere",
                    l.0
                ));
            }
            in_loops += cycle.len();
        }
        if in_loops != self.halves.iter().flatten().count() {
            return bad("a half-edge is in no loop's cycle".into());
        }
        for f in self.faces() {
            let face = self.face_of(f)?;
            if face.loops.is_empty() {
                return bad(format!("face {}: no loop", f.0));
            }
            for &l in &face.loops {
                if self.loop_of(l)?.face != f {
                    return bad(format!("face {}: loop {} names another face", f.0, l.0));
                }
            }
        }
        for v in self.vertices() {
            let vx = self.vertices[v.index()].expect("ids lists live slots");
            match vx.half {
                Some(h) if self.half(h)?.vertex == v => {}
                Some(_) => return bad(format!("vertex {}: its half-edge leaves elsewhere", v.0)),
                None => return bad(format!("vertex {}: no half-edge leaves it", v.0)),
            }
        }
        let counts = self.counts()?;
        if counts.euler_poincare() != 0 {
            return bad(format!("Euler-Poincare fails: {counts:?}"));
        }
        Ok(counts)
    }
}

/// The indices of the live slots of a table.
fn ids<T>(table: &[Option<T>]) -> impl Iterator<Item = usize> + '_ {
    table
        .iter()
        .enumerate()
        .filter_map(|(i, x)| x.as_ref().map(|_| i))
}

/// What [`sweep`] made of a loop.
struct Sweep {
    /// The loop's half-edges before the sweep, in order.
    ring: Vec<HalfEdgeId>,
    /// The vertex each of them starts at.
    base: Vec<VertexId>,
    /// Per base vertex: the edge up from it, and the vertex at its top.
    up: Vec<EdgeId>,
    tops: Vec<VertexId>,
    /// Per loop half-edge k: the face swept from it, and its edge at the top (from top
    /// k to top k + 1).
    sides: Vec<FaceId>,
    cap_edges: Vec<EdgeId>,
}

impl Sweep {
    /// The edges of the loop before the sweep, in order.
    fn base_edges(&self, b: &Brep) -> Result<Vec<EdgeId>> {
        self.ring
            .iter()
            .map(|&h| b.edge(h)?.ok_or_else(|| lost("an edge of the swept loop")))
            .collect()
    }
}

/// Sweeps loop `l` of its face (the face stays, as the cap): an edge up from each of
/// its vertices (lmev into the loop), then the tops joined in order (lmef), each join
/// cutting off the face swept from one edge of the loop. The topology of extruding a
/// face; a sheet's first lift and a flange are both this.
fn sweep(b: &mut Brep, l: LoopId) -> Result<Sweep> {
    let ring = b.loop_halves(l)?;
    let n = ring.len();
    if n < 2 || b.edge(ring[0])?.is_none() {
        return Err(TopologyError::NotApplicable(
            "a loop of fewer than two edges has nothing to sweep".into(),
        ));
    }
    let mut base = Vec::with_capacity(n);
    let mut up = Vec::with_capacity(n);
    let mut tops = Vec::with_capacity(n);
    for &h in &ring {
        base.push(b.vertex(h)?);
        let (e, w) = b.lmev(h, h)?;
        up.push(e);
        tops.push(w);
    }
    let mut sides = Vec::with_capacity(n);
    let mut cap_edges = Vec::with_capacity(n);
    for k in 0..n {
        let a = Sheet::half_leaving(b, up[k], tops[k])?;
        // The half-edge of the cap's loop that leaves the next top (after the first
        // join, that top's own up half runs in a swept face).
        let c = b
            .loop_halves(b.loop_with(a)?)?
            .into_iter()
            .find(|&h| b.vertex(h).ok() == Some(tops[(k + 1) % n]))
            .ok_or_else(|| lost("a top of the swept loop"))?;
        let (e, f) = b.lmef(a, c)?;
        cap_edges.push(e);
        sides.push(f);
    }
    Ok(Sweep {
        ring,
        base,
        up,
        tops,
        sides,
        cap_edges,
    })
}

/// A piece of a new sheet's boundary ([`Sheet::add_sheet`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Piece {
    /// A run of picked edges: the path of vertices along them, in the boundary's order.
    Picked(Vec<VertexId>),
    /// This many new boundary curves, from the end of the run before to the start of
    /// the run after.
    Curves(usize),
}

/// What [`Sheet::add_sheet`] made.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AddedSheet {
    /// The new sheet's sides: the one across the picked edges, and its twin.
    pub sides: (FaceId, FaceId),
    /// The new boundary curves' edges on the first side, in order.
    pub curves: Vec<EdgeId>,
}

/// A checked run of picked edges.
struct PickedRun {
    /// Its first vertex and that vertex's twin.
    first: (VertexId, VertexId),
    /// Its last vertex and that vertex's twin.
    last: (VertexId, VertexId),
    /// Each picked edge and its twin.
    edges: Vec<(EdgeId, EdgeId)>,
    /// Each picked edge's thickness face.
    open: Vec<FaceId>,
    /// The zero-length edges between neighbouring picked edges (Skze's).
    inner_zero: Vec<EdgeId>,
    /// The boundary curves after the run.
    curves_after: usize,
}

/// What the S-Euler operators of [`Sheet::add_sheet`] made and killed, for the roles.
#[derive(Default)]
struct Made {
    killed_edges: Vec<EdgeId>,
    thickness_gone: Vec<FaceId>,
    /// Each boundary curve and its twin.
    curves: Vec<(EdgeId, EdgeId)>,
    /// The zero-length edges between new twin vertices.
    zero: Vec<EdgeId>,
    /// Each new vertex and its twin.
    vertices: Vec<(VertexId, VertexId)>,
}

/// The half-edge of face `f`'s outer loop that leaves vertex `v`. Where the loop passes
/// through `v` twice (the free rim pinched there) which of the two a new curve should
/// leave by is not known, so the operation does not apply.
fn leaving_in(b: &Brep, f: FaceId, v: VertexId) -> Result<HalfEdgeId> {
    let mut leaving = b
        .loop_halves(b.loops_of(f)?[0])?
        .into_iter()
        .filter(|&h| b.vertex(h).ok() == Some(v));
    let h = leaving
        .next()
        .ok_or_else(|| lost("a vertex on an open loop"))?;
    if leaving.next().is_some() {
        return Err(TopologyError::NotApplicable(format!(
            "the free rim passes through vertex {} twice there, so a new curve from it \
             has two ways to go",
            v.0
        )));
    }
    Ok(h)
}

/// The face across edge `e` from the sheets that were there before (`sides`, the faces
/// that were sides): the open loop's face on that edge's side of the new sheet.
fn across_from(b: &Brep, sides: &[bool], e: EdgeId) -> Result<FaceId> {
    let (p, m) = b.halves_of(e)?;
    for h in [p, m] {
        let f = b.face_with(b.loop_with(h)?)?;
        if !sides.get(f.index()).copied().unwrap_or(false) {
            return Ok(f);
        }
    }
    Err(lost("the new sheet across a picked edge"))
}

/// Smev: a boundary curve from `at` (and its twin from `at_twin`) to a new vertex (and
/// its twin), grown into the open loop of face `open`; the new twins joined by a
/// zero-length edge, which cuts the curve's thickness face off the open loop. Returns
/// the new vertex and its twin.
fn smev(
    b: &mut Brep,
    open: FaceId,
    (at, at_twin): (VertexId, VertexId),
    made: &mut Made,
) -> Result<(VertexId, VertexId)> {
    let h = leaving_in(b, open, at)?;
    let (c, w) = b.lmev(h, h)?;
    let h2 = leaving_in(b, open, at_twin)?;
    let (c2, w2) = b.lmev(h2, h2)?;
    let a = Sheet::half_leaving(b, c, w)?;
    let d = Sheet::half_leaving(b, c2, w2)?;
    let (z, _) = b.lmef(a, d)?;
    made.curves.push((c, c2));
    made.zero.push(z);
    made.vertices.push((w, w2));
    Ok((w, w2))
}

/// Smel: the last boundary curve of a run, from `from` to `to`, both on the open loop
/// of the face across picked edge `edge` (twin `edge_twin`): one curve closes the new
/// sheet's side off the loop, its twin (between the twins) the other side, and the
/// curve's thickness face is what is left between them.
fn smel(
    b: &mut Brep,
    sides: &[bool],
    (edge, edge_twin): (EdgeId, EdgeId),
    from: (VertexId, VertexId),
    to: (VertexId, VertexId),
    made: &mut Made,
) -> Result<()> {
    let open = across_from(b, sides, edge)?;
    let (c, _) = b.lmef(leaving_in(b, open, from.0)?, leaving_in(b, open, to.0)?)?;
    let open = across_from(b, sides, edge_twin)?;
    let (c2, _) = b.lmef(leaving_in(b, open, from.1)?, leaving_in(b, open, to.1)?)?;
    made.curves.push((c, c2));
    Ok(())
}

/// Smep: the last boundary curve of a run, from `from` on the open loop of face
/// `face_from` to `to` on another open loop, of `face_to`: the second loop becomes a
/// ring of the first's face (a passage within one sheet; two sheets joined), the curve
/// joins the two loops into one, and its twin cuts the curve's thickness face off.
fn smep(
    b: &mut Brep,
    (face_from, face_to): (FaceId, FaceId),
    from: (VertexId, VertexId),
    to: (VertexId, VertexId),
    made: &mut Made,
) -> Result<()> {
    let ring = b.lkfmrh(face_from, face_to)?;
    made.thickness_gone.push(face_to);
    let h1 = leaving_in(b, face_from, from.0)?;
    let h2 = b
        .loop_halves(ring)?
        .into_iter()
        .find(|&h| b.vertex(h).ok() == Some(to.0))
        .ok_or_else(|| lost("a vertex on the second open loop"))?;
    let c = b.lmekr(h1, h2)?;
    let (c2, _) = b.lmef(
        leaving_in(b, face_from, from.1)?,
        leaving_in(b, face_from, to.1)?,
    )?;
    made.curves.push((c, c2));
    Ok(())
}

/// What a face of a sheet model is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaceRole {
    /// One side of a sheet, with its twin (the other side).
    Side {
        /// The other side.
        twin: FaceId,
    },
    /// A thickness face: a zero-area loop in the sheet model.
    Thickness,
}

/// What an edge of a sheet model is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EdgeRole {
    /// An edge of a side, with its twin on the other side.
    Side {
        /// The twin edge.
        twin: EdgeId,
    },
    /// A zero-length edge, joining a vertex to its twin.
    ZeroLength,
}

/// A sheet model's topology: the solid's [`Brep`] with each face's, edge's and
/// vertex's role and twin.
#[derive(Debug, Clone, PartialEq)]
pub struct Sheet {
    /// The topology.
    pub brep: Brep,
    faces: Vec<Option<FaceRole>>,
    edges: Vec<Option<EdgeRole>>,
    vertex_twins: Vec<Option<VertexId>>,
}

impl Sheet {
    /// The first sheet of a model: a slab of zero thickness over an outline of `n`
    /// vertices (3 or more), built by Euler operators only. Returns the sheet and its two
    /// sides (bottom, top): the bottom's outer loop runs through the outline's vertices,
    /// the top's through their twins; between them, one thickness face per outline edge.
    pub fn initial(n: usize) -> Result<(Sheet, FaceId, FaceId)> {
        if n < 3 {
            return Err(TopologyError::NotApplicable(format!(
                "a sheet's outline needs 3 vertices or more, not {n}"
            )));
        }
        let mut b = Brep::new();
        // The outline as a lamina: a chain of n vertices, closed by lmef into two faces.
        let (v0, bottom, h0) = b.mvfs();
        let mut tip = h0;
        let mut first_edge = None;
        for _ in 1..n {
            let (e, _) = b.lmev(tip, tip)?;
            first_edge.get_or_insert(e);
            // The half-edge leaving the new vertex: the one just before `tip` now.
            tip = b.prev(tip)?;
        }
        let first_edge = first_edge.expect("n >= 3 makes at least two edges");
        let leaving_v0 = Self::half_leaving(&b, first_edge, v0)?;
        let (_, top) = b.lmef(tip, leaving_v0)?;
        // Lift the top's loop: every vertex gets its twin by a zero-length edge, and
        // each outline edge a thickness face.
        let top_loop = b.loops_of(top)?[0];
        let lift = sweep(&mut b, top_loop)?;
        let outline = lift.base_edges(&b)?;
        let (up, thickness, lifted) = (lift.up, lift.sides, lift.cap_edges);
        let twins: Vec<(VertexId, VertexId)> = lift.base.into_iter().zip(lift.tops).collect();
        let mut sheet = Sheet {
            faces: Vec::new(),
            edges: Vec::new(),
            vertex_twins: Vec::new(),
            brep: b,
        };
        sheet.sync_tables();
        for f in thickness {
            sheet.faces[f.index()] = Some(FaceRole::Thickness);
        }
        sheet.faces[top.index()] = Some(FaceRole::Side { twin: bottom });
        sheet.faces[bottom.index()] = Some(FaceRole::Side { twin: top });
        for &e in &up {
            sheet.edges[e.index()] = Some(EdgeRole::ZeroLength);
        }
        for &(v, w) in &twins {
            sheet.vertex_twins[v.index()] = Some(w);
            sheet.vertex_twins[w.index()] = Some(v);
        }
        // The edge joining twins k and k + 1 is the twin of outline edge k (from vertex
        // k to vertex k + 1, as `ring` runs).
        for (&l, &o) in lifted.iter().zip(&outline) {
            sheet.edges[l.index()] = Some(EdgeRole::Side { twin: o });
            sheet.edges[o.index()] = Some(EdgeRole::Side { twin: l });
        }
        sheet.check()?;
        Ok((sheet, bottom, top))
    }

    /// The half of edge `e` that leaves vertex `v`.
    fn half_leaving(b: &Brep, e: EdgeId, v: VertexId) -> Result<HalfEdgeId> {
        let (p, m) = b.halves_of(e)?;
        if b.vertex(p)? == v {
            Ok(p)
        } else if b.vertex(m)? == v {
            Ok(m)
        } else {
            Err(TopologyError::Invalid(format!(
                "edge {} does not leave vertex {}",
                e.0, v.0
            )))
        }
    }

    /// Punches an `n`-sided hole through the sheet at side face `side` (and its twin),
    /// its first corner bridged from `at`, a vertex of the side's outer loop (paper 003,
    /// section 4.3, Fig. 10: a hole loop): a [`Sheet::region`] there, [`Sheet::remove`]d.
    /// The side and its twin each get a ring of `n` new vertices (twins of each other),
    /// the ring edges are twins, and between the two rings `n` zero-length edges and `n`
    /// thickness faces line the hole; the genus grows by one. Nothing changes when an
    /// argument is wrong.
    pub fn punch(&mut self, side: FaceId, at: VertexId, n: usize) -> Result<Hole> {
        let before = self.clone();
        let punched = self
            .region(side, at, n)
            .and_then(|region| self.make_passage(region.face));
        if punched.is_err() {
            *self = before;
        }
        punched
    }

    /// Removes a region of the sheet: a side and its twin, bounded by their outer loops
    /// only (paper 003, section 4.4, Fig. 11-12). Which of the paper's three cases it
    /// is follows from the region's rim:
    /// - every edge joins another side: a passage is made ([`Removal::Passage`]);
    /// - one run of its edges is free (on the sheet's boundary): the sheet is trimmed
    ///   and the number of passages does not change;
    /// - two runs or more are free: each further run closes a passage, or, where none
    ///   ran round the region, cuts the sheet in two ([`Removal::Trimmed`]).
    ///
    /// Where the region joined other sides, their rim is lined with thickness faces.
    /// Nothing changes when the region is not a side, has holes, lies free all round
    /// (a sheet of its own), or another sheet meets its free rim inside a run.
    pub fn remove(&mut self, region: FaceId) -> Result<Removal> {
        let FaceRole::Side { twin } = self.face_role(region)? else {
            return Err(TopologyError::NotApplicable(
                "only a side is removed, not a thickness face".into(),
            ));
        };
        let b = &self.brep;
        if b.loops_of(region)?.len() > 1 || b.loops_of(twin)?.len() > 1 {
            return Err(TopologyError::NotApplicable(
                "a region with holes is not removed yet".into(),
            ));
        }
        let rim = b.loop_halves(b.loops_of(region)?[0])?;
        let mut free = Vec::with_capacity(rim.len());
        for &h in &rim {
            let across = b.face_with(b.loop_with(b.mate(h)?)?)?;
            free.push(self.face_role(across)? == FaceRole::Thickness);
        }
        if free.iter().all(|&f| !f) {
            return self.make_passage(region).map(Removal::Passage);
        }
        if free.iter().all(|&f| f) {
            return Err(TopologyError::NotApplicable(
                "the region is a sheet of its own, free all round: nothing would be left".into(),
            ));
        }
        self.trim(region, twin, &rim, &free)
    }

    /// [`Sheet::remove`] of a region whose rim is free in `free` runs: the runs of free
    /// edges (each with its thickness faces, joined along the run into one), the region
    /// and its twin merge into thickness faces along the rim that joined other sides.
    /// Per run, in order: the zero-length edges inside it killed (`lkef`, the thickness
    /// quads merged), its first edge killed on the region's side (`lkef`), the rest of
    /// the run killed as struts (`lkev`), then the same on the twin's side, where the
    /// first run's `lkef` takes the twin in and each later run's edge runs twice round
    /// one face (`lkemr`, then `lmfkrh`: a passage closed, or the sheet cut in two).
    fn trim(
        &mut self,
        region: FaceId,
        twin: FaceId,
        rim: &[HalfEdgeId],
        free: &[bool],
    ) -> Result<Removal> {
        let b = &self.brep;
        let n = rim.len();
        // The runs of free edges, from the first free edge after a joined one.
        let start = (0..n)
            .find(|&i| free[i] && !free[(i + n - 1) % n])
            .ok_or_else(|| lost("the start of a free run"))?;
        let mut runs: Vec<Vec<HalfEdgeId>> = Vec::new();
        for k in 0..n {
            let i = (start + k) % n;
            if !free[i] {
                continue;
            }
            if k == 0 || !free[(i + n - 1) % n] {
                runs.push(Vec::new());
            }
            runs.last_mut().expect("pushed above").push(rim[i]);
        }
        // Everything each run needs, found before anything changes.
        struct Run {
            edges: Vec<EdgeId>,
            twins: Vec<EdgeId>,
            inner: Vec<VertexId>,
            inner_twins: Vec<VertexId>,
            zero: Vec<EdgeId>,
        }
        let mut plans = Vec::with_capacity(runs.len());
        for run in &runs {
            let mut plan = Run {
                edges: Vec::new(),
                twins: Vec::new(),
                inner: Vec::new(),
                inner_twins: Vec::new(),
                zero: Vec::new(),
            };
            for (k, &h) in run.iter().enumerate() {
                let e = b.edge(h)?.ok_or_else(|| lost("a rim edge"))?;
                let EdgeRole::Side { twin: e2 } = self.edge_role(e)? else {
                    return Err(lost("a side edge's twin"));
                };
                plan.edges.push(e);
                plan.twins.push(e2);
                if k > 0 {
                    let v = b.vertex(h)?;
                    let star = b.edges_at(v)?;
                    if star.len() != 3 {
                        return Err(TopologyError::NotApplicable(format!(
                            "another sheet meets the free rim at vertex {}: remove it first",
                            v.0
                        )));
                    }
                    let z = star
                        .into_iter()
                        .find(|&e| self.edge_role(e).ok() == Some(EdgeRole::ZeroLength))
                        .ok_or_else(|| lost("a zero-length edge on the free rim"))?;
                    plan.inner.push(v);
                    plan.inner_twins.push(self.twin_vertex(v)?);
                    plan.zero.push(z);
                }
            }
            plans.push(plan);
        }
        let genus = b.genus;
        let shells = b.shells()?.len();
        // The faces that merge: the region, its twin and the runs' thickness faces.
        let mut involved = vec![region, twin];
        for run in &runs {
            for &h in run {
                involved.push(b.face_with(b.loop_with(b.mate(h)?)?)?);
            }
        }
        involved.sort();
        involved.dedup();
        let mut b = self.brep.clone();
        let mut killed_faces = Vec::new();
        let mut killed_edges = Vec::new();
        let mut killed_vertices = Vec::new();
        let mut made = Vec::new();
        let face_across = |b: &Brep, e: EdgeId| -> Result<(FaceId, FaceId, HalfEdgeId)> {
            let (p, m) = b.halves_of(e)?;
            Ok((
                b.face_with(b.loop_with(p)?)?,
                b.face_with(b.loop_with(m)?)?,
                p,
            ))
        };
        for (j, plan) in plans.iter().enumerate() {
            for &z in &plan.zero {
                killed_faces.push(b.lkef(z)?);
                killed_edges.push(z);
            }
            // The region's side: its first edge between two faces, the rest struts.
            killed_faces.push(b.lkef(plan.edges[0])?);
            for (k, &e) in plan.edges.iter().enumerate().skip(1) {
                killed_vertices.push(b.lkev_at(e, plan.inner[k - 1])?);
            }
            // The twin's side.
            let (f1, f2, half) = face_across(&b, plan.twins[0])?;
            if f1 != f2 {
                killed_faces.push(b.lkef(plan.twins[0])?);
            } else if j == 0 {
                return Err(lost("the twin side, which the first run takes in"));
            } else {
                let ring = b.lkemr(half)?;
                made.push(b.lmfkrh(f1, ring)?);
            }
            for (k, &e) in plan.twins.iter().enumerate().skip(1) {
                killed_vertices.push(b.lkev_at(e, plan.inner_twins[k - 1])?);
            }
            killed_edges.extend(plan.edges.iter().chain(&plan.twins).copied());
        }
        // What is left of the merged faces, and the faces split off them, line the rim.
        let mut lining: Vec<FaceId> = involved
            .iter()
            .copied()
            .filter(|f| !killed_faces.contains(f))
            .chain(made.iter().copied())
            .collect();
        lining.sort();
        let after_genus = b.genus;
        let after_shells = b.shells()?.len();
        self.brep = b;
        self.sync_tables();
        for &f in &involved {
            self.faces[f.index()] = None;
        }
        for &f in &lining {
            self.faces[f.index()] = Some(FaceRole::Thickness);
        }
        for &e in &killed_edges {
            self.edges[e.index()] = None;
        }
        for &v in &killed_vertices {
            self.vertex_twins[v.index()] = None;
        }
        Ok(Removal::Trimmed {
            lining,
            passages_closed: genus.saturating_sub(after_genus),
            pieces_made: after_shells.saturating_sub(shells),
        })
    }

    /// [`Sheet::remove`] of a region every edge of whose rim joins another side: the
    /// twin's loop becomes a ring of the region (a through hole, genus + 1), the two
    /// loops are joined by a zero-length edge, and each further pair of twin corners by
    /// another, each cutting a thickness quad off; the region itself becomes the first.
    fn make_passage(&mut self, region: FaceId) -> Result<Hole> {
        let FaceRole::Side { twin } = self.face_role(region)? else {
            return Err(TopologyError::NotApplicable(
                "only a side is removed, not a thickness face".into(),
            ));
        };
        let b = &self.brep;
        if b.loops_of(region)?.len() > 1 || b.loops_of(twin)?.len() > 1 {
            return Err(TopologyError::NotApplicable(
                "a region with holes is not removed yet".into(),
            ));
        }
        let outer = b.loop_halves(b.loops_of(region)?[0])?;
        for &h in &outer {
            let across = b.face_with(b.loop_with(b.mate(h)?)?)?;
            if !matches!(self.face_role(across)?, FaceRole::Side { .. }) {
                return Err(TopologyError::NotApplicable(
                    "a region on the sheet's free boundary is not removed yet (no passage \
                     is made there)"
                        .into(),
                ));
            }
        }
        let corners: Vec<VertexId> = outer.iter().map(|&h| b.vertex(h)).collect::<Result<_>>()?;
        let twins: Vec<VertexId> = corners
            .iter()
            .map(|&v| self.twin_vertex(v))
            .collect::<Result<_>>()?;
        let mut b = self.brep.clone();
        b.lkfmrh(region, twin)?;
        let leaving = |b: &Brep, l: LoopId, v: VertexId| -> Option<HalfEdgeId> {
            b.loop_halves(l)
                .ok()?
                .into_iter()
                .find(|&h| b.vertex(h).ok() == Some(v))
        };
        let loops = b.loops_of(region)?.to_vec();
        let (h1, h2) = (
            leaving(&b, loops[0], corners[0]).ok_or_else(|| lost("the region's first corner"))?,
            leaving(&b, loops[1], twins[0]).ok_or_else(|| lost("its twin"))?,
        );
        let mut zero = vec![b.lmekr(h1, h2)?];
        let mut lining = vec![region];
        for k in 1..corners.len() {
            // The loop (of the lining made so far) that both corners k leave.
            let (h1, h2) = lining
                .iter()
                .map(|&f| b.loops_of(f).map(|ls| ls[0]))
                .collect::<Result<Vec<_>>>()?
                .into_iter()
                .find_map(|l| Some((leaving(&b, l, twins[k])?, leaving(&b, l, corners[k])?)))
                .ok_or_else(|| lost("a corner of the region"))?;
            // From the twin round to the corner: the quad between corners k - 1 and k.
            let (e, f) = b.lmef(h1, h2)?;
            zero.push(e);
            lining.push(f);
        }
        self.brep = b;
        self.sync_tables();
        self.faces[twin.index()] = None;
        for &f in &lining {
            self.faces[f.index()] = Some(FaceRole::Thickness);
        }
        for &e in &zero {
            self.edges[e.index()] = Some(EdgeRole::ZeroLength);
        }
        Ok(Hole {
            corners,
            twin_corners: twins,
            lining,
        })
    }

    /// Adds a flange along a free edge of the sheet (paper 003, section 4.2, Fig. 6(d):
    /// a new sheet through one edge at an angle to the sheet, bounded by that edge and
    /// three new ones). Topologically the thickness face along `edge` is swept out: the
    /// faces swept from the edge and its twin are the flange's two sides (twins), those
    /// swept from the zero-length edges at its ends are thickness faces, and the
    /// thickness face itself moves to the flange's far edge. Nothing changes when
    /// `edge` is not a free edge of the sheet.
    pub fn flange(&mut self, edge: EdgeId) -> Result<Flange> {
        let EdgeRole::Side { .. } = self.edge_role(edge)? else {
            return Err(TopologyError::NotApplicable(
                "a flange goes on a side edge, not a zero-length one".into(),
            ));
        };
        let (p, m) = self.brep.halves_of(edge)?;
        let mut thickness = None;
        for h in [p, m] {
            let f = self.brep.face_with(self.brep.loop_with(h)?)?;
            if self.face_role(f)? == FaceRole::Thickness {
                thickness = Some(f);
            }
        }
        let t = thickness.ok_or_else(|| {
            TopologyError::NotApplicable(format!(
                "edge {} is not on the sheet's free boundary: sheets meet there",
                edge.0
            ))
        })?;
        let mut b = self.brep.clone();
        let t_loop = b.loops_of(t)?[0];
        // A zero-area loop that passes through a vertex twice (the free rim pinched
        // there) has no one flange to sweep.
        let mut seen = BTreeSet::new();
        for h in b.loop_halves(t_loop)? {
            if !seen.insert(b.vertex(h)?) {
                return Err(TopologyError::NotApplicable(format!(
                    "the free rim at edge {} passes through vertex {} twice",
                    edge.0,
                    b.vertex(h)?.0
                )));
            }
        }
        let sw = sweep(&mut b, t_loop)?;
        let base_edges = sw.base_edges(&b)?;
        let roles: Vec<EdgeRole> = base_edges
            .iter()
            .map(|&e| self.edge_role(e))
            .collect::<Result<_>>()?;
        let index_of_edge = |e: EdgeId| base_edges.iter().position(|&x| x == e);
        let index_of_vertex = |v: VertexId| sw.base.iter().position(|&x| x == v);
        let twin_index = |k: usize| -> Result<usize> {
            index_of_vertex(self.twin_vertex(sw.base[k])?)
                .ok_or_else(|| lost("a twin on the thickness face"))
        };
        let mut faces = Vec::new();
        let mut edges = Vec::new();
        let mut twins = Vec::new();
        let mut sides = Vec::new();
        for (k, role) in roles.iter().enumerate() {
            let j = twin_index(k)?;
            twins.push((sw.tops[k], sw.tops[j]));
            edges.push((sw.up[k], EdgeRole::Side { twin: sw.up[j] }));
            match *role {
                EdgeRole::Side { twin } => {
                    let i = index_of_edge(twin).ok_or_else(|| lost("a twin edge"))?;
                    faces.push((sw.sides[k], FaceRole::Side { twin: sw.sides[i] }));
                    edges.push((
                        sw.cap_edges[k],
                        EdgeRole::Side {
                            twin: sw.cap_edges[i],
                        },
                    ));
                    sides.push(sw.sides[k]);
                }
                EdgeRole::ZeroLength => {
                    faces.push((sw.sides[k], FaceRole::Thickness));
                    edges.push((sw.cap_edges[k], EdgeRole::ZeroLength));
                }
            }
        }
        let k = base_edges
            .iter()
            .position(|&e| e == edge)
            .ok_or_else(|| lost("the flanged edge"))?;
        let far = sw.cap_edges[k];
        let next = (k + 1) % sw.base.len();
        let far_ends = [(sw.base[k], sw.tops[k]), (sw.base[next], sw.tops[next])];
        self.brep = b;
        self.sync_tables();
        for (f, r) in faces {
            self.faces[f.index()] = Some(r);
        }
        for (e, r) in edges {
            self.edges[e.index()] = Some(r);
        }
        for (v, w) in twins {
            self.vertex_twins[v.index()] = Some(w);
        }
        Ok(Flange {
            sides,
            far_edge: far,
            far_ends,
        })
    }

    /// Adds a sheet on picked edges (paper 003, section 4.2, Fig. 6-9): its boundary
    /// runs through `pieces` in order and back to the start: runs of picked edges (each
    /// a path of vertices along free edges of the sheets there) and, between them, runs
    /// of new boundary curves. The S-Euler operators are chosen as the paper does:
    /// - `Skze` at each vertex inside a picked run kills the zero-length edge between
    ///   two picked edges' thickness faces, so each run has one thickness face, the
    ///   loop the new sheet grows from (an open loop);
    /// - each boundary curve but a run's last is `Smev` (a new vertex and its twin, the
    ///   curve and its twin, a zero-length edge between the new twins cutting the
    ///   curve's thickness face off the open loop);
    /// - a run's last curve is `Smel` when its end lies on the open loop it started from
    ///   (the loop closes into the new sheet's two sides), or `Smep` when it lies on
    ///   another open loop (the two loops become one: a passage when they were on one
    ///   sheet, the sheets joined when not).
    ///
    /// Nothing changes when a picked edge is not free, a run is not a path, the pieces
    /// do not alternate between picked runs and curves, or (on two runs or more) the
    /// picked edges face opposite ways round the new sheet.
    pub fn add_sheet(&mut self, pieces: &[Piece]) -> Result<AddedSheet> {
        let runs = self.picked_runs(pieces)?;
        if runs.len() < 2 {
            return self.add_sheet_on(&runs);
        }
        // On two runs or more the new sheet continues the side along each picked edge,
        // so those sides must face one way round it: picked the other way round (one
        // edge's other side, or run against the others), the sheet would twist
        // through itself, a one-sided surface no solid bounds.
        let before = self.clone();
        let added = self.add_sheet_on(&runs)?;
        if self.check().is_err() {
            *self = before;
            return Err(TopologyError::NotApplicable(
                "the picked edges face opposite ways round the new sheet: it would twist \
                 through itself"
                    .into(),
            ));
        }
        Ok(added)
    }

    /// [`Sheet::add_sheet`] on its checked runs.
    fn add_sheet_on(&mut self, runs: &[PickedRun]) -> Result<AddedSheet> {
        let mut b = self.brep.clone();
        let mut made = Made::default();
        // Skze: one open loop per picked run.
        for run in runs {
            for &z in &run.inner_zero {
                b.lkef(z)?;
                made.killed_edges.push(z);
            }
        }
        // The curves of each run of them, from the end of one picked run to the start
        // of the next.
        let sides: Vec<bool> = self
            .faces
            .iter()
            .map(|r| matches!(r, Some(FaceRole::Side { .. })))
            .collect();
        let n = runs.len();
        for j in 0..n {
            let next = &runs[(j + 1) % n];
            let mut at = runs[j].last;
            for _ in 1..runs[j].curves_after {
                let open = across_from(&b, &sides, runs[j].edges[0].0)?;
                at = smev(&mut b, open, at, &mut made)?;
            }
            let face_at = across_from(&b, &sides, runs[j].edges[0].0)?;
            let face_to = across_from(&b, &sides, next.edges[0].0)?;
            if face_at == face_to {
                smel(&mut b, &sides, runs[j].edges[0], at, next.first, &mut made)?;
            } else {
                smep(&mut b, (face_at, face_to), at, next.first, &mut made)?;
            }
        }
        // The new sheet's sides lie across the picked edges from the sheets picked;
        // every other face made is a thickness face.
        let picked: Vec<(EdgeId, EdgeId)> = runs.iter().flat_map(|r| r.edges.clone()).collect();
        let (edge, edge_twin) = picked[0];
        let (side, twin) = (
            across_from(&b, &sides, edge)?,
            across_from(&b, &sides, edge_twin)?,
        );
        self.brep = b;
        self.sync_tables();
        for &e in &made.killed_edges {
            self.edges[e.index()] = None;
        }
        for f in self.brep.faces().collect::<Vec<_>>() {
            if self.faces[f.index()].is_none() || runs.iter().any(|r| r.open.contains(&f)) {
                self.faces[f.index()] = Some(FaceRole::Thickness);
            }
        }
        for &f in &made.thickness_gone {
            self.faces[f.index()] = None;
        }
        self.faces[side.index()] = Some(FaceRole::Side { twin });
        self.faces[twin.index()] = Some(FaceRole::Side { twin: side });
        for &(c, c2) in &made.curves {
            self.edges[c.index()] = Some(EdgeRole::Side { twin: c2 });
            self.edges[c2.index()] = Some(EdgeRole::Side { twin: c });
        }
        for &z in &made.zero {
            self.edges[z.index()] = Some(EdgeRole::ZeroLength);
        }
        for &(v, w) in &made.vertices {
            self.vertex_twins[v.index()] = Some(w);
            self.vertex_twins[w.index()] = Some(v);
        }
        // Faces the merges killed (open loops taken into others) have no role.
        for f in 0..self.faces.len() {
            if self.brep.faces.get(f).and_then(Option::as_ref).is_none() {
                self.faces[f] = None;
            }
        }
        Ok(AddedSheet {
            sides: (side, twin),
            curves: made.curves.iter().map(|&(c, _)| c).collect(),
        })
    }

    /// The picked runs of `pieces`, checked: each a path along free side edges, the
    /// runs separated by one or more curves, every edge's thickness face its own.
    fn picked_runs(&self, pieces: &[Piece]) -> Result<Vec<PickedRun>> {
        let bad = |why: String| Err(TopologyError::NotApplicable(why));
        let b = &self.brep;
        let mut runs: Vec<PickedRun> = Vec::new();
        let mut seen: BTreeSet<VertexId> = BTreeSet::new();
        for (i, piece) in pieces.iter().enumerate() {
            let Piece::Picked(path) = piece else {
                continue;
            };
            let Some(Piece::Curves(curves)) = pieces.get((i + 1) % pieces.len()) else {
                return bad("each run of picked edges must be followed by boundary curves".into());
            };
            if *curves == 0 || path.len() < 2 {
                return bad("a picked run needs two vertices or more, and curves after it".into());
            }
            // A run is a path: it meets no vertex twice, its own or another run's (a run
            // back to its start would close the new sheet's boundary on itself).
            if !path.iter().all(|&v| seen.insert(v)) {
                return bad("a picked run meets a vertex twice: it is not a path".into());
            }
            let mut edges = Vec::new();
            let mut open = Vec::new();
            let mut inner_zero = Vec::new();
            for (k, w) in path.windows(2).enumerate() {
                let e = b
                    .edges_at(w[0])?
                    .into_iter()
                    .find(|&e| {
                        let ends = b.halves_of(e).and_then(|(p, m)| Ok((b.vertex(p)?, b.vertex(m)?)));
                        matches!(ends, Ok((x, y)) if (x, y) == (w[0], w[1]) || (y, x) == (w[0], w[1]))
                    })
                    .ok_or_else(|| {
                        TopologyError::NotApplicable(format!(
                            "vertices {} and {} are not joined by an edge",
                            w[0].0, w[1].0
                        ))
                    })?;
                let EdgeRole::Side { twin } = self.edge_role(e)? else {
                    return bad(format!("edge {} is a zero-length edge", e.0));
                };
                let (p, m) = b.halves_of(e)?;
                let thickness = [p, m]
                    .into_iter()
                    .map(|h| b.face_with(b.loop_with(h)?))
                    .collect::<Result<Vec<_>>>()?
                    .into_iter()
                    .find(|&f| self.face_role(f).ok() == Some(FaceRole::Thickness))
                    .ok_or_else(|| {
                        TopologyError::NotApplicable(format!(
                            "edge {} is not free: sheets meet there",
                            e.0
                        ))
                    })?;
                if runs.iter().any(|r| r.open.contains(&thickness)) || open.contains(&thickness) {
                    return bad(format!("edge {} is picked twice", e.0));
                }
                if k > 0 {
                    // Skze's edge: the zero-length edge at the vertex between this picked
                    // edge and the last, on both their thickness faces.
                    let last: FaceId = open[open.len() - 1];
                    let z = b
                        .edges_at(w[0])?
                        .into_iter()
                        .find(|&z| {
                            self.edge_role(z).ok() == Some(EdgeRole::ZeroLength)
                                && b.halves_of(z).is_ok_and(|(p, m)| {
                                    let faces: Vec<FaceId> = [p, m]
                                        .into_iter()
                                        .filter_map(|h| b.face_with(b.loop_with(h).ok()?).ok())
                                        .collect();
                                    faces.contains(&last) && faces.contains(&thickness)
                                })
                        })
                        .ok_or_else(|| {
                            TopologyError::NotApplicable(format!(
                                "the picked edges at vertex {} are not neighbours on one free rim",
                                w[0].0
                            ))
                        })?;
                    inner_zero.push(z);
                }
                edges.push((e, twin));
                open.push(thickness);
            }
            let ends =
                |v: VertexId| -> Result<(VertexId, VertexId)> { Ok((v, self.twin_vertex(v)?)) };
            runs.push(PickedRun {
                first: ends(path[0])?,
                last: ends(path[path.len() - 1])?,
                edges,
                open,
                inner_zero,
                curves_after: *curves,
            });
        }
        if runs.is_empty() {
            return bad("a new sheet needs a picked edge".into());
        }
        if pieces
            .iter()
            .filter(|p| matches!(p, Piece::Curves(_)))
            .count()
            != runs.len()
        {
            return bad("picked runs and runs of curves must alternate".into());
        }
        Ok(runs)
    }

    /// Separates a side by a new edge between two vertices of its outer loop (paper
    /// 003, section 4.3, Fig. 10: new edges on a sheet), and its twin by the twin edge
    /// between their twins: each side splits in two, the new faces twins of each other.
    /// Returns the new edge and the new face on `side`'s sheet side. Nothing changes
    /// when the vertices are not two of the side's outer loop, or are neighbours
    /// along it.
    pub fn split(&mut self, side: FaceId, v1: VertexId, v2: VertexId) -> Result<(EdgeId, FaceId)> {
        let FaceRole::Side { twin } = self.face_role(side)? else {
            return Err(TopologyError::NotApplicable(
                "only a side is split, not a thickness face".into(),
            ));
        };
        if self.brep.loops_of(side)?.len() > 1 {
            // Which part keeps each hole is a question of where it lies: it waits for the
            // sheet's geometry.
            return Err(TopologyError::NotApplicable(
                "a side with holes is not split yet".into(),
            ));
        }
        let mut b = self.brep.clone();
        let cut = |b: &mut Brep, f: FaceId, a: VertexId, c: VertexId| -> Result<(EdgeId, FaceId)> {
            let outer = b.loop_halves(b.loops_of(f)?[0])?;
            let find = |v: VertexId| -> Result<HalfEdgeId> {
                outer
                    .iter()
                    .copied()
                    .find(|&h| b.vertex(h).ok() == Some(v))
                    .ok_or_else(|| {
                        TopologyError::NotApplicable(format!(
                            "vertex {} is not on the outer boundary of face {}",
                            v.0, f.0
                        ))
                    })
            };
            let (ha, hc) = (find(a)?, find(c)?);
            if a == c || b.next(ha)? == hc || b.next(hc)? == ha {
                return Err(TopologyError::NotApplicable(
                    "a split joins two vertices that are not neighbours".into(),
                ));
            }
            b.lmef(ha, hc)
        };
        let (e, f) = cut(&mut b, side, v1, v2)?;
        let (w1, w2) = (self.twin_vertex(v1)?, self.twin_vertex(v2)?);
        let (e2, f2) = cut(&mut b, twin, w2, w1)?;
        self.brep = b;
        self.sync_tables();
        // Whichever part each cut made new, the two new faces hold the twin edge pair
        // and lie on the same side of it: pair each new face with the twin face that
        // holds the twins of its vertices.
        let twin_of = |s: &Sheet, f: FaceId, candidates: [FaceId; 2]| -> Result<FaceId> {
            let vs: Vec<VertexId> = s
                .brep
                .loop_halves(s.brep.loops_of(f)?[0])?
                .into_iter()
                .map(|h| s.brep.vertex(h))
                .collect::<Result<_>>()?;
            for c in candidates {
                let cs: Vec<VertexId> = s
                    .brep
                    .loop_halves(s.brep.loops_of(c)?[0])?
                    .into_iter()
                    .map(|h| s.brep.vertex(h))
                    .collect::<Result<_>>()?;
                let all = vs
                    .iter()
                    .all(|&v| s.vertex_twins[v.index()].is_some_and(|w| cs.contains(&w)));
                if all {
                    return Ok(c);
                }
            }
            Err(lost("the twin of a split side"))
        };
        let (pf, pside) = (
            twin_of(self, f, [f2, twin])?,
            twin_of(self, side, [f2, twin])?,
        );
        self.faces[f.index()] = Some(FaceRole::Side { twin: pf });
        self.faces[pf.index()] = Some(FaceRole::Side { twin: f });
        self.faces[side.index()] = Some(FaceRole::Side { twin: pside });
        self.faces[pside.index()] = Some(FaceRole::Side { twin: side });
        self.edges[e.index()] = Some(EdgeRole::Side { twin: e2 });
        self.edges[e2.index()] = Some(EdgeRole::Side { twin: e });
        Ok((e, f))
    }

    /// Separates an `n`-sided region inside a side, its first corner bridged from `at`
    /// (a vertex of the side's outer loop), and the twin region inside the twin side
    /// (paper 003, section 4.3, Fig. 10: a loop on a sheet): the side gets a ring and
    /// the region is a new side, twin of the region on the other side. The region is
    /// what [`Sheet::lift`] raises. Nothing changes when an argument is wrong.
    pub fn region(&mut self, side: FaceId, at: VertexId, n: usize) -> Result<Region> {
        if n < 3 {
            return Err(TopologyError::NotApplicable(format!(
                "a region needs 3 corners or more, not {n}"
            )));
        }
        let FaceRole::Side { twin } = self.face_role(side)? else {
            return Err(TopologyError::NotApplicable(
                "a region is drawn on a side, not a thickness face".into(),
            ));
        };
        let start = Self::on_outer(&self.brep, side, at)?;
        let start_twin = Self::on_outer(&self.brep, twin, self.twin_vertex(at)?)?;
        let mut b = self.brep.clone();
        let (corners, edges, cap) = Self::ring_in(&mut b, start, n)?;
        let (ring, ring_edges, cap_twin) = Self::ring_in(&mut b, start_twin, n)?;
        self.brep = b;
        self.sync_tables();
        // As for a hole, the twin side's ring runs the other way round.
        for k in 0..n {
            let (v, w) = (corners[k], ring[(n - k) % n]);
            self.vertex_twins[v.index()] = Some(w);
            self.vertex_twins[w.index()] = Some(v);
            let (e, f) = (edges[k], ring_edges[n - 1 - k]);
            self.edges[e.index()] = Some(EdgeRole::Side { twin: f });
            self.edges[f.index()] = Some(EdgeRole::Side { twin: e });
        }
        self.faces[cap.index()] = Some(FaceRole::Side { twin: cap_twin });
        self.faces[cap_twin.index()] = Some(FaceRole::Side { twin: cap });
        Ok(Region {
            face: cap,
            twin: cap_twin,
        })
    }

    /// Lifts (or pushes down: the topology is the same) a region of the sheet, a side
    /// bounded by its outer loop only (paper 003, section 4.5): on both sides the
    /// region's loop is swept, so a band of wall faces joins the region to the sheet
    /// round it; the walls are sides, twins across the sheet like the edges they rise
    /// from. Returns the walls on `region`'s side. Nothing changes when `region` is
    /// not a side without holes.
    pub fn lift(&mut self, region: FaceId) -> Result<Vec<FaceId>> {
        let FaceRole::Side { twin } = self.face_role(region)? else {
            return Err(TopologyError::NotApplicable(
                "a region to lift is a side, not a thickness face".into(),
            ));
        };
        if self.brep.loops_of(region)?.len() > 1 {
            return Err(TopologyError::NotApplicable(
                "a region with holes is not lifted yet".into(),
            ));
        }
        let mut b = self.brep.clone();
        let (l, lt) = (b.loops_of(region)?[0], b.loops_of(twin)?[0]);
        let up = sweep(&mut b, l)?;
        let down = sweep(&mut b, lt)?;
        let (up_edges, down_edges) = (up.base_edges(&b)?, down.base_edges(&b)?);
        let mut faces = Vec::new();
        let mut edges = Vec::new();
        let mut twins = Vec::new();
        for (k, &edge) in up_edges.iter().enumerate() {
            // The twin of base vertex k, and of loop edge k, on the other side.
            let tv = self.twin_vertex(up.base[k])?;
            let j = down
                .base
                .iter()
                .position(|&v| v == tv)
                .ok_or_else(|| lost("a twin corner of the region"))?;
            let EdgeRole::Side { twin: te } = self.edge_role(edge)? else {
                return Err(lost("a side edge of the region"));
            };
            let i = down_edges
                .iter()
                .position(|&e| e == te)
                .ok_or_else(|| lost("a twin edge of the region"))?;
            twins.push((up.tops[k], down.tops[j]));
            edges.push((up.up[k], down.up[j]));
            edges.push((up.cap_edges[k], down.cap_edges[i]));
            faces.push((up.sides[k], down.sides[i]));
        }
        self.brep = b;
        self.sync_tables();
        for (v, w) in twins {
            self.vertex_twins[v.index()] = Some(w);
            self.vertex_twins[w.index()] = Some(v);
        }
        for (e, f) in edges {
            self.edges[e.index()] = Some(EdgeRole::Side { twin: f });
            self.edges[f.index()] = Some(EdgeRole::Side { twin: e });
        }
        for &(f, g) in &faces {
            self.faces[f.index()] = Some(FaceRole::Side { twin: g });
            self.faces[g.index()] = Some(FaceRole::Side { twin: f });
        }
        Ok(faces.into_iter().map(|(f, _)| f).collect())
    }

    /// The half-edge of face `f`'s outer loop that leaves vertex `v`.
    fn on_outer(b: &Brep, f: FaceId, v: VertexId) -> Result<HalfEdgeId> {
        b.loop_halves(b.loops_of(f)?[0])?
            .into_iter()
            .find(|&h| b.vertex(h).ok() == Some(v))
            .ok_or_else(|| {
                TopologyError::NotApplicable(format!(
                    "vertex {} is not on the outer boundary of face {}",
                    v.0, f.0
                ))
            })
    }

    /// In the face of `start` (a half-edge of its outer loop, leaving vertex v): a
    /// bridge edge from v to a new vertex, a chain of `n - 1` more edges from there,
    /// closed into an `n`-gon face (the cap), and the bridge killed so the `n`-gon's
    /// boundary is a ring of the face. Returns the ring's vertices in order, its edges
    /// (edge k from corner k to corner k + 1) and the cap.
    fn ring_in(
        b: &mut Brep,
        start: HalfEdgeId,
        n: usize,
    ) -> Result<(Vec<VertexId>, Vec<EdgeId>, FaceId)> {
        let v = b.vertex(start)?;
        let (bridge, w1) = b.lmev(start, start)?;
        let mut corners = vec![w1];
        let mut edges = Vec::with_capacity(n);
        let mut tip = b.prev(start)?;
        for _ in 1..n {
            let (e, w) = b.lmev(tip, tip)?;
            corners.push(w);
            edges.push(e);
            tip = b.prev(tip)?;
        }
        let first = Self::half_leaving(b, edges[0], w1)?;
        let (closing, cap) = b.lmef(first, tip)?;
        edges.push(closing);
        b.lkemr(Self::half_leaving(b, bridge, v)?)?;
        Ok((corners, edges, cap))
    }

    /// Grows the role tables to the topology's tables.
    fn sync_tables(&mut self) {
        self.faces.resize(self.brep.faces.len(), None);
        self.edges.resize(self.brep.edges.len(), None);
        self.vertex_twins.resize(self.brep.vertices.len(), None);
    }

    /// The role of face `f`.
    pub fn face_role(&self, f: FaceId) -> Result<FaceRole> {
        self.faces
            .get(f.index())
            .copied()
            .flatten()
            .ok_or_else(|| TopologyError::Dead(format!("face {}", f.0)))
    }

    /// The role of edge `e`.
    pub fn edge_role(&self, e: EdgeId) -> Result<EdgeRole> {
        self.edges
            .get(e.index())
            .copied()
            .flatten()
            .ok_or_else(|| TopologyError::Dead(format!("edge {}", e.0)))
    }

    /// The twin of vertex `v`.
    pub fn twin_vertex(&self, v: VertexId) -> Result<VertexId> {
        self.vertex_twins
            .get(v.index())
            .copied()
            .flatten()
            .ok_or_else(|| TopologyError::Dead(format!("vertex {}", v.0)))
    }

    /// Checks the topology ([`Brep::check`]) and the sheet's twins: every live face,
    /// edge and vertex has a role; twins are mutual and distinct; a zero-length edge
    /// joins a vertex to its twin; twin edges join twin vertices; a side face's twin is
    /// a side face whose outer loop runs through the twins of its vertices, with as many
    /// rings; a thickness face's outer loop holds zero-length edges and side edges only,
    /// at least one of each, and no rings.
    pub fn check(&self) -> Result<Counts> {
        let counts = self.brep.check()?;
        let bad = |why: String| Err(TopologyError::Invalid(why));
        let b = &self.brep;
        let ends = |e: EdgeId| -> Result<(VertexId, VertexId)> {
            let (p, m) = b.halves_of(e)?;
            Ok((b.vertex(p)?, b.vertex(m)?))
        };
        for v in b.vertices() {
            let w = self.twin_vertex(v)?;
            if w == v || self.twin_vertex(w)? != v {
                return bad(format!("vertex {}: twins not mutual", v.0));
            }
        }
        for e in b.edges() {
            let (x, y) = ends(e)?;
            match self.edge_role(e)? {
                EdgeRole::ZeroLength => {
                    if self.twin_vertex(x)? != y {
                        return bad(format!("edge {}: zero-length but not between twins", e.0));
                    }
                }
                EdgeRole::Side { twin } => {
                    if twin == e || self.edge_role(twin)? != (EdgeRole::Side { twin: e }) {
                        return bad(format!("edge {}: twins not mutual", e.0));
                    }
                    let (tx, ty) = ends(twin)?;
                    let (wx, wy) = (self.twin_vertex(x)?, self.twin_vertex(y)?);
                    if !((tx == wx && ty == wy) || (tx == wy && ty == wx)) {
                        return bad(format!("edge {}: its twin joins other vertices", e.0));
                    }
                }
            }
        }
        for f in b.faces() {
            match self.face_role(f)? {
                FaceRole::Side { twin } => {
                    if twin == f || self.face_role(twin)? != (FaceRole::Side { twin: f }) {
                        return bad(format!("face {}: twins not mutual", f.0));
                    }
                    // The two sides of one region: their outer loops run through twin
                    // vertices, and they have as many holes.
                    let vertices_of = |l: LoopId| -> Result<BTreeSet<VertexId>> {
                        b.loop_halves(l)?.into_iter().map(|h| b.vertex(h)).collect()
                    };
                    let (mine, theirs) = (b.loops_of(f)?, b.loops_of(twin)?);
                    let twins: BTreeSet<VertexId> = vertices_of(mine[0])?
                        .into_iter()
                        .map(|v| self.twin_vertex(v))
                        .collect::<Result<_>>()?;
                    if twins != vertices_of(theirs[0])? || mine.len() != theirs.len() {
                        return bad(format!("face {}: its twin bounds another region", f.0));
                    }
                }
                FaceRole::Thickness => {
                    let loops = b.loops_of(f)?;
                    if loops.len() != 1 {
                        return bad(format!("face {}: a thickness face with rings", f.0));
                    }
                    let (mut zero, mut side) = (0, 0);
                    for h in b.loop_halves(loops[0])? {
                        let e = b.edge(h)?.ok_or_else(|| {
                            TopologyError::Invalid(format!("face {}: a lone vertex", f.0))
                        })?;
                        match self.edge_role(e)? {
                            EdgeRole::ZeroLength => zero += 1,
                            EdgeRole::Side { .. } => side += 1,
                        }
                    }
                    if zero == 0 || side == 0 {
                        return bad(format!(
                            "face {}: a zero-area loop needs side and zero-length edges",
                            f.0
                        ));
                    }
                }
            }
        }
        Ok(counts)
    }
}

/// What [`Sheet::remove`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Removal {
    /// The region lay inside the sheet: a passage was made where it was.
    Passage(Hole),
    /// The region lay on the sheet's free boundary.
    Trimmed {
        /// The thickness faces now lining the rim where the region joined other sides.
        lining: Vec<FaceId>,
        /// Passages (through holes) closed: the genus fell by this much.
        passages_closed: usize,
        /// Pieces the sheet fell apart into beyond the one it was.
        pieces_made: usize,
    },
}

/// What [`Sheet::punch`] made.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Hole {
    /// The hole's corners on the punched side, in order round it.
    pub corners: Vec<VertexId>,
    /// Their twins on the other side.
    pub twin_corners: Vec<VertexId>,
    /// The thickness faces lining the hole, one per hole edge.
    pub lining: Vec<FaceId>,
}

/// An element an operator made and then could not find: a bug in the operator.
fn lost(what: &str) -> TopologyError {
    TopologyError::Invalid(format!("{what} went missing"))
}

/// What [`Sheet::flange`] made.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Flange {
    /// The flange's sides (twins of each other).
    pub sides: Vec<FaceId>,
    /// Its far edge, opposite the flanged one (on the side of the flanged edge).
    pub far_edge: EdgeId,
    /// The far edge's ends, each with the vertex of the flanged edge it was swept from:
    /// `(base, far)`.
    pub far_ends: [(VertexId, VertexId); 2],
}

/// What [`Sheet::region`] made: the region on the side it was drawn on, and its twin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    /// The region on the side it was drawn on.
    pub face: FaceId,
    /// The region on the other side.
    pub twin: FaceId,
}
