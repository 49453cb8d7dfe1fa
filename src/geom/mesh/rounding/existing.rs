//! Finding a round a mesh already has (paper 000, section 4), to re-round it with a new
//! radius: a tool mesh from CAD carries its rounds only as facets. From a picked node,
//! the round is the connected set of nodes whose curvature lies in a band round the
//! picked node's; its faces are those with a node in the set, the faces beside it on
//! its two sides are the base groups the new ball rolls on, and the line halfway
//! between its two rims is the line it runs along.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use super::base::{BaseError, BaseMeshes, Reach, BASE_REACH};
use super::polyline_nearest;
use super::round::RoundSite;
use crate::geom::mesh::curvature::NodeCurvature;
use crate::geom::mesh::{FaceId, Mesh, Topology, VertexId};

/// How far a node's curvature may lie from the picked node's and still be the round's,
/// as a share of the picked node's: a quarter. A tessellated round's own nodes agree
/// to a few per cent; its rim nodes, fitted across the round and the flat beside it,
/// come out near half and are left to the faces beside.
pub const DEFAULT_BAND: f64 = 0.25;

/// The flattest a picked node may be and still be on a round: a radius of 10 m.
const FLAT: f64 = 1e-4;

/// A round found on a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct ExistingRound {
    /// Its nodes: those whose curvature lies in the band, connected to the picked one.
    pub nodes: Vec<VertexId>,
    /// Its faces: those with one of its nodes, ascending.
    pub faces: Vec<FaceId>,
    /// Its mean radius (mm): the mean over its nodes of the sharper principal radius.
    pub radius: f64,
    /// Whether it is convex (bending away from the normals).
    pub convex: bool,
    /// The line halfway between its two rims, in order (its first point again at its
    /// end when closed).
    pub guide: Vec<DVec3>,
    /// Whether it runs round back to its start.
    pub closed: bool,
    /// The faces beside it on each side: across an edge from one of its faces.
    pub sides: [Vec<FaceId>; 2],
}

impl ExistingRound {
    /// Its length along the middle (mm).
    pub fn length(&self) -> f64 {
        self.guide.windows(2).map(|w| w[0].distance(w[1])).sum()
    }
}

/// Why no round was found at a node.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FindError {
    /// The picked node has no curvature (too few neighbours to fit).
    #[error("the mesh's curvature cannot be found at the picked node")]
    NoCurvature,
    /// The mesh is flat at the picked node: no principal curvature radius under 10 m.
    #[error("the mesh is flat at the picked node (it curves on no radius under 10 m): no round is there")]
    Flat,
    /// The faces beside the round are not two groups, one on each side.
    #[error("the faces beside the round are not two groups, one on each side ({groups} found): the round does not run from edge to edge of the mesh or round to its start")]
    NotTwoSides { groups: usize },
    /// A rim of the round branches: the band took in nodes beyond one strip.
    #[error("the round's rim branches at node {node}: its nodes are not one strip")]
    NotAStrip { node: u32 },
}

/// The sharper principal curvature at a node (signed).
fn sharper(c: &NodeCurvature) -> f64 {
    if c.max.abs() >= c.min.abs() {
        c.max
    } else {
        c.min
    }
}

/// The faces beside the round whose faces are `faces`, grouped by side: connected
/// through faces off the round that touch its rim (the nodes of its faces that also
/// lie on a face off it).
fn beside_groups(mesh: &Mesh, topology: &Topology, faces: &BTreeSet<FaceId>) -> Vec<Vec<FaceId>> {
    let rim: BTreeSet<VertexId> = faces
        .iter()
        .filter_map(|&f| mesh.face(f))
        .flat_map(|face| face.vertices().collect::<Vec<_>>())
        .filter(|&v| topology.vertex_faces(v).iter().any(|g| !faces.contains(g)))
        .collect();
    let touches_rim = |f: FaceId| {
        mesh.face(f)
            .is_some_and(|face| face.vertices().any(|v| rim.contains(&v)))
    };
    let beside: BTreeSet<FaceId> = faces
        .iter()
        .flat_map(|&f| topology.face_neighbors(f))
        .filter(|g| !faces.contains(g))
        .collect();
    let mut group_of: BTreeMap<FaceId, usize> = BTreeMap::new();
    let mut groups: Vec<Vec<FaceId>> = Vec::new();
    for &seed in &beside {
        if group_of.contains_key(&seed) {
            continue;
        }
        let g = groups.len();
        let mut members = Vec::new();
        let mut queue = vec![seed];
        group_of.insert(seed, g);
        while let Some(f) = queue.pop() {
            if beside.contains(&f) {
                members.push(f);
            }
            for n in topology.face_neighbors(f) {
                if !faces.contains(&n) && touches_rim(n) && !group_of.contains_key(&n) {
                    group_of.insert(n, g);
                    queue.push(n);
                }
            }
        }
        members.sort();
        groups.push(members);
    }
    groups
}

