//! Point inversion: the closest point on a curve and on a surface.
//!
//! The die features project points onto curves and surfaces all the time (trimming a
//! flange line to the binder, snapping a designer's pick to a profile, measuring the gap
//! between punch and die). The method is P&T section 6.1: a robust start from sampling
//! every non-empty knot span, then Newton iteration on the orthogonality condition
//! `C'(t).(C(t) - P) = 0` (eq. 6.3-6.5), respectively
//! `S_u.(S - P) = S_v.(S - P) = 0` (eq. 6.6-6.8), clamped to the parameter domain.
//!
//! # Tolerances
//!
//! All tolerances are relative to a size of the problem, `size = max(control_scale,
//! |P|)` (the largest control-point or target magnitude; rounding in `S - P` is
//! proportional to it):
//!
//! * point coincidence (P&T `eps1`): `|C - P| <= 1e-12 * size` ([`COINCIDENCE_TOLERANCE`]);
//! * zero cosine (P&T `eps2`): `|C'.(C - P)| <= 1e-12 |C'| |C - P|` ([`COSINE_TOLERANCE`]);
//! * parameter stagnation (P&T's third test): the last Newton step moved the point by at
//!   most `1e-12 * size`, and the cosine test still failed at the new point (the
//!   iteration has reached the rounding floor).
//!
//! Newton steps are safeguarded: a step that would increase the distance (beyond
//! rounding) is halved, and where the Hessian of the squared distance is not positive
//! definite the Gauss-Newton matrix is used instead, so iterations only descend to
//! minima, never climb to maxima or saddles.

use glam::DVec3;

use super::curve::NurbsCurve;
use super::error::{GeomError, Result};
use super::point::Point;
use super::surface::{Direction, NurbsSurface};

/// Relative point-coincidence tolerance (P&T `eps1`): a target within
/// `1e-12 * size` of the curve or surface is on it.
pub const COINCIDENCE_TOLERANCE: f64 = 1e-12;

/// Cosine tolerance (P&T `eps2`): the offset `C - P` is orthogonal to the tangent when
/// the cosine of the angle between them is at most this.
pub const COSINE_TOLERANCE: f64 = 1e-12;

/// Newton iteration cap per start.
const MAX_ITERATIONS: usize = 60;

/// Iteration cap of the bracketed (bisection-safeguarded) solve; bisection alone halves
/// the bracket each time, so this is far beyond what a double needs.
const MAX_BRACKET_ITERATIONS: usize = 200;

/// Curve samples per knot span are `CURVE_SAMPLES_PER_DEGREE * (degree + 1)`: a span of
/// degree `p` can turn at most `p - 1` times, so a few samples per possible turn
/// separate the local minima of the distance.
const CURVE_SAMPLES_PER_DEGREE: usize = 4;

/// Surface samples per span and direction are `SURFACE_SAMPLES_PER_DEGREE * (degree + 1)`,
/// reduced for densely knotted surfaces so that a direction has about
/// [`SURFACE_GRID_TARGET`] samples (at least two per span).
const SURFACE_SAMPLES_PER_DEGREE: usize = 3;

/// Rough number of samples per surface direction above which fewer samples per span are
/// taken: dense knots mean short, simple spans.
const SURFACE_GRID_TARGET: usize = 160;

/// How many sampled local minima start a free Newton iteration.
const START_CANDIDATES: usize = 12;

/// The closest point found on a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint<P> {
    /// Curve parameter of the point.
    pub t: f64,
    /// The point `C(t)`.
    pub point: P,
    /// Distance from the target to `point`.
    pub distance: f64,
}

/// The closest point found on a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Parameter in u.
    pub u: f64,
    /// Parameter in v.
    pub v: f64,
    /// The point `S(u, v)`.
    pub point: DVec3,
    /// Distance from the target to `point`.
    pub distance: f64,
}

