//! NURBS curves in 2-D (profiles drawn in a view) and 3-D (die-face curves).
//!
//! Evaluation follows Piegl & Tiller: basis functions and their derivatives (A2.2,
//! eq. 2.9), the homogeneous curve and its derivatives (A3.2 in `(wP, w)` space), then
//! the rational derivatives (A4.2). Arc length is integrated per knot span with
//! Gauss-Legendre quadrature.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::error::{GeomError, Result};
use super::knots::{check_degree, KnotVector};
use super::ops::{self, Spline};
use super::point::{Homogeneous, Point};
use super::quadrature::gauss_legendre_10;
use super::MAX_DERIVATIVE;

/// A (possibly rational) B-spline curve with clamped knots.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsCurve<P> {
    degree: usize,
    knots: KnotVector,
    points: Vec<P>,
    /// `None` for a polynomial B-spline (all weights 1).
    weights: Option<Vec<f64>>,
    /// The largest control-point magnitude ([`NurbsCurve::control_scale`]), kept:
    /// every projection onto the curve sizes its tolerances by it, and reading a long
    /// curve's points for each took most of the time of a projection.
    scale: f64,
}

/// The largest magnitude among `points`.
fn scale_of<P: Point>(points: &[P]) -> f64 {
    points.iter().map(|p| p.length()).fold(0.0, f64::max)
}

/// A curve drawn in a 2-D view.
pub type Curve2 = NurbsCurve<DVec2>;
/// A curve in press coordinates.
pub type Curve3 = NurbsCurve<DVec3>;

/// Ends this close, relative to a curve's size, are one point: a closed outline, a
/// sketch drawn back to its start. Far below any drawing accuracy (a nanometre on a
/// metre-sized die), far above the rounding of the joins and projections that make
/// closed curves.
pub const CLOSED_TOLERANCE: f64 = 1e-9;

impl<P: Point> NurbsCurve<P> {
    /// A polynomial B-spline from its degree, flat clamped knot vector and control points.
    pub fn new(degree: usize, knots: Vec<f64>, points: Vec<P>) -> Result<Self> {
        check_degree(degree)?;
        check_points(&points)?;
        let knots = KnotVector::new(knots, degree, points.len())?;
        Ok(Self {
            degree,
            knots,
            scale: scale_of(&points),
            points,
            weights: None,
        })
    }

    /// A rational B-spline; weights must be finite and positive, one per control point.
    /// All-equal weights are kept as given (the curve is then polynomial in shape).
    pub fn new_rational(
        degree: usize,
        knots: Vec<f64>,
        points: Vec<P>,
        weights: Vec<f64>,
    ) -> Result<Self> {
        let mut c = Self::new(degree, knots, points)?;
        check_weights(&weights, c.points.len())?;
        c.weights = Some(weights);
        Ok(c)
    }

    /// A polynomial Bezier curve on [0, 1] through its control polygon's ends.
    pub fn bezier(points: Vec<P>) -> Result<Self> {
        if points.len() < 2 {
            return Err(GeomError::TooFewPoints {
                needed: 2,
                given: points.len(),
            });
        }
        let degree = points.len() - 1;
        Self::new(degree, KnotVector::bezier(degree).into_vec(), points)
    }

    /// The straight segment from `a` to `b` on [0, 1], as a degree-1 curve.
    pub fn line(a: P, b: P) -> Result<Self> {
        Self::new(1, vec![0.0, 0.0, 1.0, 1.0], vec![a, b])
    }

    /// Builds from parts the kernel produced itself (already valid).
    pub(crate) fn from_parts(
        degree: usize,
        knots: Vec<f64>,
        points: Vec<P>,
        weights: Option<Vec<f64>>,
    ) -> Self {
        Self {
            degree,
            knots: KnotVector::trusted(knots),
            scale: scale_of(&points),
            points,
            weights,
        }
    }

    /// Builds from a homogeneous spline, dropping the weights when all are 1.
    pub(crate) fn from_homogeneous(s: Spline<Homogeneous<P>>, rational: bool) -> Self {
        let points = s.points.iter().map(|h| h.to_point()).collect();
        let weights = rational.then(|| s.points.iter().map(|h| h.weight).collect());
        Self::from_parts(s.degree, s.knots, points, weights)
    }

