//! The surface a sheet part lies on (a curved panel, a reinforcement following the
//! outer skin): the part is built flat on its working plane, as the designer draws it
//! in the outline's view, and then laid onto the surface.
//!
//! A point of the flat layout at `q` on the working plane and `z` above it goes to
//! `S(q) + z N(q)`: `S(q)` is the point of the surface seen through `q` along the view
//! (the line through `q` along the plane's normal meets the surface there) and `N(q)`
//! the surface's unit normal there, turned towards the view. So the plate's mid-surface
//! is the surface itself over the outline, a flange square to the plate stands along
//! the surface's normal, and a lifted region's top is the surface offset by its height.
//!
//! [`BaseSurface::jacobian`] is the derivative of that map, which the thickening reads
//! to turn each flat face's normal into the laid face's normal at a point
//! (`super::laid`). It is worked out from the surface's first and second derivatives
//! (Weingarten: the normal's derivative from `S_uu`, `S_uv`, `S_vv`), not by
//! differences.

use glam::{DMat2, DMat3, DVec2, DVec3};

use crate::geom::NurbsSurface;

/// The steepest the surface may stand to the view (its normal's angle to the view's
/// normal): beyond it a small step in the outline's view is a long one on the surface,
/// and at 90 deg the surface is not seen at all.
pub const STEEPEST: f64 = 75.0;

/// Seeds per parameter direction for finding the surface point under a point.
const SEEDS: usize = 33;

/// Seeds tried, after the nearest, before a point counts as not over the surface.
const SEEDS_TRIED: usize = 8;

/// Newton steps for the surface point under a point.
const ITERATIONS: usize = 40;

/// Why a point of the flat layout could not be laid on the surface.
#[derive(Debug, Clone, PartialEq)]
pub enum BaseError {
    /// No point of the surface lies along the view through `at` (on the working
    /// plane): the outline reaches past the surface's edge.
    Miss { at: DVec3 },
    /// The surface under `at` stands `angle` degrees to the view, steeper than
    /// [`STEEPEST`], or folds there (its normal vanishes).
    Steep { at: DVec3, angle: f64 },
}

impl std::fmt::Display for BaseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BaseError::Miss { at } => write!(
                f,
                "the surface does not reach under ({:.3}, {:.3}, {:.3}) of the flat part: \
                 every point of the part must lie over the surface, seen along the view",
                at.x, at.y, at.z
            ),
            BaseError::Steep { at, angle } => write!(
                f,
                "the surface under ({:.3}, {:.3}, {:.3}) stands {angle:.1} deg to the view, \
                 steeper than {STEEPEST} deg",
                at.x, at.y, at.z
            ),
        }
    }
}

impl std::error::Error for BaseError {}

/// A surface seen along a working plane's normal, onto which a flat layout is laid.
#[derive(Debug, Clone)]
pub struct BaseSurface {
    surface: NurbsSurface,
    /// A point of the working plane.
    origin: DVec3,
    /// The working plane's axes and unit normal (the view's).
    axes: DMat3,
    /// Where each seed of a grid over the parameters lies on the working plane.
    seeds: Vec<(DVec2, DVec2)>,
    /// The seeds by where they lie on the plane, to find the nearest quickly.
    buckets: Buckets,
    /// The size of the surface's control net, for relative tolerances.
    extent: f64,
}

/// The surface at a point under the layout: its point, its unit normal (towards the
/// view) and the derivatives the map's Jacobian needs.
struct Foot {
    point: DVec3,
    normal: DVec3,
    /// `S_u`, `S_v` and the normal's derivatives `N_u`, `N_v`.
    su: DVec3,
    sv: DVec3,
    nu: DVec3,
    nv: DVec3,
}

impl BaseSurface {
    /// `surface` seen along `normal` (the working plane's, through `origin`).
    pub fn new(surface: NurbsSurface, origin: DVec3, normal: DVec3) -> BaseSurface {
        let n = normal.normalize_or_zero();
        let n = if n == DVec3::ZERO { DVec3::Z } else { n };
        let e1 = n.any_orthonormal_vector();
        let axes = DMat3::from_cols(e1, n.cross(e1), n);
        let (u0, u1) = surface.domain_u();
        let (v0, v1) = surface.domain_v();
        let mut seeds = Vec::with_capacity(SEEDS * SEEDS);
        for i in 0..SEEDS {
            let u = u0 + (u1 - u0) * i as f64 / (SEEDS - 1) as f64;
            for j in 0..SEEDS {
                let v = v0 + (v1 - v0) * j as f64 / (SEEDS - 1) as f64;
                let p = surface.point_at(u, v) - origin;
                seeds.push((
                    DVec2::new(p.dot(axes.x_axis), p.dot(axes.y_axis)),
                    DVec2::new(u, v),
                ));
            }
        }
        let extent = surface.net_extent().max(1.0);
        let buckets = Buckets::new(&seeds);
        BaseSurface {
            surface,
            origin,
            axes,
            seeds,
            buckets,
            extent,
        }
    }

