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
use super::quality::{mean_corner_sine_2d, scaled_jacobian_2d};
use super::sizing::Sizes;
use super::QuadError;

/// Weights of the four errors in a split line's score.
const ANGLE_WEIGHT: f64 = 1.0;
const AREA_WEIGHT: f64 = 0.6;
const LENGTH_WEIGHT: f64 = 0.3;
const SPACING_WEIGHT: f64 = 0.6;
/// The weight of how badly a half small enough to finish at once would be finished.
const SMALL_WEIGHT: f64 = 2.0;

/// A small half whose best way leaves an element below this scaled Jacobian counts as
/// one that cannot be finished (see [`small_error`]).
const SMALL_FOLDED: f64 = 0.05;

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
    /// The four errors' score, without how a small half would be finished (which only
    /// adds: see [`LoopView::small_halves`]).
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

    /// How unevenly the line from `a` to `b` halves the area: the two halves' areas
    /// apart, before [`LoopView::area_error`] weighs and scales it.
    fn imbalance(&self, a: usize, b: usize) -> f64 {
        let first = self.half_area(a, b);
        let second = self.area - first;
        (first - second).abs()
    }

    /// The area-balance error, weighted, of a line whose halves are `imbalance` apart
    /// ([`LoopView::imbalance`]), as [`LoopView::line`] scores it.
    ///
    /// It never falls as the imbalance grows (a multiplication and a division by
    /// positive numbers, each rounded to nearest): the scans over every pair of nodes
    /// compare imbalances, and divide only where the error itself may decide.
    fn area_error(&self, imbalance: f64) -> f64 {
        AREA_WEIGHT * imbalance / self.area
    }

    /// An imbalance above which the area error is certainly above `most`, so a scan
    /// may pass the line by without dividing: `most` turned back into an imbalance,
    /// with room for the roundings. Infinite (no line passed by) where that is not
    /// sure: a loop turning the wrong way, no finite `most`, or numbers so small that
    /// the roundings are not relative.
    fn imbalance_beyond(&self, most: f64) -> f64 {
        let beyond = most * self.area / AREA_WEIGHT * (1.0 + 1e-9);
        if self.area > 0.0 && beyond.is_finite() && beyond >= 1e-200 {
            beyond
        } else {
            f64::INFINITY
        }
    }

    /// The length error of the line from `a` to `b`, weighted, computed as
    /// [`LoopView::line`] computes it.
    ///
    /// `area_error + length_error` is never above the line's score, to the last bit:
    /// the score adds the angle error (at least zero) before these two and the spacing
    /// error (at least zero) after them, and rounding never makes a sum smaller than
    /// it would be without a term at least zero (see [`best_visible`]).
    fn length_error(&self, a: usize, b: usize, scale: f64) -> f64 {
        LENGTH_WEIGHT * (self.p[b] - self.p[a]).length() / scale
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
        // Summed in this order: see [`LoopView::length_error`].
        let score = ANGLE_WEIGHT * angles / 4.0
            + self.area_error((first - second).abs())
            + LENGTH_WEIGHT * length / scale
            + SPACING_WEIGHT * spacing_error(pieces) / target;
        Some(Line {
            score,
            a,
            b,
            pieces,
        })
    }
}

impl LoopView {
    /// How badly the halves of `line` small enough to be finished at once would be
    /// finished ([`small_error`]; zero when neither is small), with what
    /// [`best_small`] made of each small half.
    fn small_halves(&self, line: &Line) -> SmallHalves {
        let Line { a, b, pieces, .. } = *line;
        let n = self.p.len();
        let along = |k: usize| self.p[a].lerp(self.p[b], k as f64 / pieces as f64);
        let mut charged = SmallHalves {
            error: 0.0,
            judged: [None, None],
        };
        if b - a + pieces <= SMALL {
            let half = SmallHalf::of(
                self.p[a..=b]
                    .iter()
                    .copied()
                    .chain((1..pieces).rev().map(along)),
            );
            let best = best_small(half.nodes());
            charged.error += small_error(best);
            charged.judged[0] = Some(best);
        }
        if n - (b - a) + pieces <= SMALL {
            let half = SmallHalf::of(
                self.p[b..]
                    .iter()
                    .chain(&self.p[..=a])
                    .copied()
                    .chain((1..pieces).map(along)),
            );
            let best = best_small(half.nodes());
            charged.error += small_error(best);
            charged.judged[1] = Some(best);
        }
        charged
    }
}

