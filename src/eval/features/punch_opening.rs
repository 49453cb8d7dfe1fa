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
    self as po, CornerSpec, Magnitude, PieceKind, PieceQuality, PieceSpec, PunchOpening,
    PunchOpeningSpec, SideSpec, SideView,
};
use crate::geom::GeomError;
use crate::syntax::Span;

use super::super::sketch::{Sketch, View};
use super::super::summary::{bbox, bounds, round, sampled_curve};
use super::super::value::{Data, Dim, Record, Value};
use super::explain::{diagnostic, Blame, Explanation};
use super::kind::{FeatureKind, FieldNames};
use super::{
    check_record, count, deg, feature_error, feature_value, length, mm, ordinal, record,
    record_value, show, show_value, Block,
};

/// The finest tolerance `delta` (mm): finer ones multiply the points of every side and
/// corner past what the kernel's interpolation can hold.
const MIN_DELTA: f64 = 0.001;

/// The most two-view steps `max_step` may ask of one side: the side's points are
/// interpolated all at once.
const MAX_STEPS_PER_SIDE: f64 = 1000.0;

/// Where each piece came from, for diagnostics.
struct PieceSource {
    /// The piece's top-view segment.
    segment: Span,
    /// The `side` field's value, or the corner's tangent value if one was given.
    field: Option<Span>,
    /// For a side: its view's first and last segments, with the view's coordinate along
    /// the axis at the start and the end of the drawing.
    view_ends: Option<ViewEnds>,
}

/// The two drawn ends of a side view.
#[derive(Clone, Copy)]
struct ViewEnds {
    first: Span,
    last: Span,
    start: f64,
    end: f64,
}

