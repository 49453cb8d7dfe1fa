//! The 3-D punch-opening side curve from its top and side views (paper 001 section 3.2,
//! eq. 1-2).

use std::f64::consts::FRAC_PI_2;

use dieface::die::two_view::{
    advance_along_tangent, next_step, parameter_at_x, side_curve_from_two_views, step_lengths,
    SideCurve, TwoView, View,
};
use dieface::geom::arc::circular_arc;
use dieface::geom::interpolate::{interpolate, Interpolation};
use dieface::geom::inversion::closest_point_on_curve;
use dieface::geom::{Curve2, GeomError};
use glam::{DVec2, DVec3};

const SAMPLES: usize = 10_000;

/// Side-view arc of radius 2000 over x in [-640, 620], apex at z = 100, drawn in -x.
const RADIUS: f64 = 2000.0;
const CENTER: DVec2 = DVec2::new(-10.0, 100.0 - RADIUS);

fn side_arc() -> Curve2 {
    let a = (630.0 / RADIUS).asin();
    circular_arc(
        CENTER,
        DVec2::X,
        DVec2::Y,
        RADIUS,
        FRAC_PI_2 - a,
        FRAC_PI_2 + a,
    )
    .unwrap()
}

fn top_line() -> Curve2 {
    Curve2::line(DVec2::new(-640.0, -330.0), DVec2::new(620.0, -330.0)).unwrap()
}

/// Points of the 3-D curve at `SAMPLES` evenly spaced parameters.
fn samples(side: &SideCurve) -> impl Iterator<Item = DVec3> + '_ {
    let (a, b) = side.curve.domain();
    (0..SAMPLES).map(move |i| {
        side.curve
            .point_at(a + (b - a) * i as f64 / (SAMPLES - 1) as f64)
    })
}

#[test]
fn straight_top_view_with_circular_side_view() {
    let (top, side) = (top_line(), side_arc());
    let half_angle = (630.0 / RADIUS).asin();
    for delta in [0.01, 0.001] {
        let out = side_curve_from_two_views(
            &top,
            &side,
            &TwoView {
                delta,
                max_step: None,
            },
        )
        .unwrap();
        // Ends exactly at the top view's ends; x strictly increasing.
        assert_eq!(out.points[0].x, -640.0);
        assert_eq!(out.points.last().unwrap().x, 620.0);
        assert!(out.points.windows(2).all(|w| w[1].x > w[0].x));

        // Projections of the interpolated curve: top view (y = -330), side view (arc).
        let (mut top_dev, mut side_dev) = (0.0f64, 0.0f64);
        for p in samples(&out) {
            top_dev = top_dev.max((p.y + 330.0).abs());
            side_dev = side_dev.max((DVec2::new(p.x, p.z).distance(CENTER) - RADIUS).abs());
        }
        // The stepped polyline itself: each chord's sag from the arc (the quantity eq. 1
        // controls) is within delta and close to it (steps are not needlessly short).
        let sags: Vec<f64> = out
            .points
            .windows(2)
            .map(|w| {
                let c = DVec2::new(w[1].x - w[0].x, w[1].z - w[0].z).length();
                RADIUS - (RADIUS * RADIUS - c * c / 4.0).sqrt()
            })
            .collect();
        let max_sag = sags.iter().copied().fold(0.0, f64::max);
        // Analytic need: the arc's angle over the angle one chord L subtends.
        let l = 2.0 * (2.0 * RADIUS * delta - delta * delta).sqrt();
        let need = half_angle / (l / (2.0 * RADIUS)).asin();
        let steps = out.points.len() - 1;
        eprintln!(
            "line/arc delta {delta}: {} points, {steps} steps (analytic {need:.2}), \
             top dev {top_dev:.3e}, side dev {side_dev:.3e}, chord sag max {max_sag:.6}",
            out.points.len()
        );
        assert!(top_dev <= delta, "top view off by {top_dev}");
        assert!(side_dev <= delta, "side view off by {side_dev}");
        assert!(
            max_sag <= delta * (1.0 + 1e-6),
            "a chord sags {max_sag} > {delta}"
        );
        assert!(
            max_sag >= 0.95 * delta,
            "largest chord sag {max_sag} far below {delta}"
        );
        assert!(
            (steps as f64 - need).abs() <= 2.0,
            "{steps} steps, analytic {need}"
        );
    }
}

/// A top view drawn in -x gives the same points as drawn in +x.
#[test]
fn views_drawn_in_minus_x_are_reversed() {
    let opts = TwoView {
        delta: 0.01,
        max_step: None,
    };
    let a = side_curve_from_two_views(&top_line(), &side_arc(), &opts).unwrap();
    let b =
        side_curve_from_two_views(&top_line().reversed(), &side_arc().reversed(), &opts).unwrap();
    assert_eq!(a.points.len(), b.points.len());
    for (p, q) in a.points.iter().zip(&b.points) {
        assert!(p.distance(*q) < 1e-9, "{p} vs {q}");
    }
}

