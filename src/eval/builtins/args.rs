//! Argument helpers shared by the builtin modules: optional arguments, directions,
//! fractions, curves of either dimension, and building result values.

use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::diag::Diagnostic;
use crate::geom::{Curve2, Curve3};
use crate::syntax::Span;

use super::super::value::{Data, Dim, Quantity, Value};
use super::{as_count, type_error, Call};

/// A curve as the curve builtins see it: 2-D curves stay 2-D; sketches are placed in
/// press coordinates through their view (3-D).
#[derive(Debug, Clone)]
pub enum AnyCurve {
    /// A 2-D curve.
    Two(Arc<Curve2>),
    /// A 3-D curve (or a placed sketch).
    Three(Arc<Curve3>),
}

impl AnyCurve {
    /// Its parameter domain.
    pub fn domain(&self) -> (f64, f64) {
        match self {
            AnyCurve::Two(c) => c.domain(),
            AnyCurve::Three(c) => c.domain(),
        }
    }
}

/// Reads a value as a curve of either dimension.
pub fn any_curve(v: &Value, what: &str) -> Result<AnyCurve, Diagnostic> {
    match &v.data {
        Data::Curve2(c) => Ok(AnyCurve::Two(c.clone())),
        Data::Curve3(c) => Ok(AnyCurve::Three(c.clone())),
        Data::Sketch(s) => Ok(AnyCurve::Three(Arc::new(s.to_3d()))),
        _ => Err(type_error(v, what, "a curve or a sketch")),
    }
}

/// `` `name` of `builtin` `` for messages.
pub fn what(call: &Call, name: &str) -> String {
    format!("`{name}` of `{}`", call.builtin.name)
}

/// The span of argument `name`, or of the call.
pub fn span_of(call: &Call, name: &str) -> Span {
    call.arg(name).map_or(call.span, |v| v.span)
}

/// A `die::bad_argument` diagnostic at argument `name`.
pub fn bad_argument(
    call: &Call,
    name: &str,
    message: impl Into<String>,
    help: impl Into<String>,
) -> Diagnostic {
    let label = format!("this `{name}`");
    Diagnostic::new("die::bad_argument", message, span_of(call, name), label).with_help(help)
}

/// A quantity argument of any dimension.
pub fn quantity(call: &Call, name: &str) -> Result<Quantity, Diagnostic> {
    let v = call.required(name)?;
    as_quantity(v, &what(call, name))
}

/// A value as a quantity of any dimension.
pub fn as_quantity(v: &Value, what: &str) -> Result<Quantity, Diagnostic> {
    match &v.data {
        Data::Number(q) => Ok(*q),
        _ => Err(type_error(v, what, "a number")),
    }
}

/// The bare side of a pair adopts the other side's dimension in the default unit, as
/// in arithmetic (`min(x, 10)` means `min(x, 10 mm)` in a millimetre file).
pub fn adopt(q: Quantity, other: Dim, call: &Call) -> Quantity {
    if q.bare && q.dim.is_none() {
        if other == Dim::LENGTH {
            return Quantity::length(q.value * call.units.length);
        }
        if other == Dim::ANGLE {
            return Quantity::angle(q.value * call.units.angle);
        }
    }
    q
}

/// Brings quantities to one dimension (bare ones adopt the others' dimension), or a
/// `die::unit_mismatch` at the first value that disagrees.
pub fn unify(call: &Call, items: &[(Quantity, &Value)]) -> Result<Vec<Quantity>, Diagnostic> {
    let target = items
        .iter()
        .map(|(q, _)| *q)
        .find(|q| !(q.bare && q.dim.is_none()));
    let Some(target) = target else {
        return Ok(items.iter().map(|(q, _)| *q).collect());
    };
    let mut out = Vec::with_capacity(items.len());
    for (q, v) in items {
        let q = adopt(*q, target.dim, call);
        if q.dim != target.dim {
            return Err(Diagnostic::new(
                "die::unit_mismatch",
                format!("`{}` needs values of one dimension, but this is {} and another is {}", call.builtin.name, describe(q), describe(target)),
                v.span,
                format!("this is {}", describe(q)),
            )
                .with_help("give all values in the same kind of unit (lengths with lengths, angles with angles)"));
        }
        out.push(q);
    }
    Ok(out)
}

/// "a length", "an angle", ... for a quantity.
pub fn describe(q: Quantity) -> String {
    Data::Number(q).type_name()
}

/// An optional whole number with a default.
pub fn opt_count(call: &Call, name: &str, default: usize) -> Result<usize, Diagnostic> {
    match call.arg(name) {
        Some(v) => as_count(v, &what(call, name)),
        None => Ok(default),
    }
}

