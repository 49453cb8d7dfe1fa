//! `bead name { ... }`: a draw bead on a blankholder, read into [`crate::die::bead`].
//!
//! ```text
//! import "std/beads" as beads
//! bead wheel_arch {
//!     binder = binder                  // the blankholder it sits on
//!     line = sketch(top) { ... }       // centre line in the top view, or
//!     // boundaries = [inner, outer]   // its two feet lines (the bead stretches across)
//!     profile = beads.round(height: 6 mm)   // cross-section, feet at height 0
//!     rules = [0 mm]                   // optional rule points across `profile`
//!     section high {                   // optional key sections at designer positions
//!         at = 50 %                    // a fraction, or a length along the centre line
//!         profile = beads.round(height: 8 mm)
//!         rules = [0 mm]               // as many rule points as every other section
//!     }
//!     taper = 30 mm                    // run-out length at both ends (default 0)
//!     spacing = 10 mm                  // sections along the bead (default 10 mm)
//!     line_spacing = 15 mm             // line-bead points (default 15 mm)
//!     force = 250                      // restraining force of the line bead, N/mm
//! }
//! ```
//!
//! `profile` is the bead's section at both ends (and everywhere, without `section`
//! blocks); each `section` sets the profile at its position, and between positions the
//! profile changes smoothly.

use std::sync::Arc;

use crate::diag::Diagnostic;
use crate::die::bead::{self as bd, Along, BeadSpec, Binder, Course, KeySection, Problem};
use crate::geom::Curve2;
use crate::syntax::Span;

use super::super::builtins::{as_length, type_error};
use super::super::sketch::View;
use super::super::summary::{bbox, bounds, round, sampled_surface};
use super::super::value::{Data, Quantity, Record, Value};
use super::explain::{diagnostic, Blame, Explanation};
use super::kind::{FeatureKind, FieldNames};
use super::{check_record, count, feature_error, feature_value, items, mm, record, show, Block};
use crate::die::model::{DieFace, LineBead};
use crate::geom::sew::{Face, Shape};

/// Where each key section came from, for diagnostics.
struct KeySource {
    /// `section NAME`, or `None` for the bead's own `profile` at an end.
    name: Option<String>,
    /// The `at` value (or the block head for the ends).
    at: Span,
    /// The profile value.
    profile: Span,
    /// The rules value (or the profile's span when there are none).
    rules: Span,
}

