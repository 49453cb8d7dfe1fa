//! The blankholder (paper 001 sections 3.3-3.4; GitHub issue 5): C1 joins by eq. 4 on the control
//! net and G1 when measured, normals up, outer edges through the designer's stations,
//! on the fender example through the language and on hand-checkable inputs built with
//! the kernel API. Run with `--nocapture` to see the measured figures.

#[path = "common/square.rs"]
mod square;

#[path = "common/fender.rs"]
mod fender_example;
#[path = "common/joins.rs"]
mod joins;
use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

use dieface::die::blankholder::{
    self as bh, outer_corner, outer_corner_samples, Blankholder, PieceSpec as BinderPiece,
    Problem as BinderProblem, SideSpec as BinderSide, Station,
};
use dieface::die::continuity::measure_join;
use dieface::die::punch_opening::{
    self as po, CornerSpec, Magnitude, PieceKind, PieceSpec, PunchOpening, PunchOpeningSpec,
    SideView,
};
use dieface::eval::features::Built;
use dieface::eval::{Data, Value};
use dieface::geom::arc::circular_arc;
use dieface::geom::inversion::closest_point_on_curve;
use dieface::geom::tessellate::{tessellate_curve, Tolerance};
use dieface::geom::{Curve3, GeomError, NurbsSurface};
use fender_example::fender_values;
use glam::{DVec2, DVec3};
use joins::*;
use square::*;

/// G1 as strict checkers see it (`docs/methods.md`, "Numbers").
const MAX_GAP: f64 = 0.001;
const MAX_NORMAL_ANGLE_DEG: f64 = 0.05;
/// Eq. 4 on the control net: parallel legs and one ratio, to rounding.
const MAX_NET_ANGLE_DEG: f64 = 1e-6;
const MAX_RATIO_SPREAD: f64 = 1e-9;

/// The worst figures over the joins of a binder: eq. 4 on the control net (boundary
/// point gap, leg angle in degrees, ratio spread) and measured (gap, normal angle).
#[derive(Debug, Default, Clone, Copy)]
struct JoinFigures {
    net_gap: f64,
    net_angle: f64,
    ratio_spread: f64,
    gap: f64,
    normal_angle: f64,
}

/// Checks every join of `binder` (the last with the first included) by eq. 4 on the
/// control net, both with the kernel's `measure_join` and with `eq4`, and measured.
fn check_joins(label: &str, binder: &Blankholder) -> JoinFigures {
    let n = binder.patches.len();
    assert_eq!(
        binder.joins.len(),
        n,
        "one join per patch, the last with the first"
    );
    let mut worst = JoinFigures::default();
    for k in 0..n {
        let (a, b) = (&binder.patches[k], &binder.patches[(k + 1) % n]);
        let join = &binder.joins[k];
        assert_eq!(
            (join.before.as_str(), join.after.as_str()),
            (a.name.as_str(), b.name.as_str())
        );
        let kernel = measure_join(&a.surface, &b.surface, JOIN_SAMPLES);
        assert_eq!(kernel, join.quality, "the stored figures are the kernel's");
        let (net_gap, net_angle, ratio_spread) = eq4(&a.surface, &b.surface);
        let (gap, normal_angle) = measured_g1(&a.surface, &b.surface);
        eprintln!(
            "{label} {:>12} > {:<12}: eq. 4 net gap {net_gap:.1e} mm, net angle \
             {net_angle:.1e} deg, ratio spread {ratio_spread:.1e} (kernel {:.1e} deg, {:.1e}); \
             measured gap {gap:.1e} mm, normal angle {normal_angle:.1e} deg (kernel {:.1e} mm, \
             {:.1e} deg)",
            a.name, b.name, kernel.net_angle, kernel.ratio_spread, kernel.gap, kernel.normal_angle
        );
        let context = format!("{label}: join {} > {}", a.name, b.name);
        assert!(
            net_gap <= 1e-9 && kernel.net_gap <= 1e-9,
            "{context}: net gap {net_gap}"
        );
        assert!(
            net_angle <= MAX_NET_ANGLE_DEG && kernel.net_angle <= MAX_NET_ANGLE_DEG,
            "{context}: eq. 4 legs {net_angle} deg apart (kernel {})",
            kernel.net_angle
        );
        assert!(
            ratio_spread <= MAX_RATIO_SPREAD && kernel.ratio_spread <= MAX_RATIO_SPREAD,
            "{context}: eq. 4 ratio spread {ratio_spread} (kernel {})",
            kernel.ratio_spread
        );
        assert!((net_angle - kernel.net_angle).abs() <= 1e-9, "{context}");
        assert!(
            gap <= MAX_GAP && kernel.gap <= MAX_GAP,
            "{context}: gap {gap}"
        );
        assert!(
            normal_angle <= MAX_NORMAL_ANGLE_DEG && kernel.normal_angle <= MAX_NORMAL_ANGLE_DEG,
            "{context}: normals {normal_angle} deg apart (kernel {})",
            kernel.normal_angle
        );
        worst.net_gap = worst.net_gap.max(net_gap);
        worst.net_angle = worst.net_angle.max(net_angle);
        worst.ratio_spread = worst.ratio_spread.max(ratio_spread);
        worst.gap = worst.gap.max(gap);
        worst.normal_angle = worst.normal_angle.max(normal_angle);
    }
    worst
}

