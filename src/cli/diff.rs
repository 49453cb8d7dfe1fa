//! `dieface diff OLD.die NEW.die` and `dieface diff FILE.die --rev REV [--json]`: two
//! versions of a script built and compared ([`crate::pipeline::compare`]).
//!
//! With `--rev`, the old version is the file as committed at REV, read with `git show
//! REV:PATH` in the repository holding the file (never written to disk); its imports are
//! read from the working tree, as the new version's are. Each version is built as
//! `build` builds it (without writing anything); a version with errors has its
//! diagnostics printed and is named. Exit codes: 0 nothing changed, 1 something changed
//! or a version has errors, 2 usage errors (no second file, not in git, an unknown
//! revision).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

use crate::export::atomic::{check_replaceable, write_atomic_with, Durability};
use crate::export::render::{Size, View};
use crate::pipeline::compare::{compare, json_report, text_report, Side};
use crate::pipeline::{diff_picture_bytes, Build, Pipeline};

use super::{ms, progress, ScriptArgs, SCRIPT_ERROR, USAGE_ERROR};

/// Where `--png` draws the new version coloured by its distance from the old, and
/// from which side.
pub(crate) struct PngOut {
    /// The picture file (`.png`).
    pub path: PathBuf,
    /// Where it is seen from.
    pub view: View,
    /// Width and height in pixels.
    pub size: Size,
}

/// Which versions to compare, besides the first file.
pub(crate) struct Versions {
    /// The new version's file.
    pub new: Option<PathBuf>,
    /// The git revision of the old version (the first file is the new one).
    pub rev: Option<String>,
    /// Where both files are evaluated as if they stood (`--as`).
    pub at: Option<PathBuf>,
}

/// `dieface diff`.
pub(crate) fn run(
    script: &ScriptArgs,
    versions: Versions,
    json: bool,
    tolerance: Option<String>,
    png: Option<PngOut>,
) -> ExitCode {
    let Versions { new, rev, at } = versions;
    let started = Instant::now();
    let usage = |msg: String| {
        eprintln!("error: {msg}");
        ExitCode::from(USAGE_ERROR)
    };
    if let Some(out) = &png {
        let is_png = out
            .path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if !is_png {
            return usage(format!(
                "`{}`: --png writes a PNG picture; give a file ending in .png",
                out.path.display()
            ));
        }
        if let Err(e) = check_replaceable(&out.path) {
            return usage(format!("cannot write `{}`: {e}", out.path.display()));
        }
    }
    let png = png.as_ref();
    let tolerance = match script.tolerance(tolerance.as_deref()) {
        Ok(t) => t,
        Err(code) => return code,
    };
    if let (Some(new), Some(at)) = (&new, at) {
        let at = ScriptArgs {
            file: at,
            ..script.clone()
        };
        return run_as(&at, &script.file, new, json, tolerance, started, png);
    }
    let (old, new_args, old_label) = match (new, rev) {
        (Some(new), None) => {
            let new_args = ScriptArgs {
                file: new,
                ..script.clone()
            };
            let old = match build_file(script, tolerance, "old") {
                Ok(b) => b,
                Err(code) => return code,
            };
            (old, new_args, script.file.display().to_string())
        }
        (None, Some(rev)) => {
            // The script must exist and lie in the root before git is asked anything.
            if let Err(code) = script.engine() {
                return code;
            }
            let (label, text) = match git_show(&script.file, &rev, &script.limits()) {
                Ok(found) => found,
                Err(msg) => return usage(msg),
            };
            let old = match build_text(script, &label, &text, tolerance, "old") {
                Ok(b) => b,
                Err(code) => return code,
            };
            (old, script.clone(), label)
        }
        (None, None) => {
            return usage(format!(
                "`dieface diff` needs the new version: `dieface diff {} NEW.die`, or `dieface diff {} --rev HEAD` to compare with the last commit",
                script.file.display(),
                script.file.display()
            ))
        }
        (Some(_), Some(_)) => {
            return usage("give either a second file or --rev, not both".into())
        }
    };
    let new_build = match build_file(&new_args, tolerance, "new") {
        Ok(b) => b,
        Err(code) => return code,
    };
    let new_label = new_args.file.display().to_string();
    report(
        &old.0,
        &new_build.0,
        &old_label,
        &new_label,
        json,
        started,
        png,
    )
}

