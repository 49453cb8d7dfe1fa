//! The punch opening line (paper 001 sections 3.1-3.2; GitHub issue 5): the figures a reviewer
//! checks, measured on the fender example through the language and on hand-checkable
//! inputs built with the kernel API.
//!
//! Every figure is measured here from the built curves and the designer's drawings, at
//! 10,000 samples per piece, independently of the figures the kernel stores (which are
//! cross-checked, not trusted). Run with `--nocapture` to see the worst figures.

#[path = "common/square.rs"]
mod square;

#[path = "common/fender.rs"]
mod fender_example;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::Arc;

use dieface::die::punch_opening::{
    self as po, natural_magnitude, side_quality, PieceKind, PieceQuality, PieceSpec, Problem,
    PunchOpening, PunchOpeningSpec, SideSpec, SideView,
};
use dieface::eval::sketch::View;
use dieface::eval::{Data, Value};
use dieface::geom::arc::{circular_arc, Circle};
use dieface::geom::{Curve2, Curve3};
use fender_example::fender_values;
use glam::{DVec2, DVec3};
use square::*;

/// Samples per piece for every measured figure.
const SAMPLES: usize = 10_000;

/// The G1 bound at the corners' ends (degrees).
const CORNER_ANGLE_DEG: f64 = 0.01;

fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// The point of `c` at fraction `i / SAMPLES` of its domain.
fn sample<P: dieface::geom::Point>(c: &dieface::geom::NurbsCurve<P>, i: usize) -> P {
    let (a, b) = c.domain();
    c.point_at(a + (b - a) * i as f64 / SAMPLES as f64)
}

/// Distance from `p` to the segment `a b`.
fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let f = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    p.distance(a + ab * f)
}

/// Whether all control points of a top-view piece lie on the line through its ends: a
/// straight side.
fn is_straight(top: &Curve2) -> bool {
    let (a, b) = (top.start_point(), top.end_point());
    top.control_points()
        .iter()
        .all(|&p| distance_to_segment(p, a, b) <= 1e-9 * (1.0 + a.length()))
}

/// The circle a top-view fillet lies on, from three of its points.
fn fillet_circle(top: &Curve2) -> Circle<DVec2> {
    let (a, b) = top.domain();
    Circle::through(
        top.point_at(a),
        top.point_at(0.5 * (a + b)),
        top.point_at(b),
    )
    .expect("a fillet is a circular arc")
}

