//! Rounds: the joint where two sheets meet given an inside radius after the fact, the
//! joint picked by a point near it (paper 003's rounding of the edge between two
//! sheets). A joint is a flange's foot (the outline edge it stands on) or a bend's
//! line; rounding it gives that flange or bend its `radius`, so the round is made as
//! theirs are: narrow facets, chords of the mid-surface's arc.

use glam::DVec3;

use super::super::geometry::distance_to_segment;
use super::layout::{nearest_outline_edge, tidy};
use super::{PartProblem, PlateSpec, PICK_REACH};

/// A joint rounded: the flange foot or bend line nearest `at` gets `radius`.
#[derive(Debug, Clone, PartialEq)]
pub struct RoundSpec {
    /// Its name.
    pub name: String,
    /// A point on (or within [`PICK_REACH`] of) the joint, in the outline's view.
    pub at: DVec3,
    /// The inside radius (mm, above 0).
    pub radius: f64,
}

/// A joint a round can pick.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Joint {
    /// The foot of flange `index`.
    Flange(usize),
    /// The line of bend `index`.
    Bend(usize),
}

/// `spec` with each of its rounds given to the joint it picks, or why one cannot be.
pub(super) fn apply_rounds(spec: &PlateSpec) -> Result<PlateSpec, PartProblem> {
    let mut out = spec.clone();
    let joints = joints(spec);
    for (index, round) in spec.rounds.iter().enumerate() {
        let bad = |why: String| PartProblem::Round { index, why };
        if !(round.radius.is_finite() && round.radius > 0.0) {
            return Err(bad(format!("radius must be above 0, not {}", round.radius)));
        }
        let mut near: Vec<(f64, Joint)> = joints
            .iter()
            .map(|&(joint, a, c)| (distance_to_segment(a, c, round.at), joint))
            .collect();
        near.sort_by(|x, y| x.0.total_cmp(&y.0));
        let Some(&(d, joint)) = near.first() else {
            return Err(bad(
                "finds no joint to round: the part has no flange and no bend".into(),
            ));
        };
        if d > PICK_REACH {
            return Err(bad(format!(
                "finds no joint within {} mm of its point: the nearest, {}, lies {} mm \
                 off",
                tidy(PICK_REACH),
                describe(spec, joint),
                tidy(d)
            )));
        }
        if let Some(&(d2, other)) = near.get(1) {
            if d2 - d < 1e-9 {
                return Err(bad(format!(
                    "picks no one joint: its point lies as near {} as {}",
                    describe(spec, joint),
                    describe(spec, other)
                )));
            }
        }
        let radius = match joint {
            Joint::Flange(i) => {
                let flange = &mut out.flanges[i];
                if flange.thickness.is_some() {
                    return Err(bad(format!(
                        "picks {}, a flange of its own thickness: a separate piece joined at \
                         the edge, not bent from the plate, so it has no bend to round",
                        describe(spec, joint)
                    )));
                }
                &mut flange.radius
            }
            Joint::Bend(i) => &mut out.bends[i].radius,
        };
        if *radius > 0.0 {
            return Err(bad(format!(
                "picks {}, which is rounded already, on a {} mm radius",
                describe(spec, joint),
                tidy(*radius)
            )));
        }
        *radius = round.radius;
    }
    Ok(out)
}

/// Every joint of `spec` with the segment it runs along on the flat plate.
fn joints(spec: &PlateSpec) -> Vec<(Joint, DVec3, DVec3)> {
    let k = spec.outline.len();
    let mut out = Vec::new();
    for (i, flange) in spec.flanges.iter().enumerate() {
        // A flange all round the outline is sharp (its strips are joined at corners):
        // it has no one foot to round.
        if flange.around || flange.on.is_some() {
            continue;
        }
        let foot = flange.span.or_else(|| {
            nearest_outline_edge(&spec.outline, flange.near)
                .map(|(_, e)| (spec.outline[e], spec.outline[(e + 1) % k]))
        });
        if let Some((a, c)) = foot {
            out.push((Joint::Flange(i), a, c));
        }
    }
    for (i, bend) in spec.bends.iter().enumerate() {
        out.push((Joint::Bend(i), bend.from, bend.to));
    }
    out
}

/// A joint as a designer names it.
fn describe(spec: &PlateSpec, joint: Joint) -> String {
    match joint {
        Joint::Flange(i) => format!("the foot of flange `{}`", spec.flanges[i].name),
        Joint::Bend(i) => format!("the line of bend `{}`", spec.bends[i].name),
    }
}