    /// The control points in homogeneous form, for algorithms that treat rational
    /// curves as polynomial ones in one more dimension.
    pub(crate) fn to_homogeneous(&self) -> Spline<Homogeneous<P>> {
        let points = (0..self.points.len())
            .map(|i| Homogeneous::from_point(self.points[i], self.weight(i)))
            .collect();
        Spline {
            degree: self.degree,
            knots: self.knots.as_slice().to_vec(),
            points,
        }
    }

    /// Polynomial degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// Control points (Euclidean, not weighted).
    pub fn control_points(&self) -> &[P] {
        &self.points
    }

    /// Weights, or `None` for a polynomial curve.
    pub fn weights(&self) -> Option<&[f64]> {
        self.weights.as_deref()
    }

    /// Weight of control point `i` (1 for polynomial curves).
    pub fn weight(&self, i: usize) -> f64 {
        self.weights.as_ref().map_or(1.0, |w| w[i])
    }

    /// Whether the curve carries weights.
    pub fn is_rational(&self) -> bool {
        self.weights.is_some()
    }

    /// Parameter domain `[t0, t1]`.
    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }

    /// First point, `C(t0)`.
    pub fn start_point(&self) -> P {
        self.points[0]
    }

    /// Last point, `C(t1)`.
    pub fn end_point(&self) -> P {
        self.points[self.points.len() - 1]
    }

    /// Whether the curve ends where it starts: its ends closer than [`CLOSED_TOLERANCE`]
    /// times its size (the control scale, at least 1 mm, so a tiny curve is not held to
    /// a tolerance below rounding).
    pub fn is_closed(&self) -> bool {
        let size = self.control_scale().max(1.0);
        self.start_point().distance(self.end_point()) <= CLOSED_TOLERANCE * size
    }

    /// The point `C(t)`. Parameters outside the domain evaluate the end spans' polynomial
    /// pieces; callers that must not extrapolate clamp first.
    pub fn point_at(&self, t: f64) -> P {
        let span = self.knots.span(self.degree, t);
        let basis = self.knots.basis(span, self.degree, t);
        let first = span - self.degree;
        match &self.weights {
            None => {
                let points = &self.points[first..=span];
                points
                    .iter()
                    .zip(&basis)
                    .fold(P::ZERO, |acc, (&p, &b)| acc + p * b)
            }
            Some(w) => {
                let mut acc = P::ZERO;
                let mut wsum = 0.0;
                for ((&p, &wi), &b) in self.points[first..=span]
                    .iter()
                    .zip(&w[first..=span])
                    .zip(&basis)
                {
                    let nw = b * wi;
                    acc = acc + p * nw;
                    wsum += nw;
                }
                acc * (1.0 / wsum)
            }
        }
    }

    /// The point and its first `N - 1` derivatives with respect to `t`:
    /// `[C, C', C'', ...]` (P&T A3.2 and A4.2). At a knot the derivatives are those of the
    /// span to its right (the left one at the domain's end), as OpenCascade evaluates them.
    pub fn derivatives<const N: usize>(&self, t: f64) -> [P; N] {
        self.derivatives_in(self.knots.span(self.degree, t), t)
    }

    /// [`NurbsCurve::derivatives`] in the knot span `span`, the one that holds `t`.
    #[inline(always)]
    pub(crate) fn derivatives_in<const N: usize>(&self, span: usize, t: f64) -> [P; N] {
        const {
            assert!(
                N >= 1 && N <= MAX_DERIVATIVE + 1,
                "at most third derivatives"
            )
        };
        let p = self.degree;
        // Degrees up to 5 (nearly every curve) with their basis sized at compile time.
        match p {
            1 => {
                return self.derivatives_with(span, &self.knots.basis_rows::<2, N>(span, t, N - 1))
            }
            2 => {
                return self.derivatives_with(span, &self.knots.basis_rows::<3, N>(span, t, N - 1))
            }
            3 => {
                return self.derivatives_with(span, &self.knots.basis_rows::<4, N>(span, t, N - 1))
            }
            4 => {
                return self.derivatives_with(span, &self.knots.basis_rows::<5, N>(span, t, N - 1))
            }
            5 => {
                return self.derivatives_with(span, &self.knots.basis_rows::<6, N>(span, t, N - 1))
            }
            _ => {}
        }
        let mut basis = [[0.0; super::MAX_DEGREE + 1]; MAX_DERIVATIVE + 1];
        self.knots.basis_derivatives(span, p, t, N - 1, &mut basis);
        let first = span - p;
        let mut a = [P::ZERO; N];
        let mut w = [0.0; N];
        for (r, &point) in self.points[first..=span].iter().enumerate() {
            let wi = self.weight(first + r);
            for k in 0..N {
                a[k] = a[k] + point * (basis[k][r] * wi);
                w[k] += basis[k][r] * wi;
            }
        }
        if self.weights.is_none() {
            return a;
        }
        rational_derivatives(&a, &w)
    }

    /// The point and derivatives in `span` from the basis `rows` of the curve's degree
    /// (`O = p + 1`, [`KnotVector::basis_rows`]): the sums of [`NurbsCurve::derivatives_in`].
    #[inline(always)]
    fn derivatives_with<const O: usize, const N: usize>(
        &self,
        span: usize,
        rows: &[[f64; O]; N],
    ) -> [P; N] {
        let first = span + 1 - O;
        let mut a = [P::ZERO; N];
        let mut w = [0.0; N];
        for (r, &point) in self.points[first..=span].iter().enumerate() {
            let wi = self.weight(first + r);
            for k in 0..N {
                a[k] = a[k] + point * (rows[k][r] * wi);
                w[k] += rows[k][r] * wi;
            }
        }
        if self.weights.is_none() {
            return a;
        }
        rational_derivatives(&a, &w)
    }

    /// First derivative `C'(t)`.
    pub fn derivative_at(&self, t: f64) -> P {
        self.derivatives::<2>(t)[1]
    }

    /// Unit tangent at `t`, or an error where the derivative vanishes.
    pub fn unit_tangent(&self, t: f64) -> Result<P> {
        let d = self.derivative_at(t);
        let len = d.length();
        if len <= f64::EPSILON * (1.0 + self.control_scale()) {
            return Err(GeomError::ZeroVector {
                what: "curve derivative",
            });
        }
        Ok(d * (1.0 / len))
    }

    /// Curvature `|C' x C''| / |C'|^3` at `t` (0 where the derivative vanishes).
    pub fn curvature(&self, t: f64) -> f64 {
        let [_, d1, d2] = self.derivatives::<3>(t);
        curvature_of(d1, d2)
    }

    /// A size for relative tolerances: the largest control-point coordinate magnitude.
    pub fn control_scale(&self) -> f64 {
        self.scale
    }

    /// Parameters that split the domain into the non-empty knot spans, ends included.
    pub fn span_breaks(&self) -> Vec<f64> {
        self.knots.distinct().into_iter().map(|(k, _)| k).collect()
    }

    /// Arc length of the whole curve.
    pub fn length(&self) -> f64 {
        let (a, b) = self.domain();
        self.length_between(a, b)
    }

    /// Arc length between parameters `a` and `b` (signed: negative when `b < a`),
    /// integrated span by span with adaptive Gauss-Legendre quadrature to about 1e-12
    /// relative accuracy.
    pub fn length_between(&self, a: f64, b: f64) -> f64 {
        if !(a.is_finite() && b.is_finite()) {
            return f64::NAN;
        }
        if b < a {
            return -self.length_between(b, a);
        }
        // One split budget for the whole curve, so a curve of many spans, each of which
        // its rules never agree on (a speed that touches zero in every span), is measured
        // in bounded time: a fuzzed opening of 100,000 such spans took minutes.
        let breaks = self.span_breaks();
        let mut splits = LENGTH_SPLITS + 4 * breaks.len();
        let mut total = 0.0;
        let mut lo = a;
        for k in breaks {
            if k > lo && k < b {
                total += halved_length(self, lo, k, gauss_length(self, lo, k), 0, &mut splits);
                lo = k;
            }
        }
        if b > lo {
            total += halved_length(self, lo, b, gauss_length(self, lo, b), 0, &mut splits);
        }
        total
    }

    /// The parameter at arc length `s` from the start (clamped to the domain), by
    /// safeguarded Newton iteration on `length_between(t0, t) - s`.
    pub fn parameter_at_length(&self, s: f64) -> Result<f64> {
        if !s.is_finite() {
            return Err(GeomError::NotFinite { what: "arc length" });
        }
        let (t0, t1) = self.domain();
        let total = self.length();
        if s <= 0.0 {
            return Ok(t0);
        }
        if s >= total {
            return Ok(t1);
        }
        let guess = t0 + (t1 - t0) * s / total;
        let tol = 1e-12 * total.max(1.0);
        invert_length(self, (t0, t1), guess, tol, |t| {
            self.length_between(t0, t) - s
        })
    }

    /// The same curve run backwards: `reversed(t0 + t1 - t) = C(t)`.
    pub fn reversed(&self) -> Self {
        let (a, b) = self.domain();
        let knots = self
            .knots
            .as_slice()
            .iter()
            .rev()
            .map(|&k| a + b - k)
            .collect();
        let points = self.points.iter().rev().copied().collect();
        let weights = self
            .weights
            .as_ref()
            .map(|w| w.iter().rev().copied().collect());
        Self::from_parts(self.degree, knots, points, weights)
    }

    /// The same curve on the domain `[a, b]` (linear reparametrization of the knots).
    pub fn reparametrized(&self, a: f64, b: f64) -> Result<Self> {
        check_domain(a, b)?;
        let knots = super::surface::remap_knots(self.knots.as_slice(), self.degree, a, b);
        Ok(Self::from_parts(
            self.degree,
            knots,
            self.points.clone(),
            self.weights.clone(),
        ))
    }

    /// `t` must lie strictly inside the domain (a knot to insert or remove, a split).
    fn check_interior(&self, t: f64) -> Result<()> {
        let (a, b) = self.domain();
        if !t.is_finite() || t <= a || t >= b {
            return Err(GeomError::ParameterOutOfRange {
                value: t,
                min: a,
                max: b,
            });
        }
        Ok(())
    }

    /// Inserts the knot `t` up to `times` times (P&T A5.1); the shape is unchanged.
    /// Insertion stops at multiplicity = degree (a C0 point).
    pub fn insert_knot(&self, t: f64, times: usize) -> Result<Self> {
        self.check_interior(t)?;
        Ok(Self::from_homogeneous(
            ops::insert_knot(&self.to_homogeneous(), t, times),
            self.is_rational(),
        ))
    }

    /// Inserts several knots at once (P&T A5.4); each value must lie inside the domain and
    /// no multiplicity may exceed the degree.
    pub fn refine(&self, new_knots: &[f64]) -> Result<Self> {
        let x = checked_refinement(&self.knots, self.degree, new_knots)?;
        Ok(Self::from_homogeneous(
            ops::refine(&self.to_homogeneous(), &x),
            self.is_rational(),
        ))
    }

    /// Raises the degree by `by` without changing the shape (P&T A5.9).
    pub fn elevate_degree(&self, by: usize) -> Result<Self> {
        check_degree(self.degree + by)?;
        Ok(Self::from_homogeneous(
            ops::elevate_degree(&self.to_homogeneous(), by),
            self.is_rational(),
        ))
    }

    /// Removes the interior knot `t` as many times as it can, at most `times`, while the
    /// curve moves by no more than `tolerance` (P&T A5.8). Returns the new curve and how
    /// many times the knot went; 0 leaves the curve as it was.
    ///
    /// This is how a curve sheds knots it does not need: a knot inserted and removed
    /// again gives back the same control points, and a knot where the curve is smoother
    /// than its multiplicity says (the seam of a closed spline, a join that is C2 in
    /// fact) goes with an error at rounding level. The bound is P&T's: at each removal
    /// the two candidate control points must agree within the error allowed (eq. 5.29,
    /// and for rational curves the homogeneous form of eq. 5.30, `tolerance * w_min /
    /// (1 + |P|_max)`), and the errors of successive removals are added up against
    /// `tolerance`. Fails when `t` is not an interior knot or the tolerance is negative
    /// or not finite.
    pub fn remove_knot(&self, t: f64, times: usize, tolerance: f64) -> Result<(Self, usize)> {
        if !tolerance.is_finite() {
            return Err(GeomError::NotFinite {
                what: "knot removal tolerance",
            });
        }
        if tolerance < 0.0 {
            return Err(GeomError::NotPositive {
                what: "knot removal tolerance",
                value: tolerance,
            });
        }
        self.check_interior(t)?;
        if self.knots.multiplicity(t) == 0 {
            return Err(GeomError::KnotVector {
                reason: format!("{t} is not a knot of the curve, so it cannot be removed"),
            });
        }
        let tol = match &self.weights {
            None => tolerance,
            Some(w) => {
                let w_min = w.iter().copied().fold(f64::INFINITY, f64::min);
                tolerance * w_min / (1.0 + self.control_scale())
            }
        };
        let dist = |x: Homogeneous<P>, y: Homogeneous<P>| {
            let d = x - y;
            (d.weighted.dot(d.weighted) + d.weight * d.weight).sqrt()
        };
        let (s, removed) = ops::remove_knot(&self.to_homogeneous(), t, times, tol, dist);
        Ok((Self::from_homogeneous(s, self.is_rational()), removed))
    }

    /// Splits at `t` into the pieces on `[t0, t]` and `[t, t1]`, each keeping its part of
    /// the parameter range.
    pub fn split_at(&self, t: f64) -> Result<(Self, Self)> {
        self.check_interior(t)?;
        let p = self.degree;
        let full = ops::insert_knot(&self.to_homogeneous(), t, p);
        // After insertion t has multiplicity p, so the control point shared by the two
        // halves lies on the curve at t.
        let mut left_knots: Vec<f64> = full.knots.iter().copied().filter(|&k| k < t).collect();
        left_knots.extend(std::iter::repeat_n(t, p + 1));
        let mut right_knots: Vec<f64> = vec![t; p + 1];
        right_knots.extend(full.knots.iter().copied().filter(|&k| k > t));
        let left_count = left_knots.len() - p - 1;
        let left = Spline {
            degree: p,
            knots: left_knots,
            points: full.points[..left_count].to_vec(),
        };
        let right = Spline {
            degree: p,
            knots: right_knots,
            points: full.points[left_count - 1..].to_vec(),
        };
        let rational = self.is_rational();
        Ok((
            Self::from_homogeneous(left, rational),
            Self::from_homogeneous(right, rational),
        ))
    }

    /// The piece of the curve on `[a, b]`, keeping its part of the parameter range: cut
    /// at `a` unless it is the domain's start, and at `b` unless it is the domain's end
    /// (so the whole domain gives the curve itself). Wants `t0 <= a < b <= t1`.
    ///
    /// Errors: [`GeomError::ParameterOutOfRange`] for a cut outside the open domain, or
    /// for `b` at or before `a`.
    pub fn between(&self, a: f64, b: f64) -> Result<Self> {
        let (t0, t1) = self.domain();
        let tail = if a > t0 {
            self.split_at(a)?.1
        } else {
            self.clone()
        };
        if b < t1 {
            Ok(tail.split_at(b)?.0)
        } else {
            Ok(tail)
        }
    }

    /// The curve cut at its C0 knots (multiplicity >= degree: a sketch's corners, the
    /// joins of joined curves) into pieces that are each smooth, in order, each keeping
    /// its part of the parameter range. A curve without such knots is one piece.
    pub fn smooth_pieces(&self) -> Result<Vec<Self>> {
        let (t0, t1) = self.domain();
        let cuts: Vec<f64> = self
            .knots
            .distinct()
            .into_iter()
            .filter(|&(k, m)| k > t0 && k < t1 && m >= self.degree)
            .map(|(k, _)| k)
            .collect();
        let mut pieces = Vec::with_capacity(cuts.len() + 1);
        let mut rest = self.clone();
        for k in cuts {
            let (left, right) = rest.split_at(k)?;
            pieces.push(left);
            rest = right;
        }
        pieces.push(rest);
        Ok(pieces)
    }

    /// Applies `f` to every control point (weights unchanged). Exact for affine maps,
    /// which is how transforms and view embeddings act on NURBS.
    pub fn map_points<Q: Point>(&self, f: impl Fn(P) -> Q) -> NurbsCurve<Q> {
        let points: Vec<Q> = self.points.iter().map(|&p| f(p)).collect();
        NurbsCurve {
            degree: self.degree,
            knots: self.knots.clone(),
            scale: scale_of(&points),
            points,
            weights: self.weights.clone(),
        }
    }

    /// The curve embedded in 3-D with z = 0 (a 2-D curve in the XY plane).
    pub fn to_3d(&self) -> Curve3 {
        self.map_points(|p| p.to_3d())
    }

    /// Axis-aligned bounds of the control polygon (which contains the curve).
    pub fn control_bounds(&self) -> (DVec3, DVec3) {
        bounds(self.points.iter().map(|p| p.to_3d()))
    }
}

