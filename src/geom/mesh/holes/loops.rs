//! Free edges and the loops they close (paper 002, section 2): each loop of free
//! half-edges from the mesh's half-edge topology, its length and span, whether it is a
//! panel's outer boundary, and whether the mesh round it is sound enough to fill.
//!
//! The outer boundary is not "the longest loop": a panel may have a hole longer than a
//! narrow outer edge. In each connected piece of the mesh, projected on the plane
//! square to the piece's mean face normal, the outer boundary is the loop that
//! encloses the most other loops (the largest by projected area where none encloses
//! another), which a designer may override.

use glam::{DVec2, DVec3};

use super::plane::ProjectionPlane;
use crate::geom::mesh::{HalfEdgeId, Mesh, Topology, VertexId};
use crate::geom::trimmed::{polygon_area, polygon_winding};
use crate::geom::union_find::UnionFind;

/// A closed loop of free edges.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeLoop {
    /// Its nodes in the order its free half-edges run (the faces' winding: round a
    /// hole clockwise, seen from the side the normals face).
    pub nodes: Vec<VertexId>,
    /// Its free half-edges, `half_edges[k]` from `nodes[k]` to the next node.
    pub half_edges: Vec<HalfEdgeId>,
    /// Its length (mm).
    pub length: f64,
    /// The largest distance between two of its nodes (mm): how far across it is.
    pub span: f64,
    /// The mean of its nodes: where it is.
    pub centre: DVec3,
    /// The connected piece of the mesh it bounds (an index into
    /// [`FreeEdges::pieces`]).
    pub piece: usize,
    /// Whether it is its piece's outer boundary.
    pub outer: bool,
}

/// A mesh's free edges: how many, the closed loops they make, and the chains that do
/// not close (only where edges are not manifold or faces are wound both ways).
#[derive(Debug, Clone, PartialEq)]
pub struct FreeEdges {
    /// How many edges have one face.
    pub count: usize,
    /// The closed loops.
    pub loops: Vec<FreeLoop>,
    /// Chains of free edges that do not close, as node lists.
    pub open_chains: Vec<Vec<VertexId>>,
    /// The mesh's connected pieces (faces joined across edges).
    pub pieces: usize,
}

/// The largest distance between two of `points` (exact for up to a few thousand: the
/// loops of one mesh).
pub fn span_of(points: &[DVec3]) -> f64 {
    let mut best = 0.0f64;
    for (i, p) in points.iter().enumerate() {
        for q in &points[i + 1..] {
            best = best.max(p.distance_squared(*q));
        }
    }
    best.sqrt()
}

/// The free edges of `mesh` and their loops, each piece's outer boundary marked (the
/// loop nearest `outer`'s point instead, for the piece holding it, where given).
pub fn free_edges(mesh: &Mesh, topology: &Topology, outer: Option<DVec3>) -> FreeEdges {
    let chains = topology.boundary_loops();
    // The mesh's pieces: faces joined across edges, each piece numbered by its first
    // face, with its faces' summed vector area (its mean normal). Half-edges are
    // numbered face by face in winding order, so in a mesh of triangles alone the face
    // of half-edge h is h / 3: the radial lists are read in order and no half-edge
    // record is fetched (the pass over a 50k-triangle mesh is bound by memory).
    let triangles = topology.half_edge_count() == 3 * topology.face_count();
    let face_of = |h: HalfEdgeId| {
        if triangles {
            h.index() / 3
        } else {
            topology.face(h).index()
        }
    };
    let mut sets = UnionFind::new(mesh.face_count());
    for e in topology.edges() {
        if let [first, others @ ..] = topology.edge_half_edges(e) {
            for &other in others {
                sets.union(face_of(*first), face_of(other));
            }
        }
    }
    let mut piece_of = vec![usize::MAX; mesh.face_count()];
    let mut piece_of_root = vec![usize::MAX; mesh.face_count()];
    let mut normals: Vec<DVec3> = Vec::new();
    for f in mesh.face_ids() {
        let root = sets.find(f.index());
        if piece_of_root[root] == usize::MAX {
            piece_of_root[root] = normals.len();
            normals.push(DVec3::ZERO);
        }
        let piece = piece_of_root[root];
        piece_of[f.index()] = piece;
        normals[piece] += mesh.face_vector_area(f).unwrap_or(DVec3::ZERO);
    }
    let mut loops: Vec<FreeLoop> = chains
        .loops
        .iter()
        .map(|chain| {
            let points: Vec<DVec3> = chain
                .vertices
                .iter()
                .map(|v| mesh.positions()[v.index()])
                .collect();
            let n = points.len();
            let length = (0..n)
                .map(|k| points[k].distance(points[(k + 1) % n]))
                .sum();
            FreeLoop {
                nodes: chain.vertices.clone(),
                half_edges: chain.half_edges.clone(),
                length,
                span: span_of(&points),
                centre: points.iter().copied().sum::<DVec3>() / n.max(1) as f64,
                piece: chain
                    .half_edges
                    .first()
                    .map_or(0, |&h| piece_of[topology.face(h).index()]),
                outer: false,
            }
        })
        .collect();
    for (piece, area) in normals.iter().enumerate() {
        let members: Vec<usize> = (0..loops.len())
            .filter(|&k| loops[k].piece == piece)
            .collect();
        if let Some(k) = enclosing_loop(mesh, *area, &loops, &members) {
            loops[k].outer = true;
        }
    }
    // The designer's choice: the loop nearest the point is its piece's outer boundary.
    if let Some(at) = outer {
        let nearest = (0..loops.len()).min_by(|&a, &b| {
            nearest_node(mesh, &loops[a], at).total_cmp(&nearest_node(mesh, &loops[b], at))
        });
        if let Some(k) = nearest {
            let piece = loops[k].piece;
            for (j, l) in loops.iter_mut().enumerate() {
                if l.piece == piece {
                    l.outer = j == k;
                }
            }
        }
    }
    FreeEdges {
        count: topology
            .edges()
            .filter(|&e| topology.edge_face_count(e) == 1)
            .count(),
        loops,
        open_chains: chains
            .open_chains
            .iter()
            .map(|c| c.vertices.clone())
            .collect(),
        pieces: normals.len(),
    }
}

