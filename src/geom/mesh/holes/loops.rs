//! Free edges and the loops they close (paper 002, section 2): each loop of free
//! edges, its length and span, whether it is a panel's outer boundary, and whether the
//! mesh round it is sound enough to fill. The loops are those the half-edge topology
//! traces ([`Topology::boundary_loops`]), found without building it for the whole mesh
//! where the mesh round them is simple ([`scan`]).
//!
//! The outer boundary is not "the longest loop": a panel may have a hole longer than a
//! narrow outer edge. In each connected piece of the mesh, projected on the plane
//! square to the piece's mean face normal, the outer boundary is the loop that
//! encloses the most other loops (the largest by projected area where none encloses
//! another), which a designer may override.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::plane::ProjectionPlane;
use crate::geom::mesh::stars::{Corner, VertexStars};
use crate::geom::mesh::{FaceId, HalfEdgeId, Mesh, Topology, VertexId};
use crate::geom::trimmed::{polygon_area, polygon_winding};
use crate::geom::union_find::{SetsBySize, UnionFind};

/// A closed loop of free edges.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeLoop {
    /// Its nodes in the order its free edges run (the faces' winding: round a hole
    /// clockwise, seen from the side the normals face).
    pub nodes: Vec<VertexId>,
    /// The face on each of its edges, `faces[k]` on the edge from `nodes[k]` to the
    /// next node.
    pub faces: Vec<FaceId>,
    /// Its length (mm).
    pub length: f64,
    /// The largest distance between two of its nodes (mm): how far across it is.
    pub span: f64,
    /// The mean of its nodes: where it is.
    pub centre: DVec3,
    /// The connected piece of the mesh it bounds (numbered from 0 in the order the
    /// loops first meet the pieces; [`FreeEdges::pieces`] counts them all).
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
    /// The closed loops, each starting at its first free edge in face order, and in
    /// that order.
    pub loops: Vec<FreeLoop>,
    /// Chains of free edges that do not close, as node lists.
    pub open_chains: Vec<Vec<VertexId>>,
    /// The mesh's connected pieces (faces joined across edges; see [`scan`] for the
    /// one exception).
    pub pieces: usize,
}

/// The largest distance between two of `points`, exactly. Pairs are compared from the
/// point farthest from the points' middle inwards, and the search stops where no pair
/// left can beat the best found (two points `r1` and `r2` from the middle are at most
/// `r1 + r2` apart): a loop's few far points decide its span, not all its pairs.
pub fn span_of(points: &[DVec3]) -> f64 {
    if points.len() < 2 {
        return 0.0;
    }
    let middle = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let mut order: Vec<(f64, usize)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| (p.distance(middle), i))
        .collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let farthest = order[0].0;
    let mut best = 0.0f64;
    for (k, &(r, i)) in order.iter().enumerate() {
        // The bound is widened by a part in 1e12 so rounding of the distances to the
        // middle never stops the search early.
        if (r + farthest) * (1.0 + 1e-12) < best.sqrt() {
            break;
        }
        for &(_, j) in &order[k + 1..] {
            best = best.max(points[i].distance_squared(points[j]));
        }
    }
    best.sqrt()
}

/// A mesh's free edges with the stars they were found from: what hole filling works
/// from.
#[derive(Debug, Clone)]
pub struct Scan<'m> {
    /// Every node's faces.
    pub stars: VertexStars<'m>,
    /// The free edges and their loops.
    pub free: FreeEdges,
    /// Whether every node on a free edge was found simple (its edges manifold and
    /// wound alike, its faces one fan): then the loops' edges need no further check.
    pub nodes_sound: bool,
}

/// The free edges of `mesh` and their loops, each piece's outer boundary marked (the
/// loop nearest `outer`'s point instead, for the piece holding it, where given).
pub fn free_edges(mesh: &Mesh, outer: Option<DVec3>) -> FreeEdges {
    scan(mesh, outer).free
}

