//! `sheet name { ... }`: a thin part declared as a zero-thickness sheet and made solid
//! at its thickness, read into [`crate::sheet::part`].
//!
//! ```text
//! sheet bracket {
//!     outline = sketch(top) { ... close }   // the plate, on its view's plane
//!     thickness = 1.2 mm
//!     punch vent = sketch(top) { ... close }             // a hole, inside the outline
//!     lift rib = { region: sketch(top) { ... close }, height: 2 mm }   // an embossment
//!     flange lip = { at: (100, 30), height: 25 mm }     // on the edge nearest `at`,
//!                                                        // `angle` up (default 90 deg),
//!                                                        // `radius` of its bend,
//!                                                        // or `from`/`to` on part of it,
//!                                                        // `thickness` of its own
//! }
//! ```
//!
//! The value: `mid` (the mid-surface, one side of each sheet, as a mesh), `solid` (the
//! closed solid at the thickness, one group per face) and `quality` (`area`, `volume`,
//! `thickness`, `holes`, `flanges`, the junction counts by type and `junctions`).

use crate::diag::Diagnostic;
use crate::geom::tessellate::{tessellate_curve, Tolerance};
use crate::sheet::base::BaseError;
use crate::sheet::junction::{Junction, JunctionType};
use crate::sheet::part::{
    self, BendSpec, CoverSpec, FlangeSpec, HoleSpec, LiftSpec, MovePick, MoveSpec, PartProblem,
    PlateSpec, RemoveSpec, RemoveTarget, RoundSpec, SheetPart,
};
use crate::sheet::topology::Removal;
use crate::syntax::Span;

use super::super::builtins::{as_angle, as_point2, as_point3, type_error};
use super::super::sketch::{Sketch, View};
use super::super::summary::round;
use super::super::units::Units;
use super::super::value::{Data, Dim, Quantity, Record, Value};
use super::kind::{FeatureKind, FieldNames};
use super::{
    check_record, count, deg, feature_error, feature_value, length, mm, record, record_value,
    Block, Field,
};

use glam::{DVec2, DVec3};
use std::sync::Arc;

/// How closely a curved outline is followed by the plate's straight edges (mm).
const OUTLINE_TOLERANCE: f64 = 0.05;

