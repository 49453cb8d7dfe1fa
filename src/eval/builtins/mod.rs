//! Functions implemented in Rust: the bindings of the geometry kernel and the basic
//! maths the language needs.
//!
//! A [`Builtin`] declares its parameters; the evaluator matches a call's positional and
//! named arguments to them (unknown names and missing arguments are diagnosed there,
//! with "did you mean"), then hands the builtin a [`Call`] whose accessors convert
//! arguments to kernel types, reporting wrong types and units at the argument's span.

mod args;
mod checks;
mod curves;
mod die_face_mesh;
mod io;
mod math;
mod meshes;
mod quad;
mod queries;
mod surfaces;
mod transforms;
mod vectors;

use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::diag::Diagnostic;
use crate::geom::{Curve2, Curve3, GeomError, NurbsSurface};
use crate::limits::Limit;
use crate::syntax::Span;

use super::budget::{exceeded, Budget};
use super::units::Units;
use super::value::{Data, Dim, Value};

/// A parameter of a builtin.
#[derive(Debug)]
pub struct ParamSpec {
    /// Its name (named arguments use it).
    pub name: &'static str,
    /// Whether the call must give it.
    pub required: bool,
}

/// Shorthand for a required parameter.
pub const fn req(name: &'static str) -> ParamSpec {
    ParamSpec {
        name,
        required: true,
    }
}

/// Shorthand for an optional parameter.
pub const fn opt(name: &'static str) -> ParamSpec {
    ParamSpec {
        name,
        required: false,
    }
}

/// A function implemented in Rust.
pub struct Builtin {
    /// The name scripts call it by.
    pub name: &'static str,
    /// Parameters in positional order.
    pub params: &'static [ParamSpec],
    /// One line for "did you mean" and help texts: what it does.
    pub doc: &'static str,
    /// The implementation.
    pub run: fn(&Call) -> Result<Data, Diagnostic>,
}

impl std::fmt::Debug for Builtin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "builtin {}", self.name)
    }
}

impl Builtin {
    /// `name(a, b, c?)` for help texts.
    pub fn signature(&self) -> String {
        let params: Vec<String> = self
            .params
            .iter()
            .map(|p| {
                if p.required {
                    p.name.to_string()
                } else {
                    format!("{}?", p.name)
                }
            })
            .collect();
        format!("{}({})", self.name, params.join(", "))
    }
}

/// Every builtin module's table.
fn tables() -> [&'static [Builtin]; 11] {
    [
        math::BUILTINS,
        checks::BUILTINS,
        vectors::BUILTINS,
        curves::BUILTINS,
        surfaces::BUILTINS,
        transforms::BUILTINS,
        queries::BUILTINS,
        io::BUILTINS,
        meshes::BUILTINS,
        quad::BUILTINS,
        die_face_mesh::BUILTINS,
    ]
}

/// The builtin called `name`.
pub fn lookup(name: &str) -> Option<&'static Builtin> {
    tables().into_iter().flatten().find(|b| b.name == name)
}

/// All builtin names (for "did you mean").
pub fn names() -> impl Iterator<Item = &'static str> {
    tables().into_iter().flatten().map(|b| b.name)
}

/// Runs the builtin of `call` and checks what it made: every number finite and
/// geometry within the modelling range ([`super::finite::builtin_result`]). The one
/// place builtins are run from the evaluator, so no builtin needs its own check.
pub fn run(call: &Call) -> Result<Data, Diagnostic> {
    let data = (call.builtin.run)(call)?;
    super::finite::builtin_result(&data, call)?;
    Ok(data)
}

/// A call being executed: its arguments aligned with the builtin's parameters.
pub struct Call<'a> {
    /// The builtin.
    pub builtin: &'static Builtin,
    /// The whole call expression.
    pub span: Span,
    /// The limits of the evaluation (what a builtin may make) and what it has used.
    pub budget: &'a Budget,
    /// The declaration being evaluated, for kernel-failure messages.
    pub decl: Option<&'a str>,
    /// Default units of the calling file.
    pub units: Units,
    /// Argument values by parameter index (`None` where omitted).
    pub args: Vec<Option<Value>>,
    /// Directory of the calling file, for relative paths (`None` for the stdlib).
    pub dir: Option<&'a std::path::Path>,
    /// The project root: files outside it cannot be read.
    pub root: Option<&'a std::path::Path>,
    /// Calls a function value (user function, lambda or builtin) with positional
    /// arguments: how `map` and friends call back into the evaluator.
    pub apply: &'a Apply<'a>,
}

