//! The fender example evaluated through the language, shared by the feature tests, and
//! the check that an evaluation came out clean.

#![allow(dead_code)] // each test file uses its own subset

use std::path::Path;

use dieface::eval::{Engine, Outcome, Value};

/// Every declaration of `examples/fender/fender.die` with its value, in source order;
/// the example must evaluate without a diagnostic.
pub fn fender_values() -> Vec<(String, Value)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut engine = Engine::new(Some(root.clone()));
    let outcome = engine
        .evaluate_path(&root.join("fender/fender.die"))
        .expect("readable example");
    clean_values(&engine, &outcome)
}

/// Every declaration of an evaluation with its value, in source order; panics with the
/// rendered diagnostics if there are any.
pub fn clean_values(engine: &Engine, outcome: &Outcome) -> Vec<(String, Value)> {
    let rendered: Vec<String> = outcome
        .diagnostics
        .iter()
        .map(|d| engine.sources.render(d, false))
        .collect();
    assert!(rendered.is_empty(), "{}", rendered.join("\n"));
    outcome
        .decls
        .iter()
        .filter_map(|d| d.value.clone().map(|v| (d.name.clone(), v)))
        .collect()
}