/// The round through `node` of `mesh`: its nodes are those connected to `node` whose
/// sharper principal curvature (`curvature` of a node) has the same sign and
/// lies within `band` (a share) of `node`'s.
pub fn find_round(
    mesh: &Mesh,
    topology: &Topology,
    curvature: &dyn Fn(VertexId) -> Option<NodeCurvature>,
    node: VertexId,
    band: f64,
) -> Result<ExistingRound, FindError> {
    let picked = curvature(node).ok_or(FindError::NoCurvature)?;
    let k0 = sharper(&picked);
    if k0.abs() < FLAT {
        return Err(FindError::Flat);
    }
    // A node on the mesh's free edge is fitted to neighbours on one side only, and to
    // the next ring as well, which reaches across the round's rim onto the face
    // beside: its curvature comes out flatter, so it is held to twice the band.
    let in_band = |v: VertexId| {
        let width = if topology.is_boundary_vertex(v) {
            2.0 * band
        } else {
            band
        };
        curvature(v).is_some_and(|c| {
            let k = sharper(&c);
            k * k0 > 0.0 && (k - k0).abs() <= width * k0.abs()
        })
    };
    let mut nodes = BTreeSet::from([node]);
    let mut queue = vec![node];
    while let Some(v) = queue.pop() {
        for w in topology.vertex_neighbors(v) {
            if in_band(w) && nodes.insert(w) {
                queue.push(w);
            }
        }
    }
    let mut faces: BTreeSet<FaceId> = nodes
        .iter()
        .flat_map(|&v| topology.vertex_faces(v).iter().copied())
        .collect();
    // A face whose every node lies on the round's faces is ringed by the round: its
    // nodes fell just outside the band (a node's quadric there reaches across the
    // round's rim), and it is the round's own.
    loop {
        let ringed: Vec<FaceId> = faces
            .iter()
            .flat_map(|&f| topology.face_neighbors(f))
            .filter(|g| !faces.contains(g))
            .filter(|&g| {
                mesh.face(g).is_some_and(|face| {
                    face.vertices()
                        .all(|v| topology.vertex_faces(v).iter().any(|h| faces.contains(h)))
                })
            })
            .collect();
        if ringed.is_empty() {
            break;
        }
        faces.extend(ringed);
    }
    let radius = nodes
        .iter()
        .filter_map(|&v| curvature(v).map(|c| 1.0 / sharper(&c).abs()))
        .sum::<f64>()
        / nodes.len() as f64;
    let groups = beside_groups(mesh, topology, &faces);
    let [one, other] =
        <[Vec<FaceId>; 2]>::try_from(groups).map_err(|groups| FindError::NotTwoSides {
            groups: groups.len(),
        })?;
    // Each rim as a polyline: the edges between the round's faces and a side's.
    let rim_line = |side: &[FaceId]| -> Result<(Vec<DVec3>, bool), FindError> {
        let side: BTreeSet<FaceId> = side.iter().copied().collect();
        let mut links: BTreeMap<VertexId, Vec<VertexId>> = BTreeMap::new();
        for &f in &side {
            for h in topology.face_half_edges(f) {
                let e = topology.edge(h);
                if topology.edge_faces(e).any(|g| faces.contains(&g)) {
                    let [a, b] = topology.edge_vertices(e);
                    links.entry(a).or_default().push(b);
                    links.entry(b).or_default().push(a);
                }
            }
        }
        if let Some((&v, _)) = links.iter().find(|(_, n)| n.len() > 2) {
            return Err(FindError::NotAStrip { node: v.0 });
        }
        let Some(start) = links
            .iter()
            .find(|(_, n)| n.len() == 1)
            .map(|(&v, _)| v)
            .or_else(|| links.keys().next().copied())
        else {
            return Ok((Vec::new(), false));
        };
        let mut path = vec![start];
        let mut prev = None;
        let mut at = start;
        loop {
            let next = links[&at].iter().copied().find(|&n| Some(n) != prev);
            match next {
                Some(n) if n == start => break,
                Some(n) if !path.contains(&n) => {
                    prev = Some(at);
                    at = n;
                    path.push(n);
                }
                _ => break,
            }
        }
        if path.len() < links.len() {
            // The rim is in pieces: not one strip.
            return Err(FindError::NotAStrip { node: start.0 });
        }
        let closed = links[&start].len() == 2;
        let mut points: Vec<DVec3> = path.iter().filter_map(|&v| mesh.position(v)).collect();
        // An open rim's end on the mesh's free edge is taken straight on from the step
        // before it, as far along: the quadric there is fitted on one side only, so the
        // band takes or leaves the free edge's nodes unlike the round's inner ones, and
        // the rim's last step runs slant across the round.
        let n = points.len();
        if !closed && n > 2 && n == path.len() {
            for [last, next, after] in [[0, 1, 2], [n - 1, n - 2, n - 3]] {
                if topology.is_boundary_vertex(path[last]) {
                    let on = (points[next] - points[after]).normalize_or_zero();
                    points[last] = points[next] + on * (points[last] - points[next]).dot(on);
                }
            }
        }
        if closed {
            points.push(points[0]);
        }
        Ok((points, closed))
    };
    let (rim0, closed) = rim_line(&one)?;
    let (rim1, _) = rim_line(&other)?;
    let guide: Vec<DVec3> = rim0
        .iter()
        .map(|&p| 0.5 * (p + polyline_nearest(&rim1, p).2))
        .collect();
    Ok(ExistingRound {
        nodes: nodes.into_iter().collect(),
        faces: faces.into_iter().collect(),
        radius,
        convex: k0 > 0.0,
        guide,
        closed,
        sides: [one, other],
    })
}

