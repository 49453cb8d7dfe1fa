//! Curve–plane, curve–coordinate and line–surface intersections.

use dieface::geom::intersect::{
    curve_at_coordinate, intersect_curve_plane, intersect_line_surface_all, intersect_ray_surface,
    Plane,
};
use dieface::geom::{Curve2, Curve3, GeomError, NurbsSurface};
use glam::{DVec2, DVec3};
use proptest::prelude::*;

const S: f64 = std::f64::consts::FRAC_1_SQRT_2;
const CIRCLE_KNOTS: [f64; 12] = [
    0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
];
const CIRCLE_WEIGHTS: [f64; 9] = [1.0, S, 1.0, S, 1.0, S, 1.0, S, 1.0];
const UNIT_SQUARE: [(f64, f64); 9] = [
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

/// The exact circle of radius `r` about the origin in the XZ plane, starting at `angle`
/// from the x axis (rotated about y).
fn circle_xz(r: f64, angle: f64) -> Curve3 {
    let (s, c) = angle.sin_cos();
    let pts = UNIT_SQUARE
        .iter()
        .map(|&(x, z)| DVec3::new(c * x - s * z, 0.0, s * x + c * z) * r)
        .collect();
    Curve3::new_rational(2, CIRCLE_KNOTS.to_vec(), pts, CIRCLE_WEIGHTS.to_vec()).unwrap()
}

/// A helix-like cubic winding around the z axis while climbing: crosses x = 0 planes
/// and z = const planes repeatedly.
fn wavy_3d() -> Curve3 {
    let n = 16;
    let pts = (0..n)
        .map(|i| {
            let a = i as f64 * 0.9;
            DVec3::new(
                3.0 * a.cos(),
                3.0 * a.sin(),
                0.1 * i as f64 + 1.5 * (2.1 * a).sin(),
            )
        })
        .collect();
    let mut knots = vec![0.0; 4];
    knots.extend((1..n - 3).map(|i| i as f64 / (n - 3) as f64));
    knots.extend([1.0; 4]);
    Curve3::new(3, knots, pts).unwrap()
}

/// Sign changes of `f` over `n + 1` uniform samples of [0, 1] (no sample is exactly 0).
fn sign_changes(f: impl Fn(f64) -> f64, n: usize) -> usize {
    let vals: Vec<f64> = (0..=n).map(|i| f(i as f64 / n as f64)).collect();
    assert!(vals.iter().all(|&v| v != 0.0));
    vals.windows(2)
        .filter(|w| (w[0] < 0.0) != (w[1] < 0.0))
        .count()
}

#[test]
fn plane_constructor_validates() {
    assert!(matches!(
        Plane::new(DVec3::ZERO, DVec3::ZERO),
        Err(GeomError::ZeroVector { .. })
    ));
    assert!(matches!(
        Plane::new(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Z),
        Err(GeomError::NotFinite { .. })
    ));
    let p = Plane::new(DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.0, 0.0, 5.0)).unwrap();
    assert_eq!(p.normal, DVec3::Z);
    assert_eq!(p.signed_distance(DVec3::new(7.0, 3.0, 4.0)), 3.0);
}

#[test]
fn circle_cut_by_a_plane() {
    let r = 10.0;
    let curve = circle_xz(r, 0.0);
    let plane = Plane::new(DVec3::new(0.0, 0.0, 0.5 * r), DVec3::Z).unwrap();
    let hits = intersect_curve_plane(&curve, &plane).unwrap();
    assert_eq!(hits.len(), 2, "{hits:?}");
    let x = r * 3f64.sqrt() / 2.0;
    assert!(
        hits[0].point.distance(DVec3::new(x, 0.0, 0.5 * r)) < 1e-12 * r,
        "{:?}",
        hits[0]
    );
    assert!(
        hits[1].point.distance(DVec3::new(-x, 0.0, 0.5 * r)) < 1e-12 * r,
        "{:?}",
        hits[1]
    );
    assert!(hits[0].t < hits[1].t);
}

