//! Snapshots over every example script: the AST with spans, and an evaluation summary
//! per declaration (kind, value type, dimensions, bounds; floats rounded). Every
//! example must evaluate without a diagnostic.

mod common;

use std::path::{Path, PathBuf};

use dieface::eval::summary::describe;
use dieface::eval::Engine;
use dieface::syntax::{parse, print::print_ast, FileId};

fn examples() -> Vec<PathBuf> {
    common::die_files("examples")
}

fn snapshot_name(path: &Path) -> String {
    let rel = path
        .strip_prefix(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))
        .expect("under examples/");
    rel.with_extension("")
        .display()
        .to_string()
        .replace(['/', '\\'], "__")
}

#[test]
fn every_example_has_an_ast_snapshot() {
    let files = examples();
    assert!(files.len() >= 3, "examples/ holds the example scripts");
    for path in files {
        let text = std::fs::read_to_string(&path).expect("readable example");
        let ast = parse(&text, FileId(0))
            .unwrap_or_else(|d| panic!("{} does not parse: {}", path.display(), d.message));
        insta::assert_snapshot!(
            format!("ast__{}", snapshot_name(&path)),
            print_ast(&ast, &text)
        );
    }
}

#[test]
fn every_example_evaluates_cleanly_and_has_a_summary_snapshot() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    for path in examples() {
        let mut engine = Engine::new(Some(root.clone()));
        let outcome = engine.evaluate_path(&path).expect("readable example");
        let rendered: Vec<String> = outcome
            .diagnostics
            .iter()
            .map(|d| engine.sources.render(d, false))
            .collect();
        assert!(
            rendered.is_empty(),
            "{} has problems:\n{}",
            path.display(),
            rendered.join("\n")
        );
        let summary: Vec<String> = outcome
            .decls
            .iter()
            .map(|d| {
                let (line, _) = engine.sources.line_col(d.span);
                format!(
                    "{} {} (line {line}): {}",
                    d.kind,
                    d.name,
                    describe(d.value.as_ref())
                )
            })
            .collect();
        insta::assert_snapshot!(
            format!("eval__{}", snapshot_name(&path)),
            summary.join("\n")
        );
    }
}
