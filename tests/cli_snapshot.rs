//! `dieface snapshot` on the real binary: written, checked, a changed number caught
//! with the changed line named, accepted by `--update`, and byte-identical across runs.

mod common;

use std::path::Path;

fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    common::run_dieface(dir, args)
}

/// A small die face: a product panel, a sketched outline on it, a curve.
const SCRIPT: &str = "\
units mm deg
let net = [ [ (i * 100, j * 80, 5 * i * j) for j in range(0, 4) ] for i in range(0, 4) ]
let panel = nurbs_surface(degree: (3, 3), points: net)
let edge = line_between((0, 0, 0), (300, 0, 0))
param gap = 2.5 mm
let pieces = [edge, line_between((0, 10, 0), (300, 10, 40))]
";

#[test]
fn write_check_catch_and_update() {
    let dir = common::fresh_dir("cli_snapshot", "cycle");
    std::fs::write(dir.join("part.die"), SCRIPT).expect("write");
    let (code, stdout, stderr) = run(&dir, &["snapshot", "part.die"]);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    assert!(stdout.contains("wrote part.die.snap"), "{stdout}");
    let first = std::fs::read(dir.join("part.die.snap")).expect("the snapshot");
    let text = String::from_utf8(first.clone()).expect("utf-8");
    assert!(text.contains("param gap (line 5): number 2.5 mm"), "{text}");
    assert!(
        text.contains("piece pieces/1 (let, line 6): curve"),
        "{text}"
    );
    assert!(common::temp_files(&dir).is_empty());

    // Deterministic: a second write gives the same bytes.
    let (code, stdout, _) = run(&dir, &["snapshot", "part.die", "--update"]);
    assert_eq!(code, Some(0));
    assert!(stdout.contains("up to date"), "{stdout}");
    std::fs::remove_file(dir.join("part.die.snap")).expect("remove");
    let (code, _, _) = run(&dir, &["snapshot", "part.die", "--update"]);
    assert_eq!(code, Some(0));
    assert_eq!(
        std::fs::read(dir.join("part.die.snap")).expect("again"),
        first,
        "byte-identical"
    );

    let (code, stdout, stderr) = run(&dir, &["snapshot", "part.die", "--check"]);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    assert!(stdout.contains("matches"), "{stdout}");

    // A changed number: --check exits 1 and names the changed line.
    std::fs::write(dir.join("part.die"), SCRIPT.replace("2.5 mm", "3 mm")).expect("write");
    let (code, stdout, stderr) = run(&dir, &["snapshot", "part.die", "--check"]);
    assert_eq!(code, Some(1), "{stdout}{stderr}");
    assert!(
        stdout.contains("-param gap (line 5): number 2.5 mm"),
        "{stdout}"
    );
    assert!(
        stdout.contains("+param gap (line 5): number 3 mm"),
        "{stdout}"
    );
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with(['-', '+'])).count(),
        4,
        "the two file lines and one changed line each way:\n{stdout}"
    );
    assert!(stderr.contains("--update"), "{stderr}");
    // With no flag an existing snapshot is checked, not overwritten.
    let (code, _, _) = run(&dir, &["snapshot", "part.die"]);
    assert_eq!(code, Some(1));
    assert_eq!(
        std::fs::read(dir.join("part.die.snap")).expect("kept"),
        first
    );

    let (code, stdout, _) = run(&dir, &["snapshot", "part.die", "--update"]);
    assert_eq!(code, Some(0), "{stdout}");
    let (code, _, _) = run(&dir, &["snapshot", "part.die", "--check"]);
    assert_eq!(code, Some(0), "accepted");
}

#[test]
fn a_comment_edit_keeps_the_snapshot_but_moved_lines_show() {
    let dir = common::fresh_dir("cli_snapshot", "comment");
    std::fs::write(dir.join("part.die"), SCRIPT).expect("write");
    assert_eq!(run(&dir, &["snapshot", "part.die"]).0, Some(0));
    std::fs::write(
        dir.join("part.die"),
        SCRIPT.replace("param gap = 2.5 mm", "param gap = 2.5 mm   // the gap"),
    )
    .expect("write");
    let (code, stdout, stderr) = run(&dir, &["snapshot", "part.die", "--check"]);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
}

#[test]
fn a_missing_snapshot_under_check_and_script_errors_fail() {
    let dir = common::fresh_dir("cli_snapshot", "missing");
    std::fs::write(dir.join("part.die"), SCRIPT).expect("write");
    let (code, _, stderr) = run(&dir, &["snapshot", "part.die", "--check"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("no snapshot"), "{stderr}");
    assert!(stderr.contains("--update"), "{stderr}");
    assert!(!dir.join("part.die.snap").exists());

    std::fs::write(dir.join("bad.die"), "let a = 1 mm + 2 deg\n").expect("write");
    let (code, _, stderr) = run(&dir, &["snapshot", "bad.die", "--color", "never"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("die::unit_mismatch"), "{stderr}");
    assert!(!dir.join("bad.die.snap").exists());

    let (code, _, stderr) = run(&dir, &["snapshot", "part.die", "--check", "--update"]);
    assert_eq!(code, Some(2), "{stderr}");
}

#[test]
fn the_fender_snapshot_has_a_line_per_piece() {
    let dir = common::fresh_dir("cli_snapshot", "fender");
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fender/fender.die");
    std::fs::copy(src, dir.join("fender.die")).expect("copy");
    let (code, stdout, stderr) = run(&dir, &["snapshot", "fender.die"]);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    let text = std::fs::read_to_string(dir.join("fender.die.snap")).expect("snapshot");
    assert!(text.contains("blankholder binder (line "), "{text}");
    assert!(
        text.lines()
            .any(|l| l.starts_with("piece binder/") && l.contains("bounds (")),
        "{text}"
    );
    assert!(text.contains("piece wheel_arch/"), "{text}");
}
