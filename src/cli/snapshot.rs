//! `dieface snapshot FILE.die [--check | --update]`: the review snapshot `FILE.die.snap`
//! ([`crate::pipeline::snapshot`]) written, or checked against the script.
//!
//! With no flag the snapshot is written when there is none and checked when there is
//! one; `--check` only checks (a missing snapshot is an error: CI must not pass on a
//! script nobody snapshotted); `--update` writes it whatever it held. A check that fails
//! prints the changed lines as a unified diff and exits 1. Writes are atomic (a temp
//! file renamed into place). Exit codes: 0 written or matching, 1 script errors, a
//! mismatch or no snapshot to check, 2 usage errors (and a snapshot that cannot be
//! read or written).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::export::atomic::{check_replaceable, write_atomic};
use crate::pipeline::snapshot::{line_diff, snapshot_text};

use super::{ScriptArgs, SCRIPT_ERROR, USAGE_ERROR};

/// What `dieface snapshot` was asked to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Write when there is no snapshot, check when there is one.
    Default,
    /// Check only.
    Check,
    /// Write whatever the snapshot held.
    Update,
}

/// Unchanged lines shown round each change of a failed check.
const CONTEXT: usize = 2;

/// Where the snapshot of `script` lives: the script's path with `.snap` added.
pub(crate) fn snap_path(script: &Path) -> PathBuf {
    let mut s = OsString::from(script.as_os_str());
    s.push(".snap");
    PathBuf::from(s)
}

/// `dieface snapshot`.
pub(crate) fn run(script: &ScriptArgs, mode: Mode) -> ExitCode {
    let snap = snap_path(&script.file);
    // Refused before evaluating when it would be written: a read-only snapshot is
    // still checked.
    if mode == Mode::Update || (mode == Mode::Default && !snap.exists()) {
        if let Err(e) = check_replaceable(&snap) {
            eprintln!("error: cannot write `{}`: {e}", snap.display());
            return ExitCode::from(USAGE_ERROR);
        }
    }
    let text = match snapshot_of(script) {
        Ok(t) => t,
        Err(code) => return code,
    };
    let existing = match std::fs::read_to_string(&snap) {
        Ok(s) => Some(s),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => {
            eprintln!("error: cannot read `{}`: {e}", snap.display());
            return ExitCode::from(USAGE_ERROR);
        }
    };
    let file = script.file.display();
    match (mode, existing) {
        (Mode::Check, None) => {
            eprintln!(
                "error: there is no snapshot `{}` to check against",
                snap.display()
            );
            eprintln!(
                "help: run `dieface snapshot {file} --update` to write it, review it and commit it beside the script"
            );
            ExitCode::from(SCRIPT_ERROR)
        }
        (Mode::Update, Some(old)) if old == text => {
            println!("{} is up to date", snap.display());
            ExitCode::SUCCESS
        }
        (Mode::Update, _) | (Mode::Default, None) => match write_atomic(&snap, text.as_bytes()) {
            Ok(()) => {
                println!("wrote {} ({} lines)", snap.display(), text.lines().count());
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: cannot write `{}`: {e}", snap.display());
                ExitCode::from(USAGE_ERROR)
            }
        },
        (Mode::Check | Mode::Default, Some(old)) => {
            let diff = line_diff(&old, &text, CONTEXT);
            if diff.is_empty() {
                println!("{} matches {file}", snap.display());
                return ExitCode::SUCCESS;
            }
            println!("--- {} (committed)", snap.display());
            println!("+++ {file} (as it evaluates now)");
            for l in &diff {
                println!("{l}");
            }
            let changed = diff
                .iter()
                .filter(|l| l.starts_with('-') || l.starts_with('+'))
                .count();
            eprintln!(
                "error: `{}` does not match `{file}` ({changed} line{} differ)",
                snap.display(),
                if changed == 1 { "" } else { "s" }
            );
            eprintln!("help: if the change is meant, run `dieface snapshot {file} --update` and commit the snapshot");
            ExitCode::from(SCRIPT_ERROR)
        }
    }
}

/// The snapshot text of the script, or the exit code after printing its diagnostics (1)
/// or a usage error (2).
fn snapshot_of(script: &ScriptArgs) -> Result<String, ExitCode> {
    let color = script.color();
    let (engine, outcome) = script.evaluated()?;
    if !outcome.diagnostics.is_empty() {
        for d in &outcome.diagnostics {
            eprintln!("{}", engine.sources.render(d, color));
        }
        let n = outcome.diagnostics.len();
        eprintln!(
            "{}: {n} problem{}; no snapshot written or checked",
            script.file.display(),
            if n == 1 { "" } else { "s" }
        );
        return Err(ExitCode::from(SCRIPT_ERROR));
    }
    let model = engine.die_model(&outcome);
    Ok(snapshot_text(&outcome, &engine.sources, &model))
}