#[test]
fn curved_top_view_with_spline_side_view() {
    let top = interpolate(
        &[
            DVec2::new(-500.0, -300.0),
            DVec2::new(-150.0, -240.0),
            DVec2::new(200.0, -330.0),
            DVec2::new(500.0, -280.0),
        ],
        &Interpolation::default(),
    )
    .unwrap();
    // Wider in x than the top view: only [-500, 500] of it is used.
    let side = interpolate(
        &[
            DVec2::new(-560.0, 20.0),
            DVec2::new(-300.0, 65.0),
            DVec2::new(-50.0, 80.0),
            DVec2::new(180.0, 40.0),
            DVec2::new(400.0, 55.0),
            DVec2::new(540.0, 10.0),
        ],
        &Interpolation::default(),
    )
    .unwrap();
    for delta in [0.01, 0.001] {
        let out = side_curve_from_two_views(
            &top,
            &side,
            &TwoView {
                delta,
                max_step: None,
            },
        )
        .unwrap();
        assert_eq!(out.points[0].x, -500.0);
        assert_eq!(out.points.last().unwrap().x, 500.0);
        // Stepped points lie on both views (to solver accuracy).
        for p in &out.points {
            let t = closest_point_on_curve(&top, DVec2::new(p.x, p.y)).unwrap();
            let s = closest_point_on_curve(&side, DVec2::new(p.x, p.z)).unwrap();
            assert!(t.distance < 1e-8 && s.distance < 1e-8, "{p}: {t:?} {s:?}");
        }
        let (mut top_dev, mut side_dev) = (0.0f64, 0.0f64);
        for p in samples(&out) {
            let t = closest_point_on_curve(&top, DVec2::new(p.x, p.y)).unwrap();
            let s = closest_point_on_curve(&side, DVec2::new(p.x, p.z)).unwrap();
            top_dev = top_dev.max(t.distance);
            side_dev = side_dev.max(s.distance);
        }
        // Chord midpoints of the stepping, against both views.
        let (mut top_sag, mut side_sag) = (0.0f64, 0.0f64);
        for w in out.points.windows(2) {
            let m = 0.5 * (w[0] + w[1]);
            top_sag = top_sag.max(
                closest_point_on_curve(&top, DVec2::new(m.x, m.y))
                    .unwrap()
                    .distance,
            );
            side_sag = side_sag.max(
                closest_point_on_curve(&side, DVec2::new(m.x, m.z))
                    .unwrap()
                    .distance,
            );
        }
        eprintln!(
            "cubic/spline delta {delta}: {} points, top dev {top_dev:.3e}, side dev {side_dev:.3e}, \
             chord midpoint sag top {top_sag:.6} side {side_sag:.6}",
            out.points.len()
        );
        assert!(top_dev <= delta, "top view off by {top_dev}");
        assert!(side_dev <= delta, "side view off by {side_dev}");
        assert!(top_sag <= delta * 1.01 && side_sag <= delta * 1.01);
        assert!(
            top_sag.max(side_sag) >= 0.5 * delta,
            "steps needlessly short"
        );
    }
}

// ---- Each step on hand-checkable input. ----

#[test]
fn eq1_step_lengths() {
    let (l, d) = step_lengths(100.0, 0.1, 1e9);
    assert!((l - 2.0 * 19.99f64.sqrt()).abs() < 1e-12);
    assert!((l - 8.942_0).abs() < 1e-3);
    assert!((d - l * (1.0 - 0.001)).abs() < 1e-12);
    // Straight: L = D = L_max.
    assert_eq!(step_lengths(f64::INFINITY, 0.1, 50.0), (50.0, 50.0));
    assert_eq!(step_lengths(1.0 / 0.0, 0.1, 50.0), (50.0, 50.0));
    // Capped: L = L_max, D its projection on the same circle.
    let (l, d) = step_lengths(100.0, 0.1, 5.0);
    assert_eq!(l, 5.0);
    assert!((d - 5.0 * (1.0 - 0.025f64.powi(2)).sqrt()).abs() < 1e-12);
    // Radius below delta: a step of one radius.
    let (l, d) = step_lengths(0.05, 0.1, 50.0);
    assert_eq!(l, 0.05);
    assert!((d - 0.05 * 3f64.sqrt() / 2.0).abs() < 1e-12);
}

#[test]
fn eq2_advance_on_a_line_is_exactly_d() {
    let line = Curve2::line(DVec2::new(0.0, 0.0), DVec2::new(300.0, 400.0)).unwrap();
    let d = step_lengths(100.0, 0.1, 1e9).1;
    let u1 = advance_along_tangent(&line, 0.2, d).unwrap();
    let chord = line.point_at(u1) - line.point_at(0.2);
    assert!((chord.length() - d).abs() < 1e-10, "{}", chord.length());
    assert!((u1 - (0.2 + d / 500.0)).abs() < 1e-12);
    // Past the end: the end of the domain.
    assert_eq!(advance_along_tangent(&line, 0.99, 50.0).unwrap(), 1.0);
}

