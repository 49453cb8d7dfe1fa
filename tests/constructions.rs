//! Constructions meet their defining conditions: arcs lie on their circles, lofts pass
//! through their sections with the asked cross tangents, rulings are straight,
//! revolutions keep their radius, Ferguson patches reproduce their corner data, and
//! transforms do what their names say.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use dieface::geom::arc::{arc_through_points, circle, circular_arc, Circle};
use dieface::geom::construct::{
    coons_triangle, ferguson, loft, revolve, ruled, HermiteCorners, Loft,
};
use dieface::geom::{Curve2, Curve3, GeomError, KnotVector, Transform};
use glam::{DMat4, DVec2, DVec3, DVec4};

fn grid(n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |i| i as f64 / n as f64)
}

#[test]
fn arcs_lie_on_their_circle_for_every_sweep() {
    let center = DVec3::new(10.0, -20.0, 5.0);
    let (x, y) = (
        DVec3::new(1.0, 1.0, 0.0).normalize(),
        DVec3::new(-1.0, 1.0, 1.0).normalize(),
    );
    for sweep in [0.3, FRAC_PI_2, 2.0, PI, 4.0, 1.5 * PI, 5.5, TAU] {
        let arc = circular_arc(center, x, y, 37.5, 0.4, 0.4 + sweep).unwrap();
        for t in grid(500) {
            let r = arc.point_at(t).distance(center);
            assert!((r - 37.5).abs() < 1e-12 * 37.5, "sweep {sweep}: radius {r}");
        }
        let start = center + (x * 0.4f64.cos() + y * 0.4f64.sin()) * 37.5;
        assert!(arc.point_at(0.0).distance(start) < 1e-12 * 50.0);
        let expected_length = 37.5 * sweep;
        assert!(
            (arc.length() - expected_length).abs() < 1e-9 * expected_length,
            "sweep {sweep}: length"
        );
    }
}

#[test]
fn circle_length_and_parameter_at_length() {
    let c = circle(DVec2::ZERO, DVec2::X, DVec2::Y, 2.0).unwrap();
    assert!((c.length() - 4.0 * PI).abs() < 1e-10);
    for s in [0.0, 1.0, PI, 7.0, 4.0 * PI] {
        let t = c.parameter_at_length(s).unwrap();
        assert!((c.length_between(0.0, t) - s).abs() < 1e-9);
        // On a circle the arc length fixes the angle.
        let p = c.point_at(t);
        let angle = p.y.atan2(p.x).rem_euclid(TAU);
        let expected = (s / 2.0).rem_euclid(TAU);
        let diff = (angle - expected).abs();
        assert!(
            diff.min(TAU - diff) < 1e-9,
            "s {s}: angle {angle} vs {expected}"
        );
    }
    assert!((c.curvature(0.3) - 0.5).abs() < 1e-12);
}

