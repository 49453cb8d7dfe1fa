//! A chain rounded at a constant radius, steps 1 to 8 put together (paper 000, section
//! 2): the balls along the spine, their profile arcs lofted into the rounding surface
//! (step 6), the mesh cut back to the trim lines (step 7: the faces reaching inside a
//! trim line removed, the nodes left on the cut snapped onto it) and the rounding
//! surface meshed row by row and stitched to the cut with a strip of triangles (step
//! 8), so the rounded mesh has no gap, no overlap and no new free edge.
//!
//! The radius may vary along the round ([`RadiusLaw`]): the spine and balls are found at
//! the mean radius and each ball then moved within its plane to its own (step 5).
//!
//! Left for later steps: open chains whose spine stops short of the mesh's boundary
//! (the paper extends the surface and trims it there), and cutting faces along a trim
//! line (the nodes next to it are moved onto it instead).

use glam::DVec3;

use super::base::{base_meshes, BaseError, BaseMeshes};
use super::chain::SharpChain;
use super::contact::{ball_in_plane, balls_at, profile, Ball};
use super::index::{PolylineIndex, TriangleGrid};
use super::offset::offset_faces;
use super::radius::RadiusLaw;
use super::spine::{base_triangles, offset_triangles, spine};
use super::{chain_polyline, polyline_nearest};
use crate::geom::construct::{loft, Loft};
use crate::geom::mesh::{Face, FaceId, Mesh, Topology, VertexId};
use crate::geom::surface::NurbsSurface;

/// The farthest apart (in radii) two neighbouring balls may stand: where the spine's
/// points are sparser (its offsets' triangles crossing in few places, as where a
/// coarse mesh twists), balls are placed between them.
const MAX_GAP: f64 = 0.5;

/// `balls` with more placed between any two farther apart than `gap`: each at its
/// share of the way from one centre to the next, re-centred on the base meshes
/// `bases` (dropped where no ball fits).
fn fill_gaps(
    balls: Vec<Ball>,
    bases: (&TriangleGrid, &TriangleGrid),
    radius: f64,
    gap: f64,
) -> Vec<Ball> {
    let mut out: Vec<Ball> = Vec::with_capacity(balls.len());
    for (k, ball) in balls.iter().enumerate() {
        if k > 0 {
            let from = balls[k - 1].centre;
            let d = from.distance(ball.centre);
            let extra = (d / gap).ceil() as usize;
            let between: Vec<DVec3> = (1..extra)
                .map(|i| from.lerp(ball.centre, i as f64 / extra as f64))
                .collect();
            out.extend(balls_at(&between, bases, radius).into_iter().flatten());
        }
        out.push(ball.clone());
    }
    out
}

/// How near (mm) two cut nodes moved onto a trim line must land to be merged.
const SAME_NODE: f64 = 1e-9;

/// The largest angle one row of the rounding surface's mesh turns through (radians).
const ROW_STEP: f64 = std::f64::consts::PI / 12.0;

/// A rounded mesh and what made it.
#[derive(Debug, Clone)]
pub struct Rounded {
    /// The mesh with the chain rounded: the base faces cut back to the trim lines, the
    /// rounding surface's strip stitched in.
    pub mesh: Mesh,
    /// The rounding surface: the profile arcs lofted, u across a profile (from the
    /// left base mesh to the right), v along the chain.
    pub surface: NurbsSurface,
    /// The trim lines: the balls' contacts on the left and on the right base mesh.
    pub trim_lines: [Vec<DVec3>; 2],
    /// The balls the surface was lofted through.
    pub balls: Vec<Ball>,
    /// How many faces of the rounded mesh are the rounding surface's (its last ones).
    pub round_faces: usize,
}

/// Why a chain could not be rounded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RoundError {
    /// The mesh has faces other than triangles.
    #[error("the mesh must be triangles only (triangulate it first)")]
    NotTriangles,
    /// The base meshes could not be split.
    #[error(transparent)]
    Base(#[from] BaseError),
    /// Too few balls fit between the base meshes, or one rolls off their edge: the
    /// radius is larger than they hold.
    #[error("the ball of radius {radius} mm does not fit between the faces beside the edge: it rolls off them")]
    NoRoom { radius: f64 },
    /// The rounding surface could not be lofted, or the mesh made.
    #[error("the rounding surface could not be made: {0}")]
    Surface(String),
}