#[test]
fn tangential_touch_is_found() {
    // Rotated so that the top of the circle lies inside a knot span, not on a sample.
    let r = 10.0;
    let curve = circle_xz(r, 0.3);
    let plane = Plane::new(DVec3::new(0.0, 0.0, r), DVec3::Z).unwrap();
    let hits = intersect_curve_plane(&curve, &plane).unwrap();
    assert_eq!(hits.len(), 1, "{hits:?}");
    assert!(
        hits[0].point.distance(DVec3::new(0.0, 0.0, r)) < 1e-6 * r,
        "{:?}",
        hits[0]
    );
    // Just above the top: no hit.
    let above = Plane::new(DVec3::new(0.0, 0.0, r * (1.0 + 1e-6)), DVec3::Z).unwrap();
    assert!(intersect_curve_plane(&curve, &above).unwrap().is_empty());
    // Just below: two close crossings.
    let below = Plane::new(DVec3::new(0.0, 0.0, r * (1.0 - 1e-6)), DVec3::Z).unwrap();
    let hits = intersect_curve_plane(&curve, &below).unwrap();
    assert_eq!(hits.len(), 2, "{hits:?}");
    for h in &hits {
        assert!(below.signed_distance(h.point).abs() < 1e-10);
    }
}

#[test]
fn crossings_at_polyline_vertices_are_not_duplicated() {
    let zs = [1.0, 0.0, -1.0, -0.5, 0.0, 2.0, 0.0, 1.0];
    let pts = zs
        .iter()
        .enumerate()
        .map(|(i, &z)| DVec3::new(i as f64, 0.0, z))
        .collect();
    let mut knots = vec![0.0, 0.0];
    knots.extend((1..7).map(|i| i as f64 / 7.0));
    knots.extend([1.0, 1.0]);
    let curve = Curve3::new(1, knots, pts).unwrap();
    let hits = intersect_curve_plane(&curve, &Plane::new(DVec3::ZERO, DVec3::Z).unwrap()).unwrap();
    let ts: Vec<f64> = hits.iter().map(|h| h.t).collect();
    // Vertices 1 and 4 cross, vertex 6 touches.
    assert_eq!(ts.len(), 3, "{ts:?}");
    for (t, i) in ts.iter().zip([1.0, 4.0, 6.0]) {
        assert!((t - i / 7.0).abs() < 1e-14, "{ts:?}");
    }
}

#[test]
fn curve_in_the_plane_is_an_overlap() {
    let curve = circle_xz(2.0, 0.1);
    let plane = Plane::new(DVec3::new(5.0, 0.0, -3.0), DVec3::Y).unwrap();
    assert!(matches!(
        intersect_curve_plane(&curve, &plane),
        Err(GeomError::Overlap { .. })
    ));
}

#[test]
fn helix_crosses_planes_many_times() {
    let curve = wavy_3d();
    let planes = [
        Plane::new(DVec3::new(0.0, 0.0, 0.8), DVec3::Z).unwrap(),
        Plane::new(DVec3::new(0.05, 0.0, 0.0), DVec3::X).unwrap(),
        Plane::new(DVec3::new(0.3, -0.2, 1.0), DVec3::new(0.4, 1.0, 0.3)).unwrap(),
    ];
    for plane in &planes {
        let hits = intersect_curve_plane(&curve, plane).unwrap();
        let expected = sign_changes(|t| plane.signed_distance(curve.point_at(t)), 100_000);
        assert!(
            expected >= 3,
            "test geometry should cross several times ({expected})"
        );
        assert_eq!(hits.len(), expected, "{plane:?}: {hits:?}");
        for w in hits.windows(2) {
            assert!(w[0].t < w[1].t);
        }
        for h in &hits {
            assert!(plane.signed_distance(h.point).abs() < 1e-10, "{h:?}");
            assert!((curve.point_at(h.t) - h.point).length() < 1e-14);
        }
    }
}

#[test]
fn coordinate_roots_on_a_2d_circle() {
    let r = 3.0;
    let pts = UNIT_SQUARE
        .iter()
        .map(|&(x, y)| DVec2::new(x, y) * r)
        .collect();
    let circle =
        Curve2::new_rational(2, CIRCLE_KNOTS.to_vec(), pts, CIRCLE_WEIGHTS.to_vec()).unwrap();
    let ts = curve_at_coordinate(&circle, 0, 0.5 * r).unwrap();
    assert_eq!(ts.len(), 2, "{ts:?}");
    let y = r * 3f64.sqrt() / 2.0;
    assert!(circle.point_at(ts[0]).distance(DVec2::new(0.5 * r, y)) < 1e-12 * r);
    assert!(circle.point_at(ts[1]).distance(DVec2::new(0.5 * r, -y)) < 1e-12 * r);
    // x = r: the seam (t = 0 and t = 1, both reported) is a touch.
    let ts = curve_at_coordinate(&circle, 0, r).unwrap();
    assert_eq!(ts, vec![0.0, 1.0]);
    assert!(curve_at_coordinate(&circle, 1, 2.0 * r).unwrap().is_empty());
    assert!(matches!(
        curve_at_coordinate(&circle, 2, 0.0),
        Err(GeomError::ParameterOutOfRange { .. })
    ));
    assert!(matches!(
        curve_at_coordinate(&circle, 0, f64::NAN),
        Err(GeomError::NotFinite { .. })
    ));
}

