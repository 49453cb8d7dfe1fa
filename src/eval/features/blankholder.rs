//! `blankholder name { ... }`: the block's fields read into
//! [`crate::die::blankholder`]'s input, and its result into a record.
//!
//! ```text
//! blankholder binder {
//!     opening = opening             // the punch_opening it surrounds
//!     width = 180 mm                // binder width d for every side (required unless
//!                                   // every side gives its own)
//!     angle = 0 deg                 // rise theta above the horizontal (default 0)
//!     side front {                  // per side, optional; scalars or one per station
//!         at = [0, 40 %, 1]         // stations along the side (default: evenly spaced)
//!         width = [170, 200, 170]
//!         angle = 2 deg
//!         direction = (0, -1)       // top-view direction (default: out of the opening)
//!         start_tangent = (1, 0, 0) // outer-curve end directions (default: the side's)
//!     }
//!     corners { tautness = 0.5 }    // every corner (default 0: keep the opening's sag)
//!     corner front_nose { tautness = 1 }
//! }
//! ```

use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::diag::{did_you_mean, Diagnostic};
use crate::die::blankholder::{self as bh, PieceSpec, SideSpec, Station};
use crate::die::punch_opening::{PieceKind, PunchOpening};
use crate::geom::GeomError;
use crate::syntax::Span;

use super::super::builtins::{as_point2, as_point3, type_error};
use super::super::summary::patches_extent;
use super::super::value::{Data, Record, Value};
use super::explain::{diagnostic, Explanation};
use super::kind::{FeatureKind, FieldNames};
use super::{
    angle, check_record, feature_error, feature_value, items, join_figures, length, number,
    ordinal, record, show, show_value, Block,
};
use crate::die::model::DieFace;
use crate::geom::sew::{Face, Shape};

/// Default number of stations along a side when the designer gives no lists.
const DEFAULT_STATIONS: usize = 5;

/// The fields of a `side NAME { ... }` block.
const SIDE_FIELDS: &[&str] = &[
    "at",
    "width",
    "angle",
    "direction",
    "start_tangent",
    "end_tangent",
];

/// Where one side's values were written, for the kernel's diagnostics.
struct SideSpans {
    /// The side's own block, or the blankholder's `width` (its head) when it has none.
    block: Span,
    /// Per station: where its width was written.
    width: Vec<Span>,
    /// Per station: where its direction was written, if it was.
    direction: Vec<Option<Span>>,
    start_tangent: Option<Span>,
    end_tangent: Option<Span>,
}

impl SideSpans {
    /// What places the outer point of station `i`: its direction if given, else its width.
    fn station(&self, i: usize) -> Span {
        self.direction
            .get(i)
            .copied()
            .flatten()
            .or_else(|| self.width.get(i).copied())
            .unwrap_or(self.block)
    }

    fn first(&self) -> Span {
        self.station(0)
    }

    fn last(&self) -> Span {
        self.station(self.width.len().saturating_sub(1))
    }
}

/// Where each piece's values were written.
enum PieceSpans {
    Side(SideSpans),
    /// A corner's own field, or `corners`, or the block's head.
    Corner(Span),
}

