//! The command line: `dieface check`, `build`, `inspect`, `render`, `watch`, `view`,
//! `snapshot` and `diff` (clap).
//!
//! Exit codes, for every command: 0 success, 1 errors in the script (diagnostics are
//! printed on stderr), 2 usage errors (bad arguments, a missing file, an output with an
//! unknown extension). Progress spinners appear on stderr only when it is a terminal.

mod build;
mod diff;
mod inspect;
mod render;
mod snapshot;
mod viewer;
mod watch;

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::eval::overrides::parse_define;
use crate::eval::paths::{check_regular_path, ReadRefusal};
use crate::eval::{Engine, Outcome};
use crate::limits::Limits;
use crate::pipeline::{tolerance_for, TOLERANCE_PARAM};

/// dieface: a declarative language for the faces of automotive stamping dies.
#[derive(Debug, Parser)]
#[command(name = "dieface", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Parse and evaluate a script and print its diagnostics (exit 0 when clean, 1 on
    /// errors).
    Check {
        /// What to evaluate.
        #[command(flatten)]
        script: ScriptArgs,
    },
    /// Evaluate a script and write its geometry (glTF binary `.glb`, glTF JSON `.gltf`,
    /// Wavefront `.obj`; the format comes from each output's extension).
    Build {
        /// What to evaluate.
        #[command(flatten)]
        script: ScriptArgs,
        /// What to write.
        #[command(flatten)]
        output: OutputArgs,
    },
    /// Print every declaration's kind and a short geometric summary, or with `--json`
    /// the full evaluated data (schema: docs/inspect-json.md).
    Inspect {
        /// What to evaluate.
        #[command(flatten)]
        script: ScriptArgs,
        /// Print the evaluated data as JSON on stdout.
        #[arg(long)]
        json: bool,
    },
    /// Draw the script's geometry as a shaded PNG picture (software rendering: no
    /// browser, no GPU), each kind in its glTF colour, from an iso, top, front, side,
    /// back or bottom view.
    Render {
        /// What to evaluate.
        #[command(flatten)]
        script: ScriptArgs,
        /// The picture and how to draw it.
        #[command(flatten)]
        render: render::RenderArgs,
    },
    /// Build, then rebuild whenever the script or a file it imports changes (Ctrl-C
    /// stops).
    Watch {
        /// What to evaluate.
        #[command(flatten)]
        script: ScriptArgs,
        /// What to write.
        #[command(flatten)]
        output: OutputArgs,
        /// Also serve the live viewer on 127.0.0.1 (see `dieface view`).
        #[arg(long)]
        serve: bool,
        /// The viewer's port (with `--serve`; 0 picks any free port).
        #[arg(long, value_name = "N", default_value_t = viewer::DEFAULT_PORT, requires = "serve")]
        port: u16,
    },
    /// Serve a live viewer of the script on 127.0.0.1 and follow its saves: open the
    /// printed address in a browser; the model updates in place at each save (the
    /// camera stays), a failed save shows its diagnostic over the last good model.
    /// Writes no file (`dieface watch --serve` also writes outputs).
    View {
        /// What to evaluate.
        #[command(flatten)]
        script: ScriptArgs,
        /// The port on 127.0.0.1 (0 picks any free port).
        #[arg(long, value_name = "N", default_value_t = viewer::DEFAULT_PORT)]
        port: u16,
        /// Chordal tolerance of the tessellation, a length with its unit. Default: the
        /// script's top-level `param tolerance`, else 0.05 mm.
        #[arg(long, value_name = "LENGTH")]
        tolerance: Option<String>,
    },
    /// Write the review snapshot `FILE.die.snap` (the `inspect` summary, rounded so
    /// float noise cannot change it), or check the script against it: with no flag it
    /// is written when missing and checked when present.
    Snapshot {
        /// What to evaluate.
        #[command(flatten)]
        script: ScriptArgs,
        /// Only check: exit 1 with the changed lines when the snapshot does not match
        /// (or does not exist).
        #[arg(long, conflicts_with = "update")]
        check: bool,
        /// Write the snapshot whatever it held.
        #[arg(long)]
        update: bool,
    },
    /// Compare two versions of a script declaration by declaration: added, removed,
    /// renamed, changed (how far the new geometry lies from the old, in mm) or
    /// unchanged. `dieface diff OLD.die NEW.die`, or `dieface diff FILE.die --rev REV`
    /// for the version committed at REV. Exit 0 when nothing changed, 1 when something
    /// did (or a version has errors), 2 on usage errors.
    Diff {
        /// The old version (with `--rev`: the script, compared with its version at REV).
        #[command(flatten)]
        script: ScriptArgs,
        /// The new version.
        #[arg(value_name = "NEW")]
        new: Option<PathBuf>,
        /// Compare the script with its version in this git revision (`HEAD`, a commit,
        /// a branch), read with `git show REV:PATH`.
        #[arg(long, value_name = "REV", conflicts_with = "new")]
        rev: Option<String>,
        /// Read OLD and NEW but evaluate both as if they stood at PATH (their imports
        /// and file reads next to PATH, within its root): for git's external diff,
        /// which hands over temporary copies (`scripts/git-diff-die`).
        #[arg(
            long = "as",
            value_name = "PATH",
            conflicts_with = "rev",
            requires = "new"
        )]
        at: Option<PathBuf>,
        /// Print the comparison as JSON on stdout.
        #[arg(long)]
        json: bool,
        /// Also draw the new version as a PNG picture, each point coloured by its
        /// distance from the old version (blue 0, red the largest), with a scale in mm.
        #[arg(long, value_name = "FILE.png")]
        png: Option<PathBuf>,
        /// Where the `--png` picture is seen from.
        #[arg(long, value_enum, default_value = "iso", requires = "png")]
        view: render::ViewArg,
        /// Width and height of the `--png` picture in pixels.
        #[arg(long, value_name = "WxH", default_value = "1200x900", value_parser = crate::export::render::Size::parse, requires = "png")]
        size: crate::export::render::Size,
        /// Chordal tolerance of the tessellations the distances are measured on, a
        /// length with its unit. Default: each version's `param tolerance`, else 0.05 mm.
        #[arg(long, value_name = "LENGTH")]
        tolerance: Option<String>,
    },
}