#[test]
fn coordinate_roots_on_a_wavy_profile() {
    let ys = [
        0.0, 2.0, -1.5, 1.0, 3.0, -2.0, 0.5, 2.5, -1.0, 1.5, 0.0, -2.5,
    ];
    let pts: Vec<DVec2> = ys
        .iter()
        .enumerate()
        .map(|(i, &y)| DVec2::new(i as f64 * 0.7, y))
        .collect();
    let knots = vec![
        0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.21, 0.22, 0.4, 0.55, 0.7, 0.85, 1.0, 1.0, 1.0, 1.0,
    ];
    let curve = Curve2::new(3, knots, pts).unwrap();
    for value in [0.37, 0.5, 1.234, 0.0001] {
        let ts = curve_at_coordinate(&curve, 1, value).unwrap();
        let expected = sign_changes(|t| curve.point_at(t).y - value, 100_000);
        assert!(expected >= 4);
        assert_eq!(ts.len(), expected, "y = {value}: {ts:?}");
        for &t in &ts {
            assert!((curve.point_at(t).y - value).abs() < 1e-12, "t = {t}");
        }
    }
    // x is monotone: exactly one root.
    let ts = curve_at_coordinate(&curve, 0, 3.3).unwrap();
    assert_eq!(ts.len(), 1);
    assert!((curve.point_at(ts[0]).x - 3.3).abs() < 1e-12);
}

/// A wavy bicubic height field over [0, 6] x [0, 6].
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

fn residual(origin: DVec3, dir: DVec3, s: &NurbsSurface, u: f64, v: f64, w: f64) -> f64 {
    (origin + dir * w - s.point_at(u, v)).length()
}

#[test]
fn line_behind_the_origin_has_negative_w() {
    let s = wavy_surface();
    let origin = DVec3::new(2.5, 3.1, -10.0);
    // Pointing down, away from the surface: the line still meets it, behind the origin.
    let hit = intersect_ray_surface(origin, DVec3::new(0.0, 0.0, -2.0), &s).unwrap();
    assert!(hit.w < 0.0);
    assert!(residual(origin, DVec3::new(0.0, 0.0, -2.0), &s, hit.u, hit.v, hit.w) < 1e-9);
    assert!((hit.point.x - 2.5).abs() < 1e-9 && (hit.point.y - 3.1).abs() < 1e-9);
}

#[test]
fn line_through_a_cylinder_hits_twice() {
    let r = 4.0;
    let pts: Vec<DVec3> = UNIT_SQUARE
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 0.0) * r)
        .collect();
    let net = pts
        .iter()
        .map(|p| vec![*p, *p + DVec3::new(0.0, 0.0, 10.0)])
        .collect();
    let weights = CIRCLE_WEIGHTS.iter().map(|&w| vec![w, w]).collect();
    let s = NurbsSurface::new_rational(
        2,
        1,
        CIRCLE_KNOTS.to_vec(),
        vec![0.0, 0.0, 1.0, 1.0],
        net,
        weights,
    )
    .unwrap();
    let origin = DVec3::new(1.0, 0.5, 3.0);
    let dir = DVec3::new(1.0, 0.2, 0.1);
    let hits = intersect_line_surface_all(origin, dir, &s).unwrap();
    assert_eq!(hits.len(), 2, "{hits:?}");
    assert!(hits[0].w < 0.0 && hits[1].w > 0.0);
    for h in &hits {
        assert!(residual(origin, dir, &s, h.u, h.v, h.w) < 1e-9);
        let p = h.point;
        assert!((DVec2::new(p.x, p.y).length() - r).abs() < 1e-9);
    }
    // The nearest along the line is the one ahead (the origin is off-centre towards +x).
    let nearest = intersect_ray_surface(origin, dir, &s).unwrap();
    let expected = if hits[0].w.abs() < hits[1].w.abs() {
        hits[0]
    } else {
        hits[1]
    };
    assert_eq!(nearest, expected);
    assert!(nearest.w > 0.0);
}