/// How a builtin calls a function value back: the function, positional arguments, and
/// the span of the call that asked.
pub type Apply<'a> = dyn Fn(&Value, Vec<Value>, Span) -> Result<Value, Diagnostic> + 'a;

impl Call<'_> {
    /// The `samples` diagnostic, at argument `arg` (the whole call when it is not
    /// given), when this call would make `n` samples or points (`what`), more than the
    /// limit allows: asked before they are made.
    pub fn check_samples(&self, arg: &str, n: f64, what: &str) -> Result<(), Diagnostic> {
        let limits = self.budget.limits();
        if n <= limits.get(Limit::Samples) as f64 {
            return Ok(());
        }
        let message = format!(
            "`{}` would make {n} {what}, more than the `samples` limit allows",
            self.builtin.name
        );
        Err(exceeded(
            Limit::Samples,
            limits,
            args::span_of(self, arg),
            message,
        ))
    }

    /// The argument for parameter `name`, if given.
    pub fn arg(&self, name: &str) -> Option<&Value> {
        let i = self.builtin.params.iter().position(|p| p.name == name)?;
        self.args.get(i)?.as_ref()
    }

    /// The argument for `name`, or a diagnostic that it is missing.
    pub fn required(&self, name: &str) -> Result<&Value, Diagnostic> {
        self.arg(name).ok_or_else(|| {
            Diagnostic::new(
                "die::missing_argument",
                format!("`{}` needs the argument `{name}`", self.builtin.name),
                self.span,
                "called here",
            )
            .with_help(format!("the signature is {}", self.builtin.signature()))
        })
    }

    /// A diagnostic for a wrong argument.
    pub fn bad(&self, value: &Value, name: &str, expected: &str) -> Diagnostic {
        type_error(
            value,
            &format!("`{name}` of `{}`", self.builtin.name),
            expected,
        )
    }

    /// A plain number (bare or ratio).
    pub fn number(&self, name: &str) -> Result<f64, Diagnostic> {
        as_number(self.required(name)?, &self.what(name))
    }

    /// A whole number >= 0.
    pub fn count(&self, name: &str) -> Result<usize, Diagnostic> {
        as_count(self.required(name)?, &self.what(name))
    }

    /// A length in mm (a bare number takes the file's default unit).
    pub fn length(&self, name: &str) -> Result<f64, Diagnostic> {
        as_length(self.required(name)?, self.units, &self.what(name))
    }

    /// An angle in radians (a bare number takes the file's default unit).
    pub fn angle(&self, name: &str) -> Result<f64, Diagnostic> {
        as_angle(self.required(name)?, self.units, &self.what(name))
    }

    /// A boolean.
    pub fn boolean(&self, name: &str) -> Result<bool, Diagnostic> {
        match &self.required(name)?.data {
            Data::Bool(b) => Ok(*b),
            _ => Err(self.bad(self.required(name)?, name, "true or false")),
        }
    }

    /// A string.
    pub fn string(&self, name: &str) -> Result<Arc<str>, Diagnostic> {
        let v = self.required(name)?;
        match &v.data {
            Data::Str(s) => Ok(s.clone()),
            _ => Err(self.bad(v, name, "a string")),
        }
    }

    /// A list's elements.
    pub fn list(&self, name: &str) -> Result<&[Value], Diagnostic> {
        let v = self.required(name)?;
        match &v.data {
            Data::List(items) => Ok(items),
            _ => Err(self.bad(v, name, "a list `[...]`")),
        }
    }

    /// A 2-D point `(x, y)` in mm.
    pub fn point2(&self, name: &str) -> Result<DVec2, Diagnostic> {
        as_point2(self.required(name)?, self.units, &self.what(name))
    }

    /// A 3-D point or vector `(x, y, z)` in mm.
    pub fn point3(&self, name: &str) -> Result<DVec3, Diagnostic> {
        as_point3(self.required(name)?, self.units, &self.what(name))
    }

    /// A list of 2-D points.
    pub fn points2(&self, name: &str) -> Result<Vec<DVec2>, Diagnostic> {
        let what = self.what(name);
        self.list(name)?
            .iter()
            .map(|v| as_point2(v, self.units, &what))
            .collect()
    }

    /// A list of 3-D points.
    pub fn points3(&self, name: &str) -> Result<Vec<DVec3>, Diagnostic> {
        let what = self.what(name);
        self.list(name)?
            .iter()
            .map(|v| as_point3(v, self.units, &what))
            .collect()
    }

    /// A 3-D curve; a sketch is placed in 3-D through its view, a 2-D curve at z = 0.
    pub fn curve3(&self, name: &str) -> Result<Arc<Curve3>, Diagnostic> {
        as_curve3(self.required(name)?, &self.what(name))
    }

    /// A 2-D curve; a sketch gives its profile in the view's plane.
    pub fn curve2(&self, name: &str) -> Result<Arc<Curve2>, Diagnostic> {
        let v = self.required(name)?;
        match &v.data {
            Data::Curve2(c) => Ok(c.clone()),
            Data::Sketch(s) => Ok(Arc::new(s.curve.clone())),
            _ => Err(self.bad(v, name, "a 2-D curve or a sketch")),
        }
    }

    /// A surface.
    pub fn surface(&self, name: &str) -> Result<Arc<NurbsSurface>, Diagnostic> {
        let v = self.required(name)?;
        match &v.data {
            Data::Surface(s) => Ok(s.clone()),
            _ => Err(self.bad(v, name, "a surface")),
        }
    }

    /// A kernel failure turned into a diagnostic that names the declaration and the
    /// argument that fed it.
    pub fn kernel_error(&self, err: GeomError, arg: Option<&str>) -> Diagnostic {
        let span = arg.and_then(|a| self.arg(a)).map_or(self.span, |v| v.span);
        let place = match (self.decl, arg) {
            (Some(d), Some(a)) => format!(" (in `{d}`, argument `{a}`)"),
            (Some(d), None) => format!(" (in `{d}`)"),
            (None, Some(a)) => format!(" (argument `{a}`)"),
            (None, None) => String::new(),
        };
        let label = match arg {
            Some(a) => format!("this `{a}` cannot be used: {err}"),
            None => format!("{err}"),
        };
        Diagnostic::new(
            "die::geometry",
            format!("`{}` failed: {err}{place}", self.builtin.name),
            span,
            label,
        )
        .with_help(kernel_help(self.builtin.name, &err))
    }

    fn what(&self, name: &str) -> String {
        format!("`{name}` of `{}`", self.builtin.name)
    }
}

