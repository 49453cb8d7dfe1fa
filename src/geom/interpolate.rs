//! Global interpolation: the B-spline through given points (P&T section 9.2).
//!
//! The die features build most of their curves this way: the punch-opening sides
//! through the points of the two-view stepping, the corners through corrected points
//! with end tangents from their neighbours, blankholder outer curves through placed
//! points. Parameters come from the points (chord length or centripetal), knots from
//! averaging the parameters (P&T eq. 9.8, 9.22) or, for the classic C2 cubic spline with
//! both end tangents, at the parameters themselves (what OpenCascade's
//! `GeomAPI_Interpolate` does). End tangents are derivatives with respect to the curve
//! parameter, whose domain is [0, 1] unless parameters are given. A closed loop of points
//! gets the periodic C2 cubic instead ([`interpolate_closed`]): no end conditions, so the
//! curve does not depend on which point of the loop comes first.

use super::banded::BandMatrix;

use super::curve::NurbsCurve;
use super::error::{GeomError, Result};
use super::knots::{check_degree, KnotVector};
use super::ops::{self, Spline};
use super::point::Point;
use super::MAX_DERIVATIVE;

/// How the points are spaced in the curve parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Parametrization {
    /// Equal steps: ignores spacing; only for evenly spaced data.
    Uniform,
    /// Steps proportional to the distance between points (P&T eq. 9.5): the default.
    #[default]
    ChordLength,
    /// Steps proportional to the square root of the distance (P&T eq. 9.6): better for
    /// data with sharp turns.
    Centripetal,
}

/// Where the interior knots go.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum KnotPlacement {
    /// Averages of `degree` consecutive parameters (P&T eq. 9.8 and 9.22): works for
    /// every degree and any end conditions.
    #[default]
    Averaged,
    /// At the interior parameters themselves; needs `degree - 1` end tangents (a cubic
    /// with both, a quadratic with the start one, or a polyline).
    AtParameters,
}

/// Options of [`interpolate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interpolation<P> {
    /// Degree of the result. It is never lowered silently: too few points for it is an
    /// error, so the designer learns of it.
    pub degree: usize,
    /// How parameters are computed from the points.
    pub parametrization: Parametrization,
    /// Where the knots go.
    pub knots: KnotPlacement,
    /// Required derivative `C'(t0)`, if any.
    pub start_tangent: Option<P>,
    /// Required derivative `C'(t1)`, if any.
    pub end_tangent: Option<P>,
}

impl<P: Point> Default for Interpolation<P> {
    fn default() -> Self {
        Self {
            degree: 3,
            parametrization: Parametrization::default(),
            knots: KnotPlacement::default(),
            start_tangent: None,
            end_tangent: None,
        }
    }
}

impl<P: Point> Interpolation<P> {
    /// Cubic, chord length, averaged knots, with the given end tangents.
    pub fn cubic_with_tangents(start: P, end: P) -> Self {
        Self {
            start_tangent: Some(start),
            end_tangent: Some(end),
            ..Self::default()
        }
    }
}

/// Parameters in [0, 1] for `points` (first 0, last 1). Consecutive coincident points
/// are an error: no parameter step can separate them.
pub fn parameters<P: Point>(points: &[P], method: Parametrization) -> Result<Vec<f64>> {
    let steps = parameter_steps(points, method, false)?;
    let total: f64 = steps.iter().sum();
    let mut t = Vec::with_capacity(points.len());
    let mut acc = 0.0;
    t.push(0.0);
    for s in &steps[..steps.len() - 1] {
        acc += s;
        t.push(acc / total);
    }
    t.push(1.0);
    Ok(t)
}

