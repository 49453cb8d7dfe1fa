//! Global interpolation: the B-spline through given points (P&T section 9.2).
//!
//! The die features build most of their curves this way: the punch-opening sides
//! through the points of the two-view stepping, the corners through corrected points
//! with end tangents from their neighbours, blankholder outer curves through placed
//! points. Parameters come from the points (chord length or centripetal), knots from
//! averaging the parameters (P&T eq. 9.8, 9.22) or, for the classic C2 cubic spline with
//! both end tangents, at the parameters themselves (what OpenCascade's
//! `GeomAPI_Interpolate` does). End tangents are derivatives with respect to the curve
//! parameter, whose domain is [0, 1] unless parameters are given.

use super::banded::BandMatrix;

use super::curve::NurbsCurve;
use super::error::{GeomError, Result};
use super::knots::{check_degree, KnotVector};
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
    if points.len() < 2 {
        return Err(GeomError::TooFewPoints {
            needed: 2,
            given: points.len(),
        });
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
    let mut steps = Vec::with_capacity(points.len() - 1);
    for (i, w) in points.windows(2).enumerate() {
        let d = w[0].distance(w[1]);
        if d <= 1e-14 * scale {
            return Err(GeomError::CoincidentPoints {
                first: i,
                second: i + 1,
            });
        }
        steps.push(match method {
            Parametrization::Uniform => 1.0,
            Parametrization::ChordLength => d,
            Parametrization::Centripetal => d.sqrt(),
        });
    }
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