/// Builds the blankholder of `block`.
fn build(block: &Block) -> Result<Value, Diagnostic> {
    let units = block.units;
    let opening_field = block.get("opening").ok_or_else(|| {
        block.missing(
            "opening",
            "name the punch opening the binder surrounds: `opening = my_opening`",
        )
    })?;
    let opening = opening_of(&opening_field.value)?;
    let default_width = match block.get("width") {
        Some(f) => {
            let w = length(&f.value, units, "`width`")?;
            check_width(w, f.value.span, "the binder `width`")?;
            Some((w, f.value.span))
        }
        None => None,
    };
    let default_angle = match block.get("angle") {
        Some(f) => {
            let a = angle(&f.value, units, "`angle`")?;
            check_angle(a, f.value.span, "the binder's rise `angle`")?;
            a
        }
        None => 0.0,
    };
    let default_tautness = match block.get("corners") {
        Some(f) => {
            let r = record(
                &f.value,
                "`corners`",
                "a block such as `corners { tautness = 0.5 }`",
            )?;
            check_record(r, f.value.span, "`corners`", &["tautness"])?;
            match r.get("tautness") {
                Some(t) => tautness(t)?,
                None => 0.0,
            }
        }
        None => 0.0,
    };

    let side_fields = block.named("side");
    let corner_fields = block.named("corner");
    let names_of = |kind: PieceKind| -> Vec<&str> {
        opening
            .pieces
            .iter()
            .filter(|p| p.kind == kind)
            .map(|p| p.name.as_str())
            .collect()
    };
    for (fields, kind, word) in [
        (&side_fields, PieceKind::Side, "side"),
        (&corner_fields, PieceKind::Corner, "corner"),
    ] {
        let known = names_of(kind);
        let other = names_of(match kind {
            PieceKind::Side => PieceKind::Corner,
            PieceKind::Corner => PieceKind::Side,
        });
        for (name, f) in fields.iter() {
            if !known.contains(name) {
                let d = feature_error(
                    KIND,
                    format!("the punch opening has no {word} `{name}`"),
                    f.name_word(),
                    format!("no such {word}"),
                    "",
                );
                let all = known.join(", ");
                return Err(if other.contains(name) {
                    let is = if word == "side" { "a corner" } else { "a side" };
                    let fix = if word == "side" { "corner" } else { "side" };
                    d.with_help(format!(
                        "`{name}` is {is} of the punch opening: write `{fix} {name}`; the {word}s are: {all}"
                    ))
                } else {
                    match did_you_mean(name, known.iter().copied()) {
                        Some(g) => {
                            d.with_help(format!("did you mean `{g}`? The {word}s are: {all}"))
                        }
                        None => d.with_help(format!("the {word}s are: {all}")),
                    }
                });
            }
        }
    }
    if default_width.is_none() {
        // Every side needs a width: its own, or the blankholder's.
        let lacking: Vec<&str> = names_of(PieceKind::Side)
            .into_iter()
            .filter(|name| {
                !side_fields.iter().any(|(n, f)| {
                    n == name
                        && matches!(&f.value.data, Data::Record(r) if r.get("width").is_some())
                })
            })
            .collect();
        if lacking.len() == names_of(PieceKind::Side).len() {
            return Err(block.missing(
                "width",
                "give the binder width for every side, `width = 180 mm`, or per side: `side NAME { width = ... }`",
            ));
        }
        if !lacking.is_empty() {
            let quoted: Vec<String> = lacking.iter().map(|n| format!("`{n}`")).collect();
            let list = match quoted.split_last() {
                Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
                _ => quoted.join(""),
            };
            return Err(Diagnostic::new(
                "die::missing_field",
                format!("the blankholder `{}` gives no width for the sides {list}", block.name),
                block.head(),
                format!("`{}` has no `width` for {list}", block.name),
            )
            .with_help(format!(
                "give a width for every side, `width = 180 mm` (a side's own `width` overrides it), or add `width = ...` to `side {} {{ ... }}`",
                lacking[0]
            )));
        }
    }

    let mut spec = Vec::with_capacity(opening.pieces.len());
    let mut written = Vec::with_capacity(opening.pieces.len());
    for piece in &opening.pieces {
        match piece.kind {
            PieceKind::Side => {
                let own = side_fields
                    .iter()
                    .find(|(n, _)| *n == piece.name)
                    .map(|(_, f)| *f);
                let (side, b) = side_spec(block, own, default_width, default_angle, &piece.name)?;
                spec.push(PieceSpec::Side(side));
                written.push(PieceSpans::Side(b));
            }
            PieceKind::Corner => {
                let own = corner_fields
                    .iter()
                    .find(|(n, _)| *n == piece.name)
                    .map(|(_, f)| *f);
                let (t, span) = match own {
                    Some(f) => {
                        let t = match &f.value.data {
                            Data::Record(r) => {
                                check_record(
                                    r,
                                    f.value.span,
                                    &format!("`corner {}`", piece.name),
                                    &["tautness"],
                                )?;
                                match r.get("tautness") {
                                    Some(t) => tautness(t)?,
                                    None => default_tautness,
                                }
                            }
                            _ => tautness(&f.value)?,
                        };
                        (t, f.value.span)
                    }
                    None => (
                        default_tautness,
                        block.get("corners").map_or(block.head(), |f| f.value.span),
                    ),
                };
                spec.push(PieceSpec::Corner { tautness: t });
                written.push(PieceSpans::Corner(span));
            }
        }
    }
    let mut binder = bh::build(&opening, &spec).map_err(|e| {
        let explanation = explain(block, &opening, &spec, &e);
        diagnostic(KIND, block, explanation, |p| resolve(&written, p))
    })?;
    if let Some(f) = block.get("max_bead_height") {
        let limit = length(&f.value, units, "`max_bead_height`")?;
        if !(limit.is_finite() && limit > 0.0) {
            return Err(feature_error(
                KIND,
                format!(
                    "the binder's `max_bead_height` must be positive, but it is {} mm",
                    show(limit)
                ),
                f.value.span,
                "not a positive height",
                "the tallest draw bead the binder takes, e.g. `20 mm` (the default is 15 mm)",
            ));
        }
        binder.max_bead_height = limit;
    }
    Ok(output(block, binder))
}

