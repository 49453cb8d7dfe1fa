//! The run-out of a bead's height at its tapered ends: the profile is lowered into the
//! binder, not squashed.
//!
//! Squashing a profile to a fraction `f` of its height scales its curvature by about
//! `f` where it is flat and by `1 / f` where it is steep: the shoulders sharpen to radii
//! near `f^2 r` just where the sheet bends over them. Lowering keeps the shape: the
//! profile moved down by `(1 - f) H` and cut at the binder line, so the crest stands at
//! `f H` with its drawn radius, and the new feet are rounded with the shoulder radius (a
//! circle tangent to the binder line and to the lowered profile), as a die maker would
//! sink the bead into the binder.

use std::cmp::Ordering;

use glam::DVec2;

/// Points on each rounded new foot. The sections' points are taken from this polyline,
/// so its chords must be far finer than their spacing: with 24 points a 3 mm foot's
/// chords (0.13 mm) left the curve through the sections sharper than drawn (2.69 mm on
/// the door's sill); at 192 the rounded foot keeps its radius (2.77 mm, as the full
/// height does).
const FOOT_ARC_POINTS: usize = 192;

/// How closely (mm) a foot circle's centre is found: far below anything the skin,
/// its tolerances (0.0005 mm at the feet) or a tessellation resolves. Finding it to
/// the last bit of a double took half as many steps again, and a third of a run-out
/// section's time.
const CENTRE_TOLERANCE: f64 = 1e-10;

/// Bisection steps for a foot circle's centre.
const BISECTIONS: usize = 60;

/// The profile `dense` (s, height), a fine polyline from foot to foot at height 0,
/// lowered to `factor` (0 to 1) of its height: moved down by `(1 - factor) H` (H its
/// tallest point), cut at height 0, and rounded at every new foot, foot `i` (counted
/// from the left) with the radius `radius(i)` (0 for a sharp foot). A profile with
/// several crests (a double bead) may be cut into several bumps, each rounded at both
/// its feet. The result runs over the same s from foot to foot, flat at height 0
/// outside and between the bumps, as a fine polyline; with it, the s where each new
/// foot meets the binder line, left to right (a rising foot, then a falling one, per
/// bump).
pub(super) fn lowered(
    dense: &[DVec2],
    factor: f64,
    radius: impl Fn(usize) -> f64,
) -> (Vec<DVec2>, Vec<f64>) {
    let tallest = dense.iter().map(|p| p.y).fold(0.0, f64::max);
    let (Some(head), Some(tail)) = (dense.first(), dense.last()) else {
        return (Vec::new(), Vec::new());
    };
    let (first, last) = (head.x, tail.x);
    if factor >= 1.0 || dense.len() < 3 {
        return (dense.to_vec(), vec![first, last]);
    }
    if factor <= 0.0 || tallest <= 0.0 {
        let middle = 0.5 * (first + last);
        return (
            vec![DVec2::new(first, 0.0), DVec2::new(last, 0.0)],
            vec![middle, middle],
        );
    }
    let drop = (1.0 - factor) * tallest;
    let moved: Vec<DVec2> = dense.iter().map(|p| *p - DVec2::Y * drop).collect();
    let crests = crests(&moved, BUMP_HEIGHT * tallest);
    if crests.is_empty() {
        let middle = 0.5 * (first + last);
        return (
            vec![DVec2::new(first, 0.0), DVec2::new(last, 0.0)],
            vec![middle, middle],
        );
    }
    // Each bump runs from the lowest point before its crest (the profile's start for
    // the first) to the lowest point after it: its left half rounded at its foot, its
    // right half mirrored (s -> -s, run from its foot), rounded and mirrored back.
    let lowest = |from: usize, to: usize| -> usize {
        (from..=to)
            .min_by(|&a, &b| moved[a].y.total_cmp(&moved[b].y))
            .expect("a crest lies after the one before it: the range is not empty")
    };
    let mut bounds = vec![0];
    for pair in crests.windows(2) {
        bounds.push(lowest(pair[0], pair[1]));
    }
    bounds.push(moved.len() - 1);
    let mut out: Vec<DVec2> = Vec::with_capacity(moved.len() + 2 * FOOT_ARC_POINTS);
    let mut feet = Vec::with_capacity(2 * crests.len());
    for (j, &top) in crests.iter().enumerate() {
        let (from, to) = (bounds[j], bounds[j + 1]);
        let (left, c0) = rounded_foot(&moved[from..=top], moved[from].x, radius(2 * j));
        let mirrored: Vec<DVec2> = moved[top..=to]
            .iter()
            .rev()
            .map(|p| DVec2::new(-p.x, p.y))
            .collect();
        let (right, c1) = rounded_foot(&mirrored, -moved[to].x, radius(2 * j + 1));
        // Neighbouring bumps meet at the same flat point: it is kept once.
        let skip = usize::from(!out.is_empty());
        out.extend(left.into_iter().skip(skip));
        out.extend(right.iter().rev().skip(1).map(|p| DVec2::new(-p.x, p.y)));
        feet.push(c0);
        feet.push(-c1);
    }
    (out, feet)
}

