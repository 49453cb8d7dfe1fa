//! The hand-checkable square opening shared by `tests/punch_opening.rs` and
//! `tests/blankholder.rs`: 400 x 400 mm, R 50 fillets, flat side views.

#![allow(dead_code)] // each test file uses its own subset

use std::f64::consts::FRAC_PI_2;

use dieface::die::punch_opening::{
    CornerSpec, Magnitude, PieceSpec, PunchOpeningSpec, SideSpec, SideView,
};
use dieface::geom::arc::circular_arc;
use dieface::geom::Curve2;
use glam::DVec2;

pub const DELTA: f64 = 0.01;
/// Half the side of the square opening (400 x 400 mm) and its fillet radius.
pub const HALF: f64 = 200.0;
pub const RADIUS: f64 = 50.0;
/// Where the fillets' centres are, on each axis.
pub const INSET: f64 = HALF - RADIUS;

pub fn line2(a: (f64, f64), b: (f64, f64)) -> Curve2 {
    Curve2::line(DVec2::new(a.0, a.1), DVec2::new(b.0, b.1)).unwrap()
}

pub fn flat_view(axis: DVec2, z: f64) -> SideView {
    SideView {
        origin: DVec2::ZERO,
        axis,
        curve: line2((-HALF - 50.0, z), (HALF + 50.0, z)),
    }
}

pub fn side(name: &str, top: Curve2, view: SideView) -> PieceSpec {
    PieceSpec::Side(SideSpec {
        name: name.into(),
        top,
        view,
    })
}

pub fn corner(name: &str, center: DVec2, from_deg: f64) -> PieceSpec {
    let a = from_deg.to_radians();
    PieceSpec::Corner(CornerSpec {
        name: name.into(),
        top: circular_arc(center, DVec2::X, DVec2::Y, RADIUS, a, a + FRAC_PI_2).unwrap(),
        magnitudes: [Magnitude::Natural(1.0); 2],
    })
}

/// The 400 x 400 square with R 50 fillets, counter-clockwise from the bottom side(s),
/// flat side views at z = 0 elsewhere.
pub fn square_with_bottom(bottom: Vec<PieceSpec>) -> PunchOpeningSpec {
    let (h, s) = (HALF, INSET);
    let mut pieces = bottom;
    pieces.extend([
        corner("bottom_right", DVec2::new(s, -s), -90.0),
        side("right", line2((h, -s), (h, s)), flat_view(DVec2::Y, 0.0)),
        corner("right_top", DVec2::new(s, s), 0.0),
        side("top", line2((s, h), (-s, h)), flat_view(DVec2::X, 0.0)),
        corner("top_left", DVec2::new(-s, s), 90.0),
        side("left", line2((-h, s), (-h, -s)), flat_view(DVec2::Y, 0.0)),
        corner("left_bottom", DVec2::new(-s, -s), 180.0),
    ]);
    PunchOpeningSpec {
        pieces,
        delta: DELTA,
        max_step: None,
    }
}

pub fn square() -> PunchOpeningSpec {
    square_with_bottom(vec![side(
        "bottom",
        line2((-INSET, -HALF), (INSET, -HALF)),
        flat_view(DVec2::X, 0.0),
    )])
}
