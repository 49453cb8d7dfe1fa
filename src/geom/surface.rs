//! Tensor-product NURBS surfaces in press coordinates.
//!
//! Control points are stored row-major, `i` along u and `j` along v, with optional
//! weights. Evaluation is P&T A3.5/A3.6 in homogeneous space followed by the rational
//! derivative formula A4.4. Knot insertion, refinement and degree elevation act on every
//! row or column with the curve algorithms of [`super::ops`].

use glam::DVec3;

use super::curve::{bounds, check_domain, check_weights, checked_refinement, Curve3};
use super::error::{GeomError, Result};
use super::grid::{BasisTable, Net, Row};
use super::knots::{check_degree, BasisRow, KnotVector};
use super::ops::{self, Spline};
use super::point::Homogeneous;
use super::{MAX_DEGREE, MAX_DERIVATIVE};

/// Which parameter direction an operation acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// The first parameter, along the index `i` of the control net.
    U,
    /// The second parameter, along the index `j`.
    V,
}

/// A (possibly rational) tensor-product B-spline surface with clamped knots.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsSurface {
    degree_u: usize,
    degree_v: usize,
    knots_u: KnotVector,
    knots_v: KnotVector,
    count_u: usize,
    count_v: usize,
    /// `points[i * count_v + j]`.
    points: Vec<DVec3>,
    weights: Option<Vec<f64>>,
    /// The largest control-point magnitude ([`NurbsSurface::control_scale`]), kept:
    /// every projection onto the surface sizes its tolerances by it, and reading a large
    /// net for each took most of the time of a projection.
    scale: f64,
    /// The diagonal of the control net's box ([`NurbsSurface::net_extent`]), kept for
    /// the same reason: every normal sizes its degeneracy test by it, and the band
    /// meshing asks for a normal at each of its points.
    extent: f64,
}

/// The largest magnitude among `points`.
fn scale_of(points: &[DVec3]) -> f64 {
    points.iter().map(|p| p.length()).fold(0.0, f64::max)
}

/// The diagonal of the bounding box of `points`.
fn extent_of(points: &[DVec3]) -> f64 {
    let (lo, hi) = bounds(points.iter().copied());
    (hi - lo).length()
}

impl NurbsSurface {
    /// A polynomial surface from degrees, flat clamped knot vectors and the control net
    /// `net[i][j]` (`i` along u).
    pub fn new(
        degree_u: usize,
        degree_v: usize,
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        net: Vec<Vec<DVec3>>,
    ) -> Result<Self> {
        check_degree(degree_u)?;
        check_degree(degree_v)?;
        let count_u = net.len();
        let count_v = net.first().map_or(0, Vec::len);
        if let Some(row) = net.iter().find(|r| r.len() != count_v) {
            return Err(GeomError::LengthMismatch {
                what: "control net row",
                expected: count_v,
                given: row.len(),
            });
        }
        let points: Vec<DVec3> = net.into_iter().flatten().collect();
        if points.iter().any(|p| !p.is_finite()) {
            return Err(GeomError::NotFinite {
                what: "control point",
            });
        }
        let knots_u = KnotVector::new(knots_u, degree_u, count_u)?;
        let knots_v = KnotVector::new(knots_v, degree_v, count_v)?;
        Ok(Self {
            degree_u,
            degree_v,
            knots_u,
            knots_v,
            count_u,
            count_v,
            scale: scale_of(&points),
            extent: extent_of(&points),
            points,
            weights: None,
        })
    }

    /// A rational surface; `weights[i][j]` finite and positive.
    pub fn new_rational(
        degree_u: usize,
        degree_v: usize,
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        net: Vec<Vec<DVec3>>,
        weights: Vec<Vec<f64>>,
    ) -> Result<Self> {
        let mut s = Self::new(degree_u, degree_v, knots_u, knots_v, net)?;
        if weights.len() != s.count_u {
            return Err(GeomError::LengthMismatch {
                what: "weight rows",
                expected: s.count_u,
                given: weights.len(),
            });
        }
        let flat: Vec<f64> = weights.into_iter().flatten().collect();
        check_weights(&flat, s.points.len())?;
        s.weights = Some(flat);
        Ok(s)
    }

