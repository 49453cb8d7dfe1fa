//! Offsets of 2-D curves, and the stretch of a curve between two points.
//!
//! A draw bead follows the punch opening at a fixed distance outside it; a punch
//! profile lies one sheet thickness inside the die profile. [`offset_curve2`] gives the
//! curve at a distance to the left of a 2-D curve's direction (negative: to the
//! right) as one smooth cubic B-spline, and [`curve_between`] cuts the stretch of a
//! curve between the points nearest two picks, so that a designer can offset only the
//! sides a bead runs along.
//!
//! # The offset
//!
//! The exact offset `O(t) = C(t) + d n(t)` (`n` the unit normal to the left) of a
//! NURBS curve is not a NURBS curve, so it is fitted:
//!
//! 1. The curve is cut at its C0 knots (multiplicity >= degree) into smooth pieces.
//!    Where the direction jumps by more than [`CORNER_ANGLE`] (a knot, or the seam of
//!    a closed curve) the curve is refused ([`GeomError::SharpCorner`]): the offset of
//!    a corner is an arc on one side and a cut on the other, not one smooth curve.
//!    Smaller turns are joined exactly: outside the turn by the arc of radius `|d|`
//!    about the corner, inside it by cutting both offsets where they cross.
//! 2. A distance at or beyond the radius of curvature on the inside of a turn folds the
//!    offset back on itself ([`GeomError::OffsetFolds`]); the largest `d κ` (κ the
//!    signed curvature) is found by sampling every knot span and refining the maximum.
//! 3. Exact offset points are sampled by the offset's own arc length, at most
//!    [`MAX_STEP`] apart and [`MAX_TURN`] of turn apart, and interpolated by one cubic
//!    (chord length, averaged knots) with the original's end tangent directions (a
//!    closed curve gets the same direction at both ends, so the offset closes C1).
//! 4. The fit is measured independently: at three points inside every interval between
//!    samples, the distance to the closest point of the original must be within half
//!    the tolerance of `|d|`. Intervals that are off get their middle as a new sample,
//!    and the fit is repeated until every check holds.
//!
//! Every sample is also checked against the whole original (a global closest point): a
//! sample closer to the curve than `|d|` means the offset runs into another part of the
//! curve ([`GeomError::OffsetOverlaps`]), which no local check sees.
//!
//! A straight curve (control points on one line, advancing) is moved exactly.

use glam::DVec2;

use super::curve::{Curve2, NurbsCurve};
use super::error::{GeomError, Result};
use super::interpolate::{interpolate, parameters, Interpolation, Parametrization};
use super::inversion::{closest_point_on_curve, project_to_curve_near};
use super::join::join_curves;
use super::quadrature::gauss_legendre_10;

/// A turn of the direction larger than this at one point is a sharp corner: 0.5 deg.
pub const CORNER_ANGLE: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// Longest step (mm) along the offset between first samples.
pub const MAX_STEP: f64 = 20.0;

/// Largest turn (radians) of the offset between first samples: 5 deg.
pub const MAX_TURN: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// Most samples a fitted offset may use.
pub const MAX_SAMPLES: usize = 20_000;

/// Rounds of the fit check at most (each adds samples only where the fit is off).
const MAX_ROUNDS: usize = 40;

/// Curvature samples per knot span for the fold check (then refined).
const FOLD_SAMPLES: usize = 32;

/// Pieces per knot span of the offset arc-length table.
const LENGTH_PIECES: usize = 8;

/// Where the fit is checked inside each interval between samples.
const CHECKS: [f64; 3] = [0.25, 0.5, 0.75];