/// The smallest +Z component of the unit normal over a grid on every patch.
fn lowest_normal_z(binder: &Blankholder) -> f64 {
    let mut lowest = f64::INFINITY;
    for p in &binder.patches {
        let s = &p.surface;
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        for i in 0..=50 {
            for j in 0..=10 {
                let (u, v) = (
                    u0 + (u1 - u0) * i as f64 / 50.0,
                    v0 + (v1 - v0) * j as f64 / 10.0,
                );
                let n = s.normal(u, v).expect("normal");
                lowest = lowest.min(n.z);
            }
        }
    }
    lowest
}

/// The v at which `patch`'s surface runs along its outer edge (the other v edge is the
/// punch opening), checked against both curves.
fn outer_v(surface: &NurbsSurface, inner: &Curve3, outer: &Curve3) -> f64 {
    let (v0, v1) = surface.domain_v();
    let (u0, u1) = surface.domain_u();
    let off = |v: f64, c: &Curve3| -> f64 {
        (0..=100)
            .map(|i| {
                let f = i as f64 / 100.0;
                surface
                    .point_at(u0 + (u1 - u0) * f, v)
                    .distance(c.point_at(f))
            })
            .fold(0.0, f64::max)
    };
    let (v_out, v_in) = if off(v0, outer) < off(v1, outer) {
        (v0, v1)
    } else {
        (v1, v0)
    };
    assert!(
        off(v_out, outer) <= 1e-9,
        "the surface's edge is not its outer curve"
    );
    assert!(
        off(v_in, inner) <= 1e-9,
        "the surface's edge is not the opening"
    );
    v_out
}

/// The outward unit top-view normal of the opening at a tangent `t`.
fn outward(opening: &PunchOpening, t: DVec3) -> DVec2 {
    let t = t.truncate().normalize();
    let u = if opening.counter_clockwise {
        DVec2::new(t.y, -t.x)
    } else {
        DVec2::new(-t.y, t.x)
    };
    assert!(u.distance(opening.outward(t.extend(0.0))) <= 1e-12);
    u
}

/// Checks that the outer edge of side `k` (the patch's surface edge and its `outer`
/// curve) passes through the station points `Q = P + d (cos(theta) u + sin(theta) Z)`;
/// returns the largest distance.
fn check_stations(
    opening: &PunchOpening,
    binder: &Blankholder,
    k: usize,
    stations: &[Station],
) -> f64 {
    let c = &opening.pieces[k].curve;
    let patch = &binder.patches[k];
    assert_eq!(patch.kind, PieceKind::Side);
    let v = outer_v(&patch.surface, c, &patch.outer);
    let length = c.length();
    let mut worst: f64 = 0.0;
    for st in stations {
        let t = if st.at <= 0.0 {
            0.0
        } else if st.at >= 1.0 {
            1.0
        } else {
            c.parameter_at_length(st.at * length).unwrap()
        };
        let p = c.point_at(t);
        let u = st
            .direction
            .map_or_else(|| outward(opening, c.derivative_at(t)), |d| d.normalize());
        let q = p + st.width * (st.angle.cos() * u.extend(0.0) + st.angle.sin() * DVec3::Z);
        let on_surface = patch.surface.point_at(t, v).distance(q);
        let nearest = closest_point_on_curve(&patch.outer, q).unwrap().distance;
        assert!(
            on_surface <= 1e-9 && nearest <= 1e-9,
            "side {}: station at {} is {on_surface} mm off the outer edge ({nearest} from the curve)",
            patch.name,
            st.at
        );
        worst = worst.max(on_surface).max(nearest);
    }
    worst
}

// ---------------------------------------------------------------------------------
// The fender example, through the language.
// ---------------------------------------------------------------------------------

fn fender() -> (Arc<PunchOpening>, Arc<Blankholder>, Vec<(String, Value)>) {
    let values = fender_values();
    let feature = |name: &str| -> Built {
        let (_, v) = values
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("the fender has no `{name}`"));
        match &v.data {
            Data::Record(r) => r.feature.clone().expect("a feature record"),
            other => panic!("`{name}` is {}", other.type_name()),
        }
    };
    let Some(opening) = feature("opening").shared::<PunchOpening>() else {
        panic!("`opening` is not a punch opening");
    };
    let Some(binder) = feature("binder").shared::<Blankholder>() else {
        panic!("`binder` is not a blankholder");
    };
    (opening, binder, values)
}

