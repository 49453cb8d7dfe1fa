//! Closed corners: two flanges on the two outline edges at one corner of the plate,
//! joined where their planes cross, so three sheets (the plate and the two flanges)
//! meet at the corner's vertex (one of the paper's open problems). Return flanges on two
//! such flanges are joined the same way at the flanges' shared far corner, so four
//! sheets meet there (a brim round a tray's rim).
//!
//! Each flange is cut on the mitre line, the line through the corner where the two
//! flanges' planes cross; the later flange is added on a run of picked edges that goes
//! from the plate's edge on up the earlier flange's end (paper 003, section 4.2: Skze
//! at the corner, then Smev and Smel), so the two share that edge and no thickness
//! face reaches the corner. The solid's vertices there are where three offset planes
//! meet (the plate's side and the two flanges'), one inside and one outside.

use glam::DVec3;

use super::layout::tidy;

/// How close to square, as the sine of the angle between them, two flanges' planes
/// must be at least to cross on a line (below it they stand in one plane).
const CROSSING: f64 = 1e-3;

/// How far up each flange the mitre line must run, as the cosine of its angle to the
/// flange's rise, at least (below it the line runs along the plate's edge or back into
/// the plate).
const RISING: f64 = 1e-2;

/// Two flanges must stand this high at the corner to within this (mm, and relative).
const SAME_HEIGHT: f64 = 1e-6;

/// A flange as a corner sees it: the edge it stands on and how it rises from it.
#[derive(Debug, Clone, Copy)]
pub(super) struct Standing {
    /// The edge's ends, in the order the plate's top runs it.
    pub from: DVec3,
    pub to: DVec3,
    /// The direction it rises in, away from the edge in its plane (unit).
    pub rise: DVec3,
    /// How far it reaches from the edge along `rise` (mm).
    pub height: f64,
}

impl Standing {
    /// The normal of the flange's plane (unit).
    fn normal(&self) -> DVec3 {
        (self.to - self.from).cross(self.rise).normalize_or_zero()
    }
}

/// Where the far corner of two flanges joined at the plate's corner `corner` lies: on
/// the mitre line, at the flanges' common height. `n` says which way along the line is
/// up (the plate's normal). Refused,
/// with the reason, when the flanges stand in one plane, when the mitre line does not
/// run up both of them, or when they stand at different heights above the plate there
/// (their far edges would not meet).
pub(super) fn mitre_top(
    corner: DVec3,
    one: &Standing,
    other: &Standing,
    n: DVec3,
) -> Result<DVec3, String> {
    let line = one.normal().cross(other.normal());
    if line.length() < CROSSING {
        return Err(
            "they stand in one plane there, so they have no mitre line to be joined on".into(),
        );
    }
    let line = if line.dot(n) < 0.0 {
        -line.normalize()
    } else {
        line.normalize()
    };
    let (up_one, up_other) = (line.dot(one.rise), line.dot(other.rise));
    if up_one < RISING || up_other < RISING {
        return Err(
            "the line where their planes cross does not run up both of them: it lies along \
             the plate"
                .into(),
        );
    }
    // Along the mitre line to each flange's far edge.
    let (reach_one, reach_other) = (one.height / up_one, other.height / up_other);
    if (reach_one - reach_other).abs() > SAME_HEIGHT * reach_one.max(reach_other).max(1.0) {
        return Err(format!(
            "they stand {} mm and {} mm above the plate at the corner, and joined flanges \
             must stand equally high there so their far edges meet",
            tidy(reach_one * line.dot(n)),
            tidy(reach_other * line.dot(n)),
        ));
    }
    Ok(corner + 0.5 * (reach_one + reach_other) * line)
}

/// Where the far corner of two return flanges joined at `corner` lies: the far corner
/// shared by the flanges they stand on (a brim round a tray's rim, say). Returns that
/// stand in one plane there (a level brim on two walls) meet on the line halving the
/// angle between their rises, the brim's corner in its plane; others on the mitre line
/// where their planes cross, as [`mitre_top`]. Refused, with the reason, when they
/// stand back to back, when the line does not run up both, or when they reach
/// different heights there.
pub(super) fn return_mitre(
    corner: DVec3,
    one: &Standing,
    other: &Standing,
) -> Result<DVec3, String> {
    let up = one.rise + other.rise;
    if one.normal().cross(other.normal()).length() >= CROSSING {
        return mitre_top(corner, one, other, up);
    }
    let line = up.normalize_or_zero();
    let rising = line.dot(one.rise);
    if rising < RISING {
        return Err(
            "they stand in one plane, back to back, so they have no corner to be joined at".into(),
        );
    }
    if (one.height - other.height).abs() > SAME_HEIGHT * one.height.max(other.height).max(1.0) {
        return Err(format!(
            "they stand in one plane and reach {} mm and {} mm from their edges, and joined \
             flanges in one plane must reach equally far so their far edges meet",
            tidy(one.height),
            tidy(other.height),
        ));
    }
    Ok(corner + 0.5 * (one.height + other.height) / rising * line)
}
