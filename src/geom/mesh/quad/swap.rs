//! Edge swaps between quads (the topological clean-up every quad mesher runs after
//! making its quads; Canann, Muthukrishnan and Phillips, "Topological improvement
//! procedures for quadrilateral finite element meshes", 1998): two quads sharing an
//! edge form a hexagon, which two quads can fill three ways; where a poor quad's way
//! is not the best, the hexagon is filled again the best way.
//!
//! Smoothing moves nodes but cannot mend a quad whose shape its topology fixes: a quad
//! on three neighbouring boundary nodes of a gently curving loop has a corner of nearly
//! 180 deg wherever its fourth node goes. Swapping the edge it shares with a neighbour
//! gives that boundary node a second element, and both a fair corner.

use glam::DVec2;

use super::quality::scaled_jacobian_2d;

/// How much better (scaled Jacobian of the worse quad) a swap must leave its hexagon,
/// so that no two ways of filling it take turns.
const GAIN: f64 = 0.05;

/// Passes over the poor quads at most (a swap may make a neighbour's swap worth it).
const PASSES: usize = 4;

/// The hexagon two counter-clockwise quads sharing the edge `(u, v)` of `first` (and
/// `(v, u)` of `second`) make, counter-clockwise from `v`: `[v, a, b, u, c, d]`, the
/// shared edge its diagonal from position 0 to 3. `None` unless the six nodes differ.
pub fn hexagon(first: [u32; 4], second: [u32; 4], u: u32, v: u32) -> Option<[u32; 6]> {
    let i = first.iter().position(|&x| x == v)?;
    let j = second.iter().position(|&x| x == u)?;
    if first[(i + 3) % 4] != u || second[(j + 3) % 4] != v {
        return None;
    }
    let h = [
        v,
        first[(i + 1) % 4],
        first[(i + 2) % 4],
        u,
        second[(j + 1) % 4],
        second[(j + 2) % 4],
    ];
    let mut sorted = h;
    sorted.sort_unstable();
    sorted.windows(2).all(|w| w[0] != w[1]).then_some(h)
}

/// The two quads filling hexagon `h` with the diagonal from position `k` to `k + 3`.
pub fn filled(h: [u32; 6], k: usize) -> [[u32; 4]; 2] {
    let at = |i: usize| h[(k + i) % 6];
    [[at(0), at(1), at(2), at(3)], [at(3), at(4), at(5), at(0)]]
}

/// Centroid passes over a hexagon's inner nodes when a swap is tried.
const RELAX: usize = 4;

/// The mesh's quads as the swaps see them: each node's quads (which also give each
/// directed edge's quad) and whether a triangle holds it.
struct Swapper<'a> {
    points: &'a mut [DVec2],
    /// The first `fixed` nodes are the boundary's.
    fixed: usize,
    star: Vec<Vec<usize>>,
    in_triangle: Vec<bool>,
}

