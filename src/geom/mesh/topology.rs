//! Half-edge connectivity of a [`Mesh`], non-manifold edges included.
//!
//! Every face side is a [`HalfEdge`] directed along the face's winding. Half-edges that
//! join the same two vertices (in either direction) share one undirected edge, which
//! keeps them all in its *radial list*. A classic half-edge structure stores a single
//! twin per half-edge and so cannot represent an edge shared by three sheets; the radial
//! list can, and [`Topology::twin`] is simply the other half-edge when the list has
//! exactly two. All tables are flat arrays (compressed rows), built once in
//! `O(n log n)`, and ordered by id, so every query answers in a deterministic order.
//!
//! The topology holds no positions: it stays valid while vertices move (fairing,
//! rounding) as long as the faces do not change. Geometric queries such as
//! [`Topology::dihedral_angle`] take the mesh as an argument.

use super::ids::to_u32;
use super::{EdgeId, FaceId, HalfEdgeId, Mesh, VertexId};
use crate::geom::union_find::UnionFind;
use glam::DVec3;

/// One side of one face, directed along the face's winding.
///
/// The fields are the classic half-edge links; a half-edge of face `f` with `next`
/// and `prev` cycles through the face's sides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HalfEdge {
    /// The vertex the half-edge starts at. It ends at `origin` of `next`.
    pub origin: VertexId,
    /// The following side of the same face.
    pub next: HalfEdgeId,
    /// The preceding side of the same face.
    pub prev: HalfEdgeId,
    /// The face this half-edge bounds.
    pub face: FaceId,
    /// The undirected edge this half-edge lies on.
    pub edge: EdgeId,
}

/// Items grouped by a dense key (vertex or edge), stored as one array plus offsets
/// ("compressed rows"): cheap to build, cache friendly, deterministic.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Rows<T> {
    /// Row `i` is `items[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<usize>,
    items: Vec<T>,
}

impl<T: Copy> Rows<T> {
    /// Groups the `count` items that `each` emits as `(row, item)` into `rows` rows,
    /// keeping their order within a row. `each` is called twice (a counting sort: the
    /// rows' sizes, then each item in its slot), so no list of pairs is held. Every
    /// `row` must be below `rows`, and both calls must emit the same pairs.
    fn grouped(rows: usize, count: usize, each: impl Fn(&mut dyn FnMut(usize, T))) -> Rows<T> {
        let mut offsets = vec![0usize; rows + 1];
        each(&mut |row, _| offsets[row + 1] += 1);
        for i in 0..rows {
            offsets[i + 1] += offsets[i];
        }
        let mut next_slot = offsets.clone();
        let mut items: Vec<Option<T>> = vec![None; count];
        each(&mut |row, item| {
            items[next_slot[row]] = Some(item);
            next_slot[row] += 1;
        });
        Rows {
            offsets,
            // Every slot is filled: the second pass emits exactly the counted pairs.
            items: items.into_iter().flatten().collect(),
        }
    }

    /// Row `i`; empty if `i` is out of range.
    fn row(&self, i: usize) -> &[T] {
        match (self.offsets.get(i), self.offsets.get(i + 1)) {
            (Some(&start), Some(&end)) => &self.items[start..end],
            _ => &[],
        }
    }
}

/// The connectivity of a [`Mesh`]: half-edges, undirected edges with radial lists, and
/// vertex stars. Build it with [`Topology::build`] or [`Mesh::topology`].
///
/// Id contract: [`HalfEdgeId`]s and [`EdgeId`]s come only from this topology. The
/// link accessors ([`Topology::next`], [`Topology::origin`], …) index directly and
/// panic on an id from another topology, like slice indexing; use
/// [`Topology::half_edge`] for a checked lookup. Queries by [`VertexId`] or [`FaceId`]
/// never panic: an out-of-range id has no neighbours.
#[derive(Debug, Clone, PartialEq)]
pub struct Topology {
    vertex_count: usize,
    half_edges: Vec<HalfEdge>,
    /// Face `f`'s half-edges are `face_start[f]..face_start[f + 1]`.
    face_start: Vec<u32>,
    /// Per edge, its vertices with the smaller id first.
    edge_vertices: Vec<[VertexId; 2]>,
    /// Per edge, its half-edges in id order (the radial list).
    edge_half_edges: Rows<HalfEdgeId>,
    /// Per vertex, the half-edges starting there, in id order.
    vertex_half_edges: Rows<HalfEdgeId>,
    /// Per vertex, the faces using it, in id order.
    vertex_faces: Rows<FaceId>,
    /// Per vertex, the edges touching it, in id order.
    vertex_edges: Rows<EdgeId>,
}