/// The stations a `side` without its own block gets (`DEFAULT_STATIONS` of
/// `src/eval/features/blankholder.rs`), evenly spaced.
const DEFAULT_STATIONS: usize = 5;

fn stations(widths: &[f64], angles_deg: &[f64]) -> Vec<Station> {
    let n = widths.len();
    (0..n)
        .map(|i| Station {
            at: i as f64 / (n - 1) as f64,
            width: widths[i],
            angle: angles_deg[i].to_radians(),
            direction: None,
        })
        .collect()
}

/// Issue 5, blankholder of the fender: every join C1 by eq. 4 and G1 measured, normals
/// up, each side's outer edge through the designer's station points.
#[test]
fn fender_blankholder_is_c1_and_follows_its_stations() {
    let (opening, binder, values) = fender();
    let width = values
        .iter()
        .find_map(|(n, v)| match (&v.data, n.as_str()) {
            (Data::Number(q), "binder_width") => Some(q.value),
            _ => None,
        })
        .expect("the param binder_width");
    assert_eq!(width, 200.0);
    assert_eq!(binder.patches.len(), opening.pieces.len());
    for (patch, piece) in binder.patches.iter().zip(&opening.pieces) {
        assert_eq!(
            (patch.name.as_str(), patch.kind),
            (piece.name.as_str(), piece.kind)
        );
    }
    let worst = check_joins("fender", &binder);
    let lowest = lowest_normal_z(&binder);
    assert!(lowest > 0.0, "a binder normal points down (z {lowest})");

    // The script's stations: `width = binder_width`, `angle = 0 deg`, and for `front`
    // `width = [w, w + 40 mm, w]`, `angle = [0 deg, 3 deg, 0 deg]`.
    let mut station_worst: f64 = 0.0;
    let mut sides = 0;
    for (k, piece) in opening.pieces.iter().enumerate() {
        if piece.kind != PieceKind::Side {
            continue;
        }
        sides += 1;
        let st = if piece.name == "front" {
            stations(&[width, width + 40.0, width], &[0.0, 3.0, 0.0])
        } else {
            stations(&[width; DEFAULT_STATIONS], &[0.0; DEFAULT_STATIONS])
        };
        station_worst = station_worst.max(check_stations(&opening, &binder, k, &st));
    }
    assert_eq!(sides, 4);
    println!(
        "fender blankholder @{JOIN_SAMPLES} samples/boundary: worst eq. 4 net gap \
         {:.1e} mm, net angle {:.1e} deg, ratio spread {:.1e}; measured gap {:.1e} mm, \
         normal angle {:.1e} deg; lowest normal z {lowest:.4}; stations off the outer edges \
         {station_worst:.1e} mm",
        worst.net_gap, worst.net_angle, worst.ratio_spread, worst.gap, worst.normal_angle
    );
}

// ---------------------------------------------------------------------------------
// Synthetic, hand-checkable inputs.
// ---------------------------------------------------------------------------------

/// The same square drawn clockwise: pieces in reverse order, each reversed.
fn clockwise_square() -> PunchOpeningSpec {
    let mut spec = square();
    spec.pieces.reverse();
    for p in &mut spec.pieces {
        match p {
            PieceSpec::Side(s) => s.top = s.top.reversed(),
            PieceSpec::Corner(c) => c.top = c.top.reversed(),
        }
    }
    spec
}

/// One binder entry per piece: `side(k)` gives side `k`'s stations.
fn binder_spec(
    opening: &PunchOpening,
    tautness: f64,
    side: impl Fn(usize) -> Vec<Station>,
) -> Vec<BinderPiece> {
    opening
        .pieces
        .iter()
        .enumerate()
        .map(|(k, p)| match p.kind {
            PieceKind::Side => BinderPiece::Side(BinderSide {
                stations: side(k),
                start_tangent: None,
                end_tangent: None,
            }),
            PieceKind::Corner => BinderPiece::Corner { tautness },
        })
        .collect()
}

fn uniform(width: f64, angle: f64) -> Vec<Station> {
    (0..3)
        .map(|i| Station {
            at: i as f64 / 2.0,
            width,
            angle,
            direction: None,
        })
        .collect()
}

/// Whether a top-view point lies inside the square opening with its R 50 fillets.
fn inside_square(p: DVec2) -> bool {
    let (x, y) = (p.x.abs(), p.y.abs());
    if x >= HALF || y >= HALF {
        return false;
    }
    if x > INSET && y > INSET {
        return DVec2::new(x, y).distance(DVec2::splat(INSET)) < RADIUS;
    }
    true
}

