//! Point inversion: closest points on curves and surfaces.

use dieface::geom::inversion::{
    closest_point_on_curve, closest_point_on_surface, project_to_curve_near,
};
use dieface::geom::{Curve2, Curve3, GeomError, NurbsSurface};
use glam::{DVec2, DVec3};
use proptest::prelude::*;

const S: f64 = std::f64::consts::FRAC_1_SQRT_2;
const CIRCLE_KNOTS: [f64; 12] = [
    0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
];
const CIRCLE_WEIGHTS: [f64; 9] = [1.0, S, 1.0, S, 1.0, S, 1.0, S, 1.0];

/// The exact circle of radius `r` about `c`, as a rational quadratic with four arcs.
fn circle(c: DVec2, r: f64) -> Curve2 {
    let unit = [
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (-1.0, 1.0),
        (-1.0, 0.0),
        (-1.0, -1.0),
        (0.0, -1.0),
        (1.0, -1.0),
        (1.0, 0.0),
    ];
    let pts = unit
        .iter()
        .map(|&(x, y)| c + DVec2::new(x, y) * r)
        .collect();
    Curve2::new_rational(2, CIRCLE_KNOTS.to_vec(), pts, CIRCLE_WEIGHTS.to_vec()).unwrap()
}

/// A wavy planar cubic with uneven knots, some of them dense.
fn wavy_cubic() -> Curve2 {
    let ys = [
        0.0, 2.0, -1.5, 1.0, 3.0, -2.0, 0.5, 2.5, -1.0, 1.5, 0.0, -2.5,
    ];
    let pts = ys
        .iter()
        .enumerate()
        .map(|(i, &y)| DVec2::new(i as f64, y))
        .collect();
    let knots = vec![
        0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.21, 0.22, 0.4, 0.55, 0.7, 0.85, 1.0, 1.0, 1.0, 1.0,
    ];
    Curve2::new(3, knots, pts).unwrap()
}

/// A wavy bicubic height field over roughly [0, 6] x [0, 6].
fn wavy_surface() -> NurbsSurface {
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0];
    let net = (0..7)
        .map(|i| {
            (0..7)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    DVec3::new(
                        x,
                        y,
                        1.5 * (1.3 * x).sin() * (0.9 * y + 0.4).cos() + 0.2 * x,
                    )
                })
                .collect()
        })
        .collect();
    NurbsSurface::new(3, 3, knots.clone(), knots, net).unwrap()
}

/// The cylinder of radius `r` about the z axis, `0 <= z <= h`: u runs around the circle.
fn cylinder(r: f64, h: f64) -> NurbsSurface {
    let c = circle(DVec2::ZERO, r);
    let net = c
        .control_points()
        .iter()
        .map(|p| vec![p.extend(0.0), p.extend(h)])
        .collect();
    let weights = CIRCLE_WEIGHTS.iter().map(|&w| vec![w, w]).collect();
    NurbsSurface::new_rational(
        2,
        1,
        CIRCLE_KNOTS.to_vec(),
        vec![0.0, 0.0, 1.0, 1.0],
        net,
        weights,
    )
    .unwrap()
}

#[test]
fn circle_from_outside_and_inside() {
    let (c, r) = (DVec2::new(3.0, -2.0), 5.0);
    let curve = circle(c, r);
    for k in 0..37 {
        let angle = 0.17 + k as f64 * 0.173;
        let dir = DVec2::new(angle.cos(), angle.sin());
        for d in [0.3, 2.0, 4.999, 5.0, 7.5, 60.0] {
            let target = c + dir * d;
            let cp = closest_point_on_curve(&curve, target).unwrap();
            assert!(
                (cp.distance - (d - r).abs()).abs() <= 1e-12 * r,
                "d = {d}, angle {angle}: {}",
                cp.distance
            );
            let expected = c + dir * r;
            assert!(
                cp.point.distance(expected) <= 1e-9 * r,
                "angle {angle}, d {d}: {:?} vs {expected:?}",
                cp.point
            );
            assert!((curve.point_at(cp.t) - cp.point).length() <= 1e-12 * r);
        }
    }
}

