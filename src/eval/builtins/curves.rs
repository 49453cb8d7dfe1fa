//! Curve builtins: NURBS from control points, interpolation, exact arcs and circles,
//! lines, and reversing, splitting and joining curves.
//!
//! 2-D input (points `(x, y)`) makes 2-D curves, 3-D input 3-D curves. Where a curve
//! is taken as input, a sketch counts as the 3-D curve it is placed at through its view,
//! so `reverse(sketch)` is a 3-D curve. Curve parameters given to builtins are fractions
//! of the domain (0 to 1, or a percentage), whatever the curve's own domain.
//!
//! `line` and `arc` are sketch keywords, so the builtins are `line_between` and
//! `arc2` (with `arc3` its 3-D sibling).

use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::diag::Diagnostic;
use crate::geom::arc::{arc_through_points, circle as circle_curve, circular_arc};
use crate::geom::interpolate::{interpolate as interp, Interpolation, Parametrization};
use crate::geom::join::join_curves;
use crate::geom::{Curve2, Curve3, GeomError, KnotVector, NurbsCurve, Point};

use super::super::value::{Data, Value};
use super::args::{
    any_curve, bad_argument, direction3, fraction, is_2d, list, opt_count, what, AnyCurve,
};
use super::{as_number, opt, req, Builtin, Call};

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
