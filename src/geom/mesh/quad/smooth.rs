//! Smoothing of the inner nodes (paper 004 stops before it; CAE engineers expect it):
//! each node not on the region's boundary moved to the mean of the centres of the
//! elements round it, the move kept only where the worst of those elements stays
//! above its floor (never folding an element, never making a good one poor) or where
//! it mends a folded one. Then each inner node of a poor element (scaled Jacobian below
//! [`POOR`]) is moved where the worst of its elements is best, by a compass search:
//! centroid smoothing evens a mesh out, but cannot pull a node out of a sliver its
//! neighbours pin it in.

use glam::DVec2;

use super::quality::scaled_jacobian_2d;

/// The worst scaled Jacobian a move may leave among a node's elements, unless they were
/// worse before it.
const FLOOR: f64 = 0.3;

/// Elements poorer than this (scaled Jacobian) have their inner nodes optimised.
pub const POOR: f64 = 0.5;

/// Sweeps of the compass search over the poor elements' nodes.
const SWEEPS: usize = 4;

/// Halvings of a compass search's step before it stops.
const HALVINGS: usize = 8;

/// Moves every node of `points` from `fixed` on (the first `fixed` are the boundary's)
/// towards the centre of its elements, `passes` times over.
pub fn smooth(
    points: &mut [DVec2],
    fixed: usize,
    quads: &[[u32; 4]],
    triangles: &[[u32; 3]],
    passes: usize,
) {
    if passes == 0 {
        return;
    }
    let elements: Vec<&[u32]> = quads
        .iter()
        .map(|q| q.as_slice())
        .chain(triangles.iter().map(|t| t.as_slice()))
        .collect();
    // Each node's elements, by a counting sort.
    let mut offsets = vec![0usize; points.len() + 1];
    for e in &elements {
        for &v in e.iter() {
            offsets[v as usize + 1] += 1;
        }
    }
    for i in 0..points.len() {
        offsets[i + 1] += offsets[i];
    }
    let mut slot = offsets.clone();
    let mut star = vec![0usize; offsets[points.len()]];
    for (k, e) in elements.iter().enumerate() {
        for &v in e.iter() {
            star[slot[v as usize]] = k;
            slot[v as usize] += 1;
        }
    }
    // An element's corners, copied to the stack (no allocation per look).
    let corners_of = |points: &[DVec2], k: usize| {
        let e = elements[k];
        let mut corners = [DVec2::ZERO; 4];
        for (c, &v) in corners.iter_mut().zip(e) {
            *c = points[v as usize];
        }
        (corners, e.len())
    };
    let jacobian_of = |points: &[DVec2], k: usize| {
        let (corners, n) = corners_of(points, k);
        scaled_jacobian_2d(&corners[..n])
    };
    // Each element's scaled Jacobian, kept up to date as its nodes move: a node's
    // elements before a move are read from here, not judged again (an element changes
    // only when one of its own nodes moves, and every move updates that node's star).
    let mut jacobians: Vec<f64> = (0..elements.len())
        .map(|k| jacobian_of(points, k))
        .collect();
    let mut moved_jacobians: Vec<f64> = Vec::new();
    for _ in 0..passes {
        for v in fixed..points.len() {
            let around = &star[offsets[v]..offsets[v + 1]];
            if around.is_empty() {
                continue;
            }
            let centre = around
                .iter()
                .map(|&k| {
                    let e = elements[k];
                    e.iter().map(|&w| points[w as usize]).sum::<DVec2>() / e.len() as f64
                })
                .sum::<DVec2>()
                / around.len() as f64;
            let before = least_of(around, &jacobians);
            let old = points[v];
            points[v] = centre;
            moved_jacobians.clear();
            moved_jacobians.extend(around.iter().map(|&k| jacobian_of(points, k)));
            let after = moved_jacobians
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            // Kept where it folds nothing and leaves no element poorer than the floor
            // (or than it was), or where it mends a fold.
            let keeps =
                (after > 0.0 && after >= before.min(FLOOR)) || (before <= 0.0 && after > before);
            if keeps {
                for (&k, &q) in around.iter().zip(&moved_jacobians) {
                    jacobians[k] = q;
                }
            } else {
                points[v] = old;
            }
        }
    }
    let directions: Vec<DVec2> = (0..8)
        .map(|k| DVec2::from_angle(std::f64::consts::FRAC_PI_4 * k as f64))
        .collect();
    // The compass search's measure: the scaled Jacobian, and no element with a side
    // under a third of its longest (the scaled Jacobian alone would let a quad fold
    // one side down to nothing, its four angles still fair).
    let judged_one = |points: &[DVec2], k: usize| {
        let (corners, n) = corners_of(points, k);
        let corners = &corners[..n];
        let sides = (0..n).map(|i| corners[i].distance(corners[(i + 1) % n]));
        let (short, long) = sides.fold((f64::INFINITY, 0.0f64), |(s, l), d| (s.min(d), l.max(d)));
        let stretch = if long > 0.0 { 3.0 * short / long } else { 0.0 };
        scaled_jacobian_2d(corners).min(stretch)
    };
    let judged = |points: &[DVec2], around: &[usize]| {
        around
            .iter()
            .map(|&k| judged_one(points, k))
            .fold(f64::INFINITY, f64::min)
    };
    // Each element's measure, kept up to date as the search moves nodes, so a node
    // whose elements are all fair is passed over without judging them again.
    let mut measures: Vec<f64> = (0..elements.len()).map(|k| judged_one(points, k)).collect();
    for _ in 0..SWEEPS {
        let mut moved = false;
        for v in fixed..points.len() {
            let around = &star[offsets[v]..offsets[v + 1]];
            if around.is_empty() {
                continue;
            }
            let mut best = least_of(around, &measures);
            if best >= POOR {
                continue;
            }
            // The step starts at a third of the node's mean distance to its corners.
            let (sum, count) = around
                .iter()
                .flat_map(|&k| elements[k].iter())
                .fold((0.0, 0usize), |(s, c), &w| {
                    (s + points[w as usize].distance(points[v]), c + 1)
                });
            let mut step = sum / count.max(1) as f64 / 3.0;
            let start = points[v];
            let mut halvings = 0;
            while halvings < HALVINGS {
                let here = points[v];
                let mut found = None;
                for d in &directions {
                    points[v] = here + step * *d;
                    let q = judged(points, around);
                    if q > best + 1e-12 {
                        best = q;
                        found = Some(points[v]);
                    }
                }
                points[v] = found.unwrap_or(here);
                if found.is_some() {
                    moved = true;
                } else {
                    step *= 0.5;
                    halvings += 1;
                }
            }
            if points[v] != start {
                for &k in around {
                    measures[k] = judged_one(points, k);
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// The least of the `values` of the elements `around` a node (infinite for none).
fn least_of(around: &[usize], values: &[f64]) -> f64 {
    around
        .iter()
        .map(|&k| values[k])
        .fold(f64::INFINITY, f64::min)
}