/// The script and how to evaluate it (shared by every command).
#[derive(Debug, Clone, Args)]
pub struct ScriptArgs {
    /// The `.die` script.
    pub file: PathBuf,
    /// The project root: imports and file reads may not leave it (default: the
    /// script's folder).
    #[arg(long)]
    pub root: Option<PathBuf>,
    /// Colour diagnostics: auto (when stderr is a terminal), always or never.
    #[arg(long, default_value = "auto")]
    pub color: ColorChoice,
    /// Override a top-level `param` with a value of the same type and unit, e.g.
    /// `-D delta=0.005mm` (repeatable; the value is an expression of the language).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<(String, String)>,
    /// Raise (or lower) a limit on the work a script may ask for, e.g. `--limit
    /// list_items=50000000` (repeatable; the limits are listed in docs/limits.md).
    #[arg(long = "limit", value_name = "NAME=VALUE", value_parser = crate::limits::parse_setting)]
    pub limits: Vec<(crate::limits::Limit, u64)>,
}

/// Outputs and tessellation (build and watch).
#[derive(Debug, Clone, Args)]
pub struct OutputArgs {
    /// An output file: `.glb`, `.gltf` or `.obj` (repeatable).
    #[arg(short = 'o', long = "output", value_name = "FILE", required = true)]
    pub outputs: Vec<PathBuf>,
    /// Chordal tolerance of the tessellation, a length with its unit (`0.01mm`,
    /// `0.001 in`). Default: the script's top-level `param tolerance`, else 0.05 mm.
    #[arg(long, value_name = "LENGTH")]
    pub tolerance: Option<String>,
}

/// When to colour diagnostics.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum ColorChoice {
    /// When stderr is a terminal.
    Auto,
    /// Always.
    Always,
    /// Never.
    Never,
}

/// Runs the command line and returns the process exit code.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    match cli.command {
        Command::Check { script } => check(&script),
        Command::Build { script, output } => build::run(&script, &output),
        Command::Inspect { script, json } => inspect::run(&script, json),
        Command::Render { script, render } => render::run(&script, &render),
        Command::Watch {
            script,
            output,
            serve,
            port,
        } => watch::run(&script, &output, serve.then_some(port)),
        Command::View {
            script,
            port,
            tolerance,
        } => watch::view(&script, port, tolerance.as_deref()),
        Command::Snapshot {
            script,
            check,
            update,
        } => snapshot::run(
            &script,
            match (check, update) {
                (true, _) => snapshot::Mode::Check,
                (_, true) => snapshot::Mode::Update,
                _ => snapshot::Mode::Default,
            },
        ),
        Command::Diff {
            script,
            new,
            rev,
            at,
            json,
            tolerance,
            png,
            view,
            size,
        } => diff::run(
            &script,
            diff::Versions { new, rev, at },
            json,
            tolerance,
            png.map(|path| diff::PngOut {
                path,
                view: view.into(),
                size,
            }),
        ),
    }
}

