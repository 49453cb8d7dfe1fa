//! Cut lines (paper 004, section 4): each inner loop joined to the loop round it by a
//! straight line between two nodes that see each other, nodes placed on it at the
//! element size, so the region is bounded by one continuous loop. The line is walked
//! there and back, so its nodes (and its two ends) appear twice in that loop and the
//! elements on either side share them.

use glam::DVec2;

use super::boundary::segments_meet;
use super::sizing::Sizes;
use super::QuadError;

/// How many of the shortest node pairs are tried for a cut line before all are sorted.
const FIRST_TRIED: usize = 256;

/// The counter-clockwise angle from `a` to `b`, in `[0, 2 pi)`.
pub fn ccw_angle(a: DVec2, b: DVec2) -> f64 {
    let t = a.perp_dot(b).atan2(a.dot(b));
    if t < 0.0 {
        t + std::f64::consts::TAU
    } else {
        t
    }
}

/// The region's angle at a loop node `at` between its neighbours `prev` and `next`
/// (the region on the loop's left): counter-clockwise from the edge out to `next`
/// round to the edge in from `prev`, in `(0, 2 pi]`.
pub fn inner_angle(prev: DVec2, at: DVec2, next: DVec2) -> f64 {
    let t = ccw_angle(next - at, prev - at);
    if t <= 0.0 {
        std::f64::consts::TAU
    } else {
        t
    }
}

/// Whether the direction `dir` from `at` leaves into the region, strictly between the
/// loop's edges there (a small margin off each edge).
pub fn leaves_inward(prev: DVec2, at: DVec2, next: DVec2, dir: DVec2) -> bool {
    let theta = inner_angle(prev, at, next);
    let phi = ccw_angle(next - at, dir);
    let margin = 1e-9;
    phi > margin && phi < theta - margin
}

/// Whether the segment from node `a` to node `b` meets any edge of `loops` (each a
/// closed loop of node ids) other than the edges at `a` or `b` themselves.
pub fn blocked(points: &[DVec2], a: u32, b: u32, loops: &[&[u32]]) -> bool {
    let (pa, pb) = (points[a as usize], points[b as usize]);
    let (lo, hi) = (pa.min(pb), pa.max(pb));
    loops.iter().any(|l| {
        (0..l.len()).any(|i| {
            let (p, q) = (l[i], l[(i + 1) % l.len()]);
            if p == a || p == b || q == a || q == b {
                return false;
            }
            let (pp, pq) = (points[p as usize], points[q as usize]);
            if pp.max(pq).cmplt(lo).any() || pp.min(pq).cmpgt(hi).any() {
                return false;
            }
            segments_meet(pa, pb, pp, pq).is_some()
        })
    })
}

/// The loop's neighbours of its `i`-th node.
fn around(points: &[DVec2], l: &[u32], i: usize) -> (DVec2, DVec2, DVec2) {
    let n = l.len();
    (
        points[l[(i + n - 1) % n] as usize],
        points[l[i] as usize],
        points[l[(i + 1) % n] as usize],
    )
}

/// One continuous loop of node ids bounding the region whose outer loop is `loops[0]`
/// and holes the rest (the outer counter-clockwise, the holes clockwise, as
/// [`checked_loops`](super::boundary::checked_loops) leaves them). The holes are joined
/// one at a time, always by the shortest cut line any remaining hole has to the loop
/// so far, so cut lines run across the narrowest gaps; new nodes on them go to
/// `points`, about the size wanted at the line's middle apart.
pub fn join_holes(
    points: &mut Vec<DVec2>,
    loops: &[Vec<u32>],
    sizes: Sizes,
) -> Result<Vec<u32>, QuadError> {
    let mut joined: Vec<u32> = loops[0].clone();
    let mut left: Vec<&[u32]> = loops[1..].iter().map(Vec::as_slice).collect();
    while !left.is_empty() {
        // Every (hole, hole node, loop node) pair by distance, the shortest first.
        let mut pairs: Vec<(f64, usize, usize, usize)> = Vec::new();
        for (h, hole) in left.iter().enumerate() {
            for (j, &hv) in hole.iter().enumerate() {
                let ph = points[hv as usize];
                for (i, &lv) in joined.iter().enumerate() {
                    pairs.push((ph.distance(points[lv as usize]), h, j, i));
                }
            }
        }
        let order = |p: &(f64, usize, usize, usize), q: &(f64, usize, usize, usize)| {
            p.0.total_cmp(&q.0)
                .then((p.1, p.2, p.3).cmp(&(q.1, q.2, q.3)))
        };
        let sees = |&(_, h, j, i): &(f64, usize, usize, usize)| {
            let hole = left[h];
            let (hp, ha, hn) = around(points, hole, j);
            let (lp, la, ln) = around(points, &joined, i);
            if !leaves_inward(hp, ha, hn, la - ha) || !leaves_inward(lp, la, ln, ha - la) {
                return false;
            }
            let mut all: Vec<&[u32]> = left.clone();
            all.push(&joined);
            !blocked(points, hole[j], joined[i], &all)
        };
        // The shortest few first (a visible pair is almost always among them), then
        // the rest in order.
        let few = pairs.len().min(FIRST_TRIED);
        if few < pairs.len() {
            pairs.select_nth_unstable_by(few, order);
        }
        pairs[..few].sort_by(order);
        let found = match pairs[..few].iter().find(|p| sees(p)) {
            Some(&p) => Some(p),
            None => {
                let rest = &mut pairs[few..];
                rest.sort_by(order);
                rest.iter().find(|p| sees(p)).copied()
            }
        };
        // Loops that neither cross nor touch always leave some hole node seeing some
        // node of the loop round it (the nearest pair of a hole and its neighbour is
        // such a pair).
        let Some((length, h, j, i)) = found else {
            let hole = left[0];
            return Err(QuadError::NoSplit {
                nodes: hole.len(),
                at: points[hole[0] as usize],
            });
        };
        let hole = left.remove(h);
        let (from, to) = (points[joined[i] as usize], points[hole[j] as usize]);
        let size = sizes.at(from.lerp(to, 0.5));
        let pieces = ((length / size).round() as usize).max(1);
        let first_new = points.len() as u32;
        for k in 1..pieces {
            points.push(from.lerp(to, k as f64 / pieces as f64));
        }
        let cut: Vec<u32> = (first_new..points.len() as u32).collect();
        let mut next: Vec<u32> = Vec::with_capacity(joined.len() + hole.len() + 2 * cut.len() + 2);
        next.extend_from_slice(&joined[..=i]);
        next.extend_from_slice(&cut);
        next.extend(hole[j..].iter().chain(&hole[..j]));
        next.push(hole[j]);
        next.extend(cut.iter().rev());
        next.extend_from_slice(&joined[i..]);
        joined = next;
    }
    Ok(joined)
}
