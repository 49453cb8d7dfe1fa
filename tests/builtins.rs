//! Builtins called directly through a hand-built `Call`, without the evaluator.

#![allow(clippy::result_large_err)] // Diagnostic is large by design, as in the library

use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

use dieface::diag::Diagnostic;
use dieface::eval::budget::Budget;
use dieface::eval::builtins::{lookup, Call};
use dieface::eval::units::Units;
use dieface::eval::value::{Data, Dim, Quantity, Value};
use dieface::geom::{Curve3, NurbsSurface};
use dieface::syntax::{FileId, Span};
use glam::{DVec2, DVec3};

#[path = "common/script.rs"]
mod script;

// ---- building arguments --------------------------------------------------------------

fn at(i: usize) -> Span {
    Span::new(FileId(0), 100 * (i + 1), 100 * (i + 1) + 7)
}

const CALL: Span = Span {
    file: FileId(0),
    start: 0,
    end: 5000,
};

fn mm(v: f64) -> Value {
    Value::new(Data::Number(Quantity::length(v)), CALL)
}
fn deg(v: f64) -> Value {
    Value::new(Data::Number(Quantity::angle(v.to_radians())), CALL)
}
fn bare(v: f64) -> Value {
    Value::new(Data::Number(Quantity::bare(v)), CALL)
}
fn ratio(v: f64) -> Value {
    Value::new(Data::Number(Quantity::ratio(v)), CALL)
}
fn text(s: &str) -> Value {
    Value::new(Data::Str(s.into()), CALL)
}
fn p2(x: f64, y: f64) -> Value {
    Value::point2(DVec2::new(x, y), CALL)
}
fn p3(x: f64, y: f64, z: f64) -> Value {
    Value::point3(DVec3::new(x, y, z), CALL)
}
fn list(items: Vec<Value>) -> Value {
    Value::new(Data::List(Arc::new(items)), CALL)
}
fn tuple(items: Vec<Value>) -> Value {
    Value::new(Data::Tuple(Arc::new(items)), CALL)
}
fn data(d: Data) -> Value {
    Value::new(d, CALL)
}

fn no_apply(_: &Value, _: Vec<Value>, _: Span) -> Result<Value, Diagnostic> {
    unreachable!("no callbacks in this test")
}

/// Calls builtin `name` with arguments by parameter index (`None` = omitted); each
/// given argument gets its own span `at(i)`.
fn call_with(
    name: &str,
    args: Vec<Option<Value>>,
    dir: Option<&Path>,
    root: Option<&Path>,
) -> Result<Data, Diagnostic> {
    let builtin = lookup(name).unwrap_or_else(|| panic!("no builtin {name}"));
    let args = args
        .into_iter()
        .enumerate()
        .map(|(i, a)| a.map(|v| Value::new(v.data, at(i))))
        .collect();
    let call = Call {
        builtin,
        span: CALL,
        budget: &Budget::default(),
        decl: Some("x"),
        units: Units::default(),
        args,
        dir,
        root,
        apply: &no_apply,
    };
    (builtin.run)(&call)
}

fn call(name: &str, args: Vec<Value>) -> Result<Data, Diagnostic> {
    let n = lookup(name).unwrap().params.len();
    let mut a: Vec<Option<Value>> = args.into_iter().map(Some).collect();
    a.resize(n, None);
    call_with(name, a, None, None)
}

fn number(d: &Data) -> Quantity {
    match d {
        Data::Number(q) => *q,
        other => panic!("not a number: {other:?}"),
    }
}

fn vec3(d: &Data) -> DVec3 {
    match d {
        Data::Tuple(t) if t.len() == 3 => DVec3::new(
            number(&t[0].data).value,
            number(&t[1].data).value,
            number(&t[2].data).value,
        ),
        other => panic!("not a 3-D point: {other:?}"),
    }
}

fn curve3(d: Data) -> Arc<Curve3> {
    match d {
        Data::Curve3(c) => c,
        other => panic!("not a 3-D curve: {other:?}"),
    }
}

fn surface(d: Data) -> Arc<NurbsSurface> {
    match d {
        Data::Surface(s) => s,
        other => panic!("not a surface: {other:?}"),
    }
}

// ---- math -----------------------------------------------------------------------------

#[test]
fn every_builtin_is_listed_with_a_doc() {
    let names: Vec<&str> = dieface::eval::builtins::names().collect();
    for n in [
        "sqrt",
        "range",
        "nurbs_curve",
        "interpolate",
        "loft",
        "revolve",
        "tip",
        "read_obj",
        "bounds",
        "join",
    ] {
        assert!(names.contains(&n), "{n} missing");
        assert!(!lookup(n).unwrap().doc.is_empty());
    }
    let mut sorted = names.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), names.len(), "duplicate builtin names");
}

#[test]
fn every_builtin_name_can_be_called_in_a_script() {
    // Sketch words (`line`, `arc`, ...) are keywords: a builtin must not be named after one.
    for name in dieface::eval::builtins::names() {
        let src = format!("let v = {name}(1)\n");
        assert!(
            dieface::syntax::parse(&src, FileId(0)).is_ok(),
            "`{name}(...)` does not parse"
        );
    }
}

#[test]
fn math_keeps_dimensions() {
    let area = Value::new(
        Data::Number(Quantity {
            value: 16.0,
            dim: Dim {
                length: 2,
                angle: 0,
            },
            bare: false,
        }),
        CALL,
    );
    let r = number(&call("sqrt", vec![area]).unwrap());
    assert_eq!(r, Quantity::length(4.0));
    let r = number(&call("sqrt", vec![bare(9.0)]).unwrap());
    assert_eq!(r, Quantity::bare(3.0));
    let e = call("sqrt", vec![mm(4.0)]).unwrap_err();
    assert_eq!(e.code, "die::unit_mismatch");
    let e = call("sqrt", vec![bare(-1.0)]).unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    let e = call("sqrt", vec![text("a")]).unwrap_err();
    assert_eq!(e.code, "die::type_mismatch");
    assert_eq!(e.primary.span, at(0));

    // Bare numbers take the default unit next to a length; degrees for angles.
    assert_eq!(
        number(&call("min", vec![mm(5.0), bare(3.0)]).unwrap()),
        Quantity::length(3.0)
    );
    assert_eq!(
        number(&call("max", vec![bare(2.0), bare(3.0)]).unwrap()),
        Quantity::bare(3.0)
    );
    let e = call("min", vec![mm(5.0), deg(3.0)]).unwrap_err();
    assert_eq!(e.code, "die::unit_mismatch");
    assert!((number(&call("sin", vec![bare(30.0)]).unwrap()).value - 0.5).abs() < 1e-15);
    assert!((number(&call("cos", vec![deg(60.0)]).unwrap()).value - 0.5).abs() < 1e-15);
    let a = number(&call("atan2", vec![mm(1.0), mm(1.0)]).unwrap());
    assert_eq!(a.dim, Dim::ANGLE);
    assert!((a.value - PI / 4.0).abs() < 1e-15);
    assert_eq!(
        number(&call("abs", vec![mm(-2.0)]).unwrap()),
        Quantity::length(2.0)
    );
}

