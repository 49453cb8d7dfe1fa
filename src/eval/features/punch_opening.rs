//! `punch_opening name { ... }`: the block's fields read into
//! [`crate::die::punch_opening`]'s input, and its result into a record.
//!
//! ```text
//! punch_opening opening {
//!     top = profile                 // closed top-view sketch: sides joined by fillets
//!     delta = 0.01 mm               // stepping tolerance (default 0.01 mm)
//!     max_step = 40 mm              // L_max (default: an eighth of the shorter view)
//!     side front = wrap_front       // one side-view sketch per side, in drawing order
//!     side nose = wrap_nose
//!     corners { tangent = 100 % }   // default end-tangent magnitude of every corner
//!     corner front_nose { tangent = (140 mm, 120 mm) }
//! }
//! ```
//!
//! Every `fillet` of the top view is a corner; every other segment is a side, matched to
//! the `side` fields in drawing order. A corner is named after its sides,
//! `<previous>_<next>`. A tangent magnitude is a length (the derivative on the corner's
//! [0, 1] parameter), a ratio of the natural, circle-like magnitude (`90 %`, `1.2`), or
//! a pair of either for the start and the end.

use std::sync::Arc;

use glam::DVec2;

use crate::diag::{did_you_mean, Diagnostic};
use crate::die::punch_opening::{
    self as po, CornerSpec, Magnitude, PieceQuality, PieceSpec, PunchOpeningSpec, SideSpec,
    SideView,
};
use crate::geom::GeomError;
use crate::syntax::Span;

use super::super::sketch::{Sketch, View};
use super::super::value::{Data, Dim, Feature, Record, Value};
use super::{check_record, count, deg, feature_error, length, mm, record, record_value, Block};

const KIND: &str = "punch_opening";

/// Where each piece came from, for diagnostics.
struct PieceSource {
    /// The piece's top-view segment.
    segment: Span,
    /// The `side` field's value, or the corner's tangent value if one was given.
    field: Option<Span>,
}