/// [`free_edges`], with the stars it found them from.
///
/// Two passes over the faces, run side by side: the stars, which flag the nodes whose
/// faces do not close round them, and the connected pieces (a union of each face's
/// nodes). Only the flagged nodes are then looked at. Where each has one free edge
/// in and one out, sound edges and one fan of faces (a panel with holes), the loops
/// are those edges chained; anywhere else (a bowtie node, an edge of three faces,
/// faces wound both ways) the mesh's whole half-edge topology traces them, as
/// [`Topology::boundary_loops`] does for every mesh, and joins the pieces across
/// edges. The loops are the same either way (property-tested against the topology);
/// the pieces too, but where two sheets touch only at a node inside both, which the
/// first way counts as one piece.
pub fn scan(mesh: &Mesh, outer: Option<DVec3>) -> Scan<'_> {
    // The pieces beside the stars and the loops chained from them, on the pool's
    // other thread where it is free (each pass takes under a millisecond on a 50k-face
    // mesh); where it is not, this thread takes them in turn, without waiting for one.
    let ((stars, simple), (mut sets, pieces)) = rayon::join(
        || {
            let stars = VertexStars::build(mesh);
            let simple = simple_loops(&stars);
            (stars, simple)
        },
        || node_sets(mesh),
    );
    let nodes_sound = simple.is_some();
    let mut free = match simple {
        Some((count, chains)) => {
            // Pieces by shared nodes: the same as by shared edges here, every node on a
            // free edge having one fan of faces.
            let mut root_piece: Vec<(usize, usize)> = Vec::new();
            let mut piece_of = |v: VertexId| {
                let root = sets.find(v.index());
                match root_piece.iter().find(|(r, _)| *r == root) {
                    Some(&(_, p)) => p,
                    None => {
                        root_piece.push((root, root_piece.len()));
                        root_piece.len() - 1
                    }
                }
            };
            // Pieces numbered in loop order, then the loops measured side by side.
            let pieces_of: Vec<usize> =
                chains.iter().map(|(nodes, _)| piece_of(nodes[0])).collect();
            let loops = chains
                .into_par_iter()
                .zip(pieces_of)
                .map(|((nodes, faces), piece)| measured(mesh, nodes, faces, piece))
                .collect();
            FreeEdges {
                count,
                loops,
                open_chains: Vec::new(),
                pieces,
            }
        }
        None => traced_on_topology(mesh),
    };
    mark_outer(mesh, &mut free.loops, outer);
    Scan {
        stars,
        free,
        nodes_sound,
    }
}

/// The mesh's nodes in sets joined by its faces (the connected pieces, by shared
/// nodes), and how many sets hold a face. Each face's first node is found once and its
/// other nodes joined to it; the sets are joined by size, as only which nodes share a
/// piece matters (the pieces are numbered by the loops that meet them).
fn node_sets(mesh: &Mesh) -> (SetsBySize, usize) {
    let mut sets = SetsBySize::new(mesh.vertex_count());
    let mut used = vec![false; mesh.vertex_count()];
    for face in mesh.faces() {
        let v = face.indices();
        used[v[0] as usize] = true;
        let mut root = sets.find(v[0] as usize);
        for &w in &v[1..] {
            used[w as usize] = true;
            let other = sets.find(w as usize);
            root = sets.join_roots(root, other);
        }
    }
    let count = (0..used.len())
        .filter(|&v| used[v] && sets.find(v) == v)
        .count();
    (sets, count)
}

/// How an edge at a node stands.
enum EdgeAt {
    /// One face.
    Free,
    /// Two faces wound opposite ways across it.
    Sound,
    /// More than two faces.
    NotManifold,
    /// Two faces wound the same way across it.
    WoundAlike,
}

/// How the edge from a node to `w` stands, from `corners` (how each face at the node
/// runs there): its faces run from the node to `w` or from `w` to the node.
fn edge_at(corners: &[Corner], w: VertexId) -> EdgeAt {
    let out = corners.iter().filter(|c| c.to == w).count();
    let back = corners.iter().filter(|c| c.from == w).count();
    match (out, back) {
        _ if out + back > 2 => EdgeAt::NotManifold,
        (2, _) | (_, 2) => EdgeAt::WoundAlike,
        _ if out + back == 1 => EdgeAt::Free,
        _ => EdgeAt::Sound,
    }
}

/// A loop of free edges as chained: its nodes, and the face on each edge.
type Chain = (Vec<VertexId>, Vec<FaceId>);

/// The loops of free edges where every node on one is simple: one free edge in, one
/// out, every edge at it with one or two faces wound alike, and its faces one fan.
/// `None` where a node is not. The free-edge count and each loop from its first free
/// edge in face order, in that order.
///
/// Each open node's free edge out is found on its own, on whichever thread of the pool
/// is free (the scan's other pass, the pieces, usually ends about when the stars do).
fn simple_loops(stars: &VertexStars) -> Option<(usize, Vec<Chain>)> {
    let open: Vec<VertexId> = stars.open_nodes().collect();
    // Per open node, its free edge out: (face, the node's corner in it, the next node).
    let out: Vec<(FaceId, usize, VertexId)> = open
        .par_iter()
        .map_init(Vec::new, |corners, &v| free_edge_out(stars, v, corners))
        .collect::<Option<_>>()?;
    // Each loop from its lowest free edge, in face order (a half-edge's number).
    let mut starts: Vec<usize> = (0..open.len()).collect();
    starts.sort_by_key(|&i| (out[i].0, out[i].1));
    let mut used = vec![false; open.len()];
    let mut loops = Vec::new();
    for start in starts {
        if used[start] {
            continue;
        }
        let (mut nodes, mut faces) = (Vec::new(), Vec::new());
        let mut at = start;
        while !used[at] {
            used[at] = true;
            nodes.push(open[at]);
            faces.push(out[at].0);
            at = open.binary_search(&out[at].2).ok()?;
        }
        // A simple node has one edge in, so the walk can only close where it began.
        if at != start {
            return None;
        }
        loops.push((nodes, faces));
    }
    Some((open.len(), loops))
}

