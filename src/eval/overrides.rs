//! Command-line values: `-D name=value` overrides of top-level `param`s, and the
//! expression helper the CLI also uses for `--tolerance 0.01mm`.
//!
//! An override's text is parsed as an expression of the language (so `-D delta=0.005mm`,
//! `-D angle=3.5deg`, `-D n=2*3` all work) and evaluated with the builtins and the main
//! file's default units only: it cannot name declarations, so it never adds an edge to
//! the dependency graph. It must have the kind and dimension of the parameter's declared
//! default, which is evaluated too (`die::bad_override` otherwise).
//!
//! Diagnostics about the text point into a pseudo-source named `-D name` that holds the
//! text as typed. The engine hooks this in where a main-file `param` is evaluated and
//! hashes the override text into that declaration's memo key, so `dieface watch` with the
//! same `-D` stays memoized and a different one re-evaluates the parameter and what uses it.

use std::sync::Arc;

use crate::diag::{did_you_mean, Diagnostic, Label, Sources};
use crate::limits::Limits;
use crate::syntax::ast::{self, DeclBody, Item};
use crate::syntax::parse::parse_with;
use crate::syntax::{FileId, Span};

use super::budget::Budget;
use super::engine::Globals;
use super::expr::{is_bare, with_default_unit, Ctx, Locals, World};
use super::units::Units;
use super::value::{Data, Record, Value};

/// What the text is parsed behind: `let __override = <text>`.
const PREFIX: &str = "let __override = ";

/// Splits a `-D name=value` argument (clap value parser).
pub fn parse_define(arg: &str) -> Result<(String, String), String> {
    let (name, value) = arg
        .split_once('=')
        .ok_or_else(|| format!("`{arg}` is not `name=value` (e.g. `-D delta=0.005mm`)"))?;
    let name = name.trim();
    let value = value.trim();
    let ident = name
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !ident {
        return Err(format!("`{name}` is not a parameter name"));
    }
    if value.is_empty() {
        return Err(format!(
            "`-D {name}=` needs a value (e.g. `-D {name}=10mm`)"
        ));
    }
    Ok((name.to_string(), value.to_string()))
}

/// The name of the pseudo-source holding the text of `-D name`.
pub fn source_name(name: &str) -> String {
    format!("-D {name}")
}

/// Parses and evaluates `text` as one expression, recorded in `sources` as the file
/// `source_name` (diagnostics point into it). Names of declarations are not visible;
/// bare numbers take `units`. The text is held to `limits` as a script is (its
/// nesting, so a long chain is refused before it is evaluated).
pub fn eval_text(
    sources: &mut Sources,
    source_name: &str,
    text: &str,
    units: Units,
    limits: &Limits,
) -> Result<Value, Diagnostic> {
    let file = sources.add(source_name, text);
    eval_in(file, text, units, limits)
}

/// [`eval_text`] for text already recorded in the sources as `file`.
pub fn eval_in(
    file: FileId,
    text: &str,
    units: Units,
    limits: &Limits,
) -> Result<Value, Diagnostic> {
    let shift = PREFIX.len() as u32;
    let full = format!("{PREFIX}{text}");
    let whole = Span::new(file, 0, text.len());
    let ast = parse_with(&full, file, limits).map_err(|d| shift_diag(d, file, shift))?;
    let expr = match ast.items.as_slice() {
        [Item::Decl(ast::Decl {
            body: DeclBody::Expr(e),
            ..
        })] => e,
        _ => {
            return Err(Diagnostic::new(
                "die::syntax",
                "expected one expression",
                whole,
                "not a single expression",
            )
            .with_help("give one value, such as `0.005mm`, `3.5deg` or `(10, 0, 5)`"))
        }
    };
    let world = TextWorld {
        globals: Globals {
            units,
            ..Globals::default()
        },
        budget: Budget::default(),
    };
    let ctx = Ctx {
        world: &world,
        file,
        decl: None,
        depth: 0,
        call: None,
    };
    let value = ctx
        .eval(expr, &Locals::new())
        .map_err(|d| shift_diag(d, file, shift))?;
    Ok(shift_value(&value, file, shift))
}