/// The height of the side-view curve at `s` along its axis (bisection on its first
/// coordinate, which is monotone for a side view).
fn view_height(view: &Curve2, s: f64) -> f64 {
    let (mut lo, mut hi) = view.domain();
    let increasing = view.end_point().x > view.start_point().x;
    let (xlo, xhi) = if increasing {
        (view.start_point().x, view.end_point().x)
    } else {
        (view.end_point().x, view.start_point().x)
    };
    assert!(
        (xlo..=xhi).contains(&s),
        "the side view ({xlo}..{xhi}) does not reach {s}"
    );
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if (view.point_at(mid).x < s) == increasing {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    view.point_at(0.5 * (lo + hi)).y
}

/// Measured figures of one side against its two drawings.
#[derive(Debug, Default, Clone, Copy)]
struct SideFigures {
    /// Largest distance (mm) from the (x, y) projection to the straight top-view piece.
    top: f64,
    /// Largest height difference (mm) between the side and its side view at the same
    /// position along the view's axis: an upper bound of the distance to the view.
    side_vertical: f64,
    /// The kernel's `side_quality` at `SAMPLES`: top and side deviation.
    kernel: (f64, f64),
}

/// Measures a side (straight in the top view) against its top view and side view.
fn measure_side(curve: &Curve3, spec: &SideSpec) -> SideFigures {
    assert!(
        is_straight(&spec.top),
        "side `{}` is not straight",
        spec.name
    );
    let (a, b) = (spec.top.start_point(), spec.top.end_point());
    let mut f = SideFigures::default();
    for i in 0..=SAMPLES {
        let p = sample(curve, i);
        f.top = f.top.max(distance_to_segment(p.truncate(), a, b));
        let s = (p.truncate() - spec.view.origin).dot(spec.view.axis);
        f.side_vertical = f
            .side_vertical
            .max((p.z - view_height(&spec.view.curve, s)).abs());
    }
    let q = side_quality(curve, spec, SAMPLES).expect("side quality");
    f.kernel = (q.top_deviation, q.side_deviation);
    f
}

/// Measured figures of one corner.
#[derive(Debug, Default, Clone, Copy)]
struct CornerFigures {
    /// Angles (degrees) between the previous side's end tangent and the corner's start
    /// tangent, and between the corner's end tangent and the next side's start tangent.
    angles: (f64, f64),
    /// Relative errors of the end-derivative lengths against the asked magnitudes.
    magnitude_errors: (f64, f64),
    /// The asked magnitudes (mm).
    asked: (f64, f64),
    /// Largest distance (mm) from the (x, y) projection to the fillet's circle.
    top: f64,
}

/// Measures corner `k` of `opening`, asked for `factor` times the natural magnitude.
fn measure_corner(opening: &PunchOpening, k: usize, factor: (f64, f64)) -> CornerFigures {
    let n = opening.pieces.len();
    let (prev, corner, next) = (
        &opening.pieces[(k + n - 1) % n],
        &opening.pieces[k],
        &opening.pieces[(k + 1) % n],
    );
    assert_eq!(prev.kind, PieceKind::Side);
    assert_eq!(corner.kind, PieceKind::Corner);
    assert_eq!(next.kind, PieceKind::Side);
    let c = &corner.curve;
    assert_eq!(c.domain(), (0.0, 1.0));
    let (p0, p3) = (prev.curve.end_point(), next.curve.start_point());
    // G0 with the sides.
    assert!(
        c.start_point().distance(p0) <= 1e-9,
        "{} start",
        corner.name
    );
    assert!(c.end_point().distance(p3) <= 1e-9, "{} end", corner.name);
    let (t_in, t_out) = (prev.curve.derivative_at(1.0), next.curve.derivative_at(0.0));
    let (d0, d1) = (c.derivative_at(0.0), c.derivative_at(1.0));
    let natural = natural_magnitude(p0, p3, t_in, t_out);
    let asked = (factor.0 * natural, factor.1 * natural);
    let circle = fillet_circle(&corner.top);
    let mut top: f64 = 0.0;
    for i in 0..=SAMPLES {
        let p = sample(c, i).truncate();
        top = top.max((p.distance(circle.center) - circle.radius).abs());
    }
    CornerFigures {
        angles: (angle_deg(t_in, d0), angle_deg(d1, t_out)),
        magnitude_errors: (
            (d0.length() - asked.0).abs() / asked.0,
            (d1.length() - asked.1).abs() / asked.1,
        ),
        asked,
        top,
    }
}

/// Checks the pieces of `opening` follow each other (G0) and that the joined line
/// passes through them.
fn check_closed(opening: &PunchOpening) -> f64 {
    let n = opening.pieces.len();
    let mut worst: f64 = 0.0;
    for k in 0..n {
        let (a, b) = (&opening.pieces[k].curve, &opening.pieces[(k + 1) % n].curve);
        worst = worst.max(a.end_point().distance(b.start_point()));
    }
    assert!(worst <= 1e-9, "pieces are {worst} mm apart");
    assert!(
        opening
            .line
            .start_point()
            .distance(opening.line.end_point())
            <= 1e-9,
        "the line is not closed"
    );
    // The joined line runs through piece `k` on [k, k + 1].
    for (k, piece) in opening.pieces.iter().enumerate() {
        for i in 0..=100 {
            let f = i as f64 / 100.0;
            let off = opening
                .line
                .point_at(k as f64 + f)
                .distance(piece.curve.point_at(f));
            assert!(
                off <= 1e-9,
                "the line is {off} mm off {} at {f}",
                piece.name
            );
        }
    }
    worst
}

// ---------------------------------------------------------------------------------
// The fender example, through the language.
// ---------------------------------------------------------------------------------

struct Fender {
    opening: Arc<PunchOpening>,
    values: Vec<(String, Value)>,
}

impl Fender {
    fn value(&self, name: &str) -> &Value {
        &self
            .values
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("the fender has no `{name}`"))
            .1
    }

    fn length(&self, name: &str) -> f64 {
        match &self.value(name).data {
            Data::Number(q) => q.value,
            other => panic!("`{name}` is {}", other.type_name()),
        }
    }

    /// The side-view sketch `name` as a kernel side view.
    fn side_view(&self, name: &str) -> SideView {
        let Data::Sketch(s) = &self.value(name).data else {
            panic!("`{name}` is not a sketch");
        };
        let axis = match s.view {
            View::SideXZ => DVec2::X,
            View::SideYZ => DVec2::Y,
            _ => panic!("`{name}` is not drawn in side_xz or side_yz"),
        };
        SideView {
            origin: DVec2::ZERO,
            axis,
            curve: s.curve.clone(),
        }
    }
}