/// Builds the sheet part of `block`.
fn build(block: &Block) -> Result<Value, Diagnostic> {
    let outline_field = block.get("outline").ok_or_else(|| {
        block.missing(
            "outline",
            "give the plate's outline as a closed sketch: `outline = sketch(top) { ... close }`",
        )
    })?;
    let thickness_field = block.get("thickness").ok_or_else(|| {
        block.missing(
            "thickness",
            "give the sheet's thickness: `thickness = 1.2 mm`",
        )
    })?;
    let thickness = length(&thickness_field.value, block.units, "`thickness`")?;
    if !(thickness.is_finite() && thickness > 0.0) {
        return Err(feature_error(
            KIND,
            format!(
                "the thickness must be above 0 mm, not {} mm",
                round(thickness)
            ),
            thickness_field.value.span,
            "not a thickness",
            "give a sheet thickness such as `thickness = 1.2 mm`",
        ));
    }
    let sketch = closed_sketch(&outline_field.value, "`outline`")?;
    let view = sketch.view;
    let normal = view_normal(view);
    let outline = polygon(&sketch, outline_field.value.span)?;
    let base = match block.get("on") {
        None => None,
        Some(field) => match &field.value.data {
            Data::Surface(surface) => Some(surface.clone()),
            _ => {
                return Err(type_error(
                    &field.value,
                    "`on`",
                    "a surface (the part is laid on it, seen along the outline's view)",
                ))
            }
        },
    };
    let punches = block.named("punch");
    let mut holes = Vec::with_capacity(punches.len());
    for (name, field) in &punches {
        let s = closed_sketch(&field.value, "a `punch`")?;
        if s.view != view {
            return Err(feature_error(
                KIND,
                format!(
                    "a hole must be drawn in the outline's view ({}), but this one is in the {} view",
                    view.name(),
                    s.view.name()
                ),
                field.value.span,
                "another view",
                format!("draw it with `sketch({}) {{ ... }}`", view.name()),
            ));
        }
        holes.push(HoleSpec {
            name: name.to_string(),
            points: polygon(&s, field.value.span)?,
        });
    }
    let lift_fields = block.named("lift");
    let mut lifts = Vec::with_capacity(lift_fields.len());
    for (name, field) in &lift_fields {
        let what = format!("`lift {name}`");
        let r = record(
            &field.value,
            &what,
            "a record `{ region: sketch(top) { ... close }, height: 3 mm }`",
        )?;
        check_record(r, field.value.span, &what, &["region", "height", "draft"])?;
        let span = field.value.span;
        let region = required(r, "region", &what, span, "add `region: sketch(top) { ... close }`, the closed sketch of the part to lift, drawn in the outline's view")?;
        let height = required(
            r,
            "height",
            &what,
            span,
            "add `height: 3 mm`, how far the region rises (below 0 pushes it down)",
        )?;
        let sketch = closed_sketch(region, &format!("`region` of {what}"))?;
        if sketch.view != view {
            return Err(feature_error(
                KIND,
                format!(
                    "a lifted region must be drawn in the outline's view ({}), but this one is in the {} view",
                    view.name(),
                    sketch.view.name()
                ),
                region.span,
                "another view",
                format!("draw it with `sketch({}) {{ ... }}`", view.name()),
            ));
        }
        let draft = match r.get("draft") {
            Some(a) => as_angle(a, block.units, &format!("`draft` of {what}"))?,
            None => 0.0,
        };
        lifts.push(LiftSpec {
            name: name.to_string(),
            points: polygon(&sketch, region.span)?,
            height: length(height, block.units, &format!("`height` of {what}"))?,
            draft,
        });
    }
    let bend_fields = block.named("bend");
    let mut bends = Vec::with_capacity(bend_fields.len());
    for (name, field) in &bend_fields {
        let what = format!("`bend {name}`");
        let r = record(
            &field.value,
            &what,
            "a record `{ from: (x, y), to: (x, y), angle: 90 deg }`",
        )?;
        check_record(
            r,
            field.value.span,
            &what,
            &["from", "to", "angle", "radius"],
        )?;
        let get = |key: &str, help: &str| required(r, key, &what, field.value.span, help);
        let end = |key: &str| -> Result<DVec3, Diagnostic> {
            let v = get(
                key,
                "give the bend line's ends on the outline: `from: (x, y), to: (x, y)`",
            )?;
            Ok(view.place(as_point2(v, block.units, &format!("`{key}` of {what}"))?))
        };
        let angle = get(
            "angle",
            "add `angle: 90 deg`, how far the part left of the line turns up",
        )?;
        bends.push(BendSpec {
            name: name.to_string(),
            from: end("from")?,
            to: end("to")?,
            angle: as_angle(angle, block.units, &format!("`angle` of {what}"))?,
            radius: bend_radius(r, block.units, &what)?,
        });
    }
    let remove_fields = block.named("remove");
    let mut removals = Vec::with_capacity(remove_fields.len());
    for (name, field) in &remove_fields {
        let what = format!("`remove {name}`");
        let example = "a record `{ at: (x, y) }` (a face), `{ flange: \"lip\" }` (a flange) or `{ cover: \"lid\" }` (a cover)";
        let r = record(&field.value, &what, example)?;
        // A flange by its name, or the face under a point.
        let target = match (r.get("flange"), r.get("cover")) {
            (Some(v), _) => {
                check_record(r, field.value.span, &what, &["flange"])?;
                RemoveTarget::Flange(flange_name(v, &format!("`flange` of {what}"))?)
            }
            (None, Some(v)) => {
                check_record(r, field.value.span, &what, &["cover"])?;
                RemoveTarget::Cover(flange_name(v, &format!("`cover` of {what}"))?)
            }
            (None, None) => {
                let (_, at) = picked(
                    field,
                    &what,
                    &["at"],
                    example,
                    "add `at: (x, y)`, a point in the outline's view over the face to remove (a lifted region's top, or a part a bend splits off), or `flange: \"NAME\"`, a flange to remove",
                    (view, block.units),
                )?;
                RemoveTarget::Face(at)
            }
        };
        removals.push(RemoveSpec {
            name: name.to_string(),
            target,
        });
    }
    let move_fields = block.named("move");
    let mut moves = Vec::with_capacity(move_fields.len());
    for (name, field) in &move_fields {
        let what = format!("`move {name}`");
        let example = "a record `{ at: (x, y), by: (dx, dy, dz) }` (a face) or `{ corner: (x, y, z), by: (dx, dy, dz) }` (a corner)";
        let r = record(&field.value, &what, example)?;
        // A corner is picked by a 3-D point near it; a face by a point over it.
        let (at, pick) = match r.get("corner") {
            Some(corner) => {
                check_record(r, field.value.span, &what, &["corner", "by"])?;
                (
                    as_point3(corner, block.units, &format!("`corner` of {what}"))?,
                    MovePick::Corner,
                )
            }
            None => {
                let (_, at) = picked(
                    field,
                    &what,
                    &["at", "by"],
                    example,
                    "add `at: (x, y)`, a point in the outline's view over the face to move (a lifted region's top), or `corner: (x, y, z)`, a point near the corner to move",
                    (view, block.units),
                )?;
                (at, MovePick::Face)
            }
        };
        let by = required(
            r,
            "by",
            &what,
            field.value.span,
            "add `by: (dx, dy, dz)`, how far the face or corner moves, in press coordinates",
        )?;
        moves.push(MoveSpec {
            name: name.to_string(),
            at,
            by: as_point3(by, block.units, &format!("`by` of {what}"))?,
            pick,
        });
    }
    let flange_fields = block.named("flange");
    let mut flanges = Vec::with_capacity(flange_fields.len());
    for (name, field) in &flange_fields {
        let what = format!("`flange {name}`");
        let r = record(
            &field.value,
            &what,
            "a record `{ at: (x, y), height: 25 mm }`",
        )?;
        check_record(
            r,
            field.value.span,
            &what,
            &[
                "at",
                "from",
                "to",
                "height",
                "angle",
                "thickness",
                "radius",
                "shape",
                "around",
                "on",
            ],
        )?;
        // A flange on an earlier flange's far edge (a return flange), by that flange's
        // name.
        let on = match r.get("on") {
            Some(v) => {
                let parent = flange_name(v, &format!("`on` of {what}"))?;
                if let Some(key) = ["at", "from", "to", "around", "shape"]
                    .into_iter()
                    .find(|k| r.get(k).is_some())
                {
                    return Err(feature_error(
                        KIND,
                        format!(
                            "{what} stands `on` the far edge of flange `{parent}`, so it takes no `{key}`"
                        ),
                        field.value.span,
                        "on a flange, and placed",
                        "leave out `at`, `from`, `to`, `around` and `shape`: a return flange runs the whole far edge of the flange it stands on",
                    ));
                }
                Some(parent)
            }
            None => None,
        };
        let around = match r.get("around") {
            Some(v) => {
                let Data::Bool(b) = v.data else {
                    return Err(type_error(
                        v,
                        &format!("`around` of {what}"),
                        "true or false",
                    ));
                };
                if b {
                    if let Some(key) = ["at", "from", "to"]
                        .into_iter()
                        .find(|k| r.get(k).is_some())
                    {
                        return Err(feature_error(
                            KIND,
                            format!(
                                "{what} runs `around` the whole outline, so it takes no `{key}`"
                            ),
                            field.value.span,
                            "around, and placed",
                            "leave out `at`, `from` and `to`, or `around`",
                        ));
                    }
                }
                b
            }
            None => false,
        };
        // Where it stands: on the edge nearest `at`, or on the part of an edge between
        // `from` and `to`.
        let point = |key: &str| -> Result<Option<DVec3>, Diagnostic> {
            r.get(key)
                .map(|v| {
                    as_point2(v, block.units, &format!("`{key}` of {what}")).map(|p| view.place(p))
                })
                .transpose()
        };
        let span = match (point("from")?, point("to")?) {
            (Some(from), Some(to)) => Some((from, to)),
            (None, None) => None,
            _ => return Err(feature_error(
                KIND,
                format!("{what} needs both `from` and `to`, or neither"),
                field.value.span,
                "one end given",
                "give both ends of the part of the edge it stands on: `from: (x, y), to: (x, y)`",
            )),
        };
        let near = match (point("at")?, span) {
            _ if around || on.is_some() => outline[0],
            (Some(at), _) => at,
            (None, Some((from, to))) => 0.5 * (from + to),
            (None, None) => {
                return Err(feature_error(
                    KIND,
                    format!("{what} needs `at`, a point near the edge it goes on"),
                    field.value.span,
                    "no `at`",
                    "add `at: (x, y)`, a point in the outline's view near the edge (or `from` and `to` for part of an edge)",
                ))
            }
        };
        let shape = match r.get("shape") {
            Some(v) => Some(flange_shape(v, &what)?),
            None => None,
        };
        let height = match (r.get("height"), &shape) {
            (Some(h), None) => length(h, block.units, &format!("`height` of {what}"))?,
            (None, Some(points)) => points.iter().map(|p| p.y).fold(0.0, f64::max),
            (Some(h), Some(_)) => {
                return Err(feature_error(
                    KIND,
                    format!("{what} has both a `height` and a `shape`"),
                    h.span,
                    "the shape gives the height",
                    "give `height` for a rectangular flange, or draw its `shape`, not both",
                ))
            }
            (None, None) => {
                let h = required(
                    r,
                    "height",
                    &what,
                    field.value.span,
                    "add `height: 25 mm`, how far the flange reaches from the edge (or draw its outline as `shape: sketch(profile) { ... }`)",
                )?;
                length(h, block.units, &format!("`height` of {what}"))?
            }
        };
        let angle = match r.get("angle") {
            Some(a) => as_angle(a, block.units, &format!("`angle` of {what}"))?,
            None => std::f64::consts::FRAC_PI_2,
        };
        let own = own_thickness(r, block.units, &what, field.value.span, "flange")?;
        let radius = bend_radius(r, block.units, &what)?;
        flanges.push(FlangeSpec {
            name: name.to_string(),
            near,
            height,
            angle,
            thickness: own,
            span,
            radius,
            shape,
            around,
            on,
        });
    }
    let round_fields = block.named("round");
    let mut rounds = Vec::with_capacity(round_fields.len());
    for (name, field) in &round_fields {
        let what = format!("`round {name}`");
        let (r, at) = picked(
            field,
            &what,
            &["at", "radius"],
            "a record `{ at: (x, y), radius: 2 mm }`",
            "add `at: (x, y)`, a point in the outline's view on the joint to round: a flange's foot or a bend's line",
            (view, block.units),
        )?;
        let radius = required(
            r,
            "radius",
            &what,
            field.value.span,
            "add `radius: 2 mm`, the joint's inside radius",
        )?;
        rounds.push(RoundSpec {
            name: name.to_string(),
            at,
            radius: length(radius, block.units, &format!("`radius` of {what}"))?,
        });
    }
    let cover_fields = block.named("cover");
    let mut covers = Vec::with_capacity(cover_fields.len());
    for (name, field) in &cover_fields {
        let what = format!("`cover {name}`");
        let example = "a record `{ on: [\"left\", \"right\"] }`";
        let r = record(&field.value, &what, example)?;
        check_record(r, field.value.span, &what, &["on", "thickness"])?;
        let on = required(
            r,
            "on",
            &what,
            field.value.span,
            "add `on: [\"left\", \"right\"]`, the two flanges whose far edges it stands across",
        )?;
        let names = match &on.data {
            Data::List(items) if items.len() == 2 => [
                flange_name(&items[0], &format!("`on` of {what}"))?,
                flange_name(&items[1], &format!("`on` of {what}"))?,
            ],
            _ => {
                return Err(type_error(
                    on,
                    &format!("`on` of {what}"),
                    "a list of two flanges' names, such as [\"left\", \"right\"]",
                ))
            }
        };
        covers.push(CoverSpec {
            name: name.to_string(),
            on: names,
            thickness: own_thickness(r, block.units, &what, field.value.span, "cover")?,
        });
    }
    let spec = PlateSpec {
        outline,
        normal,
        holes,
        lifts,
        bends,
        moves,
        removals,
        flanges,
        rounds,
        covers,
        thickness,
        base,
    };
    let fields = NamedFields {
        punches: &punches,
        lifts: &lift_fields,
        bends: &bend_fields,
        moves: &move_fields,
        removals: &remove_fields,
        flanges: &flange_fields,
        rounds: &round_fields,
        covers: &cover_fields,
    };
    let on = block.get("on").map(|f| f.value.span);
    let built =
        part::build(&spec).map_err(|p| problem(p, outline_field.value.span, on, &fields))?;
    Ok(output(
        block,
        built,
        spec.holes.len(),
        spec.flanges.len(),
        thickness,
    ))
}

