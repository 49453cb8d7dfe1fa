//! `std/addendum`: the standard step-draw section profiles, evaluated through the
//! engine, and the `profile` view they are drawn in.

use std::sync::Arc;

use dieface::eval::sketch::{Sketch, View};
use dieface::eval::{Data, Engine};
use glam::{DVec2, DVec3};

#[path = "common/profiles.rs"]
mod profiles_common;
#[path = "common/script.rs"]
mod script;

use profiles_common::{draft_of, flats, kinds, samples, walls};

/// Evaluates `lets` (one `let name = ...` per line) after importing the module, and
/// returns every declaration's sketch; panics on any diagnostic.
fn profiles(lets: &str) -> Vec<(String, Arc<Sketch>)> {
    let text = format!("import \"std/addendum\" as ad\nunits mm deg\n{lets}\n");
    script::evaluate_clean("addendum_test.die", &text)
        .into_iter()
        .map(|(name, data)| match data {
            Data::Sketch(s) => (name, s),
            other => panic!("`{name}` is not a sketch: {other:?}"),
        })
        .collect()
}

fn one(expr: &str) -> Arc<Sketch> {
    profiles(&format!("let p = {expr}")).remove(0).1
}

/// The diagnostics' messages of a script.
fn messages(text: &str) -> Vec<String> {
    let mut engine = Engine::new(None);
    engine
        .evaluate("addendum_test.die", text, None)
        .diagnostics
        .iter()
        .map(|d| format!("{}: {}", d.code, d.message))
        .collect()
}

fn p(s: f64, z: f64) -> DVec2 {
    DVec2::new(s, z)
}

/// The radius of a fillet or arc segment from its curvature at the middle and ends.
fn radius_of(sk: &Sketch, k: usize) -> f64 {
    let (a, b) = sk.segments[k].range;
    let rs: Vec<f64> = [a, 0.5 * (a + b), b - 1e-12]
        .iter()
        .map(|&t| 1.0 / sk.curve.curvature(t))
        .collect();
    for r in &rs {
        assert!((r - rs[0]).abs() < 1e-6 * rs[0], "not circular: {rs:?}");
    }
    rs[1]
}

/// What every profile must satisfy: drawn in `profile`, exact ends, G1 joins, never
/// backwards in s, monotone in z towards the opening.
fn check_common(name: &str, sk: &Sketch, product: DVec2, opening: DVec2) {
    assert_eq!(sk.view, View::Profile, "{name}");
    assert!(!sk.closed, "{name}");
    let (a, b) = (sk.curve.start_point(), sk.curve.end_point());
    assert!(
        a.distance(product) <= 1e-9,
        "{name} starts at {a}, not {product}"
    );
    assert!(
        b.distance(opening) <= 1e-9,
        "{name} ends at {b}, not {opening}"
    );
    // Tangent at every join next to a radius (two lines meet where a radius is 0 mm).
    for k in 1..sk.segments.len() {
        if sk.segments[k - 1].kind == "line" && sk.segments[k].kind == "line" {
            continue;
        }
        let t = sk.segments[k].range.0;
        let (left, right) = sk.curve.split_at(t).unwrap();
        let d_in = left.unit_tangent(left.domain().1).unwrap();
        let d_out = right.unit_tangent(right.domain().0).unwrap();
        assert!(
            d_in.distance(d_out) < 1e-9,
            "{name}: kink at the start of segment {k}: {d_in} then {d_out}"
        );
    }
    let up = opening.y > product.y;
    let pts = samples(sk, 4000);
    for w in pts.windows(2) {
        assert!(
            w[1].x >= w[0].x - 1e-9,
            "{name} runs backwards in s: {} after {}",
            w[1],
            w[0]
        );
        let dz = w[1].y - w[0].y;
        assert!(
            if up { dz >= -1e-9 } else { dz <= 1e-9 },
            "{name} turns back in z: {} after {}",
            w[1],
            w[0]
        );
    }
    // Placed for display like side_xz.
    let c3 = sk.to_3d();
    assert_eq!(c3.start_point(), DVec3::new(a.x, 0.0, a.y));
}

