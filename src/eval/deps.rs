//! Which top-level names an expression uses: the edges of the declaration graph.

use std::collections::BTreeSet;

use crate::syntax::ast::{Block, DeclBody, Expr, ExprKind, FieldValue, Param, SketchCommandKind};

/// The free names of a declaration body (names not bound by a lambda or a
/// comprehension inside it), sorted.
pub fn free_names_of_body(body: &DeclBody) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    match body {
        DeclBody::Expr(e) => free_names(e, &mut Vec::new(), &mut out),
        DeclBody::Block(b) => block_names(b, &mut out),
    }
    out
}

/// The free names of a function body, its parameters (and their defaults) bound.
pub fn free_names_of_function(params: &[Param], body: &Expr) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut bound: Vec<String> = Vec::new();
    for p in params {
        if let Some(d) = &p.default {
            free_names(d, &mut bound, &mut out);
        }
        bound.push(p.name.node.clone());
    }
    free_names(body, &mut bound, &mut out);
    out
}

fn block_names(b: &Block, out: &mut BTreeSet<String>) {
    for f in &b.fields {
        match &f.value {
            FieldValue::Expr(e) => free_names(e, &mut Vec::new(), out),
            FieldValue::Block(inner) => block_names(inner, out),
        }
    }
}

/// Collects names used in `e` and not in `bound`.
pub fn free_names(e: &Expr, bound: &mut Vec<String>, out: &mut BTreeSet<String>) {
    match &e.kind {
        ExprKind::Number { .. } | ExprKind::Str(_) | ExprKind::Bool(_) => {}
        ExprKind::Name(n) => {
            if !bound.iter().any(|b| b == n) {
                out.insert(n.clone());
            }
        }
        ExprKind::List(items) | ExprKind::Tuple(items) => {
            items.iter().for_each(|i| free_names(i, bound, out))
        }
        ExprKind::Comprehension {
            body,
            var,
            iter,
            cond,
        } => {
            free_names(iter, bound, out);
            bound.push(var.node.clone());
            free_names(body, bound, out);
            if let Some(c) = cond {
                free_names(c, bound, out);
            }
            bound.pop();
        }
        ExprKind::Record(fields) => fields.iter().for_each(|(_, v)| free_names(v, bound, out)),
        ExprKind::Field { target, .. } => free_names(target, bound, out),
        ExprKind::Index { target, index } => {
            free_names(target, bound, out);
            free_names(index, bound, out);
        }
        ExprKind::Call { callee, args } => {
            free_names(callee, bound, out);
            args.iter().for_each(|a| free_names(&a.value, bound, out));
        }
        ExprKind::Pipe { input, call } => {
            free_names(input, bound, out);
            free_names(call, bound, out);
        }
        ExprKind::Unary { operand, .. } => free_names(operand, bound, out),
        ExprKind::Binary { lhs, rhs, .. } => {
            free_names(lhs, bound, out);
            free_names(rhs, bound, out);
        }
        ExprKind::If {
            cond,
            then,
            otherwise,
        } => {
            free_names(cond, bound, out);
            free_names(then, bound, out);
            free_names(otherwise, bound, out);
        }
        ExprKind::Lambda { params, body } => {
            let depth = bound.len();
            for p in params {
                if let Some(d) = &p.default {
                    free_names(d, bound, out);
                }
                bound.push(p.name.node.clone());
            }
            free_names(body, bound, out);
            bound.truncate(depth);
        }
        ExprKind::Sketch { view, commands } => {
            free_names(view, bound, out);
            for c in commands {
                match &c.kind {
                    SketchCommandKind::From(p)
                    | SketchCommandKind::LineTo(p)
                    | SketchCommandKind::TangentArcTo(p)
                    | SketchCommandKind::Fillet(p) => free_names(p, bound, out),
                    SketchCommandKind::ArcThrough { to, through } => {
                        free_names(to, bound, out);
                        free_names(through, bound, out);
                    }
                    SketchCommandKind::Spline { through, .. } => free_names(through, bound, out),
                    SketchCommandKind::Close => {}
                }
            }
        }
    }
}