/// Where a round is made: the two base meshes the ball rolls on, the line it runs
/// along, and the faces it replaces whatever the trim lines (none for a sharp chain;
/// an existing round's own faces when it is re-rounded).
#[derive(Debug, Clone, PartialEq)]
pub struct RoundSite {
    /// The faces on either side the ball touches.
    pub base: BaseMeshes,
    /// The line the round runs along, in order (the sharp chain's polyline, or the
    /// middle of an existing round), its first point again at its end when closed.
    /// Radii are placed along it by arc length.
    pub guide: Vec<DVec3>,
    /// Whether the round runs back round to its start.
    pub closed: bool,
    /// Whether the edge is convex (the faces turn away from their normals across
    /// it): the ball then rolls on the side the normals face away from.
    pub convex: bool,
    /// Faces removed whatever the trim lines: an existing round's.
    pub replaced: Vec<FaceId>,
}

/// The length of a polyline (mm).
pub fn polyline_length(points: &[DVec3]) -> f64 {
    points.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// Rounds `chain` of the triangle mesh `mesh` at `radius` (constant, or varying along
/// the chain from its first node), the rounding surface meshed within `tolerance` (mm)
/// of its arcs.
pub fn round_chain(
    mesh: &Mesh,
    topology: &Topology,
    chain: &SharpChain,
    radius: &RadiusLaw,
    tolerance: f64,
) -> Result<Rounded, RoundError> {
    if mesh.faces().iter().any(|f| !f.is_triangle()) {
        return Err(RoundError::NotTriangles);
    }
    let guide = chain_polyline(mesh, chain);
    let mean = radius.mean(polyline_length(&guide));
    let base = base_meshes(mesh, topology, chain, mean)?;
    let convex = chain
        .edges
        .first()
        .and_then(|&e| topology.signed_dihedral_angle(mesh, e))
        .is_some_and(|a| a > 0.0);
    let site = RoundSite {
        base,
        guide,
        closed: chain.closed,
        convex,
        replaced: Vec::new(),
    };
    round_site(mesh, topology, &site, radius, tolerance)
}

/// Rounds the triangle mesh `mesh` at `site` at `radius` (paper 000, steps 2 to 8):
/// the spine and balls found at the mean radius, each ball moved within its plane to
/// its own radius where the radius varies, the profiles lofted, the mesh cut back to
/// the trim lines and the round's strip stitched in.
pub fn round_site(
    mesh: &Mesh,
    topology: &Topology,
    site: &RoundSite,
    radius: &RadiusLaw,
    tolerance: f64,
) -> Result<Rounded, RoundError> {
    if mesh.faces().iter().any(|f| !f.is_triangle()) {
        return Err(RoundError::NotTriangles);
    }
    let length = polyline_length(&site.guide);
    let mean = radius.mean(length);
    let (smallest, _) = radius.range(length);
    let base = &site.base;
    // The ball rolls on the side the normals face where the edge is concave, on the
    // other where it is convex.
    let side = if site.convex { -mean } else { mean };
    let offsets = [&base.left, &base.right].map(|f| offset_faces(mesh, topology, f, side));
    let tri = offsets.each_ref().map(|o| offset_triangles(mesh, o));
    let bases = [&base.left, &base.right].map(|f| TriangleGrid::new(base_triangles(mesh, f)));
    let centres = spine(
        &site.guide,
        (&tri[0], &tri[1]),
        (&bases[0], &bases[1]),
        mean,
    );
    // Each ball at the mean radius, then moved to its own where the radius varies.
    let guide = PolylineIndex::new(&site.guide);
    let along = |p: DVec3| guide.nearest(p).1;
    let at_mean: Vec<Ball> = balls_at(&centres, (&bases[0], &bases[1]), mean)
        .into_iter()
        .flatten()
        .collect();
    let at_mean = fill_gaps(at_mean, (&bases[0], &bases[1]), mean, MAX_GAP * smallest);
    let mut all: Vec<Ball> = Vec::new();
    for ball in at_mean {
        let own = radius.at(along(ball.centre));
        if (own - mean).abs() <= 1e-9 * mean {
            all.push(ball);
        } else {
            let moved = ball_in_plane(&ball, own, (&bases[0], &bases[1]))
                .ok_or(RoundError::NoRoom { radius: own })?;
            all.push(moved);
        }
    }
    // The balls, a quarter radius apart at least (the spine's points crowd where the
    // offsets' edges cross), the last kept.
    let mut balls: Vec<Ball> = Vec::new();
    for (k, ball) in all.iter().enumerate() {
        let far = balls
            .last()
            .is_none_or(|last| last.centre.distance(ball.centre) >= 0.25 * smallest);
        if far {
            balls.push(ball.clone());
        } else if k + 1 == all.len() && balls.len() > 1 {
            // The last ball ends the surface: it takes the place of the one before.
            balls.pop();
            balls.push(ball.clone());
        }
    }
    if balls.len() < 2 {
        return Err(RoundError::NoRoom { radius: mean });
    }
    // A ball touching the mesh's free boundary (but at an open round's ends, where the
    // round itself meets it) has rolled off its base mesh: the radius is too large.
    let free: Vec<(DVec3, DVec3)> = topology
        .free_edges()
        .into_iter()
        .filter_map(|e| {
            let [a, b] = topology.edge_vertices(e);
            Some((mesh.position(a)?, mesh.position(b)?))
        })
        .collect();
    let on_free = |q: DVec3| {
        free.iter()
            .any(|&(a, b)| polyline_nearest(&[a, b], q).0 <= 1e-9 * mean.max(1.0))
    };
    let inner = if site.closed {
        &balls[..]
    } else {
        &balls[1..balls.len() - 1]
    };
    if let Some(b) = inner
        .iter()
        .find(|b| b.contacts.iter().any(|&q| on_free(q)))
    {
        return Err(RoundError::NoRoom { radius: b.radius });
    }
    let mut profiles = Vec::with_capacity(balls.len() + 1);
    for b in &balls {
        profiles.push(profile(b).ok_or(RoundError::NoRoom { radius: b.radius })?);
    }
    let mut trim_lines = [0, 1].map(|s| balls.iter().map(|b| b.contacts[s]).collect::<Vec<_>>());
    if site.closed {
        profiles.push(profiles[0].clone());
        for line in &mut trim_lines {
            line.push(line[0]);
        }
    }
    let surface =
        loft(&profiles, &Loft::default()).map_err(|e| RoundError::Surface(e.to_string()))?;
    let Cut {
        mut positions,
        mut faces,
        rows,
    } = cut_to_trim_lines(mesh, topology, site, &guide, &trim_lines);
    if rows.iter().any(|row| row.len() < 2) {
        return Err(RoundError::Surface(
            "cutting the mesh back to a trim line left no edge along it".into(),
        ));
    }
    // The rows of the rounding surface's mesh between the two cut rows.
    let sweep = balls
        .iter()
        .map(|b| (b.contacts[0] - b.centre).angle_between(b.contacts[1] - b.centre))
        .fold(0.0, f64::max);
    let by_sag = 2.0 * (1.0 - (tolerance / smallest).min(1.0)).acos();
    let steps = (sweep / ROW_STEP.min(by_sag.max(1e-3))).ceil().max(2.0) as usize;
    let along = rows[0].len().max(rows[1].len()).max(2);
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    let mut row_ids: Vec<Vec<u32>> = vec![rows[0].clone()];
    for k in 1..steps {
        let u = u0 + (u1 - u0) * k as f64 / steps as f64;
        // Round a closed chain the row's last point is its first: the same node.
        let distinct = if site.closed { along - 1 } else { along };
        let mut ids: Vec<u32> = (0..distinct)
            .map(|j| {
                let v = v0 + (v1 - v0) * j as f64 / (along - 1) as f64;
                positions.push(surface.point_at(u, v));
                (positions.len() - 1) as u32
            })
            .collect();
        if site.closed {
            ids.push(ids[0]);
        }
        row_ids.push(ids);
    }
    row_ids.push(rows[1].clone());
    let first_round = faces.len();
    for pair in row_ids.windows(2) {
        zip_rows(&positions, &pair[0], &pair[1], &mut faces);
    }
    // Wound as the cut mesh: the first round face that holds a cut edge runs it the
    // other way from the cut face beside it.
    orient_round(&mut faces, first_round);
    let round_faces = faces.len() - first_round;
    // The nodes the cut left unused dropped, the rest kept in order.
    let mut used = vec![false; positions.len()];
    for t in &faces {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let mut new_id = vec![u32::MAX; positions.len()];
    let mut kept = Vec::with_capacity(positions.len());
    for (i, p) in positions.iter().enumerate() {
        if used[i] {
            new_id[i] = kept.len() as u32;
            kept.push(*p);
        }
    }
    let faces: Vec<Face> = faces
        .into_iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| new_id[i as usize]);
            Face::triangle(a, b, c)
        })
        .collect();
    let mesh = Mesh::new(kept, faces).map_err(|e| RoundError::Surface(e.to_string()))?;
    Ok(Rounded {
        mesh,
        surface,
        trim_lines,
        balls,
        round_faces,
    })
}

