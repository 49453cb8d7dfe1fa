//! Every step-draw section as a cubic on one knot vector whose knots sit at the
//! profile's own features.
//!
//! All sections share the corner list of [`super::chain::align`], so one knot vector
//! `U` serves them all: each run and each corner gets a fixed stretch of `U`, with a
//! double knot where a run meets a corner (the curvature jumps there, from a straight
//! run into a radius, and a double knot lets the cubic jump with it instead of
//! overshooting), four spans across each corner and three along each run. Each section
//! is then the least squares cubic through points spread along each of its pieces,
//! ends fixed on the guides. The matrix is the same for every section, so it is
//! factored once.
//!
//! The stretches are the key sections' mean lengths, so in any one section a piece
//! can be much longer or shorter than its stretch, and two pieces that meet at a
//! double knot would ask for different parameter speeds there: the cubic, C1 at the
//! knot, could keep neither, and the radius next to it came out up to a third tighter
//! than drawn. So each corner is traversed evenly (the only pace at which a cubic
//! follows an arc closely) and each straight run, which a cubic follows exactly at any
//! pace its knots allow, eases from its neighbours' speeds at its ends to its own in
//! between ([`Pace`]).
//!
//! A corner that fades out (a step running out next to a plain wall) keeps an arc of
//! some length ([`super::chain::Chain::arc_length`]), so its stretch of `U` never shrinks to
//! nothing.

// Loops over parallel arrays (runs, corners, knots) by index read clearer here than
// zipped iterators.
#![allow(clippy::needless_range_loop)]

use glam::DVec2;
use nalgebra::DMatrix;

use super::chain::{dir, Chain};
use crate::geom::{GeomError, KnotVector};

/// Spans across a corner.
const CORNER_SPANS: usize = 4;

/// Samples per span.
const SAMPLES_PER_SPAN: usize = 4;

/// The share of a run's stretch at each end over which its pace eases from the speed of
/// the corner it meets to its own cruising speed ([`Pace`]); the run has a knot there.
const EASE: f64 = 0.15;

/// The slowest a run may cruise, as a share of its mean speed: a run asked to meet two
/// fast corners slows in between, and a speed near 0 would leave the surface without a
/// tangent plane there.
const SLOWEST_CRUISE: f64 = 0.25;

