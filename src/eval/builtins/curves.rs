//! Curve builtins: NURBS from control points, interpolation, exact arcs and circles,
//! lines, reversing, splitting and joining curves, and offsets and stretches of 2-D
//! curves.
//!
//! 2-D input (points `(x, y)`) makes 2-D curves, 3-D input 3-D curves. Where a curve
//! is taken as input, a sketch counts as the 3-D curve it is placed at through its view,
//! so `reverse(sketch)` is a 3-D curve. Curve parameters given to builtins are fractions
//! of the domain (0 to 1, or a percentage), whatever the curve's own domain.
//!
//! `line` and `arc` are sketch keywords, so the builtins are `line_between` and
//! `arc2` (with `arc3` its 3-D sibling).
//!
//! `offset` and `between` work in a plane: they take a 2-D curve or a sketch (its
//! profile in its own view's plane, as the bead's `line` reads it) and return a 2-D
//! curve, so `offset(between(punch_profile, a, b), -90 mm)` can be a bead's `line`.

use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::diag::Diagnostic;
use crate::geom::arc::{arc_through_points, circle as circle_curve, circular_arc};
use crate::geom::interpolate::{interpolate as interp, Interpolation, Parametrization};
use crate::geom::join::join_curves;
use crate::geom::offset::{curve_between, offset_curve2};
use crate::geom::{Curve2, Curve3, GeomError, KnotVector, NurbsCurve, Point};

use super::super::sketch::Sketch;
use super::super::units::round;
use super::super::value::{Data, Value};
use super::args::{
    any_curve, bad_argument, direction3, fraction, is_2d, list, opt_count, span_of, what, AnyCurve,
};
use super::{as_number, opt, req, type_error, Builtin, Call};

/// The curve builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin {
        name: "nurbs_curve",
        params: &[req("degree"), req("points"), opt("knots"), opt("weights")],
        doc: "the NURBS curve from its degree and control points (2-D or 3-D); knots default to clamped uniform, weights to 1",
        run: nurbs_curve,
    },
    Builtin {
        name: "interpolate",
        params: &[req("points"), opt("degree"), opt("start_tangent"), opt("end_tangent"), opt("parametrization")],
        doc: "the B-spline through the points (degree 3 by default; parametrization \"chord\", \"centripetal\" or \"uniform\")",
        run: interpolate,
    },
    Builtin {
        name: "arc2",
        params: &[req("center"), req("radius"), req("start"), req("end")],
        doc: "the 2-D circular arc about center from angle start to angle end (counter-clockwise from +x)",
        run: arc,
    },
    Builtin {
        name: "arc3",
        params: &[req("center"), req("x_axis"), req("y_axis"), req("radius"), req("start"), req("end")],
        doc: "the 3-D circular arc about center in the plane of two perpendicular axes, angles from x_axis towards y_axis",
        run: arc3,
    },
    Builtin { name: "arc_through", params: &[req("a"), req("b"), req("c")], doc: "the circular arc from a through b to c (2-D or 3-D)", run: arc_through },
    Builtin {
        name: "circle",
        params: &[req("center"), req("radius"), opt("normal")],
        doc: "the full circle about center: in the XY plane for a 2-D centre, else about normal (default z)",
        run: circle,
    },
    Builtin { name: "line_between", params: &[req("a"), req("b")], doc: "the straight segment from a to b (2-D or 3-D)", run: line },
    Builtin { name: "reverse", params: &[req("curve")], doc: "the same curve run backwards", run: reverse },
    Builtin { name: "split", params: &[req("curve"), req("t")], doc: "[first, second]: the curve cut at fraction t of its parameter range", run: split },
    Builtin { name: "join", params: &[req("curves")], doc: "one curve from a list of curves that each start where the previous ends", run: join },
    Builtin {
        name: "offset",
        params: &[req("curve"), req("distance")],
        doc: "the 2-D curve at `distance` to the left of a 2-D curve's or sketch's direction (negative: to the right), within 0.001 mm",
        run: offset,
    },
    Builtin {
        name: "between",
        params: &[req("curve"), req("from"), req("to")],
        doc: "the stretch of a 2-D curve or sketch from the point nearest `from` to the point nearest `to`, along its direction (over the seam of a closed curve)",
        run: between,
    },
];

