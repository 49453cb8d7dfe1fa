//! Key-section profiles resampled at corresponding points: the same number of points
//! in every piece between rule points, so sections blend point by point and each rule
//! is one parameter across every section.

use std::collections::HashMap;
use std::sync::Mutex;

use glam::DVec2;
use rayon::prelude::*;

use super::runout::{resampled, run_out, smoothed};
use super::{drawn_radius, ease, BeadSpec, Problem, SECTION_INTERVALS};
use crate::geom::curve::ArcLengths;
use crate::geom::Curve2;

/// Samples of a profile for its fold and rule checks.
const PROFILE_SAMPLES: usize = 512;

/// How many times finer than the matched points the profiles are kept for the run-out
/// (lowered and rounded at the new feet before they are resampled).
const RUN_OUT_DENSITY: usize = 16;

/// The length (mm) over which a section's curvature changes where two pieces of its
/// profile meet ([`smoothed`]): about one space between the interpolated points of a
/// bead 20 to 30 mm across, so the curve through them overshoots the drawn curvature
/// far less than across a jump, and short enough to keep the skin within 0.005 mm of
/// the profile.
const BEND_WIDTH: f64 = 0.5;

/// The length over which [`smoothed`] spreads a run-out section's bends at `factor`
/// of the bead's height: [`BEND_WIDTH`] at full height, growing to twice that at the
/// tip. The lower a run-out section, the shorter the pieces between its bends (near
/// the tip a new foot meets the top corner after less than a millimetre, two bends
/// within about two spaces between the section's points), and a curve through points
/// that turn that quickly overshoots the drawn radius (2.63 mm of 3 mm drawn where a
/// 5 mm bead is 0.3 mm high). Twice the width keeps it to 2.77 mm; the section moves
/// from the lowered profile by at most 0.015 mm.
fn bend_width(factor: f64) -> f64 {
    BEND_WIDTH * (2.0 - factor.clamp(0.0, 1.0))
}

/// Interpolated points per drawn radius of a profile's length: a section's points are
/// at most a sixth of its smallest drawn radius apart, or the curve through them cuts
/// the radius where it meets a straight piece (a double bead's 2 mm shoulders at
/// 1.74 mm with 48 points across its 50 mm).
const POINTS_PER_RADIUS: f64 = 6.0;

/// The most intervals across a section (points per section minus one).
const MAX_SECTION_INTERVALS: usize = 192;

/// Intervals across a section: [`SECTION_INTERVALS`], or more where a key profile (of
/// smallest drawn radius `radii[k]`, its length in `tables[k]`) is long for that radius ([`POINTS_PER_RADIUS`]), up to
/// [`MAX_SECTION_INTERVALS`]; a multiple of 8.
fn section_intervals(radii: &[f64], tables: &[ArcLengths<DVec2>]) -> usize {
    let mut intervals = SECTION_INTERVALS;
    for (&radius, table) in radii.iter().zip(tables) {
        if radius.is_finite() && radius > 0.0 {
            let wanted = (POINTS_PER_RADIUS * table.total() / radius).ceil();
            if wanted.is_finite() {
                let wanted =
                    (wanted.min(MAX_SECTION_INTERVALS as f64) as usize).next_multiple_of(8);
                intervals = intervals.max(wanted.min(MAX_SECTION_INTERVALS));
            }
        }
    }
    intervals
}

/// The key sections' profiles resampled at corresponding points: the same number of
/// points in every piece between rule points, spaced by arc length within a piece.
pub(super) struct MatchedProfiles {
    /// Key positions along the bead (fractions).
    at: Vec<f64>,
    /// Each key section's points, (s, height).
    pub(super) points: Vec<Vec<DVec2>>,
    /// The smallest radius drawn in any key section's profile (mm).
    pub(super) drawn: f64,
    /// The shared interpolation parameters across a section (0 to 1).
    pub(super) params: Vec<f64>,
    /// The parameters of the rule points.
    pub(super) rule_params: Vec<f64>,
    /// Each key section's points [`RUN_OUT_DENSITY`] times finer, piece by piece.
    dense: Vec<Vec<DVec2>>,
    /// Intervals in each piece between rule points.
    counts: Vec<usize>,
    /// Each key section's radii at its left and right foot (0 for a sharp foot).
    feet: Vec<(f64, f64)>,
    /// The shapes made so far, by what they depend on ([`MatchedProfiles::shape_key`]):
    /// the full-height sections share their blend, and the refinement asks again for
    /// the same run-out sections (the exact section half-way between two skinned ones,
    /// each round, and then the one it inserts there). Behind a lock, so the sections
    /// of a round are shaped in parallel.
    shapes: Mutex<HashMap<ShapeKey, Vec<DVec2>>>,
}

