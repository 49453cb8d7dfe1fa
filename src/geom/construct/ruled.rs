//! Ruled surfaces.

use glam::DVec3;

use crate::geom::compat::make_compatible;
use crate::geom::curve::Curve3;
use crate::geom::error::Result;
use crate::geom::surface::NurbsSurface;

/// The ruled surface between `first` (v = 0) and `second` (v = 1): for every u the
/// iso-curve in v is the straight segment from `first(u)` to `second(u)`. The curves
/// are made compatible first (common degree, knots, domain [0, 1]), so u runs along the
/// curves' normalized parameter; the surface is degree 1 in v.
pub fn ruled(first: &Curve3, second: &Curve3) -> Result<NurbsSurface> {
    let pair = make_compatible(&[first.clone(), second.clone()])?;
    let (a, b) = (&pair[0], &pair[1]);
    let rational = a.is_rational() || b.is_rational();
    let n = a.control_points().len();
    let mut points = Vec::with_capacity(2 * n);
    let mut weights = Vec::with_capacity(2 * n);
    for i in 0..n {
        points.extend([a.control_points()[i], b.control_points()[i]]);
        weights.extend([a.weight(i), b.weight(i)]);
    }
    Ok(NurbsSurface::from_parts(
        (a.degree(), 1),
        (a.knots().as_slice().to_vec(), vec![0.0, 0.0, 1.0, 1.0]),
        (n, 2),
        points,
        rational.then_some(weights),
    ))
}

/// The bilinear patch through four corners `p[a][b]` (`a` = u end, `b` = v end).
pub(crate) fn bilinear(p: [[DVec3; 2]; 2]) -> NurbsSurface {
    NurbsSurface::from_parts(
        (1, 1),
        (vec![0.0, 0.0, 1.0, 1.0], vec![0.0, 0.0, 1.0, 1.0]),
        (2, 2),
        vec![p[0][0], p[0][1], p[1][0], p[1][1]],
        None,
    )
}
