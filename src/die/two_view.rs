//! The 3-D side curve of a punch opening from its two views (paper 001 sections
//! 3.1-3.2, eq. 1-2, Fig. 3-4; `docs/methods.md`).
//!
//! The designer draws each side of the punch opening twice: in the top view (XY) as the
//! outline of the part, and in the side view (XZ) as the section along which the blank
//! is held. The 3-D curve is the one whose projections are those two drawings; the two
//! views share the x axis, so a point of the 3-D curve is `(x, y_T(x), z_S(x))`.
//!
//! Rather than sampling x evenly, the curves are stepped so that every chord stays within
//! the tolerance `delta` of *both* views (steps 2-6 of paper 001 section 3.2):
//!
//! 1. both views are oriented to run in +x and must be graphs over x;
//! 2. at the current point of each view the local radius of curvature `rho` gives the
//!    chord step `L = 2 sqrt(2 rho delta - delta^2)` and the tangent step
//!    `D = L (1 - delta / rho)` (eq. 1, [`step_lengths`]);
//! 3. each view advances until the projection of its chord on the start tangent is `D`
//!    (eq. 2, [`advance_along_tangent`]);
//! 4. the candidate with the smaller x wins, so neither view steps further than allowed;
//! 5. the other view is located at that x ([`parameter_at_x`]);
//! 6. the 3-D point is `R = (x, y from the top view, z from the side view)`;
//! 7. the points `R_i` are interpolated with a chord-length cubic B-spline.
//!
//! Steps 2-5 are one call of [`next_step`]; [`side_curve_from_two_views`] runs them from
//! the start to the end of the top view's x range.

use glam::DVec3;

use crate::geom::interpolate::{interpolate, Interpolation};
use crate::geom::point::Point;
use crate::geom::{Curve2, Curve3, GeomError, NurbsCurve, Result};

/// Options of [`side_curve_from_two_views`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoView {
    /// The tolerance `delta` (mm): the largest distance allowed between a chord of the
    /// stepping and either view. It sets the step length through eq. 1, so it trades the
    /// number of points against fidelity to the drawings.
    pub delta: f64,
    /// The longest step `L_max` (mm), used where a view is straight (infinite radius of
    /// curvature) and as a cap everywhere. `None` takes an eighth of the shorter of the
    /// two views' lengths over the common x range, so a straight side still gets enough
    /// points for a faithful cubic.
    pub max_step: Option<f64>,
}

impl Default for TwoView {
    /// A tolerance of 0.01 mm (die-face practice) and the length-derived `L_max`.
    fn default() -> Self {
        Self {
            delta: 0.01,
            max_step: None,
        }
    }
}

/// The 3-D side curve and the points it was interpolated through.
#[derive(Debug, Clone, PartialEq)]
pub struct SideCurve {
    /// The cubic B-spline (chord-length parameters on [0, 1]) through [`Self::points`].
    pub curve: Curve3,
    /// The stepped points `R_i = (x, y, z)`, with x strictly increasing from the start
    /// to the end of the top view's x range (both ends exactly). Kept because they are
    /// exact points of both views, while the spline between them is an approximation.
    pub points: Vec<DVec3>,
}

/// Which of the two views set the length of a step (step 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// The top view (XY).
    Top,
    /// The side view (XZ).
    Side,
}

/// One step of the stepping (steps 2-5): where both views are after it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// The common coordinate reached.
    pub x: f64,
    /// Parameter of the top view at `x`.
    pub top_u: f64,
    /// Parameter of the side view at `x`.
    pub side_u: f64,
    /// The view whose candidate had the smaller x and so was taken.
    pub led_by: View,
}

/// Most steps [`side_curve_from_two_views`] takes before giving up (a cusp or a
/// tolerance far below the curve's size would otherwise step without end).
const MAX_STEPS: usize = 1_000_000;

/// Iterations of the 1-D Newton/bisection solvers.
const MAX_ITERATIONS: usize = 200;