/// What [`best_small`] makes of a small loop: its best way's worst element and that
/// way's quads, or `None` where no way will do.
type SmallBest = Option<(f64, &'static [[usize; 4]])>;

/// A split line's charge for its small halves ([`LoopView::small_halves`]), and what
/// [`best_small`] made of each half that is small (first half, second half as
/// [`split_once`] returns them): the halves are finished with exactly those nodes, so
/// the finishing takes the verdict instead of judging them again.
struct SmallHalves {
    error: f64,
    judged: [Option<SmallBest>; 2],
}

/// The nodes of a half small enough to be finished at once, held on the stack: the
/// splitting charges such halves at every line it weighs, and a heap copy of each
/// cost as much as judging it.
struct SmallHalf {
    points: [DVec2; SMALL],
    count: usize,
}

impl SmallHalf {
    /// The first [`SMALL`] of `points` (a small half has no more).
    fn of(points: impl Iterator<Item = DVec2>) -> SmallHalf {
        let mut half = SmallHalf {
            points: [DVec2::ZERO; SMALL],
            count: 0,
        };
        for (slot, p) in half.points.iter_mut().zip(points) {
            *slot = p;
            half.count += 1;
        }
        half
    }

    /// The half's nodes, in loop order.
    fn nodes(&self) -> &[DVec2] {
        &self.points[..self.count]
    }
}

/// How badly a half small enough to be finished at once would be finished: by its
/// best way's worst element, and far worse than any other error when even that
/// element comes out folded or flat (a half of six nodes, five of them on one line),
/// so such a line is taken only when no other sees.
fn small_error(best: SmallBest) -> f64 {
    let worst = best.map_or(-1.0, |w| w.0);
    let folded = if worst < SMALL_FOLDED { 100.0 } else { 0.0 };
    SMALL_WEIGHT * (1.0 - worst) + folded
}

/// The best-scored line of the loop `l` that sees from end to end, among the lines
/// `scored` makes: lines are taken best first by their four errors, each then charged
/// for how its small halves would be finished and tried for sight only when it could
/// still beat the best found; the search stops once no line left can (the charge only
/// adds). Ties go to the lower loop positions.
///
/// Scoring every one of the `n^2 / 2` lines (two arc tangents and a size look-up each)
/// was most of the meshing time, so the search runs twice, pruned by the area and
/// length errors ([`LoopView::area_error`], [`LoopView::length_error`]), whose sum is
/// never above a line's score and which cost a few multiplications and a square root:
///
/// 1. from each node, the line to the later node that halves the area most evenly is
///    searched as above, giving a visible line and its charged score `s` (an upper
///    bound on the best's, since the best is the least charged score of any visible
///    line);
/// 2. every line whose area and length errors add to at most `s` is scored and
///    searched again. A line whose two errors add to more than `s` scores more than
///    `s`, so it can be neither the best nor tie with it, and is never reached by the
///    full search before it stops: the result is the same line, to the last bit, as
///    searching all lines. Without a line from the first pass, all lines are searched.
fn best_visible(
    points: &[DVec2],
    l: &[u32],
    view: &LoopView,
    scale: f64,
    scored: impl Fn(usize, usize) -> Option<Line>,
) -> Option<Chosen> {
    let n = l.len();
    // Whether a < b is a line: not a loop edge (nor a node to its own twin on a cut
    // line). Loop positions a and a + 1 are never paired.
    let pairs = |a: usize, b: usize| !((a == 0 && b == n - 1) || l[a] == l[b]);
    // The error never falls as the imbalance grows, so a line no more even than the
    // evenest so far cannot have a smaller error: only a more even one is divided out.
    let ordered = view.area > 0.0;
    let mut evenest: Vec<Line> = Vec::with_capacity(n);
    for a in 0..n {
        // The evenest line so far: its imbalance, its error and its far end.
        let mut most_even: Option<(f64, f64, usize)> = None;
        for b in a + 2..n {
            let imbalance = view.imbalance(a, b);
            if ordered && most_even.is_some_and(|m| imbalance >= m.0) {
                continue;
            }
            let error = view.area_error(imbalance);
            if pairs(a, b) && most_even.is_none_or(|m| error < m.1) {
                most_even = Some((imbalance, error, b));
            }
        }
        evenest.extend(most_even.and_then(|(_, _, b)| scored(a, b)));
    }
    let first = search(points, l, view, evenest.into_iter());
    let most = first.map_or(f64::INFINITY, |(line, _)| line.score);
    let beyond = view.imbalance_beyond(most);
    let mut pending: Vec<Pending> = Vec::new();
    for a in 0..n {
        for b in a + 2..n {
            // The area error alone first: cheap, and most lines fail it (most before
            // any division, by their imbalance).
            let imbalance = view.imbalance(a, b);
            if imbalance > beyond {
                continue;
            }
            let area = view.area_error(imbalance);
            if area > most || !pairs(a, b) {
                continue;
            }
            let bound = area + view.length_error(a, b, scale);
            if bound <= most {
                pending.push(Pending { bound, a, b });
            }
        }
    }
    search_bounded(points, l, view, pending, scored)
}

/// Whether `line` sees from end to end and passes its loop's other nodes no nearer than
/// a share of the spacing there (a line grazing a node leaves a sliver).
fn sees(points: &[DVec2], l: &[u32], view: &LoopView, line: &Line) -> bool {
    let clearance = CLEARANCE * view.spacing[line.a].min(view.spacing[line.b]);
    !blocked(points, l[line.a], l[line.b], &[l])
        && clear_of_nodes(&view.p, line.a, line.b, clearance)
}

/// The best of the lines a heap of them pops, best first (see [`best_visible`]),
/// each charged for its small halves; `more` is asked before each pop to push every
/// line that could still come before the heap's best.
fn search_heap(
    points: &[DVec2],
    l: &[u32],
    view: &LoopView,
    heap: &mut std::collections::BinaryHeap<Ranked>,
    mut more: impl FnMut(&mut std::collections::BinaryHeap<Ranked>),
) -> Option<Chosen> {
    let mut best: Option<Chosen> = None;
    loop {
        more(heap);
        let Some(Ranked(line)) = heap.pop() else {
            break;
        };
        if best.is_some_and(|b| line.score >= b.0.score) {
            break;
        }
        let charged = view.small_halves(&line);
        let full = Line {
            score: line.score + charged.error,
            ..line
        };
        if best.is_some_and(|b| full.score >= b.0.score) {
            continue;
        }
        if sees(points, l, view, &full) {
            best = Some((full, charged.judged));
        }
    }
    best
}

/// The line a search picks, charged for its small halves, with what [`best_small`]
/// made of each ([`SmallHalves::judged`]).
type Chosen = (Line, [Option<SmallBest>; 2]);

/// The best of `lines` that sees from end to end (see [`best_visible`]).
fn search(
    points: &[DVec2],
    l: &[u32],
    view: &LoopView,
    lines: impl Iterator<Item = Line>,
) -> Option<Chosen> {
    let mut heap = lines.map(Ranked).collect();
    search_heap(points, l, view, &mut heap, |_| {})
}

/// A pair of loop positions not scored yet, with a lower bound of its score (its area
/// and length errors, [`LoopView::length_error`]).
struct Pending {
    bound: f64,
    a: usize,
    b: usize,
}

/// The best of the `pending` lines that sees from end to end, as [`search`] finds it
/// among them all scored, scoring only the lines whose bound is at most the score of
/// the best line scored so far: scoring (two arc tangents and a size look-up) was
/// most of the splitting's time, and most candidates score well above the best.
///
/// The lines are taken in the same order, so the result is the same line: before
/// each pop, every pending line whose bound is at most the heap's best score is scored
/// and pushed. A line left pending then has a bound above that score, so its own score
/// (never below its bound) is above it too: it can neither come before the line popped
/// nor tie with it.
fn search_bounded(
    points: &[DVec2],
    l: &[u32],
    view: &LoopView,
    mut pending: Vec<Pending>,
    scored: impl Fn(usize, usize) -> Option<Line>,
) -> Option<Chosen> {
    // Least bound last, so the next to score is popped off the end.
    pending.sort_unstable_by(|x, y| y.bound.total_cmp(&x.bound));
    let mut heap = std::collections::BinaryHeap::new();
    search_heap(points, l, view, &mut heap, |heap| {
        while let Some(next) = pending.last() {
            if heap
                .peek()
                .is_some_and(|Ranked(top): &Ranked| next.bound > top.score)
            {
                break;
            }
            let (a, b) = (next.a, next.b);
            pending.pop();
            heap.extend(scored(a, b).map(Ranked));
        }
    })
}

/// A line ordered for [`std::collections::BinaryHeap`] so the best (lowest score, then
/// lowest loop positions) pops first.
struct Ranked(Line);

impl Ranked {
    fn key(&self) -> (f64, usize, usize) {
        (self.0.score, self.0.a, self.0.b)
    }
}

impl PartialEq for Ranked {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}

impl Eq for Ranked {}

impl PartialOrd for Ranked {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Ranked {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        let (x, y) = (self.key(), other.key());
        // Reversed: the heap pops its greatest.
        y.0.total_cmp(&x.0).then((y.1, y.2).cmp(&(x.1, x.2)))
    }
}

/// A loop (node ids, counter-clockwise) still to be split down, with what
/// [`best_small`] made of it where the split that left it had judged it already (a
/// small half charged to its line).
type ToSplit = (Vec<u32>, Option<SmallBest>);

/// The loop `l` (node ids, counter-clockwise) split at its best line: the two halves,
/// each with what [`best_small`] made of it if it is small (the two loops a split
/// leaves, each counter-clockwise), the line's new nodes added to `points`.
fn split_once(
    points: &mut Vec<DVec2>,
    l: &[u32],
    sizes: Sizes,
) -> Result<(ToSplit, ToSplit), QuadError> {
    let n = l.len();
    let view = LoopView::new(points, l);
    let scale = view.area.abs().sqrt().max(f64::MIN_POSITIVE);
    // Lines cutting no angle sharper than LEAST_ANGLE first; any line only where none
    // of those sees (a loop with a sliver corner of its own).
    let best = best_visible(points, l, &view, scale, |a, b| {
        view.line(a, b, scale, sizes, LEAST_ANGLE)
    })
    .or_else(|| {
        best_visible(points, l, &view, scale, |a, b| {
            view.line(a, b, scale, sizes, 1e-6)
        })
    })
    .ok_or(QuadError::NoSplit {
        nodes: n,
        at: view.p[0],
    })?;
    let (Line { a, b, pieces, .. }, [first_judged, second_judged]) = best;
    // The same nodes, to the bit, as the charge judged the small halves on.
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
    Ok(((first, first_judged), (second, second_judged)))
}

/// The ways of meshing a small loop of `n` nodes ([`make_small_ways`]), with the
/// distinct quads they use: the splitting judges them at every line it charges, and
/// the 26 ways of eight nodes use only 28 quads among their 80.
struct SmallWays {
    /// Each way's quads, by loop position (`n` the centre node).
    ways: Vec<Vec<[usize; 4]>>,
    /// The distinct quads, each once whichever corner it is written from (a quad's
    /// scaled Jacobian is the least of its corners', the same from any corner).
    quads: Vec<[usize; 4]>,
    /// Each way's quads as indices into `quads`.
    uses: Vec<Vec<usize>>,
    /// The distinct quads as the ways write them, from the corner they start at (the
    /// mean corner sine sums the corners in that order).
    written: Vec<[usize; 4]>,
    /// Each way's quads as indices into `written`.
    written_uses: Vec<Vec<usize>>,
}

/// The ways of meshing a small loop of `n` nodes, made once per `n`.
fn small_ways(n: usize) -> &'static SmallWays {
    static WAYS: [std::sync::OnceLock<SmallWays>; SMALL + 1] =
        [const { std::sync::OnceLock::new() }; SMALL + 1];
    static NONE: SmallWays = SmallWays {
        ways: Vec::new(),
        quads: Vec::new(),
        uses: Vec::new(),
        written: Vec::new(),
        written_uses: Vec::new(),
    };
    let Some(slot) = WAYS.get(n) else {
        return &NONE;
    };
    slot.get_or_init(|| {
        let ways = make_small_ways(n);
        let mut quads: Vec<[usize; 4]> = Vec::new();
        let uses = ways
            .iter()
            .map(|way| {
                way.iter()
                    .map(|q| {
                        // The quad written from its least corner.
                        let first = (0..4).min_by_key(|&i| q[i]).unwrap_or(0);
                        let key = [0, 1, 2, 3].map(|i| q[(first + i) % 4]);
                        index_of(&mut quads, key)
                    })
                    .collect()
            })
            .collect();
        let mut written: Vec<[usize; 4]> = Vec::new();
        let written_uses = ways
            .iter()
            .map(|way| way.iter().map(|q| index_of(&mut written, *q)).collect())
            .collect();
        SmallWays {
            ways,
            quads,
            uses,
            written,
            written_uses,
        }
    })
}

