//! `std/beads`: the standard draw-bead cross-sections, evaluated through the engine and
//! measured on their curves: feet on the binder at the documented half width, mirror
//! symmetry, never below the binder, the crest exactly at the height, never backwards
//! in s, tangent joins, flanks at the draft and radii as asked.

use std::f64::consts::FRAC_PI_4;
use std::sync::Arc;

use dieface::eval::sketch::{Sketch, View};
use dieface::eval::{Data, Engine};
use glam::DVec2;

#[path = "common/profiles.rs"]
mod profiles_common;
#[path = "common/script.rs"]
mod script;

use profiles_common::{draft_of, flats, kinds, samples, walls as flanks};

/// Evaluates `lets` (one `let name = ...` per line) after importing the module, and
/// returns every declaration's value; panics on any diagnostic.
fn evaluate(lets: &str) -> Vec<(String, Data)> {
    let text = format!("import \"std/beads\" as b\nunits mm deg\n{lets}\n");
    script::evaluate_clean("beads_test.die", &text)
}

/// The sketch `expr` evaluates to.
fn sketch(expr: &str) -> Arc<Sketch> {
    match evaluate(&format!("let p = {expr}")).remove(0).1 {
        Data::Sketch(s) => s,
        other => panic!("`{expr}` is not a sketch: {other:?}"),
    }
}

/// The length (in mm) `expr` evaluates to.
fn length(expr: &str) -> f64 {
    match evaluate(&format!("let x = {expr}")).remove(0).1 {
        Data::Number(q) => q.value,
        other => panic!("`{expr}` is not a number: {other:?}"),
    }
}

/// The diagnostics' messages of a script importing the module.
fn messages(lets: &str) -> Vec<String> {
    let text = format!("import \"std/beads\" as b\nunits mm deg\n{lets}\n");
    let mut engine = Engine::new(None);
    engine
        .evaluate("beads_test.die", &text, None)
        .diagnostics
        .iter()
        .map(|d| format!("{}: {}", d.code, d.message))
        .collect()
}

/// The radii of the arcs and fillets, in drawing order, each checked to be circular.
fn radii(sk: &Sketch) -> Vec<f64> {
    (0..sk.segments.len())
        .filter(|&k| matches!(sk.segments[k].kind, "arc" | "fillet"))
        .map(|k| {
            let (a, b) = sk.segments[k].range;
            let rs: Vec<f64> = [a + 1e-12, 0.25 * (3.0 * a + b), 0.5 * (a + b), b - 1e-12]
                .iter()
                .map(|&t| 1.0 / sk.curve.curvature(t))
                .collect();
            for r in &rs {
                assert!((r - rs[0]).abs() < 1e-6 * rs[0], "not circular: {rs:?}");
            }
            rs[2]
        })
        .collect()
}

/// The highest point of the profile: the best of dense samples, refined by golden
/// section in the parameter around it.
fn max_z(sk: &Sketch) -> f64 {
    let (t0, t1) = sk.curve.domain();
    let n = 20_000;
    let dt = (t1 - t0) / n as f64;
    let best = (0..=n)
        .map(|k| t0 + dt * k as f64)
        .max_by(|a, b| sk.curve.point_at(*a).y.total_cmp(&sk.curve.point_at(*b).y))
        .unwrap();
    let z = |t: f64| sk.curve.point_at(t.clamp(t0, t1)).y;
    let (mut lo, mut hi) = (best - dt, best + dt);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (c, d) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if z(c) >= z(d) {
            hi = d;
        } else {
            lo = c;
        }
    }
    z(0.5 * (lo + hi)).max(z(best))
}

/// How steep the profile gets: the smallest angle from the vertical of a chord between
/// dense samples.
fn steepest(sk: &Sketch) -> f64 {
    let pts = samples(sk, 40_000);
    pts.windows(2)
        .filter(|w| w[0].distance(w[1]) > 1e-12)
        .map(|w| draft_of((w[0], w[1])))
        .fold(f64::INFINITY, f64::min)
}

