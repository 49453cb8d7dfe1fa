//! The plate laid out flat on its working plane, before anything is bent: its outline
//! (corners added where a flange's span or a bend line ends), the loops inside it
//! (holes, lifted regions) and the checks that they fit, and the rings they put on the
//! sheet model.

use glam::{DVec2, DVec3};

use super::super::geometry::{distance_to_segment, newell, MidSurface};
use super::super::topology::{FaceId, Sheet, TopologyError, VertexId};
use crate::geom::tessellate::triangulate_loops;
use crate::geom::trimmed::polygon_winding;

/// The edge of the closed polygon `outline` nearest `p` (edge `i` runs from point `i`
/// to the next), with its distance from `p`; `None` for an outline of no points.
pub(super) fn nearest_outline_edge(outline: &[DVec3], p: DVec3) -> Option<(f64, usize)> {
    let k = outline.len();
    (0..k)
        .map(|i| (distance_to_segment(outline[i], outline[(i + 1) % k], p), i))
        .min_by(|x, y| x.0.total_cmp(&y.0))
}

/// Puts `p` into the outline as a corner of the edge nearest it (unless it is a corner
/// already) and returns it as placed. Refused when it lies off the outline.
pub(super) fn add_corner(outline: &mut Vec<DVec3>, p: DVec3) -> Result<DVec3, String> {
    let k = outline.len();
    let (d, nearest) =
        nearest_outline_edge(outline, p).ok_or_else(|| "finds no edge".to_string())?;
    if d > SPAN_TOLERANCE {
        return Err(format!(
            "must end on the outline, but ({}, {}, {}) is {} mm off it",
            tidy(p.x),
            tidy(p.y),
            tidy(p.z),
            tidy(d)
        ));
    }
    let (a, c) = (outline[nearest], outline[(nearest + 1) % k]);
    for corner in [a, c] {
        if corner.distance(p) <= SPAN_TOLERANCE {
            return Ok(corner);
        }
    }
    let along = c - a;
    let q = a + ((p - a).dot(along) / along.length_squared()) * along;
    outline.insert(nearest + 1, q);
    Ok(q)
}
/// Whether the open segment from `a` to `c` crosses the polygon's boundary (touching
/// it only at its ends, on corners, is not crossing) or runs outside it.
pub(super) fn crosses_outline(outline: &[DVec2], a: DVec2, c: DVec2) -> bool {
    let k = outline.len();
    let near = |p: DVec2, q: DVec2| p.distance(q) < 1e-9;
    for i in 0..k {
        let (p, q) = (outline[i], outline[(i + 1) % k]);
        if near(p, a) || near(p, c) || near(q, a) || near(q, c) {
            continue;
        }
        let d = c - a;
        let e = q - p;
        let denom = d.perp_dot(e);
        if denom.abs() < 1e-12 {
            continue;
        }
        let t = (p - a).perp_dot(e) / denom;
        let u = (p - a).perp_dot(d) / denom;
        if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
            return true;
        }
    }
    polygon_winding(outline, 0.5 * (a + c)) == 0
}
/// The part of the plate (a side split off by bends) whose outline holds every point
/// of `flat`, and a corner of it to bridge a ring from.
pub(super) fn part_holding(
    sheet: &Sheet,
    mid: &MidSurface,
    frame: &Frame,
    parts: &[FaceId],
    flat: &[DVec2],
) -> Result<(FaceId, VertexId), String> {
    for &part in parts {
        let corners = sheet.brep.outer_vertices(part).map_err(|e| e.to_string())?;
        let outline: Vec<DVec2> = corners
            .iter()
            .filter_map(|&v| mid.point(v))
            .map(|p| frame.flat(p))
            .collect();
        if flat.iter().all(|&q| polygon_winding(&outline, q) != 0) {
            return Ok((part, corners[0]));
        }
    }
    if parts.len() > 1 {
        Err("crosses a bend line, or is not inside the outline".into())
    } else {
        Err("is not inside the outline".into())
    }
}
/// Adds `flat`, a new loop inside the plate (a hole or a lifted region), to the plate's
/// loops: refused when a point of it lies outside the outline, when it crosses the
/// outline or another loop, or when it lies inside another loop or holds one.
pub(super) fn add_loop(
    outline: &[DVec2],
    loops: &mut Vec<Vec<DVec2>>,
    flat: Vec<DVec2>,
) -> Result<(), String> {
    if flat.iter().any(|&q| polygon_winding(outline, q) == 0) {
        return Err("is not inside the outline".into());
    }
    for other in &loops[1..] {
        if other.iter().any(|&q| polygon_winding(&flat, q) != 0)
            || flat.iter().any(|&q| polygon_winding(other, q) != 0)
        {
            return Err("lies inside another hole or lifted region, or holds one".into());
        }
    }
    let mut trial = loops.clone();
    trial.push(flat);
    if triangulate_loops(&trial).is_err() {
        return Err("crosses the outline or another hole or lifted region".into());
    }
    *loops = trial;
    Ok(())
}
/// Places the ring a punch or region just made on side `top` (its last loop, which
/// runs against the outline: clockwise) at `ring` (counter-clockwise).
pub(super) fn place_ring(
    sheet: &Sheet,
    mid: &mut MidSurface,
    top: FaceId,
    ring: &[DVec3],
) -> Result<Vec<VertexId>, TopologyError> {
    let b = &sheet.brep;
    let loops = b.loops_of(top)?;
    // `punch` and `region` leave the new ring last (`lkemr` appends it).
    let last = *loops
        .last()
        .ok_or_else(|| TopologyError::Invalid(format!("face {} has no loop", top.0)))?;
    let vertices: Vec<VertexId> = b
        .loop_halves(last)?
        .into_iter()
        .map(|h| b.vertex(h))
        .collect::<Result<_, _>>()?;
    for (&v, &p) in vertices.iter().zip(ring.iter().rev()) {
        mid.place(sheet, v, p)?;
    }
    Ok(vertices)
}
/// The counter-clockwise polygon `ring` (seen along `n`) with every edge moved inward
/// by `by`, its corners where the moved edges meet; `None` when an edge would turn
/// round (the polygon too small for the inset).
pub(super) fn inset(ring: &[DVec3], n: DVec3, by: f64) -> Option<Vec<DVec3>> {
    if by == 0.0 {
        return Some(ring.to_vec());
    }
    let k = ring.len();
    let inward = |i: usize| n.cross(ring[(i + 1) % k] - ring[i]).normalize_or_zero();
    let out: Vec<DVec3> = (0..k)
        .map(|i| {
            let (a, c) = (inward((i + k - 1) % k), inward(i));
            let denom = 1.0 + a.dot(c);
            if denom < 1e-9 {
                ring[i] + by * c
            } else {
                ring[i] + by * (a + c) / denom
            }
        })
        .collect();
    // Each edge keeps its direction.
    let keeps = (0..k).all(|i| {
        let before = ring[(i + 1) % k] - ring[i];
        let after = out[(i + 1) % k] - out[i];
        before.dot(after) > 0.0
    });
    keeps.then_some(out)
}
/// How far a flange's `from` and `to` may lie off the outline's edge (mm).
pub const SPAN_TOLERANCE: f64 = 0.01;
/// Puts the ends of a flange on part of an edge, `from` and `to`, into the outline as
/// vertices of the edge nearest their midpoint (where they are not corners already),
/// and returns a point on the part between them. Refused when they do not lie on one
/// edge or are too close together.
pub(super) fn split_outline(
    outline: &mut Vec<DVec3>,
    from: DVec3,
    to: DVec3,
) -> Result<DVec3, String> {
    let k = outline.len();
    let middle = 0.5 * (from + to);
    let (_, nearest) =
        nearest_outline_edge(outline, middle).ok_or_else(|| "finds no edge".to_string())?;
    let (a, c) = (outline[nearest], outline[(nearest + 1) % k]);
    let along = c - a;
    let length = along.length();
    let at = |p: DVec3| ((p - a).dot(along) / (length * length)).clamp(0.0, 1.0);
    for p in [from, to] {
        if distance_to_segment(a, c, p) > SPAN_TOLERANCE {
            return Err(format!(
                "`from` and `to` must lie on one edge of the outline, but ({}, {}, {}) is \
                 {} mm off the edge nearest them",
                tidy(p.x),
                tidy(p.y),
                tidy(p.z),
                tidy(distance_to_segment(a, c, p))
            ));
        }
    }
    let (s, e) = (at(from).min(at(to)), at(from).max(at(to)));
    if (e - s) * length < 10.0 * SPAN_TOLERANCE {
        return Err("`from` and `to` lie too close together on the edge".into());
    }
    // The new corners, in the outline's order along the edge; ends at a corner are kept.
    let inner: Vec<DVec3> = [s, e]
        .into_iter()
        .filter(|&u| u * length > SPAN_TOLERANCE && (1.0 - u) * length > SPAN_TOLERANCE)
        .map(|u| a + u * along)
        .collect();
    let count = inner.len();
    outline.splice(nearest + 1..nearest + 1, inner);
    debug_assert!(outline.len() == k + count);
    Ok(a + 0.5 * (s + e) * along)
}
/// `points` running counter-clockwise seen from along `n`.
pub(super) fn counter_clockwise(points: &[DVec3], n: DVec3) -> Vec<DVec3> {
    let mut out = points.to_vec();
    if newell(&out).dot(n) < 0.0 {
        out.reverse();
    }
    out
}
/// A plane's 2-D coordinates.
pub(super) struct Frame {
    origin: DVec3,
    u: DVec3,
    w: DVec3,
}
impl Frame {
    pub(super) fn new(origin: DVec3, n: DVec3) -> Frame {
        let u = n.any_orthonormal_vector();
        Frame {
            origin,
            u,
            w: n.cross(u),
        }
    }

    pub(super) fn flat(&self, p: DVec3) -> DVec2 {
        DVec2::new((p - self.origin).dot(self.u), (p - self.origin).dot(self.w))
    }
}
/// A coordinate for a message: to 0.001 mm, without trailing zeros.
pub(super) fn tidy(x: f64) -> String {
    let s = format!("{:.3}", x);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}