#[test]
fn eq2_advance_on_a_circle_gives_chord_l_and_sag_delta() {
    let r = 100.0;
    let arc = circular_arc(DVec2::ZERO, DVec2::X, DVec2::Y, r, 0.0, 1.5).unwrap();
    let (l, d) = step_lengths(r, 0.1, 1e9);
    let u = 0.3;
    let u1 = advance_along_tangent(&arc, u, d).unwrap();
    let (a, b) = (arc.point_at(u), arc.point_at(u1));
    let tangent = arc.unit_tangent(u).unwrap();
    assert!(((b - a).dot(tangent) - d).abs() < 1e-10);
    assert!(((b - a).length() - l).abs() < 1e-9);
    let sag = r - (0.5 * (a + b)).length();
    assert!((sag - 0.1).abs() < 1e-9, "sag {sag}");
}

/// A side-view arc of radius 100 over x in [-70, 70] (apex at z = 0).
fn small_arc() -> Curve2 {
    let a = (70.0f64 / 100.0).asin();
    // Drawn counter-clockwise, so in -x; reversed to run in +x.
    circular_arc(
        DVec2::new(0.0, -100.0),
        DVec2::X,
        DVec2::Y,
        100.0,
        FRAC_PI_2 - a,
        FRAC_PI_2 + a,
    )
    .unwrap()
    .reversed()
}

#[test]
fn step4_takes_the_smaller_x_and_step5_finds_it_on_the_other_view() {
    let line = Curve2::line(DVec2::new(-70.0, -5.0), DVec2::new(70.0, -5.0)).unwrap();
    let arc = small_arc();
    assert!(arc.start_point().x < arc.end_point().x);
    let (delta, max_step) = (0.1, 50.0);
    let arc_u = parameter_at_x(&arc, -60.0, 0.0).unwrap();
    let line_u = parameter_at_x(&line, -60.0, 0.0).unwrap();
    // Step 5 alone: the parameter with that x.
    assert!((arc.point_at(arc_u).x + 60.0).abs() < 1e-9);
    assert!((line.point_at(line_u).x + 60.0).abs() < 1e-12);

    // Candidates by hand: the straight view would go 50 mm, the arc about 8.93.
    let arc_candidate =
        advance_along_tangent(&arc, arc_u, step_lengths(100.0, delta, max_step).1).unwrap();
    let x_arc = arc.point_at(arc_candidate).x;
    assert!(x_arc < -60.0 + 8.942 && x_arc > -60.0 + 5.0, "{x_arc}");

    // Straight top, arc side: the side view leads.
    let step = next_step(&line, &arc, line_u, arc_u, delta, max_step).unwrap();
    assert_eq!(step.led_by, View::Side);
    assert!((step.x - x_arc).abs() < 1e-9);
    assert!((step.side_u - arc_candidate).abs() < 1e-9);
    assert!((line.point_at(step.top_u).x - step.x).abs() < 1e-9);

    // Arc top, straight side: the top view leads, at the same x.
    let step = next_step(&arc, &line, arc_u, line_u, delta, max_step).unwrap();
    assert_eq!(step.led_by, View::Top);
    assert!((step.x - x_arc).abs() < 1e-9);
    assert!((line.point_at(step.side_u).x - step.x).abs() < 1e-9);
}

// ---- Errors. ----

#[test]
fn side_view_shorter_than_top_view_is_an_error() {
    let side = Curve2::line(DVec2::new(-600.0, 0.0), DVec2::new(620.0, 50.0)).unwrap();
    let err = side_curve_from_two_views(&top_line(), &side, &TwoView::default()).unwrap_err();
    assert_eq!(
        err,
        GeomError::ViewsDoNotOverlap {
            top: (-640.0, 620.0),
            side: (-600.0, 620.0)
        }
    );
    assert!(err.to_string().contains("[-600, 620]"), "{err}");
    // Short at the other end too.
    let side = Curve2::line(DVec2::new(-640.0, 0.0), DVec2::new(600.0, 50.0)).unwrap();
    assert!(matches!(
        side_curve_from_two_views(&top_line(), &side, &TwoView::default()),
        Err(GeomError::ViewsDoNotOverlap { .. })
    ));
}

#[test]
fn top_view_that_doubles_back_is_an_error() {
    let top = interpolate(
        &[
            DVec2::new(-640.0, -330.0),
            DVec2::new(100.0, -300.0),
            DVec2::new(-100.0, -250.0),
            DVec2::new(620.0, -330.0),
        ],
        &Interpolation::default(),
    )
    .unwrap();
    let err = side_curve_from_two_views(&top, &side_arc(), &TwoView::default()).unwrap_err();
    match err {
        GeomError::Singular { what } => assert!(what.contains("top view doubles back"), "{what}"),
        other => panic!("expected Singular, got {other:?}"),
    }
}

#[test]
fn bad_options_are_errors() {
    let opts = TwoView {
        delta: 0.0,
        max_step: None,
    };
    assert!(matches!(
        side_curve_from_two_views(&top_line(), &side_arc(), &opts),
        Err(GeomError::NotPositive { .. })
    ));
    let opts = TwoView {
        delta: 0.01,
        max_step: Some(-1.0),
    };
    assert!(matches!(
        side_curve_from_two_views(&top_line(), &side_arc(), &opts),
        Err(GeomError::NotPositive { .. })
    ));
}