/// Builds the punch opening of `block`.
pub fn build(block: &Block) -> Result<Value, Diagnostic> {
    block.check_fields(
        &["top", "delta", "max_step", "corners"],
        &["side", "corner"],
    )?;
    let units = block.units;
    let top_field = block.get("top").ok_or_else(|| {
        block.missing(
            "top",
            "draw the opening in the top view: `top = sketch(top) { from ...; line to ...; fillet 80; ...; close }`",
        )
    })?;
    let top = top_sketch(&top_field.value)?;
    let delta = block.length_or("delta", 0.01)?;
    if !(delta.is_finite() && delta > 0.0) {
        let span = block.get("delta").map_or(block.span, |f| f.value.span);
        return Err(feature_error(
            KIND,
            format!("the tolerance `delta` must be a positive length, but it is {delta} mm"),
            span,
            "this tolerance",
            "die-face practice is 0.01 mm",
        ));
    }
    let max_step = match block.get("max_step") {
        Some(f) => {
            let m = length(&f.value, units, "`max_step`")?;
            if !(m.is_finite() && m > 0.0) {
                return Err(feature_error(
                    KIND,
                    format!("`max_step` must be a positive length, but it is {m} mm"),
                    f.value.span,
                    "this step",
                    "L_max is the longest step along a straight side, e.g. 50 mm",
                ));
            }
            Some(m)
        }
        None => None,
    };

    // The top view's segments: fillets are corners, the rest sides.
    let sides = block.named("side");
    let side_segments: Vec<usize> = top
        .segments
        .iter()
        .enumerate()
        .filter(|(_, s)| s.kind != "fillet")
        .map(|(k, _)| k)
        .collect();
    if side_segments.len() != sides.len() {
        return Err(side_count_error(
            block,
            &top,
            &top_field.value,
            &side_segments,
            &sides,
        ));
    }
    let default_tangent = match block.get("corners") {
        Some(f) => {
            let r = record(
                &f.value,
                "`corners`",
                "a block such as `corners { tangent = 100 % }`",
            )?;
            check_record(r, f.value.span, "`corners`", &["tangent"])?;
            match r.get("tangent") {
                Some(t) => Some(magnitudes(t, units)?),
                None => None,
            }
        }
        None => None,
    };

    let mut pieces = Vec::with_capacity(top.segments.len());
    let mut sources = Vec::with_capacity(top.segments.len());
    let mut side_of_segment = vec![None; top.segments.len()];
    for (i, &k) in side_segments.iter().enumerate() {
        side_of_segment[k] = Some(i);
    }
    let n = top.segments.len();
    let side_name = |k: usize| -> &str { side_of_segment[k].map_or("", |i| sides[i].0) };
    let corner_fields = block.named("corner");
    let mut corner_names = Vec::new();
    for (k, segment) in top.segments.iter().enumerate() {
        let curve = top.segment_curve(k).map_err(|e| {
            feature_error(
                KIND,
                format!("this top-view segment cannot be used: {e}"),
                segment.span,
                "this segment",
                "check the sketch",
            )
        })?;
        match side_of_segment[k] {
            Some(i) => {
                let (name, field) = sides[i];
                pieces.push(PieceSpec::Side(SideSpec {
                    name: name.to_string(),
                    top: curve,
                    view: side_view(&field.value)?,
                }));
                sources.push(PieceSource {
                    segment: segment.span,
                    field: Some(field.value.span),
                });
            }
            None => {
                let name = format!("{}_{}", side_name((k + n - 1) % n), side_name((k + 1) % n));
                let own = corner_fields.iter().find(|(c, _)| *c == name);
                let (mags, span) = match own {
                    Some((_, f)) => {
                        let t = match &f.value.data {
                            Data::Record(r) => {
                                check_record(
                                    r,
                                    f.value.span,
                                    &format!("`corner {name}`"),
                                    &["tangent"],
                                )?;
                                r.get("tangent").cloned().ok_or_else(|| {
                                    feature_error(KIND, format!("`corner {name}` gives no `tangent`"), f.value.span, "this block", "write `corner NAME { tangent = 120 mm }` or a ratio such as `90 %`")
                                })?
                            }
                            _ => f.value.clone(),
                        };
                        (magnitudes(&t, units)?, Some(t.span))
                    }
                    None => (
                        default_tangent.unwrap_or([Magnitude::Natural(1.0); 2]),
                        block.get("corners").map(|f| f.value.span),
                    ),
                };
                corner_names.push(name.clone());
                pieces.push(PieceSpec::Corner(CornerSpec {
                    name,
                    top: curve,
                    magnitudes: mags,
                }));
                sources.push(PieceSource {
                    segment: segment.span,
                    field: span,
                });
            }
        }
    }
    for (name, f) in &corner_fields {
        if !corner_names.iter().any(|c| c == name) {
            let d = feature_error(
                KIND,
                format!("the opening has no corner `{name}`"),
                f.name_span,
                "no such corner",
                "",
            );
            return Err(match did_you_mean(name, corner_names.iter().map(String::as_str)) {
                Some(g) => d.with_help(format!("did you mean `{g}`? Corners are named after their sides, `<previous>_<next>`: {}", corner_names.join(", "))),
                None => d.with_help(format!("corners are named after their sides, `<previous>_<next>`: {}", corner_names.join(", "))),
            });
        }
        if sides.iter().any(|(s, _)| s == name) {
            return Err(feature_error(
                KIND,
                format!("`{name}` names both a side and a corner"),
                f.name_span,
                "this corner",
                "rename the side",
            ));
        }
    }
    for name in &corner_names {
        if let Some((_, f)) = sides.iter().find(|(s, _)| s == name) {
            return Err(feature_error(
                KIND,
                format!("the side `{name}` has the name of a corner"),
                f.name_span,
                "this side",
                "corners are named `<previous>_<next>`; choose another side name",
            ));
        }
    }

    let spec = PunchOpeningSpec {
        pieces,
        delta,
        max_step,
    };
    let opening = po::build(&spec).map_err(|e| build_error(block, &spec, &sources, e))?;
    Ok(output(block, opening))
}

/// The `top` value: a closed sketch in the top view.
fn top_sketch(v: &Value) -> Result<Arc<Sketch>, Diagnostic> {
    let Data::Sketch(s) = &v.data else {
        return Err(super::super::builtins::type_error(
            v,
            "`top` of a punch opening",
            "a closed sketch in the top view",
        ));
    };
    if s.view != View::Top {
        return Err(feature_error(
            KIND,
            format!(
                "`top` must be drawn in the top view, but this sketch is in the {} view",
                s.view.name()
            ),
            v.span,
            "not a top-view sketch",
            "draw the opening with `sketch(top) { ... }`",
        ));
    }
    if !s.closed {
        let (a, b) = (s.curve.start_point(), s.curve.end_point());
        return Err(feature_error(
            KIND,
            "the top-view profile of a punch opening must be closed",
            v.span,
            format!(
                "this profile ends at ({:.1}, {:.1}), {:.1} mm from its start",
                b.x,
                b.y,
                a.distance(b)
            ),
            "end the sketch with `close` (add `fillet R` before it to round the last corner)",
        ));
    }
    Ok(s.clone())
}

