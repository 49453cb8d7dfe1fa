//! `step_draw name { ... }`: the block's fields read into [`crate::die::step_draw`]'s
//! input, and its result into a record.
//!
//! ```text
//! import "std/addendum" as add
//! step_draw addendum {
//!     product = outline               // the product outline (G_D), a 3-D cubic curve
//!     opening = opening               // the punch_opening (or a 3-D curve): G_U
//!     tolerance = 0.01 mm             // profile ends, fits (default 0.01 mm)
//!     closed = true                   // default: when both guides are closed
//!     section front {                 // key sections, in order along the outline
//!         at = ((0, -300), (0, -520)) // two top-view points: the vertical plane
//!         profile = add.wall          // a function (product, opening) -> sketch, or a
//!     }                               // sketch drawn in the section plane
//! }
//! ```
//!
//! A profile function gets the section plane's two guide points as `(s, z)` tuples,
//! `s` from the first `at` point towards the second: where the plane meets the product
//! outline, then where it meets the punch opening; it returns the profile between them.
//! A drawn sketch must start and end within `tolerance` of those points.

use std::sync::Arc;

use glam::DVec2;

use crate::diag::Diagnostic;
use crate::die::step_draw::{self as sd, Guides, Options, Problem, SectionSpec};
use crate::geom::Curve3;
use crate::syntax::Span;

use super::super::builtins::{as_curve3, as_point2, type_error};
use super::super::value::{Data, Feature, Value};
use super::{
    check_record, deg, feature_error, feature_value, mm, ratio, record, record_value, Block,
};

const KIND: &str = "step_draw";

/// Spans of one section's inputs, for diagnostics.
struct SectionSource {
    name_span: Span,
    at: Span,
    profile: Span,
}

/// Builds the step draw of `block`.
pub fn build(block: &Block) -> Result<Value, Diagnostic> {
    block.check_fields(&["product", "opening", "tolerance", "closed"], &["section"])?;
    let units = block.units;
    let product_field = block.get("product").ok_or_else(|| {
        block.missing(
            "product",
            "give the product outline: `product = boundary(panel)` or `project(trim, panel)`",
        )
    })?;
    let product = (*as_curve3(&product_field.value, "`product` of a step draw")?).clone();
    let opening_field = block.get("opening").ok_or_else(|| {
        block.missing(
            "opening",
            "give the punch opening: `opening = my_opening` (a punch_opening)",
        )
    })?;
    let opening = opening_line(&opening_field.value)?;
    let tolerance = block.length_or("tolerance", 0.01)?;
    if !(tolerance.is_finite() && tolerance > 0.0) {
        let span = block.get("tolerance").map_or(block.span, |f| f.value.span);
        return Err(feature_error(
            KIND,
            "the tolerance must be a positive length",
            span,
            "this tolerance",
            "0.01 mm is die-face practice",
        ));
    }
    let both_closed = is_closed(&product) && is_closed(&opening);
    let closed = match block.get("closed") {
        Some(f) => match &f.value.data {
            Data::Bool(b) => {
                if *b && !both_closed {
                    return Err(feature_error(KIND, "a closed step draw needs a closed product outline and a closed punch opening line", f.value.span, "closed = true", "set `closed = false` for a step draw that stops at its first and last sections"));
                }
                *b
            }
            _ => {
                return Err(type_error(
                    &f.value,
                    "`closed` of a step draw",
                    "true or false",
                ))
            }
        },
        None => both_closed,
    };
    if product.degree() != 3 || product.is_rational() {
        return Err(feature_error(KIND, format!("the product outline must be a non-rational cubic curve, but this one is of degree {}{}", product.degree(), if product.is_rational() { ", rational" } else { "" }), product_field.value.span, "this outline", "project the trim line onto the product with `project(trim, panel)`, or interpolate points of it with `interpolate`"));
    }
    let guides = sd::oriented(Guides {
        product,
        opening,
        closed,
    });

    let mut specs = Vec::new();
    let mut sources = Vec::new();
    for (name, field) in block.named("section") {
        let what = format!("`section {name}`");
        let r = record(
            &field.value,
            &what,
            "a block such as `section front { at = ((0, -300), (0, -520)); profile = add.wall }`",
        )?;
        check_record(r, field.value.span, &what, &["at", "profile"])?;
        let at_value = r.get("at").ok_or_else(|| {
            feature_error(KIND, format!("{what} has no `at`"), field.value.span, "this section", "place the section with two top-view points: `at = ((x1, y1), (x2, y2))`, from the product side outwards")
        })?;
        let (a, b) = two_points(at_value, units, &what)?;
        let profile_value = r.get("profile").ok_or_else(|| {
            feature_error(KIND, format!("{what} has no `profile`"), field.value.span, "this section", "give the profile: a stdlib one such as `profile = add.wall`, or a sketch in the section plane")
        })?;
        let ends = sd::section_ends(&guides, a, b).map_err(|p| {
            problem_diag(
                block,
                &p,
                name,
                at_value.span,
                profile_value.span,
                field.name_word(),
            )
        })?;
        let profile = match &profile_value.data {
            Data::Function(_) | Data::Builtin(_) => {
                let args = vec![
                    Value::point2(ends.product, profile_value.span),
                    Value::point2(ends.opening, profile_value.span),
                ];
                let out = (block.apply)(profile_value, args, profile_value.span)?;
                profile_curve(&out, &what).map_err(|d| {
                    d.with_label(profile_value.span, "the profile function called here")
                })?
            }
            _ => profile_curve(profile_value, &what)?,
        };
        specs.push(SectionSpec {
            name: name.to_string(),
            a,
            b,
            profile,
        });
        sources.push(SectionSource {
            name_span: field.name_word(),
            at: at_value.span,
            profile: profile_value.span,
        });
    }
    let result = sd::build(&guides, &specs, &Options { tolerance }).map_err(|e| {
        let (name, src) = match (specs.get(e.section), sources.get(e.section)) {
            (Some(s), Some(src)) => (s.name.as_str(), Some(src)),
            _ => ("?", None),
        };
        match src {
            Some(src) => problem_diag(block, &e.problem, name, src.at, src.profile, src.name_span),
            None => problem_diag(block, &e.problem, name, block.span, block.span, block.span),
        }
    })?;
    Ok(output(block, result))
}

