//! `dieface diff` on the real binary, with known answers: the fender's wheel-arch bead
//! moved 5 mm sideways is measured at 5 mm on that bead and nowhere else; an edit of a
//! comment is no change; a renamed declaration is a rename; `--json` carries the same
//! figures; `--rev` reads the old version from git.

mod common;

use std::path::Path;

/// The wheel-arch bead's centre line in `examples/fender/fender.die`, and the same line
/// 5 mm further out (in -y, square to the line within 0.005 mm: it runs 700 mm in x
/// and 5.2 mm in y).
const BEAD_LINE: &str = "line = sketch(top) { from (-200, -623.6); line to (500, -628.8) }";
const BEAD_LINE_MOVED: &str = "line = sketch(top) { from (-200, -628.6); line to (500, -633.8) }";

fn fender() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fender/fender.die");
    let text = std::fs::read_to_string(path).expect("the fender example");
    assert!(text.contains(BEAD_LINE), "the example's bead line moved");
    text
}

fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    common::run_dieface(dir, args)
}

/// The largest distance on the report line that starts with `prefix`.
fn largest_on(stdout: &str, prefix: &str) -> f64 {
    let line = stdout
        .lines()
        .find(|l| l.trim_start().starts_with(prefix))
        .unwrap_or_else(|| panic!("no line `{prefix}` in:\n{stdout}"));
    let after = line.split("largest ").nth(1).expect("a largest distance");
    after
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("a number in {line}"))
}

