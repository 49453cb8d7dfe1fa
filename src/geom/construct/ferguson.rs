//! The bicubic Ferguson (Hermite) patch.

use glam::DVec3;

use crate::geom::error::{GeomError, Result};
use crate::geom::knots::KnotVector;
use crate::geom::surface::NurbsSurface;

/// Corner data of a Ferguson patch, each indexed `[a][b]` with `a` the u end (0 or 1)
/// and `b` the v end: positions, the derivatives `S_u` and `S_v`, and the twists
/// `S_uv` (zero twists give the classic Ferguson patch).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HermiteCorners {
    /// `S(a, b)`.
    pub points: [[DVec3; 2]; 2],
    /// `S_u(a, b)`.
    pub du: [[DVec3; 2]; 2],
    /// `S_v(a, b)`.
    pub dv: [[DVec3; 2]; 2],
    /// `S_uv(a, b)`.
    pub twist: [[DVec3; 2]; 2],
}

/// The bicubic patch on [0, 1]^2 with the given corner positions, derivatives and
/// twists, as a Bezier (single-span B-spline) surface: the Hermite data converts to the
/// Bezier net by `b_10 = P + S_u / 3`, `b_11 = P + (S_u + S_v) / 3 + S_uv / 9` and their
/// mirror images at the other corners.
pub fn ferguson(c: &HermiteCorners) -> Result<NurbsSurface> {
    let all = [c.points, c.du, c.dv, c.twist];
    if all.iter().flatten().flatten().any(|v| !v.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "Ferguson corner data",
        });
    }
    let mut net = vec![vec![DVec3::ZERO; 4]; 4];
    for a in 0..2 {
        for b in 0..2 {
            // Signs: moving inwards from the u = 1 end runs against S_u, and likewise in v.
            let su = if a == 0 { 1.0 } else { -1.0 };
            let sv = if b == 0 { 1.0 } else { -1.0 };
            let (i0, i1) = if a == 0 { (0, 1) } else { (3, 2) };
            let (j0, j1) = if b == 0 { (0, 1) } else { (3, 2) };
            let p = c.points[a][b];
            net[i0][j0] = p;
            net[i1][j0] = p + c.du[a][b] * (su / 3.0);
            net[i0][j1] = p + c.dv[a][b] * (sv / 3.0);
            net[i1][j1] = p
                + c.du[a][b] * (su / 3.0)
                + c.dv[a][b] * (sv / 3.0)
                + c.twist[a][b] * (su * sv / 9.0);
        }
    }
    let bezier = KnotVector::bezier(3).into_vec();
    NurbsSurface::new(3, 3, bezier.clone(), bezier, net)
}
