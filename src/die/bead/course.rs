//! The bead's course in the top view: the centre line by arc length (drawn, or halfway
//! between two boundaries), the frame across it, where a section meets the boundaries,
//! and the checks that it does not turn tighter than the bead or cross itself.

use std::collections::HashMap;
use std::sync::Mutex;

use glam::DVec2;
use rayon::prelude::*;

use super::profiles::MatchedProfiles;
use super::{Course, Problem};
use crate::geom::curve::ArcLengths;
use crate::geom::interpolate::{interpolate, Interpolation};
use crate::geom::{Curve2, GeomError};

/// Distance (mm) between the centre-line samples of the turning check.
const TURN_SAMPLE_STEP: f64 = 0.5;

/// A direction jump (degrees) at a knot of the centre line that counts as a sharp
/// corner.
const KINK_DEGREES: f64 = 0.5;

/// Samples of a boundary line for finding where a section crosses it.
const BOUNDARY_SAMPLES: usize = 512;

/// The course in the top view, ready for sections: the centre line by arc length, and
/// the boundaries (if any) sampled for crossings.
pub(super) struct CourseMap {
    /// The centre line with its arc length tabulated (every section and every
    /// centre-line sample asks for a fraction of it).
    centre: ArcLengths<'static, DVec2>,
    /// The centre line's top-view length (mm).
    pub(super) length: f64,
    boundaries: Option<[BoundarySamples; 2]>,
    /// Whether the first boundary lies to the left of the centre line (it must stay
    /// there: boundaries that swap sides cross).
    first_left: bool,
    /// The frames asked for so far, by the bits of the fraction: the refinement asks
    /// again for the same sections. Behind a lock, so sections are laid out in
    /// parallel.
    frames: Mutex<HashMap<u64, (DVec2, DVec2, f64)>>,
}

/// A boundary line with samples to find crossings from.
struct BoundarySamples {
    curve: Curve2,
    samples: Vec<(f64, DVec2)>,
}

/// The narrowest bead (mm, between its boundaries) that is not a mistake.
const MIN_WIDTH: f64 = 1.0;

impl CourseMap {
    pub(super) fn new(course: &Course) -> Result<Self, Problem> {
        let (centre, boundaries) = match course {
            Course::Centre(c) => (c.clone(), None),
            Course::Boundaries(a, b) => {
                // Boundaries drawn from opposite ends still bound one bead: run the
                // second the way the first runs.
                let (a0, a1) = (a.start_point(), a.end_point());
                let b = if b.start_point().distance(a1) + b.end_point().distance(a0)
                    < b.start_point().distance(a0) + b.end_point().distance(a1)
                {
                    b.reversed()
                } else {
                    b.clone()
                };
                let samples = [BoundarySamples::new(a.clone()), BoundarySamples::new(b)];
                let mid = mid_line(&samples[0].curve, &samples[1].curve, &samples)?;
                (mid, Some(samples))
            }
        };
        let centre = ArcLengths::owning(centre);
        let length = centre.total();
        let mut map = Self {
            centre,
            length,
            boundaries,
            first_left: true,
            frames: Mutex::new(HashMap::new()),
        };
        // Which side the first boundary is on, read where the bead is widest of five
        // places along it (boundaries that cross are caught at the sections).
        if let Some(bounds) = &map.boundaries {
            let mut widest = 0.0f64;
            for f in [0.0, 0.25, 0.5, 0.75, 1.0] {
                let (c, across) = map.frame(f)?;
                let side = |b: &BoundarySamples| b.crossing(c, across).map(|p| (p - c).dot(across));
                if let (Some(a), Some(b)) = (side(&bounds[0]), side(&bounds[1])) {
                    if (a - b).abs() > widest {
                        widest = (a - b).abs();
                        map.first_left = a > b;
                    }
                }
            }
        }
        Ok(map)
    }

    /// The centre point and the unit direction across (to the left) at fraction `f`.
    pub(super) fn frame(&self, f: f64) -> Result<(DVec2, DVec2), Problem> {
        let (c, across, _) = self.frame_and_turn(f)?;
        Ok((c, across))
    }