#[test]
fn wall_down_and_up() {
    let cases = [
        // (product, opening, draft deg, punch r, die r, run)
        (p(0.0, 0.0), p(90.0, -60.0), 8.0f64, 10.0, 8.0, 5.0),
        (p(12.5, 310.0), p(160.0, 180.0), 3.0, 15.0, 12.0, 20.0),
        (p(0.0, 0.0), p(90.0, 60.0), 10.0, 10.0, 8.0, 5.0),
        (p(-40.0, 25.0), p(45.0, -35.0), 0.0, 6.0, 6.0, 0.0),
        (p(0.0, 0.0), p(120.0, -80.0), 25.0, 0.0, 0.0, 10.0),
    ];
    for (i, &(prod, open, draft, rp, rd, run)) in cases.iter().enumerate() {
        let name = format!("wall case {i}");
        let sk = one(&format!(
            "ad.wall(({}, {}), ({}, {}), draft: {draft} deg, punch_radius: {rp} mm, die_radius: {rd} mm, run: {run} mm)",
            prod.x, prod.y, open.x, open.y
        ));
        check_common(&name, &sk, prod, open);
        // One wall at the draft, reaching from one height to the other.
        let w = walls(&sk);
        assert_eq!(w.len(), 1, "{name}: {:?}", kinds(&sk));
        assert!(
            (draft_of(w[0]) - draft.to_radians()).abs() < 1e-9,
            "{name}: wall at {} deg",
            draft_of(w[0]).to_degrees()
        );
        // The run: the first straight piece, `run` long at the product's height.
        let f = flats(&sk);
        if run > 0.0 {
            assert!((f[0].0.distance(f[0].1) - run).abs() < 1e-9, "{name}");
            assert!((f[0].0.y - prod.y).abs() < 1e-12, "{name}");
        } else {
            assert_eq!(
                kinds(&sk)[0],
                "fillet",
                "{name}: the radius starts at the product"
            );
        }
        // The radii.
        let fillets: Vec<usize> = (0..sk.segments.len())
            .filter(|&k| sk.segments[k].kind == "fillet")
            .collect();
        let expected: Vec<f64> = [rp, rd].into_iter().filter(|&r| r > 0.0).collect();
        assert_eq!(fillets.len(), expected.len(), "{name}");
        for (&k, r) in fillets.iter().zip(expected) {
            assert!((radius_of(&sk, k) - r).abs() < 1e-9 * r, "{name}");
        }
        // The flat on to the opening takes the rest.
        let half = (45.0 - draft / 2.0).to_radians().tan();
        let rest = open.x
            - prod.x
            - run
            - (open.y - prod.y).abs() * draft.to_radians().tan()
            - (rp + rd) * half;
        let last = f.last().unwrap();
        assert!((last.1.x - last.0.x - rest).abs() < 1e-9, "{name}");
    }
}

#[test]
fn step_down_and_up() {
    // (product, opening, step depth, step width, draft, punch r, die r, step r, run)
    let cases = [
        (
            p(0.0, 0.0),
            p(140.0, -80.0),
            30.0,
            20.0,
            8.0f64,
            10.0,
            8.0,
            6.0,
            5.0,
        ),
        (
            p(0.0, 0.0),
            p(140.0, 80.0),
            30.0,
            20.0,
            8.0,
            10.0,
            8.0,
            6.0,
            5.0,
        ),
        // A deep step: most of the depth in the first wall.
        (
            p(5.0, 400.0),
            p(190.0, 250.0),
            120.0,
            12.0,
            5.0,
            12.0,
            10.0,
            5.0,
            0.0,
        ),
        // Radii meeting on the step.
        (
            p(0.0, 0.0),
            p(160.0, -70.0),
            35.0,
            0.0,
            12.0,
            6.0,
            6.0,
            6.0,
            5.0,
        ),
    ];
    for (i, &(prod, open, depth, width, draft, rp, rd, rs, run)) in cases.iter().enumerate() {
        let name = format!("step case {i}");
        let sk = one(&format!(
            "ad.step(({}, {}), ({}, {}), {depth} mm, {width} mm, draft: {draft} deg, punch_radius: {rp} mm, die_radius: {rd} mm, step_radius: {rs} mm, run: {run} mm)",
            prod.x, prod.y, open.x, open.y
        ));
        check_common(&name, &sk, prod, open);
        let w = walls(&sk);
        assert_eq!(w.len(), 2, "{name}: {:?}", kinds(&sk));
        for wall in &w {
            assert!(
                (draft_of(*wall) - draft.to_radians()).abs() < 1e-9,
                "{name}"
            );
        }
        // The profile passes through the step height, on a flat `step_width` wide
        // (just a point where the two step radii meet).
        let sign = if open.y > prod.y { 1.0 } else { -1.0 };
        let step_z = prod.y + sign * depth;
        let pts = samples(&sk, 4000);
        assert!(
            pts.iter().any(|q| (q.y - step_z).abs() < 1e-9),
            "{name}: never at the step height {step_z}"
        );
        let on_step: Vec<_> = flats(&sk)
            .into_iter()
            .filter(|(a, _)| (a.y - step_z).abs() < 1e-9)
            .collect();
        if width > 0.0 {
            assert_eq!(on_step.len(), 1, "{name}");
            assert!(
                (on_step[0].1.x - on_step[0].0.x - width).abs() < 1e-9,
                "{name}"
            );
        } else {
            assert!(on_step.is_empty(), "{name}");
        }
        // The first wall ends and the second begins at the step height (their radii
        // between): the walls lie above and below it.
        let (hi, lo) = if sign < 0.0 { (0, 1) } else { (1, 0) };
        assert!(w[hi].1.y.min(w[hi].0.y) >= step_z - 1e-9, "{name}");
        assert!(w[lo].1.y.max(w[lo].0.y) <= step_z + 1e-9, "{name}");
    }
}

