//! Numbers and lists: square roots, trigonometry, ranges and the list functions that
//! call back into the language (`map`, `filter`).
//!
//! Dimensions follow the arithmetic rules: `min`, `max`, `sum`, `atan2` and `linspace`
//! need values of one dimension, and a bare number next to a length or an angle takes
//! the file's default unit. Trigonometric results are bare numbers, so
//! `100 * cos(30 deg)` can be used where a length is expected, like any bare number.

use std::sync::Arc;

use crate::diag::Diagnostic;

use super::super::value::{Data, Dim, Quantity, Value};
use super::args::{bad_argument, describe, list, num, quantity, unify, what};
use super::{opt, req, type_error, Builtin, Call};

/// The math builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin {
        name: "sqrt",
        params: &[req("x")],
        doc: "square root; the dimension halves (sqrt of an area is a length)",
        run: sqrt,
    },
    Builtin {
        name: "abs",
        params: &[req("x")],
        doc: "absolute value, same dimension",
        run: abs,
    },
    Builtin {
        name: "min",
        params: &[req("a"), req("b")],
        doc: "the smaller of two values of one dimension",
        run: min,
    },
    Builtin {
        name: "max",
        params: &[req("a"), req("b")],
        doc: "the larger of two values of one dimension",
        run: max,
    },
    Builtin {
        name: "sin",
        params: &[req("a")],
        doc: "sine of an angle (bare numbers are in the file's angle unit, degrees by default)",
        run: sin,
    },
    Builtin {
        name: "cos",
        params: &[req("a")],
        doc: "cosine of an angle (bare numbers are in the file's angle unit, degrees by default)",
        run: cos,
    },
    Builtin {
        name: "tan",
        params: &[req("a")],
        doc: "tangent of an angle (bare numbers are in the file's angle unit, degrees by default)",
        run: tan,
    },
    Builtin {
        name: "atan2",
        params: &[req("y"), req("x")],
        doc: "the angle of the vector (x, y) from +x, in (-180 deg, 180 deg]",
        run: atan2,
    },
    Builtin {
        name: "range",
        params: &[req("start"), opt("end")],
        doc: "whole numbers from start (or 0) up to but excluding end: range(3) is [0, 1, 2]",
        run: range,
    },
    Builtin {
        name: "len",
        params: &[req("list")],
        doc: "number of elements of a list or tuple, or characters of a string",
        run: len,
    },
    Builtin {
        name: "map",
        params: &[req("list"), req("f")],
        doc: "the list of f(x) for every element x",
        run: map,
    },
    Builtin {
        name: "filter",
        params: &[req("list"), req("f")],
        doc: "the elements x for which f(x) is true",
        run: filter,
    },
    Builtin {
        name: "sum",
        params: &[req("list")],
        doc: "sum of a list of numbers of one dimension (0 for an empty list)",
        run: sum,
    },
    Builtin {
        name: "linspace",
        params: &[req("a"), req("b"), req("n")],
        doc: "n evenly spaced values from a to b, both included",
        run: linspace,
    },
];

fn sqrt(call: &Call) -> Result<Data, Diagnostic> {
    let q = quantity(call, "x")?;
    if q.dim.length % 2 != 0 || q.dim.angle % 2 != 0 {
        let v = call.required("x")?;
        return Err(Diagnostic::new(
            "die::unit_mismatch",
            format!("the square root of {} has no unit the language knows", describe(q)),
            v.span,
            format!("this is {}", describe(q)),
        )
        .with_help("square roots need even powers of length and angle: sqrt(a * b) of two lengths is a length"));
    }
    if q.value < 0.0 {
        return Err(bad_argument(
            call,
            "x",
            format!("`sqrt` of a negative number ({})", q.value),
            "the square root is defined for values >= 0; check the sign, or use abs()",
        ));
    }
    let dim = Dim {
        length: q.dim.length / 2,
        angle: q.dim.angle / 2,
    };
    Ok(Data::Number(Quantity {
        value: q.value.sqrt(),
        dim,
        bare: q.bare,
    }))
}

fn abs(call: &Call) -> Result<Data, Diagnostic> {
    let q = quantity(call, "x")?;
    Ok(Data::Number(Quantity {
        value: q.value.abs(),
        ..q
    }))
}

fn pair(call: &Call, a: &str, b: &str) -> Result<(Quantity, Quantity), Diagnostic> {
    let (va, vb) = (call.required(a)?, call.required(b)?);
    let qs = unify(call, &[(quantity(call, a)?, va), (quantity(call, b)?, vb)])?;
    Ok((qs[0], qs[1]))
}

fn min(call: &Call) -> Result<Data, Diagnostic> {
    let (a, b) = pair(call, "a", "b")?;
    Ok(Data::Number(if b.value < a.value { b } else { a }))
}

fn max(call: &Call) -> Result<Data, Diagnostic> {
    let (a, b) = pair(call, "a", "b")?;
    Ok(Data::Number(if b.value > a.value { b } else { a }))
}

