//! Intersections: curve with plane, curve with a coordinate value, line with surface.
//!
//! Sections of the die face cut curves with planes; the punch-opening two-view algorithm
//! solves `S_x(u) = x` on a 2-D profile ([`curve_at_coordinate`]); its corner correction
//! moves a point along a line onto the die surface, solving `P + w r = S(u, v)`
//! ([`intersect_ray_surface`]).
//!
//! # Curve roots: method and guarantee
//!
//! Both curve functions find the zeros of a scalar `g(t) = L(C(t)) - c` with `L` linear
//! (the signed distance to a plane, or one coordinate). `g` is itself a (rational)
//! B-spline whose coefficients are `L(P_i) - c`, so a knot span whose active coefficients
//! all have the same sign (beyond the touch tolerance) cannot contain a zero and is
//! skipped. The other spans are sampled at `4 (degree + 1)` parameters each, and:
//!
//! * every sign change between neighbouring samples is refined by Newton's method
//!   safeguarded with bisection until `|g| <= 1e-15 size` or the bracket is a few ulps
//!   wide (so hits are accurate to rounding, far below the `1e-12` relative target);
//! * a sample with `|g| <= 1e-12 size` ([`ROOT_TOLERANCE`]) is a hit (polished by
//!   Newton); a run of such samples is a piece of the curve lying in the plane, reported
//!   by its first and last sample (to sample resolution);
//! * a local minimum of `|g|` over the samples without a sign change starts a search for
//!   the extremum of `g` between its neighbours: an extremum with `|g| <= 1e-10 size`
//!   ([`TOUCH_TOLERANCE`]) is a tangential touch, one on the other side of zero reveals
//!   two close crossings, both refined.
//!
//! Guaranteed: every transversal crossing whose neighbouring crossings are more than a
//! sample spacing away, every exact zero at a sample, and the span joins (hits found
//! from both sides are merged). Not guaranteed: several crossings or touches packed
//! into one sample interval beyond the pair case above. `size` is the largest
//! control-point magnitude (or the plane's offset, if larger).
//!
//! # Line–surface
//!
//! Newton's method on the 3x3 system `S(u, v) - P - w r = 0` with Jacobian
//! `[S_u, S_v, -r]` (solved by SVD, so a degenerate parametrization or a grazing line
//! gives a least-squares step instead of a failure), started from the grid samples
//! closest to the line, clamped to the domain, with step halving on the residual.

use glam::{DVec2, DVec3};
use nalgebra::{Matrix3, Vector3};

use super::curve::{Curve3, NurbsCurve};
use super::error::{GeomError, Result};
use super::inversion::{grid_local_minima, surface_grid};
use super::point::Point;
use super::surface::NurbsSurface;

/// Relative tolerance under which a sampled `|g|` counts as a zero (times the size).
pub const ROOT_TOLERANCE: f64 = 1e-12;

/// Relative tolerance under which a local minimum of `|g|` that does not cross zero
/// counts as a tangential touch (times the size).
pub const TOUCH_TOLERANCE: f64 = 1e-10;

/// Relative residual the root refinement aims for.
const ROOT_ACCURACY: f64 = 1e-15;

/// Samples per knot span are `SAMPLES_PER_DEGREE * (degree + 1)`.
const SAMPLES_PER_DEGREE: usize = 4;

/// Iteration cap of the bracketed solver (bisection alone needs at most ~1100 halvings
/// for any pair of doubles, but brackets here start at most a span wide).
const MAX_BRACKET_ITERATIONS: usize = 200;

/// Relative residual `|P + w r - S|` at which a line–surface hit is accepted.
pub const RAY_TOLERANCE: f64 = 1e-12;

/// Newton iteration cap per line–surface start.
const RAY_ITERATIONS: usize = 60;

/// How many sampled local minima of the distance to the line start Newton.
const RAY_STARTS: usize = 24;

/// A plane through `origin` with unit `normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// A point of the plane.
    pub origin: DVec3,
    /// Unit normal; the signed distance is positive on its side.
    pub normal: DVec3,
}

impl Plane {
    /// The plane through `origin` perpendicular to `normal` (normalized here).
    ///
    /// Errors: [`GeomError::NotFinite`] for NaN or infinite input,
    /// [`GeomError::ZeroVector`] for a zero normal.
    pub fn new(origin: DVec3, normal: DVec3) -> Result<Self> {
        if !origin.is_finite() {
            return Err(GeomError::NotFinite {
                what: "plane origin",
            });
        }
        if !normal.is_finite() {
            return Err(GeomError::NotFinite {
                what: "plane normal",
            });
        }
        let Some(normal) = unit_vector(normal) else {
            return Err(GeomError::ZeroVector {
                what: "plane normal",
            });
        };
        Ok(Self { origin, normal })
    }