/// The punch opening line of the `opening` field: a punch opening's closed line, or a
/// 3-D curve.
fn opening_line(v: &Value) -> Result<Curve3, Diagnostic> {
    match &v.data {
        Data::Record(r) => match &r.feature {
            Some(Feature::PunchOpening(p)) => Ok(p.line.clone()),
            _ => Err(type_error(
                v,
                "`opening` of a step draw",
                "a punch opening or a 3-D curve",
            )),
        },
        _ => as_curve3(v, "`opening` of a step draw").map(|c| (*c).clone()),
    }
}

fn is_closed(c: &Curve3) -> bool {
    c.start_point().distance(c.end_point()) <= 1e-9 * (1.0 + c.control_scale())
}

/// `at = (a, b)`: two top-view points.
fn two_points(
    v: &Value,
    units: super::super::units::Units,
    what: &str,
) -> Result<(DVec2, DVec2), Diagnostic> {
    let at_what = format!("`at` of {what}");
    let Data::Tuple(items) = &v.data else {
        return Err(type_error(
            v,
            &at_what,
            "two top-view points `((x1, y1), (x2, y2))`",
        ));
    };
    if items.len() != 2 {
        return Err(type_error(
            v,
            &at_what,
            "two top-view points `((x1, y1), (x2, y2))`",
        ));
    }
    let a = as_point2(&items[0], units, &at_what)?;
    let b = as_point2(&items[1], units, &at_what)?;
    if a.distance(b) < 1e-6 {
        return Err(feature_error(KIND, format!("the two points of `at` of {what} are the same point"), v.span, "one point twice", "the section plane runs vertically through two different top-view points: one on the product side, one beyond the punch opening"));
    }
    Ok((a, b))
}

/// A profile value: a sketch or a 2-D curve in the section plane's (s, z).
fn profile_curve(v: &Value, what: &str) -> Result<crate::geom::Curve2, Diagnostic> {
    match &v.data {
        Data::Sketch(s) => Ok(s.curve.clone()),
        Data::Curve2(c) => Ok((**c).clone()),
        _ => Err(type_error(
            v,
            &format!("`profile` of {what}"),
            "a sketch of the section profile, or a function returning one",
        )),
    }
}