/// Builds the bead of `block`.
fn build(block: &Block) -> Result<Value, Diagnostic> {
    let units = block.units;
    let binder_field = block.get("binder").ok_or_else(|| {
        block.missing(
            "binder",
            "name the blankholder the bead sits on: `binder = my_binder`",
        )
    })?;
    let binder = match &binder_field.value.data {
        Data::Record(r) => match r
            .feature
            .as_ref()
            .and_then(|f| f.shared::<crate::die::blankholder::Blankholder>())
        {
            Some(b) => b,
            _ => return Err(not_a_binder(&binder_field.value)),
        },
        _ => return Err(not_a_binder(&binder_field.value)),
    };
    let course = course(block)?;

    // Key sections: the bead's own profile at the ends, the `section` blocks between.
    let mut keys: Vec<KeySection> = Vec::new();
    let mut sources: Vec<KeySource> = Vec::new();
    let own = match block.get("profile") {
        Some(f) => {
            let profile = profile_curve(&f.value, "`profile` of a bead")?;
            let (rules, rules_span) = match block.get("rules") {
                Some(r) => (rule_points(&r.value, units)?, r.value.span),
                None => (Vec::new(), f.value.span),
            };
            Some((profile, rules, f.value.span, rules_span))
        }
        None => {
            if let Some(r) = block.get("rules") {
                return Err(feature_error(
                    KIND,
                    "`rules` of a bead belong to its `profile`, which is missing",
                    r.value.span,
                    "rule points of no profile",
                    "give `profile = ...` beside `rules`, or put the rules in each `section`",
                ));
            }
            None
        }
    };
    let mut middle = Vec::new();
    for (name, field) in block.named("section") {
        let what = format!("`section {name}`");
        let r = record(
            &field.value,
            &what,
            "a block such as `section high { at = 50 %; profile = beads.round(height: 8 mm) }`",
        )?;
        check_record(r, field.value.span, &what, &["at", "profile", "rules"])?;
        let at_value = r.get("at").ok_or_else(|| {
            field.missing(&what, "at", "place the key section along the bead: `at = 50 %` (of the centre line's length) or `at = 300 mm` (from its start)")
        })?;
        let at = along(at_value, units, &what)?;
        let profile_value = r.get("profile").ok_or_else(|| {
            field.missing(
                &what,
                "profile",
                "give the section's cross-section: `profile = beads.round(height: 8 mm)`",
            )
        })?;
        let profile = profile_curve(profile_value, &format!("`profile` of {what}"))?;
        let (rules, rules_span) = match r.get("rules") {
            Some(v) => (rule_points(v, units)?, v.span),
            None => (Vec::new(), profile_value.span),
        };
        middle.push((
            KeySection { at, profile, rules },
            KeySource {
                name: Some(name.to_string()),
                at: at_value.span,
                profile: profile_value.span,
                rules: rules_span,
            },
        ));
    }
    if own.is_none() && middle.is_empty() {
        return Err(block.missing(
            "profile",
            "give the cross-section: `profile = beads.round(height: 6 mm)` (import \"std/beads\" as beads)",
        ));
    }
    let starts_at_zero = middle
        .first()
        .is_some_and(|(k, _)| matches!(k.at, Along::Fraction(f) | Along::Length(f) if f == 0.0));
    let ends_at_one = middle
        .last()
        .is_some_and(|(k, _)| k.at == Along::Fraction(1.0));
    let end_key = |at: f64| {
        own.as_ref().map(|(profile, rules, span, rules_span)| {
            (
                KeySection {
                    at: Along::Fraction(at),
                    profile: profile.clone(),
                    rules: rules.clone(),
                },
                KeySource {
                    name: None,
                    at: block.head(),
                    profile: *span,
                    rules: *rules_span,
                },
            )
        })
    };
    let first = if starts_at_zero { None } else { end_key(0.0) };
    let last = if ends_at_one { None } else { end_key(1.0) };
    for (k, s) in first.into_iter().chain(middle).chain(last) {
        keys.push(k);
        sources.push(s);
    }

    let taper = block.length_or("taper", 0.0)?;
    let spacing = block.length_or("spacing", 10.0)?;
    let line_spacing = block.length_or("line_spacing", 15.0)?;
    let force = match block.get("force") {
        Some(f) => Some(force_of(&f.value)?),
        None => None,
    };
    let patches: Vec<_> = binder.patches.iter().map(|p| &p.surface).collect();
    let map = Binder::new(patches, &binder.inner_outline);
    let spec = BeadSpec {
        course,
        sections: keys,
        taper,
        spacing,
        line_spacing,
        max_height: binder.max_bead_height,
    };
    let bead = bd::build(&map, &spec).map_err(|p| {
        diagnostic(KIND, block, explain(block, &p, &sources), |part| {
            resolve(block, &sources, part)
        })
    })?;
    let names: Vec<String> = sources
        .iter()
        .enumerate()
        .map(|(k, s)| match &s.name {
            Some(n) => n.clone(),
            None if k == 0 => "start".to_string(),
            None => "end".to_string(),
        })
        .collect();
    Ok(output(block, bead, &names, line_spacing, force))
}

