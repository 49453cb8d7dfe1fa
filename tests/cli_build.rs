//! `dieface build` and `dieface inspect`: outputs by extension, exit codes, outputs left
//! alone on errors, `-D` overrides and `--tolerance`, inspect's text and JSON.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh folder for one test under the target's temp dir.
fn temp(name: &str) -> PathBuf {
    common::fresh_dir("cli_build", name)
}

fn dieface(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    common::run_dieface(dir, args)
}

const SCRIPT: &str = r#"
units mm deg
param depth = 30 mm
param tip_angle = 2 deg
let half = 100 mm
let net = [ [ (i * half, j * half, if i == 1 and j == 1 then depth else 0 mm) for j in range(0, 3) ] for i in range(0, 3) ]
product panel = nurbs_surface(degree: (2, 2), points: net) |> tip(about: "x", by: tip_angle)
let outline = sketch(top) {
    from (0, 0)
    line to (200, 0)
    fillet 20
    line to (200, 200)
    close
}
"#;

fn project(name: &str, script: &str) -> PathBuf {
    let dir = temp(name);
    std::fs::write(dir.join("part.die"), script).expect("write script");
    dir
}

#[test]
fn builds_every_format_in_one_run() {
    let dir = project("formats", SCRIPT);
    let (code, stdout, stderr) = dieface(
        &dir,
        &[
            "build", "part.die", "-o", "a.glb", "-o", "a.gltf", "-o", "a.obj",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("wrote a.glb"), "{stdout}");
    let glb = std::fs::read(dir.join("a.glb")).expect("glb");
    assert_eq!(&glb[..4], b"glTF", "binary glTF magic");
    let gltf = std::fs::read_to_string(dir.join("a.gltf")).expect("gltf");
    let parsed: serde_json::Value = serde_json::from_str(&gltf).expect("gltf is JSON");
    assert_eq!(parsed["asset"]["version"], "2.0");
    let obj = std::fs::read_to_string(dir.join("a.obj")).expect("obj");
    assert!(obj.lines().any(|l| l.starts_with("v ")), "OBJ vertices");
    assert!(obj.lines().any(|l| l.starts_with("f ")), "OBJ faces");
    // The last line: the whole time, then the stages', which add up to at most it.
    let last = stdout.lines().last().expect("a summary line");
    let times: Vec<f64> = last
        .split(" ms")
        .filter_map(|part| part.rsplit(' ').next()?.parse().ok())
        .collect();
    assert!(
        last.starts_with("built in ")
            && last.contains("(evaluated in ")
            && last.contains(", tessellated in ")
            && last.contains(", written in ")
            && times.len() == 4,
        "{last}"
    );
    assert!(times[1] + times[2] + times[3] <= times[0] + 0.3, "{last}");
}

#[test]
fn a_step_output_is_written_byte_identical_twice() {
    let script = r#"
import "std/sketch" as sk
let panel = nurbs_surface(degree: (2, 1), points: [[(-300, -250, 0), (-300, 250, 0)], [(0, -250, 20), (0, 250, 20)], [(300, -250, 0), (300, 250, 0)]])
product part = trim(panel, project(sk.rectangle(top, (0, 0), 400 mm, 300 mm, 50 mm), panel))
"#;
    let dir = project("step_out", script);
    let (code, _, stderr) = dieface(&dir, &["build", "part.die", "-o", "a.step", "-o", "b.STP"]);
    assert_eq!(code, Some(0), "{stderr}");
    let a = std::fs::read_to_string(dir.join("a.step")).expect("step");
    assert!(a.starts_with("ISO-10303-21;"), "{a}");
    assert_eq!(
        a.matches("ADVANCED_FACE(").count(),
        1,
        "the trimmed product only"
    );
    assert_eq!(
        a.matches("ORIENTED_EDGE(").count(),
        1,
        "one closed outline edge"
    );
    assert_eq!(a, std::fs::read_to_string(dir.join("b.STP")).expect("stp"));
    assert_eq!(
        dieface(&dir, &["build", "part.die", "-o", "a.step"]).0,
        Some(0)
    );
    assert_eq!(
        a,
        std::fs::read_to_string(dir.join("a.step")).expect("step")
    );
}

/// Declarations, step-draw patches, bead sections and tessellations run on every core:
/// the fender's GLB and STEP are the same bytes on one thread as on three.
#[test]
fn outputs_do_not_depend_on_the_number_of_threads() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fender");
    let dir = temp("threads");
    let build = |threads: &str, stem: &str| {
        let glb = dir.join(format!("{stem}.glb"));
        let step = dir.join(format!("{stem}.step"));
        let out = Command::new(env!("CARGO_BIN_EXE_dieface"))
            .current_dir(&example)
            .env("RAYON_NUM_THREADS", threads)
            .args(["build", "fender.die", "-o"])
            .arg(&glb)
            .arg("-o")
            .arg(&step)
            .output()
            .expect("run dieface");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        (
            std::fs::read(glb).expect("glb"),
            std::fs::read(step).expect("step"),
        )
    };
    let one = build("1", "one");
    let three = build("3", "three");
    assert!(one.0 == three.0, "the GLB differs with the thread count");
    assert!(one.1 == three.1, "the STEP differs with the thread count");
}