/// The 2-D curve at `distance` to the left of `curve`'s direction (negative: to the
/// right), within `tolerance` of `|distance|` from `curve` everywhere.
///
/// The result is one non-rational cubic on [0, 1] (a straight curve is moved exactly,
/// keeping its form); a closed curve (start == end) gives a closed offset with the same
/// tangent at both ends. A distance of 0 returns the curve unchanged.
///
/// Errors: [`GeomError::NotFinite`] for a non-finite distance;
/// [`GeomError::NotPositive`] for a tolerance that is not positive;
/// [`GeomError::SharpCorner`] where the direction jumps by more than [`CORNER_ANGLE`];
/// [`GeomError::OffsetFolds`] for a distance at or beyond a radius of curvature on the
/// inside of a turn; [`GeomError::OffsetOverlaps`] where the offset comes closer to
/// another part of the curve than the distance; [`GeomError::TooManyPoints`] beyond
/// [`MAX_SAMPLES`]; [`GeomError::ZeroVector`] where the curve stops (zero derivative).
pub fn offset_curve2(curve: &Curve2, distance: f64, tolerance: f64) -> Result<Curve2> {
    if !distance.is_finite() {
        return Err(GeomError::NotFinite {
            what: "offset distance",
        });
    }
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(GeomError::NotPositive {
            what: "offset tolerance",
            value: tolerance,
        });
    }
    if distance == 0.0 {
        return Ok(curve.clone());
    }
    if let Some(moved) = straight_offset(curve, distance) {
        return Ok(moved);
    }
    let closed = curve.is_closed();
    let pieces = curve.smooth_pieces()?;
    let joints = joints(curve, &pieces, closed)?;
    check_folds(&pieces, distance)?;
    let mut fit = Fitter::new(curve, &pieces, &joints, closed, distance, tolerance)?;
    fit.run()
}

/// The stretch of `curve` from the point nearest `from` to the point nearest `to`,
/// following the curve's direction. On a closed curve (start == end) the stretch runs
/// over the seam when `to` comes before `from`; the result then keeps the curve's
/// parameter speed on both sides of the seam (its domain is `[t_from, t_to + t1 - t0]`).
/// Otherwise the result is the curve's own piece on `[t_from, t_to]`.
///
/// Errors: [`GeomError::SameProjection`] when both points project to the same place
/// (within 1e-9 of the curve's size); [`GeomError::StretchBackwards`] when, on an open
/// curve, `to` projects before `from`.
pub fn curve_between(curve: &Curve2, from: DVec2, to: DVec2) -> Result<Curve2> {
    let (t0, t1) = curve.domain();
    let size = curve.control_scale().max(1.0);
    let a = closest_point_on_curve(curve, from)?;
    let b = closest_point_on_curve(curve, to)?;
    if a.point.distance(b.point) <= 1e-9 * size {
        return Err(GeomError::SameProjection {
            at: (a.point.x, a.point.y),
            parameter: a.t,
        });
    }
    let closed = curve.is_closed();
    let (mut ta, mut tb) = (a.t, b.t);
    if closed {
        // The seam is both ends: a stretch starts there at t0 and ends there at t1.
        let seam = curve.start_point();
        if a.point.distance(seam) <= 1e-9 * size {
            ta = t0;
        }
        if b.point.distance(seam) <= 1e-9 * size {
            tb = t1;
        }
    }
    if ta < tb {
        return curve.between(ta, tb);
    }
    if !closed {
        return Err(GeomError::StretchBackwards { from: ta, to: tb });
    }
    let first = curve.between(ta, t1)?;
    let second = curve.between(t0, tb)?;
    let joined = join_curves(&[first, second])?;
    // join_curves puts the pieces on [0, 1] and [1, 2]; map each back to its own
    // parameter speed (affine on each side of the C0 joint, so the shape is unchanged).
    let knots: Vec<f64> = joined
        .knots()
        .as_slice()
        .iter()
        .map(|&k| {
            if k <= 1.0 {
                ta + k * (t1 - ta)
            } else {
                t1 + (k - 1.0) * (tb - t0)
            }
        })
        .collect();
    let points = joined.control_points().to_vec();
    match joined.weights() {
        Some(w) => NurbsCurve::new_rational(joined.degree(), knots, points, w.to_vec()),
        None => NurbsCurve::new(joined.degree(), knots, points),
    }
}

/// The left unit normal of a direction.
fn left(d: DVec2) -> DVec2 {
    d.perp()
}

