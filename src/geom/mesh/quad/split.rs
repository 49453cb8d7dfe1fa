//! The loop split down to quads (paper 004, section 4, Fig. 1): a loop is split in two
//! by the best split line between two of its nodes that see each other, nodes placed
//! along the line so both halves keep an even count, until every loop has four nodes.
//!
//! Every candidate line is scored by the paper's four errors, each scaled to about 1
//! for a bad line:
//!
//! - **split angles**: each of the four angles the line cuts at its two ends should be
//!   a whole number of right angles, at least one (a straight edge is cut square, a
//!   right-angled corner not at all, a reflex corner into a right angle and a straight
//!   one), so the quads' corners there come near 90 deg;
//! - **area balance**: the two halves' areas should be equal, so the splitting goes
//!   down in about log steps and the lines run across the region;
//! - **length**: shorter lines (over the loop's size) leave squarer halves;
//! - **node spacing**: the nodes on the line should lie as far apart as the boundary's
//!   nodes at its two ends.
//!
//! Small loops are finished by trying every way: a loop of six nodes by its three
//! splits into two quads and its two templates of three quads round a centre node, a
//! loop of eight by its splits and its templates of four quads round a centre node,
//! the best kept by its worst element.

use glam::DVec2;

use super::cut::{blocked, ccw_angle, inner_angle};
use super::quality::scaled_jacobian_2d;
use super::sizing::Sizes;
use super::QuadError;

/// Weights of the four errors in a split line's score.
const ANGLE_WEIGHT: f64 = 1.0;
const AREA_WEIGHT: f64 = 0.6;
const LENGTH_WEIGHT: f64 = 0.3;
const SPACING_WEIGHT: f64 = 0.6;
/// The weight of how badly a half small enough to finish at once would be finished.
const SMALL_WEIGHT: f64 = 2.0;

/// How many of the best-scored lines are sorted and tried for visibility before all
/// the others are.
const FIRST_TRIED: usize = 64;

/// Loops of at most this many nodes are finished by trying every way.
const SMALL: usize = 8;

/// The sharpest angle a split line should cut at its ends (rad): 25 deg; sharper ones
/// are scored as slivers.
const LEAST_ANGLE: f64 = 0.436;

/// How near, as a share of the boundary's spacing at its ends, a split line may pass
/// the loop's other nodes.
const CLEARANCE: f64 = 0.2;

/// Whether the segment between loop positions `a` and `b` of `p` passes every other
/// node of the loop at least `clearance` away (nodes at the ends' own positions, a cut
/// line's ends walked twice, aside).
fn clear_of_nodes(p: &[DVec2], a: usize, b: usize, clearance: f64) -> bool {
    let (pa, pb) = (p[a], p[b]);
    let d = pb - pa;
    let dd = d.length_squared().max(f64::MIN_POSITIVE);
    p.iter().enumerate().all(|(i, &q)| {
        if i == a || i == b || q == pa || q == pb {
            return true;
        }
        let t = ((q - pa).dot(d) / dd).clamp(0.0, 1.0);
        q.distance(pa + d * t) >= clearance
    })
}

/// A split line: between loop positions `a < b`, in `pieces` pieces.
#[derive(Debug, Clone, Copy)]
struct Line {
    score: f64,
    a: usize,
    b: usize,
    pieces: usize,
}

/// The error of one angle a split line cuts at a node: zero for a whole number of
/// right angles (at least one), growing to 1 halfway between, steeply below one right
/// angle and more steeply still below [`LEAST_ANGLE`].
fn angle_error(angle: f64) -> f64 {
    let q = angle / std::f64::consts::FRAC_PI_2;
    if q < 1.0 {
        // Sharper than a good quad corner can be: a sliver on this side.
        let sliver = (LEAST_ANGLE - angle).max(0.0) / LEAST_ANGLE;
        2.0 * (1.0 - q) + 8.0 * sliver
    } else {
        2.0 * (q - q.round()).abs()
    }
}