fn fender() -> Fender {
    let values = fender_values();
    let opening = values
        .iter()
        .find_map(|(name, v)| match &v.data {
            Data::Record(r) if name == "opening" => r
                .feature
                .as_ref()
                .and_then(|f| f.shared::<dieface::die::punch_opening::PunchOpening>()),
            _ => None,
        })
        .expect("`opening` is a punch opening");
    Fender { opening, values }
}

/// Issue 5, punch opening of the fender: each side projects onto its top view and its
/// side view within `delta` at 10,000 samples; corners are G1 with their sides within
/// 0.01 deg and have the asked end-derivative magnitudes.
#[test]
fn fender_punch_opening_meets_its_drawings() {
    let fender = fender();
    let opening = &fender.opening;
    let delta = fender.length("delta");
    assert_eq!(delta, 0.01, "the script's delta is 0.01 mm");
    assert_eq!(opening.delta, delta);
    assert!(
        opening.counter_clockwise,
        "the profile is drawn counter-clockwise"
    );
    let names: Vec<&str> = opening.pieces.iter().map(|p| p.name.as_str()).collect();
    eprintln!("fender pieces: {names:?}");
    let sides = ["front", "nose", "top", "rear"];
    for s in sides {
        assert!(names.contains(&s), "no side `{s}`");
    }
    assert_eq!(opening.pieces.len(), 8, "four sides and four corners");
    check_closed(opening);

    // Sides.
    let (mut top_worst, mut side_worst) = (0.0f64, 0.0f64);
    for (k, piece) in opening.pieces.iter().enumerate() {
        if piece.kind != PieceKind::Side {
            continue;
        }
        let spec = SideSpec {
            name: piece.name.clone(),
            top: piece.top.clone(),
            view: fender.side_view(&format!("wrap_{}", piece.name)),
        };
        let f = measure_side(&piece.curve, &spec);
        eprintln!(
            "side {:>5}: top-view deviation {:.3e} mm, side-view height deviation {:.3e} mm \
             (kernel side_quality @{SAMPLES}: top {:.3e}, side {:.3e})",
            piece.name, f.top, f.side_vertical, f.kernel.0, f.kernel.1
        );
        assert!(
            f.top <= delta,
            "side {} strays {} mm from its top view",
            piece.name,
            f.top
        );
        assert!(
            f.side_vertical <= delta,
            "side {} strays {} mm from its side view",
            piece.name,
            f.side_vertical
        );
        assert!(f.kernel.0 <= delta && f.kernel.1 <= delta, "{f:?}");
        // The distance to the view is at most the height difference.
        assert!(f.kernel.1 <= f.side_vertical + 1e-9, "{f:?}");
        // The stored figures (1,000 samples) agree with these.
        let PieceQuality::Side(q) = opening.quality[k] else {
            panic!("piece {k} has no side quality");
        };
        assert!(q.top_deviation <= f.kernel.0 + 1e-9 && q.side_deviation <= f.kernel.1 + 1e-9);
        assert!(q.points >= 2);
        top_worst = top_worst.max(f.top);
        side_worst = side_worst.max(f.side_vertical);
    }

    // Corners: `corners { tangent = 100 % }`, `corner front_nose { tangent = 90 % }`.
    let (mut angle_worst, mut mag_worst, mut corner_top_worst) = (0.0f64, 0.0f64, 0.0f64);
    let mut corners = 0;
    for (k, piece) in opening.pieces.iter().enumerate() {
        if piece.kind != PieceKind::Corner {
            continue;
        }
        corners += 1;
        let factor = if piece.name == "front_nose" { 0.9 } else { 1.0 };
        let f = measure_corner(opening, k, (factor, factor));
        eprintln!(
            "corner {:>10}: angles {:.2e} / {:.2e} deg, asked {:.3} / {:.3} mm, magnitude \
             errors {:.1e} / {:.1e}, top-view deviation {:.3e} mm",
            piece.name,
            f.angles.0,
            f.angles.1,
            f.asked.0,
            f.asked.1,
            f.magnitude_errors.0,
            f.magnitude_errors.1,
            f.top
        );
        assert!(
            f.angles.0 <= CORNER_ANGLE_DEG && f.angles.1 <= CORNER_ANGLE_DEG,
            "{f:?}"
        );
        assert!(
            f.magnitude_errors.0 <= 1e-9 && f.magnitude_errors.1 <= 1e-9,
            "{f:?}"
        );
        assert!(
            f.top <= delta,
            "corner {} strays {} mm from its fillet",
            piece.name,
            f.top
        );
        let PieceQuality::Corner(q) = opening.quality[k] else {
            panic!("piece {k} has no corner quality");
        };
        assert!(
            (q.asked.0 - f.asked.0).abs() <= 1e-9 * f.asked.0,
            "{q:?} {f:?}"
        );
        assert!(
            (q.asked.1 - f.asked.1).abs() <= 1e-9 * f.asked.1,
            "{q:?} {f:?}"
        );
        angle_worst = angle_worst.max(f.angles.0).max(f.angles.1);
        mag_worst = mag_worst
            .max(f.magnitude_errors.0)
            .max(f.magnitude_errors.1);
        corner_top_worst = corner_top_worst.max(f.top);
    }
    assert_eq!(corners, 4);
    // The tauter corner really is tauter: 90 % of its own natural magnitude.
    let k = names.iter().position(|&n| n == "front_nose").unwrap();
    let f = measure_corner(opening, k, (0.9, 0.9));
    let natural = f.asked.0 / 0.9;
    let d0 = opening.pieces[k].curve.derivative_at(0.0).length();
    assert!(
        (d0 / natural - 0.9).abs() <= 1e-9,
        "front_nose at {} of natural",
        d0 / natural
    );
    println!(
        "fender punch opening @{SAMPLES} samples: worst side top-view {top_worst:.3e} mm, \
         side-view {side_worst:.3e} mm, corner top-view {corner_top_worst:.3e} mm, corner \
         angle {angle_worst:.2e} deg, magnitude error {mag_worst:.1e} (delta {delta} mm)"
    );
}