/// Curvature from the first and second derivatives, valid in 2-D and 3-D:
/// `sqrt(|d1|^2 |d2|^2 - (d1.d2)^2) / |d1|^3`.
pub fn curvature_of<P: Point>(d1: P, d2: P) -> f64 {
    let a = d1.dot(d1);
    if a == 0.0 {
        return 0.0;
    }
    let b = d2.dot(d2);
    let c = d1.dot(d2);
    (a * b - c * c).max(0.0).sqrt() / (a * a.sqrt())
}

/// Rational derivatives from homogeneous ones (P&T A4.2):
/// `C^(k) = (A^(k) - sum_{i=1..k} binom(k,i) w^(i) C^(k-i)) / w`.
pub(crate) fn rational_derivatives<P: Point, const N: usize>(a: &[P; N], w: &[f64; N]) -> [P; N] {
    let mut c = [P::ZERO; N];
    for k in 0..N {
        let mut v = a[k];
        let mut binom = 1.0;
        for i in 1..=k {
            binom = binom * (k + 1 - i) as f64 / i as f64;
            v = v - c[k - i] * (binom * w[i]);
        }
        c[k] = v * (1.0 / w[0]);
    }
    c
}

/// Axis-aligned bounds of a set of points.
pub(crate) fn bounds(points: impl Iterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

/// Checks knots to insert: finite, inside the open domain, and not pushing any knot's
/// multiplicity above the degree. Returns them sorted.
pub(crate) fn checked_refinement(
    knots: &KnotVector,
    degree: usize,
    new: &[f64],
) -> Result<Vec<f64>> {
    let (a, b) = knots.domain();
    let mut x = new.to_vec();
    for &t in &x {
        if !t.is_finite() || t <= a || t >= b {
            return Err(GeomError::ParameterOutOfRange {
                value: t,
                min: a,
                max: b,
            });
        }
    }
    x.sort_by(f64::total_cmp);
    let mut i = 0;
    while i < x.len() {
        let j = x[i..].iter().take_while(|&&v| v == x[i]).count();
        if knots.multiplicity(x[i]) + j > degree {
            return Err(GeomError::KnotVector {
                reason: format!(
                    "inserting {} would repeat it more than degree = {degree} times",
                    x[i]
                ),
            });
        }
        i += j;
    }
    Ok(x)
}

fn check_points<P: Point>(points: &[P]) -> Result<()> {
    if points.iter().any(|p| !p.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "control point",
        });
    }
    Ok(())
}

