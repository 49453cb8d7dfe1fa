//! The hole's loop on its base surface (paper 002, section 3.2): each loop node
//! projected normally onto the surface by Newton-Raphson on `r_u . (r - P) = 0`,
//! `r_v . (r - P) = 0` (eq. 7-8), stopped when the point is on the surface or the
//! offset is square to both tangents (eq. 9): its `(u, v)`, the trim loop. The kernel's
//! point inversion ([`project_by_newton`](crate::geom::inversion::project_by_newton)) is
//! that iteration (the same equations in Piegl and Tiller, eq. 6.6-6.8, with the same
//! two tests), run on the Ferguson patches themselves and started from the point
//! straight above the node on the projection plane.

use glam::{DVec2, DVec3};

use super::base::BaseSurface;

/// The trim loop of the loop through `points` on `base`: each point's `(u, v)` by
/// normal projection, with its distance from the surface; where the projection fails
/// to converge, the `(u, v)` straight above it (along the plane's normal).
pub fn trim_loop(base: &BaseSurface, points: &[DVec3]) -> Vec<(DVec2, f64)> {
    points
        .iter()
        .map(|&p| {
            let above = base.uv_above(p);
            match base.foot(p, above) {
                Some(foot) => (DVec2::new(foot.u, foot.v), foot.distance),
                None => (above, base.point_at(above).distance(p)),
            }
        })
        .collect()
}