    /// Where the flat layout's point `p` lies once laid on the surface.
    pub fn lay(&self, p: DVec3) -> Result<DVec3, BaseError> {
        let (q, z) = self.split(p);
        let foot = self.foot(q, p)?;
        Ok(foot.point + z * foot.normal)
    }

    /// [`BaseSurface::lay`] of `p`, and the map's derivative there: the matrix that
    /// takes a small step `d` of the flat layout (press coordinates) at `p` to the step
    /// it makes once laid.
    pub fn jacobian(&self, p: DVec3) -> Result<(DVec3, DMat3), BaseError> {
        let (q, z) = self.split(p);
        let f = self.foot(q, p)?;
        // The parameters' derivatives along the plane's axes: S(u, v) seen on the
        // plane is q, so [S_u S_v] (seen) times d(u, v) is dq.
        let seen = DMat2::from_cols(
            DVec2::new(f.su.dot(self.axes.x_axis), f.su.dot(self.axes.y_axis)),
            DVec2::new(f.sv.dot(self.axes.x_axis), f.sv.dot(self.axes.y_axis)),
        );
        // Not singular: `foot` refused a surface seen edge on.
        let inv = seen.inverse();
        let (du, dv) = (f.su + z * f.nu, f.sv + z * f.nv);
        let along = |k: usize| {
            let uv = inv.col(k);
            du * uv.x + dv * uv.y
        };
        // Columns: the images of the plane's two axes and of its normal.
        let local = DMat3::from_cols(along(0), along(1), f.normal);
        Ok((f.point + z * f.normal, local * self.axes.transpose()))
    }

    /// The largest curvature (1/mm) of the surface's normal sections along its
    /// parameter lines and their diagonals, sampled on a grid over its domain: what
    /// sets how finely a face laid on it is cut. Where the surface stands too steep to
    /// be seen, it is not sampled.
    pub fn curvature_bound(&self) -> f64 {
        let (u0, u1) = self.surface.domain_u();
        let (v0, v1) = self.surface.domain_v();
        let samples = 17;
        let mut worst: f64 = 0.0;
        for i in 0..samples {
            let u = u0 + (u1 - u0) * i as f64 / (samples - 1) as f64;
            for j in 0..samples {
                let v = v0 + (v1 - v0) * j as f64 / (samples - 1) as f64;
                let Ok(f) = self.frame(DVec2::new(u, v), DVec3::ZERO) else {
                    continue;
                };
                for (ds, dn) in [
                    (f.su, f.nu),
                    (f.sv, f.nv),
                    (f.su + f.sv, f.nu + f.nv),
                    (f.su - f.sv, f.nu - f.nv),
                ] {
                    let length = ds.length();
                    if length > 0.0 {
                        worst = worst.max(dn.length() / length);
                    }
                }
            }
        }
        worst
    }

    /// `p` as a point of the working plane (its axes' coordinates) and its height above.
    fn split(&self, p: DVec3) -> (DVec2, f64) {
        let d = p - self.origin;
        (
            DVec2::new(d.dot(self.axes.x_axis), d.dot(self.axes.y_axis)),
            d.dot(self.axes.z_axis),
        )
    }

    /// The surface under the plane's point `q` (`at`, the layout's point, for errors):
    /// Newton on the parameters from the nearest seeds, kept inside the domain.
    fn foot(&self, q: DVec2, at: DVec3) -> Result<Foot, BaseError> {
        let tolerance = 1e-10 * self.extent;
        let distance = |&(s, _): &(DVec2, DVec2)| s.distance_squared(q);
        // A seed near the point first; the others, nearest first, only where Newton
        // fails from it.
        let nearest = self.buckets.near(&self.seeds, q).map(|k| self.seeds[k].1);
        if let Some(uv) = nearest.and_then(|start| self.newton(q, start, tolerance)) {
            return self.frame(uv, at);
        }
        let mut order: Vec<(f64, DVec2)> = self.seeds.iter().map(|s| (distance(s), s.1)).collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &(_, start) in order.iter().skip(1).take(SEEDS_TRIED) {
            if let Some(uv) = self.newton(q, start, tolerance) {
                return self.frame(uv, at);
            }
        }
        Err(BaseError::Miss { at })
    }

