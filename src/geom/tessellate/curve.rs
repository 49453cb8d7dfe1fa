//! Curve to polyline by the chordal step rule, with every chord verified.

use crate::geom::curve::{curvature_of, NurbsCurve};
use crate::geom::error::{GeomError, Result};
use crate::geom::point::Point;

use super::{Polyline, Tolerance, MAX_VERTICES};

/// Fraction of the chordal tolerance the step rule aims at, so that the verification
/// (which accepts up to [`ACCEPT`]) passes at the first try on circles and gentle arcs.
const TARGET: f64 = 0.97;

/// Fraction of the chordal tolerance a chord's *sampled* deviation may reach. The 9
/// samples are 1/10 of the chord apart; on a deviation profile that is parabolic near its
/// peak the samples miss the peak by at most 1 %, which this margin covers.
const ACCEPT: f64 = 0.99;

/// Interior samples per chord (at `k / 10` of the parameter interval, midpoint included).
const SAMPLES: usize = 9;

/// Relative parameter step below which a chord is accepted without further checks: the
/// parameter can no longer separate points (a cusp or a stationary point).
const MIN_RELATIVE_STEP: f64 = 1e-12;

/// Approximates `curve` by a polyline within `tol`.
///
/// The vertices always include both ends and every knot of multiplicity >= degree (the
/// C0 points where the curve may kink, so corners stay exact). Between those breaks the
/// curve is marched with the step rule of paper 001 (section 3.2, eq. 1), `L = 2 sqrt(2 rho delta - delta^2)`
/// for the radius of curvature `rho` at the current vertex (`L = L_max` where the curve
/// is straight), limited by the angle (`L <= angle * rho`) and by `tol.max_edge`; the
/// chord length is turned into a parameter step through the speed `|C'|`.
///
/// Every chord is then verified: the curve is sampled at 9 interior parameters of the
/// chord's interval and the largest distance to the chord segment must stay below the
/// tolerance (with a 1 % margin for the space between samples), and the tangent may turn
/// at most `tol.angle` between the chord's ends. A failing chord is shortened (by the
/// square root of the tolerance ratio, as deviation grows with the square of the length)
/// and checked again. Curvature varies along a NURBS curve, so the rule is only the first
/// guess; the check is the guarantee.
///
/// Fails on an invalid tolerance, on coordinates so large that a chord's length or
/// deviation cannot be measured, or when more than [`MAX_VERTICES`] vertices would be
/// needed.
pub fn tessellate_curve<P: Point>(curve: &NurbsCurve<P>, tol: &Tolerance) -> Result<Polyline<P>> {
    tessellate_curve_within(curve, tol, MAX_VERTICES)
}

/// What [`tessellate_curve_within`] names when the polyline would need more vertices
/// than it was allowed.
pub const CURVE_POINT_LIMIT: &str =
    "curve tessellation (point limit reached: the tolerance is too fine for the curve)";

/// [`tessellate_curve`] with at most `max_vertices` vertices (and never more than
/// [`MAX_VERTICES`]): a caller's limit on the points of one curve, so that a huge curve
/// fails at once with [`CURVE_POINT_LIMIT`] instead of marching for minutes.
pub fn tessellate_curve_within<P: Point>(
    curve: &NurbsCurve<P>,
    tol: &Tolerance,
    max_vertices: usize,
) -> Result<Polyline<P>> {
    tol.validate()?;
    let max_vertices = max_vertices.clamp(2, MAX_VERTICES);
    let (t0, t1) = curve.domain();
    let degree = curve.degree();
    let breaks: Vec<f64> = curve
        .knots()
        .distinct()
        .into_iter()
        .filter(|&(k, m)| k == t0 || k == t1 || m >= degree)
        .map(|(k, _)| k)
        .collect();
    let start = curve.point_at(t0);
    if !start.is_finite() {
        return Err(GeomError::NotFinite {
            what: "curve point",
        });
    }
    let mut line = Polyline {
        params: vec![t0],
        points: vec![start],
    };
    for w in breaks.windows(2) {
        march(curve, w[0], w[1], tol, max_vertices, &mut line)?;
    }
    Ok(line)
}

