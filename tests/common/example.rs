//! Any example under `examples/` evaluated through the language, shared by the feature
//! tests that check every example (the fender, the door).

#![allow(dead_code)] // each test file uses its own subset

use std::path::Path;

use dieface::eval::features::Built;
use dieface::eval::{Data, Engine, Value};

/// Every declaration of `examples/<path>` with its value, in source order; the example
/// must evaluate without a diagnostic.
pub fn example_values(path: &str) -> Vec<(String, Value)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut engine = Engine::new(Some(root.clone()));
    let outcome = engine
        .evaluate_path(&root.join(path))
        .expect("readable example");
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

/// Every feature among `values`, with its declaration's name, in source order.
pub fn features(values: &[(String, Value)]) -> Vec<(String, Built)> {
    values
        .iter()
        .filter_map(|(name, v)| match &v.data {
            Data::Record(r) => r.feature.clone().map(|f| (name.clone(), f)),
            _ => None,
        })
        .collect()
}