fn trig(call: &Call, f: fn(f64) -> f64) -> Result<Data, Diagnostic> {
    Ok(Data::Number(Quantity::bare(f(call.angle("a")?))))
}

fn sin(call: &Call) -> Result<Data, Diagnostic> {
    trig(call, f64::sin)
}

fn cos(call: &Call) -> Result<Data, Diagnostic> {
    trig(call, f64::cos)
}

fn tan(call: &Call) -> Result<Data, Diagnostic> {
    trig(call, f64::tan)
}

fn atan2(call: &Call) -> Result<Data, Diagnostic> {
    let (y, x) = pair(call, "y", "x")?;
    Ok(Data::Number(Quantity::angle(y.value.atan2(x.value))))
}

fn whole(call: &Call, name: &str) -> Result<f64, Diagnostic> {
    let n = call.number(name)?;
    if n.fract() != 0.0 || !n.is_finite() {
        return Err(bad_argument(
            call,
            name,
            format!(
                "{} must be a whole number, but this is {n}",
                what(call, name)
            ),
            "use a whole number such as 3",
        ));
    }
    Ok(n)
}

fn range(call: &Call) -> Result<Data, Diagnostic> {
    let (start, end) = match call.arg("end") {
        Some(_) => (whole(call, "start")?, whole(call, "end")?),
        None => (0.0, whole(call, "start")?),
    };
    let count = (end - start).max(0.0);
    let arg = if call.arg("end").is_some() {
        "end"
    } else {
        "start"
    };
    call.check_samples(arg, count, "numbers")?;
    let items = (0..count as usize)
        .map(|i| num(Quantity::bare(start + i as f64), call.span))
        .collect();
    Ok(list(items))
}

fn len(call: &Call) -> Result<Data, Diagnostic> {
    let v = call.required("list")?;
    let n = match &v.data {
        Data::List(items) | Data::Tuple(items) => items.len(),
        Data::Str(s) => s.chars().count(),
        _ => {
            return Err(type_error(
                v,
                &what(call, "list"),
                "a list, a tuple or a string",
            ))
        }
    };
    Ok(Data::Number(Quantity::bare(n as f64)))
}

fn function<'c>(call: &'c Call, name: &str) -> Result<&'c Value, Diagnostic> {
    let f = call.required(name)?;
    match f.data {
        Data::Function(_) | Data::Builtin(_) => Ok(f),
        _ => Err(type_error(
            f,
            &what(call, name),
            "a function such as `fn(x) => x * 2`",
        )),
    }
}

fn map(call: &Call) -> Result<Data, Diagnostic> {
    let items = call.list("list")?;
    let f = function(call, "f")?;
    let out = items
        .iter()
        .map(|x| (call.apply)(f, vec![x.clone()], call.span))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(list(out))
}

fn filter(call: &Call) -> Result<Data, Diagnostic> {
    let items = call.list("list")?;
    let f = function(call, "f")?;
    let mut out = Vec::new();
    for (i, x) in items.iter().enumerate() {
        let keep = (call.apply)(f, vec![x.clone()], call.span)?;
        match keep.data {
            Data::Bool(true) => out.push(x.clone()),
            Data::Bool(false) => {}
            _ => {
                return Err(Diagnostic::new(
                    "die::type_mismatch",
                    format!("the function given to `filter` must return true or false, but for element {i} it returned {}", keep.type_name()),
                    f.span,
                    "this function",
                )
                .with_label(x.span, format!("element {i}"))
                .with_help("filter keeps the elements for which the function returns true; return a comparison such as `x > 0`"))
            }
        }
    }
    Ok(list(out))
}

fn sum(call: &Call) -> Result<Data, Diagnostic> {
    let items = call.list("list")?;
    let w = what(call, "list");
    let qs = items
        .iter()
        .map(|v| super::args::as_quantity(v, &w).map(|q| (q, v)))
        .collect::<Result<Vec<_>, _>>()?;
    let qs = unify(call, &qs)?;
    let Some(first) = qs.first() else {
        return Ok(Data::Number(Quantity::bare(0.0)));
    };
    let total = qs.iter().map(|q| q.value).sum();
    let bare = qs.iter().all(|q| q.bare);
    Ok(Data::Number(Quantity {
        value: total,
        dim: first.dim,
        bare,
    }))
}

fn linspace(call: &Call) -> Result<Data, Diagnostic> {
    let (a, b) = pair(call, "a", "b")?;
    let n = call.count("n")?;
    if n < 2 {
        return Err(bad_argument(
            call,
            "n",
            format!("`linspace` needs at least 2 values, not {n}"),
            "n counts the values including both ends",
        ));
    }
    call.check_samples("n", n as f64, "values")?;
    let bare = a.bare && b.bare;
    let items = (0..n)
        .map(|i| {
            let f = i as f64 / (n - 1) as f64;
            // Exact ends.
            let value = if i + 1 == n {
                b.value
            } else {
                a.value + f * (b.value - a.value)
            };
            num(
                Quantity {
                    value,
                    dim: a.dim,
                    bare,
                },
                call.span,
            )
        })
        .collect();
    Ok(Data::List(Arc::new(items)))
}
