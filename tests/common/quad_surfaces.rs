//! Surfaces with trim loops for the quad mesher's tests and bench (issue 18): a
//! door-inner-like panel on a Coons patch, a dished vessel end with nozzles, and a half
//! cylinder tight enough that the chordal tolerance decides the element size.

#![allow(dead_code)]

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use dieface::geom::arc::circular_arc;
use dieface::geom::construct::{coons, revolve};
use dieface::geom::interpolate::{interpolate, Interpolation};
use dieface::geom::mesh::quad::surface::SurfaceRegion;
use dieface::geom::{Curve3, NurbsSurface};
use glam::{DVec2, DVec3};

#[path = "quad_shapes.rs"]
pub mod shapes;

fn through(points: &[DVec3]) -> Curve3 {
    interpolate(points, &Interpolation::default()).expect("distinct points")
}

/// A door inner's base surface: a Coons patch over 900 x 700 mm, its edges bowed up to
/// 40 mm and the far edge 60 mm higher.
pub fn door_surface() -> NurbsSurface {
    let edge = |y: f64, lift: f64| {
        through(
            &(0..=6)
                .map(|k| {
                    let x = 150.0 * k as f64;
                    DVec3::new(x, y, lift + 40.0 * (PI * x / 900.0).sin())
                })
                .collect::<Vec<_>>(),
        )
    };
    let side = |x: f64| {
        through(
            &(0..=6)
                .map(|k| {
                    let y = 700.0 * k as f64 / 6.0;
                    DVec3::new(x, y, 60.0 * y / 700.0 + 25.0 * (PI * y / 700.0).sin())
                })
                .collect::<Vec<_>>(),
        )
    };
    coons(
        &edge(0.0, 0.0),
        &edge(700.0, 60.0),
        &side(0.0),
        &side(900.0),
    )
    .expect("corners meet")
}

/// The plane door inner's 19 loops (`quad_shapes::door_inner`) drawn on the door
/// surface: each plane point `(x, y)` placed at `S(x / 900, y / 700)`.
pub fn door_inner_on_surface() -> (NurbsSurface, SurfaceRegion) {
    let surface = door_surface();
    let plane = shapes::door_inner();
    let on = |l: &[DVec2]| -> Vec<DVec3> {
        l.iter()
            .map(|p| surface.point_at(p.x / 900.0, p.y / 700.0))
            .collect()
    };
    let region = SurfaceRegion {
        outer: Some(on(&plane.outer)),
        holes: plane.holes.iter().map(|h| on(h)).collect(),
    };
    (surface, region)
}

/// The crown of a dished vessel end: a sphere of 500 mm radius, its top at z = 0.
const CROWN: f64 = 500.0;

/// A point of the crown seen at `(x, y)` from above.
pub fn on_crown(x: f64, y: f64) -> DVec3 {
    DVec3::new(x, y, (CROWN * CROWN - x * x - y * y).sqrt() - CROWN)
}

/// A dished vessel end: the spherical crown revolved a full turn about z out to a rim of
/// 340 mm radius, trimmed at 330 mm, with a central nozzle of 45 mm radius and four
/// nozzles of 30 mm radius at 200 mm from the axis (trim circles on the crown).
pub fn vessel_end() -> (NurbsSurface, SurfaceRegion) {
    let rim = (340.0f64 / CROWN).asin();
    // The profile in the xz plane, from the apex down to the rim.
    let profile = circular_arc(
        DVec3::new(0.0, 0.0, -CROWN),
        DVec3::X,
        DVec3::Z,
        CROWN,
        FRAC_PI_2 - rim,
        FRAC_PI_2,
    )
    .expect("an arc")
    .reversed();
    let surface = revolve(&profile, DVec3::ZERO, DVec3::Z, TAU).expect("a revolution");
    let ring = |c: DVec2, r: f64, n: usize| -> Vec<DVec3> {
        shapes::circle(c, r, n)
            .into_iter()
            .map(|p| on_crown(p.x, p.y))
            .collect()
    };
    let mut holes = vec![ring(DVec2::ZERO, 45.0, 48)];
    for k in 0..4 {
        let a = FRAC_PI_2 * k as f64 + 0.4;
        holes.push(ring(200.0 * DVec2::new(a.cos(), a.sin()), 30.0, 40));
    }
    let region = SurfaceRegion {
        outer: Some(ring(DVec2::ZERO, 330.0, 180)),
        holes,
    };
    (surface, region)
}

/// Half a cylinder of 50 mm radius and 200 mm long about the y axis.
pub fn half_cylinder() -> NurbsSurface {
    let line = through(&[
        DVec3::new(50.0, 0.0, 0.0),
        DVec3::new(50.0, 66.0, 0.0),
        DVec3::new(50.0, 133.0, 0.0),
        DVec3::new(50.0, 200.0, 0.0),
    ]);
    revolve(&line, DVec3::ZERO, DVec3::Y, PI).expect("a revolution")
}