    /// Builds from parts the kernel produced itself (already valid).
    pub(crate) fn from_parts(
        degrees: (usize, usize),
        knots: (Vec<f64>, Vec<f64>),
        counts: (usize, usize),
        points: Vec<DVec3>,
        weights: Option<Vec<f64>>,
    ) -> Self {
        Self {
            degree_u: degrees.0,
            degree_v: degrees.1,
            knots_u: KnotVector::trusted(knots.0),
            knots_v: KnotVector::trusted(knots.1),
            count_u: counts.0,
            count_v: counts.1,
            scale: scale_of(&points),
            extent: extent_of(&points),
            points,
            weights,
        }
    }

    /// The same surface with `dir` run backwards: `reversed(U)(a + b - u, v) = S(u, v)`
    /// on the u domain `[a, b]` (likewise for v). Reversing one direction turns the
    /// normal `S_u x S_v` around.
    pub fn reversed(&self, dir: Direction) -> Self {
        let mirror = |k: &KnotVector| {
            let ks = k.as_slice();
            let (a, b) = (ks[0], ks[ks.len() - 1]);
            ks.iter().rev().map(|&x| a + b - x).collect::<Vec<f64>>()
        };
        let (cu, cv) = (self.count_u, self.count_v);
        let source = |i: usize, j: usize| match dir {
            Direction::U => (cu - 1 - i) * cv + j,
            Direction::V => i * cv + (cv - 1 - j),
        };
        let mut points = Vec::with_capacity(self.points.len());
        let mut weights = self.weights.as_ref().map(|w| Vec::with_capacity(w.len()));
        for i in 0..cu {
            for j in 0..cv {
                let k = source(i, j);
                points.push(self.points[k]);
                if let (Some(out), Some(w)) = (weights.as_mut(), self.weights.as_ref()) {
                    out.push(w[k]);
                }
            }
        }
        let (knots_u, knots_v) = match dir {
            Direction::U => (mirror(&self.knots_u), self.knots_v.as_slice().to_vec()),
            Direction::V => (self.knots_u.as_slice().to_vec(), mirror(&self.knots_v)),
        };
        Self::from_parts(
            (self.degree_u, self.degree_v),
            (knots_u, knots_v),
            (cu, cv),
            points,
            weights,
        )
    }

    /// Degree in u.
    pub fn degree_u(&self) -> usize {
        self.degree_u
    }
    /// Degree in v.
    pub fn degree_v(&self) -> usize {
        self.degree_v
    }
    /// Knot vector in u.
    pub fn knots_u(&self) -> &KnotVector {
        &self.knots_u
    }
    /// Knot vector in v.
    pub fn knots_v(&self) -> &KnotVector {
        &self.knots_v
    }
    /// Number of control points along u and along v.
    pub fn counts(&self) -> (usize, usize) {
        (self.count_u, self.count_v)
    }
    /// Control point `(i, j)`.
    pub fn control_point(&self, i: usize, j: usize) -> DVec3 {
        self.points[i * self.count_v + j]
    }
    /// The control net row-major (`i * count_v + j`).
    pub fn control_points(&self) -> &[DVec3] {
        &self.points
    }
    /// Weight of control point `(i, j)` (1 for polynomial surfaces).
    pub fn weight(&self, i: usize, j: usize) -> f64 {
        self.weights
            .as_ref()
            .map_or(1.0, |w| w[i * self.count_v + j])
    }
    /// Weights row-major, or `None` for a polynomial surface.
    pub fn weights(&self) -> Option<&[f64]> {
        self.weights.as_deref()
    }
    /// Whether the surface carries weights.
    pub fn is_rational(&self) -> bool {
        self.weights.is_some()
    }
    /// Parameter domain in u.
    pub fn domain_u(&self) -> (f64, f64) {
        self.knots_u.domain()
    }
    /// Parameter domain in v.
    pub fn domain_v(&self) -> (f64, f64) {
        self.knots_v.domain()
    }
    /// Axis-aligned bounds of the control net (which contains the surface).
    pub fn control_bounds(&self) -> (DVec3, DVec3) {
        bounds(self.points.iter().copied())
    }
    /// A size for relative tolerances: the largest control-point magnitude.
    pub fn control_scale(&self) -> f64 {
        self.scale
    }