#[test]
fn arc_through_three_points_takes_the_middle_point_in_both_orientations() {
    let (a, b, c) = (
        DVec2::new(1.0, 0.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(-1.0, 0.0),
    );
    for (p, q, r) in [(a, b, c), (c, b, a), (a, DVec2::new(0.0, -1.0), c)] {
        let arc = arc_through_points(p, q, r).unwrap();
        assert!(arc.start_point().distance(p) < 1e-12);
        assert!(arc.end_point().distance(r) < 1e-12);
        let hits_middle = grid(2000).any(|t| arc.point_at(t).distance(q) < 2e-3);
        assert!(hits_middle, "the arc passes through the middle point");
        assert!((arc.length() - PI).abs() < 1e-9, "a half circle");
    }
    let circle = Circle::through(a, b, c).unwrap();
    assert!(circle.center.length() < 1e-12 && (circle.radius - 1.0).abs() < 1e-12);
    assert!(matches!(
        arc_through_points(a, DVec2::new(0.0, 0.0), c),
        Err(GeomError::Singular { .. })
    ));
}

fn wavy_section(z: f64, amplitude: f64) -> Curve3 {
    let pts = (0..6)
        .map(|i| DVec3::new(i as f64 * 20.0, amplitude * ((i as f64) * 1.3 + z).sin(), z))
        .collect();
    Curve3::new(3, KnotVector::uniform(3, 6).unwrap().into_vec(), pts).unwrap()
}

#[test]
fn loft_passes_through_its_sections_with_the_asked_tangents() {
    let sections: Vec<Curve3> = (0..4)
        .map(|k| wavy_section(k as f64 * 30.0, 5.0 + k as f64))
        .collect();
    // Different degree and knots on one section: compatibility must handle it.
    let mut sections = sections;
    sections[2] = sections[2]
        .elevate_degree(1)
        .unwrap()
        .insert_knot(0.37, 1)
        .unwrap();
    let start = Curve3::new(
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![DVec3::new(0.0, 0.0, 40.0), DVec3::new(0.0, 10.0, 40.0)],
    )
    .unwrap();
    let end = Curve3::line(DVec3::new(5.0, 0.0, 25.0), DVec3::new(0.0, 0.0, 35.0)).unwrap();
    let opts = Loft {
        degree: 3,
        start_tangent: Some(start.clone()),
        end_tangent: Some(end.clone()),
        ..Loft::default()
    };
    let s = loft(&sections, &opts).unwrap();
    // The first and last sections are exact iso-curves; inner ones are passed through
    // at their section parameters, found as the v where S(u, v) meets the section.
    for u in grid(50) {
        assert!(s.point_at(u, 0.0).distance(sections[0].point_at(u)) < 1e-9);
        assert!(s.point_at(u, 1.0).distance(sections[3].point_at(u)) < 1e-9);
        let d = s.derivatives::<2>(u, 0.0);
        assert!(
            d[0][1].distance(start.point_at(u)) < 1e-9,
            "start cross tangent at {u}"
        );
        let d = s.derivatives::<2>(u, 1.0);
        assert!(
            d[0][1].distance(end.point_at(u)) < 1e-9,
            "end cross tangent at {u}"
        );
    }
    let inner_hits = (1..3).all(|k| {
        let target = sections[k].point_at(0.5);
        grid(20000).any(|v| s.point_at(0.5, v).distance(target) < 1e-2)
    });
    assert!(inner_hits, "inner sections lie on the surface");
}

#[test]
fn loft_of_rational_circles_is_exact() {
    let sections: Vec<Curve3> = [(0.0, 10.0), (20.0, 15.0), (45.0, 12.0)]
        .iter()
        .map(|&(z, r)| circle(DVec3::new(0.0, 0.0, z), DVec3::X, DVec3::Y, r).unwrap())
        .collect();
    let s = loft(
        &sections,
        &Loft {
            degree: 2,
            ..Loft::default()
        },
    )
    .unwrap();
    assert!(s.is_rational());
    for u in grid(100) {
        assert!((s.point_at(u, 0.0).truncate().length() - 10.0).abs() < 1e-12 * 10.0);
        assert!((s.point_at(u, 1.0).truncate().length() - 12.0).abs() < 1e-12 * 12.0);
        // Every v-iso-line of a loft of coaxial circles keeps circular u-sections.
        let radii: Vec<f64> = grid(10)
            .map(|uu| s.point_at(uu, 0.3).truncate().length())
            .collect();
        let spread = radii.iter().cloned().fold(f64::MIN, f64::max)
            - radii.iter().cloned().fold(f64::MAX, f64::min);
        assert!(spread < 1e-9, "u-sections stay circles: spread {spread}");
    }
}

#[test]
fn ruled_surface_rulings_are_straight_segments() {
    let a = wavy_section(0.0, 5.0);
    let b = circular_arc(
        DVec3::new(50.0, 0.0, 40.0),
        DVec3::X,
        DVec3::Y,
        30.0,
        PI,
        TAU,
    )
    .unwrap();
    let s = ruled(&a, &b).unwrap();
    for u in grid(40) {
        let (p, q) = (s.point_at(u, 0.0), s.point_at(u, 1.0));
        assert!(p.distance(a.point_at(u)) < 1e-9);
        for v in grid(10) {
            let x = s.point_at(u, v);
            let off_line = (x - p).cross(q - p).length() / (q - p).length();
            assert!(off_line < 1e-9, "ruling at u = {u} is straight");
        }
    }
}

#[test]
fn revolution_keeps_the_radius_and_closes_on_a_full_turn() {
    let profile = Curve3::new(
        2,
        vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0],
        vec![
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(30.0, 0.0, 10.0),
            DVec3::new(15.0, 0.0, 30.0),
            DVec3::new(0.0, 0.0, 40.0),
        ],
    )
    .unwrap();
    let axis_point = DVec3::new(0.0, 0.0, 0.0);
    let s = revolve(&profile, axis_point, DVec3::Z, TAU).unwrap();
    for v in grid(20) {
        let on_profile = profile.point_at(v);
        let r = on_profile.truncate().length();
        assert!(s.point_at(0.0, v).distance(on_profile) < 1e-12 * 40.0);
        assert!(s.point_at(1.0, v).distance(on_profile) < 1e-12 * 40.0);
        for u in grid(30) {
            let p = s.point_at(u, v);
            assert!((p.truncate().length() - r).abs() < 1e-12 * 40.0);
            assert!((p.z - on_profile.z).abs() < 1e-12 * 40.0);
        }
    }
    // The profile ends on the axis: a pole, where S_u is rounding noise, has no normal.
    for u in [0.0, 0.3, 0.77] {
        assert!(s.normal(u, 1.0).is_err(), "no normal at the pole (u = {u})");
        assert!(s.normal(u, 0.5).is_ok());
    }
    let quarter = revolve(&profile, axis_point, DVec3::Z, FRAC_PI_2).unwrap();
    let end = quarter.point_at(1.0, 0.0);
    assert!(
        end.distance(DVec3::new(0.0, 10.0, 0.0)) < 1e-12 * 40.0,
        "right-handed about +Z"
    );
}

