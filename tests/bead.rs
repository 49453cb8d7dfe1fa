//! Draw beads (issue 7).
//!
//! On the fender example: the feet lie on the binder, measured independently of the
//! kernel's own height field (vertical lines intersected with every binder patch); the
//! tapered ends run out to zero; the taller key section stands at its height; the rule
//! curve runs along the crest; the line bead reaches the glTF.
//!
//! On a flat binder, where every figure can be checked by hand: the skin follows the
//! profile everywhere (not only at its sections); a bead between two boundaries has its
//! feet on them; key sections blend, and the taper runs out, by the documented `ease`
//! (the quintic smootherstep).

#[path = "common/fender.rs"]
mod fender;

#[path = "common/example.rs"]
mod example;

use std::path::Path;

use dieface::die::bead::Bead;
use dieface::die::blankholder::Blankholder;
use dieface::eval::{Data, Engine, Outcome, Value};
use dieface::geom::intersect::intersect_line_surface_all;
use dieface::geom::inversion::closest_point_on_curve;
use dieface::geom::{Curve2, Direction};
use glam::{DVec2, DVec3};

fn find<'a>(values: &'a [(String, Value)], name: &str) -> &'a Value {
    &values
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("`{name}` has a value"))
        .1
}

fn bead_of(v: &Value) -> &Bead {
    match &v.data {
        Data::Record(r) => r.model::<Bead>().expect("a bead"),
        _ => panic!("not a record"),
    }
}

fn binder_of(v: &Value) -> &Blankholder {
    match &v.data {
        Data::Record(r) => r.model::<Blankholder>().expect("a blankholder"),
        _ => panic!("not a record"),
    }
}

/// The binder height under `p` by intersecting the vertical line with every patch (the
/// nearest hit in z), independent of the bead's Newton height field.
fn binder_z(binder: &Blankholder, p: DVec3) -> f64 {
    binder
        .patches
        .iter()
        .flat_map(|patch| {
            intersect_line_surface_all(p, DVec3::Z, &patch.surface)
                .expect("a vertical line")
                .into_iter()
                .map(|h| h.point.z)
        })
        .min_by(|a, b| (a - p.z).abs().total_cmp(&(b - p.z).abs()))
        .unwrap_or_else(|| panic!("no binder under ({:.1}, {:.1})", p.x, p.y))
}

/// The largest height of the skin above the binder across the bead at `v`.
fn crest(binder: &Blankholder, bead: &Bead, v: f64) -> f64 {
    let (u0, u1) = bead.surface.domain_u();
    (0..=200)
        .map(|i| {
            let p = bead.surface.point_at(u0 + (u1 - u0) * i as f64 / 200.0, v);
            p.z - binder_z(binder, p)
        })
        .fold(f64::MIN, f64::max)
}

/// Both feet of both fender beads lie on the binder within 0.001 mm (500 samples per
/// foot), and the line bead steps at most 15 mm.
#[test]
fn fender_bead_feet_lie_on_the_binder() {
    let values = fender::fender_values();
    let binder = binder_of(find(&values, "binder"));
    for name in ["wheel_arch", "rear_corner"] {
        let bead = bead_of(find(&values, name));
        let s = &bead.surface;
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let mut worst: f64 = 0.0;
        for u in [u0, u1] {
            for i in 0..=500 {
                let p = s.point_at(u, v0 + (v1 - v0) * i as f64 / 500.0);
                worst = worst.max((p.z - binder_z(binder, p)).abs());
            }
        }
        eprintln!(
            "{name}: foot gap {worst:.2e} mm (kernel's figure {:.2e} mm), section error {:.2e} mm",
            bead.quality.foot_gap, bead.quality.section_error
        );
        assert!(worst <= 0.001, "{name}: foot gap {worst} mm");
        assert!(bead.quality.foot_gap <= 0.001);
        assert!(bead.quality.section_error <= 0.01);
        let steps: Vec<f64> = bead
            .line_points
            .windows(2)
            .map(|w| w[0].distance(w[1]))
            .collect();
        let longest = steps.iter().cloned().fold(0.0, f64::max);
        assert!(
            longest <= 15.0 + 1e-6,
            "{name}: a line-bead step of {longest} mm"
        );
    }
}