    /// The point `S(u, v)`.
    pub fn point_at(&self, u: f64, v: f64) -> DVec3 {
        let (p, q) = (self.degree_u, self.degree_v);
        let su = self.knots_u.span(p, u);
        let sv = self.knots_v.span(q, v);
        let nu = self.knots_u.basis(su, p, u);
        let nv = self.knots_v.basis(sv, q, v);
        let (i0, j0) = (su - p, sv - q);
        let mut acc = DVec3::ZERO;
        let mut wsum = 0.0;
        for (r, &bu) in nu.iter().enumerate().take(p + 1) {
            let row = (i0 + r) * self.count_v + j0;
            for (c, &bv) in nv.iter().enumerate().take(q + 1) {
                let w = self.weights.as_ref().map_or(1.0, |w| w[row + c]) * bu * bv;
                acc += self.points[row + c] * w;
                wsum += w;
            }
        }
        if self.weights.is_some() {
            acc / wsum
        } else {
            acc
        }
    }

    /// The points `S(us[k], vs[l])` of a tensor grid, at index `l * us.len() + k` (rows
    /// of constant v). The basis functions are worked out once per parameter and the
    /// control net contracted once per v, so each point costs a `p + 1` term sum instead
    /// of a whole evaluation ([`crate::geom::grid`]); the points agree with
    /// [`NurbsSurface::point_at`] to rounding. For sampling a patch for display,
    /// measurement or export.
    pub fn grid_points(&self, us: &[f64], vs: &[f64]) -> Vec<DVec3> {
        let net = Net::new(self);
        let tu = BasisTable::new(&self.knots_u, self.degree_u, us, false);
        let tv = BasisTable::new(&self.knots_v, self.degree_v, vs, false);
        let mut row = Row::new();
        let mut out = Vec::with_capacity(us.len() * vs.len());
        for l in 0..vs.len() {
            row.fill(&net, &tv, l, false);
            out.extend((0..us.len()).map(|k| row.point(&tu, k)));
        }
        out
    }

    /// Partial derivatives `d[k][l] = d^(k+l) S / du^k dv^l` for `k, l < N`
    /// (P&T A3.6 on the homogeneous net, then A4.4). Entries with `k + l >= N` are
    /// computed too and are exact. At a knot, derivatives are those of the span to the
    /// right (the left one at the domain's end), as OpenCascade evaluates them.
    pub fn derivatives<const N: usize>(&self, u: f64, v: f64) -> [[DVec3; N]; N] {
        self.derivatives_from(&self.basis_u::<N>(u), &self.basis_v::<N>(v))
    }

    /// The u-direction basis at `u` for [`NurbsSurface::derivatives_from`] with the same
    /// `N`: worked out once for every sample of a grid that shares `u`.
    #[inline(always)]
    pub fn basis_u<const N: usize>(&self, u: f64) -> Basis<N> {
        Basis::new(&self.knots_u, self.degree_u, u)
    }

    /// The v-direction basis at `v`, as [`NurbsSurface::basis_u`].
    #[inline(always)]
    pub fn basis_v<const N: usize>(&self, v: f64) -> Basis<N> {
        Basis::new(&self.knots_v, self.degree_v, v)
    }

