//! The fender example evaluated through the language, shared by the feature tests.

#![allow(dead_code)] // each test file uses its own subset

use std::path::Path;

use dieface::eval::{Engine, Value};

#[path = "script.rs"]
mod script;

pub use script::clean_values;

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