/// The fender's corner bead: zero height at both tapered ends, 8 mm at its `corner`
/// key section, between 6 and 8 mm on the way there; its rule curve (`rules = [0 mm]`)
/// is the crest, straight above the centre line.
#[test]
fn fender_corner_bead_tapers_rises_and_keeps_its_crest_rule() {
    let values = fender::fender_values();
    let binder = binder_of(find(&values, "binder"));
    let bead = bead_of(find(&values, "rear_corner"));
    let (v0, v1) = bead.surface.domain_v();
    for v in [v0, v1] {
        let h = crest(binder, bead, v);
        assert!(h.abs() < 1e-6, "a tapered end stands {h} mm high");
    }
    // The key sections are iso-curves of the skin: find the `corner` one by its height.
    let corner = &bead.sections[1];
    let (t0, t1) = corner.domain();
    let tallest = (0..=400)
        .map(|i| {
            let p = corner.point_at(t0 + (t1 - t0) * i as f64 / 400.0);
            p.z - binder_z(binder, p)
        })
        .fold(f64::MIN, f64::max);
    assert!(
        (tallest - 8.0).abs() < 1e-3,
        "the corner section stands {tallest} mm"
    );
    // Past the taper (30 mm of 1,244 mm) and before the corner: between the two heights.
    let v = v0 + 0.1 * (v1 - v0);
    let h = crest(binder, bead, v);
    assert!((6.0..8.0).contains(&h), "on the way to the corner: {h} mm");

    assert_eq!(bead.rules.len(), 1);
    let rule = &bead.rules[0];
    let (r0, r1) = rule.domain();
    let centre_top: Curve2 = bead.centre.map_points(|p| p.truncate());
    for i in 0..=100 {
        let v = r0 + (r1 - r0) * i as f64 / 100.0;
        let p = rule.point_at(v);
        let foot = closest_point_on_curve(&centre_top, p.truncate()).expect("a closest point");
        let above = p.z - binder_z(binder, p);
        // The crest stands square to the binder's trace across the bead, so it leans
        // off the centre line by its height times the sine of the binder's slope there.
        let across = centre_top.derivative_at(foot.t).normalize().perp();
        let at = |d: f64| (foot.point + across * d).extend(p.z);
        let slope = binder_z(binder, at(0.5)) - binder_z(binder, at(-0.5));
        let lean = above.abs() * slope.abs() / slope.hypot(1.0);
        assert!(
            foot.distance < 1e-3 + lean,
            "the crest rule is {} mm off the centre line (it may lean {lean} mm)",
            foot.distance
        );
        let top = crest(binder, bead, v);
        assert!(
            (above - top).abs() < 2e-3,
            "the rule is {above} mm high where the crest is {top} mm"
        );
    }
}