/// The curve moved by `distance` to the left, exactly, if it is straight: all control
/// points on the line from its start to its end, advancing along it.
fn straight_offset(curve: &Curve2, distance: f64) -> Option<Curve2> {
    let pts = curve.control_points();
    let (a, b) = (curve.start_point(), curve.end_point());
    let u = (b - a).try_normalize()?;
    let size = curve.control_scale().max(1.0);
    let on_line = pts.iter().all(|&p| u.perp_dot(p - a).abs() <= 1e-12 * size);
    let advancing = pts.windows(2).all(|w| u.dot(w[1] - w[0]) >= -1e-12 * size);
    if !(on_line && advancing) {
        return None;
    }
    let shift = left(u) * distance;
    Some(curve.map_points(|p| p + shift))
}

/// The unit direction of travel at the start (`at_end == false`) or end of a piece,
/// from the first non-vanishing derivative.
fn end_direction(piece: &Curve2, at_end: bool) -> Result<DVec2> {
    let (a, b) = piece.domain();
    let t = if at_end { b } else { a };
    let [_, d1, d2, d3] = piece.derivatives::<4>(t);
    let eps = 1e-12 * (1.0 + piece.control_scale());
    // Near an end where C' vanishes, C'(t) ~ (t - end) C'': backwards at the end.
    let candidates = [d1, if at_end { -d2 } else { d2 }, d3];
    candidates
        .into_iter()
        .find(|d| d.length() > eps)
        .map(DVec2::normalize)
        .ok_or(GeomError::ZeroVector {
            what: "curve derivative",
        })
}

/// Where two smooth pieces meet (or the seam of a closed curve): the unit directions
/// on either side and the signed turn between them (positive: to the left).
#[derive(Debug, Clone, Copy)]
struct Joint {
    /// The point.
    at: DVec2,
    /// Parameter on the original.
    t: f64,
    /// Direction arriving.
    before: DVec2,
    /// Direction leaving.
    after: DVec2,
    /// Signed turn in radians.
    turn: f64,
}

/// The joints between consecutive pieces, and for a closed curve the seam last (from
/// the end of the last piece to the start of the first). Refuses sharp corners.
fn joints(curve: &Curve2, pieces: &[Curve2], closed: bool) -> Result<Vec<Joint>> {
    let mut out = Vec::with_capacity(pieces.len());
    let mut pairs: Vec<(usize, usize)> = (1..pieces.len()).map(|i| (i - 1, i)).collect();
    if closed {
        pairs.push((pieces.len() - 1, 0));
    }
    for (i, j) in pairs {
        let before = end_direction(&pieces[i], true)?;
        let after = end_direction(&pieces[j], false)?;
        let turn = before.perp_dot(after).atan2(before.dot(after));
        let t = if j == 0 {
            curve.domain().0
        } else {
            pieces[j].domain().0
        };
        let at = pieces[j].start_point();
        if turn.abs() > CORNER_ANGLE {
            return Err(GeomError::SharpCorner {
                at: (at.x, at.y),
                turn: turn.abs(),
                parameter: t,
            });
        }
        out.push(Joint {
            at,
            t,
            before,
            after,
            turn,
        });
    }
    Ok(out)
}

/// Signed curvature from the first two derivatives (positive: turning left).
fn signed_curvature(d1: DVec2, d2: DVec2) -> f64 {
    let s = d1.length();
    if s == 0.0 {
        return 0.0;
    }
    d1.perp_dot(d2) / (s * s * s)
}

/// Refuses a distance at or beyond a radius of curvature on the inside of a turn:
/// `distance * κ >= 1` anywhere. The largest `distance * κ` of every knot span is
/// sampled and refined by golden-section search; the worst one is reported.
fn check_folds(pieces: &[Curve2], distance: f64) -> Result<()> {
    let g = |c: &Curve2, t: f64| {
        let [_, d1, d2] = c.derivatives::<3>(t);
        distance * signed_curvature(d1, d2)
    };
    let mut worst: Option<(f64, f64, usize)> = None; // (g, t, piece)
    for (k, c) in pieces.iter().enumerate() {
        for span in c.span_breaks().windows(2) {
            let (a, b) = (span[0], span[1]);
            let ts: Vec<f64> = (0..=FOLD_SAMPLES)
                .map(|i| a + (b - a) * i as f64 / FOLD_SAMPLES as f64)
                .collect();
            let vals: Vec<f64> = ts.iter().map(|&t| g(c, t)).collect();
            let (j, _) = vals
                .iter()
                .enumerate()
                .fold(
                    (0, f64::NEG_INFINITY),
                    |acc, (i, &v)| {
                        if v > acc.1 {
                            (i, v)
                        } else {
                            acc
                        }
                    },
                );
            let lo = ts[j.saturating_sub(1)];
            let hi = ts[(j + 1).min(FOLD_SAMPLES)];
            let (t, v) = golden_max(|t| g(c, t), lo, hi, (ts[j], vals[j]));
            if worst.is_none_or(|w| v > w.0) {
                worst = Some((v, t, k));
            }
        }
    }
    if let Some((v, t, k)) = worst {
        if v >= 1.0 - 1e-9 {
            let at = pieces[k].point_at(t);
            return Err(GeomError::OffsetFolds {
                distance,
                radius: distance.abs() / v,
                at: (at.x, at.y),
                parameter: t,
            });
        }
    }
    Ok(())
}