impl MatchedProfiles {
    /// The profile at fraction `along`: the neighbouring key sections' points blended
    /// by [`ease`], so the shape stops changing at each key section.
    pub(super) fn blend(&self, along: f64) -> Vec<DVec2> {
        let (k, w) = self.weights(along);
        blend_of(&self.points, k, w)
    }

    /// [`weights`] at `along`, the weight 0 between two key sections with the same
    /// points: the blend is then the key section's points exactly, the same bits
    /// wherever along the bead it is asked for (a weighted sum of equal points differs
    /// in the last bits from place to place, and the shape cache, shared by sections
    /// shaped in parallel in any order, must not depend on which asked first).
    fn weights(&self, along: f64) -> (usize, f64) {
        let (k, w) = weights(&self.at, along);
        let inside = k > 0 && k < self.at.len();
        if inside && self.dense[k - 1] == self.dense[k] {
            (k, 0.0)
        } else {
            (k, w)
        }
    }

    /// Key section `k`'s profile run out to `factor` of its height ([`lowered`]), a
    /// fine polyline.
    pub(super) fn run_out_of_key(&self, k: usize, factor: f64, rate: f64) -> Vec<DVec2> {
        run_out(&self.dense[k], factor, self.feet[k], rate)
    }

    /// The profile at fraction `along` with its height run out to `factor` (0 to 1):
    /// the blended profile lowered into the binder and rounded at its new feet with the
    /// blended foot radii ([`lowered`]), resampled at corresponding points; the blend
    /// itself at full height.
    pub(super) fn shape(&self, along: f64, factor: f64, rate: f64) -> Vec<DVec2> {
        let key = self.shape_key(along, factor, rate);
        if let Some(shape) = self.cached_shapes().get(&key) {
            return shape.clone();
        }
        let shape = self.make_shape(along, factor, rate);
        self.cached_shapes().insert(key, shape.clone());
        shape
    }

    /// What a shape depends on, as the cache's key. At full height it is the blend
    /// alone (`rate` changes nothing there), and between two key sections with the same
    /// points the blend is either's points whatever its weight: every full-height
    /// section of a bead with one profile shares one shape, not one per position.
    fn shape_key(&self, along: f64, factor: f64, rate: f64) -> ShapeKey {
        if factor < 1.0 {
            return ShapeKey::RunOut([along.to_bits(), factor.to_bits(), rate.to_bits()]);
        }
        let (k, w) = self.weights(along);
        ShapeKey::Blend(k, w.to_bits())
    }

    /// The shape cache, locked. A shape depends only on its key, so a cache left by a
    /// panicking thread is still right.
    fn cached_shapes(&self) -> std::sync::MutexGuard<'_, HashMap<ShapeKey, Vec<DVec2>>> {
        self.shapes.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// [`MatchedProfiles::shape`], made.
    fn make_shape(&self, along: f64, factor: f64, rate: f64) -> Vec<DVec2> {
        let (k, w) = self.weights(along);
        let dense = blend_of(&self.dense, k, w);
        let (a, b) = (
            self.feet[k.saturating_sub(1)],
            self.feet[k.min(self.feet.len() - 1)],
        );
        let feet = (a.0 + (b.0 - a.0) * w, a.1 + (b.1 - a.1) * w);
        let shape = self.blend(along);
        let mut rules = Vec::with_capacity(self.counts.len() - 1);
        let mut index = 0;
        for &c in self.counts.iter().take(self.counts.len() - 1) {
            index += c;
            rules.push(shape[index].x);
        }
        resampled(
            &smoothed(&run_out(&dense, factor, feet, rate), bend_width(factor)),
            &rules,
            &self.counts,
        )
    }
}

/// The key of a cached shape ([`MatchedProfiles::shape_key`]).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum ShapeKey {
    /// A run-out section: the bits of its position, height factor and rate.
    RunOut([u64; 3]),
    /// A full-height section: the key section after it and the bits of its blend
    /// weight ([`MatchedProfiles::weights`]: 0 where the blend does not depend on it).
    Blend(usize, u64),
}

/// The key section index after `along` (0 before the first, the count after the last)
/// and the [`ease`] weight of that key section against the one before it.
fn weights(at: &[f64], along: f64) -> (usize, f64) {
    let k = at.partition_point(|&a| a <= along);
    if k == 0 || k == at.len() {
        return (k, 0.0);
    }
    let x = (along - at[k - 1]) / (at[k] - at[k - 1]);
    (k, ease(x))
}