#[test]
fn a_step_output_without_a_die_face_is_refused() {
    let dir = project("step_empty", "let a = circle((0, 0), 10 mm)\n");
    let (code, _, stderr) = dieface(&dir, &["build", "part.die", "-o", "a.step"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("no die face to write"), "{stderr}");
    assert!(!dir.join("a.step").exists());
}

#[test]
fn an_fe_deck_without_a_mesh_is_refused() {
    let dir = project("fe_empty", "let a = circle((0, 0), 10 mm)\n");
    for out in ["a.k", "a.bdf"] {
        let (code, _, stderr) = dieface(&dir, &["build", "part.die", "-o", out]);
        assert_eq!(code, Some(2), "{stderr}");
        assert!(stderr.contains("no mesh to write"), "{stderr}");
        assert!(stderr.contains("quad_mesh"), "{stderr}");
        assert!(!dir.join(out).exists());
    }
}

#[test]
fn an_unknown_extension_is_a_usage_error_before_evaluating() {
    // The script is broken too: exit 2 shows the outputs were checked first.
    let dir = project("bad_ext", "let a = 10 mm + 5 deg\n");
    let (code, _, stderr) = dieface(&dir, &["build", "part.die", "-o", "a.stl"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains(".glb, .gltf, .obj, .step, .k or .bdf"),
        "{stderr}"
    );
    assert!(!stderr.contains("unit_mismatch"), "{stderr}");
    assert_eq!(dieface(&dir, &["build", "part.die"]).0, Some(2), "no -o");
    assert_eq!(
        dieface(&dir, &["build", "missing.die", "-o", "a.glb"]).0,
        Some(2)
    );
    assert_eq!(
        dieface(
            &dir,
            &["build", "part.die", "-o", "a.glb", "--tolerance", "5deg"]
        )
        .0,
        Some(2),
        "a tolerance that is not a length"
    );
    assert_eq!(
        dieface(
            &dir,
            &["build", "part.die", "-o", "a.glb", "--tolerance", "0.01"]
        )
        .0,
        Some(2),
        "a tolerance without its unit"
    );
}

#[test]
fn a_script_error_exits_1_and_leaves_the_previous_output_untouched() {
    let dir = project("keep", SCRIPT);
    let (code, _, stderr) = dieface(&dir, &["build", "part.die", "-o", "a.glb", "-o", "a.obj"]);
    assert_eq!(code, Some(0), "{stderr}");
    let glb = std::fs::read(dir.join("a.glb")).expect("glb");
    let obj = std::fs::read(dir.join("a.obj")).expect("obj");
    std::fs::write(
        dir.join("part.die"),
        SCRIPT.replace("let half = 100 mm", "let half = 100 mm + 3 deg"),
    )
    .expect("break");
    let (code, _, stderr) = dieface(
        &dir,
        &[
            "build", "part.die", "-o", "a.glb", "-o", "a.obj", "--color", "never",
        ],
    );
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("die::unit_mismatch"), "{stderr}");
    assert_eq!(std::fs::read(dir.join("a.glb")).expect("glb"), glb);
    assert_eq!(std::fs::read(dir.join("a.obj")).expect("obj"), obj);
}

#[test]
fn overrides_change_the_output_and_are_unit_checked() {
    let dir = project("define", SCRIPT);
    let build = |extra: &[&str], out: &str| {
        let mut args = vec!["build", "part.die", "-o", out, "--color", "never"];
        args.extend_from_slice(extra);
        dieface(&dir, &args)
    };
    let (code, _, stderr) = build(&[], "plain.obj");
    assert_eq!(code, Some(0), "{stderr}");
    let (code, _, stderr) = build(&["-D", "depth=45mm"], "deeper.obj");
    assert_eq!(code, Some(0), "{stderr}");
    let (code, _, stderr) = build(&["-D", "depth = 3 cm"], "same.obj");
    assert_eq!(code, Some(0), "{stderr}");
    let read = |f: &str| std::fs::read(dir.join(f)).expect("output");
    assert_ne!(
        read("plain.obj"),
        read("deeper.obj"),
        "-D changed the panel"
    );
    assert_eq!(read("plain.obj"), read("same.obj"), "3 cm is 30 mm");

    // An angle for a length: exit 1, die::bad_override, no output.
    let (code, _, stderr) = build(&["-D", "depth=5deg"], "wrong.obj");
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("die::bad_override"), "{stderr}");
    assert!(stderr.contains("depth is a length"), "{stderr}");
    assert!(!dir.join("wrong.obj").exists());

    // Only params, and only names that exist.
    let (code, _, stderr) = build(&["-D", "half=5mm"], "wrong.obj");
    assert_eq!(code, Some(1));
    assert!(stderr.contains("not a `param`"), "{stderr}");
    let (code, _, stderr) = build(&["-D", "dpeth=5mm"], "wrong.obj");
    assert_eq!(code, Some(1));
    assert!(stderr.contains("did you mean `depth`?"), "{stderr}");
    // Not `name=value`: a usage error.
    assert_eq!(build(&["-D", "depth"], "wrong.obj").0, Some(2));
}