/// The shared structure: which runs have a stretch of `U`, the stretches, the knot
/// vector and the factored least-squares system.
#[derive(Debug, Clone)]
pub struct SectionBasis {
    /// Per run: whether it has its own stretch (a run of no length in every key section
    /// has none).
    runs: Vec<bool>,
    /// Corner count.
    corners: usize,
    /// The pieces in order, each with its stretch `[u0, u1]` and span count.
    pieces: Vec<(Piece, f64, f64)>,
    /// The knot vector.
    knots: Vec<f64>,
    /// Sample parameters and, for each, the piece and the fraction within it.
    samples: Vec<(f64, usize, f64)>,
    /// Per sample, the interior control points it weighs (the first one's index and
    /// the four basis values; a weight on an end point is 0 here): the rows of the
    /// least-squares matrix, which has four non-zeros in each.
    rows: Vec<(usize, [f64; 4])>,
    /// Interior control points (the matrix's columns).
    inner: usize,
    /// Basis values of the first and last control point at the samples.
    ends: Vec<(f64, f64)>,
    /// Cholesky factor of `A^T A`.
    normal: nalgebra::Cholesky<f64, nalgebra::Dyn>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Piece {
    Run(usize),
    Corner(usize),
}

impl Piece {
    /// Where the piece's stretch of `U` is cut into knot spans, as fractions of it.
    fn breaks(self) -> Vec<f64> {
        match self {
            Piece::Run(_) => vec![0.0, EASE, 1.0 - EASE, 1.0],
            Piece::Corner(_) => (0..=CORNER_SPANS)
                .map(|s| s as f64 / CORNER_SPANS as f64)
                .collect(),
        }
    }
}

impl SectionBasis {
    /// The structure for the aligned key chains (all with the same corner count).
    pub fn new(chains: &[Chain]) -> crate::geom::Result<Self> {
        let corners = chains.first().map_or(0, Chain::corners);
        let runs: Vec<bool> = (0..=corners)
            .map(|k| chains.iter().any(|c| c.runs[k].length > 1e-9))
            .collect();
        // Mean lengths give the stretches' widths, so the parameter is about even
        // along a typical section.
        let n = chains.len().max(1) as f64;
        let total: f64 = chains
            .iter()
            .map(|c| {
                c.runs.iter().map(|r| r.length).sum::<f64>()
                    + (0..c.corners()).map(|k| c.arc_length(k)).sum::<f64>()
            })
            .sum::<f64>()
            / n;
        let floor = 0.02 * total.max(1e-9);
        let mut pieces = Vec::new();
        let mut widths = Vec::new();
        for k in 0..=corners {
            if runs[k] {
                let w: f64 = chains.iter().map(|c| c.runs[k].length).sum::<f64>() / n;
                pieces.push(Piece::Run(k));
                widths.push(w.max(floor));
            }
            if k < corners {
                let w: f64 = chains.iter().map(|c| c.arc_length(k)).sum::<f64>() / n;
                pieces.push(Piece::Corner(k));
                widths.push(w.max(floor));
            }
        }
        let sum: f64 = widths.iter().sum();
        let mut at = 0.0;
        let mut placed = Vec::with_capacity(pieces.len());
        for (p, w) in pieces.iter().zip(&widths) {
            let u1 = if placed.len() + 1 == pieces.len() {
                1.0
            } else {
                at + w / sum
            };
            placed.push((*p, at, u1));
            at = u1;
        }
        // Knots: double between pieces, simple inside each piece at its breaks.
        let mut knots = vec![0.0; 4];
        for (i, &(p, u0, u1)) in placed.iter().enumerate() {
            let breaks = p.breaks();
            for &f in &breaks[1..breaks.len() - 1] {
                knots.push(u0 + (u1 - u0) * f);
            }
            if i + 1 < placed.len() {
                knots.push(u1);
                knots.push(u1);
            }
        }
        knots.extend([1.0; 4]);
        let m = knots.len() - 4;
        let kv = KnotVector::new(knots.clone(), 3, m)?;
        let mut samples = Vec::new();
        for (i, &(p, u0, u1)) in placed.iter().enumerate() {
            let breaks = p.breaks();
            for (j, w) in breaks.windows(2).enumerate() {
                let first = if i == 0 && j == 0 { 0 } else { 1 };
                for s in first..=SAMPLES_PER_SPAN {
                    let f = w[0] + (w[1] - w[0]) * s as f64 / SAMPLES_PER_SPAN as f64;
                    samples.push((u0 + (u1 - u0) * f, i, f));
                }
            }
        }
        let inner = m - 2;
        let mut rows = Vec::with_capacity(samples.len());
        let mut ends = Vec::with_capacity(samples.len());
        for &(u, _, _) in &samples {
            let span = kv.span(3, u);
            let b = kv.basis(span, 3, u);
            let (mut first, mut last) = (0.0, 0.0);
            let mut weights = [0.0; 4];
            for r in 0..4 {
                let col = span - 3 + r;
                if col == 0 {
                    first = b[r];
                } else if col == m - 1 {
                    last = b[r];
                } else {
                    weights[r] = b[r];
                }
            }
            // Interior index of the span's first control point (an end point's weight
            // is 0 above, so an index past either end is never used).
            rows.push((span - 3, weights));
            ends.push((first, last));
        }
        let mut ata = DMatrix::zeros(inner, inner);
        for &(first, w) in &rows {
            for (r, &a) in w.iter().enumerate() {
                for (c, &b) in w.iter().enumerate() {
                    if a != 0.0 && b != 0.0 {
                        ata[(first + r - 1, first + c - 1)] += a * b;
                    }
                }
            }
        }
        let normal = ata.cholesky().ok_or(GeomError::Singular {
            what: "step-draw section basis (too few samples for the knots)",
        })?;
        Ok(Self {
            runs,
            corners,
            pieces: placed,
            knots,
            samples,
            rows,
            inner,
            ends,
            normal,
        })
    }

    /// Which runs have their own stretch of `U` (the others keep length 0 in every
    /// section).
    pub fn runs_with_stretch(&self) -> &[bool] {
        &self.runs
    }

