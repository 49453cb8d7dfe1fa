//! `dieface build FILE -o OUT.glb [-o OUT.obj] [-o OUT.step] [--tolerance 0.01mm]
//! [-D name=value]`.
//!
//! The work is [`crate::pipeline`]'s: evaluate, make the die model, tessellate, encode,
//! write atomically (a failed or interrupted build leaves the previous file whole).
//! This command checks its arguments, prints the diagnostics (and exits 1 without
//! touching an output) or the files written. `watch` reuses [`Plan`] and
//! [`Plan::build`] with one pipeline kept across rebuilds.

use std::cell::RefCell;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use indicatif::ProgressBar;

use crate::export::atomic::{check_replaceable, Durability};
use crate::pipeline::{Build, Output, OutputFile, Pipeline, Stage};

use super::{
    ms, progress, stop_on_interrupt, OutputArgs, ScriptArgs, INTERRUPTED, SCRIPT_ERROR, USAGE_ERROR,
};

/// What a build writes, checked before anything is evaluated.
pub(crate) struct Plan {
    /// Outputs with their formats, in command-line order.
    pub outputs: Vec<(PathBuf, Output)>,
    /// `--tolerance` in mm, which wins over the script's `param tolerance`.
    pub tolerance: Option<f64>,
    /// Colour diagnostics.
    pub color: bool,
    /// `build` flushes its outputs to disk before renaming them into place; `watch`
    /// only renames ([`Durability`]).
    pub durability: Durability,
}

/// How one build went.
pub(crate) enum Built {
    /// Every output written (or, in `watch`, found already holding the same bytes).
    Written {
        /// Each output with its size in bytes and whether it was left unchanged.
        files: Vec<OutputFile>,
        /// Wall time of evaluation, tessellation and writing.
        took: Duration,
        /// The same wall time by stage.
        stages: StageTimes,
        /// The declarations that re-ran.
        reran: Vec<String>,
        /// How many pieces were tessellated anew (the rest came from the cache).
        tessellated: usize,
    },
    /// The script has errors (printed); no output was touched.
    ScriptErrors(usize),
    /// An output could not be written (printed); outputs before it were (exit 2).
    WriteFailed,
}

/// Wall time spent in each stage of one build, from the progress callbacks: what
/// `dieface build` prints after its total, so the split of a cold build is measured on
/// the real binary.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct StageTimes {
    /// Parsing, evaluating the declarations and making the die model.
    pub evaluate: Duration,
    /// Tessellating the die model's pieces (the ones not cached).
    pub tessellate: Duration,
    /// Encoding and writing every output.
    pub write: Duration,
}

impl StageTimes {
    /// Adds the time since `since` to the stage `slot` ([`StageTimes::slot`]) names.
    fn add(&mut self, slot: Option<usize>, since: Instant) {
        let slot = match slot {
            Some(0) => &mut self.evaluate,
            Some(1) => &mut self.tessellate,
            Some(_) => &mut self.write,
            None => return,
        };
        *slot += since.elapsed();
    }

    /// Which of the three times `stage` counts towards.
    fn slot(stage: &Stage) -> usize {
        match stage {
            Stage::Evaluating(_) => 0,
            Stage::Tessellating => 1,
            Stage::Writing(_) => 2,
        }
    }
}

impl Plan {
    /// Checks the outputs' extensions and that each may be replaced (an existing
    /// read-only output is refused: exit 2, like any output that cannot be written,
    /// before anything is evaluated), and parses `--tolerance`; a usage error (printed)
    /// otherwise.
    pub(crate) fn new(script: &ScriptArgs, out: &OutputArgs) -> Result<Plan, ExitCode> {
        let mut outputs = Vec::new();
        for path in &out.outputs {
            if let Err(e) = check_replaceable(path) {
                eprintln!("error: cannot write `{}`: {e}", path.display());
                return Err(ExitCode::from(USAGE_ERROR));
            }
            match Output::from_path(path) {
                Some(f) => outputs.push((path.clone(), f)),
                None => {
                    eprintln!(
                        "error: cannot tell the format of `{}`: use .glb, .gltf, .obj, .step, .k or .bdf",
                        path.display()
                    );
                    return Err(ExitCode::from(USAGE_ERROR));
                }
            }
        }
        let tolerance = script.tolerance(out.tolerance.as_deref())?;
        Ok(Plan {
            outputs,
            tolerance,
            color: script.color(),
            durability: Durability::Flushed,
        })
    }