/// The course of the bead: `line` (the centre line) or `boundaries` (its two feet
/// lines), exactly one of them, in the top view.
fn course(block: &Block) -> Result<Course, Diagnostic> {
    match (block.get("line"), block.get("boundaries")) {
        (Some(l), Some(b)) => Err(feature_error(
            KIND,
            format!(
                "the bead `{}` has both a centre `line` and `boundaries`",
                block.name
            ),
            b.value.span,
            "these boundaries",
            "give one: the centre line (the profile keeps its width) or the two boundaries (the profile stretches between them)",
        )
        .with_label(l.value.span, "and this centre line")),
        (Some(l), None) => Ok(Course::Centre(top_curve(&l.value, "`line` of a bead")?)),
        (None, Some(b)) => {
            let lines = items(&b.value);
            if lines.len() != 2 {
                return Err(feature_error(
                    KIND,
                    format!(
                        "`boundaries` of a bead are two top-view lines, not {}",
                        lines.len()
                    ),
                    b.value.span,
                    "here",
                    "give the bead's two feet lines: `boundaries = [inner_foot, outer_foot]`",
                ));
            }
            let what = "`boundaries` of a bead";
            Ok(Course::Boundaries(
                top_curve(&lines[0], what)?,
                top_curve(&lines[1], what)?,
            ))
        }
        (None, None) => Err(block.missing(
            "line",
            "draw the bead's centre line in the top view: `line = sketch(top) { from ...; line to ... }`, or its two feet lines as `boundaries = [a, b]`",
        )),
    }
}

/// A top-view curve: a `sketch(top)` or a 2-D curve.
fn top_curve(v: &Value, what: &str) -> Result<Curve2, Diagnostic> {
    match &v.data {
        Data::Sketch(s) if s.view == View::Top => Ok(s.curve.clone()),
        Data::Sketch(s) => Err(Diagnostic::new(
            "die::bead",
            format!("{what} is drawn in the {} view", s.view.name()),
            v.span,
            "not the top view",
        )
        .with_help("a bead's course is drawn in the top view: `sketch(top) { ... }`; dieface projects it onto the binder along the press direction")),
        Data::Curve2(c) => Ok((**c).clone()),
        _ => Err(type_error(v, what, "a top-view sketch")),
    }
}

/// A bead cross-section: a sketch or 2-D curve of (s across, height).
fn profile_curve(v: &Value, what: &str) -> Result<Curve2, Diagnostic> {
    match &v.data {
        Data::Sketch(s) if s.view == View::Profile => Ok(s.curve.clone()),
        Data::Sketch(s) => Err(Diagnostic::new(
            "die::bead",
            format!("{what} is drawn in the {} view", s.view.name()),
            v.span,
            "not a cross-section",
        )
        .with_help("draw a bead's cross-section in `sketch(profile) { ... }`: s across the bead, height above the binder; or use `std/beads`")),
        Data::Curve2(c) => Ok((**c).clone()),
        _ => Err(type_error(
            v,
            what,
            "a bead cross-section sketch such as `beads.round(height: 6 mm)`",
        )),
    }
}

/// Rule points: a list of lengths across the profile.
fn rule_points(v: &Value, units: super::super::units::Units) -> Result<Vec<f64>, Diagnostic> {
    items(v)
        .iter()
        .map(|x| as_length(x, units, "a rule point (mm across the profile)"))
        .collect()
}

/// A position along the bead: a ratio (`40 %`) or a length (`300 mm`).
fn along(v: &Value, units: super::super::units::Units, what: &str) -> Result<Along, Diagnostic> {
    match &v.data {
        Data::Number(q) if q.dim.is_none() && !q.bare => Ok(Along::Fraction(q.value)),
        _ => as_length(v, units, &format!("`at` of {what}"))
            .map(Along::Length)
            .map_err(|d| {
                d.with_help("place the key section with a fraction of the bead's length, `at = 40 %`, or a length from its start, `at = 300 mm`")
            }),
    }
}

