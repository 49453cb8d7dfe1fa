//! Rounds: the joint where two sheets meet given an inside radius after the fact, the
//! joint picked by a point near it (paper 003's rounding of the edge between two
//! sheets). A joint is a flange's foot (the outline edge it stands on) or a bend's
//! line; rounding it gives that flange or bend its `radius`, so the round is made as
//! theirs are: narrow facets, chords of the mid-surface's arc. A joint is also the
//! corner where two walls meet (two flanges joined at a corner of the outline, or a
//! flange run round it): rounding it rounds the outline's corner in plan, and the walls
//! run on round it as strips on the arc's chords, each joined to the next.

use glam::DVec3;

use super::super::geometry::distance_to_segment;
use super::layout::{nearest_outline_edge, tidy};
use super::{FlangeSpec, PartProblem, PlateSpec, PICK_REACH};

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

/// How far (mm) the chords of a corner round in plan stray from its arc: the outline
/// tolerance sketches' arcs are followed within.
const CORNER_TOLERANCE: f64 = 0.05;

/// `spec` with each of its rounds given to the joint it picks, or why one cannot be.
pub(super) fn apply_rounds(spec: &PlateSpec) -> Result<PlateSpec, PartProblem> {
    let mut out = spec.clone();
    for (index, round) in spec.rounds.iter().enumerate() {
        let bad = |why: String| PartProblem::Round { index, why };
        if !(round.radius.is_finite() && round.radius > 0.0) {
            return Err(bad(format!("radius must be above 0, not {}", round.radius)));
        }
        // The joints as the rounds before this one left them.
        let joints = joints(&out);
        if let Some(corner) = wall_corner(&out, &joints, round.at) {
            round_corner(&mut out, corner, round).map_err(bad)?;
            continue;
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

/// A corner of the outline where walls meet: its index, and the flanges whose feet
/// end there (none for a flange run all round).
#[derive(Debug, Clone, Copy, PartialEq)]
struct WallCorner {
    corner: usize,
    flanges: Option<(usize, usize)>,
}

/// The corner where two walls meet that `at` picks: the outline's corner within
/// [`PICK_REACH`] of `at` where two flanges' feet end, `at` as near both feet (it lies
/// off the corner's end of each), or where a flange runs round the outline.
fn wall_corner(
    spec: &PlateSpec,
    joints: &[(Joint, DVec3, DVec3)],
    at: DVec3,
) -> Option<WallCorner> {
    let (d, corner) = spec
        .outline
        .iter()
        .enumerate()
        .map(|(i, p)| (p.distance(at), i))
        .min_by(|x, y| x.0.total_cmp(&y.0))?;
    if d > PICK_REACH {
        return None;
    }
    let c = spec.outline[corner];
    if spec.flanges.iter().any(|f| f.around) {
        return Some(WallCorner {
            corner,
            flanges: None,
        });
    }
    // The flanges whose feet end at the corner, and `at` no nearer either foot than
    // the corner itself.
    let ending: Vec<usize> = joints
        .iter()
        .filter_map(|&(joint, a, b)| match joint {
            Joint::Flange(i)
                if (a.distance(c) < 1e-9 || b.distance(c) < 1e-9)
                    && distance_to_segment(a, b, at) >= d - 1e-9 =>
            {
                Some(i)
            }
            _ => None,
        })
        .collect();
    match ending[..] {
        [i, j] => Some(WallCorner {
            corner,
            flanges: Some((i, j)),
        }),
        _ => None,
    }
}

/// Rounds the outline's corner `corner` in plan on `round`'s radius (its chords
/// within [`CORNER_TOLERANCE`] of the arc), and runs the walls on round it: a flange
/// run all round covers the chords as it expands; two flanges meeting there get a
/// strip on each chord, `ROUND.K`, of their height and angle, joined each to the next.
fn round_corner(spec: &mut PlateSpec, wall: WallCorner, round: &RoundSpec) -> Result<(), String> {
    let k = spec.outline.len();
    let c = spec.outline[wall.corner];
    let (p, q) = (
        spec.outline[(wall.corner + k - 1) % k],
        spec.outline[(wall.corner + 1) % k],
    );
    let (din, dout) = ((c - p).normalize_or_zero(), (q - c).normalize_or_zero());
    let turn = din.angle_between(dout);
    if !(turn > 1e-6 && turn < std::f64::consts::PI - 1e-6) {
        return Err("picks a corner that does not turn".into());
    }
    let r = round.radius;
    let back = r * (turn / 2.0).tan();
    if back >= p.distance(c) - 1e-6 || back >= c.distance(q) - 1e-6 {
        return Err(format!(
            "radius {} mm does not fit the corner: it takes {} mm of each edge",
            tidy(r),
            tidy(back)
        ));
    }
    let (t1, t2) = (c - back * din, c + back * dout);
    // The arc's centre, inside the turn.
    let normal = din.cross(dout).normalize_or_zero();
    let inward = normal.cross(din);
    let centre = t1 + r * inward;
    let chord = 2.0 * (1.0 - CORNER_TOLERANCE / r).clamp(-1.0, 1.0).acos();
    let steps = ((turn / chord.max(1e-3)).ceil() as usize).clamp(1, 64);
    let arc: Vec<DVec3> = (0..=steps)
        .map(|i| {
            let a = turn * i as f64 / steps as f64;
            let from = t1 - centre;
            // Turn `from` by `a` about the normal (Rodrigues, `from` square to it).
            centre + from * a.cos() + normal.cross(from) * a.sin()
        })
        .collect();
    spec.outline
        .splice(wall.corner..=wall.corner, arc.iter().copied());
    let Some((i, j)) = wall.flanges else {
        return Ok(());
    };
    let (fi, fj) = (spec.flanges[i].clone(), spec.flanges[j].clone());
    for f in [&fi, &fj] {
        if f.radius > 0.0 || f.shape.is_some() || f.thickness.is_some() {
            return Err(format!(
                "picks the corner where `{}` and `{}` meet, and `{}` is bent on a radius, \
                 drawn, or of its own thickness: the walls round a corner are sharp strips \
                 of one sheet",
                fi.name, fj.name, f.name
            ));
        }
    }
    if (fi.height - fj.height).abs() > 1e-9 || (fi.angle - fj.angle).abs() > 1e-12 {
        return Err(format!(
            "picks the corner where `{}` and `{}` meet, which stand at different heights or \
             angles: the walls round a corner run on alike",
            fi.name, fj.name
        ));
    }
    // Each flange's foot ends at the arc's end on its edge now: a part-edge flange's
    // end on the corner moves there, a whole-edge flange's point to its shorter edge.
    for f in [i, j] {
        let flange = &mut spec.flanges[f];
        let (on_in, end) = match flange.span {
            Some((a, b)) => {
                let other = if a.distance(c) < 1e-9 { b } else { a };
                let on_in = distance_to_segment(p, c, other) < distance_to_segment(c, q, other);
                (on_in, Some((a, b)))
            }
            None => (
                distance_to_segment(p, c, flange.near) < distance_to_segment(c, q, flange.near),
                None,
            ),
        };
        let tangent = if on_in { t1 } else { t2 };
        match end {
            Some((a, b)) => {
                let moved = |x: DVec3| if x.distance(c) < 1e-9 { tangent } else { x };
                let (a, b) = (moved(a), moved(b));
                flange.span = Some((a, b));
                flange.near = 0.5 * (a + b);
            }
            None => flange.near = 0.5 * (tangent + if on_in { p } else { q }),
        }
    }
    for (n, pair) in arc.windows(2).enumerate() {
        spec.flanges.push(FlangeSpec {
            name: format!("{}.{}", round.name, n + 1),
            near: 0.5 * (pair[0] + pair[1]),
            span: Some((pair[0], pair[1])),
            ..fi.clone()
        });
    }
    Ok(())
}

/// A joint as a designer names it.
fn describe(spec: &PlateSpec, joint: Joint) -> String {
    match joint {
        Joint::Flange(i) => format!("the foot of flange `{}`", spec.flanges[i].name),
        Joint::Bend(i) => format!("the line of bend `{}`", spec.bends[i].name),
    }
}
