//! `dieface watch FILE -o OUT.glb`: build, then rebuild on every change of the script
//! or of a file it imports, until Ctrl-C. With `--serve`, and in `dieface view` (which
//! writes no file), each build is also published to the live viewer ([`super::viewer`]).
//!
//! The rename trap: editors such as vim and VS Code save by writing a new file and
//! renaming it over the old one, so a watch on the file itself follows the old inode and
//! goes deaf after the first save (notify issues 531, 165, 166). We therefore watch the
//! *parent directories* of the script and of every imported file, non-recursively, and
//! keep the events whose path is one of those files (compared by folder and file name,
//! never by inode). Bursts of events (write, chmod, rename, close) are debounced into
//! one rebuild.
//!
//! One [`Pipeline`] lives across rebuilds: its engine's memo re-evaluates only the
//! declarations an edit touched, and its scene cache re-tessellates only the pieces
//! whose geometry changed. Each rebuild prints one line with its time (from the save
//! being noticed to the files written), the declarations that re-ran and how many
//! pieces were tessellated. A rebuild with errors prints the diagnostics and leaves the outputs as
//! the last good build wrote them (writes are atomic).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

use notify::event::{AccessKind, AccessMode};
use notify::{EventKind, RecursiveMode, Watcher};

use crate::eval::Engine;
use crate::export::atomic::Durability;
use crate::export::Format;
use crate::pipeline::viewer_data::model_info;
use crate::pipeline::{Build, Output, OutputFile, Pipeline};

use super::build::{Built, Plan};
use super::viewer::Viewer;
use super::{ms, stop_on_interrupt, OutputArgs, ScriptArgs, USAGE_ERROR};

/// Quiet time that ends a burst of events.
const DEBOUNCE: Duration = Duration::from_millis(150);
/// Longest a burst may delay a rebuild.
const MAX_DELAY: Duration = Duration::from_secs(2);

/// `dieface watch`, serving the live viewer on `serve`'s port when given.
pub(crate) fn run(script: &ScriptArgs, out: &OutputArgs, serve: Option<u16>) -> ExitCode {
    let plan = match Plan::new(script, out) {
        // Previews are rewritten at every save: renamed into place, not flushed.
        Ok(p) => Plan {
            durability: Durability::Renamed,
            ..p
        },
        Err(code) => return code,
    };
    let viewer = match serve.map(start_viewer).transpose() {
        Ok(v) => v,
        Err(code) => return code,
    };
    watch(&plan, script, viewer.as_ref())
}

/// `dieface view`: the live viewer of the script, following its saves; writes no file.
pub(crate) fn view(script: &ScriptArgs, port: u16, tolerance: Option<&str>) -> ExitCode {
    let tolerance = match script.tolerance(tolerance) {
        Ok(t) => t,
        Err(code) => return code,
    };
    let plan = Plan {
        outputs: Vec::new(),
        tolerance,
        color: script.color(),
        durability: Durability::Renamed,
    };
    match start_viewer(port) {
        Ok(viewer) => watch(&plan, script, Some(&viewer)),
        Err(code) => code,
    }
}

/// Starts the viewer's server on 127.0.0.1:`port` and says where it is (stdout), or
/// says why not (a port taken is a usage error, 2).
fn start_viewer(port: u16) -> Result<Viewer, ExitCode> {
    match super::viewer::serve(port) {
        Ok(v) => {
            println!("viewer at http://{}/ (open it in a browser)", v.addr);
            Ok(v)
        }
        Err(e) if e.kind() == std::io::ErrorKind::AddrInUse => {
            eprintln!(
                "error: port {port} on 127.0.0.1 is taken (another `dieface view` or server?)\n  \
                 help: choose another with `--port N`, or `--port 0` for any free port"
            );
            Err(ExitCode::from(USAGE_ERROR))
        }
        Err(e) => {
            eprintln!("error: cannot serve the viewer on 127.0.0.1:{port}: {e}");
            Err(ExitCode::from(USAGE_ERROR))
        }
    }
}