/// A `keyword NAME = { at: (x, y), ... }` field that picks a face or a joint by a
/// point: its record, checked to hold only `keys` (`example` shows one), and its `at`
/// (required, with `at_help`) placed on the outline's view, `place` (the view and the
/// block's units).
fn picked<'a>(
    field: &'a Field,
    what: &str,
    keys: &[&str],
    example: &str,
    at_help: &str,
    place: (View, Units),
) -> Result<(&'a Record, DVec3), Diagnostic> {
    let (view, units) = place;
    let r = record(&field.value, what, example)?;
    check_record(r, field.value.span, what, keys)?;
    let at = required(r, "at", what, field.value.span, at_help)?;
    Ok((
        r,
        view.place(as_point2(at, units, &format!("`at` of {what}"))?),
    ))
}

/// Field `key` of record `r`, the value of `what` written at `span`, or the diagnostic
/// that it is missing, with `help`.
fn required<'a>(
    r: &'a Record,
    key: &str,
    what: &str,
    span: Span,
    help: &str,
) -> Result<&'a Value, Diagnostic> {
    r.get(key).ok_or_else(|| {
        feature_error(
            KIND,
            format!("{what} needs `{key}`"),
            span,
            format!("no `{key}`"),
            help.to_string(),
        )
    })
}

