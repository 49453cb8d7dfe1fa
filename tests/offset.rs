//! `offset` and `between`: the offset of a 2-D curve lies at the distance asked from the
//! original everywhere (measured independently: the closest point on the original, at
//! many more points than the fit was checked at), lines and arcs give their exact
//! parallels, closed curves stay closed, and the stretch between two points follows the
//! curve over the seam of a closed curve.

use std::f64::consts::PI;
use std::path::Path;

use dieface::eval::{Data, Engine};
use dieface::geom::arc::circular_arc;
use dieface::geom::interpolate::{interpolate, Interpolation};
use dieface::geom::inversion::{closest_point_on_curve, project_to_curve_near};
use dieface::geom::offset::{curve_between, offset_curve2, CORNER_ANGLE};
use dieface::geom::{Curve2, GeomError};
use glam::DVec2;
use proptest::prelude::*;

#[path = "common/script.rs"]
mod script;

/// The tolerance the `offset` builtin asks of the kernel.
const TOL: f64 = 0.001;

// ---- helpers ----------------------------------------------------------------------------

/// Evaluates a script (`units mm deg` first) and returns every declaration's value;
/// panics on any diagnostic.
fn evaluate(text: &str) -> Vec<(String, Data)> {
    script::evaluate_clean("offset_test.die", &format!("units mm deg\n{text}\n"))
}

/// The diagnostics of a script, as `code: message`.
fn messages(text: &str) -> Vec<String> {
    let text = format!("units mm deg\n{text}\n");
    let mut engine = Engine::new(None);
    engine
        .evaluate("offset_test.die", &text, None)
        .diagnostics
        .iter()
        .map(|d| format!("{}: {}", d.code, d.message))
        .collect()
}

/// The value of declaration `name`.
fn value(values: &[(String, Data)], name: &str) -> Data {
    values
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no declaration {name}"))
        .1
        .clone()
}

/// The 2-D curve a value is: a 2-D curve, or a sketch's profile.
fn flat(d: &Data) -> Curve2 {
    match d {
        Data::Curve2(c) => (**c).clone(),
        Data::Sketch(s) => s.curve.clone(),
        other => panic!("not a 2-D curve: {other:?}"),
    }
}

/// The `punch_profile` sketch of `examples/fender/fender.die` (its text, evaluated on
/// its own): a counter-clockwise rounded quadrilateral with fillets of 110 to 150 mm.
fn fender_profile_text() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fender/fender.die");
    let text = std::fs::read_to_string(path).expect("the fender example");
    let start = text
        .find("let punch_profile = sketch(top) {")
        .expect("the fender declares punch_profile");
    let end = start + text[start..].find("\n}").expect("the sketch closes") + 2;
    text[start..end].to_string()
}

fn fender_profile() -> Curve2 {
    flat(&value(&evaluate(&fender_profile_text()), "punch_profile"))
}

/// `n + 1` points evenly spaced in the parameter of a curve.
fn samples(c: &Curve2, n: usize) -> Vec<DVec2> {
    let (t0, t1) = c.domain();
    (0..=n)
        .map(|k| c.point_at(t0 + (t1 - t0) * k as f64 / n as f64))
        .collect()
}

/// Distances to a curve, measured on their own: the nearest of 20 000 points evenly
/// spaced in the parameter, refined by Newton from there (closest point near it). The
/// kernel's global search samples every knot span a few times only, which a very tight
/// hook (a radius of 0.2 mm on a 500 mm curve) can fool.
struct Measure<'a> {
    curve: &'a Curve2,
    ts: Vec<f64>,
    pts: Vec<DVec2>,
}

impl<'a> Measure<'a> {
    fn new(curve: &'a Curve2) -> Self {
        let (t0, t1) = curve.domain();
        let ts: Vec<f64> = (0..=20_000)
            .map(|k| t0 + (t1 - t0) * k as f64 / 20_000.0)
            .collect();
        let pts = ts.iter().map(|&t| curve.point_at(t)).collect();
        Self { curve, ts, pts }
    }