/// The parameter step from each point to the next by `method` (for a `closed` loop also
/// from the last point back to the first), after the checks both [`parameters`] and
/// [`closed_parameters`] make: enough points (2, or 3 for a loop), all finite, no two
/// neighbours within 1e-14 of the points' size.
fn parameter_steps<P: Point>(
    points: &[P],
    method: Parametrization,
    closed: bool,
) -> Result<Vec<f64>> {
    let n = points.len();
    let needed = if closed { 3 } else { 2 };
    if n < needed {
        return Err(GeomError::TooFewPoints { needed, given: n });
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "interpolation point",
        });
    }
    let scale = points
        .iter()
        .map(|p| p.length())
        .fold(0.0, f64::max)
        .max(1e-300);
    let pairs = if closed { n } else { n - 1 };
    let mut steps = Vec::with_capacity(pairs);
    for k in 0..pairs {
        let next = (k + 1) % n;
        let d = points[k].distance(points[next]);
        if d <= 1e-14 * scale {
            return Err(GeomError::CoincidentPoints {
                first: k,
                second: next,
            });
        }
        steps.push(match method {
            Parametrization::Uniform => 1.0,
            Parametrization::ChordLength => d,
            Parametrization::Centripetal => d.sqrt(),
        });
    }
    Ok(steps)
}

/// The B-spline of `opts.degree` through `points`, with the optional end tangents.
pub fn interpolate<P: Point>(points: &[P], opts: &Interpolation<P>) -> Result<NurbsCurve<P>> {
    let params = parameters(points, opts.parametrization)?;
    interpolate_at(points, &params, opts)
}

/// Like [`interpolate`] with explicit, strictly increasing parameters; the curve's
/// domain is `[params[0], params[last]]` and `C(params[k]) = points[k]`.
pub fn interpolate_at<P: Point>(
    points: &[P],
    params: &[f64],
    opts: &Interpolation<P>,
) -> Result<NurbsCurve<P>> {
    let p = opts.degree;
    check_degree(p)?;
    if params.len() != points.len() {
        return Err(GeomError::LengthMismatch {
            what: "parameters",
            expected: points.len(),
            given: params.len(),
        });
    }
    if points.len() < 2 {
        return Err(GeomError::TooFewPoints {
            needed: 2,
            given: points.len(),
        });
    }
    if points.iter().any(|q| !q.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "interpolation point",
        });
    }
    if params.iter().any(|t| !t.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "interpolation parameter",
        });
    }
    if let Some(i) = params.windows(2).position(|w| w[1] <= w[0]) {
        return Err(GeomError::CoincidentPoints {
            first: i,
            second: i + 1,
        });
    }
    for tangent in [opts.start_tangent, opts.end_tangent].into_iter().flatten() {
        if !tangent.is_finite() {
            return Err(GeomError::NotFinite {
                what: "end tangent",
            });
        }
        if tangent.length() == 0.0 {
            return Err(GeomError::ZeroVector {
                what: "end tangent",
            });
        }
    }
    let n = points.len() - 1;
    let ders = usize::from(opts.start_tangent.is_some()) + usize::from(opts.end_tangent.is_some());
    let count = n + 1 + ders;
    if count < p + 1 {
        return Err(GeomError::TooFewPoints {
            needed: p + 1 - ders,
            given: points.len(),
        });
    }
    let knots = knot_vector(params, p, opts, count)?;
    let kv = KnotVector::new(knots.clone(), p, count)?;

    // Collocation rows: point 0, [start tangent], points 1..n-1, [end tangent], point n.
    // Each row holds p + 1 basis values: the system is banded, solved as such.
    let mut entries: Vec<(usize, usize, f64)> = Vec::with_capacity(count * (p + 1));
    let mut rhs = vec![0.0; count * P::DIM];
    let mut row = 0;
    let mut put_row = |row: usize, t: f64, order: usize, value: P| {
        let span = kv.span(p, t);
        let mut basis = [[0.0; super::MAX_DEGREE + 1]; MAX_DERIVATIVE + 1];
        kv.basis_derivatives(span, p, t, order, &mut basis);
        for (r, &b) in basis[order].iter().take(p + 1).enumerate() {
            entries.push((row, span - p + r, b));
        }
        for d in 0..P::DIM {
            rhs[row * P::DIM + d] = value.coord(d);
        }
    };
    for k in 0..=n {
        if k == n {
            if let Some(tan) = opts.end_tangent {
                put_row(row, params[n], 1, tan);
                row += 1;
            }
        }
        put_row(row, params[k], 0, points[k]);
        row += 1;
        if k == 0 {
            if let Some(tan) = opts.start_tangent {
                put_row(row, params[0], 1, tan);
                row += 1;
            }
        }
    }
    let lower = entries
        .iter()
        .map(|&(i, j, _)| i.saturating_sub(j))
        .max()
        .unwrap_or(0);
    let upper = entries
        .iter()
        .map(|&(i, j, _)| j.saturating_sub(i))
        .max()
        .unwrap_or(0);
    let mut matrix = BandMatrix::zeros(count, lower, upper);
    for (i, j, value) in entries {
        let inside = matrix.set(i, j, value);
        debug_assert!(inside, "the bandwidths were measured from these entries");
    }
    let singular = GeomError::Singular {
        what: "the interpolation system has no unique solution for these parameters",
    };
    matrix.solve(&mut rhs, P::DIM).ok_or(singular.clone())?;
    let mut control = Vec::with_capacity(count);
    for i in 0..count {
        let mut q = P::ZERO;
        for d in 0..P::DIM {
            q = q + P::axis(d) * rhs[i * P::DIM + d];
        }
        if !q.is_finite() {
            return Err(singular);
        }
        control.push(q);
    }
    // The ends are interpolated exactly; pin them against rounding in the solve.
    control[0] = points[0];
    control[count - 1] = points[n];
    NurbsCurve::new(p, knots, control)
}