/// The punch opening a `opening` field names.
fn opening_of(v: &Value) -> Result<Arc<PunchOpening>, Diagnostic> {
    match &v.data {
        Data::Record(r) => match r.feature.as_ref().and_then(|f| f.shared::<PunchOpening>()) {
            Some(p) => Ok(p),
            _ => Err(type_error(
                v,
                "`opening` of a blankholder",
                "a punch opening (the name of a `punch_opening` declaration)",
            )),
        },
        _ => Err(type_error(
            v,
            "`opening` of a blankholder",
            "a punch opening (the name of a `punch_opening` declaration)",
        )),
    }
}

/// A tautness: a number or percentage in [0, 1].
fn tautness(v: &Value) -> Result<f64, Diagnostic> {
    let t = number(v, "a corner's `tautness`")?;
    if !(0.0..=1.0).contains(&t) {
        let bare = matches!(&v.data, Data::Number(q) if q.bare);
        let help = if bare && t > 1.0 && t <= 100.0 {
            format!("tautness is a fraction: did you mean `{} %`? 0 keeps the sag of the punch-opening corner, 1 (`100 %`) makes the outer edge straight in height", show(t))
        } else {
            "0 keeps the sag of the punch-opening corner, 1 (`100 %`) makes the outer edge straight in height; `50 %` is halfway".to_string()
        };
        return Err(feature_error(
            KIND,
            format!(
                "a corner's tautness lies between 0 and 1 (0 % and 100 %), but this is {}",
                show_value(v)
            ),
            v.span,
            "outside 0 to 1",
            help,
        ));
    }
    Ok(t)
}

/// Refuses a width that is not a positive length.
fn check_width(w: f64, span: Span, what: &str) -> Result<(), Diagnostic> {
    if w.is_finite() && w > 0.0 {
        return Ok(());
    }
    Err(feature_error(
        KIND,
        format!("{what} must be positive, but it is {} mm", show(w)),
        span,
        "not a positive width",
        "the width is the distance from the punch opening out to the binder's outer edge, e.g. `180 mm`",
    ))
}

/// Refuses a rise angle that does not lie strictly between -90 and 90 deg.
fn check_angle(a: f64, span: Span, what: &str) -> Result<(), Diagnostic> {
    if a.is_finite() && a.abs() < std::f64::consts::FRAC_PI_2 {
        return Ok(());
    }
    Err(feature_error(
        KIND,
        format!(
            "{what} must lie between -90 and 90 deg, but it is {} deg",
            show(a.to_degrees())
        ),
        span,
        "not a rise angle",
        "the angle tilts the binder up (positive) or down from the horizontal, going out from the opening; binders rise a few degrees, e.g. `angle = 3 deg`",
    ))
}

/// A top-view direction in words: `(0, -1)`.
fn show2(v: DVec2) -> String {
    format!("({}, {})", show(v.x), show(v.y))
}

