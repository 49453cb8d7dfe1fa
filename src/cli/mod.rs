//! The command line: `dieface check` (build, inspect and watch arrive with the export
//! stage). Exit codes: 0 clean, 1 errors in the script, 2 usage errors.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::eval::Engine;

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
        /// The `.die` script.
        file: PathBuf,
        /// The project root: imports and file reads may not leave it (default: the
        /// script's folder).
        #[arg(long)]
        root: Option<PathBuf>,
        /// Colour diagnostics: auto (when stderr is a terminal), always or never.
        #[arg(long, default_value = "auto")]
        color: ColorChoice,
    },
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
        Command::Check { file, root, color } => check(&file, root.as_deref(), color),
    }
}

/// `dieface check`.
fn check(file: &Path, root: Option<&Path>, color: ColorChoice) -> ExitCode {
    let color = match color {
        ColorChoice::Auto => std::io::stderr().is_terminal(),
        ColorChoice::Always => true,
        ColorChoice::Never => false,
    };
    let root = root
        .map(Path::to_path_buf)
        .unwrap_or_else(|| script_dir(file));
    if !file.is_file() {
        eprintln!("error: cannot read `{}`: no such file", file.display());
        return ExitCode::from(2);
    }
    let mut engine = Engine::new(Some(root));
    let outcome = match engine.evaluate_path(file) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: cannot read `{}`: {e}", file.display());
            return ExitCode::from(2);
        }
    };
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
        ExitCode::from(1)
    }
}

/// The folder holding the script (`.` for a bare file name).
fn script_dir(file: &Path) -> PathBuf {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}
