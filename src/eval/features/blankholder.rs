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
use crate::syntax::Span;

use super::super::builtins::{as_point2, as_point3, type_error};
use super::super::units::Units;
use super::super::value::{Data, Feature, Record, Value};
use super::{
    angle, check_record, deg, feature_error, items, length, mm, number, ratio, record,
    record_value, Block,
};

const KIND: &str = "blankholder";

/// Default number of stations along a side when the designer gives no lists.
const DEFAULT_STATIONS: usize = 5;

/// Builds the blankholder of `block`.
pub fn build(block: &Block) -> Result<Value, Diagnostic> {
    block.check_fields(
        &["opening", "width", "angle", "corners"],
        &["side", "corner"],
    )?;
    let units = block.units;
    let opening_field = block.get("opening").ok_or_else(|| {
        block.missing(
            "opening",
            "name the punch opening the binder surrounds: `opening = my_opening`",
        )
    })?;
    let opening = opening_of(&opening_field.value)?;
    let default_width = match block.get("width") {
        Some(f) => Some((length(&f.value, units, "`width`")?, f.value.span)),
        None => None,
    };
    let default_angle = match block.get("angle") {
        Some(f) => angle(&f.value, units, "`angle`")?,
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
        for (name, f) in fields.iter() {
            if !known.contains(name) {
                let d = feature_error(
                    KIND,
                    format!("the punch opening has no {word} `{name}`"),
                    f.name_span,
                    format!("no such {word}"),
                    "",
                );
                return Err(match did_you_mean(name, known.iter().copied()) {
                    Some(g) => d.with_help(format!(
                        "did you mean `{g}`? The {word}s are: {}",
                        known.join(", ")
                    )),
                    None => d.with_help(format!("the {word}s are: {}", known.join(", "))),
                });
            }
        }
    }

    let mut spec = Vec::with_capacity(opening.pieces.len());
    let mut blame = Vec::with_capacity(opening.pieces.len());
    for piece in &opening.pieces {
        match piece.kind {
            PieceKind::Side => {
                let own = side_fields
                    .iter()
                    .find(|(n, _)| *n == piece.name)
                    .map(|(_, f)| *f);
                let (side, span) =
                    side_spec(block, own, default_width, default_angle, &piece.name)?;
                spec.push(PieceSpec::Side(side));
                blame.push(span);
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
                        block.get("corners").map_or(block.span, |f| f.value.span),
                    ),
                };
                spec.push(PieceSpec::Corner { tautness: t });
                blame.push(span);
            }
        }
    }
    let binder = bh::build(&opening, &spec).map_err(|e| build_error(block, &opening, &blame, e))?;
    Ok(output(block, binder))
}

/// The punch opening a `opening` field names.
fn opening_of(v: &Value) -> Result<Arc<PunchOpening>, Diagnostic> {
    match &v.data {
        Data::Record(r) => match &r.feature {
            Some(Feature::PunchOpening(p)) => Ok(p.clone()),
            _ => Err(type_error(
                v,
                "`opening` of a blankholder",
                "a punch opening",
            )),
        },
        _ => Err(type_error(
            v,
            "`opening` of a blankholder",
            "a punch opening",
        )),
    }
}

/// A tautness: a number or percentage in [0, 1].
fn tautness(v: &Value) -> Result<f64, Diagnostic> {
    let t = number(v, "a corner's `tautness`")?;
    if !(0.0..=1.0).contains(&t) {
        return Err(feature_error(KIND, format!("a corner's tautness lies between 0 and 1, but this is {t}"), v.span, "this tautness", "0 keeps the sag of the punch-opening corner, 1 makes the outer edge straight in height; `50 %` is halfway"));
    }
    Ok(t)
}