/// Exit code 1: errors in the script.
pub(crate) const SCRIPT_ERROR: u8 = 1;
/// Exit code 2: usage errors.
pub(crate) const USAGE_ERROR: u8 = 2;
/// Exit code of a `build` stopped by Ctrl-C or SIGTERM (128 + SIGINT, as shells report
/// a process ended by SIGINT).
pub(crate) const INTERRUPTED: i32 = 130;

/// Set once a build has every output in place: a Ctrl-C after that interrupts only the
/// printing, so the process ends with success rather than [`INTERRUPTED`] (which says
/// the outputs were left as they were).
pub(crate) static OUTPUTS_WRITTEN: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// On Ctrl-C (SIGINT) or SIGTERM, removes the temporary files of the writes under way
/// and ends the process with `code` at once, even in the middle of an evaluation or a
/// tessellation: the outputs stay as they were and no `.tmp` file is left. The `ctrlc`
/// crate (already used, with its `termination` feature for SIGTERM) runs the handler on
/// its own thread, outside the signal context, so it may remove files and exit.
pub(crate) fn stop_on_interrupt(code: i32) {
    if let Err(e) = ctrlc::set_handler(move || {
        crate::export::atomic::remove_temp_files();
        // Every output already in place: nothing was interrupted but the printing.
        if OUTPUTS_WRITTEN.load(std::sync::atomic::Ordering::SeqCst) {
            std::process::exit(0);
        }
        std::process::exit(code);
    }) {
        eprintln!("warning: cannot catch Ctrl-C: {e}");
    }
}

impl ScriptArgs {
    /// Whether to colour diagnostics.
    fn color(&self) -> bool {
        match self.color {
            ColorChoice::Auto => std::io::stderr().is_terminal(),
            ColorChoice::Always => true,
            ColorChoice::Never => false,
        }
    }

    /// A `--tolerance` given on the command line in millimetres (`None` when not given),
    /// or the usage error (2) after saying why it is not a length.
    fn tolerance(&self, given: Option<&str>) -> Result<Option<f64>, ExitCode> {
        let Some(text) = given else {
            return Ok(None);
        };
        crate::pipeline::parse_tolerance(text, &self.limits())
            .map(Some)
            .map_err(|msg| {
                eprintln!(
                    "error: --tolerance {}: {msg}",
                    crate::diag::abridged(text, 40)
                );
                ExitCode::from(USAGE_ERROR)
            })
    }

    /// The script evaluated behind a spinner, its tolerance parameter checked
    /// ([`with_tolerance_checked`]), with the engine that holds its sources; or the
    /// usage error (2) when the script cannot be read. Diagnostics are left to the
    /// caller to print.
    fn evaluated(&self) -> Result<(Engine, Outcome), ExitCode> {
        let mut engine = self.engine()?;
        let bar = progress(format!("evaluating {}", self.file.display()));
        let outcome = engine.evaluate_path(&self.file);
        bar.finish_and_clear();
        match outcome {
            Ok(o) => Ok((engine, with_tolerance_checked(o))),
            Err(e) => {
                eprintln!("error: cannot read `{}`: {e}", self.file.display());
                Err(ExitCode::from(USAGE_ERROR))
            }
        }
    }

    /// The project root (default: the script's folder).
    fn root(&self) -> PathBuf {
        self.root.clone().unwrap_or_else(|| script_dir(&self.file))
    }

    /// The script must be a regular file within the `file_bytes` limit: a folder, a
    /// FIFO or a device is refused before anything opens it.
    fn check_script(&self) -> Result<(), ExitCode> {
        let max = self.limits().get(crate::limits::Limit::FileBytes);
        let why = match check_regular_path(&self.file, max) {
            Ok(()) => return Ok(()),
            Err(ReadRefusal::Io(e)) if e.kind() == std::io::ErrorKind::NotFound => {
                "no such file".to_string()
            }
            // A script over the limit is the engine's diagnostic (`die::limit::file_bytes`,
            // with the limit's help), as a module over it is.
            Err(ReadRefusal::TooLarge { .. }) => return Ok(()),
            Err(r) => r.to_string(),
        };
        eprintln!("error: cannot read `{}`: {why}", self.file.display());
        Err(ExitCode::from(USAGE_ERROR))
    }

