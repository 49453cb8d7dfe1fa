//! `dieface build FILE -o OUT.glb [-o OUT.obj] [-o OUT.step] [--tolerance 0.01mm]
//! [-D name=value]`.
//!
//! Evaluate; on any diagnostic print them all and exit 1 without touching an output;
//! else tessellate once into a scene and write every output atomically (a failed or
//! interrupted build leaves the previous file whole). `watch` reuses [`Plan`] and
//! [`Plan::build`] with one engine kept across rebuilds.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use crate::diag::{Diagnostic, Sources};
use crate::eval::overrides::eval_text;
use crate::eval::units::Units;
use crate::eval::value::{Data, Dim};
use crate::eval::{Engine, Outcome};
use crate::export::atomic::write_atomic;
use crate::export::step::{encode_step, StepModel};
use crate::export::{build_scene, encode, Format};
use crate::geom::sew::sew;
use crate::geom::tessellate::Tolerance;

use super::{ms, progress, OutputArgs, ScriptArgs, SCRIPT_ERROR, USAGE_ERROR};

/// The tolerance used when neither the command line nor the script sets one, in mm.
pub(crate) const DEFAULT_TOLERANCE_MM: f64 = 0.05;

/// The name of the script parameter that sets the tolerance.
const TOLERANCE_PARAM: &str = "tolerance";

/// What a build writes, checked before anything is evaluated.
pub(crate) struct Plan {
    /// Outputs with their formats, in command-line order.
    pub outputs: Vec<(PathBuf, Output)>,
    /// `--tolerance` in mm, which wins over the script's `param tolerance`.
    pub tolerance: Option<f64>,
    /// Colour diagnostics.
    pub color: bool,
}

/// An output's format: a tessellated scene (glTF, OBJ) or the die face's B-spline
/// faces (STEP, `.step` or `.stp`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Output {
    /// A scene format.
    Scene(Format),
    /// STEP AP214: the die face sewn into a shell ([`crate::export::step`]).
    Step,
}

impl Output {
    fn from_path(p: &std::path::Path) -> Option<Output> {
        let ext = p.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "step" | "stp" => Some(Output::Step),
            _ => Format::from_path(p).map(Output::Scene),
        }
    }
}

/// How far apart (mm) two faces' boundaries may lie and still be sewn into one edge in
/// the STEP output.
const SEW_TOLERANCE_MM: f64 = crate::geom::sew::DIE_FACE_TOLERANCE;

/// The STEP bytes of the die face of `outcome`: the product, step draw and binder
/// faces sewn into one shell, the beads in a second.
pub(crate) fn step_bytes(outcome: &Outcome, name: &str) -> Result<Vec<u8>, String> {
    let faces = crate::eval::die_face::die_face(outcome);
    let die = sew(faces.faces, SEW_TOLERANCE_MM)
        .map_err(|e| format!("sewing the die face failed: {e}"))?;
    let beads =
        sew(faces.beads, SEW_TOLERANCE_MM).map_err(|e| format!("sewing the beads failed: {e}"))?;
    let mut shells = Vec::new();
    if !die.faces.is_empty() {
        shells.push(("die_face".to_string(), &die));
    }
    if !beads.faces.is_empty() {
        shells.push(("beads".to_string(), &beads));
    }
    if shells.is_empty() {
        return Err("the script has no die face to write: STEP carries the products (trimmed with `trim(panel, outline)`) and the step draw, blankholder and bead features, and this script has none".into());
    }
    Ok(encode_step(&StepModel {
        name: name.to_string(),
        shells,
        uncertainty: SEW_TOLERANCE_MM,
    }))
}

/// How one build went.
pub(crate) enum Built {
    /// Every output written.
    Written {
        /// Each output with its size in bytes.
        files: Vec<(PathBuf, usize)>,
        /// Wall time of evaluation, tessellation and writing.
        took: Duration,
    },
    /// Nothing re-ran and the outputs are up to date (watch only): nothing written.
    Unchanged,
    /// The script has errors (printed); no output was touched.
    ScriptErrors(usize),
    /// An output could not be written (printed); outputs before it were (exit 2).
    WriteFailed,
}