fn problem_diag(
    block: &Block,
    p: &Problem,
    name: &str,
    at: Span,
    profile: Span,
    name_span: Span,
) -> Diagnostic {
    let pt = |q: DVec2| format!("(s {:.3}, z {:.3})", q.x, q.y);
    match p {
        Problem::TooFewSections { needed } => feature_error(
            KIND,
            format!("the step draw has too few sections: a {} outline needs at least {needed}", if *needed == 3 { "closed" } else { "open" }),
            block.span,
            "in this step draw",
            "add `section NAME { at = (...); profile = ... }` blocks around the outline, in order; one at each change of profile and a few along long sides",
        ),
        Problem::MissesGuide { product } => feature_error(
            KIND,
            format!("the plane of section `{name}` does not meet the {}", if *product { "product outline" } else { "punch opening line" }),
            at,
            "this section plane",
            "the plane is vertical through the two `at` points: draw them across the addendum, from inside the product outline to beyond the punch opening",
        ),
        Problem::EndsOffGuides { product, opening, gap } => feature_error(
            KIND,
            format!("the profile of section `{name}` does not reach both guides: its ends are up to {gap:.3} mm away"),
            profile,
            "this profile",
            format!("in this section plane the product outline is at {} and the punch opening at {}: start and end the profile there, or use a stdlib profile function that takes them (`profile = add.wall`)", pt(*product), pt(*opening)),
        ),
        Problem::FoldsBack { at: q } => feature_error(
            KIND,
            format!("the profile of section `{name}` folds back on itself near {}", pt(*q)),
            profile,
            "this profile",
            "a step-draw profile runs from the product outwards to the punch opening without turning back: check the wall angle and the runs, and that the wall fits between the two points",
        ),
        Problem::WrongOrder => feature_error(
            KIND,
            format!("section `{name}` comes before the previous section along the outline"),
            name_span,
            "out of order",
            "list the sections in order around the outline (counter-clockwise seen from above), each further along than the one before",
        ),
        Problem::ProductNotCubic => feature_error(
            KIND,
            "the product outline must be a non-rational cubic curve",
            block.span,
            "in this step draw",
            "project the trim line onto the product with `project(trim, panel)`",
        ),
        Problem::Kernel(e) => feature_error(
            KIND,
            format!("the step draw cannot be built at section `{name}`: {e} (in `{}`)", block.name),
            profile,
            "this section",
            "check this section's points and profile, and its neighbours'",
        ),
    }
}

/// The feature record: one surface per patch, one curve per key section, `quality`.
fn output(block: &Block, sd_result: sd::StepDraw) -> Value {
    let span = block.span;
    let mut fields: Vec<(String, Value)> = sd_result
        .patches
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                Value::new(Data::Surface(Arc::new(p.surface.clone())), span),
            )
        })
        .collect();
    for (name, curve) in &sd_result.key_sections {
        fields.push((
            format!("section {name}"),
            Value::new(Data::Curve3(Arc::new(curve.clone())), span),
        ));
    }
    let q = &sd_result.quality;
    let (mut normal, mut net, mut spread, mut gap) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut joins = Vec::new();
    for (a, b, j) in &q.joins {
        normal = normal.max(j.normal_angle);
        net = net.max(j.net_angle);
        spread = spread.max(j.ratio_spread);
        gap = gap.max(j.gap).max(j.net_gap);
        joins.push((
            format!("{a} > {b}"),
            record_value(
                vec![
                    ("gap".into(), mm(j.gap.max(j.net_gap), span)),
                    ("normal_angle".into(), deg(j.normal_angle, span)),
                    ("net_angle".into(), deg(j.net_angle, span)),
                    ("ratio_spread".into(), ratio(j.ratio_spread, span)),
                ],
                span,
            ),
        ));
    }
    let mut quality = vec![
        ("product_gap".to_string(), mm(q.product_gap, span)),
        (
            "opening_deviation".to_string(),
            mm(q.opening_deviation, span),
        ),
        ("section_fit".to_string(), mm(q.section_fit, span)),
        ("end_snap".to_string(), mm(q.end_snap, span)),
        ("gap".to_string(), mm(gap, span)),
        ("normal_angle".to_string(), deg(normal, span)),
        ("net_angle".to_string(), deg(net, span)),
        ("ratio_spread".to_string(), ratio(spread, span)),
    ];
    quality.extend(joins);
    feature_value(
        KIND,
        span,
        fields,
        quality,
        Feature::StepDraw(Arc::new(sd_result)),
    )
}