/// A loop's nodes as seen by the splitting: positions, the region's angle at each,
/// the spacing of the boundary there, and the running sum of the area.
struct LoopView {
    p: Vec<DVec2>,
    theta: Vec<f64>,
    spacing: Vec<f64>,
    /// `shoelace[m]` = sum of `p[i] x p[i+1]` for `i < m`.
    shoelace: Vec<f64>,
    area: f64,
}

impl LoopView {
    fn new(points: &[DVec2], l: &[u32]) -> LoopView {
        let n = l.len();
        let p: Vec<DVec2> = l.iter().map(|&v| points[v as usize]).collect();
        let theta = (0..n)
            .map(|i| inner_angle(p[(i + n - 1) % n], p[i], p[(i + 1) % n]))
            .collect();
        let spacing = (0..n)
            .map(|i| 0.5 * (p[i].distance(p[(i + n - 1) % n]) + p[i].distance(p[(i + 1) % n])))
            .collect();
        let mut shoelace = Vec::with_capacity(n + 1);
        let mut sum = 0.0;
        shoelace.push(0.0);
        for i in 0..n {
            sum += p[i].perp_dot(p[(i + 1) % n]);
            shoelace.push(sum);
        }
        LoopView {
            area: 0.5 * sum,
            p,
            theta,
            spacing,
            shoelace,
        }
    }

    /// The area of the half running `a, a+1, .., b` and back along the line.
    fn half_area(&self, a: usize, b: usize) -> f64 {
        0.5 * (self.shoelace[b] - self.shoelace[a] + self.p[b].perp_dot(self.p[a]))
    }

    /// The scored line from `a` to `b`, if it leaves both ends into the region cutting
    /// no angle there below `least` (rad), both
    /// halves have area and an even count of at least four nodes can be made.
    fn line(&self, a: usize, b: usize, scale: f64, sizes: Sizes, least: f64) -> Option<Line> {
        let n = self.p.len();
        let d = self.p[b] - self.p[a];
        let length = d.length();
        if length <= f64::MIN_POSITIVE {
            return None;
        }
        let next = |i: usize| self.p[(i + 1) % n] - self.p[i];
        let phi_a = ccw_angle(next(a), d);
        let phi_b = ccw_angle(next(b), -d);
        if phi_a <= least
            || phi_a >= self.theta[a] - least
            || phi_b <= least
            || phi_b >= self.theta[b] - least
        {
            return None;
        }
        let first = self.half_area(a, b);
        let second = self.area - first;
        // Both halves must hold area (a line along a straight run of the loop's own
        // nodes leaves a half of none).
        let least_area = 1e-9 * self.area;
        if first <= least_area || second <= least_area {
            return None;
        }
        // The spacing along the line: halfway between the boundary's at its ends and
        // the element size, so lines inside come back to the size.
        let size = sizes.at(self.p[a].lerp(self.p[b], 0.5));
        let target = 0.5 * (0.5 * (self.spacing[a] + self.spacing[b]) + size);
        // Pieces along the line: as near the target spacing as the halves' parity
        // allows (the first half has b - a + pieces nodes).
        let ideal = (length / target).round().max(1.0) as usize;
        let even = |pieces: usize| (b - a + pieces) % 2 == 0;
        let spacing_error = |pieces: usize| (length / pieces as f64 - target).abs();
        let pieces = if even(ideal) {
            ideal
        } else if ideal > 1 && spacing_error(ideal - 1) < spacing_error(ideal + 1) {
            ideal - 1
        } else {
            ideal + 1
        };
        let first_nodes = b - a + pieces;
        let second_nodes = n - (b - a) + pieces;
        if first_nodes < 4 || second_nodes < 4 {
            return None;
        }
        let angles = angle_error(phi_a)
            + angle_error(self.theta[a] - phi_a)
            + angle_error(phi_b)
            + angle_error(self.theta[b] - phi_b);
        let mut score = ANGLE_WEIGHT * angles / 4.0
            + AREA_WEIGHT * (first - second).abs() / self.area
            + LENGTH_WEIGHT * length / scale
            + SPACING_WEIGHT * spacing_error(pieces) / target;
        // A half small enough to be finished at once is judged by how well it can be.
        let along = |k: usize| self.p[a].lerp(self.p[b], k as f64 / pieces as f64);
        if first_nodes <= SMALL {
            let half: Vec<DVec2> = self.p[a..=b]
                .iter()
                .copied()
                .chain((1..pieces).rev().map(along))
                .collect();
            score += SMALL_WEIGHT * (1.0 - best_small(&half).map_or(-1.0, |w| w.0));
        }
        if second_nodes <= SMALL {
            let half: Vec<DVec2> = self.p[b..]
                .iter()
                .chain(&self.p[..=a])
                .copied()
                .chain((1..pieces).map(along))
                .collect();
            score += SMALL_WEIGHT * (1.0 - best_small(&half).map_or(-1.0, |w| w.0));
        }
        Some(Line {
            score,
            a,
            b,
            pieces,
        })
    }
}