/// Evaluates `-D name=text` (recorded in the sources as `file`) for the parameter `decl`
/// of the main file: the override's value, checked against `declared`, the value of the
/// declaration as written. A bare number for a length or an angle takes the main file's
/// default unit, as a bare number does in the file (`-D tip_angle=6` is 6 deg in a
/// `units mm deg` file).
pub(crate) fn evaluate_override(
    file: FileId,
    decl: &ast::Decl,
    text: &str,
    units: Units,
    declared: Result<Value, Diagnostic>,
    limits: &Limits,
) -> Result<Value, Diagnostic> {
    let name = decl.name.node.as_str();
    let value = eval_in(file, text, units, limits)?;
    let declared = declared?;
    let value = if is_bare(&value) {
        with_default_unit(value, &declared, units)
    } else {
        value
    };
    if same_kind(&value.data, &declared.data) {
        return Ok(value);
    }
    let example = example_for(&declared.data, name);
    Err(Diagnostic::new(
        "die::bad_override",
        format!(
            "`-D {name}` gives {}, but `{name}` is {}",
            value.type_name(),
            declared.type_name()
        ),
        value.span,
        format!("this is {}", value.type_name()),
    )
    .with_label(
        decl.span,
        format!("`{name}` is declared here as {}", declared.type_name()),
    )
    .with_help(format!("`{example}`: {name} is {}", declared.type_name())))
}

/// Reports overrides that name no `param` of the main file: a `let` or another kind
/// (only params can be overridden), or an unknown name (with "did you mean").
pub(crate) fn check_names(
    sources: &mut Sources,
    overrides: &[(String, String)],
    decls: &[&ast::Decl],
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for (name, text) in overrides {
        let file = sources.add(source_name(name), text.as_str());
        let whole = Span::new(file, 0, text.len());
        match decls.iter().find(|d| d.name.node == *name) {
            Some(d) if d.kind.node == "param" => {}
            Some(d) => out.push(
                Diagnostic::new(
                    "die::bad_override",
                    format!(
                        "`{name}` is a `{}`, not a `param`; only params can be overridden",
                        d.kind.node
                    ),
                    d.kind.span,
                    format!("`{name}` is declared with `{}`", d.kind.node),
                )
                .with_label(whole, format!("`-D {name}` sets it"))
                .with_help(format!(
                    "declare it as `param {name} = ...` to let the command line set it"
                )),
            ),
            None => {
                let params = decls
                    .iter()
                    .filter(|d| d.kind.node == "param")
                    .map(|d| d.name.node.as_str());
                let diag = Diagnostic::new(
                    "die::bad_override",
                    format!("`-D {name}`: the script has no parameter `{name}`"),
                    whole,
                    format!("value for `{name}`"),
                );
                let names: Vec<&str> = params.clone().collect();
                out.push(match did_you_mean(name, params) {
                    Some(s) => diag.with_help(format!("did you mean `{s}`?")),
                    None if names.is_empty() => diag.with_help("the script declares no `param`s"),
                    None => diag.with_help(format!("its parameters: {}", names.join(", "))),
                });
            }
        }
    }
    out
}

/// Whether an override may replace a declared value: numbers of the same dimension,
/// else values of the same type.
fn same_kind(a: &Data, b: &Data) -> bool {
    match (a, b) {
        (Data::Number(x), Data::Number(y)) => x.dim == y.dim,
        _ => a.type_name() == b.type_name(),
    }
}