/// Appends the vertices of `(a, b]` to `line`, whose last vertex is the point at `a`.
fn march<P: Point>(
    curve: &NurbsCurve<P>,
    a: f64,
    b: f64,
    tol: &Tolerance,
    max_vertices: usize,
    line: &mut Polyline<P>,
) -> Result<()> {
    let target = TARGET * tol.chordal;
    let accept = ACCEPT * tol.chordal;
    let min_step = MIN_RELATIVE_STEP * (b - a).max(f64::MIN_POSITIVE);
    let mut t = a;
    let mut p = match line.points.last() {
        Some(&p) => p,
        None => curve.point_at(a),
    };
    // Derivatives at the current vertex, from the span to its right (the piece we march on).
    let [_, mut d1, mut d2] = curve.derivatives::<3>(t);
    while t < b {
        let mut dt = first_step(d1, d2, target, tol).min(b - t);
        loop {
            let at_end = dt >= b - t - min_step;
            let te = if at_end { b } else { t + dt };
            let pe = curve.point_at(te);
            if !pe.is_finite() {
                return Err(GeomError::NotFinite {
                    what: "curve point",
                });
            }
            // Tangent at the chord's end, seen from this piece: at a break the knot's own
            // derivative belongs to the next piece, so take the left limit numerically.
            let probe = if at_end { b - (b - a) * 1e-9 } else { te };
            let [_, e1, e2] = curve.derivatives::<3>(probe);
            let mut shrink: f64 = 1.0;
            if dt > min_step {
                let dev = chord_deviation(curve, t, te, p, pe);
                let len = (pe - p).length();
                if !(dev.is_finite() && len.is_finite()) {
                    // Coordinates so large that distances overflow: no chord can be
                    // verified, and shrinking it would march forever.
                    return Err(GeomError::NotFinite {
                        what: "curve chord (coordinates too large to measure)",
                    });
                }
                if dev > accept {
                    shrink = shrink.min((0.95 * (accept / dev).sqrt()).clamp(0.1, 0.9));
                }
                let turn = angle_between(d1, e1);
                if turn > tol.angle {
                    shrink = shrink.min((0.95 * tol.angle / turn).clamp(0.1, 0.9));
                }
                if len > tol.edge_limit() {
                    shrink = shrink.min((0.99 * tol.edge_limit() / len).clamp(0.1, 0.9));
                }
            }
            if shrink < 1.0 {
                dt *= shrink;
                continue;
            }
            if line.points.len() >= max_vertices {
                return Err(GeomError::NoConvergence {
                    what: CURVE_POINT_LIMIT,
                    iterations: line.points.len(),
                    residual: tol.chordal,
                });
            }
            line.params.push(te);
            line.points.push(pe);
            t = te;
            p = pe;
            if !at_end {
                d1 = e1;
                d2 = e2;
            }
            break;
        }
    }
    Ok(())
}

/// The parameter step the step rule suggests at a point with derivatives `d1`, `d2`.
fn first_step<P: Point>(d1: P, d2: P, target: f64, tol: &Tolerance) -> f64 {
    let speed = d1.length();
    if !(speed > 0.0 && speed.is_finite()) {
        return f64::INFINITY; // stationary point: let the verification find the step
    }
    let kappa = curvature_of(d1, d2);
    let mut chord = tol.edge_limit();
    if kappa > 0.0 && kappa.is_finite() {
        let rho = 1.0 / kappa;
        let rule = 2.0 * (2.0 * rho * target - target * target).max(0.0).sqrt();
        // Below rho = delta / 2 the whole circle is within tolerance: any chord up to the
        // diameter will do.
        let rule = if rule > 0.0 { rule } else { 2.0 * rho };
        chord = chord.min(rule).min(tol.angle * rho);
    }
    chord / speed
}

/// Largest distance from the curve on `(t, te)` (sampled) to the segment `p`-`pe`.
fn chord_deviation<P: Point>(curve: &NurbsCurve<P>, t: f64, te: f64, p: P, pe: P) -> f64 {
    let chord = pe - p;
    let len2 = chord.dot(chord);
    let mut worst: f64 = 0.0;
    for k in 1..=SAMPLES {
        let s = k as f64 / (SAMPLES + 1) as f64;
        let q = curve.point_at(t + (te - t) * s);
        let rel = q - p;
        let along = if len2 > 0.0 {
            (rel.dot(chord) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (rel - chord * along).length();
        // A NaN deviation must fail the check, not pass it.
        worst = if d.is_nan() {
            f64::INFINITY
        } else {
            worst.max(d)
        };
    }
    worst
}

/// Angle between two tangents (0 when either vanishes: no direction to compare).
fn angle_between<P: Point>(a: P, b: P) -> f64 {
    let (la, lb) = (a.length(), b.length());
    if !(la > 0.0 && lb > 0.0) {
        return 0.0;
    }
    let cos = a.dot(b) / (la * lb);
    let sin2 = (1.0 - cos * cos).max(0.0);
    sin2.sqrt().atan2(cos)
}