#[test]
fn circle_centre_is_at_radius() {
    let curve = circle(DVec2::new(1.0, 1.0), 2.0);
    let cp = closest_point_on_curve(&curve, DVec2::new(1.0, 1.0)).unwrap();
    assert!((cp.distance - 2.0).abs() < 1e-12);
}

#[test]
fn end_minimum_of_open_curve() {
    // Beyond the start of a straight-ish cubic: the start point is the answer.
    let curve = Curve3::bezier(vec![
        DVec3::ZERO,
        DVec3::new(1.0, 0.2, 0.0),
        DVec3::new(2.0, -0.2, 0.0),
        DVec3::new(3.0, 0.0, 0.0),
    ])
    .unwrap();
    let cp = closest_point_on_curve(&curve, DVec3::new(-2.0, 0.5, 0.3)).unwrap();
    assert_eq!(cp.t, 0.0);
    assert_eq!(cp.point, DVec3::ZERO);
    let cp = closest_point_on_curve(&curve, DVec3::new(5.0, -1.0, 0.0)).unwrap();
    assert_eq!(cp.t, 1.0);
}

#[test]
fn non_finite_target_is_an_error() {
    let curve = wavy_cubic();
    assert!(matches!(
        closest_point_on_curve(&curve, DVec2::new(f64::NAN, 0.0)),
        Err(GeomError::NotFinite { .. })
    ));
    assert!(matches!(
        project_to_curve_near(&curve, DVec2::ZERO, f64::NAN),
        Err(GeomError::NotFinite { .. })
    ));
    let s = wavy_surface();
    assert!(matches!(
        closest_point_on_surface(&s, DVec3::new(0.0, f64::INFINITY, 0.0)),
        Err(GeomError::NotFinite { .. })
    ));
}

#[test]
fn project_near_stays_near_the_guess() {
    let curve = wavy_cubic();
    for k in 0..=50 {
        let s = k as f64 / 50.0;
        let [c, d1] = curve.derivatives::<2>(s);
        let normal = DVec2::new(-d1.y, d1.x).normalize();
        let target = c + normal * 0.01;
        let cp = project_to_curve_near(&curve, target, s).unwrap();
        assert!((cp.t - s).abs() < 1e-9, "{k}: t = {}", cp.t);
        assert!((cp.distance - 0.01).abs() < 1e-12, "{k}: {}", cp.distance);
    }
}