/// Re-evaluations of the curvature inside a step (see [`next_step`]).
const CURVATURE_REFINEMENTS: usize = 4;

/// Samples per knot span and per degree when checking that a view is a graph over x.
const GRAPH_SAMPLES_PER_DEGREE: usize = 8;

/// The chord step `L` and tangent step `D` of eq. 1 for the radius of curvature `rho`,
/// tolerance `delta` and longest step `max_step`, as `(L, D)`.
///
/// A chord of length `L = 2 sqrt(2 rho delta - delta^2)` on a circle of radius `rho` is
/// `delta` from its arc; its projection on the tangent at its start is
/// `D = L (1 - delta / rho)`. Where `rho` is infinite (a straight piece) both are
/// `max_step`; a chord longer than `max_step` is shortened to it, with `D` its projection
/// on the same circle. Where `rho <= delta` eq. 1 breaks down (every chord up to `2 rho`
/// is within `delta`), so the step is `L = rho`, `D = rho sqrt(3) / 2`, keeping the
/// stepping close to the sharp bend.
pub fn step_lengths(rho: f64, delta: f64, max_step: f64) -> (f64, f64) {
    let rho = rho.abs();
    // Projection on the start tangent of a chord of length `l` on a circle of radius `rho`.
    let projection = |l: f64| l * (1.0 - (l / (2.0 * rho)).powi(2)).max(0.0).sqrt();
    if !rho.is_finite() {
        return (max_step, max_step);
    }
    if rho <= delta {
        let l = rho.min(max_step);
        return (l, projection(l));
    }
    let l = 2.0 * (2.0 * rho * delta - delta * delta).sqrt();
    if l > max_step {
        return (max_step, projection(max_step));
    }
    (l, l * (1.0 - delta / rho))
}

/// The parameter `u1 >= u` where the chord from `C(u)` projects onto the unit tangent at
/// `u` with length `d` (eq. 2): `(C(u1) - C(u)) . C'(u) / |C'(u)| = d`.
///
/// Solved by Newton iteration safeguarded with bisection, in a bracket found by doubling
/// the step `d / |C'(u)|` from `u`. If the curve ends before the projection reaches `d`,
/// the end of the domain is returned (the caller clamps to the end there anyway).
///
/// Errors: [`GeomError::NotFinite`] for a NaN or infinite `u` or `d`;
/// [`GeomError::ZeroVector`] where `C'(u)` vanishes (no tangent to project on);
/// [`GeomError::NoConvergence`] if the iteration fails (not expected in a bracket).
pub fn advance_along_tangent<P: Point>(curve: &NurbsCurve<P>, u: f64, d: f64) -> Result<f64> {
    if !(u.is_finite() && d.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "tangent step or parameter",
        });
    }
    let (t0, t1) = curve.domain();
    let u = u.clamp(t0, t1);
    if d <= 0.0 || u >= t1 {
        return Ok(u);
    }
    let [c0, d0] = curve.derivatives::<2>(u);
    let speed = d0.length();
    if !(speed.is_finite() && speed > f64::EPSILON * (1.0 + curve.control_scale())) {
        return Err(GeomError::ZeroVector {
            what: "curve derivative",
        });
    }
    let tangent = d0 * (1.0 / speed);
    let f = |t: f64| {
        let [c, dc] = curve.derivatives::<2>(t);
        ((c - c0).dot(tangent) - d, dc.dot(tangent))
    };
    // Bracket: f(u) = -d < 0; double the step until f >= 0 or the domain ends.
    let mut lo = u;
    let mut h = d / speed;
    let hi = loop {
        let t = (u + h).min(t1);
        if f(t).0 >= 0.0 {
            break t;
        }
        if t >= t1 {
            return Ok(t1);
        }
        lo = t;
        h *= 2.0;
    };
    let tol = 1e-12 * (1.0 + d);
    // Newton from the bracket's upper end: exact at once on a straight line.
    solve_bracketed(&f, lo, hi, hi, tol, "tangent step (eq. 2)")
}

