//! Operators on values, with dimension checking.
//!
//! Adding or comparing quantities needs equal dimensions; a bare number (written
//! without a unit) next to a length or an angle takes the file's default unit, so
//! `x + 10` means `x + 10 mm` in a millimetre file. Multiplication and division combine
//! dimensions. Points are tuples and add, subtract and scale element-wise. A result that
//! overflows is a diagnostic at the expression ([`super::finite`]), never an infinity.

use std::sync::Arc;

use crate::diag::Diagnostic;
use crate::syntax::ast::{BinaryOp, UnaryOp};
use crate::syntax::Span;

use super::finite;
use super::units::Units;
use super::value::{Data, Dim, Quantity, Value};

/// `lhs op rhs` for the arithmetic and comparison operators (`and`/`or` short-circuit in
/// the evaluator). `span` is the whole expression, `op_span` the operator.
pub fn binary(
    op: BinaryOp,
    lhs: &Value,
    rhs: &Value,
    span: Span,
    op_span: Span,
    units: Units,
) -> Result<Value, Diagnostic> {
    use BinaryOp::*;
    let data = match (&lhs.data, &rhs.data) {
        (Data::Number(a), Data::Number(b)) => finite_number(
            number_op(op, *a, *b, lhs, rhs, op_span, units)?,
            op,
            lhs,
            rhs,
            op_span,
        )?,
        (Data::Tuple(a), Data::Tuple(b)) if matches!(op, Add | Sub | Eq | Ne) => {
            if a.len() != b.len() {
                return Err(Diagnostic::new(
                    "die::type_mismatch",
                    format!(
                        "cannot {} a {}-tuple and a {}-tuple",
                        verb(op),
                        a.len(),
                        b.len()
                    ),
                    op_span,
                    "here",
                )
                .with_label(lhs.span, format!("{} values", a.len()))
                .with_label(rhs.span, format!("{} values", b.len()))
                .with_help("points must have the same number of coordinates"));
            }
            if matches!(op, Eq | Ne) {
                let mut all = true;
                for (x, y) in a.iter().zip(b.iter()) {
                    let eq = binary(Eq, x, y, span, op_span, units)?;
                    all &= matches!(eq.data, Data::Bool(true));
                }
                Data::Bool(if op == Eq { all } else { !all })
            } else {
                let items = a
                    .iter()
                    .zip(b.iter())
                    .map(|(x, y)| binary(op, x, y, span, op_span, units))
                    .collect::<Result<Vec<_>, _>>()?;
                Data::Tuple(Arc::new(items))
            }
        }
        (Data::Tuple(a), Data::Number(_)) if matches!(op, Mul | Div) => {
            let items = a
                .iter()
                .map(|x| binary(op, x, rhs, span, op_span, units))
                .collect::<Result<Vec<_>, _>>()?;
            Data::Tuple(Arc::new(items))
        }
        (Data::Number(_), Data::Tuple(b)) if op == Mul => {
            let items = b
                .iter()
                .map(|y| binary(op, lhs, y, span, op_span, units))
                .collect::<Result<Vec<_>, _>>()?;
            Data::Tuple(Arc::new(items))
        }
        (Data::List(a), Data::List(b)) if op == Add => {
            let mut items = a.as_ref().clone();
            items.extend(b.iter().cloned());
            Data::List(Arc::new(items))
        }
        (Data::Str(a), Data::Str(b)) => match op {
            Add => Data::Str(format!("{a}{b}").into()),
            Eq => Data::Bool(a == b),
            Ne => Data::Bool(a != b),
            _ => return Err(unsupported(op, lhs, rhs, op_span)),
        },
        (Data::Bool(a), Data::Bool(b)) if matches!(op, Eq | Ne) => {
            Data::Bool((a == b) == (op == Eq))
        }
        _ => return Err(unsupported(op, lhs, rhs, op_span)),
    };
    Ok(Value::new(data, span))
}

/// The result of a number operation, refused when it is not finite (an overflow):
/// numbers are finite everywhere, so the expression that made one infinite is named.
fn finite_number(
    data: Data,
    op: BinaryOp,
    lhs: &Value,
    rhs: &Value,
    op_span: Span,
) -> Result<Data, Diagnostic> {
    if let Data::Number(q) = data {
        finite::arithmetic(q.value, op, lhs, rhs, op_span)?;
    }
    Ok(data)
}

fn verb(op: BinaryOp) -> &'static str {
    match op {
        BinaryOp::Add => "add",
        BinaryOp::Sub => "subtract",
        BinaryOp::Mul => "multiply",
        BinaryOp::Div => "divide",
        _ => "compare",
    }
}

fn unsupported(op: BinaryOp, lhs: &Value, rhs: &Value, op_span: Span) -> Diagnostic {
    Diagnostic::new(
        "die::type_mismatch",
        format!(
            "`{}` does not apply to {} and {}",
            op.symbol(),
            lhs.type_name(),
            rhs.type_name()
        ),
        op_span,
        "this operator",
    )
    .with_label(lhs.span, format!("this is {}", lhs.type_name()))
    .with_label(rhs.span, format!("this is {}", rhs.type_name()))
    .with_help(
        "arithmetic works on numbers and on points (tuples); `+` also joins lists and strings",
    )
}