    /// Newton on the parameters for the point seen at `q`, or `None` when it leaves the
    /// domain or stalls off the point.
    fn newton(&self, q: DVec2, start: DVec2, tolerance: f64) -> Option<DVec2> {
        let (u0, u1) = self.surface.domain_u();
        let (v0, v1) = self.surface.domain_v();
        let mut uv = start;
        for _ in 0..ITERATIONS {
            let d = self.surface.derivatives::<2>(uv.x, uv.y);
            let p = d[0][0] - self.origin;
            let r = DVec2::new(p.dot(self.axes.x_axis), p.dot(self.axes.y_axis)) - q;
            if r.length() <= tolerance {
                return Some(uv);
            }
            let m = DMat2::from_cols(
                DVec2::new(d[1][0].dot(self.axes.x_axis), d[1][0].dot(self.axes.y_axis)),
                DVec2::new(d[0][1].dot(self.axes.x_axis), d[0][1].dot(self.axes.y_axis)),
            );
            if m.determinant().abs() < 1e-300 {
                return None;
            }
            let next = uv - m.inverse() * r;
            let clamped = DVec2::new(next.x.clamp(u0, u1), next.y.clamp(v0, v1));
            if !clamped.is_finite() {
                return None;
            }
            // Pushed against the domain's edge twice over: the point lies beyond it.
            if clamped != next && clamped == uv {
                return None;
            }
            uv = clamped;
        }
        None
    }

    /// The surface's point, normal and derivatives at the parameters `uv`.
    fn frame(&self, uv: DVec2, at: DVec3) -> Result<Foot, BaseError> {
        let d = self.surface.derivatives::<3>(uv.x, uv.y);
        let (su, sv) = (d[1][0], d[0][1]);
        let cross = su.cross(sv);
        let length = cross.length();
        let steep = |cos: f64| BaseError::Steep {
            at,
            angle: cos.clamp(-1.0, 1.0).acos().to_degrees(),
        };
        if length <= 1e-12 * self.extent * self.extent {
            return Err(steep(0.0));
        }
        let mut normal = cross / length;
        let facing = normal.dot(self.axes.z_axis);
        // Towards the view: a surface whose parameters run the other way is turned.
        let sign = if facing < 0.0 { -1.0 } else { 1.0 };
        normal *= sign;
        if facing.abs() < STEEPEST.to_radians().cos() {
            return Err(steep(facing.abs()));
        }
        // Weingarten: the derivative of the unit normal n / |n| of n = S_u x S_v.
        let unit_derivative = |dn: DVec3| sign * (dn - normal * normal.dot(dn)) / length;
        let nu = unit_derivative(d[2][0].cross(sv) + su.cross(d[1][1]));
        let nv = unit_derivative(d[1][1].cross(sv) + su.cross(d[0][2]));
        Ok(Foot {
            point: d[0][0],
            normal,
            su,
            sv,
            nu,
            nv,
        })
    }
}

/// The seeds sorted into a square grid of cells over where they lie on the plane.
#[derive(Debug, Clone)]
struct Buckets {
    low: DVec2,
    cell: f64,
    side: usize,
    cells: Vec<Vec<usize>>,
}