/// The parameter where the x coordinate of `curve` equals `x` (step 5), for a curve that
/// increases in x. `guess` (usually the previous step's parameter) starts the Newton
/// iteration and narrows the bracket.
///
/// Errors: [`GeomError::NotFinite`] for a NaN or infinite `x`;
/// [`GeomError::ParameterOutOfRange`] (value `x`, min and max the curve's x range) when
/// `x` lies outside the curve's x range by more than rounding;
/// [`GeomError::NoConvergence`] if the iteration fails.
pub fn parameter_at_x<P: Point>(curve: &NurbsCurve<P>, x: f64, guess: f64) -> Result<f64> {
    if !x.is_finite() {
        return Err(GeomError::NotFinite {
            what: "coordinate value",
        });
    }
    let (t0, t1) = curve.domain();
    let (xa, xb) = (curve.start_point().coord(0), curve.end_point().coord(0));
    let tol = 1e-12 * (1.0 + curve.control_scale());
    if x < xa - 1e3 * tol || x > xb + 1e3 * tol {
        return Err(GeomError::ParameterOutOfRange {
            value: x,
            min: xa,
            max: xb,
        });
    }
    if x <= xa {
        return Ok(t0);
    }
    if x >= xb {
        return Ok(t1);
    }
    let f = |t: f64| {
        let [c, dc] = curve.derivatives::<2>(t);
        (c.coord(0) - x, dc.coord(0))
    };
    let (mut lo, mut hi) = (t0, t1);
    let g = if guess.is_finite() {
        guess.clamp(t0, t1)
    } else {
        0.5 * (t0 + t1)
    };
    if f(g).0 <= 0.0 {
        lo = g;
    } else {
        hi = g;
    }
    solve_bracketed(&f, lo, hi, g, tol, "parameter at x (step 5)")
}

/// Steps 2-5 from the parameters `top_u`, `side_u` (both at the same x) of views that run
/// in +x: each view's candidate by eq. 1 and 2, the smaller x taken, the other view
/// located at that x.
///
/// The radius of curvature is taken at the step's start, then at its middle and end, and
/// the smallest of them is used (up to a few refinements): the paper's local radius at
/// the start alone lets a chord entering a tighter bend (or crossing a knot into one)
/// exceed `delta`.
///
/// Errors: as [`advance_along_tangent`] and [`parameter_at_x`].
pub fn next_step(
    top: &Curve2,
    side: &Curve2,
    top_u: f64,
    side_u: f64,
    delta: f64,
    max_step: f64,
) -> Result<Step> {
    let t = candidate(top, top_u, delta, max_step)?;
    let s = candidate(side, side_u, delta, max_step)?;
    let (xt, xs) = (top.point_at(t).x, side.point_at(s).x);
    if xt <= xs {
        Ok(Step {
            x: xt,
            top_u: t,
            side_u: parameter_at_x(side, xt, side_u)?,
            led_by: View::Top,
        })
    } else {
        Ok(Step {
            x: xs,
            top_u: parameter_at_x(top, xs, top_u)?,
            side_u: s,
            led_by: View::Side,
        })
    }
}