#[test]
fn lists() {
    let Data::List(r) = call("range", vec![bare(3.0)]).unwrap() else {
        panic!()
    };
    let v: Vec<f64> = r.iter().map(|x| number(&x.data).value).collect();
    assert_eq!(v, [0.0, 1.0, 2.0]);
    let Data::List(r) = call("range", vec![bare(2.0), bare(5.0)]).unwrap() else {
        panic!()
    };
    assert_eq!(r.len(), 3);
    // Over the `samples` limit (1,000,000 by default): refused before it is made.
    let e = call("range", vec![bare(2e6)]).unwrap_err();
    assert_eq!(e.code, "die::limit::samples");
    assert_eq!(e.primary.span, at(0));

    let Data::List(r) = call("linspace", vec![mm(0.0), mm(10.0), bare(5.0)]).unwrap() else {
        panic!()
    };
    let v: Vec<Quantity> = r.iter().map(|x| number(&x.data)).collect();
    assert_eq!(v[1], Quantity::length(2.5));
    assert_eq!(v[4], Quantity::length(10.0));
    assert_eq!(
        number(&call("sum", vec![list(vec![mm(1.0), bare(2.0), mm(3.0)])]).unwrap()),
        Quantity::length(6.0)
    );
    assert_eq!(
        number(&call("sum", vec![list(vec![])]).unwrap()),
        Quantity::bare(0.0)
    );
    assert_eq!(
        number(&call("len", vec![list(vec![mm(1.0), mm(2.0)])]).unwrap()),
        Quantity::bare(2.0)
    );

    // map and filter call back through `apply`.
    let double = |_: &Value, args: Vec<Value>, span: Span| -> Result<Value, Diagnostic> {
        let q = number(&args[0].data);
        Ok(Value::new(
            Data::Number(Quantity {
                value: 2.0 * q.value,
                ..q
            }),
            span,
        ))
    };
    let positive = |_: &Value, args: Vec<Value>, span: Span| -> Result<Value, Diagnostic> {
        Ok(Value::new(
            Data::Bool(number(&args[0].data).value > 0.0),
            span,
        ))
    };
    let f = data(Data::Builtin(lookup("abs").unwrap()));
    let items = list(vec![mm(1.0), mm(-2.0), mm(3.0)]);
    for (name, apply, expected) in [
        (
            "map",
            &double as &dyn Fn(&Value, Vec<Value>, Span) -> Result<Value, Diagnostic>,
            vec![2.0, -4.0, 6.0],
        ),
        ("filter", &positive, vec![1.0, 3.0]),
    ] {
        let builtin = lookup(name).unwrap();
        let c = Call {
            builtin,
            span: CALL,
            budget: &Budget::default(),
            decl: Some("x"),
            units: Units::default(),
            args: vec![Some(items.clone()), Some(f.clone())],
            dir: None,
            root: None,
            apply,
        };
        let Data::List(out) = (builtin.run)(&c).unwrap() else {
            panic!()
        };
        let v: Vec<f64> = out.iter().map(|x| number(&x.data).value).collect();
        assert_eq!(v, expected, "{name}");
    }
}

#[test]
fn vectors() {
    let d = number(&call("dot", vec![p3(1.0, 2.0, 3.0), p3(4.0, 5.0, 6.0)]).unwrap());
    assert_eq!(
        d,
        Quantity {
            value: 32.0,
            dim: Dim {
                length: 2,
                angle: 0
            },
            bare: false
        }
    );
    let n = call("normalize", vec![p3(3.0, 0.0, 4.0)]).unwrap();
    assert!((vec3(&n) - DVec3::new(0.6, 0.0, 0.8)).length() < 1e-15);
    assert_eq!(
        number(&call("distance", vec![p2(0.0, 0.0), p2(3.0, 4.0)]).unwrap()),
        Quantity::length(5.0)
    );
    let m = call(
        "lerp",
        vec![p3(0.0, 0.0, 0.0), p3(10.0, 20.0, 30.0), ratio(0.25)],
    )
    .unwrap();
    assert_eq!(vec3(&m), DVec3::new(2.5, 5.0, 7.5));
    let c = call("cross", vec![p3(1.0, 0.0, 0.0), p3(0.0, 1.0, 0.0)]).unwrap();
    assert_eq!(vec3(&c), DVec3::new(0.0, 0.0, 1.0));
    assert_eq!(
        vec3(&call("point", vec![bare(1.0), mm(2.0), bare(3.0)]).unwrap()),
        DVec3::new(1.0, 2.0, 3.0)
    );
}

// ---- curves ---------------------------------------------------------------------------

#[test]
fn nurbs_curve_from_points() {
    let pts = list(vec![
        p3(0.0, 0.0, 0.0),
        p3(10.0, 10.0, 0.0),
        p3(20.0, 0.0, 0.0),
        p3(30.0, 10.0, 5.0),
    ]);
    let c = curve3(call("nurbs_curve", vec![bare(2.0), pts.clone()]).unwrap());
    assert_eq!(c.degree(), 2);
    assert_eq!(c.knots().as_slice(), &[0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0]);
    assert_eq!(c.end_point(), DVec3::new(30.0, 10.0, 5.0));

    let knots = list(
        [0.0, 0.0, 0.0, 0.25, 1.0, 1.0, 1.0]
            .iter()
            .map(|&k| bare(k))
            .collect(),
    );
    let weights = list([1.0, 2.0, 1.0, 1.0].iter().map(|&w| bare(w)).collect());
    let c = curve3(call("nurbs_curve", vec![bare(2.0), pts.clone(), knots, weights]).unwrap());
    assert!(c.is_rational());
    assert_eq!(c.knots().as_slice()[3], 0.25);

    // 2-D points make a 2-D curve.
    let c = call(
        "nurbs_curve",
        vec![bare(1.0), list(vec![p2(0.0, 0.0), p2(1.0, 1.0)])],
    )
    .unwrap();
    assert!(matches!(c, Data::Curve2(_)));

    // A kernel failure names the declaration and the argument, at the argument.
    let bad = list(
        [0.0, 0.0, 0.5, 0.2, 1.0, 1.0, 1.0]
            .iter()
            .map(|&k| bare(k))
            .collect(),
    );
    let e = call("nurbs_curve", vec![bare(2.0), pts.clone(), bad]).unwrap_err();
    assert_eq!(e.code, "die::geometry");
    assert!(
        e.message.contains("(in `x`, argument `knots`)"),
        "{}",
        e.message
    );
    assert_eq!(e.primary.span, at(2));
    let e = call("nurbs_curve", vec![bare(5.0), pts.clone()]).unwrap_err();
    assert!(e.message.contains("argument `points`"), "{}", e.message);
    let e = call(
        "nurbs_curve",
        vec![bare(2.0), pts, Value::new(Data::Bool(true), CALL)],
    )
    .unwrap_err();
    assert_eq!(e.code, "die::type_mismatch");
    let e = call(
        "nurbs_curve",
        vec![bare(2.0), list(vec![p3(0.0, 0.0, 0.0), mm(1.0)])],
    )
    .unwrap_err();
    assert_eq!(e.code, "die::type_mismatch");
}

