//! Joining consecutive curves into one.
//!
//! A sketch is drawn as lines, arcs and splines, one after the other; features want
//! one curve. [`join_curves`] concatenates the pieces exactly: every piece is raised to
//! the highest degree, made rational if any piece is, reparametrized to its own unit
//! interval and glued with a knot of multiplicity `degree` (a C0 joint, so corners stay
//! corners and tangent joints stay tangent in shape).

use super::curve::NurbsCurve;
use super::error::{GeomError, Result};
use super::point::Point;

/// The curve made of `pieces` one after the other.
///
/// Piece `i` runs over the parameter range `[i, i + 1]` of the result (whatever its own
/// domain), so the piece a parameter falls in is `floor(t)`; the piece's own parameter
/// `s` in `[a, b]` becomes `i + (s - a) / (b - a)`. (Uniform ranges rather than ranges
/// proportional to length keep segment lookup trivial; the shape is the same.)
///
/// Each piece must start where the previous one ends, within `1e-9` of the size of the
/// whole (the largest control-point coordinate, at least 1); otherwise the result is
/// [`GeomError::CornersDoNotMeet`] with `corner: i` for the joint before piece `i`. The
/// shared point is stored once (the previous piece's end point).
///
/// Rational pieces keep their shape: a piece's weights are scaled by one constant (which
/// leaves a NURBS curve unchanged) so that the weight of the shared point agrees on both
/// sides of every joint. A single piece comes back reparametrized to `[0, 1]`.
pub fn join_curves<P: Point>(pieces: &[NurbsCurve<P>]) -> Result<NurbsCurve<P>> {
    if pieces.is_empty() {
        return Err(GeomError::TooFewPoints {
            needed: 1,
            given: 0,
        });
    }
    let size = pieces
        .iter()
        .flat_map(|c| c.control_points().iter())
        .flat_map(|p| (0..P::DIM).map(move |i| p.coord(i).abs()))
        .fold(1.0, f64::max);
    if !size.is_finite() {
        return Err(GeomError::NotFinite {
            what: "control point",
        });
    }
    for (i, w) in pieces.windows(2).enumerate() {
        let gap = w[0].end_point().distance(w[1].start_point());
        if gap.is_nan() || gap > 1e-9 * size {
            return Err(GeomError::CornersDoNotMeet { corner: i + 1, gap });
        }
    }

    let degree = pieces.iter().map(NurbsCurve::degree).max().unwrap_or(1);
    let rational = pieces.iter().any(NurbsCurve::is_rational);

    let mut knots: Vec<f64> = vec![0.0; degree + 1];
    let mut points: Vec<P> = Vec::new();
    let mut weights: Vec<f64> = Vec::new();
    for (i, piece) in pieces.iter().enumerate() {
        let piece = piece.elevate_degree(degree - piece.degree())?;
        let (a, b) = piece.domain();
        let offset = i as f64;
        let k = piece.knots().as_slice();
        let interior = &k[degree + 1..k.len() - degree - 1];
        knots.extend(interior.iter().map(|&t| offset + (t - a) / (b - a)));
        let end = offset + 1.0;
        let repeat = if i + 1 == pieces.len() {
            degree + 1
        } else {
            degree
        };
        knots.extend(std::iter::repeat_n(end, repeat));

        // Scale this piece's weights so that its first weight equals the weight the
        // previous piece gave the shared point.
        let scale = match weights.last() {
            Some(&w_prev) => w_prev / piece.weight(0),
            None => 1.0,
        };
        let skip = usize::from(i > 0);
        for (j, &p) in piece.control_points().iter().enumerate().skip(skip) {
            points.push(p);
            weights.push(piece.weight(j) * scale);
        }
    }
    if rational {
        NurbsCurve::new_rational(degree, knots, points, weights)
    } else {
        NurbsCurve::new(degree, knots, points)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::arc::{arc_through_points, circular_arc};
    use glam::DVec2;

    fn check_pieces(joined: &NurbsCurve<DVec2>, pieces: &[NurbsCurve<DVec2>]) {
        for (i, piece) in pieces.iter().enumerate() {
            let (a, b) = piece.domain();
            for k in 0..=50 {
                let f = k as f64 / 50.0;
                let expected = piece.point_at(a + f * (b - a));
                let got = joined.point_at(i as f64 + f);
                assert!(
                    got.distance(expected) < 1e-12,
                    "piece {i} at {f}: {got} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn lines_and_arcs_join_exactly() {
        let l1 = NurbsCurve::line(DVec2::ZERO, DVec2::new(10.0, 0.0)).unwrap();
        let arc = arc_through_points(
            DVec2::new(10.0, 0.0),
            DVec2::new(13.0, 2.0),
            DVec2::new(10.0, 10.0),
        )
        .unwrap();
        let l2 = NurbsCurve::line(DVec2::new(10.0, 10.0), DVec2::new(0.0, 10.0)).unwrap();
        // A rational arc whose end weights are not 1 (scaled on purpose).
        let c = circular_arc(DVec2::new(0.0, 5.0), DVec2::Y, DVec2::NEG_X, 5.0, 0.0, 2.0).unwrap();
        let w: Vec<f64> = c.weights().unwrap().iter().map(|w| w * 3.0).collect();
        let c = NurbsCurve::new_rational(
            2,
            c.knots().as_slice().to_vec(),
            c.control_points().to_vec(),
            w,
        )
        .unwrap();
        let c = c.reparametrized(2.0, 7.0).unwrap();
        let pieces = vec![l1, arc, l2, c];
        // The last piece must start where l2 ends.
        assert!(pieces[3].start_point().distance(DVec2::new(0.0, 10.0)) < 1e-12);
        let joined = join_curves(&pieces).unwrap();
        assert_eq!(joined.degree(), 2);
        assert_eq!(joined.domain(), (0.0, 4.0));
        check_pieces(&joined, &pieces);
    }

    #[test]
    fn gap_is_reported() {
        let l1 = NurbsCurve::line(DVec2::ZERO, DVec2::new(10.0, 0.0)).unwrap();
        let l2 = NurbsCurve::line(DVec2::new(10.0, 1.0), DVec2::new(0.0, 10.0)).unwrap();
        let err = join_curves(&[l1, l2]).unwrap_err();
        assert_eq!(
            err,
            GeomError::CornersDoNotMeet {
                corner: 1,
                gap: 1.0
            }
        );
    }

    #[test]
    fn single_piece_is_reparametrized() {
        let l = NurbsCurve::line(DVec2::ZERO, DVec2::new(4.0, 0.0))
            .unwrap()
            .reparametrized(3.0, 5.0)
            .unwrap();
        let j = join_curves(std::slice::from_ref(&l)).unwrap();
        assert_eq!(j.domain(), (0.0, 1.0));
        check_pieces(&j, &[l]);
    }
}
