//! One build pipeline for `build`, `watch`, `inspect` and the viewer: evaluate the
//! script, make the die model, tessellate it with a cache, encode the outputs.
//!
//! [`Pipeline`] keeps one [`Engine`] (whose memo re-evaluates only the declarations an
//! edit touched), one [`SceneCache`] (which re-tessellates only the pieces whose
//! geometry changed) and one [`GltfCache`] (which converts only their vertices to glTF
//! buffer bytes) across builds. It prints nothing: the commands in `cli` report
//! what it returns, and follow its stages through [`Stage`] for their progress line.

pub mod compare;
pub mod diff_picture;
pub mod report;
pub mod snapshot;
mod tolerance;
pub mod viewer_data;

use std::path::{Path, PathBuf};

use crate::diag::Diagnostic;
use crate::die::model::DieModel;
use crate::eval::{Engine, Outcome};
use crate::export::atomic::{write_atomic_with, Durability};
use crate::export::gltf::GltfCache;
use crate::export::render::{encode_png, render, scene_picture, Size, View};
use crate::export::scene::{Scene, SceneCache, TessellationError};
use crate::export::step::{encode_step, StepModel};
use crate::export::{encode_with, Format};
use crate::geom::sew::sew;
use crate::geom::tessellate::{Tolerance, CURVE_POINT_LIMIT, SURFACE_VERTEX_LIMIT};
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
    /// An LS-DYNA keyword deck (`.k`, `.key`, `.dyn`) of the meshed parts
    /// ([`crate::export::fe`]).
    LsDyna,
    /// Nastran bulk data (`.bdf`, `.nas`) of the meshed parts.
    Nastran,
}

impl Output {
    /// The format named by a path's extension, or `None` for an unknown one.
    pub fn from_path(p: &Path) -> Option<Output> {
        let ext = p.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "step" | "stp" => Some(Output::Step),
            "k" | "key" | "dyn" => Some(Output::LsDyna),
            "bdf" | "nas" => Some(Output::Nastran),
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
    /// What this pipeline last wrote to each output.
    written: std::collections::HashMap<PathBuf, Written>,
    /// Whether a clean build is tessellated ([`Pipeline::set_scene_wanted`]).
    scene_wanted: bool,
}

impl Pipeline {
    /// A pipeline around `engine`, with an empty cache.
    pub fn new(engine: Engine) -> Pipeline {
        Pipeline {
            engine,
            cache: SceneCache::default(),
            encoded: GltfCache::default(),
            written: Default::default(),
            scene_wanted: true,
        }
    }

    /// Whether a clean build is tessellated into a scene (from the start it is). The
    /// glTF and OBJ outputs, pictures and the viewer draw the scene; STEP and the FE
    /// decks read the die model alone, so `build` writing only those leaves the
    /// scene out (a 5 mm fender deck's 131,000 quads took 70 ms to tessellate for
    /// nothing), and with it the scene's own checks (its size limits, the glTF range).
    pub fn set_scene_wanted(&mut self, wanted: bool) {
        self.scene_wanted = wanted;
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
        Ok(self.finish(outcome, tolerance, stage))
    }

    /// [`Pipeline::build`] of a script given as text: `name` as diagnostics show it,
    /// `dir` where its relative imports and file reads start. `dieface diff --rev`
    /// builds a committed version this way, never writing it to disk.
    pub fn build_text(
        &mut self,
        name: &str,
        text: &str,
        dir: Option<PathBuf>,
        tolerance: Option<f64>,
        stage: &mut dyn FnMut(Stage),
    ) -> Build {
        stage(Stage::Evaluating(Path::new(name)));
        let outcome = self.engine.evaluate(name, text, dir);
        self.finish(outcome, tolerance, stage)
    }

    /// The rest of a build after the evaluation: the tolerance, the die model and its
    /// tessellation (a clean evaluation only; the tessellation when a scene is wanted).
    fn finish(
        &mut self,
        outcome: Outcome,
        tolerance: Option<f64>,
        stage: &mut dyn FnMut(Stage),
    ) -> Build {
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
            return build;
        }
        let tol = match tolerance_for(&build.outcome, tolerance) {
            Ok(t) => t,
            Err(d) => {
                build.problems.push(d);
                return build;
            }
        };
        let model = self.engine.die_model(&build.outcome);
        if !self.scene_wanted {
            build.model = Some(model);
            return build;
        }
        stage(Stage::Tessellating);
        let limits = *self.engine.limits();
        self.cache
            .set_max_curve_points(limits.count(Limit::Samples));
        self.cache
            .set_max_mesh_vertices(limits.count(Limit::MeshVertices));
        match self.cache.build(&model, &tol) {
            Ok(scene) => match crate::export::gltf::out_of_range(&scene) {
                Some(far) => build.problems.push(range_diagnostic(&build.outcome, &far)),
                None => build.scene = Some(scene),
            },
            Err(e) => {
                build
                    .problems
                    .push(tessellation_diagnostic(&build.outcome, &e, &tol, &limits))
            }
        }
        build.tessellated = self.cache.last_misses();
        build.model = Some(model);
        build
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
        Output::LsDyna | Output::Nastran => match &build.model {
            Some(model) => fe_bytes(model, name, output),
            None => Err("the build has problems; nothing to write".into()),
        },
    }
}