    /// [`NurbsSurface::derivatives`] at the parameters of `bu` and `bv` (this surface's
    /// [`NurbsSurface::basis_u`] and [`NurbsSurface::basis_v`]): the same numbers, without
    /// working the basis out again at every sample of a grid.
    #[inline(always)]
    pub fn derivatives_from<const N: usize>(
        &self,
        bu: &Basis<N>,
        bv: &Basis<N>,
    ) -> [[DVec3; N]; N] {
        let (p, q) = (self.degree_u, self.degree_v);
        let (su, sv) = (bu.span, bv.span);
        let (nu, nv) = (&bu.rows, &bv.rows);
        let (i0, j0) = (su - p, sv - q);
        let mut a = [[DVec3::ZERO; N]; N];
        let mut w = [[0.0; N]; N];
        for r in 0..=p {
            // Contract along v first: temp[l] = sum_c Nv^(l)_c * Pw_{r,c}.
            let row = (i0 + r) * self.count_v + j0;
            let mut tp = [DVec3::ZERO; N];
            let mut tw = [0.0; N];
            for c in 0..=q {
                let wi = self.weights.as_ref().map_or(1.0, |w| w[row + c]);
                let pw = self.points[row + c] * wi;
                for l in 0..N {
                    tp[l] += pw * nv[l][c];
                    tw[l] += wi * nv[l][c];
                }
            }
            for ((ak, wk), nuk) in a.iter_mut().zip(w.iter_mut()).zip(nu) {
                let b = nuk[r];
                for l in 0..N {
                    ak[l] += tp[l] * b;
                    wk[l] += tw[l] * b;
                }
            }
        }
        if self.weights.is_none() {
            return a;
        }
        rational_surface_derivatives(&a, &w)
    }

    /// Unit normal `S_u x S_v / |S_u x S_v|`, or an error at a degenerate point (a
    /// collapsed edge, as at the apex of a three-sided patch). A partial derivative counts
    /// as vanishing when it is below 1e-10 of the control net's extent over the domain:
    /// at a collapsed edge it is rounding noise, not exactly zero.
    pub fn normal(&self, u: f64, v: f64) -> Result<DVec3> {
        self.normal_within(u, v, self.net_extent())
    }

    /// The diagonal of the control net's box: what [`NurbsSurface::normal_within`]
    /// takes. Worked out once when the surface is made (it reads every control point,
    /// which costs more than a normal of a large net).
    pub fn net_extent(&self) -> f64 {
        self.extent
    }

    /// [`NurbsSurface::normal`] with the net's extent ([`NurbsSurface::net_extent`])
    /// given: the same result.
    pub fn normal_within(&self, u: f64, v: f64, extent: f64) -> Result<DVec3> {
        let d = self.derivatives::<2>(u, v);
        let (su, sv) = (d[1][0], d[0][1]);
        let (du, dv) = (self.domain_u(), self.domain_v());
        let small_u = su.length() <= 1e-10 * extent / (du.1 - du.0);
        let small_v = sv.length() <= 1e-10 * extent / (dv.1 - dv.0);
        let n = su.cross(sv);
        let len = n.length();
        if small_u || small_v || len <= 1e-14 * su.length() * sv.length() || !len.is_finite() {
            return Err(GeomError::ZeroVector {
                what: "surface normal",
            });
        }
        Ok(n / len)
    }

    /// The control points of row `i` (fixed `i`, running along v) in homogeneous form.
    fn column_spline(&self, i: usize) -> Spline<Homogeneous<DVec3>> {
        let points = (0..self.count_v)
            .map(|j| Homogeneous::from_point(self.control_point(i, j), self.weight(i, j)))
            .collect();
        Spline {
            degree: self.degree_v,
            knots: self.knots_v.as_slice().to_vec(),
            points,
        }
    }

    /// The control points along u at fixed `j`, in homogeneous form.
    fn row_spline(&self, j: usize) -> Spline<Homogeneous<DVec3>> {
        let points = (0..self.count_u)
            .map(|i| Homogeneous::from_point(self.control_point(i, j), self.weight(i, j)))
            .collect();
        Spline {
            degree: self.degree_u,
            knots: self.knots_u.as_slice().to_vec(),
            points,
        }
    }