impl Buckets {
    fn new(seeds: &[(DVec2, DVec2)]) -> Buckets {
        let (low, high) = seeds.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &(p, _)| (lo.min(p), hi.max(p)),
        );
        let side = SEEDS;
        let span = (high - low).max_element();
        let cell = if span.is_finite() && span > 0.0 {
            span / side as f64
        } else {
            1.0
        };
        let low = if low.is_finite() { low } else { DVec2::ZERO };
        let mut cells = vec![Vec::new(); side * side];
        let mut out = Buckets {
            low,
            cell,
            side,
            cells: Vec::new(),
        };
        for (k, &(p, _)) in seeds.iter().enumerate() {
            let (i, j) = out.cell_of(p);
            cells[i * side + j].push(k);
        }
        out.cells = cells;
        out
    }

    /// The cell holding `p`, or the nearest cell to it.
    fn cell_of(&self, p: DVec2) -> (usize, usize) {
        let at = |x: f64| {
            let c = (x / self.cell).floor();
            if c.is_finite() {
                c.clamp(0.0, (self.side - 1) as f64) as usize
            } else {
                0
            }
        };
        (at(p.x - self.low.x), at(p.y - self.low.y))
    }

    /// The seed nearest `q` among those in the first ring of cells round `q`'s cell
    /// that holds any, and the ring beyond it.
    fn near(&self, seeds: &[(DVec2, DVec2)], q: DVec2) -> Option<usize> {
        let (ci, cj) = self.cell_of(q);
        let mut best: Option<(f64, usize)> = None;
        let mut found_at: Option<usize> = None;
        for ring in 0..self.side {
            if found_at.is_some_and(|r| ring > r + 1) {
                break;
            }
            let (i0, i1) = (ci.saturating_sub(ring), (ci + ring).min(self.side - 1));
            let (j0, j1) = (cj.saturating_sub(ring), (cj + ring).min(self.side - 1));
            for i in i0..=i1 {
                for j in j0..=j1 {
                    // The ring's cells only: the inner ones were searched.
                    if i.abs_diff(ci) != ring && j.abs_diff(cj) != ring {
                        continue;
                    }
                    for &k in &self.cells[i * self.side + j] {
                        let d = seeds[k].0.distance_squared(q);
                        if best.is_none_or(|(b, _)| d < b) {
                            best = Some((d, k));
                        }
                    }
                }
            }
            if best.is_some() && found_at.is_none() {
                found_at = Some(ring);
            }
        }
        best.map(|(_, k)| k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bilinear-in-x, quadratic-in-y patch: z = 10 + 0.002 (y - 50)^2 over
    /// x in [0, 100], y in [0, 100] (a cylinder-like trough), as a degree (1, 2) net.
    fn trough() -> NurbsSurface {
        // A quadratic Bezier in y reproduces the parabola exactly: control heights at
        // y = 0, 50, 100 are 15, 10 - 5, 15 (the middle one where the end tangents meet).
        let rows = [0.0, 100.0]
            .iter()
            .map(|&x| {
                vec![
                    DVec3::new(x, 0.0, 15.0),
                    DVec3::new(x, 50.0, 5.0),
                    DVec3::new(x, 100.0, 15.0),
                ]
            })
            .collect();
        NurbsSurface::new(
            1,
            2,
            vec![0.0, 0.0, 1.0, 1.0],
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            rows,
        )
        .expect("valid: the counts match the knots")
    }

    fn height(y: f64) -> f64 {
        10.0 + 0.002 * (y - 50.0) * (y - 50.0)
    }

    #[test]
    fn a_point_on_the_plane_lands_on_the_surface_under_it() {
        let base = BaseSurface::new(trough(), DVec3::ZERO, DVec3::Z);
        for (x, y) in [(10.0, 20.0), (50.0, 50.0), (99.0, 3.0), (0.0, 100.0)] {
            let p = base.lay(DVec3::new(x, y, 0.0)).expect("over the surface");
            assert!((p - DVec3::new(x, y, height(y))).length() < 1e-9, "{p}");
        }
    }

    #[test]
    fn a_point_above_the_plane_goes_along_the_normal() {
        let base = BaseSurface::new(trough(), DVec3::ZERO, DVec3::Z);
        let y: f64 = 80.0;
        let slope = 0.004 * (y - 50.0);
        let normal = DVec3::new(0.0, -slope, 1.0).normalize();
        let p = base
            .lay(DVec3::new(30.0, y, 5.0))
            .expect("over the surface");
        let expected = DVec3::new(30.0, y, height(y)) + 5.0 * normal;
        assert!((p - expected).length() < 1e-9, "{p} vs {expected}");
    }

    #[test]
    fn the_jacobian_matches_differences_of_the_map() {
        let base = BaseSurface::new(trough(), DVec3::ZERO, DVec3::Z);
        let p = DVec3::new(40.0, 70.0, 3.0);
        let (at, j) = base.jacobian(p).expect("over the surface");
        assert!((at - base.lay(p).expect("over")).length() < 1e-12);
        let h = 1e-4;
        for d in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.3, -0.8, 0.5)] {
            let a = base.lay(p + h * d).expect("over");
            let b = base.lay(p - h * d).expect("over");
            let fd = (a - b) / (2.0 * h);
            assert!((fd - j * d).length() < 1e-6, "{d}: {fd} vs {}", j * d);
        }
    }

    #[test]
    fn a_point_beyond_the_surface_is_refused() {
        let base = BaseSurface::new(trough(), DVec3::ZERO, DVec3::Z);
        let err = base.lay(DVec3::new(120.0, 50.0, 0.0)).unwrap_err();
        assert!(matches!(err, BaseError::Miss { .. }), "{err}");
    }

    #[test]
    fn a_surface_seen_edge_on_is_refused() {
        // The trough seen from the side (along +X): its points all lie over one line.
        let base = BaseSurface::new(trough(), DVec3::ZERO, DVec3::X);
        let err = base.lay(DVec3::new(0.0, 10.0, 30.0)).unwrap_err();
        assert!(
            matches!(err, BaseError::Steep { .. } | BaseError::Miss { .. }),
            "{err}"
        );
    }
}