/// Corresponding points of the key sections blended with weight `w` of key section `k`
/// against the one before it ([`weights`]).
fn blend_of(points: &[Vec<DVec2>], k: usize, w: f64) -> Vec<DVec2> {
    if k == 0 {
        return points[0].clone();
    }
    if k == points.len() {
        return points[k - 1].clone();
    }
    points[k - 1]
        .iter()
        .zip(&points[k])
        .map(|(a, b)| a.lerp(*b, w))
        .collect()
}

/// Checks every key section's profile (feet at 0, not folding back, not too tall,
/// rules inside and in order) and resamples them at corresponding points.
pub(super) fn matched_profiles(spec: &BeadSpec, ats: &[f64]) -> Result<MatchedProfiles, Problem> {
    let rule_count = spec.sections[0].rules.len();
    let mut pieces_per_section = Vec::with_capacity(spec.sections.len());
    for (k, key) in spec.sections.iter().enumerate() {
        let profile = &key.profile;
        let (a, b) = (profile.start_point(), profile.end_point());
        let scale = profile.control_scale().max(1.0);
        if a.y.abs() > 1e-9 * scale || b.y.abs() > 1e-9 * scale {
            return Err(Problem::ProfileFeet { section: k });
        }
        let (t0, t1) = profile.domain();
        let samples: Vec<(f64, DVec2)> = (0..=PROFILE_SAMPLES)
            .map(|i| {
                let t = t0 + (t1 - t0) * i as f64 / PROFILE_SAMPLES as f64;
                (t, profile.point_at(t))
            })
            .collect();
        let backwards = 1e-9 * scale;
        if b.x <= a.x {
            return Err(Problem::ProfileFolds { section: k, s: a.x });
        }
        if let Some(w) = samples.windows(2).find(|w| w[1].1.x < w[0].1.x - backwards) {
            return Err(Problem::ProfileFolds {
                section: k,
                s: w[0].1.x,
            });
        }
        let lowest = samples
            .iter()
            .map(|&(_, p)| p)
            .min_by(|p, q| p.y.total_cmp(&q.y))
            .expect("PROFILE_SAMPLES + 1 samples");
        if lowest.y < -1e-9 * scale {
            return Err(Problem::BelowBinder {
                section: k,
                s: lowest.x,
            });
        }
        let tallest = samples.iter().map(|(_, p)| p.y).fold(0.0, f64::max);
        if tallest <= 1e-9 * scale {
            return Err(Problem::BelowBinder {
                section: k,
                s: 0.5 * (a.x + b.x),
            });
        }
        if tallest > spec.max_height {
            return Err(Problem::TooTall {
                section: k,
                height: tallest,
                limit: spec.max_height,
            });
        }
        if key.rules.len() != rule_count {
            return Err(Problem::RuleCount {
                section: k,
                expected: rule_count,
                given: key.rules.len(),
            });
        }
        // Piece boundaries: the feet and the rule points, strictly increasing in s.
        let feet = (a.x, b.x);
        let mut cuts = vec![t0];
        let mut last_s = a.x;
        for &s in &key.rules {
            if !(s > last_s && s < b.x) {
                return Err(Problem::RuleOutside {
                    section: k,
                    s,
                    feet,
                });
            }
            cuts.push(parameter_at_s(profile, &samples, s));
            last_s = s;
        }
        cuts.push(t1);
        pieces_per_section.push(cuts);
    }

    // Intervals per piece: in proportion to the longest the piece is on any section
    // (as a fraction of that section's length), at least two each.
    let tables: Vec<ArcLengths<DVec2>> = spec
        .sections
        .iter()
        .map(|k| ArcLengths::new(&k.profile))
        .collect();
    let pieces = rule_count + 1;
    let mut share = vec![0.0f64; pieces];
    let mut piece_lengths = Vec::with_capacity(spec.sections.len());
    for (table, cuts) in tables.iter().zip(&pieces_per_section) {
        let lengths: Vec<f64> = cuts.iter().map(|&t| table.length_at(t)).collect();
        for j in 0..pieces {
            share[j] = share[j].max((lengths[j + 1] - lengths[j]) / table.total());
        }
        piece_lengths.push(lengths);
    }
    let total_share: f64 = share.iter().sum();
    let radii: Vec<f64> = spec
        .sections
        .iter()
        .map(|k| drawn_radius(&k.profile))
        .collect();
    let intervals = section_intervals(&radii, &tables);
    let counts: Vec<usize> = share
        .iter()
        .map(|s| ((s / total_share * intervals as f64).round() as usize).max(2))
        .collect();

    let mut points: Vec<Vec<DVec2>> = Vec::with_capacity(spec.sections.len());
    let mut dense: Vec<Vec<DVec2>> = Vec::with_capacity(spec.sections.len());
    let mut feet = Vec::with_capacity(spec.sections.len());
    for (k, ((key, table), lengths)) in spec
        .sections
        .iter()
        .zip(&tables)
        .zip(&piece_lengths)
        .enumerate()
    {
        // A key section with the profile and pieces of an earlier one (a bead's start
        // and end, say) has its points.
        let same = (0..k)
            .find(|&j| spec.sections[j].profile == key.profile && piece_lengths[j] == *lengths);
        if let Some(j) = same {
            points.push(points[j].clone());
            dense.push(dense[j].clone());
            feet.push(feet[j]);
            continue;
        }
        let section = dense_points(&key.profile, table, lengths, &counts)?;
        // The matched points are every RUN_OUT_DENSITY-th dense point: in piece j the
        // i-th of `c` steps lies at `d * i / c` along it, the dense one at
        // `d * (16 i) / (16 c)`, the same number (scaling by a power of two is exact).
        points.push(section.iter().step_by(RUN_OUT_DENSITY).copied().collect());
        dense.push(section);
        let (t0, t1) = key.profile.domain();
        let radius = |t: f64| {
            let k = key.profile.curvature(t);
            if k.is_finite() && k > 0.0 {
                k.recip()
            } else {
                0.0
            }
        };
        feet.push((radius(t0), radius(t1)));
    }

    // Shared parameters: the chord-length fractions, averaged over the key sections.
    let n = points[0].len();
    let mut params = vec![0.0; n];
    for section in &points {
        let mut acc = vec![0.0; n];
        for i in 1..n {
            acc[i] = acc[i - 1] + section[i].distance(section[i - 1]).max(1e-12);
        }
        for i in 0..n {
            params[i] += acc[i] / acc[n - 1] / points.len() as f64;
        }
    }
    params[0] = 0.0;
    params[n - 1] = 1.0;
    let mut rule_params = Vec::with_capacity(rule_count);
    let mut index = 0;
    for &c in counts.iter().take(rule_count) {
        index += c;
        rule_params.push(params[index]);
    }
    Ok(MatchedProfiles {
        drawn: radii.iter().copied().fold(f64::INFINITY, f64::min),
        at: ats.to_vec(),
        points,
        params,
        rule_params,
        dense,
        counts,
        feet,
        shapes: Mutex::new(HashMap::new()),
    })
}