pub(crate) fn check_weights(weights: &[f64], count: usize) -> Result<()> {
    if weights.len() != count {
        return Err(GeomError::LengthMismatch {
            what: "weights",
            expected: count,
            given: weights.len(),
        });
    }
    if let Some((index, &value)) = weights
        .iter()
        .enumerate()
        .find(|(_, w)| !(w.is_finite() && **w > 0.0))
    {
        return Err(GeomError::Weight { index, value });
    }
    Ok(())
}

/// A new domain `[a, b]` (curve or surface reparametrization) must be finite and of
/// positive length.
pub(crate) fn check_domain(a: f64, b: f64) -> Result<()> {
    if !(a.is_finite() && b.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "domain bound",
        });
    }
    if b <= a {
        return Err(GeomError::NotPositive {
            what: "domain length",
            value: b - a,
        });
    }
    Ok(())
}

/// The root of `excess(t)` (arc length to `t` minus the length asked for, increasing
/// in `t`) inside `bracket`: Newton from `guess` on the curve's speed, bisection when a
/// step would leave the shrinking bracket.
fn invert_length<P: Point>(
    c: &NurbsCurve<P>,
    bracket: (f64, f64),
    guess: f64,
    tol: f64,
    excess: impl Fn(f64) -> f64,
) -> Result<f64> {
    let (mut lo, mut hi) = bracket;
    let width = bracket.1 - bracket.0;
    let mut t = guess;
    for _ in 0..100 {
        let f = excess(t);
        if f.abs() <= tol {
            return Ok(t);
        }
        if f > 0.0 {
            hi = t;
        } else {
            lo = t;
        }
        let speed = c.derivative_at(t).length();
        let newton = t - f / speed;
        t = if speed > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo <= 1e-15 * width {
            return Ok(t);
        }
    }
    Err(GeomError::NoConvergence {
        what: "parameter at arc length",
        iterations: 100,
        residual: excess(t).abs(),
    })
}

