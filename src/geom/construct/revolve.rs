//! Exact surfaces of revolution (P&T A8.1).

use std::f64::consts::{FRAC_PI_2, TAU};

use glam::DVec3;

use crate::geom::curve::Curve3;
use crate::geom::error::{GeomError, Result};
use crate::geom::surface::NurbsSurface;
use crate::geom::transform::unit;

/// The surface swept by `profile` turning by `angle` radians (right-handed, at most a
/// full turn) about the axis through `axis_point` along `axis_dir`. u runs around the
/// axis (degree 2, rational, parameter in [0, 1] but not proportional to the angle),
/// v along the profile. Exact: every u-iso-curve is a circle arc.
pub fn revolve(
    profile: &Curve3,
    axis_point: DVec3,
    axis_dir: DVec3,
    angle: f64,
) -> Result<NurbsSurface> {
    let axis = unit(axis_dir, "revolution axis")?;
    if !axis_point.is_finite() {
        return Err(GeomError::NotFinite {
            what: "revolution axis point",
        });
    }
    if !(angle.is_finite() && angle > 0.0 && angle <= TAU + 1e-12) {
        return Err(GeomError::NotPositive {
            what: "revolution angle (at most a full turn)",
            value: angle,
        });
    }
    let angle = angle.min(TAU);
    let arcs = (angle / FRAC_PI_2 - 1e-12).ceil().max(1.0) as usize;
    let dtheta = angle / arcs as f64;
    let wm = (0.5 * dtheta).cos();

    let mut knots_u = vec![0.0; 3];
    for i in 1..arcs {
        let k = i as f64 / arcs as f64;
        knots_u.extend([k, k]);
    }
    knots_u.extend([1.0; 3]);

    let nv = profile.control_points().len();
    let nu = 2 * arcs + 1;
    let mut points = vec![DVec3::ZERO; nu * nv];
    let mut weights = vec![1.0; nu * nv];
    for (j, &p) in profile.control_points().iter().enumerate() {
        let w = profile.weight(j);
        let o = axis_point + axis * (p - axis_point).dot(axis);
        let x = p - o;
        let r = x.length();
        let (xdir, ydir) = if r > 0.0 {
            (x / r, axis.cross(x / r))
        } else {
            (DVec3::ZERO, DVec3::ZERO)
        };
        let at = |theta: f64, radius: f64| {
            o + xdir * (radius * theta.cos()) + ydir * (radius * theta.sin())
        };
        for k in 0..nu {
            let theta = dtheta * (k / 2) as f64;
            let (pt, wk) = if k % 2 == 0 {
                (at(theta, r), 1.0)
            } else {
                (at(theta + 0.5 * dtheta, r / wm), wm)
            };
            points[k * nv + j] = pt;
            weights[k * nv + j] = wk * w;
        }
    }
    Ok(NurbsSurface::from_parts(
        (2, profile.degree()),
        (knots_u, profile.knots().as_slice().to_vec()),
        (nu, nv),
        points,
        Some(weights),
    ))
}