/// One side's stations: its own block over the blankholder's defaults, with where each
/// value was written.
fn side_spec(
    block: &Block,
    own: Option<&super::Field>,
    default_width: Option<(f64, Span)>,
    default_angle: f64,
    name: &str,
) -> Result<(SideSpec, SideSpans), Diagnostic> {
    let units = block.units;
    let empty = Record::default();
    let default_span = default_width.map_or(block.head(), |(_, s)| s);
    let (r, span) = match own {
        Some(f) => (
            record(
                &f.value,
                &format!("`side {name}`"),
                "a block such as `side front { width = 180 mm }`",
            )?,
            f.value.span,
        ),
        None => (&empty, default_span),
    };
    let what = format!("`side {name}`");
    check_record(r, span, &what, SIDE_FIELDS)?;
    // Lists per station, in the order they decide the number of stations.
    let lists: Vec<(&str, &Value)> = ["width", "angle", "direction"]
        .iter()
        .filter_map(|k| r.get(k).map(|v| (*k, v)))
        .filter(|(_, v)| matches!(v.data, Data::List(_)))
        .collect();
    let at: Vec<f64> = match r.get("at") {
        Some(v) => stations(v, &what)?,
        None => {
            let n = lists
                .iter()
                .map(|(_, v)| items(v).len())
                .max()
                .unwrap_or(DEFAULT_STATIONS)
                .max(2);
            (0..n).map(|i| i as f64 / (n - 1) as f64).collect()
        }
    };
    let n = at.len();
    // What set the number of stations, for the diagnostics of a list of another length.
    let counted: Option<(Span, String)> = match r.get("at") {
        Some(v) => Some((v.span, format!("{n} stations"))),
        None => lists
            .iter()
            .find(|(_, v)| items(v).len() == n)
            .map(|(k, v)| (v.span, format!("{n} values of `{k}` make {n} stations"))),
    };
    let per_station = |key: &str| -> Result<Option<Vec<Value>>, Diagnostic> {
        let Some(v) = r.get(key) else { return Ok(None) };
        let list = match &v.data {
            Data::List(items) => items.to_vec(),
            _ => vec![v.clone(); n],
        };
        if list.len() != n {
            let mut d = feature_error(
                KIND,
                format!(
                    "`{key}` of {what} gives {} values for {n} stations",
                    list.len()
                ),
                v.span,
                format!("{} values", list.len()),
                format!("give one `{key}` for the whole side, or one per station (`at` places the stations)"),
            );
            if let Some((s, m)) = &counted {
                if *s != v.span {
                    d = d.with_label(*s, m.clone());
                }
            }
            return Err(d);
        }
        Ok(Some(list))
    };
    let (widths, width_spans) = match per_station("width")? {
        Some(list) => {
            let mut widths = Vec::with_capacity(n);
            for (i, v) in list.iter().enumerate() {
                let w = length(v, units, &format!("`width` of {what}"))?;
                let whose = if matches!(r.get("width").map(|w| &w.data), Some(Data::List(_))) {
                    format!(
                        "the binder width at the {} station of {what}",
                        ordinal(i + 1)
                    )
                } else {
                    format!("the `width` of {what}")
                };
                check_width(w, v.span, &whose)?;
                widths.push(w);
            }
            let spans = list.iter().map(|v| v.span).collect();
            (widths, spans)
        }
        None => match default_width {
            Some((w, s)) => (vec![w; n], vec![s; n]),
            None => {
                return Err(block.missing("width", &format!("give the binder width for every side (`width = 180 mm`) or in `side {name} {{ width = ... }}`")));
            }
        },
    };
    let angles = match per_station("angle")? {
        Some(list) => {
            let mut out = Vec::with_capacity(n);
            for v in &list {
                let a = angle(v, units, &format!("`angle` of {what}"))?;
                check_angle(a, v.span, &format!("the rise `angle` of {what}"))?;
                out.push(a);
            }
            out
        }
        None => vec![default_angle; n],
    };
    let (directions, direction_spans): (Vec<Option<DVec2>>, Vec<Option<Span>>) = match per_station(
        "direction",
    )? {
        Some(list) => {
            let mut dirs = Vec::with_capacity(n);
            for v in &list {
                let d = as_point2(v, units, &format!("`direction` of {what}"))?;
                if d.normalize_or_zero() == DVec2::ZERO {
                    return Err(feature_error(
                            KIND,
                            format!("the `direction` {} of {what} is not a direction", show2(d)),
                            v.span,
                            "no usable direction",
                            "a station's direction points from the punch opening out to the binder's outer edge, e.g. `(0, -1)`; leave it out to go straight out of the opening",
                        ));
                }
                dirs.push(Some(d));
            }
            (dirs, list.iter().map(|v| Some(v.span)).collect())
        }
        None => (vec![None; n], vec![None; n]),
    };
    let tangent = |key: &str| -> Result<Option<(DVec3, Span)>, Diagnostic> {
        let Some(v) = r.get(key) else { return Ok(None) };
        let t = as_point3(v, units, &format!("`{key}` of {what}"))?;
        if t.normalize_or_zero() == DVec3::ZERO {
            return Err(feature_error(
                KIND,
                format!(
                    "`{key}` of {what} is not a direction: it is ({}, {}, {})",
                    show(t.x),
                    show(t.y),
                    show(t.z)
                ),
                v.span,
                "no usable direction",
                "give the direction the binder's outer edge leaves in, e.g. `(1, 0, 0)`, or leave it out to follow the punch opening",
            ));
        }
        Ok(Some((t, v.span)))
    };
    let (start_tangent, end_tangent) = (tangent("start_tangent")?, tangent("end_tangent")?);
    let stations = (0..n)
        .map(|i| Station {
            at: at[i],
            width: widths[i],
            angle: angles[i],
            direction: directions[i],
        })
        .collect();
    Ok((
        SideSpec {
            stations,
            start_tangent: start_tangent.map(|(t, _)| t),
            end_tangent: end_tangent.map(|(t, _)| t),
        },
        SideSpans {
            block: span,
            width: width_spans,
            direction: direction_spans,
            start_tangent: start_tangent.map(|(_, s)| s),
            end_tangent: end_tangent.map(|(_, s)| s),
        },
    ))
}