/// The arc length on `[a, b]` by one 10-point Gauss-Legendre rule on the speed. The
/// nodes of a piece inside one knot span share its span: it is looked up once and only
/// checked at each node ([`KnotVector::span_from`]).
fn gauss_length<P: Point>(c: &NurbsCurve<P>, a: f64, b: f64) -> f64 {
    let hint = c.knots.span(c.degree, 0.5 * (a + b));
    gauss_legendre_10(
        |t| {
            let span = c.knots.span_from(c.degree, t, hint);
            c.derivatives_in::<2>(span, t)[1].length()
        },
        a,
        b,
    )
}

/// The arc length on `[a, b]` by adaptive Gauss-Legendre quadrature: the rule on the
/// whole against the rule on its two halves, each half split again until they agree to
/// 1e-13, at most 20 levels deep and [`LENGTH_SPLITS`] splits in all.
fn adaptive_length<P: Point>(c: &NurbsCurve<P>, a: f64, b: f64) -> f64 {
    adaptive_length_within(c, a, b, LENGTH_SPLITS)
}

/// [`adaptive_length`] with at most `splits` splits.
fn adaptive_length_within<P: Point>(c: &NurbsCurve<P>, a: f64, b: f64, splits: usize) -> f64 {
    let mut splits = splits;
    halved_length(c, a, b, gauss_length(c, a, b), 0, &mut splits)
}