    /// Signed distance of `p` from the plane, positive on the normal's side.
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p - self.origin)
    }
}

/// `v / |v|` computed without overflow or underflow, or `None` for a zero vector.
fn unit_vector(v: DVec3) -> Option<DVec3> {
    let big = v.abs().max_element();
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    let scaled = v / big;
    Some(scaled / scaled.length())
}

/// One intersection of a curve with a plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePlaneHit {
    /// Curve parameter.
    pub t: f64,
    /// The point `C(t)`.
    pub point: DVec3,
}

/// All intersections of `curve` with `plane`, sorted by parameter.
///
/// See the module documentation for the method and what is guaranteed. An empty vector
/// means no intersection. A closed curve crossing the plane at its seam reports both
/// `t0` and `t1`.
///
/// Errors: [`GeomError::Overlap`] if the whole curve lies in the plane (within
/// [`ROOT_TOLERANCE`]).
pub fn intersect_curve_plane(curve: &Curve3, plane: &Plane) -> Result<Vec<CurvePlaneHit>> {
    if !(plane.origin.is_finite() && plane.normal.is_finite()) {
        return Err(GeomError::NotFinite { what: "plane" });
    }
    // Tolerate a hand-built, non-unit normal: measure true distances.
    let Some(n) = unit_vector(plane.normal) else {
        return Err(GeomError::ZeroVector {
            what: "plane normal",
        });
    };
    let offset = n.dot(plane.origin);
    let scale = curve.control_scale().max(plane.origin.length());
    let ts = curve_roots(
        curve,
        &|p: DVec3| n.dot(p),
        offset,
        scale,
        "curve-plane intersection",
    )?;
    Ok(ts
        .into_iter()
        .map(|t| CurvePlaneHit {
            t,
            point: curve.point_at(t),
        })
        .collect())
}

/// All parameters `t`, sorted, where coordinate `axis` (0 = x, 1 = y, 2 = z) of `C(t)`
/// equals `value`: the punch-opening two-view algorithm solves `S_x(u) = x` with it.
///
/// Same method and guarantee as [`intersect_curve_plane`] (module documentation).
///
/// Errors: [`GeomError::NotFinite`] for a NaN or infinite value,
/// [`GeomError::ParameterOutOfRange`] for an axis the point type does not have,
/// [`GeomError::Overlap`] if the whole curve has that coordinate.
pub fn curve_at_coordinate<P: Point>(
    curve: &NurbsCurve<P>,
    axis: usize,
    value: f64,
) -> Result<Vec<f64>> {
    if !value.is_finite() {
        return Err(GeomError::NotFinite {
            what: "coordinate value",
        });
    }
    if axis >= P::DIM {
        return Err(GeomError::ParameterOutOfRange {
            value: axis as f64,
            min: 0.0,
            max: (P::DIM - 1) as f64,
        });
    }
    curve_roots(
        curve,
        &|p: P| p.coord(axis),
        value,
        curve.control_scale(),
        "curve at coordinate",
    )
}

/// `g(t) = form(C(t)) - offset` with its first two derivatives (`form` is linear).
fn eval_g<P: Point>(
    curve: &NurbsCurve<P>,
    form: &dyn Fn(P) -> f64,
    offset: f64,
    t: f64,
) -> (f64, f64, f64) {
    let [c, d1, d2] = curve.derivatives::<3>(t);
    (form(c) - offset, form(d1), form(d2))
}

/// A zero of `f` in `[a, b]` where `f(a)` and `f(b)` have opposite signs, by Newton
/// safeguarded with bisection; `f` returns the value and the slope. Stops when
/// `|f| <= accuracy` or the bracket is a few ulps wide, returning the best point seen.
fn bracket_root(
    f: &dyn Fn(f64) -> (f64, f64),
    mut a: f64,
    mut b: f64,
    fa: f64,
    accuracy: f64,
) -> f64 {
    let neg_at_a = fa < 0.0;
    let mut t = 0.5 * (a + b);
    let mut best = (f64::INFINITY, t);
    let mut last_width = f64::INFINITY;
    for _ in 0..MAX_BRACKET_ITERATIONS {
        let (v, slope) = f(t);
        if v.abs() < best.0 {
            best = (v.abs(), t);
        }
        if v.abs() <= accuracy || !v.is_finite() {
            break;
        }
        if (v < 0.0) == neg_at_a {
            a = t;
        } else {
            b = t;
        }
        let width = (b - a).abs();
        if width <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) + f64::MIN_POSITIVE {
            break;
        }
        let newton = t - v / slope;
        let inside = newton.is_finite() && newton > a.min(b) && newton < a.max(b);
        t = if inside && width < 0.75 * last_width {
            newton
        } else {
            0.5 * (a + b)
        };
        last_width = width;
    }
    best.1
}