    /// The section `chain` as a cubic in its plane's (x, z) on the shared knots, ends
    /// exactly at the chain's, with its largest distance from the chain (sampled
    /// halfway between the fitting points).
    pub fn fit(&self, chain: &Chain) -> crate::geom::Result<(crate::geom::Curve2, f64)> {
        let curve = self.fit_warped(chain, |p| p)?;
        let geo = PieceGeometry::new(chain);
        let mut worst: f64 = 0.0;
        for w in self.samples.windows(2) {
            let u = 0.5 * (w[0].0 + w[1].0);
            worst = worst.max(geo.distance(curve.point_at(u)));
        }
        Ok((curve, worst))
    }

    /// The cubic through the chain's points moved by `warp` (a smooth map of the
    /// section plane), ends exactly at the warped chain's.
    pub fn fit_warped(
        &self,
        chain: &Chain,
        warp: impl Fn(DVec2) -> DVec2,
    ) -> crate::geom::Result<crate::geom::Curve2> {
        debug_assert_eq!(chain.corners(), self.corners);
        let geo = PieceGeometry::new(chain);
        let pace = self.pace(&geo);
        let points: Vec<DVec2> = self
            .samples
            .iter()
            .map(|&(_, piece, f)| warp(geo.point(self.pieces[piece].0, pace[piece].at(f))))
            .collect();
        let p0 = warp(chain.start);
        let p1 = warp(chain.end());
        let inner = self.inner;
        // A^T (points - end terms), both axes at once, from the rows' four non-zeros.
        let mut atb = DMatrix::<f64>::zeros(inner, 2);
        for ((p, &(a, b)), &(first, w)) in points.iter().zip(&self.ends).zip(&self.rows) {
            let rest = *p - a * p0 - b * p1;
            for (r, &weight) in w.iter().enumerate() {
                if weight != 0.0 {
                    atb[(first + r - 1, 0)] += weight * rest.x;
                    atb[(first + r - 1, 1)] += weight * rest.y;
                }
            }
        }
        let x = self.normal.solve(&atb);
        let mut out = vec![p0; inner + 2];
        for i in 0..inner {
            out[i + 1] = DVec2::new(x[(i, 0)], x[(i, 1)]);
        }
        out[inner + 1] = p1;
        let curve = crate::geom::Curve2::new(3, self.knots.clone(), out)?;
        Ok(curve)
    }
}

/// How the points are spread along one piece: the fraction of its length reached at
/// a fraction of its stretch of `U`, with slopes at the ends that match the speeds
/// where the piece meets its neighbours.
#[derive(Debug, Clone, Copy)]
enum Pace {
    /// A corner: one cubic from slope `start` to slope `end` (1 and 1 is an even pace,
    /// the only one at which a cubic follows an arc closely).
    Cubic { start: f64, end: f64 },
    /// A run: from slope `start` it eases over the first [`EASE`] of its stretch to a
    /// steady `cruise`, and over the last [`EASE`] on to slope `end` (the speed is
    /// quadratic in each easing, flat at the cruise). That is a C2 cubic on the run's
    /// knots, so the fit reproduces the straight run exactly at any such pace.
    Eased { start: f64, cruise: f64, end: f64 },
}

impl Pace {
    fn at(&self, t: f64) -> f64 {
        match *self {
            Pace::Cubic { start, end } => {
                let (t2, t3) = (t * t, t * t * t);
                (t3 - 2.0 * t2 + t) * start + (-2.0 * t3 + 3.0 * t2) + (t3 - t2) * end
            }
            Pace::Eased { start, cruise, end } => {
                let e = EASE;
                // Length covered while easing in from `start` over `e`.
                let first = cruise * e + (start - cruise) * e / 3.0;
                if t < e {
                    let g = 1.0 - t / e;
                    cruise * t + (start - cruise) * e / 3.0 * (1.0 - g * g * g)
                } else if t <= 1.0 - e {
                    first + cruise * (t - e)
                } else {
                    let g = (t - (1.0 - e)) / e;
                    first + cruise * (t - e) + (end - cruise) * e / 3.0 * g * g * g
                }
            }
        }
    }