/// How tall (as a fraction of the profile's height) a run above the binder line must
/// stand to count as a bump of its own: a run lower than this is noise where a flat of
/// the profile lies at the cut.
const BUMP_HEIGHT: f64 = 1e-9;

/// The crest (tallest point) of each run of `moved` that stands above height 0 by
/// more than `least`, left to right.
fn crests(moved: &[DVec2], least: f64) -> Vec<usize> {
    let mut crests = Vec::new();
    let mut run: Option<usize> = None;
    for (i, p) in moved.iter().enumerate() {
        if p.y > 0.0 {
            run = match run {
                Some(best) if moved[best].y >= p.y => Some(best),
                _ => Some(i),
            };
        } else if let Some(best) = run.take() {
            if moved[best].y > least {
                crests.push(best);
            }
        }
    }
    if let Some(best) = run {
        if moved[best].y > least {
            crests.push(best);
        }
    }
    crests
}

/// One half of a lowered profile, `half` running from its (sunk) foot up to the crest,
/// cut at height 0 and rounded with a circle of `radius` tangent to height 0 and to
/// the profile; flat at height 0 from `foot` (the original foot's s) to the circle.
/// With it, the s where the rounded foot meets height 0.
fn rounded_foot(half: &[DVec2], foot: f64, radius: f64) -> (Vec<DVec2>, f64) {
    // Where the lowered profile first rises through height 0.
    let Some(up) = half.iter().position(|p| p.y > 0.0) else {
        let end = half[half.len() - 1].x;
        return (vec![DVec2::new(foot, 0.0), DVec2::new(end, 0.0)], end);
    };
    let crossing = if up == 0 {
        half[0]
    } else {
        let (a, b) = (half[up - 1], half[up]);
        a.lerp(b, -a.y / (b.y - a.y))
    };
    let mut out = vec![DVec2::new(foot, 0.0)];
    if radius <= 0.0 {
        if crossing.x > foot {
            out.push(DVec2::new(crossing.x, 0.0));
        }
        out.extend_from_slice(&half[up..]);
        return (out, crossing.x.max(foot));
    }
    let segments = Segments::new(half);
    let (mut c, mut last_touch) = foot_centre(&segments, crossing.x, up, radius);
    let mut radius = radius;
    if c < foot {
        // The circle would start before the profile's own foot (the run-out moves the
        // feet across faster than its raised radius fits): the largest radius that
        // starts at the foot, so the section never runs back on itself.
        let (mut lo, mut hi) = (0.0, radius);
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if foot_centre(&segments, crossing.x, up, mid).0 >= foot {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        radius = lo;
        (c, last_touch) = foot_centre(&segments, crossing.x, up, radius);
    }
    let (segment, touch) = segments.nearest(DVec2::new(c, radius), last_touch);
    let centre = DVec2::new(c, radius);
    if c > foot {
        out.push(DVec2::new(c, 0.0));
    }
    // The arc from straight below the centre round to the touching point.
    let start = -std::f64::consts::FRAC_PI_2;
    let end = (touch - centre).to_angle();
    for i in 1..FOOT_ARC_POINTS {
        let a = start + (end - start) * i as f64 / FOOT_ARC_POINTS as f64;
        out.push(centre + radius * DVec2::from_angle(a));
    }
    out.push(touch);
    out.extend(half[segment + 1..].iter().filter(|p| p.x > touch.x));
    (out, c.max(foot))
}

/// The centre's s of the foot circle of `radius` on the half profile `segments`,
/// which first rises through height 0 at `crossing` (after point `up - 1`), and the
/// segment it touches: every point of the profile lies at least `radius` from the
/// centre `(c, radius)` while c is left of the crossing by `radius` (nothing of the
/// profile is left of its foot, nothing below height 0 comes nearer than `radius`),
/// and within `radius` at the crossing itself; c is found by bisection between the two.
fn foot_centre(segments: &Segments, crossing: f64, up: usize, radius: f64) -> (f64, usize) {
    let mut last_touch = up.saturating_sub(1);
    let (mut lo, mut hi) = (crossing - radius, crossing);
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (lo + hi);
        let before = (lo, hi);
        match segments.within(DVec2::new(mid, radius), radius, last_touch) {
            Some(i) => {
                last_touch = i;
                hi = mid;
            }
            None => lo = mid,
        }
        // Whether a segment lies within reach does not depend on the hint, so a step
        // that leaves the bracket as it was (it is down to neighbouring numbers) would
        // leave it so at every step after: the rest of the steps are skipped. A bracket
        // narrower than CENTRE_TOLERANCE is as good as settled.
        if (lo, hi) == before || hi - lo <= CENTRE_TOLERANCE {
            break;
        }
    }
    (0.5 * (lo + hi), last_touch)
}

