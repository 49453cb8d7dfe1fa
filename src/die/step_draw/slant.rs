//! How slanted a section plane cuts the step draw's walls, and the walls' direction at
//! the punch opening that the slant is measured against.
//!
//! A section plane is vertical through its product point and its matched opening point.
//! It leaves the product square ([`super::matching`]) but may meet the opening at a
//! slant, and a slanted cut through a wall widens it: the section is stretched back by
//! the slant so the walls keep their drawn radii and draft ([`super::Stations`]).
//!
//! The punch opening line is drawn from lines and arcs, whose curvature jumps where they
//! meet. Its bare tangent would carry each jump into the slant as a kink along the
//! outline, and a kink in the sections' widths is a ripple along the wall: on the
//! fender it tightened an 8 mm die radius to 7.1 mm between two sections half a
//! millimetre apart. So the opening's direction is its tangent averaged over a short
//! arc ([`OPENING_WINDOW`] either side), which turns smoothly through every such joint.

use glam::{DVec2, DVec3};

use crate::geom::curve::ArcLengths;
use crate::geom::{Curve3, GeomError};

/// Half the arc of punch opening line (mm) over which its direction is averaged for a
/// section's slant: short beside the opening's corner radii (tens of mm), long beside
/// the sections' spacing where a corner's fan crowds them (under 1 mm).
pub const OPENING_WINDOW: f64 = 6.0;

/// The punch opening line's direction for measuring slants: the chord between the
/// points [`OPENING_WINDOW`] before and after a point, along the line's arc length
/// (wrapping round a closed line, so it does not depend on where the line starts;
/// shortened at an open line's ends).
pub struct OpeningDirection<'a> {
    lengths: ArcLengths<'a, DVec3>,
    closed: bool,
}

impl<'a> OpeningDirection<'a> {
    /// The directions along `opening` (the whole line), `closed` when it closes.
    pub fn new(opening: &'a Curve3, closed: bool) -> Self {
        Self {
            lengths: ArcLengths::new(opening),
            closed,
        }
    }

    /// The averaged direction at parameter `t` of the whole line (not unit).
    pub fn at(&self, t: f64) -> Result<DVec3, GeomError> {
        let curve = self.lengths.curve();
        let total = self.lengths.total();
        let s = self.lengths.length_at(t);
        let point_at_length = |l: f64| -> Result<DVec3, GeomError> {
            let l = if self.closed {
                l.rem_euclid(total)
            } else {
                l.clamp(0.0, total)
            };
            Ok(curve.point_at(self.lengths.parameter_at(l)?))
        };
        let window = OPENING_WINDOW.min(0.25 * total);
        let chord = point_at_length(s + window)? - point_at_length(s - window)?;
        if chord.truncate().length() <= 1e-9 {
            // A line shorter than its window, or one that doubles back within it: the
            // bare tangent is all there is.
            return Ok(curve.derivative_at(t));
        }
        Ok(chord)
    }
}

/// How square a section plane along `h` (horizontal, unit) cuts the walls at its
/// product end and at its opening end: the cosine of its angle to each guide's normal
/// in the top view (from their directions), at least 0.5.
pub fn obliquity(h: DVec3, (opening, product): (DVec3, DVec3)) -> (f64, f64) {
    let square = |t: DVec3| {
        let t = t.truncate().normalize_or_zero();
        if t == DVec2::ZERO {
            1.0
        } else {
            h.truncate().perp_dot(t).abs()
        }
    };
    (
        square(product).clamp(0.5, 1.0),
        square(opening).clamp(0.5, 1.0),
    )
}