/// Advice for each kind of kernel failure in the builtin `builtin`.
fn kernel_help(builtin: &str, err: &GeomError) -> String {
    match (builtin, err) {
        ("join", GeomError::CornersDoNotMeet { corner, .. }) => {
            return format!("consecutive curves must meet end to end: move the start of curve {corner} (counting from 0) onto the end of the one before it")
        }
        ("loft", GeomError::TooFewPoints { needed, .. }) => {
            return format!("a loft skins at least {needed} sections: give a list of {needed} or more curves")
        }
        _ => {}
    }
    match err {
        GeomError::CoincidentPoints { first, second } => {
            format!("points {first} and {second} of the list (counting from 0) are the same point; remove one or move it")
        }
        GeomError::TooFewPoints { needed, .. } => format!("give at least {needed} points, or lower the degree"),
        GeomError::KnotVector { .. } => {
            "a clamped knot vector repeats its first and last value degree + 1 times and never decreases".into()
        }
        GeomError::Weight { .. } => "weights must be positive numbers".into(),
        GeomError::ZeroVector { .. } => "give a direction or tangent of non-zero length".into(),
        GeomError::NoConvergence { .. } => "check that the inputs are not degenerate or far apart".into(),
        GeomError::CornersDoNotMeet { corner, .. } => {
            let which = ["start of `bottom` and `left`", "end of `bottom` and start of `right`", "end of `top` and `right`", "start of `top` and end of `left`"];
            match which.get(*corner) {
                Some(w) => format!("each corner is the end of two boundaries; here the {w} must be the same point"),
                None => "the curves must meet end to end".into(),
            }
        }
        GeomError::Singular { .. } => "the input is degenerate; see the message for which values".into(),
        GeomError::ViewsDoNotOverlap { .. } => {
            "the side view must cover the top view's x range at both ends; extend the shorter view".into()
        }
        _ => "check the values passed to this call".into(),
    }
}

/// A type-mismatch diagnostic at `value`'s span.
pub fn type_error(value: &Value, what: &str, expected: &str) -> Diagnostic {
    Diagnostic::new(
        "die::type_mismatch",
        format!(
            "{what} must be {expected}, but this is {}",
            value.type_name()
        ),
        value.span,
        format!("this is {}", value.type_name()),
    )
    .with_help(format!("pass {expected} here"))
}

/// A plain number.
pub fn as_number(v: &Value, what: &str) -> Result<f64, Diagnostic> {
    match &v.data {
        Data::Number(q) if q.dim.is_none() => Ok(q.value),
        _ => Err(type_error(v, what, "a plain number")),
    }
}

