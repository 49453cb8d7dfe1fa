//! The step draw (paper 001 section 4; GitHub issue 6): the product edge on the product
//! outline, C1 joins by eq. 4 on the control net and G1 when measured, every section
//! from the punch opening line to the product outline, the punch-side edge's deviation
//! from the opening line, normals up; on the fender example through the language and on
//! hand-checkable inputs built with the kernel API. Run with `--nocapture` to see the
//! measured figures.
//!
//! Every figure is measured here from the built surfaces and the guides, independently
//! of the figures the kernel stores (which are cross-checked, not trusted).

#[path = "common/fender.rs"]
mod fender_example;
#[path = "common/joins.rs"]
mod joins;
use std::sync::Arc;

use dieface::die::continuity::measure_join;
use dieface::die::punch_opening::PunchOpening;
use dieface::die::step_draw::{self as sd, Guides, Options, Patch, Problem, SectionSpec, StepDraw};
use dieface::eval::features::Built;
use dieface::eval::{Data, Value};
use dieface::geom::interpolate::{interpolate, Interpolation};
use dieface::geom::inversion::{closest_point_on_curve, project_to_curve_near};
use dieface::geom::{Curve2, Curve3, Direction, NurbsCurve, NurbsSurface};
use fender_example::fender_values;
use glam::{DVec2, DVec3};
use joins::*;

/// Samples per patch along the outline for the edge figures.
const EDGE_SAMPLES: usize = 1000;
/// The step draw meets the product exactly (paper 001 section 4.4): to rounding, well under
/// the 0.001 mm of strict checkers.
const MAX_PRODUCT_GAP: f64 = 1e-6;
/// Sections start on the opening line and end on the outline.
const MAX_END_DISTANCE: f64 = 1e-9;
/// G1 as strict checkers see it (`docs/methods.md`, "Numbers").
const MAX_JOIN_GAP: f64 = 0.001;
const MAX_NORMAL_ANGLE_DEG: f64 = 0.05;
/// Eq. 4 on the control net: parallel legs and one ratio, to rounding.
const MAX_NET_ANGLE_DEG: f64 = 1e-6;
const MAX_RATIO_SPREAD: f64 = 1e-9;
/// A patch's `sections` are its iso-curves at the knots along the outline.
const MAX_ISO_MISMATCH: f64 = 1e-8;

fn sz(s: f64, z: f64) -> DVec2 {
    DVec2::new(s, z)
}

// ---------------------------------------------------------------------------------
// Measurements.
// ---------------------------------------------------------------------------------

/// The parameters v of a patch's product edge and punch-side edge.
fn edge_vs(p: &Patch) -> (f64, f64) {
    let (v0, v1) = p.surface.domain_v();
    if p.reversed {
        (v0, v1)
    } else {
        (v1, v0)
    }
}

/// The distinct knots of the surface along u: where the patch's sections are.
fn u_knots(s: &NurbsSurface) -> Vec<f64> {
    s.knots_u().distinct().iter().map(|&(k, _)| k).collect()
}

/// Largest distance from the edge `v = v_edge` of `s` to `curve` at `EDGE_SAMPLES + 1`
/// points. Each sample is projected starting from the previous foot point; a local
/// minimum found that way is never closer than the true one, so the figure can only be
/// too large; a sample whose local distance exceeds `recheck` is searched globally.
fn edge_to_curve(s: &NurbsSurface, v_edge: f64, curve: &Curve3, recheck: f64) -> f64 {
    let (u0, u1) = s.domain_u();
    let mut worst: f64 = 0.0;
    let mut guess: Option<f64> = None;
    for i in 0..=EDGE_SAMPLES {
        let p = s.point_at(u0 + (u1 - u0) * i as f64 / EDGE_SAMPLES as f64, v_edge);
        let hit = match guess {
            Some(t) => {
                let near = project_to_curve_near(curve, p, t).expect("projection");
                if near.distance > recheck {
                    closest_point_on_curve(curve, p).expect("closest point")
                } else {
                    near
                }
            }
            None => closest_point_on_curve(curve, p).expect("closest point"),
        };
        guess = Some(hit.t);
        worst = worst.max(hit.distance);
    }
    worst
}