/// A side's view: a sketch in `side_xz`, `side_yz` or a section plane.
fn side_view(v: &Value) -> Result<SideView, Diagnostic> {
    let Data::Sketch(s) = &v.data else {
        return Err(super::super::builtins::type_error(
            v,
            "a `side` of a punch opening",
            "a side-view sketch (`sketch(side_xz)`, `sketch(side_yz)` or `sketch(section(a, b))`)",
        ));
    };
    let (origin, axis) = match s.view {
        View::SideXZ => (DVec2::ZERO, DVec2::X),
        View::SideYZ => (DVec2::ZERO, DVec2::Y),
        View::Section { a, b } => (a, (b - a).normalize_or_zero()),
        View::Top => {
            return Err(feature_error(KIND, "a side's binder wrap is drawn in a side view, but this sketch is in the top view", v.span, "a top-view sketch", "draw it with `sketch(side_xz)` for sides along X, `sketch(side_yz)` for sides along Y, or `sketch(section(a, b))`"));
        }
    };
    Ok(SideView {
        origin,
        axis,
        curve: s.curve.clone(),
    })
}

/// A tangent spec: a magnitude, or a pair for start and end.
fn magnitudes(v: &Value, units: super::super::units::Units) -> Result<[Magnitude; 2], Diagnostic> {
    match &v.data {
        Data::Tuple(items) if items.len() == 2 => {
            Ok([magnitude(&items[0], units)?, magnitude(&items[1], units)?])
        }
        _ => {
            let m = magnitude(v, units)?;
            Ok([m, m])
        }
    }
}

fn magnitude(v: &Value, units: super::super::units::Units) -> Result<Magnitude, Diagnostic> {
    let (m, value) = match &v.data {
        Data::Number(q) if q.dim == Dim::LENGTH => (Magnitude::Length(q.value), q.value),
        Data::Number(q) if q.dim.is_none() && !q.bare => (Magnitude::Natural(q.value), q.value),
        Data::Number(q) if q.dim.is_none() => {
            // A bare number is a factor of the natural magnitude, not a length: `1.2`.
            let _ = units;
            (Magnitude::Natural(q.value), q.value)
        }
        _ => {
            return Err(super::super::builtins::type_error(
                v,
                "a corner tangent",
                "a length such as `120 mm`, a ratio such as `90 %`, or a pair of them",
            ));
        }
    };
    if !(value.is_finite() && value > 0.0) {
        return Err(feature_error(KIND, "a corner's tangent magnitude must be positive", v.span, format!("this magnitude is {value}"), "a magnitude near the corner's length gives a round corner: try `100 %`, or a length such as `120 mm`"));
    }
    Ok(m)
}

fn side_count_error(
    block: &Block,
    top: &Sketch,
    top_value: &Value,
    side_segments: &[usize],
    sides: &[(&str, &super::Field)],
) -> Diagnostic {
    if sides.len() < side_segments.len() {
        let missing = top.segments[side_segments[sides.len()]].span;
        feature_error(
            KIND,
            format!("the top view has {} sides but the block gives {} `side` fields", side_segments.len(), sides.len()),
            missing,
            "this side of the top view has no side view",
            "add `side NAME = sketch(side_xz) { ... }` for every side, in the order the top view draws them (every segment that is not a `fillet` is a side)",
        )
        .with_label(top_value.span, "the top view")
        .with_label(block.span, "in this punch opening")
    } else {
        let extra = sides[side_segments.len()].1;
        feature_error(
            KIND,
            format!(
                "the top view has {} sides but the block gives {} `side` fields",
                side_segments.len(),
                sides.len()
            ),
            extra.name_span,
            "no side of the top view is left for this one",
            "give one `side` per top-view segment that is not a `fillet`, in drawing order",
        )
        .with_label(top_value.span, "the top view")
    }
}