// ---------------------------------------------------------------------------------
// Synthetic, hand-checkable inputs.
// ---------------------------------------------------------------------------------

/// Case (a): straight flat sides, corners on their quarter circles; the natural
/// magnitude of a quarter circle is its arc length, pi R / 2.
#[test]
fn square_opening_with_fillets_is_flat_and_round() {
    let spec = square();
    let opening = po::build(&spec).unwrap();
    assert!(opening.counter_clockwise);
    check_closed(&opening);
    let quarter = PI * RADIUS / 2.0;
    let (mut off_line, mut off_circle, mut height) = (0.0f64, 0.0f64, 0.0f64);
    let (mut angle_worst, mut mag_worst) = (0.0f64, 0.0f64);
    for (k, (piece, piece_spec)) in opening.pieces.iter().zip(&spec.pieces).enumerate() {
        for i in 0..=SAMPLES {
            height = height.max(sample(&piece.curve, i).z.abs());
        }
        match piece_spec {
            PieceSpec::Side(s) => {
                let f = measure_side(&piece.curve, s);
                off_line = off_line.max(f.top);
                assert!(f.side_vertical <= 1e-9, "{f:?}");
                // The whole side: its ends are the drawn ends.
                assert!(
                    piece
                        .curve
                        .start_point()
                        .distance(s.top.start_point().extend(0.0))
                        <= 1e-9
                );
                assert!(
                    piece
                        .curve
                        .end_point()
                        .distance(s.top.end_point().extend(0.0))
                        <= 1e-9
                );
            }
            PieceSpec::Corner(_) => {
                let f = measure_corner(&opening, k, (1.0, 1.0));
                assert!((f.asked.0 - quarter).abs() <= 1e-9 * quarter, "{f:?}");
                assert!((f.asked.1 - quarter).abs() <= 1e-9 * quarter, "{f:?}");
                off_circle = off_circle.max(f.top);
                angle_worst = angle_worst.max(f.angles.0).max(f.angles.1);
                mag_worst = mag_worst
                    .max(f.magnitude_errors.0)
                    .max(f.magnitude_errors.1);
            }
        }
    }
    eprintln!(
        "square: sides off their lines {off_line:.2e} mm, corners off R {RADIUS} \
         {off_circle:.3e} mm, |z| {height:.1e} mm, corner angles {angle_worst:.1e} deg, \
         magnitude errors {mag_worst:.1e}"
    );
    assert!(off_line <= 1e-9, "a side is not straight: {off_line} mm");
    assert!(
        height <= 1e-9,
        "the flat opening leaves z = 0 by {height} mm"
    );
    assert!(
        off_circle <= DELTA,
        "a corner strays {off_circle} mm from its fillet"
    );
    assert!(angle_worst <= CORNER_ANGLE_DEG && mag_worst <= 1e-9);
}

