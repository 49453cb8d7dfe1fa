//! `die_checks name { features = [...]; min_radius = 5 mm; ... }`: limits a designer
//! sets on the figures the features report in their `quality` records, each violation
//! an error at the feature.
//!
//! A limit names a figure: `min_radius` the smallest radius (`min_radius`), `min_draft`
//! the smallest draft (`draft`), `max_crease` every crease (`crease`, `*_crease`),
//! `max_gap` every gap along a seam (`gap`, `*_gap`), `max_sag` the dip below the punch
//! opening (`sag_below_opening`), `max_chord_sag` the dip below the chord
//! (`sag`). A feature without the figure is skipped for that limit. All violations are
//! found; the diagnostic points at the first (in the order of `features`, then of the
//! limits above) and its help lists every one. A passing check's value is a record per
//! feature of what was checked: the worst value, the limit, the margin and where.

use crate::diag::Diagnostic;
use crate::eval::value::{Data, Record, Value};
use crate::syntax::Span;

use super::kind::{FeatureKind, FieldNames};
use super::{angle, deg, items, length, mm, record_value, show, Block, Fields};

/// The declaration kind.
const NAME: &str = "die_checks";

/// One limit: its field, the figures it bounds, and whether the figures must stay above
/// it (`min_*`) or below it (`max_*`).
struct Limit {
    /// The field that sets it.
    field: &'static str,
    /// What the designer reads: "radius", "draft".
    what: &'static str,
    /// Whether a quality field is one of the figures it bounds.
    matches: fn(&str) -> bool,
    /// `true` for a lower limit.
    lower: bool,
    /// Angle (degrees) rather than length (mm).
    angle: bool,
    /// What to change when it is violated.
    help: &'static str,
}

/// The limits, in the order they are checked and reported.
const LIMITS: &[Limit] = &[
    Limit {
        field: "min_radius",
        what: "smallest radius",
        matches: |n| n == "min_radius",
        lower: true,
        angle: false,
        help: "open the radii drawn in the sections next to this patch (a binder: its corners' `tautness`), or lower `min_radius`",
    },
    Limit {
        field: "min_draft",
        what: "smallest draft",
        matches: |n| n == "draft",
        lower: true,
        angle: true,
        help: "draw the walls further from vertical (the `draft` of a step draw's profiles, the `angle` of a binder), or lower `min_draft`",
    },
    Limit {
        field: "max_crease",
        what: "crease",
        matches: |n| n == "crease" || n.ends_with("_crease"),
        lower: false,
        angle: true,
        help: "start the profiles tangent to the neighbouring surface there, or raise `max_crease`",
    },
    Limit {
        field: "max_gap",
        what: "gap",
        matches: |n| n == "gap" || n.ends_with("_gap"),
        lower: false,
        angle: false,
        help: "tighten the feature's `tolerance`, or raise `max_gap`",
    },
    Limit {
        field: "max_sag",
        what: "sag below the punch opening",
        matches: |n| n == "sag_below_opening",
        lower: false,
        angle: false,
        help: "check the profiles of the sections next to this patch: a section that dips below the punch opening traps metal; or raise `max_sag`",
    },
    Limit {
        field: "max_chord_sag",
        what: "sag below the section's chord",
        matches: |n| n == "sag",
        lower: false,
        angle: false,
        help: "check the profiles of the sections next to this patch, or raise `max_chord_sag`",
    },
];

/// The worst of one figure over a feature.
struct Worst {
    /// The quality field (`min_radius`, `product_gap`).
    figure: String,
    /// Its value (mm or degrees).
    value: f64,
    /// The patch (or join) whose record holds it, if any.
    patch: Option<String>,
    /// Where, if the feature says.
    at: Option<Value>,
}

/// The number in a quality field, in mm or degrees.
fn figure_value(v: &Value) -> Option<f64> {
    match &v.data {
        Data::Number(q) if q.dim == crate::eval::value::Dim::ANGLE => Some(q.value.to_degrees()),
        Data::Number(q) => Some(q.value),
        _ => None,
    }
}