#[test]
fn interpolate_through_points() {
    let pts = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(10.0, 5.0, 1.0),
        DVec3::new(25.0, 3.0, 2.0),
        DVec3::new(40.0, 10.0, 0.0),
    ];
    let list_pts = list(pts.iter().map(|p| Value::point3(*p, CALL)).collect());
    let c = curve3(call("interpolate", vec![list_pts.clone()]).unwrap());
    assert_eq!(c.degree(), 3);
    for p in pts {
        let d = (0..=4000)
            .map(|k| c.point_at(k as f64 / 4000.0).distance(p))
            .fold(f64::INFINITY, f64::min);
        assert!(d < 0.02, "misses {p}");
    }
    // With a start tangent and degree 2, centripetal.
    let c = curve3(
        call_with(
            "interpolate",
            vec![
                Some(list_pts.clone()),
                Some(bare(2.0)),
                Some(p3(0.0, 50.0, 0.0)),
                None,
                Some(text("centripetal")),
            ],
            None,
            None,
        )
        .unwrap(),
    );
    assert_eq!(c.degree(), 2);
    assert!((c.derivative_at(0.0) - DVec3::new(0.0, 50.0, 0.0)).length() < 1e-9);

    let e = call_with(
        "interpolate",
        vec![Some(list_pts), None, None, None, Some(text("arc"))],
        None,
        None,
    )
    .unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    assert_eq!(e.primary.span, at(4));
    let dup = list(vec![
        p3(0.0, 0.0, 0.0),
        p3(1.0, 0.0, 0.0),
        p3(1.0, 0.0, 0.0),
        p3(2.0, 1.0, 0.0),
    ]);
    let e = call("interpolate", vec![dup]).unwrap_err();
    assert_eq!(e.code, "die::geometry");
    assert!(
        e.message.contains("(in `x`, argument `points`)"),
        "{}",
        e.message
    );
    assert!(e.help.unwrap().contains("points 1 and 2"));
}

#[test]
fn arcs_lines_split_join() {
    let a = curve3(
        call(
            "arc_through",
            vec![p3(10.0, 0.0, 0.0), p3(0.0, 10.0, 0.0), p3(-10.0, 0.0, 0.0)],
        )
        .unwrap(),
    );
    for k in 0..=20 {
        assert!((a.point_at(k as f64 / 20.0).length() - 10.0).abs() < 1e-12);
    }
    let e = call(
        "arc_through",
        vec![p3(0.0, 0.0, 0.0), p3(1.0, 0.0, 0.0), p3(2.0, 0.0, 0.0)],
    )
    .unwrap_err();
    assert_eq!(e.code, "die::geometry");
    assert!(e.message.contains("argument `b`"));

    let c = curve3(
        call(
            "arc3",
            vec![
                p3(0.0, 0.0, 5.0),
                text("x"),
                text("z"),
                mm(3.0),
                deg(0.0),
                deg(90.0),
            ],
        )
        .unwrap(),
    );
    assert!((c.end_point() - DVec3::new(0.0, 0.0, 8.0)).length() < 1e-12);
    let Data::Curve2(circle) = call("circle", vec![p2(1.0, 1.0), mm(2.0)]).unwrap() else {
        panic!()
    };
    assert!((circle.length() - 4.0 * PI).abs() < 1e-9);
    let circle3 = curve3(
        call(
            "circle",
            vec![p3(0.0, 0.0, 0.0), mm(2.0), p3(1.0, 0.0, 0.0)],
        )
        .unwrap(),
    );
    assert!(circle3.control_points().iter().all(|p| p.x.abs() < 1e-15));

    let line = call("line_between", vec![p3(0.0, 0.0, 0.0), p3(10.0, 0.0, 0.0)]).unwrap();
    let arc = call(
        "arc_through",
        vec![p3(10.0, 0.0, 0.0), p3(15.0, 5.0, 0.0), p3(10.0, 10.0, 0.0)],
    )
    .unwrap();
    let joined = curve3(call("join", vec![list(vec![data(line.clone()), data(arc)])]).unwrap());
    assert_eq!(joined.domain(), (0.0, 2.0));
    assert!((joined.point_at(0.5) - DVec3::new(5.0, 0.0, 0.0)).length() < 1e-12);
    let gap = call("line_between", vec![p3(11.0, 0.0, 0.0), p3(20.0, 0.0, 0.0)]).unwrap();
    let e = call("join", vec![list(vec![data(line.clone()), data(gap)])]).unwrap_err();
    assert_eq!(e.code, "die::geometry");
    assert!(e.message.contains("argument `curves`"));

    let Data::List(parts) = call("split", vec![data(line.clone()), ratio(0.25)]).unwrap() else {
        panic!()
    };
    let first = curve3(parts[0].data.clone());
    assert!((first.end_point() - DVec3::new(2.5, 0.0, 0.0)).length() < 1e-12);
    let e = call("split", vec![data(line.clone()), bare(25.0)]).unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    let r = curve3(call("reverse", vec![data(line)]).unwrap());
    assert_eq!(r.start_point(), DVec3::new(10.0, 0.0, 0.0));
}

// ---- surfaces -------------------------------------------------------------------------

fn section(y: f64, sag: f64) -> Value {
    let pts = list(vec![p3(0.0, y, 0.0), p3(50.0, y, -sag), p3(100.0, y, 0.0)]);
    data(
        call_with(
            "interpolate",
            vec![Some(pts), Some(bare(2.0)), None, None, None],
            None,
            None,
        )
        .unwrap(),
    )
}

