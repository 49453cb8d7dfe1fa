//! Flanges along a run of the outline's edges: from a point on one edge to a point on
//! another, counter-clockwise (the plate on the left, seen along the normal), or all
//! round the outline. Each edge of the run carries one strip, a flange of its own on
//! (part of) that edge, and neighbouring strips are joined at the corner between them
//! on their mitre line ([`super::corners`]), so a wall along a filleted outline is a
//! drawn tray's wall with round corners in plan, its strips the arc's chords. A return
//! flange on a run stands on each of its strips, `NAME.K` on `RUN.K`, joined at the
//! same corners (a brim round a tray's rim).

use glam::DVec3;

use super::layout::{counter_clockwise, nearest_outline_edge, tidy, SPAN_TOLERANCE};
use super::{FlangeSpec, PartProblem, PlateSpec};

/// `spec` with every flange along a run of edges given as one strip per edge, named
/// `NAME.K` (K from 1 along the run), and for each flange of the result the index of
/// the flange it came from.
pub(super) fn expand_runs(spec: &PlateSpec) -> Result<(PlateSpec, Vec<usize>), PartProblem> {
    let outline = counter_clockwise(&spec.outline, spec.normal.normalize_or_zero());
    let mut flanges = Vec::with_capacity(spec.flanges.len());
    let mut origin = Vec::with_capacity(spec.flanges.len());
    for (index, flange) in spec.flanges.iter().enumerate() {
        let bad = |why: String| PartProblem::Flange { index, why };
        if let Some(parent) = &flange.on {
            // A return on a run: one strip on each of the run's strips, joined at the
            // corners between them as the run's strips are.
            let on_run: Vec<String> = (1..)
                .map(|k| format!("{parent}.{k}"))
                .take_while(|name| flanges.iter().any(|f: &FlangeSpec| &f.name == name))
                .collect();
            let named = flanges.iter().any(|f: &FlangeSpec| &f.name == parent);
            if named || on_run.is_empty() {
                flanges.push(flange.clone());
                origin.push(index);
                continue;
            }
            for (k, strip) in on_run.into_iter().enumerate() {
                flanges.push(FlangeSpec {
                    name: format!("{}.{}", flange.name, k + 1),
                    on: Some(strip),
                    ..flange.clone()
                });
                origin.push(index);
            }
            continue;
        }
        let strips = if flange.around {
            (0..outline.len())
                .map(|i| (outline[i], outline[(i + 1) % outline.len()]))
                .collect()
        } else {
            match flange.span {
                Some((from, to)) => run(&outline, from, to).map_err(bad)?,
                None => Vec::new(),
            }
        };
        if strips.len() < 2 {
            flanges.push(flange.clone());
            origin.push(index);
            continue;
        }
        if flange.radius > 0.0 || flange.shape.is_some() {
            return Err(bad(
                "runs along several edges, so it must be sharp and of `height` (no `radius` \
                 or `shape`): its strips are joined at the corners between them"
                    .into(),
            ));
        }
        for (k, (a, c)) in strips.into_iter().enumerate() {
            flanges.push(FlangeSpec {
                name: format!("{}.{}", flange.name, k + 1),
                near: 0.5 * (a + c),
                span: Some((a, c)),
                around: false,
                ..flange.clone()
            });
            origin.push(index);
        }
    }
    Ok((
        PlateSpec {
            flanges,
            ..spec.clone()
        },
        origin,
    ))
}

/// The pieces of the outline's edges from `from` to `to`, counter-clockwise, when the
/// two lie on different edges (one piece when on one edge: a flange on part of it).
fn run(outline: &[DVec3], from: DVec3, to: DVec3) -> Result<Vec<(DVec3, DVec3)>, String> {
    let k = outline.len();
    let edge = |i: usize| (outline[i % k], outline[(i + 1) % k]);
    // Where a point lies on the outline: the edge and how far along it (0 to 1). A
    // point on a corner is taken at the start of the edge leaving it when `leaving`,
    // else at the end of the edge arriving there.
    let place = |p: DVec3, leaving: bool| -> Result<(usize, f64), String> {
        let (d, i) = nearest_outline_edge(outline, p).ok_or_else(|| "finds no edge".to_string())?;
        if d > SPAN_TOLERANCE {
            return Err(format!(
                "`from` and `to` must lie on the outline, but ({}, {}, {}) is {} mm off it",
                tidy(p.x),
                tidy(p.y),
                tidy(p.z),
                tidy(d)
            ));
        }
        if let Some(c) = (0..k).find(|&c| outline[c].distance(p) <= SPAN_TOLERANCE) {
            return Ok(if leaving {
                (c, 0.0)
            } else {
                ((c + k - 1) % k, 1.0)
            });
        }
        let (a, c) = edge(i);
        Ok((i, (p - a).dot(c - a) / (c - a).length_squared()))
    };
    let (i, u) = place(from, true)?;
    let (j, v) = place(to, false)?;
    if i == j && u < v {
        return Ok(vec![(from, to)]);
    }
    let point = |e: usize, t: f64| {
        let (a, c) = edge(e);
        a + t * (c - a)
    };
    let mut pieces = vec![(point(i, u), edge(i).1)];
    let mut e = (i + 1) % k;
    while e != j {
        pieces.push(edge(e));
        e = (e + 1) % k;
    }
    pieces.push((edge(j).0, point(j, v)));
    // A piece shorter than the tolerance (an end on a corner) is no strip.
    pieces.retain(|(a, c)| a.distance(*c) > SPAN_TOLERANCE);
    Ok(pieces)
}
