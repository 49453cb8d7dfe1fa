//! Contacts and profiles (paper 000, section 2, steps 4 and 5): for each spine point,
//! the point of each base mesh nearest it (the foot of the normal in a face, the
//! nearest point on an edge, or a corner), the ball re-centred where the circles of
//! radius R about the two contacts cross in the plane of the centre and the contacts,
//! and the profile: the exact circular arc from contact to contact about that centre
//! (a rational quadratic). For a variable radius, the ball found at the mean radius is
//! moved within the plane of its centre and contacts until it touches the base meshes'
//! sections in that plane at its true radius.

use glam::DVec3;

use super::index::TriangleGrid;
use super::spine::Region;
use crate::geom::arc::circular_arc;
use crate::geom::curve::NurbsCurve;

/// A ball placed on the spine: its centre, touching both base meshes at R.
#[derive(Debug, Clone, PartialEq)]
pub struct Ball {
    /// Its centre, re-centred to lie R from both contacts (the contacts found again
    /// from each new centre until it stays put).
    pub centre: DVec3,
    /// Where it touches each base mesh.
    pub contacts: [DVec3; 2],
    /// Which part of a base triangle each contact lies on.
    pub regions: [Region; 2],
    /// How far the spine point was from the re-centred centre (mm), at the mean
    /// radius (a variable radius's move to the ball's own is not counted).
    pub moved: f64,
    /// Its radius (mm).
    pub radius: f64,
}

/// The ball of radius `radius` at spine point `at`, touching the base meshes `bases`
/// (their triangles): `None` when a base mesh is empty or the two contacts lie more
/// than 2R apart (no circle of radius R touches both).
pub fn ball_at(at: DVec3, bases: (&[[DVec3; 3]], &[[DVec3; 3]]), radius: f64) -> Option<Ball> {
    let grids = (
        TriangleGrid::new(bases.0.to_vec()),
        TriangleGrid::new(bases.1.to_vec()),
    );
    ball_on(at, (&grids.0, &grids.1), radius)
}

/// The balls of radius `radius` at each spine point of `points` on the indexed base
/// meshes `bases`, as [`ball_at`] finds them.
pub fn balls_at(
    points: &[DVec3],
    bases: (&TriangleGrid, &TriangleGrid),
    radius: f64,
) -> Vec<Option<Ball>> {
    points.iter().map(|&p| ball_on(p, bases, radius)).collect()
}

/// [`ball_at`] on indexed base meshes.
fn ball_on(at: DVec3, bases: (&TriangleGrid, &TriangleGrid), radius: f64) -> Option<Ball> {
    let mut centre = at;
    let mut ball = None;
    // Re-centred, the ball's nearest points move a little on a curved base: the
    // contacts are found again from the new centre until it stays put.
    for _ in 0..RECENTRE_STEPS {
        let (q1, _, r1) = bases.0.nearest(centre)?;
        let (q2, _, r2) = bases.1.nearest(centre)?;
        // In the plane of the centre and the contacts: the point R from both.
        let half = 0.5 * q1.distance(q2);
        if half > radius || half == 0.0 {
            return None;
        }
        let mid = 0.5 * (q1 + q2);
        let along = (q2 - q1) / (2.0 * half);
        let towards = (centre - mid) - along * (centre - mid).dot(along);
        let out = towards.try_normalize()?;
        let next = mid + out * (radius * radius - half * half).sqrt();
        let step = next.distance(centre);
        centre = next;
        ball = Some(Ball {
            centre,
            contacts: [q1, q2],
            regions: [r1, r2],
            moved: centre.distance(at),
            radius,
        });
        if step <= 1e-12 * radius {
            break;
        }
    }
    ball
}

/// `ball` moved to touch the base meshes `bases` at `radius` instead, within the
/// plane of its centre and contacts (paper 000, step 5 for a variable radius): the
/// base meshes cut by that plane, the ball's contacts with the cuts found again from
/// each new centre until it stays put, and then re-centred in 3-D at that radius.
/// `None` when the cuts hold no such ball.
pub fn ball_in_plane(
    ball: &Ball,
    radius: f64,
    bases: (&TriangleGrid, &TriangleGrid),
) -> Option<Ball> {
    let c = ball.centre;
    let normal = (ball.contacts[0] - c)
        .cross(ball.contacts[1] - c)
        .try_normalize()?;
    // The cuts within reach of the ball's new contacts: first near (enough where the
    // faces meet at a wide angle, as a die shoulder's do), then, for a sharp corner
    // where the centre moves far along it, farther.
    let near = 2.0 * radius.max(ball.radius) + 2.0 * (radius - ball.radius).abs();
    [near, 4.0 * near].into_iter().find_map(|reach| {
        let cuts = [bases.0, bases.1].map(|grid| plane_cut(grid, c, normal, reach));
        in_plane(ball, radius, &cuts, bases)
    })
}