/// A flange's drawn `shape`: an open sketch in the `profile` view, (s, z) in the
/// flange's plane, as its points (its curves followed within [`OUTLINE_TOLERANCE`]).
fn flange_shape(v: &Value, what: &str) -> Result<Vec<DVec2>, Diagnostic> {
    let Data::Sketch(s) = &v.data else {
        return Err(type_error(v, &format!("`shape` of {what}"), "a sketch"));
    };
    if s.view != View::Profile || s.closed {
        return Err(feature_error(
            KIND,
            format!(
                "the `shape` of {what} must be an open sketch in the `profile` view, not {} in the {} view",
                if s.closed { "a closed sketch" } else { "a sketch" },
                s.view.name()
            ),
            v.span,
            "this sketch",
            "draw the flange's outline seen from outside the part as `sketch(profile) { from (0, 0) ... }`: s along the edge from its left end, z up the flange, from (0, 0) to the edge's other end (length, 0); the edge closes the loop",
        ));
    }
    let tol = Tolerance {
        chordal: OUTLINE_TOLERANCE,
        angle: 0.2,
        max_edge: None,
    };
    let flat = s.curve.map_points(|p| DVec3::new(p.x, p.y, 0.0));
    let line = tessellate_curve(&flat, &tol).map_err(|e| {
        feature_error(
            KIND,
            format!("the `shape` of {what} cannot be followed by straight edges: {e}"),
            v.span,
            "this sketch",
            "simplify the sketch",
        )
    })?;
    Ok(line.points.iter().map(|p| DVec2::new(p.x, p.y)).collect())
}