/// A few Newton steps on `g` from a sample already within tolerance, kept in `[lo, hi]`
/// and only while `|g|` decreases.
fn polish(curve_g: &dyn Fn(f64) -> (f64, f64), t: f64, lo: f64, hi: f64) -> f64 {
    let (mut t, (mut g, mut slope)) = (t, curve_g(t));
    for _ in 0..8 {
        if g == 0.0 || slope == 0.0 {
            break;
        }
        let tn = (t - g / slope).clamp(lo, hi);
        let (gn, sn) = curve_g(tn);
        if gn.is_nan() || gn.abs() >= g.abs() {
            break;
        }
        (t, g, slope) = (tn, gn, sn);
    }
    t
}

/// All zeros of `g(t) = form(C(t)) - offset`, sorted; see the module documentation.
fn curve_roots<P: Point>(
    curve: &NurbsCurve<P>,
    form: &dyn Fn(P) -> f64,
    offset: f64,
    scale: f64,
    what: &'static str,
) -> Result<Vec<f64>> {
    let size = scale.max(offset.abs()).max(f64::MIN_POSITIVE);
    let zero_tol = ROOT_TOLERANCE * size;
    let touch_tol = TOUCH_TOLERANCE * size;
    let accuracy = ROOT_ACCURACY * size;
    let coeffs: Vec<f64> = curve
        .control_points()
        .iter()
        .map(|&p| form(p) - offset)
        .collect();
    // g is a positive combination of the coefficients (weights are positive).
    if coeffs.iter().all(|c| c.abs() <= zero_tol) {
        return Err(GeomError::Overlap { what });
    }
    let g = |t: f64| {
        let (v, s, _) = eval_g(curve, form, offset, t);
        (v, s)
    };
    let dg = |t: f64| {
        let (_, s, c) = eval_g(curve, form, offset, t);
        (s, c)
    };

    let p = curve.degree();
    let (t0, t1) = curve.domain();
    let breaks = curve.span_breaks();
    let mut samples: Vec<(f64, f64)> = Vec::new();
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        let span = curve.knots().span(p, 0.5 * (a + b));
        let active = &coeffs[span - p..=span];
        let skip = active.iter().all(|&c| c > touch_tol) || active.iter().all(|&c| c < -touch_tol);
        let count = if skip {
            1
        } else {
            SAMPLES_PER_DEGREE * (p + 1)
        };
        for i in 0..count {
            let t = a + (b - a) * (i as f64 / count as f64);
            samples.push((t, g(t).0));
        }
    }
    samples.push((t1, g(t1).0));

    let n = samples.len();
    let is_zero = |i: usize| samples[i].1.abs() <= zero_tol;
    let mut hits: Vec<f64> = Vec::new();
    let mut i = 0;
    while i < n {
        if is_zero(i) {
            let mut j = i;
            while j + 1 < n && is_zero(j + 1) {
                j += 1;
            }
            if i == j {
                let lo = if i > 0 { samples[i - 1].0 } else { t0 };
                let hi = if i + 1 < n { samples[i + 1].0 } else { t1 };
                hits.push(polish(&g, samples[i].0, lo, hi));
            } else {
                hits.push(samples[i].0);
                hits.push(samples[j].0);
            }
            i = j + 1;
            continue;
        }
        if i + 1 < n && !is_zero(i + 1) && (samples[i].1 < 0.0) != (samples[i + 1].1 < 0.0) {
            hits.push(bracket_root(
                &g,
                samples[i].0,
                samples[i + 1].0,
                samples[i].1,
                accuracy,
            ));
        }
        i += 1;
    }
    // Touches and close pairs: local minima of |g| that do not cross zero.
    for i in 1..n.saturating_sub(1) {
        let (prev, here, next) = (samples[i - 1], samples[i], samples[i + 1]);
        if is_zero(i - 1) || is_zero(i) || is_zero(i + 1) {
            continue;
        }
        let same_sign = (prev.1 < 0.0) == (here.1 < 0.0) && (here.1 < 0.0) == (next.1 < 0.0);
        if !(same_sign && here.1.abs() < prev.1.abs() && here.1.abs() <= next.1.abs()) {
            continue;
        }
        let (sa, sb) = (dg(prev.0).0, dg(next.0).0);
        if sa == 0.0 || sb == 0.0 || (sa < 0.0) == (sb < 0.0) {
            continue;
        }
        let te = bracket_root(&dg, prev.0, next.0, sa, 0.0);
        let ge = g(te).0;
        if ge.abs() <= touch_tol {
            hits.push(te);
        } else if (ge < 0.0) != (here.1 < 0.0) {
            hits.push(bracket_root(&g, prev.0, te, prev.1, accuracy));
            hits.push(bracket_root(&g, te, next.0, ge, accuracy));
        }
    }

    hits.sort_by(f64::total_cmp);
    let width = t1 - t0;
    let mut out: Vec<f64> = Vec::with_capacity(hits.len());
    for t in hits {
        if let Some(&last) = out.last() {
            let dt = t - last;
            let close = dt <= 1e-9 * width
                || (dt <= 1e-6 * width
                    && curve.point_at(t).distance(curve.point_at(last)) <= 1e-9 * size);
            if close {
                if g(t).0.abs() < g(last).0.abs() {
                    if let Some(l) = out.last_mut() {
                        *l = t;
                    }
                }
                continue;
            }
        }
        out.push(t);
    }
    Ok(out)
}