fn distance_to(curve: &Curve3, p: DVec3) -> f64 {
    closest_point_on_curve(curve, p)
        .expect("closest point")
        .distance
}

/// The worst measured figures of a step draw.
#[derive(Debug, Default, Clone, Copy)]
struct Figures {
    /// Product edge to the product outline (mm).
    product_gap: f64,
    /// Punch-side edge to the punch opening line (mm).
    opening_deviation: f64,
    /// Section start points to the opening line, end points to the outline (mm).
    section_start: f64,
    section_end: f64,
    /// A patch's sections against its iso-curves at its knots (mm).
    iso_mismatch: f64,
    /// Sections' control points off the vertical plane through their ends (mm).
    off_plane: f64,
    /// Sections checked.
    sections: usize,
    /// Eq. 4 on the control net.
    net_gap: f64,
    net_angle: f64,
    ratio_spread: f64,
    /// Measured along the shared boundaries.
    join_gap: f64,
    normal_angle: f64,
    /// Smallest +Z component of the unit normal over a grid on every patch.
    lowest_normal_z: f64,
}

/// Measures everything issue 6 asks of `built` against its guides, asserts the bounds
/// common to every case (the opening deviation is left to the caller) and prints the
/// figures under `label`.
fn check(label: &str, guides: &Guides, built: &StepDraw) -> Figures {
    let (product, opening) = (&guides.product, &guides.opening);
    let mut f = Figures {
        lowest_normal_z: f64::INFINITY,
        ..Figures::default()
    };
    assert!(!built.patches.is_empty(), "{label}: no patches");
    for p in &built.patches {
        let (pv, ov) = edge_vs(p);
        // Edges.
        let gap = edge_to_curve(&p.surface, pv, product, MAX_PRODUCT_GAP);
        let dev = edge_to_curve(&p.surface, ov, opening, 1e-3);
        // Sections: start on the opening, end on the outline, and they are the
        // surface's iso-curves at the knots along u.
        let knots = u_knots(&p.surface);
        assert_eq!(
            knots.len(),
            p.sections.len(),
            "{label} {}: one section per distinct knot along the outline",
            p.name
        );
        let (mut start, mut end, mut iso, mut upright) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for (k, (c, &u)) in p.sections.iter().zip(&knots).enumerate() {
            let ds = distance_to(opening, c.start_point());
            let de = distance_to(product, c.end_point());
            assert!(
                ds <= MAX_END_DISTANCE && de <= MAX_END_DISTANCE,
                "{label} {} section {k}: starts {ds} mm off the opening line, ends {de} mm \
                 off the product outline",
                p.name
            );
            start = start.max(ds);
            end = end.max(de);
            // In the vertical plane through its ends: in the top view on their line.
            let (a, b) = (c.start_point().truncate(), c.end_point().truncate());
            let d = (b - a).normalize();
            for q in c.control_points() {
                upright = upright.max(d.perp_dot(q.truncate() - a).abs());
            }
            let along = p.surface.iso_curve(Direction::U, u);
            let mut pts = along.control_points().to_vec();
            if p.reversed {
                pts.reverse();
            }
            assert_eq!(pts.len(), c.control_points().len());
            for (a, b) in pts.iter().zip(c.control_points()) {
                iso = iso.max(a.distance(*b));
            }
        }
        assert!(
            iso <= MAX_ISO_MISMATCH,
            "{label} {}: sections {iso} mm from the iso-curves at the knots",
            p.name
        );
        // Normals up.
        let ((u0, u1), (v0, v1)) = (p.surface.domain_u(), p.surface.domain_v());
        let mut low = f64::INFINITY;
        for i in 0..=20 {
            for j in 0..=20 {
                let (u, v) = (
                    u0 + (u1 - u0) * i as f64 / 20.0,
                    v0 + (v1 - v0) * j as f64 / 20.0,
                );
                let n = p.surface.normal(u, v).expect("normal");
                low = low.min(n.z);
            }
        }
        eprintln!(
            "{label} patch {:>22}: product gap {gap:.2e} mm, punch-side deviation {dev:.3e} \
             mm, {} sections: start {start:.1e} mm, end {end:.1e} mm, iso {iso:.1e} mm, off \
             their vertical planes {upright:.1e} mm, lowest normal z {low:.3}{}",
            p.name,
            p.sections.len(),
            if p.reversed { " (v reversed)" } else { "" }
        );
        assert!(
            gap <= MAX_PRODUCT_GAP,
            "{label} {}: product edge {gap} mm off the outline",
            p.name
        );
        assert!(
            low > 0.0,
            "{label} {}: a normal points down (z {low})",
            p.name
        );
        f.product_gap = f.product_gap.max(gap);
        f.opening_deviation = f.opening_deviation.max(dev);
        f.section_start = f.section_start.max(start);
        f.section_end = f.section_end.max(end);
        f.iso_mismatch = f.iso_mismatch.max(iso);
        f.off_plane = f.off_plane.max(upright);
        f.sections += p.sections.len();
        f.lowest_normal_z = f.lowest_normal_z.min(low);
    }

    // Joins, the last with the first for a closed outline.
    let n = built.patches.len();
    let pairs = if guides.closed { n } else { n - 1 };
    assert_eq!(
        built.quality.joins.len(),
        pairs,
        "{label}: one join per pair"
    );
    for k in 0..pairs {
        let (a, b) = (&built.patches[k], &built.patches[(k + 1) % n]);
        let context = format!("{label}: join {} > {}", a.name, b.name);
        assert_eq!(
            a.reversed, b.reversed,
            "{context}: neighbours disagree on the direction across"
        );
        // The shared boundary is the same section.
        let last = a.sections.last().unwrap();
        let first = &b.sections[0];
        let shared = last
            .control_points()
            .iter()
            .zip(first.control_points())
            .map(|(x, y)| x.distance(*y))
            .fold(0.0f64, f64::max);
        assert!(
            shared <= 1e-9,
            "{context}: the shared section differs by {shared} mm"
        );
        let (net_gap, net_angle, ratio_spread) = eq4(&a.surface, &b.surface);
        let (gap, normal_angle) = measured_g1(&a.surface, &b.surface);
        let kernel = measure_join(&a.surface, &b.surface, JOIN_SAMPLES);
        let stored = &built.quality.joins[k];
        assert_eq!(
            (stored.0.as_str(), stored.1.as_str()),
            (a.name.as_str(), b.name.as_str())
        );
        assert_eq!(
            stored.2, kernel,
            "{context}: the stored figures are measure_join's"
        );
        eprintln!(
            "{label} join {:>22} > {:<22}: eq. 4 net gap {net_gap:.1e} mm, net angle \
             {net_angle:.1e} deg, ratio spread {ratio_spread:.1e} (measure_join {:.1e} deg, \
             {:.1e}); measured gap {gap:.1e} mm, normal angle {normal_angle:.1e} deg \
             (measure_join {:.1e} mm, {:.1e} deg)",
            a.name, b.name, kernel.net_angle, kernel.ratio_spread, kernel.gap, kernel.normal_angle
        );
        assert!(
            net_gap <= 1e-9 && kernel.net_gap <= 1e-9,
            "{context}: net gap {net_gap}"
        );
        assert!(
            net_angle <= MAX_NET_ANGLE_DEG && kernel.net_angle <= MAX_NET_ANGLE_DEG,
            "{context}: eq. 4 legs {net_angle} deg apart (measure_join {})",
            kernel.net_angle
        );
        assert!(
            ratio_spread <= MAX_RATIO_SPREAD && kernel.ratio_spread <= MAX_RATIO_SPREAD,
            "{context}: eq. 4 ratio spread {ratio_spread} (measure_join {})",
            kernel.ratio_spread
        );
        assert!(
            gap <= MAX_JOIN_GAP && kernel.gap <= MAX_JOIN_GAP,
            "{context}: gap {gap}"
        );
        assert!(
            normal_angle <= MAX_NORMAL_ANGLE_DEG && kernel.normal_angle <= MAX_NORMAL_ANGLE_DEG,
            "{context}: normals {normal_angle} deg apart (measure_join {})",
            kernel.normal_angle
        );
        f.net_gap = f.net_gap.max(net_gap);
        f.net_angle = f.net_angle.max(net_angle);
        f.ratio_spread = f.ratio_spread.max(ratio_spread);
        f.join_gap = f.join_gap.max(gap);
        f.normal_angle = f.normal_angle.max(normal_angle);
    }
    let q = &built.quality;
    eprintln!(
        "{label}: {} patches, {} sections; worst product gap {:.2e} mm, section start {:.1e} \
         mm / end {:.1e} mm, off their vertical planes {:.2e} mm, punch-side deviation {:.4e} \
         mm; eq. 4 net gap {:.1e} mm, angle \
         {:.1e} deg, ratio spread {:.1e}; measured join gap {:.1e} mm, normal angle {:.1e} \
         deg; lowest normal z {:.3} (kernel: product gap {:.2e}, opening deviation {:.4e}, \
         section fit {:.1e}, end snap {:.1e})",
        n,
        f.sections,
        f.product_gap,
        f.section_start,
        f.section_end,
        f.off_plane,
        f.opening_deviation,
        f.net_gap,
        f.net_angle,
        f.ratio_spread,
        f.join_gap,
        f.normal_angle,
        f.lowest_normal_z,
        q.product_gap,
        q.opening_deviation,
        q.section_fit,
        q.end_snap.max(q.knot_move)
    );
    // Sections lie in the vertical planes through their ends (eq. 7-9 on sections drawn
    // in vertical planes), except by as much as a key section's product end was moved
    // along the outline onto a knot.
    assert!(
        f.off_plane <= q.knot_move.max(q.end_snap) + 1e-9,
        "{label}: sections lean {} mm out of their vertical planes (knot move {})",
        f.off_plane,
        q.knot_move
    );
    // The stored figures agree with the measured ones (the kernel measures the punch
    // side against the opening tessellated to a hundredth of its tolerance).
    assert!(q.product_gap <= MAX_PRODUCT_GAP, "{label}: {q:?}");
    assert!(
        (q.opening_deviation - f.opening_deviation).abs() <= 1e-3 * (1.0 + f.opening_deviation),
        "{label}: the kernel's opening deviation {} against {} measured",
        q.opening_deviation,
        f.opening_deviation
    );
    f
}

