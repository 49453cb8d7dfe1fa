//! Questions to geometry: points and normals at parameters, lengths, end points, bounds.
//!
//! Parameters are fractions of the parameter range, 0 to 1 (or percentages: `50 %`),
//! whatever the curve's or surface's own domain; `point_at(c, 0.5)` is the point at the
//! middle parameter, which is not the middle of the length in general. Sketches are
//! placed through their view (3-D answers); 2-D curves give 2-D points. Unit normals
//! are tuples of lengths 1 mm long, like `normalize`.

use std::sync::Arc;

use glam::DVec3;

use crate::diag::Diagnostic;
use crate::geom::join::join_curves;
use crate::geom::surface::Direction;
use crate::geom::tessellate::{tessellate_curve, tessellate_surface, Tolerance};
use crate::geom::{Curve3, GeomError, NurbsCurve, NurbsSurface, Point};

use super::super::value::{Data, Quantity, Record, Value};
use super::args::{any_curve, fraction, point2, point3, what, AnyCurve};
use super::{as_point2, as_point3, req, type_error, Builtin, Call};

/// The query builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin { name: "point_at", params: &[req("curve"), req("t")], doc: "the curve's point at fraction t (0 to 1, or a percentage) of its parameter range", run: point_at },
    Builtin { name: "length_of", params: &[req("curve")], doc: "the arc length of a curve", run: length_of },
    Builtin { name: "start_point", params: &[req("curve")], doc: "where a curve starts", run: start_point },
    Builtin { name: "end_point", params: &[req("curve")], doc: "where a curve ends", run: end_point },
    Builtin { name: "point_on", params: &[req("surface"), req("u"), req("v")], doc: "the surface point at fractions u, v of its parameter ranges", run: point_on },
    Builtin { name: "normal_at", params: &[req("surface"), req("u"), req("v")], doc: "the unit surface normal (S_u x S_v) at fractions u, v, 1 mm long", run: normal_at },
    Builtin { name: "edge", params: &[req("surface"), req("side")], doc: "one boundary curve of a surface: side \"u0\", \"u1\" (v runs along it) or \"v0\", \"v1\" (u runs along it)", run: edge },
    Builtin { name: "boundary", params: &[req("surface")], doc: "the closed boundary of a surface as one curve: v0, u1, v1 reversed, u0 reversed (counter-clockwise in the parameter plane)", run: boundary },
    Builtin { name: "bounds", params: &[req("geom")], doc: "{min, max}: the axis-aligned box around geometry (to 1e-4 of its size for curves and surfaces)", run: bounds },
];

/// The four boundary curves of a surface in counter-clockwise order, each running
/// forwards along the loop.
fn edges(s: &NurbsSurface) -> [(&'static str, Curve3); 4] {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    [
        ("v0", s.iso_curve(Direction::V, v0)),
        ("u1", s.iso_curve(Direction::U, u1)),
        ("v1", s.iso_curve(Direction::V, v1).reversed()),
        ("u0", s.iso_curve(Direction::U, u0).reversed()),
    ]
}

fn edge(call: &Call) -> Result<Data, Diagnostic> {
    let s = call.surface("surface")?;
    let side = call.string("side")?;
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let c = match side.as_ref() {
        "u0" => s.iso_curve(Direction::U, u0),
        "u1" => s.iso_curve(Direction::U, u1),
        "v0" => s.iso_curve(Direction::V, v0),
        "v1" => s.iso_curve(Direction::V, v1),
        other => {
            return Err(super::args::bad_argument(
                call,
                "side",
                format!("`side` of `edge` names a boundary, \"u0\", \"u1\", \"v0\" or \"v1\", not \"{other}\""),
                "\"u0\" is the edge where u is smallest (v runs along it); \"v1\" where v is largest",
            ))
        }
    };
    Ok(Data::Curve3(Arc::new(c)))
}

fn boundary(call: &Call) -> Result<Data, Diagnostic> {
    let s = call.surface("surface")?;
    let pieces: Vec<Curve3> = edges(&s)
        .into_iter()
        .map(|(_, c)| c)
        .filter(|c| {
            let (lo, hi) = c.control_bounds();
            (hi - lo).length() > 1e-9 * (1.0 + s.control_scale())
        })
        .collect();
    let joined = join_curves(&pieces).map_err(|e| call.kernel_error(e, Some("surface")))?;
    Ok(Data::Curve3(Arc::new(joined)))
}

fn curve(call: &Call) -> Result<AnyCurve, Diagnostic> {
    any_curve(call.required("curve")?, &what(call, "curve"))
}

fn at(domain: (f64, f64), f: f64) -> f64 {
    if f >= 1.0 {
        domain.1
    } else {
        domain.0 + f * (domain.1 - domain.0)
    }
}