/// How near `at` the nearest node of `l` lies.
fn nearest_node(mesh: &Mesh, l: &FreeLoop, at: DVec3) -> f64 {
    l.nodes
        .iter()
        .map(|v| mesh.positions()[v.index()].distance(at))
        .fold(f64::INFINITY, f64::min)
}

/// Of the loops `members` of a piece whose faces' vector areas sum to `area`, the one
/// that encloses the most others in the piece's projection (square to its mean face
/// normal); among equals, the largest by projected area.
fn enclosing_loop(
    mesh: &Mesh,
    area: DVec3,
    loops: &[FreeLoop],
    members: &[usize],
) -> Option<usize> {
    let normal = area.try_normalize().unwrap_or(DVec3::Z);
    let e1 = normal.any_orthonormal_vector();
    let plane = ProjectionPlane {
        origin: DVec3::ZERO,
        e1,
        e2: normal.cross(e1),
        normal,
    };
    let flat: Vec<Vec<DVec2>> = members
        .iter()
        .map(|&k| {
            loops[k]
                .nodes
                .iter()
                .map(|v| plane.to_plane(mesh.positions()[v.index()]).0)
                .collect()
        })
        .collect();
    let encloses = |a: usize, b: usize| -> bool {
        // Most of b's nodes inside a: a loop touching another at a node still counts.
        let inside = flat[b]
            .iter()
            .filter(|&&q| polygon_winding(&flat[a], q) != 0)
            .count();
        2 * inside > flat[b].len()
    };
    (0..members.len())
        .map(|a| {
            let count = (0..members.len())
                .filter(|&b| b != a && encloses(a, b))
                .count();
            (count, polygon_area(flat[a].iter().copied()).abs(), a)
        })
        .max_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)).then(y.2.cmp(&x.2)))
        .map(|(_, _, a)| members[a])
}

/// Why a loop cannot be filled as it is.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LoopProblem {
    /// Fewer than three distinct nodes, or no area.
    #[error("the loop is degenerate: {0}")]
    Degenerate(&'static str),
    /// An edge at one of its nodes joins more than two faces.
    #[error("an edge at the loop's node {node} (at {at}) joins more than two faces")]
    NotManifold { node: u32, at: DVec3 },
    /// Two faces at one of its nodes are wound opposite ways across their edge.
    #[error("the faces at the loop's node {node} (at {at}) are not wound alike")]
    Inconsistent { node: u32, at: DVec3 },
    /// Its free edges do not close: they run into each other the wrong way (a fault
    /// the checks at its nodes did not find).
    #[error("its free edges do not close a loop")]
    Open,
}

/// Checks the mesh round `l`: at least three distinct nodes enclosing some area, and
/// every edge at its nodes manifold and wound alike on both sides.
pub fn check_loop(mesh: &Mesh, topology: &Topology, l: &FreeLoop) -> Result<(), LoopProblem> {
    let mut distinct: Vec<DVec3> = Vec::new();
    for v in &l.nodes {
        let p = mesh.positions()[v.index()];
        if !distinct
            .iter()
            .any(|q| q.distance(p) <= 1e-9 * l.span.max(1.0))
        {
            distinct.push(p);
        }
    }
    if distinct.len() < 3 {
        return Err(LoopProblem::Degenerate("fewer than 3 distinct nodes"));
    }
    let n = distinct.len();
    let area = (0..n)
        .map(|k| (distinct[k] - distinct[0]).cross(distinct[(k + 1) % n] - distinct[0]))
        .sum::<DVec3>()
        .length()
        * 0.5;
    if area <= 1e-9 * l.length * l.length {
        return Err(LoopProblem::Degenerate("its nodes enclose no area"));
    }
    check_nodes(mesh, topology, &l.nodes)
}

/// Checks every edge at `nodes`: manifold, and its two faces wound alike. An open chain
/// of free edges (one that does not close a loop) comes from one of these faults.
pub fn check_nodes(
    mesh: &Mesh,
    topology: &Topology,
    nodes: &[VertexId],
) -> Result<(), LoopProblem> {
    for &v in nodes {
        for &e in topology.vertex_edges(v) {
            if topology.is_non_manifold_edge(e) {
                return Err(LoopProblem::NotManifold {
                    node: v.0,
                    at: mesh.positions()[v.index()],
                });
            }
            let wound_alike = match *topology.edge_half_edges(e) {
                [a, b] => topology.origin(a) == topology.origin(b),
                _ => false,
            };
            if wound_alike {
                return Err(LoopProblem::Inconsistent {
                    node: v.0,
                    at: mesh.positions()[v.index()],
                });
            }
        }
    }
    Ok(())
}