/// The stations `at` of a side: fractions of its length from 0 to 1, increasing.
fn stations(v: &Value, what: &str) -> Result<Vec<f64>, Diagnostic> {
    let list = items(v);
    let mut out = Vec::with_capacity(list.len());
    for item in &list {
        out.push(number(item, &format!("`at` of {what}"))?);
    }
    let help = "stations are fractions of the side's length in drawing order, from 0 (its start) to 1 (its end): e.g. `at = [0, 30 %, 1]`";
    // A station written as a bare percentage (`at = [0, 30, 100]`) gets "did you mean".
    let hint = list.iter().find_map(super::percent_hint);
    let help = match &hint {
        Some(h) => format!("{h} {help}"),
        None => help.to_string(),
    };
    let bad = |span: Span, message: String, label: &str| {
        Err(feature_error(KIND, message, span, label, help.clone()))
    };
    if out.len() < 2 {
        return bad(
            v.span,
            format!(
                "the stations `at` of {what} need at least two entries, 0 and 1, but there {}",
                match out.len() {
                    0 => "are none".to_string(),
                    _ => "is one".to_string(),
                }
            ),
            "too few stations",
        );
    }
    if out[0] != 0.0 {
        return bad(
            list[0].span,
            format!(
                "the first station of {what} must be 0, the side's start, but it is {}",
                show_value(&list[0])
            ),
            "not 0",
        );
    }
    let last = out.len() - 1;
    if out[last] != 1.0 {
        return bad(
            list[last].span,
            format!(
                "the last station of {what} must be 1 (100 %), the side's end, but it is {}",
                show_value(&list[last])
            ),
            "not 1",
        );
    }
    if let Some(i) = (1..out.len()).find(|&i| out[i] <= out[i - 1]) {
        return bad(
            list[i].span,
            format!(
                "the stations of {what} must increase, but the {} ({}) does not come after the {} ({})",
                ordinal(i + 1),
                show_value(&list[i]),
                ordinal(i),
                show_value(&list[i - 1])
            ),
            "out of order",
        );
    }
    Ok(out)
}

/// The unit top-view direction out of the opening at the fraction `at` of piece `k`'s
/// length, as the kernel computes it.
fn outward_at(opening: &PunchOpening, k: usize, at: f64) -> Option<DVec2> {
    let c = &opening.pieces.get(k)?.curve;
    let t = if at <= 0.0 {
        0.0
    } else if at >= 1.0 {
        1.0
    } else {
        c.parameter_at_length(at * c.length()).ok()?
    };
    let [_, d] = c.derivatives::<2>(t);
    Some(opening.outward(d))
}