    fn distance(&self, p: DVec2) -> f64 {
        let (i, nearest) = self.pts.iter().map(|q| q.distance(p)).enumerate().fold(
            (0, f64::INFINITY),
            |a, (i, d)| if d < a.1 { (i, d) } else { a },
        );
        let cp = project_to_curve_near(self.curve, p, self.ts[i]).expect("closest point");
        nearest.min(cp.distance)
    }
}

/// The largest difference between `|distance|` and the distance of `n + 1` points of
/// `offset` from `original` (closest point on the original).
fn worst_distance_error(original: &Curve2, offset: &Curve2, distance: f64, n: usize) -> f64 {
    let m = Measure::new(original);
    samples(offset, n)
        .into_iter()
        .map(|p| (m.distance(p) - distance.abs()).abs())
        .fold(0.0, f64::max)
}

/// The largest distance of `n + 1` points of `a` from the curve `b`.
fn one_sided_gap(a: &Curve2, b: &Curve2, n: usize) -> f64 {
    let m = Measure::new(b);
    samples(a, n)
        .into_iter()
        .map(|p| m.distance(p))
        .fold(0.0, f64::max)
}

/// The signed area enclosed by a closed curve (positive: counter-clockwise).
fn area(c: &Curve2) -> f64 {
    let pts = samples(c, 4000);
    0.5 * pts.windows(2).map(|w| w[0].perp_dot(w[1])).sum::<f64>()
}

