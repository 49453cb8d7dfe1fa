//! Feature blocks: `punch_opening`, `blankholder`, `step_draw`, `bead` and `die_checks`.
//!
//! A feature is written as a block. The engine evaluates the block's fields like any
//! record, then hands them here with the spans of their names. Each kind is one module
//! implementing [`FeatureKind`] ([`kind`]) and one entry in [`Registry::standard`]: it
//! reads its fields (checking types, units and names, with "did you mean"), calls the
//! kernel feature in [`crate::die`], and turns the result into a record of the
//! feature's kind: one geometric field per named piece (what `build` exports and
//! scripts reach with `name.piece`), plus a `quality` record of the figures a reviewer
//! checks. The kernel model rides along in [`Record::feature`] ([`Built`]) for the
//! features built on top of it and for the die model.

mod bead;
mod blankholder;
mod die_checks;
pub mod explain;
mod fill;
pub mod kind;
mod punch_opening;
mod round;
mod sheet;
mod step_draw;

pub use explain::{Blame, Explanation};
pub use kind::{Built, FeatureKind, FieldNames, Registry};

use std::sync::Arc;

use crate::diag::{did_you_mean, Diagnostic};
use crate::syntax::Span;

use super::builtins::{as_angle, as_length, as_number, type_error};
use super::units::Units;
use super::value::{Data, Dim, Quantity, Record, Value};

/// One field of a feature block.
#[derive(Debug, Clone)]
pub struct Field {
    /// Its words (`["side", "front"]`).
    pub words: Vec<String>,
    /// Where its name was written.
    pub name_span: Span,
    /// Its value.
    pub value: Value,
}

impl Field {
    /// Where the field's last word was written: the name in `side front`.
    pub fn name_word(&self) -> Span {
        let (start, end) = (self.name_span.start as usize, self.name_span.end as usize);
        let len = self.words.last().map_or(0, String::len);
        Span::new(self.name_span.file, end.saturating_sub(len).max(start), end)
    }

    /// The diagnostic for a nested block (`section front { ... }`, here `what`) that
    /// lacks the field `key`, pointing at the block's name.
    pub fn missing(&self, what: &str, key: &str, help: impl Into<String>) -> Diagnostic {
        let name = self.words.last().map_or("", String::as_str);
        Diagnostic::new(
            "die::missing_field",
            format!("{what} needs the field `{key}`"),
            self.name_word(),
            format!("`{name}` has no `{key}`"),
        )
        .with_help(help)
    }
}

/// A feature block, evaluated.
pub struct Block<'a> {
    /// The declaration's kind.
    pub kind: &'a str,
    /// The declaration's name.
    pub name: &'a str,
    /// The whole declaration.
    pub span: Span,
    /// Its fields in source order.
    pub fields: Vec<Field>,
    /// The file's default units, for bare numbers.
    pub units: Units,
    /// Calls a function value given in a field (a step-draw profile) with positional
    /// arguments, at the span of the call that asks.
    pub apply: &'a super::builtins::Apply<'a>,
    /// The source text at a span: a feature's name as written in `die_checks`'
    /// `features` list.
    pub text: &'a dyn Fn(Span) -> String,
    /// The engine's piece memo for this declaration: pieces whose inputs did not change
    /// since the last evaluation are taken from it.
    pub pieces: crate::die::memo::Pieces<'a>,
}

