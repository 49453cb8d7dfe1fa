//! Smoothing of the inner nodes (paper 004 stops before it; CAE engineers expect it):
//! each node not on the region's boundary moved to the mean of the centres of the
//! elements round it, the move kept only where the worst of those elements stays
//! above its floor (never folding an element, never making a good one poor) or where
//! it mends a folded one. A node is moved again in the next pass only where it or a
//! neighbour moved by more than [`SETTLED`] of its reach in this one: where nothing
//! round it moves, its centre stays where it is, and smoothing a region again after a
//! few elements changed (the edge swaps, the mending) moves only the nodes near them.
//! Then each inner node of a poor element (scaled Jacobian below
//! [`POOR`]) is moved where the worst of its elements is best, by a compass search:
//! centroid smoothing evens a mesh out, but cannot pull a node out of a sliver its
//! neighbours pin it in.

use glam::DVec2;

use super::quality::scaled_jacobian_2d;

/// The worst scaled Jacobian a move may leave among a node's elements, unless they were
/// worse before it.
const FLOOR: f64 = 0.3;

/// A move shorter than this share of the node's reach (its mean distance to the
/// centres of its elements) counts as none: the node and its neighbours are not moved
/// again for it. A thousandth of an element: 5 um on a 5 mm mesh.
const SETTLED: f64 = 1e-3;

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
    // The nodes to move in this pass, and those marked for the next.
    let mut active = vec![true; points.len()];
    let mut next = vec![false; points.len()];
    for _ in 0..passes {
        for v in fixed..points.len() {
            let around = &star[offsets[v]..offsets[v + 1]];
            if around.is_empty() || !active[v] {
                continue;
            }
            let old = points[v];
            let (sum, reach) = around.iter().fold((DVec2::ZERO, 0.0), |(sum, reach), &k| {
                let e = elements[k];
                let c = e.iter().map(|&w| points[w as usize]).sum::<DVec2>() / e.len() as f64;
                (sum + c, reach + c.distance(old))
            });
            let centre = sum / around.len() as f64;
            let reach = reach / around.len() as f64;
            let before = least_of(around, &jacobians);
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
                if centre.distance(old) > SETTLED * reach {
                    for &k in around {
                        for &w in elements[k] {
                            next[w as usize] = true;
                        }
                    }
                }
            } else {
                points[v] = old;
            }
        }
        std::mem::swap(&mut active, &mut next);
        next.fill(false);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// An `n` x `n` grid of unit squares: the boundary's nodes first, then the inner
    /// ones, and its quads counter-clockwise.
    fn grid(n: usize) -> (Vec<DVec2>, usize, Vec<[u32; 4]>) {
        let at = |i: usize, j: usize| DVec2::new(i as f64, j as f64);
        let on_edge = |i: usize, j: usize| i == 0 || j == 0 || i == n || j == n;
        let mut order: Vec<(usize, usize)> = Vec::new();
        for pass in [true, false] {
            for j in 0..=n {
                for i in 0..=n {
                    if on_edge(i, j) == pass {
                        order.push((i, j));
                    }
                }
            }
        }
        let fixed = order.iter().filter(|&&(i, j)| on_edge(i, j)).count();
        // Every (i, j) of the grid is in `order`, on the boundary or inside.
        let id = |i: usize, j: usize| order.iter().position(|&o| o == (i, j)).unwrap() as u32;
        let mut quads = Vec::new();
        for j in 0..n {
            for i in 0..n {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (order.iter().map(|&(i, j)| at(i, j)).collect(), fixed, quads)
    }

    /// Plain centroid smoothing, every inner node in every pass, no quality floor: the
    /// reference the settling is measured against.
    fn every_node_every_pass(
        points: &mut [DVec2],
        fixed: usize,
        quads: &[[u32; 4]],
        passes: usize,
    ) {
        for _ in 0..passes {
            for v in fixed..points.len() {
                let around: Vec<&[u32; 4]> =
                    quads.iter().filter(|q| q.contains(&(v as u32))).collect();
                let centres = around
                    .iter()
                    .map(|q| q.iter().map(|&w| points[w as usize]).sum::<DVec2>() / 4.0);
                points[v] = centres.sum::<DVec2>() / around.len() as f64;
            }
        }
    }

    #[test]
    fn settled_nodes_left_alone_change_the_result_by_less_than_a_hundredth_of_an_element() {
        let (square, fixed, quads) = grid(12);
        // The inner nodes swirled (every element stays fair, so no move is refused).
        let swirled: Vec<DVec2> = square
            .iter()
            .enumerate()
            .map(|(k, &p)| {
                if k < fixed {
                    return p;
                }
                let phase = 0.5 * p.x + 0.3 * p.y;
                p + 0.2 * DVec2::new(phase.sin(), (1.7 * phase).cos())
            })
            .collect();
        let mut settled = swirled.clone();
        smooth(&mut settled, fixed, &quads, &[], 10);
        let mut reference = swirled.clone();
        every_node_every_pass(&mut reference, fixed, &quads, 10);
        let apart = settled
            .iter()
            .zip(&reference)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(apart < 0.01, "{apart}");
        // And the smoothing did its work: the swirl is mostly gone.
        let off = |p: &[DVec2]| {
            p.iter()
                .zip(&square)
                .map(|(a, b)| a.distance(*b))
                .fold(0.0, f64::max)
        };
        assert!(
            off(&settled) < 0.5 * off(&swirled),
            "{} {}",
            off(&settled),
            off(&swirled)
        );
    }

    #[test]
    fn smoothing_again_after_one_node_moved_moves_only_the_nodes_near_it() {
        let (square, fixed, quads) = grid(24);
        // The last inner node in the sweep's order pushed off its place: smoothed
        // back, its neighbours following a little. Plain Gauss-Seidel carries the push
        // a ring further out at every pass, ever smaller; settled nodes stop it where
        // the moves fall below a thousandth of an element.
        let pushed = square.len() - 1;
        let mut points = square.clone();
        points[pushed] += DVec2::new(-0.3, -0.2);
        let mut reference = points.clone();
        smooth(&mut points, fixed, &quads, &[], 10);
        every_node_every_pass(&mut reference, fixed, &quads, 10);
        assert!(points[pushed].distance(square[pushed]) < 0.05);
        let moved = |p: &[DVec2]| -> Vec<f64> {
            p.iter()
                .zip(&square)
                .filter(|(a, b)| a != b)
                .map(|(_, b)| b.distance(square[pushed]))
                .collect()
        };
        let (settled, plain) = (moved(&points), moved(&reference));
        let reach = |d: &[f64]| d.iter().copied().fold(0.0, f64::max);
        // Measured: 24 nodes within 5 elements of the push, against plain smoothing's
        // 166 reaching 17 elements away.
        assert!(reach(&settled) <= 6.0, "{}", reach(&settled));
        assert!(reach(&plain) > 12.0, "{}", reach(&plain));
        assert!(
            4 * settled.len() < plain.len(),
            "{} {}",
            settled.len(),
            plain.len()
        );
    }
}
