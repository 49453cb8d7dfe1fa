//! Step 7 (paper 000, section 2): the mesh cut along the trim lines. Each node of a base
//! mesh lies inside its trim line (nearer the guide than the trim line beside it) or
//! outside; a face with nodes on both sides is split where the trim line crosses its
//! edges and its outside part kept, and a node that lies within a fifth of an edge of
//! the trim line is snapped onto it instead of leaving a sliver between it and the
//! cut. The cut's nodes (the crossings and the snapped nodes) are then placed on the
//! trim line exactly, at their place along the guide, so the round's strip can be
//! stitched to them (step 8).

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use super::index::PolylineIndex;
use super::polyline_nearest;
use super::round::RoundSite;
use crate::geom::mesh::{FaceId, Mesh, Topology, VertexId};

/// How near (mm) two cut nodes placed on a trim line must land to be merged.
pub const SAME_NODE: f64 = 1e-9;

/// The share of an edge within which a node at one end of it is snapped onto the trim
/// line crossing it, rather than the edge split there (which would leave a sliver).
pub const SNAP: f64 = 0.2;

/// How near (a share of the edge) a crossing is placed to where the trim line crosses
/// its edge, and in how many steps at most.
const CROSSING_TOLERANCE: f64 = 1e-10;
const CROSSING_STEPS: usize = 30;

/// Where along an edge (0 at its outside end, 1 at its inside end) `outside`, how far
/// outside the trim line a point of the edge lies, falls to nothing, given its values
/// `(at_out, at_in)` at the ends (positive, negative): regula falsi with the Illinois
/// halving, so a nearly straight `outside` takes two or three steps.
fn crossing_on_edge(outside: impl Fn(f64) -> f64, (at_out, at_in): (f64, f64)) -> f64 {
    let (mut a, mut fa, mut b, mut fb) = (0.0f64, at_out, 1.0f64, at_in);
    let mut t = fa / (fa - fb);
    let mut last_side = 0i8;
    for _ in 0..CROSSING_STEPS {
        t = (a * fb - b * fa) / (fb - fa);
        if !(t > a && t < b) {
            t = 0.5 * (a + b);
        }
        let ft = outside(t);
        if ft >= 0.0 {
            a = t;
            fa = ft;
            if last_side == 1 {
                fb *= 0.5;
            }
            last_side = 1;
        } else {
            b = t;
            fb = ft;
            if last_side == -1 {
                fa *= 0.5;
            }
            last_side = -1;
        }
        if b - a <= CROSSING_TOLERANCE || ft.abs() <= CROSSING_TOLERANCE * (at_out - at_in) {
            break;
        }
    }
    t
}

/// The mesh cut back to its trim lines: its positions (the original nodes, then the
/// crossings; the cut's nodes on the trim lines), the triangles kept, and each cut's
/// nodes in order along the guide (a closed round's first again at its end).
#[derive(Debug, Clone)]
pub struct Cut {
    /// Every node: the mesh's own, then one per edge the trim lines split.
    pub positions: Vec<DVec3>,
    /// The triangles kept: the faces outside the trim lines and the outside parts of
    /// the faces they cross.
    pub faces: Vec<[u32; 3]>,
    /// Per triangle kept, the mesh's face it is (part of), ascending: the mesh's face
    /// groups follow it.
    pub origin: Vec<FaceId>,
    /// Each trim line's cut, its nodes ordered along the guide.
    pub rows: [Vec<u32>; 2],
    /// How many of the mesh's faces the trim lines split.
    pub split_faces: usize,
    /// How many nodes were snapped onto a trim line.
    pub snapped_nodes: usize,
}

/// Where a node lies against the trim line on its side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Place {
    /// Kept, off the cut.
    Outside,
    /// Snapped onto the trim line: kept, on the cut.
    OnLine,
    /// Removed with the round's region.
    Inside,
}