/// The clamped knot vector for `count` control points of degree `p` on `params`.
fn knot_vector<P: Point>(
    params: &[f64],
    p: usize,
    opts: &Interpolation<P>,
    count: usize,
) -> Result<Vec<f64>> {
    let n = params.len() - 1;
    let (t0, t1) = (params[0], params[n]);
    let mut knots = vec![t0; p + 1];
    match opts.knots {
        KnotPlacement::Averaged => {
            // Averages of p consecutive entries of the parameter list in which each end
            // with a tangent condition appears twice (eq. 9.8 without, 9.22 with tangents).
            let mut aug = Vec::with_capacity(count);
            aug.push(t0);
            if opts.start_tangent.is_some() {
                aug.push(t0);
            }
            aug.extend_from_slice(&params[1..n]);
            if opts.end_tangent.is_some() {
                aug.push(t1);
            }
            aug.push(t1);
            for j in 1..count - p {
                let s: f64 = aug[j..j + p].iter().sum();
                knots.push(s / p as f64);
            }
        }
        KnotPlacement::AtParameters => {
            let ders = count - (n + 1);
            if ders + 1 != p {
                return Err(GeomError::KnotVector {
                    reason: format!(
                        "knots at the parameters need degree - 1 = {} end tangents, {ders} given",
                        p - 1
                    ),
                });
            }
            knots.extend_from_slice(&params[1..n]);
        }
    }
    knots.extend(std::iter::repeat_n(t1, p + 1));
    Ok(knots)
}

/// Parameters in [0, 1) for a closed loop of points, the last point NOT repeated: point
/// `k` gets the share of the loop's length (chord length, centripetal or uniform, as in
/// [`parameters`]) before it, the step from the last point back to the first included,
/// so the loop's period is 1. Rotating the points cyclically shifts every parameter by
/// the same amount (mod 1): nothing depends on which point comes first. Coincident
/// neighbours (the last and the first included) are an error.
pub fn closed_parameters<P: Point>(points: &[P], method: Parametrization) -> Result<Vec<f64>> {
    let n = points.len();
    let steps = parameter_steps(points, method, true)?;
    let total: f64 = steps.iter().sum();
    let mut t = Vec::with_capacity(n);
    let mut acc = 0.0;
    for s in &steps[..n - 1] {
        t.push(acc / total);
        acc += s;
    }
    t.push(acc / total);
    Ok(t)
}