#[test]
fn flat_binder_takes_the_rest_on_the_product_side() {
    let cases = [
        (p(0.0, 0.0), p(120.0, -50.0), 40.0, 8.0f64, 10.0, 8.0),
        (p(0.0, 0.0), p(150.0, 70.0), 25.0, 12.0, 10.0, 8.0),
        (p(30.0, 200.0), p(150.0, 120.0), 0.0, 6.0, 8.0, 10.0),
    ];
    for (i, &(prod, open, flat, draft, rp, rd)) in cases.iter().enumerate() {
        let name = format!("flat_binder case {i}");
        let sk = one(&format!(
            "ad.flat_binder(({}, {}), ({}, {}), flat: {flat} mm, draft: {draft} deg, punch_radius: {rp} mm, die_radius: {rd} mm)",
            prod.x, prod.y, open.x, open.y
        ));
        check_common(&name, &sk, prod, open);
        let w = walls(&sk);
        assert_eq!(w.len(), 1, "{name}");
        assert!((draft_of(w[0]) - draft.to_radians()).abs() < 1e-9, "{name}");
        let f = flats(&sk);
        if flat > 0.0 {
            let last = f.last().unwrap();
            assert!((last.1.x - last.0.x - flat).abs() < 1e-9, "{name}");
            assert!((last.1 - open).length() < 1e-9, "{name}");
        } else {
            assert_eq!(*kinds(&sk).last().unwrap(), "fillet", "{name}");
        }
        let half = (45.0 - draft / 2.0).to_radians().tan();
        let run = open.x
            - prod.x
            - flat
            - (open.y - prod.y).abs() * draft.to_radians().tan()
            - (rp + rd) * half;
        assert!((f[0].1.x - f[0].0.x - run).abs() < 1e-9, "{name}");
    }
}

#[test]
fn profiles_with_defaults_and_at_one_height() {
    let all = profiles(
        "let w = ad.wall((0, 0), (90, -60))
let s = ad.step((0, 0), (140, -80), 30 mm, 20 mm)
let f = ad.flat_binder((0, 0), (120, -50))
let level = ad.wall((0, 10), (50, 10))
let level_f = ad.flat_binder((0, 10), (50, 10))",
    );
    let get = |n: &str| all.iter().find(|(m, _)| m == n).unwrap().1.clone();
    assert_eq!(
        kinds(&get("w")),
        ["line", "fillet", "line", "fillet", "line"]
    );
    assert_eq!(
        kinds(&get("s")),
        ["line", "fillet", "line", "fillet", "line", "fillet", "line", "fillet", "line"]
    );
    // Defaults: 8 deg walls, 10 mm and 8 mm radii, a 5 mm run, a 40 mm binder flat.
    let w = get("w");
    assert!((draft_of(walls(&w)[0]) - 8f64.to_radians()).abs() < 1e-9);
    assert!((radius_of(&w, 1) - 10.0).abs() < 1e-9);
    assert!((radius_of(&w, 3) - 8.0).abs() < 1e-9);
    let f0 = flats(&w)[0];
    assert!((f0.1.x - f0.0.x - 5.0).abs() < 1e-9);
    let f = get("f");
    let last = *flats(&f).last().unwrap();
    assert!((last.1.x - last.0.x - 40.0).abs() < 1e-9);
    let s = get("s");
    assert!((radius_of(&s, 3) - 6.0).abs() < 1e-9);
    for n in ["level", "level_f"] {
        let l = get(n);
        assert_eq!(kinds(&l), ["line"]);
        check_common(n, &l, p(0.0, 10.0), p(50.0, 10.0));
    }
}

