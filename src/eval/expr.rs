//! Evaluation of expressions.
//!
//! An [`Ctx`] evaluates one expression in one file: names resolve to local bindings
//! (parameters, comprehension variables), then the file's declarations, functions and
//! imports, then the builtins. Evaluation is pure and bounded by the limits of its
//! [`Budget`]: the depth of nested calls (`call_depth`, so a runaway recursive function
//! is an error, not a stack overflow), the steps of the whole evaluation (`work`, so
//! exponential recursion within the depth ends), and the sizes of lists and strings
//! (`list_items`, `string_bytes`, checked before they are made).

use std::sync::Arc;

use crate::diag::{did_you_mean, Diagnostic};
use crate::limits::Limit;
use crate::syntax::ast::{Arg, BinaryOp, Expr, ExprKind, Param, SketchCommandKind};
use crate::syntax::{FileId, Span};

use super::budget::{exceeded, Budget};
use super::builtins::{self, as_length, as_point2, type_error, Call};
use super::engine::Globals;
use super::ops;
use super::sketch::{self, Command, View};
use super::units::{self, Units};
use super::value::{Closure, Data, Dim, Quantity, Record, Value};

/// The views a sketch is drawn in, by the names the language gives them.
const VIEW_NAMES: [&str; 5] = ["top", "side_xz", "side_yz", "section", "profile"];

/// Most "in this call of `f`" labels a diagnostic gathers on its way out of nested
/// calls: the innermost ones say where; hundreds would bury the message.
const MAX_CALL_LABELS: usize = 8;

/// Deepest nesting of calls whatever `call_depth` says: the evaluation threads' 512 MB
/// stacks hold about 90,000 levels of the largest frames (a function called through
/// `map` and `sum`), so a raised limit still ends in a diagnostic, never an overflow.
pub const STACK_SAFE_CALL_DEPTH: usize = 50_000;

/// Local bindings, innermost last.
pub type Locals = Vec<(String, Value)>;

/// Read access to the globals of every loaded file.
pub trait World {
    /// The globals of `file`.
    fn globals(&self, file: FileId) -> Option<&Globals>;
    /// The directory of `file` (for relative paths) and the project root.
    fn paths(&self, file: FileId) -> (Option<&std::path::Path>, Option<&std::path::Path>);
    /// The limits of the evaluation and what it has used of them.
    fn budget(&self) -> &Budget;
}

/// Evaluation context of one expression.
pub struct Ctx<'w> {
    /// Loaded files.
    pub world: &'w dyn World,
    /// The file whose names are in scope.
    pub file: FileId,
    /// The declaration being evaluated (for kernel-failure messages).
    pub decl: Option<&'w str>,
    /// Current call depth.
    pub depth: usize,
    /// The call whose function is being evaluated (`None` at a declaration's top):
    /// where running out of steps is reported.
    pub call: Option<Span>,
}

impl<'w> Ctx<'w> {
    /// The default units of the file in scope.
    pub fn units(&self) -> Units {
        self.world
            .globals(self.file)
            .map_or_else(Units::default, |g| g.units)
    }