/// The argument a kernel failure of a curve construction points at.
fn culprit(err: &GeomError, knots_given: bool) -> &'static str {
    match err {
        GeomError::Degree { .. } => "degree",
        GeomError::KnotVector { .. } if knots_given => "knots",
        GeomError::Weight { .. }
        | GeomError::LengthMismatch {
            what: "weights", ..
        } => "weights",
        _ => "points",
    }
}

/// A list of plain numbers.
fn numbers(call: &Call, name: &str) -> Result<Option<Vec<f64>>, Diagnostic> {
    if call.arg(name).is_none() {
        return Ok(None);
    }
    let w = what(call, name);
    call.list(name)?
        .iter()
        .map(|v| as_number(v, &w))
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// Whether the list argument `name` holds 2-D points (judged by its first element).
fn points_are_2d(call: &Call, name: &str) -> Result<bool, Diagnostic> {
    Ok(call.list(name)?.first().is_some_and(is_2d))
}

fn build_nurbs<P: Point>(
    degree: usize,
    points: Vec<P>,
    knots: Option<Vec<f64>>,
    weights: Option<Vec<f64>>,
) -> Result<NurbsCurve<P>, GeomError> {
    let knots = match knots {
        Some(k) => k,
        None => KnotVector::uniform(degree, points.len())?.into_vec(),
    };
    match weights {
        Some(w) => {
            if w.len() != points.len() {
                return Err(GeomError::LengthMismatch {
                    what: "weights",
                    expected: points.len(),
                    given: w.len(),
                });
            }
            NurbsCurve::new_rational(degree, knots, points, w)
        }
        None => NurbsCurve::new(degree, knots, points),
    }
}

fn nurbs_curve(call: &Call) -> Result<Data, Diagnostic> {
    let degree = call.count("degree")?;
    let knots = numbers(call, "knots")?;
    let weights = numbers(call, "weights")?;
    let given = knots.is_some();
    if points_are_2d(call, "points")? {
        let c = build_nurbs(degree, call.points2("points")?, knots, weights).map_err(|e| {
            let arg = culprit(&e, given);
            call.kernel_error(e, Some(arg))
        })?;
        Ok(Data::Curve2(Arc::new(c)))
    } else {
        let c = build_nurbs(degree, call.points3("points")?, knots, weights).map_err(|e| {
            let arg = culprit(&e, given);
            call.kernel_error(e, Some(arg))
        })?;
        Ok(Data::Curve3(Arc::new(c)))
    }
}

fn parametrization(call: &Call) -> Result<Parametrization, Diagnostic> {
    if call.arg("parametrization").is_none() {
        return Ok(Parametrization::ChordLength);
    }
    let s = call.string("parametrization")?;
    match s.as_ref() {
        "chord" | "chord_length" => Ok(Parametrization::ChordLength),
        "centripetal" => Ok(Parametrization::Centripetal),
        "uniform" => Ok(Parametrization::Uniform),
        _ => Err(bad_argument(
            call,
            "parametrization",
            format!("unknown parametrization \"{s}\""),
            "use \"chord\" (the default), \"centripetal\" (for sharp turns) or \"uniform\"",
        )),
    }
}

fn interp_culprit(err: &GeomError) -> &'static str {
    match err {
        GeomError::Degree { .. } => "degree",
        _ => "points",
    }
}

fn interpolate(call: &Call) -> Result<Data, Diagnostic> {
    let degree = opt_count(call, "degree", 3)?;
    let parametrization = parametrization(call)?;
    for name in ["start_tangent", "end_tangent"] {
        let zero = match call.arg(name) {
            Some(v) if is_2d(v) => call.point2(name)? == DVec2::ZERO,
            Some(_) => call.point3(name)? == DVec3::ZERO,
            None => false,
        };
        if zero {
            return Err(bad_argument(
                call,
                name,
                format!("`{name}` has zero length"),
                "an end tangent is the curve's derivative there: give a vector along the direction, about as long as the curve",
            ));
        }
    }
    let fail = |e: GeomError| {
        let arg = interp_culprit(&e);
        call.kernel_error(e, Some(arg))
    };
    if points_are_2d(call, "points")? {
        let pts = call.points2("points")?;
        let opts = Interpolation {
            degree,
            parametrization,
            start_tangent: call
                .arg("start_tangent")
                .map(|_| call.point2("start_tangent"))
                .transpose()?,
            end_tangent: call
                .arg("end_tangent")
                .map(|_| call.point2("end_tangent"))
                .transpose()?,
            ..Interpolation::default()
        };
        Ok(Data::Curve2(Arc::new(interp(&pts, &opts).map_err(fail)?)))
    } else {
        let pts = call.points3("points")?;
        let opts = Interpolation {
            degree,
            parametrization,
            start_tangent: call
                .arg("start_tangent")
                .map(|_| call.point3("start_tangent"))
                .transpose()?,
            end_tangent: call
                .arg("end_tangent")
                .map(|_| call.point3("end_tangent"))
                .transpose()?,
            ..Interpolation::default()
        };
        Ok(Data::Curve3(Arc::new(interp(&pts, &opts).map_err(fail)?)))
    }
}