/// The maximum of `f` on `[lo, hi]` by golden-section search, no worse than `start`.
fn golden_max(f: impl Fn(f64) -> f64, lo: f64, hi: f64, start: (f64, f64)) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (lo, hi);
    let mut c = b - r * (b - a);
    let mut d = a + r * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..60 {
        if b - a <= 1e-14 * (1.0 + a.abs().max(b.abs())) {
            break;
        }
        if fc >= fd {
            b = d;
            (d, fd) = (c, fc);
            c = b - r * (b - a);
            fc = f(c);
        } else {
            a = c;
            (c, fc) = (d, fd);
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    let best = if fc >= fd { (c, fc) } else { (d, fd) };
    if best.1.is_finite() && best.1 > start.1 {
        best
    } else {
        start
    }
}

/// One continuous stretch of the exact offset: a piece of the curve moved along its
/// normal, or the arc of radius `|d|` around a small outside turn.
#[derive(Debug, Clone, Copy)]
enum Path {
    /// The offset of piece `k`, parametrized by the original's parameter.
    Piece(usize),
    /// The arc about joint `k`, parametrized by the turn of the normal from the
    /// arriving one.
    Arc(usize),
}

/// An interval between two consecutive samples: a path and its parameters there.
#[derive(Debug, Clone, Copy)]
struct Interval {
    path: Path,
    lo: f64,
    hi: f64,
}

/// The sampling, fitting and checking of one offset.
struct Fitter<'a> {
    curve: &'a Curve2,
    pieces: &'a [Curve2],
    joints: &'a [Joint],
    closed: bool,
    distance: f64,
    tolerance: f64,
    intervals: Vec<Interval>,
    /// Unit end directions of the result.
    ends: (DVec2, DVec2),
}

impl<'a> Fitter<'a> {
    fn new(
        curve: &'a Curve2,
        pieces: &'a [Curve2],
        joints: &'a [Joint],
        closed: bool,
        distance: f64,
        tolerance: f64,
    ) -> Result<Self> {
        let mut f = Self {
            curve,
            pieces,
            joints,
            closed,
            distance,
            tolerance,
            intervals: Vec::new(),
            ends: (DVec2::X, DVec2::X),
        };
        f.ends = if closed {
            let seam = joints[joints.len() - 1];
            let d = (seam.before + seam.after).normalize();
            (d, d)
        } else {
            (
                end_direction(&pieces[0], false)?,
                end_direction(&pieces[pieces.len() - 1], true)?,
            )
        };
        f.intervals = f.first_samples()?;
        Ok(f)
    }

    /// Whether a turn is so small that the offsets on either side meet within
    /// rounding of the tolerance (no arc, no cut).
    fn negligible(&self, turn: f64) -> bool {
        (self.distance * turn).abs() <= 1e-3 * self.tolerance
    }

    /// The offset point of path `p` at parameter `s`.
    fn point(&self, p: Path, s: f64) -> Result<DVec2> {
        match p {
            Path::Piece(k) => {
                let c = &self.pieces[k];
                let [pt, d1] = c.derivatives::<2>(s);
                let n = match d1.try_normalize() {
                    Some(u) if d1.length() > 1e-12 * (1.0 + c.control_scale()) => left(u),
                    _ => {
                        let (a, b) = c.domain();
                        if s <= a {
                            left(end_direction(c, false)?)
                        } else if s >= b {
                            left(end_direction(c, true)?)
                        } else {
                            return Err(GeomError::ZeroVector {
                                what: "curve derivative",
                            });
                        }
                    }
                };
                Ok(pt + n * self.distance)
            }
            Path::Arc(k) => {
                let j = self.joints[k];
                let n = DVec2::from_angle(s).rotate(left(j.before));
                Ok(j.at + n * self.distance)
            }
        }
    }