/// Dense points of a key profile found by one parallel task.
const POINTS_PER_TASK: usize = 32;

/// A key profile's points [`RUN_OUT_DENSITY`] times finer than the matched ones: in each
/// piece between the arc `lengths` of its rule points, `RUN_OUT_DENSITY` times the
/// piece's `counts` equal steps of arc length (`table`).
fn dense_points(
    profile: &Curve2,
    table: &ArcLengths<DVec2>,
    lengths: &[f64],
    counts: &[usize],
) -> Result<Vec<DVec2>, Problem> {
    const { assert!(RUN_OUT_DENSITY.is_power_of_two()) };
    let mut along = Vec::new();
    for (j, &count) in counts.iter().enumerate() {
        let first = if j == 0 { 0 } else { 1 };
        let n = count * RUN_OUT_DENSITY;
        for i in first..=n {
            along.push(lengths[j] + (lengths[j + 1] - lengths[j]) * i as f64 / n as f64);
        }
    }
    // Each point on its own, in parallel; the first failure in order.
    let points: Vec<Result<DVec2, Problem>> = along
        .par_iter()
        .with_min_len(POINTS_PER_TASK)
        .map(|&l| Ok(profile.point_at(table.parameter_at(l)?)))
        .collect();
    points.into_iter().collect()
}

/// The parameter where a profile that never runs backwards reaches `s` across, from its
/// samples and bisection between them.
fn parameter_at_s(profile: &Curve2, samples: &[(f64, DVec2)], s: f64) -> f64 {
    let i = samples
        .windows(2)
        .position(|w| w[0].1.x <= s && s <= w[1].1.x)
        .unwrap_or(samples.len() - 2);
    let (mut lo, mut hi) = (samples[i].0, samples[i + 1].0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if profile.point_at(mid).x < s {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