/// Steps in the height factor for how fast the new feet move across.
const FACTOR_STEP: f64 = 1e-4;

/// The profile `dense` run out to `factor` of its height by [`lowered`], where the
/// factor changes by `rate` per mm along the bead. The new feet then run across the
/// bead at a slope `m` (mm across per mm along), and a skin whose sections are rounded
/// with a radius `r` is rounded, across its foot line, with about `r / (1 + m^2)`;
/// each foot's radius is raised by `1 + m^2` (from the slope found with the drawn
/// radius, then once more with the raised one) so the skin keeps the drawn one. Rising
/// feet are drawn with the profile's left foot radius `feet.0`, falling ones with its
/// right `feet.1`. Before it is lowered, the profile is stretched for the descent of
/// its upper part ([`stretched_for_descent`]).
pub(super) fn run_out(dense: &[DVec2], factor: f64, feet: (f64, f64), rate: f64) -> Vec<DVec2> {
    let drawn = |i: usize| if i % 2 == 0 { feet.0 } else { feet.1 };
    if factor >= 1.0 || factor <= 0.0 || rate == 0.0 {
        return lowered(dense, factor, drawn).0;
    }
    let stretched = stretched_for_descent(dense, rate);
    let dense = &stretched[..];
    let mut radii: Vec<f64> = Vec::new();
    let radius_of = |radii: &[f64], i: usize| radii.get(i).copied().unwrap_or(drawn(i));
    for _ in 0..2 {
        let (a, b) = (
            (factor - FACTOR_STEP).max(0.0),
            (factor + FACTOR_STEP).min(1.0),
        );
        let (_, low) = lowered(dense, a, |i| radius_of(&radii, i));
        let (_, high) = lowered(dense, b, |i| radius_of(&radii, i));
        // Feet matched by their order; where a bump appears or goes between the two
        // factors, only the outermost two are matched.
        let slopes: Vec<f64> = if low.len() == high.len() {
            low.iter()
                .zip(&high)
                .map(|(x0, x1)| (x1 - x0) / (b - a) * rate)
                .collect()
        } else {
            let n = high.len();
            (0..n)
                .map(|i| match i {
                    0 => (high[0] - low[0]) / (b - a) * rate,
                    _ if i + 1 == n => (high[n - 1] - low[low.len() - 1]) / (b - a) * rate,
                    _ => 0.0,
                })
                .collect()
        };
        radii = slopes
            .iter()
            .enumerate()
            .map(|(i, m)| drawn(i) * (1.0 + m.min(MAX_FOOT_SLOPE).powi(2)).powi(2))
            .collect();
    }
    lowered(dense, factor, |i| radius_of(&radii, i)).0
}