/// The best of `n + 1` uniformly spaced samples.
fn dense_best_curve(curve: &Curve2, target: DVec2, n: usize) -> f64 {
    (0..=n)
        .map(|i| curve.point_at(i as f64 / n as f64).distance(target))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn cylinder_distance_is_radial() {
    let (r, h) = (4.0, 10.0);
    let s = cylinder(r, h);
    for k in 0..23 {
        let phi = -3.0 + k as f64 * 0.27;
        for d in [0.5, 3.0, 4.0, 6.0, 40.0] {
            let z = 0.3 + 0.4 * k as f64;
            let target = DVec3::new(d * phi.cos(), d * phi.sin(), z);
            let sp = closest_point_on_surface(&s, target).unwrap();
            assert!(
                (sp.distance - (d - r).abs()).abs() <= 1e-11 * r,
                "phi {phi} d {d}: {}",
                sp.distance
            );
            let expected = DVec3::new(r * phi.cos(), r * phi.sin(), z);
            assert!(
                sp.point.distance(expected) <= 1e-9 * r,
                "phi {phi} d {d}: {:?}",
                sp.point
            );
        }
    }
    // Beyond the top edge: the closest point is on the boundary v = 1.
    let sp = closest_point_on_surface(&s, DVec3::new(7.0, 0.0, 13.0)).unwrap();
    assert_eq!(sp.v, 1.0);
    assert!((sp.distance - 18f64.sqrt()).abs() < 1e-11);
    assert!(sp.point.distance(DVec3::new(4.0, 0.0, 10.0)) < 1e-9);
}

/// Checks the orthogonality of the offset at an interior result.
fn assert_orthogonal(s: &NurbsSurface, target: DVec3, u: f64, v: f64) {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let d = s.derivatives::<2>(u, v);
    let r = d[0][0] - target;
    let dist = r.length();
    if dist < 1e-9 {
        return;
    }
    if u > u0 && u < u1 {
        assert!(
            r.dot(d[1][0]).abs() <= 1e-9 * dist * d[1][0].length(),
            "S_u not orthogonal at ({u}, {v})"
        );
    }
    if v > v0 && v < v1 {
        assert!(
            r.dot(d[0][1]).abs() <= 1e-9 * dist * d[0][1].length(),
            "S_v not orthogonal at ({u}, {v})"
        );
    }
}

#[test]
fn points_on_the_surface_are_found() {
    let s = wavy_surface();
    for (u, v) in [
        (0.13, 0.77),
        (0.5, 0.5),
        (0.99, 0.01),
        (0.0, 0.3),
        (1.0, 1.0),
    ] {
        let p = s.point_at(u, v);
        let sp = closest_point_on_surface(&s, p).unwrap();
        assert!(sp.distance <= 1e-10, "({u}, {v}): {}", sp.distance);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn wavy_cubic_beats_dense_sampling(x in -3.0f64..14.0, y in -6.0f64..7.0) {
        let curve = wavy_cubic();
        let target = DVec2::new(x, y);
        let cp = closest_point_on_curve(&curve, target).unwrap();
        prop_assert!((curve.point_at(cp.t) - cp.point).length() < 1e-12);
        prop_assert!((cp.point.distance(target) - cp.distance).abs() < 1e-12);
        let best = dense_best_curve(&curve, target, 2000);
        prop_assert!(cp.distance <= best + 1e-9, "{} > dense {}", cp.distance, best);
        let (t0, t1) = curve.domain();
        if cp.t > t0 && cp.t < t1 && cp.distance > 1e-9 {
            let d1 = curve.derivative_at(cp.t);
            let f = d1.dot(cp.point - target);
            prop_assert!(f.abs() <= 1e-9 * d1.length() * cp.distance, "f = {f} at t = {}", cp.t);
        }
    }

    #[test]
    fn wavy_surface_beats_dense_grid(x in -2.0f64..8.0, y in -2.0f64..8.0, z in -4.0f64..4.0) {
        let s = wavy_surface();
        let target = DVec3::new(x, y, z);
        let sp = closest_point_on_surface(&s, target).unwrap();
        prop_assert!((s.point_at(sp.u, sp.v) - sp.point).length() < 1e-12);
        let n = 200;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n {
                best = best.min(s.point_at(i as f64 / n as f64, j as f64 / n as f64).distance(target));
            }
        }
        prop_assert!(sp.distance <= best + 1e-9, "{} > grid {}", sp.distance, best);
        assert_orthogonal(&s, target, sp.u, sp.v);
    }
}

/// Marching along a seam: points on a doubly curved patch (the surface's own points,
/// where rounding makes the cosine test meaningless) and points off it, projected from
/// the previous foot, land on the same foot as the global search.
#[test]
fn projection_near_a_guess_follows_a_line_of_points() {
    use dieface::geom::inversion::project_to_surface_near;
    let net: Vec<Vec<DVec3>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let (x, y) = (i as f64 * 100.0, j as f64 * 100.0);
                    DVec3::new(x, y, 0.001 * ((x - 150.0).powi(2) - (y - 150.0).powi(2)))
                })
                .collect()
        })
        .collect();
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let s = NurbsSurface::new(3, 3, knots.clone(), knots, net).expect("a valid patch");
    let mut guess = (0.0, 0.0);
    for k in 0..=40 {
        let t = k as f64 / 40.0;
        let on = s.point_at(t, 0.3 + 0.4 * t);
        let near = project_to_surface_near(&s, on, guess).expect("converges");
        assert!(near.distance < 1e-9, "{near:?}");
        let off = on + DVec3::new(0.0, 0.0, 2.0);
        let a = project_to_surface_near(&s, off, guess).expect("converges");
        let b = closest_point_on_surface(&s, off).expect("converges");
        assert!((a.distance - b.distance).abs() < 1e-9, "{a:?} vs {b:?}");
        guess = (near.u, near.v);
    }
}
