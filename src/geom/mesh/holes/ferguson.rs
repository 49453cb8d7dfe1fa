//! The base surface as bicubic Ferguson patches (paper 002, eq. 2-4): each grid cell a
//! patch through its four corner points, with the u and v tangents at the corners taken
//! from cubic spline interpolation along the grid lines and zero twist. Neighbouring
//! patches share their corner points and tangents, so the surface is C1 across them.
//!
//! [`FergusonPatches`] keeps the Hermite data (the grid's points and tangents) and
//! evaluates a patch from it directly, as eq. 2 writes it: what filling a hole asks of
//! its base surface many times (the loop's nodes projected onto it, the fill's nodes
//! mapped back), at a fraction of a general NURBS evaluation's cost. The same patches
//! are handed on as one bicubic B-spline with double interior knots
//! ([`FergusonPatches::surface`]: a patch's Bézier net is its Hermite data, the corner
//! and a third of a step along each tangent; C1 joins make the corners between patches
//! implicit), so the rest of the kernel (point inversion, tessellation, export) takes
//! the base surface like any other surface.

use glam::DVec3;

use crate::geom::error::{GeomError, Result};
use crate::geom::inversion::SurfaceEval;
use crate::geom::surface::NurbsSurface;

/// The first derivatives of the natural cubic spline through `points`, a parameter
/// step `h` apart (the C2 spline's tangents, eq. 3's r_u or r_v at each point): the
/// tridiagonal system `D[i-1] + 4 D[i] + D[i+1] = 3 (P[i+1] - P[i-1]) / h`, with
/// `2 D[0] + D[1]` and `D[n-1] + 2 D[n]` at the ends (zero second derivative there).
pub fn spline_tangents(points: &[DVec3], h: f64) -> Vec<DVec3> {
    let mut out = vec![DVec3::ZERO; points.len()];
    spline_tangents_along(points, 0, 1, points.len(), h, &mut out, &mut Vec::new());
    out
}

/// [`spline_tangents`] of the `n` points `points[start + k * stride]`, written to the
/// same places of `out`: a grid line read where it lies in the grid, `scratch` the
/// Thomas algorithm's work row (kept between lines).
fn spline_tangents_along(
    points: &[DVec3],
    start: usize,
    stride: usize,
    n: usize,
    h: f64,
    out: &mut [DVec3],
    scratch: &mut Vec<f64>,
) {
    let at = |k: usize| start + k * stride;
    match n {
        0 => return,
        1 => {
            out[at(0)] = DVec3::ZERO;
            return;
        }
        2 => {
            let t = (points[at(1)] - points[at(0)]) / h;
            out[at(0)] = t;
            out[at(1)] = t;
            return;
        }
        _ => {}
    }
    // Thomas algorithm: sub-diagonal 1, diagonal b, super-diagonal c, right side d
    // (d in `out`, solved in place).
    scratch.clear();
    scratch.resize(n, 0.0);
    let c = scratch;
    c[0] = 0.5;
    out[at(0)] = 1.5 * (points[at(1)] - points[at(0)]) / h;
    for i in 1..n {
        let (b, cc, rhs) = if i + 1 == n {
            (2.0, 0.0, 3.0 * (points[at(i)] - points[at(i - 1)]) / h)
        } else {
            (4.0, 1.0, 3.0 * (points[at(i + 1)] - points[at(i - 1)]) / h)
        };
        let m = b - c[i - 1];
        c[i] = cc / m;
        out[at(i)] = (rhs - out[at(i - 1)]) / m;
    }
    for i in (0..n - 1).rev() {
        out[at(i)] = out[at(i)] - c[i] * out[at(i + 1)];
    }
}