#[test]
fn a_wall_that_does_not_fit_folds_back_but_still_ends_on_the_points() {
    // flat_binder: 50 mm of s for a 40 mm flat, radii and a 50 mm deep wall: the run
    // on the product side would be negative.
    let prod = p(0.0, 0.0);
    let open = p(50.0, -50.0);
    let folded = [
        one("ad.flat_binder((0, 0), (50, -50))"),
        // wall: the flat on to the opening would be negative.
        one("ad.wall((0, 0), (20, -50))"),
        one("ad.step((0, 0), (60, -80), 30 mm, 20 mm)"),
    ];
    let opens = [open, p(20.0, -50.0), p(60.0, -80.0)];
    for (sk, open) in folded.iter().zip(opens) {
        let (a, b) = (sk.curve.start_point(), sk.curve.end_point());
        assert!(a.distance(prod) <= 1e-9 && b.distance(open) <= 1e-9);
        // It runs backwards in s somewhere: that is the fold the step draw reports.
        let pts = samples(sk, 4000);
        assert!(
            pts.windows(2).any(|w| w[1].x < w[0].x - 1e-6),
            "{:?} does not fold",
            kinds(sk)
        );
        // The radii are still exact arcs, the walls still at the default draft.
        assert!((draft_of(walls(sk)[0]) - 8f64.to_radians()).abs() < 1e-9);
        assert!(kinds(sk).contains(&"arc"));
        for k in 0..sk.segments.len() {
            if matches!(sk.segments[k].kind, "arc" | "fillet") {
                let r = radius_of(sk, k);
                assert!([6.0, 8.0, 10.0].iter().any(|x| (r - x).abs() < 1e-9), "{r}");
            }
        }
    }
}

#[test]
fn profile_view() {
    let sk = profiles(
        "let p = sketch(profile) {
    from (0, 0)
    line to (30, 0)
    fillet 5
    line to (40, -50)
}",
    )
    .remove(0)
    .1;
    assert_eq!(sk.view, View::Profile);
    assert_eq!(sk.view.name(), "profile");
    assert_eq!(View::Profile.place(p(3.0, 4.0)), DVec3::new(3.0, 0.0, 4.0));
    // A typo is offered `profile`.
    let m = messages("let p = sketch(profil) {\n    from (0, 0)\n    line to (1, 0)\n}\n");
    assert!(
        m.iter().any(|m| m.contains("cannot find `profil`")),
        "{m:?}"
    );
    let mut engine = Engine::new(None);
    let out = engine.evaluate(
        "typo.die",
        "let p = sketch(profil) {\n    from (0, 0)\n    line to (1, 0)\n}\n",
        None,
    );
    assert_eq!(
        out.diagnostics[0].help.as_deref(),
        Some("did you mean `profile`?")
    );
    // A script's own `profile` declaration does not reach into the module.
    let m = messages(
        "import \"std/addendum\" as ad
let profile = 3 mm
let w = ad.wall((0, 0), (90, -60), die_radius: profile)
",
    );
    assert!(m.is_empty(), "{m:?}");
}