#[test]
fn loft_through_sections() {
    let sections = vec![section(0.0, 10.0), section(60.0, 14.0), section(120.0, 9.0)];
    let s = surface(call("loft", vec![list(sections.clone())]).unwrap());
    // The sections are iso-curves: first at v = 0, last at v = 1.
    let first = curve3(sections[0].data.clone());
    let last = curve3(sections[2].data.clone());
    for k in 0..=10 {
        let u = k as f64 / 10.0;
        assert!((s.point_at(u, 0.0) - first.point_at(u)).length() < 1e-9);
        assert!((s.point_at(u, 1.0) - last.point_at(u)).length() < 1e-9);
    }
    let mid = vec3(
        &call(
            "point_on",
            vec![data(Data::Surface(s.clone())), ratio(0.5), ratio(0.0)],
        )
        .unwrap(),
    );
    assert!((mid - first.point_at(0.5)).length() < 1e-9);
    let e = call("loft", vec![list(vec![sections[0].clone()])]).unwrap_err();
    assert_eq!(e.code, "die::geometry");
    assert!(
        e.message.contains("(in `x`, argument `sections`)"),
        "{}",
        e.message
    );
}

#[test]
fn revolve_makes_a_cylinder() {
    let profile = call(
        "line_between",
        vec![p3(10.0, 0.0, 0.0), p3(10.0, 0.0, 20.0)],
    )
    .unwrap();
    let s = surface(
        call(
            "revolve",
            vec![data(profile.clone()), p3(0.0, 0.0, 0.0), text("z")],
        )
        .unwrap(),
    );
    for i in 0..=8 {
        for j in 0..=4 {
            let p = s.point_at(i as f64 / 8.0, j as f64 / 4.0);
            assert!((p.truncate().length() - 10.0).abs() < 1e-12);
        }
    }
    let quarter = surface(
        call(
            "revolve",
            vec![
                data(profile.clone()),
                p3(0.0, 0.0, 0.0),
                p3(0.0, 0.0, 1.0),
                deg(90.0),
            ],
        )
        .unwrap(),
    );
    let end = quarter.point_at(1.0, 0.0);
    assert!((end - DVec3::new(0.0, 10.0, 0.0)).length() < 1e-12, "{end}");
    let n = vec3(
        &call(
            "normal_at",
            vec![data(Data::Surface(quarter)), ratio(0.0), ratio(0.5)],
        )
        .unwrap(),
    );
    assert!((n.length() - 1.0).abs() < 1e-12 && n.z.abs() < 1e-12);
    let e = call(
        "revolve",
        vec![data(profile.clone()), p3(0.0, 0.0, 0.0), p3(0.0, 0.0, 0.0)],
    )
    .unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    assert_eq!(e.primary.span, at(2));
    let e = call(
        "revolve",
        vec![data(profile), p3(0.0, 0.0, 0.0), text("z"), deg(400.0)],
    )
    .unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
}

#[test]
fn other_surfaces() {
    let a = call("line_between", vec![p3(0.0, 0.0, 0.0), p3(10.0, 0.0, 0.0)]).unwrap();
    let b = call(
        "line_between",
        vec![p3(0.0, 10.0, 2.0), p3(10.0, 10.0, 2.0)],
    )
    .unwrap();
    let s = surface(call("ruled", vec![data(a.clone()), data(b.clone())]).unwrap());
    assert!((s.point_at(0.5, 0.5) - DVec3::new(5.0, 5.0, 1.0)).length() < 1e-12);
    let l = call("line_between", vec![p3(0.0, 0.0, 0.0), p3(0.0, 10.0, 2.0)]).unwrap();
    let r = call(
        "line_between",
        vec![p3(10.0, 0.0, 0.0), p3(10.0, 10.0, 2.0)],
    )
    .unwrap();
    let c = surface(call("coons", vec![data(a), data(b), data(l), data(r)]).unwrap());
    assert!((c.point_at(0.5, 0.5) - DVec3::new(5.0, 5.0, 1.0)).length() < 1e-12);

    let net = list(vec![
        list(vec![p3(0.0, 0.0, 0.0), p3(0.0, 10.0, 0.0)]),
        list(vec![p3(10.0, 0.0, 0.0), p3(10.0, 10.0, 5.0)]),
    ]);
    let s = surface(call("nurbs_surface", vec![bare(1.0), net.clone()]).unwrap());
    assert!((s.point_at(1.0, 1.0) - DVec3::new(10.0, 10.0, 5.0)).length() < 1e-12);
    let s = surface(
        call(
            "nurbs_surface",
            vec![tuple(vec![bare(1.0), bare(1.0)]), net.clone()],
        )
        .unwrap(),
    );
    assert_eq!((s.degree_u(), s.degree_v()), (1, 1));
    let e = call("nurbs_surface", vec![bare(3.0), net]).unwrap_err();
    assert_eq!(e.code, "die::geometry");
    assert!(e.message.contains("argument `points`"), "{}", e.message);
}

// ---- transforms -----------------------------------------------------------------------

#[test]
fn tip_a_product() {
    // Tipping 90 deg about x turns +y into +z.
    let p = vec3(&call("tip", vec![p3(0.0, 10.0, 0.0), text("x"), deg(90.0)]).unwrap());
    assert!((p - DVec3::new(0.0, 0.0, 10.0)).length() < 1e-12);
    // About y through a centre; a bare angle is in degrees.
    let p = vec3(
        &call(
            "tip",
            vec![
                p3(20.0, 0.0, 0.0),
                text("y"),
                bare(90.0),
                p3(10.0, 0.0, 0.0),
            ],
        )
        .unwrap(),
    );
    assert!((p - DVec3::new(10.0, 0.0, -10.0)).length() < 1e-12, "{p}");
    // Curves and lists of geometry.
    let line = call("line_between", vec![p3(0.0, 0.0, 0.0), p3(0.0, 10.0, 0.0)]).unwrap();
    let Data::List(out) = call(
        "tip",
        vec![
            list(vec![data(line), p3(0.0, 5.0, 0.0)]),
            text("x"),
            deg(5.0),
        ],
    )
    .unwrap() else {
        panic!()
    };
    let c = curve3(out[0].data.clone());
    let a = 5f64.to_radians();
    assert!((c.end_point() - DVec3::new(0.0, 10.0 * a.cos(), 10.0 * a.sin())).length() < 1e-12);
    let e = call("tip", vec![p3(0.0, 10.0, 0.0), text("z"), deg(5.0)]).unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    assert_eq!(e.primary.span, at(1));
    let e = call("tip", vec![p3(0.0, 10.0, 0.0), text("w"), deg(5.0)]).unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    let e = call("tip", vec![mm(1.0), text("x"), deg(5.0)]).unwrap_err();
    assert_eq!(e.code, "die::type_mismatch");
}