/// The bottom side of the square split at x = 0 into two collinear sides, each with its
/// own side view: `left_view` is an arc of radius 5000 tangent to z = 0 at x = 0,
/// `right_view` the line z = `right_z` (agreeing with the arc at x = 0, in value and
/// slope, when `right_z` is 0).
fn split_bottom(right_z: f64) -> PunchOpeningSpec {
    let s = HALF - RADIUS;
    let big = 5000.0;
    // z = big - sqrt(big^2 - x^2) for x in [-250, 50], drawn in +x.
    let (a0, a1) = ((-250.0f64 / big).asin(), (50.0f64 / big).asin());
    let arc = circular_arc(
        DVec2::new(0.0, big),
        DVec2::X,
        DVec2::Y,
        big,
        -FRAC_PI_2 + a0,
        -FRAC_PI_2 + a1,
    )
    .unwrap();
    let left_view = SideView {
        origin: DVec2::ZERO,
        axis: DVec2::X,
        curve: arc,
    };
    let right_view = SideView {
        origin: DVec2::ZERO,
        axis: DVec2::X,
        curve: line2((-50.0, right_z), (250.0, right_z)),
    };
    square_with_bottom(vec![
        side("bottom_a", line2((-s, -HALF), (0.0, -HALF)), left_view),
        side("bottom_b", line2((0.0, -HALF), (s, -HALF)), right_view),
    ])
}

/// Case (b): two collinear sides meeting without a corner, their views agreeing at the
/// shared point: the line is G1 there and each side still follows its two views.
#[test]
fn sides_meeting_without_a_corner_are_g1() {
    let spec = split_bottom(0.0);
    let opening = po::build(&spec).unwrap();
    check_closed(&opening);
    let (a, b) = (&opening.pieces[0], &opening.pieces[1]);
    assert_eq!((a.name.as_str(), b.name.as_str()), ("bottom_a", "bottom_b"));
    let shared = a.curve.end_point();
    assert!(
        shared.distance(DVec3::new(0.0, -HALF, 0.0)) <= DELTA,
        "{shared}"
    );
    let angle = angle_deg(a.curve.derivative_at(1.0), b.curve.derivative_at(0.0));
    let mut worst = SideFigures::default();
    for (piece, piece_spec) in opening.pieces.iter().zip(&spec.pieces).take(2) {
        let PieceSpec::Side(s) = piece_spec else {
            unreachable!()
        };
        let f = measure_side(&piece.curve, s);
        worst.top = worst.top.max(f.top);
        worst.side_vertical = worst.side_vertical.max(f.side_vertical);
    }
    eprintln!(
        "split side: tangent angle at the shared point {angle:.2e} deg, top-view deviation \
         {:.2e} mm, side-view height deviation {:.3e} mm",
        worst.top, worst.side_vertical
    );
    assert!(angle <= CORNER_ANGLE_DEG, "the line kinks by {angle} deg");
    assert!(
        worst.top <= DELTA && worst.side_vertical <= DELTA,
        "{worst:?}"
    );
    // The arc side really rises away from the join (the test is not flat by accident).
    assert!(a.curve.start_point().z > 2.0, "{}", a.curve.start_point());
}

/// Case (c): the same sides with views 0.05 mm apart at the shared point (more than
/// delta) cannot meet; 0.005 mm apart (less than delta) they can.
#[test]
fn sides_whose_views_disagree_are_refused() {
    let err = po::build(&split_bottom(0.05)).unwrap_err();
    match err.problem {
        Problem::SidesDisagree { gap } => {
            eprintln!(
                "views 0.05 mm apart: SidesDisagree {{ gap: {gap:.6} }} at piece {}",
                err.piece
            );
            assert!((gap - 0.05).abs() <= 1e-6, "gap {gap}");
        }
        other => panic!("expected SidesDisagree, got {other:?}"),
    }
    assert_eq!(err.piece, 1, "the second of the two sides is blamed");
    let ok = po::build(&split_bottom(0.005)).unwrap();
    let (a, b) = (&ok.pieces[0].curve, &ok.pieces[1].curve);
    assert!(a.end_point().distance(b.start_point()) <= 1e-12);
}