/// Builds, then rebuilds at every change of the script or its imports, until Ctrl-C.
fn watch(plan: &Plan, script: &ScriptArgs, viewer: Option<&Viewer>) -> ExitCode {
    let mut pipeline = match script.engine() {
        Ok(e) => Pipeline::new(e),
        Err(code) => return code,
    };
    let main_file = match normalize(&script.file) {
        Some(p) => p,
        None => {
            eprintln!("error: cannot read `{}`", script.file.display());
            return ExitCode::from(USAGE_ERROR);
        }
    };

    // Ctrl-C is the way to stop watching: exit 0 at once, even mid-rebuild.
    stop_on_interrupt(0);
    let (tx, rx) = mpsc::channel::<notify::Result<notify::Event>>();
    let mut watcher = match notify::recommended_watcher(move |res| {
        let _ = tx.send(res);
    }) {
        Ok(w) => w,
        Err(e) => {
            eprintln!("error: cannot watch files: {e}");
            return ExitCode::from(USAGE_ERROR);
        }
    };

    // Watch the script's folder before the first build, so no save is missed.
    let mut files: BTreeSet<PathBuf> = BTreeSet::from([main_file.clone()]);
    let mut dirs: BTreeSet<PathBuf> = BTreeSet::new();
    register(&mut watcher, &files, &mut dirs);

    let mut state = State::default();
    rebuild(plan, &mut pipeline, script, &mut state, viewer);
    files.extend(loaded_files(&pipeline.engine, &script.root()));
    register(&mut watcher, &files, &mut dirs);
    eprintln!(
        "watching {} file{} in {} folder{} (Ctrl-C to stop)",
        files.len(),
        if files.len() == 1 { "" } else { "s" },
        dirs.len(),
        if dirs.len() == 1 { "" } else { "s" }
    );

    loop {
        let Ok(msg) = rx.recv() else {
            return ExitCode::SUCCESS;
        };
        match msg {
            Err(e) => eprintln!("warning: file watching: {e}"),
            Ok(event) => {
                if !relevant(&event, &files) {
                    continue;
                }
                // Debounce: wait until our files have been quiet for DEBOUNCE (or too
                // long has passed). Only events on our files extend the wait: reads of
                // the outputs (a viewer reloading them) must not hold the rebuild back.
                let first = Instant::now();
                let mut last = first;
                loop {
                    let deadline = (last + DEBOUNCE).min(first + MAX_DELAY);
                    let now = Instant::now();
                    if now >= deadline {
                        break;
                    }
                    match rx.recv_timeout(deadline - now) {
                        Ok(Ok(e)) if relevant(&e, &files) => last = Instant::now(),
                        Ok(_) => {}
                        Err(RecvTimeoutError::Timeout) => break,
                        Err(RecvTimeoutError::Disconnected) => return ExitCode::SUCCESS,
                    }
                }
                rebuild(plan, &mut pipeline, script, &mut state, viewer);
                // Imports may have changed: watch the folders of new ones too.
                files.extend(loaded_files(&pipeline.engine, &script.root()));
                register(&mut watcher, &files, &mut dirs);
            }
        }
    }
}

/// Publishes a build to the viewer: a clean one's model (GLB, declarations, scene),
/// or a failed one's diagnostics as plain text. `started` is when the save was
/// noticed.
fn publish(viewer: &Viewer, pipeline: &mut Pipeline, build: &Build, name: &str, started: Instant) {
    if !build.problems.is_empty() {
        let text: Vec<String> = build
            .problems
            .iter()
            .map(|d| pipeline.engine.sources.render(d, false))
            .collect();
        viewer.publish_errors(text.join("\n"), started.elapsed());
        return;
    }
    let (Some(scene), Some(model)) = (&build.scene, &build.model) else {
        return;
    };
    match pipeline.encode(build, Output::Scene(Format::Glb), name) {
        Ok(glb) => {
            let info = model_info(&build.outcome, &pipeline.engine.sources, scene).to_string();
            viewer.publish_model(
                glb,
                info,
                scene.clone(),
                model.parts.clone(),
                started.elapsed(),
                &build.reran,
            );
        }
        Err(e) => viewer.publish_errors(e, started.elapsed()),
    }
}

/// What the previous builds left.
#[derive(Default)]
struct State {
    /// Whether any build has written the outputs.
    built_once: bool,
}

/// One build, and its line: `built in ...`, `rebuilt in 12.3 ms: a, b`, `no changes`,
/// or the diagnostics and `error: see above, keeping the last good output`.
///
/// The outputs always equal what a fresh `dieface build` of the last good script
/// writes: every clean rebuild is encoded, and written unless the outputs already hold
/// those very bytes (so a deleted declaration leaves the scene and a moved one carries
/// its new line). An empty (or whitespace-only) script is not built: it is what an
/// editor that saves by truncating and then writing leaves for a moment, and a designer
/// never means "replace my die face by nothing".
fn rebuild(
    plan: &Plan,
    pipeline: &mut Pipeline,
    script: &ScriptArgs,
    state: &mut State,
    viewer: Option<&Viewer>,
) {
    let started = Instant::now();
    if script_is_empty(&script.file, pipeline) {
        if state.built_once {
            eprintln!("warning: the script is empty; keeping the last output");
        } else {
            eprintln!("warning: the script is empty; nothing written yet");
        }
        return;
    }
    if let Some(v) = viewer {
        v.building();
    }
    let name = script
        .file
        .file_stem()
        .map_or_else(|| "die_face".into(), |s| s.to_string_lossy().into_owned());
    let mut on_build = |pipeline: &mut Pipeline, build: &Build| {
        if let Some(v) = viewer {
            publish(v, pipeline, build, &name, started);
        }
    };
    match plan.build(pipeline, script, &mut on_build) {
        Err(msg) => {
            // Typically the moment between an editor's delete and its write: the next
            // event brings the new file.
            eprintln!("warning: {msg}; waiting for the next change");
            if let Some(v) = viewer {
                v.publish_errors(
                    format!("{msg}; waiting for the next change"),
                    started.elapsed(),
                );
            }
        }
        Ok(Built::ScriptErrors(_)) | Ok(Built::WriteFailed) => {
            if state.built_once {
                eprintln!("error: see above, keeping the last good output");
            } else {
                eprintln!("error: see above, no output written yet");
            }
        }
        Ok(Built::Written {
            files,
            reran: ran,
            tessellated,
            ..
        }) => {
            report(
                &files,
                &ran,
                tessellated,
                started.elapsed(),
                state,
                !plan.outputs.is_empty(),
            );
            state.built_once = true;
        }
    }
}