fn arc_culprit(err: &GeomError) -> &'static str {
    match err {
        GeomError::NotPositive { .. } => "radius",
        GeomError::NotFinite { what: "arc angle" } => "end",
        GeomError::Singular { .. } => "y_axis",
        GeomError::ZeroVector { .. } => "x_axis",
        _ => "center",
    }
}

fn arc(call: &Call) -> Result<Data, Diagnostic> {
    let center = call.point2("center")?;
    let radius = call.length("radius")?;
    let (start, end) = (call.angle("start")?, call.angle("end")?);
    let c = circular_arc(center, DVec2::X, DVec2::Y, radius, start, end).map_err(|e| {
        let arg = arc_culprit(&e);
        call.kernel_error(e, Some(arg))
    })?;
    Ok(Data::Curve2(Arc::new(c)))
}

fn arc3(call: &Call) -> Result<Data, Diagnostic> {
    let center = call.point3("center")?;
    let x = direction3(call, "x_axis")?;
    let y = direction3(call, "y_axis")?;
    let radius = call.length("radius")?;
    let (start, end) = (call.angle("start")?, call.angle("end")?);
    let (x, y) = (x.normalize(), y.normalize());
    if x.dot(y).abs() > 1e-9 {
        return Err(bad_argument(
            call,
            "y_axis",
            format!(
                "the arc's axes are not perpendicular (they make {:.6} deg)",
                x.angle_between(y).to_degrees()
            ),
            "give y_axis perpendicular to x_axis, e.g. cross(normal, x_axis)",
        ));
    }
    let c = circular_arc(center, x, y, radius, start, end).map_err(|e| {
        let arg = arc_culprit(&e);
        call.kernel_error(e, Some(arg))
    })?;
    Ok(Data::Curve3(Arc::new(c)))
}

fn through_culprit(err: &GeomError) -> &'static str {
    match err {
        GeomError::CoincidentPoints { second, .. } => ["a", "b", "c"][(*second).min(2)],
        _ => "b",
    }
}

fn arc_through(call: &Call) -> Result<Data, Diagnostic> {
    let fail = |e: GeomError| {
        let arg = through_culprit(&e);
        call.kernel_error(e, Some(arg))
    };
    if is_2d(call.required("a")?) {
        let c = arc_through_points(call.point2("a")?, call.point2("b")?, call.point2("c")?)
            .map_err(fail)?;
        Ok(Data::Curve2(Arc::new(c)))
    } else {
        let c = arc_through_points(call.point3("a")?, call.point3("b")?, call.point3("c")?)
            .map_err(fail)?;
        Ok(Data::Curve3(Arc::new(c)))
    }
}

fn circle(call: &Call) -> Result<Data, Diagnostic> {
    let radius = call.length("radius")?;
    let fail = |e: GeomError| call.kernel_error(e, Some("radius"));
    if is_2d(call.required("center")?) {
        if call.arg("normal").is_some() {
            return Err(bad_argument(
                call,
                "normal",
                "a 2-D circle lies in its view's plane and takes no normal",
                "give a 3-D centre to use a normal",
            ));
        }
        let c = circle_curve(call.point2("center")?, DVec2::X, DVec2::Y, radius).map_err(fail)?;
        return Ok(Data::Curve2(Arc::new(c)));
    }
    let center = call.point3("center")?;
    let n = if call.arg("normal").is_some() {
        direction3(call, "normal")?.normalize()
    } else {
        DVec3::Z
    };
    // x: the projection of +X (or +Y when the normal is near X) onto the plane.
    let seed = if n.dot(DVec3::X).abs() < 0.9 {
        DVec3::X
    } else {
        DVec3::Y
    };
    let x = (seed - n * n.dot(seed)).normalize();
    let y = n.cross(x);
    let c = circle_curve(center, x, y, radius).map_err(fail)?;
    Ok(Data::Curve3(Arc::new(c)))
}