/// Signed distance-like figure: how far outside the square opening a top-view point is
/// (negative inside), exact outside.
fn outside_by(p: DVec2) -> f64 {
    let (x, y) = (p.x.abs(), p.y.abs());
    if x > INSET && y > INSET {
        DVec2::new(x, y).distance(DVec2::splat(INSET)) - RADIUS
    } else {
        (x - HALF).max(y - HALF)
    }
}

/// The fillet centre nearest a top-view point.
fn fillet_center(p: DVec2) -> DVec2 {
    DVec2::new(INSET * p.x.signum(), INSET * p.y.signum())
}

/// Case (a): width 100, angle 0, tautness 0 on the flat square: the binder is flat and
/// normal to +Z, its sides' outer edges are the square's sides moved out by 100 mm and
/// its corners' outer edges lie on the concentric circles of radius 150.
///
/// The corner tolerance, 0.05 mm. The outer corner `g1` interpolates the opening corner
/// `g0` (measured within 5e-7 mm of R 50) scaled by 3 about the fillet centre, so at its
/// interpolation points it lies within 3 x 5e-7 mm of R 150 (measured 1e-6 mm). Between
/// them it is a cubic spline whose end derivatives eq. 4 fixes to the opening corner's,
/// 78.5 mm (pi R / 2): a third of the scaled curve's speed, 235.6 mm, because the
/// straight sides' outer edges run exactly as fast as the sides. Over the end span (a
/// fortieth of the parameter) that shortfall of 157 mm moves points up to about
/// 4/27 x 157 / 40 = 0.6 mm along the curve, and across it by that times the turn of the
/// tangent over the span (90 deg / 40 = 0.04 rad): about 0.02 mm. 0.05 mm (5 delta)
/// leaves a factor 2 over that estimate; measured: 0.0116 mm, in the end spans.
#[test]
fn flat_square_binder_is_flat_with_round_corners() {
    let opening = po::build(&square()).unwrap();
    let spec = binder_spec(&opening, 0.0, |_| uniform(100.0, 0.0));
    let binder = bh::build(&opening, &spec).unwrap();
    let worst = check_joins("square", &binder);
    let mut height: f64 = 0.0;
    for p in &binder.patches {
        for q in p.surface.control_points() {
            height = height.max(q.z.abs());
        }
    }
    let lowest = lowest_normal_z(&binder);
    let (mut side_off, mut corner_off) = (0.0f64, 0.0f64);
    let samples = 10_000;
    for p in &binder.patches {
        for i in 0..=samples {
            let q = p.outer.point_at(i as f64 / samples as f64);
            height = height.max(q.z.abs());
            let xy = q.truncate();
            match p.kind {
                // Out by 100: on the line |x| = 300 or |y| = 300.
                PieceKind::Side => {
                    side_off = side_off.max((xy.x.abs().max(xy.y.abs()) - (HALF + 100.0)).abs())
                }
                PieceKind::Corner => {
                    let c = fillet_center(xy);
                    corner_off = corner_off.max((xy.distance(c) - (RADIUS + 100.0)).abs())
                }
            }
        }
    }
    for (k, p) in opening.pieces.iter().enumerate() {
        if p.kind == PieceKind::Side {
            check_stations(&opening, &binder, k, &uniform(100.0, 0.0));
        }
    }
    eprintln!(
        "flat square binder: |z| {height:.1e} mm, lowest normal z {lowest:.15}, side outer \
         edges off |x|,|y| = 300 by {side_off:.1e} mm, corner outer edges off R 150 by \
         {corner_off:.4} mm; joins {worst:?}"
    );
    assert!(
        height <= 1e-9,
        "the flat binder leaves z = 0 by {height} mm"
    );
    assert!(
        lowest >= 1.0 - 1e-12,
        "a normal of the flat binder is not +Z: {lowest}"
    );
    assert!(side_off <= 1e-9, "a side's outer edge is {side_off} mm off");
    assert!(
        corner_off <= 0.05,
        "a corner's outer edge is {corner_off} mm off R 150"
    );
}

/// The bottom side split at x = 0 into two collinear sides: the left one's view an arc
/// of radius 5000 tangent to z = 0 at x = 0, the right one's the line z = 0.
fn split_square() -> PunchOpeningSpec {
    let big = 5000.0;
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
    let view = |curve| SideView {
        origin: DVec2::ZERO,
        axis: DVec2::X,
        curve,
    };
    square_with_bottom(vec![
        side("bottom_a", line2((-INSET, -HALF), (0.0, -HALF)), view(arc)),
        side(
            "bottom_b",
            line2((0.0, -HALF), (INSET, -HALF)),
            view(line2((-50.0, 0.0), (250.0, 0.0))),
        ),
    ])
}