fn point_at(call: &Call) -> Result<Data, Diagnostic> {
    let c = curve(call)?;
    let f = fraction(call, "t")?;
    Ok(match c {
        AnyCurve::Two(c) => point2(c.point_at(at(c.domain(), f)), call.span),
        AnyCurve::Three(c) => point3(c.point_at(at(c.domain(), f)), call.span),
    })
}

fn length_of(call: &Call) -> Result<Data, Diagnostic> {
    let l = match curve(call)? {
        AnyCurve::Two(c) => c.length(),
        AnyCurve::Three(c) => c.length(),
    };
    Ok(Data::Number(Quantity::length(l)))
}

fn start_point(call: &Call) -> Result<Data, Diagnostic> {
    Ok(match curve(call)? {
        AnyCurve::Two(c) => point2(c.start_point(), call.span),
        AnyCurve::Three(c) => point3(c.start_point(), call.span),
    })
}

fn end_point(call: &Call) -> Result<Data, Diagnostic> {
    Ok(match curve(call)? {
        AnyCurve::Two(c) => point2(c.end_point(), call.span),
        AnyCurve::Three(c) => point3(c.end_point(), call.span),
    })
}

fn surface_params(call: &Call) -> Result<(Arc<NurbsSurface>, f64, f64), Diagnostic> {
    let s = call.surface("surface")?;
    let (fu, fv) = (fraction(call, "u")?, fraction(call, "v")?);
    let (u, v) = (at(s.domain_u(), fu), at(s.domain_v(), fv));
    Ok((s, u, v))
}

fn point_on(call: &Call) -> Result<Data, Diagnostic> {
    let (s, u, v) = surface_params(call)?;
    Ok(point3(s.point_at(u, v), call.span))
}

fn normal_at(call: &Call) -> Result<Data, Diagnostic> {
    let (s, u, v) = surface_params(call)?;
    let n = s
        .normal(u, v)
        .map_err(|e| call.kernel_error(e, Some("u")))?;
    Ok(point3(n, call.span))
}

/// A box that grows to hold points.
#[derive(Debug, Clone, Copy)]
struct Box3 {
    min: DVec3,
    max: DVec3,
}

impl Box3 {
    const EMPTY: Box3 = Box3 {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    fn add(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }
}

/// Chordal tolerance for bounds: 1e-4 of the control net's extent.
fn tolerance(lo: DVec3, hi: DVec3) -> Result<Tolerance, GeomError> {
    Tolerance::new(((hi - lo).length() * 1e-4).max(1e-9))
}

fn curve_points<P: Point>(c: &NurbsCurve<P>, b: &mut Box3) -> Result<(), GeomError> {
    let (lo, hi) = c.control_bounds();
    for p in tessellate_curve(c, &tolerance(lo, hi)?)?.points {
        b.add(p.to_3d());
    }
    Ok(())
}

fn grow(call: &Call, v: &Value, b: &mut Box3) -> Result<(), Diagnostic> {
    let w = what(call, "geom");
    let fail = |e: GeomError| call.kernel_error(e, Some("geom"));
    match &v.data {
        Data::Curve2(c) => curve_points(c.as_ref(), b).map_err(fail)?,
        Data::Curve3(c) => curve_points(c.as_ref(), b).map_err(fail)?,
        Data::Sketch(s) => curve_points(&s.to_3d(), b).map_err(fail)?,
        Data::Surface(s) => {
            let (lo, hi) = s.control_bounds();
            let mesh = tessellate_surface(s, &tolerance(lo, hi).map_err(fail)?).map_err(fail)?;
            mesh.positions.iter().for_each(|p| b.add(*p));
        }
        Data::Mesh(m) => m.positions().iter().for_each(|p| b.add(*p)),
        Data::Tuple(items) if items.len() == 2 => b.add(as_point2(v, call.units, &w)?.extend(0.0)),
        Data::Tuple(_) => b.add(as_point3(v, call.units, &w)?),
        Data::List(items) => {
            for x in items.iter() {
                grow(call, x, b)?;
            }
        }
        _ => {
            return Err(type_error(
                v,
                &w,
                "geometry: a curve, a sketch, a surface, a mesh, a point, or a list of them",
            ))
        }
    }
    Ok(())
}

fn bounds(call: &Call) -> Result<Data, Diagnostic> {
    let mut b = Box3::EMPTY;
    grow(call, call.required("geom")?, &mut b)?;
    if b.is_empty() {
        return Err(super::args::bad_argument(
            call,
            "geom",
            "`bounds` of nothing: there is no geometry here",
            "pass a curve, a surface, a mesh or points",
        ));
    }
    let record = Record {
        kind: None,
        fields: vec![
            ("min".to_string(), Value::point3(b.min, call.span)),
            ("max".to_string(), Value::point3(b.max, call.span)),
        ],
        feature: None,
    };
    Ok(Data::Record(Arc::new(record)))
}
