//! Continuity between two B-spline patches that share a boundary: the control-net test
//! of eq. 4 (paper 001) and the measured gap and normal jump.
//!
//! Both patches run in u across the join: the first patch ends at its `u = max` boundary
//! where the second starts at its `u = min` boundary, and both are parametrized the same
//! way in v along it. With `R_j`, `S_j`, `T_j` the control points next to, on, and past
//! the boundary in row `j`, the patches are C1 (eq. 4) when `S_j - R_j` and `T_j - S_j`
//! are parallel and `|S_j - R_j| : |T_j - S_j|` is one ratio `alpha : beta` for every `j`.

use glam::DVec3;

use crate::geom::NurbsSurface;

/// Figures of one join.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JoinQuality {
    /// Largest distance (mm) between the two boundaries, sampled.
    pub gap: f64,
    /// Largest angle (degrees) between the two surfaces' normals along the boundary,
    /// sampled.
    pub normal_angle: f64,
    /// Largest angle (degrees) between `S_j - R_j` and `T_j - S_j` (eq. 4).
    pub net_angle: f64,
    /// Spread of the eq. 4 ratio `|S_j - R_j| / |T_j - S_j|` over the rows:
    /// `max / min - 1` (0 for C1).
    pub ratio_spread: f64,
    /// Largest distance (mm) between the two patches' boundary control points `S_j`.
    pub net_gap: f64,
}

/// Measures the join of `first`'s `u = max` boundary to `second`'s `u = min` boundary at
/// `samples + 1` points along v.
///
/// The patches must have the same number of control points in v on the boundary (the
/// caller makes them compatible); if they do not, the control-net figures are infinite.
pub fn measure_join(first: &NurbsSurface, second: &NurbsSurface, samples: usize) -> JoinQuality {
    let (na, ma) = first.counts();
    let (nb, mb) = second.counts();
    let (mut net_angle, mut net_gap) = (0.0f64, 0.0f64);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    if ma == mb && na >= 2 && nb >= 2 {
        for j in 0..ma {
            let r = first.control_point(na - 2, j);
            let s = first.control_point(na - 1, j);
            let s2 = second.control_point(0, j);
            let t = second.control_point(1, j);
            net_gap = net_gap.max(s.distance(s2));
            let (before, after) = (s - r, t - s2);
            net_angle = net_angle.max(angle_deg(before, after));
            let ratio = before.length() / after.length();
            lo = lo.min(ratio);
            hi = hi.max(ratio);
        }
    } else {
        net_angle = f64::INFINITY;
        net_gap = f64::INFINITY;
    }
    let ratio_spread = if lo.is_finite() && lo > 0.0 {
        hi / lo - 1.0
    } else {
        f64::INFINITY
    };
    let ua = first.domain_u().1;
    let ub = second.domain_u().0;
    let (va0, va1) = first.domain_v();
    let (vb0, vb1) = second.domain_v();
    let (mut gap, mut normal_angle) = (0.0f64, 0.0f64);
    let (extent_a, extent_b) = (first.net_extent(), second.net_extent());
    for i in 0..=samples {
        let f = i as f64 / samples.max(1) as f64;
        let (va, vb) = (va0 + (va1 - va0) * f, vb0 + (vb1 - vb0) * f);
        gap = gap.max(first.point_at(ua, va).distance(second.point_at(ub, vb)));
        match (
            first.normal_within(ua, va, extent_a),
            second.normal_within(ub, vb, extent_b),
        ) {
            (Ok(a), Ok(b)) => normal_angle = normal_angle.max(angle_deg(a, b)),
            _ => normal_angle = f64::INFINITY,
        }
    }
    JoinQuality {
        gap,
        normal_angle,
        net_angle,
        ratio_spread,
        net_gap,
    }
}

/// The angle in degrees between two vectors (robust near 0).
fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}