/// Whether `p` lies inside the closed polygon `poly` (even-odd rule).
fn inside(poly: &[DVec2], p: DVec2) -> bool {
    let mut inside = false;
    for w in poly.windows(2) {
        let (a, b) = (w[0], w[1]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// The unit tangent at the start and at the end.
fn end_tangents(c: &Curve2) -> (DVec2, DVec2) {
    let (t0, t1) = c.domain();
    (
        c.derivative_at(t0).normalize(),
        c.derivative_at(t1).normalize(),
    )
}

// ---- lines and arcs -----------------------------------------------------------------------

#[test]
fn the_offset_of_a_line_is_the_parallel_line() {
    let (a, b) = (DVec2::new(10.0, 20.0), DVec2::new(310.0, -80.0));
    let line = Curve2::line(a, b).unwrap();
    let left = (b - a).normalize().perp();
    for d in [25.0, -90.0, 0.5] {
        let off = offset_curve2(&line, d, TOL).unwrap();
        assert!(off.start_point().distance(a + left * d) < 1e-9);
        assert!(off.end_point().distance(b + left * d) < 1e-9);
        for p in samples(&off, 500) {
            let across = (p - a).dot(left);
            assert!((across - d).abs() < 1e-9, "{across} vs {d}");
            let along = (p - a).dot((b - a).normalize());
            assert!((-1e-9..=(b - a).length() + 1e-9).contains(&along));
        }
    }
    // A straight cubic (interpolated through collinear points) is moved exactly too.
    let pts: Vec<DVec2> = [0.0, 0.1, 0.45, 1.0]
        .iter()
        .map(|&f| a + (b - a) * f)
        .collect();
    let cubic = interpolate(&pts, &Interpolation::default()).unwrap();
    let off = offset_curve2(&cubic, 40.0, TOL).unwrap();
    for p in samples(&off, 500) {
        assert!(((p - a).dot(left) - 40.0).abs() < 1e-9);
    }
    // Through the language: a bare number is in the file's unit.
    let v = evaluate("let o = offset(line_between((0, 0), (100, 0)), 10)\nlet o_cm = offset(line_between((0, 0), (100, 0)), -1 cm)");
    let (o, o_cm) = (flat(&value(&v, "o")), flat(&value(&v, "o_cm")));
    assert!(o.start_point().distance(DVec2::new(0.0, 10.0)) < 1e-9);
    assert!(o.end_point().distance(DVec2::new(100.0, 10.0)) < 1e-9);
    assert!(o_cm.start_point().distance(DVec2::new(0.0, -10.0)) < 1e-9);
}

#[test]
fn the_offset_of_an_arc_is_the_concentric_arc() {
    let center = DVec2::new(30.0, -40.0);
    let r = 100.0;
    // Counter-clockwise: the left is the inside.
    let arc = circular_arc(
        center,
        DVec2::X,
        DVec2::Y,
        r,
        10f64.to_radians(),
        160f64.to_radians(),
    )
    .unwrap();
    let mut worst: f64 = 0.0;
    for d in [30.0, -30.0, 99.0, -250.0] {
        let off = offset_curve2(&arc, d, TOL).unwrap();
        for p in samples(&off, 1000) {
            worst = worst.max((p.distance(center) - (r - d)).abs());
        }
        // The ends lie on the radii through the arc's ends.
        let s = center + DVec2::from_angle(10f64.to_radians()) * (r - d);
        let e = center + DVec2::from_angle(160f64.to_radians()) * (r - d);
        assert!(off.start_point().distance(s) < 1e-9);
        assert!(off.end_point().distance(e) < 1e-9);
    }
    assert!(worst <= TOL, "concentric arc off by {worst} mm");
    eprintln!("arc: worst radius error {worst:.2e} mm");

    // A full circle: closed in, closed out.
    let circle = evaluate("let c = offset(circle((0, 0), 50 mm), -20 mm)");
    let c = flat(&value(&circle, "c"));
    assert!(c.is_closed());
    for p in samples(&c, 1000) {
        assert!((p.length() - 70.0).abs() <= TOL);
    }
}

// ---- the fender's punch opening ---------------------------------------------------------

#[test]
fn the_fender_opening_offset_outside_by_90_mm_stays_90_mm_away_and_closes() {
    let profile = fender_profile();
    assert!(profile.is_closed());
    assert!(
        area(&profile) > 0.0,
        "the punch profile is counter-clockwise"
    );
    let off = offset_curve2(&profile, -90.0, TOL).unwrap();
    let worst = worst_distance_error(&profile, &off, -90.0, 2000);
    eprintln!(
        "fender -90 mm: worst distance error {worst:.2e} mm, {} control points",
        off.control_points().len()
    );
    assert!(worst <= TOL, "{worst}");
    // Closed, with one tangent at the seam, and outside: larger than the opening.
    assert_eq!(off.start_point(), off.end_point());
    let (s, e) = end_tangents(&off);
    assert!(s.angle_to(e).abs() < 1e-9, "seam kink {}", s.angle_to(e));
    assert!(area(&off) > area(&profile) + 90.0 * 4000.0);
    // The fillets of 110 to 150 mm become arcs of 200 to 240 mm about the same centres:
    // every point of the opening is 90 mm from the offset too.
    let back = one_sided_gap(&profile, &off, 2000);
    assert!((back - 90.0).abs() <= TOL, "{back}");

    // Inside by 100 mm (below the smallest fillet, 110 mm).
    let inside = offset_curve2(&profile, 100.0, TOL).unwrap();
    let worst_in = worst_distance_error(&profile, &inside, 100.0, 2000);
    eprintln!("fender +100 mm: worst distance error {worst_in:.2e} mm");
    assert!(worst_in <= TOL, "{worst_in}");
    assert!(area(&inside) < area(&profile));
}

#[test]
fn offsetting_by_d_then_minus_d_returns_to_the_original() {
    let profile = fender_profile();
    let out = offset_curve2(&profile, -90.0, TOL).unwrap();
    let back = offset_curve2(&out, 90.0, TOL).unwrap();
    let there = one_sided_gap(&back, &profile, 2000);
    let and_back = one_sided_gap(&profile, &back, 2000);
    eprintln!("round trip: {there:.2e} mm / {and_back:.2e} mm");
    assert!(
        there <= 2.0 * TOL && and_back <= 2.0 * TOL,
        "{there} {and_back}"
    );
    assert!(back.is_closed());
}

#[test]
fn the_designers_bead_line_outside_the_rear_and_front_sides() {
    let text = format!(
        "{}\nlet rear_front = between(punch_profile, (-660, 300), (-300, -480))\nlet bead_line = offset(rear_front, -90 mm)",
        fender_profile_text()
    );
    let v = evaluate(&text);
    let profile = flat(&value(&v, "punch_profile"));
    let stretch = flat(&value(&v, "rear_front"));
    let Data::Curve2(line) = value(&v, "bead_line") else {
        panic!("the offset of a 2-D stretch is a 2-D curve")
    };
    // 90 mm outside the stretch everywhere, starting and ending on its normals.
    let worst = worst_distance_error(&stretch, &line, -90.0, 2000);
    assert!(worst <= TOL, "{worst}");
    let (t0, t1) = stretch.domain();
    let out = |t: f64| stretch.point_at(t) - stretch.derivative_at(t).normalize().perp() * 90.0;
    assert!(line.start_point().distance(out(t0)) < 1e-9);
    assert!(line.end_point().distance(out(t1)) < 1e-9);
    // Outside the opening.
    let outline = samples(&profile, 4000);
    assert!(samples(&line, 500).iter().all(|&p| !inside(&outline, p)));
    // The stretch is part of the profile and runs over its seam.
    assert!(one_sided_gap(&stretch, &profile, 1000) < 1e-9);
    assert!(
        closest_point_on_curve(&stretch, profile.start_point())
            .unwrap()
            .distance
            < 1e-9
    );
}

// ---- small turns, refusals ------------------------------------------------------------------

#[test]
fn small_turns_below_half_a_degree_are_joined_exactly() {
    // A polyline bending by 0.23 deg, and by 0.001 deg (an arc of 0.001 mm at 50 mm):
    // an arc around the corner outside, the offsets cut where they cross inside.
    for rise in [2.0, 0.01] {
        let pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(500.0, 0.0),
            DVec2::new(1000.0, rise),
        ];
        let bent = Curve2::new(1, vec![0.0, 0.0, 0.5, 1.0, 1.0], pts).unwrap();
        for d in [50.0, -50.0] {
            let off = offset_curve2(&bent, d, TOL).unwrap();
            let worst = worst_distance_error(&bent, &off, d, 4000);
            assert!(worst <= TOL, "{rise} {d}: {worst}");
        }
    }
}

#[test]
fn a_sharp_corner_is_refused_with_where_it_is() {
    let pts = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(400.0, 0.0),
        DVec2::new(400.0, 300.0),
    ];
    let ell = Curve2::new(1, vec![0.0, 0.0, 0.5, 1.0, 1.0], pts).unwrap();
    match offset_curve2(&ell, -90.0, TOL) {
        Err(GeomError::SharpCorner { at, turn, .. }) => {
            assert_eq!(at, (400.0, 0.0));
            assert!((turn - PI / 2.0).abs() < 1e-12);
        }
        other => panic!("{other:?}"),
    }
    // Just above the limit is a corner; the seam of a closed curve counts too.
    let square = evaluate(
        "let s = sketch(top) { from (0, 0); line to (100, 0); line to (100, 100); line to (0, 100); close }",
    );
    assert!(matches!(
        offset_curve2(&flat(&value(&square, "s")), 10.0, TOL),
        Err(GeomError::SharpCorner { .. })
    ));
    let a = CORNER_ANGLE * 1.01;
    let kink = Curve2::new(
        1,
        vec![0.0, 0.0, 0.5, 1.0, 1.0],
        vec![
            DVec2::ZERO,
            DVec2::new(100.0, 0.0),
            DVec2::new(100.0, 0.0) + DVec2::from_angle(a) * 100.0,
        ],
    )
    .unwrap();
    assert!(matches!(
        offset_curve2(&kink, 10.0, TOL),
        Err(GeomError::SharpCorner { .. })
    ));
    let msgs = messages("let s = sketch(top) { from (0, 0); line to (400, 0); line to (400, 300) }\nlet o = offset(s, -90 mm)");
    assert!(
        msgs[0].starts_with("die::bad_argument: the curve has a sharp corner at (400, 0)"),
        "{msgs:?}"
    );
}

#[test]
fn a_distance_at_or_beyond_an_inside_radius_is_refused() {
    let circle = dieface::geom::arc::circle(DVec2::ZERO, DVec2::X, DVec2::Y, 50.0).unwrap();
    for d in [50.0, 60.0] {
        match offset_curve2(&circle, d, TOL) {
            Err(GeomError::OffsetFolds { radius, .. }) => assert!((radius - 50.0).abs() < 1e-6),
            other => panic!("{d}: {other:?}"),
        }
    }
    // Outside there is no limit; just inside the radius is fine.
    assert!(offset_curve2(&circle, -500.0, TOL).is_ok());
    let tight = offset_curve2(&circle, 49.0, TOL).unwrap();
    for p in samples(&tight, 1000) {
        assert!((p.length() - 1.0).abs() <= TOL);
    }
    // The fender's smallest fillets are 110 mm: 110 mm inside folds at one of them.
    match offset_curve2(&fender_profile(), 110.0, TOL) {
        Err(GeomError::OffsetFolds { radius, at, .. }) => {
            assert!((radius - 110.0).abs() < 1e-6, "{radius}");
            let at = DVec2::new(at.0, at.1);
            let corners = [DVec2::new(-680.0, -470.0), DVec2::new(-660.0, 470.0)];
            assert!(corners.iter().any(|c| at.distance(*c) < 110.0), "{at}");
        }
        other => panic!("{other:?}"),
    }
    let msgs = messages("let o = offset(circle((0, 0), 50 mm), 60 mm)");
    assert!(msgs[0].contains("radius of 50 mm"), "{msgs:?}");
}

#[test]
fn an_offset_running_into_another_part_of_the_curve_is_refused() {
    // A U whose legs close in: 250 mm apart at the open end, radii 200 mm. 150 mm inside
    // fits every turn but the two legs' offsets cross near the open end.
    let v = evaluate(
        "let u = sketch(top) { from (0, 0); line to (1000, 0); fillet 200; line to (1000, 600); fillet 200; line to (0, 250) }",
    );
    let u = flat(&value(&v, "u"));
    assert!(matches!(
        offset_curve2(&u, 150.0, TOL),
        Err(GeomError::OffsetOverlaps { .. })
    ));
    assert!(offset_curve2(&u, 100.0, TOL).is_ok());
}

#[test]
fn bad_arguments_are_diagnosed() {
    let m = messages("let o = offset(line_between((0, 0), (100, 0)), 5 deg)");
    assert!(
        m[0].starts_with("die::type_mismatch: `distance` of `offset` must be a length"),
        "{m:?}"
    );
    let m = messages("let o = offset(line_between((0, 0, 0), (100, 0, 0)), 5 mm)");
    assert!(
        m[0].starts_with("die::type_mismatch: `curve` of `offset` must be a 2-D curve or a sketch"),
        "{m:?}"
    );
    let m = messages("let b = between(circle((0, 0), 50 mm), (0, 0, 0), (1, 1))");
    assert!(m[0].starts_with("die::type_mismatch"), "{m:?}");
    assert!(matches!(
        offset_curve2(&Curve2::line(DVec2::ZERO, DVec2::X).unwrap(), f64::NAN, TOL),
        Err(GeomError::NotFinite { .. })
    ));
    // Offsetting by nothing gives the curve back.
    let line = Curve2::line(DVec2::ZERO, DVec2::X).unwrap();
    assert_eq!(offset_curve2(&line, 0.0, TOL).unwrap(), line);
}

// ---- between ------------------------------------------------------------------------------

#[test]
fn between_on_a_closed_curve_wraps_over_the_seam() {
    let profile = fender_profile();
    let (t0, t1) = profile.domain();
    let (from, to) = (DVec2::new(-660.0, 300.0), DVec2::new(-300.0, -480.0));
    let a = closest_point_on_curve(&profile, from).unwrap();
    let b = closest_point_on_curve(&profile, to).unwrap();
    assert!(
        b.t < a.t,
        "`to` comes before `from` in the profile's parameter"
    );
    let s = curve_between(&profile, from, to).unwrap();
    assert!(s.start_point().distance(a.point) < 1e-9);
    assert!(s.end_point().distance(b.point) < 1e-9);
    // Its length is the profile's from `from` to the seam plus from the seam to `to`.
    let expected = profile.length_between(a.t, t1) + profile.length_between(t0, b.t);
    assert!(
        (s.length() - expected).abs() < 1e-6,
        "{} vs {expected}",
        s.length()
    );
    // The same parameter speed as the profile on both sides of the seam.
    assert!((s.domain().0 - a.t).abs() < 1e-12);
    assert!((s.domain().1 - (t1 + b.t - t0)).abs() < 1e-12);
    let mid = s.point_at(t1 + 0.5 * (b.t - t0));
    assert!(mid.distance(profile.point_at(t0 + 0.5 * (b.t - t0))) < 1e-9);

    // The other way round: no seam, the rest of the loop.
    let rest = curve_between(&profile, to, from).unwrap();
    assert!((rest.length() + s.length() - profile.length()).abs() < 1e-6);
    assert!(!rest.is_closed());

    // A point at the seam starts or ends a stretch there.
    let seam = profile.start_point();
    let to_seam = curve_between(&profile, from, seam).unwrap();
    assert!((to_seam.length() - profile.length_between(a.t, t1)).abs() < 1e-6);
    let from_seam = curve_between(&profile, seam, from).unwrap();
    assert!((from_seam.length() - profile.length_between(t0, a.t)).abs() < 1e-6);
}

#[test]
fn between_on_an_open_curve_and_its_errors() {
    let line = Curve2::line(DVec2::ZERO, DVec2::new(100.0, 0.0)).unwrap();
    let s = curve_between(&line, DVec2::new(20.0, 5.0), DVec2::new(70.0, -5.0)).unwrap();
    assert!(s.start_point().distance(DVec2::new(20.0, 0.0)) < 1e-9);
    assert!(s.end_point().distance(DVec2::new(70.0, 0.0)) < 1e-9);
    // Past the end: the end.
    let s = curve_between(&line, DVec2::new(20.0, 5.0), DVec2::new(170.0, 0.0)).unwrap();
    assert!(s.end_point().distance(DVec2::new(100.0, 0.0)) < 1e-9);
    // Backwards on an open curve.
    assert!(matches!(
        curve_between(&line, DVec2::new(70.0, 0.0), DVec2::new(20.0, 0.0)),
        Err(GeomError::StretchBackwards { .. })
    ));
    // Both on one normal: the same place.
    match curve_between(&line, DVec2::new(40.0, 10.0), DVec2::new(40.0, -30.0)) {
        Err(GeomError::SameProjection { at, .. }) => {
            assert!(DVec2::new(at.0, at.1).distance(DVec2::new(40.0, 0.0)) < 1e-9)
        }
        other => panic!("{other:?}"),
    }
    // On a closed curve too, also both at the seam.
    let circle = dieface::geom::arc::circle(DVec2::ZERO, DVec2::X, DVec2::Y, 50.0).unwrap();
    assert!(matches!(
        curve_between(&circle, DVec2::new(80.0, 0.0), DVec2::new(50.0, -1e-12)),
        Err(GeomError::SameProjection { .. })
    ));
    // Through the language.
    let m = messages("let b = between(circle((0, 0), 50 mm), (0, 60), (0, 70))");
    assert!(
        m[0].starts_with("die::bad_argument: `from` and `to` both project to (0, 50)"),
        "{m:?}"
    );
    let m = messages("let b = between(line_between((0, 0), (100, 0)), (70, 0), (20, 0))");
    assert!(m[0].contains("comes before `from`"), "{m:?}");
    let v =
        evaluate("let b = between(circle((0, 0), 50 mm), (0, 60), (0, -70))\nlet n = length_of(b)");
    let Data::Number(n) = value(&v, "n") else {
        panic!()
    };
    assert!((n.value - 50.0 * PI).abs() < 1e-6, "{}", n.value);
}

// ---- property -------------------------------------------------------------------------------

/// A smooth open cubic through 4 to 8 points marching along x with random heights
/// (some turn back on themselves in tight hooks).
fn smooth_curve() -> impl Strategy<Value = Curve2> {
    prop::collection::vec((60.0..160.0f64, -100.0..100.0f64), 4..9).prop_map(|steps| {
        let mut x = 0.0;
        let pts: Vec<DVec2> = steps
            .iter()
            .map(|&(dx, y)| {
                x += dx;
                DVec2::new(x, y)
            })
            .collect();
        interpolate(&pts, &Interpolation::default()).expect("distinct points")
    })
}

/// The smallest radius of curvature, sampled densely.
fn min_radius(c: &Curve2) -> f64 {
    let (t0, t1) = c.domain();
    (0..=20_000)
        .map(|k| c.curvature(t0 + (t1 - t0) * k as f64 / 20_000.0))
        .fold(0.0, f64::max)
        .recip()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn smooth_curves_offset_below_their_smallest_radius_stay_at_the_distance(
        c in smooth_curve(),
        fraction in 0.05..0.95f64,
        left in any::<bool>(),
    ) {
        let d = fraction * min_radius(&c).min(200.0) * if left { 1.0 } else { -1.0 };
        match offset_curve2(&c, d, TOL) {
            Ok(off) => {
                let worst = worst_distance_error(&c, &off, d, 1000);
                prop_assert!(worst <= TOL, "d = {d}: off by {worst}");
            }
            // A curve that comes back near itself may be narrower than twice the
            // distance somewhere: that refusal is right.
            Err(GeomError::OffsetOverlaps { .. }) => {}
            Err(e) => prop_assert!(false, "d = {d}: {e}"),
        }
    }
}

#[test]
fn the_fender_bead_drawn_by_hand_is_the_offset_and_a_bead_takes_the_offset() {
    // The fender's `rear_corner` bead line was drawn by hand 90 mm outside the rear and
    // front sides, its points rounded to 0.1 mm.
    let v = evaluate(&format!(
        "{}\nlet by_hand = sketch(top) {{ from (-753.6, 300); line to (-771.9, -559.3); fillet 200; line to (-300, -562.8) }}\nlet by_offset = offset(between(punch_profile, (-660, 300), (-300, -480)), -90 mm)",
        fender_profile_text()
    ));
    let (hand, off) = (flat(&value(&v, "by_hand")), flat(&value(&v, "by_offset")));
    // The offset starts and ends on the sides' normals through the picked points'
    // projections, the hand-drawn line at the picked y and x: up to 2 mm apart along
    // the tilted sides. In between they agree to the rounding of the hand-drawn points.
    let m = Measure::new(&off);
    let (t0, t1) = hand.domain();
    let inner = (10..=990)
        .map(|k| m.distance(hand.point_at(t0 + (t1 - t0) * k as f64 / 1000.0)))
        .fold(0.0, f64::max);
    let ends = [
        off.start_point().distance(hand.start_point()),
        off.end_point().distance(hand.end_point()),
    ];
    eprintln!("hand-drawn bead line vs offset: {inner:.3} mm across, ends {ends:.3?} mm apart");
    assert!(inner < 0.1, "{inner}");
    assert!(ends.iter().all(|&e| e < 2.5), "{ends:?}");

    // As a bead's `line` on the fender's blankholder.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(root.join("fender/fender.die")).expect("the fender");
    let text = format!(
        "{text}\nbead rear_offset {{\n    binder = binder\n    line = offset(between(punch_profile, (-660, 300), (-300, -480)), -90 mm)\n    profile = bead_round\n    taper = 30 mm\n}}\n"
    );
    let mut engine = Engine::new(Some(root.clone()));
    let out = engine.evaluate(
        "fender/with_offset_bead.die",
        &text,
        Some(root.join("fender")),
    );
    let rendered: Vec<String> = out
        .diagnostics
        .iter()
        .map(|d| engine.sources.render(d, false))
        .collect();
    assert!(rendered.is_empty(), "{}", rendered.join("\n"));
    let length = |name: &str| {
        let d = out.decls.iter().find(|d| d.name == name).expect(name);
        let Some(Data::Record(r)) = d.value.as_ref().map(|v| &v.data) else {
            panic!("{name} is not a record")
        };
        let Some(Data::Record(q)) = r.get("quality").map(|v| &v.data) else {
            panic!("{name} has no quality")
        };
        let Some(Data::Number(l)) = q.get("length").map(|v| &v.data) else {
            panic!("{name} has no length")
        };
        l.value
    };
    let (a, b) = (length("rear_offset"), length("rear_corner"));
    eprintln!("bead centre lines on the binder: {a:.3} mm by offset, {b:.3} mm by hand");
    // The same course but for the ends (above): the lengths differ by what the ends do.
    assert!((a - b).abs() < 2.5, "{a} {b}");
}