    /// The limits of this evaluation and what it has used of them.
    pub fn budget(&self) -> &'w Budget {
        self.world.budget()
    }

    /// Counts one evaluation step of the expression at `span`; once the steps have run
    /// out, the `work` diagnostic at the call being evaluated (at `span` outside any
    /// call), naming the declaration.
    fn step(&self, span: Span) -> Result<(), Diagnostic> {
        let budget = self.budget();
        let Err(limit) = budget.step() else {
            return Ok(());
        };
        let limits = budget.limits();
        let n = limits.get(limit);
        let what = match self.decl {
            Some(d) => format!("`{d}`"),
            None => "this".to_string(),
        };
        let message = if limit == Limit::MemoryMb {
            format!("{what} needs more than {n} MiB of memory")
        } else {
            format!("{what} takes more than {n} evaluation steps")
        };
        Err(exceeded(limit, limits, self.call.unwrap_or(span), message))
    }

    /// Counts the items of a list made at `span` against the items of all lists of
    /// the evaluation (the `list_items` limit).
    fn made_list(&self, n: usize, span: Span) -> Result<(), Diagnostic> {
        let budget = self.budget();
        if budget.add_items(n) {
            return Ok(());
        }
        let limits = budget.limits();
        let message = format!(
            "the lists made so far hold more than {} items together",
            limits.get(Limit::ListItems)
        );
        Err(exceeded(Limit::ListItems, limits, span, message))
    }

    /// The context of the function called at `call`, whose body sees the names of
    /// `file`: one level deeper.
    fn called(&self, file: FileId, call: Span) -> Ctx<'w> {
        Ctx {
            world: self.world,
            file,
            decl: self.decl,
            depth: self.depth + 1,
            call: Some(call),
        }
    }

    /// Evaluates `e` with the given local bindings.
    pub fn eval(&self, e: &Expr, locals: &Locals) -> Result<Value, Diagnostic> {
        let span = e.span;
        self.step(span)?;
        let data = match &e.kind {
            ExprKind::Number { value, unit } => {
                let q = match unit {
                    Some(u) => units::literal(*value, u.node, span)?,
                    None => Quantity::bare(*value),
                };
                Data::Number(q)
            }
            ExprKind::Str(s) => Data::Str(s.as_str().into()),
            ExprKind::Bool(b) => Data::Bool(*b),
            ExprKind::Name(n) => return self.lookup(n, span, locals),
            ExprKind::List(items) => {
                let items = self.eval_all(items, locals)?;
                self.made_list(items.len(), span)?;
                Data::List(Arc::new(items))
            }
            ExprKind::Tuple(items) => Data::Tuple(Arc::new(self.eval_all(items, locals)?)),
            ExprKind::Record(fields) => {
                let mut rec = Record::default();
                for (name, value) in fields {
                    if rec.get(&name.node).is_some() {
                        return Err(Diagnostic::new(
                            "die::duplicate_field",
                            format!("the field `{}` is given twice", name.node),
                            name.span,
                            "given again here",
                        )
                        .with_help("remove one of them"));
                    }
                    rec.fields
                        .push((name.node.clone(), self.eval(value, locals)?));
                }
                Data::Record(Arc::new(rec))
            }
            ExprKind::Comprehension {
                body,
                var,
                iter,
                cond,
            } => {
                let source = self.eval(iter, locals)?;
                let Data::List(items) = &source.data else {
                    return Err(type_error(&source, "the list after `in`", "a list"));
                };
                let mut out = Vec::with_capacity(items.len());
                let mut inner = locals.clone();
                for item in items.iter() {
                    inner.push((var.node.clone(), item.clone()));
                    let keep = match cond {
                        Some(c) => self.truth(c, &inner, "the condition after `if`")?,
                        None => true,
                    };
                    if keep {
                        out.push(self.eval(body, &inner)?);
                    }
                    inner.pop();
                }
                self.made_list(out.len(), span)?;
                Data::List(Arc::new(out))
            }
            ExprKind::Field { target, name } => {
                let t = self.eval(target, locals)?;
                let what = match &target.kind {
                    ExprKind::Name(n) => match &t.data {
                        Data::Module(m) => format!("module `{}` (imported as `{n}`)", m.path),
                        _ => format!("`{n}`"),
                    },
                    _ => t.type_name(),
                };
                return self.field(&t, &what, &name.node, name.span, span);
            }
            ExprKind::Index { target, index } => {
                let t = self.eval(target, locals)?;
                let i = self.eval(index, locals)?;
                return self.index(&t, &i, span);
            }
            ExprKind::Call { callee, args } => {
                return self.call_expr(callee, args, None, span, locals)
            }
            ExprKind::Pipe { input, call } => {
                let first = self.eval(input, locals)?;
                return match &call.kind {
                    ExprKind::Call { callee, args } => {
                        self.call_expr(callee, args, Some(first), span, locals)
                    }
                    _ => {
                        let f = self.eval(call, locals)?;
                        self.apply(&f, vec![first], Vec::new(), span)
                    }
                };
            }
            ExprKind::Unary { op, operand } => {
                let v = self.eval(operand, locals)?;
                return ops::unary(op.node, &v, span, op.span);
            }
            ExprKind::Binary { op, lhs, rhs } => {
                if matches!(op.node, BinaryOp::And | BinaryOp::Or) {
                    let what = format!("the left side of `{}`", op.node.symbol());
                    let l = self.truth(lhs, locals, &what)?;
                    let result = match (op.node, l) {
                        (BinaryOp::And, false) => false,
                        (BinaryOp::Or, true) => true,
                        _ => self.truth(
                            rhs,
                            locals,
                            &format!("the right side of `{}`", op.node.symbol()),
                        )?,
                    };
                    Data::Bool(result)
                } else {
                    let l = self.eval(lhs, locals)?;
                    let r = self.eval(rhs, locals)?;
                    if op.node == BinaryOp::Add {
                        self.check_joined(&l, &r, span)?;
                    }
                    return ops::binary(op.node, &l, &r, span, op.span, self.units());
                }
            }
            ExprKind::If {
                cond,
                then,
                otherwise,
            } => {
                let branch = if self.truth(cond, locals, "the condition of `if`")? {
                    then
                } else {
                    otherwise
                };
                return self.eval(branch, locals);
            }
            ExprKind::Lambda { params, body } => Data::Function(Arc::new(Closure {
                name: "<lambda>".into(),
                params: params.clone(),
                body: Arc::new((**body).clone()),
                captured: locals.clone(),
                file: self.file,
            })),
            ExprKind::Sketch { view, commands } => {
                let v = self.eval(view, locals)?;
                let Data::View(view) = v.data else {
                    if let ExprKind::Name(name) = &view.kind {
                        if VIEW_NAMES.contains(&name.as_str()) {
                            return Err(Diagnostic::new(
                                "die::type_mismatch",
                                format!("`{name}` here is a name of this file, which hides the view `{name}`"),
                                view.span,
                                format!("this `{name}` is {}", v.type_name()),
                            )
                            .with_help(format!(
                                "rename the declaration, function or variable called `{name}` (for example `opening_{name}`): view names are ordinary names, and a file's own names come first"
                            )));
                        }
                    }
                    return Err(type_error(
                        &v,
                        "the view of a sketch",
                        "a view (top, side_xz, side_yz, section(a, b) or profile)",
                    ));
                };
                let units = self.units();
                let point = |e: &Expr| -> Result<glam::DVec2, Diagnostic> {
                    as_point2(&self.eval(e, locals)?, units, "a sketch point")
                };
                let mut cmds = Vec::with_capacity(commands.len());
                for c in commands {
                    let cmd = match &c.kind {
                        SketchCommandKind::From(p) => Command::From(point(p)?),
                        SketchCommandKind::LineTo(p) => Command::LineTo(point(p)?),
                        SketchCommandKind::ArcThrough { to, through } => Command::ArcThrough {
                            to: point(to)?,
                            through: point(through)?,
                        },
                        SketchCommandKind::TangentArcTo(p) => Command::TangentArcTo(point(p)?),
                        SketchCommandKind::Spline { through, tangent } => {
                            let list = self.eval(through, locals)?;
                            let Data::List(items) = &list.data else {
                                return Err(type_error(
                                    &list,
                                    "the points of a spline",
                                    "a list of points `[(x, y), ...]`",
                                ));
                            };
                            let pts = items
                                .iter()
                                .map(|p| as_point2(p, units, "a spline point"))
                                .collect::<Result<Vec<_>, _>>()?;
                            Command::Spline {
                                through: pts,
                                tangent: *tangent,
                            }
                        }
                        SketchCommandKind::Fillet(r) => Command::Fillet(as_length(
                            &self.eval(r, locals)?,
                            units,
                            "a fillet radius",
                        )?),
                        SketchCommandKind::Close => Command::Close,
                    };
                    cmds.push((cmd, c.span));
                }
                Data::Sketch(Arc::new(sketch::build(view, &cmds, span)?))
            }
        };
        Ok(Value::new(data, span))
    }

    fn eval_all(&self, items: &[Expr], locals: &Locals) -> Result<Vec<Value>, Diagnostic> {
        items.iter().map(|i| self.eval(i, locals)).collect()
    }

    /// Evaluates a condition.
    fn truth(&self, e: &Expr, locals: &Locals, what: &str) -> Result<bool, Diagnostic> {
        let v = self.eval(e, locals)?;
        match v.data {
            Data::Bool(b) => Ok(b),
            _ => Err(type_error(&v, what, "true or false")),
        }
    }

    /// Resolves a name: locals, the file's declarations, functions and imports, the
    /// views, the builtins.
    fn lookup(&self, name: &str, span: Span, locals: &Locals) -> Result<Value, Diagnostic> {
        // A name's value is labelled where the name is used: diagnostics about an operand
        // then point at the operand, not at the line that defined it.
        if let Some((_, v)) = locals.iter().rev().find(|(n, _)| n == name) {
            return Ok(Value::new(v.data.clone(), span));
        }
        if let Some(g) = self.world.globals(self.file) {
            if let Some(v) = g.decls.get(name) {
                return Ok(Value::new(v.data.clone(), span));
            }
            if let Some(c) = g.functions.get(name) {
                return Ok(Value::new(Data::Function(c.clone()), span));
            }
            if let Some(m) = g.imports.get(name) {
                return Ok(Value::new(m.data.clone(), span));
            }
            if g.failed.contains(name) {
                return Err(Diagnostic::new(
                    "die::failed_dependency",
                    format!("`{name}` has no value because its own evaluation failed"),
                    span,
                    "used here",
                )
                .with_help(format!("fix the error reported for `{name}` first")));
            }
        }
        let view = match name {
            "top" => Some(View::Top),
            "side_xz" => Some(View::SideXZ),
            "side_yz" => Some(View::SideYZ),
            "profile" => Some(View::Profile),
            _ => None,
        };
        if let Some(v) = view {
            return Ok(Value::new(Data::View(v), span));
        }
        if let Some(b) = builtins::lookup(name).or_else(|| super::views::lookup(name)) {
            return Ok(Value::new(Data::Builtin(b), span));
        }
        Err(self.unknown_name(name, span, locals))
    }

    fn unknown_name(&self, name: &str, span: Span, locals: &Locals) -> Diagnostic {
        let mut candidates: Vec<String> = locals.iter().map(|(n, _)| n.clone()).collect();
        if let Some(g) = self.world.globals(self.file) {
            candidates.extend(g.names.iter().cloned());
        }
        candidates.extend(["top", "side_xz", "side_yz", "profile"].map(String::from));
        candidates.extend(builtins::names().map(String::from));
        candidates.extend(super::views::names().map(String::from));
        let mut d = Diagnostic::new(
            "die::unknown_name",
            format!("cannot find `{name}`"),
            span,
            "not defined",
        );
        d = match did_you_mean(name, candidates.iter().map(String::as_str)) {
            Some(s) => d.with_help(format!("did you mean `{s}`?")),
            None => d.with_help(
                "declare it (`let name = ...`), import a module that has it, or check the spelling",
            ),
        };
        d
    }

    /// `t.name`; `what` names `t` in messages (`` `blank` ``, "module `std/sketch`").
    fn field(
        &self,
        t: &Value,
        what: &str,
        name: &str,
        name_span: Span,
        span: Span,
    ) -> Result<Value, Diagnostic> {
        let found = match &t.data {
            Data::Record(r) => r
                .get(name)
                .cloned()
                .ok_or_else(|| r.fields.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>()),
            Data::Module(m) => m
                .get(name)
                .cloned()
                .ok_or_else(|| m.members.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>()),
            Data::Tuple(items) => {
                let i = match name {
                    "x" => Some(0),
                    "y" => Some(1),
                    "z" => Some(2),
                    _ => None,
                };
                i.and_then(|i| items.get(i).cloned()).ok_or_else(|| {
                    ["x", "y", "z"][..items.len().min(3)]
                        .iter()
                        .map(|s| s.to_string())
                        .collect()
                })
            }
            _ => {
                return Err(Diagnostic::new(
                    "die::no_field",
                    format!("{what} has no fields ({} has none)", t.type_name()),
                    name_span,
                    format!("`.{name}` asked for here"),
                )
                .with_label(t.span, format!("this is {}", t.type_name())))
            }
        };
        match found {
            Ok(v) => Ok(Value::new(v.data, span)),
            Err(names) => {
                let d = Diagnostic::new(
                    "die::no_field",
                    format!("{what} has no field `{name}`"),
                    name_span,
                    "no such field",
                );
                Err(match did_you_mean(name, names.iter().map(String::as_str)) {
                    Some(s) => d.with_help(format!("did you mean `{s}`?")),
                    None if names.is_empty() => d.with_help("it has no fields"),
                    None => d.with_help(format!("its fields are {}", names.join(", "))),
                })
            }
        }
    }

    fn index(&self, t: &Value, i: &Value, span: Span) -> Result<Value, Diagnostic> {
        let items = match &t.data {
            Data::List(items) | Data::Tuple(items) => items,
            _ => {
                return Err(type_error(
                    t,
                    "the value being indexed",
                    "a list or a tuple",
                ))
            }
        };
        let k = builtins::as_count(i, "an index")?;
        match items.get(k) {
            Some(v) => Ok(Value::new(v.data.clone(), span)),
            None => Err(Diagnostic::new(
                "die::index_out_of_range",
                format!(
                    "index {k} is out of range: the list has {} items",
                    items.len()
                ),
                i.span,
                "this index",
            )
            .with_help(format!(
                "indices run from 0 to {}",
                items.len().saturating_sub(1)
            ))),
        }
    }

    fn call_expr(
        &self,
        callee: &Expr,
        args: &[Arg],
        first: Option<Value>,
        span: Span,
        locals: &Locals,
    ) -> Result<Value, Diagnostic> {
        let f = self.eval(callee, locals)?;
        let mut positional: Vec<Value> = first.into_iter().collect();
        let mut named: Vec<(crate::syntax::ast::Ident, Value)> = Vec::new();
        for a in args {
            let v = self.eval(&a.value, locals)?;
            match &a.name {
                Some(n) => named.push((n.clone(), v)),
                None => {
                    if let Some((n, _)) = named.first() {
                        return Err(Diagnostic::new(
                            "die::positional_after_named",
                            "a positional argument cannot follow named ones",
                            a.value.span,
                            "positional argument",
                        )
                        .with_label(n.span, "named argument before it")
                        .with_help("put positional arguments first, or name this one too"));
                    }
                    positional.push(v);
                }
            }
        }
        self.apply(&f, positional, named, span)
    }

    /// The `call_depth` diagnostic when a call of `f` at `span` would nest deeper than
    /// the limit allows.
    fn check_depth(&self, f: &Value, span: Span) -> Result<(), Diagnostic> {
        let limits = self.budget().limits();
        let max = limits.count(Limit::CallDepth).min(STACK_SAFE_CALL_DEPTH);
        if self.depth < max {
            return Ok(());
        }
        let what = match &f.data {
            Data::Function(c) => format!("`{}` is called more than {max} levels deep", c.name),
            _ => format!("function calls nest deeper than {max} levels"),
        };
        Err(Diagnostic::new(
            "die::recursion_limit",
            what,
            span,
            "this call goes too deep (the `call_depth` limit)",
        )
        .with_help(format!(
            "a recursive function must reach its base case; check the condition that ends the recursion; {}",
            Limit::CallDepth.help(limits)
        )))
    }

    /// The `string_bytes` or `list_items` diagnostic when `l + r` at `span` would make
    /// a string or a list over its limit, asked before it is made.
    fn check_joined(&self, l: &Value, r: &Value, span: Span) -> Result<(), Diagnostic> {
        let (limit, n, what) = match (&l.data, &r.data) {
            (Data::Str(a), Data::Str(b)) => (Limit::StringBytes, a.len() + b.len(), "bytes"),
            (Data::List(a), Data::List(b)) => (Limit::ListItems, a.len() + b.len(), "items"),
            _ => return Ok(()),
        };
        let budget = self.budget();
        if budget.allows(limit, n as u64) {
            return Ok(());
        }
        let message = format!(
            "joining these would make {} of {n} {what}, more than the `{}` limit allows",
            if limit == Limit::StringBytes {
                "a string"
            } else {
                "a list"
            },
            limit.name()
        );
        Err(exceeded(limit, budget.limits(), span, message))
    }

    /// Calls a function value with positional and named arguments.
    pub fn apply(
        &self,
        f: &Value,
        positional: Vec<Value>,
        named: Vec<(crate::syntax::ast::Ident, Value)>,
        span: Span,
    ) -> Result<Value, Diagnostic> {
        self.check_depth(f, span)?;
        self.step(span)?;
        match &f.data {
            Data::Builtin(b) => {
                let names: Vec<&str> = b.params.iter().map(|p| p.name).collect();
                let slots = bind_arguments(b.name, &names, positional, named)?;
                for (p, slot) in b.params.iter().zip(&slots) {
                    if p.required && slot.is_none() {
                        return Err(missing(b.name, p.name, &b.signature(), span));
                    }
                }
                let (dir, root) = self.world.paths(self.file);
                let inner = self.called(self.file, span);
                let apply =
                    |g: &Value, args: Vec<Value>, s: Span| inner.apply(g, args, Vec::new(), s);
                let call = Call {
                    builtin: b,
                    span,
                    budget: self.budget(),
                    decl: self.decl,
                    units: self.units(),
                    args: slots,
                    dir,
                    root,
                    apply: &apply,
                };
                let data = builtins::run(&call)?;
                if let Data::List(items) = &data {
                    self.made_list(items.len(), span)?;
                }
                Ok(Value::new(data, span))
            }
            Data::Function(c) => {
                let names: Vec<&str> = c.params.iter().map(|p| p.name.node.as_str()).collect();
                let slots = bind_arguments(&c.name, &names, positional, named)?;
                let inner = self.called(c.file, span);
                let mut locals = c.captured.clone();
                for (p, slot) in c.params.iter().zip(slots) {
                    let v = match (slot, &p.default) {
                        // A bare number given for a parameter whose default is a length
                        // or an angle takes the calling file's default unit, as it would
                        // where a builtin needs a length or an angle.
                        (Some(v), Some(d)) if is_bare(&v) => match inner.eval(d, &locals) {
                            Ok(default) => with_default_unit(v, &default, self.units()),
                            Err(_) => v,
                        },
                        (Some(v), _) => v,
                        (None, Some(d)) => inner.eval(d, &locals)?,
                        (None, None) => {
                            return Err(missing(
                                &c.name,
                                &p.name.node,
                                &signature(&c.name, &c.params),
                                span,
                            ))
                        }
                    };
                    locals.push((p.name.node.clone(), v));
                }
                let v = inner.eval(&c.body, &locals).map_err(|d| {
                    // Show where the failing function was called from, unless the
                    // problem is already pointed at inside this call.
                    let inside = d.primary.span.file == span.file
                        && d.primary.span.start >= span.start
                        && d.primary.span.end <= span.end;
                    if inside
                        || d.secondary.len() >= MAX_CALL_LABELS
                        || d.secondary.iter().any(|l| l.span == span)
                    {
                        d
                    } else {
                        d.with_label(span, format!("in this call of `{}`", c.name))
                    }
                })?;
                Ok(Value::new(v.data, span))
            }
            _ => Err(Diagnostic::new(
                "die::not_a_function",
                format!("{} cannot be called", f.type_name()),
                f.span,
                format!("this is {}", f.type_name()),
            )
            .with_label(span, "called here")
            .with_help("only functions can be called: `name(args)`; for arithmetic write the operator, e.g. `radius * 2`")),
        }
    }
}

