//! Surface builtins: NURBS from a control net, and the constructions die faces are
//! made of (ruled, loft, Coons, revolution).
//!
//! Curves given to them are 3-D: sketches are placed through their views and 2-D
//! curves lie at z = 0.

use std::f64::consts::TAU;
use std::sync::Arc;

use crate::diag::Diagnostic;
use crate::geom::construct::{
    coons as coons_patch, coons_triangle, loft as loft_surface, revolve as revolve_surface,
    ruled as ruled_surface, Loft,
};
use crate::geom::{Curve3, GeomError, KnotVector, NurbsSurface};

use super::super::value::{Data, Value};
use super::args::{bad_argument, direction3, opt_count, vector3, what};
use super::{as_count, as_curve3, as_number, as_point3, opt, req, type_error, Builtin, Call};

/// The surface builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin {
        name: "nurbs_surface",
        params: &[req("degree"), req("points"), opt("knots_u"), opt("knots_v"), opt("weights")],
        doc: "the NURBS surface from its degree (one number or (u, v)) and rows of 3-D control points; knots default to clamped uniform",
        run: nurbs_surface,
    },
    Builtin { name: "ruled", params: &[req("a"), req("b")], doc: "the ruled surface of straight lines between two curves", run: ruled },
    Builtin {
        name: "loft",
        params: &[req("sections"), opt("degree"), opt("start_tangent"), opt("end_tangent")],
        doc: "the surface skinned through a list of section curves, optionally with cross-boundary tangent curves at the first and last",
        run: loft,
    },
    Builtin {
        name: "coons",
        params: &[req("bottom"), req("top"), req("left"), req("right")],
        doc: "the Coons patch of four boundary curves (bottom and top run along u, left and right along v)",
        run: coons,
    },
    Builtin { name: "coons3", params: &[req("a"), req("b"), req("c")], doc: "the three-sided Coons patch of three boundary curves meeting end to end", run: coons3 },
    Builtin {
        name: "revolve",
        params: &[req("profile"), req("axis_point"), req("axis_dir"), opt("angle")],
        doc: "the exact surface swept by a profile turning about an axis (a full turn by default)",
        run: revolve,
    },
];

/// `(u, v)` degrees from a number or a pair of numbers.
fn degrees(call: &Call) -> Result<(usize, usize), Diagnostic> {
    let v = call.required("degree")?;
    let w = what(call, "degree");
    match &v.data {
        Data::Tuple(items) if items.len() == 2 => {
            Ok((as_count(&items[0], &w)?, as_count(&items[1], &w)?))
        }
        Data::Number(_) => {
            let d = as_count(v, &w)?;
            Ok((d, d))
        }
        _ => Err(type_error(
            v,
            &w,
            "a degree such as `3` or a pair `(3, 2)` for u and v",
        )),
    }
}

/// A list of rows (lists) of items converted by `f`.
fn rows<T>(
    call: &Call,
    name: &str,
    f: impl Fn(&Value, &str) -> Result<T, Diagnostic>,
) -> Result<Vec<Vec<T>>, Diagnostic> {
    let w = what(call, name);
    call.list(name)?
        .iter()
        .map(|row| match &row.data {
            Data::List(items) => items.iter().map(|v| f(v, &w)).collect(),
            _ => Err(type_error(row, &w, "a list of rows, each a list `[...]`")),
        })
        .collect()
}