impl Block<'_> {
    /// The one-word field `name`.
    pub fn get(&self, name: &str) -> Option<&Field> {
        self.fields
            .iter()
            .find(|f| f.words.len() == 1 && f.words[0] == name)
    }

    /// The fields `word <name>`, with their names.
    pub fn named(&self, word: &str) -> Vec<(&str, &Field)> {
        self.fields
            .iter()
            .filter(|f| f.words.len() == 2 && f.words[0] == word)
            .map(|f| (f.words[1].as_str(), f))
            .collect()
    }

    /// Refuses fields other than `single` (one word) and `named` (`word <name>`).
    pub fn check_fields(&self, single: &[&str], named: &[&str]) -> Result<(), Diagnostic> {
        let mut forms: Vec<String> = single.iter().map(|s| s.to_string()).collect();
        forms.extend(named.iter().map(|n| format!("{n} <name>")));
        let forms = forms.join(", ");
        for f in &self.fields {
            let ok = match f.words.as_slice() {
                [one] => single.contains(&one.as_str()),
                [word, _] => named.contains(&word.as_str()),
                _ => false,
            };
            if ok {
                continue;
            }
            let written = f.words.join(" ");
            let first = f.words.first().map_or("", String::as_str);
            // The right word with the wrong number of names.
            if f.words.len() == 1 && named.contains(&first) {
                return Err(Diagnostic::new(
                    "die::unknown_field",
                    format!("a `{}` field `{first}` needs a name", self.kind),
                    f.name_span,
                    format!("which {first}?"),
                )
                .with_help(format!(
                    "write `{first} NAME ...`, e.g. `{first} front = ...`; the fields are: {forms}"
                )));
            }
            if f.words.len() == 2 && single.contains(&first) {
                return Err(Diagnostic::new(
                    "die::unknown_field",
                    format!(
                        "the field `{first}` of a `{}` takes no name, but this one is `{written}`",
                        self.kind
                    ),
                    f.name_span,
                    "a name after a field that has none",
                )
                .with_help(format!("write `{first} = ...`; the fields are: {forms}")));
            }
            let guess = did_you_mean(first, single.iter().chain(named).copied());
            let d = Diagnostic::new(
                "die::unknown_field",
                format!("a `{}` has no field `{written}`", self.kind),
                f.name_span,
                "not a field of this feature",
            );
            return Err(match guess {
                Some(g) if g != first => {
                    let fix = match f.words.as_slice() {
                        [_, name] if named.contains(&g) => format!("{g} {name}"),
                        _ => g.to_string(),
                    };
                    d.with_help(format!("did you mean `{fix}`? The fields are: {forms}"))
                }
                _ => d.with_help(format!("the fields are: {forms}")),
            });
        }
        Ok(())
    }

    /// The declaration's head: its kind word (`blankholder` in `blankholder binder {`),
    /// where a diagnostic about the whole block points.
    pub fn head(&self) -> Span {
        let end = (self.span.start as usize + self.kind.len()).min(self.span.end as usize);
        Span::new(self.span.file, self.span.start as usize, end)
    }

    /// A diagnostic that the required field `name` is missing.
    pub fn missing(&self, name: &str, help: &str) -> Diagnostic {
        Diagnostic::new(
            "die::missing_field",
            format!("a `{}` needs the field `{name}`", self.kind),
            self.head(),
            format!("`{}` has no `{name}`", self.name),
        )
        .with_help(help.to_string())
    }

    /// The length in field `name`, or `default`.
    pub fn length_or(&self, name: &str, default: f64) -> Result<f64, Diagnostic> {
        match self.get(name) {
            Some(f) => as_length(&f.value, self.units, &format!("`{name}`")),
            None => Ok(default),
        }
    }
}

/// Builds a feature of `kind` from its evaluated block: its fields checked against
/// the kind's, then the kind's own build.
pub fn build(kind: &dyn FeatureKind, block: &Block) -> Result<Value, Diagnostic> {
    let fields = kind.fields();
    block.check_fields(&fields.single, &fields.named)?;
    kind.build(block)
}

/// A diagnostic for a bad value in a feature block, with the kind's code.
fn feature_error(
    kind: &dyn FeatureKind,
    message: impl Into<String>,
    span: Span,
    label: impl Into<String>,
    help: impl Into<String>,
) -> Diagnostic {
    Diagnostic::new(kind.code(), message, span, label).with_help(help)
}

/// A value as a list of items (a single value is a list of one).
fn items(v: &Value) -> Vec<Value> {
    match &v.data {
        Data::List(items) => items.to_vec(),
        _ => vec![v.clone()],
    }
}

