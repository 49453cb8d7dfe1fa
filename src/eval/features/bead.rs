//! `bead name { ... }`: a draw bead on a blankholder, read into [`crate::die::bead`].
//!
//! ```text
//! import "std/beads" as beads
//! bead wheel_arch {
//!     binder = binder                  // the blankholder it sits on
//!     line = sketch(top) { ... }       // centre line in the top view
//!     profile = beads.round(height: 6 mm)   // cross-section, feet at height 0
//!     taper = 30 mm                    // run-out length at both ends (default 0)
//!     spacing = 10 mm                  // key sections along the bead (default 10 mm)
//!     line_spacing = 15 mm             // line-bead points (default 15 mm)
//!     force = 250                      // restraining force of the line bead, N/mm
//! }
//! ```

use std::sync::Arc;

use crate::diag::Diagnostic;
use crate::die::bead::{self as bd, BeadSpec, Binder, Problem};
use crate::syntax::Span;

use super::super::builtins::{as_number, type_error};
use super::super::value::{Data, Feature, Quantity, Value};
use super::{count, feature_error, feature_value, mm, Block};

const KIND: &str = "bead";

/// Builds the bead of `block`.
pub fn build(block: &Block) -> Result<Value, Diagnostic> {
    block.check_fields(
        &[
            "binder",
            "line",
            "profile",
            "taper",
            "spacing",
            "line_spacing",
            "force",
        ],
        &[],
    )?;
    let binder_field = block.get("binder").ok_or_else(|| {
        block.missing(
            "binder",
            "name the blankholder the bead sits on: `binder = my_binder`",
        )
    })?;
    let binder = match &binder_field.value.data {
        Data::Record(r) => match &r.feature {
            Some(Feature::Blankholder(b)) => b.clone(),
            _ => {
                return Err(type_error(
                    &binder_field.value,
                    "`binder` of a bead",
                    "a blankholder",
                ))
            }
        },
        _ => {
            return Err(type_error(
                &binder_field.value,
                "`binder` of a bead",
                "a blankholder",
            ))
        }
    };
    let line_field = block.get("line").ok_or_else(|| {
        block.missing("line", "draw the bead's centre line in the top view: `line = sketch(top) { from ...; line to ... }`")
    })?;
    let centre = match &line_field.value.data {
        Data::Sketch(s) if s.view == super::super::sketch::View::Top => s.curve.clone(),
        Data::Curve2(c) => (**c).clone(),
        _ => {
            return Err(type_error(
                &line_field.value,
                "`line` of a bead",
                "a top-view sketch of the centre line",
            ));
        }
    };
    let profile_field = block.get("profile").ok_or_else(|| {
        block.missing("profile", "give the cross-section: `profile = beads.round(height: 6 mm)` (import \"std/beads\" as beads)")
    })?;
    let profile = match &profile_field.value.data {
        Data::Sketch(s) => s.curve.clone(),
        Data::Curve2(c) => (**c).clone(),
        _ => {
            return Err(type_error(
                &profile_field.value,
                "`profile` of a bead",
                "a bead cross-section sketch such as `beads.round(height: 6 mm)`",
            ));
        }
    };
    let taper = block.length_or("taper", 0.0)?;
    let spacing = block.length_or("spacing", 10.0)?;
    let line_spacing = block.length_or("line_spacing", 15.0)?;
    let force = match block.get("force") {
        Some(f) => Some((
            as_number(&f.value, "`force` of a bead (N/mm)")?,
            f.value.span,
        )),
        None => None,
    };
    let patches: Vec<_> = binder.patches.iter().map(|p| &p.surface).collect();
    let map = Binder::new(patches, &binder.inner_outline);
    let spec = BeadSpec {
        centre,
        profile,
        taper,
        spacing,
        line_spacing,
    };
    let bead = bd::build(&map, &spec)
        .map_err(|p| problem_diag(block, &p, line_field.value.span, profile_field.value.span))?;
    Ok(output(block, bead, line_spacing, force.map(|f| f.0)))
}

fn problem_diag(block: &Block, p: &Problem, line: Span, profile: Span) -> Diagnostic {
    match p {
        Problem::LeavesBinder { at } => feature_error(
            KIND,
            format!("the bead `{}` leaves the binder near ({:.1}, {:.1})", block.name, at.x, at.y),
            line,
            "this centre line",
            "keep the centre line, and the bead's width around it, over the blankholder in the top view",
        ),
        Problem::CrossesOpening { at } => feature_error(
            KIND,
            format!("the bead `{}` crosses the punch opening near ({:.1}, {:.1})", block.name, at.x, at.y),
            line,
            "this centre line",
            "a bead runs on the binder, outside the punch opening: move the centre line outwards or narrow the profile",
        ),
        Problem::ProfileFeet => feature_error(
            KIND,
            "a bead profile must start and end on the binder, at height 0",
            profile,
            "this profile",
            "draw the cross-section from (-w, 0) over the crest to (w, 0), or use `std/beads`",
        ),
        Problem::BadLength(what) => feature_error(
            KIND,
            format!("the bead's {what} must be a positive length"),
            block.span,
            "in this bead",
            "sections every 10 mm and line-bead points every 15 mm are common",
        ),
        Problem::Kernel(e) => feature_error(
            KIND,
            format!("the bead `{}` cannot be built: {e}", block.name),
            line,
            "this bead",
            "check the centre line for a doubling back and the profile for degenerate input",
        ),
    }
}

/// The feature record: `surface`, `centre` (on the binder), `line_bead`, `quality`.
fn output(block: &Block, bead: bd::Bead, spacing: f64, force: Option<f64>) -> Value {
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
    let fields = vec![
        (
            "surface".to_string(),
            Value::new(Data::Surface(Arc::new(bead.surface.clone())), span),
        ),
        (
            "centre".to_string(),
            Value::new(Data::Curve3(Arc::new(bead.centre.clone())), span),
        ),
        (
            "line_bead".to_string(),
            super::record_value(line_bead, span),
        ),
    ];
    let q = bead.quality;
    let quality = vec![
        ("foot_gap".to_string(), mm(q.foot_gap, span)),
        ("section_error".to_string(), mm(q.section_error, span)),
        ("sections".to_string(), count(q.sections, span)),
        ("length".to_string(), mm(q.length, span)),
    ];
    feature_value(KIND, span, fields, quality, Feature::Bead(Arc::new(bead)))
}
