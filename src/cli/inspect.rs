//! `dieface inspect FILE [--json]`: what each declaration evaluated to.
//!
//! Text mode prints one line per declaration, `kind name (line N, 1.2 ms): summary`,
//! with the stable summary of `eval::summary` (degree, control points, bounds, length)
//! plus the area of surfaces and meshes. `--json` prints the full evaluated data in the
//! schema documented in `docs/inspect-json.md`. Both reports are made by
//! [`crate::pipeline::report`]; this command evaluates and prints. Exit codes as for
//! `check`.

use std::process::ExitCode;

use crate::pipeline::report::{inspect_json, inspect_lines};

use super::{ScriptArgs, SCRIPT_ERROR};

/// `dieface inspect`.
pub(crate) fn run(script: &ScriptArgs, json: bool) -> ExitCode {
    let color = script.color();
    let (engine, outcome) = match script.evaluated() {
        Ok(done) => done,
        Err(code) => return code,
    };
    for d in &outcome.diagnostics {
        eprintln!("{}", engine.sources.render(d, color));
    }
    let timings = engine.last_timings();
    if json {
        match serde_json::to_string_pretty(&inspect_json(&outcome, &engine.sources, timings)) {
            Ok(s) => println!("{s}"),
            Err(e) => {
                eprintln!("error: cannot write JSON: {e}");
                return ExitCode::from(SCRIPT_ERROR);
            }
        }
    } else {
        for line in inspect_lines(&outcome, &engine.sources, timings) {
            println!("{line}");
        }
    }
    if outcome.diagnostics.is_empty() {
        ExitCode::SUCCESS
    } else {
        let n = outcome.diagnostics.len();
        eprintln!(
            "{}: {n} problem{}",
            script.file.display(),
            if n == 1 { "" } else { "s" }
        );
        ExitCode::from(SCRIPT_ERROR)
    }
}