    /// Applies a curve algorithm to every line of the net in `dir` and rebuilds.
    fn map_lines(
        &self,
        dir: Direction,
        f: impl Fn(&Spline<Homogeneous<DVec3>>) -> Spline<Homogeneous<DVec3>>,
    ) -> Self {
        let rational = self.is_rational();
        match dir {
            Dir::U => {
                let lines: Vec<_> = (0..self.count_v).map(|j| f(&self.row_spline(j))).collect();
                let nu = lines[0].points.len();
                let mut points = vec![DVec3::ZERO; nu * self.count_v];
                let mut weights = vec![1.0; nu * self.count_v];
                for (j, line) in lines.iter().enumerate() {
                    for (i, h) in line.points.iter().enumerate() {
                        points[i * self.count_v + j] = h.to_point();
                        weights[i * self.count_v + j] = h.weight;
                    }
                }
                Self::from_parts(
                    (lines[0].degree, self.degree_v),
                    (lines[0].knots.clone(), self.knots_v.as_slice().to_vec()),
                    (nu, self.count_v),
                    points,
                    rational.then_some(weights),
                )
            }
            Dir::V => {
                let lines: Vec<_> = (0..self.count_u)
                    .map(|i| f(&self.column_spline(i)))
                    .collect();
                let nv = lines[0].points.len();
                let mut points = Vec::with_capacity(self.count_u * nv);
                let mut weights = Vec::with_capacity(self.count_u * nv);
                for line in &lines {
                    for h in &line.points {
                        points.push(h.to_point());
                        weights.push(h.weight);
                    }
                }
                Self::from_parts(
                    (self.degree_u, lines[0].degree),
                    (self.knots_u.as_slice().to_vec(), lines[0].knots.clone()),
                    (self.count_u, nv),
                    points,
                    rational.then_some(weights),
                )
            }
        }
    }

    /// Inserts the knot `t` up to `times` times in direction `dir`; shape unchanged.
    pub fn insert_knot(&self, dir: Direction, t: f64, times: usize) -> Result<Self> {
        let (a, b) = self.domain(dir);
        if !t.is_finite() || t <= a || t >= b {
            return Err(GeomError::ParameterOutOfRange {
                value: t,
                min: a,
                max: b,
            });
        }
        Ok(self.map_lines(dir, |s| ops::insert_knot(s, t, times)))
    }

    /// Inserts several knots in direction `dir` (P&T A5.5).
    pub fn refine(&self, dir: Direction, new_knots: &[f64]) -> Result<Self> {
        let (knots, degree) = match dir {
            Dir::U => (&self.knots_u, self.degree_u),
            Dir::V => (&self.knots_v, self.degree_v),
        };
        let x = checked_refinement(knots, degree, new_knots)?;
        Ok(self.map_lines(dir, |s| ops::refine(s, &x)))
    }

    /// Raises the degree in direction `dir` by `by` (P&T A5.10); shape unchanged.
    pub fn elevate_degree(&self, dir: Direction, by: usize) -> Result<Self> {
        let degree = match dir {
            Dir::U => self.degree_u,
            Dir::V => self.degree_v,
        };
        check_degree(degree + by)?;
        Ok(self.map_lines(dir, |s| ops::elevate_degree(s, by)))
    }

    /// Parameter domain in direction `dir`.
    pub fn domain(&self, dir: Direction) -> (f64, f64) {
        match dir {
            Dir::U => self.domain_u(),
            Dir::V => self.domain_v(),
        }
    }