/// Splits one [`adaptive_length`] may make. Agreement to 1e-13 cannot be reached where
/// round-off is larger than that (a control polygon of 1e6 mm round a 10 mm arc): the
/// depth limit alone would then split every half 20 levels deep, a million rules for
/// one piece. The examples' curves need under a hundred.
const LENGTH_SPLITS: usize = 2000;

/// [`adaptive_length`] with the rule on the whole, `whole`, already known: a half that
/// is split again hands its own rule down instead of working it out twice (the same
/// numbers, a third less work). `splits` is what is left of the budget.
fn halved_length<P: Point>(
    c: &NurbsCurve<P>,
    a: f64,
    b: f64,
    whole: f64,
    depth: usize,
    splits: &mut usize,
) -> f64 {
    if !whole.is_finite() {
        return whole;
    }
    let m = 0.5 * (a + b);
    let (left, right) = (gauss_length(c, a, m), gauss_length(c, m, b));
    let halves = left + right;
    if depth >= 20 || *splits == 0 || (whole - halves).abs() <= 1e-13 * halves.max(1e-300) {
        halves
    } else {
        *splits -= 1;
        halved_length(c, a, m, left, depth + 1, splits)
            + halved_length(c, m, b, right, depth + 1, splits)
    }
}

/// A curve's arc length tabulated once, for many arc-length queries on the same curve
/// (resampling a line bead, placing sections at fractions of a centre line).
///
/// [`NurbsCurve::parameter_at_length`] integrates from the start for every query; the
/// table integrates each of `PIECES_PER_SPAN` pieces of every knot span once with
/// Gauss-Legendre quadrature, then answers a query by Newton inside one piece.
#[derive(Debug, Clone)]
pub struct ArcLengths<'a, P: Point> {
    /// The curve, borrowed, or owned by a table that outlives its maker
    /// ([`ArcLengths::owning`]).
    curve: std::borrow::Cow<'a, NurbsCurve<P>>,
    /// Piece boundaries in parameter, increasing.
    ts: Vec<f64>,
    /// Arc length from the start to each piece boundary.
    lengths: Vec<f64>,
}