/// The best-scored line of the loop `l` that sees from end to end, among the lines
/// `scored` makes.
fn best_visible(
    points: &[DVec2],
    l: &[u32],
    view: &LoopView,
    scored: impl Fn(usize, usize) -> Option<Line>,
) -> Option<Line> {
    let n = l.len();
    let mut lines: Vec<Line> = Vec::new();
    for a in 0..n {
        for b in a + 2..n {
            if (a == 0 && b == n - 1) || l[a] == l[b] {
                continue;
            }
            if let Some(line) = scored(a, b) {
                lines.push(line);
            }
        }
    }
    let order = |x: &Line, y: &Line| {
        x.score
            .total_cmp(&y.score)
            .then((x.a, x.b).cmp(&(y.a, y.b)))
    };
    // A line must see from end to end and pass its loop's other nodes no nearer than a
    // share of the spacing there (a line grazing a node leaves a sliver).
    let sees = |line: &Line| {
        let clearance = CLEARANCE * view.spacing[line.a].min(view.spacing[line.b]);
        !blocked(points, l[line.a], l[line.b], &[l])
            && clear_of_nodes(&view.p, line.a, line.b, clearance)
    };
    let few = lines.len().min(FIRST_TRIED);
    if few < lines.len() {
        lines.select_nth_unstable_by(few, order);
    }
    lines[..few].sort_by(order);
    if let Some(&line) = lines[..few].iter().find(|line| sees(line)) {
        return Some(line);
    }
    let rest = &mut lines[few..];
    rest.sort_by(order);
    rest.iter().find(|line| sees(line)).copied()
}

/// The loop `l` (node ids, counter-clockwise) split at its best line: the two halves,
/// the line's new nodes added to `points`.
fn split_once(
    points: &mut Vec<DVec2>,
    l: &[u32],
    sizes: Sizes,
) -> Result<(Vec<u32>, Vec<u32>), QuadError> {
    let n = l.len();
    let view = LoopView::new(points, l);
    let scale = view.area.abs().sqrt().max(f64::MIN_POSITIVE);
    let best = best_visible(points, l, &view, |a, b| view.line(a, b, scale, sizes, 1e-6)).ok_or(
        QuadError::NoSplit {
            nodes: n,
            at: view.p[0],
        },
    )?;
    let Line { a, b, pieces, .. } = best;
    let (from, to) = (view.p[a], view.p[b]);
    let first_new = points.len() as u32;
    for k in 1..pieces {
        points.push(from.lerp(to, k as f64 / pieces as f64));
    }
    let new: Vec<u32> = (first_new..points.len() as u32).collect();
    let mut first: Vec<u32> = l[a..=b].to_vec();
    first.extend(new.iter().rev());
    let mut second: Vec<u32> = l[b..].iter().chain(&l[..=a]).copied().collect();
    second.extend(&new);
    Ok((first, second))
}