/// One side's stations: its own block over the blankholder's defaults. Returns the span
/// to blame for the side's problems.
fn side_spec(
    block: &Block,
    own: Option<&super::Field>,
    default_width: Option<(f64, Span)>,
    default_angle: f64,
    name: &str,
) -> Result<(SideSpec, Span), Diagnostic> {
    let units = block.units;
    let empty = Record::default();
    let (r, span) = match own {
        Some(f) => (
            record(
                &f.value,
                &format!("`side {name}`"),
                "a block such as `side front { width = 180 mm }`",
            )?,
            f.value.span,
        ),
        None => (&empty, default_width.map_or(block.span, |(_, s)| s)),
    };
    let what = format!("`side {name}`");
    check_record(
        r,
        span,
        &what,
        &[
            "at",
            "width",
            "angle",
            "direction",
            "start_tangent",
            "end_tangent",
        ],
    )?;
    let lists: Vec<(&str, Vec<Value>)> = ["width", "angle", "direction"]
        .iter()
        .filter_map(|k| r.get(k).map(|v| (*k, v)))
        .filter(|(_, v)| matches!(v.data, Data::List(_)))
        .map(|(k, v)| (k, items(v)))
        .collect();
    let at: Vec<f64> = match r.get("at") {
        Some(v) => {
            let list = items(v);
            let mut out = Vec::with_capacity(list.len());
            for item in &list {
                out.push(number(item, &format!("`at` of {what}"))?);
            }
            if out.len() < 2
                || out[0] != 0.0
                || out[out.len() - 1] != 1.0
                || out.windows(2).any(|w| w[1] <= w[0])
            {
                return Err(feature_error(KIND, format!("the stations `at` of {what} must run from 0 to 1 and increase"), v.span, "these stations", "stations are fractions of the side's length: e.g. `at = [0, 30 %, 1]`; the first is 0 (the side's start) and the last 1 (its end)"));
            }
            out
        }
        None => {
            let n = lists
                .iter()
                .map(|(_, l)| l.len())
                .max()
                .unwrap_or(DEFAULT_STATIONS)
                .max(2);
            (0..n).map(|i| i as f64 / (n - 1) as f64).collect()
        }
    };
    let n = at.len();
    let per_station = |key: &str| -> Result<Option<Vec<Value>>, Diagnostic> {
        let Some(v) = r.get(key) else { return Ok(None) };
        let list = match &v.data {
            Data::List(items) => items.to_vec(),
            _ => vec![v.clone(); n],
        };
        if list.len() != n {
            return Err(feature_error(
                KIND,
                format!(
                    "`{key}` of {what} gives {} values for {n} stations",
                    list.len()
                ),
                v.span,
                format!("{} values", list.len()),
                "give one value, or one per station (`at`)",
            ));
        }
        Ok(Some(list))
    };
    let widths = match per_station("width")? {
        Some(list) => list
            .iter()
            .map(|v| length(v, units, &format!("`width` of {what}")))
            .collect::<Result<Vec<_>, _>>()?,
        None => match default_width {
            Some((w, _)) => vec![w; n],
            None => {
                return Err(block.missing("width", &format!("give the binder width for every side (`width = 180 mm`) or in `side {name} {{ width = ... }}`")));
            }
        },
    };
    for (i, &w) in widths.iter().enumerate() {
        if !(w.is_finite() && w > 0.0) {
            let s =
                r.get("width")
                    .map_or(default_width.map_or(block.span, |(_, s)| s), |v| {
                        match &v.data {
                            Data::List(items) => items.get(i).map_or(v.span, |x| x.span),
                            _ => v.span,
                        }
                    });
            return Err(feature_error(KIND, format!("a binder width must be positive, but this is {w} mm"), s, "this width", "the width is the distance from the punch opening to the binder's outer edge, e.g. 180 mm"));
        }
    }
    let angles = match per_station("angle")? {
        Some(list) => list
            .iter()
            .map(|v| angle(v, units, &format!("`angle` of {what}")))
            .collect::<Result<Vec<_>, _>>()?,
        None => vec![default_angle; n],
    };
    let directions: Vec<Option<DVec2>> = match r.get("direction") {
        Some(v) => {
            let list = match &v.data {
                Data::List(items) => items.to_vec(),
                _ => vec![v.clone(); n],
            };
            if list.len() != n {
                return Err(feature_error(
                    KIND,
                    format!(
                        "`direction` of {what} gives {} values for {n} stations",
                        list.len()
                    ),
                    v.span,
                    format!("{} values", list.len()),
                    "give one direction, or one per station",
                ));
            }
            list.iter()
                .map(|d| direction2(d, units, &what).map(Some))
                .collect::<Result<Vec<_>, _>>()?
        }
        None => vec![None; n],
    };
    let tangent = |key: &str| -> Result<Option<DVec3>, Diagnostic> {
        match r.get(key) {
            Some(v) => Ok(Some(as_point3(v, units, &format!("`{key}` of {what}"))?)),
            None => Ok(None),
        }
    };
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
            start_tangent: tangent("start_tangent")?,
            end_tangent: tangent("end_tangent")?,
        },
        span,
    ))
}