/// The worst figure of `quality` that `limit` bounds (a feature-level field), with the
/// per-patch record holding that same value.
fn worst(quality: &Record, limit: &Limit) -> Option<Worst> {
    let mut best: Option<Worst> = None;
    for (name, v) in &quality.fields {
        if !(limit.matches)(name) {
            continue;
        }
        let Some(value) = figure_value(v) else {
            continue;
        };
        let worse = best.as_ref().is_none_or(|b| {
            if limit.lower {
                value < b.value
            } else {
                value > b.value
            }
        });
        if worse {
            best = Some(Worst {
                figure: name.clone(),
                value,
                patch: None,
                at: quality.get(&format!("{name}_at")).cloned(),
            });
        }
    }
    let mut w = best?;
    // The patch (or join) whose own record reports the worst value.
    for (name, v) in &quality.fields {
        let Data::Record(inner) = &v.data else {
            continue;
        };
        if inner.get(&w.figure).and_then(figure_value) == Some(w.value) {
            w.patch = Some(name.clone());
            if w.at.is_none() {
                w.at = inner.get(&format!("{}_at", w.figure)).cloned();
            }
            break;
        }
    }
    Some(w)
}

/// A point value as `(x, y, z)` rounded to 0.01 mm.
fn show_point(v: &Value) -> String {
    match &v.data {
        Data::Tuple(items) => {
            let c: Vec<String> = items
                .iter()
                .filter_map(figure_value)
                .map(|x| show((x * 100.0).round() / 100.0))
                .collect();
            format!("({})", c.join(", "))
        }
        _ => String::new(),
    }
}

/// One violation, for the diagnostic.
struct Violation {
    /// The feature's name as written in `features`, and where.
    feature: (String, Span),
    limit: &'static Limit,
    limit_span: Span,
    limit_value: f64,
    worst: Worst,
}

impl Violation {
    fn unit(&self) -> &'static str {
        if self.limit.angle {
            "deg"
        } else {
            "mm"
        }
    }

    /// "`addendum` patch `top_to_top_rear`: smallest radius 1.233 mm at (...), under
    /// `min_radius = 5 mm`".
    fn describe(&self) -> String {
        let unit = self.unit();
        let patch = self.worst.patch.as_ref().map_or(String::new(), |p| {
            let what = if p.contains(" > ") { "join" } else { "patch" };
            format!(" {what} `{p}`")
        });
        let at = self
            .worst
            .at
            .as_ref()
            .map_or(String::new(), |p| format!(" at {}", show_point(p)));
        let named = self.worst.figure == self.limit.field
            || (self.limit.field == "min_draft" && self.worst.figure == "draft");
        let figure = if named {
            self.limit.what.to_string()
        } else {
            format!("{} (`{}`)", self.limit.what, self.worst.figure)
        };
        format!(
            "`{}`{patch}: {figure} {} {unit}{at}, {} `{} = {} {unit}`",
            self.feature.0,
            rounded(self.worst.value),
            if self.limit.lower { "under" } else { "over" },
            self.limit.field,
            show(self.limit_value),
        )
    }
}

/// A figure to a thousandth, as a designer reads it in a message.
fn rounded(x: f64) -> String {
    show((x * 1000.0).round() / 1000.0)
}