impl Topology {
    /// Builds the connectivity of `mesh`. Never fails: [`Mesh::new`] has already
    /// rejected out-of-range indices, repeated corners and oversized meshes, and every
    /// other configuration (non-manifold edges, bowtie vertices, inconsistent winding,
    /// isolated vertices, duplicate faces) is represented as it is.
    pub fn build(mesh: &Mesh) -> Topology {
        let vertex_count = mesh.vertex_count();
        let (half_edges, face_start) = link_faces(mesh);
        let (edge_vertices, edge_half_edges, half_edges) = collect_edges(vertex_count, half_edges);

        // A face uses a vertex once, so the half-edges leaving a vertex name each of its
        // faces once, in the same (id) order: the two stars share their rows.
        let vertex_half_edges = Rows::grouped(vertex_count, half_edges.len(), |emit| {
            for (h, he) in half_edges.iter().enumerate() {
                emit(he.origin.index(), HalfEdgeId(to_u32(h)));
            }
        });
        let vertex_faces = Rows {
            offsets: vertex_half_edges.offsets.clone(),
            items: vertex_half_edges
                .items
                .iter()
                .map(|&h| half_edges[h.index()].face)
                .collect(),
        };
        let vertex_edges = Rows::grouped(vertex_count, 2 * edge_vertices.len(), |emit| {
            for (e, [a, b]) in edge_vertices.iter().enumerate() {
                emit(a.index(), EdgeId(to_u32(e)));
                emit(b.index(), EdgeId(to_u32(e)));
            }
        });
        Topology {
            vertex_count,
            half_edges,
            face_start,
            edge_vertices,
            edge_half_edges,
            vertex_half_edges,
            vertex_faces,
            vertex_edges,
        }
    }