/// The line bead's restraining force: a bare positive number, in N/mm.
fn force_of(v: &Value) -> Result<f64, Diagnostic> {
    let what = "`force` of a bead (N/mm)";
    let help =
        "the restraining force per length of bead, in N/mm, as a plain number: `force = 250`";
    match &v.data {
        Data::Number(q) if q.dim.is_none() && q.bare => {
            if q.value.is_finite() && q.value > 0.0 {
                Ok(q.value)
            } else {
                Err(feature_error(
                    KIND,
                    format!("the {what} must be positive, but it is {}", show(q.value)),
                    v.span,
                    "not a positive force",
                    help,
                ))
            }
        }
        Data::Number(q) if q.dim.is_none() => Err(feature_error(
            KIND,
            format!("the {what} is a force per length, not a ratio"),
            v.span,
            "a ratio",
            help,
        )),
        _ => Err(type_error(v, what, "a plain number of N/mm such as `250`").with_help(help)),
    }
}

fn not_a_binder(v: &Value) -> Diagnostic {
    type_error(v, "`binder` of a bead", "a blankholder")
}

/// The name a designer reads for key section `k` of `sources`: a `section NAME`, or
/// the bead's own `profile` (at its start or end when there are sections between).
fn section_name(sources: &[KeySource], k: usize) -> String {
    let only_profile = sources.iter().all(|s| s.name.is_none());
    match &sources[k].name {
        Some(n) => format!("section `{n}`"),
        None if only_profile => "the bead's `profile`".to_string(),
        None if k == 0 => "the bead's `profile` at its start".to_string(),
        None => "the bead's `profile` at its end".to_string(),
    }
}

/// The parts of a bead block a problem is blamed on.
enum Part {
    /// The course: the centre `line`, or the `boundaries`.
    Course,
    /// A key section's profile.
    Profile(usize),
    /// A key section's rule points (its profile when it gives none).
    Rules(usize),
    /// A key section's position `at` (the block's head for the bead's own profile).
    At(usize),
}

/// Where the part of `block` `part` was written (`sources`: the key sections').
fn resolve(block: &Block, sources: &[KeySource], part: &Part) -> Option<Span> {
    let source = |k: usize| sources.get(k.min(sources.len().saturating_sub(1)));
    match *part {
        Part::Course => block
            .get("line")
            .or_else(|| block.get("boundaries"))
            .map(|f| f.value.span),
        Part::Profile(k) => source(k).map(|s| s.profile),
        Part::Rules(k) => source(k).map(|s| s.rules),
        Part::At(k) => source(k).map(|s| s.at),
    }
}