fn line(call: &Call) -> Result<Data, Diagnostic> {
    let same = || {
        bad_argument(
            call,
            "b",
            "a line needs two different points",
            "move `b` away from `a`",
        )
    };
    if is_2d(call.required("a")?) {
        let (a, b) = (call.point2("a")?, call.point2("b")?);
        if a.distance(b) == 0.0 {
            return Err(same());
        }
        Ok(Data::Curve2(Arc::new(
            Curve2::line(a, b).map_err(|e| call.kernel_error(e, Some("b")))?,
        )))
    } else {
        let (a, b) = (call.point3("a")?, call.point3("b")?);
        if a.distance(b) == 0.0 {
            return Err(same());
        }
        Ok(Data::Curve3(Arc::new(
            Curve3::line(a, b).map_err(|e| call.kernel_error(e, Some("b")))?,
        )))
    }
}

fn reverse(call: &Call) -> Result<Data, Diagnostic> {
    let c = any_curve(call.required("curve")?, &what(call, "curve"))?;
    Ok(match c {
        AnyCurve::Two(c) => Data::Curve2(Arc::new(c.reversed())),
        AnyCurve::Three(c) => Data::Curve3(Arc::new(c.reversed())),
    })
}

fn split(call: &Call) -> Result<Data, Diagnostic> {
    let c = any_curve(call.required("curve")?, &what(call, "curve"))?;
    let f = fraction(call, "t")?;
    if f <= 0.0 || f >= 1.0 {
        return Err(bad_argument(
            call,
            "t",
            format!(
                "`split` cuts inside the curve, at a fraction strictly between 0 and 1, not at {f}"
            ),
            "a cut at an end would leave an empty piece",
        ));
    }
    let (a, b) = c.domain();
    let t = a + f * (b - a);
    let fail = |e: GeomError| call.kernel_error(e, Some("t"));
    let (first, second) = match c {
        AnyCurve::Two(c) => {
            let (l, r) = c.split_at(t).map_err(fail)?;
            (Data::Curve2(Arc::new(l)), Data::Curve2(Arc::new(r)))
        }
        AnyCurve::Three(c) => {
            let (l, r) = c.split_at(t).map_err(fail)?;
            (Data::Curve3(Arc::new(l)), Data::Curve3(Arc::new(r)))
        }
    };
    Ok(list(vec![
        Value::new(first, call.span),
        Value::new(second, call.span),
    ]))
}

fn join(call: &Call) -> Result<Data, Diagnostic> {
    let items = call.list("curves")?;
    let w = what(call, "curves");
    let curves = items
        .iter()
        .map(|v| any_curve(v, &w))
        .collect::<Result<Vec<_>, _>>()?;
    if curves.is_empty() {
        return Err(bad_argument(
            call,
            "curves",
            "`join` needs at least one curve",
            "pass a list of curves, each starting where the previous ends",
        ));
    }
    let fail = |e: GeomError| {
        let corner = match e {
            GeomError::CornersDoNotMeet { corner, .. } => Some(corner),
            _ => None,
        };
        let mut d = call.kernel_error(e, Some("curves"));
        if let Some(k) = corner.filter(|&k| k >= 1 && k < items.len()) {
            d = d
                .with_label(items[k - 1].span, format!("curve {} ends here", k - 1))
                .with_label(
                    items[k].span,
                    format!("curve {k} does not start where it ends"),
                );
        }
        d
    };
    let flat: Vec<Curve2> = curves
        .iter()
        .filter_map(|c| match c {
            AnyCurve::Two(c) => Some((**c).clone()),
            AnyCurve::Three(_) => None,
        })
        .collect();
    if flat.len() == curves.len() {
        return Ok(Data::Curve2(Arc::new(join_curves(&flat).map_err(fail)?)));
    }
    let cs: Vec<Curve3> = curves
        .iter()
        .map(|c| match c {
            AnyCurve::Two(c) => c.to_3d(),
            AnyCurve::Three(c) => (**c).clone(),
        })
        .collect();
    Ok(Data::Curve3(Arc::new(join_curves(&cs).map_err(fail)?)))
}

