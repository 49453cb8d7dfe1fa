//! Cracks stitched (paper 002, section 2: the free edges CAD leaves between patches):
//! two chains of free edges running side by side closer than a tolerance are joined.
//! First each free node within the tolerance of another free node (of a face it does
//! not share) is merged into it; then each free node that lies within the tolerance of
//! a free edge on the other side, between its ends, splits that edge's face there, so
//! the two chains meet node for node and no T-junction is left. What remains of a
//! crack wider than the tolerance is a hole like any other.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use crate::geom::error::Result;
use crate::geom::mesh::box_grid::BoxGrid;
use crate::geom::mesh::{Face, FaceId, Mesh, Topology, VertexId};
use crate::geom::union_find::UnionFind;

/// What stitching did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stitched {
    /// Free nodes merged into another.
    pub merged_nodes: usize,
    /// Free edges split at a node of the other side.
    pub split_edges: usize,
}

/// The nodes splitting a face's sides: per side (its two nodes, in the face's order),
/// the splitting nodes and where along the side each lies.
type SideSplits = BTreeMap<(u32, u32), Vec<(f64, u32)>>;

/// Stitches the cracks of `mesh` (triangles and quads) narrower than `tolerance` (mm).
pub fn stitch_cracks(mesh: &Mesh, tolerance: f64) -> Result<(Mesh, Stitched)> {
    let mut report = Stitched::default();
    if tolerance <= 0.0 {
        return Ok((mesh.clone(), report));
    }
    let merged = merge_free_nodes(mesh, tolerance, &mut report)?;
    let split = split_at_free_nodes(&merged, tolerance, &mut report)?;
    Ok((split, report))
}

/// Free nodes within `tolerance` of each other merged (a node never into one of its
/// own faces' nodes), each group at its lowest-numbered node's position.
fn merge_free_nodes(mesh: &Mesh, tolerance: f64, report: &mut Stitched) -> Result<Mesh> {
    let topology = Topology::build(mesh);
    let free: Vec<u32> = topology
        .free_edges()
        .into_iter()
        .flat_map(|e| topology.edge_vertices(e).map(|v| v.0))
        .collect::<BTreeSet<u32>>()
        .into_iter()
        .collect();
    let positions = mesh.positions();
    let reach = DVec3::splat(tolerance);
    let grid = BoxGrid::new(
        &free
            .iter()
            .map(|&v| (positions[v as usize], positions[v as usize]))
            .collect::<Vec<_>>(),
    );
    let mut sets = UnionFind::new(mesh.vertex_count());
    let shares_face = |a: u32, b: u32| {
        topology.vertex_faces(VertexId(a)).iter().any(|f| {
            mesh.face(*f)
                .is_some_and(|face| face.vertices().any(|v| v.0 == b))
        })
    };
    for &v in &free {
        let p = positions[v as usize];
        for k in grid.candidates(p - reach, p + reach) {
            let w = free[k as usize];
            if w > v && positions[w as usize].distance(p) <= tolerance && !shares_face(v, w) {
                if sets.find(v as usize) != sets.find(w as usize) {
                    report.merged_nodes += 1;
                }
                sets.union(v as usize, w as usize);
            }
        }
    }
    // Each group takes its lowest node's number and position.
    let root: Vec<usize> = (0..mesh.vertex_count()).map(|v| sets.find(v)).collect();
    let mut lowest: BTreeMap<usize, u32> = BTreeMap::new();
    for (v, r) in root.iter().enumerate() {
        lowest.entry(*r).or_insert(v as u32);
    }
    let to = |v: u32| lowest[&root[v as usize]];
    let faces: Vec<(Face, FaceId)> = mesh
        .faces()
        .iter()
        .zip(mesh.face_ids())
        .filter_map(|(f, id)| {
            // A side whose two nodes were merged is gone: a quad so becomes a
            // triangle, a triangle a line (dropped).
            let mut ids: Vec<u32> = f.indices().iter().map(|&v| to(v)).collect();
            ids.dedup();
            if ids.len() > 1 && ids.first() == ids.last() {
                ids.pop();
            }
            let distinct: BTreeSet<u32> = ids.iter().copied().collect();
            (ids.len() >= 3 && distinct.len() == ids.len())
                .then(|| Face::from_slice(&ids))
                .and_then(|r| r.ok())
                .map(|face| (face, id))
        })
        .collect();
    compacted(mesh, positions.to_vec(), faces)
}

