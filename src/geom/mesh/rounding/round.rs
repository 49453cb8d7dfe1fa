//! A chain rounded, steps 1 to 8 put together (paper 000, section 2): the balls along
//! the spine, their profile arcs lofted into the rounding surface (step 6; an open
//! round's surface carried on past the mesh's boundary at each end and trimmed where
//! the boundary crosses it), the mesh cut along the trim lines (step 7, [`super::cut`])
//! and the rounding surface meshed row by row and stitched to the cut with a strip of
//! triangles (step 8), so the rounded mesh has no gap, no overlap and no new free edge.
//!
//! The radius may vary along the round ([`RadiusLaw`]): the spine and balls are found at
//! the mean radius and each ball then moved within its plane to its own (step 5).

use glam::DVec3;

use super::base::{base_meshes, BaseError, BaseMeshes};
use super::chain::SharpChain;
use super::contact::{ball_in_plane, balls_at, profile, Ball};
use super::cut::{cut_to_trim_lines, Cut};
use super::index::{PolylineIndex, TriangleGrid};
use super::offset::offset_faces;
use super::radius::RadiusLaw;
use super::spine::{base_triangles, offset_triangles, spine};
use super::{chain_polyline, polyline_nearest};
use crate::geom::construct::{loft, Loft};
use crate::geom::mesh::{Face, FaceId, Mesh, Topology};
use crate::geom::surface::NurbsSurface;

/// The farthest apart (in radii) two neighbouring balls may stand: where the spine's
/// points are sparser (its offsets' triangles crossing in few places, as where a
/// coarse mesh twists), balls are placed between them.
const MAX_GAP: f64 = 0.5;

/// `balls` with those nearer than `gap` to the last one kept dropped; the last ball
/// always kept (it ends the surface: it takes the place of the one before).
fn thin_out(balls: Vec<Ball>, gap: f64) -> Vec<Ball> {
    let count = balls.len();
    let mut out: Vec<Ball> = Vec::with_capacity(count);
    for (k, ball) in balls.into_iter().enumerate() {
        let far = out
            .last()
            .is_none_or(|last| last.centre.distance(ball.centre) >= gap);
        if far {
            out.push(ball);
        } else if k + 1 == count && out.len() > 1 {
            out.pop();
            out.push(ball);
        }
    }
    out
}

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

/// Where the mesh's boundary crosses an open round's end: a plane, its normal towards
/// the round.
#[derive(Debug, Clone, Copy)]
struct EndPlane {
    point: DVec3,
    normal: DVec3,
}

impl EndPlane {
    /// How far `p` lies on the round's side of the plane (negative past it).
    fn side(&self, p: DVec3) -> f64 {
        self.normal.dot(p - self.point)
    }
}

/// The plane the mesh's boundary lies in at an open round's end `at` (the guide's end,
/// `outward` the way the guide leaves there): fitted to the nodes of the free edges
/// within `reach` of it that run across the round (the normal of least spread), or,
/// where those do not span a plane, square to the guide.
fn end_plane(mesh: &Mesh, topology: &Topology, at: DVec3, outward: DVec3, reach: f64) -> EndPlane {
    let out = outward.normalize_or_zero();
    let square = EndPlane {
        point: at,
        normal: -out,
    };
    // The free edges running across the round there (more across than along it): the
    // mesh's edges beside the round, running along it, are no part of its end.
    let mut nodes: Vec<DVec3> = topology
        .free_edges()
        .into_iter()
        .filter_map(|e| {
            let [a, b] = topology.edge_vertices(e);
            let (p, q) = (mesh.position(a)?, mesh.position(b)?);
            let across =
                (q - p).normalize_or_zero().dot(out).abs() < std::f64::consts::FRAC_1_SQRT_2;
            (across && (p.distance(at) <= reach || q.distance(at) <= reach)).then_some([p, q])
        })
        .flatten()
        .collect();
    nodes.sort_by(|a, b| {
        a.x.total_cmp(&b.x)
            .then(a.y.total_cmp(&b.y))
            .then(a.z.total_cmp(&b.z))
    });
    nodes.dedup();
    if nodes.len() < 3 {
        return square;
    }
    let centre = nodes.iter().copied().sum::<DVec3>() / nodes.len() as f64;
    let mut spread = nalgebra::Matrix3::<f64>::zeros();
    for p in &nodes {
        let d = nalgebra::Vector3::new(p.x - centre.x, p.y - centre.y, p.z - centre.z);
        spread += d * d.transpose();
    }
    let eigen = nalgebra::SymmetricEigen::new(spread);
    let order: Vec<usize> = {
        let mut o = vec![0, 1, 2];
        o.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
        o
    };
    // Nodes along one line (or one point) pin no plane.
    if eigen.eigenvalues[order[1]] <= 1e-12 * eigen.eigenvalues[order[2]].max(f64::MIN_POSITIVE) {
        return square;
    }
    let n = eigen.eigenvectors.column(order[0]);
    let mut normal = DVec3::new(n[0], n[1], n[2]).normalize_or_zero();
    if normal.dot(out) > 0.0 {
        normal = -normal;
    }
    // A boundary running along the round, not across it, is no end.
    if normal.dot(-out) < 0.25 {
        return square;
    }
    EndPlane {
        point: centre,
        normal,
    }
}

