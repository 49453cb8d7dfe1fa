//! Kernel identities as property tests: operations that must not change a shape do not,
//! and constructions meet their defining conditions.
//!
//! "Change no point" is measured against the geometry's size: control points lie in a
//! box of about 200 mm, and a change of 1e-12 of that (2e-10 mm) is the limit, about a
//! hundred units in the last place of the coordinates.

use dieface::geom::compat::make_compatible;
use dieface::geom::construct::coons;
use dieface::geom::interpolate::{
    closed_parameters, interpolate, interpolate_closed, Interpolation, KnotPlacement,
    Parametrization,
};
use dieface::geom::{Curve2, Curve3, Direction, NurbsSurface};
use glam::{DVec2, DVec3};
use proptest::prelude::*;

/// Relative change allowed by operations that must not change the shape.
const SAME: f64 = 1e-12;

fn coord() -> impl Strategy<Value = f64> {
    -100.0..100.0f64
}

fn point3() -> impl Strategy<Value = DVec3> {
    (coord(), coord(), coord()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// A clamped knot vector on [a, a + len] for `count` control points of `degree`, with
/// interior knots drawn at random and some repeated up to the degree.
fn knots(degree: usize, count: usize) -> impl Strategy<Value = Vec<f64>> {
    let interior = count - degree - 1;
    (
        prop::collection::vec(0.05..0.95f64, interior),
        -5.0..5.0f64,
        0.5..20.0f64,
        0..3usize,
    )
        .prop_map(move |(mut inner, a, len, repeat)| {
            inner.sort_by(f64::total_cmp);
            // Repeat some knots (never beyond the degree) to cover C0/C1 joints.
            for r in 0..repeat.min(inner.len()) {
                let i = (r * 7) % inner.len();
                let run = inner.iter().filter(|&&k| k == inner[i]).count();
                if i + 1 < inner.len() && run < degree && inner[i + 1] != inner[i] {
                    let v = inner[i];
                    inner[i + 1] = v;
                }
            }
            inner.sort_by(f64::total_cmp);
            // Distinct knots at least 1% of the domain apart. Much closer knots make the
            // knot-removal step of degree elevation (A5.9) lose digits to cancellation:
            // spans of 4e-5 of the domain give errors near 2e-12 of the curve's size.
            // That is the algorithm's conditioning, not a defect, and not die geometry.
            // Equal knots are kept only as repeats the degree allows: the generator can
            // draw the same value twice (a range's end), which degree 1 cannot take.
            let mut run = 1;
            for i in 1..inner.len() {
                let gap = inner[i] - inner[i - 1];
                if gap == 0.0 && run < degree {
                    run += 1;
                } else if gap < 0.01 {
                    inner[i] = inner[i - 1] + 0.01;
                    run = 1;
                } else {
                    run = 1;
                }
            }
            let mut k = vec![a; degree + 1];
            k.extend(inner.iter().map(|t| a + t * len));
            k.extend(std::iter::repeat_n(a + len, degree + 1));
            k
        })
}

/// Random curves of degree 1 to 5, half of them rational.
fn curve3() -> impl Strategy<Value = Curve3> {
    (1..=5usize, 0..6usize, any::<bool>())
        .prop_flat_map(|(degree, extra, rational)| {
            let count = degree + 1 + extra;
            (
                Just(degree),
                knots(degree, count),
                prop::collection::vec(point3(), count),
                prop::collection::vec(0.3..3.0f64, count),
                Just(rational),
            )
        })
        .prop_map(|(degree, k, pts, w, rational)| {
            if rational {
                Curve3::new_rational(degree, k, pts, w).expect("valid by construction")
            } else {
                Curve3::new(degree, k, pts).expect("valid by construction")
            }
        })
}

fn surface() -> impl Strategy<Value = NurbsSurface> {
    (1..=4usize, 1..=4usize, 0..3usize, 0..3usize, any::<bool>())
        .prop_flat_map(|(du, dv, eu, ev, rational)| {
            let (nu, nv) = (du + 1 + eu, dv + 1 + ev);
            (
                Just((du, dv)),
                knots(du, nu),
                knots(dv, nv),
                prop::collection::vec(prop::collection::vec(point3(), nv), nu),
                prop::collection::vec(prop::collection::vec(0.3..3.0f64, nv), nu),
                Just(rational),
            )
        })
        .prop_map(|((du, dv), ku, kv, net, w, rational)| {
            if rational {
                NurbsSurface::new_rational(du, dv, ku, kv, net, w).expect("valid by construction")
            } else {
                NurbsSurface::new(du, dv, ku, kv, net).expect("valid by construction")
            }
        })
}

/// 1,000 parameters spread over the domain, ends included.
fn samples(domain: (f64, f64)) -> impl Iterator<Item = f64> {
    (0..1000).map(move |i| domain.0 + (domain.1 - domain.0) * i as f64 / 999.0)
}

#[track_caller]
fn assert_same_curve(a: &Curve3, b: &Curve3) {
    assert_eq!(a.domain(), b.domain());
    let scale = a.control_scale().max(1.0);
    for t in samples(a.domain()) {
        let d = a.point_at(t).distance(b.point_at(t));
        assert!(d <= SAME * scale, "point at {t} moved by {d:e}");
    }
}

#[track_caller]
fn assert_same_surface(a: &NurbsSurface, b: &NurbsSurface) {
    let scale = a.control_scale().max(1.0);
    let (du, dv) = (a.domain_u(), b.domain_v());
    for i in 0..32 {
        for j in 0..32 {
            let u = du.0 + (du.1 - du.0) * i as f64 / 31.0;
            let v = dv.0 + (dv.1 - dv.0) * j as f64 / 31.0;
            let d = a.point_at(u, v).distance(b.point_at(u, v));
            assert!(d <= SAME * scale, "point at ({u}, {v}) moved by {d:e}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn knot_insertion_changes_nothing(c in curve3(), f in 0.01..0.99f64, times in 1..4usize) {
        let (a, b) = c.domain();
        let t = a + (b - a) * f;
        let d = c.insert_knot(t, times).unwrap();
        prop_assert!(d.knots().multiplicity(t) <= c.degree());
        assert_same_curve(&c, &d);
    }

    #[test]
    fn knot_refinement_changes_nothing(c in curve3(), fs in prop::collection::vec(0.01..0.99f64, 1..8)) {
        let (a, b) = c.domain();
        let mut new: Vec<f64> = fs.iter().map(|f| a + (b - a) * f).collect();
        new.sort_by(f64::total_cmp);
        new.dedup();
        // Drop values that would exceed the degree's multiplicity.
        new.retain(|&t| c.knots().multiplicity(t) < c.degree());
        let d = c.refine(&new).unwrap();
        prop_assert_eq!(d.control_points().len(), c.control_points().len() + new.len());
        assert_same_curve(&c, &d);
    }

    #[test]
    fn degree_elevation_changes_nothing(c in curve3(), by in 1..4usize) {
        let d = c.elevate_degree(by).unwrap();
        prop_assert_eq!(d.degree(), c.degree() + by);
        assert_same_curve(&c, &d);
    }

    #[test]
    fn reversing_a_surface_direction_runs_it_backwards(s in surface(), dir_u in any::<bool>()) {
        let dir = if dir_u { Direction::U } else { Direction::V };
        let r = s.reversed(dir);
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        let size = 200.0;
        for u in samples((u0, u1)) {
            for v in samples((v0, v1)) {
                let (ru, rv) = match dir {
                    Direction::U => (u0 + u1 - u, v),
                    Direction::V => (u, v0 + v1 - v),
                };
                let d = s.point_at(u, v).distance(r.point_at(ru, rv));
                prop_assert!(d <= SAME * size, "({u}, {v}): {d}");
            }
        }
        // Twice is the identity (up to the rounding of a + b - (a + b - k) in the knots).
        assert_same_surface(&s, &r.reversed(dir));
    }

    #[test]
    fn grid_points_are_the_surface_points(s in surface(), extra in prop::collection::vec(0.0..1.0f64, 0..4)) {
        // The grid takes knots, domain ends and points between them alike.
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        let mut us: Vec<f64> = samples((u0, u1)).step_by(37).collect();
        us.extend(extra.iter().map(|f| u0 + (u1 - u0) * f));
        us.extend(s.knots_u().distinct().into_iter().map(|(k, _)| k));
        let vs: Vec<f64> = samples((v0, v1)).step_by(41).chain(s.knots_v().distinct().into_iter().map(|(k, _)| k)).collect();
        let grid = s.grid_points(&us, &vs);
        prop_assert_eq!(grid.len(), us.len() * vs.len());
        for (l, &v) in vs.iter().enumerate() {
            for (k, &u) in us.iter().enumerate() {
                let d = grid[l * us.len() + k].distance(s.point_at(u, v));
                prop_assert!(d <= SAME * 200.0, "({u}, {v}): {d}");
            }
        }
    }

    #[test]
    fn surface_refinement_and_elevation_change_nothing(
        s in surface(), f in 0.05..0.95f64, dir_u in any::<bool>(), by in 1..3usize,
    ) {
        let dir = if dir_u { Direction::U } else { Direction::V };
        let (a, b) = s.domain(dir);
        let t = a + (b - a) * f;
        assert_same_surface(&s, &s.insert_knot(dir, t, 1).unwrap());
        if s.knots_u().multiplicity(t) == 0 && s.knots_v().multiplicity(t) == 0 {
            assert_same_surface(&s, &s.refine(dir, &[t]).unwrap());
        }
        let e = s.elevate_degree(dir, by).unwrap();
        assert_same_surface(&s, &e);
    }

    #[test]
    fn compatibility_keeps_shapes_and_unifies_knots(cs in prop::collection::vec(curve3(), 2..5)) {
        let out = make_compatible(&cs).unwrap();
        for (c, d) in cs.iter().zip(&out) {
            prop_assert_eq!(d.degree(), out[0].degree());
            prop_assert_eq!(d.knots(), out[0].knots());
            let on_unit = c.reparametrized(0.0, 1.0).unwrap();
            assert_same_curve(&on_unit, d);
        }
    }

    #[test]
    fn interpolation_passes_through_points_with_asked_tangents(
        pts in prop::collection::vec(point3(), 4..12),
        t0 in point3(), t1 in point3(),
        degree in 2..=5usize,
        centripetal in any::<bool>(),
        with_tangents in any::<bool>(),
    ) {
        // Random points that nearly coincide make a meaningless (if valid) problem.
        prop_assume!(pts.windows(2).all(|w| w[0].distance(w[1]) > 1.0));
        prop_assume!(t0.length() > 1.0 && t1.length() > 1.0);
        let parametrization = if centripetal { Parametrization::Centripetal } else { Parametrization::ChordLength };
        let opts = Interpolation {
            degree: degree.min(pts.len() - 1),
            parametrization,
            knots: KnotPlacement::Averaged,
            start_tangent: with_tangents.then_some(t0),
            end_tangent: with_tangents.then_some(t1),
        };
        let c = interpolate(&pts, &opts).unwrap();
        let params = dieface::geom::interpolate::parameters(&pts, parametrization).unwrap();
        let scale = pts.iter().map(|p| p.length()).fold(1.0, f64::max);
        for (p, t) in pts.iter().zip(&params) {
            let d = c.point_at(*t).distance(*p);
            prop_assert!(d <= 1e-9 * scale, "misses point by {}", d);
        }
        if with_tangents {
            let [_, d0] = c.derivatives::<2>(0.0);
            let [_, d1] = c.derivatives::<2>(1.0);
            prop_assert!(d0.distance(t0) <= 1e-9 * t0.length().max(scale), "start tangent {:?} vs {:?}", d0, t0);
            prop_assert!(d1.distance(t1) <= 1e-9 * t1.length().max(scale), "end tangent {:?} vs {:?}", d1, t1);
        }
    }

    #[test]
    fn cubic_spline_with_knots_at_parameters_interpolates(
        pts in prop::collection::vec(point3(), 2..10), t0 in point3(), t1 in point3(),
    ) {
        prop_assume!(pts.windows(2).all(|w| w[0].distance(w[1]) > 1.0));
        let opts = Interpolation {
            knots: KnotPlacement::AtParameters,
            ..Interpolation::cubic_with_tangents(t0, t1)
        };
        let c = interpolate(&pts, &opts).unwrap();
        let params = dieface::geom::interpolate::parameters(&pts, Parametrization::ChordLength).unwrap();
        for (p, t) in pts.iter().zip(&params) {
            prop_assert!(c.point_at(*t).distance(*p) <= 1e-9 * 200.0);
        }
        prop_assert!(c.derivatives::<2>(0.0)[1].distance(t0) <= 1e-9 * 200.0);
    }

    #[test]
    fn coons_boundaries_equal_the_input_curves(
        a in prop::collection::vec(point3(), 4..7), b in prop::collection::vec(point3(), 3..6),
        c in prop::collection::vec(point3(), 4..6), d in prop::collection::vec(point3(), 2..5),
    ) {
        // Four open polylines turned into curves of different degrees; force the corners.
        let (p00, p10, p11, p01) = (a[0], a[a.len() - 1], c[c.len() - 1], c[0]);
        let mut right = b.clone();
        right[0] = p10;
        let last = right.len() - 1;
        right[last] = p11;
        let mut left = d.clone();
        left[0] = p00;
        let last = left.len() - 1;
        left[last] = p01;
        let bottom = Curve3::bezier(a.clone()).unwrap();
        let top = Curve3::bezier(c.clone()).unwrap();
        let left = Curve3::bezier(left).unwrap();
        let right = Curve3::new(2, uniform(2, right.len()), right).unwrap();
        let s = coons(&bottom, &top, &left, &right).unwrap();
        let scale = 200.0;
        for i in 0..=100 {
            let t = i as f64 / 100.0;
            prop_assert!(s.point_at(t, 0.0).distance(bottom.point_at(t)) <= SAME * scale);
            prop_assert!(s.point_at(t, 1.0).distance(top.point_at(t)) <= SAME * scale);
            prop_assert!(s.point_at(0.0, t).distance(left.point_at(t)) <= SAME * scale);
            prop_assert!(s.point_at(1.0, t).distance(right.point_at(t)) <= SAME * scale);
        }
    }

    #[test]
    fn splitting_and_reversing_keep_the_shape(c in curve3(), f in 0.05..0.95f64) {
        let (a, b) = c.domain();
        let t = a + (b - a) * f;
        let (l, r) = c.split_at(t).unwrap();
        let rev = c.reversed();
        let scale = c.control_scale().max(1.0);
        for s in samples(c.domain()) {
            let piece = if s <= t { l.point_at(s) } else { r.point_at(s) };
            prop_assert!(piece.distance(c.point_at(s)) <= SAME * scale);
            prop_assert!(rev.point_at(a + b - s).distance(c.point_at(s)) <= SAME * scale);
        }
    }

    #[test]
    fn the_piece_between_two_parameters_is_the_curve_there(
        c in curve3(), f0 in 0.0..1.0f64, f1 in 0.0..1.0f64,
    ) {
        let (t0, t1) = c.domain();
        let (lo, hi) = (f0.min(f1), f0.max(f1));
        prop_assume!(hi - lo > 0.01);
        // The whole domain is one of the cases: the ends are kept, not cut.
        let (a, b) = if hi - lo > 0.98 { (t0, t1) } else { (t0 + (t1 - t0) * lo, t0 + (t1 - t0) * hi) };
        let piece = c.between(a, b).unwrap();
        prop_assert_eq!(piece.domain(), (a, b));
        let scale = c.control_scale().max(1.0);
        for s in samples((a, b)) {
            prop_assert!(piece.point_at(s).distance(c.point_at(s)) <= SAME * scale);
        }
        prop_assert!(c.between(b, a).is_err());
    }

    #[test]
    fn smooth_pieces_cut_exactly_at_the_corners(c in curve3(), f in 0.1..0.9f64) {
        let (t0, t1) = c.domain();
        let corner = t0 + (t1 - t0) * f;
        // Raising a knot to the degree's multiplicity makes a C0 joint there.
        let already = c.knots().distinct().into_iter().find(|&(k, _)| k == corner).map_or(0, |(_, m)| m);
        let cornered = c.insert_knot(corner, c.degree().saturating_sub(already)).unwrap();
        let pieces = cornered.smooth_pieces().unwrap();
        prop_assert_eq!(pieces[0].domain().0, t0);
        prop_assert_eq!(pieces[pieces.len() - 1].domain().1, t1);
        prop_assert!(pieces.iter().any(|p| p.domain().1 == corner));
        for w in pieces.windows(2) {
            prop_assert_eq!(w[0].domain().1, w[1].domain().0);
        }
        let scale = c.control_scale().max(1.0);
        for p in &pieces {
            let (a, b) = p.domain();
            // Smooth inside: no interior knot as often as the degree.
            prop_assert!(p.knots().distinct().iter().all(|&(k, m)| k == a || k == b || m < p.degree()));
            for s in samples(p.domain()) {
                prop_assert!(p.point_at(s).distance(c.point_at(s)) <= SAME * scale);
            }
        }
    }

    #[test]
    fn two_d_curves_evaluate_like_their_3d_embedding(
        pts in prop::collection::vec((coord(), coord()), 4..8), t in 0.0..1.0f64,
    ) {
        let pts: Vec<DVec2> = pts.into_iter().map(|(x, y)| DVec2::new(x, y)).collect();
        let c2 = Curve2::new(3, uniform(3, pts.len()), pts).unwrap();
        let c3 = c2.to_3d();
        let [p2, d2, dd2] = c2.derivatives::<3>(t);
        let [p3, d3, dd3] = c3.derivatives::<3>(t);
        prop_assert_eq!(p2.extend(0.0), p3);
        prop_assert_eq!(d2.extend(0.0), d3);
        prop_assert_eq!(dd2.extend(0.0), dd3);
    }
}

#[test]
fn a_curve_is_closed_when_its_ends_meet_within_its_size() {
    use dieface::geom::curve::CLOSED_TOLERANCE;
    let square = |gap: f64| {
        let pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(100.0, 0.0),
            DVec2::new(100.0, 100.0),
            DVec2::new(0.0, 100.0),
            DVec2::new(gap, 0.0),
        ];
        Curve2::new(1, vec![0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0], pts).unwrap()
    };
    // The size is the control scale, 100 * sqrt(2) here.
    let tolerance = CLOSED_TOLERANCE * 100.0 * 2f64.sqrt();
    assert!(square(0.0).is_closed());
    assert!(square(0.9 * tolerance).is_closed());
    assert!(!square(1.1 * tolerance).is_closed());
    // A tiny curve is held to the tolerance of a 1 mm one.
    let tiny = Curve2::line(DVec2::ZERO, DVec2::new(0.5 * CLOSED_TOLERANCE, 0.0)).unwrap();
    assert!(tiny.is_closed());
    assert!(!Curve2::line(DVec2::ZERO, DVec2::X).unwrap().is_closed());
}

/// Largest distance, at the same parameter, between two curves on one domain (sampled).
fn parametric_distance(a: &Curve3, b: &Curve3) -> f64 {
    samples(a.domain())
        .map(|t| a.point_at(t).distance(b.point_at(t)))
        .fold(0.0, f64::max)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Knot removal (P&T A5.8) undoes knot insertion exactly: the same knots, the same
    /// control points and weights.
    #[test]
    fn removing_inserted_knots_gives_back_the_curve(
        c in curve3(), f in 0.01..0.99f64, times in 1..6usize,
    ) {
        let (a, b) = c.domain();
        let t = a + (b - a) * f;
        let more = c.insert_knot(t, times).unwrap();
        let inserted = more.control_points().len() - c.control_points().len();
        prop_assume!(inserted > 0);
        // A tolerance well above rounding (rational curves measure it in homogeneous
        // space, scaled down by w_min / (1 + |P|max), P&T eq. 5.30).
        let (back, removed) = more.remove_knot(t, inserted, 1e-6).unwrap();
        prop_assert_eq!(removed, inserted);
        prop_assert_eq!(back.knots().as_slice(), c.knots().as_slice());
        for (p, q) in back.control_points().iter().zip(c.control_points()) {
            prop_assert!(p.distance(*q) <= 1e-9, "{p} against {q}");
        }
        for i in 0..c.control_points().len() {
            prop_assert!((back.weight(i) - c.weight(i)).abs() <= 1e-9);
        }
    }

    /// Removal within a tolerance never moves the curve by more than the tolerance, for
    /// any knot of any curve (most removals are refused; those that go stay inside).
    #[test]
    fn knot_removal_stays_within_its_tolerance(
        c in curve3(), pick in 0..20usize, times in 1..6usize, tol_exp in -4.0..1.5f64,
    ) {
        let (a, b) = c.domain();
        let interior: Vec<f64> = c.span_breaks().into_iter().filter(|&k| k > a && k < b).collect();
        prop_assume!(!interior.is_empty());
        let t = interior[pick % interior.len()];
        let tol = 10f64.powf(tol_exp);
        let (d, removed) = c.remove_knot(t, times, tol).unwrap();
        prop_assert!(removed <= times.min(c.knots().multiplicity(t)));
        prop_assert_eq!(d.control_points().len(), c.control_points().len() - removed);
        let moved = parametric_distance(&c, &d);
        prop_assert!(moved <= tol * (1.0 + 1e-9) + 1e-12, "moved {moved:e} > {tol:e} ({removed} removed)");
    }

    /// A cubic that is C1 but not C2 at a knot (drawn as a double knot, then inserted to a
    /// triple one) loses exactly the one copy its smoothness allows at a tight tolerance.
    #[test]
    fn knot_removal_stops_at_the_curves_continuity(
        pts in prop::collection::vec(point3(), 6), f in 0.2..0.8f64,
    ) {
        let knots = vec![0.0, 0.0, 0.0, 0.0, f, f, 1.0, 1.0, 1.0, 1.0];
        let c = Curve3::new(3, knots, pts).unwrap();
        // Skip the (measure-zero) curves that happen to be C2 at f.
        let jump = c.derivatives::<3>(f - 1e-9)[2].distance(c.derivatives::<3>(f)[2]);
        prop_assume!(jump > 1e-3 * c.control_scale().max(1.0));
        let triple = c.insert_knot(f, 1).unwrap();
        prop_assert_eq!(triple.knots().multiplicity(f), 3);
        let (d, removed) = triple.remove_knot(f, 3, 1e-9).unwrap();
        prop_assert_eq!(removed, 1);
        prop_assert_eq!(d.knots().multiplicity(f), 2);
        prop_assert!(parametric_distance(&c, &d) <= 1e-9);
    }
}

/// Only G1 at a knot (same tangent direction, different speeds on either side): no copy
/// of the triple knot goes at a tight tolerance, since any removal would move the curve.
#[test]
fn knot_removal_keeps_a_knot_where_the_speed_jumps() {
    let pts = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(10.0, 20.0, 0.0),
        DVec3::new(30.0, 20.0, 5.0),
        DVec3::new(50.0, 20.0, 5.0),
        // Along the same direction as the previous leg, three times as far.
        DVec3::new(110.0, 20.0, 5.0),
        DVec3::new(140.0, -10.0, 0.0),
        DVec3::new(160.0, 0.0, 0.0),
    ];
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
    let c = Curve3::new(3, knots, pts).unwrap();
    let (same, removed) = c.remove_knot(0.5, 3, 1e-6).unwrap();
    assert_eq!(removed, 0);
    assert_eq!(same, c);
    // With a loose tolerance some copies go, and the curve stays inside it.
    let (d, removed) = c.remove_knot(0.5, 3, 50.0).unwrap();
    assert!(removed >= 1, "a 50 mm tolerance removes at least one copy");
    assert!(parametric_distance(&c, &d) <= 50.0);
}

/// Asking to remove a value that is not a knot, or with a bad tolerance, is an error.
#[test]
fn knot_removal_refuses_what_is_not_a_knot() {
    let c = Curve3::new(
        3,
        uniform(3, 6),
        (0..6)
            .map(|i| DVec3::new(i as f64, (i * i) as f64, 0.0))
            .collect(),
    )
    .unwrap();
    assert!(c.remove_knot(0.3, 1, 1e-6).is_err());
    assert!(c.remove_knot(0.0, 1, 1e-6).is_err());
    assert!(c.remove_knot(c.span_breaks()[1], 1, -1.0).is_err());
    assert!(c.remove_knot(c.span_breaks()[1], 1, f64::NAN).is_err());
}

/// A closed loop of points around the origin: angles and radii drawn at random, so
/// neighbours are distinct and spacing is uneven (z varies too).
fn point_loop() -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec((0.2..1.0f64, 20.0..100.0f64, -10.0..10.0f64), 3..24).prop_map(|raw| {
        let total: f64 = raw.iter().map(|r| r.0).sum();
        let mut angle = 0.0f64;
        raw.iter()
            .map(|&(step, r, z)| {
                let p = DVec3::new(r * angle.cos(), 0.6 * r * angle.sin(), z);
                angle += std::f64::consts::TAU * step / total;
                p
            })
            .collect()
    })
}

/// `c` at `t` taken modulo its period (domain length 1).
fn periodic_point(c: &Curve3, t: f64) -> DVec3 {
    let (a, _) = c.domain();
    c.point_at(a + (t - a).rem_euclid(1.0))
}

/// Checks the defining conditions of a closed interpolant and its independence of the
/// starting point, for one loop and one parametrization.
fn check_closed(points: &[DVec3], method: Parametrization) -> Result<(), TestCaseError> {
    let n = points.len();
    let c = interpolate_closed(points, method).unwrap();
    let params = closed_parameters(points, method).unwrap();
    let scale = c.control_scale().max(1.0);
    prop_assert_eq!(c.domain(), (0.0, 1.0));
    // Through every point.
    for (q, &t) in points.iter().zip(&params) {
        prop_assert!(
            c.point_at(t).distance(*q) <= 1e-9,
            "{q} missed by {:e}",
            c.point_at(t).distance(*q)
        );
    }
    // C2 at the seam: derivatives at the start (right side) equal those at the end (left).
    let start = c.derivatives::<3>(0.0);
    let end = c.derivatives::<3>(1.0);
    prop_assert!(start[0].distance(end[0]) <= 1e-12 * scale);
    for k in 1..3 {
        let size = start[k].length().max(end[k].length()).max(1e-9);
        prop_assert!(
            start[k].distance(end[k]) <= 1e-9 * size,
            "derivative {k}: {} against {}",
            start[k],
            end[k]
        );
    }
    // Started at another point, the same curve with its parameter shifted.
    for m in 1..n.min(6) {
        let rotated: Vec<DVec3> = points[m..].iter().chain(&points[..m]).copied().collect();
        let r = interpolate_closed(&rotated, method).unwrap();
        for t in samples((0.0, 1.0)).step_by(7) {
            let d = r.point_at(t).distance(periodic_point(&c, t + params[m]));
            prop_assert!(d <= 1e-9, "start {m}: {d:e} at {t}");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]

    /// The closed cubic passes through its points, is C2 at its seam, and does not
    /// depend on which point of the loop comes first.
    #[test]
    fn closed_interpolation_is_periodic_and_start_independent(points in point_loop()) {
        check_closed(&points, Parametrization::ChordLength)?;
        check_closed(&points, Parametrization::Centripetal)?;
        check_closed(&points, Parametrization::Uniform)?;
    }

    /// Joined to itself end to start, the closed cubic's seam is a triple knot of which
    /// knot removal takes two copies at rounding level: C2 in the representation too.
    #[test]
    fn closed_interpolation_seam_knot_goes_by_removal(points in point_loop()) {
        let c = interpolate_closed(&points, Parametrization::ChordLength).unwrap();
        let k = c.knots().as_slice();
        let mut knots: Vec<f64> = k[..k.len() - 1].to_vec();
        knots.extend(k[4..].iter().map(|t| t + 1.0));
        let mut net = c.control_points().to_vec();
        net.extend_from_slice(&c.control_points()[1..]);
        let twice = Curve3::new(3, knots, net).unwrap();
        prop_assert_eq!(twice.knots().multiplicity(1.0), 3);
        let (smooth, removed) = twice.remove_knot(1.0, 3, 1e-9).unwrap();
        prop_assert_eq!(removed, 2);
        prop_assert_eq!(smooth.knots().multiplicity(1.0), 1);
    }
}

/// Too few points, or a point repeated (the last equal to the first included), are
/// errors, not a curve.
#[test]
fn closed_interpolation_refuses_degenerate_loops() {
    let sq = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    assert!(interpolate_closed(&sq[..2], Parametrization::ChordLength).is_err());
    let mut repeated = sq.to_vec();
    repeated.push(sq[0]);
    assert!(interpolate_closed(&repeated, Parametrization::ChordLength).is_err());
    // A square of four points: the curve is symmetric, through the corners.
    let c = interpolate_closed(&sq, Parametrization::ChordLength).unwrap();
    for (q, t) in sq.iter().zip([0.0, 0.25, 0.5, 0.75]) {
        assert!(c.point_at(t).distance(*q) <= 1e-12);
    }
    // Its quarter turn about the centre maps corner k to corner k + 1 and the curve
    // onto itself, a quarter of the period on: C(t + 1/4) = R(C(t)).
    let turn = |p: DVec3| DVec3::new(1.0 - p.y, p.x, p.z);
    for t in [0.05, 0.125, 0.3, 0.6] {
        let d = periodic_point(&c, t + 0.25).distance(turn(c.point_at(t)));
        assert!(d <= 1e-12, "{d:e} at {t}");
    }
}

/// A clamped uniform knot vector on [0, 1].
fn uniform(degree: usize, count: usize) -> Vec<f64> {
    dieface::geom::KnotVector::uniform(degree, count)
        .unwrap()
        .into_vec()
}