/// Case (b): two sides meeting without a corner share their boundary ruling and are C1
/// by eq. 4 and G1 measured there, with stations that vary in width and angle.
#[test]
fn sides_meeting_without_a_corner_join_c1() {
    let opening = po::build(&split_square()).unwrap();
    assert_eq!(opening.pieces[0].name, "bottom_a");
    assert_eq!(opening.pieces[1].name, "bottom_b");
    let st = |k: usize| -> Vec<Station> {
        match k {
            // Different widths and angles away from the shared end, equal at it.
            0 => vec![
                Station {
                    at: 0.0,
                    width: 120.0,
                    angle: 0.05,
                    direction: None,
                },
                Station {
                    at: 0.4,
                    width: 160.0,
                    angle: 0.10,
                    direction: None,
                },
                Station {
                    at: 1.0,
                    width: 140.0,
                    angle: 0.02,
                    direction: None,
                },
            ],
            1 => vec![
                Station {
                    at: 0.0,
                    width: 140.0,
                    angle: 0.02,
                    direction: None,
                },
                Station {
                    at: 0.7,
                    width: 100.0,
                    angle: 0.0,
                    direction: None,
                },
                Station {
                    at: 1.0,
                    width: 110.0,
                    angle: 0.0,
                    direction: None,
                },
            ],
            _ => uniform(110.0, 0.0),
        }
    };
    let spec = binder_spec(&opening, 0.5, st);
    let binder = bh::build(&opening, &spec).unwrap();
    let (a, b) = (&binder.patches[0].surface, &binder.patches[1].surface);
    let (net_gap, net_angle, ratio_spread) = eq4(a, b);
    let (gap, normal_angle) = measured_g1(a, b);
    eprintln!(
        "split side join: eq. 4 net gap {net_gap:.1e} mm, net angle {net_angle:.1e} deg, \
         ratio spread {ratio_spread:.1e}; measured gap {gap:.1e} mm, normal angle \
         {normal_angle:.1e} deg"
    );
    let worst = check_joins("split square", &binder);
    assert!(worst.net_angle <= MAX_NET_ANGLE_DEG);
    for k in 0..2 {
        check_stations(&opening, &binder, k, &st(k));
    }
    assert!(lowest_normal_z(&binder) > 0.0);
    // Stations that disagree at the shared end are refused.
    let bad = binder_spec(&opening, 0.5, |k| {
        if k == 1 {
            uniform(150.0, 0.0)
        } else {
            uniform(110.0, 0.0)
        }
    });
    let err = bh::build(&opening, &bad).unwrap_err();
    assert!(
        matches!(err.problem, BinderProblem::OuterEndsDisagree { gap } if (gap - 40.0).abs() < 1e-6),
        "{err:?}"
    );
}

/// Case (d): drawn clockwise, the binder's normals still point up and its outer edges
/// lie outside the opening (checked against the exact rounded square).
#[test]
fn clockwise_profile_gives_an_upward_binder_outside_the_opening() {
    let opening = po::build(&clockwise_square()).unwrap();
    assert!(!opening.counter_clockwise);
    for (width, angle) in [(100.0, 0.0), (60.0, 0.2), (250.0, -0.1)] {
        let spec = binder_spec(&opening, 0.3, |_| uniform(width, angle));
        let binder = bh::build(&opening, &spec).unwrap();
        let lowest = lowest_normal_z(&binder);
        let mut nearest = f64::INFINITY;
        for p in &binder.patches {
            for i in 0..=2000 {
                let q = p.outer.point_at(i as f64 / 2000.0).truncate();
                assert!(!inside_square(q), "{}: outer edge inside at {q}", p.name);
                nearest = nearest.min(outside_by(q));
            }
        }
        // Measured horizontally, the edge is `width cos(angle)` out.
        let out = width * f64::cos(angle);
        eprintln!(
            "clockwise square, width {width} angle {angle}: lowest normal z {lowest:.6}, outer \
             edges at least {nearest:.4} mm outside (width cos(angle) {out:.4})"
        );
        assert!(lowest > 0.0, "a normal points down: {lowest}");
        assert!(
            nearest >= 0.9 * out,
            "the outer edge comes within {nearest} mm"
        );
        check_joins("clockwise square", &binder);
        for (k, p) in opening.pieces.iter().enumerate() {
            if p.kind == PieceKind::Side {
                check_stations(&opening, &binder, k, &uniform(width, angle));
            }
        }
    }
}

/// The corner `g0` of case (e): a cubic Bezier from (0, -100) to (100, 0) in the top
/// view, sagging from z = 10 down towards 0 and up to z = 20.
fn sagging_g0() -> Curve3 {
    Curve3::bezier(vec![
        DVec3::new(0.0, -100.0, 10.0),
        DVec3::new(55.0, -100.0, 0.0),
        DVec3::new(100.0, -55.0, 0.0),
        DVec3::new(100.0, 0.0, 20.0),
    ])
    .unwrap()
}

