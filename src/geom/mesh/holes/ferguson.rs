//! The base surface as bicubic Ferguson patches (paper 002, eq. 2-4): each grid cell a
//! patch through its four corner points, with the u and v tangents at the corners taken
//! from cubic spline interpolation along the grid lines and zero twist. Neighbouring
//! patches share their corner points and tangents, so the surface is C1 across them.
//!
//! The patches are handed on as one bicubic B-spline with double interior knots (a
//! patch's Bézier net is its Hermite data: the corner, a third of a step along each
//! tangent; C1 joins make the corners between patches implicit), so the rest of the
//! kernel (point inversion, tessellation, export) takes the base surface like any
//! other surface.

use glam::DVec3;

use crate::geom::error::Result;
use crate::geom::surface::NurbsSurface;

/// The first derivatives of the natural cubic spline through `points`, a parameter
/// step `h` apart (the C2 spline's tangents, eq. 3's r_u or r_v at each point): the
/// tridiagonal system `D[i-1] + 4 D[i] + D[i+1] = 3 (P[i+1] - P[i-1]) / h`, with
/// `2 D[0] + D[1]` and `D[n-1] + 2 D[n]` at the ends (zero second derivative there).
pub fn spline_tangents(points: &[DVec3], h: f64) -> Vec<DVec3> {
    let n = points.len();
    match n {
        0 => return Vec::new(),
        1 => return vec![DVec3::ZERO],
        2 => return vec![(points[1] - points[0]) / h; 2],
        _ => {}
    }
    // Thomas algorithm: sub-diagonal a, diagonal b, super-diagonal c, right side d.
    let mut c = vec![0.0f64; n];
    let mut d = vec![DVec3::ZERO; n];
    let (b0, c0) = (2.0, 1.0);
    c[0] = c0 / b0;
    d[0] = 3.0 * (points[1] - points[0]) / h / b0;
    for i in 1..n {
        let (a, b, cc, rhs) = if i + 1 == n {
            (1.0, 2.0, 0.0, 3.0 * (points[i] - points[i - 1]) / h)
        } else {
            (1.0, 4.0, 1.0, 3.0 * (points[i + 1] - points[i - 1]) / h)
        };
        let m = b - a * c[i - 1];
        c[i] = cc / m;
        d[i] = (rhs - a * d[i - 1]) / m;
    }
    for i in (0..n - 1).rev() {
        d[i] = d[i] - c[i] * d[i + 1];
    }
    d
}

/// The Ferguson surface through the grid `points[i][j]` (`i` along u, `j` along v, at
/// least 2 x 2), a step `h` apart in both parameters: u runs from 0 to `h` times the
/// cells along u, v likewise. Patch `(i, j)` interpolates its four corners and their
/// spline tangents, with zero twist (eq. 3, the paper's choice).
pub fn ferguson_surface(points: &[Vec<DVec3>], h: f64) -> Result<NurbsSurface> {
    let nu = points.len();
    let nv = points.first().map_or(0, Vec::len);
    // Tangents along u: down each column j; along v: along each row i.
    let mut du = vec![vec![DVec3::ZERO; nv]; nu];
    for j in 0..nv {
        let line: Vec<DVec3> = (0..nu).map(|i| points[i][j]).collect();
        for (i, t) in spline_tangents(&line, h).into_iter().enumerate() {
            du[i][j] = t;
        }
    }
    let dv: Vec<Vec<DVec3>> = points.iter().map(|row| spline_tangents(row, h)).collect();
    // Patch (i, j)'s Bézier net is its Hermite data: control point k along a
    // direction belongs to grid node k / 3 and stands a third of a step along that
    // node's tangent, forwards (k % 3 == 1) or back (k % 3 == 2). At a join between
    // patches the corner is the midpoint of the two points either side (the tangent is
    // the same both ways, the twist zero), so as a B-spline with double knots there it
    // drops out: the net keeps the ends and the points a third of a step off each node.
    let node = |k: usize| -> (usize, f64) {
        match k % 3 {
            0 => (k / 3, 0.0),
            1 => (k / 3, 1.0),
            _ => (k / 3 + 1, -1.0),
        }
    };
    let kept = |n: usize| -> Vec<usize> {
        let last = 3 * (n.max(1) - 1);
        (0..=last)
            .filter(|&k| k == 0 || k == last || k % 3 != 0)
            .collect()
    };
    let third = h / 3.0;
    let net: Vec<Vec<DVec3>> = kept(nu)
        .into_iter()
        .map(|k| {
            let (i, su) = node(k);
            kept(nv)
                .into_iter()
                .map(|l| {
                    let (j, sv) = node(l);
                    points[i][j] + su * third * du[i][j] + sv * third * dv[i][j]
                })
                .collect()
        })
        .collect();
    let knots = |n: usize| -> Vec<f64> {
        let cells = n.max(1) - 1;
        let mut k = vec![0.0; 4];
        for c in 1..cells {
            k.extend([c as f64 * h; 2]);
        }
        k.extend([cells as f64 * h; 4]);
        k
    };
    NurbsSurface::new(3, 3, knots(nu), knots(nv), net)
}