#[test]
fn transforms_and_transform_values() {
    let p = vec3(&call("translate", vec![p3(1.0, 2.0, 3.0), p3(10.0, 0.0, 0.0)]).unwrap());
    assert_eq!(p, DVec3::new(11.0, 2.0, 3.0));
    let p = vec3(&call("rotate", vec![p2(10.0, 0.0), text("z"), deg(90.0)]).unwrap());
    assert!((p - DVec3::new(0.0, 10.0, 0.0)).length() < 1e-12);
    let p = vec3(
        &call(
            "scale",
            vec![p3(2.0, 0.0, 0.0), bare(3.0), p3(1.0, 0.0, 0.0)],
        )
        .unwrap(),
    );
    assert!((p - DVec3::new(4.0, 0.0, 0.0)).length() < 1e-12);
    let t = call("rotation", vec![text("x"), deg(90.0)]).unwrap();
    assert!(matches!(t, Data::Transform(_)));
    let p = vec3(&call("transform_by", vec![p3(0.0, 1.0, 0.0), data(t)]).unwrap());
    assert!((p - DVec3::Z).length() < 1e-12);
    let e = call("transform_by", vec![p3(0.0, 1.0, 0.0), mm(1.0)]).unwrap_err();
    assert_eq!(e.code, "die::type_mismatch");
    assert_eq!(e.primary.span, at(1));
}

// ---- files ----------------------------------------------------------------------------

const OBJ: &str = "\
# a quad and a triangle in two groups
v 0 0 0
v 10 0 0
v 10 10 0
v 0 10 0
v 20 0 1
vn 0 0 1
vn 0 0 1
vn 0 0 1
vn 0 0 1
vn 0 0 1
g panel
f 1//1 2//2 3//3 4//4
g flange
f 2//2 5//5 3//3
";

fn project() -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("builtins_read_obj");
    std::fs::create_dir_all(root.join("parts")).unwrap();
    std::fs::write(root.join("parts/fender.obj"), OBJ).unwrap();
    std::fs::write(
        Path::new(env!("CARGO_TARGET_TMPDIR")).join("outside.obj"),
        OBJ,
    )
    .unwrap();
    root
}

#[test]
fn read_obj_keeps_quads_and_groups() {
    let root = project();
    let d = call_with(
        "read_obj",
        vec![Some(text("parts/fender.obj"))],
        Some(&root),
        Some(&root),
    )
    .unwrap();
    let Data::Mesh(m) = &d else {
        panic!("not a mesh")
    };
    assert_eq!(m.triangle_and_quad_counts(), (1, 1));
    assert_eq!(m.group("panel").unwrap().faces().len(), 1);
    assert_eq!(m.group("flange").unwrap().faces().len(), 1);
    let (lo, hi) = m.bounding_box().unwrap();
    assert_eq!((lo, hi), (DVec3::ZERO, DVec3::new(20.0, 10.0, 1.0)));
    assert!(m.normals().is_some());

    // bounds of the mesh
    let Data::Record(r) = call("bounds", vec![data(d.clone())]).unwrap() else {
        panic!()
    };
    assert_eq!(
        vec3(&r.get("max").unwrap().data),
        DVec3::new(20.0, 10.0, 1.0)
    );

    // Tipping the mesh moves vertices and turns normals.
    let Data::Mesh(t) = call("tip", vec![data(d), text("x"), deg(90.0)]).unwrap() else {
        panic!()
    };
    let n = t.normals().unwrap()[0];
    assert!((n - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-12, "{n}");
    assert!((t.positions()[2] - DVec3::new(10.0, 0.0, 10.0)).length() < 1e-12);
    assert_eq!(t.groups().len(), 2);

    // Relative to the script's directory.
    let parts = root.join("parts");
    assert!(call_with(
        "read_obj",
        vec![Some(text("fender.obj"))],
        Some(&parts),
        Some(&root)
    )
    .is_ok());
}

/// Positions are read in f64: a die's coordinates run to metres with micrometre
/// detail, which single precision loses (1000.123456789 read as 1000.123474).
#[test]
fn read_obj_keeps_positions_in_double_precision() {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("builtins_read_obj_f64");
    std::fs::create_dir_all(&root).unwrap();
    std::fs::write(
        root.join("far.obj"),
        "v 1000.123456789 -1500.987654321 250.000000001\nv 1001 0 0\nv 1000 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let d = call_with(
        "read_obj",
        vec![Some(text("far.obj"))],
        Some(&root),
        Some(&root),
    )
    .unwrap();
    let Data::Mesh(m) = &d else {
        panic!("not a mesh")
    };
    let p = m.positions()[0];
    let expected = DVec3::new(1000.123456789, -1500.987654321, 250.000000001);
    assert!((p - expected).abs().max_element() < 1e-12, "{p}");
}

#[test]
fn read_obj_errors() {
    let root = project();
    let e = call_with(
        "read_obj",
        vec![Some(text("parts/missing.obj"))],
        Some(&root),
        Some(&root),
    )
    .unwrap_err();
    assert_eq!(e.code, "die::file_not_found");
    assert!(e.message.contains("missing.obj"), "{}", e.message);
    assert!(
        e.message.contains("parts/missing.obj") && !e.message.contains("builtins_read_obj"),
        "the path as written, not the machine's absolute path: {}",
        e.message
    );
    assert_eq!(e.primary.span, at(0));

    let e = call_with(
        "read_obj",
        vec![Some(text("../outside.obj"))],
        Some(&root),
        Some(&root),
    )
    .unwrap_err();
    assert_eq!(e.code, "die::path_escapes_root");
    assert!(e.help.is_some());
    let e = call_with(
        "read_obj",
        vec![Some(text("../nothing/there.obj"))],
        Some(&root),
        Some(&root),
    )
    .unwrap_err();
    assert_eq!(e.code, "die::path_escapes_root");
    let e = call_with("read_obj", vec![Some(text("parts/fender.obj"))], None, None).unwrap_err();
    assert_eq!(e.code, "die::file_not_found");
}

#[test]
fn queries() {
    let line = call("line_between", vec![p3(0.0, 0.0, 0.0), p3(10.0, 0.0, 0.0)]).unwrap();
    let m = vec3(&call("point_at", vec![data(line.clone()), ratio(0.5)]).unwrap());
    assert_eq!(m, DVec3::new(5.0, 0.0, 0.0));
    assert_eq!(
        number(&call("length_of", vec![data(line.clone())]).unwrap()),
        Quantity::length(10.0)
    );
    assert_eq!(
        vec3(&call("end_point", vec![data(line.clone())]).unwrap()),
        DVec3::new(10.0, 0.0, 0.0)
    );
    let e = call("point_at", vec![data(line), bare(50.0)]).unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    assert!(e.help.unwrap().contains("%"));

    let circle = call("circle", vec![p3(0.0, 0.0, 0.0), mm(10.0)]).unwrap();
    let Data::Record(r) = call("bounds", vec![data(circle)]).unwrap() else {
        panic!()
    };
    let (lo, hi) = (
        vec3(&r.get("min").unwrap().data),
        vec3(&r.get("max").unwrap().data),
    );
    assert!((lo - DVec3::new(-10.0, -10.0, 0.0)).length() < 1e-2, "{lo}");
    assert!((hi - DVec3::new(10.0, 10.0, 0.0)).length() < 1e-2, "{hi}");
}

// ---- robustness -----------------------------------------------------------------------

#[test]
fn no_builtin_panics_on_odd_arguments() {
    let line = call("line_between", vec![p3(0.0, 0.0, 0.0), p3(10.0, 0.0, 0.0)]).unwrap();
    let line2 = call("line_between", vec![p2(0.0, 0.0), p2(10.0, 0.0)]).unwrap();
    let quad = call(
        "ruled",
        vec![
            data(line.clone()),
            data(call("line_between", vec![p3(0.0, 5.0, 0.0), p3(10.0, 5.0, 1.0)]).unwrap()),
        ],
    )
    .unwrap();
    let samples = vec![
        bare(0.0),
        bare(1.0),
        bare(3.0),
        bare(-2.5),
        bare(1e308),
        bare(-1e308),
        bare(f64::NAN),
        bare(f64::INFINITY),
        mm(0.0),
        mm(5.0),
        mm(-1e300),
        deg(90.0),
        deg(720.0),
        ratio(0.5),
        ratio(2.0),
        text("x"),
        text("z"),
        text(""),
        text("../../etc/passwd"),
        p2(0.0, 0.0),
        p2(1e308, -1e308),
        p3(0.0, 0.0, 0.0),
        p3(1.0, 2.0, 3.0),
        p3(f64::NAN, 0.0, 0.0),
        tuple(vec![bare(3.0), bare(3.0)]),
        tuple(vec![]),
        list(vec![]),
        list(vec![
            p3(0.0, 0.0, 0.0),
            p3(1.0, 0.0, 0.0),
            p3(2.0, 1.0, 0.0),
            p3(3.0, 0.0, 1.0),
        ]),
        list(vec![p2(0.0, 0.0), p2(0.0, 0.0), p2(1.0, 1.0)]),
        list(vec![
            list(vec![p3(0.0, 0.0, 0.0), p3(0.0, 1.0, 0.0)]),
            list(vec![p3(1.0, 0.0, 0.0)]),
        ]),
        list(vec![bare(0.0), bare(0.0), bare(1.0), bare(1.0)]),
        list(vec![data(line.clone()), data(line.clone())]),
        list(vec![data(line.clone()), mm(1.0)]),
        data(line),
        data(line2),
        data(quad),
        Value::new(Data::Bool(true), CALL),
    ];
    let echo =
        |_: &Value, args: Vec<Value>, _: Span| -> Result<Value, Diagnostic> { Ok(args[0].clone()) };
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let root = project();
    for name in dieface::eval::builtins::names() {
        let builtin = lookup(name).unwrap();
        for _ in 0..400 {
            let args = builtin
                .params
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    if !p.required && next(3) == 0 {
                        None
                    } else {
                        Some(Value::new(samples[next(samples.len())].data.clone(), at(i)))
                    }
                })
                .collect();
            let c = Call {
                builtin,
                span: CALL,
                budget: &Budget::default(),
                decl: Some("x"),
                units: Units::default(),
                args,
                dir: Some(&root),
                root: Some(&root),
                apply: &echo,
            };
            let _ = (builtin.run)(&c);
        }
    }
}