/// Every way of meshing a small loop of `n` nodes (4, 6 or 8) into quads: each quad by
/// loop positions, position `n` being a centre node (the mean of the loop's nodes)
/// where the way has one.
fn small_ways(n: usize) -> Vec<Vec<[usize; 4]>> {
    let mut ways: Vec<Vec<[usize; 4]>> = Vec::new();
    if n == 4 {
        ways.push(vec![[0, 1, 2, 3]]);
    }
    if n == 6 {
        for r in 0..3 {
            let q = |i: usize| (r + i) % 6;
            ways.push(vec![[q(0), q(1), q(2), q(3)], [q(3), q(4), q(5), q(0)]]);
        }
        for r in 0..2 {
            let q = |i: usize| (r + i) % 6;
            ways.push(vec![
                [q(0), q(1), q(2), 6],
                [q(2), q(3), q(4), 6],
                [q(4), q(5), q(0), 6],
            ]);
        }
    }
    if n == 8 {
        for r in 0..2 {
            let q = |i: usize| (r + i) % 8;
            ways.push(vec![
                [q(0), q(1), q(2), 8],
                [q(2), q(3), q(4), 8],
                [q(4), q(5), q(6), 8],
                [q(6), q(7), q(0), 8],
            ]);
        }
        // A quad cut off and the six left split in two.
        for r in 0..8 {
            let q = |i: usize| (r + i) % 8;
            for s in 0..3 {
                let six = [q(3), q(4), q(5), q(6), q(7), q(0)];
                let t = |i: usize| six[(s + i) % 6];
                ways.push(vec![
                    [q(0), q(1), q(2), q(3)],
                    [t(0), t(1), t(2), t(3)],
                    [t(3), t(4), t(5), t(0)],
                ]);
            }
        }
    }
    ways
}

/// The best way of meshing the small loop through `p` (its quads by loop position, `n`
/// the centre node) and its worst element's scaled Jacobian; `None` for a loop with no
/// way (not 4, 6 or 8 nodes).
fn best_small(p: &[DVec2]) -> Option<(f64, Vec<[usize; 4]>)> {
    let n = p.len();
    let centre = p.iter().copied().sum::<DVec2>() / n as f64;
    let at = |i: usize| if i < n { p[i] } else { centre };
    small_ways(n)
        .into_iter()
        .map(|quads| {
            let worst = quads
                .iter()
                .map(|q| scaled_jacobian_2d(&q.map(at)))
                .fold(f64::INFINITY, f64::min);
            (worst, quads)
        })
        .max_by(|x, y| x.0.total_cmp(&y.0))
}

/// A small loop finished the best way ([`best_small`]): its quads, and the centre
/// node's position if that way has one.
fn finish_small(points: &[DVec2], l: &[u32]) -> (Vec<[u32; 4]>, Option<DVec2>) {
    let p: Vec<DVec2> = l.iter().map(|&v| points[v as usize]).collect();
    let n = l.len();
    let Some((_, quads)) = best_small(&p) else {
        return (Vec::new(), None);
    };
    let centre = quads
        .iter()
        .any(|q| q.contains(&n))
        .then(|| p.iter().copied().sum::<DVec2>() / n as f64);
    let id = |i: usize| if i < n { l[i] } else { points.len() as u32 };
    (quads.iter().map(|q| q.map(id)).collect(), centre)
}

/// The loop `first` (node ids into `points`, counter-clockwise, an even count) split
/// down to quads, pushed to `quads`; an odd loop leaves a triangle in `triangles`.
pub fn split_down(
    points: &mut Vec<DVec2>,
    first: Vec<u32>,
    sizes: Sizes,
    quads: &mut Vec<[u32; 4]>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), QuadError> {
    let mut stack = vec![first];
    while let Some(l) = stack.pop() {
        let n = l.len();
        if n < 3 {
            continue;
        }
        if n == 3 {
            triangles.push([l[0], l[1], l[2]]);
            continue;
        }
        if n % 2 == 0 && n <= SMALL {
            let (made, extra) = finish_small(points, &l);
            if let Some(c) = extra {
                points.push(c);
            }
            quads.extend(made);
            continue;
        }
        if n % 2 == 1 && n <= 5 {
            // An odd loop (never made from the boundary's even counts): a fan.
            for k in 1..n - 1 {
                triangles.push([l[0], l[k], l[k + 1]]);
            }
            continue;
        }
        let (first, second) = split_once(points, &l, sizes)?;
        stack.push(second);
        stack.push(first);
    }
    Ok(())
}