/// A length value.
fn length(v: &Value, units: Units, what: &str) -> Result<f64, Diagnostic> {
    as_length(v, units, what)
}

/// An angle value.
fn angle(v: &Value, units: Units, what: &str) -> Result<f64, Diagnostic> {
    as_angle(v, units, what)
}

/// A plain number or a ratio (`50 %`).
fn number(v: &Value, what: &str) -> Result<f64, Diagnostic> {
    as_number(v, what)
}

/// A record value's fields, or a type error.
fn record<'v>(v: &'v Value, what: &str, expected: &str) -> Result<&'v Record, Diagnostic> {
    match &v.data {
        Data::Record(r) => Ok(r),
        _ => Err(type_error(v, what, expected)),
    }
}

/// Refuses fields of a nested block other than `allowed`.
fn check_record(r: &Record, at: Span, what: &str, allowed: &[&str]) -> Result<(), Diagnostic> {
    for (name, value) in &r.fields {
        if allowed.contains(&name.as_str()) {
            continue;
        }
        let span = if value.span.file == at.file {
            value.span
        } else {
            at
        };
        let d = Diagnostic::new(
            "die::unknown_field",
            format!("{what} has no field `{name}`"),
            span,
            format!("the value of `{name}`"),
        );
        return Err(match did_you_mean(name, allowed.iter().copied()) {
            Some(g) => d.with_help(format!(
                "did you mean `{g}`? The fields are: {}",
                allowed.join(", ")
            )),
            None => d.with_help(format!("the fields are: {}", allowed.join(", "))),
        });
    }
    Ok(())
}