/// Whether the script holds nothing but white space (an empty save, or the moment
/// between an editor's truncate and its write). A script that cannot be read is not
/// called empty: the build reports why.
fn script_is_empty(file: &Path, pipeline: &Pipeline) -> bool {
    crate::eval::paths::read_script(file, pipeline.engine.limits())
        .is_ok_and(|text| text.trim().is_empty())
}

/// The line of a clean rebuild: what it wrote, or `no changes` when every output
/// already held the new bytes.
fn report(
    files: &[OutputFile],
    ran: &[String],
    tessellated: usize,
    took: std::time::Duration,
    state: &State,
    has_outputs: bool,
) {
    let took = ms(took);
    let written: Vec<String> = files
        .iter()
        .filter(|f| !f.unchanged)
        .map(|f| f.path.display().to_string())
        .collect();
    if !has_outputs {
        // `dieface view`: nothing is written; the line says what the viewer got.
        if !state.built_once {
            println!("built in {took}: {} declarations", ran.len());
        } else if ran.is_empty() {
            println!("no changes");
        } else {
            println!(
                "rebuilt in {took}: {}; {tessellated} piece{} tessellated",
                ran.join(", "),
                if tessellated == 1 { "" } else { "s" }
            );
        }
    } else if !state.built_once {
        println!(
            "built in {took}: {} declarations, wrote {}",
            ran.len(),
            written.join(", ")
        );
    } else if written.is_empty() && ran.is_empty() {
        println!("no changes");
    } else if written.is_empty() {
        println!(
            "rebuilt in {took}: {}; the outputs are unchanged",
            ran.join(", ")
        );
    } else if ran.is_empty() {
        println!(
            "rebuilt in {took}: nothing re-ran (all memoized); wrote {}",
            written.join(", ")
        );
    } else {
        println!(
            "rebuilt in {took}: {}; {tessellated} piece{} tessellated",
            ran.join(", "),
            if tessellated == 1 { "" } else { "s" }
        );
    }
}

/// Watches the folder of every file not yet covered (non-recursive).
fn register(watcher: &mut impl Watcher, files: &BTreeSet<PathBuf>, dirs: &mut BTreeSet<PathBuf>) {
    for f in files {
        let Some(dir) = f.parent() else { continue };
        if dirs.contains(dir) {
            continue;
        }
        match watcher.watch(dir, RecursiveMode::NonRecursive) {
            Ok(()) => {
                dirs.insert(dir.to_path_buf());
            }
            Err(e) => eprintln!("warning: cannot watch `{}`: {e}", dir.display()),
        }
    }
}

/// The files on disk the engine has loaded (the script, its imports and the files
/// builtins read, such as a product OBJ), normalized.
/// Diagnostic names are relative to the root; the standard library and `-D` texts are
/// not files and are skipped.
fn loaded_files(engine: &Engine, root: &Path) -> Vec<PathBuf> {
    let root = root.canonicalize().unwrap_or_else(|_| root.to_path_buf());
    (0u32..)
        .map_while(|i| engine.sources.get(crate::syntax::FileId(i)))
        .filter(|f| !f.name.starts_with("-D ") && !f.name.starts_with("--"))
        .filter_map(|f| {
            let p = root.join(&f.name);
            p.is_file().then(|| normalize(&p)).flatten()
        })
        .chain(engine.read_files().iter().filter_map(|p| normalize(p)))
        .collect()
}

/// A path as its canonical folder plus its file name: stable across saves that replace
/// the file (new inode) and comparable with the paths in events.
fn normalize(p: &Path) -> Option<PathBuf> {
    let name = p.file_name()?;
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(dir.canonicalize().ok()?.join(name))
}

/// Whether an event may have changed one of `files`: any creation, modification,
/// rename or removal of such a path (reads are ignored: the build itself reads).
fn relevant(event: &notify::Event, files: &BTreeSet<PathBuf>) -> bool {
    let counts = match event.kind {
        EventKind::Access(AccessKind::Close(AccessMode::Write)) => true,
        EventKind::Access(_) => false,
        _ => true,
    };
    counts
        && event
            .paths
            .iter()
            .any(|p| files.contains(p) || normalize(p).is_some_and(|n| files.contains(&n)))
}
