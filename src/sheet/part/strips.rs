//! A flange's strips: the facets of its bend on an inside radius, then the straight
//! flange, as where each strip's far edge lies from the edge the flange stands on.

use glam::DVec3;

use super::FlangeSpec;

/// The largest angle one facet of a bend turns through.
pub(super) const BEND_STEP: f64 = std::f64::consts::PI / 12.0;
/// How far a bend's facets may lie inside its arc (mm).
pub(super) const BEND_TOLERANCE: f64 = 0.01;
/// Where the far edge of each strip of a flange lies, from the edge it stands on
/// (`out` in the plate's plane away from it, `n` the plate's normal): first the facets
/// of its bend, as chords of the mid-surface's arc (inside radius plus half the
/// thickness) within [`BEND_TOLERANCE`] and [`BEND_STEP`], then the straight flange,
/// `height` long, at `angle` to the plate.
pub(super) fn flange_reaches(
    flange: &FlangeSpec,
    thickness: f64,
    out: DVec3,
    n: DVec3,
) -> Vec<DVec3> {
    let dir = flange.angle.cos() * out + flange.angle.sin() * n;
    let rho = flange.radius + 0.5 * flange.thickness.unwrap_or(thickness);
    let steps = if flange.radius > 0.0 && flange.angle > 0.0 {
        facets(flange.angle, rho)
    } else {
        0
    };
    let arc = |phi: f64| rho * (phi.sin() * out + (1.0 - phi.cos()) * n);
    let mut reaches: Vec<DVec3> = (1..=steps)
        .map(|i| arc(flange.angle * i as f64 / steps as f64))
        .collect();
    let start = reaches.last().copied().unwrap_or(DVec3::ZERO);
    reaches.push(start + flange.height * dir);
    reaches
}
/// The most facets a bend is cut into.
pub(super) const MAX_BEND_FACETS: usize = 64;

/// How many facets a bend through `angle` (radians, above 0) on a mid-surface radius
/// `rho` is cut into: each turns at most [`BEND_STEP`] and lies within
/// [`BEND_TOLERANCE`] of the arc, and there are at most [`MAX_BEND_FACETS`].
pub(super) fn facets(angle: f64, rho: f64) -> usize {
    let by_angle = (angle / BEND_STEP).ceil();
    let chord = 2.0 * (1.0 - BEND_TOLERANCE / rho).clamp(-1.0, 1.0).acos();
    let by_sag = (angle / chord.max(1e-3)).ceil();
    by_angle.max(by_sag).min(MAX_BEND_FACETS as f64) as usize
}