/// The way a round carries on past its end ball `end`, out of the round (the way
/// `outward` points): along both faces it touches there (square to both contact
/// directions), so carried balls keep touching the faces' planes; `outward` itself
/// where the two contacts lie in line with the centre.
fn carry_direction(end: &Ball, outward: DVec3) -> DVec3 {
    let outward = outward.normalize_or_zero();
    let along = (end.contacts[0] - end.centre)
        .cross(end.contacts[1] - end.centre)
        .normalize_or_zero();
    match along.dot(outward) {
        d if along == DVec3::ZERO || d.abs() < 0.5 => outward,
        d if d < 0.0 => -along,
        _ => along,
    }
}

/// Balls carried on from `end` by `step` at a time (along the guide, out of the round),
/// until one's profile lies wholly past `plane`; none when `end`'s already does. At
/// most 40.
fn carry_on(end: &Ball, step: DVec3, plane: &EndPlane) -> Vec<Ball> {
    let past = |b: &Ball| {
        profile(b)
            .is_some_and(|arc| (0..=8).all(|k| plane.side(arc.point_at(k as f64 / 8.0)) < 0.0))
    };
    let mut out = Vec::new();
    let mut last = end.clone();
    while !past(&last) && out.len() < 40 {
        last = Ball {
            centre: last.centre + step,
            contacts: last.contacts.map(|q| q + step),
            ..last
        };
        out.push(last.clone());
    }
    out
}

/// The v at which row `u` of `surface` crosses `plane`, between `from` (past the plane)
/// and `to` (on the round's side), by bisection; `None` when the two do not bracket it.
fn plane_crossing(
    surface: &NurbsSurface,
    u: f64,
    (from, to): (f64, f64),
    plane: &EndPlane,
) -> Option<f64> {
    let side = |v: f64| plane.side(surface.point_at(u, v));
    let (mut out, mut inside) = (from, to);
    if side(out) >= 0.0 || side(inside) < 0.0 {
        return None;
    }
    for _ in 0..60 {
        let mid = 0.5 * (out + inside);
        if side(mid) < 0.0 {
            out = mid;
        } else {
            inside = mid;
        }
    }
    Some(inside)
}