/// A surface the Newton iteration of the point inversion can evaluate: its domain, its
/// points and its derivatives up to the second. Every NURBS surface is one; so is a
/// special form that evaluates faster (a hole's Ferguson patches), which then shares
/// the same iteration, the same tests and the same tolerances.
pub trait SurfaceEval {
    /// The parameter range along u.
    fn domain_u(&self) -> (f64, f64);
    /// The parameter range along v.
    fn domain_v(&self) -> (f64, f64);
    /// The point `S(u, v)`.
    fn point_at(&self, u: f64, v: f64) -> DVec3;
    /// `d[k][l]` = `d^(k+l) S / du^k dv^l` at `(u, v)`, read for `k + l <= 2`.
    fn second_derivatives(&self, u: f64, v: f64) -> [[DVec3; 3]; 3];
    /// The size the tolerances are relative to: the largest control-point magnitude.
    fn scale(&self) -> f64;
}

impl SurfaceEval for NurbsSurface {
    fn domain_u(&self) -> (f64, f64) {
        NurbsSurface::domain_u(self)
    }

    fn domain_v(&self) -> (f64, f64) {
        NurbsSurface::domain_v(self)
    }

    fn point_at(&self, u: f64, v: f64) -> DVec3 {
        NurbsSurface::point_at(self, u, v)
    }

    fn second_derivatives(&self, u: f64, v: f64) -> [[DVec3; 3]; 3] {
        self.derivatives::<3>(u, v)
    }

    fn scale(&self) -> f64 {
        self.control_scale()
    }
}

/// Absolute tolerances for one inversion problem.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tolerances {
    /// Point coincidence, `eps1` in P&T.
    pub(crate) coincide: f64,
    /// Smallest point move that still counts as progress.
    pub(crate) step: f64,
    /// Rounding slack when comparing distances.
    pub(crate) slack: f64,
}

impl Tolerances {
    /// Tolerances for geometry of magnitude `scale` and a target of magnitude `target`.
    pub(crate) fn new(scale: f64, target: f64) -> Self {
        let size = scale.max(target).max(f64::MIN_POSITIVE);
        Self {
            coincide: COINCIDENCE_TOLERANCE * size,
            step: COINCIDENCE_TOLERANCE * size,
            slack: 16.0 * f64::EPSILON * size,
        }
    }
}

/// Parameters sampling every non-empty span between consecutive `breaks` at `per_span`
/// equal steps, each break included once.
pub(crate) fn span_samples(breaks: &[f64], per_span: usize) -> Vec<f64> {
    let per_span = per_span.max(1);
    let mut out = Vec::with_capacity(breaks.len().saturating_sub(1) * per_span + 1);
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        for i in 0..per_span {
            out.push(a + (b - a) * (i as f64 / per_span as f64));
        }
    }
    if let Some(&last) = breaks.last() {
        out.push(last);
    }
    out
}

/// Sample parameters in u and v for the start grid of surface algorithms: several per
/// knot span, fewer on densely knotted surfaces.
pub(crate) fn surface_grid(surface: &NurbsSurface) -> (Vec<f64>, Vec<f64>) {
    let per_dir = |breaks: Vec<f64>, degree: usize| {
        let spans = breaks.len().saturating_sub(1).max(1);
        let per_span = (SURFACE_SAMPLES_PER_DEGREE * (degree + 1))
            .min(SURFACE_GRID_TARGET.div_ceil(spans))
            .max(2);
        span_samples(&breaks, per_span)
    };
    let bu: Vec<f64> = surface
        .knots_u()
        .distinct()
        .into_iter()
        .map(|(k, _)| k)
        .collect();
    let bv: Vec<f64> = surface
        .knots_v()
        .distinct()
        .into_iter()
        .map(|(k, _)| k)
        .collect();
    (
        per_dir(bu, surface.degree_u()),
        per_dir(bv, surface.degree_v()),
    )
}