    /// The iso-parametric curve at fixed `dir = t`: for `Direction::U` the curve
    /// `v -> S(t, v)`, for `Direction::V` the curve `u -> S(u, t)`. Exact (the net is
    /// contracted with the basis of the fixed parameter in homogeneous space).
    pub fn iso_curve(&self, dir: Direction, t: f64) -> Curve3 {
        let rational = self.is_rational();
        let (fixed_knots, fixed_degree, run_knots, run_degree, run_count) = match dir {
            Dir::U => (
                &self.knots_u,
                self.degree_u,
                &self.knots_v,
                self.degree_v,
                self.count_v,
            ),
            Dir::V => (
                &self.knots_v,
                self.degree_v,
                &self.knots_u,
                self.degree_u,
                self.count_u,
            ),
        };
        let span = fixed_knots.span(fixed_degree, t);
        let basis = fixed_knots.basis(span, fixed_degree, t);
        let first = span - fixed_degree;
        let mut points = Vec::with_capacity(run_count);
        let mut weights = Vec::with_capacity(run_count);
        for m in 0..run_count {
            let mut h = Homogeneous {
                weighted: DVec3::ZERO,
                weight: 0.0,
            };
            for (r, &b) in basis.iter().enumerate().take(fixed_degree + 1) {
                let (i, j) = match dir {
                    Dir::U => (first + r, m),
                    Dir::V => (m, first + r),
                };
                h = h + Homogeneous::from_point(self.control_point(i, j), self.weight(i, j)) * b;
            }
            points.push(h.to_point());
            weights.push(h.weight);
        }
        Curve3::from_parts(
            run_degree,
            run_knots.as_slice().to_vec(),
            points,
            rational.then_some(weights),
        )
    }

    /// The same surface with the domain of `dir` mapped linearly onto `[a, b]`.
    pub fn reparametrized(&self, dir: Direction, a: f64, b: f64) -> Result<Self> {
        check_domain(a, b)?;
        let (knots, degree) = match dir {
            Dir::U => (&self.knots_u, self.degree_u),
            Dir::V => (&self.knots_v, self.degree_v),
        };
        let mapped = remap_knots(knots.as_slice(), degree, a, b);
        let mut out = self.clone();
        match dir {
            Dir::U => out.knots_u = KnotVector::trusted(mapped),
            Dir::V => out.knots_v = KnotVector::trusted(mapped),
        }
        Ok(out)
    }

    /// Surface area, by 4-point Gauss-Legendre quadrature on each knot span split into
    /// 4 x 4 sub-cells (about 1e-9 relative on smooth die-face patches).
    pub fn area(&self) -> f64 {
        // 4-point Gauss-Legendre on each knot span, split in 4 sub-intervals per direction.
        const X: [f64; 4] = [
            -0.861_136_311_594_052_6,
            -0.339_981_043_584_856_3,
            0.339_981_043_584_856_3,
            0.861_136_311_594_052_6,
        ];
        const W: [f64; 4] = [
            0.347_854_845_137_453_9,
            0.652_145_154_862_546_1,
            0.652_145_154_862_546_1,
            0.347_854_845_137_453_9,
        ];
        let intervals = |knots: &[f64]| -> Vec<(f64, f64)> {
            let mut out = Vec::new();
            for w in knots.windows(2) {
                if w[1] > w[0] {
                    for k in 0..4 {
                        let a = w[0] + (w[1] - w[0]) * k as f64 / 4.0;
                        let b = w[0] + (w[1] - w[0]) * (k + 1) as f64 / 4.0;
                        out.push((a, b));
                    }
                }
            }
            out
        };
        let us = intervals(self.knots_u().as_slice());
        let vs = intervals(self.knots_v().as_slice());
        let mut total = 0.0;
        for &(u0, u1) in &us {
            for &(v0, v1) in &vs {
                let (hu, hv) = ((u1 - u0) / 2.0, (v1 - v0) / 2.0);
                for (xi, wi) in X.iter().zip(W) {
                    for (xj, wj) in X.iter().zip(W) {
                        let u = u0 + hu * (xi + 1.0);
                        let v = v0 + hv * (xj + 1.0);
                        let d = self.derivatives::<2>(u, v);
                        total += wi * wj * hu * hv * d[1][0].cross(d[0][1]).length();
                    }
                }
            }
        }
        total
    }