/// The profile `dense` stretched in height about its crest so the run-out keeps its
/// shape square to the way it runs. Lowering moves every point of the profile down by
/// the same amount, at `rate * H` per mm along the bead (H the crest's height): the
/// skin there is a cylinder whose rulings descend at that slope `m`, and its cross
/// section square to them is the section squashed in height by `1 / sqrt(1 + m^2)`
/// (a 3 mm shoulder on a flank came out at 2.62 mm where a 5 mm bead runs out over
/// 30 mm). Stretched by `sqrt(1 + m^2)` beforehand, the squashed section is the drawn
/// profile again.
fn stretched_for_descent(dense: &[DVec2], rate: f64) -> Vec<DVec2> {
    let tallest = dense.iter().map(|p| p.y).fold(0.0, f64::max);
    let m = tallest * rate;
    let k = (1.0 + m * m).sqrt();
    dense
        .iter()
        .map(|p| DVec2::new(p.x, tallest - (tallest - p.y) * k))
        .collect()
}

/// The steepest foot slope (mm across per mm along) a foot radius is raised for: a
/// taper too short for its bead's height moves the feet across faster than they can be
/// rounded (at 5 mm across per mm the raised radius was 75 times the drawn one and the
/// foot reached 60 mm from the centre line). Beyond it the skin comes out sharper than
/// drawn, which the end radius figure shows.
const MAX_FOOT_SLOPE: f64 = 1.0;

/// Segments of a half profile per block: a block's bounding box.
const BLOCK: usize = 8;

/// A polyline's segments with the bounding box of every [`BLOCK`] of them, so the
/// segments near a point are found without measuring the far ones: the foot circle
/// only ever comes near the few segments around the crossing, and each of its
/// [`BISECTIONS`] steps asks again.
pub(super) struct Segments<'a> {
    points: &'a [DVec2],
    /// (lower corner, upper corner) of segments `k * BLOCK ..` up to `BLOCK` of them.
    boxes: Vec<(DVec2, DVec2)>,
}

impl<'a> Segments<'a> {
    /// The segments of `points`, boxed.
    pub(super) fn new(points: &'a [DVec2]) -> Self {
        let count = points.len().saturating_sub(1);
        let boxes = (0..count)
            .step_by(BLOCK)
            .map(|first| {
                let block = &points[first..=(first + BLOCK).min(count)];
                block
                    .iter()
                    .fold((block[0], block[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)))
            })
            .collect();
        Self { points, boxes }
    }

    /// Segment `i`'s distance from `p`, and its point nearest `p`.
    fn distance(&self, i: usize, p: DVec2) -> (f64, DVec2) {
        let q = nearest_on_segment(self.points[i], self.points[i + 1], p);
        (q.distance(p), q)
    }

    /// The segments of the blocks whose box may come within `reach` of `p`. The box
    /// distance is a lower bound of every distance in the block; the margin covers the
    /// rounding in the nearest point, so no block is passed over that holds a segment
    /// whose computed distance is at most `reach`.
    fn candidates(&self, p: DVec2, reach: f64) -> impl Iterator<Item = usize> + '_ {
        let margin = 1e-9 * (1.0 + p.abs().max_element() + reach.abs());
        let count = self.points.len().saturating_sub(1);
        self.boxes
            .iter()
            .enumerate()
            .filter(move |(_, (lo, hi))| {
                let outside = (*lo - p).max(p - *hi).max(DVec2::ZERO);
                // Kept unless surely beyond reach (a NaN distance is kept).
                outside.length().partial_cmp(&(reach + margin)) != Some(Ordering::Greater)
            })
            .flat_map(move |(k, _)| k * BLOCK..(k * BLOCK + BLOCK).min(count))
    }

    /// A segment at most `radius` from `p`, trying segment `hint` first (the one the
    /// last step touched); `None` if every segment lies farther (or is not a number).
    fn within(&self, p: DVec2, radius: f64, hint: usize) -> Option<usize> {
        if hint + 1 < self.points.len() && self.distance(hint, p).0 <= radius {
            return Some(hint);
        }
        self.candidates(p, radius)
            .find(|&i| self.distance(i, p).0 <= radius)
    }

    /// The segment nearest `p` (the first of equally near ones) and its point nearest
    /// `p`, starting from segment `hint` for the bound.
    fn nearest(&self, p: DVec2, hint: usize) -> (usize, DVec2) {
        let count = self.points.len().saturating_sub(1);
        let mut best = (f64::INFINITY, 0, DVec2::ZERO);
        let consider = |best: &mut (f64, usize, DVec2), i: usize| {
            let (d, q) = self.distance(i, p);
            if d < best.0 || (d == best.0 && i < best.1) {
                *best = (d, i, q);
            }
        };
        if hint < count {
            consider(&mut best, hint);
        }
        for i in self.candidates(p, best.0) {
            consider(&mut best, i);
        }
        (best.1, best.2)
    }

    /// The distance from `p` to the polyline (infinite for a single point), found
    /// starting from the segment `hint`, which becomes the nearest segment: callers
    /// marching along the polyline pass the same `hint` again.
    pub(super) fn distance_from(&self, p: DVec2, hint: &mut usize) -> f64 {
        let (i, q) = self.nearest(p, *hint);
        *hint = i;
        if self.points.len() < 2 {
            return f64::INFINITY;
        }
        q.distance(p)
    }
}