/// The free edge out of the open node `v` where `v` is simple (see [`simple_loops`]):
/// its face, `v`'s corner in that face, and the node it runs to. `corners` is room for
/// the node's corners, reused from node to node.
fn free_edge_out(
    stars: &VertexStars,
    v: VertexId,
    corners: &mut Vec<Corner>,
) -> Option<(FaceId, usize, VertexId)> {
    corners.clear();
    corners.extend(stars.corners(v));
    let (mut free_out, mut free_in) = (None, 0usize);
    for c in corners.iter() {
        for w in [c.to, c.from] {
            match edge_at(corners, w) {
                EdgeAt::NotManifold | EdgeAt::WoundAlike => return None,
                EdgeAt::Sound => {}
                EdgeAt::Free => {
                    if w == c.to {
                        if free_out.replace(c.face).is_some() {
                            return None;
                        }
                    } else {
                        free_in += 1;
                    }
                }
            }
        }
    }
    let face = free_out?;
    if free_in != 1 {
        return None;
    }
    // One fan: turning round the node from the face on the free edge out, face by
    // face across the edges they share, reaches every face at the node (a closed
    // fan also hung on the node would make the node's pieces the topology's job).
    let mut at = corners.iter().find(|c| c.face == face)?;
    let mut fan = 1;
    while let Some(across) = corners.iter().find(|d| d.to == at.from) {
        at = across;
        fan += 1;
        if fan > corners.len() {
            return None;
        }
    }
    if fan != corners.len() {
        return None;
    }
    let corner = stars
        .mesh()
        .faces()
        .get(face.index())?
        .indices()
        .iter()
        .position(|&w| w == v.0)?;
    let next = corners.iter().find(|c| c.face == face)?.to;
    Some((face, corner, next))
}

/// A loop's figures from its nodes.
fn measured(mesh: &Mesh, nodes: Vec<VertexId>, faces: Vec<FaceId>, piece: usize) -> FreeLoop {
    let points: Vec<DVec3> = nodes.iter().map(|v| mesh.positions()[v.index()]).collect();
    let n = points.len();
    let length = (0..n)
        .map(|k| points[k].distance(points[(k + 1) % n]))
        .sum();
    FreeLoop {
        nodes,
        faces,
        length,
        span: span_of(&points),
        centre: points.iter().copied().sum::<DVec3>() / n.max(1) as f64,
        piece,
        outer: false,
    }
}

/// The free edges traced on the mesh's whole half-edge topology, pieces joined across
/// edges: for meshes with a node that is not simple.
fn traced_on_topology(mesh: &Mesh) -> FreeEdges {
    let topology = Topology::build(mesh);
    let chains = topology.boundary_loops();
    // Half-edges are numbered face by face in winding order, so in a mesh of triangles
    // alone the face of half-edge h is h / 3 and no half-edge record is fetched.
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
    let mut roots: Vec<usize> = Vec::new();
    let mut piece_of = |h: HalfEdgeId| {
        let root = sets.find(face_of(h));
        match roots.iter().position(|&r| r == root) {
            Some(p) => p,
            None => {
                roots.push(root);
                roots.len() - 1
            }
        }
    };
    let loops = chains
        .loops
        .iter()
        .map(|chain| {
            let piece = chain.half_edges.first().map_or(0, |&h| piece_of(h));
            let faces = chain.half_edges.iter().map(|&h| topology.face(h)).collect();
            measured(mesh, chain.vertices.clone(), faces, piece)
        })
        .collect();
    let pieces = (0..mesh.face_count())
        .filter(|&f| sets.find(f) == f)
        .count();
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
        pieces,
    }
}