    /// Number of vertices of the mesh it was built from (used or not).
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_start.len().saturating_sub(1)
    }

    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        self.edge_vertices.len()
    }

    /// Number of half-edges: the sum of the face sizes.
    pub fn half_edge_count(&self) -> usize {
        self.half_edges.len()
    }

    /// All half-edge ids, in order (face by face, each in winding order).
    pub fn half_edges(&self) -> impl Iterator<Item = HalfEdgeId> {
        (0..to_u32(self.half_edges.len())).map(HalfEdgeId)
    }

    /// All edge ids, in order (sorted by their vertex pair).
    pub fn edges(&self) -> impl Iterator<Item = EdgeId> {
        (0..to_u32(self.edge_vertices.len())).map(EdgeId)
    }

    /// The half-edge record `h`, or `None` for an id not from this topology.
    pub fn half_edge(&self, h: HalfEdgeId) -> Option<&HalfEdge> {
        self.half_edges.get(h.index())
    }

    /// The vertex `h` starts at.
    pub fn origin(&self, h: HalfEdgeId) -> VertexId {
        self.half_edges[h.index()].origin
    }

    /// The vertex `h` ends at (the origin of its `next`).
    pub fn destination(&self, h: HalfEdgeId) -> VertexId {
        self.origin(self.next(h))
    }

    /// The following half-edge of the same face.
    pub fn next(&self, h: HalfEdgeId) -> HalfEdgeId {
        self.half_edges[h.index()].next
    }

    /// The preceding half-edge of the same face.
    pub fn prev(&self, h: HalfEdgeId) -> HalfEdgeId {
        self.half_edges[h.index()].prev
    }

    /// The face `h` bounds.
    pub fn face(&self, h: HalfEdgeId) -> FaceId {
        self.half_edges[h.index()].face
    }

    /// The undirected edge `h` lies on.
    pub fn edge(&self, h: HalfEdgeId) -> EdgeId {
        self.half_edges[h.index()].edge
    }

    /// The other half-edge on `h`'s edge, if that edge has exactly two (a manifold
    /// edge). `None` on a free edge or a non-manifold edge (see
    /// [`Topology::edge_half_edges`] for those). The twin runs opposite to `h` when
    /// the two faces are consistently oriented; it is returned either way.
    pub fn twin(&self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        match *self.edge_half_edges(self.half_edge(h)?.edge) {
            [a, b] if a == h => Some(b),
            [a, b] if b == h => Some(a),
            _ => None,
        }
    }

    /// The two vertices of edge `e`, smaller id first.
    pub fn edge_vertices(&self, e: EdgeId) -> [VertexId; 2] {
        self.edge_vertices[e.index()]
    }

    /// The half-edges on edge `e` in id order: its radial list. One for a free edge,
    /// two for a manifold edge, three or more where sheets meet.
    pub fn edge_half_edges(&self, e: EdgeId) -> &[HalfEdgeId] {
        self.edge_half_edges.row(e.index())
    }

    /// The faces on edge `e`, in id order (a face appears once per side it has on the
    /// edge, which for valid faces is once).
    pub fn edge_faces(&self, e: EdgeId) -> impl Iterator<Item = FaceId> + '_ {
        self.edge_half_edges(e).iter().map(|&h| self.face(h))
    }

    /// How many faces share edge `e`.
    pub fn edge_face_count(&self, e: EdgeId) -> usize {
        self.edge_half_edges(e).len()
    }

    /// Whether `e` is a free (boundary) edge: exactly one face uses it.
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        self.edge_face_count(e) == 1
    }

    /// Whether `e` is a manifold edge: exactly two faces share it.
    pub fn is_manifold_edge(&self, e: EdgeId) -> bool {
        self.edge_face_count(e) == 2
    }

    /// Whether three or more faces share `e` (sheets meeting along an edge).
    pub fn is_non_manifold_edge(&self, e: EdgeId) -> bool {
        self.edge_face_count(e) >= 3
    }

    /// The edge joining `a` and `b` (in either direction), if there is one.
    pub fn find_edge(&self, a: VertexId, b: VertexId) -> Option<EdgeId> {
        let key = [a.min(b), a.max(b)];
        self.edge_vertices
            .binary_search(&key)
            .ok()
            .map(|e| EdgeId(to_u32(e)))
    }

    /// The first half-edge (lowest id) running from `from` to `to`, if any.
    pub fn find_half_edge(&self, from: VertexId, to: VertexId) -> Option<HalfEdgeId> {
        self.vertex_half_edges(from)
            .iter()
            .copied()
            .find(|&h| self.destination(h) == to)
    }

    /// The half-edges of face `f` in winding order (empty if `f` is out of range).
    pub fn face_half_edges(&self, f: FaceId) -> impl Iterator<Item = HalfEdgeId> {
        let range = match (
            self.face_start.get(f.index()),
            self.face_start.get(f.index() + 1),
        ) {
            (Some(&start), Some(&end)) => start..end,
            _ => 0..0,
        };
        range.map(HalfEdgeId)
    }

    /// The faces sharing an edge with face `f` (across manifold and non-manifold
    /// edges), sorted and without duplicates; `f` itself is excluded.
    pub fn face_neighbors(&self, f: FaceId) -> Vec<FaceId> {
        let mut out: Vec<FaceId> = self
            .face_half_edges(f)
            .flat_map(|h| self.edge_faces(self.edge(h)))
            .filter(|&g| g != f)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The half-edges starting at `v`, in id order.
    pub fn vertex_half_edges(&self, v: VertexId) -> &[HalfEdgeId] {
        self.vertex_half_edges.row(v.index())
    }

    /// The faces using `v`, in id order.
    pub fn vertex_faces(&self, v: VertexId) -> &[FaceId] {
        self.vertex_faces.row(v.index())
    }

    /// The edges touching `v`, in id order.
    pub fn vertex_edges(&self, v: VertexId) -> &[EdgeId] {
        self.vertex_edges.row(v.index())
    }

    /// The one-ring of `v`: the vertices sharing an edge with it, sorted ascending.
    /// (Diagonal corners of a quad are not neighbours.)
    pub fn vertex_neighbors(&self, v: VertexId) -> Vec<VertexId> {
        // Edges are sorted by vertex pair, so the other ends come out nearly sorted.
        let mut out: Vec<VertexId> = self
            .vertex_edges(v)
            .iter()
            .map(|&e| {
                let [a, b] = self.edge_vertices(e);
                if a == v {
                    b
                } else {
                    a
                }
            })
            .collect();
        out.sort_unstable();
        out
    }

    /// Whether `v` lies on a free edge.
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        self.vertex_edges(v)
            .iter()
            .any(|&e| self.is_boundary_edge(e))
    }

    /// All free (boundary) edges, in id order.
    pub fn free_edges(&self) -> Vec<EdgeId> {
        self.edges().filter(|&e| self.is_boundary_edge(e)).collect()
    }

    /// All edges shared by three or more faces, in id order.
    pub fn non_manifold_edges(&self) -> Vec<EdgeId> {
        self.edges()
            .filter(|&e| self.is_non_manifold_edge(e))
            .collect()
    }

    /// Whether the mesh has no free edges (every edge has two or more faces).
    pub fn is_closed(&self) -> bool {
        self.edges().all(|e| !self.is_boundary_edge(e))
    }

    /// The manifold edges whose two half-edges run the same way, i.e. whose faces
    /// disagree on orientation, in id order.
    pub fn inconsistent_edges(&self) -> Vec<EdgeId> {
        self.edges()
            .filter(|&e| match *self.edge_half_edges(e) {
                [a, b] => self.origin(a) == self.origin(b),
                _ => false,
            })
            .collect()
    }

    /// Whether the two half-edges of every manifold edge run opposite, so all faces
    /// agree on which side is "up". Free and non-manifold edges are not judged.
    pub fn is_consistently_oriented(&self) -> bool {
        self.inconsistent_edges().is_empty()
    }

    /// The Euler characteristic `V - E + F`, counting only vertices used by a face
    /// (isolated points are not part of the surface). 2 for a closed sphere-like
    /// shell, 1 for a disc, 0 for an annulus or torus.
    pub fn euler_characteristic(&self) -> i64 {
        let used = (0..self.vertex_count)
            .filter(|&v| !self.vertex_faces.row(v).is_empty())
            .count();
        used as i64 - self.edge_count() as i64 + self.face_count() as i64
    }

    /// The faces grouped into connected components: faces sharing an edge (manifold
    /// or not) are connected; faces touching only at a vertex are not. Each component
    /// is sorted; components are ordered by their smallest face.
    pub fn connected_components(&self) -> Vec<Vec<FaceId>> {
        let mut sets = UnionFind::new(self.face_count());
        for e in self.edges() {
            let mut faces = self.edge_faces(e);
            let Some(first) = faces.next() else { continue };
            for other in faces {
                sets.union(first.index(), other.index());
            }
        }
        let mut component_of_root = vec![usize::MAX; self.face_count()];
        let mut components: Vec<Vec<FaceId>> = Vec::new();
        for f in 0..self.face_count() {
            let root = sets.find(f);
            if component_of_root[root] == usize::MAX {
                component_of_root[root] = components.len();
                components.push(Vec::new());
            }
            components[component_of_root[root]].push(FaceId(to_u32(f)));
        }
        components
    }

    /// The angle between the normals of the two faces on manifold edge `e`, in
    /// radians in `[0, π]`: 0 where the surface is flat across the edge, π/2 at a
    /// cube's edge. `None` on free or non-manifold edges, for degenerate (zero-area)
    /// faces, or if `mesh` is not the mesh this topology was built from. Quads use
    /// their Newell normal; triangulate first for exact per-edge angles on warped quads.
    pub fn dihedral_angle(&self, mesh: &Mesh, e: EdgeId) -> Option<f64> {
        let (n1, n2) = self.edge_face_normals(mesh, e)?;
        Some(n1.cross(n2).length().atan2(n1.dot(n2)))
    }

    /// [`Topology::dihedral_angle`] with a sign: positive where the edge is convex
    /// (the surface bends away from its normals, like a punch shoulder seen from
    /// outside), negative where it is concave (a die cavity's floor edge). `None`
    /// additionally when the two faces disagree on orientation, since "convex" then
    /// has no meaning.
    pub fn signed_dihedral_angle(&self, mesh: &Mesh, e: EdgeId) -> Option<f64> {
        let (n1, n2) = self.edge_face_normals(mesh, e)?;
        let [h, other] = *self.edge_half_edges(e) else {
            return None;
        };
        if self.origin(h) == self.origin(other) {
            return None;
        }
        let along = mesh.position(self.destination(h))? - mesh.position(self.origin(h))?;
        let angle = n1.cross(n2).length().atan2(n1.dot(n2));
        Some(if n1.cross(n2).dot(along) < 0.0 {
            -angle
        } else {
            angle
        })
    }

    /// The unit normals of the two faces on manifold edge `e`, in radial-list order.
    fn edge_face_normals(&self, mesh: &Mesh, e: EdgeId) -> Option<(DVec3, DVec3)> {
        let [a, b] = *self.edge_half_edges(e) else {
            return None;
        };
        Some((
            mesh.face_normal(self.face(a))?,
            mesh.face_normal(self.face(b))?,
        ))
    }
}