/// The inside radius of a bend or a flange's bend (`radius`, 0 mm when left out), 0 mm
/// or more.
fn bend_radius(r: &Record, units: Units, what: &str) -> Result<f64, Diagnostic> {
    let Some(v) = r.get("radius") else {
        return Ok(0.0);
    };
    let radius = length(v, units, &format!("`radius` of {what}"))?;
    if !(radius.is_finite() && radius >= 0.0) {
        return Err(feature_error(
            KIND,
            format!(
                "{what}: the bend's inside radius must be 0 mm or more, not {} mm",
                round(radius)
            ),
            v.span,
            "not a radius",
            "give the inside radius of the bend, such as `radius: 2 mm` (0 for a sharp fold)",
        ));
    }
    Ok(radius)
}

/// A sheet block's `keyword NAME = ...` fields, by keyword, in order.
struct NamedFields<'a> {
    punches: &'a [(&'a str, &'a Field)],
    lifts: &'a [(&'a str, &'a Field)],
    bends: &'a [(&'a str, &'a Field)],
    moves: &'a [(&'a str, &'a Field)],
    removals: &'a [(&'a str, &'a Field)],
    flanges: &'a [(&'a str, &'a Field)],
    rounds: &'a [(&'a str, &'a Field)],
    covers: &'a [(&'a str, &'a Field)],
}