/// The line bead reaches forming simulation through the glTF: the bead's node carries
/// its points (press mm), spacing and force in `extras.line_bead`; every key section is
/// a node of its own.
#[test]
fn line_beads_and_key_sections_are_in_the_gltf() {
    use dieface::export::{build_scene, encode, Format};
    use dieface::geom::tessellate::Tolerance;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut engine = Engine::new(Some(root.clone()));
    let out = engine
        .evaluate_path(&root.join("fender/fender.die"))
        .expect("readable");
    assert!(out.diagnostics.is_empty());
    let scene = build_scene(
        &engine.die_model(&out),
        &Tolerance::new(0.05).expect("tolerance"),
    )
    .expect("the scene builds");
    let glb = encode(&scene, Format::Glb);
    let len = u32::from_le_bytes(glb[12..16].try_into().expect("4 bytes")) as usize;
    let json: serde_json::Value = serde_json::from_slice(&glb[20..20 + len]).expect("JSON chunk");
    let nodes = json["nodes"].as_array().expect("nodes");
    let names: Vec<&str> = nodes.iter().filter_map(|n| n["name"].as_str()).collect();
    for expected in [
        "wheel_arch/surface",
        "rear_corner/surface",
        "rear_corner/section-start",
        "rear_corner/section-corner",
        "rear_corner/section-end",
        "rear_corner/rules/0",
    ] {
        assert!(names.contains(&expected), "no node {expected}: {names:?}");
    }
    let node = nodes
        .iter()
        .find(|n| n["name"] == "wheel_arch")
        .expect("the bead is a node");
    let lb = &node["extras"]["line_bead"];
    assert_eq!(lb["force_n_per_mm"], 250.0);
    assert_eq!(lb["spacing_mm"], 15.0);
    let points = lb["points_mm"].as_array().expect("points");
    let values = fender::clean_values(&engine, &out);
    let bead = bead_of(find(&values, "wheel_arch"));
    assert_eq!(points.len(), bead.line_points.len());
    assert!(points.len() >= 700 / 15, "about one point every 15 mm");
    for (p, q) in points.iter().zip(&bead.line_points) {
        let x = p[0].as_f64().expect("a number");
        assert!((x - q.x).abs() < 1e-9);
    }
}

/// A square opening with a flat binder at z = -60 (with `binder_extra` fields) and
/// `beads`, evaluated.
fn flat_with(beads: &str, binder_extra: &str) -> (Engine, Outcome) {
    let text = format!(
        "import \"std/beads\" as beads
units mm deg
let top_view = sketch(top) {{
    from (-200, -200)
    fillet 50
    line to (200, -200)
    fillet 50
    line to (200, 200)
    fillet 50
    line to (-200, 200)
    fillet 50
    close
}}
let flat_x = sketch(side_xz) {{ from (-260, -60); line to (260, -60) }}
let flat_y = sketch(side_yz) {{ from (-260, -60); line to (260, -60) }}
punch_opening opening {{
    top = top_view
    side bottom = flat_x
    side right = flat_y
    side top = flat_x
    side left = flat_y
}}
blankholder binder {{
    opening = opening
    width = 150 mm
    {binder_extra}
}}
{beads}
"
    );
    let mut engine = Engine::new(None);
    let out = engine.evaluate("flat.die", &text, None);
    (engine, out)
}

/// [`flat_with`] a blankholder of default settings.
fn flat(beads: &str) -> (Engine, Outcome) {
    flat_with(beads, "")
}

fn values_of(engine: &Engine, out: &Outcome) -> Vec<(String, Value)> {
    fender::clean_values(engine, out)
}

fn profile_of(v: &Value) -> Curve2 {
    match &v.data {
        Data::Sketch(s) => s.curve.clone(),
        _ => panic!("not a sketch"),
    }
}

/// On a flat binder a straight bead is its profile swept along the line: every point of
/// the skin (not only the sections) lies within 0.005 mm of the profile, measured in
/// the plane across the bead.
#[test]
fn flat_straight_bead_is_its_profile_everywhere() {
    let (engine, out) = flat(
        "let p = beads.round(height: 6 mm, radius: 6 mm)
bead b { binder = binder; line = sketch(top) { from (-100, -260); line to (100, -260) }; profile = p }",
    );
    let values = values_of(&engine, &out);
    let bead = bead_of(find(&values, "b"));
    let profile = profile_of(find(&values, "p"));
    let s = &bead.surface;
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut worst: f64 = 0.0;
    for i in 0..=150 {
        for j in 0..=40 {
            let p = s.point_at(
                u0 + (u1 - u0) * i as f64 / 150.0,
                v0 + (v1 - v0) * j as f64 / 40.0,
            );
            // Travel +x: s runs to the left, +y.
            let q = DVec2::new(p.y + 260.0, p.z + 60.0);
            worst = worst.max(
                closest_point_on_curve(&profile, q)
                    .expect("closest")
                    .distance,
            );
        }
    }
    eprintln!("flat straight bead: skin to profile {worst:.2e} mm");
    assert!(worst <= 0.005, "the skin leaves the profile by {worst} mm");
    assert!(bead.quality.section_error <= 0.005);
    assert!(bead.quality.foot_gap <= 1e-9);
}