/// The parts of a blankholder block a problem is blamed on, by piece index.
enum Part {
    /// A piece's values: a side's block (the blankholder's `width` when it has none), a
    /// corner's tautness.
    Piece(usize),
    /// What places the outer point of a side's first or last station.
    End { side: usize, last: bool },
    /// The `direction` of one station of a side.
    Direction { side: usize, station: usize },
    /// Every `direction` of a side, when it gives any.
    Directions(usize),
    /// A side's `start_tangent` or `end_tangent`.
    Tangent { side: usize, end: bool },
}

/// Where the part of the block `part` was written.
fn resolve(written: &[PieceSpans], part: &Part) -> Option<Span> {
    let side = |k: usize| match written.get(k) {
        Some(PieceSpans::Side(b)) => Some(b),
        _ => None,
    };
    match *part {
        Part::Piece(k) => match written.get(k)? {
            PieceSpans::Side(b) => Some(b.block),
            PieceSpans::Corner(s) => Some(*s),
        },
        Part::End { side: k, last } => side(k).map(|b| if last { b.last() } else { b.first() }),
        Part::Direction { side: k, station } => side(k)?.direction.get(station).copied().flatten(),
        Part::Directions(k) => {
            let mut spans = side(k)?.direction.iter().flatten().copied();
            let first = spans.next()?;
            Some(spans.fold(first, |all, s| all.to(s)))
        }
        Part::Tangent { side: k, end } => {
            let b = side(k)?;
            if end {
                b.end_tangent
            } else {
                b.start_tangent
            }
        }
    }
}

