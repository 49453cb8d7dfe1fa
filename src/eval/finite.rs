//! Numbers are finite everywhere: the one check of what an operation made.
//!
//! A script's numbers come from literals (checked by the parser and by
//! [`super::units::literal`]), from operators ([`super::ops`]), from builtins (every
//! result goes through [`builtin_result`]) and from `-D` overrides (literals and
//! operators again). So a number that overflows to infinity or becomes NaN is caught
//! where it is made, and the diagnostic points at that expression with labels on its
//! inputs, instead of the number travelling on to a `null` in the JSON or an `inf` in
//! the GLB.
//!
//! Geometry a builtin makes must also lie within [`MAX_COORDINATE`] of the origin
//! (`docs/limits.md`): beyond it the GLB's 32-bit floats no longer hold the default
//! tolerance, and the kernel's squared distances come near overflow.

use crate::diag::Diagnostic;
use crate::geom::{NurbsSurface, Point, MAX_COORDINATE};
use crate::syntax::ast::BinaryOp;
use crate::syntax::Span;

use super::builtins::Call;
use super::value::{Data, Dim, Quantity, Value};

/// The diagnostic code of a number that is not finite.
pub const CODE: &str = "die::non_finite";

/// The diagnostic code of geometry beyond [`MAX_COORDINATE`].
pub const RANGE_CODE: &str = "die::out_of_range";

/// The help of an overflow: how large numbers may be, and the usual cause.
const OVERFLOW_HELP: &str = "numbers lie between about -1.8e308 and 1.8e308; check the magnitudes and the units of the inputs (a number in metres where millimetres are meant is 1000 times larger)";

/// A number shown in a message: plain when short, with an exponent when very large or
/// very small (`1e308`, not 309 digits).
pub fn show(v: f64) -> String {
    let a = v.abs();
    if v.is_nan() {
        "NaN".into()
    } else if v.is_infinite() {
        if v > 0.0 { "infinity" } else { "-infinity" }.into()
    } else if a != 0.0 && !(1e-6..1e15).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{}", super::units::round(v))
    }
}

/// A quantity shown with its unit in the designer's units (`1e308 mm`, `90 deg`).
pub fn show_quantity(q: Quantity) -> String {
    match q.dim {
        Dim::LENGTH => format!("{} mm", show(q.value)),
        Dim::ANGLE => format!("{} deg", show(q.value.to_degrees())),
        _ => show(q.value),
    }
}

/// What a non-finite `value` is, in words.
fn kind(value: f64) -> &'static str {
    if value.is_nan() {
        "NaN (not a number)"
    } else {
        "infinity (an overflow)"
    }
}

/// `value`, the result of `lhs op rhs`, or a diagnostic if it is not finite: the
/// primary label on the operator (`op_span`), one on each operand with its value.
/// (A primary label over the whole expression would enclose the operands' labels,
/// which the renderer cannot draw.)
pub fn arithmetic(
    value: f64,
    op: BinaryOp,
    lhs: &Value,
    rhs: &Value,
    op_span: Span,
) -> Result<f64, Diagnostic> {
    if value.is_finite() {
        return Ok(value);
    }
    Err(Diagnostic::new(
        CODE,
        format!(
            "`{} {} {}` makes {}",
            describe(lhs),
            op.symbol(),
            describe(rhs),
            kind(value)
        ),
        op_span,
        "the result is not a finite number",
    )
    .with_label(lhs.span, format!("this is {}", describe(lhs)))
    .with_label(rhs.span, format!("this is {}", describe(rhs)))
    .with_help(OVERFLOW_HELP))
}

/// A value in a label: a number with its unit, a point of lengths as `(x, y) mm`, else
/// its type.
fn describe(v: &Value) -> String {
    match &v.data {
        Data::Number(q) => show_quantity(*q),
        Data::Tuple(items) => {
            let lengths: Option<Vec<String>> = items
                .iter()
                .map(|c| match &c.data {
                    Data::Number(q) if q.dim == Dim::LENGTH || q.bare => Some(show(q.value)),
                    _ => None,
                })
                .collect();
            match lengths {
                Some(cs) if !cs.is_empty() => format!("({})", cs.join(", ")),
                _ => v.type_name(),
            }
        }
        _ => v.type_name(),
    }
}

/// A number made by converting `written` (as written at `span`) to base units, or a
/// diagnostic when the conversion overflows or underflows (a literal written non-zero
/// must not become 0 or lose its precision).
pub fn conversion(value: f64, written: &str, span: Span) -> Result<f64, Diagnostic> {
    if !value.is_finite() {
        return Err(Diagnostic::new(
            CODE,
            format!("`{written}` is too large once converted to millimetres and radians"),
            span,
            "too large in base units",
        )
        .with_help(OVERFLOW_HELP));
    }
    if value != 0.0 && value.abs() < f64::MIN_POSITIVE {
        return Err(Diagnostic::new(
            CODE,
            format!("`{written}` is below the smallest number (about 2.2e-308) once converted to millimetres and radians, and would lose its precision"),
            span,
            "too small in base units",
        )
        .with_help("write 0 if zero is meant; numbers smaller than about 2.2e-308 cannot be held exactly"));
    }
    Ok(value)
}

/// What is wrong in a value: where (in words) and the offending coordinate.
#[derive(Debug, Clone, PartialEq)]
pub struct Fault {
    /// Where in the value: "element 3", "control point 5", "knot 2".
    pub place: String,
    /// The offending number.
    pub value: f64,
    /// Whether it is finite but beyond [`MAX_COORDINATE`] (else it is not finite).
    pub out_of_range: bool,
}