/// [`ball_in_plane`] on the cuts `cuts` of the base meshes.
fn in_plane(
    ball: &Ball,
    radius: f64,
    cuts: &[Vec<(DVec3, DVec3)>; 2],
    bases: (&TriangleGrid, &TriangleGrid),
) -> Option<Ball> {
    let c = ball.centre;
    // Each step moves the centre so that it would stand `radius` off the planes
    // tangent to the cuts at the contacts found from it: along the contact normals,
    // by how far each distance falls short of the radius.
    let mut centre = c;
    let mut moved = None;
    for _ in 0..RECENTRE_STEPS * 2 {
        let (q1, r1) = nearest_on_segments(&cuts[0], centre)?;
        let (q2, r2) = nearest_on_segments(&cuts[1], centre)?;
        let (d1, d2) = (centre.distance(q1), centre.distance(q2));
        let n1 = (centre - q1).try_normalize()?;
        let n2 = (centre - q2).try_normalize()?;
        let (e1, e2) = (radius - d1, radius - d2);
        moved = Some(Ball {
            centre,
            contacts: [q1, q2],
            regions: [r1, r2],
            moved: ball.moved,
            radius,
        });
        if e1.abs().max(e2.abs()) <= 1e-12 * radius {
            break;
        }
        // delta = a n1 + b n2 with n1·delta = e1 and n2·delta = e2.
        let cos = n1.dot(n2);
        let det = 1.0 - cos * cos;
        if det < 1e-12 {
            return None;
        }
        let a = (e1 - cos * e2) / det;
        let b = (e2 - cos * e1) / det;
        centre += a * n1 + b * n2;
    }
    let ball = moved?;
    // Unconverged (the cuts end before the ball touches them at its radius): none.
    let off = ball
        .contacts
        .iter()
        .map(|&q| (q.distance(ball.centre) - radius).abs())
        .fold(0.0, f64::max);
    if off > 1e-6 * radius {
        return None;
    }
    // Then re-centred in 3-D at its own radius, as step 4 does at the mean: on a
    // faceted mesh the plane through the mean ball's contacts may cross a face
    // slantwise, and the ball's nearest points lie a little out of it; re-centred,
    // each contact is the foot of the ball's normal on its face.
    Some(match ball_on(ball.centre, bases, radius) {
        Some(b) => Ball {
            moved: ball.moved,
            ..b
        },
        None => ball,
    })
}

/// The segments where the plane through `at` with unit `normal` cuts the triangles of
/// `grid` within `reach` of `at`, each with the region of its triangle it lies in
/// (a face, or an edge when the plane runs along one).
fn plane_cut(grid: &TriangleGrid, at: DVec3, normal: DVec3, reach: f64) -> Vec<(DVec3, DVec3)> {
    let mut segments = Vec::new();
    for k in grid.candidates(at - DVec3::splat(reach), at + DVec3::splat(reach)) {
        let t = &grid.triangles[k as usize];
        let d = t.map(|p| normal.dot(p - at));
        let mut hits: Vec<DVec3> = Vec::with_capacity(3);
        for i in 0..3 {
            let j = (i + 1) % 3;
            if d[i] == 0.0 {
                hits.push(t[i]);
            } else if d[i] * d[j] < 0.0 {
                hits.push(t[i] + (t[j] - t[i]) * (d[i] / (d[i] - d[j])));
            }
        }
        if let [p, q, ..] = hits[..] {
            if p != q {
                segments.push((p, q));
            }
        }
    }
    segments
}

/// The point of `segments` nearest `p`, with the region it lies in on its triangle:
/// where the plane crosses the triangle, so within its face.
fn nearest_on_segments(segments: &[(DVec3, DVec3)], p: DVec3) -> Option<(DVec3, Region)> {
    segments
        .iter()
        .map(|&(a, b)| super::polyline_nearest(&[a, b], p))
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, _, q)| (q, Region::Face))
}

/// How many times at most the ball is re-centred on the contacts found from its
/// last centre.
const RECENTRE_STEPS: usize = 16;

/// The profile of `ball`: the circular arc of its radius about its centre from its
/// first contact to its second, the short way round (the arc facing the sharp edge it
/// rounds off).
pub fn profile(ball: &Ball) -> Option<NurbsCurve<DVec3>> {
    let radius = ball.radius;
    let x = (ball.contacts[0] - ball.centre).try_normalize()?;
    let to = (ball.contacts[1] - ball.centre).try_normalize()?;
    let y = (to - x * to.dot(x)).try_normalize()?;
    let sweep = to.dot(y).atan2(to.dot(x));
    circular_arc(ball.centre, x, y, radius, 0.0, sweep).ok()
}