/// The bare side of a mixed pair adopts the other side's default unit.
fn adopt(q: Quantity, other: Dim, units: Units) -> Quantity {
    if q.bare && q.dim.is_none() {
        match other {
            Dim::LENGTH => {
                return Quantity {
                    value: q.value * units.length,
                    dim: Dim::LENGTH,
                    bare: false,
                }
            }
            Dim::ANGLE => {
                return Quantity {
                    value: q.value * units.angle,
                    dim: Dim::ANGLE,
                    bare: false,
                }
            }
            _ => {}
        }
    }
    q
}

fn number_op(
    op: BinaryOp,
    a: Quantity,
    b: Quantity,
    lhs: &Value,
    rhs: &Value,
    op_span: Span,
    units: Units,
) -> Result<Data, Diagnostic> {
    use BinaryOp::*;
    let bare = a.bare && b.bare;
    match op {
        Mul => Ok(Data::Number(Quantity {
            value: a.value * b.value,
            dim: Dim {
                length: a.dim.length + b.dim.length,
                angle: a.dim.angle + b.dim.angle,
            },
            bare,
        })),
        Div => {
            if b.value == 0.0 {
                return Err(Diagnostic::new(
                    "die::division_by_zero",
                    "division by zero",
                    rhs.span,
                    "this is zero",
                )
                .with_label(op_span, "dividing here"));
            }
            Ok(Data::Number(Quantity {
                value: a.value / b.value,
                dim: Dim {
                    length: a.dim.length - b.dim.length,
                    angle: a.dim.angle - b.dim.angle,
                },
                bare,
            }))
        }
        _ => {
            let (a, b) = (adopt(a, b.dim, units), adopt(b, a.dim, units));
            if a.dim != b.dim {
                return Err(mismatch(op, a, b, lhs, rhs));
            }
            let (x, y) = (a.value, b.value);
            Ok(match op {
                Add => Data::Number(Quantity {
                    value: x + y,
                    dim: a.dim,
                    bare,
                }),
                Sub => Data::Number(Quantity {
                    value: x - y,
                    dim: a.dim,
                    bare,
                }),
                Eq => Data::Bool(x == y),
                Ne => Data::Bool(x != y),
                Lt => Data::Bool(x < y),
                Le => Data::Bool(x <= y),
                Gt => Data::Bool(x > y),
                Ge => Data::Bool(x >= y),
                // `and`/`or` short-circuit in the evaluator; `*` and `/` are above.
                And | Or | Mul | Div => return Err(unsupported(op, lhs, rhs, op_span)),
            })
        }
    }
}

fn mismatch(op: BinaryOp, a: Quantity, b: Quantity, lhs: &Value, rhs: &Value) -> Diagnostic {
    let name = |q: Quantity| match q.dim {
        d if d.is_none() && !q.bare => "a plain ratio".to_string(),
        Dim::LENGTH => "a length".to_string(),
        Dim::ANGLE => "an angle".to_string(),
        d if d.is_none() => "a plain number".to_string(),
        d => format!("a quantity of {d}"),
    };
    let (na, nb) = (name(a), name(b));
    let help = if a.dim == Dim::LENGTH && b.dim == Dim::ANGLE
        || a.dim == Dim::ANGLE && b.dim == Dim::LENGTH
    {
        "a length and an angle cannot be combined; check the units (mm, cm, m, in for lengths; deg, rad for angles)".to_string()
    } else {
        format!(
            "both sides of `{}` must have the same dimension",
            op.symbol()
        )
    };
    Diagnostic::new(
        "die::unit_mismatch",
        format!("cannot {} {na} and {nb}", verb(op)),
        lhs.span,
        format!("this is {na}"),
    )
    .with_label(rhs.span, format!("this is {nb}"))
    .with_help(help)
}

/// `-x` and `not x`.
pub fn unary(op: UnaryOp, v: &Value, span: Span, op_span: Span) -> Result<Value, Diagnostic> {
    let data = match (op, &v.data) {
        (UnaryOp::Neg, Data::Number(q)) => Data::Number(Quantity {
            value: -q.value,
            ..*q
        }),
        (UnaryOp::Neg, Data::Tuple(items)) => {
            let items = items
                .iter()
                .map(|x| unary(op, x, span, op_span))
                .collect::<Result<Vec<_>, _>>()?;
            Data::Tuple(Arc::new(items))
        }
        (UnaryOp::Not, Data::Bool(b)) => Data::Bool(!b),
        _ => {
            let want = if op == UnaryOp::Neg {
                "a number or a point"
            } else {
                "true or false"
            };
            return Err(Diagnostic::new(
                "die::type_mismatch",
                format!(
                    "`{}` needs {want}, but this is {}",
                    if op == UnaryOp::Neg { "-" } else { "not" },
                    v.type_name()
                ),
                v.span,
                format!("this is {}", v.type_name()),
            )
            .with_label(op_span, "applied here")
            .with_help(if op == UnaryOp::Neg {
                "`-` negates a number, or each coordinate of a point: `-x`, `-(10, 0)`"
            } else {
                "`not` turns true into false and false into true: give it a condition such as `x > 0 mm`, or remove it"
            }));
        }
    };
    Ok(Value::new(data, span))
}
