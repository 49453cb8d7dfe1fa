//! The corner of the punch opening (paper 001 section 3.2, eq. 3, Fig. 5).

use std::f64::consts::FRAC_PI_2;

use dieface::die::corner::{build_corner, Corner, CornerInput};
use dieface::geom::arc::circular_arc;
use dieface::geom::{Curve2, Curve3, GeomError};
use glam::{DVec2, DVec3};

const RADIUS: f64 = 100.0;
const DELTA: f64 = 0.05;
const A: DVec3 = DVec3::new(0.0, -100.0, 10.0);
const B: DVec3 = DVec3::new(100.0, 0.0, 20.0);
const SAMPLES: usize = 200;

/// The quarter circle of radius 100 about the origin, from -90 to 0 degrees.
fn top_corner() -> Curve2 {
    circular_arc(DVec2::ZERO, DVec2::X, DVec2::Y, RADIUS, -FRAC_PI_2, 0.0).unwrap()
}

fn input(top: &Curve2, magnitudes: (f64, f64)) -> CornerInput<'_> {
    CornerInput {
        end_of_previous: A,
        tangent_in: DVec3::X,
        start_of_next: B,
        tangent_out: DVec3::Y,
        magnitudes,
        top_view_corner: top,
        punch_dir: DVec3::NEG_Z,
        delta: DELTA,
    }
}

/// Largest `| |(x, y)| - 100 |` over `SAMPLES + 1` evenly spaced parameters.
fn top_view_deviation(c: &Curve3) -> f64 {
    let (a, b) = c.domain();
    (0..=SAMPLES)
        .map(|k| {
            let p = c.point_at(a + (b - a) * k as f64 / SAMPLES as f64);
            (p.truncate().length() - RADIUS).abs()
        })
        .fold(0.0, f64::max)
}

fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.angle_between(b).to_degrees()
}

fn check(corner: &Corner, magnitudes: (f64, f64)) -> (f64, f64) {
    let c = &corner.curve;
    assert_eq!(c.domain(), (0.0, 1.0));
    assert!(c.start_point().distance(A) <= 1e-9);
    assert!(c.end_point().distance(B) <= 1e-9);
    let (d0, d1) = (c.derivative_at(0.0), c.derivative_at(1.0));
    assert!(angle_deg(d0, DVec3::X) <= 0.01, "start tangent {d0}");
    assert!(angle_deg(d1, DVec3::Y) <= 0.01, "end tangent {d1}");
    assert!((d0.length() - magnitudes.0).abs() <= 1e-9 * magnitudes.0);
    assert!((d1.length() - magnitudes.1).abs() <= 1e-9 * magnitudes.1);
    // The corrected points lie on the swept circle.
    for x in &corner.corrected_points {
        assert!((x.truncate().length() - RADIUS).abs() <= 1e-6, "{x}");
    }
    // C0 has the same end conditions (on its own [0, 1] parameter).
    let c0 = &corner.initial;
    assert!(c0.start_point().distance(A) <= 1e-12);
    assert!(c0.end_point().distance(B) <= 1e-12);
    assert!(c0.derivative_at(0.0).distance(DVec3::X * magnitudes.0) <= 1e-9);
    assert!(c0.derivative_at(1.0).distance(DVec3::Y * magnitudes.1) <= 1e-9);
    (top_view_deviation(c0), top_view_deviation(c))
}

#[test]
fn corrected_corner_follows_the_top_view() {
    let top = top_corner();
    for magnitudes in [(120.0, 120.0), (160.0, 200.0), (250.0, 180.0)] {
        let corner = build_corner(&input(&top, magnitudes)).unwrap();
        let (dev0, dev_f) = check(&corner, magnitudes);
        eprintln!(
            "magnitudes {magnitudes:?}: {} corrected points, top-view deviation C0 {dev0:.4} mm, C_F {dev_f:.2e} mm",
            corner.corrected_points.len()
        );
        assert!(dev_f <= DELTA, "C_F deviates {dev_f} mm");
        assert!(
            dev0 >= 20.0 * dev_f && dev0 > 1.0,
            "C0 deviates only {dev0} mm"
        );
        // z still climbs monotonically from 10 to 20 (the correction moves points
        // across the punch direction only).
        let mut z = f64::NEG_INFINITY;
        for k in 0..=SAMPLES {
            let p = corner.curve.point_at(k as f64 / SAMPLES as f64);
            assert!(p.z >= z - 1e-9 && (10.0 - 1e-9..=20.0 + 1e-9).contains(&p.z));
            z = p.z;
        }
    }
}

#[test]
fn zero_magnitude_is_rejected() {
    let top = top_corner();
    for magnitudes in [(0.0, 100.0), (100.0, -1.0)] {
        let err = build_corner(&input(&top, magnitudes)).unwrap_err();
        assert!(
            matches!(
                err,
                GeomError::NotPositive {
                    what: "corner tangent magnitude",
                    ..
                }
            ),
            "{err:?}"
        );
    }
}

#[test]
fn zero_tangent_is_rejected() {
    let top = top_corner();
    let mut bad = input(&top, (150.0, 150.0));
    bad.tangent_in = DVec3::ZERO;
    assert!(matches!(
        build_corner(&bad).unwrap_err(),
        GeomError::ZeroVector { .. }
    ));
}

/// Side ends 1 mm off the drawn corner: the paper's `C_R` construction sets the
/// projection directions; the interior points still land on the circle and the corner
/// still joins the given side ends.
#[test]
fn side_ends_off_the_top_view_use_the_paper_directions() {
    let top = top_corner();
    let mut off = input(&top, (150.0, 150.0));
    off.end_of_previous = DVec3::new(0.0, -101.0, 10.0);
    off.start_of_next = DVec3::new(101.0, 0.0, 20.0);
    let corner = build_corner(&off).unwrap();
    let xs = &corner.corrected_points;
    assert!(corner.curve.start_point().distance(off.end_of_previous) <= 1e-9);
    assert!(corner.curve.end_point().distance(off.start_of_next) <= 1e-9);
    for x in &xs[1..xs.len() - 1] {
        assert!((x.truncate().length() - RADIUS).abs() <= 1e-6, "{x}");
    }
}