/// The closed (periodic) C2 cubic through a loop of distinct points, the last point NOT
/// repeated: the classic periodic cubic spline, with a knot at every point's parameter
/// ([`closed_parameters`]) and no end conditions, so no point of the loop is special.
/// Rotating the points cyclically gives the same curve (the same point set, its
/// parametrization shifted): a closed sketch projected or offset this way does not
/// depend on where it was started.
///
/// The result is an ordinary clamped cubic on [0, 1] that starts and ends at
/// `points[0]`, with simple knots at the other points' parameters. It is C2 across its
/// seam: joined to itself end to start, the triple knot of the join can be removed twice
/// exactly ([`NurbsCurve::remove_knot`]). The periodic curve is built on the knot vector
/// extended periodically past both ends, then clamped at 0 and 1 by knot insertion.
pub fn interpolate_closed<P: Point>(
    points: &[P],
    method: Parametrization,
) -> Result<NurbsCurve<P>> {
    let params = closed_parameters(points, method)?;
    interpolate_closed_at(points, &params)
}

/// Like [`interpolate_closed`] with explicit parameters: `params` strictly increasing
/// within [`params[0]`, `params[0] + 1`), the period being 1. The curve's domain is
/// `[params[0], params[0] + 1]` and `C(params[k]) = points[k]`.
pub fn interpolate_closed_at<P: Point>(points: &[P], params: &[f64]) -> Result<NurbsCurve<P>> {
    const P3: usize = 3;
    let n = points.len();
    if params.len() != n {
        return Err(GeomError::LengthMismatch {
            what: "parameters",
            expected: n,
            given: params.len(),
        });
    }
    if n < 3 {
        return Err(GeomError::TooFewPoints {
            needed: 3,
            given: n,
        });
    }
    if points.iter().any(|q| !q.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "interpolation point",
        });
    }
    if params.iter().any(|t| !t.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "interpolation parameter",
        });
    }
    let t0 = params[0];
    if let Some(i) = params.windows(2).position(|w| w[1] <= w[0]) {
        return Err(GeomError::CoincidentPoints {
            first: i,
            second: i + 1,
        });
    }
    if params[n - 1] >= t0 + 1.0 {
        return Err(GeomError::CoincidentPoints {
            first: n - 1,
            second: 0,
        });
    }
    // The periodic knot sequence: u(j) = params[j mod n] + floor(j / n).
    let u = |j: isize| {
        let k = j.rem_euclid(n as isize) as usize;
        params[k] + j.div_euclid(n as isize) as f64
    };
    // At the knot u(k) only N(k-3), N(k-2), N(k-1) are non-zero (simple knots, cubic).
    // With X(k) = P(k-2) the conditions form a cyclic tridiagonal system:
    // lo(k) X(k-1) + mid(k) X(k) + hi(k) X(k+1) = Q(k).
    let mut lo = vec![0.0; n];
    let mut mid = vec![0.0; n];
    let mut hi = vec![0.0; n];
    for k in 0..n {
        let k_ = k as isize;
        let (um2, um1, uk, up1, up2) = (u(k_ - 2), u(k_ - 1), u(k_), u(k_ + 1), u(k_ + 2));
        let a = (up1 - uk).powi(2) / ((up1 - um2) * (up1 - um1));
        let c = (uk - um1).powi(2) / ((up2 - um1) * (up1 - um1));
        lo[k] = a;
        hi[k] = c;
        mid[k] = 1.0 - a - c;
    }
    let singular = GeomError::Singular {
        what: "the closed interpolation system has no unique solution for these parameters",
    };
    let x = solve_cyclic_tridiagonal(&lo, &mid, &hi, points).ok_or(singular.clone())?;
    if x.iter().any(|q| !q.is_finite()) {
        return Err(singular);
    }
    // Control point P(j) = X(j + 2), periodic. The unclamped curve with control points
    // P(-3)..=P(n) on the knots u(-3)..=u(n+4) covers [u(0), u(n+1)] ⊃ [t0, t0 + 1].
    let control = |j: isize| x[(j + 2).rem_euclid(n as isize) as usize];
    let spline = Spline {
        degree: P3,
        knots: (-3..=n as isize + 4).map(u).collect(),
        points: (-3..=n as isize).map(control).collect(),
    };
    // Clamp: raise the knots at t0 + 1 (interior here) and t0 (the domain's start) to
    // multiplicity 3, where the curve passes through a control point, and cut there.
    let spline = ops::insert_knot(&spline, u(n as isize), P3 - 1);
    let spline = ops::insert_knot(&spline, t0, P3 - 1);
    // The knots before t0 are u(-3), u(-2), u(-1): the clamped curve's first control
    // point is the one after them (index 2), the n + 3 that follow are its net.
    let first = 2;
    let mut net: Vec<P> = spline.points[first..first + n + 3].to_vec();
    // Both ends are points[0]; pin them against rounding in the solve and insertion.
    net[0] = points[0];
    net[n + 2] = points[0];
    let mut knots = vec![t0; P3 + 1];
    knots.extend_from_slice(&params[1..]);
    knots.extend(std::iter::repeat_n(t0 + 1.0, P3 + 1));
    NurbsCurve::new(P3, knots, net)
}