/// A bead between two boundaries that open from 20 to 28 mm apart: its feet run along
/// the boundaries, the profile stretches to the width, and the height stays.
#[test]
fn flat_bead_between_boundaries_stretches_to_them() {
    let (engine, out) = flat(
        "let p = beads.round(height: 5 mm, radius: 5 mm)
let inner = sketch(top) { from (-100, -250); line to (100, -246) }
let outer = sketch(top) { from (-100, -270); line to (100, -274) }
bead b { binder = binder; boundaries = [inner, outer]; profile = p }",
    );
    let values = values_of(&engine, &out);
    let bead = bead_of(find(&values, "b"));
    let s = &bead.surface;
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    // The boundary lines: y = -250 + 0.02 (x + 100) and y = -270 - 0.02 (x + 100).
    let lines = [(-250.0, 0.02), (-270.0, -0.02)];
    let mut worst: f64 = 0.0;
    for u in [u0, u1] {
        for j in 0..=200 {
            let p = s.point_at(u, v0 + (v1 - v0) * j as f64 / 200.0);
            let off = lines
                .iter()
                .map(|(y0, k)| (p.y - (y0 + k * (p.x + 100.0))).abs() / (1.0 + k * k).sqrt())
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(off);
            assert!((p.z + 60.0).abs() < 1e-9, "a foot off the flat binder");
        }
    }
    assert!(worst < 1e-6, "a foot lies {worst} mm off its boundary");
    let (narrow, wide) = (bead.quality.width.0, bead.quality.width.1);
    assert!(
        (narrow - 20.0).abs() < 1e-6 && (wide - 28.0).abs() < 1e-6,
        "{narrow}..{wide}"
    );
    assert!((bead.quality.height - 5.0).abs() < 1e-6);
    assert!((bead.centre.point_at(bead.centre.domain().0).y + 260.0).abs() < 1e-6);
}

/// Boundaries drawn from opposite ends bound the same bead as boundaries drawn the same
/// way; boundaries that cross are refused where they cross.
#[test]
fn flat_boundaries_in_either_direction_and_crossing() {
    let bead = |outer: &str| {
        format!(
            "let inner = sketch(top) {{ from (-100, -250); line to (100, -246) }}
let outer = {outer}
bead b {{ binder = binder; boundaries = [inner, outer]; profile = beads.round(height: 5 mm, radius: 5 mm) }}"
        )
    };
    let forward = bead("sketch(top) { from (-100, -270); line to (100, -274) }");
    let backward = bead("sketch(top) { from (100, -274); line to (-100, -270) }");
    let (e1, o1) = flat(&forward);
    let (e2, o2) = flat(&backward);
    let (v1, v2) = (values_of(&e1, &o1), values_of(&e2, &o2));
    let (b1, b2) = (bead_of(find(&v1, "b")), bead_of(find(&v2, "b")));
    assert_eq!(b1.quality.width, b2.quality.width);
    let (p, q) = (b1.surface.point_at(0.3, 0.6), b2.surface.point_at(0.3, 0.6));
    assert!(p.distance(q) < 1e-9, "{p} vs {q}");

    let crossing = bead("sketch(top) { from (-100, -240); line to (100, -274) }");
    let (_, out) = flat(&crossing);
    let d = out
        .diagnostics
        .iter()
        .find(|d| d.code == "die::bead")
        .expect("a bead diagnostic");
    assert!(d.message.contains("cross"), "{}", d.message);
}

