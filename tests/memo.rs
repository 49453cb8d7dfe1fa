//! Memoized evaluation: editing one declaration re-evaluates only it and what depends
//! on it, counted by the engine.

use dieface::eval::Engine;

const SCRIPT: &str = r#"
let width = 1100 mm
let depth = 700 mm
let half = width / 2
fn corner(r) = r * 2
let profile = sketch(top) {
    from (-half, -depth / 2)
    line to (half, -depth / 2)
    fillet 60 mm
    line to (half, depth / 2)
    line to (-half, depth / 2)
    close
}
let doubled = corner(depth)
let unrelated = 3 deg + 4 deg
"#;

#[test]
fn editing_one_declaration_reevaluates_only_it_and_its_dependents() {
    let mut engine = Engine::new(None);
    let first = engine.evaluate("memo.die", SCRIPT, None);
    assert!(first.diagnostics.is_empty(), "{:?}", first.diagnostics);
    assert_eq!(
        engine.evaluation_count(),
        6,
        "cold run evaluates every declaration once"
    );

    // Unchanged text: nothing re-runs.
    engine.evaluate("memo.die", SCRIPT, None);
    assert_eq!(engine.evaluation_count(), 6);
    assert!(engine.last_evaluated().is_empty());

    // Edit `width`: it, `half` and `profile` re-run; `depth`, `doubled`, `unrelated` do not.
    let edited = SCRIPT.replace("let width = 1100 mm", "let width = 1150 mm");
    let out = engine.evaluate("memo.die", &edited, None);
    assert!(out.diagnostics.is_empty());
    let mut ran = engine.last_evaluated().to_vec();
    ran.sort();
    assert_eq!(ran, ["half", "profile", "width"]);
    assert_eq!(engine.evaluation_count(), 9);

    // Edit the function: only the declaration that calls it re-runs.
    let edited2 = edited.replace("fn corner(r) = r * 2", "fn corner(r) = r * 3");
    engine.evaluate("memo.die", &edited2, None);
    assert_eq!(engine.last_evaluated(), ["doubled"]);
}

#[test]
fn memoized_values_follow_their_declarations_when_text_above_moves() {
    let mut engine = Engine::new(None);
    engine.evaluate("move.die", "let a = 5 mm\nlet b = (1, 2, 3)\n", None);
    // Insert a long comment above: no declaration re-runs, yet `b`'s span points at its
    // new place.
    let moved =
        "// a long comment that shifts everything below it\nlet a = 5 mm\nlet b = (1, 2, 3)\n";
    let out = engine.evaluate("move.die", moved, None);
    assert!(
        engine.last_evaluated().is_empty(),
        "{:?}",
        engine.last_evaluated()
    );
    let b = out
        .decls
        .iter()
        .find(|d| d.name == "b")
        .and_then(|d| d.value.clone())
        .expect("b has a value");
    assert_eq!(&moved[b.span.range()], "(1, 2, 3)");
}

/// The fender example: changing the crown height re-evaluates the height function's
/// users (the control net, the panel, its outline, the product trimmed there and the
/// step draw that meets it) and nothing else.
#[test]
fn editing_the_fender_example_reevaluates_only_the_dependents() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fender");
    let text = std::fs::read_to_string(dir.join("fender.die")).expect("the example exists");
    let mut engine = Engine::new(Some(dir.clone()));
    let cold = engine.evaluate("fender.die", &text, Some(dir.clone()));
    assert!(cold.diagnostics.is_empty());
    let after_cold = engine.evaluation_count();
    assert!(
        after_cold >= 14,
        "cold run evaluates every declaration (and the imported modules')"
    );

    let edited = text.replace("let crown = 48 mm", "let crown = 52 mm");
    assert_ne!(edited, text, "the example declares `crown`");
    let warm = engine.evaluate("fender.die", &edited, Some(dir));
    assert!(warm.diagnostics.is_empty());
    let mut ran = engine.last_evaluated().to_vec();
    ran.sort();
    assert_eq!(
        ran,
        ["addendum", "crown", "fender", "net", "outline", "panel"]
    );
    assert_eq!(engine.evaluation_count(), after_cold + 6);

    // Redrawing one side's binder wrap rebuilds that sketch, the punch opening, the
    // blankholder around it, the step draw that reaches it and the beads on the
    // blankholder, and leaves the product alone.
    let rewrapped = edited.replace("(0, -78)", "(0, -76)");
    assert_ne!(
        rewrapped, edited,
        "the example's front wrap passes (0, -78)"
    );
    let warm = engine.evaluate("fender.die", &rewrapped, Some(dir_again()));
    assert!(warm.diagnostics.is_empty());
    let mut ran = engine.last_evaluated().to_vec();
    ran.sort();
    assert_eq!(
        ran,
        [
            "addendum",
            "binder",
            "opening",
            "rear_corner",
            "wheel_arch",
            "wrap_front"
        ]
    );
}