    /// The eased pace with end slopes `start` and `end` (`None` at a free end, which
    /// then keeps the cruise), the cruise chosen so the whole run is covered.
    fn eased(start: Option<f64>, end: Option<f64>) -> Pace {
        // Covered: cruise + (start - cruise) e/3 + (end - cruise) e/3 = 1.
        let k = EASE / 3.0;
        let given = start.iter().chain(end.iter());
        let (sum, count) = given.fold((0.0, 0.0), |(s, n), v| (s + v, n + 1.0));
        let cruise = ((1.0 - sum * k) / (1.0 - count * k)).max(SLOWEST_CRUISE);
        Pace::Eased {
            start: start.unwrap_or(cruise),
            cruise,
            end: end.unwrap_or(cruise),
        }
    }
}

/// The most a run's speed at an end may differ from its mean speed, either way
/// (at both ends at once it still cruises at [`SLOWEST_CRUISE`] or faster).
const RUN_SPEED_RATIO: f64 = 6.0;

impl SectionBasis {
    /// The pace of each piece of `geo`: both pieces that meet at a double knot ask for
    /// the same parameter speed there (the cubic must keep one: it is C1 there), so
    /// the fit follows the geometry instead of trading it for the pace.
    fn pace(&self, geo: &PieceGeometry) -> Vec<Pace> {
        let own: Vec<f64> = self
            .pieces
            .iter()
            .map(|&(p, u0, u1)| geo.length(p) / (u1 - u0))
            .collect();
        let n = own.len();
        // Where a run meets a corner the corner keeps its own speed (a cubic follows an
        // arc closely only at an even pace) and the run, which is straight and follows
        // any pace exactly, takes it up, within [`RUN_SPEED_RATIO`] of its own; two
        // corners meet at the geometric mean of theirs.
        let junction = |a: usize, b: usize| -> f64 {
            let ratio = RUN_SPEED_RATIO;
            match (self.pieces[a].0, self.pieces[b].0) {
                (Piece::Run(_), Piece::Corner(_)) => own[b].clamp(own[a] / ratio, ratio * own[a]),
                (Piece::Corner(_), Piece::Run(_)) => own[a].clamp(own[b] / ratio, ratio * own[b]),
                _ => (own[a] * own[b]).sqrt(),
            }
        };
        (0..n)
            .map(|i| {
                let (p, u0, u1) = self.pieces[i];
                let length = geo.length(p);
                if length <= 0.0 {
                    return Pace::Cubic {
                        start: 1.0,
                        end: 1.0,
                    };
                }
                let scale = (u1 - u0) / length;
                let left = (i > 0).then(|| junction(i - 1, i) * scale);
                let right = (i + 1 < n).then(|| junction(i, i + 1) * scale);
                if let Piece::Run(_) = p {
                    return Pace::eased(left, right);
                }
                // Slopes up to 3 keep the fraction increasing (Fritsch and Carlson); their
                // sum up to 5 keeps the speed at a quarter of the mean or more midway
                // (at a sum of 6 it stops there: a line of the surface with no tangent
                // plane).
                let (start, end) = (
                    left.unwrap_or(1.0).clamp(0.0, 3.0),
                    right.unwrap_or(1.0).clamp(0.0, 3.0),
                );
                let shrink = if start + end > 5.0 {
                    5.0 / (start + end)
                } else {
                    1.0
                };
                Pace::Cubic {
                    start: start * shrink,
                    end: end * shrink,
                }
            })
            .collect()
    }
}

/// A chain's pieces with the collars of its gentle corners: where each run's own
/// stretch starts and ends, and each corner's stretch (collar, arc, collar).
struct PieceGeometry {
    /// Per run: the straight part that is its own (after collars are taken).
    runs: Vec<(DVec2, DVec2)>,
    /// Per corner: collar start, arc start, arc end, collar end, centre, radius, turn.
    corners: Vec<CornerPath>,
}

struct CornerPath {
    from: DVec2,
    arc_start: DVec2,
    arc_end: DVec2,
    to: DVec2,
    centre: DVec2,
    turn: f64,
    /// The arc's length (a straight piece when the turn is nil).
    arc: f64,
}

impl PieceGeometry {
    fn new(chain: &Chain) -> Self {
        let lay = chain.layout();
        let k = chain.corners();
        // No collars: a gentle corner is rounded wider instead ([`Chain::arc_length`]).
        let want = vec![0.0; k];
        // Each run gives at most 80 % of its length to the collars at its ends.
        let mut before = vec![0.0; k]; // collar taken from run i (before corner i)
        let mut after = vec![0.0; k]; // collar taken from run i + 1
        for r in 0..=k {
            let at_start = if r > 0 { want[r - 1] } else { 0.0 };
            let at_end = if r < k { want[r] } else { 0.0 };
            let room = 0.8 * chain.runs[r].length;
            let scale = if at_start + at_end > room && at_start + at_end > 0.0 {
                room / (at_start + at_end)
            } else {
                1.0
            };
            if r > 0 {
                after[r - 1] = at_start * scale;
            }
            if r < k {
                before[r] = at_end * scale;
            }
        }
        let runs = (0..=k)
            .map(|r| {
                let (a, b) = lay.runs[r];
                let d = dir(chain.runs[r].angle);
                let a = if r > 0 { a + d * after[r - 1] } else { a };
                let b = if r < k { b - d * before[r] } else { b };
                (a, b)
            })
            .collect();
        let corners = (0..k)
            .map(|i| {
                let (s, e, c) = lay.arcs[i];
                let din = dir(chain.runs[i].angle);
                let dout = dir(chain.runs[i + 1].angle);
                CornerPath {
                    from: s - din * before[i],
                    arc_start: s,
                    arc_end: e,
                    to: e + dout * after[i],
                    centre: c,
                    turn: chain.turn(i),
                    arc: chain.arc_length(i),
                }
            })
            .collect();
        Self { runs, corners }
    }