fn knots(call: &Call, name: &str) -> Result<Option<Vec<f64>>, Diagnostic> {
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

fn nurbs_surface(call: &Call) -> Result<Data, Diagnostic> {
    let (du, dv) = degrees(call)?;
    let units = call.units;
    let net = rows(call, "points", |v, w| as_point3(v, units, w))?;
    let count_u = net.len();
    let count_v = net.first().map_or(0, Vec::len);
    if let Some(i) = net.iter().position(|r| r.len() != count_v) {
        return Err(bad_argument(
            call,
            "points",
            format!(
                "row {i} of the control net has {} points, but row 0 has {count_v}",
                net[i].len()
            ),
            "every row of the net needs the same number of points",
        ));
    }
    let degree_fail = |e: GeomError| call.kernel_error(e, Some("degree"));
    let ku = match knots(call, "knots_u")? {
        Some(k) => {
            KnotVector::new(k, du, count_u).map_err(|e| call.kernel_error(e, Some("knots_u")))?
        }
        None => KnotVector::uniform(du, count_u).map_err(|e| match e {
            GeomError::TooFewPoints { .. } => call.kernel_error(e, Some("points")),
            e => degree_fail(e),
        })?,
    };
    let kv = match knots(call, "knots_v")? {
        Some(k) => {
            KnotVector::new(k, dv, count_v).map_err(|e| call.kernel_error(e, Some("knots_v")))?
        }
        None => KnotVector::uniform(dv, count_v).map_err(|e| match e {
            GeomError::TooFewPoints { .. } => call.kernel_error(e, Some("points")),
            e => degree_fail(e),
        })?,
    };
    let (ku, kv) = (ku.into_vec(), kv.into_vec());
    let surface = if call.arg("weights").is_some() {
        let weights = rows(call, "weights", as_number)?;
        if weights.len() != count_u || weights.iter().any(|r| r.len() != count_v) {
            return Err(bad_argument(
                call,
                "weights",
                format!("the weights must form a {count_u} x {count_v} net like the points"),
                "give one weight per control point, in rows like the points",
            ));
        }
        NurbsSurface::new_rational(du, dv, ku, kv, net, weights)
            .map_err(|e| call.kernel_error(e, Some("weights")))?
    } else {
        NurbsSurface::new(du, dv, ku, kv, net).map_err(|e| call.kernel_error(e, Some("points")))?
    };
    Ok(Data::Surface(Arc::new(surface)))
}

fn ruled(call: &Call) -> Result<Data, Diagnostic> {
    let (a, b) = (call.curve3("a")?, call.curve3("b")?);
    Ok(Data::Surface(Arc::new(
        ruled_surface(&a, &b).map_err(|e| call.kernel_error(e, Some("b")))?,
    )))
}

fn optional_curve(call: &Call, name: &str) -> Result<Option<Curve3>, Diagnostic> {
    call.arg(name)
        .map(|_| call.curve3(name).map(|c| (*c).clone()))
        .transpose()
}

fn loft(call: &Call) -> Result<Data, Diagnostic> {
    let w = what(call, "sections");
    let sections = call
        .list("sections")?
        .iter()
        .map(|v| as_curve3(v, &w).map(|c| (*c).clone()))
        .collect::<Result<Vec<_>, _>>()?;
    let opts = Loft {
        degree: opt_count(call, "degree", 0)?,
        start_tangent: optional_curve(call, "start_tangent")?,
        end_tangent: optional_curve(call, "end_tangent")?,
        ..Loft::default()
    };
    let s = loft_surface(&sections, &opts).map_err(|e| {
        let arg = match &e {
            GeomError::RationalNotSupported { .. } | GeomError::ZeroVector { .. } => {
                if opts.start_tangent.is_some() {
                    "start_tangent"
                } else {
                    "end_tangent"
                }
            }
            _ => "sections",
        };
        call.kernel_error(e, Some(arg))
    })?;
    Ok(Data::Surface(Arc::new(s)))
}

fn coons(call: &Call) -> Result<Data, Diagnostic> {
    let (b, t, l, r) = (
        call.curve3("bottom")?,
        call.curve3("top")?,
        call.curve3("left")?,
        call.curve3("right")?,
    );
    Ok(Data::Surface(Arc::new(
        coons_patch(&b, &t, &l, &r).map_err(|e| call.kernel_error(e, None))?,
    )))
}

fn coons3(call: &Call) -> Result<Data, Diagnostic> {
    let (a, b, c) = (call.curve3("a")?, call.curve3("b")?, call.curve3("c")?);
    Ok(Data::Surface(Arc::new(
        coons_triangle(&a, &b, &c).map_err(|e| call.kernel_error(e, None))?,
    )))
}

fn revolve(call: &Call) -> Result<Data, Diagnostic> {
    let profile = call.curve3("profile")?;
    let point = vector3(call, "axis_point")?;
    let dir = direction3(call, "axis_dir")?;
    let angle = if call.arg("angle").is_some() {
        call.angle("angle")?
    } else {
        TAU
    };
    if !(angle > 0.0 && angle <= TAU + 1e-12) {
        return Err(bad_argument(
            call,
            "angle",
            format!(
                "a revolution turns by more than 0 and at most 360 deg, not {} deg",
                crate::eval::units::round(angle.to_degrees())
            ),
            "give an angle such as `90 deg`; leave it out for a full turn",
        ));
    }
    let s = revolve_surface(&profile, point, dir, angle)
        .map_err(|e| call.kernel_error(e, Some("profile")))?;
    Ok(Data::Surface(Arc::new(s)))
}
