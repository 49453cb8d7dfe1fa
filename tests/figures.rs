//! The die engineer's figures (`die::figures`) on shapes whose figures are known in
//! closed form: a cylinder and a rounded step for radius, a cone and an overhanging
//! wall for draft, two planes at a known angle for crease and gap, a parabola for sag.

use std::f64::consts::FRAC_PI_2;

use dieface::die::figures::{
    edge_samples, seam, section_sag, surface_figures, Edge, Facing, SectionEnd, UNDERCUT_TOLERANCE,
};
use dieface::geom::arc::circular_arc;
use dieface::geom::construct::{revolve, ruled};
use dieface::geom::{Curve3, Direction, NurbsSurface};
use glam::DVec3;
use proptest::prelude::*;

/// A polyline as a degree-1 curve.
fn polyline(points: &[DVec3]) -> Curve3 {
    let n = points.len();
    let mut knots = vec![0.0, 0.0];
    knots.extend((1..n - 1).map(|i| i as f64 / (n - 1) as f64));
    knots.extend([1.0, 1.0]);
    Curve3::new(1, knots, points.to_vec()).expect("a valid polyline")
}

/// The profile `curve` (in the XZ plane) extruded 50 mm along Y.
fn extrude(curve: &Curve3) -> NurbsSurface {
    let moved = curve.map_points(|p| p + DVec3::new(0.0, 50.0, 0.0));
    ruled(curve, &moved).expect("a valid extrusion")
}

/// The bilinear patch `origin + u du + v dv`, u and v in [0, 1].
fn square(origin: DVec3, du: DVec3, dv: DVec3) -> NurbsSurface {
    NurbsSurface::new(
        1,
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![0.0, 0.0, 1.0, 1.0],
        vec![
            vec![origin, origin + dv],
            vec![origin + du, origin + du + dv],
        ],
    )
    .expect("a valid bilinear patch")
}

#[test]
fn a_cylinder_has_its_radius_and_vertical_walls_without_undercut() {
    let axial = Curve3::line(DVec3::new(6.0, 0.0, 0.0), DVec3::new(6.0, 0.0, 30.0)).expect("line");
    let cylinder = revolve(&axial, DVec3::ZERO, DVec3::Z, FRAC_PI_2).expect("a cylinder");
    let f = surface_figures(&cylinder);
    assert!((f.min_radius - 6.0).abs() < 1e-9, "{f:?}");
    let r = f.min_radius_at.truncate().length();
    assert!(
        (r - 6.0).abs() < 1e-9,
        "the point lies on the cylinder: {f:?}"
    );
    assert!(
        f.draft.abs() < 1e-9,
        "a vertical wall has 0 deg draft: {f:?}"
    );
    assert!(
        !f.undercut,
        "a vertical wall measured to rounding is no undercut"
    );
}

#[test]
fn a_flat_patch_has_no_radius_and_90_degrees_of_draft() {
    let flat = square(DVec3::ZERO, DVec3::X * 10.0, DVec3::Y * 10.0);
    let f = surface_figures(&flat);
    assert!(f.min_radius.is_infinite(), "{f:?}");
    assert!((f.draft - 90.0).abs() < 1e-9, "{f:?}");
    // Facing down as a whole: judged with its normal turned up.
    let down = square(DVec3::ZERO, DVec3::Y * 10.0, DVec3::X * 10.0);
    let g = surface_figures(&down);
    assert!(
        g.flipped && (g.draft - 90.0).abs() < 1e-9 && !g.undercut,
        "{g:?}"
    );
}