/// `1st`, `2nd`, `3rd`, `4th`, ...
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// A number as a designer reads it: at most six decimals, no trailing zeros.
fn show(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x != 0.0 && !(1e-4..1e9).contains(&x.abs()) {
        return format!("{x:e}");
    }
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// "did you mean `100 %`?" for a bare number above 1 where a fraction (0 to 1, or a
/// percentage) is wanted: a bare number is a fraction, so `100` is 10000 %, but the
/// designer most likely meant the percentage. `None` for anything else.
fn percent_hint(v: &Value) -> Option<String> {
    match &v.data {
        Data::Number(q) if q.bare && q.dim.is_none() && q.value > 1.0 && q.value <= 1000.0 => {
            Some(format!(
                "a bare number is a fraction here (`1` is `100 %`): did you mean `{} %`?",
                show(q.value)
            ))
        }
        _ => None,
    }
}

/// A plain number or ratio value as it was written: `90 %` for a ratio, `0.9` for a bare
/// number, `120 mm` for a length.
fn show_value(v: &Value) -> String {
    match &v.data {
        Data::Number(q) if q.dim == Dim::LENGTH => format!("{} mm", show(q.value)),
        Data::Number(q) if q.dim.is_none() && !q.bare => format!("{} %", show(q.value * 100.0)),
        Data::Number(q) if q.dim.is_none() => show(q.value),
        Data::Number(q) => show(q.value),
        _ => v.type_name().to_string(),
    }
}

/// A number value with a dimension, at `span`.
fn quantity(q: Quantity, span: Span) -> Value {
    Value::new(Data::Number(q), span)
}

/// A length in mm as a value.
fn mm(v: f64, span: Span) -> Value {
    quantity(Quantity::length(v), span)
}

/// An angle in degrees as a value.
fn deg(v: f64, span: Span) -> Value {
    quantity(Quantity::angle(v.to_radians()), span)
}

/// A plain count as a value.
fn count(v: usize, span: Span) -> Value {
    quantity(
        Quantity {
            value: v as f64,
            dim: Dim::NONE,
            bare: true,
        },
        span,
    )
}

/// A plain ratio as a value.
fn ratio(v: f64, span: Span) -> Value {
    quantity(Quantity::ratio(v), span)
}

/// A record value of named fields.
fn record_value(fields: Vec<(String, Value)>, span: Span) -> Value {
    Value::new(
        Data::Record(Arc::new(Record {
            kind: None,
            fields,
            feature: None,
        })),
        span,
    )
}

/// The value of a feature block: its pieces' fields, then `quality` (the overall figures
/// followed by the per-piece records), with the kernel model attached.
pub fn feature_value<T: std::any::Any + Send + Sync>(
    kind: &'static dyn FeatureKind,
    span: Span,
    mut fields: Vec<(String, Value)>,
    quality: Vec<(String, Value)>,
    model: T,
) -> Value {
    fields.push(("quality".into(), record_value(quality, span)));
    Value::new(
        Data::Record(Arc::new(Record {
            kind: Some(kind.name().to_string()),
            fields,
            feature: Some(Built::new(kind, model)),
        })),
        span,
    )
}

/// Named values, in order: the fields of a record being built.
type Fields = Vec<(String, Value)>;

/// The join figures of a feature made of patches: the worst `gap`, `normal_angle`,
/// `net_angle` and `ratio_spread` over all joins, then one record per join named
/// `before > after`, for the `quality` record.
fn join_figures<'j>(
    joins: impl IntoIterator<Item = (&'j str, &'j str, &'j crate::die::continuity::JoinQuality)>,
    span: Span,
) -> (Fields, Fields) {
    let (mut gap, mut normal, mut net, mut spread) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut per_join = Vec::new();
    for (a, b, q) in joins {
        let join_gap = q.gap.max(q.net_gap);
        gap = gap.max(join_gap);
        normal = normal.max(q.normal_angle);
        net = net.max(q.net_angle);
        spread = spread.max(q.ratio_spread);
        per_join.push((
            format!("{a} > {b}"),
            record_value(
                vec![
                    ("gap".into(), mm(join_gap, span)),
                    ("normal_angle".into(), deg(q.normal_angle, span)),
                    ("net_angle".into(), deg(q.net_angle, span)),
                    ("ratio_spread".into(), ratio(q.ratio_spread, span)),
                ],
                span,
            ),
        ));
    }
    let worst = vec![
        ("gap".to_string(), mm(gap, span)),
        ("normal_angle".to_string(), deg(normal, span)),
        ("net_angle".to_string(), deg(net, span)),
        ("ratio_spread".to_string(), ratio(spread, span)),
    ];
    (worst, per_join)
}

/// The die engineer's figures of a feature's patches (`die::figures`), added to its
/// `quality` record: the worst over the feature (`min_radius`, `min_radius_at`, `draft`,
/// `draft_at`, `undercut`, and where patches carry sections, `sag`, `sag_at`,
/// `sag_below_opening`, `sag_below_opening_at`), then one record per patch, named as
/// the patch, with the same figures. Each patch is given with its surface, its
/// sections (from the opening end to the product end; none for a binder) and the
/// smallest radius drawn for it, when one is (`drawn_radius`, beside `min_radius`).
/// Returns each patch's name with its figures, for checks a kind makes on them.
fn surface_figures<'p>(
    quality: &mut Fields,
    patches: impl IntoIterator<
        Item = (
            &'p str,
            &'p crate::geom::NurbsSurface,
            &'p [crate::geom::Curve3],
            Option<f64>,
        ),
    >,
    span: Span,
) -> Vec<(&'p str, crate::die::figures::SurfaceFigures)> {
    use crate::die::figures::surface_figures as measure;
    use rayon::prelude::*;
    // The surfaces measured on their own, in parallel; the worst taken in patch order.
    let patches: Vec<_> = patches.into_iter().collect();
    let measured: Vec<_> = patches.par_iter().map(|p| measure(p.1)).collect();
    let named = patches
        .iter()
        .map(|p| p.0)
        .zip(measured.iter().copied())
        .collect();
    let measured = patches
        .into_iter()
        .zip(measured)
        .map(|((name, _, sections, drawn), f)| (name, f, sections, drawn));
    measured_figures(quality, measured, span);
    named
}