impl Plan {
    /// Checks the outputs' extensions and parses `--tolerance`; a usage error (printed)
    /// otherwise.
    pub(crate) fn new(script: &ScriptArgs, out: &OutputArgs) -> Result<Plan, ExitCode> {
        let mut outputs = Vec::new();
        for path in &out.outputs {
            match Output::from_path(path) {
                Some(f) => outputs.push((path.clone(), f)),
                None => {
                    eprintln!(
                        "error: cannot tell the format of `{}`: use .glb, .gltf, .obj or .step",
                        path.display()
                    );
                    return Err(ExitCode::from(USAGE_ERROR));
                }
            }
        }
        let tolerance = match &out.tolerance {
            None => None,
            Some(text) => match parse_tolerance(text) {
                Ok(mm) => Some(mm),
                Err(msg) => {
                    eprintln!("error: --tolerance {text}: {msg}");
                    return Err(ExitCode::from(USAGE_ERROR));
                }
            },
        };
        Ok(Plan {
            outputs,
            tolerance,
            color: script.color(),
        })
    }

    /// Evaluates `script` with `engine` and, when clean, writes every output. Prints
    /// diagnostics and write errors on stderr. With `skip_unchanged` (outputs written by
    /// the previous, good build of this engine), a clean evaluation in which no
    /// declaration re-ran writes nothing.
    pub(crate) fn build(
        &self,
        engine: &mut Engine,
        script: &ScriptArgs,
        skip_unchanged: bool,
    ) -> Result<Built, String> {
        let started = Instant::now();
        let bar = progress(format!("evaluating {}", script.file.display()));
        let outcome = engine
            .evaluate_path(&script.file)
            .map_err(|e| format!("cannot read `{}`: {e}", script.file.display()));
        bar.finish_and_clear();
        let outcome = outcome?;
        if skip_unchanged && outcome.diagnostics.is_empty() && engine.last_evaluated().is_empty() {
            return Ok(Built::Unchanged);
        }
        let mut problems = outcome.diagnostics.clone();
        let tolerance = if problems.is_empty() {
            match self.tolerance_for(&outcome) {
                Ok(t) => Some(t),
                Err(d) => {
                    problems.push(d);
                    None
                }
            }
        } else {
            None
        };
        let scene = match tolerance {
            Some(tol) => {
                let bar = progress("tessellating");
                let scene = build_scene(&outcome, &engine.sources, &tol);
                bar.finish_and_clear();
                match scene {
                    Ok(s) => Some(s),
                    Err(d) => {
                        problems.push(d);
                        None
                    }
                }
            }
            None => None,
        };
        let Some(scene) = scene else {
            for d in &problems {
                eprintln!("{}", engine.sources.render(d, self.color));
            }
            return Ok(Built::ScriptErrors(problems.len()));
        };
        let mut files = Vec::new();
        for (path, format) in &self.outputs {
            let bar = progress(format!("writing {}", path.display()));
            let bytes = match format {
                Output::Scene(f) => encode(&scene, *f),
                Output::Step => {
                    let stem = script
                        .file
                        .file_stem()
                        .map_or_else(|| "die_face".into(), |s| s.to_string_lossy().into_owned());
                    match step_bytes(&outcome, &stem) {
                        Ok(b) => b,
                        Err(e) => {
                            bar.finish_and_clear();
                            eprintln!("error: cannot write `{}`: {e}", path.display());
                            return Ok(Built::WriteFailed);
                        }
                    }
                }
            };
            let written = write_atomic(path, &bytes);
            bar.finish_and_clear();
            if let Err(e) = written {
                eprintln!("error: cannot write `{}`: {e}", path.display());
                return Ok(Built::WriteFailed);
            }
            files.push((path.clone(), bytes.len()));
        }
        Ok(Built::Written {
            files,
            took: started.elapsed(),
        })
    }

