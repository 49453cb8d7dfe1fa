//! The bad-input corpus: every `tests/diagnostics/*.die` holds one mistake a designer
//! makes (its first line says which). Each must produce at least one diagnostic with a
//! stable code, and the rendered diagnostics (no colour) are snapshots reviewed as a
//! user would read them.

use std::path::{Path, PathBuf};

use dieface::eval::Engine;

fn corpus() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/diagnostics");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the corpus folder exists")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "die"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_mistake_in_the_corpus_is_diagnosed() {
    let files = corpus();
    assert!(
        files.len() >= 40,
        "at least 40 distinct mistakes, found {}",
        files.len()
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/diagnostics");
    let mut codes = std::collections::BTreeSet::new();
    for path in files {
        let text = std::fs::read_to_string(&path).expect("readable");
        assert!(
            text.starts_with("// "),
            "{}: the first line names the mistake",
            path.display()
        );
        let mut engine = Engine::new(Some(root.clone()));
        let outcome = engine.evaluate_path(&path).expect("readable");
        assert!(
            !outcome.diagnostics.is_empty(),
            "{}: no diagnostic for this mistake",
            path.display()
        );
        let mut rendered = String::new();
        for d in &outcome.diagnostics {
            assert!(d.code.starts_with("die::"), "stable code");
            codes.insert(d.code);
            rendered.push_str(&engine.sources.render(d, false));
            rendered.push('\n');
        }
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("corpus")
            .to_string();
        insta::assert_snapshot!(format!("diag__{name}"), rendered);
    }
    assert!(
        codes.len() >= 15,
        "the corpus exercises many kinds of mistakes: {codes:?}"
    );
}
