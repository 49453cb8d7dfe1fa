//! One build pipeline for `build`, `watch`, `inspect` and the viewer: evaluate the
//! script, make the die model, tessellate it with a cache, encode the outputs.
//!
//! [`Pipeline`] keeps one [`Engine`] (whose memo re-evaluates only the declarations an
//! edit touched), one [`SceneCache`] (which re-tessellates only the pieces whose
//! geometry changed) and one [`GltfCache`] (which converts only their vertices to glTF
//! buffer bytes) across builds. It prints nothing: the commands in `cli` report
//! what it returns, and follow its stages through [`Stage`] for their progress line.

pub mod report;
mod tolerance;

use std::path::{Path, PathBuf};

use crate::diag::Diagnostic;
use crate::die::model::DieModel;
use crate::eval::{Engine, Outcome};
use crate::export::atomic::{write_atomic_with, Durability};
use crate::export::gltf::GltfCache;
use crate::export::scene::{Scene, SceneCache, TessellationError};
use crate::export::step::{encode_step, StepModel};
use crate::export::{encode_with, Format};
use crate::geom::sew::sew;
use crate::geom::tessellate::{Tolerance, CURVE_POINT_LIMIT};
use crate::geom::GeomError;
use crate::limits::{Limit, Limits};

pub use tolerance::{parse_tolerance, tolerance_for, DEFAULT_TOLERANCE_MM, TOLERANCE_PARAM};

/// An output's format: a tessellated scene (glTF, OBJ) or the die face's B-spline
/// faces (STEP, `.step` or `.stp`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    /// A scene format.
    Scene(Format),
    /// STEP AP214: the die face sewn into a shell ([`crate::export::step`]).
    Step,
}

impl Output {
    /// The format named by a path's extension, or `None` for an unknown one.
    pub fn from_path(p: &Path) -> Option<Output> {
        let ext = p.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "step" | "stp" => Some(Output::Step),
            _ => Format::from_path(p).map(Output::Scene),
        }
    }
}