/// Indices `(i, j)` of the local minima of a row-major `nu x nv` grid of values (each no
/// larger than its up to eight neighbours), best first, at most `limit` of them.
pub(crate) fn grid_local_minima(
    values: &[f64],
    nu: usize,
    nv: usize,
    limit: usize,
) -> Vec<(usize, usize)> {
    let mut minima = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let here = values[i * nv + j];
            let mut is_min = true;
            'neighbours: for di in -1i64..=1 {
                for dj in -1i64..=1 {
                    let (ni, nj) = (i as i64 + di, j as i64 + dj);
                    if (di, dj) == (0, 0) || ni < 0 || nj < 0 || ni >= nu as i64 || nj >= nv as i64
                    {
                        continue;
                    }
                    if values[ni as usize * nv + nj as usize] < here {
                        is_min = false;
                        break 'neighbours;
                    }
                }
            }
            if is_min {
                minima.push((i, j));
            }
        }
    }
    minima.sort_by(|a, b| values[a.0 * nv + a.1].total_cmp(&values[b.0 * nv + b.1]));
    // Plateaus give runs of equal neighbouring minima; keep one per plateau cell block by
    // dropping minima adjacent to an earlier (better or equal) one.
    let mut kept: Vec<(usize, usize)> = Vec::new();
    for m in minima {
        if kept
            .iter()
            .any(|k| k.0.abs_diff(m.0) <= 1 && k.1.abs_diff(m.1) <= 1)
        {
            continue;
        }
        kept.push(m);
        if kept.len() >= limit {
            break;
        }
    }
    kept
}

/// The better of two optional results by distance.
fn keep_best<T: Copy>(best: &mut Option<(T, f64)>, value: T, distance: f64) {
    if best.as_ref().is_none_or(|(_, d)| distance < *d) {
        *best = Some((value, distance));
    }
}

/// `Ok(value)` unless the distance overflowed (a target beyond f64 range of the geometry).
fn finite_distance<T>(value: T, distance: f64) -> Result<T> {
    if distance.is_finite() {
        Ok(value)
    } else {
        Err(GeomError::NotFinite {
            what: "distance to the target",
        })
    }
}

/// Result of one Newton run: the point reached and whether it met a convergence test.
struct Outcome<T> {
    value: T,
    converged: bool,
    /// The cosine (or distance) that failed, for error reports.
    residual: f64,
}

// ---------------------------------------------------------------------------------------
// Curves
// ---------------------------------------------------------------------------------------

fn curve_point<P: Point>(curve: &NurbsCurve<P>, target: P, t: f64) -> CurvePoint<P> {
    let point = curve.point_at(t);
    CurvePoint {
        t,
        point,
        distance: point.distance(target),
    }
}

/// Safeguarded Newton (P&T eq. 6.3) from `t`, clamped to the domain, descending only.
fn newton_curve<P: Point>(
    curve: &NurbsCurve<P>,
    target: P,
    mut t: f64,
    tol: Tolerances,
) -> Outcome<CurvePoint<P>> {
    let (t0, t1) = curve.domain();
    t = t.clamp(t0, t1);
    let mut last_move = f64::INFINITY;
    let mut residual = f64::INFINITY;
    for _ in 0..MAX_ITERATIONS {
        let [c, d1, d2] = curve.derivatives::<3>(t);
        let r = c - target;
        let dist = r.length();
        let here = CurvePoint {
            t,
            point: c,
            distance: dist,
        };
        if dist <= tol.coincide {
            return Outcome {
                value: here,
                converged: true,
                residual: dist,
            };
        }
        let f = d1.dot(r);
        let speed2 = d1.dot(d1);
        let speed = speed2.sqrt();
        // A clamped end where the distance grows into the domain is a true end minimum.
        let end_min = (t <= t0 && f >= 0.0) || (t >= t1 && f <= 0.0);
        if end_min || f.abs() <= COSINE_TOLERANCE * speed * dist {
            return Outcome {
                value: here,
                converged: true,
                residual: 0.0,
            };
        }
        residual = f.abs() / (speed * dist);
        if last_move <= tol.step {
            // P&T's third test: the parameter no longer moves the point.
            return Outcome {
                value: here,
                converged: true,
                residual,
            };
        }
        let fp = d2.dot(r) + speed2;
        let step = if fp > 0.0 {
            -f / fp
        } else if speed2 > 0.0 {
            -f / speed2 // Gauss-Newton: always a descent direction.
        } else {
            break;
        };
        if !step.is_finite() {
            break;
        }
        let mut lambda = 1.0;
        let mut accepted = None;
        for _ in 0..40 {
            let tn = (t + lambda * step).clamp(t0, t1);
            let dn = curve.point_at(tn).distance(target);
            if dn <= dist + tol.slack {
                accepted = Some(tn);
                break;
            }
            lambda *= 0.5;
        }
        let Some(tn) = accepted else { break };
        if tn == t {
            // The step is below the parameter's resolution: the point no longer moves
            // at all (P&T's third test), so `t` is the minimum to rounding.
            last_move = 0.0;
            break;
        }
        last_move = (tn - t).abs() * speed;
        t = tn;
    }
    let value = curve_point(curve, target, t);
    // Stalled at the rounding floor with the point essentially fixed: accept (P&T test 3).
    let converged = last_move <= tol.step;
    Outcome {
        value,
        converged,
        residual,
    }
}