/// The cubic Hermite basis and its first two derivatives at `s` in `[0, 1]`:
/// `[order][k]`, `k` = the start point, the end point, the start tangent, the end
/// tangent (eq. 2's F1, F2, G1, G2).
fn hermite(s: f64) -> [[f64; 4]; 3] {
    let (s2, s3) = (s * s, s * s * s);
    [
        [
            1.0 - 3.0 * s2 + 2.0 * s3,
            3.0 * s2 - 2.0 * s3,
            s - 2.0 * s2 + s3,
            s3 - s2,
        ],
        [
            6.0 * (s2 - s),
            6.0 * (s - s2),
            1.0 - 4.0 * s + 3.0 * s2,
            3.0 * s2 - 2.0 * s,
        ],
        [12.0 * s - 6.0, 6.0 - 12.0 * s, 6.0 * s - 4.0, 6.0 * s - 2.0],
    ]
}

/// Bicubic Ferguson patches over a regular grid of `nu` by `nv` points a step `h`
/// apart in both parameters: the points, and the spline tangents along u and along v
/// at each (node `(i, j)` at `i * nv + j`, `i` along u). `u` runs from 0 to
/// `h (nu - 1)`, `v` likewise.
#[derive(Debug, Clone, PartialEq)]
pub struct FergusonPatches {
    nu: usize,
    nv: usize,
    h: f64,
    points: Vec<DVec3>,
    du: Vec<DVec3>,
    dv: Vec<DVec3>,
    /// The largest distance of a grid point from the origin: the size the projection's
    /// tolerances are relative to.
    scale: f64,
}

impl FergusonPatches {
    /// The patches through the grid `points` (`nu` by `nv`, node `(i, j)` at
    /// `i * nv + j`), `h` apart: at least 2 x 2 finite points and a positive step.
    pub fn new(points: Vec<DVec3>, nu: usize, nv: usize, h: f64) -> Result<FergusonPatches> {
        if nu < 2 || nv < 2 || points.len() != nu * nv {
            return Err(GeomError::LengthMismatch {
                what: "Ferguson grid points",
                expected: nu.max(2) * nv.max(2),
                given: points.len(),
            });
        }
        if !(h.is_finite() && h > 0.0) || points.iter().any(|p| !p.is_finite()) {
            return Err(GeomError::NotFinite {
                what: "Ferguson grid",
            });
        }
        let mut du = vec![DVec3::ZERO; points.len()];
        let mut dv = vec![DVec3::ZERO; points.len()];
        let mut scratch = Vec::new();
        for j in 0..nv {
            spline_tangents_along(&points, j, nv, nu, h, &mut du, &mut scratch);
        }
        for i in 0..nu {
            spline_tangents_along(&points, i * nv, 1, nv, h, &mut dv, &mut scratch);
        }
        let scale = points.iter().map(|p| p.length()).fold(0.0, f64::max);
        Ok(FergusonPatches {
            nu,
            nv,
            h,
            points,
            du,
            dv,
            scale,
        })
    }

    /// The patch holding parameter `u` along a direction of `n` grid points, and the
    /// patch's own parameter there in `[0, 1]` (clamped to the grid).
    fn cell(&self, u: f64, n: usize) -> (usize, f64) {
        let x = (u / self.h).clamp(0.0, (n - 1) as f64);
        // x is finite and in [0, n - 1]: the cast cannot wrap.
        let i = (x.floor() as usize).min(n - 2);
        (i, x - i as f64)
    }

    /// The derivatives `d[k][l]` = `d^(k+l) S / du^k dv^l` at `(u, v)` for `k + l <= 2`
    /// (the rest zero): eq. 2 with its basis differentiated.
    pub fn derivatives(&self, u: f64, v: f64) -> [[DVec3; 3]; 3] {
        let (i, s) = self.cell(u, self.nu);
        let (j, t) = self.cell(v, self.nv);
        let (fs, ft) = (hermite(s), hermite(t));
        let node = |a: usize, b: usize| (i + a) * self.nv + j + b;
        let mut d = [[DVec3::ZERO; 3]; 3];
        for (k, row) in d.iter_mut().enumerate() {
            for (l, out) in row.iter_mut().enumerate().take(3 - k) {
                let mut sum = DVec3::ZERO;
                for a in 0..2 {
                    for b in 0..2 {
                        let n = node(a, b);
                        sum += fs[k][a] * ft[l][b] * self.points[n]
                            + self.h * fs[k][a + 2] * ft[l][b] * self.du[n]
                            + self.h * fs[k][a] * ft[l][b + 2] * self.dv[n];
                    }
                }
                *out = sum / self.h.powi((k + l) as i32);
            }
        }
        d
    }