// ---- project --------------------------------------------------------------------------

/// A product-like bicubic patch over x in [-600, 600], y in [-420, 420], with a crown
/// and a twist (z from about -75 to 112 mm).
fn crowned_product() -> Arc<NurbsSurface> {
    let height = |i: f64, j: f64| {
        80.0 * (45f64.to_radians() * i).sin()
            + 40.0 * (60f64.to_radians() * j).cos()
            + 0.0002 * (i * 250.0 - 500.0) * (j * 233.0 - 350.0)
    };
    let rows = (0..5)
        .map(|i| {
            list(
                (0..4)
                    .map(|j| {
                        let (i, j) = (i as f64, j as f64);
                        p3(-600.0 + i * 300.0, -420.0 + j * 280.0, height(i, j))
                    })
                    .collect(),
            )
        })
        .collect();
    surface(call("nurbs_surface", vec![bare(3.0), list(rows)]).unwrap())
}

/// A closed top-view rectangle with rounded corners, drawn like std/sketch's
/// `rectangle` (the last fillet after `close`, so the seam is a line-fillet join).
fn rounded_rectangle(center: DVec2, w: f64, h: f64, r: f64) -> Value {
    use dieface::eval::sketch::{build, Command::*, View};
    let (x0, x1, y0, y1) = (
        center.x - w / 2.0,
        center.x + w / 2.0,
        center.y - h / 2.0,
        center.y + h / 2.0,
    );
    let cmds = vec![
        From(DVec2::new(x0, y0)),
        LineTo(DVec2::new(x1, y0)),
        Fillet(r),
        LineTo(DVec2::new(x1, y1)),
        Fillet(r),
        LineTo(DVec2::new(x0, y1)),
        Fillet(r),
        Close,
        Fillet(r),
    ];
    let cmds: Vec<_> = cmds.into_iter().map(|c| (c, CALL)).collect();
    data(Data::Sketch(Arc::new(
        build(View::Top, &cmds, CALL).unwrap(),
    )))
}

/// The distance of `p` from the surface: `closest_point_on_surface`, or, where its
/// Newton cannot settle because `p` lies within rounding of the surface (it then fails
/// with `NoConvergence`, its cosine test being relative to that tiny distance), the
/// vertical distance to the surface, which bounds the true distance from above.
fn distance_to_surface(s: &NurbsSurface, p: DVec3) -> f64 {
    use dieface::geom::inversion::closest_point_on_surface;
    use dieface::geom::GeomError;
    match closest_point_on_surface(s, p) {
        Ok(sp) => sp.distance,
        Err(GeomError::NoConvergence { .. }) => {
            dieface::geom::intersect::intersect_ray_surface(p, DVec3::Z, s)
                .unwrap()
                .w
                .abs()
        }
        Err(e) => panic!("{e}"),
    }
}

/// The largest distance of the projected curve from the surface and of its top view
/// from the input's top view, at `n` evenly spaced parameters.
fn projection_errors(
    c: &Curve3,
    s: &NurbsSurface,
    top: &dieface::geom::Curve2,
    n: usize,
) -> (f64, f64) {
    use dieface::geom::inversion::closest_point_on_curve;
    let (t0, t1) = c.domain();
    let (mut on_surface, mut in_top) = (0.0f64, 0.0f64);
    for k in 0..=n {
        let p = c.point_at(t0 + (t1 - t0) * k as f64 / n as f64);
        on_surface = on_surface.max(distance_to_surface(s, p));
        in_top = in_top.max(closest_point_on_curve(top, p.truncate()).unwrap().distance);
    }
    (on_surface, in_top)
}