/// Builds a `die_checks` block: reads the limits and the features, checks every figure.
fn build(block: &Block) -> Result<Value, Diagnostic> {
    let Some(features) = block.get("features") else {
        return Err(block.missing(
            "features",
            "list the features to check, e.g. `features = [addendum, binder]`",
        ));
    };
    let mut limits = Vec::new();
    for limit in LIMITS {
        let Some(f) = block.get(limit.field) else {
            continue;
        };
        let what = format!("`{}`", limit.field);
        let value = if limit.angle {
            angle(&f.value, block.units, &what)?.to_degrees()
        } else {
            length(&f.value, block.units, &what)?
        };
        limits.push((limit, value, f.name_word()));
    }
    if limits.is_empty() {
        return Err(Diagnostic::new(
            "die::die_checks",
            "a `die_checks` sets no limit",
            block.head(),
            format!("`{}` checks nothing", block.name),
        )
        .with_help(format!(
            "set at least one of: {}",
            LIMITS
                .iter()
                .map(|l| l.field)
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let span = block.span;
    let mut checked: Fields = Vec::new();
    let mut violations = Vec::new();
    for item in items(&features.value) {
        let name = (block.text)(item.span);
        let quality =
            match &item.data {
                Data::Record(r) if r.feature.is_some() => match r.get("quality").map(|q| &q.data) {
                    Some(Data::Record(q)) => q.clone(),
                    _ => continue,
                },
                _ => return Err(Diagnostic::new(
                    "die::die_checks",
                    format!(
                        "`features` lists die-face features, but `{name}` is {}",
                        item.type_name()
                    ),
                    item.span,
                    "not a feature",
                )
                .with_help(
                    "list the names of punch_opening, blankholder, step_draw or bead declarations",
                )),
            };
        let mut per_feature: Fields = Vec::new();
        for &(limit, limit_value, limit_span) in &limits {
            let Some(w) = worst(&quality, limit) else {
                continue;
            };
            let margin = if limit.lower {
                w.value - limit_value
            } else {
                limit_value - w.value
            };
            let as_value = |x: f64| {
                if limit.angle {
                    deg(x, span)
                } else {
                    mm(x, span)
                }
            };
            let mut fields = vec![
                (
                    "figure".to_string(),
                    Value::new(Data::Str(w.figure.as_str().into()), span),
                ),
                ("worst".to_string(), as_value(w.value)),
                ("limit".to_string(), as_value(limit_value)),
                ("margin".to_string(), as_value(margin)),
            ];
            if let Some(p) = &w.patch {
                fields.push((
                    "patch".to_string(),
                    Value::new(Data::Str(p.as_str().into()), span),
                ));
            }
            if let Some(at) = &w.at {
                fields.push(("at".to_string(), at.clone()));
            }
            per_feature.push((limit.field.to_string(), record_value(fields, span)));
            if margin < 0.0 {
                violations.push(Violation {
                    feature: (name.clone(), item.span),
                    limit,
                    limit_span,
                    limit_value,
                    worst: w,
                });
            }
        }
        checked.push((name, record_value(per_feature, span)));
    }
    if let Some(first) = violations.first() {
        let count = violations.len();
        let mut help = first.limit.help.to_string();
        if count > 1 {
            help.push_str(&format!(". All {count} violations:"));
            for v in &violations {
                help.push_str(&format!("\n- {}", v.describe()));
            }
        }
        return Err(Diagnostic::new(
            "die::die_checks",
            first.describe(),
            first.feature.1,
            format!(
                "its {} is {} {}",
                first.limit.what,
                rounded(first.worst.value),
                first.unit()
            ),
        )
        .with_label(first.limit_span, "the limit")
        .with_help(help));
    }
    Ok(Value::new(
        Data::Record(std::sync::Arc::new(Record {
            kind: Some(NAME.to_string()),
            fields: checked,
            feature: None,
        })),
        span,
    ))
}

/// The `die_checks` kind: limits on the features' quality figures.
pub(super) static KIND: &dyn FeatureKind = &DieChecksKind;

struct DieChecksKind;

impl FeatureKind for DieChecksKind {
    fn name(&self) -> &'static str {
        NAME
    }
    fn code(&self) -> &'static str {
        "die::die_checks"
    }
    /// `features`, then one field per limit.
    fn fields(&self) -> FieldNames {
        let mut single = vec!["features"];
        single.extend(LIMITS.iter().map(|l| l.field));
        FieldNames {
            single,
            named: Vec::new(),
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build(block)
    }
}