/// Case (e), `outer_corner` step by step.
#[test]
fn outer_corner_steps() {
    let g0 = sagging_g0();
    // Step 1's similarity: the chord (100, 100) onto (200, 200) (scale 2), moved so
    // (0, -100) lands on A.
    let (a, b) = (DVec3::new(0.0, -200.0, 30.0), DVec3::new(200.0, 0.0, 40.0));
    let similarity =
        |p: DVec3| DVec2::new(0.0, -200.0) + 2.0 * (p.truncate() - DVec2::new(0.0, -100.0));
    let samples = tessellate_curve(&g0, &Tolerance::new(DELTA).unwrap()).unwrap();
    assert!(samples.params.len() >= 5);
    let linear = |t: f64| (1.0 - t) * a.z + t * b.z;
    // The moved curve's own derivatives at its ends (g0' is (165, 0, -30) and
    // (0, 165, 60); the end corrections za = zb = 20 add no slope): eq. 4 end
    // derivatives along them, slower than them, leave the heights as moved.
    let natural = |tautness: f64| {
        let rise = b.z - a.z;
        (
            DVec3::new(330.0, 0.0, (1.0 - tautness) * -30.0 + tautness * rise),
            DVec3::new(0.0, 330.0, (1.0 - tautness) * 60.0 + tautness * rise),
        )
    };

    for tautness in [0.0, 0.3, 1.0] {
        let (x0, x1) = natural(tautness);
        let (d0, d1) = (x0 * (240.0 / 330.0), x1 * (260.0 / 330.0));
        let corner = outer_corner_samples(&g0, a, b, tautness, d0, d1, DELTA).unwrap();
        let g1 = &corner.curve;
        assert_eq!(
            g1,
            &outer_corner(&g0, a, b, tautness, d0, d1, DELTA).unwrap()
        );
        // Ends exactly A and B, end derivatives d0 and d1.
        assert_eq!(g1.start_point(), a);
        assert_eq!(g1.end_point(), b);
        let (e0, e1) = (g1.derivative_at(0.0), g1.derivative_at(1.0));
        assert!(e0.distance(d0) <= 1e-9 * d0.length(), "{e0} vs {d0}");
        assert!(e1.distance(d1) <= 1e-9 * d1.length(), "{e1} vs {d1}");
        // The samples are g0's step-rule samples; their parameters on g1 increase from
        // 0 to 1, and g1 passes through every point at its parameter.
        assert_eq!(corner.sample_params, samples.params);
        let n = corner.params.len();
        assert_eq!((corner.params[0], corner.params[n - 1]), (0.0, 1.0));
        assert!(corner.params.windows(2).all(|w| w[1] > w[0]));
        // At the interior samples: the similarity in the top view, and heights that are
        // g0's moved by the end corrections, pulled towards the straight blend.
        let (mut xy_off, mut z_off, mut on) = (0.0f64, 0.0f64, 0.0f64);
        for i in 1..n - 1 {
            let (t, p, q) = (
                samples.params[i],
                g0.point_at(samples.params[i]),
                corner.points[i],
            );
            on = on.max(g1.point_at(corner.params[i]).distance(q));
            xy_off = xy_off.max(q.truncate().distance(similarity(p)));
            let moved = p.z + (1.0 - t) * (a.z - 10.0) + t * (b.z - 20.0);
            let z = (1.0 - tautness) * moved + tautness * linear(t);
            z_off = z_off.max((q.z - z).abs());
        }
        eprintln!(
            "outer corner, tautness {tautness}: {n} samples, top view off the similarity \
             {xy_off:.1e} mm, heights off {z_off:.1e} mm, g1 off its points {on:.1e} mm"
        );
        assert!(
            xy_off <= 1e-9 && z_off <= 1e-9 && on <= 1e-9,
            "{xy_off} {z_off} {on}"
        );
    }

    // Tautness 0 keeps the sag.
    let (x0, x1) = natural(0.0);
    let sagging = outer_corner_samples(&g0, a, b, 0.0, x0 * 0.8, x1 * 0.8, DELTA).unwrap();
    let mid = sagging.points.len() / 2;
    let sag = linear(sagging.sample_params[mid]) - sagging.points[mid].z;
    eprintln!("tautness 0 sags {sag:.3} mm at mid-corner");
    assert!(sag > 5.0, "the corner does not sag: {sag}");

    // End derivatives steeper than the moved curve (eq. 4 from sides that climb faster
    // than the corner's moved heights): the edge still ends on d0 and d1 exactly, and
    // the difference is spread over the corner (`tests/blankholder_corners.rs` checks
    // that no radius collapses near the joins).
    let (d0, d1) = (DVec3::new(240.0, 0.0, 30.0), DVec3::new(0.0, 260.0, -20.0));
    let steep = outer_corner_samples(&g0, a, b, 0.0, d0, d1, DELTA).unwrap();
    assert!(steep.curve.derivative_at(0.0).distance(d0) <= 1e-9 * d0.length());
    assert!(steep.curve.derivative_at(1.0).distance(d1) <= 1e-9 * d1.length());

    // Tautness 0 on a g0 at constant z, with A and B at that z: the outer corner stays at
    // it.
    let flat = g0.map_points(|p| DVec3::new(p.x, p.y, 5.0));
    let (a5, b5) = (DVec3::new(a.x, a.y, 5.0), DVec3::new(b.x, b.y, 5.0));
    let g1 = outer_corner(
        &flat,
        a5,
        b5,
        0.0,
        DVec3::new(240.0, 0.0, 0.0),
        DVec3::new(0.0, 260.0, 0.0),
        DELTA,
    )
    .unwrap();
    let mut off: f64 = 0.0;
    for i in 0..=10_000 {
        off = off.max((g1.point_at(i as f64 / 10_000.0).z - 5.0).abs());
    }
    assert!(off <= 1e-9, "the flat corner leaves z = 5 by {off} mm");
}