/// Each free edge with free nodes of the other side lying on it (within `tolerance`,
/// strictly between its ends) split at them: its one face cut into a fan.
fn split_at_free_nodes(mesh: &Mesh, tolerance: f64, report: &mut Stitched) -> Result<Mesh> {
    let topology = Topology::build(mesh);
    let positions = mesh.positions().to_vec();
    let free_edges = topology.free_edges();
    let free_nodes: BTreeSet<u32> = free_edges
        .iter()
        .flat_map(|&e| topology.edge_vertices(e).map(|v| v.0))
        .collect();
    let reach = DVec3::splat(tolerance);
    let grid = BoxGrid::new(
        &free_edges
            .iter()
            .map(|&e| {
                let [a, b] = topology.edge_vertices(e).map(|v| positions[v.index()]);
                (a.min(b), a.max(b))
            })
            .collect::<Vec<_>>(),
    );
    // Per free edge, the nodes splitting it and where along it.
    let mut splits: BTreeMap<usize, Vec<(f64, u32)>> = BTreeMap::new();
    for &v in &free_nodes {
        let p = positions[v as usize];
        for k in grid.candidates(p - reach, p + reach) {
            let k = k as usize;
            let [a, b] = topology.edge_vertices(free_edges[k]);
            if a.0 == v || b.0 == v {
                continue;
            }
            let (pa, pb) = (positions[a.index()], positions[b.index()]);
            let ab = pb - pa;
            let t = (p - pa).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE);
            let off = p.distance(pa + t.clamp(0.0, 1.0) * ab);
            let clear = p.distance(pa) > tolerance && p.distance(pb) > tolerance;
            if off <= tolerance && t > 0.0 && t < 1.0 && clear {
                splits.entry(k).or_default().push((t, v));
            }
        }
    }
    if splits.is_empty() {
        return Ok(mesh.clone());
    }
    // The face of each split edge, and the nodes to insert on each of its sides.
    let mut on_face: BTreeMap<usize, SideSplits> = BTreeMap::new();
    for (k, mut nodes) in splits {
        nodes.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        nodes.dedup_by_key(|n| n.1);
        report.split_edges += 1;
        let e = free_edges[k];
        let Some(f) = topology.edge_faces(e).next() else {
            continue;
        };
        let [a, b] = topology.edge_vertices(e);
        on_face
            .entry(f.index())
            .or_default()
            .insert((a.0, b.0), nodes);
    }
    let mut positions = positions;
    let mut faces: Vec<(Face, FaceId)> = Vec::with_capacity(mesh.face_count() + 2 * on_face.len());
    for ((fi, face), id) in mesh.faces().iter().enumerate().zip(mesh.face_ids()) {
        let Some(sides) = on_face.get(&fi) else {
            faces.push((*face, id));
            continue;
        };
        // The face's outline with the splitting nodes in order along each side.
        let ids = face.indices();
        let m = ids.len();
        let mut outline: Vec<u32> = Vec::new();
        for s in 0..m {
            let (p, q) = (ids[s], ids[(s + 1) % m]);
            outline.push(p);
            if let Some(nodes) = sides.get(&(p, q)) {
                outline.extend(nodes.iter().map(|n| n.1));
            } else if let Some(nodes) = sides.get(&(q, p)) {
                outline.extend(nodes.iter().rev().map(|n| n.1));
            }
        }
        if sides.len() == 1 && m == 3 {
            // One side split: a fan from the corner opposite it.
            let corner_at = outline
                .iter()
                .position(|&v| ids.contains(&v) && !sides.keys().any(|&(p, q)| p == v || q == v))
                .unwrap_or(0);
            outline.rotate_left(corner_at);
            for w in outline[1..].windows(2) {
                faces.push((Face::triangle(outline[0], w[0], w[1]), id));
            }
        } else {
            // Several sides split: a fan from a new node at the face's middle.
            let middle = outline
                .iter()
                .map(|&v| positions[v as usize])
                .sum::<DVec3>()
                / outline.len() as f64;
            positions.push(middle);
            let c = (positions.len() - 1) as u32;
            for s in 0..outline.len() {
                faces.push((
                    Face::triangle(c, outline[s], outline[(s + 1) % outline.len()]),
                    id,
                ));
            }
        }
    }
    compacted(mesh, positions, faces)
}

/// The mesh of `faces` over `positions`, nodes no face uses dropped (numbers kept in
/// order), each face paired with the face of `source` it came from, whose groups it
/// joins.
fn compacted(source: &Mesh, positions: Vec<DVec3>, faces: Vec<(Face, FaceId)>) -> Result<Mesh> {
    let (faces, origin): (Vec<Face>, Vec<FaceId>) = faces.into_iter().unzip();
    let mut used = vec![false; positions.len()];
    for f in &faces {
        for &v in f.indices() {
            used[v as usize] = true;
        }
    }
    let mut id = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    for (v, p) in positions.into_iter().enumerate() {
        if used[v] {
            id[v] = kept.len() as u32;
            kept.push(p);
        }
    }
    // Renumbering keeps every face's corners distinct, so no face is lost here and
    // `origin` still lines up with the faces.
    let faces: Vec<Face> = faces
        .iter()
        .map(|f| {
            let ids: Vec<u32> = f.indices().iter().map(|&v| id[v as usize]).collect();
            Face::from_slice(&ids)
        })
        .collect::<Result<_>>()?;
    Ok(Mesh::new(kept, faces)?.with_groups_of(source, &origin))
}