    /// [`CourseMap::frame`] and the centre line's signed curvature there (1/mm,
    /// positive turning left).
    pub(super) fn frame_and_turn(&self, f: f64) -> Result<(DVec2, DVec2, f64), Problem> {
        let frames = || self.frames.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(&frame) = frames().get(&f.to_bits()) {
            return Ok(frame);
        }
        let frame = self.frame_and_turn_once(f)?;
        frames().insert(f.to_bits(), frame);
        Ok(frame)
    }

    /// [`CourseMap::frame_and_turn`], worked out (not kept).
    fn frame_and_turn_once(&self, f: f64) -> Result<(DVec2, DVec2, f64), Problem> {
        let t = self.parameter(f)?;
        let [c, d, dd] = self.line().derivatives::<3>(t);
        let across = d.normalize_or_zero().perp();
        if across == DVec2::ZERO {
            return Err(Problem::Kernel(GeomError::ZeroVector {
                what: "bead centre-line tangent",
            }));
        }
        let speed = d.length();
        Ok((c, across, d.perp_dot(dd) / (speed * speed * speed)))
    }

    /// For a centre-line course: the first place where the centre line turns tighter
    /// than the bead reaches to the inside of the turn, sampled every
    /// `TURN_SAMPLE_STEP` mm (so a small fillet between two sections is not missed).
    pub(super) fn too_tight(&self, profiles: &MatchedProfiles) -> Option<Problem> {
        if self.boundaries.is_some() {
            return None;
        }
        let all = || profiles.points.iter().flatten();
        let left = all().map(|q| q.x).fold(0.0, f64::max);
        let right = all().map(|q| -q.x).fold(0.0, f64::max);
        let n = ((self.length / TURN_SAMPLE_STEP).ceil() as usize).clamp(64, 100_000);
        // Each sample on its own, the first tight one kept: the answer of a loop.
        (0..=n).into_par_iter().find_map_first(|i| {
            let (c, _, turn) = self.frame_and_turn_once(i as f64 / n as f64).ok()?;
            let reach = if turn > 0.0 { left } else { right };
            (reach * turn.abs() >= 1.0).then(|| Problem::TooTight {
                at: c,
                radius: 1.0 / turn.abs(),
                reach,
            })
        })
    }

    /// Whether the centre line is a closed ring.
    pub(super) fn closed(&self) -> bool {
        let (t0, t1) = self.line().domain();
        let (a, b) = (self.line().point_at(t0), self.line().point_at(t1));
        a.distance(b) <= 1e-6 * (1.0 + self.length)
    }

    /// The first sharp corner of the centre line (a knot where its direction jumps by
    /// more than `KINK_DEGREES`), if any.
    pub(super) fn kink(&self) -> Option<DVec2> {
        let (t0, t1) = self.line().domain();
        let eps = 1e-9 * (t1 - t0);
        self.line()
            .span_breaks()
            .into_iter()
            .filter(|&k| k > t0 + eps && k < t1 - eps)
            .find(|&k| {
                let before = self.line().derivative_at(k - eps);
                let after = self.line().derivative_at(k + eps);
                before.angle_to(after).abs().to_degrees() > KINK_DEGREES
            })
            .map(|k| self.line().point_at(k))
    }

    /// The parameter at fraction `f` (clamped to 0..1) of the length.
    pub(super) fn parameter(&self, f: f64) -> Result<f64, Problem> {
        Ok(self.centre.parameter_at_fraction(f.clamp(0.0, 1.0))?)
    }

    /// The centre line in the top view.
    fn line(&self) -> &Curve2 {
        self.centre.curve()
    }

    /// Where the section through `c`, running `across`, meets the two
    /// boundaries, as offsets along `across` (low, high); `None` for a centre line.
    pub(super) fn feet(&self, c: DVec2, across: DVec2) -> Result<Option<(f64, f64)>, Problem> {
        let Some(bounds) = &self.boundaries else {
            return Ok(None);
        };
        let mut offsets = [0.0; 2];
        for (k, b) in bounds.iter().enumerate() {
            let hit = b
                .crossing(c, across)
                .ok_or(Problem::MissesBoundary { boundary: k, at: c })?;
            offsets[k] = (hit - c).dot(across);
        }
        let (left, right) = if self.first_left {
            (offsets[0], offsets[1])
        } else {
            (offsets[1], offsets[0])
        };
        if left - right < MIN_WIDTH {
            return Err(Problem::BoundariesCross { at: c });
        }
        Ok(Some((right, left)))
    }
}