/// An example of a well-typed override, for help texts.
fn example_for(declared: &Data, name: &str) -> String {
    let v = match declared {
        Data::Number(q) if q.dim == super::value::Dim::LENGTH => "0.005mm",
        Data::Number(q) if q.dim == super::value::Dim::ANGLE => "3.5deg",
        Data::Number(q) if q.bare => "2",
        Data::Number(q) if q.dim.is_none() => "50%",
        Data::Bool(_) => "true",
        Data::Str(_) => "\"text\"",
        Data::Tuple(t) if t.len() == 3 => "(0, 0, 10)",
        Data::Tuple(t) if t.len() == 2 => "(0, 10)",
        _ => "...",
    };
    format!("-D {name}={v}")
}

/// Sees no declarations: only the builtins, with the given default units.
struct TextWorld {
    globals: Globals,
    budget: Budget,
}

impl World for TextWorld {
    fn globals(&self, _file: FileId) -> Option<&Globals> {
        Some(&self.globals)
    }
    fn paths(&self, _file: FileId) -> (Option<&std::path::Path>, Option<&std::path::Path>) {
        (None, None)
    }
    fn budget(&self) -> &Budget {
        &self.budget
    }
}

/// Moves a span in `file` back by the parse prefix.
fn shift_span(s: Span, file: FileId, by: u32) -> Span {
    if s.file != file {
        return s;
    }
    Span {
        file,
        start: s.start.saturating_sub(by),
        end: s.end.saturating_sub(by).max(s.start.saturating_sub(by)),
    }
}

fn shift_diag(mut d: Diagnostic, file: FileId, by: u32) -> Diagnostic {
    let fix = |l: &mut Label| l.span = shift_span(l.span, file, by);
    fix(&mut d.primary);
    d.secondary.iter_mut().for_each(fix);
    d
}

fn shift_value(v: &Value, file: FileId, by: u32) -> Value {
    let each = |items: &Arc<Vec<Value>>| {
        Arc::new(
            items
                .iter()
                .map(|i| shift_value(i, file, by))
                .collect::<Vec<_>>(),
        )
    };
    let data = match &v.data {
        Data::List(items) => Data::List(each(items)),
        Data::Tuple(items) => Data::Tuple(each(items)),
        Data::Record(r) => Data::Record(Arc::new(Record {
            kind: r.kind.clone(),
            fields: r
                .fields
                .iter()
                .map(|(n, f)| (n.clone(), shift_value(f, file, by)))
                .collect(),
            feature: r.feature.clone(),
        })),
        Data::Sketch(s) => {
            let mut s = (**s).clone();
            for seg in &mut s.segments {
                seg.span = shift_span(seg.span, file, by);
            }
            Data::Sketch(Arc::new(s))
        }
        other => other.clone(),
    };
    Value::new(data, shift_span(v.span, file, by))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defines_split_at_the_first_equals_sign() {
        assert_eq!(
            parse_define("delta=0.005mm"),
            Ok(("delta".into(), "0.005mm".into()))
        );
        assert_eq!(
            parse_define(" p = (1, 2) "),
            Ok(("p".into(), "(1, 2)".into()))
        );
        assert!(parse_define("delta").is_err());
        assert!(parse_define("1x=2").is_err());
        assert!(parse_define("x=").is_err());
    }

    #[test]
    fn text_evaluates_with_units_and_points_into_its_own_source() {
        let mut sources = Sources::new();
        let limits = Limits::default();
        let v = eval_text(&mut sources, "-D d", "0.5 cm", Units::default(), &limits).expect("ok");
        match v.data {
            Data::Number(q) => assert!((q.value - 5.0).abs() < 1e-12 && !q.bare),
            other => panic!("{other:?}"),
        }
        let err = eval_text(
            &mut sources,
            "-D d",
            "1mm + 2deg",
            Units::default(),
            &limits,
        )
        .unwrap_err();
        assert_eq!(err.code, "die::unit_mismatch");
        assert!(
            sources.slice(err.primary.span) == "1mm" || sources.slice(err.primary.span) == "2deg"
        );
        let err = eval_text(&mut sources, "-D d", "1mm +", Units::default(), &limits).unwrap_err();
        assert_eq!(err.code, "die::syntax");
    }
}
