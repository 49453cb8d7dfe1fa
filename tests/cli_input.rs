//! Input of any size, line length, encoding and line ending is diagnosed through the
//! real binary, never a crash (issue 14): the exit code and where the message points.
//! Huge inputs are made here at run time, never committed.

mod common;

use std::path::{Path, PathBuf};

/// A fresh folder for one test under the target's temp dir.
fn temp(name: &str) -> PathBuf {
    common::fresh_dir("cli_input", name)
}

/// Runs dieface in `dir`: exit code, stdout, stderr.
fn dieface(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    common::run_dieface(dir, args)
}

/// `check` of `bytes` written as `name` in a fresh folder.
fn check(test: &str, name: &str, bytes: &[u8], extra: &[&str]) -> (Option<i32>, String) {
    let dir = temp(test);
    std::fs::write(dir.join(name), bytes).expect("write");
    let mut args = vec!["check", "--color", "never", name];
    args.extend_from_slice(extra);
    let (code, _, stderr) = dieface(&dir, &args);
    (code, stderr)
}

#[test]
fn an_8_mib_line_is_diagnosed_at_its_column_in_check_and_build() {
    let dir = temp("long_line");
    let text = format!("let a = 1 mm {}\n", "x".repeat(8 << 20));
    std::fs::write(dir.join("l.die"), &text).expect("write");
    for args in [
        vec!["check", "--color", "never", "l.die"],
        vec!["build", "--color", "never", "l.die", "-o", "l.glb"],
    ] {
        let (code, _, stderr) = dieface(&dir, &args);
        assert_eq!(
            code,
            Some(1),
            "{args:?}: {}",
            &stderr[..stderr.len().min(2000)]
        );
        assert!(!stderr.contains("panicked"), "{stderr:.2000}");
        // The end of the file, after the 8 MiB word: the column is the whole line's.
        assert!(
            stderr.contains(&format!("l.die:1:{}", text.len())),
            "{stderr:.2000}"
        );
        assert!(
            stderr.len() < 4000,
            "the line is shown as a window, not whole"
        );
        assert!(stderr.contains("help:"), "{stderr:.2000}");
    }
    assert!(!dir.join("l.glb").exists());
}

#[test]
fn a_label_deep_in_a_long_line_keeps_its_column() {
    let line = format!("let a = [{}1 mm + 2 deg]\n", "1, ".repeat(40_000));
    let (code, stderr) = check("long_line_label", "m.die", line.as_bytes(), &[]);
    assert_eq!(code, Some(1), "{stderr:.2000}");
    assert!(stderr.contains("die::unit_mismatch"), "{stderr:.2000}");
    let col = line.find("1 mm + 2 deg").expect("in the line") + 1;
    assert!(stderr.contains(&format!("m.die:1:{col}")), "{stderr:.2000}");
    assert!(
        stderr.contains("1 mm + 2 deg"),
        "the label's window: {stderr:.2000}"
    );
}