#[test]
fn ferguson_patch_reproduces_its_corner_data() {
    let mut c = HermiteCorners {
        points: [
            [DVec3::ZERO, DVec3::new(0.0, 100.0, 5.0)],
            [DVec3::new(120.0, 0.0, -3.0), DVec3::new(110.0, 95.0, 8.0)],
        ],
        du: [
            [DVec3::new(100.0, 10.0, 0.0), DVec3::new(90.0, 0.0, 5.0)],
            [DVec3::new(120.0, -5.0, 2.0), DVec3::new(100.0, 0.0, 0.0)],
        ],
        dv: [
            [DVec3::new(0.0, 90.0, 4.0), DVec3::new(5.0, 100.0, 0.0)],
            [DVec3::new(-10.0, 95.0, 0.0), DVec3::new(0.0, 80.0, 10.0)],
        ],
        twist: [[DVec3::ZERO; 2]; 2],
    };
    c.twist[1][0] = DVec3::new(3.0, -2.0, 7.0);
    let s = ferguson(&c).unwrap();
    for a in 0..2 {
        for b in 0..2 {
            let d = s.derivatives::<2>(a as f64, b as f64);
            assert!(d[0][0].distance(c.points[a][b]) < 1e-10);
            assert!(d[1][0].distance(c.du[a][b]) < 1e-10, "S_u at corner {a}{b}");
            assert!(d[0][1].distance(c.dv[a][b]) < 1e-10, "S_v at corner {a}{b}");
            assert!(
                d[1][1].distance(c.twist[a][b]) < 1e-10,
                "twist at corner {a}{b}"
            );
        }
    }
}

#[test]
fn three_sided_coons_patch_keeps_its_boundaries() {
    let p = [
        DVec3::ZERO,
        DVec3::new(100.0, 0.0, 10.0),
        DVec3::new(40.0, 80.0, 20.0),
    ];
    let arc = arc_free_curve(p[0], p[1], DVec3::new(0.0, -10.0, 5.0));
    let b = arc_free_curve(p[1], p[2], DVec3::new(15.0, 5.0, 0.0));
    let c = arc_free_curve(p[2], p[0], DVec3::new(-10.0, 5.0, -5.0));
    let s = coons_triangle(&arc, &b, &c).unwrap();
    for t in grid(50) {
        assert!(s.point_at(t, 0.0).distance(arc.point_at(t)) < 1e-10);
        assert!(s.point_at(1.0, t).distance(b.point_at(t)) < 1e-10);
        assert!(s.point_at(0.0, t).distance(c.point_at(1.0 - t)) < 1e-10);
        assert!(s.point_at(t, 1.0).distance(p[2]) < 1e-10);
    }
    assert!(
        s.normal(0.5, 1.0).is_err(),
        "the collapsed side has no normal"
    );
    assert!(s.normal(0.5, 0.5).is_ok());
}