    /// A parameter on the original curve near where path `p` at `s` comes from (the
    /// start of a closest-point search).
    fn source(&self, p: Path, s: f64) -> f64 {
        match p {
            Path::Piece(_) => s,
            Path::Arc(k) => self.joints[k].t,
        }
    }

    /// The parameters `(s, t)` where the offsets of piece `a` (near its end) and piece
    /// `b` (near its start) cross: Newton on `O_a(s) - O_b(t)`, clamped to the given
    /// ranges.
    fn cut(&self, a: usize, b: usize, ra: (f64, f64), rb: (f64, f64)) -> Result<(f64, f64)> {
        // The offset point of piece k at t and its derivative C' (1 - d κ).
        let at = |k: usize, t: f64| -> Result<(DVec2, DVec2)> {
            let [_, d1, d2] = self.pieces[k].derivatives::<3>(t);
            let o = self.point(Path::Piece(k), t)?;
            Ok((o, d1 * (1.0 - self.distance * signed_curvature(d1, d2))))
        };
        let size = self.curve.control_scale().max(1.0) + self.distance.abs();
        let (mut s, mut t) = (ra.1, rb.0);
        for _ in 0..60 {
            let (oa, va) = at(a, s)?;
            let (ob, vb) = at(b, t)?;
            let f = oa - ob;
            if f.length() <= 1e-12 * size {
                return Ok((s, t));
            }
            // Solve va ds - vb dt = -f.
            let det = vb.perp_dot(va);
            if det == 0.0 || !det.is_finite() {
                break;
            }
            let ds = f.perp_dot(vb) / det;
            let dt = f.perp_dot(va) / det;
            let (ns, nt) = ((s + ds).clamp(ra.0, ra.1), (t + dt).clamp(rb.0, rb.1));
            if ns == s && nt == t {
                break;
            }
            (s, t) = (ns, nt);
        }
        let (oa, _) = at(a, s)?;
        let (ob, _) = at(b, t)?;
        if oa.distance(ob) <= 1e-3 * self.tolerance {
            return Ok((s, t));
        }
        Err(GeomError::NoConvergence {
            what: "crossing of the offsets at a small inside turn",
            iterations: 60,
            residual: oa.distance(ob),
        })
    }

    /// The paths of the exact offset in order, each with its parameter range.
    fn paths(&self) -> Result<Vec<Interval>> {
        let n = self.pieces.len();
        let mut ranges: Vec<(f64, f64)> = self.pieces.iter().map(|c| c.domain()).collect();
        // Joint k sits before piece k + 1 (the seam, last, before piece 0).
        let mut arcs: Vec<Option<(f64, f64)>> = vec![None; self.joints.len()];
        for (k, j) in self.joints.iter().enumerate() {
            if self.negligible(j.turn) {
                continue;
            }
            let (a, b) = (k % n, (k + 1) % n);
            if self.distance * j.turn < 0.0 {
                arcs[k] = Some((0.0, j.turn));
            } else {
                let (s, t) = self.cut(a, b, ranges[a], ranges[b])?;
                ranges[a].1 = s;
                ranges[b].0 = t;
                if ranges[a].1 <= ranges[a].0 || ranges[b].1 <= ranges[b].0 {
                    // The cut swallows a whole piece: the offsets of the pieces
                    // around it cross beyond it.
                    let at = j.at + left(j.before) * self.distance;
                    let gap = closest_point_on_curve(self.curve, at)?.distance;
                    return Err(GeomError::OffsetOverlaps {
                        at: (at.x, at.y),
                        gap,
                    });
                }
            }
        }
        let mut out = Vec::with_capacity(2 * n + 1);
        let seam = if self.closed {
            arcs[self.joints.len() - 1]
        } else {
            None
        };
        if let Some((_, turn)) = seam {
            out.push(Interval {
                path: Path::Arc(self.joints.len() - 1),
                lo: 0.5 * turn,
                hi: turn,
            });
        }
        for k in 0..n {
            out.push(Interval {
                path: Path::Piece(k),
                lo: ranges[k].0,
                hi: ranges[k].1,
            });
            if k + 1 < n {
                if let Some((lo, hi)) = arcs[k] {
                    out.push(Interval {
                        path: Path::Arc(k),
                        lo,
                        hi,
                    });
                }
            }
        }
        if let Some((_, turn)) = seam {
            out.push(Interval {
                path: Path::Arc(self.joints.len() - 1),
                lo: 0.0,
                hi: 0.5 * turn,
            });
        }
        Ok(out)
    }