/// Builds the punch opening of `block`.
fn build(block: &Block) -> Result<Value, Diagnostic> {
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
            format!(
                "the tolerance `delta` must be a positive length, but it is {} mm",
                show(delta)
            ),
            span,
            "this tolerance",
            "die-face practice is 0.01 mm",
        ));
    }
    if delta < MIN_DELTA {
        let span = block.get("delta").map_or(block.span, |f| f.value.span);
        return Err(feature_error(
            KIND,
            format!(
                "the tolerance `delta` must be at least {MIN_DELTA} mm, but it is {delta:e} mm"
            ),
            span,
            "too fine a tolerance",
            format!("a finer tolerance multiplies the points of every side and corner without making the die any better: use at least {MIN_DELTA} mm (die-face practice is 0.01 mm)"),
        ));
    }
    let max_step = match block.get("max_step") {
        Some(f) => {
            let m = length(&f.value, units, "`max_step`")?;
            if !(m.is_finite() && m > 0.0) {
                return Err(feature_error(
                    KIND,
                    format!(
                        "`max_step` must be a positive length, but it is {} mm",
                        show(m)
                    ),
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
            &top,
            &top_field.value,
            &side_segments,
            &sides,
        ));
    }
    if let (Some(m), Some(f)) = (max_step, block.get("max_step")) {
        // The longest side, for the number of steps `max_step` asks of it.
        let longest = side_segments
            .iter()
            .zip(&sides)
            .filter_map(|(&k, (name, _))| Some((top.segment_curve(k).ok()?.length(), *name)))
            .reduce(|a, b| if b.0 > a.0 { b } else { a });
        if let Some((len, name)) = longest {
            if len / m > MAX_STEPS_PER_SIDE {
                return Err(feature_error(
                    KIND,
                    format!(
                        "`max_step` = {} mm would cut the side `{name}` ({len:.1} mm long) into {:.0} steps",
                        show(m),
                        (len / m).ceil()
                    ),
                    f.value.span,
                    "too short a step",
                    format!(
                        "a side's points are interpolated all at once, so keep to {MAX_STEPS_PER_SIDE} steps per side: `max_step` of at least {} mm here (die-face practice is 20 to 50 mm)",
                        show((len / MAX_STEPS_PER_SIDE * 100.0).ceil() / 100.0)
                    ),
                ));
            }
        }
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
                Some(t) => Some(magnitudes(t, units, "of every corner (`corners`)")?),
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
                let (view, ends) = side_view(&field.value, name)?;
                pieces.push(PieceSpec::Side(SideSpec {
                    name: name.to_string(),
                    top: curve,
                    view,
                }));
                sources.push(PieceSource {
                    segment: segment.span,
                    field: Some(field.value.span),
                    view_ends: ends,
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
                        (
                            magnitudes(&t, units, &format!("of the corner `{name}`"))?,
                            Some(t.span),
                        )
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
                    view_ends: None,
                });
            }
        }
    }
    for (name, f) in &corner_fields {
        if !corner_names.iter().any(|c| c == name) {
            let d = feature_error(
                KIND,
                format!("the punch opening has no corner `{name}`"),
                f.name_word(),
                "no such corner",
                "",
            );
            // A corner named with its sides the wrong way round: `right_front`.
            let swapped = corner_names.iter().find(|c| {
                sides.iter().any(|(a, _)| {
                    sides.iter().any(|(b, _)| {
                        c.as_str() == format!("{a}_{b}") && name == &format!("{b}_{a}")
                    })
                })
            });
            let all = corner_names.join(", ");
            return Err(match swapped {
                Some(g) => d.with_help(format!("did you mean `{g}`? A corner is named after its sides in drawing order, `<previous>_<next>`; the corners are: {all}")),
                None => match did_you_mean(name, corner_names.iter().map(String::as_str)) {
                    Some(g) => d.with_help(format!("did you mean `{g}`? Corners are named after their sides in drawing order, `<previous>_<next>`: {all}")),
                    None => d.with_help(format!("corners are named after their sides in drawing order, `<previous>_<next>`: {all}")),
                },
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
    let opening = po::build_with(&spec, &block.pieces).map_err(|e| {
        diagnostic(KIND, block, explain(block.name, &spec, &e), |p| {
            resolve(&sources, p)
        })
    })?;
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
        let gap = format!(
            "ends at ({:.1}, {:.1}), {:.1} mm from its start",
            b.x,
            b.y,
            a.distance(b)
        );
        let d = match s.segments.last() {
            Some(last) => feature_error(
                KIND,
                "the top-view profile of a punch opening must be closed",
                last.span,
                format!("the profile {gap}"),
                "end the sketch with `close` (add `fillet R` before it to round the last corner)",
            )
            .with_label(v.span, "the top view of this punch opening"),
            None => feature_error(
                KIND,
                "the top-view profile of a punch opening must be closed",
                v.span,
                format!("this profile {gap}"),
                "end the sketch with `close` (add `fillet R` before it to round the last corner)",
            ),
        };
        return Err(d);
    }
    Ok(s.clone())
}

/// A side's view: a sketch in `side_xz`, `side_yz` or a section plane, with its drawn
/// ends.
fn side_view(v: &Value, name: &str) -> Result<(SideView, Option<ViewEnds>), Diagnostic> {
    let Data::Sketch(s) = &v.data else {
        return Err(super::super::builtins::type_error(
            v,
            &format!("`side {name}` of a punch opening"),
            "a side-view sketch (`sketch(side_xz)`, `sketch(side_yz)` or `sketch(section(a, b))`)",
        ));
    };
    let (origin, axis) = match s.view {
        View::SideXZ => (DVec2::ZERO, DVec2::X),
        View::SideYZ => (DVec2::ZERO, DVec2::Y),
        View::Section { a, b } => (a, (b - a).normalize_or_zero()),
        View::Top => {
            return Err(feature_error(
                KIND,
                format!("the binder wrap of the side `{name}` must be drawn in a side view, but this sketch is in the top view"),
                v.span,
                "a top-view sketch",
                "draw it with `sketch(side_xz)` for a side along X, `sketch(side_yz)` for a side along Y, or `sketch(section(a, b))` for a slanted one",
            ));
        }
        View::Profile => {
            return Err(feature_error(
                KIND,
                format!("the binder wrap of the side `{name}` must be drawn in a side view, but this sketch is a section profile (`profile`), which has no place in the press until a feature puts it there"),
                v.span,
                "a `profile` sketch",
                "draw it with `sketch(side_xz)` for a side along X, `sketch(side_yz)` for a side along Y, or `sketch(section(a, b))` for a slanted one",
            ));
        }
    };
    let ends = match (s.segments.first(), s.segments.last()) {
        (Some(first), Some(last)) => Some(ViewEnds {
            first: first.span,
            last: last.span,
            start: s.curve.start_point().x,
            end: s.curve.end_point().x,
        }),
        _ => None,
    };
    Ok((
        SideView {
            origin,
            axis,
            curve: s.curve.clone(),
        },
        ends,
    ))
}

/// The largest bare tangent factor taken as written: a corner's natural magnitude times
/// more than this loops, so a bigger bare number is a percentage without its `%`.
const MAX_BARE_FACTOR: f64 = 5.0;

/// A tangent spec: a magnitude, or a pair for start and end. `whose` completes "the
/// tangent magnitude ..." (`of the corner `front_nose``).
fn magnitudes(
    v: &Value,
    units: super::super::units::Units,
    whose: &str,
) -> Result<[Magnitude; 2], Diagnostic> {
    match &v.data {
        Data::Tuple(items) if items.len() == 2 => Ok([
            magnitude(&items[0], units, whose)?,
            magnitude(&items[1], units, whose)?,
        ]),
        _ => {
            let m = magnitude(v, units, whose)?;
            Ok([m, m])
        }
    }
}

fn magnitude(
    v: &Value,
    units: super::super::units::Units,
    whose: &str,
) -> Result<Magnitude, Diagnostic> {
    let (m, value) = match &v.data {
        Data::Number(q) if q.dim == Dim::LENGTH => (Magnitude::Length(q.value), q.value),
        Data::Number(q) if q.dim.is_none() && !q.bare => (Magnitude::Natural(q.value), q.value),
        Data::Number(q) if q.dim.is_none() => {
            // A bare number is a factor of the natural magnitude, not a length: `1.2`.
            // One far above any sensible factor is a percentage written without `%`.
            let _ = units;
            if q.value > MAX_BARE_FACTOR {
                return Err(feature_error(
                    KIND,
                    format!(
                        "the tangent magnitude {whose} is {}: a bare number is a factor of the corner's natural magnitude, so this would make it {} times as long",
                        show_value(v),
                        show(q.value)
                    ),
                    v.span,
                    "a bare factor",
                    format!(
                        "a bare number is a factor here (`1` is `100 %`): did you mean `{0} %`, or a length such as `{0} mm`?",
                        show(q.value)
                    ),
                ));
            }
            (Magnitude::Natural(q.value), q.value)
        }
        _ => {
            return Err(super::super::builtins::type_error(
                v,
                &format!("the tangent magnitude {whose}"),
                "a length such as `120 mm`, a ratio such as `90 %`, or a pair of them",
            ));
        }
    };
    if !(value.is_finite() && value > 0.0) {
        return Err(feature_error(
            KIND,
            format!(
                "the tangent magnitude {whose} must be positive, but it is {}",
                show_value(v)
            ),
            v.span,
            "not a positive magnitude",
            "a corner cannot be sharp or turn back on itself: `100 %` gives a circle-like corner, a smaller ratio such as `80 %` a tauter one, or give a length such as `120 mm`; for a tighter corner draw a smaller fillet in the top view",
        ));
    }
    Ok(m)
}

fn side_count_error(
    top: &Sketch,
    top_value: &Value,
    side_segments: &[usize],
    sides: &[(&str, &super::Field)],
) -> Diagnostic {
    let (want, given) = (side_segments.len(), sides.len());
    if given < want {
        let missing = top.segments[side_segments[given]].span;
        let (message, after) = match sides.last() {
            Some((last, _)) => (
                format!("the top view has {want} sides but only {given} `side` views are given"),
                format!(" after `side {last}`"),
            ),
            None => (
                format!("the top view has {want} sides but no `side` view is given"),
                String::new(),
            ),
        };
        let mut d = feature_error(
            KIND,
            message,
            missing,
            format!("the {} side has no side view", ordinal(given + 1)),
            format!("the `side` fields take the top view's sides in drawing order (every segment that is not a `fillet` is a side): add `side NAME = sketch(side_xz) {{ ... }}`{after} for this one"),
        )
        .with_label(top_value.span, "the top view");
        if let Some((last, f)) = sides.last() {
            d = d.with_label(
                f.name_span,
                format!("`{last}` takes the {} side", ordinal(given)),
            );
        }
        d
    } else {
        let (extra, f) = sides[want];
        feature_error(
            KIND,
            format!("the top view has {want} sides but {given} `side` views are given"),
            f.name_span,
            format!("no side of the top view is left for `{extra}`"),
            "the `side` fields take the top view's sides in drawing order, one per segment that is not a `fillet`: remove this field, or draw the missing side in the top view",
        )
        .with_label(top_value.span, "the top view")
    }
}

/// A position along a side view's axis, as a designer reads it: `x = 200.0`.
fn along(view: &SideView, v: f64) -> String {
    if view.axis == DVec2::X {
        format!("x = {v:.1}")
    } else if view.axis == DVec2::Y {
        format!("y = {v:.1}")
    } else {
        format!("{v:.1} mm along the section")
    }
}

/// A range along a side view's axis: `x = -320.0 to 320.0`.
fn range(view: &SideView, a: f64, b: f64) -> String {
    if view.axis == DVec2::X {
        format!("x = {a:.1} to {b:.1}")
    } else if view.axis == DVec2::Y {
        format!("y = {a:.1} to {b:.1}")
    } else {
        format!("{a:.1} to {b:.1} mm along the section")
    }
}

/// The view a side view is drawn in, in words: "`side_xz` (along X)".
fn view_words(view: &SideView) -> String {
    if view.axis == DVec2::X {
        "`side_xz` (along X)".to_string()
    } else if view.axis == DVec2::Y {
        "`side_yz` (along Y)".to_string()
    } else {
        format!("a section along ({:.2}, {:.2})", view.axis.x, view.axis.y)
    }
}

/// Which way a top-view chord runs, in words, with the view to draw it in.
fn runs(chord: DVec2) -> (String, &'static str) {
    let angle = chord.y.atan2(chord.x).to_degrees().rem_euclid(180.0);
    if !(1.0..=179.0).contains(&angle) {
        ("along X".to_string(), "`sketch(side_xz)`")
    } else if (angle - 90.0).abs() < 1.0 {
        ("along Y".to_string(), "`sketch(side_yz)`")
    } else {
        let to_x = angle.min(180.0 - angle);
        (
            format!("at {to_x:.0} deg to X"),
            "`sketch(section(a, b))` with `a` and `b` at its ends",
        )
    }
}

/// The parts of a punch-opening block a problem is blamed on, by piece index.
enum Part {
    /// The piece's segment of the top view.
    Segment(usize),
    /// The piece's own field (a side's view, a corner's tangent), else its segment.
    Field(usize),
    /// The drawn end of a side's view at the low or the high end of its axis.
    ViewEnd { piece: usize, high: bool },
}

/// Where the part of the block `part` was written.
fn resolve(sources: &[PieceSource], part: &Part) -> Option<Span> {
    match *part {
        Part::Segment(k) => sources.get(k).map(|s| s.segment),
        Part::Field(k) => sources.get(k).map(|s| s.field.unwrap_or(s.segment)),
        Part::ViewEnd { piece, high } => {
            let ends = sources.get(piece)?.view_ends?;
            let (lo, hi) = if ends.start <= ends.end {
                (ends.first, ends.last)
            } else {
                (ends.last, ends.first)
            };
            Some(if high { hi } else { lo })
        }
    }
}

/// What the designer reads about the kernel's error `e` in the punch opening `name`,
/// built from `spec`.
fn explain(name_of_block: &str, spec: &PunchOpeningSpec, e: &po::Error) -> Explanation<Part> {
    let names = po::piece_names(spec);
    let n = names.len().max(1);
    let k = e.piece;
    let name = names.get(k).copied().unwrap_or("?");
    let before = (k + n - 1) % n;
    let prev = names.get(before).copied().unwrap_or("?");
    let side = match spec.pieces.get(k) {
        Some(PieceSpec::Side(s)) => Some(s),
        _ => None,
    };
    let what = if side.is_some() { "side" } else { "corner" };
    match &e.problem {
        po::Problem::Kernel(GeomError::ViewsDoNotOverlap { top, side: drawn }) => {
            let (t0, t1) = (top.0.min(top.1), top.0.max(top.1));
            let (v0, v1) = (drawn.0.min(drawn.1), drawn.0.max(drawn.1));
            let (range_top, range_view, at_lo, at_hi) = match side {
                Some(s) => (
                    range(&s.view, t0, t1),
                    range(&s.view, v0, v1),
                    along(&s.view, v0),
                    along(&s.view, v1),
                ),
                None => (
                    format!("{t0:.1} to {t1:.1}"),
                    format!("{v0:.1} to {v1:.1}"),
                    format!("{v0:.1}"),
                    format!("{v1:.1}"),
                ),
            };
            let mut x = Explanation::new(
                format!("the side view of `{name}` does not reach past both ends of the side: the side runs from {range_top}, its view only from {range_view}"),
                Part::Field(k),
                "this side view is too short",
                "extend the side view past both ends of the side: the side's height is read from it at every point of the side (drawing it as long as the whole edge of the opening is enough)",
            );
            let tol = 1e-6 * (1.0 + t0.abs().max(t1.abs()));
            if v1 < t1 - tol {
                x = x.also(Part::ViewEnd { piece: k, high: true }, format!("the view ends at {at_hi}"));
            }
            if v0 > t0 + tol {
                x = x.also(Part::ViewEnd { piece: k, high: false }, format!("the view starts at {at_lo}"));
            }
            x.also(Part::Segment(k), format!("the side `{name}` runs from {range_top}"))
        }
        po::Problem::Kernel(GeomError::Singular { what: why }) if why.contains("top view") => {
            let across = side.and_then(|s| {
                let c = s.top.end_point() - s.top.start_point();
                (c.dot(s.view.axis).abs() < c.dot(s.view.axis.perp()).abs()).then_some((s, c))
            });
            match across {
                Some((s, c)) => {
                    let (way, fix) = runs(c);
                    let drawn = view_words(&s.view);
                    Explanation::new(
                        format!("the side `{name}` runs {way} in the top view, but its side view is drawn in {drawn}"),
                        Part::Field(k),
                        format!("drawn in {drawn}"),
                        format!("the side's height is read from its side view along the view's axis, so the side must advance along that axis: draw the binder wrap of `{name}` in {fix}"),
                    )
                    .also(Part::Segment(k), format!("`{name}` runs {way} in the top view"))
                }
                None => Explanation::new(
                    format!("the side `{name}` cannot be built from its views: {why}"),
                    Part::Segment(k),
                    "this top-view side",
                    "a side must advance steadily along its side view's axis: draw sides running along X in `side_xz`, sides along Y in `side_yz`, slanted ones in `section(a, b)` along them, and split a side that turns back with a fillet",
                )
                .also(Part::Field(k), format!("the side view of `{name}`")),
            }
        }
        po::Problem::Kernel(GeomError::Singular { what: why }) => Explanation::new(
            format!("the side `{name}` cannot be built from its views: {why}"),
            Part::Field(k),
            "this side view",
            "the side view must be a graph over its axis: one height per position, never turning back or standing vertical",
        )
        .also(Part::Segment(k), format!("the side `{name}` in the top view")),
        po::Problem::Kernel(GeomError::NotPositive { what: w, value }) if w.contains("magnitude") => {
            Explanation::new(
                format!("the tangent magnitude of the corner `{name}` must be positive, but it comes to {} mm", show(*value)),
                Part::Field(k),
                "this magnitude",
                "give a positive length such as `120 mm` or a ratio such as `100 %`",
            )
            .also(Part::Segment(k), format!("the corner `{name}` in the top view"))
        }
        po::Problem::SharpJoin { angle_deg } => Explanation::new(
            format!("the sides `{prev}` and `{name}` meet at a {angle_deg:.2} deg kink in the top view, with no corner between them"),
            Part::Segment(k),
            format!("`{name}` starts at a kink"),
            format!("put a `fillet R` between the two segments in the top view (it becomes a corner), or draw `{name}` on from `{prev}` without a kink (`tangent arc to ...`, `spline tangent through [...]`); sides may meet without a corner only where they turn by less than {} deg", po::MAX_SIDE_JOIN_ANGLE_DEG),
        )
        .also(Part::Segment(before), format!("`{prev}` ends here")),
        po::Problem::SidesDisagree { gap } => Explanation::new(
            format!("the sides `{prev}` and `{name}` meet without a corner, but their side views put the shared point {gap:.3} mm apart"),
            Part::Field(k),
            format!("the side view of `{name}`"),
            format!("make both side views give the same height where the sides meet (within delta = {} mm), or put a fillet between them in the top view", show(spec.delta)),
        )
        .also(Part::Field(before), format!("the side view of `{prev}`"))
        .also(Part::Segment(k), format!("`{name}` starts where `{prev}` ends, without a corner")),
        po::Problem::OffItsView {
            view,
            deviation,
            bound,
        } => Explanation::new(
            format!(
                "the side `{name}` could not be built as drawn: it strays {} mm from its {view} (at most {} mm, ten times delta)",
                show(*deviation),
                show(*bound)
            ),
            Part::Field(k),
            format!("the side view of `{name}`"),
            "a side follows its top view and its side view together, step by step; where the side view climbs far more steeply than the top view can carry (a spline driven through an extreme point, say), the steps lose it. Keep the side view's heights and slopes within what the die can be (a smooth graph over its axis, a few degrees to a few tens of degrees)",
        )
        .also(Part::Segment(k), format!("the side `{name}` in the top view")),
        po::Problem::NoSides => Explanation::new(
            "the top view has no side: every segment is a fillet",
            Blame::Block,
            "this punch opening",
            "draw the sides as lines or splines, joined by `fillet R`",
        ),
        po::Problem::CrossesItself { other, at } => {
            let other_name = names.get(*other).copied().unwrap_or("?");
            let place = format!("({}, {})", show(at.x), show(at.y));
            let message = if *other == k {
                format!("the top view of `{name_of_block}` crosses itself at {place}: the {what} `{name}` runs over itself")
            } else {
                format!("the top view of `{name_of_block}` crosses itself at {place}: `{name}` meets `{other_name}`")
            };
            Explanation::new(
                message,
                Part::Segment(k),
                format!("`{name}` crosses here"),
                "a punch opening is one simple closed outline seen from above: move the points so the sketch goes round once without crossing or touching itself (a figure of eight is two openings)",
            )
            .also(Part::Segment(*other), format!("`{other_name}` is crossed at {place}"))
        }
        po::Problem::CornerAfterCorner => Explanation::new(
            format!("the corner `{name}` follows another corner"),
            Part::Segment(k),
            "two fillets in a row",
            "put a side between the two fillets",
        ),
        po::Problem::Kernel(err) => Explanation::new(
            format!("the {what} `{name}` of `{name_of_block}` cannot be built: {err}"),
            Part::Field(k),
            format!("this {what}"),
            if side.is_some() {
                "check this side's top view and side view for degenerate input (zero-length or self-overlapping segments)"
            } else {
                "a tangent magnitude far from the corner's size makes it loop or collapse: try a ratio near `100 %`"
            },
        )
        .also(Part::Segment(k), format!("the {what} `{name}` in the top view")),
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
    feature_value(KIND, span, fields, quality, opening)
}

/// The `punch_opening` feature kind.
pub(super) static KIND: &dyn FeatureKind = &PunchOpeningKind;

struct PunchOpeningKind;

impl FeatureKind for PunchOpeningKind {
    fn name(&self) -> &'static str {
        "punch_opening"
    }
    fn code(&self) -> &'static str {
        "die::punch_opening"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec!["top", "delta", "max_step", "corners"],
            named: vec!["side", "corner"],
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build(block)
    }
    fn color(&self) -> [f64; 3] {
        [0.85, 0.15, 0.15] // red
    }
    /// The closed `line` repeats the sides and corners: only the pieces are exported.
    fn exports_field(&self, field: &str) -> bool {
        field != "line"
    }
    fn summary(&self, record: &Record) -> String {
        let Some(p) = record.model::<PunchOpening>() else {
            return String::new();
        };
        let names = |kind: PieceKind| -> Vec<&str> {
            p.pieces
                .iter()
                .filter(|x| x.kind == kind)
                .map(|x| x.name.as_str())
                .collect()
        };
        let (lo, hi) = bounds(sampled_curve(&p.line));
        format!(
            "punch opening, sides [{}], corners [{}], closed line of {} mm, bounds {}",
            names(PieceKind::Side).join(", "),
            names(PieceKind::Corner).join(", "),
            round(p.line.length()),
            bbox(lo, hi)
        )
    }
}