/// Root of `f(t) = C'.(C - P)` in `[a, b]` with `f(a) < 0 < f(b)` (a local minimum of the
/// distance), by Newton safeguarded with bisection. Always converges.
fn bracketed_curve_min<P: Point>(
    curve: &NurbsCurve<P>,
    target: P,
    mut a: f64,
    mut b: f64,
    tol: Tolerances,
) -> CurvePoint<P> {
    let mut t = 0.5 * (a + b);
    let mut last_width = f64::INFINITY;
    for _ in 0..MAX_BRACKET_ITERATIONS {
        let [c, d1, d2] = curve.derivatives::<3>(t);
        let r = c - target;
        let dist = r.length();
        let f = d1.dot(r);
        let speed2 = d1.dot(d1);
        let speed = speed2.sqrt();
        if dist <= tol.coincide || f.abs() <= COSINE_TOLERANCE * speed * dist {
            break;
        }
        if f < 0.0 {
            a = t;
        } else {
            b = t;
        }
        let width = b - a;
        if width * speed <= 0.01 * tol.step || width <= 4.0 * f64::EPSILON * (a.abs().max(b.abs()))
        {
            break;
        }
        let fp = d2.dot(r) + speed2;
        let newton = if fp > 0.0 { t - f / fp } else { f64::NAN };
        // Bisect when Newton leaves the bracket or the bracket stopped shrinking fast.
        t = if newton > a && newton < b && width < 0.75 * last_width {
            newton
        } else {
            0.5 * (a + b)
        };
        last_width = width;
    }
    curve_point(curve, target, t)
}