#[test]
fn a_bead_moved_5_mm_is_measured_at_5_mm_on_that_bead_only() {
    let dir = common::fresh_dir("cli_diff", "bead_moved");
    let old = fender();
    std::fs::write(dir.join("old.die"), &old).expect("write");
    std::fs::write(dir.join("new.die"), old.replace(BEAD_LINE, BEAD_LINE_MOVED)).expect("write");
    let (code, stdout, stderr) = run(&dir, &["diff", "old.die", "new.die"]);
    assert_eq!(code, Some(1), "something changed: {stdout}{stderr}");
    let max = largest_on(&stdout, "changed  bead wheel_arch:");
    assert!((4.9..=5.1).contains(&max), "{max} mm:\n{stdout}");
    // Every changed line belongs to the bead: its own line and its pieces.
    let changed: Vec<&str> = stdout
        .lines()
        .filter(|l| {
            ["changed", "added", "removed", "renamed"]
                .iter()
                .any(|w| l.starts_with(w))
        })
        .collect();
    assert_eq!(changed.len(), 1, "only the bead changed:\n{stdout}");
    assert!(stdout.contains("1 changed, "), "{stdout}");
    // Each of its changed pieces moved by about 5 mm, none by more.
    let pieces: Vec<f64> = stdout
        .lines()
        .filter(|l| l.starts_with("    wheel_arch") && l.contains("largest"))
        .map(|l| largest_on(l, "wheel_arch"))
        .collect();
    assert!(!pieces.is_empty(), "{stdout}");
    assert!(pieces.iter().all(|d| *d <= 5.1), "{pieces:?}");

    // The JSON document has the same figures.
    let (code, json, stderr) = run(&dir, &["diff", "old.die", "new.die", "--json"]);
    assert_eq!(code, Some(1), "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&json).expect("diff --json parses");
    assert_eq!(doc["changed"], true);
    let decls = doc["declarations"].as_array().expect("declarations");
    let moved: Vec<&serde_json::Value> = decls
        .iter()
        .filter(|d| d["status"] != "unchanged")
        .collect();
    assert_eq!(moved.len(), 1, "{json}");
    assert_eq!(moved[0]["name"], "wheel_arch");
    assert_eq!(moved[0]["status"], "changed");
    assert_eq!(
        moved[0]["deviation"]["max_mm"].as_f64(),
        Some(max),
        "{json}"
    );
    let binder = decls
        .iter()
        .find(|d| d["name"] == "binder")
        .expect("binder");
    assert_eq!(binder["status"], "unchanged");
}

#[test]
fn an_edited_comment_is_no_change_and_a_rename_is_a_rename() {
    let dir = common::fresh_dir("cli_diff", "comment_rename");
    let old = fender();
    std::fs::write(dir.join("old.die"), &old).expect("write");
    let commented = format!(
        "// a new first line moves every declaration down\n{}",
        old.replace(
            "// the height runs out over the last 40 mm",
            "//   reworded"
        )
        .replace("bead wheel_arch {", "bead   wheel_arch  {")
    );
    std::fs::write(dir.join("commented.die"), commented).expect("write");
    let (code, stdout, stderr) = run(&dir, &["diff", "old.die", "commented.die"]);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    assert!(stdout.contains("no change ("), "{stdout}");

    std::fs::write(
        dir.join("renamed.die"),
        old.replace("bead wheel_arch {", "bead arch_bead {"),
    )
    .expect("write");
    let (code, stdout, stderr) = run(&dir, &["diff", "old.die", "renamed.die"]);
    assert_eq!(code, Some(1), "{stdout}{stderr}");
    assert!(
        stdout.contains("renamed  bead wheel_arch -> arch_bead"),
        "{stdout}"
    );
    assert!(!stdout.contains("removed"), "{stdout}");
    assert!(!stdout.contains("added"), "{stdout}");

    // A change that moves no geometry: the line bead's restraining force.
    std::fs::write(
        dir.join("force.die"),
        old.replacen("force = 250", "force = 300", 1),
    )
    .expect("write");
    let (code, stdout, stderr) = run(&dir, &["diff", "old.die", "force.die"]);
    assert_eq!(code, Some(1), "{stdout}{stderr}");
    assert!(stdout.contains("changed  bead wheel_arch"), "{stdout}");
    assert!(
        stdout.contains("quality line_bead.force: 250 N/mm -> 300 N/mm"),
        "{stdout}"
    );
}

#[test]
fn rev_reads_the_old_version_from_git() {
    let dir = common::fresh_dir("cli_diff", "rev");
    let git = |args: &[&str]| {
        let out = std::process::Command::new("git")
            .current_dir(&dir)
            .args(["-c", "user.name=t", "-c", "user.email=t@example.com"])
            .args(args)
            .output()
            .expect("run git");
        assert!(out.status.success(), "git {args:?}: {out:?}");
    };
    let script = "units mm deg\nlet a = line_between((0, 0, 0), (100, 0, 0))\nlet b = 2 mm\n";
    std::fs::write(dir.join("part.die"), script).expect("write");
    git(&["init", "-q"]);
    git(&["add", "part.die"]);
    git(&["commit", "-q", "-m", "first"]);
    let (code, stdout, stderr) = run(&dir, &["diff", "part.die", "--rev", "HEAD"]);
    assert_eq!(code, Some(0), "the committed file: {stdout}{stderr}");
    std::fs::write(
        dir.join("part.die"),
        script.replace("(100, 0, 0)", "(100, 3, 0)"),
    )
    .expect("write");
    let (code, stdout, stderr) = run(&dir, &["diff", "part.die", "--rev", "HEAD"]);
    assert_eq!(code, Some(1), "{stdout}{stderr}");
    assert!(stdout.contains("--- HEAD:part.die"), "{stdout}");
    let max = largest_on(&stdout, "changed  let a:");
    assert!((max - 3.0).abs() < 1e-3, "{stdout}");

    let (code, _, stderr) = run(&dir, &["diff", "part.die", "--rev", "no-such-rev"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("git cannot show `no-such-rev:part.die`"),
        "{stderr}"
    );
}

#[test]
fn usage_errors_exit_2() {
    let dir = common::fresh_dir("cli_diff", "usage");
    std::fs::write(dir.join("a.die"), "let b = 2 mm\n").expect("write");
    let (code, _, stderr) = run(&dir, &["diff", "a.die"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("--rev HEAD"), "{stderr}");
    let (code, _, stderr) = run(&dir, &["diff", "a.die", "missing.die"]);
    assert_eq!(code, Some(2), "{stderr}");
    let (code, _, stderr) = run(&dir, &["diff", "a.die", "--rev=-x"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("is not a revision"), "{stderr}");
    // Outside any git repository (the target folder is, unless it lies in one).
    let in_git = std::process::Command::new("git")
        .current_dir(&dir)
        .args(["rev-parse", "--show-toplevel"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !in_git {
        let (code, _, stderr) = run(&dir, &["diff", "a.die", "--rev", "HEAD"]);
        assert_eq!(code, Some(2), "{stderr}");
        assert!(stderr.contains("is not in a git repository"), "{stderr}");
    }
    // A version with errors is named.
    std::fs::write(dir.join("bad.die"), "let b = 2 mm + 3 deg\n").expect("write");
    let (code, _, stderr) = run(&dir, &["diff", "a.die", "bad.die", "--color", "never"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("the new version (`bad.die`)"), "{stderr}");
    assert!(stderr.contains("die::unit_mismatch"), "{stderr}");
}

#[test]
fn git_diff_runs_dieface_through_the_wrapper_script() {
    let dir = common::fresh_dir("cli_diff", "git_wrapper");
    let wrapper = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/git-diff-die");
    let git = |args: &[&str]| {
        let out = std::process::Command::new("git")
            .current_dir(&dir)
            .env("DIEFACE", env!("CARGO_BIN_EXE_dieface"))
            .args(["-c", "user.name=t", "-c", "user.email=t@example.com"])
            .args(args)
            .output()
            .expect("run git");
        assert!(out.status.success(), "git {args:?}: {out:?}");
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    // An import next to the script: the old version, a temporary copy, must still find
    // it (`--as`).
    std::fs::create_dir_all(dir.join("die")).expect("folder");
    std::fs::write(dir.join("die/sizes.die"), "let reach = 100 mm\n").expect("write");
    let script = "units mm deg\nimport \"sizes.die\" as s\nlet a = line_between((0, 0, 0), (s.reach, 0, 0))\n";
    std::fs::write(dir.join("die/part.die"), script).expect("write");
    std::fs::write(dir.join(".gitattributes"), "*.die diff=dieface\n").expect("write");
    git(&["init", "-q"]);
    git(&[
        "config",
        "diff.dieface.command",
        wrapper.to_str().expect("utf-8 path"),
    ]);
    git(&["add", "."]);
    git(&["commit", "-q", "-m", "first"]);
    std::fs::write(dir.join("die/part.die"), script.replace("0, 0))", "0, 4))")).expect("write");
    let shown = git(&["diff"]);
    assert!(shown.contains("dieface diff die/part.die"), "{shown}");
    let max = largest_on(&shown, "changed  let a:");
    assert!((max - 4.0).abs() < 1e-3, "{shown}");
    // A comment edit is no change.
    std::fs::write(dir.join("die/part.die"), format!("// note\n{script}")).expect("write");
    let shown = git(&["diff"]);
    assert!(shown.contains("no change ("), "{shown}");
}

/// Green through red: a distance above about a quarter of the scale.
fn warm(p: &[u8; 3]) -> bool {
    p[0].max(p[1]) > 60 && p[0].max(p[1]) as u16 > p[2] as u16 + 40
}

fn bluish(p: &[u8; 3]) -> bool {
    p[2] > 80 && p[2] as u16 > 2 * p[0] as u16 && p[2] as u16 * 2 > 3 * p[1] as u16
}

#[test]
fn the_diff_picture_shows_the_moved_bead_red_on_a_blue_die_face() {
    let dir = common::fresh_dir("cli_diff", "picture");
    let old = fender();
    std::fs::write(dir.join("old.die"), &old).expect("write");
    std::fs::write(dir.join("new.die"), old.replace(BEAD_LINE, BEAD_LINE_MOVED)).expect("write");
    std::fs::write(
        dir.join("same.die"),
        old.replacen("//", "// an edited comment:", 1),
    )
    .expect("write");
    let args = |new: &str, out: &str| {
        run(
            &dir,
            &[
                "diff", "old.die", new, "--png", out, "--view", "top", "--size", "600x450",
            ],
        )
    };
    let (code, stdout, stderr) = args("new.die", "moved.png");
    assert_eq!(code, Some(1), "{stdout}{stderr}");
    let (code, stdout, stderr) = args("same.die", "same.png");
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    let moved = common::picture::Image::read(&dir.join("moved.png"))
        .pixels()
        .collect::<Vec<_>>();
    let same = common::picture::Image::read(&dir.join("same.png"))
        .pixels()
        .collect::<Vec<_>>();
    assert_eq!(moved.len(), 600 * 450);
    // Both show the die face, nearly all of it at the scale's cold end (blue); both
    // carry the scale bar, which runs from blue to red.
    let blue = |px: &[[u8; 3]]| px.iter().filter(|p| bluish(p)).count();
    let red = |px: &[[u8; 3]]| px.iter().filter(|p| warm(p)).count();
    assert!(blue(&moved) > 20_000, "{} blue pixels", blue(&moved));
    assert!(blue(&same) > 20_000, "{} blue pixels", blue(&same));
    // The moved bead is drawn green to red (its flanks lie up to 5 mm, the top of the
    // scale, off the old bead's surface) where nothing unchanged is: the picture of an
    // edit that moved nothing has only the bar's green and red.
    assert!(
        red(&moved) > red(&same) + 300,
        "green to red pixels: moved {}, unchanged {}",
        red(&moved),
        red(&same)
    );
    // The same input draws the same bytes.
    let again = args("new.die", "again.png");
    assert_eq!(again.0, Some(1));
    assert_eq!(
        std::fs::read(dir.join("moved.png")).expect("read"),
        std::fs::read(dir.join("again.png")).expect("read")
    );
    // A picture that is not a PNG is a usage error, and nothing is built.
    let (code, _, stderr) = args("new.die", "moved.jpg");
    assert_eq!(code, Some(2), "{stderr}");
}