/// Solves the cyclic tridiagonal system `lo[k] x[k-1] + mid[k] x[k] + hi[k] x[k+1] =
/// rhs[k]` (indices mod n, n >= 3) by the Sherman-Morrison correction of the Thomas
/// algorithm (Numerical Recipes' `cyclic`). The collocation matrix of a periodic cubic
/// is totally positive, which keeps elimination without pivoting stable. `None` when a
/// pivot vanishes.
fn solve_cyclic_tridiagonal<P: Point>(
    lo: &[f64],
    mid: &[f64],
    hi: &[f64],
    rhs: &[P],
) -> Option<Vec<P>> {
    let n = rhs.len();
    let alpha = hi[n - 1]; // row n-1, column 0
    let beta = lo[0]; // row 0, column n-1
    let gamma = -mid[0];
    let mut diag = mid.to_vec();
    diag[0] = mid[0] - gamma;
    diag[n - 1] = mid[n - 1] - alpha * beta / gamma;
    // Thomas: forward elimination shared by both right-hand sides.
    let mut c_prime = vec![0.0; n];
    let mut d = vec![0.0; n];
    let mut piv = diag[0];
    if piv == 0.0 {
        return None;
    }
    d[0] = piv;
    for k in 1..n {
        c_prime[k - 1] = hi[k - 1] / piv;
        piv = diag[k] - lo[k] * c_prime[k - 1];
        if piv == 0.0 || !piv.is_finite() {
            return None;
        }
        d[k] = piv;
    }
    let solve = |r: &dyn Fn(usize) -> P| -> Vec<P> {
        let mut y = vec![P::ZERO; n];
        y[0] = r(0) * (1.0 / d[0]);
        for k in 1..n {
            y[k] = (r(k) - y[k - 1] * lo[k]) * (1.0 / d[k]);
        }
        for k in (0..n - 1).rev() {
            y[k] = y[k] - y[k + 1] * c_prime[k];
        }
        y
    };
    let x = solve(&|k| rhs[k]);
    // The correction vector u = (gamma, 0, ..., 0, alpha), solved as scalars along axis 0.
    let e = P::axis(0);
    let z = solve(&|k| {
        if k == 0 {
            e * gamma
        } else if k == n - 1 {
            e * alpha
        } else {
            P::ZERO
        }
    });
    let (z0, zn) = (z[0].coord(0), z[n - 1].coord(0));
    let denom = 1.0 + z0 + beta * zn / gamma;
    if denom == 0.0 || !denom.is_finite() {
        return None;
    }
    let fact = (x[0] + x[n - 1] * (beta / gamma)) * (1.0 / denom);
    Some(
        x.iter()
            .zip(&z)
            .map(|(&xi, zi)| xi - fact * zi.coord(0))
            .collect(),
    )
}