/// Marks each piece's outer boundary among `loops`: the loop enclosing the most others
/// of its piece, seen along the piece's mean normal, or the loop nearest `outer` for the
/// piece holding it.
///
/// A piece's mean normal is its faces' summed vector area, read off its loops: the
/// vector area of a surface is half the sum of `p x q` over its boundary's edges `p-q`
/// (the faces' inner edges cancel in pairs), so no face need be visited.
fn mark_outer(mesh: &Mesh, loops: &mut [FreeLoop], outer: Option<DVec3>) {
    let pieces = loops.iter().map(|l| l.piece + 1).max().unwrap_or(0);
    for piece in 0..pieces {
        let members: Vec<usize> = (0..loops.len())
            .filter(|&k| loops[k].piece == piece)
            .collect();
        let area: DVec3 = members
            .iter()
            .flat_map(|&k| {
                let nodes = &loops[k].nodes;
                (0..nodes.len()).map(move |i| {
                    let p = mesh.positions()[nodes[i].index()];
                    let q = mesh.positions()[nodes[(i + 1) % nodes.len()].index()];
                    0.5 * p.cross(q)
                })
            })
            .sum();
        if let Some(k) = enclosing_loop(mesh, area, loops, &members) {
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
    let boxes: Vec<(DVec2, DVec2)> = flat
        .iter()
        .map(|f| {
            f.iter()
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &q| {
                    (lo.min(q), hi.max(q))
                })
        })
        .collect();
    let encloses = |a: usize, b: usize| -> bool {
        // Only a loop whose box holds most of b's can hold most of b.
        let ((alo, ahi), (blo, bhi)) = (boxes[a], boxes[b]);
        let middle = (blo + bhi) / 2.0;
        if middle.cmplt(alo).any() || middle.cmpgt(ahi).any() {
            return false;
        }
        // Most of b's nodes inside a (a loop touching another at a node still counts),
        // judged on up to SAMPLES of them spread evenly along b, and decided as soon
        // as a majority either way is reached.
        let step = flat[b].len().div_ceil(SAMPLES).max(1);
        let tried = flat[b].len().div_ceil(step);
        let (mut inside, mut outside) = (0, 0);
        for &q in flat[b].iter().step_by(step) {
            if polygon_winding(&flat[a], q) != 0 {
                inside += 1;
            } else {
                outside += 1;
            }
            if 2 * inside > tried || 2 * outside >= tried {
                break;
            }
        }
        2 * inside > tried
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

/// How many of a loop's nodes are tried for lying inside another loop.
const SAMPLES: usize = 15;

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
pub fn check_loop(stars: &VertexStars, l: &FreeLoop) -> Result<(), LoopProblem> {
    check_shape(stars.mesh(), l)?;
    check_nodes(stars, &l.nodes)
}

/// Checks that `l` has at least three distinct nodes (positions more than a part in
/// 1e9 of its span apart) and encloses some area: the vector area of the loop as it
/// runs, nodes that coincide adding nothing to it.
pub fn check_shape(mesh: &Mesh, l: &FreeLoop) -> Result<(), LoopProblem> {
    let at = |v: &VertexId| mesh.positions()[v.index()];
    let apart = 1e-9 * l.span.max(1.0);
    // A first node, a second apart from it, and a third apart from both: enough to
    // know there are three, and found in one pass in the usual loop.
    let mut distinct: Vec<DVec3> = Vec::with_capacity(3);
    for p in l.nodes.iter().map(at) {
        if distinct.iter().all(|q| q.distance(p) > apart) {
            distinct.push(p);
            if distinct.len() == 3 {
                break;
            }
        }
    }
    if distinct.len() < 3 {
        return Err(LoopProblem::Degenerate("fewer than 3 distinct nodes"));
    }
    let first = at(&l.nodes[0]);
    let n = l.nodes.len();
    let area = (0..n)
        .map(|k| (at(&l.nodes[k]) - first).cross(at(&l.nodes[(k + 1) % n]) - first))
        .sum::<DVec3>()
        .length()
        * 0.5;
    if area <= 1e-9 * l.length * l.length {
        return Err(LoopProblem::Degenerate("its nodes enclose no area"));
    }
    Ok(())
}

/// Checks every edge at `nodes`: manifold, and its two faces wound alike. An open chain
/// of free edges (one that does not close a loop) comes from one of these faults.
pub fn check_nodes(stars: &VertexStars, nodes: &[VertexId]) -> Result<(), LoopProblem> {
    let at = |v: VertexId| stars.mesh().positions()[v.index()];
    for &v in nodes {
        let corners: Vec<_> = stars.corners(v).collect();
        // The node's edges, by the neighbour at their other end, in its order.
        let mut neighbours: Vec<VertexId> = corners.iter().flat_map(|c| [c.to, c.from]).collect();
        neighbours.sort_unstable();
        neighbours.dedup();
        for w in neighbours {
            match edge_at(&corners, w) {
                EdgeAt::NotManifold => {
                    return Err(LoopProblem::NotManifold {
                        node: v.0,
                        at: at(v),
                    })
                }
                EdgeAt::WoundAlike => {
                    return Err(LoopProblem::Inconsistent {
                        node: v.0,
                        at: at(v),
                    })
                }
                EdgeAt::Free | EdgeAt::Sound => {}
            }
        }
    }
    Ok(())
}