/// An intersection of a line with a surface: `origin + w * direction = S(u, v)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayHit {
    /// Surface parameter in u.
    pub u: f64,
    /// Surface parameter in v.
    pub v: f64,
    /// Line parameter, in units of the given direction's length; negative behind the
    /// origin.
    pub w: f64,
    /// The intersection point `S(u, v)`.
    pub point: DVec3,
}

/// How one Newton run on the line–surface system ended.
enum RayOutcome {
    Hit(RayHit),
    /// No hit; `interior` says the run stopped away from the domain boundary (a near
    /// miss of Newton, not a line passing outside the patch).
    Failed {
        residual: f64,
        interior: bool,
    },
}

fn ray_newton(
    surface: &NurbsSurface,
    origin: DVec3,
    r: DVec3,
    u: f64,
    v: f64,
    tol: f64,
) -> RayOutcome {
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    let (mut u, mut v) = (u, v);
    let s = surface.point_at(u, v);
    let mut w = (s - origin).dot(r) / r.dot(r);
    let mut res = (s - origin - r * w).length();
    for _ in 0..RAY_ITERATIONS {
        let d = surface.derivatives::<2>(u, v);
        let f = d[0][0] - origin - r * w;
        res = f.length();
        if res <= tol {
            return RayOutcome::Hit(RayHit {
                u,
                v,
                w,
                point: d[0][0],
            });
        }
        let (su, sv) = (d[1][0], d[0][1]);
        let m = Matrix3::new(su.x, sv.x, -r.x, su.y, sv.y, -r.y, su.z, sv.z, -r.z);
        let rhs = Vector3::new(-f.x, -f.y, -f.z);
        if !(m.iter().all(|x| x.is_finite()) && rhs.iter().all(|x| x.is_finite())) {
            break;
        }
        let eps = 1e-14 * (su.length() + sv.length() + r.length());
        // Bounded SVD iterations: never loop on pathological input.
        let Some(svd) = m.try_svd(true, true, f64::EPSILON, 200) else {
            break;
        };
        let Ok(delta) = svd.solve(&rhs, eps) else {
            break;
        };
        if !delta.iter().all(|x| x.is_finite()) {
            break;
        }
        let mut lambda = 1.0;
        let mut accepted = None;
        for _ in 0..30 {
            let nu = (u + lambda * delta[0]).clamp(u0, u1);
            let nv = (v + lambda * delta[1]).clamp(v0, v1);
            let nw = w + lambda * delta[2];
            let nres = (surface.point_at(nu, nv) - origin - r * nw).length();
            if nres < res {
                accepted = Some((nu, nv, nw));
                break;
            }
            lambda *= 0.5;
        }
        let Some((nu, nv, nw)) = accepted else { break };
        (u, v, w) = (nu, nv, nw);
    }
    let interior = u > u0 && u < u1 && v > v0 && v < v1;
    RayOutcome::Failed {
        residual: res,
        interior,
    }
}