/// The half-edges of every face, linked in winding order (edges still unset), and
/// the face start offsets.
fn link_faces(mesh: &Mesh) -> (Vec<HalfEdge>, Vec<u32>) {
    let corners = mesh.faces().iter().map(|f| f.vertex_count()).sum();
    let mut half_edges = Vec::with_capacity(corners);
    let mut face_start = Vec::with_capacity(mesh.face_count() + 1);
    for (f, face) in mesh.faces().iter().enumerate() {
        let base = half_edges.len();
        face_start.push(to_u32(base));
        let n = face.vertex_count();
        for (i, origin) in face.vertices().enumerate() {
            half_edges.push(HalfEdge {
                origin,
                next: HalfEdgeId(to_u32(base + (i + 1) % n)),
                prev: HalfEdgeId(to_u32(base + (i + n - 1) % n)),
                face: FaceId(to_u32(f)),
                edge: EdgeId(0),
            });
        }
    }
    face_start.push(to_u32(half_edges.len()));
    (half_edges, face_start)
}

/// Groups the half-edges by unordered vertex pair into edges numbered in pair order,
/// sets each half-edge's `edge`, and returns the edges' vertices and radial lists.
///
/// No global sort: the half-edges are filed under the smaller vertex of their pair by
/// a counting sort (vertex order, then id order), and each vertex's few half-edges are
/// ordered by the other vertex, then id. Walking the vertices in order then meets the
/// edges in pair order and each edge's half-edges in id order: its radial list.
fn collect_edges(
    vertex_count: usize,
    mut half_edges: Vec<HalfEdge>,
) -> (Vec<[VertexId; 2]>, Rows<HalfEdgeId>, Vec<HalfEdge>) {
    let ends = |h: usize| -> (u32, u32) {
        let a = half_edges[h].origin.0;
        let b = half_edges[half_edges[h].next.index()].origin.0;
        (a.min(b), a.max(b))
    };
    let mut start = vec![0usize; vertex_count + 1];
    for h in 0..half_edges.len() {
        start[ends(h).0 as usize + 1] += 1;
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    // Each half-edge as (other vertex, id), filed under its smaller vertex.
    let mut filed: Vec<(u32, u32)> = vec![(0, 0); half_edges.len()];
    let mut slot = start.clone();
    for h in 0..half_edges.len() {
        let (low, high) = ends(h);
        filed[slot[low as usize]] = (high, to_u32(h));
        slot[low as usize] += 1;
    }
    let mut edge_vertices: Vec<[VertexId; 2]> = Vec::new();
    let mut offsets: Vec<usize> = Vec::with_capacity(half_edges.len() / 2 + 1);
    let mut items: Vec<HalfEdgeId> = Vec::with_capacity(half_edges.len());
    for low in 0..vertex_count {
        let here = &mut filed[start[low]..start[low + 1]];
        // A vertex has a handful of half-edges: an insertion sort (in the standard
        // library's small-slice path) orders them at once.
        here.sort_unstable();
        let mut last = None;
        for &(high, h) in here.iter() {
            if last != Some(high) {
                last = Some(high);
                offsets.push(items.len());
                edge_vertices.push([VertexId(to_u32(low)), VertexId(high)]);
            }
            half_edges[h as usize].edge = EdgeId(to_u32(edge_vertices.len() - 1));
            items.push(HalfEdgeId(h));
        }
    }
    offsets.push(items.len());
    (edge_vertices, Rows { offsets, items }, half_edges)
}
