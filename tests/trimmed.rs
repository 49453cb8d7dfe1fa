//! Trimmed faces: area against closed forms, the inside test, the tessellation cut at
//! the outline, and the refusals (open loop, loop off the surface).

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use dieface::geom::arc::{circle, circular_arc};
use dieface::geom::construct::revolve;
use dieface::geom::inversion::closest_point_on_curve;
use dieface::geom::tessellate::{tessellate_trimmed, Tolerance};
use dieface::geom::{GeomError, NurbsSurface, TrimmedSurface};
use glam::{DVec2, DVec3};

/// A bicubic patch of the plane z = 0.3 x + 0.1 y with unevenly spaced control points,
/// so `|S_u x S_v|` varies across it.
fn tilted_plane() -> NurbsSurface {
    let xs = [0.0, 10.0, 40.0, 100.0];
    let ys = [0.0, 30.0, 50.0, 100.0];
    let net = xs
        .iter()
        .map(|&x| {
            ys.iter()
                .map(|&y| DVec3::new(x, y, 0.3 * x + 0.1 * y))
                .collect()
        })
        .collect();
    let k = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    NurbsSurface::new(3, 3, k.clone(), k, net).unwrap()
}

/// The plane's unit in-plane axes and a point on it.
fn plane_frame(x: f64, y: f64) -> (DVec3, DVec3, DVec3) {
    let p = DVec3::new(x, y, 0.3 * x + 0.1 * y);
    let n = DVec3::new(-0.3, -0.1, 1.0).normalize();
    let e1 = DVec3::new(1.0, 0.0, 0.3).normalize();
    (p, e1, n.cross(e1))
}

/// A quarter-turn sphere patch of radius `r`: latitude -60..60 deg, longitude 0..90.
fn sphere_patch(r: f64) -> NurbsSurface {
    let profile = circular_arc(DVec3::ZERO, DVec3::X, DVec3::Z, r, -PI / 3.0, PI / 3.0).unwrap();
    revolve(&profile, DVec3::ZERO, DVec3::Z, FRAC_PI_2).unwrap()
}

/// The small circle at angular radius `alpha` about longitude 45 deg on the equator.
fn small_circle(r: f64, alpha: f64) -> dieface::geom::Curve3 {
    let c = DVec3::new(FRAC_PI_4.cos(), FRAC_PI_4.sin(), 0.0);
    let e1 = DVec3::Z;
    let e2 = c.cross(e1);
    circle(c * (r * alpha.cos()), e1, e2, r * alpha.sin()).unwrap()
}

#[test]
fn plane_trimmed_by_a_circle_has_the_circle_area() {
    let (p, e1, e2) = plane_frame(50.0, 45.0);
    let outline = circle(p, e1, e2, 20.0).unwrap();
    let face = TrimmedSurface::new(tilted_plane(), outline, 0.01).unwrap();
    let exact = PI * 20.0 * 20.0;
    let rel = (face.area() - exact).abs() / exact;
    assert!(rel < 1e-9, "area {} vs {exact}: {rel:e}", face.area());
    // The loop's orientation does not change the area.
    let reversed =
        TrimmedSurface::new(tilted_plane(), face.outer().curve().reversed(), 0.01).unwrap();
    assert!((reversed.area() - exact).abs() / exact < 1e-9);
    assert_ne!(
        face.outer().counter_clockwise(),
        reversed.outer().counter_clockwise()
    );
}

#[test]
fn sphere_trimmed_by_a_small_circle_has_the_cap_area() {
    let r = 200.0;
    for alpha in [0.1_f64, 0.5] {
        let face = TrimmedSurface::new(sphere_patch(r), small_circle(r, alpha), 0.01).unwrap();
        let exact = 2.0 * PI * r * r * (1.0 - alpha.cos());
        let rel = (face.area() - exact).abs() / exact;
        assert!(
            rel < 1e-9,
            "alpha {alpha}: area {} vs {exact}: {rel:e}",
            face.area()
        );
    }
}

#[test]
fn inside_test_follows_the_outline() {
    let (p, e1, e2) = plane_frame(50.0, 45.0);
    let face = TrimmedSurface::new(tilted_plane(), circle(p, e1, e2, 20.0).unwrap(), 0.01).unwrap();
    let s = face.surface();
    let uv_of = |q: DVec3| {
        let sp = dieface::geom::inversion::closest_point_on_surface(s, q).unwrap();
        DVec2::new(sp.u, sp.v)
    };
    assert!(face.contains(uv_of(p)));
    assert!(face.contains(uv_of(p + e1 * 19.9)));
    assert!(!face.contains(uv_of(p + e1 * 20.1)));
    assert!(!face.contains(uv_of(p + e2 * 25.0)));
}

#[test]
fn tessellation_is_cut_at_the_outline_and_within_tolerance() {
    let r = 200.0;
    let alpha = 0.5;
    let outline = small_circle(r, alpha);
    let face = TrimmedSurface::new(sphere_patch(r), outline.clone(), 0.01).unwrap();
    let tol = Tolerance::new(0.05).unwrap();
    let mesh = tessellate_trimmed(&face, &tol).unwrap();
    let m = mesh.to_mesh().unwrap();
    let topo = m.topology();
    let loops = topo.boundary_loops();
    assert_eq!(loops.loops.len(), 1, "one boundary loop");
    assert!(loops.open_chains.is_empty());
    // Every boundary vertex lies on the outline (to rounding).
    for &v in &loops.loops[0].vertices {
        let p = m.position(v).unwrap();
        let d = closest_point_on_curve(&outline, p).unwrap().distance;
        assert!(d < 1e-9, "boundary vertex {d} mm off the outline");
    }
    // Every vertex on the sphere, every triangle's middle within the tolerance.
    for &p in &mesh.positions {
        assert!((p.length() - r).abs() < 1e-9);
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let mid = (a + b + c) / 3.0;
        assert!(
            r - mid.length() <= tol.chordal * 1.01,
            "sag {}",
            r - mid.length()
        );
        for m in [(a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0] {
            assert!(
                r - m.length() <= tol.chordal * 1.01,
                "edge sag {}",
                r - m.length()
            );
        }
        // Counter-clockwise around the outward normal.
        let n = (b - a).cross(c - a);
        assert!(
            n.dot(mid) > 0.0,
            "triangle wound against the surface normal"
        );
    }
    let exact = 2.0 * PI * r * r * (1.0 - alpha.cos());
    let rel = (m.total_area() - exact).abs() / exact;
    assert!(rel < 1e-3, "mesh area {} vs {exact}", m.total_area());
}

#[test]
fn an_open_loop_is_refused() {
    let (p, e1, e2) = plane_frame(50.0, 45.0);
    let arc = circular_arc(p, e1, e2, 20.0, 0.0, 1.5 * PI).unwrap();
    match TrimmedSurface::new(tilted_plane(), arc, 0.01) {
        Err(GeomError::OpenLoop { gap }) => assert!((gap - 20.0 * 2f64.sqrt()).abs() < 1e-9),
        other => panic!("expected OpenLoop, got {other:?}"),
    }
}

#[test]
fn a_loop_off_the_surface_is_refused() {
    let (p, e1, e2) = plane_frame(50.0, 45.0);
    let n = e1.cross(e2);
    let lifted = circle(p + n * 0.5, e1, e2, 20.0).unwrap();
    match TrimmedSurface::new(tilted_plane(), lifted, 0.01) {
        Err(GeomError::OffSurface { distance, .. }) => {
            assert!((distance - 0.5).abs() < 1e-6, "distance {distance}")
        }
        other => panic!("expected OffSurface, got {other:?}"),
    }
}