impl BoundarySamples {
    fn new(curve: Curve2) -> Self {
        let (t0, t1) = curve.domain();
        let samples = (0..=BOUNDARY_SAMPLES)
            .map(|i| {
                let t = t0 + (t1 - t0) * i as f64 / BOUNDARY_SAMPLES as f64;
                (t, curve.point_at(t))
            })
            .collect();
        Self { curve, samples }
    }

    /// The point of the boundary on the line through `c` along `across` nearest `c`.
    /// A boundary that stops a little short of the line (by at most half the distance
    /// from `c`, or 1 mm) is extended along its end tangent, so boundaries drawn with
    /// slightly different ends still bound the end sections.
    fn crossing(&self, c: DVec2, across: DVec2) -> Option<DVec2> {
        let along = across.perp();
        let g = |p: DVec2| (p - c).dot(along);
        let zero = 1e-9 * (1.0 + c.length());
        let mut hits: Vec<DVec2> = Vec::new();
        let mut consider = |p: DVec2| hits.push(p);
        for w in self.samples.windows(2) {
            let ((ta, pa), (tb, pb)) = (w[0], w[1]);
            let (ga, gb) = (g(pa), g(pb));
            if ga.abs() <= zero {
                consider(pa);
            } else if gb.abs() <= zero {
                consider(pb);
            } else if (ga < 0.0) != (gb < 0.0) {
                let (mut lo, mut hi) = (ta, tb);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if (g(self.curve.point_at(mid)) < 0.0) == (ga < 0.0) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                consider(self.curve.point_at(0.5 * (lo + hi)));
            }
        }
        if hits.is_empty() {
            let (t0, t1) = self.curve.domain();
            for (t, outward) in [(t0, -1.0), (t1, 1.0)] {
                let p = self.curve.point_at(t);
                let tangent = self.curve.derivative_at(t).normalize_or_zero();
                let rate = tangent.dot(along);
                if rate.abs() < 1e-12 {
                    continue;
                }
                let reach = -g(p) / rate;
                let q = p + tangent * reach;
                if reach * outward >= 0.0 && reach.abs() <= (0.5 * q.distance(c)).max(1.0) {
                    hits.push(q);
                }
            }
        }
        hits.into_iter()
            .min_by(|a, b| a.distance(c).total_cmp(&b.distance(c)))
    }
}

/// The line halfway between two boundaries: midpoints of points at equal arc-length
/// fractions, then corrected once to the midpoints of the crossings of the lines
/// normal to that first guess.
fn mid_line(a: &Curve2, b: &Curve2, samples: &[BoundarySamples; 2]) -> Result<Curve2, Problem> {
    let (ta, tb) = (ArcLengths::new(a), ArcLengths::new(b));
    let n = ((ta.total().max(tb.total()) / 4.0).ceil() as usize).clamp(16, 2000);
    let mut guess = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let f = i as f64 / n as f64;
        let (pa, pb) = (
            a.point_at(ta.parameter_at_fraction(f)?),
            b.point_at(tb.parameter_at_fraction(f)?),
        );
        guess.push(0.5 * (pa + pb));
    }
    let first = interpolate(&guess, &Interpolation::default())?;
    let mut corrected = Vec::with_capacity(n + 1);
    for (i, &g) in guess.iter().enumerate() {
        let t = first.domain().0 + (first.domain().1 - first.domain().0) * i as f64 / n as f64;
        let t = crate::geom::inversion::closest_point_on_curve(&first, g)
            .map(|h| h.t)
            .unwrap_or(t);
        let across = first.derivative_at(t).normalize_or_zero().perp();
        let hits = (
            samples[0].crossing(g, across),
            samples[1].crossing(g, across),
        );
        corrected.push(match hits {
            (Some(p), Some(q)) if i > 0 && i < n => 0.5 * (p + q),
            _ => g,
        });
    }
    Ok(interpolate(&corrected, &Interpolation::default())?)
}