/// The 3-D side curve whose top view (XY) is `top` and whose side view (XZ) is `side`;
/// the two share the x axis. `side`'s 2-D coordinates are `(x, z)`.
///
/// Either view may be drawn in -x (it is reversed); both must be graphs over x (no
/// doubling back). The result spans the top view's x range, which the side view must
/// cover (a longer side view is used only over that range). See the module documentation
/// for the steps.
///
/// Errors: [`GeomError::NotPositive`] for a `delta` or `max_step` that is not a positive
/// number; [`GeomError::Singular`] for a view that does not advance in x or doubles back
/// in x; [`GeomError::ViewsDoNotOverlap`] when the side view does not cover the top
/// view's x range; [`GeomError::NoConvergence`] if the stepping stalls or exceeds a
/// million steps; errors of the steps and of the interpolation otherwise.
pub fn side_curve_from_two_views(top: &Curve2, side: &Curve2, opts: &TwoView) -> Result<SideCurve> {
    let delta = opts.delta;
    if !(delta.is_finite() && delta > 0.0) {
        return Err(GeomError::NotPositive {
            what: "two-view tolerance",
            value: delta,
        });
    }
    if let Some(m) = opts.max_step {
        if !(m.is_finite() && m > 0.0) {
            return Err(GeomError::NotPositive {
                what: "two-view maximum step",
                value: m,
            });
        }
    }
    // Step 1: both views in +x, both graphs over x.
    let top = oriented(top, View::Top)?;
    let side = oriented(side, View::Side)?;
    check_graph_over_x(&top, View::Top)?;
    check_graph_over_x(&side, View::Side)?;

    let (tu0, tu1) = top.domain();
    let (x0, x1) = (top.start_point().x, top.end_point().x);
    let (sx0, sx1) = (side.start_point().x, side.end_point().x);
    let tol = 1e-9 * (1.0 + x0.abs().max(x1.abs()).max(sx0.abs()).max(sx1.abs()));
    if sx0 > x0 + tol || sx1 < x1 - tol {
        return Err(GeomError::ViewsDoNotOverlap {
            top: (x0, x1),
            side: (sx0, sx1),
        });
    }
    let su0 = parameter_at_x(&side, x0.max(sx0), side.domain().0)?;
    let su1 = parameter_at_x(&side, x1.min(sx1), su0)?;
    let max_step = match opts.max_step {
        Some(m) => m,
        None => top.length().min(side.length_between(su0, su1)) / 8.0,
    };
    if !(max_step.is_finite() && max_step > 0.0) {
        return Err(GeomError::NotPositive {
            what: "two-view maximum step",
            value: max_step,
        });
    }

    let point = |x: f64, tu: f64, su: f64| DVec3::new(x, top.point_at(tu).y, side.point_at(su).y);
    let mut points = vec![point(x0, tu0, su0)];
    let (mut x, mut tu, mut su) = (x0, tu0, su0);
    let mut finished = false;
    for _ in 0..MAX_STEPS {
        let step = next_step(&top, &side, tu, su, delta, max_step)?;
        if step.x >= x1 - tol {
            points.push(point(x1, tu1, su1));
            finished = true;
            break;
        }
        if step.x <= x {
            return Err(GeomError::NoConvergence {
                what: "two-view stepping (no progress in x)",
                iterations: points.len(),
                residual: x1 - x,
            });
        }
        let (nx, ntu, nsu) = if x1 - step.x < 0.3 * (step.x - x) {
            // A sliver would remain before the end: split the rest evenly instead, so no
            // two points crowd together (both halves are shorter than the allowed step).
            let xm = 0.5 * (x + x1);
            (
                xm,
                parameter_at_x(&top, xm, tu)?,
                parameter_at_x(&side, xm, su)?,
            )
        } else {
            (step.x, step.top_u, step.side_u)
        };
        points.push(point(nx, ntu, nsu));
        (x, tu, su) = (nx, ntu, nsu);
    }
    if !finished {
        return Err(GeomError::NoConvergence {
            what: "two-view stepping (too many steps)",
            iterations: MAX_STEPS,
            residual: x1 - x,
        });
    }
    // A cubic needs four points: split the widest x gaps of very short or straight sides.
    while points.len() < 4 {
        let i = (0..points.len() - 1)
            .max_by(|&a, &b| {
                (points[a + 1].x - points[a].x).total_cmp(&(points[b + 1].x - points[b].x))
            })
            .unwrap_or(0);
        let xm = 0.5 * (points[i].x + points[i + 1].x);
        let p = point(
            xm,
            parameter_at_x(&top, xm, tu0)?,
            parameter_at_x(&side, xm, su0)?,
        );
        points.insert(i + 1, p);
    }
    // Step 7.
    let curve = interpolate(&points, &Interpolation::default())?;
    Ok(SideCurve { curve, points })
}