/// The diagnostic of a part that could not be built, at the field at fault.
fn problem(p: PartProblem, outline: Span, on: Option<Span>, fields: &NamedFields) -> Diagnostic {
    let NamedFields {
        punches,
        lifts,
        bends,
        moves,
        removals,
        flanges,
        rounds,
        covers,
    } = *fields;
    // The error at field `index` of the `keyword NAME = ...` fields `fields`.
    let at_field =
        |keyword: &str, fields: &[(&str, &Field)], index: usize, label: &str, help: &str| {
            feature_error(
                KIND,
                format!("`{keyword} {}`: {p}", fields[index].0),
                fields[index].1.value.span,
                label,
                help,
            )
        };
    match &p {
        PartProblem::Outline(_) => feature_error(
            KIND,
            p.to_string(),
            outline,
            "this outline",
            "draw the outline as one loop that does not cross itself",
        ),
        PartProblem::Hole { index, .. } => at_field("punch", punches, *index, "this hole", "draw each hole inside the outline, clear of its edges and of the other holes"),
        PartProblem::Lift { index, .. } => at_field("lift", lifts, *index, "this lift", "draw the region inside the outline, clear of its edges, the holes and the other lifted regions, with a height other than 0 and a draft below 90 deg that its size allows"),
        PartProblem::Bend { index, .. } => at_field("bend", bends, *index, "this bend", "draw the bend line across the plate from one edge of the outline to another, clear of the holes, the lifted regions, the other bends' lines and the flanges' edges, with an angle between -180 and 180 deg; on a `radius`, the zone of facets centred on the line (the radius plus half the thickness, times the angle in radians, wide) must fit on the plate too"),
        PartProblem::Remove { index, .. } => at_field("remove", removals, *index, "this removal", "put `at` over the top of a lifted region (removing it leaves a collar round a hole) or over a part a bend splits off; or name a flange with `flange: \"NAME\"` that no other flange stands on alone, or a cover with `cover: \"NAME\"`"),
        PartProblem::Move { index, .. } => at_field("move", moves, *index, "this move", "put `at` over the top of a lifted region, and keep it on its side of the plate: `by` moves it in press coordinates, its walls following; or put `corner` within 5 mm of one corner of the part and move it in the plane of every face that meets there"),
        PartProblem::Round { index, .. } => at_field("round", rounds, *index, "this round", "put `at` on (or within 5 mm of) a flange's foot or a bend's line, nearer it than any other, or on the corner where two walls meet (alike, sharp, of the plate's gauge), and give a radius above 0 that fits; a joint takes one radius, and a flange of its own thickness none"),
        PartProblem::Flange { index, .. } => at_field("flange", flanges, *index, "this flange", "put `at` on (or within 5 mm of) a free edge of the outline, nearer it than any other, or `from` and `to` on one (one edge takes one flange); give a height above 0 (or a `shape` from the edge's left end to its right, seen from outside), an angle below 180 deg, and a bend `radius` or a `thickness` of its own, not both; or stand it `on` an earlier flange by name (a straight far edge; at a corner where that flange is joined to another, joined to a return on the other)"),
        PartProblem::Cover { index, .. } => at_field("cover", covers, *index, "this cover", "stand the cover `on` two flanges by name, each with one straight far edge free of other flanges and not joined at a corner, the two far edges in one plane and running opposite ways round the part (as a channel's two walls do)"),
        PartProblem::FlangesMeet { index, other, .. } => feature_error(
            KIND,
            format!("`flange {}` and `flange {}`: {p}", flanges[*other].0, flanges[*index].0),
            flanges[*index].1.value.span,
            "this flange",
            "flanges joined at a corner must be sharp (no `radius`), out of one plane, and stand equally high above the plate at the corner; or end one short of the corner with a relief edge between them in the outline",
        )
        .with_label(flanges[*other].1.value.span, "meets this one"),
        PartProblem::SelfIntersection {
            flange: Some(index),
            ..
        } => feature_error(
            KIND,
            format!("`flange {}`: {p}", flanges[*index].0),
            flanges[*index].1.value.span,
            "this flange, the nearest",
            "keep the flanges and the plate apart by more than the thickness: a shorter flange, or a lower angle",
        ),
        PartProblem::Junction {
            flange: Some(index),
            ..
        } => feature_error(
            KIND,
            format!("`flange {}`: {p}", flanges[*index].0),
            flanges[*index].1.value.span,
            "this flange, the nearest",
            "start a flange's ends square to the plate's edge where they meet it (a drawn shape's first and last segments straight up from the edge); a flange of its own thickness needs an angle well away from 0 deg, so its sides cross the plate's on a mitre, or the plate's thickness",
        ),
        PartProblem::Junction { flange: None, .. } => feature_error(
            KIND,
            p.to_string(),
            outline,
            "this sheet",
            "check where the sheets meet",
        ),
        PartProblem::SelfIntersection { flange: None, .. } => feature_error(
            KIND,
            p.to_string(),
            outline,
            "this sheet",
            "make the sheet thinner than the gaps between its parts",
        ),
        PartProblem::Base(BaseError::Miss { .. }) => feature_error(
            KIND,
            format!("the sheet cannot be laid on its surface: {p}"),
            on.unwrap_or(outline),
            "this surface",
            "every point of the part, seen along the outline's view (the plate, and the flanges and lifted regions standing on it), must lie over the surface: draw the outline inside the surface's edges, or extend the surface",
        )
        .with_label(outline, "this outline"),
        PartProblem::Base(BaseError::Steep { .. }) => feature_error(
            KIND,
            format!("the sheet cannot be laid on its surface: {p}"),
            on.unwrap_or(outline),
            "this surface",
            "draw the outline in a view that sees the surface from above: the surface under the part must stand less than 75 deg to the view",
        )
        .with_label(outline, "this outline"),
        PartProblem::Thicken(_) => feature_error(
            KIND,
            format!("the sheet cannot be made solid: {p}"),
            outline,
            "this sheet",
            "check that the flanges do not fold onto the plate",
        ),
    }
}