// ---- offset and between ---------------------------------------------------------------

/// How far (mm) every point of an offset may be from the asked distance.
const OFFSET_TOLERANCE: f64 = 0.001;

/// A point in words, `(x, y)` rounded for messages.
fn place(p: (f64, f64)) -> String {
    format!("({}, {})", round(p.0), round(p.1))
}

/// A 2-D curve argument: a 2-D curve, or a sketch's profile in its view's plane (with
/// the sketch, for pointing at its segments).
fn flat_curve<'c>(
    call: &'c Call,
    name: &str,
) -> Result<(Arc<Curve2>, Option<&'c Sketch>), Diagnostic> {
    let v = call.required(name)?;
    match &v.data {
        Data::Curve2(c) => Ok((c.clone(), None)),
        Data::Sketch(s) => Ok((Arc::new(s.curve.clone()), Some(s.as_ref()))),
        Data::Curve3(_) => Err(type_error(v, &what(call, name), "a 2-D curve or a sketch")
            .with_help(format!(
                "`{}` works in a view's plane: pass the sketch itself or a 2-D curve (`reverse`, `split` and `join` of a sketch give 3-D curves, so call `{}` first and reverse or split its result)",
                call.builtin.name, call.builtin.name
            ))),
        _ => Err(type_error(v, &what(call, name), "a 2-D curve or a sketch")),
    }
}

/// The segment of `sketch` whose parameter range holds `t` (the one starting there
/// at a joint).
fn segment_at(sketch: &Sketch, t: f64) -> Option<usize> {
    let n = sketch.segments.len();
    (0..n).find(|&k| {
        let (a, b) = sketch.segments[k].range;
        t >= a && (t < b || (k + 1 == n && t <= b))
    })
}

/// The segments of `sketch` on either side of the corner at `t`: the one arriving and
/// the one leaving (the last and the first at the seam).
fn segments_at_corner(sketch: &Sketch, t: f64) -> Option<(usize, usize)> {
    let n = sketch.segments.len();
    if n == 0 {
        return None;
    }
    let leaving = (0..n).find(|&k| (sketch.segments[k].range.0 - t).abs() <= 1e-12)?;
    let arriving = if leaving == 0 { n - 1 } else { leaving - 1 };
    Some((arriving, leaving))
}

/// A point in words to 0.1 mm, for places found by a search (`about (597.7, -365)`).
fn near(p: (f64, f64)) -> String {
    let r = |v: f64| round((v * 10.0).round() / 10.0);
    format!("({}, {})", r(p.0), r(p.1))
}

/// "to the left" or "to the right" of the curve's direction, and for a closed curve
/// which side of the outline that is ("(inside this counter-clockwise outline)").
fn side_words(curve: &Curve2, distance: f64) -> String {
    let side = if distance < 0.0 { "right" } else { "left" };
    if !curve.is_closed() {
        return format!("to the {side}");
    }
    let (t0, t1) = curve.domain();
    let pts: Vec<DVec2> = (0..=400)
        .map(|k| curve.point_at(t0 + (t1 - t0) * f64::from(k) / 400.0))
        .collect();
    let area: f64 = pts.windows(2).map(|w| w[0].perp_dot(w[1])).sum();
    let ccw = area > 0.0;
    let inside = ccw == (distance > 0.0);
    format!(
        "to the {side} ({} this {} outline)",
        if inside { "inside" } else { "outside" },
        if ccw {
            "counter-clockwise"
        } else {
            "clockwise"
        }
    )
}