/// The point of the trim line `line` (its points at `line_along` along the guide) at
/// `along` along the guide, between the two points either side of it; `None` outside
/// the stretch of the guide the line runs beside, or where it doubles back.
pub fn trim_point_along(line: &[DVec3], line_along: &[f64], along: f64) -> Option<DVec3> {
    line.windows(2)
        .zip(line_along.windows(2))
        .find_map(|(p, s)| {
            let (lo, hi) = (s[0].min(s[1]), s[0].max(s[1]));
            if along < lo || along > hi || hi - lo <= 0.0 {
                return None;
            }
            let t = (along - s[0]) / (s[1] - s[0]);
            Some(p[0] + t * (p[1] - p[0]))
        })
}

/// A trim line and where its points stand along the guide.
struct TrimLine<'a> {
    points: &'a [DVec3],
    along: Vec<f64>,
    /// Whether its points run on along the guide, never back (so the point at a place
    /// along the guide is found by halving).
    runs_on: bool,
}

impl<'a> TrimLine<'a> {
    fn new(points: &'a [DVec3], guide: &PolylineIndex) -> TrimLine<'a> {
        let along: Vec<f64> = points.iter().map(|&q| guide.nearest(q).1).collect();
        let runs_on = along.windows(2).all(|w| w[1] > w[0]);
        TrimLine {
            points,
            along,
            runs_on,
        }
    }

    /// The trim line's point beside `p` (at `along`, `p`'s place along the guide), or,
    /// past the line's ends, its point nearest `p`.
    fn beside(&self, p: DVec3, along: f64) -> DVec3 {
        let at = if self.runs_on {
            let k = self.along.partition_point(|&a| a < along);
            (k > 0 && k < self.along.len())
                .then(|| {
                    let (a, b) = (self.along[k - 1], self.along[k]);
                    let t = (along - a) / (b - a);
                    self.points[k - 1] + t * (self.points[k] - self.points[k - 1])
                })
                .or_else(|| (self.along.first() == Some(&along)).then(|| self.points[0]))
        } else {
            trim_point_along(self.points, &self.along, along)
        };
        at.unwrap_or_else(|| polyline_nearest(self.points, p).2)
    }
}

/// How far `p` lies outside the trim line `line` (negative inside): its distance from
/// the guide less that of the trim line's point beside it.
fn outside_by(guide: &PolylineIndex, line: &TrimLine, p: DVec3) -> f64 {
    let (off, along, _) = guide.nearest(p);
    off - guide.nearest(line.beside(p, along)).0
}

/// Cuts `mesh` at `site` back to `trim_lines` (the contacts on the left and right base
/// meshes), `guide` the line the round runs along. The faces `site` replaces go
/// whatever the trim lines, with their nodes on no base face.
pub fn cut_to_trim_lines(
    mesh: &Mesh,
    topology: &Topology,
    site: &RoundSite,
    guide: &PolylineIndex,
    trim_lines: &[Vec<DVec3>; 2],
) -> Cut {
    let lines = trim_lines
        .each_ref()
        .map(|points| TrimLine::new(points, guide));
    let n = mesh.vertex_count();
    let mut positions = mesh.positions().to_vec();
    // Each base node's side and how far outside its trim line it lies; those inside
    // (by more than rounding: a node on its trim line stays) go with the round's region.
    let mut side_of: Vec<Option<usize>> = vec![None; n];
    let mut outside: Vec<f64> = vec![f64::INFINITY; n];
    let mut place: Vec<Place> = vec![Place::Outside; n];
    for (s, faces) in [&site.base.left, &site.base.right].iter().enumerate() {
        for face in faces.iter().filter_map(|&f| mesh.face(f)) {
            for v in face.vertices() {
                let v = v.index();
                if side_of[v].is_none() {
                    side_of[v] = Some(s);
                    let p = positions[v];
                    let (off, along, _) = guide.nearest(p);
                    outside[v] = off - guide.nearest(lines[s].beside(p, along)).0;
                    if outside[v] < -1e-9 * off {
                        place[v] = Place::Inside;
                    }
                }
            }
        }
    }
    let mut gone = vec![false; mesh.face_count()];
    for &f in &site.replaced {
        gone[f.index()] = true;
        for v in mesh.face(f).iter().flat_map(|face| face.vertices()) {
            if side_of[v.index()].is_none() {
                place[v.index()] = Place::Inside;
            }
        }
    }
    // The edges a trim line crosses (both ends on one side's base, one in, one out),
    // and the share of the way along from the outside end where it crosses (the
    // straight-line estimate, for the snap).
    let crossing_share = |place: &[Place], a: usize, b: usize| -> Option<f64> {
        let (fa, fb) = (outside[a], outside[b]);
        let split = side_of[a].is_some()
            && side_of[b].is_some()
            && place[a] == Place::Outside
            && place[b] == Place::Inside
            && fa.is_finite()
            && fb.is_finite();
        split.then(|| fa / (fa - fb))
    };
    // Nodes snapped onto the line: an outside node the line crosses one of its edges
    // within SNAP of, and an inside one likewise (moved out onto the line, kept).
    let mut snap = vec![false; n];
    for (f, face) in mesh.face_ids().zip(mesh.faces()) {
        if gone[f.index()] {
            continue;
        }
        for (a, b) in face.sides() {
            let (a, b) = (a.index(), b.index());
            for (out, inn) in [(a, b), (b, a)] {
                if let Some(t) = crossing_share(&place, out, inn) {
                    if t < SNAP {
                        snap[out] = true;
                    } else if t > 1.0 - SNAP {
                        snap[inn] = true;
                    }
                }
            }
        }
    }
    let snapped_nodes = snap.iter().filter(|&&s| s).count();
    for (v, snapped) in snap.iter().enumerate() {
        if *snapped {
            place[v] = Place::OnLine;
        }
    }
    // The crossings: one node per split edge, on the edge where the node's distance
    // outside the trim line falls to nothing.
    let mut crossing: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    let mut crossing_side: Vec<usize> = Vec::new();
    let mut crossing_edge: Vec<(u32, u32)> = Vec::new();
    let mut cross = |out: u32, inn: u32, positions: &mut Vec<DVec3>| -> u32 {
        let key = (out.min(inn), out.max(inn));
        if let Some(&v) = crossing.get(&key) {
            return v;
        }
        // Both ends have a side: a crossing is only made between two base nodes.
        let s = side_of[out as usize].unwrap_or(0);
        let (p, q) = (positions[out as usize], positions[inn as usize]);
        let t = crossing_on_edge(
            |t| outside_by(guide, &lines[s], p.lerp(q, t)),
            (outside[out as usize], outside[inn as usize]),
        );
        positions.push(p.lerp(q, t));
        let v = (positions.len() - 1) as u32;
        crossing.insert(key, v);
        crossing_side.push(s);
        crossing_edge.push(key);
        v
    };
    // The faces kept: whole where no node is inside, their outside part where the trim
    // line crosses them, none where no node is outside.
    let mut faces: Vec<[u32; 3]> = Vec::with_capacity(mesh.face_count());
    let mut from_face: Vec<FaceId> = Vec::with_capacity(mesh.face_count());
    let mut split_faces = 0;
    for (f, face) in mesh.face_ids().zip(mesh.faces()) {
        let &[a, b, c] = face.indices() else { continue };
        if gone[f.index()] {
            continue;
        }
        let t = [a, b, c];
        let at = |v: u32| place[v as usize];
        if t.iter().all(|&v| at(v) != Place::Inside) {
            faces.push(t);
            from_face.push(f);
            continue;
        }
        if !t.iter().any(|&v| at(v) == Place::Outside) {
            continue;
        }
        // The outside part, in the face's own winding: each node kept but the inside
        // ones, and a crossing wherever a side runs from outside to inside or back.
        let splits_cleanly = (0..3).all(|k| {
            let (p, q) = (t[k] as usize, t[(k + 1) % 3] as usize);
            match (place[p], place[q]) {
                (Place::Outside, Place::Inside) => crossing_share(&place, p, q).is_some(),
                (Place::Inside, Place::Outside) => crossing_share(&place, q, p).is_some(),
                _ => true,
            }
        });
        if !splits_cleanly {
            // A face across a trim line from a node on no base face (the fringe of a
            // replaced round): it goes whole, its outside nodes left on the cut.
            continue;
        }
        let mut part: Vec<u32> = Vec::with_capacity(4);
        for k in 0..3 {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            if at(p) != Place::Inside {
                part.push(p);
            }
            match (at(p), at(q)) {
                (Place::Outside, Place::Inside) => part.push(cross(p, q, &mut positions)),
                (Place::Inside, Place::Outside) => part.push(cross(q, p, &mut positions)),
                _ => {}
            }
        }
        split_faces += 1;
        let before = faces.len();
        match part[..] {
            [p, q, r] => faces.push([p, q, r]),
            [p, q, r, s] => {
                // The quad split on its shorter diagonal.
                let d = |i: u32, j: u32| positions[i as usize].distance(positions[j as usize]);
                if d(p, r) <= d(q, s) {
                    faces.extend([[p, q, r], [p, r, s]]);
                } else {
                    faces.extend([[p, q, s], [q, r, s]]);
                }
            }
            _ => {}
        }
        from_face.resize(from_face.len() + faces.len() - before, f);
    }
    // The cut: the kept faces' edges with no kept face on their other side that are
    // not (part of) the mesh's own free edges.
    let original = mesh.vertex_count() as u32;
    let origin = |v: u32| -> Option<(u32, u32)> {
        (v >= original).then(|| crossing_edge[(v - original) as usize])
    };
    let free_in_mesh = |a: u32, b: u32| -> bool {
        let edge = match (origin(a), origin(b)) {
            (None, None) => Some((a, b)),
            (Some((p, q)), None) if b == p || b == q => Some((p, q)),
            (None, Some((p, q))) if a == p || a == q => Some((p, q)),
            _ => None,
        };
        edge.and_then(|(p, q)| topology.find_edge(VertexId(p), VertexId(q)))
            .is_some_and(|e| topology.is_boundary_edge(e))
    };
    let side_of_node = |v: u32| -> Option<usize> {
        match origin(v) {
            Some(_) => Some(crossing_side[(v - original) as usize]),
            None => side_of[v as usize],
        }
    };
    // Only faces with a base node can lie on a cut (a face beside a removed one shares
    // a node with it, and every removed face's nodes are base nodes or inside).
    let mut uses: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for t in faces
        .iter()
        .filter(|t| t.iter().any(|&v| side_of_node(v).is_some()))
    {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut cut_nodes: [BTreeSet<u32>; 2] = [BTreeSet::new(), BTreeSet::new()];
    for (&(a, b), &count) in &uses {
        if count != 1 || free_in_mesh(a, b) {
            continue;
        }
        for v in [a, b] {
            if let Some(s) = side_of_node(v) {
                cut_nodes[s].insert(v);
            }
        }
    }
    let mut on_cut = cut_nodes.map(|nodes| nodes.into_iter().collect::<Vec<u32>>());
    // Each cut's nodes along the guide, placed on their trim line at the same place
    // along the guide (so they keep their order, and no face beside the cut turns
    // over where the trim line runs slant to the guide).
    let mut merged: Vec<u32> = (0..positions.len() as u32).collect();
    for (s, nodes) in on_cut.iter_mut().enumerate() {
        let mut keyed: Vec<(f64, u32)> = nodes
            .iter()
            .map(|&v| (guide.nearest(positions[v as usize]).1, v))
            .collect();
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for &(along, v) in &keyed {
            positions[v as usize] = lines[s].beside(positions[v as usize], along);
        }
        // Two nodes at one place along the guide land on one point (where the cut
        // steps across a row of the mesh): the later is merged into the earlier (the
        // step's edge collapsed, the faces on it dropped below).
        let mut row: Vec<u32> = Vec::with_capacity(keyed.len());
        for (_, v) in keyed {
            match row.last() {
                Some(&u) if positions[u as usize].distance(positions[v as usize]) <= SAME_NODE => {
                    merged[v as usize] = u;
                }
                _ => row.push(v),
            }
        }
        *nodes = row;
        if site.closed {
            if let Some(&first) = nodes.first() {
                nodes.push(first);
            }
        }
    }
    let (faces, origin) = faces
        .into_iter()
        .zip(from_face)
        .map(|(t, f)| (t.map(|v| merged[v as usize]), f))
        .filter(|(t, _)| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .unzip();
    Cut {
        positions,
        faces,
        origin,
        rows: on_cut,
        split_faces,
        snapped_nodes,
    }
}
