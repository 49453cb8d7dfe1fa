//! Smoothing of the inner nodes (paper 004 stops before it; CAE engineers expect it):
//! each node not on the region's boundary moved to the mean of the centres of the
//! elements round it, the move kept only where the worst of those elements stays
//! above its floor (never folding an element, never making a good one poor) or where
//! it mends a folded one.

use glam::DVec2;

use super::quality::scaled_jacobian_2d;

/// The worst scaled Jacobian a move may leave among a node's elements, unless they were
/// worse before it.
const FLOOR: f64 = 0.3;

/// Moves every node of `points` from `fixed` on (the first `fixed` are the boundary's)
/// towards the centre of its elements, `passes` times over.
pub fn smooth(
    points: &mut [DVec2],
    fixed: usize,
    quads: &[[u32; 4]],
    triangles: &[[u32; 3]],
    passes: usize,
) {
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
    let worst = |points: &[DVec2], around: &[usize]| {
        around
            .iter()
            .map(|&k| {
                let corners: Vec<DVec2> = elements[k].iter().map(|&v| points[v as usize]).collect();
                scaled_jacobian_2d(&corners)
            })
            .fold(f64::INFINITY, f64::min)
    };
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
            let before = worst(points, around);
            let old = points[v];
            points[v] = centre;
            let after = worst(points, around);
            // Kept where it folds nothing and leaves no element poorer than the floor
            // (or than it was), or where it mends a fold.
            let keeps =
                (after > 0.0 && after >= before.min(FLOOR)) || (before <= 0.0 && after > before);
            if !keeps {
                points[v] = old;
            }
        }
    }
}