fn offset(call: &Call) -> Result<Data, Diagnostic> {
    let (curve, sketch) = flat_curve(call, "curve")?;
    let distance = call.length("distance")?;
    let reach = round(distance.abs());
    let c = offset_curve2(&curve, distance, OFFSET_TOLERANCE).map_err(|e| match e {
        GeomError::SharpCorner {
            at,
            turn,
            parameter,
        } => {
            let mut d = bad_argument(
                call,
                "curve",
                format!(
                    "the curve has a sharp corner at {} (its direction turns by {} deg there): the offset of a corner is not one curve",
                    place(at),
                    round(turn.to_degrees())
                ),
                format!(
                    "round the corner with a `fillet` (`offset` takes turns of up to 0.5 deg): outside the turn a fillet of radius r becomes an arc of radius r + {reach} mm, on the inside of the turn the fillet must be larger than {reach} mm; or offset the pieces on either side of the corner separately (`between`)"
                ),
            );
            if let Some((s, (a, b))) =
                sketch.and_then(|s| Some((s, segments_at_corner(s, parameter)?)))
            {
                d = d
                    .with_label(
                        s.segments[a].span,
                        format!("this `{}` ends in the corner", s.segments[a].kind),
                    )
                    .with_label(
                        s.segments[b].span,
                        format!("this `{}` leaves it in another direction", s.segments[b].kind),
                    );
            }
            d
        }
        GeomError::OffsetFolds {
            radius,
            at,
            parameter,
            ..
        } => {
            let mut d = bad_argument(
                call,
                "distance",
                format!(
                    "an offset of {reach} mm {} folds over itself: near {} the curve turns that way with a radius of {} mm, no more than the distance",
                    side_words(&curve, distance),
                    near(at),
                    round(radius)
                ),
                format!(
                    "on the inside of a turn the offset's radius is the turn's radius less the distance, so the distance must stay below {} mm there; use a smaller distance, or draw that turn with a larger radius (a `fillet` above {reach} mm)",
                    round(radius)
                ),
            );
            if let Some((s, k)) = sketch.and_then(|s| Some((s, segment_at(s, parameter)?))) {
                d = d.with_label(
                    s.segments[k].span,
                    format!(
                        "this `{}` turns with radius {} mm",
                        s.segments[k].kind,
                        round(radius)
                    ),
                );
            }
            d
        }
        GeomError::OffsetOverlaps { at, gap } => bad_argument(
            call,
            "distance",
            format!(
                "an offset of {reach} mm {} runs into another part of the curve: near {} it comes within {} mm of it",
                side_words(&curve, distance),
                near(at),
                round(gap)
            ),
            "the curve is narrower than twice the distance there; use a smaller distance, or offset only the stretch you need (`between`)",
        )
        .with_label(span_of(call, "curve"), "this curve"),
        GeomError::TooManyPoints { limit, .. } => bad_argument(
            call,
            "curve",
            format!(
                "offsetting this curve by {} mm needs more than {limit} points to stay within {OFFSET_TOLERANCE} mm",
                round(distance)
            ),
            "offset a shorter stretch of the curve (`between`), or use a smaller distance",
        ),
        GeomError::NoConvergence {
            what: "offset fit",
            residual,
            ..
        } => bad_argument(
            call,
            "curve",
            format!(
                "the offset by {} mm could not be fitted within {OFFSET_TOLERANCE} mm (it stays {} mm off)",
                round(distance),
                round(residual)
            ),
            "the curve turns too tightly or unevenly for one smooth offset; offset a shorter stretch (`between`), smooth the curve, or use a smaller distance",
        ),
        other => call.kernel_error(other, Some("curve")),
    })?;
    Ok(Data::Curve2(Arc::new(c)))
}

fn between(call: &Call) -> Result<Data, Diagnostic> {
    let (curve, _) = flat_curve(call, "curve")?;
    let from = call.point2("from")?;
    let to = call.point2("to")?;
    let c = curve_between(&curve, from, to).map_err(|e| match e {
        GeomError::SameProjection { at, .. } => bad_argument(
            call,
            "to",
            format!(
                "`from` and `to` both project to {} on the curve, so the stretch between them is empty",
                place(at)
            ),
            "each point is moved to its nearest point on the curve: give `to` near where the stretch should end, away from `from` along the curve",
        )
        .with_label(span_of(call, "from"), format!("`from` projects to {}", place(at))),
        GeomError::StretchBackwards { from: tf, to: tt } => {
            let (pf, pt) = (curve.point_at(tf), curve.point_at(tt));
            bad_argument(
                call,
                "to",
                format!(
                    "on this open curve `to` (nearest point {}) comes before `from` (nearest point {}): `between` follows the curve's direction",
                    place((pt.x, pt.y)),
                    place((pf.x, pf.y))
                ),
                "swap `from` and `to`, and `reverse` the result if the stretch must run the other way: `reverse(between(curve, to, from))`",
            )
            .with_label(span_of(call, "from"), format!("`from` projects to {}", place((pf.x, pf.y))))
        }
        other => call.kernel_error(other, Some("curve")),
    })?;
    Ok(Data::Curve2(Arc::new(c)))
}