/// Whether `v` is a bare number: written without a unit, or computed only from such.
pub(super) fn is_bare(v: &Value) -> bool {
    matches!(&v.data, Data::Number(q) if q.bare && q.dim.is_none())
}

/// The bare number `v` in `units`' length or angle unit when `default` is a length or
/// an angle; otherwise `v` unchanged.
pub(super) fn with_default_unit(v: Value, default: &Value, units: Units) -> Value {
    let (Data::Number(q), Data::Number(d)) = (&v.data, &default.data) else {
        return v;
    };
    let q = match d.dim {
        Dim::LENGTH => Quantity::length(q.value * units.length),
        Dim::ANGLE => Quantity::angle(q.value * units.angle),
        _ => return v,
    };
    if !q.value.is_finite() {
        // Overflows in base units: kept bare, so the use that needs a length or an
        // angle reports it (`die::non_finite`) instead of an infinity passing on.
        return v;
    }
    Value::new(Data::Number(q), v.span)
}

/// `name(a, b = ...)` for help texts.
fn signature(name: &str, params: &[Param]) -> String {
    let ps: Vec<String> = params
        .iter()
        .map(|p| {
            if p.default.is_some() {
                format!("{}?", p.name.node)
            } else {
                p.name.node.clone()
            }
        })
        .collect();
    format!("{name}({})", ps.join(", "))
}