/// A fraction in [0, 1] (a plain number or a percentage such as `50 %`).
pub fn fraction(call: &Call, name: &str) -> Result<f64, Diagnostic> {
    let f = call.number(name)?;
    if !(0.0..=1.0).contains(&f) {
        return Err(bad_argument(
            call,
            name,
            format!(
                "`{name}` of `{}` is a fraction of the parameter range, 0 to 1, but this is {f}",
                call.builtin.name
            ),
            if (1.0..=100.0).contains(&f)
                && call
                    .arg(name)
                    .is_some_and(|v| matches!(&v.data, Data::Number(q) if q.bare))
            {
                format!("a bare number is a fraction here (`1` is `100 %`): did you mean `{f} %`?")
            } else {
                "write a number from 0 to 1 or a percentage such as `50 %`".to_string()
            },
        ));
    }
    Ok(f)
}

/// The numbers of a tuple, all of one dimension (bare numbers adopt it); returns them
/// in base units with that dimension.
pub fn tuple_quantities(call: &Call, v: &Value, what: &str) -> Result<(Vec<f64>, Dim), Diagnostic> {
    let Data::Tuple(items) = &v.data else {
        return Err(type_error(v, what, "a point or vector such as `(1, 0, 0)`"));
    };
    let qs = items
        .iter()
        .map(|c| as_quantity(c, what).map(|q| (q, c)))
        .collect::<Result<Vec<_>, _>>()?;
    let unified = unify(call, &qs)?;
    let dim = unified.first().map_or(Dim::NONE, |q| q.dim);
    Ok((unified.iter().map(|q| q.value).collect(), dim))
}

/// A 3-D direction: one of the strings `"x"`, `"y"`, `"z"` or a tuple of three numbers
/// of any one dimension (only the direction counts). Not normalized; zero is refused.
pub fn direction3(call: &Call, name: &str) -> Result<DVec3, Diagnostic> {
    let v = call.required(name)?;
    let w = what(call, name);
    let d =
        match &v.data {
            Data::Str(s) => match s.as_ref() {
                "x" | "X" => DVec3::X,
                "y" | "Y" => DVec3::Y,
                "z" | "Z" => DVec3::Z,
                _ => return Err(bad_argument(
                    call,
                    name,
                    format!("{w} must be \"x\", \"y\", \"z\" or a vector, not \"{s}\""),
                    "name an axis (\"x\", \"y\", \"z\") or give a direction such as `(0, 1, 1)`",
                )),
            },
            Data::Tuple(items) if items.len() == 3 => {
                let (c, _) = tuple_quantities(call, v, &w)?;
                DVec3::new(c[0], c[1], c[2])
            }
            _ => {
                return Err(type_error(
                    v,
                    &w,
                    "an axis name (\"x\", \"y\", \"z\") or a 3-D vector",
                ))
            }
        };
    if !d.is_finite() || d.length() == 0.0 {
        return Err(bad_argument(
            call,
            name,
            format!("{w} has zero length"),
            "give a direction of non-zero length",
        ));
    }
    Ok(d)
}

/// A 3-D vector of lengths; a 2-D one gets z = 0.
pub fn vector3(call: &Call, name: &str) -> Result<DVec3, Diagnostic> {
    let v = call.required(name)?;
    match &v.data {
        Data::Tuple(items) if items.len() == 2 => Ok(call.point2(name)?.extend(0.0)),
        _ => call.point3(name),
    }
}

/// An optional 3-D point (a 2-D one gets z = 0), or the origin.
pub fn opt_point3(call: &Call, name: &str) -> Result<DVec3, Diagnostic> {
    match call.arg(name) {
        Some(_) => vector3(call, name),
        None => Ok(DVec3::ZERO),
    }
}

/// Whether a tuple value has two elements (a 2-D point) rather than three.
pub fn is_2d(v: &Value) -> bool {
    matches!(&v.data, Data::Tuple(t) if t.len() == 2)
}

/// A number value.
pub fn num(q: Quantity, span: Span) -> Value {
    Value::new(Data::Number(q), span)
}

/// A list of values.
pub fn list(items: Vec<Value>) -> Data {
    Data::List(Arc::new(items))
}

/// A 2-D point as data.
pub fn point2(p: DVec2, span: Span) -> Data {
    Value::point2(p, span).data
}

/// A 3-D point as data.
pub fn point3(p: DVec3, span: Span) -> Data {
    Value::point3(p, span).data
}