/// What a pipeline is doing, for a progress line.
#[derive(Debug, Clone, Copy)]
pub enum Stage<'a> {
    /// Evaluating the script.
    Evaluating(&'a Path),
    /// Tessellating the die model.
    Tessellating,
    /// Encoding and writing one output.
    Writing(&'a Path),
}

/// How far apart (mm) two faces' boundaries may lie and still be sewn into one edge in
/// the STEP output.
const SEW_TOLERANCE_MM: f64 = crate::geom::sew::DIE_FACE_TOLERANCE;

/// A build's evaluation, and, when it is clean, its model and scene.
pub struct Build {
    /// The evaluation.
    pub outcome: Outcome,
    /// Every problem: the evaluation's diagnostics, a bad tolerance, a tessellation
    /// failure. Outputs are written only when there is none.
    pub problems: Vec<Diagnostic>,
    /// The declarations that re-ran (all of them on a cold build).
    pub reran: Vec<String>,
    /// The die model (a clean evaluation only).
    pub model: Option<DieModel>,
    /// The tessellated model (a clean evaluation only).
    pub scene: Option<Scene>,
    /// How many pieces were tessellated anew (the rest came from the cache).
    pub tessellated: usize,
}

/// An engine and a tessellation cache kept across builds.
pub struct Pipeline {
    /// The engine: its memo, its sources (for rendering diagnostics).
    pub engine: Engine,
    cache: SceneCache,
    encoded: GltfCache,
}

impl Pipeline {
    /// A pipeline around `engine`, with an empty cache.
    pub fn new(engine: Engine) -> Pipeline {
        Pipeline {
            engine,
            cache: SceneCache::default(),
            encoded: GltfCache::default(),
        }
    }

    /// Evaluates `file`; when the evaluation is clean, makes the die model and
    /// tessellates it at `tolerance` (or the script's `param tolerance`, else the
    /// default), reusing the tessellations of unchanged pieces. An error only when the
    /// file cannot be read.
    pub fn build(
        &mut self,
        file: &Path,
        tolerance: Option<f64>,
        stage: &mut dyn FnMut(Stage),
    ) -> std::io::Result<Build> {
        stage(Stage::Evaluating(file));
        let outcome = self.engine.evaluate_path(file)?;
        let reran = self.engine.last_evaluated().to_vec();
        let mut build = Build {
            problems: outcome.diagnostics.clone(),
            outcome,
            reran,
            model: None,
            scene: None,
            tessellated: 0,
        };
        if !build.problems.is_empty() {
            return Ok(build);
        }
        let tol = match tolerance_for(&build.outcome, tolerance) {
            Ok(t) => t,
            Err(d) => {
                build.problems.push(d);
                return Ok(build);
            }
        };
        let model = self.engine.die_model(&build.outcome);
        stage(Stage::Tessellating);
        let limits = *self.engine.limits();
        self.cache
            .set_max_curve_points(limits.count(Limit::Samples));
        match self.cache.build(&model, &tol) {
            Ok(scene) => build.scene = Some(scene),
            Err(e) => {
                build
                    .problems
                    .push(tessellation_diagnostic(&build.outcome, &e, &tol, &limits))
            }
        }
        build.tessellated = self.cache.last_misses();
        build.model = Some(model);
        Ok(build)
    }
}

/// The bytes of one output of a clean build: the scene encoded (glTF buffer bytes of
/// unchanged tessellations from `cache`), or the die face as STEP (named `name`).
pub fn encode_output(
    build: &Build,
    output: Output,
    name: &str,
    cache: &mut GltfCache,
) -> Result<Vec<u8>, String> {
    match output {
        Output::Scene(f) => match &build.scene {
            Some(scene) => Ok(encode_with(scene, f, cache)),
            None => Err("the build has problems; nothing to write".into()),
        },
        Output::Step => match &build.model {
            Some(model) => step_bytes(model, name),
            None => Err("the build has problems; nothing to write".into()),
        },
    }
}

impl Pipeline {
    /// Encodes and writes every output of a clean build atomically (a failed write
    /// leaves the previous file whole), in order, with the given [`Durability`]; stops
    /// at the first that fails. Returns each written path with its size, or the path
    /// that failed and why.
    pub fn write_outputs(
        &mut self,
        build: &Build,
        outputs: &[(PathBuf, Output)],
        name: &str,
        durability: Durability,
        stage: &mut dyn FnMut(Stage),
    ) -> Result<Vec<(PathBuf, usize)>, (PathBuf, String)> {
        let mut written = Vec::new();
        for (path, output) in outputs {
            stage(Stage::Writing(path));
            let bytes = encode_output(build, *output, name, &mut self.encoded)
                .map_err(|e| (path.clone(), e))?;
            write_atomic_with(path, &bytes, durability)
                .map_err(|e| (path.clone(), e.to_string()))?;
            written.push((path.clone(), bytes.len()));
        }
        Ok(written)
    }
}

/// The STEP bytes of a die model's die face: the product, step draw and binder faces
/// sewn into one shell, the beads in a second.
pub fn step_bytes(model: &DieModel, name: &str) -> Result<Vec<u8>, String> {
    let faces = &model.die_face;
    let die = sew(faces.faces.clone(), SEW_TOLERANCE_MM)
        .map_err(|e| format!("sewing the die face failed: {e}"))?;
    let beads = sew(faces.beads.clone(), SEW_TOLERANCE_MM)
        .map_err(|e| format!("sewing the beads failed: {e}"))?;
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

/// A tessellation failure as a `die::geometry` diagnostic at the declaration the piece
/// belongs to.
fn tessellation_diagnostic(
    outcome: &Outcome,
    e: &TessellationError,
    tol: &Tolerance,
    limits: &Limits,
) -> Diagnostic {
    let decl_name = e.part.split('/').next().unwrap_or(&e.part);
    let decl = outcome.decls.iter().find(|d| d.name == decl_name);
    let span = decl.map_or_else(
        || crate::syntax::Span::new(outcome.file, 0, 0),
        |d| d.value.as_ref().map_or(d.span, |v| v.span),
    );
    let mut d = Diagnostic::new(
        "die::geometry",
        format!(
            "`{}` cannot be tessellated for export within {} mm: {}",
            e.part, tol.chordal, e.error
        ),
        span,
        "this geometry",
    );
    if let Some(decl) = decl {
        d = d.with_label(decl.span, "in this declaration");
    }
    if matches!(e.error, GeomError::NoConvergence { what, .. } if what == CURVE_POINT_LIMIT) {
        // The curve needs more points than the `samples` limit allows.
        return d.with_help(format!(
            "the `samples` limit bounds the points of one curve: {}; or use a coarser tolerance (`--tolerance`)",
            Limit::Samples.help(limits)
        ));
    }
    if matches!(e.error, GeomError::NotFinite { .. }) {
        return d.with_help("its coordinates are too large to tessellate: keep the geometry within a few kilometres of the origin (lengths are in millimetres)");
    }
    d.with_help("use a coarser tolerance (`--tolerance`), e.g. 0.01mm or 0.05mm")
}