/// Case (f): a very wide binder is fine; a direction into the opening is refused; an
/// outer edge swung into the opening by a direction override is refused.
#[test]
fn wide_binders_are_fine_but_inward_edges_are_refused() {
    let opening = po::build(&square()).unwrap();
    let binder = bh::build(
        &opening,
        &binder_spec(&opening, 0.0, |_| uniform(2000.0, 0.0)),
    )
    .unwrap();
    assert!(lowest_normal_z(&binder) > 0.0);
    for p in &binder.patches {
        for i in 0..=1000 {
            let q = p.outer.point_at(i as f64 / 1000.0).truncate();
            assert!(outside_by(q) >= 1900.0, "{}: {q}", p.name);
        }
    }
    check_joins("wide square", &binder);

    // Bottom side (piece 0) with a direction into the opening, or with none at all.
    for dir in [DVec2::Y, DVec2::new(1.0, 0.0), DVec2::ZERO] {
        let spec = binder_spec(&opening, 0.0, |k| {
            let mut s = uniform(2000.0, 0.0);
            if k == 0 {
                s[1].direction = Some(dir);
            }
            s
        });
        let err = bh::build(&opening, &spec).unwrap_err();
        assert_eq!(err.piece, 0);
        assert_eq!(err.problem, BinderProblem::Direction, "direction {dir}");
    }

    // A middle station on the bottom side whose direction runs almost along the side
    // (still outward: (-1, -0.01)) puts its point just below the side at x = -150: the
    // outer curve doubles back (from x = -150 left and back, then right) and the patch
    // folds over itself, its normal turning down.
    let spec = binder_spec(&opening, 0.0, |k| {
        let mut s = uniform(100.0, 0.0);
        if k == 0 {
            s[1].width = 150.0;
            s[1].direction = Some(DVec2::new(-1.0, -0.01));
        }
        s
    });
    let err = bh::build(&opening, &spec).unwrap_err();
    eprintln!("folded side: {}", err.problem);
    assert_eq!(err.piece, 0);
    assert!(
        matches!(err.problem, BinderProblem::Kernel(GeomError::Singular { what }) if what.contains("folds")),
        "{err:?}"
    );
}

/// The flat L-shaped opening of case (f): the 400 x 400 square without its upper right
/// quarter, every corner rounded with R 50 (the inner one, at (200, 200), concave),
/// counter-clockwise from the bottom.
fn l_shape() -> PunchOpeningSpec {
    let view = |axis| SideView {
        origin: DVec2::ZERO,
        axis,
        curve: line2((-100.0, 0.0), (500.0, 0.0)),
    };
    let concave = circular_arc(
        DVec2::new(250.0, 250.0),
        DVec2::X,
        DVec2::Y,
        RADIUS,
        FRAC_PI_2 * 2.0,
        FRAC_PI_2 * 3.0,
    )
    .unwrap()
    .reversed();
    let pieces = vec![
        side("bottom", line2((50.0, 0.0), (350.0, 0.0)), view(DVec2::X)),
        corner("c1", DVec2::new(350.0, 50.0), -90.0),
        side(
            "right",
            line2((400.0, 50.0), (400.0, 150.0)),
            view(DVec2::Y),
        ),
        corner("c2", DVec2::new(350.0, 150.0), 0.0),
        side(
            "step",
            line2((350.0, 200.0), (250.0, 200.0)),
            view(DVec2::X),
        ),
        PieceSpec::Corner(CornerSpec {
            name: "inner".into(),
            top: concave,
            magnitudes: [Magnitude::Natural(1.0); 2],
        }),
        side(
            "riser",
            line2((200.0, 250.0), (200.0, 350.0)),
            view(DVec2::Y),
        ),
        corner("c4", DVec2::new(150.0, 350.0), 0.0),
        side("top", line2((150.0, 400.0), (50.0, 400.0)), view(DVec2::X)),
        corner("c5", DVec2::new(50.0, 350.0), 90.0),
        side("left", line2((0.0, 350.0), (0.0, 50.0)), view(DVec2::Y)),
        corner("c6", DVec2::new(50.0, 50.0), 180.0),
    ];
    PunchOpeningSpec {
        pieces,
        delta: DELTA,
        max_step: None,
    }
}

