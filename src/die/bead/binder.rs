//! The binder as a height field over the top view: the bead's course, sections and
//! feet are dropped onto it along press Z.

use glam::{DVec2, DVec3};

use super::Problem;
use crate::die::punch_opening::inside_outline;
use crate::geom::NurbsSurface;

/// A patch sample `(u, v, top-view point)`, a start for Newton.
type GridSample = (f64, f64, DVec2);

/// The binder as a height field over the top view: each patch with a grid of samples
/// to start Newton from.
pub struct Binder<'a> {
    patches: Vec<(&'a NurbsSurface, Vec<GridSample>)>,
    inner: Opening<'a>,
    /// The patch and parameters of the last hit: the next query (usually nearby)
    /// starts Newton there.
    last: std::cell::Cell<Option<(usize, f64, f64)>>,
}

impl<'a> Binder<'a> {
    /// The height field of `patches`, whose inner edge is the closed polygon `inner`.
    pub fn new(patches: Vec<&'a NurbsSurface>, inner: &'a [DVec2]) -> Self {
        let patches = patches
            .into_iter()
            .map(|s| {
                let (u0, u1) = s.domain_u();
                let (v0, v1) = s.domain_v();
                let mut grid = Vec::new();
                for i in 0..=48 {
                    for j in 0..=6 {
                        let (u, v) = (
                            u0 + (u1 - u0) * i as f64 / 48.0,
                            v0 + (v1 - v0) * j as f64 / 6.0,
                        );
                        grid.push((u, v, s.point_at(u, v).truncate()));
                    }
                }
                (s, grid)
            })
            .collect();
        Self {
            patches,
            inner: Opening::new(inner),
            last: std::cell::Cell::new(None),
        }
    }

    /// The binder point above or below the top-view point `p`, if any patch lies there.
    pub fn point_over(&self, p: DVec2) -> Option<DVec3> {
        if let Some((k, u, v)) = self.last.get() {
            if let Some((hit, u, v)) = solve_xy(self.patches[k].0, p, u, v) {
                self.last.set(Some((k, u, v)));
                return Some(hit);
            }
        }
        let mut starts: Vec<(f64, usize, f64, f64)> = Vec::new();
        for (k, (_, grid)) in self.patches.iter().enumerate() {
            let best = grid
                .iter()
                .map(|&(u, v, q)| (q.distance_squared(p), u, v))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((d, u, v)) = best {
                starts.push((d, k, u, v));
            }
        }
        starts.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &(_, k, u, v) in starts.iter().take(4) {
            if let Some((hit, u, v)) = solve_xy(self.patches[k].0, p, u, v) {
                self.last.set(Some((k, u, v)));
                return Some(hit);
            }
        }
        None
    }

    /// Whether `p` lies inside the binder's inner edge (the punch opening).
    pub fn in_opening(&self, p: DVec2) -> bool {
        self.inner.contains(p)
    }

    /// The binder point under `p`, `offset` mm across from the centre line, or why
    /// there is none.
    pub(super) fn base(&self, p: DVec2, offset: Option<f64>) -> Result<DVec3, Problem> {
        if self.in_opening(p) {
            return Err(Problem::CrossesOpening { at: p, offset });
        }
        self.point_over(p)
            .ok_or(Problem::LeavesBinder { at: p, offset })
    }
}

/// Height bands of the opening's outline.
const OPENING_BANDS: usize = 256;

/// The punch opening's outline with its edges sorted into bands of height (top-view
/// y), so the inside test of every bead point (every section point asks) reads only
/// the edges that reach its band, not the whole outline.
struct Opening<'a> {
    outline: &'a [DVec2],
    /// Lowest and highest y of the outline, and the bands' height (`None` for an
    /// outline without height, which is tested whole).
    range: Option<(f64, f64, f64)>,
    /// Per band, the indices (in outline order) of the edges whose y-range meets it.
    bands: Vec<Vec<usize>>,
}

