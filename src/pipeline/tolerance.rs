//! The chordal tolerance of a build: `--tolerance`, else the script's
//! `param tolerance`, else the default.

use crate::diag::{Diagnostic, Sources};
use crate::eval::overrides::eval_text;
use crate::eval::units::Units;
use crate::eval::value::{Data, Dim};
use crate::eval::Outcome;
use crate::geom::tessellate::Tolerance;
use crate::limits::Limits;

/// The tolerance used when neither the command line nor the script sets one, in mm.
pub const DEFAULT_TOLERANCE_MM: f64 = 0.05;

/// The finest tolerance a build accepts, in mm (a nanometre). Finer is below what
/// double precision resolves across a die-sized part: every chord check then fails by
/// rounding, and a fuzzed `param tolerance = 1e-12 mm` spent 11 s tessellating before a
/// limit stopped it.
pub const MIN_TOLERANCE_MM: f64 = 1e-6;

/// The name of the script parameter that sets the tolerance.
pub const TOLERANCE_PARAM: &str = "tolerance";

/// The chordal tolerance: `given` (mm, from `--tolerance`), else the script's
/// top-level `param tolerance` (a positive length), else [`DEFAULT_TOLERANCE_MM`].
pub fn tolerance_for(outcome: &Outcome, given: Option<f64>) -> Result<Tolerance, Diagnostic> {
    if let Some(Ok(t)) = given.map(Tolerance::new) {
        return Ok(t);
    }
    let decl = outcome
        .decls
        .iter()
        .find(|d| d.name == TOLERANCE_PARAM && d.kind == "param");
    let Some(decl) = decl else {
        return Ok(Tolerance::new(DEFAULT_TOLERANCE_MM).expect("a positive constant"));
    };
    let value = decl.value.as_ref();
    let mm = value.and_then(|v| match v.data {
        Data::Number(q)
            if q.dim == Dim::LENGTH && q.value.is_finite() && q.value >= MIN_TOLERANCE_MM =>
        {
            Some(q.value)
        }
        _ => None,
    });
    match mm.map(Tolerance::new) {
        Some(Ok(t)) => Ok(t),
        _ => {
            let what = match value.map(|v| &v.data) {
                Some(Data::Number(q)) if q.dim == Dim::LENGTH => format!("{} mm", q.value),
                _ => value.map_or_else(|| "no value".to_string(), |v| v.type_name()),
            };
            Err(Diagnostic::new(
                "die::bad_tolerance",
                format!("`param tolerance` sets the tessellation's chordal tolerance and must be a length of at least {MIN_TOLERANCE_MM} mm, but this is {what}"),
                value.map_or(decl.span, |v| v.span),
                format!("this is {what}"),
            )
            .with_label(decl.span, "the tolerance parameter")
            .with_help("e.g. `param tolerance = 0.05 mm`, or pass `--tolerance 0.05mm`"))
        }
    }
}

/// Parses `--tolerance`: an expression of the language that is a positive length
/// (`0.01mm`, `0.01 mm`, `0.001in`), held to `limits` as a script is; returns
/// millimetres.
pub fn parse_tolerance(text: &str, limits: &Limits) -> Result<f64, String> {
    let mut sources = Sources::new();
    let value = eval_text(&mut sources, "--tolerance", text, Units::default(), limits).map_err(
        |d| match d.help {
            Some(help) => format!("{} ({help})", d.message),
            None => d.message,
        },
    )?;
    match value.data {
        Data::Number(q) if q.dim == Dim::LENGTH => {
            if q.value.is_finite() && q.value >= MIN_TOLERANCE_MM {
                Ok(q.value)
            } else if q.value.is_finite() && q.value > 0.0 {
                Err(format!(
                    "the tolerance must be at least {MIN_TOLERANCE_MM} mm (a nanometre): finer is below what double precision resolves on a part"
                ))
            } else {
                Err("the tolerance must be positive".into())
            }
        }
        Data::Number(q) if q.bare => {
            Err(format!("give the tolerance with its unit, e.g. `{text}mm`"))
        }
        _ => Err(format!(
            "the tolerance must be a length (mm, cm, m, in), but this is {}",
            value.type_name()
        )),
    }
}
