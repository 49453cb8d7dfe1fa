//! Checks: how a function written in the language refuses a bad argument.
//!
//! `fail(message, help?)` stops evaluation with a `die::bad_argument` diagnostic at the
//! `fail(...)` call; the evaluator adds the call chain ("in this call of `round`") up
//! to the designer's own line. `is_length` and `is_angle` test a value's dimension and
//! `str` writes a value as messages show it, so a library function can say what it was
//! given: `fail("beads.round: `height` must be a positive length, but it is " +
//! str(height))`.

use crate::diag::Diagnostic;

use super::super::units::display;
use super::super::value::{Data, Dim, Value};
use super::{opt, req, Builtin, Call};

/// The check builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin {
        name: "fail",
        params: &[req("message"), opt("help")],
        doc: "stops with a `die::bad_argument` error saying `message` (and `help`) at this call, with the call chain: how a function refuses its arguments",
        run: fail,
    },
    Builtin {
        name: "is_length",
        params: &[req("x")],
        doc: "whether x can be used as a length: a length, or a bare number (it takes the file's length unit)",
        run: is_length,
    },
    Builtin {
        name: "is_angle",
        params: &[req("x")],
        doc: "whether x can be used as an angle: an angle, or a bare number (it takes the file's angle unit)",
        run: is_angle,
    },
    Builtin {
        name: "str",
        params: &[req("x")],
        doc: "x as text, as messages show it: str(-6 mm) is \"-6 mm\", str(95 deg) is \"95 deg\"",
        run: str,
    },
];

fn fail(call: &Call) -> Result<Data, Diagnostic> {
    let message = call.string("message")?;
    let help = match call.arg("help") {
        Some(_) => call.string("help")?.to_string(),
        None => "the function's documentation lists the values it accepts".to_string(),
    };
    Err(Diagnostic::new(
        "die::bad_argument",
        message.as_ref(),
        call.span,
        "refused here",
    )
    .with_help(help))
}

/// Whether `v` is a number of dimension `dim`, or a bare number (which takes the
/// file's default unit wherever a length or an angle is needed).
fn usable_as(v: &Value, dim: Dim) -> bool {
    matches!(&v.data, Data::Number(q) if q.dim == dim || (q.bare && q.dim.is_none()))
}

fn is_length(call: &Call) -> Result<Data, Diagnostic> {
    Ok(Data::Bool(usable_as(call.required("x")?, Dim::LENGTH)))
}

fn is_angle(call: &Call) -> Result<Data, Diagnostic> {
    Ok(Data::Bool(usable_as(call.required("x")?, Dim::ANGLE)))
}

fn str(call: &Call) -> Result<Data, Diagnostic> {
    Ok(Data::Str(text(call.required("x")?).into()))
}

/// A value as messages show it: numbers in mm and deg, points as `(x, y)`, strings as
/// they are, other values by their type ("a sketch").
fn text(v: &Value) -> String {
    let join = |items: &[Value]| items.iter().map(text).collect::<Vec<_>>().join(", ");
    match &v.data {
        Data::Number(q) => display(*q),
        Data::Bool(b) => b.to_string(),
        Data::Str(s) => s.to_string(),
        Data::Tuple(items) => format!("({})", join(items)),
        Data::List(items) => format!("[{}]", join(items)),
        _ => v.type_name(),
    }
}