/// A flange's or cover's name given as a string (`on: "lip"`, `flange: "wall.2"`), or a
/// diagnostic naming `what`.
fn flange_name(v: &Value, what: &str) -> Result<String, Diagnostic> {
    match &v.data {
        Data::Str(name) => Ok(name.to_string()),
        _ => Err(type_error(
            v,
            what,
            "the name of a flange, as a string such as \"lip\" (a strip of a run as \"wall.2\")",
        )),
    }
}

/// The `thickness` of a flange or cover (`what`, a `kind`) when it has one of its own:
/// a length above 0.
fn own_thickness(
    r: &Record,
    units: Units,
    what: &str,
    at: Span,
    kind: &str,
) -> Result<Option<f64>, Diagnostic> {
    let Some(t) = r.get("thickness") else {
        return Ok(None);
    };
    let t = length(t, units, &format!("`thickness` of {what}"))?;
    if !(t.is_finite() && t > 0.0) {
        return Err(feature_error(
            KIND,
            format!("{what}: the thickness must be above 0 mm, not {} mm", round(t)),
            at,
            "not a thickness",
            format!("give the {kind}'s own thickness such as `thickness: 1.2 mm`, or leave it out for the plate's"),
        ));
    }
    Ok(Some(t))
}

/// A closed sketch value, or a diagnostic.
fn closed_sketch(v: &Value, what: &str) -> Result<Arc<Sketch>, Diagnostic> {
    let Data::Sketch(s) = &v.data else {
        return Err(type_error(v, what, "a closed sketch"));
    };
    if !s.closed {
        return Err(feature_error(
            KIND,
            format!("{what} must be a closed sketch"),
            v.span,
            "this sketch does not end where it starts",
            "end the sketch with `close`",
        ));
    }
    Ok(s.clone())
}

/// The view's normal: the plate's first side faces it.
fn view_normal(view: View) -> DVec3 {
    let o = view.place(glam::DVec2::ZERO);
    (view.place(glam::DVec2::X) - o)
        .cross(view.place(glam::DVec2::Y) - o)
        .normalize_or_zero()
}

/// The closed sketch as the points of a polygon (its corners, and its curves followed
/// within [`OUTLINE_TOLERANCE`]), in press coordinates.
fn polygon(s: &Sketch, span: Span) -> Result<Vec<DVec3>, Diagnostic> {
    let tol = Tolerance {
        chordal: OUTLINE_TOLERANCE,
        angle: 0.2,
        max_edge: None,
    };
    let line = tessellate_curve(&s.to_3d(), &tol).map_err(|e| {
        feature_error(
            KIND,
            format!("the sketch cannot be followed by straight edges: {e}"),
            span,
            "this sketch",
            "simplify the sketch",
        )
    })?;
    let mut points = line.points;
    if points.len() > 1 && points[0].distance(points[points.len() - 1]) < 1e-9 {
        points.pop();
    }
    Ok(points)
}