/// Simple interior knots: the projected curve is C2 between its ends.
fn interior_knots_are_simple(c: &Curve3) -> bool {
    let (t0, t1) = c.domain();
    c.knots()
        .distinct()
        .iter()
        .all(|&(k, m)| k == t0 || k == t1 || m == 1)
}

#[test]
fn project_a_closed_top_view_trim_line_onto_the_product() {
    let product = crowned_product();
    let trim = rounded_rectangle(DVec2::new(20.0, -10.0), 900.0, 560.0, 60.0);
    let Data::Sketch(sketch) = &trim.data else {
        unreachable!()
    };
    let top = sketch.curve.clone();
    let c = curve3(
        call(
            "project",
            vec![trim.clone(), data(Data::Surface(product.clone()))],
        )
        .unwrap(),
    );
    assert_eq!(c.degree(), 3);
    assert!(!c.is_rational());
    assert!(interior_knots_are_simple(&c), "repeated interior knots");
    let (on_surface, in_top) = projection_errors(&c, &product, &top, 1000);
    assert!(on_surface < 1e-3, "{on_surface} mm off the surface");
    assert!(in_top < 1e-2, "{in_top} mm off the top view");
    // Closed, and C1 across the seam: equal end derivatives.
    let (t0, t1) = c.domain();
    assert!(c.start_point().distance(c.end_point()) < 1e-12);
    let (d0, d1) = (c.derivative_at(t0), c.derivative_at(t1));
    assert!(
        (d0 - d1).length() <= 1e-9 * d0.length(),
        "seam derivatives {d0} and {d1}"
    );
    // The seam lies over the sketch's start, on the surface.
    let start = sketch.curve.start_point();
    assert!(c.start_point().truncate().distance(start) < 1e-9);
    println!(
        "closed trim line: {} control points, {on_surface:.2e} mm off the surface, {in_top:.2e} mm off the top view",
        c.control_points().len()
    );
}

#[test]
fn project_an_open_curve_and_along_a_slanted_direction() {
    let product = crowned_product();
    // A 2-D spline (z = 0), open.
    let spline = call(
        "interpolate",
        vec![list(vec![
            p2(-500.0, -300.0),
            p2(-200.0, -100.0),
            p2(100.0, 50.0),
            p2(450.0, 300.0),
        ])],
    )
    .unwrap();
    let Data::Curve2(top) = &spline else {
        panic!("not a 2-D curve: {spline:?}")
    };
    let top = (**top).clone();
    let c = curve3(
        call(
            "project",
            vec![data(spline.clone()), data(Data::Surface(product.clone()))],
        )
        .unwrap(),
    );
    assert!(interior_knots_are_simple(&c));
    let (on_surface, in_top) = projection_errors(&c, &product, &top, 1000);
    assert!(on_surface < 1e-3, "{on_surface}");
    assert!(in_top < 1e-2, "{in_top}");
    // The ends lie over the input's ends.
    assert!(c.start_point().truncate().distance(top.start_point()) < 1e-8);
    assert!(c.end_point().truncate().distance(top.end_point()) < 1e-8);
    println!(
        "open spline: {} control points, {on_surface:.2e} mm off the surface, {in_top:.2e} mm off the top view",
        c.control_points().len()
    );

    // A 3-D curve above the product, projected along a slanted direction: every point
    // of the result lies on the surface and on the line through some input point.
    let high = call(
        "line_between",
        vec![p3(-400.0, -200.0, 400.0), p3(300.0, 250.0, 400.0)],
    )
    .unwrap();
    let dir = DVec3::new(0.2, -0.1, -1.0);
    let c = curve3(
        call(
            "project",
            vec![
                data(high),
                data(Data::Surface(product.clone())),
                p3(dir.x, dir.y, dir.z),
            ],
        )
        .unwrap(),
    );
    let u = dir.normalize();
    let (a, b) = (
        DVec3::new(-400.0, -200.0, 400.0),
        DVec3::new(300.0, 250.0, 400.0),
    );
    let plane_normal = (b - a).cross(u).normalize();
    let (t0, t1) = c.domain();
    for k in 0..=200 {
        let p = c.point_at(t0 + (t1 - t0) * k as f64 / 200.0);
        let on = distance_to_surface(&product, p);
        assert!(on < 1e-3, "{on}");
        // In the plane swept by the line along the direction.
        assert!((p - a).dot(plane_normal).abs() < 1e-2);
    }
}

#[test]
fn project_errors() {
    let product = crowned_product();
    let s = data(Data::Surface(product));
    // Wider than the product: the curve leaves it.
    let wide = rounded_rectangle(DVec2::ZERO, 1300.0, 560.0, 60.0);
    let e = call_with(
        "project",
        vec![Some(wide), Some(s.clone()), None],
        None,
        None,
    )
    .unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    assert!(
        e.message.contains("leaves the surface near ("),
        "{}",
        e.message
    );
    assert_eq!(e.primary.span, at(0));
    assert_eq!(e.secondary[0].span, at(1));
    // A zero direction.
    let inside = rounded_rectangle(DVec2::ZERO, 400.0, 300.0, 50.0);
    let e = call(
        "project",
        vec![inside.clone(), s.clone(), p3(0.0, 0.0, 0.0)],
    )
    .unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    assert!(e.message.contains("zero length"), "{}", e.message);
    assert_eq!(e.primary.span, at(2));
    // A corner the smooth result cannot follow.
    let corner = call(
        "nurbs_curve",
        vec![
            bare(1.0),
            list(vec![p2(-100.0, 0.0), p2(0.0, 0.0), p2(0.0, 100.0)]),
        ],
    )
    .unwrap();
    let e = call("project", vec![data(corner), s.clone()]).unwrap_err();
    assert!(e.message.contains("corner at (0, 0)"), "{}", e.message);
    assert!(e.message.contains("90 deg"), "{}", e.message);
    // A surface that is not one.
    let e = call("project", vec![inside, mm(3.0)]).unwrap_err();
    assert_eq!(e.code, "die::type_mismatch");
}

