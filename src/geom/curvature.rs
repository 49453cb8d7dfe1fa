//! Surface curvature: principal curvatures from the two fundamental forms, and the
//! smallest radius of a patch found by sampling every knot span.
//!
//! A die engineer judges a die face by its radii (`docs/methods.md`, "What a die engineer checks"): no patch may be
//! tighter anywhere than the radii the designer drew. [`min_radius`] is the figure that
//! checks it; it samples each knot span of both directions (a curvature spike sits
//! inside a span, where the control net gives no hint of it).

use glam::DVec3;

use super::NurbsSurface;

/// Principal curvatures at one point of a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Principal {
    /// The larger principal curvature (1/mm), signed positive where the surface bends
    /// towards its normal.
    pub k1: f64,
    /// The smaller principal curvature (1/mm).
    pub k2: f64,
    /// The unit normal `S_u x S_v / |S_u x S_v|`.
    pub normal: DVec3,
}

impl Principal {
    /// The smallest radius of curvature at the point, `1 / max(|k1|, |k2|)` (infinite on
    /// a plane).
    pub fn min_radius(&self) -> f64 {
        let k = self.k1.abs().max(self.k2.abs());
        if k > 0.0 {
            1.0 / k
        } else {
            f64::INFINITY
        }
    }
}

/// Principal curvatures at `(u, v)`, or `None` at a degenerate point (a collapsed edge,
/// where the first fundamental form is singular).
pub fn principal_curvatures(s: &NurbsSurface, u: f64, v: f64) -> Option<Principal> {
    principal_of(&s.derivatives::<3>(u, v))
}

/// Principal curvatures from a surface's partial derivatives up to the second
/// ([`NurbsSurface::derivatives`] or, over a grid, [`NurbsSurface::derivatives_from`]),
/// or `None` at a degenerate point.
pub fn principal_of(d: &[[DVec3; 3]; 3]) -> Option<Principal> {
    let (su, sv) = (d[1][0], d[0][1]);
    let (suu, suv, svv) = (d[2][0], d[1][1], d[0][2]);
    let cross = su.cross(sv);
    let area = cross.length();
    if area <= 1e-12 * (su.length_squared() + sv.length_squared()).max(f64::MIN_POSITIVE) {
        return None;
    }
    let n = cross / area;
    let (e, f, g) = (su.dot(su), su.dot(sv), sv.dot(sv));
    let (l, m, nn) = (suu.dot(n), suv.dot(n), svv.dot(n));
    let det = e * g - f * f;
    let mean = (e * nn - 2.0 * f * m + g * l) / (2.0 * det);
    let gauss = (l * nn - m * m) / det;
    let disc = (mean * mean - gauss).max(0.0).sqrt();
    Some(Principal {
        k1: mean + disc,
        k2: mean - disc,
        normal: n,
    })
}

/// Every span between the increasing `breaks` (a direction's distinct knots) at
/// `per_span` equal steps, each break once: where a curvature spike inside a span shows.
pub fn span_steps(breaks: &[f64], per_span: usize) -> Vec<f64> {
    let per_span = per_span.max(1);
    let mut out = Vec::with_capacity(breaks.len() * per_span + 1);
    for w in breaks.windows(2) {
        for k in 0..per_span {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / per_span as f64);
        }
    }
    if let Some(&last) = breaks.last() {
        out.push(last);
    }
    out
}

/// Where a patch is tightest: the smallest radius of curvature found and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MinRadius {
    /// The smallest radius (mm); infinite for a flat patch.
    pub radius: f64,
    /// The parameters where it was found.
    pub uv: (f64, f64),
    /// The point there.
    pub point: DVec3,
}

/// The smallest radius of curvature of `s`, sampled `per_span` times across every knot
/// span of each direction (span ends included), then refined around the worst sample by
/// a finer local grid. Degenerate points are skipped.
pub fn min_radius(s: &NurbsSurface, per_span: usize) -> MinRadius {
    let breaks =
        |k: &super::KnotVector| -> Vec<f64> { k.distinct().iter().map(|&(t, _)| t).collect() };
    let us = span_steps(&breaks(s.knots_u()), per_span);
    let vs = span_steps(&breaks(s.knots_v()), per_span);
    let mut best = MinRadius {
        radius: f64::INFINITY,
        uv: (us[0], vs[0]),
        point: s.point_at(us[0], vs[0]),
    };
    let mut best_index = (0, 0);
    // Keeps the sample at (u, v) when it is tighter than the best so far.
    let consider = |best: &mut MinRadius, u: f64, v: f64| -> bool {
        match principal_curvatures(s, u, v) {
            Some(p) if p.min_radius() < best.radius => {
                *best = MinRadius {
                    radius: p.min_radius(),
                    uv: (u, v),
                    point: s.point_at(u, v),
                };
                true
            }
            _ => false,
        }
    };
    for (i, &u) in us.iter().enumerate() {
        for (j, &v) in vs.iter().enumerate() {
            if consider(&mut best, u, v) {
                best_index = (i, j);
            }
        }
    }
    if !best.radius.is_finite() {
        return best;
    }
    // A finer grid over the cells around the worst sample.
    let (i, j) = best_index;
    let (ua, ub) = (us[i.saturating_sub(1)], us[(i + 1).min(us.len() - 1)]);
    let (va, vb) = (vs[j.saturating_sub(1)], vs[(j + 1).min(vs.len() - 1)]);
    let fine = 16;
    for a in 0..=fine {
        for b in 0..=fine {
            let u = ua + (ub - ua) * a as f64 / fine as f64;
            let v = va + (vb - va) * b as f64 / fine as f64;
            consider(&mut best, u, v);
        }
    }
    best
}
