//! Points and vectors: tuples of numbers.
//!
//! Points are tuples of lengths. `dot` and `cross` multiply dimensions (two length
//! vectors give a length² product); `norm` keeps the vector's dimension. `normalize`
//! returns a unit vector as a tuple of lengths one millimetre long, so `p + 10 *
//! normalize(v)` is the point 10 mm from `p` along `v`. Direction arguments elsewhere
//! (axes, normals) accept vectors of any one dimension.

use std::sync::Arc;

use crate::diag::Diagnostic;

use super::super::value::{Data, Dim, Quantity, Value};
use super::args::{as_quantity, bad_argument, is_2d, num, tuple_quantities, unify, what};
use super::{opt, req, type_error, Builtin, Call};

/// The point and vector builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin {
        name: "point",
        params: &[req("x"), req("y"), opt("z")],
        doc: "the point (x, y) or (x, y, z) from lengths",
        run: point,
    },
    Builtin {
        name: "dot",
        params: &[req("a"), req("b")],
        doc: "dot product of two vectors (two length vectors give a length²)",
        run: dot,
    },
    Builtin {
        name: "cross",
        params: &[req("a"), req("b")],
        doc: "cross product: a vector for 3-D vectors, a number for 2-D ones",
        run: cross,
    },
    Builtin {
        name: "norm",
        params: &[req("v")],
        doc: "length of a vector",
        run: norm,
    },
    Builtin {
        name: "normalize",
        params: &[req("v")],
        doc: "the unit vector along v, as lengths 1 mm long in total",
        run: normalize,
    },
    Builtin {
        name: "distance",
        params: &[req("a"), req("b")],
        doc: "distance between two points",
        run: distance,
    },
    Builtin {
        name: "lerp",
        params: &[req("a"), req("b"), req("t")],
        doc: "a + t (b - a) for numbers or points (t = 0 gives a, 1 gives b)",
        run: lerp,
    },
];

fn point(call: &Call) -> Result<Data, Diagnostic> {
    let x = call.length("x")?;
    let y = call.length("y")?;
    let mut items = vec![
        num(Quantity::length(x), call.span),
        num(Quantity::length(y), call.span),
    ];
    if call.arg("z").is_some() {
        items.push(num(Quantity::length(call.length("z")?), call.span));
    }
    Ok(Data::Tuple(Arc::new(items)))
}

/// The components and dimension of vector argument `name` (2 or 3 components).
fn vector(call: &Call, name: &str) -> Result<(Vec<f64>, Dim, bool), Diagnostic> {
    let v = call.required(name)?;
    let w = what(call, name);
    match &v.data {
        Data::Tuple(items) if items.len() == 2 || items.len() == 3 => {
            let (c, dim) = tuple_quantities(call, v, &w)?;
            let bare = items
                .iter()
                .all(|c| matches!(c.data, Data::Number(q) if q.bare));
            Ok((c, dim, bare))
        }
        _ => Err(type_error(v, &w, "a 2-D or 3-D vector such as `(1, 0, 0)`")),
    }
}

fn same_size(call: &Call, a: &[f64], b: &[f64]) -> Result<(), Diagnostic> {
    if a.len() != b.len() {
        return Err(bad_argument(
            call,
            "b",
            format!(
                "`{}` needs two vectors of the same size, but `a` has {} components and `b` {}",
                call.builtin.name,
                a.len(),
                b.len()
            ),
            "use two 2-D or two 3-D vectors",
        ));
    }
    Ok(())
}

fn product_dim(a: Dim, b: Dim) -> Dim {
    Dim {
        length: a.length + b.length,
        angle: a.angle + b.angle,
    }
}

fn dot(call: &Call) -> Result<Data, Diagnostic> {
    let (a, da, ba) = vector(call, "a")?;
    let (b, db, bb) = vector(call, "b")?;
    same_size(call, &a, &b)?;
    let value = a.iter().zip(&b).map(|(x, y)| x * y).sum();
    Ok(Data::Number(Quantity {
        value,
        dim: product_dim(da, db),
        bare: ba && bb,
    }))
}

fn cross(call: &Call) -> Result<Data, Diagnostic> {
    let (a, da, ba) = vector(call, "a")?;
    let (b, db, bb) = vector(call, "b")?;
    same_size(call, &a, &b)?;
    let q = |value: f64| Quantity {
        value,
        dim: product_dim(da, db),
        bare: ba && bb,
    };
    if a.len() == 2 {
        return Ok(Data::Number(q(a[0] * b[1] - a[1] * b[0])));
    }
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    Ok(Data::Tuple(Arc::new(
        c.iter().map(|&x| num(q(x), call.span)).collect(),
    )))
}

fn norm(call: &Call) -> Result<Data, Diagnostic> {
    let (a, dim, bare) = vector(call, "v")?;
    let value = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    Ok(Data::Number(Quantity { value, dim, bare }))
}

fn normalize(call: &Call) -> Result<Data, Diagnostic> {
    let (a, _, _) = vector(call, "v")?;
    let n = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(n > 0.0 && n.is_finite()) {
        return Err(bad_argument(
            call,
            "v",
            "`normalize` of a zero-length vector",
            "a direction needs a vector of non-zero length",
        ));
    }
    Ok(Data::Tuple(Arc::new(
        a.iter()
            .map(|x| num(Quantity::length(x / n), call.span))
            .collect(),
    )))
}

fn distance(call: &Call) -> Result<Data, Diagnostic> {
    let a = call.required("a")?;
    let d = if is_2d(a) {
        call.point2("a")?.distance(call.point2("b")?)
    } else {
        call.point3("a")?.distance(call.point3("b")?)
    };
    Ok(Data::Number(Quantity::length(d)))
}

fn lerp(call: &Call) -> Result<Data, Diagnostic> {
    let t = call.number("t")?;
    let (va, vb) = (call.required("a")?, call.required("b")?);
    let mix = |x: &Value, y: &Value| -> Result<Value, Diagnostic> {
        let qs = unify(
            call,
            &[
                (as_quantity(x, &what(call, "a"))?, x),
                (as_quantity(y, &what(call, "b"))?, y),
            ],
        )?;
        let (p, q) = (qs[0], qs[1]);
        Ok(num(
            Quantity {
                value: p.value + t * (q.value - p.value),
                dim: p.dim,
                bare: p.bare && q.bare,
            },
            call.span,
        ))
    };
    match (&va.data, &vb.data) {
        (Data::Number(_), Data::Number(_)) => Ok(mix(va, vb)?.data),
        (Data::Tuple(a), Data::Tuple(b)) if a.len() == b.len() => {
            let items = a
                .iter()
                .zip(b.iter())
                .map(|(x, y)| mix(x, y))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(Data::Tuple(Arc::new(items)))
        }
        (Data::Tuple(_), Data::Tuple(_)) => Err(bad_argument(
            call,
            "b",
            "`lerp` needs two points of the same size",
            "use two 2-D or two 3-D points",
        )),
        _ => Err(type_error(
            vb,
            &what(call, "b"),
            &format!("of the same kind as `a` ({})", va.type_name()),
        )),
    }
}