/// Where `found` is re-rounded at a mean radius `radius`: the faces beside it within
/// [`BASE_REACH`] `radius` of its middle, reached from its sides without crossing it,
/// as the two base meshes; its faces replaced. Refused when the two sides join within
/// reach.
pub fn reround_site(
    mesh: &Mesh,
    topology: &Topology,
    found: &ExistingRound,
    radius: f64,
) -> Result<RoundSite, BaseError> {
    let reach = BASE_REACH * radius;
    let round: BTreeSet<FaceId> = found.faces.iter().copied().collect();
    let within = Reach::new(mesh, &found.guide, reach);
    let near = |f: FaceId| within.face(f);
    let flood = |seeds: &[FaceId]| -> BTreeSet<FaceId> {
        let mut seen: BTreeSet<FaceId> = seeds.iter().copied().collect();
        let mut queue = seeds.to_vec();
        while let Some(f) = queue.pop() {
            for g in topology.face_neighbors(f) {
                if !round.contains(&g) && near(g) && seen.insert(g) {
                    queue.push(g);
                }
            }
        }
        seen
    };
    let (left, right) = (flood(&found.sides[0]), flood(&found.sides[1]));
    if let Some(&f) = left.intersection(&right).next() {
        return Err(BaseError::NotSplit { face: f.0 });
    }
    Ok(RoundSite {
        base: BaseMeshes {
            left: left.into_iter().collect(),
            right: right.into_iter().collect(),
        },
        guide: found.guide.clone(),
        closed: found.closed,
        convex: found.convex,
        replaced: found.faces.clone(),
    })
}