/// The point of `curve` closest to `target`.
///
/// Every non-empty knot span is sampled at `4 (degree + 1)` parameters; each sign change
/// from negative to positive of `f(t) = C'(t).(C(t) - P)` between neighbouring samples
/// brackets a local minimum of the distance, refined by bisection-safeguarded Newton;
/// the best sampled local minima also start free Newton iterations (P&T eq. 6.3,
/// clamped to the domain) to catch minima hidden between two samples; the curve's end
/// points are candidates when the distance grows into the domain there. The closest
/// converged candidate wins. The result is a global minimum except when two local minima
/// closer than the sample spacing compete (then the better one of those found is kept).
///
/// Errors: [`GeomError::NotFinite`] for a NaN or infinite target;
/// [`GeomError::NoConvergence`] if no candidate converged (not expected: bracketed
/// minima always converge).
pub fn closest_point_on_curve<P: Point>(curve: &NurbsCurve<P>, target: P) -> Result<CurvePoint<P>> {
    if !target.is_finite() {
        return Err(GeomError::NotFinite {
            what: "target point",
        });
    }
    let tol = Tolerances::new(curve.control_scale(), target.length());
    let (t0, t1) = curve.domain();
    let per_span = CURVE_SAMPLES_PER_DEGREE * (curve.degree() + 1);
    // (t, distance, f) at the parameters of `span_samples`, each span's samples
    // evaluated in that span (looked up once per span, not once per sample: a long curve
    // has tens of thousands).
    let breaks = curve.span_breaks();
    let sample = |span: usize, t: f64| {
        let [c, d1] = curve.derivatives_in::<2>(span, t);
        let r = c - target;
        (t, r.length(), d1.dot(r))
    };
    let (knots, degree) = (curve.knots(), curve.degree());
    let mut samples: Vec<(f64, f64, f64)> =
        Vec::with_capacity(breaks.len().saturating_sub(1) * per_span + 1);
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        let span = knots.span(degree, a);
        for i in 0..per_span {
            samples.push(sample(span, a + (b - a) * (i as f64 / per_span as f64)));
        }
    }
    if let Some(&last) = breaks.last() {
        samples.push(sample(knots.span(degree, last), last));
    }

    let mut best: Option<(CurvePoint<P>, f64)> = None;
    let offer = |cp: CurvePoint<P>, best: &mut Option<(CurvePoint<P>, f64)>| {
        keep_best(best, cp, cp.distance)
    };

    // End points: minima when the distance grows into the domain.
    if let (Some(first), Some(last)) = (samples.first(), samples.last()) {
        if first.2 >= 0.0 || first.1 <= tol.coincide {
            offer(curve_point(curve, target, t0), &mut best);
        }
        if last.2 <= 0.0 || last.1 <= tol.coincide {
            offer(curve_point(curve, target, t1), &mut best);
        }
    }
    // Bracketed minima.
    for w in samples.windows(2) {
        let ((ta, _, fa), (tb, _, fb)) = (w[0], w[1]);
        if fa == 0.0 {
            offer(curve_point(curve, target, ta), &mut best);
        } else if fa < 0.0 && fb > 0.0 {
            offer(bracketed_curve_min(curve, target, ta, tb, tol), &mut best);
        }
    }
    // Free Newton from the sampled local minima of the distance.
    let mut minima: Vec<usize> = (0..samples.len())
        .filter(|&i| {
            let d = samples[i].1;
            (i == 0 || samples[i - 1].1 >= d) && (i + 1 == samples.len() || samples[i + 1].1 >= d)
        })
        .collect();
    minima.sort_by(|&a, &b| samples[a].1.total_cmp(&samples[b].1));
    let mut residual = f64::INFINITY;
    for &i in minima.iter().take(START_CANDIDATES) {
        let out = newton_curve(curve, target, samples[i].0, tol);
        if out.converged {
            offer(out.value, &mut best);
        } else {
            residual = residual.min(out.residual);
        }
    }
    match best {
        Some((cp, _)) => finite_distance(cp, cp.distance),
        None => Err(GeomError::NoConvergence {
            what: "closest point on curve",
            iterations: MAX_ITERATIONS,
            residual,
        }),
    }
}

/// The closest point of `curve` to `target` near the parameter `t_guess`, for callers
/// that march along a curve (projecting a sequence of nearby points).
///
/// Newton iteration starts at `t_guess` (clamped to the domain) and returns the local
/// minimum it converges to, which need not be the global one; if it does not converge,
/// the global search of [`closest_point_on_curve`] answers instead.
///
/// Errors: [`GeomError::NotFinite`] for a NaN or infinite target or guess, otherwise as
/// [`closest_point_on_curve`].
pub fn project_to_curve_near<P: Point>(
    curve: &NurbsCurve<P>,
    target: P,
    t_guess: f64,
) -> Result<CurvePoint<P>> {
    let out = newton_from(curve, target, t_guess)?;
    if out.converged {
        return finite_distance(out.value, out.value.distance);
    }
    closest_point_on_curve(curve, target)
}

/// Newton's projection of `target` onto `curve` from `t_guess`, after checking that
/// both are finite: what the two local projections share.
fn newton_from<P: Point>(
    curve: &NurbsCurve<P>,
    target: P,
    t_guess: f64,
) -> Result<Outcome<CurvePoint<P>>> {
    if !target.is_finite() {
        return Err(GeomError::NotFinite {
            what: "target point",
        });
    }
    if !t_guess.is_finite() {
        return Err(GeomError::NotFinite {
            what: "parameter guess",
        });
    }
    let tol = Tolerances::new(curve.control_scale(), target.length());
    Ok(newton_curve(curve, target, t_guess, tol))
}