/// Pieces per knot span of [`ArcLengths`]. Each piece is integrated to 1e-13 whatever
/// its length, so more pieces buy no accuracy: they only shorten a query's Newton
/// steps, and cost the table (a bead's draped centre line has hundreds of spans, and
/// tabulating it at eight pieces a span was 8 % of a fender build; at two, 2 %).
const PIECES_PER_SPAN: usize = 2;

/// Pieces of an [`ArcLengths`] table measured by one parallel task.
const PIECES_PER_TASK: usize = 64;

/// Pieces from which an [`ArcLengths`] table is measured in parallel: a short curve's
/// table is made faster than the thread pool is asked.
const PARALLEL_PIECES: usize = 512;

impl<'a, P: Point> ArcLengths<'a, P> {
    /// Tabulates the arc length of `curve`.
    pub fn new(curve: &'a NurbsCurve<P>) -> Self {
        Self::tabulate(std::borrow::Cow::Borrowed(curve))
    }

    /// Tabulates the arc length of `curve`, keeping the curve in the table.
    pub fn owning(curve: NurbsCurve<P>) -> ArcLengths<'static, P> {
        ArcLengths::tabulate(std::borrow::Cow::Owned(curve))
    }

    /// The curve the table measures.
    pub fn curve(&self) -> &NurbsCurve<P> {
        &self.curve
    }

    /// The table: the pieces' lengths, each on its own (in parallel for a long curve,
    /// such as a bead's centre line with hundreds of spans), added up in order.
    fn tabulate(curve: std::borrow::Cow<'a, NurbsCurve<P>>) -> Self {
        let breaks = curve.span_breaks();
        let mut ts = vec![breaks[0]];
        for w in breaks.windows(2) {
            for k in 1..=PIECES_PER_SPAN {
                ts.push(w[0] + (w[1] - w[0]) * k as f64 / PIECES_PER_SPAN as f64);
            }
        }
        // The split budget of a whole curve's length (`length_between`), shared out
        // evenly and in advance, so the table does not depend on the thread count: a
        // curve of 100,000 spans whose rules never agree took seconds per table.
        let pieces = (ts.len() - 1).max(1);
        let budget = 2 + LENGTH_SPLITS / pieces;
        let piece = |w: &[f64]| adaptive_length_within(&curve, w[0], w[1], budget);
        let pieces: Vec<f64> = if ts.len() > PARALLEL_PIECES {
            ts.par_windows(2)
                .with_min_len(PIECES_PER_TASK)
                .map(piece)
                .collect()
        } else {
            ts.windows(2).map(piece).collect()
        };
        let mut lengths = Vec::with_capacity(ts.len());
        lengths.push(0.0);
        for piece in pieces {
            let acc = *lengths.last().expect("lengths starts with 0");
            lengths.push(acc + piece);
        }
        Self { curve, ts, lengths }
    }

    /// The whole length.
    pub fn total(&self) -> f64 {
        *self.lengths.last().expect("lengths is never empty")
    }

    /// The parameter at arc length `s` from the start, clamped to the domain.
    pub fn parameter_at(&self, s: f64) -> Result<f64> {
        if !s.is_finite() {
            return Err(GeomError::NotFinite { what: "arc length" });
        }
        let last = self.ts.len() - 1;
        if s <= 0.0 {
            return Ok(self.ts[0]);
        }
        if s >= self.total() {
            return Ok(self.ts[last]);
        }
        // The piece [ts[i], ts[i + 1]] holding s; Newton inside it, bisection as guard.
        let i = (self.lengths.partition_point(|&l| l <= s) - 1).min(last - 1);
        let (a, rest) = (self.ts[i], s - self.lengths[i]);
        let (lo, hi) = (a, self.ts[i + 1]);
        let piece = self.lengths[i + 1] - self.lengths[i];
        let t = if piece > 0.0 {
            a + (hi - lo) * rest / piece
        } else {
            a
        };
        let tol = 1e-12 * self.total().max(1.0);
        let curve: &NurbsCurve<P> = &self.curve;
        // Each Newton step measures only the stretch from the step before (it shrinks
        // quadratically, so its rules agree at once), the first from the piece's start.
        let last = std::cell::Cell::new(None::<(f64, f64)>);
        invert_length(curve, (lo, hi), t, tol, |t| {
            let length = match last.get() {
                None => adaptive_length(curve, a, t),
                Some((t_last, l_last)) if t >= t_last => l_last + adaptive_length(curve, t_last, t),
                Some((t_last, l_last)) => l_last - adaptive_length(curve, t, t_last),
            };
            last.set(Some((t, length)));
            length - rest
        })
    }

    /// The arc length from the start to parameter `t` (clamped to the domain).
    pub fn length_at(&self, t: f64) -> f64 {
        let last = self.ts.len() - 1;
        if t <= self.ts[0] {
            return 0.0;
        }
        if t >= self.ts[last] {
            return self.total();
        }
        let i = (self.ts.partition_point(|&x| x <= t) - 1).min(last - 1);
        self.lengths[i] + adaptive_length(&self.curve, self.ts[i], t)
    }

    /// The parameter at fraction `f` (0 to 1) of the length.
    pub fn parameter_at_fraction(&self, f: f64) -> Result<f64> {
        self.parameter_at(f * self.total())
    }
}