#[test]
fn a_tight_round_between_two_walls_is_found_on_a_densely_knotted_profile() {
    // A step: floor, a 1.4 mm round, a wall up; the profile refined to 120 spans, as a
    // step-draw profile is fitted on a hundred.
    let r = 1.4;
    let round = circular_arc(
        DVec3::new(40.0, 0.0, r),
        DVec3::NEG_Z,
        DVec3::X,
        r,
        0.0,
        FRAC_PI_2,
    )
    .expect("an arc");
    let floor = Curve3::line(DVec3::ZERO, DVec3::new(40.0, 0.0, 0.0)).expect("line");
    let wall = Curve3::line(
        DVec3::new(40.0 + r, 0.0, r),
        DVec3::new(40.0 + r, 0.0, 30.0),
    )
    .expect("line");
    let profile = dieface::geom::join::join_curves(&[floor, round, wall])
        .expect("the pieces meet end to end");
    let (a, b) = profile.domain();
    let knots: Vec<f64> = (1..120)
        .map(|i| a + (b - a) * (i as f64 + 0.37) / 120.0)
        .collect();
    let profile = profile.refine(&knots).expect("refined");
    let s = extrude(&profile);
    let f = surface_figures(&s);
    assert!((f.min_radius - r).abs() < 1e-6, "{f:?}");
    let centre = DVec3::new(40.0, f.min_radius_at.y, r);
    assert!((f.min_radius_at.distance(centre) - r).abs() < 1e-6, "{f:?}");
}

#[test]
fn a_cone_has_its_wall_angle_as_draft_whichever_way_it_is_parametrized() {
    // Radius 10 at the foot to 5 at 20 mm up: the wall leans 14.04 deg from vertical.
    let line = Curve3::line(DVec3::new(10.0, 0.0, 0.0), DVec3::new(5.0, 0.0, 20.0)).expect("line");
    let cone = revolve(&line, DVec3::ZERO, DVec3::Z, FRAC_PI_2).expect("a cone");
    let want = (5.0f64 / 20.0).atan().to_degrees();
    for s in [cone.clone(), cone.reversed(Direction::U)] {
        let f = surface_figures(&s);
        assert!((f.draft - want).abs() < 1e-9, "{f:?} vs {want}");
        assert!(!f.undercut);
    }
}

#[test]
fn an_overhanging_wall_is_an_undercut_with_its_negative_draft() {
    // Floor to x = 40, a wall up and back to x = 35 (over the floor), then the top.
    let profile = polyline(&[
        DVec3::ZERO,
        DVec3::new(40.0, 0.0, 0.0),
        DVec3::new(35.0, 0.0, 20.0),
        DVec3::new(80.0, 0.0, 20.0),
    ]);
    let s = extrude(&profile);
    let f = surface_figures(&s);
    let want = -(5.0f64 / 20.0).atan().to_degrees();
    assert!(f.undercut, "{f:?}");
    assert!((f.draft - want).abs() < 1e-9, "{f:?} vs {want}");
    assert!(
        (35.0..=40.0).contains(&f.draft_at.x) && (0.0..=20.0).contains(&f.draft_at.z),
        "on the wall: {f:?}"
    );
    // Leaning the other way it is a wall with draft, no undercut.
    let fine = extrude(&polyline(&[
        DVec3::ZERO,
        DVec3::new(40.0, 0.0, 0.0),
        DVec3::new(45.0, 0.0, 20.0),
        DVec3::new(80.0, 0.0, 20.0),
    ]));
    let g = surface_figures(&fine);
    assert!(!g.undercut && (g.draft + want).abs() < 1e-9, "{g:?}");
    assert!(g.draft > UNDERCUT_TOLERANCE);
}

/// A flat square ending at `x = 10`, and a plane hinged there rising at `angle`
/// (radians), lifted by `lift` mm.
fn hinge(angle: f64, lift: f64, flip_b: bool) -> (NurbsSurface, NurbsSurface) {
    let a = square(DVec3::ZERO, DVec3::X * 10.0, DVec3::Y * 10.0);
    let rise = DVec3::new(angle.cos(), 0.0, angle.sin()) * 10.0;
    let origin = DVec3::new(10.0, 0.0, lift);
    let b = if flip_b {
        square(origin, DVec3::Y * 10.0, rise)
    } else {
        square(origin, rise, DVec3::Y * 10.0)
    };
    (a, b)
}