    /// The first samples: every path cut by the offset's arc length into steps of at
    /// most [`MAX_STEP`] and [`MAX_TURN`].
    fn first_samples(&self) -> Result<Vec<Interval>> {
        let mut out = Vec::new();
        for path in self.paths()? {
            let cuts = match path.path {
                Path::Arc(_) => {
                    let sweep = (path.hi - path.lo).abs();
                    let n = steps(self.distance.abs() * sweep, sweep);
                    (0..=n)
                        .map(|i| path.lo + (path.hi - path.lo) * i as f64 / n as f64)
                        .collect::<Vec<_>>()
                }
                Path::Piece(k) => {
                    let room = MAX_SAMPLES.saturating_sub(out.len());
                    self.piece_samples(&self.pieces[k], path.lo, path.hi, room)?
                }
            };
            if cuts.len() > MAX_SAMPLES || out.len() + cuts.len() > MAX_SAMPLES {
                return Err(GeomError::TooManyPoints {
                    needed: out.len() + cuts.len(),
                    limit: MAX_SAMPLES,
                });
            }
            out.extend(cuts.windows(2).map(|w| Interval {
                path: path.path,
                lo: w[0],
                hi: w[1],
            }));
        }
        Ok(out)
    }

    /// Parameters on `[lo, hi]` of a piece, evenly spaced in the offset's arc length
    /// within each knot span, ends included; more than `room` intervals are refused.
    fn piece_samples(&self, c: &Curve2, lo: f64, hi: f64, room: usize) -> Result<Vec<f64>> {
        let mut breaks: Vec<f64> = vec![lo];
        breaks.extend(c.span_breaks().into_iter().filter(|&k| k > lo && k < hi));
        breaks.push(hi);
        let mut out = vec![lo];
        for w in breaks.windows(2) {
            // Table of (t, offset length, turn) on LENGTH_PIECES pieces.
            let (a, b) = (w[0], w[1]);
            let mut ts = vec![a];
            let mut lens = vec![0.0];
            let mut turn = 0.0;
            for i in 1..=LENGTH_PIECES {
                let (u0, u1) = (ts[i - 1], a + (b - a) * i as f64 / LENGTH_PIECES as f64);
                // The offset's length and the turn, integrated at the same nodes.
                let DVec2 { x: l, y: r } = gauss_legendre_10(
                    |t| {
                        let [_, d1, d2] = c.derivatives::<3>(t);
                        let kappa = signed_curvature(d1, d2);
                        let speed = d1.length();
                        DVec2::new(
                            speed * (1.0 - self.distance * kappa).abs(),
                            speed * kappa.abs(),
                        )
                    },
                    u0,
                    u1,
                );
                lens.push(lens[i - 1] + l);
                turn += r;
                ts.push(u1);
            }
            let total = lens[LENGTH_PIECES];
            let n = steps(total, turn);
            if out.len() + n > room {
                return Err(GeomError::TooManyPoints {
                    needed: MAX_SAMPLES - room + out.len() + n,
                    limit: MAX_SAMPLES,
                });
            }
            for i in 1..=n {
                let target = total * i as f64 / n as f64;
                let t = if i == n {
                    b
                } else {
                    let m = lens
                        .partition_point(|&l| l < target)
                        .clamp(1, LENGTH_PIECES);
                    let (l0, l1) = (lens[m - 1], lens[m]);
                    let f = if l1 > l0 {
                        (target - l0) / (l1 - l0)
                    } else {
                        0.5
                    };
                    ts[m - 1] + f * (ts[m] - ts[m - 1])
                };
                out.push(t);
            }
        }
        Ok(out)
    }