/// A ring bead all round the binder (a closed centre line, here the opening's top view
/// offset 60 mm outwards) closes on itself C1: at the seam the skin's two ends meet
/// with the same point and the same normal.
#[test]
fn flat_ring_bead_closes_smoothly() {
    let (engine, out) = flat(
        "bead ring { binder = binder; line = offset(top_view, -60 mm); profile = beads.round(height: 6 mm, radius: 6 mm) }",
    );
    let values = values_of(&engine, &out);
    let bead = bead_of(find(&values, "ring"));
    let s = &bead.surface;
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let (mut gap, mut angle): (f64, f64) = (0.0, 0.0);
    for i in 0..=100 {
        let u = u0 + (u1 - u0) * i as f64 / 100.0;
        gap = gap.max(s.point_at(u, v0).distance(s.point_at(u, v1)));
        let (a, b) = (s.normal(u, v0), s.normal(u, v1));
        if let (Ok(a), Ok(b)) = (a, b) {
            angle = angle.max(a.angle_between(b).to_degrees());
        }
        let (da, db) = (
            s.derivatives::<2>(u, v0)[0][1],
            s.derivatives::<2>(u, v1)[0][1],
        );
        assert!(
            da.distance(db) <= 1e-6 * da.length().max(1.0),
            "the v-derivative jumps at the seam: {da} vs {db}"
        );
    }
    eprintln!("ring seam: gap {gap:.1e} mm, normals {angle:.1e} deg");
    assert!(gap < 1e-6, "the ring does not close: {gap} mm");
    assert!(
        angle < 0.05,
        "the ring is not smooth at its seam: {angle} deg"
    );
    assert!(bead.quality.foot_gap <= 0.001);
}

/// Key sections blend by the documented `ease`: 6 mm at the ends, 9 mm at 50 %, and
/// 6 + 3 w(x) in between, w the quintic smootherstep of the fraction between them;
/// the rule at the crest carries that height.
#[test]
fn flat_key_sections_blend_by_ease() {
    let (engine, out) = flat(
        "bead b {
    binder = binder
    line = sketch(top) { from (-100, -260); line to (100, -260) }
    profile = beads.round(height: 6 mm, radius: 6 mm)
    rules = [0 mm]
    section high { at = 50 %; profile = beads.round(height: 9 mm, radius: 6 mm); rules = [0 mm] }
}",
    );
    let values = values_of(&engine, &out);
    let bead = bead_of(find(&values, "b"));
    let rule = &bead.rules[0];
    let (r0, r1) = rule.domain();
    let mut worst: f64 = 0.0;
    for i in 0..=200 {
        let p = rule.point_at(r0 + (r1 - r0) * i as f64 / 200.0);
        let f = (p.x + 100.0) / 200.0;
        let x = if f <= 0.5 { f / 0.5 } else { (1.0 - f) / 0.5 };
        let w = x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
        let expected = 6.0 + 3.0 * w;
        worst = worst.max((p.z + 60.0 - expected).abs());
        assert!(
            (p.y + 260.0).abs() < 1e-6,
            "the crest rule leaves the centre line"
        );
    }
    eprintln!("key-section blend: crest off the blend by {worst:.2e} mm");
    assert!(worst < 0.01, "the crest is {worst} mm off the blend");
}