/// What the designer reads about the kernel's problem `p` with the bead of `block`,
/// whose key sections are `sources`.
fn explain(block: &Block, p: &Problem, sources: &[KeySource]) -> Explanation<Part> {
    let bead = block.name;
    let course = if block.get("boundaries").is_some() {
        "these boundaries"
    } else {
        "this centre line"
    };
    let name = |k: usize| section_name(sources, k.min(sources.len().saturating_sub(1)));
    match p {
        Problem::LeavesBinder { at, offset } | Problem::CrossesOpening { at, offset } => {
            // What the bead's side does, what the whole bead does, and the help for each.
            let [side, whole, side_help, whole_help] = if matches!(p, Problem::LeavesBinder { .. }) {
                [
                    "leaves the binder",
                    "leaves the binder",
                    "move the centre line away from the binder's outer edge, or narrow the profile",
                    "keep the centre line, and the bead's width around it, over the blankholder in the top view",
                ]
            } else {
                [
                    "reaches into the punch opening",
                    "runs inside the punch opening",
                    "move the centre line out from the opening by at least the bead's half width, or narrow the profile",
                    "a bead runs on the binder, outside the punch opening: draw the centre line outside the opening's top view",
                ]
            };
            let near = format!("near ({:.1}, {:.1})", at.x, at.y);
            let (message, help) = match offset {
                Some(o) if o.abs() > 1e-9 => (
                    format!(
                        "the bead `{bead}` is too wide here: its side, {} mm from the centre line, {side} {near}",
                        show(o.abs())
                    ),
                    side_help,
                ),
                _ => (format!("the bead `{bead}` {whole} {near}"), whole_help),
            };
            Explanation::new(message, Part::Course, course, help)
        }
        Problem::TooTight { at, radius, reach } => {
            let turn = if *radius == 0.0 {
                "has a sharp corner".to_string()
            } else {
                format!("turns with a radius of {} mm", show(*radius))
            };
            Explanation::new(
                format!(
                    "the centre line of the bead `{bead}` {turn} near ({:.1}, {:.1}), but the bead reaches {} mm to the inside of the turn: it would fold over itself",
                    at.x,
                    at.y,
                    show(*reach)
                ),
                Part::Course,
                course,
                format!(
                    "round the turn with a `fillet` larger than {} mm (the bead's reach), or narrow the profile",
                    show(*reach)
                ),
            )
        }
        Problem::BelowBinder { section, s } => Explanation::new(
            format!(
                "the cross-section of {} is not above the binder at s = {} mm",
                name(*section),
                show(*s)
            ),
            Part::Profile(*section),
            "this profile",
            "a draw bead is a ridge standing on the binder: its heights are 0 at the feet and positive between (the groove in the other binder half is made from it)",
        ),
        Problem::ClosedTaper => Explanation::new(
            format!("the bead `{bead}` is a closed ring, which has no ends to taper"),
            Blame::Field("taper"),
            "this taper",
            "remove `taper` for a ring bead, or draw an open centre line",
        )
        .also(Part::Course, "a closed centre line"),
        Problem::TooFine { what, count } => Explanation::new(
            format!(
                "the bead's {what} is so fine that it would take {} sections or points",
                if *count > 1_000_000_000 { "more than a billion".to_string() } else { count.to_string() }
            ),
            Blame::Field(match *what {
                "section spacing" => "spacing",
                "taper" => "taper",
                _ => "line_spacing",
            }),
            "too fine",
            if *what == "taper" {
                "a taper runs the height out over 10-50 mm; for a bead at full height to its ends, leave `taper` out"
            } else {
                "sections every 5-10 mm follow any bead profile within 0.01 mm; line beads every 10-20 mm are what forming simulation uses"
            },
        ),
        Problem::ProfileFeet { section } => Explanation::new(
            format!("the cross-section of {} must start and end on the binder, at height 0", name(*section)),
            Part::Profile(*section),
            "this profile",
            "draw the cross-section from (-w, 0) over the crest to (w, 0), or use `std/beads`",
        ),
        Problem::ProfileFolds { section, s } => Explanation::new(
            format!("the cross-section of {} runs backwards across the bead at s = {} mm", name(*section), show(*s)),
            Part::Profile(*section),
            "this profile",
            "a bead's cross-section must run one way across the bead (from one foot to the other): a wall that leans back would be an undercut the press cannot form",
        ),
        Problem::TooTall { section, height, limit } => Explanation::new(
            format!(
                "{} is {} mm tall, but the binder allows beads up to {} mm",
                name(*section),
                show(*height),
                show(*limit)
            ),
            Part::Profile(*section),
            "this cross-section",
            format!("lower the bead, or, for a special die, raise the blankholder's `max_bead_height` (now {} mm)", show(*limit)),
        )
        .also(Blame::Field("binder"), "on this binder"),
        Problem::RuleCount { section, expected, given } => Explanation::new(
            format!("{} has {given} rule points, but {} has {expected}", name(*section), name(0)),
            Part::Rules(*section),
            format!("{given} rule points"),
            "rules tie the same feature of every key section together (a crest, a step): give each key section the same number, in the same order across",
        )
        .also(Part::Rules(0), format!("{expected} here")),
        Problem::RuleOutside { section, s, feet } => Explanation::new(
            format!(
                "the rule point {} mm of {} is not between its feet ({} mm, {} mm) in order",
                show(*s),
                name(*section),
                show(feet.0),
                show(feet.1)
            ),
            Part::Rules(*section),
            "these rule points",
            "rule points are positions across the profile, strictly between its feet and increasing",
        ),
        Problem::SectionOrder { section } => Explanation::new(
            format!("{} is not on the bead after the one before it", name(*section)),
            Part::At(*section),
            "this position",
            "key sections go in order along the centre line, from 0 % to 100 % of its length",
        ),
        Problem::BoundariesCross { at } => Explanation::new(
            format!(
                "the boundaries of the bead `{bead}` cross or run closer than 1 mm near ({:.1}, {:.1})",
                at.x, at.y
            ),
            Part::Course,
            "these boundaries",
            "the two boundaries are the bead's feet: draw them side by side, apart over the whole bead",
        ),
        Problem::MissesBoundary { boundary, at } => Explanation::new(
            format!(
                "the section across the bead `{bead}` near ({:.1}, {:.1}) does not meet boundary {}",
                at.x,
                at.y,
                boundary + 1
            ),
            Part::Course,
            "these boundaries",
            "the two boundaries must run side by side over the whole bead: draw them the same length, from the same end",
        ),
        Problem::TaperTooLong { taper, length } => Explanation::new(
            format!(
                "the bead `{bead}` tapers over {} mm at both ends, more than half its {} mm",
                show(*taper),
                show(*length)
            ),
            Blame::Field("taper"),
            "this taper",
            format!(
                "the bead would never reach its full height: keep `taper` below {} mm, half the centre line",
                show(length / 2.0)
            ),
        )
        .also(Part::Course, "this centre line"),
        Problem::BadLength(what) => {
            let (field, must, help) = match *what {
                "taper length" => (Blame::Field("taper"), "a length of 0 mm or more", "the taper is the length over which the bead's height runs out at each end: `0 mm` for none, 20-50 mm is common"),
                "section spacing" => (Blame::Field("spacing"), "a positive length", SPACING_HELP),
                "line-bead spacing" => (Blame::Field("line_spacing"), "a positive length", SPACING_HELP),
                _ => (Blame::Block, "a positive length", SPACING_HELP),
            };
            Explanation::new(
                format!("the bead's {what} must be {must}"),
                field,
                "not a usable length",
                help,
            )
        }
        Problem::Kernel(e) => Explanation::new(
            format!("the bead `{bead}` cannot be built: {e}"),
            Part::Course,
            "this bead",
            "check the centre line for a doubling back and the profile for degenerate input",
        ),
    }
}