/// A point of `curve` near `target`, found by Newton from `t_guess` alone: the foot
/// it converges to or, where it does not converge, its last iterate. Never the global
/// search of [`project_to_curve_near`]: for callers that want a distance near a known
/// match and take an upper bound where Newton fails (the point found lies on the curve,
/// so its distance is at least the true one), rather than a search of every span of a
/// long curve for each sample.
///
/// Errors: [`GeomError::NotFinite`] for a NaN or infinite target or guess, or a point
/// that evaluates to non-finite coordinates.
pub fn project_to_curve_locally<P: Point>(
    curve: &NurbsCurve<P>,
    target: P,
    t_guess: f64,
) -> Result<CurvePoint<P>> {
    let out = newton_from(curve, target, t_guess)?;
    finite_distance(out.value, out.value.distance)
}

// ---------------------------------------------------------------------------------------
// Surfaces
// ---------------------------------------------------------------------------------------

fn surface_point<S: SurfaceEval + ?Sized>(
    surface: &S,
    target: DVec3,
    u: f64,
    v: f64,
) -> SurfacePoint {
    let point = surface.point_at(u, v);
    SurfacePoint {
        u,
        v,
        point,
        distance: point.distance(target),
    }
}

/// Solves the symmetric 2x2 system `[a b; b c] x = -(gu, gv)`, or `None` if singular.
fn solve_sym2(a: f64, b: f64, c: f64, gu: f64, gv: f64) -> Option<(f64, f64)> {
    let det = a * c - b * b;
    if !(det.is_finite() && det.abs() > 1e-300) {
        return None;
    }
    let du = (-gu * c + gv * b) / det;
    let dv = (-gv * a + gu * b) / det;
    (du.is_finite() && dv.is_finite()).then_some((du, dv))
}