/// `dieface diff --as PATH OLD NEW`: both files read as they are and evaluated as if
/// they stood at `at.file`.
fn run_as(
    at: &ScriptArgs,
    old: &Path,
    new: &Path,
    json: bool,
    tolerance: Option<f64>,
    started: Instant,
    png: Option<&PngOut>,
) -> ExitCode {
    // One version read and built as if it stood at `at`, or the exit code of why not.
    let version = |file: &Path, which: &str| -> Result<(Built, String), ExitCode> {
        let text = read_text(file, &at.limits()).map_err(|msg| {
            eprintln!("error: {msg}");
            ExitCode::from(USAGE_ERROR)
        })?;
        let label = format!("{} ({which})", at.file.display());
        let built = build_text(at, &label, &text, tolerance, which)?;
        Ok((built, label))
    };
    let (old_built, old_label) = match version(old, "old") {
        Ok(v) => v,
        Err(code) => return code,
    };
    let (new_built, new_label) = match version(new, "new") {
        Ok(v) => v,
        Err(code) => return code,
    };
    report(
        &old_built.0,
        &new_built.0,
        &old_label,
        &new_label,
        json,
        started,
        png,
    )
}

/// The text of a version given as a file (a regular file within the `file_bytes`
/// limit, UTF-8), or why not.
fn read_text(file: &Path, limits: &crate::limits::Limits) -> Result<String, String> {
    let max = limits.get(crate::limits::Limit::FileBytes);
    crate::eval::paths::check_regular_path(file, max)
        .map_err(|e| format!("cannot read `{}`: {e}", file.display()))?;
    let bytes =
        std::fs::read(file).map_err(|e| format!("cannot read `{}`: {e}", file.display()))?;
    String::from_utf8(bytes).map_err(|e| format!("`{}` is not UTF-8 text: {e}", file.display()))
}

/// Compares two clean builds and prints the report; exit 0 when nothing changed, 1
/// when something did.
fn report(
    old: &Build,
    new: &Build,
    old_label: &str,
    new_label: &str,
    json: bool,
    started: Instant,
    png: Option<&PngOut>,
) -> ExitCode {
    let usage = |msg: String| {
        eprintln!("error: {msg}");
        ExitCode::from(USAGE_ERROR)
    };
    let (Some(old_side), Some(new_side)) = (side(old), side(new)) else {
        // `checked` returns only builds with a model and a scene.
        return usage("internal: a clean build without its model".into());
    };
    let comparison = compare(old_side, new_side);
    if json {
        match serde_json::to_string_pretty(&json_report(&comparison, old_label, new_label)) {
            Ok(s) => println!("{s}"),
            Err(e) => return usage(format!("cannot write JSON: {e}")),
        }
    } else {
        println!("--- {old_label}");
        println!("+++ {new_label}");
        for l in text_report(&comparison) {
            println!("{l}");
        }
        eprintln!("compared in {}", ms(started.elapsed()));
    }
    if let Some(out) = png {
        let bytes = match diff_picture_bytes(old, new, out.view, out.size) {
            Ok(b) => b,
            Err(msg) => {
                eprintln!("error: {msg}; no picture written");
                return ExitCode::from(SCRIPT_ERROR);
            }
        };
        if let Err(e) = write_atomic_with(&out.path, &bytes, Durability::Flushed) {
            return usage(format!("cannot write `{}`: {e}", out.path.display()));
        }
        eprintln!("wrote {}", out.path.display());
    }
    if comparison.changed() {
        ExitCode::from(SCRIPT_ERROR)
    } else {
        ExitCode::SUCCESS
    }
}

/// A build and the pipeline that made it (its engine holds the sources diagnostics
/// are rendered from).
type Built = (Build, Pipeline);

/// The side of a clean build.
fn side(build: &Build) -> Option<Side<'_>> {
    Some(Side {
        outcome: &build.outcome,
        model: build.model.as_ref()?,
        scene: build.scene.as_ref()?,
    })
}

/// Builds the script file of `args`; `which` (`old`, `new`) names it in messages.
fn build_file(args: &ScriptArgs, tolerance: Option<f64>, which: &str) -> Result<Built, ExitCode> {
    let mut pipeline = Pipeline::new(args.engine()?);
    let bar = progress(format!("building {}", args.file.display()));
    let build = pipeline.build(&args.file, tolerance, &mut |_| {});
    bar.finish_and_clear();
    match build {
        Ok(b) => checked(b, pipeline, args, which, &args.file.display().to_string()),
        Err(e) => {
            eprintln!("error: cannot read `{}`: {e}", args.file.display());
            Err(ExitCode::from(USAGE_ERROR))
        }
    }
}

