//! Wrong results with exit 0 (issue 14): numbers are finite everywhere, geometry lies
//! within the modelling range, a punch opening or trim outline that crosses itself, a
//! fillet with no corner and an invalid `param tolerance` are diagnosed. Each case runs
//! through the real binary (`check`, `build`, `inspect --json`) and asserts the exit
//! code and where the message points; the arithmetic is also checked as a property.

mod common;

use std::path::{Path, PathBuf};

use dieface::eval::ops::binary;
use dieface::eval::units::Units;
use dieface::eval::value::{Data, Quantity, Value};
use dieface::syntax::ast::BinaryOp;
use dieface::syntax::{FileId, Span};
use proptest::prelude::*;

/// Runs dieface with `args` (the script's path substituted for `{}`), returning the exit
/// code, stdout and stderr.
fn dieface(args: &[&str]) -> (Option<i32>, String, String) {
    common::run_dieface(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

/// Writes `text` as `name` in this test binary's temporary folder.
fn script(name: &str, text: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("finite");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join(name);
    std::fs::write(&file, text).expect("write");
    file
}

/// `dieface check` of the script: exit 1 with `code` at `name:line:column`.
fn check_fails_at(name: &str, text: &str, code: &str, at: &str) -> String {
    let file = script(name, text);
    let path = file.to_str().expect("utf-8 path");
    let (exit, _, stderr) = dieface(&["check", "--color", "never", path]);
    assert_eq!(exit, Some(1), "{name}: {stderr}");
    assert!(stderr.contains(code), "{name}: expected {code}: {stderr}");
    assert!(
        stderr.contains(&format!("{name}:{at}")),
        "{name}: expected to point at {at}: {stderr}"
    );
    assert!(stderr.contains("help:"), "{name}: a help line: {stderr}");
    stderr
}

#[test]
fn an_overflowing_product_is_refused_at_its_operator() {
    let text = "units mm deg\nlet a = 1e308 * 10\nlet b = a - a\n";
    let stderr = check_fails_at("overflow.die", text, "die::non_finite", "2:15");
    assert!(stderr.contains("this is 1e308"), "{stderr}");
    assert!(stderr.contains("this is 10"), "{stderr}");
    // `inspect --json` refuses too, and writes no `null` in place of a number.
    let path = script("overflow.die", text);
    let (exit, stdout, _) = dieface(&["inspect", "--json", path.to_str().unwrap()]);
    assert_eq!(exit, Some(1));
    let json: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    for decl in json["declarations"].as_array().expect("declarations") {
        // A declaration that failed has no value; one that evaluated has no `null`.
        let value = &decl["value"];
        assert!(
            value.is_null() || !value.to_string().contains("null"),
            "{decl}"
        );
    }
}

#[test]
fn sums_quotients_and_differences_that_overflow_are_refused() {
    check_fails_at(
        "sum.die",
        "let a = 1.5e308 + 1.5e308\n",
        "die::non_finite",
        "1:17",
    );
    check_fails_at(
        "quotient.die",
        "let a = 1e308 / 1e-10\n",
        "die::non_finite",
        "1:15",
    );
    check_fails_at(
        "difference.die",
        "let big = 1.5e308 mm\nlet a = -big - big\n",
        "die::non_finite",
        "2:14",
    );
}

#[test]
fn literals_too_large_or_too_small_are_refused_alike() {
    check_fails_at("large.die", "let a = 1e309\n", "die::syntax", "1:9");
    let stderr = check_fails_at("small.die", "let a = 1e-400\n", "die::syntax", "1:9");
    assert!(stderr.contains("smallest number"), "{stderr}");
    check_fails_at("subnormal.die", "let a = 2e-310 mm\n", "die::syntax", "1:9");
    // A zero written with an exponent is still zero.
    let zero = script("zero.die", "let a = 0.0e-400\nlet b = 0e5 mm\n");
    let (exit, _, stderr) = dieface(&["check", zero.to_str().unwrap()]);
    assert_eq!(exit, Some(0), "{stderr}");
}

#[test]
fn a_unit_conversion_that_overflows_is_refused_at_the_literal() {
    check_fails_at("metres.die", "let a = 1e306 m\n", "die::non_finite", "1:9");
    // In a file whose default length is the metre, a bare number given as a length.
    check_fails_at(
        "default_unit.die",
        "units m deg\nlet a = line_between((0, 0), (1e307, 0))\n",
        "die::non_finite",
        "2:31",
    );
}

#[test]
fn an_override_that_overflows_is_refused() {
    let file = script("define.die", "param delta = 1 mm\nlet b = delta * 2\n");
    let path = file.to_str().unwrap();
    let (exit, _, stderr) = dieface(&["check", "--color", "never", "-D", "delta=1e308m", path]);
    assert_eq!(exit, Some(1), "{stderr}");
    assert!(stderr.contains("die::non_finite"), "{stderr}");
    assert!(stderr.contains("-D delta:1:1"), "{stderr}");
}

#[test]
fn builtins_that_make_non_finite_numbers_are_refused_at_the_call() {
    let stderr = check_fails_at(
        "linspace.die",
        "let a = linspace(-1e308, 1e308, 3)\n",
        "die::non_finite",
        "1:9",
    );
    assert!(stderr.contains("`a` = -1e308"), "{stderr}");
    check_fails_at(
        "lerp.die",
        "let a = lerp(-1e308, 1e308, 0.5)\n",
        "die::non_finite",
        "1:9",
    );
    check_fails_at(
        "sum_list.die",
        "let a = sum([1e308, 1e308])\n",
        "die::non_finite",
        "1:9",
    );
}

#[test]
fn geometry_beyond_the_modelling_range_is_refused_where_it_is_made() {
    check_fails_at(
        "far_line.die",
        "let a = line_between((0, 0, 0), (2e6, 0, 0))\n",
        "die::out_of_range",
        "1:34",
    );
    // A point beyond the range is refused at its coordinate, before the kernel
    // squares it (which made `interpolate` report "points 0 and 1 coincide").
    check_fails_at(
        "far_sketch.die",
        "let a = sketch(top) {\n    from (0, 0)\n    line to (0, 3e38)\n}\n",
        "die::out_of_range",
        "3:17",
    );
    check_fails_at(
        "far_points.die",
        "let a = interpolate([(0, 0, 0), (1e200, 0, 0), (2e200, 1, 0)])\n",
        "die::out_of_range",
        "1:34",
    );
    // A transform that carries geometry out of range: the builtin's result is checked.
    check_fails_at(
        "far_scale.die",
        "let a = line_between((0, 0, 0), (1000, 0, 0)) |> scale(factor: 1e4)\n",
        "die::out_of_range",
        "1:9",
    );
}

#[test]
fn a_fillet_between_collinear_lines_is_refused_at_the_fillet() {
    let stderr = check_fails_at(
        "collinear.die",
        "let a = sketch(top) {\n    from (0, 0)\n    line to (10, 0)\n    fillet 2\n    line to (20, 0)\n}\n",
        "die::sketch",
        "4:5",
    );
    assert!(stderr.contains("no corner to round"), "{stderr}");
}

/// A punch opening whose top view is a figure of eight.
const FIGURE_EIGHT: &str = "let profile = sketch(top) {
    from (-400, -300)
    fillet 60
    line to (400, 300)
    fillet 60
    line to (400, -300)
    fillet 60
    line to (-400, 300)
    fillet 60
    close
}
let wrap_x = sketch(side_xz) {
    from (-500, 0)
    line to (500, 0)
}
let wrap_y = sketch(side_yz) {
    from (-400, 0)
    line to (400, 0)
}
punch_opening opening {
    top = profile
    side rising = wrap_x
    side right = wrap_y
    side falling = wrap_x
    side left = wrap_y
}
";

#[test]
fn a_figure_of_eight_punch_opening_is_refused_where_it_crosses() {
    let stderr = check_fails_at("eight.die", FIGURE_EIGHT, "die::punch_opening", "4:5");
    assert!(stderr.contains("crosses itself at (0, 0)"), "{stderr}");
    assert!(stderr.contains("`falling` is crossed"), "{stderr}");
    // `build` refuses it too and writes nothing.
    let file = script("eight.die", FIGURE_EIGHT);
    let out = file.with_extension("glb");
    let _ = std::fs::remove_file(&out);
    let (exit, _, stderr) = dieface(&[
        "build",
        "--color",
        "never",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(exit, Some(1), "{stderr}");
    assert!(stderr.contains("eight.die:4:5"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn a_trim_outline_that_crosses_itself_is_refused() {
    let text = "let panel = nurbs_surface(degree: (1, 1), points: [[(-500, -500, 0), (-500, 500, 0)], [(500, -500, 0), (500, 500, 0)]])
let line8 = sketch(top) {
    from (-200, -100)
    fillet 20
    line to (200, 100)
    fillet 20
    line to (200, -100)
    fillet 20
    line to (-200, 100)
    fillet 20
    close
}
product part = trim(panel, project(line8, panel))
";
    let stderr = check_fails_at("trim8.die", text, "die::bad_argument", "13:28");
    assert!(stderr.contains("crosses itself"), "{stderr}");
}

#[test]
fn an_invalid_tolerance_parameter_fails_check_and_inspect_as_build() {
    let text = "units mm deg\nparam tolerance = 5 deg\nlet a = 2 mm\n";
    check_fails_at("tolerance.die", text, "die::bad_tolerance", "2:19");
    let file = script("tolerance.die", text);
    let path = file.to_str().unwrap();
    for json in [false, true] {
        let mut args = vec!["inspect", "--color", "never", path];
        if json {
            args.push("--json");
        }
        let (exit, _, stderr) = dieface(&args);
        assert_eq!(exit, Some(1), "inspect (json: {json}): {stderr}");
        assert!(stderr.contains("die::bad_tolerance"), "{stderr}");
        assert!(stderr.contains("tolerance.die:2:19"), "{stderr}");
    }
    let out = file.with_extension("glb");
    let (exit, _, stderr) = dieface(&["build", path, "-o", out.to_str().unwrap()]);
    assert_eq!(exit, Some(1), "build: {stderr}");
    assert!(stderr.contains("die::bad_tolerance"), "{stderr}");
}

const SPAN: Span = Span {
    file: FileId(0),
    start: 0,
    end: 1,
};

fn number(value: f64, length: bool) -> Value {
    let q = if length {
        Quantity::length(value)
    } else {
        Quantity::bare(value)
    };
    Value::new(Data::Number(q), SPAN)
}

/// Any finite value, weighted towards the extremes where overflow lives.
fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e3..1e3f64,
        -f64::MAX..f64::MAX,
        prop::sample::select(vec![
            f64::MAX,
            -f64::MAX,
            f64::MIN_POSITIVE,
            1e-300,
            1e300,
            1e154,
            0.0
        ]),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Arithmetic on finite numbers gives a finite number or a `die::non_finite`
    /// diagnostic (or another diagnostic, such as division by zero), never a silent
    /// infinity or NaN.
    #[test]
    fn arithmetic_never_returns_a_non_finite_number(
        a in finite(),
        b in finite(),
        op in prop::sample::select(vec![BinaryOp::Add, BinaryOp::Sub, BinaryOp::Mul, BinaryOp::Div]),
        la in any::<bool>(),
        lb in any::<bool>(),
    ) {
        let units = Units { length: 1000.0, angle: 1.0 };
        let (x, y) = (number(a, la), number(b, lb));
        match binary(op, &x, &y, SPAN, SPAN, units) {
            Ok(v) => match v.data {
                Data::Number(q) => prop_assert!(q.value.is_finite(), "{a} {op:?} {b} = {}", q.value),
                other => prop_assert!(false, "a number, not {other:?}"),
            },
            Err(d) => prop_assert!(
                matches!(d.code, "die::non_finite" | "die::division_by_zero" | "die::unit_mismatch"),
                "{a} {op:?} {b}: {}", d.code
            ),
        }
    }

    /// Points add and scale element-wise through the same check.
    #[test]
    fn point_arithmetic_never_returns_a_non_finite_coordinate(a in finite(), b in finite(), k in finite()) {
        let p = Value::new(Data::Tuple(std::sync::Arc::new(vec![number(a, true), number(b, true)])), SPAN);
        let s = number(k, false);
        for (op, rhs) in [(BinaryOp::Add, &p), (BinaryOp::Sub, &p), (BinaryOp::Mul, &s), (BinaryOp::Div, &s)] {
            if let Ok(v) = binary(op, &p, rhs, SPAN, SPAN, Units::default()) {
                prop_assert!(dieface::eval::finite::fault(&v.data).is_none(), "{op:?}: {v:?}");
            }
        }
    }
}