/// The same rounded rectangle, `std/sketch`'s `rectangle` and the four sketches that
/// draw it from each of its corners (counter-clockwise, the start corner rounded after
/// `close`), projected onto a crowned panel: one outline, whatever the start. Sampled on
/// each, the others lie within 1e-6 mm.
#[test]
fn projecting_a_closed_sketch_does_not_depend_on_its_start() {
    use dieface::geom::inversion::closest_point_on_curve;
    let height = |i: f64, j: f64| {
        80.0 * (45f64.to_radians() * i).sin()
            + 40.0 * (60f64.to_radians() * j).cos()
            + 0.0002 * (i * 250.0 - 500.0) * (j * 233.0 - 350.0)
    };
    let rows: Vec<String> = (0..5)
        .map(|i| {
            let row: Vec<String> = (0..4)
                .map(|j| {
                    let (i, j) = (i as f64, j as f64);
                    format!(
                        "({}, {}, {})",
                        -600.0 + i * 300.0,
                        -420.0 + j * 280.0,
                        height(i, j)
                    )
                })
                .collect();
            format!("[{}]", row.join(", "))
        })
        .collect();
    let corners = [
        (-430.0, -290.0),
        (470.0, -290.0),
        (470.0, 270.0),
        (-430.0, 270.0),
    ];
    let mut text = format!(
        "import \"std/sketch\" as sk\nunits mm deg\nlet panel = nurbs_surface(degree: (3, 3), points: [{}])\n\
         let rect = project(sk.rectangle(top, (20, -10), 900 mm, 560 mm, 60 mm), panel)\n",
        rows.join(", ")
    );
    for k in 0..4 {
        let c = |i: usize| corners[(k + i) % 4];
        text += &format!(
            "let from_{k} = project(sketch(top) {{\n from {:?}\n line to {:?}\n fillet 60\n line to {:?}\n fillet 60\n line to {:?}\n fillet 60\n close\n fillet 60\n}}, panel)\n",
            c(0), c(1), c(2), c(3)
        );
    }
    let outlines: Vec<(String, Curve3)> = evaluate(&text)
        .into_iter()
        .filter_map(|(name, d)| match d {
            Data::Curve3(c) => Some((name, (*c).clone())),
            _ => None,
        })
        .collect();
    assert_eq!(outlines.len(), 5);
    let mut worst = 0.0f64;
    for (a_name, a) in &outlines {
        let (t0, t1) = a.domain();
        for (b_name, b) in &outlines {
            if a_name == b_name {
                continue;
            }
            for k in 0..400 {
                let p = a.point_at(t0 + (t1 - t0) * (k as f64 + 0.5) / 400.0);
                let d = closest_point_on_curve(b, p).unwrap().distance;
                assert!(d <= 1e-6, "{a_name} is {d:e} mm off {b_name} at {p}");
                worst = worst.max(d);
            }
        }
    }
    println!("closed outlines started at each corner agree within {worst:.1e} mm");
}

// ---- checks ---------------------------------------------------------------------------

#[test]
fn fail_and_the_dimension_tests() {
    // `fail` stops with its message and help at the call.
    let e = call(
        "fail",
        vec![text("f: `x` must be positive, but it is -1 mm")],
    )
    .unwrap_err();
    assert_eq!(e.code, "die::bad_argument");
    assert_eq!(e.message, "f: `x` must be positive, but it is -1 mm");
    assert_eq!(e.primary.span, CALL);
    assert!(e.help.is_some());
    let e = call("fail", vec![text("no"), text("give 3 mm")]).unwrap_err();
    assert_eq!(e.help.as_deref(), Some("give 3 mm"));
    assert_eq!(
        call("fail", vec![mm(3.0)]).unwrap_err().code,
        "die::type_mismatch"
    );
    // A bare number can be used as a length or an angle; a ratio as neither.
    let test = |name: &str, v: Value| match call(name, vec![v]).unwrap() {
        Data::Bool(b) => b,
        other => panic!("{name}: {other:?}"),
    };
    assert!(test("is_length", mm(-6.0)));
    assert!(test("is_length", bare(6.0)));
    assert!(!test("is_length", deg(6.0)));
    assert!(!test("is_length", ratio(0.5)));
    assert!(!test("is_length", text("6 mm")));
    assert!(test("is_angle", deg(95.0)));
    assert!(test("is_angle", bare(6.0)));
    assert!(!test("is_angle", mm(6.0)));
    // `str` writes values as messages show them.
    let show = |v: Value| match call("str", vec![v]).unwrap() {
        Data::Str(s) => s.to_string(),
        other => panic!("{other:?}"),
    };
    assert_eq!(show(mm(-6.0)), "-6 mm");
    assert_eq!(show(deg(95.0)), "95 deg");
    assert_eq!(show(bare(6.0)), "6");
    assert_eq!(show(p2(1.0, 2.5)), "(1 mm, 2.5 mm)");
    assert_eq!(show(list(vec![bare(1.0), text("a")])), "[1, a]");
    assert_eq!(show(Value::new(Data::Bool(true), CALL)), "true");
}

/// The values of a script's declarations, by name; panics on any diagnostic.
fn evaluate(text: &str) -> Vec<(String, Data)> {
    script::evaluate_clean("script.die", text)
}

#[test]
fn a_bare_argument_takes_the_unit_of_its_parameters_default() {
    // A user function whose parameters default to lengths, dividing by a length: called
    // with bare numbers, they are millimetres (the calling file's unit).
    let values = evaluate(
        "fn wrap_z(x = 0 mm, y = 0 mm) = -60 mm * (1 - (x / 650 mm) * (x / 650 mm)) + y / 10\n\
         fn tilt(a = 0 deg) = 100 mm * tan(a)\n\
         fn plain(x) = x * 2\n\
         let bare = wrap_z(-600, -395)\n\
         let lengths = wrap_z(-600 mm, -395 mm)\n\
         let angle = tilt(30)\n\
         let kept = plain(3)\n\
         let added = 5 mm + 10\n",
    );
    let q = |name: &str| match &values.iter().find(|(n, _)| n == name).unwrap().1 {
        Data::Number(q) => *q,
        other => panic!("{name}: {other:?}"),
    };
    let expected = -60.0 * (1.0 - (600.0f64 / 650.0).powi(2)) - 39.5;
    assert_eq!(q("bare"), q("lengths"));
    assert_eq!(q("bare").dim, Dim::LENGTH);
    assert!((q("bare").value - expected).abs() < 1e-9);
    assert!((q("angle").value - 100.0 * (PI / 6.0).tan()).abs() < 1e-9);
    // Without a default the number stays bare; next to a length it takes the unit.
    assert_eq!(q("kept"), Quantity::bare(6.0));
    assert_eq!(q("added"), Quantity::length(15.0));
    // In a centimetre file they are centimetres (a module's functions, `tests/beads.rs`,
    // take the unit of the file that calls them).
    let values = evaluate(
        "units cm\n\
         fn wrap_z(x = 0 mm) = -60 mm * (1 - (x / 650 mm) * (x / 650 mm))\n\
         let bare = wrap_z(-60)\n\
         let added = 5 mm + 10\n",
    );
    let q = |name: &str| match &values.iter().find(|(n, _)| n == name).unwrap().1 {
        Data::Number(q) => *q,
        other => panic!("{name}: {other:?}"),
    };
    assert!((q("bare").value - (-60.0 * (1.0 - (600.0f64 / 650.0).powi(2)))).abs() < 1e-9);
    assert_eq!(q("added"), Quantity::length(105.0));
}