/// `(b - a) / ln(b / a)`, or `a` when they are equal: the width a section takes when
/// its slant goes linearly from `a` to `b` across it.
pub fn log_mean(a: f64, b: f64) -> f64 {
    if (b - a).abs() <= 1e-9 * a {
        a
    } else {
        (b - a) / (b / a).ln()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::arc::arc_through_points;
    use crate::geom::join::join_curves;

    /// The rounded square's corner radius (mm).
    const CORNER: f64 = 10.0;

    /// A closed rounded square (side 100, corner radius 10) of exact lines and arcs,
    /// starting at the corner `start_corner` (counter-clockwise from +x +y).
    fn rounded_square(start_corner: usize) -> Curve3 {
        let r = CORNER;
        let mut pieces = Vec::new();
        for i in 0..4 {
            let k = (i + start_corner) % 4;
            let a0 = k as f64 * std::f64::consts::FRAC_PI_2;
            let c = 40.0 * DVec2::new(a0.cos() - a0.sin(), a0.sin() + a0.cos());
            let at = |a: f64| (c + r * DVec2::new(a.cos(), a.sin())).extend(0.0);
            let q = std::f64::consts::FRAC_PI_2;
            pieces.push(arc_through_points(at(a0), at(a0 + 0.5 * q), at(a0 + q)).unwrap());
            let next = (k + 1) % 4;
            let b0 = next as f64 * q;
            let cn = 40.0 * DVec2::new(b0.cos() - b0.sin(), b0.sin() + b0.cos());
            pieces.push(
                Curve3::line(
                    at(a0 + q),
                    (cn + r * DVec2::new(b0.cos(), b0.sin())).extend(0.0),
                )
                .unwrap(),
            );
        }
        join_curves(&pieces).unwrap()
    }

    #[test]
    fn the_direction_does_not_depend_on_where_a_closed_line_starts() {
        let a = rounded_square(0);
        let b = rounded_square(2);
        let (da, db) = (
            OpeningDirection::new(&a, true),
            OpeningDirection::new(&b, true),
        );
        for i in 0..40 {
            let t = a.domain().0 + (a.domain().1 - a.domain().0) * i as f64 / 40.0;
            let p = a.point_at(t);
            let tb = crate::geom::inversion::closest_point_on_curve(&b, p)
                .expect("a point of the same square")
                .t;
            let (u, v) = (
                da.at(t).unwrap().normalize(),
                db.at(tb).unwrap().normalize(),
            );
            assert!(u.distance(v) < 1e-3, "at {p}: {u} against {v}");
        }
    }

    #[test]
    fn the_direction_is_the_tangent_on_a_straight_stretch() {
        let c = rounded_square(0);
        let d = OpeningDirection::new(&c, true);
        // The middle of the right-hand side, x = 50, is straight for 40 mm.
        let t = crate::geom::inversion::closest_point_on_curve(&c, DVec3::new(50.0, 0.0, 0.0))
            .unwrap()
            .t;
        let dir = d.at(t).unwrap().normalize();
        let tangent = c.derivative_at(t).normalize();
        assert!(dir.distance(tangent) < 1e-3, "{dir} against {tangent}");
    }

    #[test]
    fn the_direction_turns_smoothly_through_a_curvature_jump() {
        // Where a straight side meets a corner arc the tangent's turning rate jumps
        // from 0 to 1/r; the averaged direction's turning rate does not jump.
        let c = rounded_square(0);
        let d = OpeningDirection::new(&c, true);
        let lengths = ArcLengths::new(&c);
        let joint = lengths.length_at(
            crate::geom::inversion::closest_point_on_curve(&c, DVec3::new(40.0, 50.0, 0.0))
                .unwrap()
                .t,
        );
        let angle_at = |s: f64| {
            let v = d.at(lengths.parameter_at(s).unwrap()).unwrap();
            v.y.atan2(v.x)
        };
        let h = 0.25;
        let rate = |s: f64| (angle_at(s + h) - angle_at(s - h)) / (2.0 * h);
        let (before, after) = (rate(joint - 0.5), rate(joint + 0.5));
        assert!(
            (after - before).abs() < 0.2 / CORNER,
            "turning rate {before} before the joint, {after} after"
        );
    }
}