impl<'a> Swapper<'a> {
    fn new(
        points: &'a mut [DVec2],
        fixed: usize,
        quads: &[[u32; 4]],
        triangles: &[[u32; 3]],
    ) -> Swapper<'a> {
        let mut star = vec![Vec::new(); points.len()];
        for (k, q) in quads.iter().enumerate() {
            for i in 0..4 {
                star[q[i] as usize].push(k);
            }
        }
        let mut in_triangle = vec![false; points.len()];
        for &v in triangles.iter().flatten() {
            in_triangle[v as usize] = true;
        }
        Swapper {
            points,
            fixed,
            star,
            in_triangle,
        }
    }

    /// A quad's plane scaled Jacobian.
    fn sj(&self, q: [u32; 4]) -> f64 {
        scaled_jacobian_2d(&q.map(|v| self.points[v as usize]))
    }

    /// How many elements hold node `v`.
    fn valence(&self, v: u32) -> usize {
        self.star[v as usize].len() + usize::from(self.in_triangle[v as usize])
    }

    /// Whether node `v` may move: not on the boundary, not in a triangle.
    fn free(&self, v: u32) -> bool {
        v as usize >= self.fixed && !self.in_triangle[v as usize]
    }

    /// The quad running along the edge from node `a` to node `b`, found among `a`'s
    /// quads (a handful) rather than in a map of every edge.
    fn owner(&self, quads: &[[u32; 4]], a: u32, b: u32) -> Option<usize> {
        self.star[a as usize].iter().rev().copied().find(|&k| {
            let q = quads[k];
            (0..4).any(|i| q[i] == a && q[(i + 1) % 4] == b)
        })
    }

    /// Whether the nodes `a` and `b` are already joined by an edge.
    fn joined(&self, quads: &[[u32; 4]], a: u32, b: u32) -> bool {
        self.owner(quads, a, b).is_some() || self.owner(quads, b, a).is_some()
    }

    /// The hexagon of quad `k` and its neighbour across the edge from its corner `i`,
    /// with the neighbour's index.
    fn across(&self, quads: &[[u32; 4]], k: usize, i: usize) -> Option<(usize, [u32; 6])> {
        let q = quads[k];
        let (u, v) = (q[i], q[(i + 1) % 4]);
        let other = self.owner(quads, v, u)?;
        Some((other, hexagon(q, quads[other], u, v)?))
    }

    /// The worst quad round the hexagon's nodes.
    fn worst_round(&self, quads: &[[u32; 4]], h: &[u32; 6]) -> f64 {
        h.iter()
            .flat_map(|&v| self.star[v as usize].iter())
            .map(|&k| self.sj(quads[k]))
            .fold(f64::INFINITY, f64::min)
    }

    /// The hexagon's free nodes each moved to the mean of its quads' centres, a few
    /// times over (as smoothing will, so a swap is judged by what it can become).
    fn relax(&mut self, quads: &[[u32; 4]], h: &[u32; 6]) {
        for _ in 0..RELAX {
            for &v in h {
                if !self.free(v) {
                    continue;
                }
                let around = &self.star[v as usize];
                let centre = around
                    .iter()
                    .map(|&k| {
                        quads[k]
                            .iter()
                            .map(|&w| self.points[w as usize])
                            .sum::<DVec2>()
                    })
                    .sum::<DVec2>()
                    / (4 * around.len()).max(1) as f64;
                self.points[v as usize] = centre;
            }
        }
    }

    /// Quads `k` and `other` replaced by `pair`.
    fn apply(&mut self, quads: &mut [[u32; 4]], k: usize, other: usize, pair: [[u32; 4]; 2]) {
        for slot in [k, other] {
            for v in quads[slot] {
                self.star[v as usize].retain(|&s| s != slot);
            }
        }
        quads[k] = pair[0];
        quads[other] = pair[1];
        for slot in [k, other] {
            for v in quads[slot] {
                self.star[v as usize].push(slot);
            }
        }
    }

    /// Whether the old diagonal's ends `h[0]` and `h[3]` keep enough elements once it
    /// goes: an inner node three (two would make a doublet), a boundary node one.
    fn keeps(&self, h: &[u32; 6]) -> bool {
        [h[0], h[3]].iter().all(|&v| {
            let least = if (v as usize) < self.fixed { 2 } else { 4 };
            self.valence(v) >= least
        })
    }

    /// Tries every swap of quad `k` with a neighbour, each judged by the worst quad
    /// round its hexagon after relaxing the hexagon's free nodes; keeps the best if it
    /// beats the worst there before by [`GAIN`], else leaves the mesh as it was.
    /// Whether a swap was kept.
    fn improve(&mut self, quads: &mut [[u32; 4]], k: usize) -> bool {
        let mut best: Option<Swap> = None;
        let mut before_best = f64::INFINITY;
        for i in 0..4 {
            let Some((other, h)) = self.across(quads, k, i) else {
                continue;
            };
            if !self.keeps(&h) {
                continue;
            }
            let before = self.worst_round(quads, &h);
            let kept: Vec<DVec2> = h.iter().map(|&v| self.points[v as usize]).collect();
            let old = [quads[k], quads[other]];
            for way in [1, 2] {
                if self.joined(quads, h[way], h[way + 3]) {
                    continue;
                }
                self.apply(quads, k, other, filled(h, way));
                self.relax(quads, &h);
                let after = self.worst_round(quads, &h);
                if after > before + GAIN && best.is_none_or(|b| after - before > b.gain) {
                    best = Some(Swap {
                        gain: after - before,
                        other,
                        pair: filled(h, way),
                        hexagon: h,
                    });
                    before_best = before;
                }
                self.apply(quads, k, other, old);
                for (&v, &p) in h.iter().zip(&kept) {
                    self.points[v as usize] = p;
                }
            }
        }
        let Some(Swap {
            other,
            pair,
            hexagon: h,
            ..
        }) = best
        else {
            return false;
        };
        self.apply(quads, k, other, pair);
        self.relax(quads, &h);
        debug_assert!(self.worst_round(quads, &h) > before_best);
        true
    }
}