impl Fault {
    fn non_finite(place: impl Into<String>, value: f64) -> Self {
        Fault {
            place: place.into(),
            value,
            out_of_range: false,
        }
    }

    /// The same fault inside a part named `outer` ("element 2, control point 5").
    fn within(mut self, outer: &str) -> Self {
        self.place = if self.place.is_empty() {
            outer.to_string()
        } else {
            format!("{outer}, {}", self.place)
        };
        self
    }
}

/// The first number of `data` that is not finite, or (for geometry: curves, sketches,
/// surfaces, trimmed surfaces, meshes) the first coordinate beyond [`MAX_COORDINATE`].
/// Lists, tuples and records are searched element by element.
pub fn fault(data: &Data) -> Option<Fault> {
    match data {
        Data::Number(q) => (!q.value.is_finite()).then(|| Fault::non_finite("", q.value)),
        Data::List(items) | Data::Tuple(items) => items
            .iter()
            .enumerate()
            .find_map(|(i, v)| fault(&v.data).map(|f| f.within(&format!("element {i}")))),
        Data::Record(r) if r.feature.is_none() => r
            .fields
            .iter()
            .find_map(|(n, v)| fault(&v.data).map(|f| f.within(&format!("field `{n}`")))),
        Data::Curve2(c) => curve_fault(c),
        Data::Sketch(s) => curve_fault(&s.curve),
        Data::Curve3(c) => curve_fault(c),
        Data::Surface(s) => surface_fault(s),
        Data::Trimmed(t) => surface_fault(t.surface())
            .or_else(|| curve_fault(t.outer().curve()).map(|f| f.within("the trim outline"))),
        Data::Mesh(m) => points_fault(m.positions(), "vertex"),
        Data::Transform(t) => {
            let m = t.matrix().to_cols_array();
            m.iter()
                .position(|x| !x.is_finite())
                .map(|i| Fault::non_finite(format!("matrix entry {i}"), m[i]))
        }
        _ => None,
    }
}

/// The first knot, weight or control point of a curve that is not finite or out of
/// range.
fn curve_fault<P: Point>(c: &crate::geom::NurbsCurve<P>) -> Option<Fault> {
    numbers_fault(c.knots().as_slice(), "knot")
        .or_else(|| numbers_fault(c.weights().unwrap_or(&[]), "weight"))
        .or_else(|| points_fault(c.control_points(), "control point"))
}

/// The first knot, weight or control point of a surface that is not finite or out of
/// range.
fn surface_fault(s: &NurbsSurface) -> Option<Fault> {
    numbers_fault(s.knots_u().as_slice(), "u knot")
        .or_else(|| numbers_fault(s.knots_v().as_slice(), "v knot"))
        .or_else(|| numbers_fault(s.weights().unwrap_or(&[]), "weight"))
        .or_else(|| points_fault(s.control_points(), "control point"))
}

/// The first number of a list that is not finite.
fn numbers_fault(values: &[f64], what: &str) -> Option<Fault> {
    values
        .iter()
        .position(|x| !x.is_finite())
        .map(|i| Fault::non_finite(format!("{what} {i}"), values[i]))
}

/// The first coordinate of points that is not finite or beyond [`MAX_COORDINATE`].
fn points_fault<P: Point>(points: &[P], what: &str) -> Option<Fault> {
    points.iter().enumerate().find_map(|(i, &p)| {
        (0..P::DIM).map(|k| p.coord(k)).find_map(|x| {
            if !x.is_finite() {
                Some(Fault::non_finite(format!("{what} {i}"), x))
            } else if x.abs() > MAX_COORDINATE {
                Some(Fault {
                    place: format!("{what} {i}"),
                    value: x,
                    out_of_range: true,
                })
            } else {
                None
            }
        })
    })
}

/// Checks what a builtin returned: `Ok` when every number is finite and geometry lies
/// within range, else a diagnostic at the call whose label gives each argument's value
/// (one label: labels inside the call's would not render).
pub fn builtin_result(data: &Data, call: &Call) -> Result<(), Diagnostic> {
    let Some(f) = fault(data) else {
        return Ok(());
    };
    let args: Vec<String> = call
        .builtin
        .params
        .iter()
        .filter_map(|p| {
            call.arg(p.name)
                .map(|v| format!("`{}` = {}", p.name, describe(v)))
        })
        .collect();
    let label = if args.is_empty() {
        "this call".to_string()
    } else {
        format!("this call, with {}", args.join(", "))
    };
    let mut d = made(&f, &format!("`{}`", call.builtin.name), call.span, &label);
    if let Some(decl) = call.decl {
        d.message.push_str(&format!(" (in `{decl}`)"));
    }
    Err(d)
}

/// The diagnostic for `fault` in what `maker` made at `span`.
pub fn made(f: &Fault, maker: &str, span: Span, label: &str) -> Diagnostic {
    let at = if f.place.is_empty() {
        String::new()
    } else {
        format!(" at {}", f.place)
    };
    if f.out_of_range {
        Diagnostic::new(
            RANGE_CODE,
            format!(
                "{maker} made geometry beyond the modelling range: {} has a coordinate of {} mm, more than {} mm from the origin",
                f.place,
                show(f.value),
                show(MAX_COORDINATE)
            ),
            span,
            label,
        )
        .with_help(format!("die faces are modelled in millimetres within {} mm (1 km) of the origin, where the GLB's 32-bit floats still hold the default tolerance of 0.05 mm; check the units and the scale of the inputs", show(MAX_COORDINATE)))
    } else {
        Diagnostic::new(
            CODE,
            format!("{maker} made {}{at}", kind(f.value)),
            span,
            label,
        )
        .with_help(format!(
            "the inputs are finite, but the result is not; {OVERFLOW_HELP}"
        ))
    }
}