    /// The project root, resolved: an existing folder that holds the script. A `--root`
    /// that does not exist, or is not a folder, or does not hold the script, is a
    /// usage error, never a root check quietly lifted.
    fn checked_root(&self) -> Result<PathBuf, ExitCode> {
        let root = self.root();
        let fail = |why: String| {
            eprintln!("error: {why}");
            Err(ExitCode::from(USAGE_ERROR))
        };
        let resolved = match root.canonicalize() {
            Ok(r) if r.is_dir() => r,
            Ok(_) => return fail(format!("--root `{}` is not a folder", root.display())),
            Err(e) => {
                return fail(format!(
                "--root `{}` cannot be used: {e}; give an existing folder that holds the script",
                root.display()
            ))
            }
        };
        let inside = self
            .file
            .canonicalize()
            .is_ok_and(|f| f.starts_with(&resolved));
        if !inside {
            return fail(format!(
                "`{}` lies outside --root `{}`; the root must hold the script",
                self.file.display(),
                root.display()
            ));
        }
        Ok(resolved)
    }

    /// The limits in force: the defaults with the `--limit` settings applied in order.
    fn limits(&self) -> Limits {
        let mut limits = Limits::default();
        for &(limit, value) in &self.limits {
            limits.set(limit, value);
        }
        limits
    }

    /// An engine for the script with its overrides, or a usage error (printed) if the
    /// script is not a regular file or the root is not a folder holding it.
    fn engine(&self) -> Result<Engine, ExitCode> {
        self.check_script()?;
        let root = self.checked_root()?;
        let mut engine = Engine::new(Some(root));
        engine.set_overrides(self.define.clone());
        engine.set_limits(self.limits());
        Ok(engine)
    }
}

/// `dieface check`.
fn check(script: &ScriptArgs) -> ExitCode {
    let color = script.color();
    let file = script.file.as_path();
    let mut engine = match script.engine() {
        Ok(e) => e,
        Err(code) => return code,
    };
    let outcome = match engine.evaluate_path(file) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: cannot read `{}`: {e}", file.display());
            return ExitCode::from(USAGE_ERROR);
        }
    };
    let outcome = with_tolerance_checked(outcome);
    for d in &outcome.diagnostics {
        eprintln!("{}", engine.sources.render(d, color));
    }
    let evaluated = outcome.decls.iter().filter(|d| d.value.is_some()).count();
    if outcome.diagnostics.is_empty() {
        println!(
            "{}: {} declarations, no problems",
            file.display(),
            outcome.decls.len()
        );
        ExitCode::SUCCESS
    } else {
        let n = outcome.diagnostics.len();
        eprintln!(
            "{}: {n} problem{} ({evaluated} of {} declarations evaluated)",
            file.display(),
            if n == 1 { "" } else { "s" },
            outcome.decls.len()
        );
        ExitCode::from(SCRIPT_ERROR)
    }
}

/// The outcome with the script's `param tolerance` checked as `build` checks it
/// ([`crate::pipeline::tolerance_for`]), so `check` and `inspect` refuse what `build`
/// would (a `param tolerance` that failed to evaluate has its own diagnostic already).
pub(crate) fn with_tolerance_checked(mut outcome: Outcome) -> Outcome {
    let failed = outcome
        .decls
        .iter()
        .any(|d| d.name == TOLERANCE_PARAM && d.kind == "param" && d.value.is_none());
    if !failed {
        if let Err(d) = tolerance_for(&outcome, None) {
            outcome.diagnostics.push(d);
        }
    }
    outcome
}

/// The folder holding the script (`.` for a bare file name).
fn script_dir(file: &Path) -> PathBuf {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A spinner on stderr with `message`, drawn only when stderr is a terminal (hidden,
/// and free, otherwise). Finish it with `finish_and_clear`.
fn progress(message: impl Into<String>) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} {elapsed}") {
        bar.set_style(style);
    }
    bar.set_message(message.into());
    bar.enable_steady_tick(Duration::from_millis(80));
    bar
}

/// Milliseconds with one decimal, for timing lines.
fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1e3)
}