/// The taper runs the height out by the documented `ease` over `taper` at both ends:
/// 6 w(d / 20) at distance d from an end.
#[test]
fn flat_taper_runs_out_by_ease() {
    let (engine, out) = flat(
        "bead b {
    binder = binder
    line = sketch(top) { from (-100, -260); line to (100, -260) }
    profile = beads.round(height: 6 mm, radius: 6 mm)
    rules = [0 mm]
    taper = 20 mm
}",
    );
    let values = values_of(&engine, &out);
    let bead = bead_of(find(&values, "b"));
    let rule = &bead.rules[0];
    let (r0, r1) = rule.domain();
    let mut worst: f64 = 0.0;
    for i in 0..=400 {
        let p = rule.point_at(r0 + (r1 - r0) * i as f64 / 400.0);
        let d = (p.x + 100.0).min(100.0 - p.x);
        let x = (d / 20.0).clamp(0.0, 1.0);
        let expected = 6.0 * x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
        worst = worst.max((p.z + 60.0 - expected).abs());
    }
    eprintln!("taper: crest off the run-out by {worst:.2e} mm");
    assert!(worst < 0.005, "the tapered crest is {worst} mm off");
    let iso = bead
        .surface
        .iso_curve(Direction::V, bead.surface.domain_v().0);
    assert!(iso.point_at(0.5).z + 60.0 < 1e-9, "the end section is flat");
}

/// A bead taller than the binder allows is refused at its profile, and allowed once the
/// blankholder's `max_bead_height` is raised.
#[test]
fn bead_taller_than_the_binder_allows_is_refused() {
    let bead = "bead b {
    binder = binder
    line = sketch(top) { from (-100, -260); line to (100, -260) }
    profile = beads.round(height: 18 mm, radius: 8 mm)
}";
    let (_, out) = flat(bead);
    let d = out
        .diagnostics
        .iter()
        .find(|d| d.code == "die::bead")
        .expect("a bead diagnostic");
    assert!(
        d.message.contains("18 mm tall") && d.message.contains("15 mm"),
        "{}",
        d.message
    );
    let (engine, out) = flat_with(bead, "max_bead_height = 20 mm");
    let values = values_of(&engine, &out);
    assert!((bead_of(find(&values, "b")).quality.height - 18.0).abs() < 1e-6);
}

/// The skin faces up like the binder under it: its normal at the crest of every bead of
/// the fender points along +Z (viewers shade the front face, and offsets for the
/// sheet's thickness go the right way).
#[test]
fn fender_bead_skins_face_up() {
    let values = fender::fender_values();
    for name in ["wheel_arch", "rear_corner"] {
        let s = &bead_of(find(&values, name)).surface;
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        for j in 1..10 {
            let v = v0 + (v1 - v0) * j as f64 / 10.0;
            let n = s.normal(0.5 * (u0 + u1), v).expect("a regular crest");
            assert!(n.z > 0.9, "{name}: the crest normal is {n}");
        }
    }
}

// ---------------------------------------------------------------------------------
// Issue 12, item 8: bead radii. The skin's smallest radius against the smallest radius
// drawn in the key profiles, on the full-height part and in the tapered ends.
// ---------------------------------------------------------------------------------

/// Every bead of an example with its figures printed; returns (name, quality).
fn example_beads(path: &str) -> Vec<(String, dieface::die::bead::BeadQuality)> {
    let values = example::example_values(path);
    example::features(&values)
        .into_iter()
        .filter_map(|(name, f)| f.model::<Bead>().map(|b| (name, b.quality)))
        .inspect(|(name, q)| {
            eprintln!(
                "{path} {name}: min radius {:.3} mm at ({:.1}, {:.1}, {:.1}), ends {:.3} mm, \
                 drawn {:.3} mm",
                q.min_radius,
                q.min_radius_at.x,
                q.min_radius_at.y,
                q.min_radius_at.z,
                q.end_min_radius,
                q.drawn_radius
            )
        })
        .collect()
}