/// What every bead profile must satisfy: drawn in `profile`, open, from (-w, 0) to
/// (w, 0), mirror-symmetric about s = 0, never below the binder, its top exactly at
/// `height`, never backwards in s, tangent at every join except a sharp corner between
/// two lines or on the binder (a shoulder of 0).
fn check_common(name: &str, sk: &Sketch, w: f64, height: f64) {
    assert_eq!(sk.view, View::Profile, "{name}");
    assert!(!sk.closed, "{name}");
    let (a, b) = (sk.curve.start_point(), sk.curve.end_point());
    assert!(
        a.distance(DVec2::new(-w, 0.0)) <= 1e-9,
        "{name} starts at {a}, not (-{w}, 0)"
    );
    assert!(
        b.distance(DVec2::new(w, 0.0)) <= 1e-9,
        "{name} ends at {b}, not ({w}, 0)"
    );
    assert!(
        a.y.abs() <= 1e-9 && b.y.abs() <= 1e-9,
        "{name}: feet at {a}, {b}"
    );
    // Mirror symmetry: the point at parameter t mirrors the one at the far end's t
    // (the segments are drawn mirrored, each on its own unit parameter range), and
    // every segment end mirrors one.
    let (t0, t1) = sk.curve.domain();
    let n = 4000;
    for k in 0..=n {
        let t = t0 + (t1 - t0) * k as f64 / n as f64;
        let p = sk.curve.point_at(t);
        let q = sk.curve.point_at(t0 + t1 - t);
        assert!(
            p.distance(DVec2::new(-q.x, q.y)) <= 1e-9,
            "{name} is not symmetric: {p} against {q}"
        );
    }
    let m = sk.segments.len();
    for k in 0..m {
        assert_eq!(
            sk.segments[k].kind,
            sk.segments[m - 1 - k].kind,
            "{name}: {:?}",
            kinds(sk)
        );
    }
    // Never below the binder, never backwards in s.
    let pts = samples(sk, 20_000);
    for w in pts.windows(2) {
        assert!(w[1].y >= -1e-9, "{name} dips below the binder at {}", w[1]);
        assert!(
            w[1].x >= w[0].x - 1e-9,
            "{name} runs backwards in s: {} after {}",
            w[1],
            w[0]
        );
    }
    // The top exactly at the height.
    let top = max_z(sk);
    assert!(
        (top - height).abs() <= 1e-6,
        "{name}: top at {top}, not {height}"
    );
    assert!(
        pts.iter().all(|p| p.y <= height + 1e-9),
        "{name} overshoots"
    );
    // Tangent joins.
    for k in 1..m {
        let (prev, next) = (sk.segments[k - 1].kind, sk.segments[k].kind);
        let t = sk.segments[k].range.0;
        let at = sk.curve.point_at(t);
        if (prev == "line" && next == "line")
            || at.y.abs() <= 1e-9 && (prev == "line" || next == "line")
        {
            continue;
        }
        let (left, right) = sk.curve.split_at(t).unwrap();
        let d_in = left.unit_tangent(left.domain().1).unwrap();
        let d_out = right.unit_tangent(right.domain().0).unwrap();
        if at.y.abs() <= 1e-9 && d_in.y.abs() > 1e-6 {
            // A sharp shoulder: an arc or flank meeting the binder at an angle.
            continue;
        }
        assert!(
            d_in.distance(d_out) < 1e-9,
            "{name}: kink at the start of segment {k} ({:?}): {d_in} then {d_out}",
            kinds(sk)
        );
    }
}

fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// `r * tan(45 deg - draft / 2)`.
fn takes(r: f64, draft: f64) -> f64 {
    r * (FRAC_PI_4 - draft / 2.0).tan()
}

/// The straight flank of a round bead, along the flank.
fn round_flank(h: f64, r: f64, shoulder: f64, draft: f64) -> f64 {
    (h - (r + shoulder) * (1.0 - draft.sin())) / draft.cos()
}

/// The documented half width of a round bead.
fn round_w(h: f64, r: f64, shoulder: f64, draft: f64) -> f64 {
    let k = r + shoulder;
    if round_flank(h, r, shoulder, draft) > 1e-6 {
        h * draft.tan() + takes(k, draft)
    } else {
        (h * (2.0 * k - h)).sqrt()
    }
}