/// What the designer reads about the kernel's error `e` in the blankholder of `block`
/// around `opening`, built from `spec`.
fn explain(
    block: &Block,
    opening: &PunchOpening,
    spec: &[PieceSpec],
    e: &bh::Error,
) -> Explanation<Part> {
    let n = opening.pieces.len().max(1);
    let k = e.piece;
    let name_of = |k: usize| opening.pieces.get(k).map_or("?", |p| p.name.as_str());
    let name = name_of(k);
    let (before, after) = ((k + n - 1) % n, (k + 1) % n);
    let side_of = |k: usize| match spec.get(k) {
        Some(PieceSpec::Side(s)) => Some(s),
        _ => None,
    };
    // A side the designer set apart with a block of its own.
    let own = |k: usize| {
        side_of(k).is_some() && block.named("side").iter().any(|(s, _)| *s == name_of(k))
    };
    let corner = opening.pieces.get(k).map(|p| p.kind) == Some(PieceKind::Corner);
    let what = if corner { "corner" } else { "side" };
    let (prev, next) = (name_of(before), name_of(after));
    match &e.problem {
        bh::Problem::Direction => {
            // Find the station the kernel refused, to point at its direction.
            let found = side_of(k).and_then(|s| {
                s.stations.iter().enumerate().find_map(|(i, st)| {
                    let dir = st.direction?;
                    let out = outward_at(opening, k, st.at)?;
                    let u = dir.normalize_or_zero();
                    (u == DVec2::ZERO || u.dot(out) <= 0.0).then_some((i, st.at, dir, out))
                })
            });
            match found {
                Some((i, at, dir, out)) => Explanation::new(
                    format!(
                        "the `direction` {} of `side {name}` points into the punch opening at its {} station ({} % along the side)",
                        show2(dir),
                        ordinal(i + 1),
                        show(at * 100.0)
                    ),
                    Part::Direction { side: k, station: i },
                    "into the opening",
                    format!(
                        "a station's direction points from the punch opening out to the binder's outer edge; out of the opening there is {}, and any direction less than 90 deg from it will do",
                        show2(DVec2::new((out.x * 100.0).round() / 100.0, (out.y * 100.0).round() / 100.0))
                    ),
                )
                .or(Part::Piece(k)),
                None => Explanation::new(
                    format!("a station `direction` of `side {name}` does not point out of the punch opening"),
                    Part::Piece(k),
                    format!("the side `{name}`"),
                    "a station's direction points from the punch opening out to the binder's outer edge",
                ),
            }
        }
        bh::Problem::CrossesOpening { at } => {
            let near = format!("({:.1}, {:.1})", at.x, at.y);
            if corner {
                return corner_ends(
                    spec,
                    k,
                    (before, prev),
                    (after, next),
                    format!("the binder's outer edge at the corner `{name}` crosses into the punch opening near {near}"),
                    format!("a corner's outer edge runs from the outer end of `{prev}` to the outer start of `{next}`, shaped like the opening's corner: place those two ends (their `direction` and `width`) so that the edge between them stays outside the opening"),
                );
            }
            let label = if own(k) {
                format!("the binder of `{name}`")
            } else {
                format!("this width puts the outer edge of `{name}` inside the opening")
            };
            Explanation::new(
                format!("the binder's outer edge along the side `{name}` crosses into the punch opening near {near}"),
                Part::Piece(k),
                label,
                format!("the outer edge must stay outside the opening in the top view: where the opening curves in, as at a notch, the binder must be narrower than the gap across it; make the binder narrower here with `side {name} {{ width = ... }}`, or turn its `direction` away from the opening"),
            )
        }
        bh::Problem::Kernel(GeomError::Singular { what: why }) if why.contains("fold") => {
            if corner {
                return corner_ends(
                    spec,
                    k,
                    (before, prev),
                    (after, next),
                    format!("the binder at the corner `{name}` folds over itself: its outer edge runs back against the punch opening"),
                    format!("a corner's outer edge runs from the outer end of `{prev}` to the outer start of `{next}`, turning the same way as the opening's corner: place those two ends (their `direction` and `width`) so that it can, or make the binder narrower or the punch-opening corner fuller here"),
                );
            }
            // Point at what steers the outer edge: directions, then end tangents.
            Explanation::new(
                format!("the binder along the side `{name}` folds over itself: its outer edge runs back against the punch opening"),
                Part::Directions(k),
                "these directions turn the outer edge back",
                "the outer edge must run along the side the same way as the opening: point each station's `direction` squarely out of the opening rather than along it, keep end tangents along the side, and avoid large changes of width between close stations",
            )
            .or_labelled(Part::Tangent { side: k, end: false }, "this end tangent turns the outer edge back")
            .or(Part::Tangent { side: k, end: true })
            .or_labelled(Part::Piece(k), format!("the binder of `{name}`"))
        }
        bh::Problem::OuterEndsDisagree { gap } => {
            let [end, start] = outer_ends((before, prev), (k, name));
            let message = format!("the sides `{prev}` and `{name}` meet without a corner, but their binder outer edges end {gap:.1} mm apart there");
            let help = format!("sides that meet without a corner share their end station: give `{prev}` and `{name}` the same `width`, `angle` and `direction` where they meet");
            // Blame the side the designer set apart with a block of its own.
            if own(before) && !own(k) {
                Explanation::new(message, end.0, end.1, help).also(start.0, start.1)
            } else {
                Explanation::new(message, start.0, start.1, help)
                    .or(Part::Piece(k))
                    .also(end.0, end.1)
            }
        }
        bh::Problem::TangentAtSideJoin => {
            // The kernel refuses the end tangent of the side before a join first.
            let this = side_of(k);
            let end_case =
                side_of(after).is_some() && this.is_some_and(|s| s.end_tangent.is_some());
            let start_case =
                side_of(before).is_some() && this.is_some_and(|s| s.start_tangent.is_some());
            // The kernel checks each join in order, the one before piece 0 last.
            let end = end_case && (!start_case || k == 0);
            let (key, other) = if end {
                ("end_tangent", next)
            } else {
                ("start_tangent", prev)
            };
            Explanation::new(
                format!("`{key}` of `side {name}` is given where `{name}` meets `{other}` without a corner"),
                Part::Tangent { side: k, end },
                "not allowed where two sides meet",
                format!("remove `{key}`: where two sides meet without a corner the binder's outer edge runs on smoothly from one to the other, with the tangent the opening gives it (eq. 4); end tangents are for ends at a corner"),
            )
            .or(Part::Piece(k))
        }
        problem => Explanation::new(
            format!(
                "the blankholder {what} `{name}` cannot be built: {problem} (in `{}`)",
                block.name
            ),
            Part::Piece(k),
            format!("the {what} `{name}`"),
            match problem {
                bh::Problem::Stations => "stations run from 0 to 1 and increase",
                bh::Problem::Width(_) => "give a positive width",
                bh::Problem::Tautness(_) => "tautness lies between 0 and 1",
                bh::Problem::Mismatch => "this is a bug in dieface: please report it",
                _ => "check this piece's widths, angles and tangents for degenerate input",
            },
        ),
    }
}