    /// The sample points: the start of the first interval, then every interval's end.
    fn points(&self) -> Result<Vec<DVec2>> {
        let mut pts = Vec::with_capacity(self.intervals.len() + 1);
        let first = self.intervals[0];
        pts.push(self.point(first.path, first.lo)?);
        for iv in &self.intervals {
            pts.push(self.point(iv.path, iv.hi)?);
        }
        if self.closed {
            let n = pts.len() - 1;
            pts[n] = pts[0];
        }
        Ok(pts)
    }

    /// The cubic through the sample points with the end directions.
    fn fit(&self, pts: &[DVec2]) -> Result<Curve2> {
        let chord: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
        let opts = Interpolation {
            degree: 3,
            parametrization: Parametrization::ChordLength,
            start_tangent: Some(self.ends.0 * chord),
            end_tangent: Some(self.ends.1 * chord),
            ..Interpolation::default()
        };
        interpolate(pts, &opts)
    }

    /// Refuses samples that lie closer to the curve than the distance (the offset runs
    /// into another part of the curve), measured with a global closest-point search.
    fn check_samples(&self, pts: &[DVec2], which: &[usize]) -> Result<()> {
        let want = self.distance.abs();
        for &i in which {
            let cp = closest_point_on_curve(self.curve, pts[i])?;
            if cp.distance < want - self.tolerance {
                return Err(GeomError::OffsetOverlaps {
                    at: (pts[i].x, pts[i].y),
                    gap: cp.distance,
                });
            }
        }
        Ok(())
    }

    /// Samples, fits and refines until the fit holds.
    fn run(&mut self) -> Result<Curve2> {
        let want = self.distance.abs();
        let mut pts = self.points()?;
        let all: Vec<usize> = (0..pts.len()).collect();
        self.check_samples(&pts, &all)?;
        let mut worst = f64::INFINITY;
        for _ in 0..MAX_ROUNDS {
            let fit = self.fit(&pts)?;
            let u = parameters(&pts, Parametrization::ChordLength)?;
            let mut bad = vec![false; self.intervals.len()];
            worst = 0.0;
            for (i, iv) in self.intervals.iter().enumerate() {
                for f in CHECKS {
                    let q = fit.point_at(u[i] + f * (u[i + 1] - u[i]));
                    let guess = self.source(iv.path, iv.lo + f * (iv.hi - iv.lo));
                    let cp = project_to_curve_near(self.curve, q, guess)?;
                    let dev = (cp.distance - want).abs();
                    worst = worst.max(dev);
                    if dev > 0.5 * self.tolerance {
                        bad[i] = true;
                    }
                }
            }
            let count = bad.iter().filter(|&&b| b).count();
            if count == 0 {
                return Ok(fit);
            }
            if self.intervals.len() + count > MAX_SAMPLES {
                return Err(GeomError::TooManyPoints {
                    needed: self.intervals.len() + count,
                    limit: MAX_SAMPLES,
                });
            }
            let mut next = Vec::with_capacity(self.intervals.len() + count);
            let mut fresh = Vec::with_capacity(count);
            for (iv, b) in self.intervals.iter().zip(bad) {
                if b {
                    let mid = 0.5 * (iv.lo + iv.hi);
                    next.push(Interval { hi: mid, ..*iv });
                    fresh.push(next.len());
                    next.push(Interval { lo: mid, ..*iv });
                } else {
                    next.push(*iv);
                }
            }
            self.intervals = next;
            pts = self.points()?;
            self.check_samples(&pts, &fresh)?;
        }
        Err(GeomError::NoConvergence {
            what: "offset fit",
            iterations: MAX_ROUNDS,
            residual: worst,
        })
    }
}

/// Steps for a stretch of `length` that turns by `turn` radians.
fn steps(length: f64, turn: f64) -> usize {
    let by_length = (length / MAX_STEP).ceil();
    let by_turn = (turn / MAX_TURN).ceil();
    let n = by_length.max(by_turn).max(1.0);
    if n.is_finite() && n < MAX_SAMPLES as f64 {
        n as usize
    } else {
        MAX_SAMPLES + 1
    }
}