    /// The surface with u and v exchanged.
    pub fn transposed(&self) -> Self {
        let mut points = Vec::with_capacity(self.points.len());
        let mut weights = Vec::with_capacity(self.points.len());
        for j in 0..self.count_v {
            for i in 0..self.count_u {
                points.push(self.control_point(i, j));
                weights.push(self.weight(i, j));
            }
        }
        Self::from_parts(
            (self.degree_v, self.degree_u),
            (
                self.knots_v.as_slice().to_vec(),
                self.knots_u.as_slice().to_vec(),
            ),
            (self.count_v, self.count_u),
            points,
            self.is_rational().then_some(weights),
        )
    }

    /// Applies `f` to every control point (weights unchanged): exact for affine maps.
    pub fn map_points(&self, f: impl Fn(DVec3) -> DVec3) -> Self {
        let points: Vec<DVec3> = self.points.iter().map(|&p| f(p)).collect();
        Self {
            scale: scale_of(&points),
            extent: extent_of(&points),
            points,
            ..self.clone()
        }
    }
}

use Direction as Dir;

/// Maps a clamped knot vector linearly onto `[a, b]`, pinning the clamped ends exactly.
pub(crate) fn remap_knots(knots: &[f64], degree: usize, a: f64, b: f64) -> Vec<f64> {
    let (t0, t1) = (knots[0], knots[knots.len() - 1]);
    let scale = (b - a) / (t1 - t0);
    let n = knots.len();
    knots
        .iter()
        .enumerate()
        .map(|(i, &k)| {
            if i <= degree {
                a
            } else if i >= n - degree - 1 {
                b
            } else {
                a + (k - t0) * scale
            }
        })
        .collect()
}

/// The basis functions of one direction of a surface, and their derivatives up to order
/// `N - 1`, at one parameter ([`NurbsSurface::basis_u`], [`NurbsSurface::basis_v`]).
#[derive(Debug, Clone, Copy)]
pub struct Basis<const N: usize> {
    /// The knot span of the parameter.
    span: usize,
    /// `rows[k][r]`: the k-th derivative of the r-th basis function non-zero there.
    rows: [BasisRow; MAX_DERIVATIVE + 1],
}

impl<const N: usize> Basis<N> {
    #[inline(always)]
    fn new(knots: &KnotVector, degree: usize, t: f64) -> Self {
        const {
            assert!(
                N >= 1 && N <= MAX_DERIVATIVE + 1,
                "at most third derivatives"
            )
        };
        let span = knots.span(degree, t);
        let mut rows = [[0.0; MAX_DEGREE + 1]; MAX_DERIVATIVE + 1];
        knots.basis_derivatives(span, degree, t, N - 1, &mut rows);
        Self { span, rows }
    }
}

/// Rational surface derivatives from homogeneous ones (P&T A4.4).
pub(crate) fn rational_surface_derivatives<const N: usize>(
    a: &[[DVec3; N]; N],
    w: &[[f64; N]; N],
) -> [[DVec3; N]; N] {
    // Binomial coefficients up to the highest derivative order.
    const BINOM: [[f64; MAX_DERIVATIVE + 1]; MAX_DERIVATIVE + 1] = [
        [1.0, 0.0, 0.0, 0.0],
        [1.0, 1.0, 0.0, 0.0],
        [1.0, 2.0, 1.0, 0.0],
        [1.0, 3.0, 3.0, 1.0],
    ];
    let inv_w = 1.0 / w[0][0];
    let mut s = [[DVec3::ZERO; N]; N];
    for k in 0..N {
        for l in 0..N {
            let mut v = a[k][l];
            for j in 1..=l {
                v -= s[k][l - j] * (BINOM[l][j] * w[0][j]);
            }
            for i in 1..=k {
                let mut v2 = s[k - i][l] * w[i][0];
                for j in 1..=l {
                    v2 += s[k - i][l - j] * (BINOM[l][j] * w[i][j]);
                }
                v -= v2 * BINOM[k][i];
            }
            s[k][l] = v * inv_w;
        }
    }
    s
}