/// [`surface_figures`] of patches already measured (a bead measures its skin within
/// its build): each patch with its name, its figures, its sections and its drawn
/// radius.
fn measured_figures<'p>(
    quality: &mut Fields,
    patches: impl IntoIterator<
        Item = (
            &'p str,
            crate::die::figures::SurfaceFigures,
            &'p [crate::geom::Curve3],
            Option<f64>,
        ),
    >,
    span: Span,
) {
    use crate::die::figures::{section_sag, SectionEnd};
    use glam::DVec3;
    let point = |p: DVec3| Value::point3(p, span);
    let mut per_patch = Vec::new();
    // (value, where) of the worst so far.
    let mut radius = (f64::INFINITY, DVec3::ZERO);
    let mut draft = (f64::INFINITY, DVec3::ZERO);
    let mut sag: Option<((f64, DVec3), (f64, DVec3))> = None;
    let mut drawn_min = f64::INFINITY;
    for (name, f, sections, drawn) in patches {
        let mut fields = vec![
            ("min_radius".to_string(), mm(f.min_radius, span)),
            ("min_radius_at".to_string(), point(f.min_radius_at)),
            ("draft".to_string(), deg(f.draft, span)),
            ("draft_at".to_string(), point(f.draft_at)),
            (
                "undercut".to_string(),
                Value::new(Data::Bool(f.undercut), span),
            ),
        ];
        if let Some(d) = drawn.filter(|d| d.is_finite()) {
            fields.push(("drawn_radius".to_string(), mm(d, span)));
            drawn_min = drawn_min.min(d);
        }
        if per_patch.is_empty() || f.min_radius < radius.0 {
            radius = (f.min_radius, f.min_radius_at);
        }
        if per_patch.is_empty() || f.draft < draft.0 {
            draft = (f.draft, f.draft_at);
        }
        if let Some(first) = sections.first() {
            let mut chord = (0.0, first.start_point());
            let mut below = (0.0, first.start_point());
            for s in sections {
                let g = section_sag(s, SectionEnd::Start);
                if g.below_chord > chord.0 {
                    chord = (g.below_chord, g.below_chord_at);
                }
                if g.below_opening > below.0 {
                    below = (g.below_opening, g.below_opening_at);
                }
            }
            fields.extend([
                ("sag".to_string(), mm(chord.0, span)),
                ("sag_at".to_string(), point(chord.1)),
                ("sag_below_opening".to_string(), mm(below.0, span)),
                ("sag_below_opening_at".to_string(), point(below.1)),
            ]);
            let worst = sag.get_or_insert((chord, below));
            if chord.0 > worst.0 .0 {
                worst.0 = chord;
            }
            if below.0 > worst.1 .0 {
                worst.1 = below;
            }
        }
        per_patch.push((name.to_string(), record_value(fields, span)));
    }
    if per_patch.is_empty() {
        return;
    }
    let undercut = draft.0 < -crate::die::figures::UNDERCUT_TOLERANCE;
    quality.extend([
        ("min_radius".to_string(), mm(radius.0, span)),
        ("min_radius_at".to_string(), point(radius.1)),
    ]);
    if drawn_min.is_finite() {
        quality.push(("drawn_radius".to_string(), mm(drawn_min, span)));
    }
    quality.extend([
        ("draft".to_string(), deg(draft.0, span)),
        ("draft_at".to_string(), point(draft.1)),
        (
            "undercut".to_string(),
            Value::new(Data::Bool(undercut), span),
        ),
    ]);
    if let Some((chord, below)) = sag {
        quality.extend([
            ("sag".to_string(), mm(chord.0, span)),
            ("sag_at".to_string(), point(chord.1)),
            ("sag_below_opening".to_string(), mm(below.0, span)),
            ("sag_below_opening_at".to_string(), point(below.1)),
        ]);
    }
    quality.extend(per_patch);
}