/// How many points of each edge of the rounding surface the cut follows between two
/// neighbouring profiles: the chord between them then parts from the edge by 1/256 of
/// the chord between the contacts themselves.
const TRIM_SAMPLES: usize = 16;

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
    /// The trim lines: where the mesh was cut on the left and on the right base mesh
    /// (the rounding surface's edges, through the balls' contacts), the cut's nodes in
    /// order along the round.
    pub trim_lines: [Vec<DVec3>; 2],
    /// The balls rolled along the round, in order.
    pub balls: Vec<Ball>,
    /// The balls the surface was lofted through: [`Rounded::balls`] and, for an open
    /// round, the balls carried on past its ends until the mesh's boundary is passed.
    pub lofted: Vec<Ball>,
    /// How many faces of the rounded mesh are the rounding surface's (its last ones).
    pub round_faces: usize,
    /// How many of the mesh's faces the trim lines split (step 7).
    pub split_faces: usize,
    /// How many nodes lay so near a trim line that they were snapped onto it (step 7).
    pub snapped_nodes: usize,
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
    // The balls at the mean radius, a quarter radius apart at least (the spine's points
    // crowd where the offsets' edges cross), then half a radius apart at most (more
    // placed where they are sparse), each then moved to its own radius where the
    // radius varies.
    let at_mean: Vec<Ball> = balls_at(&centres, (&bases[0], &bases[1]), mean)
        .into_iter()
        .flatten()
        .collect();
    let at_mean = thin_out(at_mean, 0.25 * smallest);
    let at_mean = fill_gaps(at_mean, (&bases[0], &bases[1]), mean, MAX_GAP * smallest);
    let mut balls: Vec<Ball> = Vec::with_capacity(at_mean.len());
    for ball in at_mean {
        let own = radius.at(along(ball.centre));
        if (own - mean).abs() <= 1e-9 * mean {
            balls.push(ball);
        } else {
            let moved = ball_in_plane(&ball, own, (&bases[0], &bases[1]))
                .ok_or(RoundError::NoRoom { radius: own })?;
            balls.push(moved);
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
    // Step 6 for an open round: the surface carried on past each end of the mesh (balls
    // carried on along the guide until their profiles lie wholly past the boundary
    // there), then trimmed where the boundary crosses it (each end's plane).
    let n = site.guide.len();
    let guide_out = [
        site.guide[0] - site.guide[1],
        site.guide[n - 1] - site.guide[n - 2],
    ];
    let end_balls = [&balls[0], &balls[balls.len() - 1]];
    let outward = [0, 1].map(|k| carry_direction(end_balls[k], guide_out[k]));
    let ends = (!site.closed).then(|| {
        let reach = 2.0 * radius.range(length).1;
        [
            end_plane(mesh, topology, site.guide[0], outward[0], reach),
            end_plane(mesh, topology, site.guide[n - 1], outward[1], reach),
        ]
    });
    let mut carried: Vec<Ball> = balls.clone();
    let mut extension = 0.0f64;
    if let Some(planes) = &ends {
        let step = 0.5 * smallest;
        let before = carry_on(&balls[0], outward[0] * step, &planes[0]);
        let after = carry_on(&balls[balls.len() - 1], outward[1] * step, &planes[1]);
        extension = step * before.len().max(after.len()) as f64;
        carried = before
            .into_iter()
            .rev()
            .chain(balls.iter().cloned())
            .chain(after)
            .collect();
    }
    let mut profiles = Vec::with_capacity(carried.len() + 1);
    for b in &carried {
        profiles.push(profile(b).ok_or(RoundError::NoRoom { radius: b.radius })?);
    }
    if site.closed {
        profiles.push(profiles[0].clone());
    }
    let surface =
        loft(&profiles, &Loft::default()).map_err(|e| RoundError::Surface(e.to_string()))?;
    // The mesh is cut along the rounding surface's own edges (the loft through the
    // balls' contacts, sampled finely between them), so the cut's nodes lie on the
    // surface's edge, not on chords between contacts.
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    let samples = (profiles.len() - 1) * TRIM_SAMPLES;
    let cut_lines = [u0, u1].map(|u| {
        (0..=samples)
            .map(|j| surface.point_at(u, v0 + (v1 - v0) * j as f64 / samples as f64))
            .collect::<Vec<DVec3>>()
    });
    // The guide carried on as far as the surface, so the places along it of the nodes
    // past the round's last balls fall on the carried part of the cut lines.
    let long_guide = if site.closed || extension == 0.0 {
        site.guide.clone()
    } else {
        let reach = extension + smallest;
        std::iter::once(site.guide[0] + outward[0] * reach)
            .chain(site.guide.iter().copied())
            .chain(std::iter::once(site.guide[n - 1] + outward[1] * reach))
            .collect()
    };
    let guide = PolylineIndex::new(&long_guide);
    let Cut {
        mut positions,
        mut faces,
        origin,
        rows,
        split_faces,
        snapped_nodes,
    } = cut_to_trim_lines(mesh, topology, site, &guide, &cut_lines);
    if rows.iter().any(|row| row.len() < 2) {
        return Err(RoundError::Surface(
            "cutting the mesh back to a trim line left no edge along it".into(),
        ));
    }
    // The trim lines as cut: each cut's nodes in order along the round.
    let trim_lines = rows.each_ref().map(|row| {
        row.iter()
            .map(|&v| positions[v as usize])
            .collect::<Vec<DVec3>>()
    });
    // The rows of the rounding surface's mesh between the two cut rows.
    let sweep = balls
        .iter()
        .map(|b| (b.contacts[0] - b.centre).angle_between(b.contacts[1] - b.centre))
        .fold(0.0, f64::max);
    let by_sag = 2.0 * (1.0 - (tolerance / smallest).min(1.0)).acos();
    let steps = (sweep / ROW_STEP.min(by_sag.max(1e-3))).ceil().max(2.0) as usize;
    let along = rows[0].len().max(rows[1].len()).max(2);
    let mut row_ids: Vec<Vec<u32>> = vec![rows[0].clone()];
    for k in 1..steps {
        let u = u0 + (u1 - u0) * k as f64 / steps as f64;
        // Round a closed chain the row's last point is its first: the same node.
        let distinct = if site.closed { along - 1 } else { along };
        // An open round's row runs between its ends' planes.
        let (va, vb) = match &ends {
            Some([first, last]) => (
                plane_crossing(&surface, u, (v0, 0.5 * (v0 + v1)), first).unwrap_or(v0),
                plane_crossing(&surface, u, (v1, 0.5 * (v0 + v1)), last).unwrap_or(v1),
            ),
            None => (v0, v1),
        };
        let mut ids: Vec<u32> = (0..distinct)
            .map(|j| {
                let v = va + (vb - va) * j as f64 / (along - 1) as f64;
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
    // The cut faces keep the groups of the faces they came from; the round's own
    // faces (after them) join none.
    let rounded = Mesh::new(kept, faces)
        .map_err(|e| RoundError::Surface(e.to_string()))?
        .with_groups_of(mesh, &origin);
    Ok(Rounded {
        mesh: rounded,
        surface,
        trim_lines,
        balls,
        lofted: carried,
        round_faces,
        split_faces,
        snapped_nodes,
    })
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