#[test]
fn missing_line_and_bad_input() {
    let s = wavy_surface();
    let err = intersect_ray_surface(DVec3::new(20.0, 20.0, 5.0), DVec3::new(0.0, 0.0, -1.0), &s);
    assert!(
        matches!(err, Err(GeomError::NoIntersection { .. })),
        "{err:?}"
    );
    // Parallel to the surface, high above it.
    let err = intersect_ray_surface(DVec3::new(-1.0, 3.0, 50.0), DVec3::new(1.0, 0.0, 0.0), &s);
    assert!(
        matches!(err, Err(GeomError::NoIntersection { .. })),
        "{err:?}"
    );
    assert!(
        intersect_line_surface_all(DVec3::new(20.0, 20.0, 5.0), DVec3::Z, &s)
            .unwrap()
            .is_empty()
    );
    assert!(matches!(
        intersect_ray_surface(DVec3::ZERO, DVec3::ZERO, &s),
        Err(GeomError::ZeroVector { .. })
    ));
    assert!(matches!(
        intersect_ray_surface(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Z, &s),
        Err(GeomError::NotFinite { .. })
    ));
    assert!(matches!(
        intersect_ray_surface(DVec3::ZERO, DVec3::new(0.0, f64::INFINITY, 1.0), &s),
        Err(GeomError::NotFinite { .. })
    ));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn rays_from_above_hit_the_wavy_surface(
        x in 1.5f64..4.5, y in 1.5f64..4.5, z in 4.0f64..20.0, dx in -0.05f64..0.05, dy in -0.05f64..0.05,
    ) {
        let s = wavy_surface();
        let origin = DVec3::new(x, y, z);
        let dir = DVec3::new(dx, dy, -1.0);
        let hit = intersect_ray_surface(origin, dir, &s).unwrap();
        prop_assert!(residual(origin, dir, &s, hit.u, hit.v, hit.w) < 1e-9);
        prop_assert!((s.point_at(hit.u, hit.v) - hit.point).length() < 1e-12);
        prop_assert!(hit.w > 0.0);
        // Nearest along the line among all the hits.
        let all = intersect_line_surface_all(origin, dir, &s).unwrap();
        prop_assert!(!all.is_empty());
        for h in &all {
            prop_assert!(hit.w.abs() <= h.w.abs() + 1e-12);
        }
    }
}

/// The self-crossing check behind the punch opening and trim outline: a figure of eight
/// crosses where its diagonals meet, a square or an open zig-zag does not, and a loop
/// that touches itself at one point counts.
#[test]
fn polylines_that_cross_or_touch_themselves_are_found() {
    use dieface::geom::intersect::polyline_self_crossing;
    use glam::DVec2;
    let p = DVec2::new;
    let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
    assert_eq!(polyline_self_crossing(&square, true), None);
    let zigzag = [p(0.0, 0.0), p(1.0, 1.0), p(2.0, 0.0), p(3.0, 1.0)];
    assert_eq!(polyline_self_crossing(&zigzag, false), None);
    let eight = [p(-1.0, -1.0), p(1.0, 1.0), p(1.0, -1.0), p(-1.0, 1.0)];
    let c = polyline_self_crossing(&eight, true).expect("a figure of eight crosses");
    assert_eq!((c.first, c.second), (0, 2));
    assert!(c.at.length() < 1e-12, "at the centre: {:?}", c.at);
    // Touching: the loop comes back to a point of an earlier segment.
    let touch = [
        p(0.0, 0.0),
        p(2.0, 0.0),
        p(2.0, 1.0),
        p(1.0, 0.0),
        p(0.0, 1.0),
    ];
    let c = polyline_self_crossing(&touch, true).expect("touches at (1, 0)");
    assert!(c.at.distance(p(1.0, 0.0)) < 1e-12);
    // Many points: a circle drawn twice round is found, quickly.
    let n = 4000;
    let twice: Vec<DVec2> = (0..n)
        .map(|i| {
            let t = 4.0 * std::f64::consts::PI * i as f64 / n as f64;
            p(t.cos() * (1.0 + 0.1 * (t / 2.0).cos()), t.sin())
        })
        .collect();
    assert!(polyline_self_crossing(&twice, true).is_some());
}