#[test]
fn two_planes_meet_at_their_angle_with_no_gap() {
    let angle = 12f64.to_radians();
    let (a, b) = hinge(angle, 0.0, false);
    let along = edge_samples(&a, Edge::U1, 8);
    assert!(along.iter().all(|&(u, _)| u == 1.0));
    let s = seam(Facing::new(&a), &along, &[Facing::new(&b)]).expect("finite");
    assert!((s.crease - 12.0).abs() < 1e-9, "{s:?}");
    assert!(s.gap < 1e-12, "{s:?}");
    assert!((s.crease_at.x - 10.0).abs() < 1e-12, "on A's edge: {s:?}");
}

#[test]
fn a_lifted_plane_leaves_its_lift_as_the_gap() {
    let (a, b) = hinge(0.0, 0.3, false);
    let s = seam(
        Facing::new(&a),
        &edge_samples(&a, Edge::U1, 4),
        &[Facing::new(&b)],
    )
    .expect("finite");
    assert!((s.gap - 0.3).abs() < 1e-12, "{s:?}");
    assert!(s.crease < 1e-9, "{s:?}");
}

#[test]
fn the_nearest_of_several_surfaces_answers() {
    // B split in two halves along y, a far decoy too: every sample finds its half.
    let angle = 7f64.to_radians();
    let rise = DVec3::new(angle.cos(), 0.0, angle.sin()) * 10.0;
    let lower = square(DVec3::new(10.0, 0.0, 0.0), rise, DVec3::Y * 5.0);
    let upper = square(DVec3::new(10.0, 5.0, 0.0), DVec3::Y * 5.0, rise);
    let decoy = square(DVec3::new(100.0, 0.0, 50.0), DVec3::X, DVec3::Y);
    let a = square(DVec3::ZERO, DVec3::X * 10.0, DVec3::Y * 10.0);
    let s = seam(
        Facing::new(&a),
        &edge_samples(&a, Edge::U1, 16),
        &[decoy, upper, lower].each_ref().map(Facing::new),
    )
    .expect("finite");
    assert!(s.gap < 1e-12 && (s.crease - 7.0).abs() < 1e-9, "{s:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The crease is the hinge angle, up or down, whichever way B is parametrized.
    #[test]
    fn crease_is_the_hinge_angle(deg in -80.0f64..80.0, flip in any::<bool>()) {
        let (a, b) = hinge(deg.to_radians(), 0.0, flip);
        let s = seam(Facing::new(&a), &edge_samples(&a, Edge::U1, 3), &[Facing::new(&b)]).expect("finite");
        prop_assert!((s.crease - deg.abs()).abs() < 1e-8, "{:?} vs {}", s, deg);
        prop_assert!(s.gap < 1e-9);
    }

    /// The sag of a quadratic Bezier section from the opening (start) to the product,
    /// in closed form: with its middle control point `d` below the chord's middle, the
    /// curve's depth below the chord is `2 d t (1 - t)`, at most `d / 2`.
    #[test]
    fn sag_of_a_parabola(d in 0.1f64..40.0, rise in 0.0f64..80.0) {
        let a = DVec3::new(0.0, 0.0, -rise);
        let b = DVec3::new(100.0, 0.0, 0.0);
        let mid = (a + b) / 2.0 - DVec3::Z * d;
        let c = Curve3::bezier(vec![a, mid, b]).expect("a parabola");
        let s = section_sag(&c, SectionEnd::Start);
        prop_assert!((s.below_chord - d / 2.0).abs() < 1e-9, "{:?}", s);
        // z(t) = -rise (1 - t)^2 + 2 (-rise / 2 - d) t (1 - t): lowest where z' = 0.
        let k = 2.0 * d; // z(t) = -rise + rise t - k t (1 - t)
        let t = ((k - rise) / (2.0 * k)).clamp(0.0, 1.0);
        let low = -rise + rise * t - k * t * (1.0 - t);
        prop_assert!((s.below_opening - (-rise - low).max(0.0)).abs() < 1e-9, "{:?}", s);
        // Measured from the other end, the opening is the product end at z = 0.
        let e = section_sag(&c, SectionEnd::End);
        prop_assert!((e.below_opening - (-low).max(0.0)).abs() < 1e-9, "{:?}", e);
    }
}

#[test]
fn a_section_above_its_chord_has_no_sag() {
    let c = Curve3::bezier(vec![
        DVec3::new(0.0, 0.0, -50.0),
        DVec3::new(20.0, 0.0, 10.0),
        DVec3::new(100.0, 0.0, 0.0),
    ])
    .expect("a parabola");
    let s = section_sag(&c, SectionEnd::Start);
    assert_eq!(s.below_chord, 0.0, "{s:?}");
    assert_eq!(s.below_opening, 0.0, "{s:?}");
    // The worked case: middle point 40 mm below the chord's middle at (50, -25).
    let c = Curve3::bezier(vec![
        DVec3::new(0.0, 0.0, -50.0),
        DVec3::new(50.0, 0.0, -65.0),
        DVec3::new(100.0, 0.0, 0.0),
    ])
    .expect("a parabola");
    let s = section_sag(&c, SectionEnd::Start);
    assert!((s.below_chord - 20.0).abs() < 1e-9, "{s:?}");
    assert!(
        s.below_chord_at.distance(DVec3::new(50.0, 0.0, -45.0)) < 1e-6,
        "{s:?}"
    );
    // z(t) = -50 + 50 t - 80 t (1 - t): lowest at t = 30 / 160.
    let t = 30.0 / 160.0;
    let low = -50.0 + 50.0 * t - 80.0 * t * (1.0 - t);
    assert!((s.below_opening - (-50.0 - low)).abs() < 1e-9, "{s:?}");
    assert!((s.below_opening_at.x - 100.0 * t).abs() < 1e-5, "{s:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// A cone's draft is its wall angle in closed form, `atan(dr / dz)`.
    #[test]
    fn cone_draft_is_its_wall_angle(r0 in 5.0f64..50.0, shrink in 0.0f64..0.9, h in 5.0f64..60.0) {
        let r1 = r0 * (1.0 - shrink);
        let line = Curve3::line(DVec3::new(r0, 0.0, 0.0), DVec3::new(r1, 0.0, h)).expect("line");
        let cone = revolve(&line, DVec3::ZERO, DVec3::Z, FRAC_PI_2).expect("a cone");
        let f = surface_figures(&cone);
        let want = ((r0 - r1) / h).atan().to_degrees();
        prop_assert!((f.draft - want).abs() < 1e-8, "{:?} vs {}", f, want);
        prop_assert!(!f.undercut);
    }

    /// Turning a patch about the press axis and moving it changes none of its figures.
    #[test]
    fn figures_do_not_depend_on_where_a_patch_stands(angle in 0.0f64..std::f64::consts::TAU, dx in -500.0f64..500.0, dz in -100.0f64..100.0) {
        let line = Curve3::line(DVec3::new(10.0, 0.0, 0.0), DVec3::new(6.0, 0.0, 20.0)).expect("line");
        let cone = revolve(&line, DVec3::ZERO, DVec3::Z, FRAC_PI_2).expect("a cone");
        let (s, c) = angle.sin_cos();
        let moved = cone.map_points(|p| {
            DVec3::new(c * p.x - s * p.y + dx, s * p.x + c * p.y, p.z + dz)
        });
        let (a, b) = (surface_figures(&cone), surface_figures(&moved));
        prop_assert!((a.min_radius - b.min_radius).abs() < 1e-7 * a.min_radius);
        prop_assert!((a.draft - b.draft).abs() < 1e-8);
        prop_assert_eq!(a.undercut, b.undercut);
    }
}