/// The help for a spacing that is not a usable length.
const SPACING_HELP: &str = "sections every 10 mm and line-bead points every 15 mm are common";

/// The feature record: `surface`, `centre` (on the binder), one `section NAME` per key
/// section (`start` and `end` for the bead's own profile at its ends), `rules`,
/// `line_bead`, `quality`.
fn output(
    block: &Block,
    bead: bd::Bead,
    names: &[String],
    spacing: f64,
    force: Option<f64>,
) -> Value {
    let span = block.span;
    let points: Vec<Value> = bead
        .line_points
        .iter()
        .map(|&p| Value::point3(p, span))
        .collect();
    let mut line_bead = vec![
        (
            "points".to_string(),
            Value::new(Data::List(Arc::new(points)), span),
        ),
        ("spacing".to_string(), mm(spacing, span)),
    ];
    if let Some(f) = force {
        line_bead.push((
            "force".to_string(),
            Value::new(Data::Number(Quantity::bare(f)), span),
        ));
    }
    let curve = |c: &crate::geom::Curve3| Value::new(Data::Curve3(Arc::new(c.clone())), span);
    let rules: Vec<Value> = bead.rules.iter().map(curve).collect();
    let mut fields = vec![
        (
            "surface".to_string(),
            Value::new(Data::Surface(Arc::new(bead.surface.clone())), span),
        ),
        (
            "centre".to_string(),
            Value::new(Data::Curve3(Arc::new(bead.centre.clone())), span),
        ),
        (
            "rules".to_string(),
            Value::new(Data::List(Arc::new(rules)), span),
        ),
        (
            "line_bead".to_string(),
            super::record_value(line_bead, span),
        ),
    ];
    for (name, section) in names.iter().zip(&bead.sections) {
        fields.push((format!("section {name}"), curve(section)));
    }
    let q = bead.quality;
    let mut quality = vec![
        ("foot_gap".to_string(), mm(q.foot_gap, span)),
        ("section_error".to_string(), mm(q.section_error, span)),
        ("height".to_string(), mm(q.height, span)),
        ("width_min".to_string(), mm(q.width.0, span)),
        ("width_max".to_string(), mm(q.width.1, span)),
        ("sections".to_string(), count(q.sections, span)),
        ("length".to_string(), mm(q.length, span)),
        ("min_radius".to_string(), mm(q.min_radius, span)),
        (
            "min_radius_at".to_string(),
            Value::point3(q.min_radius_at, span),
        ),
        ("end_min_radius".to_string(), mm(q.end_min_radius, span)),
        ("drawn_radius".to_string(), mm(q.drawn_radius, span)),
    ];
    // The skin's draft and undercut (and its figures as the record `surface`); the
    // bead's own radii above (full height, ends, drawn) stay as they are.
    let mut skin = Vec::new();
    super::measured_figures(&mut skin, [("surface", bead.figures, &[][..], None)], span);
    for (key, value) in skin {
        if !quality.iter().any(|(k, _)| *k == key) {
            quality.push((key, value));
        }
    }
    feature_value(KIND, span, fields, quality, bead)
}