impl<'a> Opening<'a> {
    fn new(outline: &'a [DVec2]) -> Self {
        let n = outline.len();
        let (low, high) = outline
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.y), hi.max(p.y))
            });
        let step = (high - low) / OPENING_BANDS as f64;
        let range = (step.is_finite() && step > 0.0).then_some((low, high, step));
        let mut bands = vec![Vec::new(); OPENING_BANDS];
        if let Some(range) = range {
            for k in 0..n {
                let (a, b) = (outline[k], outline[(k + 1) % n]);
                let (first, last) = (band(range, a.y.min(b.y)), band(range, a.y.max(b.y)));
                for band in &mut bands[first..=last] {
                    band.push(k);
                }
            }
        }
        Self {
            outline,
            range,
            bands,
        }
    }

    /// [`inside_outline`]: whether `p` lies inside the outline (even-odd rule). Only
    /// edges with one end above `p.y` and one not (`y_min <= p.y < y_max`) can flip
    /// the answer: none when `p.y` is outside the outline's heights, otherwise edges
    /// that all reach `p`'s band (the band is monotone in y); they are read in the
    /// outline's order, with the same test.
    fn contains(&self, p: DVec2) -> bool {
        let Some(range) = self.range else {
            return inside_outline(self.outline, p);
        };
        if !(p.y >= range.0 && p.y < range.1) {
            return false;
        }
        let n = self.outline.len();
        let mut inside = false;
        for &k in &self.bands[band(range, p.y)] {
            let (a, b) = (self.outline[k], self.outline[(k + 1) % n]);
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if p.x < x {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

/// The band of height `y` (within the outline's heights) of `range` (low, high, step).
fn band(range: (f64, f64, f64), y: f64) -> usize {
    (((y - range.0) / range.2).max(0.0) as usize).min(OPENING_BANDS - 1)
}

/// Newton on `S(u, v).xy = p` from `(u, v)`, inside the domain; the point if it
/// converges there.
fn solve_xy(s: &NurbsSurface, p: DVec2, mut u: f64, mut v: f64) -> Option<(DVec3, f64, f64)> {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let tol = 1e-10 * (1.0 + p.length());
    for _ in 0..40 {
        let d = s.derivatives::<2>(u, v);
        let (pt, su, sv) = (d[0][0], d[1][0], d[0][1]);
        let f = pt.truncate() - p;
        if f.length() <= tol {
            return Some((pt, u, v));
        }
        let det = su.x * sv.y - su.y * sv.x;
        if det.abs() < 1e-300 {
            return None;
        }
        let du = (f.x * sv.y - f.y * sv.x) / det;
        let dv = (su.x * f.y - su.y * f.x) / det;
        let (nu, nv) = (u - du, v - dv);
        let eps_u = 1e-9 * (u1 - u0);
        let eps_v = 1e-9 * (v1 - v0);
        if nu < u0 - eps_u || nu > u1 + eps_u || nv < v0 - eps_v || nv > v1 + eps_v {
            // Allow one clamped step before giving up: the point may lie in a
            // neighbouring patch.
            let (cu, cv) = (nu.clamp(u0, u1), nv.clamp(v0, v1));
            if (cu - u).abs() < eps_u && (cv - v).abs() < eps_v {
                return None;
            }
            u = cu;
            v = cv;
        } else {
            u = nu.clamp(u0, u1);
            v = nv.clamp(v0, v1);
        }
    }
    let pt = s.point_at(u, v);
    (pt.truncate().distance(p) <= 1e-7 * (1.0 + p.length())).then_some((pt, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn banded_opening_answers_as_the_whole_outline() {
        // A wavy closed outline with points on band boundaries and flat runs.
        let outline: Vec<DVec2> = (0..200)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 200.0;
                let r = 100.0 + 20.0 * (5.0 * a).sin();
                DVec2::new(r * a.cos(), (r * a.sin()).round())
            })
            .collect();
        let opening = Opening::new(&outline);
        let mut seed = 777u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for i in 0..5000 {
            let mut p = DVec2::new(-150.0 + 300.0 * next(), -150.0 + 300.0 * next());
            if i % 3 == 0 {
                p.y = p.y.round();
            }
            if i % 7 == 0 {
                p = outline[i % outline.len()];
            }
            if i % 11 == 0 {
                p.y = if i % 2 == 0 { -120.0 } else { 120.0 };
            }
            assert_eq!(opening.contains(p), inside_outline(&outline, p), "{p}");
        }
        assert!(!Opening::new(&[]).contains(DVec2::ZERO));
    }
}