/// The PNG of a clean build's scene drawn from `view` at `size`
/// ([`crate::export::render`]: each kind in its glTF colour, curves over the surfaces, a
/// swatch per kind), or why there is none (the build has problems, or nothing to draw).
pub fn picture_bytes(build: &Build, view: View, size: Size) -> Result<Vec<u8>, String> {
    let Some(scene) = &build.scene else {
        return Err("the build has problems; nothing to draw".into());
    };
    let picture = scene_picture(scene);
    if picture.is_empty() {
        return Err("the script has nothing to draw: a picture shows the surfaces, meshes and curves it declares, and this script has none".into());
    }
    encode_png(&render(&picture, view, size))
}

/// The PNG `dieface diff --png` writes: the new build's scene coloured by its distance
/// from the old build's ([`diff_picture::distance_picture`]), drawn from `view`.
pub fn diff_picture_bytes(
    old: &Build,
    new: &Build,
    view: View,
    size: Size,
) -> Result<Vec<u8>, String> {
    let (Some(old), Some(new)) = (&old.scene, &new.scene) else {
        return Err("a version has problems; nothing to draw".into());
    };
    let picture = diff_picture::distance_picture(old, new);
    if picture.is_empty() {
        return Err("the new version has nothing to draw".into());
    }
    encode_png(&render(&picture, view, size))
}

/// The FE deck of a die model's meshed parts (`quad_mesh` and other meshes, one shell
/// part each, coincident nodes shared) and its line beads, as LS-DYNA keywords or
/// Nastran bulk data.
pub fn fe_bytes(model: &DieModel, name: &str, output: Output) -> Result<Vec<u8>, String> {
    let deck = crate::export::fe::from_model::fe_model(model, name);
    if deck.parts.is_empty() {
        return Err("the script has no mesh to write: an FE deck holds shell elements; mesh the die face's surfaces with `quad_mesh(surface, size: 5 mm)`".into());
    }
    deck.check()
        .map_err(|e| format!("the deck cannot be written: {e}"))?;
    Ok(match output {
        Output::Nastran => crate::export::fe::encode_nastran(&deck),
        _ => crate::export::fe::encode_lsdyna(&deck),
    })
}

/// One output of [`Pipeline::write_outputs`].
#[derive(Debug, Clone)]
pub struct OutputFile {
    /// Where.
    pub path: PathBuf,
    /// Its size in bytes.
    pub bytes: usize,
    /// Whether the file already held exactly these bytes, written by this pipeline
    /// and untouched since, so it was left as it was.
    pub unchanged: bool,
}

/// What a pipeline last wrote to one output: the bytes' hash and length, and the file's
/// modification time just after, so an identical rebuild is not written again while a
/// file changed or removed by someone else is.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Written {
    hash: u64,
    len: u64,
    modified: Option<std::time::SystemTime>,
}

impl Written {
    /// The fingerprint of bytes of length `len` and hash `hash` ([`hash_bytes`]) as
    /// now on disk at `path`.
    fn of(path: &Path, hash: u64, len: usize) -> Written {
        let meta = std::fs::metadata(path).ok();
        Written {
            hash,
            len: len as u64,
            modified: meta.and_then(|m| m.modified().ok()),
        }
    }
}

/// A hash of an output's bytes.
fn hash_bytes(bytes: &[u8]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    bytes.hash(&mut h);
    h.finish()
}

impl Pipeline {
    /// The file a builtin of the script read (an OBJ) that `output` would replace: an
    /// output never overwrites an input (and `watch` never rebuilds on its own write).
    /// Scripts and modules are `.die` files, never an output.
    fn input_at(&self, output: &Path) -> Option<String> {
        let dir = match output.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let target = dir.canonicalize().ok()?.join(output.file_name()?);
        let target = target.canonicalize().unwrap_or(target);
        self.engine
            .read_files()
            .iter()
            .find(|p| **p == target)
            .map(|p| p.display().to_string())
    }

    /// The bytes of one output of a clean build, through this pipeline's glTF cache
    /// (the viewer's GLB is encoded this way at every save).
    pub fn encode(&mut self, build: &Build, output: Output, name: &str) -> Result<Vec<u8>, String> {
        encode_output(build, output, name, &mut self.encoded)
    }