    /// Evaluates `script` with `pipeline` and, when clean, writes every output (an
    /// output that already holds the same bytes from this pipeline's previous build is
    /// left alone: see [`Pipeline::write_outputs`]). Prints diagnostics and write
    /// errors on stderr. `on_build` sees every build that evaluated, clean or not,
    /// after its outputs are written (the live viewer publishes it).
    pub(crate) fn build(
        &self,
        pipeline: &mut Pipeline,
        script: &ScriptArgs,
        on_build: &mut dyn FnMut(&mut Pipeline, &Build),
    ) -> Result<Built, String> {
        let started = Instant::now();
        // One progress line at a time, replaced at each stage and cleared before
        // anything is printed.
        let bar: RefCell<Option<ProgressBar>> = RefCell::new(None);
        let clear = || {
            if let Some(b) = bar.borrow_mut().take() {
                b.finish_and_clear();
            }
        };
        // The stage under way and when it began, for the stage times.
        let current: RefCell<(Option<usize>, Instant)> = RefCell::new((None, started));
        let times = RefCell::new(StageTimes::default());
        let mut stage = |s: Stage| {
            let mut cur = current.borrow_mut();
            times.borrow_mut().add(cur.0, cur.1);
            *cur = (Some(StageTimes::slot(&s)), Instant::now());
            clear();
            *bar.borrow_mut() = Some(progress(match s {
                Stage::Evaluating(f) => format!("evaluating {}", f.display()),
                Stage::Tessellating => "tessellating".to_string(),
                Stage::Writing(p) => format!("writing {}", p.display()),
            }));
        };
        let build = pipeline.build(&script.file, self.tolerance, &mut stage);
        let build = build.map_err(|e| format!("cannot read `{}`: {e}", script.file.display()));
        let result = match build {
            Err(e) => Err(e),
            Ok(b) if !b.problems.is_empty() => {
                clear();
                for d in &b.problems {
                    eprintln!("{}", pipeline.engine.sources.render(d, self.color));
                }
                on_build(pipeline, &b);
                Ok(Built::ScriptErrors(b.problems.len()))
            }
            Ok(b) => {
                let stem = script
                    .file
                    .file_stem()
                    .map_or_else(|| "die_face".into(), |s| s.to_string_lossy().into_owned());
                let written =
                    pipeline.write_outputs(&b, &self.outputs, &stem, self.durability, &mut stage);
                on_build(pipeline, &b);
                match written {
                    Ok(files) => {
                        super::OUTPUTS_WRITTEN.store(true, std::sync::atomic::Ordering::SeqCst);
                        Ok(Built::Written {
                            files,
                            took: started.elapsed(),
                            stages: {
                                let cur = current.borrow();
                                let mut t = *times.borrow();
                                t.add(cur.0, cur.1);
                                t
                            },
                            reran: b.reran,
                            tessellated: b.tessellated,
                        })
                    }
                    Err((path, e)) => {
                        clear();
                        eprintln!("error: cannot write `{}`: {e}", path.display());
                        Ok(Built::WriteFailed)
                    }
                }
            }
        };
        clear();
        result
    }
}

/// `dieface build`.
pub(crate) fn run(script: &ScriptArgs, out: &OutputArgs) -> ExitCode {
    let plan = match Plan::new(script, out) {
        Ok(p) => p,
        Err(code) => return code,
    };
    let mut pipeline = match script.engine() {
        Ok(e) => Pipeline::new(e),
        Err(code) => return code,
    };
    // Only glTF and OBJ outputs need the tessellated scene.
    pipeline.set_scene_wanted(
        plan.outputs
            .iter()
            .any(|(_, output)| matches!(output, Output::Scene(_))),
    );
    stop_on_interrupt(INTERRUPTED);
    match plan.build(&mut pipeline, script, &mut |_, _| {}) {
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
        Ok(Built::Written {
            files,
            took,
            stages,
            ..
        }) => {
            for f in &files {
                println!("wrote {} ({} bytes)", f.path.display(), f.bytes);
            }
            println!(
                "built in {} (evaluated in {}, tessellated in {}, written in {})",
                ms(took),
                ms(stages.evaluate),
                ms(stages.tessellate),
                ms(stages.write)
            );
            ExitCode::SUCCESS
        }
    }
}