/// The radius figures are there and mean what they say: the drawn radius is the
/// smallest arc of the key profiles (the beads of the fender and the door draw 3 mm
/// shoulders, their smallest arcs), and the skin's radii are found on the skin.
#[test]
fn bead_radius_figures_are_reported() {
    for (path, drawn) in [
        ("fender/fender.die", 3.0),
        ("door_outer/door_outer.die", 3.0),
    ] {
        let beads = example_beads(path);
        assert!(!beads.is_empty(), "{path} has beads");
        let smallest = beads
            .iter()
            .map(|(_, q)| q.drawn_radius)
            .fold(f64::INFINITY, f64::min);
        assert!((smallest - drawn).abs() <= 1e-6, "{path}: drawn {smallest}");
        for (name, q) in &beads {
            assert!(q.min_radius.is_finite() && q.min_radius > 0.0, "{name}");
            assert!(
                q.end_min_radius.is_finite() && q.end_min_radius > 0.0,
                "{name}"
            );
        }
    }
}

/// The requirement (issue 12, item 8): no radius on the full-height part below 90 % of
/// the drawn one, and the tapered ends none below 90 % of the drawn shoulder. Failed on
/// the method before the run-out was stretched for its descent and its bends spread
/// (full height 2.4 to 2.6 mm against 3 mm drawn; ends 0.37 to 1.26 mm, later 2.62 mm
/// on the door's `belt_front`).
#[test]
fn bead_radii_are_kept_as_drawn() {
    let mut failures = Vec::new();
    for path in ["fender/fender.die", "door_outer/door_outer.die"] {
        for (name, q) in example_beads(path) {
            if q.min_radius < 0.9 * q.drawn_radius || q.end_min_radius < 0.9 * q.drawn_radius {
                failures.push(format!(
                    "{path} {name}: {:.3} / {:.3} mm against {:.3} drawn",
                    q.min_radius, q.end_min_radius, q.drawn_radius
                ));
            }
        }
    }
    let q = straight_tapered_bead("");
    eprintln!(
        "flat tapered bead: min radius {:.3} mm, ends {:.3} mm, drawn {:.3} mm",
        q.min_radius, q.end_min_radius, q.drawn_radius
    );
    if q.min_radius < 0.9 * q.drawn_radius || q.end_min_radius < 0.9 * q.drawn_radius {
        failures.push(format!(
            "flat: {:.3} / {:.3} mm",
            q.min_radius, q.end_min_radius
        ));
    }
    assert!(failures.is_empty(), "{}", failures.join("; "));
}

/// A straight bead of `profile` with `taper` (mm) on [`flat_with`]'s binder, with
/// `binder_extra` in the binder's block; its figures.
fn straight_bead(profile: &str, taper: f64, binder_extra: &str) -> dieface::die::bead::BeadQuality {
    let (engine, out) = flat_with(
        &format!(
            "bead b {{
    binder = binder
    line = sketch(top) {{ from (-100, -260); line to (100, -260) }}
    profile = {profile}
    taper = {taper} mm
}}"
        ),
        binder_extra,
    );
    let values = values_of(&engine, &out);
    bead_of(find(&values, "b")).quality
}