    /// The chordal tolerance: `--tolerance`, else the script's top-level
    /// `param tolerance` (a positive length), else [`DEFAULT_TOLERANCE_MM`].
    fn tolerance_for(&self, outcome: &Outcome) -> Result<Tolerance, Diagnostic> {
        if let Some(mm) = self.tolerance {
            return Ok(Tolerance::new(mm).expect("checked when parsed"));
        }
        let decl = outcome
            .decls
            .iter()
            .find(|d| d.name == TOLERANCE_PARAM && d.kind == "param");
        let Some(decl) = decl else {
            return Ok(Tolerance::new(DEFAULT_TOLERANCE_MM).expect("a positive constant"));
        };
        let value = decl.value.as_ref();
        let mm = value.and_then(|v| match v.data {
            Data::Number(q) if q.dim == Dim::LENGTH && q.value.is_finite() && q.value > 0.0 => {
                Some(q.value)
            }
            _ => None,
        });
        match mm.map(Tolerance::new) {
            Some(Ok(t)) => Ok(t),
            _ => {
                let what = value.map_or_else(|| "no value".to_string(), |v| v.type_name());
                Err(Diagnostic::new(
                    "die::bad_tolerance",
                    format!("`param tolerance` sets the tessellation's chordal tolerance and must be a positive length, but this is {what}"),
                    value.map_or(decl.span, |v| v.span),
                    format!("this is {what}"),
                )
                .with_label(decl.span, "the tolerance parameter")
                .with_help("e.g. `param tolerance = 0.05 mm`, or pass `--tolerance 0.05mm`"))
            }
        }
    }
}

/// Parses `--tolerance`: an expression of the language that is a positive length
/// (`0.01mm`, `0.01 mm`, `0.001in`); returns millimetres.
pub(crate) fn parse_tolerance(text: &str) -> Result<f64, String> {
    let mut sources = Sources::new();
    let value =
        eval_text(&mut sources, "--tolerance", text, Units::default()).map_err(|d| d.message)?;
    match value.data {
        Data::Number(q) if q.dim == Dim::LENGTH => {
            if q.value.is_finite() && q.value > 0.0 {
                Ok(q.value)
            } else {
                Err("the tolerance must be positive".into())
            }
        }
        Data::Number(q) if q.bare => {
            Err(format!("give the tolerance with its unit, e.g. `{text}mm`"))
        }
        _ => Err(format!(
            "the tolerance must be a length (mm, cm, m, in), but this is {}",
            value.type_name()
        )),
    }
}

/// `dieface build`.
pub(crate) fn run(script: &ScriptArgs, out: &OutputArgs) -> ExitCode {
    let plan = match Plan::new(script, out) {
        Ok(p) => p,
        Err(code) => return code,
    };
    let mut engine = match script.engine() {
        Ok(e) => e,
        Err(code) => return code,
    };
    match plan.build(&mut engine, script, false) {
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::from(USAGE_ERROR)
        }
        Ok(Built::ScriptErrors(n)) => {
            eprintln!(
                "{}: {n} problem{}; no output written",
                script.file.display(),
                if n == 1 { "" } else { "s" }
            );
            ExitCode::from(SCRIPT_ERROR)
        }
        // An output that cannot be written (no such folder, no permission) is a problem
        // with the command line, not the script.
        Ok(Built::WriteFailed) => ExitCode::from(USAGE_ERROR),
        Ok(Built::Unchanged) => ExitCode::SUCCESS,
        Ok(Built::Written { files, took }) => {
            for (path, bytes) in &files {
                println!("wrote {} ({bytes} bytes)", path.display());
            }
            println!("built in {}", ms(took));
            ExitCode::SUCCESS
        }
    }
}