/// Builds a version given as `text` (read from git, or from git's temporary copy),
/// named `label`, with its imports read next to the script of `args`; `which` (`old`,
/// `new`) names it in messages.
fn build_text(
    args: &ScriptArgs,
    label: &str,
    text: &str,
    tolerance: Option<f64>,
    which: &str,
) -> Result<Built, ExitCode> {
    let mut pipeline = Pipeline::new(args.engine()?);
    let dir = args
        .file
        .canonicalize()
        .ok()
        .and_then(|f| f.parent().map(Path::to_path_buf));
    let bar = progress(format!("building {label}"));
    let build = pipeline.build_text(label, text, dir, tolerance, &mut |_| {});
    bar.finish_and_clear();
    checked(build, pipeline, args, which, label)
}

/// The build when clean; otherwise its problems printed, the version named, exit 1.
fn checked(
    build: Build,
    pipeline: Pipeline,
    args: &ScriptArgs,
    which: &str,
    label: &str,
) -> Result<Built, ExitCode> {
    if build.problems.is_empty() && build.model.is_some() && build.scene.is_some() {
        return Ok((build, pipeline));
    }
    for d in &build.problems {
        eprintln!("{}", pipeline.engine.sources.render(d, args.color()));
    }
    let n = build.problems.len();
    eprintln!(
        "error: the {which} version (`{label}`) has {n} problem{}; nothing compared",
        if n == 1 { "" } else { "s" }
    );
    Err(ExitCode::from(SCRIPT_ERROR))
}

/// The text of `file` as committed at `rev`, and its label `REV:PATH` (the path within
/// the repository), read with `git show`; an error in words otherwise (not in a git
/// repository, git missing, an unknown revision, a file not in it, too large, not
/// UTF-8).
fn git_show(
    file: &Path,
    rev: &str,
    limits: &crate::limits::Limits,
) -> Result<(String, String), String> {
    if rev.is_empty() || rev.starts_with('-') || rev.contains(':') {
        return Err(format!(
            "--rev `{}` is not a revision: give a commit, a branch or a tag, e.g. `--rev HEAD`",
            crate::diag::abridged(rev, 40)
        ));
    }
    let path = file
        .canonicalize()
        .map_err(|e| format!("cannot read `{}`: {e}", file.display()))?;
    let dir = path.parent().unwrap_or(Path::new("/"));
    let git = |dir: &Path, args: &[&str]| {
        Command::new("git")
            .arg("-C")
            .arg(dir)
            .args(args)
            .output()
            .map_err(|e| format!("cannot run git (needed for --rev): {e}"))
    };
    let first_line = |bytes: &[u8]| {
        String::from_utf8_lossy(bytes)
            .lines()
            .next()
            .unwrap_or("")
            .trim()
            .to_string()
    };
    let top = git(dir, &["rev-parse", "--show-toplevel"])?;
    if !top.status.success() {
        return Err(format!(
            "`{}` is not in a git repository, so --rev cannot read an old version ({}); compare two files with `dieface diff OLD.die NEW.die`",
            file.display(),
            first_line(&top.stderr)
        ));
    }
    let top = PathBuf::from(String::from_utf8_lossy(&top.stdout).trim());
    let top = top.canonicalize().unwrap_or(top);
    let relative = path.strip_prefix(&top).map_err(|_| {
        format!(
            "`{}` does not lie in its git repository `{}`",
            file.display(),
            top.display()
        )
    })?;
    let relative: Vec<String> = relative
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    let relative = relative.join("/");
    let spec = format!("{rev}:{relative}");
    let shown = git(&top, &["show", &spec])?;
    if !shown.status.success() {
        return Err(format!(
            "git cannot show `{spec}`: {}; check that `{rev}` is a revision of this repository and that the file was committed there (`git log --oneline -- {}` lists the commits that changed it)",
            first_line(&shown.stderr),
            file.display()
        ));
    }
    let max = limits.get(crate::limits::Limit::FileBytes);
    if shown.stdout.len() as u64 > max {
        return Err(format!(
            "`{spec}` is {} bytes, over the file_bytes limit of {max}; raise it with `--limit file_bytes=N`",
            shown.stdout.len()
        ));
    }
    let text =
        String::from_utf8(shown.stdout).map_err(|e| format!("`{spec}` is not UTF-8 text: {e}"))?;
    Ok((spec, text))
}