/// All distinct intersections of the line `origin + w * direction` with `surface`,
/// sorted by `w` (negative values lie behind the origin).
///
/// Newton starts from the local minima of the sampled distance to the line; hits closer
/// than `1e-9 size` to each other are merged. Intersections whose neighbourhoods the
/// sampling grid does not resolve (several hits inside one grid cell) may be missed.
/// An empty vector means the line misses the surface.
///
/// Errors: [`GeomError::NotFinite`] for NaN or infinite input,
/// [`GeomError::ZeroVector`] for a zero direction.
pub fn intersect_line_surface_all(
    origin: DVec3,
    direction: DVec3,
    surface: &NurbsSurface,
) -> Result<Vec<RayHit>> {
    Ok(line_surface_search(origin, direction, surface)?.0)
}

/// Hits plus the best residual of a run that failed in the interior of the domain.
fn line_surface_search(
    origin: DVec3,
    direction: DVec3,
    surface: &NurbsSurface,
) -> Result<(Vec<RayHit>, Option<f64>)> {
    if !origin.is_finite() {
        return Err(GeomError::NotFinite { what: "ray origin" });
    }
    if !direction.is_finite() {
        return Err(GeomError::NotFinite {
            what: "ray direction",
        });
    }
    // Normalize without overflow or underflow: divide by the largest component first.
    let big = direction.abs().max_element();
    if big == 0.0 {
        return Err(GeomError::ZeroVector {
            what: "ray direction",
        });
    }
    let scaled = direction / big;
    let unit = scaled / scaled.length();
    // |direction|, possibly infinite for huge components (then every w is 0).
    let length = big * scaled.length();
    let size = surface
        .control_scale()
        .max(origin.length())
        .max(f64::MIN_POSITIVE);
    let tol = RAY_TOLERANCE * size;

    let (us, vs) = surface_grid(surface);
    let (nu, nv) = (us.len(), vs.len());
    let mut line_dist = Vec::with_capacity(nu * nv);
    for &u in &us {
        for &v in &vs {
            line_dist.push((surface.point_at(u, v) - origin).cross(unit).length());
        }
    }
    let starts = grid_local_minima(&line_dist, nu, nv, RAY_STARTS);
    let mut hits: Vec<RayHit> = Vec::new();
    let mut near_miss: Option<f64> = None;
    for (i, j) in starts {
        match ray_newton(surface, origin, unit, us[i], vs[j], tol) {
            RayOutcome::Hit(mut h) => {
                // Newton ran with the unit direction; report w in the caller's units.
                h.w /= length;
                if !hits
                    .iter()
                    .any(|k| k.point.distance(h.point) <= 1e-9 * size)
                {
                    hits.push(h);
                }
            }
            RayOutcome::Failed { residual, interior } => {
                if interior && residual <= 1e-6 * size {
                    near_miss = Some(near_miss.map_or(residual, |r: f64| r.min(residual)));
                }
            }
        }
    }
    hits.sort_by(|a, b| a.w.total_cmp(&b.w));
    Ok((hits, near_miss))
}

/// The intersection of the line `origin + w * direction` with `surface` nearest to the
/// origin along the line (smallest `|w|`, in either direction: this is a line, not a
/// half-line, and `w` may be negative), as the punch opening's corner correction needs.
///
/// `w` is measured in units of `direction`'s length. See
/// [`intersect_line_surface_all`] for the method.
///
/// Errors: [`GeomError::NotFinite`] for NaN or infinite input;
/// [`GeomError::ZeroVector`] for a zero direction; [`GeomError::NoIntersection`] when
/// the line misses the surface; [`GeomError::NoConvergence`] when Newton stalled inside
/// the domain close to the line (within `1e-6 size`) without reaching
/// [`RAY_TOLERANCE`] anywhere (a grazing or degenerate hit).
pub fn intersect_ray_surface(
    origin: DVec3,
    direction: DVec3,
    surface: &NurbsSurface,
) -> Result<RayHit> {
    let (hits, near_miss) = line_surface_search(origin, direction, surface)?;
    if let Some(h) = hits
        .into_iter()
        .min_by(|a, b| a.w.abs().total_cmp(&b.w.abs()))
    {
        if !h.w.is_finite() {
            // Only for absurd magnitudes (|w| beyond f64).
            return Err(GeomError::NotFinite {
                what: "line parameter",
            });
        }
        return Ok(h);
    }
    match near_miss {
        Some(residual) => Err(GeomError::NoConvergence {
            what: "line-surface intersection",
            iterations: RAY_ITERATIONS,
            residual,
        }),
        None => Err(GeomError::NoIntersection {
            what: "the line misses the surface",
        }),
    }
}