/// The point of the segment from `a` to `b` nearest to `p`.
fn nearest_on_segment(a: DVec2, b: DVec2, p: DVec2) -> DVec2 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    a + d * t
}

/// The fine polyline `line` resampled at corresponding points: `counts[j]` equal steps
/// of arc length in each piece between the rule positions `rules` (s across), so the
/// result has as many points as the matched profiles and its rule points where theirs
/// are.
pub(super) fn resampled(line: &[DVec2], rules: &[f64], counts: &[usize]) -> Vec<DVec2> {
    let mut lengths = Vec::with_capacity(line.len());
    let mut acc = 0.0;
    lengths.push(0.0);
    for w in line.windows(2) {
        acc += w[0].distance(w[1]);
        lengths.push(acc);
    }
    let length_at_s = |s: f64| -> f64 {
        let i = line
            .windows(2)
            .position(|w| w[0].x <= s && s <= w[1].x)
            .unwrap_or(line.len() - 2);
        let (a, b) = (line[i], line[i + 1]);
        let t = if b.x > a.x {
            ((s - a.x) / (b.x - a.x)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        lengths[i] + t * (lengths[i + 1] - lengths[i])
    };
    let point_at = |l: f64| -> DVec2 {
        let i = lengths.partition_point(|&x| x < l).clamp(1, line.len() - 1);
        let (la, lb) = (lengths[i - 1], lengths[i]);
        let t = if lb > la { (l - la) / (lb - la) } else { 0.0 };
        line[i - 1].lerp(line[i], t.clamp(0.0, 1.0))
    };
    let mut cuts = vec![0.0];
    cuts.extend(rules.iter().map(|&s| length_at_s(s)));
    cuts.push(acc);
    let mut out = Vec::new();
    for (j, &count) in counts.iter().enumerate() {
        let first = if j == 0 { 0 } else { 1 };
        for i in first..=count {
            out.push(point_at(
                cuts[j] + (cuts[j + 1] - cuts[j]) * i as f64 / count as f64,
            ));
        }
    }
    out
}

/// The fine polyline `line` with its bends spread over `width` (mm of arc length): its
/// tangent angle averaged over a window of that length (held constant past the feet),
/// the points rebuilt from the averaged angles, and the small drift this leaves at the
/// far foot taken out in proportion to arc length, the tallest point kept at its
/// height. An average never exceeds what it averages, so no radius gets smaller;
/// where a drawn radius meets a straight piece or another radius, the curvature now
/// changes over `width` instead of at a point, which the curve through the section's
/// points follows with far less overshoot than a jump.
pub(super) fn smoothed(line: &[DVec2], width: f64) -> Vec<DVec2> {
    let m = line.len();
    if m < 3 || width <= 0.0 {
        return line.to_vec();
    }
    let mut lengths = Vec::with_capacity(m - 1);
    let mut angles: Vec<f64> = Vec::with_capacity(m - 1);
    for w in line.windows(2) {
        let d = w[1] - w[0];
        lengths.push(d.length());
        let mut a = d.to_angle();
        if let Some(&prev) = angles.last() {
            // Unwrapped, so averaging never crosses the +-180 deg seam.
            while a - prev > std::f64::consts::PI {
                a -= std::f64::consts::TAU;
            }
            while a - prev < -std::f64::consts::PI {
                a += std::f64::consts::TAU;
            }
        }
        angles.push(a);
    }
    // Arc length at each segment's start, and the running integral of the angle.
    let mut starts = Vec::with_capacity(m);
    let mut integral = Vec::with_capacity(m);
    let (mut l, mut area) = (0.0, 0.0);
    for (len, a) in lengths.iter().zip(&angles) {
        starts.push(l);
        integral.push(area);
        l += len;
        area += len * a;
    }
    starts.push(l);
    integral.push(area);
    let total = l;
    let (first, last) = (angles[0], angles[angles.len() - 1]);
    // The integral of the angle from 0 to x, constant angles continued past the ends;
    // the segment holding x is looked for from `from` on (see `Walk`).
    let integral_to = |x: f64, from: &mut Walk| -> f64 {
        if x <= 0.0 {
            return x * first;
        }
        if x >= total {
            return area + (x - total) * last;
        }
        let i = from.last_at_most(&starts, x);
        integral[i] + (x - starts[i]) * angles[i]
    };
    let (mut ahead, mut behind) = (Walk::new(total), Walk::new(total));
    let mut out = Vec::with_capacity(m);
    out.push(line[0]);
    let mut at = 0.0;
    for (len, _) in lengths.iter().zip(&angles) {
        let mid = at + 0.5 * len;
        let a = (integral_to(mid + 0.5 * width, &mut ahead)
            - integral_to(mid - 0.5 * width, &mut behind))
            / width;
        let p = out[out.len() - 1] + *len * DVec2::from_angle(a);
        out.push(p);
        at += len;
    }
    let drift = out[m - 1] - line[m - 1];
    let mut at = 0.0;
    for (i, p) in out.iter_mut().enumerate() {
        *p -= drift * (at / total);
        if i + 1 < m {
            at += lengths[i];
        }
    }
    let tallest = line.iter().map(|p| p.y).fold(0.0, f64::max);
    let now = out.iter().map(|p| p.y).fold(0.0, f64::max);
    if now > 0.0 {
        for p in &mut out {
            p.y *= tallest / now;
        }
    }
    out
}

/// The last index `i` with `starts[i] <= x` in a non-decreasing `starts` (whose first
/// entry is at most `x`), for `x` that only grow from one question to the next: walked
/// on from the last answer, the index a binary search finds (`partition_point`). A
/// table with a length that is not a number (`total`) is searched every time.
struct Walk {
    at: usize,
    search: bool,
}

impl Walk {
    fn new(total: f64) -> Self {
        Self {
            at: 0,
            search: !total.is_finite(),
        }
    }

    fn last_at_most(&mut self, starts: &[f64], x: f64) -> usize {
        if self.search {
            return starts.partition_point(|&s| s <= x) - 1;
        }
        while self.at + 1 < starts.len() && starts[self.at + 1] <= x {
            self.at += 1;
        }
        self.at
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every segment measured, the first nearest kept: what [`Segments`] must answer.
    fn brute_nearest(points: &[DVec2], p: DVec2) -> (f64, usize, DVec2) {
        let mut best = (f64::INFINITY, 0, DVec2::ZERO);
        for (i, w) in points.windows(2).enumerate() {
            let q = nearest_on_segment(w[0], w[1], p);
            let d = q.distance(p);
            if d < best.0 {
                best = (d, i, q);
            }
        }
        best
    }

    /// Two round bumps of height 5 on a flat at height 0 (a double bead): feet at -20 and
    /// 20, crests at -10 and 10, flat between -2 and 2.
    fn double_profile() -> Vec<DVec2> {
        (0..=4000)
            .map(|i| {
                let x = -20.0 + 0.01 * i as f64;
                let bump = |c: f64| (5.0 * (1.0 - ((x - c) / 8.0).powi(2))).max(0.0);
                DVec2::new(x, bump(-10.0) + bump(10.0))
            })
            .collect()
    }

    /// Whether `line` never runs back across (s never decreases) and never dips below
    /// the binder line.
    fn runs_forward_above_the_binder(line: &[DVec2]) -> bool {
        line.windows(2).all(|w| w[1].x >= w[0].x - 1e-12) && line.iter().all(|p| p.y >= -1e-12)
    }

    #[test]
    fn a_double_profile_is_lowered_bump_by_bump() {
        let dense = double_profile();
        let (line, feet) = lowered(&dense, 0.5, |_| 2.0);
        // Both bumps cut, each with a rising and a falling foot, the flat between them
        // at the binder line, the crests at half height.
        assert_eq!(feet.len(), 4, "{feet:?}");
        assert!(feet.windows(2).all(|w| w[1] > w[0]), "{feet:?}");
        assert!(feet[1] < 0.0 && feet[2] > 0.0, "{feet:?}");
        assert!(runs_forward_above_the_binder(&line));
        let tallest = line.iter().map(|p| p.y).fold(0.0, f64::max);
        assert!((tallest - 2.5).abs() < 1e-9, "{tallest}");
        let middle = line.iter().filter(|p| p.x.abs() < feet[2].min(-feet[1]));
        assert!(middle.clone().count() > 0 && middle.into_iter().all(|p| p.y == 0.0));
    }

    #[test]
    fn a_foot_radius_too_large_for_the_room_starts_at_the_profiles_foot() {
        let dense = double_profile();
        // A radius far larger than the room between the old and the new foot: the
        // circle is made smaller, so the section still runs forward from -20.
        let (line, feet) = lowered(&dense, 0.9, |_| 500.0);
        assert!(runs_forward_above_the_binder(&line));
        assert!(feet[0] >= -20.0, "{feet:?}");
        assert_eq!(line[0], DVec2::new(-20.0, 0.0));
    }

    #[test]
    fn walking_forward_finds_what_the_binary_search_finds() {
        // Segment starts with repeated values (zero-length segments), asked at growing
        // places, some of them exactly on a start.
        let starts = [0.0, 0.5, 0.5, 0.5, 1.25, 2.0, 2.0, 3.75, 4.0];
        let mut walk = Walk::new(4.0);
        let mut x = 0.0;
        while x < 4.0 {
            let expected = starts.partition_point(|&s| s <= x) - 1;
            assert_eq!(walk.last_at_most(&starts, x), expected, "x = {x}");
            x += 0.125;
        }
        let mut search = Walk::new(f64::NAN);
        assert_eq!(search.last_at_most(&starts, 2.0), 6);
        assert_eq!(search.last_at_most(&starts, 0.25), 0);
    }

    #[test]
    fn boxed_segments_answer_as_measuring_every_segment() {
        // A lowered half profile: sunk below 0, rising through it to a crest, with a
        // run of repeated points (equally near segments) in between.
        let mut points: Vec<DVec2> = (0..=200)
            .map(|i| {
                let x = -10.0 + 0.05 * i as f64;
                DVec2::new(x, 6.0 * (1.0 - (x / 10.0).powi(2)) - 2.5)
            })
            .collect();
        points.splice(100..100, [points[100]; 3]);
        let segments = Segments::new(&points);
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let p = DVec2::new(-12.0 + 14.0 * next(), 8.0 * next());
            let radius = 6.0 * next();
            let hint = (next() * 203.0) as usize;
            let (d, i, q) = brute_nearest(&points, p);
            assert_eq!(segments.nearest(p, hint), (i, q));
            let mut marching = hint;
            assert_eq!(segments.distance_from(p, &mut marching), d);
            assert_eq!(marching, i);
            assert_eq!(
                segments.within(p, radius, hint).is_some(),
                d - radius <= 0.0
            );
        }
        let single = [DVec2::new(1.0, 2.0)];
        let one = Segments::new(&single);
        assert_eq!(one.nearest(DVec2::ZERO, 0), (0, DVec2::ZERO));
        assert_eq!(one.within(DVec2::ZERO, 1.0, 0), None);
    }
}
