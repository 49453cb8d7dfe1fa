//! Agreement with OpenCascade (and geomdl for averaged-knot interpolation).
//!
//! `tests/reference/occ_reference.py` evaluates curves and surfaces with OpenCascade
//! 8.0.1 (`Geom_BSplineCurve`, `Geom_BSplineSurface`, `GeomAPI_Interpolate`,
//! `Geom_SurfaceOfRevolution`, boundary curves for Coons) and writes the values to
//! `tests/data/occ_reference.json`. These tests build the same geometry with dieface's
//! kernel and compare points and first and second derivatives to 1e-9 relative.

use std::f64::consts::TAU;

use dieface::geom::construct::{coons, revolve};
use dieface::geom::interpolate::{interpolate_at, Interpolation, KnotPlacement};
use dieface::geom::{Curve3, NurbsSurface};
use glam::DVec3;
use serde_json::Value;

const REL: f64 = 1e-9;

fn data() -> Value {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/occ_reference.json"
    ))
    .expect("the reference data is committed");
    serde_json::from_str(&text).expect("the reference data is valid JSON")
}

fn vec3(v: &Value) -> DVec3 {
    let a = v.as_array().expect("a point is an array");
    DVec3::new(
        a[0].as_f64().unwrap(),
        a[1].as_f64().unwrap(),
        a[2].as_f64().unwrap(),
    )
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array of numbers")
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// `|ours - theirs| <= 1e-9 * max(1, |theirs|)`, per vector. Returns the relative
/// error so the tests can report the worst one they saw.
#[track_caller]
fn assert_close(what: &str, ours: DVec3, theirs: DVec3) -> f64 {
    let err = (ours - theirs).length();
    let scale = theirs.length().max(1.0);
    assert!(
        err <= REL * scale,
        "{what}: ours {ours:?}, OpenCascade {theirs:?}, error {err:e}"
    );
    err / scale
}

fn curve(c: &Value) -> Curve3 {
    let degree = c["degree"].as_u64().unwrap() as usize;
    let knots = floats(&c["knots"]);
    let points: Vec<DVec3> = c["points"].as_array().unwrap().iter().map(vec3).collect();
    match &c["weights"] {
        Value::Null => Curve3::new(degree, knots, points).expect("reference curve is valid"),
        w => Curve3::new_rational(degree, knots, points, floats(w))
            .expect("reference curve is valid"),
    }
}

fn surface(s: &Value) -> NurbsSurface {
    let du = s["degree_u"].as_u64().unwrap() as usize;
    let dv = s["degree_v"].as_u64().unwrap() as usize;
    let net: Vec<Vec<DVec3>> = s["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| row.as_array().unwrap().iter().map(vec3).collect())
        .collect();
    let (ku, kv) = (floats(&s["knots_u"]), floats(&s["knots_v"]));
    match &s["weights"] {
        Value::Null => NurbsSurface::new(du, dv, ku, kv, net).expect("reference surface is valid"),
        w => {
            let weights = w.as_array().unwrap().iter().map(floats).collect();
            NurbsSurface::new_rational(du, dv, ku, kv, net, weights)
                .expect("reference surface is valid")
        }
    }
}

/// Compares every sample; returns the worst relative error.
fn check_curve_samples(name: &str, c: &Curve3, samples: &Value) -> f64 {
    let mut worst = 0.0f64;
    for s in samples.as_array().unwrap() {
        let t = s["t"].as_f64().unwrap();
        let [p, d1, d2] = c.derivatives::<3>(t);
        let checks = [
            ("C", p, "p"),
            ("C'", d1, "d1"),
            ("C''", d2, "d2"),
            ("point_at", c.point_at(t), "p"),
        ];
        for (what, ours, key) in checks {
            worst = worst.max(assert_close(
                &format!("{name} {what}({t})"),
                ours,
                vec3(&s[key]),
            ));
        }
    }
    worst
}

#[test]
fn curves_match_opencascade() {
    let d = data();
    let cases = d["curves"].as_array().unwrap();
    assert!(cases.len() >= 20);
    let mut degrees = [false; 6];
    let mut rational = 0;
    let mut worst = 0.0f64;
    for c in cases {
        let nc = curve(c);
        degrees[nc.degree()] = true;
        rational += usize::from(nc.is_rational());
        worst = worst.max(check_curve_samples(
            c["name"].as_str().unwrap(),
            &nc,
            &c["samples"],
        ));
    }
    println!(
        "curves: {} cases, worst relative error {worst:e}",
        cases.len()
    );
    assert!(
        degrees[1..=5].iter().all(|&d| d),
        "degrees 1 to 5 are all covered"
    );
    assert!(rational >= 5);
}

#[test]
fn surfaces_match_opencascade() {
    let d = data();
    let cases = d["surfaces"].as_array().unwrap();
    assert!(cases.len() >= 10);
    let mut worst = 0.0f64;
    for s in cases {
        let name = s["name"].as_str().unwrap();
        let ns = surface(s);
        for x in s["samples"].as_array().unwrap() {
            let (u, v) = (x["u"].as_f64().unwrap(), x["v"].as_f64().unwrap());
            let d = ns.derivatives::<3>(u, v);
            let at = format!("{name} ({u}, {v})");
            let checks = [
                ("S", d[0][0], "p"),
                ("point_at", ns.point_at(u, v), "p"),
                ("S_u", d[1][0], "du"),
                ("S_v", d[0][1], "dv"),
                ("S_uu", d[2][0], "duu"),
                ("S_uv", d[1][1], "duv"),
                ("S_vv", d[0][2], "dvv"),
            ];
            for (what, ours, key) in checks {
                worst = worst.max(assert_close(&format!("{what} {at}"), ours, vec3(&x[key])));
            }
        }
    }
    println!(
        "surfaces: {} cases, worst relative error {worst:e}",
        cases.len()
    );
}

/// OpenCascade's `GeomAPI_Interpolate` puts the cubic's knots at the parameters and
/// imposes both end derivatives (given ones, or its own estimate from the first and
/// last four points). Given the same end derivatives, our interpolation with knots at the
/// parameters must produce the same curve.
#[test]
fn interpolation_matches_opencascade() {
    let d = data();
    let cases = d["interpolations"].as_array().unwrap();
    assert!(cases.len() >= 4);
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let points: Vec<DVec3> = case["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(vec3)
            .collect();
        let params = floats(&case["parameters"]);
        let samples = case["samples"].as_array().unwrap();
        let end_derivative = |t: f64| {
            samples
                .iter()
                .find(|s| s["t"].as_f64() == Some(t))
                .map(|s| vec3(&s["d1"]))
                .expect("samples include the ends")
        };
        let start = case["start_tangent"]
            .as_array()
            .map(|_| vec3(&case["start_tangent"]));
        let end = case["end_tangent"]
            .as_array()
            .map(|_| vec3(&case["end_tangent"]));
        let opts = Interpolation {
            degree: 3,
            knots: KnotPlacement::AtParameters,
            start_tangent: Some(start.unwrap_or_else(|| end_derivative(params[0]))),
            end_tangent: Some(end.unwrap_or_else(|| end_derivative(params[params.len() - 1]))),
            ..Interpolation::default()
        };
        let c = interpolate_at(&points, &params, &opts).expect("interpolation succeeds");
        assert_eq!(
            c.knots().as_slice(),
            floats(&case["knots"]).as_slice(),
            "{name}: knots"
        );
        for (ours, theirs) in c
            .control_points()
            .iter()
            .zip(case["control_points"].as_array().unwrap())
        {
            assert_close(&format!("{name} pole"), *ours, vec3(theirs));
        }
        let worst = check_curve_samples(name, &c, &case["samples"]);
        println!("{name}: worst relative error {worst:e}");
    }
}

/// geomdl implements P&T A9.1 with averaged knots: our default interpolation.
#[test]
fn averaged_interpolation_matches_geomdl() {
    let d = data();
    for case in d["interpolations_averaged"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let points: Vec<DVec3> = case["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(vec3)
            .collect();
        let params = floats(&case["parameters"]);
        let degree = case["degree"].as_u64().unwrap() as usize;
        let opts = Interpolation {
            degree,
            ..Interpolation::default()
        };
        let c = interpolate_at(&points, &params, &opts).expect("interpolation succeeds");
        for (ours, theirs) in c.knots().as_slice().iter().zip(floats(&case["knots"])) {
            assert!(
                (ours - theirs).abs() <= 1e-12,
                "{name}: knot {ours} vs {theirs}"
            );
        }
        for (ours, theirs) in c
            .control_points()
            .iter()
            .zip(case["control_points"].as_array().unwrap())
        {
            assert_close(&format!("{name} pole"), *ours, vec3(theirs));
        }
        let worst = check_curve_samples(name, &c, &case["samples"]);
        println!("{name}: worst relative error {worst:e}");
    }
}

#[test]
fn coons_matches_the_bilinearly_blended_formula_on_opencascade_boundaries() {
    let d = data();
    let cases = d["coons"].as_array().unwrap();
    assert!(!cases.is_empty());
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let b = &case["boundaries"];
        let s = coons(
            &curve(&b["bottom"]),
            &curve(&b["top"]),
            &curve(&b["left"]),
            &curve(&b["right"]),
        )
        .expect("the boundaries meet");
        for x in case["samples"].as_array().unwrap() {
            let (u, v) = (x["u"].as_f64().unwrap(), x["v"].as_f64().unwrap());
            assert_close(
                &format!("{name} ({u}, {v})"),
                s.point_at(u, v),
                vec3(&x["p"]),
            );
        }
    }
}

/// OpenCascade parametrizes a revolution by the angle; our rational arcs are not
/// proportional to it. For each sample we find our u with the same angle (bisection on
/// the monotone angle of the u-iso-curve) and compare the point, and the derivatives
/// after the chain rule: `S_u(ours) = S_theta * dtheta/du`.
#[test]
fn revolution_matches_opencascade() {
    let d = data();
    for case in d["revolutions"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let profile = curve(&case["profile"]);
        let (origin, axis) = (
            vec3(&case["axis_point"]),
            vec3(&case["axis_dir"]).normalize(),
        );
        let angle = case["angle_rad"].as_f64().unwrap();
        let s = revolve(&profile, origin, axis, angle).expect("revolution succeeds");
        for x in case["samples"].as_array().unwrap() {
            let (theta, v) = (x["u"].as_f64().unwrap(), x["v"].as_f64().unwrap());
            let u = u_at_angle(&s, origin, axis, theta, v, angle);
            let dd = s.derivatives::<2>(u, v);
            let at = format!("{name} (theta {theta}, v {v})");
            assert_close(&format!("S {at}"), dd[0][0], vec3(&x["p"]));
            assert_close(&format!("S_v {at}"), dd[0][1], vec3(&x["dv"]));
            // S_u must be parallel to OpenCascade's S_theta with a positive factor.
            let s_theta = vec3(&x["du"]);
            if s_theta.length() > 1e-12 {
                let factor = dd[1][0].dot(s_theta) / s_theta.length_squared();
                assert!(factor > 0.0, "{at}: u runs with the angle");
                assert_close(&format!("S_u direction {at}"), dd[1][0], s_theta * factor);
            }
        }
    }
}

/// The parameter u of our revolution whose rotation angle is `theta`, measured on the
/// profile point at `v` (or any off-axis point of that iso-curve).
fn u_at_angle(s: &NurbsSurface, origin: DVec3, axis: DVec3, theta: f64, v: f64, total: f64) -> f64 {
    if theta <= 0.0 {
        return 0.0;
    }
    if theta >= total {
        return 1.0;
    }
    let radial = |p: DVec3| {
        let r = p - origin;
        r - axis * r.dot(axis)
    };
    // Measure on the iso-curve at v unless that point lies on the axis.
    let v_probe = if radial(s.point_at(0.0, v)).length() > 1e-9 {
        v
    } else {
        0.5
    };
    let x0 = radial(s.point_at(0.0, v_probe));
    let angle_of = |u: f64| {
        let r = radial(s.point_at(u, v_probe));
        let a = x0.cross(r).dot(axis).atan2(x0.dot(r));
        if a < -1e-12 {
            a + TAU
        } else {
            a
        }
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if angle_of(mid) < theta {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