#[test]
fn long_flat_chains_are_a_nesting_diagnostic_not_a_stack_overflow() {
    let n = 110_000;
    let chains = [
        ("sum", format!("let a = {}1\n", "1 + ".repeat(n))),
        ("product", format!("let a = {}1\n", "2 * ".repeat(n))),
        (
            "pipe",
            format!("fn f(x) = x\nlet a = 1{}\n", " |> f".repeat(n)),
        ),
        ("and", format!("let a = {}true\n", "true and ".repeat(n))),
        ("or", format!("let a = {}true\n", "false or ".repeat(n))),
        (
            "field",
            format!("let b = {{ x: 1 }}\nlet a = b{}\n", ".x".repeat(n)),
        ),
        (
            "index",
            format!("let b = [1]\nlet a = b{}\n", "[0]".repeat(n)),
        ),
        ("call", format!("fn f() = f\nlet a = f{}\n", "()".repeat(n))),
        ("negation", format!("let a = {}1\n", "- ".repeat(n))),
        ("not", format!("let a = {}true\n", "not ".repeat(n))),
    ];
    for (what, text) in chains {
        let (code, stderr) = check("chains", "c.die", text.as_bytes(), &[]);
        assert_eq!(code, Some(1), "{what}: {stderr:.2000}");
        assert!(
            stderr.contains("levels deep") && stderr.contains("--limit nesting="),
            "{what}: {stderr:.3000}"
        );
        assert!(stderr.contains("c.die:"), "{what}: {stderr:.2000}");
    }
    // A comparison chain says comparisons do not chain, at the second one.
    let text = format!("let a = {}1\n", "1 < ".repeat(n));
    let (code, stderr) = check("chains", "c.die", text.as_bytes(), &[]);
    assert_eq!(code, Some(1));
    assert!(stderr.contains("comparisons cannot be chained") && stderr.contains("c.die:1:15"));
    // Raising the limit lets a longer chain through.
    let text = format!("let a = {}1\n", "1 + ".repeat(200));
    assert_eq!(check("chains", "c.die", text.as_bytes(), &[]).0, Some(1));
    let (code, stderr) = check(
        "chains",
        "c.die",
        text.as_bytes(),
        &["--limit", "nesting=300"],
    );
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn a_huge_tolerance_or_define_is_held_to_the_nesting_limit() {
    let dir = temp("huge_values");
    std::fs::write(
        dir.join("s.die"),
        "param tip_angle = 2 deg\nlet a = tip_angle * 2\n",
    )
    .expect("write");
    let sum = format!("1mm{}", "+1mm".repeat(6000));
    let (code, _, stderr) = dieface(
        &dir,
        &["build", "s.die", "-o", "s.glb", "--tolerance", &sum],
    );
    assert_eq!(code, Some(2), "{stderr:.2000}");
    assert!(stderr.contains("--tolerance 1mm+1mm") && stderr.contains("levels deep"));
    assert!(stderr.len() < 2000, "the text is not echoed whole");
    let define = format!("tip_angle={}", sum.replace("mm", "deg"));
    let (code, _, stderr) = dieface(&dir, &["check", "--color", "never", "-D", &define, "s.die"]);
    assert_eq!(code, Some(1), "{stderr:.2000}");
    assert!(stderr.contains("[-D tip_angle:1:"), "{stderr:.2000}");
    assert!(stderr.contains("levels deep"), "{stderr:.2000}");
}

#[test]
fn a_bare_define_takes_the_files_unit_as_in_the_language() {
    let dir = temp("bare_define");
    std::fs::write(
        dir.join("s.die"),
        "units cm rad\nparam tip_angle = 0.1 rad\nparam width = 2 cm\nlet a = tip_angle\nlet w = width\n",
    )
    .expect("write");
    let (code, stdout, stderr) = dieface(
        &dir,
        &[
            "inspect",
            "--json",
            "-D",
            "tip_angle=0.5",
            "-D",
            "width=3",
            "s.die",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).expect("json");
    let text = json.to_string();
    assert!(text.contains("30"), "width 3 cm is 30 mm: {text:.3000}");
    // A string for an angle is still refused, pointing at the -D text.
    let (code, _, stderr) = dieface(
        &dir,
        &[
            "check",
            "--color",
            "never",
            "-D",
            "tip_angle=\"x\"",
            "s.die",
        ],
    );
    assert_eq!(code, Some(1));
    assert!(stderr.contains("[-D tip_angle:1:1]"), "{stderr}");
}

#[test]
fn cr_only_line_ends_end_comments_and_count_as_lines() {
    let (code, stderr) = check(
        "cr",
        "cr.die",
        b"let a = 1 mm // first\rlet b = a + 2 mm\rlet c = b + 3 deg\r",
        &[],
    );
    assert_eq!(
        code,
        Some(1),
        "the comment must not swallow the rest: {stderr}"
    );
    assert!(stderr.contains("die::unit_mismatch"), "{stderr}");
    assert!(stderr.contains("cr.die:3:9"), "line 3: {stderr}");
    assert!(
        stderr.contains(" 3 │ let c = b + 3 deg"),
        "printed as its own line: {stderr}"
    );
    // Mixed line ends.
    let (code, stderr) = check(
        "cr",
        "mixed.die",
        b"let a = 1 mm\r\nlet b = 2 mm\rlet c = x\n",
        &[],
    );
    assert_eq!(code, Some(1));
    assert!(stderr.contains("mixed.die:3:9"), "{stderr}");
}

#[test]
fn invalid_utf8_names_the_byte_offset_and_a_bom_is_fine() {
    let (code, stderr) = check(
        "utf8",
        "bad.die",
        b"let a = 1 mm\nlet b = \"\xff\xfe\"\n",
        &[],
    );
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("die::not_utf8"), "{stderr}");
    assert!(
        stderr.contains("byte 0xFF at offset 22 (line 2, column 10)"),
        "{stderr}"
    );
    assert!(stderr.contains("bad.die:2:10"), "{stderr}");
    let (code, stderr) = check("utf8", "bom.die", b"\xef\xbb\xbflet a = 1 mm\n", &[]);
    assert_eq!(code, Some(0), "{stderr}");
    // A module that is not UTF-8: at its import.
    let dir = temp("utf8_import");
    std::fs::write(dir.join("m.die"), b"let x = \"\xc3\x28\"\n").expect("write");
    std::fs::write(dir.join("s.die"), "import \"m.die\" as m\nlet y = m.x\n").expect("write");
    let (code, _, stderr) = dieface(&dir, &["check", "--color", "never", "s.die"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("die::not_utf8") && stderr.contains("s.die:1:8"),
        "{stderr}"
    );
}

#[test]
fn a_file_over_the_file_bytes_limit_is_a_diagnostic() {
    let (code, stderr) = check(
        "file_bytes",
        "big.die",
        b"let a = 1 mm\nlet b = 2 mm\n",
        &["--limit", "file_bytes=10"],
    );
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("die::limit::file_bytes"), "{stderr}");
    assert!(stderr.contains("--limit file_bytes=N"), "{stderr}");
}

#[test]
fn a_block_after_let_param_or_product_is_a_syntax_error() {
    for (kind, help) in [
        ("let", "let a = { x: 1, y: 2 }"),
        ("param", "param a = value"),
        ("product", "a product declaration names the finished part"),
    ] {
        let text = format!("{kind} a {{ x = 1 }}\n");
        let (code, stderr) = check("value_block", "b.die", text.as_bytes(), &[]);
        assert_eq!(code, Some(1), "{stderr}");
        assert!(
            stderr.contains(&format!("`{kind}` takes `= value`, not a block of fields")),
            "{stderr}"
        );
        let col = kind.len() + 4;
        assert!(
            stderr.contains(&format!("b.die:1:{col}")),
            "at the `{{`: {stderr}"
        );
        assert!(stderr.contains(help), "{stderr}");
    }
}

#[test]
fn invisible_characters_are_named_by_code_point() {
    for (c, name) in [
        ('\u{200B}', "U+200B ZERO WIDTH SPACE"),
        ('\0', "U+0000 NULL"),
        ('\u{A0}', "U+00A0 NO-BREAK SPACE"),
        ('\u{202E}', "U+202E RIGHT-TO-LEFT OVERRIDE"),
    ] {
        let text = format!("let a = 1 mm\nlet wi{c}dth = 2 mm\n");
        let (code, stderr) = check("invisible", "i.die", text.as_bytes(), &[]);
        assert_eq!(code, Some(1), "{stderr}");
        assert!(stderr.contains(name), "{name}: {stderr}");
        assert!(stderr.contains("i.die:2:7"), "{stderr}");
        assert!(stderr.contains("help:"), "{stderr}");
        // One that would print nothing, or turn the line around, is not printed itself (a
        // no-break space prints as the space it looks like).
        if c != '\u{A0}' {
            assert!(!stderr.contains(c), "not printed itself: {stderr:?}");
        }
    }
}

#[test]
fn a_missing_brace_labels_the_block_it_leaves_open() {
    let text = "bead rib {\n    height = 6 mm\n\nlet c = 2\nfn f(x) = x\n";
    let (code, stderr) = check("missing_brace", "m.die", text.as_bytes(), &[]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("this block is not closed"), "{stderr}");
    assert!(
        stderr.contains(" 1 │ bead rib {"),
        "the `{{` is shown: {stderr}"
    );
    assert!(
        stderr.contains("is a `}` missing before line 4?"),
        "{stderr}"
    );
}

#[test]
fn a_broken_module_reports_its_own_error_not_a_missing_field() {
    let dir = temp("broken_module");
    std::fs::write(dir.join("m.die"), "let x = 1 mm +\n").expect("write");
    std::fs::write(dir.join("n.die"), "let x = 1 mm + 2 deg\nlet z = 2\n").expect("write");
    std::fs::write(
        dir.join("s.die"),
        "import \"m.die\" as m\nimport \"n.die\" as n\nlet y = m.x\nlet w = n.x\nlet v = n.z\n",
    )
    .expect("write");
    let (code, _, stderr) = dieface(&dir, &["check", "--color", "never", "s.die"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(!stderr.contains("has no field"), "{stderr}");
    assert!(
        stderr.contains("[m.die:1:15]") && stderr.contains("[n.die:1:9]"),
        "{stderr}"
    );
    assert!(stderr.contains("2 problems"), "{stderr}");
}

/// A tolerance finer than a nanometre is refused at once, from the command line and
/// from the script (a fuzzed `param tolerance = 1e-12 mm` spent 11 s tessellating).
#[test]
fn a_tolerance_finer_than_a_nanometre_is_refused() {
    let dir = temp("fine_tolerance");
    std::fs::write(
        dir.join("s.die"),
        "let a = sketch(top) { from (0, 0); line to (10, 0) }\n",
    )
    .expect("write");
    let (code, _, stderr) = dieface(
        &dir,
        &["build", "s.die", "-o", "s.glb", "--tolerance", "1e-9mm"],
    );
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("at least 0.000001 mm"), "{stderr}");
    std::fs::write(
        dir.join("p.die"),
        "param tolerance = 1e-12 mm\nlet a = sketch(top) { from (0, 0); line to (10, 0) }\n",
    )
    .expect("write");
    let (code, _, stderr) = dieface(&dir, &["build", "p.die", "-o", "p.glb", "--color", "never"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("die::bad_tolerance"), "{stderr}");
    assert!(!dir.join("p.glb").exists());
    // A nanometre itself is accepted.
    let (code, _, stderr) = dieface(
        &dir,
        &["build", "s.die", "-o", "s.glb", "--tolerance", "1e-6mm"],
    );
    assert_eq!(code, Some(0), "{stderr}");
}