/// Every profile of `std/beads` keeps 90 % of its drawn radius at full height and
/// through its run-out, over tapers of 20 and 45 mm (three to nine bead heights) on a
/// flat and a sloping binder. Before: the default square bead's run-out came to 2.27
/// mm of 3 mm drawn, the lock step's to 1.66 mm of 2, the double bead's to 0.03 mm
/// (its lowering cut only one crest and left the valley below the binder, 2.6 mm off
/// its profile), and the double bead's full height to 1.74 mm (48 points across its
/// 50 mm: too few for its 2 mm shoulders).
#[test]
fn every_library_bead_runs_out_with_its_drawn_radii() {
    let mut failures = Vec::new();
    for profile in [
        "beads.round()",
        "beads.square()",
        "beads.square(height: 5 mm, width: 12 mm)",
        "beads.lock_step()",
        "beads.double()",
    ] {
        for taper in [20.0, 45.0] {
            for binder in ["", "angle = 10 deg"] {
                let q = straight_bead(profile, taper, binder);
                eprintln!(
                    "{profile}, taper {taper} mm, binder '{binder}': full height {:.3} mm, \
                     ends {:.3} mm, drawn {:.3} mm, section error {:.4} mm",
                    q.min_radius, q.end_min_radius, q.drawn_radius, q.section_error
                );
                let least = q.min_radius.min(q.end_min_radius);
                if !(least >= 0.9 * q.drawn_radius && q.section_error <= 0.025) {
                    failures.push(format!(
                        "{profile} taper {taper} '{binder}': {least:.3} of {:.3} mm, \
                         section error {:.4}",
                        q.drawn_radius, q.section_error
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("; "));
}

/// A taper shorter than the bead's height can follow (8 mm for a 6 mm bead: the run-out
/// falls at up to 55 deg) cannot keep the drawn radii, but the bead stays what it is:
/// the feet are not rounded past the profile's own feet (they ran back on themselves,
/// 0.0001 mm radii, and a raised foot radius reached 60 mm out from the centre line),
/// the sections follow the run-out within 0.025 mm, and the end radius figure tells.
#[test]
fn a_too_short_taper_is_sharper_but_not_folded() {
    for profile in ["beads.round()", "beads.square()", "beads.double()"] {
        let full = straight_bead(profile, 30.0, "");
        let q = straight_bead(profile, 8.0, "");
        eprintln!(
            "{profile}, taper 8 mm: ends {:.3} mm, section error {:.4} mm, width {:.3} mm",
            q.end_min_radius, q.section_error, q.width.1
        );
        assert!(q.section_error <= 0.025, "{profile}: {}", q.section_error);
        assert!(
            (q.width.1 - full.width.1).abs() <= 1e-6,
            "{profile}: {} mm wide against {}",
            q.width.1,
            full.width.1
        );
        assert!(
            q.end_min_radius > 0.05 * q.drawn_radius && q.end_min_radius < 0.9 * q.drawn_radius,
            "{profile}: ends {} mm",
            q.end_min_radius
        );
    }
}

/// A straight round bead (3 mm shoulders, 20 mm taper) 60 mm out from the bottom side
/// of [`flat_with`]'s binder, with `binder_extra` in the binder's block; its figures.
fn straight_tapered_bead(binder_extra: &str) -> dieface::die::bead::BeadQuality {
    let (engine, out) = flat_with(
        "bead b {
    binder = binder
    line = sketch(top) { from (-100, -260); line to (100, -260) }
    profile = beads.round(height: 6 mm, radius: 6 mm, shoulder: 3 mm)
    taper = 20 mm
}",
        binder_extra,
    );
    let values = values_of(&engine, &out);
    bead_of(find(&values, "b")).quality
}

/// On a binder that slopes across the bead the profile stands square to the binder, not
/// straight up: raised along press Z it would be sheared, its downhill shoulder
/// sharpened (2.2 mm of 3 mm drawn on this 10 deg binder; 2.76 mm square to it) and
/// its uphill one softened. Both shoulders keep 90 % of the drawn radius, the section
/// follows the profile, and the bead is as tall as drawn, measured square to the binder.
#[test]
fn a_bead_across_a_sloping_binder_keeps_its_radii() {
    let q = straight_tapered_bead("angle = 10 deg");
    eprintln!(
        "sloping binder: min radius {:.3} mm, ends {:.3} mm, drawn {:.3} mm, height {:.4} mm, \
         section error {:.4} mm",
        q.min_radius, q.end_min_radius, q.drawn_radius, q.height, q.section_error
    );
    assert!(
        q.min_radius >= 0.9 * q.drawn_radius,
        "full height: {} mm against {} drawn",
        q.min_radius,
        q.drawn_radius
    );
    assert!(
        q.end_min_radius >= 0.9 * q.drawn_radius,
        "ends: {} mm against {} drawn",
        q.end_min_radius,
        q.drawn_radius
    );
    assert!(q.section_error <= 0.01, "section error {}", q.section_error);
    assert!((q.height - 6.0).abs() <= 1e-3, "height {}", q.height);
}
