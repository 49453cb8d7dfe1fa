//! The views sketches are drawn in: `top`, `side_xz`, `side_yz` are names the evaluator
//! knows; `section(a, b)` makes the vertical section plane through two top-view points
//! (paper 001 section 4.2, eq. 5).

use crate::diag::Diagnostic;

use super::builtins::{req, Builtin, Call};
use super::sketch::View;
use super::value::Data;

fn section(call: &Call) -> Result<Data, Diagnostic> {
    let a = call.point2("a")?;
    let b = call.point2("b")?;
    if a.distance(b) < 1e-9 {
        let span = call.arg("b").map_or(call.span, |v| v.span);
        return Err(Diagnostic::new(
            "die::bad_argument",
            "a section plane needs two different top-view points",
            span,
            "the same point as `a`",
        )
        .with_help("the plane runs vertically through `a` and `b`; move `b` away from `a`"));
    }
    Ok(Data::View(View::Section { a, b }))
}

static VIEWS: [Builtin; 1] = [Builtin {
    name: "section",
    params: &[req("a"), req("b")],
    doc: "the vertical section plane through two top-view points; sketch x runs from a towards b, y is up (Z)",
    run: section,
}];

/// The view builtin called `name`.
pub fn lookup(name: &str) -> Option<&'static Builtin> {
    VIEWS.iter().find(|b| b.name == name)
}

/// Names of the view builtins.
pub fn names() -> impl Iterator<Item = &'static str> {
    VIEWS.iter().map(|b| b.name)
}