/// The candidate parameter of one view (steps 2-3), with the curvature refined over the
/// step as [`next_step`] describes.
fn candidate(curve: &Curve2, u: f64, delta: f64, max_step: f64) -> Result<f64> {
    let radius = |t: f64| 1.0 / curve.curvature(t);
    let mut rho = radius(u);
    let mut u1 = advance_along_tangent(curve, u, step_lengths(rho, delta, max_step).1)?;
    for _ in 0..CURVATURE_REFINEMENTS {
        let inside = radius(0.5 * (u + u1)).min(radius(u1));
        if inside.is_nan() || inside >= rho * (1.0 - 1e-9) {
            break;
        }
        rho = inside;
        u1 = advance_along_tangent(curve, u, step_lengths(rho, delta, max_step).1)?;
    }
    Ok(u1)
}

/// `curve` run in +x, or an error if its ends have the same x.
fn oriented(curve: &Curve2, view: View) -> Result<Curve2> {
    let (a, b) = (curve.start_point().x, curve.end_point().x);
    let tol = 1e-12 * (1.0 + curve.control_scale());
    if (b - a).abs() <= tol {
        return Err(GeomError::Singular {
            what: match view {
                View::Top => "the top view does not advance in x (its ends have the same x)",
                View::Side => "the side view does not advance in x (its ends have the same x)",
            },
        });
    }
    Ok(if b < a {
        curve.reversed()
    } else {
        curve.clone()
    })
}

/// Checks that `curve` (run in +x) never runs backwards in x: every knot span is sampled
/// and neither the sampled x values nor the derivative's x component may decrease beyond
/// rounding. The two-view method needs one point per x on each view.
fn check_graph_over_x(curve: &Curve2, view: View) -> Result<()> {
    let tol = 1e-9 * (1.0 + curve.control_scale());
    let per_span = GRAPH_SAMPLES_PER_DEGREE * (curve.degree() + 1);
    let breaks = curve.span_breaks();
    let mut last_x = f64::NEG_INFINITY;
    for w in breaks.windows(2) {
        for k in 0..=per_span {
            let t = w[0] + (w[1] - w[0]) * k as f64 / per_span as f64;
            let [c, d] = curve.derivatives::<2>(t);
            let backwards = c.x < last_x - tol || d.x < -1e-9 * d.length();
            if backwards {
                return Err(GeomError::Singular {
                    what: match view {
                        View::Top => "the top view doubles back in x; the two-view method needs each view to be a graph over x",
                        View::Side => "the side view doubles back in x; the two-view method needs each view to be a graph over x",
                    },
                });
            }
            last_x = last_x.max(c.x);
        }
    }
    Ok(())
}

/// A zero of `f` (value, slope) in `[lo, hi]` with `f(lo) < 0 <= f(hi)`, by Newton from
/// `start` safeguarded with bisection; stops when `|f| <= tol` or the bracket is a few
/// ulps wide.
fn solve_bracketed(
    f: &dyn Fn(f64) -> (f64, f64),
    mut lo: f64,
    mut hi: f64,
    start: f64,
    tol: f64,
    what: &'static str,
) -> Result<f64> {
    let mut t = start.clamp(lo, hi);
    let mut residual = f64::INFINITY;
    for _ in 0..MAX_ITERATIONS {
        let (v, slope) = f(t);
        residual = v.abs();
        if residual <= tol {
            return Ok(t);
        }
        if v < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        if hi - lo <= 4.0 * f64::EPSILON * (1.0 + lo.abs().max(hi.abs())) {
            return Ok(t);
        }
        let newton = t - v / slope;
        t = if newton.is_finite() && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    Err(GeomError::NoConvergence {
        what,
        iterations: MAX_ITERATIONS,
        residual,
    })
}