fn direction2(v: &Value, units: Units, what: &str) -> Result<DVec2, Diagnostic> {
    as_point2(v, units, &format!("`direction` of {what}"))
}

fn build_error(block: &Block, opening: &PunchOpening, blame: &[Span], e: bh::Error) -> Diagnostic {
    let piece = opening.pieces.get(e.piece);
    let name = piece.map_or("?", |p| p.name.as_str());
    let what = match piece.map(|p| p.kind) {
        Some(PieceKind::Corner) => "corner",
        _ => "side",
    };
    let span = blame.get(e.piece).copied().unwrap_or(block.span);
    let help = match &e.problem {
        bh::Problem::CrossesOpening { .. } => "the outer edge must stay outside the punch opening: widen the binder here, lower the angle, or point `direction` out of the opening",
        bh::Problem::OuterEndsDisagree { .. } => "sides that meet without a corner share their end station: give them the same width, angle and direction there",
        bh::Problem::TangentAtSideJoin => "remove this end tangent: where two sides meet without a corner, eq. 4 decides it",
        bh::Problem::Direction => "a direction points from the punch opening out to the binder's edge",
        bh::Problem::Stations => "stations run from 0 to 1 and increase",
        bh::Problem::Width(_) => "give a positive width",
        bh::Problem::Tautness(_) => "tautness lies between 0 and 1",
        bh::Problem::Mismatch => "this is a bug in dieface: please report it",
        bh::Problem::Kernel(_) => "check this piece's widths, angles and tangents for degenerate input",
    };
    feature_error(
        KIND,
        format!(
            "the blankholder {what} `{name}` cannot be built: {} (in `{}`)",
            e.problem, block.name
        ),
        span,
        format!("the {what} `{name}`"),
        help,
    )
}

/// The feature record: one surface per patch and `quality`.
fn output(block: &Block, binder: bh::Blankholder) -> Value {
    let span = block.span;
    let mut fields: Vec<(String, Value)> = binder
        .patches
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                Value::new(Data::Surface(Arc::new(p.surface.clone())), span),
            )
        })
        .collect();
    let (mut gap, mut normal, mut net, mut spread) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut joins = Vec::new();
    for j in &binder.joins {
        let q = &j.quality;
        gap = gap.max(q.gap).max(q.net_gap);
        normal = normal.max(q.normal_angle);
        net = net.max(q.net_angle);
        spread = spread.max(q.ratio_spread);
        joins.push((
            format!("{} > {}", j.before, j.after),
            record_value(
                vec![
                    ("gap".into(), mm(q.gap.max(q.net_gap), span)),
                    ("normal_angle".into(), deg(q.normal_angle, span)),
                    ("net_angle".into(), deg(q.net_angle, span)),
                    ("ratio_spread".into(), ratio(q.ratio_spread, span)),
                ],
                span,
            ),
        ));
    }
    let mut quality = vec![
        ("gap".to_string(), mm(gap, span)),
        ("normal_angle".to_string(), deg(normal, span)),
        ("net_angle".to_string(), deg(net, span)),
        ("ratio_spread".to_string(), ratio(spread, span)),
    ];
    quality.extend(joins);
    fields.push(("quality".into(), record_value(quality, span)));
    Value::new(
        Data::Record(Arc::new(Record {
            kind: Some(KIND.to_string()),
            fields,
            feature: Some(Feature::Blankholder(Arc::new(binder))),
        })),
        span,
    )
}