/// A corner's problem (the corner is piece `k`) blamed on the outer ends of its sides,
/// `(index, name)` before and after it: the end whose direction the designer set, else
/// the end before.
fn corner_ends(
    spec: &[PieceSpec],
    k: usize,
    (before, prev): (usize, &str),
    (after, next): (usize, &str),
    message: String,
    help: String,
) -> Explanation<Part> {
    let steered = |k: usize, last: bool| match spec.get(k) {
        Some(PieceSpec::Side(s)) => {
            let i = if last {
                s.stations.len().saturating_sub(1)
            } else {
                0
            };
            s.stations.get(i).is_some_and(|st| st.direction.is_some())
        }
        _ => false,
    };
    let [end, start] = outer_ends((before, prev), (after, next));
    let (primary, other) = if steered(before, true) || !steered(after, false) {
        (end, start)
    } else {
        (start, end)
    };
    Explanation::new(message, primary.0, primary.1, help)
        .or(Part::Piece(k))
        .also(other.0, other.1)
}

/// The outer end of side `a` and the outer start of side `b` (`(index, name)` each),
/// with their labels: where two sides' outer edges meet, with a corner between them or
/// without one.
fn outer_ends((a, a_name): (usize, &str), (b, b_name): (usize, &str)) -> [(Part, String); 2] {
    [
        (
            Part::End {
                side: a,
                last: true,
            },
            format!("places the outer end of `{a_name}`"),
        ),
        (
            Part::End {
                side: b,
                last: false,
            },
            format!("places the outer start of `{b_name}`"),
        ),
    ]
}

/// The feature record: one surface per patch and `quality`.
fn output(block: &Block, binder: bh::Blankholder) -> Value {
    let span = block.span;
    let fields: Vec<(String, Value)> = binder
        .patches
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                Value::new(Data::Surface(Arc::new(p.surface.clone())), span),
            )
        })
        .collect();
    let (mut quality, joins) = join_figures(
        binder
            .joins
            .iter()
            .map(|j| (j.before.as_str(), j.after.as_str(), &j.quality)),
        span,
    );
    quality.extend(joins);
    let patches = binder.patches.iter();
    super::surface_figures(
        &mut quality,
        patches.map(|p| (p.name.as_str(), &p.surface, &[][..], None)),
        span,
    );
    feature_value(KIND, span, fields, quality, binder)
}

/// The `blankholder` feature kind.
pub(super) static KIND: &dyn FeatureKind = &BlankholderKind;

struct BlankholderKind;

impl FeatureKind for BlankholderKind {
    fn name(&self) -> &'static str {
        "blankholder"
    }
    fn code(&self) -> &'static str {
        "die::blankholder"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec!["opening", "width", "angle", "corners", "max_bead_height"],
            named: vec!["side", "corner"],
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build(block)
    }
    fn color(&self) -> [f64; 3] {
        [0.25, 0.65, 0.30] // green
    }
    fn summary(&self, record: &Record) -> String {
        let Some(b) = record.model::<bh::Blankholder>() else {
            return String::new();
        };
        let (area, extent) = patches_extent(b.patches.iter().map(|p| &p.surface));
        format!(
            "blankholder, {} patches [{}], area {} mm², bounds {}",
            b.patches.len(),
            b.patches
                .iter()
                .map(|p| p.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            area,
            extent
        )
    }
    /// The binder's patches are faces of the die face.
    fn die_face(&self, name: &str, record: &Record, out: &mut DieFace) {
        if let Some(b) = record.model::<bh::Blankholder>() {
            out.faces.extend(b.patches.iter().map(|p| Face {
                name: format!("{name}/{}", p.name),
                shape: Shape::Patch(p.surface.clone()),
            }));
        }
    }
}
