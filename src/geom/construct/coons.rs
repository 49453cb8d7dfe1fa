//! Bilinearly blended Coons patches (P&T section 10.5).

use glam::DVec3;

use super::ruled::{bilinear, ruled};
use crate::geom::compat::make_surfaces_compatible;
use crate::geom::curve::Curve3;
use crate::geom::error::{GeomError, Result};
use crate::geom::surface::NurbsSurface;

/// The Coons patch bounded by four curves:
/// `S(u, 0) = bottom(u)`, `S(u, 1) = top(u)`, `S(0, v) = left(v)`, `S(1, v) = right(v)`,
/// each curve's domain mapped to [0, 1]. The corners must meet (within 1e-9 of the
/// curves' size): bottom starts where left starts, and so on.
///
/// `S = R_bottom-top + R_left-right - B`, two ruled surfaces minus the bilinear patch
/// of the corners, summed on compatible control nets; the result is exact for
/// polynomial boundaries, which is what this accepts.
pub fn coons(bottom: &Curve3, top: &Curve3, left: &Curve3, right: &Curve3) -> Result<NurbsSurface> {
    let curves = [bottom, top, left, right];
    if curves.iter().any(|c| c.is_rational()) {
        return Err(GeomError::RationalNotSupported {
            what: "a Coons patch",
        });
    }
    let scale = curves.iter().map(|c| c.control_scale()).fold(1.0, f64::max);
    let corners = [
        (bottom.start_point(), left.start_point()),
        (bottom.end_point(), right.start_point()),
        (top.end_point(), right.end_point()),
        (top.start_point(), left.end_point()),
    ];
    for (corner, (a, b)) in corners.iter().enumerate() {
        let gap = a.distance(*b);
        if gap > 1e-9 * scale {
            return Err(GeomError::CornersDoNotMeet { corner, gap });
        }
    }
    let along_u = ruled(bottom, top)?;
    let along_v = ruled(left, right)?.transposed();
    let corners = bilinear([
        [bottom.start_point(), top.start_point()],
        [bottom.end_point(), top.end_point()],
    ]);
    let parts = make_surfaces_compatible(&[along_u, along_v, corners])?;
    let points: Vec<DVec3> = (0..parts[0].control_points().len())
        .map(|k| {
            parts[0].control_points()[k] + parts[1].control_points()[k]
                - parts[2].control_points()[k]
        })
        .collect();
    Ok(NurbsSurface::from_parts(
        (parts[0].degree_u(), parts[0].degree_v()),
        (
            parts[0].knots_u().as_slice().to_vec(),
            parts[0].knots_v().as_slice().to_vec(),
        ),
        parts[0].counts(),
        points,
        None,
    ))
}

/// The three-sided Coons patch bounded by the closed loop `a` (from P0 to P1), `b` (P1 to
/// P2), `c` (P2 back to P0): a four-sided patch whose fourth side collapses to P2.
/// `S(u, 0) = a(u)`, `S(1, v) = b(v)`, `S(0, v) = c(1 - v)`, `S(u, 1) = P2`. The normal
/// is undefined at P2, as on every degenerate patch.
pub fn coons_triangle(a: &Curve3, b: &Curve3, c: &Curve3) -> Result<NurbsSurface> {
    let apex = b.end_point();
    let top = Curve3::line(apex, apex)?;
    coons(a, &top, &c.reversed(), b)
}