/// The value of a built sheet part.
fn output(block: &Block, built: SheetPart, holes: usize, flanges: usize, thickness: f64) -> Value {
    let span = block.span;
    let mid = Value::new(Data::Mesh(built.mid_mesh.clone()), span);
    let solid = Value::new(Data::Mesh(built.solid.clone()), span);
    let quantity = |value: f64, dim: Dim| {
        Value::new(
            Data::Number(Quantity {
                value,
                dim,
                bare: false,
            }),
            span,
        )
    };
    let quality = vec![
        (
            "area".to_string(),
            quantity(
                built.area,
                Dim {
                    length: 2,
                    angle: 0,
                },
            ),
        ),
        (
            "volume".to_string(),
            quantity(
                built.volume,
                Dim {
                    length: 3,
                    angle: 0,
                },
            ),
        ),
        ("thickness".to_string(), mm(thickness, span)),
        ("holes".to_string(), count(holes, span)),
        ("flanges".to_string(), count(flanges, span)),
    ];
    let mut quality = quality;
    for kind in [JunctionType::One, JunctionType::Two, JunctionType::Three] {
        let n = built.junctions.iter().filter(|j| j.kind == kind).count();
        quality.push((format!("junctions_type_{}", kind.number()), count(n, span)));
    }
    quality.push((
        "junctions".to_string(),
        junction_list(&built.junctions, span),
    ));
    // Each named sheet's area and thickness (issue 15: "per sheet its area and
    // thickness").
    let sheets = built
        .sheets
        .iter()
        .map(|figures| {
            let fields = vec![
                (
                    "name".to_string(),
                    Value::new(Data::Str(figures.name.as_str().into()), span),
                ),
                (
                    "area".to_string(),
                    quantity(
                        figures.area,
                        Dim {
                            length: 2,
                            angle: 0,
                        },
                    ),
                ),
                ("thickness".to_string(), mm(figures.thickness, span)),
            ];
            record_value(fields, span)
        })
        .collect();
    quality.push((
        "sheets".to_string(),
        Value::new(Data::List(Arc::new(sheets)), span),
    ));
    // What each removal did, in the paper's words (section 4.4).
    let removals = built
        .removals
        .iter()
        .map(|r| {
            let case = match r {
                Removal::Passage(_) => "a passage made".to_string(),
                Removal::Trimmed {
                    passages_closed: 0, ..
                } => "trimmed, no passage changed".to_string(),
                Removal::Trimmed {
                    passages_closed, ..
                } => format!("trimmed, {passages_closed} passage(s) closed"),
            };
            Value::new(Data::Str(case.into()), span)
        })
        .collect();
    quality.push((
        "removals".to_string(),
        Value::new(Data::List(Arc::new(removals)), span),
    ));
    feature_value(
        KIND,
        span,
        vec![("mid".into(), mid), ("solid".into(), solid)],
        quality,
        built,
    )
}

/// Each junction as a record: where it lies, its type and the paper's four angles.
fn junction_list(junctions: &[Junction], span: Span) -> Value {
    let items = junctions
        .iter()
        .map(|j| {
            let at = Value::new(
                Data::Tuple(Arc::new(vec![
                    mm(j.at.x, span),
                    mm(j.at.y, span),
                    mm(j.at.z, span),
                ])),
                span,
            );
            let fields = vec![
                ("at".to_string(), at),
                ("type".to_string(), count(j.kind.number() as usize, span)),
                ("alpha".to_string(), deg(j.alpha.to_degrees(), span)),
                ("beta".to_string(), deg(j.beta.to_degrees(), span)),
                ("theta".to_string(), deg(j.theta.to_degrees(), span)),
                ("phi".to_string(), deg(j.phi.to_degrees(), span)),
            ];
            record_value(fields, span)
        })
        .collect();
    Value::new(Data::List(Arc::new(items)), span)
}

/// The `sheet` kind.
pub(super) static KIND: &dyn FeatureKind = &SheetKind;

struct SheetKind;

impl FeatureKind for SheetKind {
    fn name(&self) -> &'static str {
        "sheet"
    }
    fn code(&self) -> &'static str {
        "die::sheet"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec!["outline", "thickness", "on"],
            named: vec![
                "punch", "lift", "move", "remove", "bend", "flange", "round", "cover",
            ],
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build(block)
    }
    /// The solid is a piece of its own kind.
    fn piece_kind(&self, field: &str) -> Option<&'static str> {
        (field == "solid").then_some("solid")
    }
    fn summary(&self, record: &Record) -> String {
        let Some(p) = record.model::<SheetPart>() else {
            return String::new();
        };
        let c = p.sheet.check().ok();
        let of = |kind: JunctionType| p.junctions.iter().filter(|j| j.kind == kind).count();
        format!(
            "sheet, mid-surface {} mm², solid {} mm³ ({} triangles), genus {}, junctions of type 1/2/3: {}/{}/{}",
            round(p.area),
            round(p.volume),
            p.solid.face_count(),
            c.map_or(0, |c| c.genus),
            of(JunctionType::One),
            of(JunctionType::Two),
            of(JunctionType::Three)
        )
    }
}