/// A whole number >= 0.
pub fn as_count(v: &Value, what: &str) -> Result<usize, Diagnostic> {
    let n = as_number(v, what)?;
    if n >= 0.0 && n.fract() == 0.0 && n < 1e9 {
        Ok(n as usize)
    } else {
        Err(Diagnostic::new(
            "die::type_mismatch",
            format!("{what} must be a whole number"),
            v.span,
            format!("this is {n}"),
        )
        .with_help("use a whole number such as 3"))
    }
}

/// A length in mm; bare numbers take the default unit.
pub fn as_length(v: &Value, units: Units, what: &str) -> Result<f64, Diagnostic> {
    match &v.data {
        Data::Number(q) if q.dim == Dim::LENGTH => Ok(q.value),
        Data::Number(q) if q.bare => in_default_unit(v, q.value * units.length, what),
        _ => Err(type_error(v, what, "a length such as `12 mm`")),
    }
}

/// An angle in radians; bare numbers take the default unit.
pub fn as_angle(v: &Value, units: Units, what: &str) -> Result<f64, Diagnostic> {
    match &v.data {
        Data::Number(q) if q.dim == Dim::ANGLE => Ok(q.value),
        Data::Number(q) if q.bare => in_default_unit(v, q.value * units.angle, what),
        _ => Err(type_error(v, what, "an angle such as `5 deg`")),
    }
}

/// A bare number converted to the file's default unit, refused when the conversion
/// overflows (`1e307` in a file whose lengths are in metres).
fn in_default_unit(v: &Value, converted: f64, what: &str) -> Result<f64, Diagnostic> {
    if converted.is_finite() {
        return Ok(converted);
    }
    Err(Diagnostic::new(
        super::finite::CODE,
        format!("{what} is too large once converted from the file's default unit to millimetres and radians"),
        v.span,
        "too large in base units",
    )
    .with_help("numbers lie between about -1.8e308 and 1.8e308; check the `units` line and the magnitude of this number"))
}

/// A point's coordinate `mm` (written at `c`), refused beyond the modelling range
/// ([`crate::geom::MAX_COORDINATE`]): the kernel would square it on the way to
/// geometry that could not be exported, and report the overflow as something else.
fn in_range(c: &Value, mm: f64, what: &str) -> Result<f64, Diagnostic> {
    if mm.abs() <= crate::geom::MAX_COORDINATE {
        return Ok(mm);
    }
    Err(Diagnostic::new(
        super::finite::RANGE_CODE,
        format!(
            "{what} has a coordinate of {} mm, beyond the modelling range of {} mm from the origin",
            super::finite::show(mm),
            super::finite::show(crate::geom::MAX_COORDINATE)
        ),
        c.span,
        "beyond the modelling range",
    )
    .with_help("die faces are modelled in millimetres within 1 km of the origin (docs/limits.md); check the units and the magnitude of this coordinate"))
}

/// The coordinates of a tuple of lengths.
fn coords(
    v: &Value,
    units: Units,
    what: &str,
    n: usize,
    expected: &str,
) -> Result<Vec<f64>, Diagnostic> {
    match &v.data {
        Data::Tuple(items) if items.len() == n => items
            .iter()
            .map(|c| in_range(c, as_length(c, units, what)?, what))
            .collect(),
        _ => Err(type_error(v, what, expected)),
    }
}

/// A 2-D point `(x, y)` in mm.
pub fn as_point2(v: &Value, units: Units, what: &str) -> Result<DVec2, Diagnostic> {
    let c = coords(v, units, what, 2, "a 2-D point such as `(10, 20)`")?;
    Ok(DVec2::new(c[0], c[1]))
}

/// A 3-D point or vector `(x, y, z)` in mm.
pub fn as_point3(v: &Value, units: Units, what: &str) -> Result<DVec3, Diagnostic> {
    let c = coords(v, units, what, 3, "a 3-D point such as `(10, 20, 5)`")?;
    Ok(DVec3::new(c[0], c[1], c[2]))
}

/// A 3-D curve from a curve, a sketch (through its view) or a 2-D curve (z = 0).
pub fn as_curve3(v: &Value, what: &str) -> Result<Arc<Curve3>, Diagnostic> {
    match &v.data {
        Data::Curve3(c) => Ok(c.clone()),
        Data::Sketch(s) => Ok(Arc::new(s.to_3d())),
        Data::Curve2(c) => Ok(Arc::new(c.to_3d())),
        _ => Err(type_error(v, what, "a curve or a sketch")),
    }
}