    /// The distance from `p` to the chain (its runs and arcs).
    fn distance(&self, p: DVec2) -> f64 {
        let seg = |a: DVec2, b: DVec2| {
            let ab = b - a;
            let t = if ab.length_squared() > 0.0 {
                ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            p.distance(a + ab * t)
        };
        let mut best = f64::INFINITY;
        for &(a, b) in &self.runs {
            best = best.min(seg(a, b));
        }
        for c in &self.corners {
            best = best.min(seg(c.from, c.arc_start)).min(seg(c.arc_end, c.to));
            if c.turn.abs() <= 1e-12 {
                best = best.min(seg(c.arc_start, c.arc_end));
                continue;
            }
            let r = c.centre.distance(c.arc_start);
            if r > 0.0 {
                let (ra, rp) = (c.arc_start - c.centre, p - c.centre);
                let a = ra.perp_dot(rp).atan2(ra.dot(rp));
                let inside = if c.turn >= 0.0 {
                    (0.0..=c.turn).contains(&a)
                } else {
                    (c.turn..=0.0).contains(&a)
                };
                if inside {
                    best = best.min((rp.length() - r).abs());
                } else {
                    best = best.min(p.distance(c.arc_start)).min(p.distance(c.arc_end));
                }
            }
        }
        best
    }

    /// The length of a piece (a corner's with its collars).
    fn length(&self, piece: Piece) -> f64 {
        match piece {
            Piece::Run(r) => self.runs[r].0.distance(self.runs[r].1),
            Piece::Corner(i) => {
                let c = &self.corners[i];
                c.from.distance(c.arc_start) + c.arc + c.arc_end.distance(c.to)
            }
        }
    }

    /// The point at fraction `f` of a piece's length.
    fn point(&self, piece: Piece, f: f64) -> DVec2 {
        match piece {
            Piece::Run(r) => {
                let (a, b) = self.runs[r];
                a + (b - a) * f
            }
            Piece::Corner(i) => {
                let c = &self.corners[i];
                let l0 = c.from.distance(c.arc_start);
                let la = c.arc;
                let l1 = c.arc_end.distance(c.to);
                let total = l0 + la + l1;
                if total <= 0.0 {
                    return c.arc_start;
                }
                let s = f * total;
                if s <= l0 {
                    c.from + (c.arc_start - c.from) * if l0 > 0.0 { s / l0 } else { 0.0 }
                } else if s <= l0 + la && la > 0.0 {
                    if c.turn.abs() <= 1e-12 {
                        return c.arc_start + (c.arc_end - c.arc_start) * ((s - l0) / la);
                    }
                    let a = (s - l0) / la * c.turn;
                    let r0 = c.arc_start - c.centre;
                    c.centre
                        + DVec2::new(
                            r0.x * a.cos() - r0.y * a.sin(),
                            r0.x * a.sin() + r0.y * a.cos(),
                        )
                } else {
                    let g = if l1 > 0.0 { (s - l0 - la) / l1 } else { 1.0 };
                    c.arc_end + (c.to - c.arc_end) * g.clamp(0.0, 1.0)
                }
            }
        }
    }
}