fn dir_again() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fender")
}

/// A declaration that reads a file (`read_obj`) is re-evaluated, with its dependents,
/// when the file's content changes, even though the script text did not.
#[test]
fn editing_a_file_read_by_a_builtin_reevaluates_its_readers() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("memo_obj");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let dir = dir.canonicalize().expect("canonical temp dir");
    let obj = dir.join("part.obj");
    std::fs::write(&obj, "v 0 0 0\nv 100 0 0\nv 0 100 0\nf 1 2 3\n").expect("write obj");
    let script = "let mesh = read_obj(\"part.obj\")\nproduct part = mesh\nlet other = 5 mm\n";
    let mut engine = Engine::new(Some(dir.clone()));
    let first = engine.evaluate("part.die", script, Some(dir.clone()));
    assert!(first.diagnostics.is_empty(), "{:?}", first.diagnostics);
    assert_eq!(engine.read_files(), std::slice::from_ref(&obj));

    engine.evaluate("part.die", script, Some(dir.clone()));
    assert!(engine.last_evaluated().is_empty(), "nothing changed");

    std::fs::write(&obj, "v 0 0 0\nv 200 0 0\nv 0 100 0\nf 1 2 3\n").expect("edit obj");
    engine.evaluate("part.die", script, Some(dir));
    let mut ran = engine.last_evaluated().to_vec();
    ran.sort();
    assert_eq!(ran, ["mesh", "part"]);
}

/// Inside a feature, pieces are memoized by their inputs: editing the front binder
/// wrap of the fender re-runs the punch opening, which makes the front side's two-view
/// curve again and takes the other three sides from the memo; the result is the same
/// opening a fresh engine builds. An edit the opening does not see keeps its pieces.
#[test]
fn a_wrap_edit_rebuilds_only_that_side_of_the_opening() {
    use dieface::die::punch_opening::PunchOpening;
    use dieface::eval::Data;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/fender")
        .canonicalize()
        .unwrap();
    let text = std::fs::read_to_string(dir.join("fender.die")).unwrap();
    let rewrapped = text.replacen("(0, -78)", "(0, -76)", 1);
    let unrelated = text.replacen("1700 mm, 1400 mm, 80 mm", "1720 mm, 1400 mm, 80 mm", 1);
    assert!(
        rewrapped != text && unrelated != text,
        "the example's wrap and blank"
    );
    let opening = |outcome: &dieface::eval::Outcome| -> PunchOpening {
        let d = outcome.decls.iter().find(|d| d.name == "opening").unwrap();
        match &d.value.as_ref().unwrap().data {
            Data::Record(r) => r.model::<PunchOpening>().unwrap().clone(),
            _ => panic!("`opening` is a punch opening"),
        }
    };

    let mut engine = Engine::new(Some(dir.clone()));
    engine.evaluate("fender.die", &text, Some(dir.clone()));
    assert_eq!(
        engine.piece_counts(),
        (4, 0),
        "a cold build makes the four sides"
    );

    engine.evaluate("fender.die", &unrelated, Some(dir.clone()));
    assert_eq!(engine.piece_counts(), (0, 0), "the opening did not run");

    let edited = engine.evaluate("fender.die", &rewrapped, Some(dir.clone()));
    assert!(engine.last_evaluated().iter().any(|n| n == "opening"));
    assert_eq!(
        engine.piece_counts(),
        (1, 3),
        "the front side again, three kept"
    );

    let mut fresh = Engine::new(Some(dir.clone()));
    let cold = fresh.evaluate("fender.die", &rewrapped, Some(dir));
    assert_eq!(opening(&edited), opening(&cold));
}

/// Declarations run in waves of ones that use none of each other, each as late as its
/// users allow: a declaration nothing uses (as a feature mostly is) runs in the last
/// wave, beside the ends of the longest chains, not first. `last_evaluated` lists them
/// in wave order (source order within a wave).
#[test]
fn what_nothing_uses_runs_in_the_last_wave() {
    let script = r#"
let lone = 5 mm
let a = 1 mm
let b = a + 1 mm
let c = b + 1 mm
let d = c + a
let side = a * 2
"#;
    let mut engine = Engine::new(None);
    let out = engine.evaluate("waves.die", script, None);
    assert!(out.diagnostics.is_empty(), "{:?}", out.diagnostics);
    // Waves: [a], [b], [c], [d, lone, side] (`lone` and `side` are used by nothing, so
    // they join `d`, the end of the longest chain; as early as possible they would have
    // run with `a` and `b`).
    assert_eq!(
        engine.last_evaluated(),
        ["a", "b", "c", "lone", "d", "side"]
    );
}
