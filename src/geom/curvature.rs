//! Surface curvature: principal curvatures from the two fundamental forms, and the
//! smallest radius of a patch found by sampling every knot span.
//!
//! A die engineer judges a die face by its radii (`docs/methods.md`, "What a die engineer checks"): no patch may be
//! tighter anywhere than the radii the designer drew. [`min_radius`] is the figure that
//! checks it; it samples each knot span of both directions (a curvature spike sits
//! inside a span, where the control net gives no hint of it).

use glam::DVec3;

use super::{KnotVector, NurbsSurface};

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

/// The sample parameters of one direction of a surface for its curvature: every knot
/// span at `per_span` equal steps ([`span_steps`]), and just before every interior knot
/// where the surface is at most C1 (multiplicity `degree - 1` or more) the left-hand
/// limit too. Curvature jumps at such a knot (a cubic step-draw section turns from an
/// arc into a run there), and evaluating at the knot itself gives only the right-hand
/// span's value: the tightest point of the arc, at its end, would go unseen.
pub fn curvature_steps(knots: &KnotVector, degree: usize, per_span: usize) -> Vec<f64> {
    let distinct = knots.distinct();
    let breaks: Vec<f64> = distinct.iter().map(|&(t, _)| t).collect();
    let steps = span_steps(&breaks, per_span);
    let jumps: Vec<(f64, f64)> = distinct
        .windows(2)
        .zip(distinct.iter().skip(1))
        .take(distinct.len().saturating_sub(2))
        .filter(|&(_, &(_, mult))| mult + 1 >= degree)
        .map(|(w, _)| (w[0].0, w[1].0))
        .collect();
    if jumps.is_empty() {
        return steps;
    }
    let mut out = Vec::with_capacity(steps.len() + jumps.len());
    let mut next = jumps.iter().peekable();
    for t in steps {
        while let Some(&&(before, knot)) = next.peek() {
            if knot > t {
                break;
            }
            if knot == t {
                out.push(knot - LEFT_LIMIT * (knot - before));
            }
            next.next();
        }
        out.push(t);
    }
    out
}

/// How far before a knot (a share of the span before it) its left-hand limit is taken:
/// far enough that the evaluation falls in that span, near enough to read its end.
const LEFT_LIMIT: f64 = 1e-9;

/// Steps per side of each finer grid of [`refine_lowest_minima`].
const REFINE: usize = 4;

/// How many times [`refine_lowest_minima`] zooms in on its best point: each grid spans
/// half the one before, so the last step is 1/32 of the two cells first searched.
const ZOOMS: usize = 4;

/// How many of a grid's lowest local minima [`refine_lowest_minima`] refines.
const REFINED_MINIMA: usize = 3;

/// The smallest value of `measure` near the lowest local minima of `values`, sampled
/// on the grid `us` x `vs` (row-major, `values[i * vs.len() + j]` at `(us[i], vs[j])`):
/// around each of the [`REFINED_MINIMA`] lowest (each sample no higher than its
/// neighbours), finer and finer grids zooming in on the best point ([`ZOOMS`]); the best
/// of them with its parameters. The
/// tightest point of a patch may sit in a cell whose samples read a little above the
/// lowest sample elsewhere, so refining only the lowest sample can miss it. `None` when
/// no sample is finite.
pub fn refine_lowest_minima(
    us: &[f64],
    vs: &[f64],
    values: &[f64],
    measure: &dyn Fn(f64, f64) -> Option<f64>,
) -> Option<(f64, (f64, f64))> {
    let (nu, nv) = (us.len(), vs.len());
    let around = |i: usize, n: usize| i.saturating_sub(1)..=(i + 1).min(n - 1);
    let mut minima: Vec<usize> = (0..values.len())
        .filter(|&k| {
            let (i, j) = (k / nv, k % nv);
            values[k].is_finite()
                && around(i, nu).all(|a| around(j, nv).all(|b| values[k] <= values[a * nv + b]))
        })
        .collect();
    minima.sort_by(|&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b)));
    minima.truncate(REFINED_MINIMA);
    // A grid of REFINE x REFINE steps over the two cells each side of the sample,
    // then again over the two steps each side of the best point, ZOOMS times.
    let refine = |k: usize| {
        let (i, j) = (k / nv, k % nv);
        let (mut ua, mut ub) = (us[i.saturating_sub(1)], us[(i + 1).min(nu - 1)]);
        let (mut va, mut vb) = (vs[j.saturating_sub(1)], vs[(j + 1).min(nv - 1)]);
        let mut best = (values[k], (us[i], vs[j]));
        for _ in 0..ZOOMS {
            let (du, dv) = ((ub - ua) / REFINE as f64, (vb - va) / REFINE as f64);
            let mut centre = best.1;
            for a in 0..=REFINE {
                for b in 0..=REFINE {
                    let (u, v) = (ua + du * a as f64, va + dv * b as f64);
                    if let Some(m) = measure(u, v) {
                        if m < best.0 {
                            best = (m, (u, v));
                            centre = (u, v);
                        }
                    }
                }
            }
            (ua, ub) = ((centre.0 - du).max(ua), (centre.0 + du).min(ub));
            (va, vb) = ((centre.1 - dv).max(va), (centre.1 + dv).min(vb));
        }
        best
    };
    minima
        .into_iter()
        .map(refine)
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The smallest radius of curvature of `s`, sampled `per_span` times across every knot
/// span of each direction (span ends included, and the left-hand side of every knot
/// where curvature may jump: [`curvature_steps`]), then refined around the lowest local
/// minima by finer local grids ([`refine_lowest_minima`]). Degenerate points are
/// skipped.
pub fn min_radius(s: &NurbsSurface, per_span: usize) -> MinRadius {
    let us = curvature_steps(s.knots_u(), s.degree_u(), per_span);
    let vs = curvature_steps(s.knots_v(), s.degree_v(), per_span);
    let radius_at = |u: f64, v: f64| principal_curvatures(s, u, v).map(|p| p.min_radius());
    let values: Vec<f64> = us
        .iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .map(|(u, v)| radius_at(u, v).unwrap_or(f64::INFINITY))
        .collect();
    let (radius, (u, v)) = refine_lowest_minima(&us, &vs, &values, &radius_at)
        .unwrap_or((f64::INFINITY, (us[0], vs[0])));
    MinRadius {
        radius,
        uv: (u, v),
        point: s.point_at(u, v),
    }
}