/// Whether a top-view point lies inside the L of `l_shape`, its fillets included.
fn inside_l(p: DVec2) -> bool {
    let (x, y) = (p.x, p.y);
    let arms = (x > 0.0 && x < 400.0 && y > 0.0 && y < 200.0)
        || (x > 0.0 && x < 200.0 && y > 0.0 && y < 400.0);
    // The concave fillet adds the notch's corner outside its circle.
    let notch = (200.0..=250.0).contains(&x)
        && (200.0..=250.0).contains(&y)
        && p.distance(DVec2::splat(250.0)) > RADIUS;
    // The convex fillets cut the corners outside their circles.
    let cut = [
        (DVec2::new(350.0, 50.0), x > 350.0 && y < 50.0),
        (DVec2::new(350.0, 150.0), x > 350.0 && y > 150.0),
        (DVec2::new(150.0, 350.0), x > 150.0 && y > 350.0),
        (DVec2::new(50.0, 350.0), x < 50.0 && y > 350.0),
        (DVec2::new(50.0, 50.0), x < 50.0 && y < 50.0),
    ]
    .iter()
    .any(|&(c, beyond)| beyond && p.distance(c) >= RADIUS);
    (arms || notch) && !cut
}

/// Case (f) on a concave opening: a station direction on the step (the short arm's top
/// side, outward +Y) tilted towards the tall arm, still outward, places its point inside
/// the tall arm: the outer edge enters the opening.
#[test]
fn outer_edge_entering_a_concave_opening_is_refused() {
    let opening = po::build(&l_shape()).unwrap();
    assert!(opening.counter_clockwise);
    let step = opening
        .pieces
        .iter()
        .position(|p| p.name == "step")
        .unwrap();
    // 30 mm all round is fine, and C1 everywhere, the concave corner included.
    let fine = bh::build(
        &opening,
        &binder_spec(&opening, 0.0, |_| uniform(30.0, 0.0)),
    )
    .unwrap();
    assert!(lowest_normal_z(&fine) > 0.0);
    check_joins("L shape", &fine);
    // The step's middle station: P = (300, 200), u = (-1, 0.25) / |.|, d = 150 puts Q at
    // about (154, 236), inside the tall arm.
    let spec = binder_spec(&opening, 0.0, |k| {
        let mut s = uniform(30.0, 0.0);
        if k == step {
            s[1].width = 150.0;
            s[1].direction = Some(DVec2::new(-1.0, 0.25));
        }
        s
    });
    let err = bh::build(&opening, &spec).unwrap_err();
    eprintln!("swung edge on the L: {err:?}");
    assert_eq!(err.piece, step);
    match err.problem {
        BinderProblem::CrossesOpening { at } => {
            // Inside the opening above the step: across the notch.
            assert!(inside_l(at.truncate()), "{at} is not inside the opening");
            assert!(at.y > 200.0 && at.x < 250.0, "{at}");
        }
        other => panic!("expected CrossesOpening, got {other:?}"),
    }
    // A width beyond the concave fillet's radius: the sides' outer ends, (250, 350) and
    // (350, 250), lie the other way round than the opening corner's ends, (250, 200) and
    // (200, 250); the outer corner turned half a turn to meet them runs back against the
    // opening corner and the patch folds over itself.
    let inner = opening
        .pieces
        .iter()
        .position(|p| p.name == "inner")
        .unwrap();
    let err = bh::build(
        &opening,
        &binder_spec(&opening, 0.0, |_| uniform(150.0, 0.0)),
    )
    .unwrap_err();
    eprintln!(
        "150 mm round the L: piece {} ({}): {}",
        err.piece, opening.pieces[err.piece].name, err.problem
    );
    assert_eq!(err.piece, inner);
    assert!(
        matches!(err.problem, BinderProblem::Kernel(GeomError::Singular { what }) if what.contains("folds")),
        "{err:?}"
    );
}