#[test]
fn a_profile_is_not_a_side_view_of_a_punch_opening() {
    let text = "let outline = sketch(top) {
    from (-400, -300)
    fillet 80
    line to (400, -300)
    fillet 80
    line to (400, 300)
    fillet 80
    line to (-400, 300)
    fillet 80
    close
}
let wrap_x = sketch(profile) {
    from (-500, 0)
    line to (500, 0)
}
let wrap_y = sketch(side_yz) {
    from (-400, 0)
    line to (400, 0)
}
punch_opening opening {
    top = outline
    side front = wrap_x
    side right = wrap_y
    side back = wrap_x
    side left = wrap_y
}
";
    let m = messages(text);
    assert!(
        m.iter()
            .any(|m| m.contains("must be drawn in a side view") && m.contains("`profile`")),
        "{m:?}"
    );
}

#[test]
fn bad_parameters_are_refused_at_the_designers_call() {
    // (call, message)
    let cases = [
        (
            "ad.wall((0, 0), (90, -60), punch_radius: -10 mm)",
            "addendum.wall: `punch_radius` must be 0 mm or more, but it is -10 mm",
        ),
        (
            "ad.wall((0, 0), (90, -60), draft: 95 deg)",
            "addendum.wall: `draft`, the walls' angle from the vertical, must be at least 0 deg and less than 90 deg, but it is 95 deg",
        ),
        (
            "ad.wall((0, 0), (90, -60), run: 4 deg)",
            "addendum.wall: `run` must be a length (mm, cm, m or in) such as `10 mm`, but it is 4 deg",
        ),
        (
            "ad.wall((0, 0), (90, -60), run: 0 mm, punch_radius: 0 mm)",
            "addendum.wall: `run` and `punch_radius` are both 0 mm, so the profile's first line would have no length",
        ),
        (
            "ad.step((0, 0), (140, -80), -30 mm, 20 mm)",
            "addendum.step: `step_depth` must be a positive length, but it is -30 mm",
        ),
        (
            "ad.step((0, 0), (140, -80), 30 mm, -20 mm)",
            "addendum.step: `step_width` must be 0 mm or more, but it is -20 mm",
        ),
        (
            "ad.step((0, 0), (140, -80), 30 mm, 20 mm, step_radius: -6 mm)",
            "addendum.step: `step_radius` must be 0 mm or more, but it is -6 mm",
        ),
        (
            "ad.step((0, 0), (140, -80), 80 mm, 20 mm)",
            "addendum.step: `step_depth` must be less than the height from the product edge to the punch opening, 80 mm, so that the second wall has some height left, but it is 80 mm",
        ),
        (
            "ad.flat_binder((0, 0), (120, -50), flat: -40 mm)",
            "addendum.flat_binder: `flat` must be 0 mm or more, but it is -40 mm",
        ),
        (
            "ad.flat_binder((0, 0), (120, -50), flat: 0 mm, die_radius: 0 mm)",
            "addendum.flat_binder: `flat` and `die_radius` are both 0 mm, so the profile's last line would have no length",
        ),
    ];
    for (call, message) in cases {
        let text = format!("import \"std/addendum\" as ad\nunits mm deg\nlet p = {call}\n");
        let mut engine = Engine::new(None);
        let out = engine.evaluate("addendum_test.die", &text, None);
        assert_eq!(out.diagnostics.len(), 1, "{call}: {:?}", out.diagnostics);
        let d = &out.diagnostics[0];
        assert_eq!(d.code, "die::bad_argument", "{call}");
        assert_eq!(d.message, message, "{call}");
        // At the module's `fail(...)`, with the designer's call in the chain.
        let primary = engine.sources.slice(d.primary.span);
        assert!(primary.starts_with("fail("), "{call}: {primary}");
        let function = call.trim_start_matches("ad.").split('(').next().unwrap();
        let chain: Vec<(&str, &str)> = d
            .secondary
            .iter()
            .map(|l| (l.message.as_str(), engine.sources.slice(l.span)))
            .collect();
        assert_eq!(
            chain,
            [(format!("in this call of `{function}`").as_str(), call)],
            "{call}"
        );
    }
    // Bare numbers for the parameters without a default are still lengths, and at one
    // height a wall needs no run or radius.
    let bare = one("ad.step((0, 0), (140, -80), 30, 20, draft: 10)");
    let units = one("ad.step((0, 0), (140, -80), 30 mm, 20 mm, draft: 10 deg)");
    assert_eq!(bare.curve, units.curve);
    one("ad.wall((0, 10), (50, 10), run: 0 mm, punch_radius: 0 mm)");
}