#[test]
fn the_tolerance_comes_from_the_cli_then_the_script_then_the_default() {
    let dir = project("tolerance", SCRIPT);
    let size = |args: &[&str]| {
        let (code, _, stderr) = dieface(&dir, args);
        assert_eq!(code, Some(0), "{stderr}");
        std::fs::metadata(dir.join(args[3])).expect("output").len()
    };
    let default = size(&["build", "part.die", "-o", "default.obj"]);
    let explicit = size(&[
        "build",
        "part.die",
        "-o",
        "explicit.obj",
        "--tolerance",
        "0.05 mm",
    ]);
    assert_eq!(default, explicit, "the default is 0.05 mm");
    let fine = size(&[
        "build",
        "part.die",
        "-o",
        "fine.obj",
        "--tolerance",
        "0.001mm",
    ]);
    assert!(fine > default, "a finer tolerance gives more triangles");

    std::fs::write(
        dir.join("part.die"),
        format!("{SCRIPT}\nparam tolerance = 0.001 mm\n"),
    )
    .expect("write");
    let scripted = size(&["build", "part.die", "-o", "scripted.obj"]);
    assert_eq!(scripted, fine, "`param tolerance` sets it");
    let cli_wins = size(&[
        "build",
        "part.die",
        "-o",
        "cli.obj",
        "--tolerance",
        "0.05mm",
    ]);
    assert_eq!(cli_wins, default, "--tolerance wins over the script");
}

#[test]
fn inspect_prints_one_line_per_declaration() {
    let dir = project("inspect_text", SCRIPT);
    let (code, stdout, stderr) = dieface(&dir, &["inspect", "part.die"]);
    assert_eq!(code, Some(0), "{stderr}");
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 6, "{stdout}");
    assert!(lines[0].starts_with("param depth (line 3, "), "{stdout}");
    assert!(lines[0].contains(" ms): number 30 mm (length)"), "{stdout}");
    let panel = lines
        .iter()
        .find(|l| l.starts_with("product panel"))
        .expect("panel");
    assert!(panel.contains("degree 2x2, 3x3 control points"), "{panel}");
    assert!(panel.contains("area "), "{panel}");
    let outline = lines
        .iter()
        .find(|l| l.starts_with("let outline"))
        .expect("outline");
    assert!(
        outline.contains("closed") && outline.contains("length"),
        "{outline}"
    );

    let broken = project("inspect_broken", "let a = 10 mm + 5 deg\n");
    assert_eq!(dieface(&broken, &["inspect", "part.die"]).0, Some(1));
    assert_eq!(dieface(&broken, &["inspect", "nope.die"]).0, Some(2));
}

