//! Every example's `.glb` (and `.gltf`) passes the Khronos glTF validator with no errors
//! and no warnings.
//!
//! The validator is the npm package `gltf-validator`, installed by `scripts/test`
//! (`npm ci`, from the committed `package-lock.json`) and run through
//! `tests/validate.mjs` with Node. Without it this test fails: a validator that is not
//! there must never look like a pass.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use dieface::eval::Engine;
use dieface::export::{build_scene, encode, Format};
use dieface::geom::tessellate::Tolerance;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn examples() -> Vec<PathBuf> {
    common::die_files("examples")
}

/// Builds `script` at the default 0.01 mm tolerance and writes it in `format` under
/// `target/`; returns the file.
fn build(script: &Path, format: Format) -> PathBuf {
    let mut engine = Engine::new(Some(root().join("examples")));
    let outcome = engine.evaluate_path(script).expect("readable example");
    assert!(
        outcome.diagnostics.is_empty(),
        "{} has diagnostics",
        script.display()
    );
    let tol = Tolerance::new(0.01).expect("valid tolerance");
    let scene = build_scene(&engine.die_model(&outcome), &tol)
        .unwrap_or_else(|e| panic!("{}: {e}", script.display()));
    assert!(
        !scene.nodes.is_empty(),
        "{} exports nothing",
        script.display()
    );
    let dir = root().join("target").join("gltf-validator");
    std::fs::create_dir_all(&dir).expect("target dir");
    let stem = script.file_stem().expect("file name").to_string_lossy();
    let out = dir.join(format!("{stem}.{}", format.extension()));
    std::fs::write(&out, encode(&scene, format)).expect("write");
    out
}

#[test]
fn every_example_passes_the_khronos_validator() {
    let validator = root().join("node_modules").join("gltf-validator");
    assert!(
        validator.join("package.json").is_file(),
        "the Khronos glTF validator is not installed ({} is missing): run `scripts/test` \
         (it runs `npm ci` and then `cargo test --locked`), or `npm ci` once",
        validator.display()
    );
    let mut files = Vec::new();
    for script in examples() {
        files.push(build(&script, Format::Glb));
        files.push(build(&script, Format::Gltf));
    }
    assert!(
        files.len() >= 8,
        "expected the four examples, found {files:?}"
    );
    let output = Command::new("node")
        .arg(root().join("tests").join("validate.mjs"))
        .args(&files)
        .current_dir(root())
        .output()
        .expect("`node` must be on PATH to run the glTF validator (scripts/test)");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "the validator script failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let reports: Vec<serde_json::Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON report per line"))
        .collect();
    assert_eq!(reports.len(), files.len(), "one report per file:\n{stdout}");
    let mut failures = Vec::new();
    for r in &reports {
        let count = |k: &str| r[k].as_u64().expect("a count");
        println!(
            "{}: {} errors, {} warnings, {} infos, {} hints",
            r["file"].as_str().unwrap_or("?"),
            count("errors"),
            count("warnings"),
            count("infos"),
            count("hints")
        );
        for m in r["messages"].as_array().into_iter().flatten() {
            println!(
                "  [{}] {} at {}: {}",
                m["severity"], m["code"], m["pointer"], m["message"]
            );
        }
        if count("errors") > 0 || count("warnings") > 0 {
            failures.push(r.to_string());
        }
    }
    assert!(
        failures.is_empty(),
        "glTF validator errors or warnings:\n{}",
        failures.join("\n")
    );
}
