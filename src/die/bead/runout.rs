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

/// Bisection steps for a foot circle's centre.
const BISECTIONS: usize = 60;

/// The profile `dense` (s, height), a fine polyline from foot to foot at height 0,
/// lowered to `factor` (0 to 1) of its height: moved down by `(1 - factor) H` (H its
/// tallest point), cut at height 0, and rounded at the new feet with the radii
/// `feet` (left, right; 0 for a sharp foot). The result runs over the same s from foot
/// to foot, flat at height 0 outside the new feet, as a fine polyline; with it, the s
/// where each new foot meets the binder line.
pub(super) fn lowered(dense: &[DVec2], factor: f64, feet: (f64, f64)) -> (Vec<DVec2>, (f64, f64)) {
    let tallest = dense.iter().map(|p| p.y).fold(0.0, f64::max);
    let (Some(head), Some(tail)) = (dense.first(), dense.last()) else {
        return (Vec::new(), (0.0, 0.0));
    };
    let (first, last) = (head.x, tail.x);
    if factor >= 1.0 || dense.len() < 3 {
        return (dense.to_vec(), (first, last));
    }
    if factor <= 0.0 || tallest <= 0.0 {
        let middle = 0.5 * (first + last);
        return (
            vec![DVec2::new(first, 0.0), DVec2::new(last, 0.0)],
            (middle, middle),
        );
    }
    let drop = (1.0 - factor) * tallest;
    let moved: Vec<DVec2> = dense.iter().map(|p| *p - DVec2::Y * drop).collect();
    let top = moved
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.y.total_cmp(&b.1.y))
        .map(|(i, _)| i)
        .expect("`dense` has at least three points: shorter ones returned above");
    // The left half, and the right half mirrored (s -> -s, run from its foot), each
    // rounded at its foot; then the right half mirrored back.
    let (left, c0) = rounded_foot(&moved[..=top], first, feet.0);
    let mirrored: Vec<DVec2> = moved[top..]
        .iter()
        .rev()
        .map(|p| DVec2::new(-p.x, p.y))
        .collect();
    let (right, c1) = rounded_foot(&mirrored, -last, feet.1);
    let mut out = left;
    out.extend(right.iter().rev().skip(1).map(|p| DVec2::new(-p.x, p.y)));
    (out, (c0, -c1))
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
    // The circle's centre (c, radius): every point of the profile lies at least
    // `radius` from it while c is left of the crossing by `radius` (nothing of the
    // profile is left of its foot, nothing below height 0 comes nearer than `radius`),
    // and within `radius` at the crossing itself.
    let segments = Segments::new(half);
    let mut last_touch = up.saturating_sub(1);
    let (mut lo, mut hi) = (crossing.x - radius, crossing.x);
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
        // leave it so at every step after: the rest of the steps are skipped.
        if (lo, hi) == before {
            break;
        }
    }
    let c = 0.5 * (lo + hi);
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

/// Steps in the height factor for how fast the new feet move across.
const FACTOR_STEP: f64 = 1e-4;

/// The profile `dense` run out to `factor` of its height by [`lowered`], where the
/// factor changes by `rate` per mm along the bead. The new feet then run across the
/// bead at a slope `m` (mm across per mm along), and a skin whose sections are rounded
/// with a radius `r` is rounded, across its foot line, with about `r / (1 + m^2)`;
/// each foot's radius is raised by `1 + m^2` (from the slope found with the drawn
/// radius, then once more with the raised one) so the skin keeps the drawn one.
pub(super) fn run_out(dense: &[DVec2], factor: f64, feet: (f64, f64), rate: f64) -> Vec<DVec2> {
    if factor >= 1.0 || factor <= 0.0 || rate == 0.0 {
        return lowered(dense, factor, feet).0;
    }
    let mut radii = feet;
    for _ in 0..2 {
        let (a, b) = (
            (factor - FACTOR_STEP).max(0.0),
            (factor + FACTOR_STEP).min(1.0),
        );
        let (_, low) = lowered(dense, a, radii);
        let (_, high) = lowered(dense, b, radii);
        let slope = |x0: f64, x1: f64| (x1 - x0) / (b - a) * rate;
        let (m0, m1) = (slope(low.0, high.0), slope(low.1, high.1));
        radii = (
            feet.0 * (1.0 + m0 * m0).powi(2),
            feet.1 * (1.0 + m1 * m1).powi(2),
        );
    }
    lowered(dense, factor, radii).0
}

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
