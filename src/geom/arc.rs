//! Exact circular arcs as rational quadratic NURBS (P&T A7.1).
//!
//! Die designers draw with arcs everywhere: die and punch radii in sections, corner
//! radii in the top view, bead shoulders. An arc of up to 90 degrees is one rational
//! quadratic segment with middle weight `cos(dtheta / 2)`; longer arcs are split into
//! equal segments joined by double knots. The result lies on the circle to rounding,
//! unlike a polynomial approximation.

use std::f64::consts::{FRAC_PI_2, TAU};

use super::curve::NurbsCurve;
use super::error::{GeomError, Result};
use super::point::Point;

/// The arc of radius `radius` about `center`, in the plane spanned by the orthonormal
/// `x_axis` and `y_axis`, from angle `start` to angle `end` (radians, measured from
/// `x_axis` towards `y_axis`). `end` is taken modulo a full turn to lie after `start`,
/// so `end - start` in (0, 2 pi]; a full circle is `end = start + 2 pi`.
pub fn circular_arc<P: Point>(
    center: P,
    x_axis: P,
    y_axis: P,
    radius: f64,
    start: f64,
    end: f64,
) -> Result<NurbsCurve<P>> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(GeomError::NotPositive {
            what: "arc radius",
            value: radius,
        });
    }
    if !(start.is_finite() && end.is_finite()) {
        return Err(GeomError::NotFinite { what: "arc angle" });
    }
    if !(center.is_finite() && x_axis.is_finite() && y_axis.is_finite()) {
        return Err(GeomError::NotFinite { what: "arc frame" });
    }
    let (xl, yl) = (x_axis.length(), y_axis.length());
    if xl == 0.0 || yl == 0.0 {
        return Err(GeomError::ZeroVector { what: "arc axis" });
    }
    let x = x_axis * (1.0 / xl);
    let y = y_axis * (1.0 / yl);
    if x.dot(y).abs() > 1e-9 {
        return Err(GeomError::Singular {
            what: "arc frame: the axes are not perpendicular",
        });
    }
    let mut sweep = (end - start).rem_euclid(TAU);
    if sweep <= 1e-15 {
        sweep = TAU;
    }
    let arcs = (sweep / FRAC_PI_2 - 1e-12).ceil().max(1.0) as usize;
    let dtheta = sweep / arcs as f64;
    let w1 = (0.5 * dtheta).cos();
    let on_circle = |angle: f64, r: f64| center + x * (r * angle.cos()) + y * (r * angle.sin());

    let mut points = Vec::with_capacity(2 * arcs + 1);
    let mut weights = Vec::with_capacity(2 * arcs + 1);
    points.push(on_circle(start, radius));
    weights.push(1.0);
    for i in 0..arcs {
        let a0 = start + dtheta * i as f64;
        // The middle control point is where the end tangents meet: on the bisector at
        // distance r / cos(dtheta / 2).
        points.push(on_circle(a0 + 0.5 * dtheta, radius / w1));
        weights.push(w1);
        points.push(on_circle(a0 + dtheta, radius));
        weights.push(1.0);
    }
    let mut knots = vec![0.0; 3];
    for i in 1..arcs {
        let k = i as f64 / arcs as f64;
        knots.extend([k, k]);
    }
    knots.extend([1.0; 3]);
    NurbsCurve::new_rational(2, knots, points, weights)
}

/// The full circle of `radius` about `center` in the plane of `x_axis`, `y_axis`,
/// starting and ending on `x_axis`.
pub fn circle<P: Point>(center: P, x_axis: P, y_axis: P, radius: f64) -> Result<NurbsCurve<P>> {
    circular_arc(center, x_axis, y_axis, radius, 0.0, TAU)
}

/// The arc that starts at `a`, passes through `b` and ends at `c`.
pub fn arc_through_points<P: Point>(a: P, b: P, c: P) -> Result<NurbsCurve<P>> {
    let circle = Circle::through(a, b, c)?;
    let x = (a - circle.center) * (1.0 / circle.radius);
    // y: the in-plane unit vector perpendicular to x on the side of b.
    let rb = b - circle.center;
    let yb = rb - x * rb.dot(x);
    let y = yb * (1.0 / yb.length());
    let angle = |p: P| {
        let r = p - circle.center;
        r.dot(y).atan2(r.dot(x)).rem_euclid(TAU)
    };
    let (tb, tc) = (angle(b), angle(c));
    if tc > tb {
        circular_arc(circle.center, x, y, circle.radius, 0.0, tc)
    } else {
        // b comes after c counter-clockwise: run the other way round.
        circular_arc(circle.center, x, y * -1.0, circle.radius, 0.0, TAU - tc)
    }
}

/// A circle through three points: its centre and radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle<P> {
    /// Centre, in the plane of the three points.
    pub center: P,
    /// Radius.
    pub radius: f64,
}

impl<P: Point> Circle<P> {
    /// The circle through `a`, `b`, `c`; an error when two coincide or all are collinear.
    /// The step draw takes its cross-boundary tangent directions from such circles
    /// (paper 001, section 4.4, Fig. 12; `docs/methods.md`).
    pub fn through(a: P, b: P, c: P) -> Result<Self> {
        let (u, v) = (b - a, c - a);
        let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
        if uu == 0.0 {
            return Err(GeomError::CoincidentPoints {
                first: 0,
                second: 1,
            });
        }
        if vv == 0.0 {
            return Err(GeomError::CoincidentPoints {
                first: 0,
                second: 2,
            });
        }
        if (c - b).dot(c - b) == 0.0 {
            return Err(GeomError::CoincidentPoints {
                first: 1,
                second: 2,
            });
        }
        // Centre = a + s u + t v with (centre - a).u = uu / 2 and (centre - a).v = vv / 2.
        let det = uu * vv - uv * uv;
        if det <= 1e-24 * uu * vv {
            return Err(GeomError::Singular {
                what: "the three points lie on one straight line, so no circle passes through them",
            });
        }
        let s = 0.5 * (uu * vv - vv * uv) / det;
        let t = 0.5 * (vv * uu - uu * uv) / det;
        let center = a + u * s + v * t;
        Ok(Self {
            center,
            radius: (a - center).length(),
        })
    }
}
