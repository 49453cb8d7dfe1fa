//! A bend's creases on the flat plate: one line for a sharp bend; for a bend on an
//! inside radius, the edges of its facets, lines parallel to the bend line across a
//! zone centred on it (paper 003, Fig. 14, geometry only, with the radius made of
//! narrow strips as a flange's bend is).
//!
//! The mid-surface of a bend on radius r at thickness t is an arc of radius
//! ρ = r + t/2. Its facets are the arc's chords (each turning at most
//! [`BEND_STEP`](super::strips::BEND_STEP) and lying within
//! [`BEND_TOLERANCE`](super::strips::BEND_TOLERANCE) of the arc), so the flat zone is
//! as wide as the chords together and the sheet does not stretch. The first and last
//! creases turn half a facet's angle (the flat parts are the arc's tangents there), the
//! rest a whole one.

use glam::DVec3;

use super::layout::{add_corner, tidy, Frame, SPAN_TOLERANCE};
use super::strips::facets;
use super::BendSpec;

/// One crease of a bend: a line across the flat plate, between two points on its
/// outline, about which the part to its left turns by `angle`.
#[derive(Debug, Clone)]
pub(super) struct Crease {
    /// The bend it belongs to (its index in the part's bends).
    pub bend: usize,
    /// The line's ends, corners of the outline.
    pub from: DVec3,
    pub to: DVec3,
    /// How far the part to its left turns (radians).
    pub angle: f64,
    /// The name of the part it turns: the bend's facets are `NAME.bend_K`, the part
    /// beyond the last crease `NAME`.
    pub name: String,
}

/// The narrowest facet a bend on a radius may have (mm): narrower ones would put their
/// creases' ends closer together than the outline's corners can be told apart.
const NARROWEST_FACET: f64 = 10.0 * SPAN_TOLERANCE;

/// The creases of bend `index` on the plate's `outline` (its corners gain each
/// crease's ends), for a plate of `thickness` on the plane `frame`. `left` is the
/// direction in the plane to the left of the bend line.
pub(super) fn creases(
    outline: &mut Vec<DVec3>,
    frame: &Frame,
    index: usize,
    bend: &BendSpec,
    thickness: f64,
    n: DVec3,
) -> Result<Vec<Crease>, String> {
    if bend.radius == 0.0 {
        let from = add_corner(outline, bend.from)?;
        let to = add_corner(outline, bend.to)?;
        too_close(from, to)?;
        return Ok(vec![Crease {
            bend: index,
            from,
            to,
            angle: bend.angle,
            name: bend.name.clone(),
        }]);
    }
    // The bend line's ends must lie on the outline, but are not corners of it: the
    // creases lie either side.
    let from = add_corner(&mut outline.clone(), bend.from)?;
    let to = add_corner(&mut outline.clone(), bend.to)?;
    too_close(from, to)?;
    let rho = bend.radius + 0.5 * thickness;
    let turn = bend.angle.abs();
    let widest = (rho * turn / NARROWEST_FACET).floor().max(1.0) as usize;
    let k = facets(turn, rho).min(widest).max(1);
    let chord = 2.0 * rho * (0.5 * turn / k as f64).sin();
    if chord < NARROWEST_FACET {
        return Err(format!(
            "radius {} mm is too small for a bend on a radius: its facets would be under \
             {} mm wide; leave the radius out for a sharp bend",
            tidy(bend.radius),
            tidy(NARROWEST_FACET)
        ));
    }
    let along = (to - from).normalize();
    let left = n.cross(along);
    let step = bend.angle / k as f64;
    let half = 0.5 * chord * k as f64;
    let mut out = Vec::with_capacity(k + 1);
    for i in 0..=k {
        let offset = -half + i as f64 * chord;
        let (a, c) = across(outline, frame, from + offset * left, along).ok_or_else(|| {
            format!(
                "zone ({} mm wide for radius {} mm) runs off the plate: the line {} mm \
                 {} of the bend line does not cross the plate from edge to edge",
                tidy(2.0 * half),
                tidy(bend.radius),
                tidy(offset.abs()),
                if offset < 0.0 { "right" } else { "left" },
            )
        })?;
        let (a, c) = (add_corner(outline, a)?, add_corner(outline, c)?);
        too_close(a, c)?;
        let angle = if i == 0 || i == k { 0.5 * step } else { step };
        let name = if i == k {
            bend.name.clone()
        } else {
            format!("{}.bend_{}", bend.name, i + 1)
        };
        out.push(Crease {
            bend: index,
            from: a,
            to: c,
            angle,
            name,
        });
    }
    Ok(out)
}

/// A crease's ends must lie well apart.
fn too_close(from: DVec3, to: DVec3) -> Result<(), String> {
    if from.distance(to) < 10.0 * SPAN_TOLERANCE {
        return Err("`from` and `to` lie too close together".into());
    }
    Ok(())
}

/// Where the line through `p` along `along` enters and leaves the outline (in that
/// order along the line), or `None` when it meets the outline at other than two
/// points.
fn across(outline: &[DVec3], frame: &Frame, p: DVec3, along: DVec3) -> Option<(DVec3, DVec3)> {
    let (p2, d2) = (frame.flat(p), frame.flat(p + along) - frame.flat(p));
    let k = outline.len();
    let mut hits: Vec<(f64, DVec3)> = Vec::new();
    for i in 0..k {
        let (a, c) = (outline[i], outline[(i + 1) % k]);
        let (a2, c2) = (frame.flat(a), frame.flat(c));
        let e = c2 - a2;
        let denom = d2.perp_dot(e);
        if denom.abs() < 1e-12 * e.length().max(1.0) {
            continue;
        }
        let s = (a2 - p2).perp_dot(e) / denom;
        let u = (a2 - p2).perp_dot(d2) / denom;
        if (0.0..=1.0).contains(&u) {
            let q = a + u * (c - a);
            if hits.iter().all(|&(_, h)| h.distance(q) > 1e-9) {
                hits.push((s, q));
            }
        }
    }
    hits.sort_by(|x, y| x.0.total_cmp(&y.0));
    match hits[..] {
        [(_, a), (_, c)] => Some((a, c)),
        _ => None,
    }
}