/// The index of `quad` in `distinct`, added at the end if it is not there yet.
fn index_of(distinct: &mut Vec<[usize; 4]>, quad: [usize; 4]) -> usize {
    match distinct.iter().position(|k| *k == quad) {
        Some(at) => at,
        None => {
            distinct.push(quad);
            distinct.len() - 1
        }
    }
}

/// Every way of meshing a small loop of `n` nodes (4, 6 or 8) into quads: each quad by
/// loop positions, position `n` being a centre node (the mean of the loop's nodes)
/// where the way has one.
fn make_small_ways(n: usize) -> Vec<Vec<[usize; 4]>> {
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
fn best_small(p: &[DVec2]) -> Option<(f64, &'static [[usize; 4]])> {
    let n = p.len();
    let centre = p.iter().copied().sum::<DVec2>() / n as f64;
    let at = |i: usize| if i < n { p[i] } else { centre };
    let table = small_ways(n);
    let jacobians: Vec<f64> = table
        .quads
        .iter()
        .map(|q| scaled_jacobian_2d(&q.map(at)))
        .collect();
    // Each way's worst element.
    let worsts: Vec<f64> = table
        .uses
        .iter()
        .map(|uses| {
            uses.iter()
                .map(|&k| jacobians[k])
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let best_worst = worsts.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // Between ways whose worst corners are alike (each with a straight corner where a
    // side has more nodes than the other), the one whose flattest element still spans
    // area: a quad on four nodes of one line is no element at all.
    // (A way whose worst is more than 0.02 below the best cannot win: the flattest
    // element moves the key by at most 0.01 either way.)
    let alike: Vec<usize> = (0..table.ways.len())
        .filter(|&w| worsts[w] >= best_worst - 0.02)
        .collect();
    let chosen = match alike.as_slice() {
        [] => return None,
        [only] => *only,
        _ => flattest_kept(table, &alike, at, &worsts)?,
    };
    Some((worsts[chosen], table.ways[chosen].as_slice()))
}

/// Among the ways `alike` (whose worst elements are within 0.02 of each other), the
/// one whose worst element plus a hundredth of its flattest element's mean corner sine
/// is greatest (the last of equals); each distinct quad's sine is worked out once.
fn flattest_kept(
    table: &SmallWays,
    alike: &[usize],
    at: impl Fn(usize) -> DVec2,
    worsts: &[f64],
) -> Option<usize> {
    let mut sines: Vec<Option<f64>> = vec![None; table.written.len()];
    let mut best: Option<(f64, usize)> = None;
    for &way in alike {
        let mut flattest = f64::INFINITY;
        for &k in &table.written_uses[way] {
            let sine =
                *sines[k].get_or_insert_with(|| mean_corner_sine_2d(&table.written[k].map(&at)));
            flattest = flattest.min(sine);
        }
        let key = worsts[way] + 0.01 * flattest;
        // As `max_by` keeps it: the last of equal keys.
        if best.is_none_or(|b| key.total_cmp(&b.0) != std::cmp::Ordering::Less) {
            best = Some((key, way));
        }
    }
    best.map(|b| b.1)
}

/// A small loop finished the best way (`best`, [`best_small`] of its nodes): its
/// quads, and the centre node's position if that way has one.
fn finish_small(points: &[DVec2], l: &[u32], best: SmallBest) -> (Vec<[u32; 4]>, Option<DVec2>) {
    let n = l.len();
    let Some((_, quads)) = best else {
        return (Vec::new(), None);
    };
    let centre = quads
        .iter()
        .any(|q| q.contains(&n))
        .then(|| l.iter().map(|&v| points[v as usize]).sum::<DVec2>() / n as f64);
    let id = |i: usize| if i < n { l[i] } else { points.len() as u32 };
    (quads.iter().map(|q| q.map(id)).collect(), centre)
}

/// A small loop whose every way of finishing leaves a quad folded (three or more of
/// its nodes on a nearly straight line, as where a crowded seam meets larger elements)
/// split at its best line instead, where that line carries nodes of its own and leaves
/// both halves smaller than the loop (so the splitting ends): the new nodes give the
/// straight run's middle nodes elements of their own. `None` where the loop is to be
/// finished as it is; the points are left as they were then. `best` is [`best_small`]
/// of the loop's nodes.
fn split_folded_small(
    points: &mut Vec<DVec2>,
    l: &[u32],
    best: SmallBest,
    sizes: Sizes,
) -> Result<Option<(ToSplit, ToSplit)>, QuadError> {
    if best.is_some_and(|(worst, _)| worst >= super::FOLDED) {
        return Ok(None);
    }
    let before = points.len();
    let Ok((first, second)) = split_once(points, l, sizes) else {
        points.truncate(before);
        return Ok(None);
    };
    if points.len() == before || first.0.len() >= l.len() || second.0.len() >= l.len() {
        points.truncate(before);
        return Ok(None);
    }
    Ok(Some((first, second)))
}

/// The loop `first` (node ids into `points`, counter-clockwise, an even count) split
/// down to quads, pushed to `quads`; an odd loop leaves a triangle in `triangles`.
///
/// Loops are split depth first, the first half's whole tree before the second's; where
/// both halves of a split have at least [`SIDE_BY_SIDE`] nodes, the two trees are split
/// side by side ([`split_halves_apart`]) and joined as if split one after the other:
/// the same nodes, numbers and elements, to the bit, on any number of threads.
pub fn split_down(
    points: &mut Vec<DVec2>,
    first: Vec<u32>,
    sizes: Sizes,
    quads: &mut Vec<[u32; 4]>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), QuadError> {
    split_tree(points, (first, None), sizes, SIDE_BY_SIDE, quads, triangles)
}

/// Halves of a split with at least this many nodes each are split down side by side:
/// a tree of some hundreds of quads, worth a task.
const SIDE_BY_SIDE: usize = 48;

/// The two halves of a split, split down at once, each on its own points (its loop's
/// nodes, numbered in the order first met, then the nodes it makes): the first half's
/// new nodes are then added to `points` and its elements pushed, then the second's. A
/// half splits only its own loop, which holds none of the other's new nodes, and reads
/// nothing of its node numbers but which are the same node, so this is what splitting
/// them one after the other makes. The first error, in that order, is returned.
fn split_halves_apart(
    points: &mut Vec<DVec2>,
    (first, second): (ToSplit, ToSplit),
    sizes: Sizes,
    side_by_side: usize,
    quads: &mut Vec<[u32; 4]>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), QuadError> {
    let shared: &[DVec2] = points;
    let tree = |(l, judged): ToSplit| {
        let (mut own, nodes) = on_its_own(shared, &l);
        let (mut q, mut t) = (Vec::new(), Vec::new());
        split_tree(
            &mut own.points,
            (own.l, judged),
            sizes,
            side_by_side,
            &mut q,
            &mut t,
        )
        .map(|()| (own.points.split_off(nodes.len()), nodes, q, t))
    };
    let (one, two) = rayon::join(|| tree(first), || tree(second));
    for (made, nodes, half_quads, half_triangles) in [one?, two?] {
        // The half's own numbers: its loop's nodes first, then those it made.
        let (given, base) = (nodes.len() as u32, points.len() as u32);
        let id = |v: u32| {
            if v < given {
                nodes[v as usize]
            } else {
                base + (v - given)
            }
        };
        points.extend(made);
        quads.extend(half_quads.into_iter().map(|q| q.map(id)));
        triangles.extend(half_triangles.into_iter().map(|t| t.map(id)));
    }
    Ok(())
}

/// A loop on points of its own: its nodes' positions and the loop in their numbers.
struct OwnLoop {
    points: Vec<DVec2>,
    l: Vec<u32>,
}

/// The loop `l` renumbered onto points of its own (each node once, in the order first
/// met: a cut line's node walked twice stays one node), and each own node's id in
/// `points`.
fn on_its_own(points: &[DVec2], l: &[u32]) -> (OwnLoop, Vec<u32>) {
    let mut own_id: std::collections::HashMap<u32, u32> = Default::default();
    let mut nodes: Vec<u32> = Vec::with_capacity(l.len());
    let own_l = l
        .iter()
        .map(|&v| {
            *own_id.entry(v).or_insert_with(|| {
                nodes.push(v);
                nodes.len() as u32 - 1
            })
        })
        .collect();
    let own_points = nodes.iter().map(|&v| points[v as usize]).collect();
    (
        OwnLoop {
            points: own_points,
            l: own_l,
        },
        nodes,
    )
}

/// [`split_down`] from a loop with what [`best_small`] made of it, if known, the
/// halves of a split split side by side where both have at least `side_by_side` nodes.
fn split_tree(
    points: &mut Vec<DVec2>,
    start: ToSplit,
    sizes: Sizes,
    side_by_side: usize,
    quads: &mut Vec<[u32; 4]>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), QuadError> {
    let mut stack: Vec<ToSplit> = vec![start];
    while let Some((l, judged)) = stack.pop() {
        let n = l.len();
        if n < 3 {
            continue;
        }
        if n == 3 {
            triangles.push([l[0], l[1], l[2]]);
            continue;
        }
        if n % 2 == 0 && n <= SMALL {
            let best = judged.unwrap_or_else(|| {
                let p: Vec<DVec2> = l.iter().map(|&v| points[v as usize]).collect();
                best_small(&p)
            });
            if let Some(halves) = split_folded_small(points, &l, best, sizes)? {
                stack.push(halves.1);
                stack.push(halves.0);
                continue;
            }
            let (made, extra) = finish_small(points, &l, best);
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
        if first.0.len().min(second.0.len()) >= side_by_side {
            // Both trees finished here, before the loops below on the stack.
            split_halves_apart(
                points,
                (first, second),
                sizes,
                side_by_side,
                quads,
                triangles,
            )?;
            continue;
        }
        stack.push(second);
        stack.push(first);
    }
    Ok(())
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::geom::mesh::quad::quality::worst_quad_2d;

    /// A 4 x 2 strip's eight nodes, counter-clockwise from its bottom left: five along
    /// its bottom (the middle one 0.03 below the line), three along its top.
    pub(in crate::geom::mesh::quad) fn bowed_strip() -> Vec<DVec2> {
        vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, -0.03),
            DVec2::new(3.0, 0.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(4.0, 2.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ]
    }

    /// An eight-node loop with five nodes along its bottom (bowed a little) and three
    /// along its top: every way of finishing it at once leaves a quad on three bottom
    /// nodes, nearly straight; split on a line with a node of its own, all its quads
    /// have fair corners.
    /// Splitting the halves of large splits side by side makes what splitting them one
    /// after the other makes: the same nodes in the same order and the same elements,
    /// to the bit, on a wavy-topped 60 x 40 region of 200 boundary nodes (its first
    /// splits leave halves of about a hundred).
    #[test]
    fn halves_split_side_by_side_make_what_one_after_the_other_makes() {
        let mut boundary: Vec<DVec2> = Vec::new();
        boundary.extend((0..60).map(|i| DVec2::new(i as f64, 0.0)));
        boundary.extend((0..40).map(|j| DVec2::new(60.0, j as f64)));
        boundary.extend((0..60).map(|i| {
            let x = 60.0 - i as f64;
            DVec2::new(x, 40.0 + 3.0 * (x / 7.0).sin())
        }));
        boundary.extend((0..40).map(|j| DVec2::new(0.0, 40.0 - j as f64)));
        let split = |side_by_side: usize| {
            let mut points = boundary.clone();
            let (mut quads, mut triangles) = (Vec::new(), Vec::new());
            split_tree(
                &mut points,
                ((0..boundary.len() as u32).collect(), None),
                Sizes::uniform(1.0),
                side_by_side,
                &mut quads,
                &mut triangles,
            )
            // A plain region with an even count of distinct boundary nodes: it splits.
            .expect("split");
            (points, quads, triangles)
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            // Two worker threads are always available to a test process.
            .expect("a pool of two threads");
        let apart = pool.install(|| split(SIDE_BY_SIDE));
        let in_turn = split(usize::MAX);
        assert!(in_turn.1.len() > 2000, "{} quads", in_turn.1.len());
        assert_eq!(apart, in_turn);
    }

    /// The line the pruned search picks, found the slow way: every pair of loop
    /// positions scored, charged for its small halves and tried for sight, the least
    /// by charged score (ties to the lower four-error score, then the lower positions,
    /// the order the search pops them in).
    fn best_line_of_all(
        points: &[DVec2],
        l: &[u32],
        view: &LoopView,
        scored: impl Fn(usize, usize) -> Option<Line>,
    ) -> Option<(f64, f64, usize, usize)> {
        let n = l.len();
        let mut best: Option<(f64, f64, usize, usize)> = None;
        for a in 0..n {
            for b in a + 2..n {
                if (a == 0 && b == n - 1) || l[a] == l[b] {
                    continue;
                }
                let Some(line) = scored(a, b) else { continue };
                let full = Line {
                    score: line.score + view.small_halves(&line).error,
                    ..line
                };
                if !sees(points, l, view, &full) {
                    continue;
                }
                let key = (full.score, line.score, a, b);
                if best.is_none_or(|k| key.partial_cmp(&k) == Some(std::cmp::Ordering::Less)) {
                    best = Some(key);
                }
            }
        }
        best
    }

    proptest::proptest! {
        /// The search's two prunings (by the area and length errors, and the area
        /// scans' comparisons of imbalances before any division) pick the very line
        /// that scoring every line picks, on star-shaped loops of uneven spacing.
        #[test]
        fn the_pruned_search_picks_the_line_of_all_lines(
            radii in proptest::collection::vec(0.4f64..1.6, 8..40),
            wobble in proptest::collection::vec(-0.3f64..0.3, 40),
            stretch in 0.3f64..3.0,
        ) {
            let n = radii.len() + radii.len() % 2;
            let points: Vec<DVec2> = (0..n)
                .map(|i| {
                    let t = std::f64::consts::TAU * (i as f64 + wobble[i]) / n as f64;
                    let r = 10.0 * radii[i % radii.len()];
                    DVec2::new(stretch * r * t.cos(), r * t.sin())
                })
                .collect();
            let l: Vec<u32> = (0..n as u32).collect();
            let view = LoopView::new(&points, &l);
            let scale = view.area.abs().sqrt();
            let sizes = Sizes::uniform(2.0);
            let scored = |a: usize, b: usize| view.line(a, b, scale, sizes, LEAST_ANGLE);
            let pruned = best_visible(&points, &l, &view, scale, scored)
                .map(|(line, _)| (line.score, line.a, line.b));
            let all = best_line_of_all(&points, &l, &view, scored)
                .map(|(score, _, a, b)| (score, a, b));
            proptest::prop_assert_eq!(pruned, all);
        }
    }

    #[test]
    fn a_small_loop_that_would_finish_folded_is_split_on_new_nodes() {
        let mut points = bowed_strip();
        let at_once = best_small(&points).map(|w| w.0);
        assert!(
            at_once.is_some_and(|w| w < crate::geom::mesh::quad::FOLDED),
            "{at_once:?}"
        );
        let (mut quads, mut triangles) = (Vec::new(), Vec::new());
        split_down(
            &mut points,
            (0..8).collect(),
            Sizes::uniform(1.0),
            &mut quads,
            &mut triangles,
        )
        .expect("split");
        assert!(triangles.is_empty());
        assert!(points.len() > 8, "no node was added");
        let worst = worst_quad_2d(&points, &quads);
        assert!(worst > 0.3, "{worst}");
    }
}