// ---------------------------------------------------------------------------------
// The fender example, through the language.
// ---------------------------------------------------------------------------------

fn fender() -> (Arc<StepDraw>, Curve3, Arc<PunchOpening>) {
    let values = fender_values();
    let value = |name: &str| -> &Value {
        &values
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("the fender has no `{name}`"))
            .1
    };
    let feature = |name: &str| -> Built {
        match &value(name).data {
            Data::Record(r) => r.feature.clone().expect("a feature record"),
            other => panic!("`{name}` is {}", other.type_name()),
        }
    };
    let Some(addendum) = feature("addendum").shared::<dieface::die::step_draw::StepDraw>() else {
        panic!("`addendum` is not a step draw");
    };
    let Some(opening) = feature("opening").shared::<dieface::die::punch_opening::PunchOpening>()
    else {
        panic!("`opening` is not a punch opening");
    };
    let Data::Curve3(outline) = &value("outline").data else {
        panic!("`outline` is not a 3-D curve");
    };
    (addendum, (**outline).clone(), opening)
}

/// Issue 6, step draw of the fender: the product edge on the outline within 1e-6 mm,
/// every join C1 by eq. 4 and G1 within 0.05 deg (the last patch with the first), every
/// section from the opening line to the outline within 1e-9 mm, the punch-side edge
/// within the script's tolerance of the opening line, normals up.
#[test]
fn fender_step_draw_meets_the_product_and_is_c1() {
    let (addendum, outline, opening) = fender();
    let tolerance = Options::default().tolerance;
    assert_eq!(
        tolerance, 0.01,
        "the script gives no tolerance: the default 0.01 mm"
    );
    let guides = Guides {
        product: outline,
        opening: opening.line.clone(),
        closed: true,
        product_surface: None,
        binder: Vec::new(),
    };
    let names: Vec<&str> = addendum.patches.iter().map(|p| p.name.as_str()).collect();
    eprintln!("fender step draw patches: {names:?}");
    let keys: Vec<&str> = addendum
        .key_sections
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    assert_eq!(
        keys,
        [
            "front",
            "front_nose",
            "nose",
            "nose_top",
            "top",
            "top_rear",
            "rear",
            "rear_front"
        ]
    );
    assert!(addendum.patches.len() >= 8, "one patch or more per pair");
    // The key sections (exact profiles in their planes) reach both guides.
    for (name, c) in &addendum.key_sections {
        let (dp, dov) = (
            distance_to(&guides.product, c.start_point())
                .min(distance_to(&guides.product, c.end_point())),
            distance_to(&guides.opening, c.start_point())
                .min(distance_to(&guides.opening, c.end_point())),
        );
        eprintln!(
            "fender key section {name:>10}: product end {dp:.1e} mm, opening end {dov:.1e} mm"
        );
        assert!(dp <= MAX_END_DISTANCE && dov <= MAX_END_DISTANCE, "{name}");
    }
    let f = check("fender", &guides, &addendum);
    assert!(
        f.opening_deviation <= tolerance,
        "fender: the punch-side edge strays {} mm from the punch opening line (tolerance \
         {tolerance} mm)",
        f.opening_deviation
    );
}