/// A swap found: how much it improves the worst quad round the hexagon, the
/// neighbouring quad, the two quads that fill the hexagon the new way, and the hexagon.
#[derive(Debug, Clone, Copy)]
struct Swap {
    gain: f64,
    other: usize,
    pair: [[u32; 4]; 2],
    hexagon: [u32; 6],
}

/// Swaps the edges of every quad poorer than `poor` (plane scaled Jacobian) with a
/// neighbour where that, with the hexagon's free nodes relaxed, leaves the worst quad
/// round the hexagon better by [`GAIN`] (the first `fixed` nodes are the boundary's and
/// stay; nodes of `triangles` stay too), until no swap helps (or [`PASSES`] passes).
/// Returns how many edges were swapped; smooth after.
pub fn swap_edges(
    points: &mut [DVec2],
    fixed: usize,
    quads: &mut [[u32; 4]],
    triangles: &[[u32; 3]],
    poor: f64,
) -> usize {
    let mut swapper = Swapper::new(points, fixed, quads, triangles);
    let mut swaps = 0;
    for _ in 0..PASSES {
        let before = swaps;
        for k in 0..quads.len() {
            if swapper.sj(quads[k]) < poor && swapper.improve(quads, k) {
                swaps += 1;
            }
        }
        if swaps == before {
            break;
        }
    }
    swaps
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::mesh::quad::quality::worst_quad_2d;

    #[test]
    fn the_hexagon_of_two_quads_runs_round_both() {
        let h = hexagon([0, 1, 2, 3], [3, 2, 4, 5], 2, 3).expect("a hexagon");
        assert_eq!(h, [3, 0, 1, 2, 4, 5]);
        assert_eq!(filled(h, 0), [[3, 0, 1, 2], [2, 4, 5, 3]]);
        // Two quads sharing two edges make no hexagon.
        assert!(hexagon([0, 1, 2, 3], [3, 2, 1, 4], 2, 3).is_none());
    }

    #[test]
    fn a_quad_on_three_boundary_nodes_is_swapped_with_its_neighbour() {
        // A 2 x 1 strip, its bottom bowed a little at node 1: the quads 0 1 2 4 (nearly
        // straight at 1) and 4 3 5 0 (straight at 3) fill it the worst way.
        let mut points = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, -0.05),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        let mut quads = vec![[0, 1, 2, 4], [4, 3, 5, 0]];
        let before = worst_quad_2d(&points, &quads);
        // Every node on the boundary: the swap alone mends the pair.
        assert_eq!(swap_edges(&mut points, 6, &mut quads, &[], 0.5), 1);
        let after = worst_quad_2d(&points, &quads);
        assert!(after > 0.9 && before < 0.1, "{before} -> {after}");
        // Nodes 1 and 3 now have a corner in both quads.
        assert!(quads.iter().all(|q| q.contains(&1) && q.contains(&3)));
    }

    #[test]
    fn good_quads_are_left_alone() {
        let mut points = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        let mut quads = vec![[0, 1, 4, 5], [1, 2, 3, 4]];
        let kept = quads.clone();
        assert_eq!(swap_edges(&mut points, 0, &mut quads, &[], 0.5), 0);
        assert_eq!(quads, kept);
    }
}