fn build_error(
    block: &Block,
    spec: &PunchOpeningSpec,
    sources: &[PieceSource],
    e: po::Error,
) -> Diagnostic {
    let names = po::piece_names(spec);
    let name = names.get(e.piece).copied().unwrap_or("?");
    let source = sources.get(e.piece);
    let segment = source.map_or(block.span, |s| s.segment);
    let field = source.and_then(|s| s.field).unwrap_or(segment);
    let is_side = matches!(spec.pieces.get(e.piece), Some(PieceSpec::Side(_)));
    let what = if is_side { "side" } else { "corner" };
    let d = match &e.problem {
        po::Problem::Kernel(GeomError::ViewsDoNotOverlap { top, side }) => feature_error(
            KIND,
            format!("the side view of `{name}` does not cover the side's range along its axis: the side runs from {:.1} to {:.1}, the view from {:.1} to {:.1}", top.0, top.1, side.0.min(side.1), side.0.max(side.1)),
            field,
            "this side view is too short",
            "extend the side view's curve past both ends of the side (the two-view method reads the height at every point of the side)",
        ),
        po::Problem::Kernel(GeomError::Singular { what: why }) if why.contains("top view") => feature_error(
            KIND,
            format!("the side `{name}` cannot be built from its views: {why}"),
            segment,
            "this top-view side",
            "a side must advance along its side view's axis: draw sides running along X in `side_xz`, sides along Y in `side_yz`, slanted ones in `section(a, b)` along them",
        ),
        po::Problem::Kernel(GeomError::Singular { what: why }) => feature_error(
            KIND,
            format!("the side `{name}` cannot be built from its views: {why}"),
            field,
            "this side view",
            "the side view must be a graph over its axis: one height per position",
        ),
        po::Problem::Kernel(GeomError::NotPositive { what: w, value }) if w.contains("magnitude") => feature_error(
            KIND,
            format!("the corner `{name}` has a tangent magnitude that is not positive ({value})"),
            field,
            "this magnitude",
            "give a positive length or ratio",
        ),
        po::Problem::SharpJoin { angle_deg } => feature_error(
            KIND,
            format!("the sides before and at `{name}` meet at {angle_deg:.2} deg without a corner"),
            segment,
            "this side starts at a kink",
            "put a `fillet R` between the two segments in the top view, or draw the second one `tangent`",
        ),
        po::Problem::SidesDisagree { gap } => feature_error(
            KIND,
            format!("`{name}` and the side before it meet without a corner, but their side views put the shared point {gap:.4} mm apart"),
            field,
            "this side view",
            format!("make both side views give the same height at the shared point (within delta = {} mm), or put a fillet between them", spec.delta),
        ),
        po::Problem::NoSides => feature_error(
            KIND,
            "the top view has no side: every segment is a fillet",
            block.span,
            "this punch opening",
            "draw the sides as lines or splines, joined by `fillet R`",
        ),
        po::Problem::CornerAfterCorner => feature_error(
            KIND,
            format!("the corner `{name}` follows another corner"),
            segment,
            "two fillets in a row",
            "put a side between the two fillets",
        ),
        po::Problem::Kernel(err) => feature_error(
            KIND,
            format!("the {what} `{name}` cannot be built: {err} (in `{}`)", block.name),
            field,
            format!("this {what}"),
            "check the views and tangents of this piece for degenerate input",
        ),
    };
    if field != segment {
        d.with_label(segment, format!("the {what} `{name}` in the top view"))
    } else {
        d
    }
}

/// The feature record: one 3-D curve per piece, the closed `line`, and `quality`.
fn output(block: &Block, opening: po::PunchOpening) -> Value {
    let span = block.span;
    let mut fields: Vec<(String, Value)> = opening
        .pieces
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                Value::new(Data::Curve3(Arc::new(p.curve.clone())), span),
            )
        })
        .collect();
    fields.push((
        "line".into(),
        Value::new(Data::Curve3(Arc::new(opening.line.clone())), span),
    ));
    let (mut top, mut side, mut angle, mut magnitude) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut per_piece = Vec::new();
    for (piece, q) in opening.pieces.iter().zip(&opening.quality) {
        let figures = match q {
            PieceQuality::Side(s) => {
                top = top.max(s.top_deviation);
                side = side.max(s.side_deviation);
                vec![
                    ("top_deviation".to_string(), mm(s.top_deviation, span)),
                    ("side_deviation".to_string(), mm(s.side_deviation, span)),
                    ("points".to_string(), count(s.points, span)),
                ]
            }
            PieceQuality::Corner(c) => {
                angle = angle.max(c.angle_in).max(c.angle_out);
                magnitude = magnitude
                    .max((c.actual.0 - c.asked.0).abs())
                    .max((c.actual.1 - c.asked.1).abs());
                vec![
                    ("angle_in".to_string(), deg(c.angle_in, span)),
                    ("angle_out".to_string(), deg(c.angle_out, span)),
                    ("tangent_in".to_string(), mm(c.actual.0, span)),
                    ("tangent_out".to_string(), mm(c.actual.1, span)),
                    ("top_deviation".to_string(), mm(c.top_deviation, span)),
                ]
            }
        };
        per_piece.push((piece.name.clone(), record_value(figures, span)));
    }
    let mut quality = vec![
        ("delta".to_string(), mm(opening.delta, span)),
        ("top_deviation".to_string(), mm(top, span)),
        ("side_deviation".to_string(), mm(side, span)),
        ("corner_angle".to_string(), deg(angle, span)),
        ("corner_tangent_error".to_string(), mm(magnitude, span)),
    ];
    quality.extend(per_piece);
    fields.push(("quality".into(), record_value(quality, span)));
    Value::new(
        Data::Record(Arc::new(Record {
            kind: Some(KIND.to_string()),
            fields,
            feature: Some(Feature::PunchOpening(Arc::new(opening))),
        })),
        span,
    )
}
