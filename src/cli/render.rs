//! `dieface render FILE -o VIEW.png [--view iso|top|front|side|back|bottom] [--size
//! WxH] [--tolerance 0.05mm]`: the script's geometry as a shaded picture, drawn by the
//! software rasterizer of [`crate::export::render`] (no browser, no GPU).
//!
//! The build is `build`'s ([`crate::pipeline::Pipeline::build`]); the picture is
//! written atomically, so a script with errors or a failed write leaves the last good
//! picture as it was.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;

use crate::export::atomic::{check_replaceable, write_atomic_with, Durability};
use crate::export::render::{Size, View};
use crate::pipeline::{picture_bytes, Pipeline, Stage};

use super::{
    ms, progress, stop_on_interrupt, ScriptArgs, INTERRUPTED, OUTPUTS_WRITTEN, SCRIPT_ERROR,
    USAGE_ERROR,
};

/// The picture to write and how to draw it.
#[derive(Debug, Clone, Args)]
pub struct RenderArgs {
    /// The picture file (`.png`).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    pub output: PathBuf,
    /// Where it is seen from: iso (front, right and above), top (looking down the press
    /// Z), front (from -Y), side (from +X), back or bottom.
    #[arg(long, value_enum, default_value = "iso")]
    pub view: ViewArg,
    /// Width and height in pixels (at most 8192 a side and 32 megapixels).
    #[arg(long, value_name = "WxH", default_value = "1200x900", value_parser = Size::parse)]
    pub size: Size,
    /// Chordal tolerance of the tessellation, a length with its unit (`0.1mm`).
    /// Default: the script's top-level `param tolerance`, else 0.05 mm.
    #[arg(long, value_name = "LENGTH")]
    pub tolerance: Option<String>,
}

/// The views, as the command line names them.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum ViewArg {
    /// From the front, the right and above.
    Iso,
    /// From above.
    Top,
    /// From the front (-Y).
    Front,
    /// From the right (+X).
    Side,
    /// From the back (+Y).
    Back,
    /// From below.
    Bottom,
}

impl From<ViewArg> for View {
    fn from(v: ViewArg) -> View {
        match v {
            ViewArg::Iso => View::Iso,
            ViewArg::Top => View::Top,
            ViewArg::Front => View::Front,
            ViewArg::Side => View::Side,
            ViewArg::Back => View::Back,
            ViewArg::Bottom => View::Bottom,
        }
    }
}

/// Whether `path` names a PNG file.
fn is_png(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// `dieface render`.
pub(crate) fn run(script: &ScriptArgs, args: &RenderArgs) -> ExitCode {
    let started = Instant::now();
    let out = &args.output;
    if !is_png(out) {
        eprintln!(
            "error: `{}`: render writes PNG pictures; give an output ending in .png",
            out.display()
        );
        return ExitCode::from(USAGE_ERROR);
    }
    if let Err(e) = check_replaceable(out) {
        eprintln!("error: cannot write `{}`: {e}", out.display());
        return ExitCode::from(USAGE_ERROR);
    }
    let tolerance = match script.tolerance(args.tolerance.as_deref()) {
        Ok(t) => t,
        Err(code) => return code,
    };
    let mut pipeline = match script.engine() {
        Ok(e) => Pipeline::new(e),
        Err(code) => return code,
    };
    stop_on_interrupt(INTERRUPTED);
    let color = script.color();
    let mut bar = None;
    let mut stage = |s: Stage| {
        if let Some(b) = bar.take() {
            indicatif::ProgressBar::finish_and_clear(&b);
        }
        bar = Some(progress(match s {
            Stage::Evaluating(f) => format!("evaluating {}", f.display()),
            Stage::Tessellating => "tessellating".to_string(),
            Stage::Writing(p) => format!("drawing {}", p.display()),
        }));
    };
    let build = pipeline.build(&script.file, tolerance, &mut stage);
    let built = started.elapsed();
    stage(Stage::Writing(out));
    let drawn = build
        .as_ref()
        .ok()
        .filter(|b| b.problems.is_empty())
        .map(|b| {
            let bytes = picture_bytes(b, args.view.into(), args.size);
            (bytes, started.elapsed())
        });
    if let Some(b) = bar.take() {
        b.finish_and_clear();
    }
    let build = match build {
        Ok(b) => b,
        Err(e) => {
            eprintln!("error: cannot read `{}`: {e}", script.file.display());
            return ExitCode::from(USAGE_ERROR);
        }
    };
    if !build.problems.is_empty() {
        for d in &build.problems {
            eprintln!("{}", pipeline.engine.sources.render(d, color));
        }
        let n = build.problems.len();
        eprintln!(
            "{}: {n} problem{}; no picture written",
            script.file.display(),
            if n == 1 { "" } else { "s" }
        );
        return ExitCode::from(SCRIPT_ERROR);
    }
    let Some((bytes, drawn_at)) = drawn else {
        // A clean build always has its picture drawn above.
        return ExitCode::from(SCRIPT_ERROR);
    };
    let bytes = match bytes {
        Ok(b) => b,
        Err(msg) => {
            eprintln!("error: {msg}; no picture written");
            return ExitCode::from(SCRIPT_ERROR);
        }
    };
    if let Err(e) = write_atomic_with(out, &bytes, Durability::Flushed) {
        eprintln!("error: cannot write `{}`: {e}", out.display());
        return ExitCode::from(USAGE_ERROR);
    }
    OUTPUTS_WRITTEN.store(true, std::sync::atomic::Ordering::SeqCst);
    println!(
        "wrote {} ({} bytes, {}x{})",
        out.display(),
        bytes.len(),
        args.size.width,
        args.size.height
    );
    println!(
        "rendered in {} (built in {}, drawn in {}, written in {})",
        ms(started.elapsed()),
        ms(built),
        ms(drawn_at - built),
        ms(started.elapsed() - drawn_at)
    );
    ExitCode::SUCCESS
}