/// A cubic from `a` to `b` bulging by `bulge`.
fn arc_free_curve(a: DVec3, b: DVec3, bulge: DVec3) -> Curve3 {
    Curve3::bezier(vec![
        a,
        a + (b - a) / 3.0 + bulge,
        a + (b - a) * 2.0 / 3.0 + bulge,
        b,
    ])
    .unwrap()
}

#[test]
fn transforms_do_what_their_names_say() {
    let p = DVec3::new(3.0, -4.0, 12.0);
    let rot = Transform::rotate_about_axis(DVec3::new(1.0, 1.0, 0.0), DVec3::Z, FRAC_PI_2).unwrap();
    assert!(
        rot.apply_point(DVec3::new(2.0, 1.0, 7.0))
            .distance(DVec3::new(1.0, 2.0, 7.0))
            < 1e-12
    );
    assert!(
        rot.apply_point(DVec3::new(1.0, 1.0, 9.0))
            .distance(DVec3::new(1.0, 1.0, 9.0))
            < 1e-12
    );

    let scale = Transform::scale_about(p, 2.5).unwrap();
    assert!(scale.apply_point(p).distance(p) < 1e-12);
    assert!(scale.apply_point(p + DVec3::X).distance(p + DVec3::X * 2.5) < 1e-12);

    for (a, b) in [
        (DVec3::X, DVec3::Y),
        (DVec3::new(1.0, 2.0, 3.0), DVec3::new(-3.0, 0.5, 1.0)),
        (DVec3::Z, -DVec3::Z),
        (DVec3::Y, DVec3::Y * 4.0),
    ] {
        let r = Transform::rotation_between(a, b).unwrap();
        assert!(
            r.apply_vector(a.normalize()).distance(b.normalize()) < 1e-12,
            "{a} onto {b}"
        );
        assert!(
            (r.apply_vector(p).length() - p.length()).abs() < 1e-12,
            "a rotation keeps lengths"
        );
    }
    assert!(Transform::rotation_between(DVec3::ZERO, DVec3::X).is_err());

    let mut projective = DMat4::IDENTITY;
    projective.x_axis = DVec4::new(1.0, 0.0, 0.0, 0.5);
    assert_eq!(
        Transform::from_matrix(projective),
        Err(GeomError::NotAffine)
    );
    assert_eq!(
        Transform::from_matrix(DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0))),
        Err(GeomError::NotAffine)
    );

    // A transformed curve is the curve of transformed points (affine invariance).
    let c = circular_arc(DVec3::ZERO, DVec3::X, DVec3::Z, 5.0, 0.0, 2.0).unwrap();
    let t = Transform::translate(DVec3::new(1.0, 2.0, 3.0))
        .unwrap()
        .then(rot)
        .then(scale);
    let tc = t.apply_curve(&c);
    for s in grid(100) {
        assert!(tc.point_at(s).distance(t.apply_point(c.point_at(s))) < 1e-10);
    }
}

#[test]
fn two_d_profiles_are_curves_too() {
    let c = Curve2::new(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        vec![DVec2::ZERO, DVec2::new(1.0, 1.0), DVec2::new(2.0, 0.0)],
    )
    .unwrap();
    assert!(
        (c.curvature(0.5) - 1.0).abs() < 1e-12,
        "parabola y = x - x^2/2 at its apex has curvature 1"
    );
    assert_eq!(c.to_3d().point_at(0.5), c.point_at(0.5).extend(0.0));
}

#[test]
fn surface_area_of_a_quarter_cylinder() {
    let (r, h) = (50.0, 100.0);
    let bottom = circular_arc(DVec3::ZERO, DVec3::X, DVec3::Y, r, 0.0, FRAC_PI_2).unwrap();
    let top = circular_arc(
        DVec3::new(0.0, 0.0, h),
        DVec3::X,
        DVec3::Y,
        r,
        0.0,
        FRAC_PI_2,
    )
    .unwrap();
    let s = ruled(&bottom, &top).unwrap();
    let exact = FRAC_PI_2 * r * h;
    assert!(
        (s.area() - exact).abs() < 1e-9 * exact,
        "area {} vs {exact}",
        s.area()
    );
}
