//! Principal curvatures and the smallest radius of a patch, on surfaces whose curvature
//! is known in closed form (a torus and a cylinder, both exact rational surfaces).

use std::f64::consts::{FRAC_PI_2, TAU};

use dieface::geom::arc::circular_arc;
use dieface::geom::construct::revolve;
use dieface::geom::curvature::{min_radius, principal_curvatures};
use dieface::geom::Curve3;
use glam::DVec3;

/// A torus of tube radius `r` at distance `big` from the Z axis.
fn torus(big: f64, r: f64) -> dieface::geom::NurbsSurface {
    let tube = circular_arc(DVec3::new(big, 0.0, 0.0), DVec3::X, DVec3::Z, r, 0.0, TAU)
        .expect("a valid circle");
    revolve(&tube, DVec3::ZERO, DVec3::Z, TAU).expect("a valid revolution")
}

#[test]
fn torus_principal_curvatures_match_the_closed_form() {
    let (big, r) = (50.0, 8.0);
    let s = torus(big, r);
    for &u in &[0.0, 0.13, 0.5, 0.77] {
        for &v in &[0.0, 0.21, 0.4, 0.66, 0.9] {
            let p = s.point_at(u, v);
            let dist = (p.x * p.x + p.y * p.y).sqrt();
            // At angle phi round the tube, the curvatures are 1/r (round the tube) and
            // cos(phi) / (big + r cos(phi)) (round the axis).
            let cos_phi = (dist - big) / r;
            let ring = cos_phi / (big + r * cos_phi);
            let k = principal_curvatures(&s, u, v).expect("a regular point");
            let mut got = [k.k1.abs(), k.k2.abs()];
            got.sort_by(f64::total_cmp);
            let mut want = [1.0 / r, ring.abs()];
            want.sort_by(f64::total_cmp);
            assert!((got[0] - want[0]).abs() < 1e-9, "{got:?} vs {want:?}");
            assert!((got[1] - want[1]).abs() < 1e-9, "{got:?} vs {want:?}");
        }
    }
}

#[test]
fn min_radius_of_a_torus_is_its_tube_radius_and_a_plane_has_none() {
    let s = torus(50.0, 8.0);
    let m = min_radius(&s, 4);
    assert!((m.radius - 8.0).abs() < 1e-9, "{m:?}");

    // A radial line turned about Z sweeps a flat sector; along the axis, a cylinder.
    let radial =
        Curve3::line(DVec3::new(2.0, 0.0, 0.0), DVec3::new(10.0, 0.0, 0.0)).expect("a line");
    let plane = revolve(&radial, DVec3::ZERO, DVec3::Z, FRAC_PI_2).expect("a flat sector");
    let flat = min_radius(&plane, 4);
    assert!(
        flat.radius > 1e9,
        "a flat sector has no finite radius: {flat:?}"
    );
    let axial =
        Curve3::line(DVec3::new(6.0, 0.0, 0.0), DVec3::new(6.0, 0.0, 30.0)).expect("a line");
    let cylinder = revolve(&axial, DVec3::ZERO, DVec3::Z, FRAC_PI_2).expect("a cylinder");
    let c = min_radius(&cylinder, 4);
    assert!((c.radius - 6.0).abs() < 1e-9, "{c:?}");
}

/// A profile that tightens towards its end and runs on straight from there (a cubic
/// with a triple knot, C1 by its collinear control points, as a step-draw section turns
/// from a corner into a run), swept straight along Y: the tightest radius is the
/// left-hand limit at the knot, which evaluating at the knot itself (the run's side)
/// never reads.
#[test]
fn min_radius_reads_the_tight_side_of_a_knot_where_curvature_jumps() {
    use dieface::geom::construct::ruled;
    let p = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(10.0, 0.0, 0.0),
        DVec3::new(16.0, 0.0, 1.0),
        DVec3::new(19.0, 0.0, 4.0),
    ];
    let step = p[3] - p[2];
    let mut points = p.to_vec();
    points.extend((1..=3).map(|k| p[3] + k as f64 * step));
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0];
    let profile = Curve3::new(3, knots, points).expect("a valid cubic");
    let swept = profile.map_points(|q| q + DVec3::new(0.0, 50.0, 0.0));
    let s = ruled(&profile, &swept).expect("a valid sweep");

    // The Bezier piece's curvature from its control points, at its end and inside.
    let curvature = |t: f64| {
        let d1 = 3.0
            * ((1.0 - t) * (1.0 - t) * (p[1] - p[0])
                + 2.0 * t * (1.0 - t) * (p[2] - p[1])
                + t * t * (p[3] - p[2]));
        let d2 = 6.0 * ((1.0 - t) * (p[2] - 2.0 * p[1] + p[0]) + t * (p[3] - 2.0 * p[2] + p[1]));
        d1.cross(d2).length() / d1.length().powi(3)
    };
    let at_end = curvature(1.0);
    for k in 0..100 {
        let t = k as f64 / 100.0;
        assert!(curvature(t) < at_end, "the piece is tightest at its end");
    }
    let m = min_radius(&s, 4);
    assert!(
        (m.radius * at_end - 1.0).abs() < 1e-6,
        "smallest radius {} mm, the piece's end {} mm",
        m.radius,
        1.0 / at_end
    );
}
