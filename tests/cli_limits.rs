//! The limits of `docs/limits.md` through the real binary: scripts that ask for too much
//! memory or work end with a diagnostic naming the limit, at the expression that reached
//! it, and scripts that are merely large stay fast (issue 14). Every large input is made
//! here at run time.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs dieface with `args`; exit code, stdout, stderr.
fn dieface(args: &[&str]) -> (Option<i32>, String, String) {
    common::run_dieface(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

/// A fresh directory for one test.
fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_limits")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Writes `text` as `name.die` in its own directory; the path.
fn script(name: &str, text: &str) -> String {
    let file = dir(name).join(format!("{name}.die"));
    std::fs::write(&file, text).expect("write script");
    file.to_str().expect("utf-8 path").to_string()
}

/// `check`s `text` with `extra` arguments: exit 1 and the diagnostics.
fn check_fails(name: &str, text: &str, extra: &[&str]) -> String {
    let file = script(name, text);
    let mut args = vec!["check", "--color", "never", &file];
    args.extend_from_slice(extra);
    let (code, _, stderr) = dieface(&args);
    assert_eq!(code, Some(1), "{stderr}");
    stderr
}

/// Asserts that `stderr` reports the limit `name` at `file:line:column` with its help.
fn names_limit(stderr: &str, name: &str, at: &str) {
    assert!(
        stderr.contains(&format!("die::limit::{name}")),
        "code: {stderr}"
    );
    assert!(
        stderr.contains(&format!("reaches the `{name}` limit")),
        "label: {stderr}"
    );
    assert!(stderr.contains(&format!("{name}=N`")), "help: {stderr}");
    assert!(stderr.contains(at), "where ({at}): {stderr}");
}

#[test]
fn exponential_recursion_runs_out_of_work_at_a_call_naming_the_declaration() {
    let stderr = check_fails(
        "expo",
        "fn f(n) = if n == 0 then 1 else f(n - 1) + f(n - 1)\nlet a = f(60)\nlet b = 2\n",
        &["--limit", "work=200000"],
    );
    names_limit(&stderr, "work", "expo.die:1:");
    assert!(
        stderr.contains("`a` takes more than 200000 evaluation steps"),
        "{stderr}"
    );
    assert!(stderr.contains("1 problem"), "reported once: {stderr}");
}

#[test]
fn work_is_counted_over_every_declaration_and_reported_once() {
    let text: String = (0..50)
        .map(|i| format!("let a{i} = len(map(range(10000), fn(x) => x * 2))\n"))
        .collect();
    let stderr = check_fails("work_many", &text, &["--limit", "work=100000"]);
    assert_eq!(stderr.matches("die::limit::work").count(), 1, "{stderr}");
}

#[test]
fn call_depth_is_read_from_the_limits() {
    let text = "fn down(n) = if n == 0 then 0 else down(n - 1)\nlet a = down(100)\n";
    let file = script("depth_ok", text);
    assert_eq!(
        dieface(&["check", &file]).0,
        Some(0),
        "100 levels are allowed"
    );
    let stderr = check_fails("depth", text, &["--limit", "call_depth=50"]);
    assert!(stderr.contains("die::recursion_limit"), "{stderr}");
    assert!(stderr.contains("more than 50 levels deep"), "{stderr}");
    assert!(stderr.contains("call_depth=N`"), "{stderr}");
    assert!(stderr.contains("depth.die:1:36"), "{stderr}");
}

#[test]
fn deep_recursion_through_builtins_stops_at_the_limit_not_the_stack() {
    // Each level goes through `map`, `sum` and a lambda: the biggest frames there are.
    let text =
        "fn f(n) = if n == 0 then 0 else sum(map([n], fn(x) => f(x - 1)))\nlet a = f(100000)\n";
    let stderr = check_fails("deep_builtins", text, &[]);
    assert!(stderr.contains("die::recursion_limit"), "{stderr}");
    assert!(stderr.contains("more than 200 levels deep"), "{stderr}");
}

#[test]
fn nested_ranges_reach_list_items_at_the_inner_range() {
    let stderr = check_fails(
        "ranges",
        "let a = map(range(100000), fn(i) => range(100000))\n",
        &["--limit", "list_items=1000000"],
    );
    names_limit(&stderr, "list_items", "ranges.die:1:37");
}

#[test]
fn a_range_over_samples_fails_before_it_is_made() {
    let stderr = check_fails("range", "let a = range(100000000)\n", &[]);
    names_limit(&stderr, "samples", "range.die:1:15");
    let stderr = check_fails("linspace", "let a = linspace(0, 1, 2000000)\n", &[]);
    names_limit(&stderr, "samples", "linspace.die:1:24");
}

#[test]
fn a_string_doubled_40_times_reaches_string_bytes() {
    let mut text = String::from("let s0 = \"ab\"\n");
    for i in 1..=40 {
        text.push_str(&format!("let s{i} = s{} + s{}\n", i - 1, i - 1));
    }
    let stderr = check_fails("double", &text, &["--limit", "string_bytes=1000000"]);
    // s19 holds 2^20 bytes, over a million: the join that makes it is refused.
    names_limit(&stderr, "string_bytes", "double.die:20:11");
}

#[test]
fn a_list_doubled_40_times_reaches_list_items() {
    let mut text = String::from("let l0 = [1, 2]\n");
    for i in 1..=40 {
        text.push_str(&format!("let l{i} = l{} + l{}\n", i - 1, i - 1));
    }
    let stderr = check_fails("ldouble", &text, &["--limit", "list_items=100000"]);
    // l16 would hold 2^17 items.
    names_limit(&stderr, "list_items", "ldouble.die:17:11");
}

#[test]
fn a_loft_of_too_many_points_fails_before_lofting() {
    let text = "let secs = map(range(60), fn(i) => interpolate(map(range(60), fn(j) => (j * 1 mm, i * 1 mm, sin(i * j * 1 deg) * 1 mm))))\nlet s = loft(secs)\n";
    let file = script("loft", text);
    let (code, stdout, stderr) =
        dieface(&["inspect", "--json", "--limit", "samples=100000", &file]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stdout.contains("die::limit::samples"), "{stdout}");
    assert!(stdout.contains("\"line\": 2"), "{stdout}");
}

#[test]
fn did_you_mean_on_a_huge_unknown_name_is_quick_and_quiet() {
    let name = "q".repeat(100_000);
    let stderr = check_fails("dym", &format!("let qqq = 1\nlet a = {name}\n"), &[]);
    assert!(stderr.contains("die::unknown_name"), "{stderr}");
    assert!(stderr.contains("dym.die:2:9"), "{stderr}");
    assert!(!stderr.contains("did you mean"), "{stderr}");
}

#[test]
fn a_diamond_of_imports_evaluates_each_module_once() {
    let d = dir("diamond");
    const LEVELS: usize = 40;
    for i in 0..LEVELS {
        for n in ["x", "y"] {
            let text = format!(
                "import \"x{}.die\" as a\nimport \"y{}.die\" as b\nlet v = a.v + b.v\n",
                i + 1,
                i + 1
            );
            std::fs::write(d.join(format!("{n}{i}.die")), text).expect("write");
        }
    }
    for n in ["x", "y"] {
        std::fs::write(d.join(format!("{n}{LEVELS}.die")), "let v = 1\n").expect("write");
    }
    std::fs::write(
        d.join("main.die"),
        "import \"x0.die\" as a\nimport \"y0.die\" as b\nlet v = a.v + b.v\n",
    )
    .expect("write");
    let main = d.join("main.die");
    let (code, stdout, stderr) = dieface(&["inspect", main.to_str().expect("utf-8")]);
    assert_eq!(code, Some(0), "{stderr}");
    // 2^41: every path through the diamond counted, each module evaluated once.
    assert!(stdout.contains("2199023255552"), "{stdout}");
}

#[test]
fn a_line_far_out_fails_to_build_at_its_declaration() {
    let file = script(
        "far",
        "let ok = 1 mm\nlet l = line_between((0, 0, 0), (1e160, 1e160, 0))\n",
    );
    let out = dir("far_out").join("far.glb");
    let (code, _, stderr) = dieface(&[
        "build",
        "--color",
        "never",
        &file,
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    assert_eq!(code, Some(1), "{stderr}");
    // Refused where the point is read: beyond the modelling range (docs/limits.md), so
    // the curve never reaches the tessellator, whose chord checks would overflow.
    assert!(stderr.contains("die::out_of_range"), "{stderr}");
    assert!(stderr.contains("far.die:2:34"), "{stderr}");
    assert!(!out.exists(), "no output written");
}

#[test]
fn a_curve_needing_more_points_than_samples_fails_naming_the_limit() {
    let stderr = builds_until_limited(
        "circle",
        "let c = circle((0, 0, 0), 1000 mm)\n",
        "samples=20",
    );
    assert!(stderr.contains("samples=N`"), "{stderr}");
    assert!(stderr.contains("circle.die:1:9"), "{stderr}");
}

/// Peak resident memory of a child, sampled from `/proc` while it runs (a lower
/// bound of the true peak; enough to tell megabytes from gigabytes), in kB.
#[cfg(target_os = "linux")]
fn peak_kb_of(args: &[&str]) -> (Option<i32>, u64) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dieface"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("run dieface");
    let status = format!("/proc/{}/status", child.id());
    let mut peak = 0;
    loop {
        if let Ok(text) = std::fs::read_to_string(&status) {
            let hwm = text
                .lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok());
            peak = peak.max(hwm.unwrap_or(0));
        }
        if let Some(s) = child.try_wait().expect("wait") {
            return (s.code(), peak);
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
}

#[cfg(target_os = "linux")]
#[test]
fn twenty_thousand_declarations_check_in_bounded_memory() {
    let text: String = (0..20_000)
        .map(|i| format!("let a{i} = {i} mm\n"))
        .collect();
    let file = script("lets20k", &text);
    // Memory grew with the square of the declarations: 5k took 2.1 GB, 20k would take
    // over 30 GB. Linear, 20k take about 50 MB.
    let (code, peak) = peak_kb_of(&["check", &file]);
    assert_eq!(code, Some(0));
    assert!(peak < 400_000, "peak {peak} kB");
    let (code, peak) = peak_kb_of(&["inspect", "--json", &file]);
    assert_eq!(code, Some(0));
    assert!(peak < 400_000, "peak {peak} kB");
}

#[test]
fn large_lists_and_sketches_build_and_inspect() {
    // Both were quadratic in their size (a line's position found by scanning the file).
    let list = format!(
        "let xs = [{}]\nlet p = line_between((0, 0, 0), (1, 1, 1))\n",
        (0..100_000)
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let file = script("list100k", &list);
    let out = dir("list_out").join("l.glb");
    let (code, _, stderr) = dieface(&["build", &file, "-o", out.to_str().expect("utf-8")]);
    assert_eq!(code, Some(0), "{stderr}");
    let mut sketch = String::from("let s = sketch(top) {\n from (0, 0)\n");
    for i in 1..20_000 {
        sketch.push_str(&format!(" line to ({i}, {})\n", i % 7));
    }
    sketch.push_str("}\n");
    let file = script("sketch20k", &sketch);
    let (code, stdout, stderr) = dieface(&["inspect", "--json", &file]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("\"schema\""));
}

#[test]
fn a_long_chain_of_functions_is_checked_quickly() {
    // What each function reaches was closed by repeating a pass over all of them until
    // nothing changed: the cube of the chain (2,000 functions took three minutes).
    let mut text = String::from("fn f0(x) = x\n");
    for i in 1..3000 {
        text.push_str(&format!("fn f{i}(x) = f{}(x) + 1\n", i - 1));
    }
    text.push_str("let a = f150(1)\nlet b = f2999(1)\n");
    let stderr = check_fails("fchain", &text, &[]);
    assert!(stderr.contains("die::recursion_limit"), "{stderr}");
    assert!(
        stderr.contains("1 problem"),
        "only `b` goes too deep: {stderr}"
    );
}

#[test]
fn a_raised_call_depth_still_ends_in_a_diagnostic_not_an_overflow() {
    let text =
        "fn f(n) = if n == 0 then 0 else sum(map([n], fn(x) => f(x - 1)))\nlet a = f(10000000)\n";
    let stderr = check_fails("raised_depth", text, &["--limit", "call_depth=100000000"]);
    assert!(stderr.contains("die::recursion_limit"), "{stderr}");
    assert!(stderr.contains("more than 50000 levels deep"), "{stderr}");
}

#[test]
fn a_surface_needing_more_vertices_than_mesh_vertices_fails_naming_the_limit() {
    let stderr = builds_until_limited(
        "dome",
        "let net = [[(i * 100 mm, j * 100 mm, if i == 1 and j == 1 then 40 mm else 0 mm) for j in range(0, 3)] for i in range(0, 3)]\nlet dome = nurbs_surface(degree: (2, 2), points: net)\n",
        "mesh_vertices=100",
    );
    assert!(stderr.contains("die::limit::mesh_vertices"), "{stderr}");
    assert!(stderr.contains("mesh_vertices=N`"), "{stderr}");
    assert!(stderr.contains("dome.die:2:12"), "{stderr}");
}

#[test]
fn records_holding_closures_reach_memory_mb_though_few_items() {
    // A million records, each holding a closure: two million list items and record
    // fields, under `list_items`, but a kilobyte each.
    let stderr = check_fails(
        "closures",
        "let ok = 1 mm\nlet a = [[{k: fn(x) => x} for i in range(0, 1000)] for j in range(0, 1000)]\n",
        &["--limit", "memory_mb=200"],
    );
    names_limit(&stderr, "memory_mb", "closures.die:2:");
    assert!(
        stderr.contains("`a` needs more than 200 MiB of memory"),
        "{stderr}"
    );
}

/// Builds script `text` (saved as `<name>.die`) at the default limits, which must
/// succeed, then with `--limit <limit>`, which must fail with exit 1; the second
/// build's error text.
fn builds_until_limited(name: &str, text: &str, limit: &str) -> String {
    let file = script(name, text);
    let out = dir(&format!("{name}_out")).join("out.glb");
    let out = out.to_str().expect("utf-8");
    let (code, _, stderr) = dieface(&["build", &file, "-o", out]);
    assert_eq!(code, Some(0), "{stderr}");
    let (code, _, stderr) = dieface(&[
        "build", "--color", "never", &file, "-o", out, "--limit", limit,
    ]);
    assert_eq!(code, Some(1), "{stderr}");
    stderr
}