/// Where a closed or open 2-D polyline crosses or touches itself: the indices of the
/// two segments (segment `i` runs from point `i` to point `i + 1`, and for a closed
/// polyline the last runs back to point 0) and the crossing point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfCrossing {
    /// The earlier segment.
    pub first: usize,
    /// The later segment.
    pub second: usize,
    /// Where they meet.
    pub at: DVec2,
}

/// The first place where the polyline `points` crosses or touches itself, or `None`
/// when it is simple. Neighbouring segments (sharing an end point) never count; two
/// other segments count when they intersect or overlap (exact predicates on the
/// coordinates, with a touch tolerance of `1e-12` of the polyline's size).
///
/// A sweep along x: segments sorted by their smallest x, each compared only with those
/// whose x ranges overlap its own, so a figure of eight of thousands of points is
/// checked in a few milliseconds.
pub fn polyline_self_crossing(points: &[DVec2], closed: bool) -> Option<SelfCrossing> {
    let n = points.len();
    let count = if closed { n } else { n.saturating_sub(1) };
    if count < 3 {
        return None;
    }
    let size = points
        .iter()
        .fold(1.0f64, |m, p| m.max(p.abs().max_element()));
    let tol = 1e-12 * size;
    let seg = |i: usize| (points[i], points[(i + 1) % n]);
    let mut order: Vec<usize> = (0..count).collect();
    let lo = |i: usize| {
        let (a, b) = seg(i);
        a.x.min(b.x)
    };
    order.sort_by(|&i, &j| lo(i).total_cmp(&lo(j)).then(i.cmp(&j)));
    let neighbours = |i: usize, j: usize| {
        let d = i.abs_diff(j);
        d <= 1 || (closed && d == count - 1)
    };
    let mut best: Option<SelfCrossing> = None;
    for (k, &i) in order.iter().enumerate() {
        let (a, b) = seg(i);
        let hi = a.x.max(b.x) + tol;
        for &j in &order[k + 1..] {
            if lo(j) > hi {
                break;
            }
            if neighbours(i, j) {
                continue;
            }
            let (c, d) = seg(j);
            if let Some(at) = segments_meet(a, b, c, d, tol) {
                let (first, second) = (i.min(j), i.max(j));
                let found = SelfCrossing { first, second, at };
                if best.is_none_or(|b| (first, second) < (b.first, b.second)) {
                    best = Some(found);
                }
            }
        }
    }
    best
}

/// Where segments `ab` and `cd` meet (within `tol`), if they do.
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2, tol: f64) -> Option<DVec2> {
    let r = b - a;
    let s = d - c;
    let denom = r.perp_dot(s);
    let ac = c - a;
    if denom.abs() > tol * (r.length() + s.length()) {
        let t = ac.perp_dot(s) / denom;
        let u = ac.perp_dot(r) / denom;
        let (tt, tu) = (tol / r.length().max(tol), tol / s.length().max(tol));
        return ((-tt..=1.0 + tt).contains(&t) && (-tu..=1.0 + tu).contains(&u)).then(|| a + r * t);
    }
    // Parallel: they meet only if collinear and overlapping.
    if ac.perp_dot(r).abs() > tol * r.length().max(tol) {
        return None;
    }
    let len2 = r.length_squared();
    if len2 == 0.0 {
        return (a.distance(c) <= tol).then_some(a);
    }
    let t0 = ac.dot(r) / len2;
    let t1 = (d - a).dot(r) / len2;
    let (lo, hi) = (t0.min(t1).max(0.0), t0.max(t1).min(1.0));
    (lo <= hi).then(|| a + r * lo)
}

/// Points along a 2-D curve for a self-crossing check: `per_span` points per non-empty
/// knot span (so arcs and fillets, one span each, are followed closely), from the
/// start, without the end point; each with its parameter.
pub fn sample_spans(curve: &crate::geom::Curve2, per_span: usize) -> Vec<(f64, DVec2)> {
    let breaks = curve.span_breaks();
    let mut out = Vec::with_capacity(breaks.len() * per_span);
    for w in breaks.windows(2) {
        for i in 0..per_span {
            let t = w[0] + (w[1] - w[0]) * i as f64 / per_span as f64;
            out.push((t, curve.point_at(t)));
        }
    }
    out
}