#[test]
fn inspect_json_has_the_documented_schema() {
    let dir = project("inspect_json", SCRIPT);
    let (code, stdout, stderr) =
        dieface(&dir, &["inspect", "--json", "part.die", "-D", "depth=40mm"]);
    assert_eq!(code, Some(0), "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(doc["schema"], 1);
    assert_eq!(doc["file"], "part.die");
    assert_eq!(doc["diagnostics"].as_array().map(Vec::len), Some(0));
    let decls = doc["declarations"].as_array().expect("declarations");
    let names: Vec<&str> = decls.iter().filter_map(|d| d["name"].as_str()).collect();
    assert_eq!(
        names,
        ["depth", "tip_angle", "half", "net", "panel", "outline"]
    );
    // Keys in the documented order.
    let keys: Vec<&String> = decls[0].as_object().expect("object").keys().collect();
    assert_eq!(
        keys,
        ["name", "kind", "line", "column", "type", "eval_ms", "value"]
    );

    let depth = &decls[0];
    assert_eq!(depth["kind"], "param");
    assert_eq!(depth["type"], "length");
    assert_eq!(depth["line"], 3);
    assert_eq!(depth["value"]["value"], 40.0);
    assert_eq!(depth["value"]["unit"], "mm");
    assert_eq!(decls[1]["value"]["unit"], "deg");
    assert_eq!(decls[1]["value"]["value"], 2.0);

    let panel = &decls[4];
    assert_eq!(panel["type"], "surface");
    let s = &panel["value"];
    assert_eq!(s["degree_u"], 2);
    assert_eq!(s["degree_v"], 2);
    assert_eq!(
        s["knots_u"],
        serde_json::json!([0.0, 0.0, 0.0, 1.0, 1.0, 1.0])
    );
    assert!(s["weights"].is_null());
    let rows = s["control_points"].as_array().expect("rows");
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[0].as_array().map(Vec::len), Some(3));
    assert_eq!(rows[1][1].as_array().map(Vec::len), Some(3), "[x, y, z]");

    let outline = &decls[5];
    assert_eq!(outline["type"], "sketch");
    let sk = &outline["value"];
    assert_eq!(sk["view"], "top");
    assert_eq!(sk["closed"], true);
    let kinds: Vec<&str> = sk["segments"]
        .as_array()
        .expect("segments")
        .iter()
        .filter_map(|g| g["kind"].as_str())
        .collect();
    assert_eq!(kinds, ["line", "fillet", "line", "line"]);
    assert_eq!(sk["segments"][0]["line"], 10);
    let curve = &sk["curve"];
    assert_eq!(curve["dimension"], 2);
    assert_eq!(curve["degree"], 2);
    let n = curve["control_points"].as_array().expect("points").len();
    assert_eq!(
        curve["weights"].as_array().map(Vec::len),
        Some(n),
        "the fillet arc is rational"
    );
    assert_eq!(curve["knots"].as_array().map(Vec::len), Some(n + 3));

    // A point is [x, y, z] in mm, a list is an array.
    let net = &decls[3]["value"];
    assert_eq!(net[1][1], serde_json::json!([100.0, 100.0, 40.0]));
}

#[test]
fn an_override_is_part_of_its_params_memo_key() {
    use dieface::eval::{Data, Engine};
    let script = "param d = 1 mm\nlet twice = d * 2\nlet other = 5 deg\n";
    let mut engine = Engine::new(None);
    engine.set_overrides(vec![("d".into(), "2mm".into())]);
    let first = engine.evaluate("memo.die", script, None);
    assert!(first.diagnostics.is_empty(), "{:?}", first.diagnostics);
    assert_eq!(engine.evaluation_count(), 3);
    assert_eq!(engine.last_timings().len(), 3, "one timing per evaluation");

    // The same override: everything comes from the memo.
    engine.evaluate("memo.die", script, None);
    assert!(engine.last_evaluated().is_empty());

    // Another value: the param and what uses it re-run.
    engine.set_overrides(vec![("d".into(), "3mm".into())]);
    let out = engine.evaluate("memo.die", script, None);
    let mut ran = engine.last_evaluated().to_vec();
    ran.sort();
    assert_eq!(ran, ["d", "twice"]);
    let twice = out.decls.iter().find(|d| d.name == "twice").expect("twice");
    match twice.value.as_ref().map(|v| &v.data) {
        Some(Data::Number(q)) => assert!((q.value - 6.0).abs() < 1e-12),
        other => panic!("{other:?}"),
    }
}

/// `dieface inspect` of every example, timings removed: the reviewed summary, feature
/// quality reports included.
#[test]
fn inspect_of_every_example_is_a_snapshot() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for name in ["fender", "door_outer", "door", "sections"] {
        let dir = root.join("examples").join(name);
        let (code, stdout, stderr) = dieface(&dir, &["inspect", &format!("{name}.die")]);
        assert_eq!(code, Some(0), "{name}: {stderr}");
        let stable: Vec<String> = stdout.lines().map(without_timing).collect();
        insta::assert_snapshot!(format!("inspect__{name}"), stable.join("\n"));
    }
}

/// `kind name (line 3, 1.2 ms): ...` without the timing, which varies between runs.
fn without_timing(line: &str) -> String {
    let (Some(open), Some(close)) = (line.find(" (line "), line.find("): ")) else {
        return line.to_string();
    };
    let inside = &line[open + 2..close];
    let kept = inside.split(", ").next().unwrap_or(inside);
    format!("{} ({kept}{}", &line[..open], &line[close..])
}