fn missing(func: &str, param: &str, signature: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        "die::missing_argument",
        format!("`{func}` needs the argument `{param}`"),
        span,
        format!("`{param}` is missing"),
    )
    .with_help(format!("the signature is {signature}"))
}

/// Matches arguments to parameter names: positional ones in order, then named ones.
fn bind_arguments(
    func: &str,
    params: &[&str],
    positional: Vec<Value>,
    named: Vec<(crate::syntax::ast::Ident, Value)>,
) -> Result<Vec<Option<Value>>, Diagnostic> {
    let mut slots: Vec<Option<Value>> = vec![None; params.len()];
    // Where each named argument's name was written, for the duplicate labels.
    let mut named_at: Vec<Option<Span>> = vec![None; params.len()];
    let count = positional.len();
    for (i, v) in positional.into_iter().enumerate() {
        if i >= params.len() {
            return Err(Diagnostic::new(
                "die::too_many_arguments",
                format!(
                    "`{func}` takes {} argument{}, but {count} were given",
                    params.len(),
                    if params.len() == 1 { "" } else { "s" }
                ),
                v.span,
                "one too many",
            )
            .with_help(format!("the parameters are {}", params.join(", "))));
        }
        slots[i] = Some(v);
    }
    for (name, v) in named {
        let Some(i) = params.iter().position(|p| *p == name.node) else {
            let d = Diagnostic::new(
                "die::unknown_argument",
                format!("`{func}` has no parameter `{}`", name.node),
                name.span,
                "unknown parameter",
            );
            return Err(match did_you_mean(&name.node, params.iter().copied()) {
                Some(s) => d.with_help(format!("did you mean `{s}`?")),
                None => d.with_help(format!("the parameters are {}", params.join(", "))),
            });
        };
        if let Some(prev) = &slots[i] {
            let (first, what) = match named_at[i] {
                Some(s) => (s, "first given here"),
                None => (prev.span, "given here by position"),
            };
            return Err(Diagnostic::new(
                "die::duplicate_argument",
                format!("`{}` is given twice", name.node),
                name.span,
                "given again here",
            )
            .with_label(first, what)
            .with_help("give each argument once"));
        }
        named_at[i] = Some(name.span);
        slots[i] = Some(v);
    }
    Ok(slots)
}