/// The `bead` feature kind.
pub(super) static KIND: &dyn FeatureKind = &BeadKind;

struct BeadKind;

impl FeatureKind for BeadKind {
    fn name(&self) -> &'static str {
        "bead"
    }
    fn code(&self) -> &'static str {
        "die::bead"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec![
                "binder",
                "line",
                "boundaries",
                "profile",
                "rules",
                "taper",
                "spacing",
                "line_spacing",
                "force",
            ],
            named: vec!["section"],
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build(block)
    }
    fn color(&self) -> [f64; 3] {
        [0.55, 0.25, 0.75] // purple
    }
    /// The line bead is simulation data (glTF extras), not a piece to draw.
    fn exports_field(&self, field: &str) -> bool {
        field != "line_bead"
    }
    fn summary(&self, record: &Record) -> String {
        let Some(b) = record.model::<bd::Bead>() else {
            return String::new();
        };
        let (lo, hi) = bounds(sampled_surface(&b.surface));
        let line_bead = match self.line_bead(record) {
            Some(lb) => {
                let spacing = format!(" every {} mm", round(lb.spacing));
                let force = lb.force.map_or(", no force".to_string(), |f| {
                    format!(" at {} N/mm", round(f))
                });
                format!("{spacing}{force}")
            }
            None => String::new(),
        };
        format!(
            "draw bead, {} mm long, {} key sections ({} skinned), {} line-bead points{}, bounds {}",
            round(b.quality.length),
            b.sections.len(),
            b.quality.sections,
            b.line_points.len(),
            line_bead,
            bbox(lo, hi)
        )
    }
    /// The bead's centre line with the spacing and force its `line_bead` field holds.
    fn line_bead(&self, record: &Record) -> Option<LineBead> {
        let b = record.model::<bd::Bead>()?;
        let Some(Value {
            data: Data::Record(lb),
            ..
        }) = record.get("line_bead")
        else {
            return None;
        };
        let number = |name: &str| match lb.get(name).map(|v| &v.data) {
            Some(Data::Number(q)) => Some(q.value),
            _ => None,
        };
        Some(LineBead {
            points: b.line_points.clone(),
            spacing: number("spacing")?,
            force: number("force"),
            depth: b.quality.height,
        })
    }
    /// A bead's skin is a face of its own, beside the die face.
    fn die_face(&self, name: &str, record: &Record, out: &mut DieFace) {
        if let Some(b) = record.model::<bd::Bead>() {
            out.beads.push(Face {
                name: name.to_string(),
                shape: Shape::Patch(b.surface.clone()),
            });
        }
    }
}