/// Safeguarded 2-D Newton (P&T eq. 6.6-6.8) from `(u, v)`, clamped to the domain. A
/// parameter at a domain bound whose gradient points out of the domain is frozen, and
/// the iteration continues as a 1-D problem along that edge (none at a corner minimum).
fn newton_surface<S: SurfaceEval + ?Sized>(
    surface: &S,
    target: DVec3,
    u: f64,
    v: f64,
    tol: Tolerances,
) -> Outcome<SurfacePoint> {
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    let (mut u, mut v) = (u.clamp(u0, u1), v.clamp(v0, v1));
    let mut last_move = f64::INFINITY;
    let mut residual = f64::INFINITY;
    for _ in 0..MAX_ITERATIONS {
        let d = surface.second_derivatives(u, v);
        let (s, su, sv) = (d[0][0], d[1][0], d[0][1]);
        let r = s - target;
        let dist = r.length();
        let here = SurfacePoint {
            u,
            v,
            point: s,
            distance: dist,
        };
        if dist <= tol.coincide {
            return Outcome {
                value: here,
                converged: true,
                residual: dist,
            };
        }
        let (gu, gv) = (r.dot(su), r.dot(sv));
        let (lu, lv) = (su.length(), sv.length());
        let fix_u = (u <= u0 && gu >= 0.0) || (u >= u1 && gu <= 0.0);
        let fix_v = (v <= v0 && gv >= 0.0) || (v >= v1 && gv <= 0.0);
        let ok_u = fix_u || gu.abs() <= COSINE_TOLERANCE * lu * dist;
        let ok_v = fix_v || gv.abs() <= COSINE_TOLERANCE * lv * dist;
        if ok_u && ok_v {
            return Outcome {
                value: here,
                converged: true,
                residual: 0.0,
            };
        }
        let cos = |g: f64, l: f64| if l > 0.0 { g.abs() / (l * dist) } else { 0.0 };
        residual =
            (if fix_u { 0.0 } else { cos(gu, lu) }).max(if fix_v { 0.0 } else { cos(gv, lv) });
        if last_move <= tol.step {
            return Outcome {
                value: here,
                converged: true,
                residual,
            };
        }
        // Hessian of |S - P|^2 / 2 (the Jacobian of eq. 6.7).
        let (guu, guv, gvv) = (su.dot(su), su.dot(sv), sv.dot(sv));
        let huu = guu + r.dot(d[2][0]);
        let huv = guv + r.dot(d[1][1]);
        let hvv = gvv + r.dot(d[0][2]);
        let one_dim = |g: f64, h: f64, gn: f64| {
            if h > 0.0 {
                -g / h
            } else if gn > 0.0 {
                -g / gn
            } else {
                0.0
            }
        };
        let (mut du, mut dv) = match (fix_u, fix_v) {
            (false, false) => {
                let newton = if huu > 0.0 && huu * hvv - huv * huv > 0.0 {
                    solve_sym2(huu, huv, hvv, gu, gv)
                } else {
                    None
                };
                newton
                    .or_else(|| {
                        // Gauss-Newton, regularized for a degenerate parametrization.
                        let mu = 1e-12 * (guu + gvv) + f64::MIN_POSITIVE;
                        solve_sym2(guu + mu, guv, gvv + mu, gu, gv)
                    })
                    .unwrap_or((0.0, 0.0))
            }
            (true, false) => (0.0, one_dim(gv, hvv, gvv)),
            (false, true) => (one_dim(gu, huu, guu), 0.0),
            (true, true) => (0.0, 0.0),
        };
        // A step the bounds cancel entirely: fall back to projected steepest descent.
        if (u + du).clamp(u0, u1) == u && (v + dv).clamp(v0, v1) == v {
            du = if fix_u || guu <= 0.0 { 0.0 } else { -gu / guu };
            dv = if fix_v || gvv <= 0.0 { 0.0 } else { -gv / gvv };
        }
        if !(du.is_finite() && dv.is_finite()) {
            break;
        }
        let mut lambda = 1.0;
        let mut accepted = None;
        for _ in 0..40 {
            let nu = (u + lambda * du).clamp(u0, u1);
            let nv = (v + lambda * dv).clamp(v0, v1);
            if surface.point_at(nu, nv).distance(target) <= dist + tol.slack {
                accepted = Some((nu, nv));
                break;
            }
            lambda *= 0.5;
        }
        let Some((nu, nv)) = accepted else { break };
        if nu == u && nv == v {
            // The step is below the parameters' resolution: the point no longer moves
            // at all (P&T's third test), so `(u, v)` is the minimum to rounding.
            last_move = 0.0;
            break;
        }
        last_move = (su * (nu - u) + sv * (nv - v)).length();
        u = nu;
        v = nv;
    }
    let value = surface_point(surface, target, u, v);
    Outcome {
        value,
        converged: last_move <= tol.step,
        residual,
    }
}

/// The point of `surface` closest to `target`.
///
/// The surface is sampled on a grid with several parameters per knot span and direction
/// (`3 (degree + 1)`, fewer on densely knotted surfaces); the best local minima of the
/// sampled distance start a 2-D Newton iteration (P&T eq. 6.6-6.8 with the second
/// derivatives) clamped to the domain, which continues along an edge as a 1-D problem
/// where it is pushed onto one. The four boundary curves are searched globally with
/// [`closest_point_on_curve`], and their minima start the same 2-D iteration (it stays
/// on the edge when that is a true boundary minimum, and moves inside otherwise). The
/// closest converged candidate wins.
///
/// At an interior result, `(S - P).S_u` and `(S - P).S_v` vanish to
/// [`COSINE_TOLERANCE`] relative to `|S - P| |S_u|` (up to rounding), unless the target
/// is on the surface.
///
/// Errors: [`GeomError::NotFinite`] for a NaN or infinite target;
/// [`GeomError::NoConvergence`] if no start converged.
pub fn closest_point_on_surface(surface: &NurbsSurface, target: DVec3) -> Result<SurfacePoint> {
    if !target.is_finite() {
        return Err(GeomError::NotFinite {
            what: "target point",
        });
    }
    let tol = Tolerances::new(surface.control_scale(), target.length());
    let (us, vs) = surface_grid(surface);
    let (nu, nv) = (us.len(), vs.len());
    let mut dist = Vec::with_capacity(nu * nv);
    for &u in &us {
        for &v in &vs {
            dist.push(surface.point_at(u, v).distance(target));
        }
    }
    let mut starts: Vec<(f64, f64)> = grid_local_minima(&dist, nu, nv, START_CANDIDATES)
        .into_iter()
        .map(|(i, j)| (us[i], vs[j]))
        .collect();
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    for (dir, fixed) in [
        (Direction::U, u0),
        (Direction::U, u1),
        (Direction::V, v0),
        (Direction::V, v1),
    ] {
        let edge = surface.iso_curve(dir, fixed);
        if let Ok(cp) = closest_point_on_curve(&edge, target) {
            starts.push(match dir {
                Direction::U => (fixed, cp.t),
                Direction::V => (cp.t, fixed),
            });
        }
    }
    let mut best: Option<(SurfacePoint, f64)> = None;
    let mut residual = f64::INFINITY;
    for (u, v) in starts {
        let out = newton_surface(surface, target, u, v, tol);
        if out.converged {
            keep_best(&mut best, out.value, out.value.distance);
        } else {
            residual = residual.min(out.residual);
        }
    }
    match best {
        Some((sp, _)) => finite_distance(sp, sp.distance),
        None => Err(GeomError::NoConvergence {
            what: "closest point on surface",
            iterations: MAX_ITERATIONS,
            residual,
        }),
    }
}