/// The mesh cut back to the trim lines: its positions and triangles (nodes inside the
/// round's region left unused), the faces replaced and those with a node inside a trim
/// line removed, and the nodes left on each cut moved onto its trim line; and each
/// cut's nodes, ordered along the guide. A node of a base mesh is inside when it lies
/// nearer the guide than the contact (on its side) nearest it; a node of a replaced
/// face on no base face is inside.
fn cut_to_trim_lines(
    mesh: &Mesh,
    topology: &Topology,
    site: &RoundSite,
    guide: &PolylineIndex,
    trim_lines: &[Vec<DVec3>; 2],
) -> Cut {
    let mut positions = mesh.positions().to_vec();
    let to_guide = |p: DVec3| guide.nearest(p).0;
    // Each trim line's points: where along the guide they stand, and how far off it.
    let line_along: [Vec<f64>; 2] = trim_lines
        .each_ref()
        .map(|line| line.iter().map(|&q| guide.nearest(q).1).collect());
    let mut inside = vec![false; positions.len()];
    let mut side_of = vec![None; positions.len()];
    for (s, faces) in [&site.base.left, &site.base.right].iter().enumerate() {
        for &f in faces.iter() {
            let Some(face) = mesh.face(f) else { continue };
            for v in face.vertices() {
                if side_of[v.index()].is_some() {
                    continue;
                }
                let p = positions[v.index()];
                let (off, along, _) = guide.nearest(p);
                // The trim line beside the node: at its place along the guide, or (past
                // the line's ends) its nearest point.
                let line = &trim_lines[s];
                let beside = trim_point_along(line, &line_along[s], along)
                    .unwrap_or_else(|| polyline_nearest(line, p).2);
                if off < to_guide(beside) * (1.0 - 1e-9) {
                    inside[v.index()] = true;
                }
                side_of[v.index()].get_or_insert(s);
            }
        }
    }
    let mut gone = vec![false; mesh.face_count()];
    for &f in &site.replaced {
        gone[f.index()] = true;
        if let Some(face) = mesh.face(f) {
            for v in face.vertices() {
                if side_of[v.index()].is_none() {
                    inside[v.index()] = true;
                }
            }
        }
    }
    let goes = |f: crate::geom::mesh::FaceId, face: &Face| {
        gone[f.index()] || face.vertices().any(|v| inside[v.index()])
    };
    let kept: Vec<[u32; 3]> = mesh
        .face_ids()
        .zip(mesh.faces())
        .filter(|(id, f)| !goes(*id, f))
        .filter_map(|(_, f)| match f.indices() {
            &[a, b, c] => Some([a, b, c]),
            _ => None,
        })
        .collect();
    // The cut: edges of kept faces whose other face went.
    let removed_beside = |a: u32, b: u32| -> bool {
        let Some(e) = topology.find_edge(VertexId(a), VertexId(b)) else {
            return false;
        };
        topology
            .edge_faces(e)
            .any(|g| mesh.face(g).is_some_and(|face| goes(g, &face)))
    };
    let mut on_cut: [Vec<u32>; 2] = [Vec::new(), Vec::new()];
    let mut merged: Vec<u32> = (0..positions.len() as u32).collect();
    // Only faces with a base mesh's node can lie on a cut.
    for t in kept
        .iter()
        .filter(|t| t.iter().any(|&v| side_of[v as usize].is_some()))
    {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if removed_beside(a, b) {
                for v in [a, b] {
                    if let Some(s) = side_of[v as usize] {
                        if !on_cut[s].contains(&v) {
                            on_cut[s].push(v);
                        }
                    }
                }
            }
        }
    }
    // Each cut's nodes along the guide, moved onto their trim line at the same place
    // along the guide (so they keep their order, and no face beside the cut turns
    // over where the trim line runs slant to the guide).
    for (s, nodes) in on_cut.iter_mut().enumerate() {
        let mut keyed: Vec<(f64, u32)> = nodes
            .iter()
            .map(|&v| (guide.nearest(positions[v as usize]).1, v))
            .collect();
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let line = &trim_lines[s];
        for &(along, v) in &keyed {
            let p = positions[v as usize];
            positions[v as usize] = trim_point_along(line, &line_along[s], along)
                .unwrap_or_else(|| polyline_nearest(line, p).2);
        }
        // Where the cut steps across a row of the mesh, two of its nodes lie at one
        // place along the guide and land on one point: the later is merged into the
        // earlier (the step's edge collapsed, the faces on it dropped below).
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
    let faces = kept
        .into_iter()
        .map(|t| t.map(|v| merged[v as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect();
    Cut {
        positions,
        faces,
        rows: on_cut,
    }
}

/// The point of the trim line `line` (its points at `line_along` along the guide) at
/// `along` along the guide, between the two points either side of it; `None` outside
/// the stretch of the guide the line runs beside, or where it doubles back.
fn trim_point_along(line: &[DVec3], line_along: &[f64], along: f64) -> Option<DVec3> {
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

/// The mesh cut back to its trim lines: its positions (the cut's nodes moved onto the
/// trim lines), the triangles kept, and each cut's nodes in order along the chain.
struct Cut {
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    rows: [Vec<u32>; 2],
}

/// Triangles between two rows of nodes running the same way (a strip), each node
/// taken in turn by how far along its row it lies.
fn zip_rows(positions: &[DVec3], a: &[u32], b: &[u32], faces: &mut Vec<[u32; 3]>) {
    let fractions = |row: &[u32]| -> Vec<f64> {
        let mut run = vec![0.0];
        for w in row.windows(2) {
            let d = positions[w[0] as usize].distance(positions[w[1] as usize]);
            run.push(run[run.len() - 1] + d);
        }
        let total = run[run.len() - 1].max(f64::MIN_POSITIVE);
        run.into_iter().map(|r| r / total).collect()
    };
    let (fa, fb) = (fractions(a), fractions(b));
    let (mut i, mut j) = (0, 0);
    while i + 1 < a.len() || j + 1 < b.len() {
        let take_a = j + 1 >= b.len() || (i + 1 < a.len() && fa[i + 1] <= fb[j + 1]);
        if take_a {
            faces.push([a[i], a[i + 1], b[j]]);
            i += 1;
        } else {
            faces.push([a[i], b[j + 1], b[j]]);
            j += 1;
        }
    }
}

/// Winds the faces from `first` on (the round's strip, all wound alike) against the
/// faces before them: where a round face shares an edge with a cut face, the two must
/// run it opposite ways; if they run it the same way, every round face is turned.
fn orient_round(faces: &mut [[u32; 3]], first: usize) {
    let (cut, round) = faces.split_at_mut(first);
    let runs = |t: &[u32; 3], a: u32, b: u32| (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b);
    let mut same = None;
    'search: for r in round.iter() {
        for k in 0..3 {
            let (a, b) = (r[k], r[(k + 1) % 3]);
            for c in cut.iter() {
                if runs(c, a, b) {
                    same = Some(true);
                    break 'search;
                }
                if runs(c, b, a) {
                    same = Some(false);
                    break 'search;
                }
            }
        }
    }
    if same == Some(true) {
        for r in round.iter_mut() {
            r.swap(1, 2);
        }
    }
}