    /// Encodes and writes every output of a clean build atomically (a failed write
    /// leaves the previous file whole), in order, with the given [`Durability`]; stops
    /// at the first that fails. An output that already holds exactly the new bytes,
    /// because this pipeline wrote them and nobody has touched the file since, is left
    /// as it is (`watch` after an edit that changes nothing in the outputs). Returns
    /// each output with its size, or the path that failed and why.
    pub fn write_outputs(
        &mut self,
        build: &Build,
        outputs: &[(PathBuf, Output)],
        name: &str,
        durability: Durability,
        stage: &mut dyn FnMut(Stage),
    ) -> Result<Vec<OutputFile>, (PathBuf, String)> {
        let mut files = Vec::new();
        for (path, output) in outputs {
            stage(Stage::Writing(path));
            let bytes = self
                .encode(build, *output, name)
                .map_err(|e| (path.clone(), e))?;
            if let Some(input) = self.input_at(path) {
                return Err((
                    path.clone(),
                    format!(
                        "it is `{input}`, which the script reads; write the output to another file"
                    ),
                ));
            }
            // The bytes are hashed once: before writing only when the last write had
            // their length (else they cannot be the same), otherwise on the other
            // core while they are written (a fender's GLB is 5.6 MB, a few ms).
            let len = bytes.len();
            let earlier_hash = match self.written.get(path) {
                Some(w) if w.len == len as u64 => Some(hash_bytes(&bytes)),
                _ => None,
            };
            let unchanged = earlier_hash
                .is_some_and(|h| self.written.get(path) == Some(&Written::of(path, h, len)));
            if !unchanged {
                self.written.remove(path);
                let (hash, wrote) = rayon::join(
                    || earlier_hash.unwrap_or_else(|| hash_bytes(&bytes)),
                    || write_atomic_with(path, &bytes, durability),
                );
                wrote.map_err(|e| (path.clone(), e.to_string()))?;
                self.written
                    .insert(path.clone(), Written::of(path, hash, len));
            }
            files.push(OutputFile {
                path: path.clone(),
                bytes: bytes.len(),
                unchanged,
            });
        }
        Ok(files)
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

/// The diagnostic for geometry beyond the modelling range, at the declaration that
/// made it (the export writes metres as 32-bit floats, which cannot hold it).
fn range_diagnostic(outcome: &Outcome, far: &crate::export::gltf::OutOfRange) -> Diagnostic {
    let decl_name = far.part.split('/').next().unwrap_or(&far.part);
    let decl = outcome.decls.iter().find(|d| d.name == decl_name);
    let span = decl.map_or_else(|| crate::syntax::Span::new(outcome.file, 0, 0), |d| d.span);
    Diagnostic::new(
        crate::eval::finite::RANGE_CODE,
        format!(
            "`{}` reaches a coordinate of {} mm, beyond the modelling range of {} mm from the origin: the export cannot hold it",
            far.part,
            crate::eval::finite::show(far.coordinate),
            crate::eval::finite::show(crate::geom::MAX_COORDINATE)
        ),
        span,
        "this declaration",
    )
    .with_help("die faces are modelled in millimetres within 1 km of the origin, where the GLB's 32-bit floats still hold the default tolerance; check the units and the sizes given to this declaration")
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
    // A limit reached is named by its code, as during evaluation.
    let limit = match e.error {
        GeomError::NoConvergence { what, .. } if what == CURVE_POINT_LIMIT => Some(Limit::Samples),
        GeomError::NoConvergence { what, .. } if what == SURFACE_VERTEX_LIMIT => {
            Some(Limit::MeshVertices)
        }
        _ => None,
    };
    let mut d = Diagnostic::new(
        limit.map_or("die::geometry", crate::eval::budget::limit_code),
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
    if limit == Some(Limit::Samples) {
        // The curve needs more points than the `samples` limit allows.
        return d.with_help(format!(
            "the `samples` limit bounds the points of one curve: {}; or use a coarser tolerance (`--tolerance`)",
            Limit::Samples.help(limits)
        ));
    }
    if limit == Some(Limit::MeshVertices) {
        // The surface needs more vertices than the `mesh_vertices` limit allows.
        let at_default =
            limits.get(Limit::MeshVertices) >= Limits::default().get(Limit::MeshVertices);
        let fold = if tol.chordal < DEFAULT_TOLERANCE_MM {
            format!("; or use a coarser tolerance, e.g. `--tolerance {DEFAULT_TOLERANCE_MM}mm`")
        } else if at_default {
            format!(
                "; at {} mm a surface needs that many only where it folds back or pinches \
                 (`dieface inspect` shows its smallest radius, `min_radius`)",
                tol.chordal
            )
        } else {
            String::new()
        };
        return d.with_help(format!("{}{fold}", Limit::MeshVertices.help(limits)));
    }
    if matches!(e.error, GeomError::NotFinite { .. }) {
        return d.with_help("its coordinates are too large to tessellate: keep the geometry within a few kilometres of the origin (lengths are in millimetres)");
    }
    if tol.chordal < DEFAULT_TOLERANCE_MM {
        return d.with_help(format!(
            "use a coarser tolerance (`--tolerance`), e.g. {DEFAULT_TOLERANCE_MM}mm"
        ));
    }
    // At a tolerance this coarse a smooth die face needs a few hundred thousand
    // triangles; millions mean a fold or a pinch (a radius near 0), not a fine one.
    d.with_help(format!(
        "at {} mm a surface needs this many triangles only where it folds back or pinches: \
         `dieface inspect` shows its smallest radius (`min_radius`) and where; \
         a coarser `--tolerance` is the other way out",
        tol.chordal
    ))
}