/// The documented half width of a square bead or lock step.
fn square_w(h: f64, width: f64, shoulder: f64, draft: f64) -> f64 {
    width / 2.0 + h * draft.tan() + takes(shoulder, draft)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

/// Checks the radii: the sketch's arcs and fillets each have one of `allowed`, and
/// every one of `required` occurs.
fn check_radii(name: &str, sk: &Sketch, allowed: &[f64], required: &[f64]) {
    let rs = radii(sk);
    for r in &rs {
        assert!(
            allowed.iter().any(|x| close(*r, *x)),
            "{name}: radius {r}, not one of {allowed:?}"
        );
    }
    for x in required {
        assert!(
            rs.iter().any(|r| close(*r, *x)),
            "{name}: no radius {x} in {rs:?}"
        );
    }
}

#[test]
fn round_beads() {
    // (height, radius, shoulder, draft deg); None: the defaults.
    let cases = [
        (None, "defaults: a low bead, no straight flank"),
        (Some((6.0, 4.0, 3.0, 15.0)), "a short flank"),
        (
            Some((12.0, 5.0, 3.0, 0.0)),
            "vertical flanks, a half-circle crown",
        ),
        (Some((8.0, 6.0, 4.0, 25.0)), "a long flank"),
        (Some((6.0, 8.0, 0.0, 15.0)), "sharp shoulders with a flank"),
        (Some((3.0, 8.0, 0.0, 15.0)), "sharp shoulders, no flank"),
        (Some((2.5, 10.0, 5.0, 10.0)), "a flat, low bead"),
    ];
    for (params, what) in cases {
        let (h, r, s, d) = params.unwrap_or((6.0, 8.0, 3.0, 15.0));
        let call = match params {
            None => "b.round()".to_string(),
            Some(_) => {
                format!("b.round(height: {h} mm, radius: {r} mm, shoulder: {s} mm, draft: {d} deg)")
            }
        };
        let name = format!("{call} ({what})");
        let sk = sketch(&call);
        let draft = deg(d);
        let w = round_w(h, r, s, draft);
        check_common(&name, &sk, w, h);
        let companion = call.replace("b.round(", "b.round_half_width(");
        assert!(close(length(&companion), w), "{name}: {companion}");
        // The crown and the shoulders at their radii.
        let shoulders: &[f64] = if s > 0.0 { &[s] } else { &[] };
        let allowed: Vec<f64> = [r].iter().chain(shoulders).copied().collect();
        check_radii(&name, &sk, &allowed, &allowed);
        // The crest on the centre line, halfway along the (symmetric) parameter.
        let (t0, t1) = sk.curve.domain();
        let crest = sk.curve.point_at(0.5 * (t0 + t1));
        assert!(crest.distance(DVec2::new(0.0, h)) < 1e-9, "{name}: {crest}");
        let flank = round_flank(h, r, s, draft);
        let f = flanks(&sk);
        if flank > 1e-6 {
            // Two straight flanks, at the draft, `flank` long.
            assert_eq!(f.len(), 2, "{name}: {:?}", kinds(&sk));
            for fl in &f {
                assert!(
                    (draft_of(*fl) - draft).abs() < 1e-9,
                    "{name}: flank at {} deg",
                    draft_of(*fl).to_degrees()
                );
                assert!((fl.0.distance(fl.1) - flank).abs() < 1e-9, "{name}");
            }
            assert!((steepest(&sk) - draft).abs() < 1e-9, "{name}");
        } else {
            // No straight flank: the crown meets the shoulders (or the binder) at
            // atan2(radius + shoulder - height, w) from the vertical, less steep than
            // the draft.
            assert!(f.is_empty(), "{name}: {:?}", kinds(&sk));
            let slope = (r + s - h).atan2(w);
            assert!(slope >= draft, "{name}");
            assert!(
                (steepest(&sk) - slope).abs() < 1e-3,
                "{name}: steepest {} deg, expected {} deg",
                steepest(&sk).to_degrees(),
                slope.to_degrees()
            );
        }
        assert!(flats(&sk).is_empty(), "{name}");
    }
}

#[test]
fn round_defaults_and_figures() {
    // The defaults make a low bead: 6 mm < 11 mm * (1 - sin 15 deg) = 8.153 mm.
    let sk = sketch("b.round()");
    assert_eq!(kinds(&sk), ["arc", "arc", "arc"]);
    let w = 96f64.sqrt();
    assert!((w - 9.797959).abs() < 1e-6);
    assert!(close(sk.curve.end_point().x, w));
    assert!(close(length("b.round_half_width()"), w));
    // The documented example with a flank: a 0.84 mm flank.
    let sk = sketch("b.round(radius: 4 mm)");
    assert_eq!(kinds(&sk), ["arc", "line", "arc", "line", "arc"]);
    let f = flanks(&sk)[0];
    assert!((f.0.distance(f.1) - 0.8404).abs() < 1e-4);
    // Named and positional arguments mean the same.
    let a = sketch("b.round(7 mm, 5 mm, 2 mm, 12 deg)");
    let b = sketch("b.round(draft: 12 deg, shoulder: 2 mm, radius: 5 mm, height: 7 mm)");
    assert_eq!(a.curve, b.curve);
}

#[test]
fn square_beads_and_lock_steps() {
    // (function, height, width, corner, shoulder, draft deg, explicit?)
    let cases = [
        ("square", 6.0, 14.0, 3.0, 3.0, 10.0, false),
        ("square", 10.0, 20.0, 4.0, 5.0, 0.0, true),
        ("square", 6.0, 14.0, 0.0, 0.0, 10.0, true),
        ("square", 5.0, 8.0, 2.0, 1.0, 20.0, true),
        ("square", 6.0, 14.0, 3.0, 0.0, 30.0, true),
        ("lock_step", 4.0, 20.0, 2.0, 2.0, 5.0, false),
        ("lock_step", 6.0, 30.0, 3.0, 3.0, 5.0, true),
        ("lock_step", 4.0, 20.0, 1.5, 2.5, 2.0, true),
    ];
    for (f, h, width, corner, shoulder, d, explicit) in cases {
        let call = if explicit {
            format!(
                "b.{f}(height: {h} mm, width: {width} mm, corner: {corner} mm, shoulder: {shoulder} mm, draft: {d} deg)"
            )
        } else {
            format!("b.{f}()")
        };
        let name = call.clone();
        let sk = sketch(&call);
        let draft = deg(d);
        let w = square_w(h, width, shoulder, draft);
        check_common(&name, &sk, w, h);
        let companion = call.replace(&format!("b.{f}("), &format!("b.{f}_half_width("));
        assert!(close(length(&companion), w), "{name}: {companion}");
        // Two flanks at the draft, aimed at the virtual top corners (+-width / 2, h)
        // and the virtual feet (+-(width / 2 + h tan(draft)), 0).
        let fl = flanks(&sk);
        assert_eq!(fl.len(), 2, "{name}: {:?}", kinds(&sk));
        for (i, (a, b)) in fl.iter().enumerate() {
            assert!(
                (draft_of((*a, *b)) - draft).abs() < 1e-9,
                "{name}: flank at {} deg",
                draft_of((*a, *b)).to_degrees()
            );
            let dir = (*b - *a) / (b.y - a.y);
            let at_top = *a + dir * (h - a.y);
            let at_binder = *a - dir * a.y;
            let side = if i == 0 { -1.0 } else { 1.0 };
            assert!(close(at_top.x, side * width / 2.0), "{name}: {at_top}");
            assert!(
                close(at_binder.x, side * (width / 2.0 + h * draft.tan())),
                "{name}: {at_binder}"
            );
        }
        // The flat top: between the corner radii, at the height.
        let tops = flats(&sk);
        assert_eq!(tops.len(), 1, "{name}");
        let (a, b) = tops[0];
        assert!((a.y - h).abs() < 1e-12 && (b.y - h).abs() < 1e-12, "{name}");
        assert!(
            (b.x - a.x - (width - 2.0 * takes(corner, draft))).abs() < 1e-9,
            "{name}: top flat {}",
            b.x - a.x
        );
        let allowed: Vec<f64> = [corner, shoulder]
            .into_iter()
            .filter(|&r| r > 0.0)
            .collect();
        check_radii(&name, &sk, &allowed, &allowed);
        assert!((steepest(&sk) - draft).abs() < 1e-9, "{name}");
    }
    // The defaults as documented.
    assert_eq!(
        kinds(&sketch("b.square()")),
        ["arc", "line", "fillet", "line", "fillet", "line", "arc"]
    );
    assert!((length("b.square_half_width()") - 10.575261).abs() < 1e-6);
    assert!((length("b.lock_step_half_width()") - 12.182617).abs() < 1e-6);
    // A lock step is a square bead with 5 deg flanks and its own defaults.
    assert_eq!(
        sketch("b.lock_step()").curve,
        sketch("b.square(height: 4 mm, width: 20 mm, corner: 2 mm, shoulder: 2 mm, draft: 5 deg)")
            .curve
    );
}

#[test]
fn double_beads() {
    // (height, radius, gap, shoulder, draft deg); None: the defaults.
    let cases = [
        (None, "defaults: low beads, a flat valley"),
        (
            Some((5.0, 6.0, 0.0, 2.0, 15.0)),
            "low beads meeting in one shoulder radius",
        ),
        (
            Some((5.0, 3.0, 10.0, 2.0, 15.0)),
            "beads with flanks, a flat valley",
        ),
        (
            Some((5.0, 3.0, 0.0, 2.0, 15.0)),
            "beads with flanks, no flat",
        ),
        (
            Some((5.0, 3.0, 0.0, 0.0, 15.0)),
            "sharp shoulders: a V valley",
        ),
        (Some((5.0, 3.0, 10.0, 0.0, 15.0)), "sharp shoulders, a flat"),
        (
            Some((5.0, 6.0, 0.0, 0.0, 15.0)),
            "low beads, sharp shoulders",
        ),
        (
            Some((5.0, 6.0, 4.0, 0.0, 15.0)),
            "low beads, sharp shoulders, a flat",
        ),
        (Some((10.0, 4.0, 6.0, 2.0, 0.0)), "vertical flanks"),
    ];
    for (params, what) in cases {
        let (h, r, gap, s, d) = params.unwrap_or((5.0, 6.0, 10.0, 2.0, 15.0));
        let call = match params {
            None => "b.double()".to_string(),
            Some(_) => format!(
                "b.double(height: {h} mm, radius: {r} mm, gap: {gap} mm, shoulder: {s} mm, draft: {d} deg)"
            ),
        };
        let name = format!("{call} ({what})");
        let sk = sketch(&call);
        let draft = deg(d);
        let w1 = round_w(h, r, s, draft);
        let offset = w1 + gap / 2.0;
        let w = 2.0 * w1 + gap / 2.0;
        check_common(&name, &sk, w, h);
        for (fname, value) in [("double_half_width", w), ("double_offset", offset)] {
            let companion = call.replace("b.double(", &format!("b.{fname}("));
            assert!(close(length(&companion), value), "{name}: {companion}");
        }
        // The crests at s = -offset and offset, and nowhere else at the height.
        let pts = samples(&sk, 40_000);
        for c in [-offset, offset] {
            assert!(
                pts.iter().any(|p| p.distance(DVec2::new(c, h)) < 2e-3),
                "{name}: no crest at {c}"
            );
        }
        assert!(
            pts.iter()
                .filter(|p| p.y > h - 1e-3)
                .all(|p| (p.x.abs() - offset).abs() < 0.5),
            "{name}"
        );
        // The valley reaches the binder: a flat from -gap / 2 to gap / 2, or (no gap)
        // the point (0, 0).
        let valley = flats(&sk);
        if gap > 0.0 {
            assert_eq!(valley.len(), 1, "{name}: {:?}", kinds(&sk));
            let (a, b) = valley[0];
            assert!(a.y.abs() < 1e-12 && b.y.abs() < 1e-12, "{name}");
            assert!(
                close(a.x, -gap / 2.0) && close(b.x, gap / 2.0),
                "{name}: {a} {b}"
            );
        } else {
            assert!(valley.is_empty(), "{name}: {:?}", kinds(&sk));
            assert!(
                sk.curve.point_at(sk.curve.domain().1 / 2.0).length() < 1e-9,
                "{name}: the valley is not at (0, 0)"
            );
        }
        // Every radius is the crown's or the shoulder's; flanks at the draft.
        let allowed: Vec<f64> = [r, s].into_iter().filter(|&x| x > 0.0).collect();
        check_radii(&name, &sk, &allowed, &allowed);
        let fl = flanks(&sk);
        let flank = round_flank(h, r, s, draft);
        if flank > 1e-6 {
            assert_eq!(fl.len(), 4, "{name}: {:?}", kinds(&sk));
            for f in &fl {
                assert!((draft_of(*f) - draft).abs() < 1e-9, "{name}");
                assert!((f.0.distance(f.1) - flank).abs() < 1e-9, "{name}");
            }
        } else {
            assert!(fl.is_empty(), "{name}: {:?}", kinds(&sk));
        }
        // Each half is the round bead, moved.
        let single = sketch(&format!(
            "b.round(height: {h} mm, radius: {r} mm, shoulder: {s} mm, draft: {d} deg)"
        ));
        for p in samples(&single, 500) {
            let moved = p - DVec2::new(offset, 0.0);
            assert!(
                pts.iter().any(|q| q.distance(moved) < 0.05),
                "{name}: {moved} of the left bead is missing"
            );
        }
    }
}

/// The one diagnostic of `lets`: (code, message, where its primary label is, the
/// secondary labels' messages and the text they point at).
fn refusal(lets: &str) -> (String, String, String, Vec<(String, String)>) {
    let text = format!("import \"std/beads\" as b\nunits mm deg\n{lets}\n");
    let mut engine = Engine::new(None);
    let out = engine.evaluate("beads_test.die", &text, None);
    assert_eq!(out.diagnostics.len(), 1, "{:?}", out.diagnostics);
    let d = &out.diagnostics[0];
    let file = |span: dieface::syntax::Span| engine.sources.get(span.file).unwrap().name.clone();
    let labels = d
        .secondary
        .iter()
        .map(|l| (l.message.clone(), engine.sources.slice(l.span).to_string()))
        .collect();
    (
        d.code.to_string(),
        d.message.clone(),
        format!(
            "{}: {}",
            file(d.primary.span),
            engine.sources.slice(d.primary.span)
        ),
        labels,
    )
}

#[test]
fn bad_parameters_are_refused_at_the_designers_call() {
    // (call, message)
    let cases = [
        (
            "b.round(height: -6 mm)",
            "beads.round: `height` must be a positive length, but it is -6 mm",
        ),
        (
            "b.round(height: 0 mm)",
            "beads.round: `height` must be a positive length, but it is 0 mm",
        ),
        (
            "b.round(height: 6 deg)",
            "beads.round: `height` must be a length (mm, cm, m or in) such as `6 mm`, but it is 6 deg",
        ),
        (
            "b.round(draft: 90 deg)",
            "beads.round: `draft`, the flanks' angle from the vertical, must be at least 0 deg and less than 90 deg, but it is 90 deg",
        ),
        (
            "b.round(draft: -1 deg)",
            "beads.round: `draft`, the flanks' angle from the vertical, must be at least 0 deg and less than 90 deg, but it is -1 deg",
        ),
        (
            "b.round(draft: 5 mm)",
            "beads.round: `draft` must be an angle (deg or rad) such as `15 deg`, but it is 5 mm",
        ),
        (
            "b.round(shoulder: -3 mm)",
            "beads.round: `shoulder` must be 0 mm or more, but it is -3 mm",
        ),
        (
            "b.round(radius: 0 mm)",
            "beads.round: `radius` must be a positive length, but it is 0 mm",
        ),
        (
            "b.round_half_width(radius: -2 mm)",
            "beads.round_half_width: `radius` must be a positive length, but it is -2 mm",
        ),
        (
            "b.double(gap: -30 mm)",
            "beads.double: `gap` must be 0 mm or more, but it is -30 mm",
        ),
        (
            "b.double_half_width(height: 50 %)",
            "beads.double_half_width: `height` must be a length (mm, cm, m or in) such as `6 mm`, but it is 0.5",
        ),
        (
            "b.square(corner: -1 mm)",
            "beads.square: `corner` must be 0 mm or more, but it is -1 mm",
        ),
        (
            "b.square_half_width(width: 0 mm)",
            "beads.square_half_width: `width` must be a positive length, but it is 0 mm",
        ),
        (
            "b.lock_step(shoulder: -2 mm)",
            "beads.lock_step: `shoulder` must be 0 mm or more, but it is -2 mm",
        ),
        (
            "b.lock_step_half_width(draft: 90 deg)",
            "beads.lock_step_half_width: `draft`, the flanks' angle from the vertical, must be at least 0 deg and less than 90 deg, but it is 90 deg",
        ),
    ];
    for (call, message) in cases {
        let (code, m, primary, labels) = refusal(&format!("let p = {call}"));
        assert_eq!(code, "die::bad_argument", "{call}");
        assert_eq!(m, message, "{call}");
        // The primary label is the library's `fail(...)`; the call chain ends at the
        // designer's own call.
        assert!(primary.starts_with("std/beads: fail("), "{call}: {primary}");
        let function = call.trim_start_matches("b.").split('(').next().unwrap();
        assert_eq!(
            labels,
            [(format!("in this call of `{function}`"), call.to_string())],
            "{call}"
        );
    }
    // The edges that can be drawn are accepted: sharp shoulders and corners, touching
    // beads, vertical flanks.
    for call in [
        "b.round(shoulder: 0 mm)",
        "b.round(draft: 0 deg, height: 20 mm)",
        "b.double(gap: 0 mm)",
        "b.square(corner: 0 mm, shoulder: 0 mm)",
        "b.lock_step(draft: 0 deg)",
    ] {
        sketch(call);
    }
}

#[test]
fn a_negative_gap_is_refused() {
    assert_eq!(
        messages("let p = b.double(gap: -2 mm)"),
        ["die::bad_argument: beads.double: `gap` must be 0 mm or more, but it is -2 mm"]
    );
}

#[test]
fn a_square_bead_whose_radii_do_not_fit_is_refused() {
    // (3 + 3) * (1 - sin 10 deg) = 4.958111 mm of flank height needed.
    let (code, m, _, _) = refusal("let p = b.square(height: 4 mm)");
    assert_eq!(code, "die::bad_argument");
    assert_eq!(
        m,
        "beads.square: the `height` of 4 mm leaves no room on the flanks for the `corner` and \
         `shoulder` radii (3 mm and 3 mm): at a draft of 10 deg it must be at least 4.958111 mm \
         ((corner + shoulder) * (1 - sin(draft)))"
    );
    assert!((6.0 * (1.0 - deg(10.0).sin()) - 4.958111).abs() < 1e-6);
    // A top too narrow for its corners: 2 * 3 mm * tan(40 deg) = 5.034598 mm.
    let (_, m, _, _) = refusal("let p = b.square(width: 4 mm, corner: 3 mm)");
    assert_eq!(
        m,
        "beads.square: the top `width` of 4 mm cannot hold its two `corner` radii of 3 mm: at a \
         draft of 10 deg it must be at least 5.034598 mm (2 * corner * tan(45 deg - draft / 2))"
    );
    assert!((2.0 * takes(3.0, deg(10.0)) - 5.034598).abs() < 1e-6);
    // A lock step is refused under its own name.
    let (_, m, _, labels) = refusal("let p = b.lock_step(width: 3 mm)");
    assert!(
        m.starts_with("beads.lock_step: the top `width` of 3 mm"),
        "{m}"
    );
    assert_eq!(labels.len(), 1, "{labels:?}");
}

#[test]
fn a_bare_number_takes_the_callers_default_unit() {
    // In a millimetre file `b.round(6)` is `b.round(6 mm)`, and a bare draft is in degrees.
    assert_eq!(sketch("b.round(6)").curve, sketch("b.round(6 mm)").curve);
    assert_eq!(
        sketch("b.round(7, 5, 2, 12)").curve,
        sketch("b.round(7 mm, 5 mm, 2 mm, 12 deg)").curve
    );
    assert_eq!(
        length("b.double_half_width(gap: 4)"),
        length("b.double_half_width(gap: 4 mm)")
    );
    // In a centimetre / radian file the same numbers are centimetres and radians.
    let text = "import \"std/beads\" as b\nunits cm rad\n\
                let p = b.round(0.6)\nlet q = b.round(6 mm)\n\
                let w = b.round_half_width(0.6, draft: 0.3)\n\
                let v = b.round_half_width(6 mm, draft: 0.3 rad)\n";
    let mut engine = Engine::new(None);
    let out = engine.evaluate("beads_cm.die", text, None);
    assert!(out.diagnostics.is_empty(), "{:?}", out.diagnostics);
    let value = |name: &str| {
        out.decls
            .iter()
            .find(|d| d.name == name)
            .and_then(|d| d.value.as_ref())
            .map(|v| v.data.clone())
            .unwrap()
    };
    match (value("p"), value("q")) {
        (Data::Sketch(p), Data::Sketch(q)) => assert_eq!(p.curve, q.curve),
        other => panic!("not sketches: {other:?}"),
    }
    match (value("w"), value("v")) {
        (Data::Number(w), Data::Number(v)) => {
            assert_eq!(w, v);
            assert!(close(w.value, round_w(6.0, 8.0, 3.0, 0.3)));
        }
        other => panic!("not numbers: {other:?}"),
    }
}
