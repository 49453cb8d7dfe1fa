//! Contacts and profiles (paper 000, section 2, steps 4 and 5): for each spine point,
//! the point of each base mesh nearest it (the foot of the normal in a face, the
//! nearest point on an edge, or a corner), the ball re-centred where the circles of
//! radius R about the two contacts cross in the plane of the centre and the contacts,
//! and the profile: the exact circular arc from contact to contact about that centre
//! (a rational quadratic).

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
    /// How far the spine point was from the re-centred centre (mm).
    pub moved: f64,
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
        });
        if step <= 1e-12 * radius {
            break;
        }
    }
    ball
}

/// How many times at most the ball is re-centred on the contacts found from its
/// last centre.
const RECENTRE_STEPS: usize = 16;

/// The profile of `ball`: the circular arc of radius `radius` about its centre from
/// its first contact to its second, the short way round (the arc facing the sharp
/// edge it rounds off).
pub fn profile(ball: &Ball, radius: f64) -> Option<NurbsCurve<DVec3>> {
    let x = (ball.contacts[0] - ball.centre).try_normalize()?;
    let to = (ball.contacts[1] - ball.centre).try_normalize()?;
    let y = (to - x * to.dot(x)).try_normalize()?;
    let sweep = to.dot(y).atan2(to.dot(x));
    circular_arc(ball.centre, x, y, radius, 0.0, sweep).ok()
}