/// The closest point of `surface` to `target` near the parameters `guess`, for callers
/// that march along a line of nearby points (measuring the gap along a seam).
///
/// The 2-D Newton iteration of [`closest_point_on_surface`] starts at `guess` (clamped
/// to the domain) and returns the local minimum it converges to, which need not be the
/// global one. A target within [`NEAR_COINCIDENCE`] (relative) of the point reached is
/// on the surface for every purpose: rounding in `S - P` then makes the cosine test
/// meaningless, so that point is returned even if the test did not pass. Otherwise, if
/// Newton does not converge, the global search answers instead.
///
/// Errors: [`GeomError::NotFinite`] for a NaN or infinite target or guess, otherwise as
/// [`closest_point_on_surface`].
pub fn project_to_surface_near(
    surface: &NurbsSurface,
    target: DVec3,
    guess: (f64, f64),
) -> Result<SurfacePoint> {
    if !target.is_finite() {
        return Err(GeomError::NotFinite {
            what: "target point",
        });
    }
    if !(guess.0.is_finite() && guess.1.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "parameter guess",
        });
    }
    match project_by_newton(surface, target, guess) {
        Some(foot) => finite_distance(foot, foot.distance),
        None => closest_point_on_surface(surface, target),
    }
}

/// The foot of `target` on `surface` that the 2-D Newton iteration of
/// [`project_to_surface_near`] reaches from `guess` (clamped to the domain), with the
/// same tests and tolerances; `None` where it does not converge (and the target is not
/// within [`NEAR_COINCIDENCE`] of the point reached), or the target or guess is not
/// finite. No global search follows: for callers with a start they trust and a
/// fallback of their own, on any [`SurfaceEval`].
pub fn project_by_newton<S: SurfaceEval + ?Sized>(
    surface: &S,
    target: DVec3,
    guess: (f64, f64),
) -> Option<SurfacePoint> {
    if !(target.is_finite() && guess.0.is_finite() && guess.1.is_finite()) {
        return None;
    }
    let tol = Tolerances::new(surface.scale(), target.length());
    let out = newton_surface(surface, target, guess.0, guess.1, tol);
    let size = surface.scale().max(target.length());
    let found = out.converged || out.value.distance <= NEAR_COINCIDENCE * size;
    (found && out.value.distance.is_finite()).then_some(out.value)
}

/// Relative distance under which [`project_to_surface_near`] takes the point Newton
/// reached as the foot even when the cosine test fails to rounding (1e-7 of a 1 m part
/// is a tenth of a micrometre: curves that lie on a surface, such as a trim line
/// projected onto it, sit that close, and their direction to the surface is noise).
pub const NEAR_COINCIDENCE: f64 = 1e-7;
