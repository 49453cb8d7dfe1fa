//! `dieface check` exit codes and output: 0 clean, 1 script errors, 2 usage errors.

mod common;

use std::path::Path;

fn dieface(args: &[&str]) -> (Option<i32>, String, String) {
    common::run_dieface(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

#[test]
fn a_clean_example_exits_0() {
    let (code, stdout, stderr) = dieface(&["check", "examples/fender/fender.die"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("no problems"));
}

#[test]
fn a_script_with_mistakes_exits_1_and_prints_located_diagnostics() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("bad.die");
    std::fs::write(
        &file,
        "let a = 10 mm + 5 deg\nlet b = widht\nlet width = 2 mm\n",
    )
    .expect("write");
    let (code, _, stderr) = dieface(&[
        "check",
        "--color",
        "never",
        file.to_str().expect("utf-8 path"),
    ]);
    assert_eq!(code, Some(1));
    assert!(stderr.contains("die::unit_mismatch"), "{stderr}");
    assert!(
        stderr.contains("bad.die:1:9"),
        "file, line and column: {stderr}"
    );
    assert!(stderr.contains("did you mean `width`?"), "{stderr}");
    assert!(stderr.contains("2 problems"), "{stderr}");
}

#[test]
fn usage_errors_exit_2() {
    assert_eq!(dieface(&["check"]).0, Some(2), "missing file argument");
    assert_eq!(
        dieface(&["check", "no/such/file.die"]).0,
        Some(2),
        "file that does not exist"
    );
    assert_eq!(dieface(&["frobnicate"]).0, Some(2), "unknown command");
    assert_eq!(
        dieface(&[
            "check",
            "--color",
            "sometimes",
            "examples/fender/fender.die"
        ])
        .0,
        Some(2)
    );
}