    /// The patches as one bicubic B-spline surface with double interior knots, the
    /// same surface point for point.
    pub fn surface(&self) -> NurbsSurface {
        // Patch (i, j)'s Bézier net is its Hermite data: control point k along a
        // direction belongs to grid node k / 3 and stands a third of a step along that
        // node's tangent, forwards (k % 3 == 1) or back (k % 3 == 2). At a join between
        // patches the corner is the midpoint of the two points either side (the tangent
        // is the same both ways, the twist zero), so as a B-spline with double knots
        // there it drops out: the net keeps the ends and the points a third of a step
        // off each node.
        let node = |k: usize| -> (usize, f64) {
            match k % 3 {
                0 => (k / 3, 0.0),
                1 => (k / 3, 1.0),
                _ => (k / 3 + 1, -1.0),
            }
        };
        let kept = |n: usize| -> Vec<usize> {
            let last = 3 * (n - 1);
            (0..=last)
                .filter(|&k| k == 0 || k == last || k % 3 != 0)
                .collect()
        };
        let third = self.h / 3.0;
        let (along_u, along_v) = (kept(self.nu), kept(self.nv));
        let mut net = Vec::with_capacity(along_u.len() * along_v.len());
        for &k in &along_u {
            let (i, su) = node(k);
            for &l in &along_v {
                let (j, sv) = node(l);
                let n = i * self.nv + j;
                net.push(self.points[n] + su * third * self.du[n] + sv * third * self.dv[n]);
            }
        }
        let knots = |n: usize| -> Vec<f64> {
            let mut k = vec![0.0; 4];
            for c in 1..n - 1 {
                k.extend([c as f64 * self.h; 2]);
            }
            k.extend([(n - 1) as f64 * self.h; 4]);
            k
        };
        // A clamped cubic with double interior knots over `n` grid points has
        // 2 (n - 1) + 2 control points per direction, as `kept` gives, and the net is
        // finite as the grid and the tangents are: valid by construction.
        NurbsSurface::from_parts(
            (3, 3),
            (knots(self.nu), knots(self.nv)),
            (along_u.len(), along_v.len()),
            net,
            None,
        )
    }
}

impl SurfaceEval for FergusonPatches {
    /// The parameter range along u, `[0, h (nu - 1)]`.
    fn domain_u(&self) -> (f64, f64) {
        (0.0, self.h * (self.nu - 1) as f64)
    }

    /// The parameter range along v, `[0, h (nv - 1)]`.
    fn domain_v(&self) -> (f64, f64) {
        (0.0, self.h * (self.nv - 1) as f64)
    }

    /// The point `S(u, v)`: eq. 2.
    fn point_at(&self, u: f64, v: f64) -> DVec3 {
        let (i, s) = self.cell(u, self.nu);
        let (j, t) = self.cell(v, self.nv);
        let (fs, ft) = (hermite(s)[0], hermite(t)[0]);
        let mut sum = DVec3::ZERO;
        for a in 0..2 {
            for b in 0..2 {
                let n = (i + a) * self.nv + j + b;
                sum += fs[a] * ft[b] * self.points[n]
                    + self.h * (fs[a + 2] * ft[b] * self.du[n] + fs[a] * ft[b + 2] * self.dv[n]);
            }
        }
        sum
    }

    fn second_derivatives(&self, u: f64, v: f64) -> [[DVec3; 3]; 3] {
        self.derivatives(u, v)
    }

    fn scale(&self) -> f64 {
        self.scale
    }
}