// ---------------------------------------------------------------------------------
// Hand-checkable inputs.
// ---------------------------------------------------------------------------------

/// A cubic with `spans` uniform spans along the segment `a b` at constant speed (its
/// control points at the Greville abscissae: linear precision), so that the arc-length
/// fraction is the parameter exactly.
fn straight_guide(a: DVec3, b: DVec3, spans: usize) -> Curve3 {
    let mut knots = vec![0.0; 4];
    knots.extend((1..spans).map(|i| i as f64 / spans as f64));
    knots.extend([1.0; 4]);
    let points = (0..spans + 3)
        .map(|i| a.lerp(b, (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0))
        .collect();
    Curve3::new(3, knots, points).unwrap()
}

/// The open straight guides: the product along y = 0 at z = 0 and the opening along
/// y = -150 at z = -60, both from x = 0 to 600.
fn straight_guides() -> Guides {
    Guides {
        product: straight_guide(DVec3::ZERO, DVec3::new(600.0, 0.0, 0.0), 12),
        opening: straight_guide(
            DVec3::new(0.0, -150.0, -60.0),
            DVec3::new(600.0, -150.0, -60.0),
            5,
        ),
        closed: false,
        product_surface: None,
        binder: Vec::new(),
    }
}

/// In the planes `x = const` through `(x, 50)` and `(x, -300)` (s runs along -y from
/// y = 50): the product point and the opening point.
const PRODUCT_SZ: DVec2 = DVec2::new(50.0, 0.0);
const OPENING_SZ: DVec2 = DVec2::new(200.0, -60.0);

fn across(name: &str, x: f64, profile: Curve2) -> SectionSpec {
    SectionSpec {
        name: name.into(),
        a: DVec2::new(x, 50.0),
        b: DVec2::new(x, -300.0),
        profile,
    }
}

fn straight_profile() -> Curve2 {
    Curve2::line(PRODUCT_SZ, OPENING_SZ).unwrap()
}

/// An S-shaped cubic from the product point to the opening point, s increasing.
fn s_profile() -> Curve2 {
    NurbsCurve::bezier(vec![
        PRODUCT_SZ,
        PRODUCT_SZ + sz(60.0, 0.0),
        OPENING_SZ - sz(60.0, 0.0),
        OPENING_SZ,
    ])
    .unwrap()
}

/// A run, a wall and a flat through points, drawn from the opening to the product (the
/// other direction, which the kernel accepts).
fn wall_profile() -> Curve2 {
    let pts = [
        OPENING_SZ,
        sz(160.0, -59.0),
        sz(120.0, -40.0),
        sz(95.0, -8.0),
        sz(75.0, -1.0),
        PRODUCT_SZ,
    ];
    interpolate(&pts, &Interpolation::default()).unwrap()
}

/// Distance from `p` to the line through `q` along x.
fn off_x_line(p: DVec3, q: DVec3) -> f64 {
    DVec2::new(p.y - q.y, p.z - q.z).length()
}

/// Issue 6, "keeps the shape of its neighbours": between key sections with the same
/// profile along parallel straight guides every intermediate section is the key section
/// translated along x, and so is every iso-curve across the surface.
#[test]
fn identical_key_profiles_are_translated_along_straight_guides() {
    for (label, profile) in [
        ("straight profile", straight_profile()),
        ("S profile", s_profile()),
    ] {
        let guides = straight_guides();
        let sections = vec![
            across("left", 0.0, profile.clone()),
            across("middle", 300.0, profile.clone()),
            across("right", 600.0, profile),
        ];
        for s in &sections {
            let e = sd::section_ends(&guides, s.a, s.b).unwrap();
            assert!(
                e.product.distance(PRODUCT_SZ) <= 1e-9 && e.opening.distance(OPENING_SZ) <= 1e-9,
                "{label} {}: {e:?}",
                s.name
            );
        }
        let built = sd::build(&guides, &sections, &Options::default()).unwrap();
        let label = format!("open, identical {label}s");
        let f = check(&label, &guides, &built);
        assert_eq!(built.patches.len(), 2);
        // Every section (key and intermediate) is the first one translated along x.
        let key = &built.patches[0].sections[0];
        let mut worst: f64 = 0.0;
        let mut count = 0;
        for p in &built.patches {
            for c in &p.sections {
                let shift = c.end_point() - key.end_point();
                assert!(
                    shift.y.abs() <= 1e-9 && shift.z.abs() <= 1e-9,
                    "{label}: a section moved off x by {shift}"
                );
                for (a, b) in c.control_points().iter().zip(key.control_points()) {
                    worst = worst.max(a.distance(*b + DVec3::X * shift.x));
                }
                count += 1;
            }
        }
        // The surfaces are the extrusion: every iso-curve across is the key translated.
        let mut surface_worst: f64 = 0.0;
        for p in &built.patches {
            let ((u0, u1), (v0, v1)) = (p.surface.domain_u(), p.surface.domain_v());
            for i in 0..=50 {
                let u = u0 + (u1 - u0) * i as f64 / 50.0;
                let base = p.surface.point_at(u, v0);
                let first = p.sections[0].control_points();
                let shift = base.x
                    - if p.reversed {
                        first[first.len() - 1].x
                    } else {
                        first[0].x
                    };
                for j in 0..=50 {
                    let v = v0 + (v1 - v0) * j as f64 / 50.0;
                    let q = p.surface.point_at(u, v);
                    let w = if p.reversed { v1 + v0 - v } else { v };
                    let r = p.sections[0].point_at(w) + DVec3::X * shift;
                    surface_worst = surface_worst.max(q.distance(r));
                }
            }
        }
        eprintln!(
            "{label}: {count} sections, worst control-point distance from the translated key \
             {worst:.1e} mm, surface from the extrusion {surface_worst:.1e} mm, punch-side \
             deviation {:.1e} mm",
            f.opening_deviation
        );
        assert!(count > 6, "{label}: intermediate sections expected");
        assert!(worst <= 1e-9, "{label}: {worst}");
        assert!(surface_worst <= 1e-9, "{label}: {surface_worst}");
        assert!(f.opening_deviation <= 1e-9, "{label}: {f:?}");
    }
}

/// Issue 6: with different key profiles the intermediate sections still run from guide
/// to guide and the patches join C1 (eq. 4) and G1 measured.
#[test]
#[ignore = "issue 12: morphing a straight key profile into a free-form S (no lines or arcs to match) folds the first patch since sections are carried as runs and corners; lines-and-arcs profiles (every std/addendum profile) are covered by the tests below"]
fn different_key_profiles_stay_on_the_guides_and_join_c1() {
    let guides = straight_guides();
    let sections = vec![
        across("line", 0.0, straight_profile()),
        across("s", 250.0, s_profile()),
        across("wall", 600.0, wall_profile()),
    ];
    let built = sd::build(&guides, &sections, &Options::default()).unwrap();
    let f = check("open, different profiles", &guides, &built);
    assert_eq!(built.patches.len(), 2);
    // The straight guides: the ends' distances in closed form as well.
    let (mut start, mut end): (f64, f64) = (0.0, 0.0);
    for p in &built.patches {
        for c in &p.sections {
            start = start.max(off_x_line(c.start_point(), DVec3::new(0.0, -150.0, -60.0)));
            end = end.max(off_x_line(c.end_point(), DVec3::ZERO));
        }
    }
    eprintln!(
        "open, different profiles: {} sections, ends from the straight guides {start:.1e} / \
         {end:.1e} mm",
        f.sections
    );
    assert!(start <= 1e-9 && end <= 1e-9);
    assert!(f.sections > 6, "intermediate sections expected");
    assert!(f.opening_deviation <= 0.01, "{f:?}");
}

/// `n` points on the ellipse with semi-axes `a`, `b` at height `z`, counter-clockwise
/// from +X, interpolated into a closed cubic with equal end derivatives (C1 at the seam).
fn ellipse(a: f64, b: f64, z: f64, n: usize) -> Curve3 {
    let point = |k: usize| {
        let t = std::f64::consts::TAU * k as f64 / n as f64;
        DVec3::new(a * t.cos(), b * t.sin(), z)
    };
    let mut pts: Vec<DVec3> = (0..n).map(point).collect();
    pts.push(pts[0]);
    let length: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
    // Chord-length parameters on [0, 1]: the speed is about the perimeter.
    let tangent = DVec3::Y * length;
    interpolate(&pts, &Interpolation::cubic_with_tangents(tangent, tangent)).unwrap()
}

fn closed_guides() -> Guides {
    Guides {
        product: ellipse(250.0, 165.0, 0.0, 40),
        opening: ellipse(350.0, 240.0, -80.0, 40),
        closed: true,
        product_surface: None,
        binder: Vec::new(),
    }
}

/// The four sections at the axis directions, from the centre outwards, in order
/// counter-clockwise; each profile from the product point to the opening point.
fn closed_sections(profile: impl Fn(DVec2, DVec2) -> Curve2) -> Vec<SectionSpec> {
    [
        ("px", DVec2::X, 250.0, 350.0),
        ("py", DVec2::Y, 165.0, 240.0),
        ("nx", -DVec2::X, 250.0, 350.0),
        ("ny", -DVec2::Y, 165.0, 240.0),
    ]
    .into_iter()
    .map(|(name, d, sp, so)| SectionSpec {
        name: name.into(),
        a: DVec2::ZERO,
        b: d * 400.0,
        profile: profile(sz(sp, 0.0), sz(so, -80.0)),
    })
    .collect()
}

fn s_between(p: DVec2, q: DVec2) -> Curve2 {
    let run = 0.4 * (q.x - p.x);
    NurbsCurve::bezier(vec![p, p + sz(run, 0.0), q - sz(run, 0.0), q]).unwrap()
}

/// Issue 6, a closed step draw around an ellipse: C1 joins (the last with the first),
/// the product edge on the outline.
#[test]
fn closed_step_draw_around_an_ellipse() {
    let guides = closed_guides();
    for (label, sections) in [
        (
            "closed, straight profiles",
            closed_sections(|p, q| Curve2::line(p, q).unwrap()),
        ),
        ("closed, S profiles", closed_sections(s_between)),
    ] {
        for s in &sections {
            let e = sd::section_ends(&guides, s.a, s.b).unwrap();
            assert!(
                e.product.distance(s.profile.start_point()) <= 1e-6
                    && e.opening.distance(s.profile.end_point()) <= 1e-6,
                "{label} {}: {e:?}",
                s.name
            );
        }
        let built = sd::build(&guides, &sections, &Options::default()).unwrap();
        let f = check(label, &guides, &built);
        assert!(built.patches.len() >= 4);
        assert!(f.opening_deviation <= 0.01, "{label}: {f:?}");
    }
}

// ---------------------------------------------------------------------------------
// Errors.
// ---------------------------------------------------------------------------------

fn error(guides: &Guides, sections: &[SectionSpec]) -> sd::Error {
    match sd::build(guides, sections, &Options::default()) {
        Ok(_) => panic!("built, but an error was expected"),
        Err(e) => e,
    }
}

#[test]
fn sections_out_of_order_are_refused_at_the_culprit() {
    let guides = straight_guides();
    let e = error(
        &guides,
        &[
            across("a", 0.0, straight_profile()),
            across("b", 400.0, straight_profile()),
            across("c", 200.0, straight_profile()),
            across("d", 600.0, straight_profile()),
        ],
    );
    assert_eq!(e.problem, Problem::WrongOrder);
    assert_eq!(e.section, 2);
    // Closed: +X, -X, +Y, -Y goes round twice.
    let guides = closed_guides();
    let mut sections = closed_sections(|p, q| Curve2::line(p, q).unwrap());
    sections.swap(1, 2);
    let e = error(&guides, &sections);
    assert_eq!(e.problem, Problem::WrongOrder);
    assert_eq!(e.section, 2);
}

#[test]
fn too_few_sections_are_refused() {
    let guides = closed_guides();
    let sections = closed_sections(|p, q| Curve2::line(p, q).unwrap());
    let e = error(&guides, &sections[..2]);
    assert_eq!(e.problem, Problem::TooFewSections { needed: 3 });
    assert_eq!(e.section, 1);
    let e = error(
        &straight_guides(),
        &[across("one", 0.0, straight_profile())],
    );
    assert_eq!(e.problem, Problem::TooFewSections { needed: 2 });
    // Three are enough for a closed outline.
    let three = [
        sections[0].clone(),
        sections[1].clone(),
        sections[2].clone(),
    ];
    let built = sd::build(&guides, &three, &Options::default()).unwrap();
    let f = check("closed, three sections", &guides, &built);
    assert!(f.opening_deviation <= 0.01, "{f:?}");
}

#[test]
fn profile_ends_off_the_guides_are_refused() {
    let guides = straight_guides();
    let off = Curve2::line(PRODUCT_SZ + sz(0.0, 1.0), OPENING_SZ + sz(0.0, 1.0)).unwrap();
    let e = error(
        &guides,
        &[
            across("a", 0.0, straight_profile()),
            across("b", 300.0, off),
            across("c", 600.0, straight_profile()),
        ],
    );
    assert_eq!(e.section, 1);
    let Problem::EndsOffGuides {
        product,
        opening,
        gap,
    } = e.problem
    else {
        panic!("{e:?}");
    };
    assert!(product.distance(PRODUCT_SZ) <= 1e-9, "{product}");
    assert!(opening.distance(OPENING_SZ) <= 1e-9, "{opening}");
    assert!((gap - 1.0).abs() <= 1e-9, "{gap}");
}

#[test]
fn a_folding_profile_is_refused() {
    let guides = straight_guides();
    let pts = [PRODUCT_SZ, sz(150.0, -30.0), sz(120.0, -40.0), OPENING_SZ];
    let folding = Curve2::new(
        1,
        vec![0.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0, 1.0],
        pts.to_vec(),
    )
    .unwrap();
    let e = error(
        &guides,
        &[
            across("a", 0.0, straight_profile()),
            across("b", 300.0, straight_profile()),
            across("c", 600.0, folding),
        ],
    );
    assert_eq!(e.section, 2);
    let Problem::FoldsBack { at } = e.problem else {
        panic!("{e:?}");
    };
    // On the backwards leg from (150, -30) to (120, -40).
    let (a, b) = (sz(150.0, -30.0), sz(120.0, -40.0));
    let f = (at - a).dot(b - a) / (b - a).length_squared();
    assert!(
        (0.0..=1.0).contains(&f) && at.distance(a.lerp(b, f)) <= 1e-9,
        "{at}"
    );
}

#[test]
fn a_section_plane_missing_a_guide_is_refused() {
    let guides = straight_guides();
    // Beyond both guides' ends: misses the product first.
    let e = error(
        &guides,
        &[
            across("a", 0.0, straight_profile()),
            across("b", 800.0, straight_profile()),
        ],
    );
    assert_eq!(
        (e.section, e.problem),
        (1, Problem::MissesGuide { product: true })
    );
    // A slanted plane through (300, 10) and (900, -300): meets the product at x = 319,
    // passes y = -150 at x = 610, beyond the opening's end.
    let slanted = SectionSpec {
        name: "slanted".into(),
        a: DVec2::new(300.0, 10.0),
        b: DVec2::new(900.0, -300.0),
        profile: straight_profile(),
    };
    assert_eq!(
        sd::section_ends(&guides, slanted.a, slanted.b),
        Err(Problem::MissesGuide { product: false })
    );
    let e = error(&guides, &[across("a", 0.0, straight_profile()), slanted]);
    assert_eq!(
        (e.section, e.problem),
        (1, Problem::MissesGuide { product: false })
    );
}
