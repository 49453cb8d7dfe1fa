//! The evaluation engine: files, modules, the declaration graph and the memo.
//!
//! [`Engine::evaluate`] parses a file, loads its imports (the embedded standard library
//! or files relative to it, never outside the project root), builds the graph of its
//! declarations from the names each one uses (directly or through the functions it
//! calls), reports cycles, and evaluates the declarations in dependency order.
//!
//! Memoization: each declaration's result is stored under a hash of its own source text,
//! the file's units, the hashes of the declarations it uses, the text of the functions
//! it calls and the hashes of the modules it imports. Re-evaluating a file after an edit
//! therefore recomputes only the edited declaration and what depends on it; the
//! [`Engine::evaluation_count`] counter makes that observable. Values remember spans; a
//! value taken from the memo has its spans moved to where its declarations now stand.

use std::collections::hash_map::DefaultHasher;
use std::collections::{BTreeSet, HashMap, HashSet};
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::diag::{did_you_mean, Diagnostic, Sources};
use crate::limits::{Limit, Limits};
use crate::syntax::ast::{self, Block, DeclBody, FieldValue, Item};
use crate::syntax::incremental::reparse_with;
use crate::syntax::parse::parse_with;
use crate::syntax::{FileId, Span};

use super::budget::{limit_code, Budget};
use super::deps::{free_names_of_body, free_names_of_function};
use super::expr::{Ctx, Locals, World};
use super::features::{self, FeatureKind, Registry};
use super::layout::{remap, Layout};
use super::paths::{self, resolve_in_root};
use super::stdlib;
use super::units::{self, Units};
use super::value::{Closure, Data, Module, Record, Value};

/// Stack size of each evaluation thread.
const EVAL_STACK_BYTES: usize = 512 << 20;

/// The threads declarations are evaluated on, one per core, made once per process.
///
/// Evaluation recurses with the script's nesting (calls, comprehensions); threads with
/// a large stack keep the 200-call recursion limit reachable in debug builds and in test
/// threads, whose default stacks are small. Declarations that do not depend on each
/// other run on them side by side, and features spread their own work over them.
/// `None` when no thread can be had.
fn evaluation_pool() -> Option<&'static rayon::ThreadPool> {
    static POOL: std::sync::OnceLock<Option<rayon::ThreadPool>> = std::sync::OnceLock::new();
    POOL.get_or_init(|| {
        rayon::ThreadPoolBuilder::new()
            .thread_name(|i| format!("dieface-eval-{i}"))
            .stack_size(EVAL_STACK_BYTES)
            // Each thread's stack is far larger than the parser needs.
            .start_handler(|_| crate::syntax::parse::mark_large_stack())
            .build()
            .ok()
    })
    .as_ref()
}

/// Declaration kinds written with `=` that every engine knows; the feature kinds come
/// from its [`Registry`].
pub const PLAIN_KINDS: &[&str] = &["let", "param", "product"];

/// The names, values and units visible at the top level of one file.
#[derive(Debug, Default)]
pub struct Globals {
    /// Default units for bare numbers.
    pub units: Units,
    /// Evaluated declarations.
    pub decls: HashMap<String, Value>,
    /// User functions.
    pub functions: HashMap<String, Arc<Closure>>,
    /// Imported modules by alias.
    pub imports: HashMap<String, Value>,
    /// Declarations that failed (or sit in a cycle, or depend on a failure).
    pub failed: HashSet<String>,
    /// Every top-level name, for "did you mean".
    pub names: Vec<String>,
}

/// One declaration's outcome.
#[derive(Debug, Clone)]
pub struct DeclResult {
    /// Its kind (`let`, `param`, `product`, ...).
    pub kind: String,
    /// Its name.
    pub name: String,
    /// The whole declaration.
    pub span: Span,
    /// The value, or `None` if it failed or was skipped.
    pub value: Option<Value>,
}

/// What evaluating a file produced.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The evaluated file.
    pub file: FileId,
    /// Its declarations in source order.
    pub decls: Vec<DeclResult>,
    /// Every problem found, in the file and in what it imports.
    pub diagnostics: Vec<Diagnostic>,
}

struct FileState {
    dir: Option<PathBuf>,
    globals: Globals,
    /// Hash of the file's text and of everything it imports.
    module_hash: u64,
}

struct MemoEntry {
    hash: u64,
    value: Value,
    /// Files the evaluation read (with builtins such as `read_obj`) and their content
    /// hashes: the value is stale once one of them changes.
    reads: Vec<(PathBuf, u64)>,
    /// Where each top-level item stood when the value was computed (shared by the
    /// entries of one evaluation of the file).
    layout: Arc<Layout>,
}

/// Evaluates files, keeping loaded modules and memoized declarations between runs.
pub struct Engine {
    /// Every file loaded, for rendering diagnostics.
    pub sources: Sources,
    root: Option<PathBuf>,
    files: HashMap<FileId, FileState>,
    memo: HashMap<(FileId, String), MemoEntry>,
    /// Files read by builtins (`read_obj`) in any evaluation, for `watch`.
    read_files: Vec<PathBuf>,
    /// Where each file's items stood in its last evaluation: an unchanged layout is
    /// shared, so memoized values need no moving.
    layouts: HashMap<FileId, Arc<Layout>>,
    /// The modules loaded by the current evaluation, by name: a module imported again
    /// (a diamond of imports) is evaluated once per evaluation, not once per import;
    /// `None` for one that failed with errors of its own.
    loaded: HashMap<String, Option<FileId>>,
    /// The last parse of each file, by the hash of its text.
    parsed: HashMap<FileId, (u64, Arc<str>, Arc<ast::File>)>,
    evaluations: u64,
    last_evaluated: Vec<String>,
    /// The limits in force (`--limit`).
    limits: Limits,
    /// What the current evaluation has used of them.
    budget: Budget,
    // CLI hooks (see `overrides.rs` and `last_timings`): `-D name=value` texts for the
    // main file's params, and how long each evaluated declaration took.
    overrides: Vec<(String, String)>,
    last_timings: Vec<(String, Duration)>,
    /// The feature kinds blocks are built by.
    registry: Registry,
    /// Pieces of features kept between evaluations (a side, a patch), by their inputs.
    pieces: crate::die::memo::PieceMemo,
}

impl World for Engine {
    fn globals(&self, file: FileId) -> Option<&Globals> {
        self.files.get(&file).map(|f| &f.globals)
    }
    fn paths(&self, file: FileId) -> (Option<&Path>, Option<&Path>) {
        (
            self.files.get(&file).and_then(|f| f.dir.as_deref()),
            self.root.as_deref(),
        )
    }
    fn budget(&self) -> &Budget {
        &self.budget
    }
}

impl Engine {
    /// An engine whose relative imports and file reads stay inside `root` (`None`: no
    /// file access beyond the standard library).
    pub fn new(root: Option<PathBuf>) -> Self {
        Self {
            sources: Sources::new(),
            // A root that cannot be resolved still bounds reads (to nothing), never
            // lifts the bound.
            root: root.map(|r| r.canonicalize().unwrap_or(r)),
            files: HashMap::new(),
            memo: HashMap::new(),
            parsed: HashMap::new(),
            layouts: HashMap::new(),
            loaded: HashMap::new(),
            read_files: Vec::new(),
            evaluations: 0,
            last_evaluated: Vec::new(),
            overrides: Vec::new(),
            last_timings: Vec::new(),
            registry: Registry::standard(),
            limits: Limits::default(),
            budget: Budget::default(),
            pieces: Default::default(),
        }
    }

    /// Sets the limits on the work a script may ask for (`--limit`; see
    /// [`crate::limits`]).
    pub fn set_limits(&mut self, limits: Limits) {
        self.limits = limits;
        self.budget = Budget::new(limits);
    }

    /// The limits in force (see [`crate::limits`]).
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// Sets the command line's `-D name=value` overrides (name, expression text) of the
    /// main file's `param`s; a later entry for the same name wins. See
    /// [`super::overrides`].
    pub fn set_overrides(&mut self, overrides: Vec<(String, String)>) {
        let mut kept: Vec<(String, String)> = Vec::new();
        for (name, text) in overrides {
            kept.retain(|(n, _)| *n != name);
            kept.push((name, text));
        }
        self.overrides = kept;
    }

    /// How long each declaration evaluated by the last [`Engine::evaluate`] took (named
    /// as in [`Engine::last_evaluated`]; memoized ones are absent).
    pub fn last_timings(&self) -> &[(String, Duration)] {
        &self.last_timings
    }

    /// Files that builtins such as `read_obj` have read (absolute paths): `watch` watches
    /// them besides the scripts.
    pub fn read_files(&self) -> &[PathBuf] {
        &self.read_files
    }

    /// How many declarations have been evaluated (not taken from the memo) so far.
    pub fn evaluation_count(&self) -> u64 {
        self.evaluations
    }

    /// The declarations evaluated by the last [`Engine::evaluate`], as `file:name`
    /// for imported files and `name` for the main one, in evaluation order.
    pub fn last_evaluated(&self) -> &[String] {
        &self.last_evaluated
    }

    /// Evaluates the file `name` with contents `text`; `dir` is its directory (relative
    /// imports and `read_obj` start there).
    pub fn evaluate(&mut self, name: &str, text: &str, dir: Option<PathBuf>) -> Outcome {
        match evaluation_pool() {
            // A panic inside is a bug: `install` passes it on rather than hide it.
            Some(pool) => pool.install(|| self.evaluate_here(name, text, dir)),
            // No threads to be had: evaluate here, with the caller's stack.
            None => self.evaluate_here(name, text, dir),
        }
    }

    fn evaluate_here(&mut self, name: &str, text: &str, dir: Option<PathBuf>) -> Outcome {
        self.last_evaluated.clear();
        self.last_timings.clear();
        self.budget = Budget::new(self.limits);
        self.loaded.clear();
        self.pieces.begin();
        let mut diagnostics = Vec::new();
        let mut stack = Vec::new();
        let (file, decls) = self.load(
            name,
            text,
            dir,
            &mut stack,
            &mut diagnostics,
            FileRole::Script,
        );
        // Report in reading order: the script's own problems by position, then those in
        // imported files.
        diagnostics.sort_by_key(|d| {
            (
                d.primary.span.file != file,
                d.primary.span.file,
                d.primary.span.start,
            )
        });
        self.pieces.finish();
        Outcome {
            file,
            decls,
            diagnostics,
        }
    }

    /// Evaluates the script at `path` (read from disk).
    pub fn evaluate_path(&mut self, path: &Path) -> std::io::Result<Outcome> {
        let name = self.display_name(path);
        let text = match crate::diag::read_source(path, &self.limits) {
            Ok(text) => text,
            // Too large or not UTF-8: a diagnostic, not a usage error.
            Err(e) => {
                let d = e.diagnostic(&mut self.sources, &name, &self.limits)?;
                return Ok(Outcome {
                    file: d.primary.span.file,
                    decls: Vec::new(),
                    diagnostics: vec![d],
                });
            }
        };
        let dir = path.parent().map(|p| {
            if p.as_os_str().is_empty() {
                PathBuf::from(".")
            } else {
                p.to_path_buf()
            }
        });
        let dir = dir.and_then(|d| d.canonicalize().ok());
        Ok(self.evaluate(&name, &text, dir))
    }

    /// A path as shown in diagnostics: relative to the root when inside it.
    fn display_name(&self, path: &Path) -> String {
        let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        match &self.root {
            Some(root) => canonical
                .strip_prefix(root)
                .map(|p| p.display().to_string())
                .unwrap_or_else(|_| path.display().to_string()),
            None => path.display().to_string(),
        }
    }

    /// Parses and evaluates one file (the main script or a module).
    fn load(
        &mut self,
        name: &str,
        text: &str,
        dir: Option<PathBuf>,
        stack: &mut Vec<FileId>,
        diagnostics: &mut Vec<Diagnostic>,
        role: FileRole,
    ) -> (FileId, Vec<DeclResult>) {
        let file = self.sources.add(name, text);
        let state = FileState {
            dir: dir.clone(),
            globals: Globals::default(),
            module_hash: hash_of(&text),
        };
        self.files.insert(file, state);
        // Unchanged files (the standard library, untouched imports) are not parsed again;
        // an edited one is re-parsed only where it changed.
        let text_hash = hash_of(&text);
        let previous = self.parsed.get(&file).cloned();
        let ast = match previous {
            Some((h, _, ast)) if h == text_hash => ast,
            _ => {
                let result = match &previous {
                    Some((_, old_text, old_ast)) => {
                        reparse_with(old_text, old_ast, text, file, &self.limits)
                    }
                    None => parse_with(text, file, &self.limits),
                };
                match result {
                    Ok(a) => {
                        let a = Arc::new(a);
                        self.parsed
                            .insert(file, (text_hash, Arc::from(text), a.clone()));
                        a
                    }
                    Err(d) => {
                        diagnostics.push(d);
                        return (file, Vec::new());
                    }
                }
            }
        };
        stack.push(file);
        let items = self.collect(&ast, diagnostics);
        self.parse_standard_imports(&items.imports);
        let units = self.file_units(&items, diagnostics);
        let mut module_hash = hash_of(&text);
        let mut imports: HashMap<String, Value> = HashMap::new();
        let mut import_hashes: HashMap<String, u64> = HashMap::new();
        for imp in &items.imports {
            if let Some((value, h)) = self.import(imp, dir.as_deref(), stack, diagnostics) {
                module_hash = combine(module_hash, h);
                import_hashes.insert(imp.alias.node.clone(), h);
                imports.insert(imp.alias.node.clone(), value);
            }
        }
        stack.pop();

        let functions: HashMap<String, Arc<Closure>> = items
            .functions
            .iter()
            .map(|f| {
                let c = Closure {
                    name: f.name.node.clone(),
                    params: f.params.clone(),
                    body: Arc::new(f.body.clone()),
                    captured: Locals::new(),
                    file,
                };
                (f.name.node.clone(), Arc::new(c))
            })
            .collect();
        {
            let st = self.files.get_mut(&file).expect("inserted above");
            st.module_hash = module_hash;
            st.globals.units = units;
            st.globals.imports = imports;
            st.globals.functions = functions;
            st.globals.names = items.names.clone();
        }

        let layout = item_layout(&items, self.layouts.get(&file));
        self.layouts.insert(file, layout.clone());
        let run = FileRun::new(file, text, &items, role, units, &import_hashes, layout);
        let results = self.evaluate_decls(run, &items, diagnostics);
        (file, results)
    }

    /// Sorts a file's items and reports duplicate names.
    fn collect<'a>(&self, ast: &'a ast::File, diagnostics: &mut Vec<Diagnostic>) -> Items<'a> {
        let mut items = Items::default();
        let mut seen: HashMap<String, Span> = HashMap::new();
        let mut declare = |name: &ast::Ident, diagnostics: &mut Vec<Diagnostic>| -> bool {
            if let Some(prev) = seen.get(&name.node) {
                diagnostics.push(
                    Diagnostic::new(
                        "die::duplicate_name",
                        format!("`{}` is declared twice", name.node),
                        name.span,
                        "declared again here",
                    )
                    .with_label(*prev, "first declared here")
                    .with_help("every top-level name must be unique; rename one of them"),
                );
                false
            } else {
                seen.insert(name.node.clone(), name.span);
                true
            }
        };
        for item in &ast.items {
            match item {
                Item::Import(i) => {
                    if declare(&i.alias, diagnostics) {
                        items.imports.push(i);
                    }
                }
                Item::Units(u) => items.units.push(u),
                Item::Function(f) => {
                    if declare(&f.name, diagnostics) {
                        items.functions.push(f);
                    }
                }
                Item::Decl(d) => {
                    if declare(&d.name, diagnostics) {
                        items.decls.push(d);
                    }
                }
            }
        }
        items.names = seen.into_keys().collect();
        items.names.sort();
        items
    }

    /// The file's default units from its `units` directive.
    fn file_units(&self, items: &Items, diagnostics: &mut Vec<Diagnostic>) -> Units {
        let mut u = Units::default();
        if let Some(extra) = items.units.get(1) {
            diagnostics.push(
                Diagnostic::new(
                    "die::duplicate_units",
                    "a file has one `units` directive",
                    extra.span,
                    "second directive",
                )
                .with_label(items.units[0].span, "first one")
                .with_help("name both units in one directive, e.g. `units cm rad`"),
            );
        }
        if let Some(directive) = items.units.first() {
            for unit in &directive.units {
                let (dim, f) = units::factor(unit.node);
                match dim {
                    super::value::Dim::LENGTH => u.length = f,
                    super::value::Dim::ANGLE => u.angle = f,
                    _ => diagnostics.push(
                        Diagnostic::new(
                            "die::bad_units",
                            format!("`{}` cannot be a default unit", unit.node.symbol()),
                            unit.span,
                            "not a length or angle unit",
                        )
                        .with_help(
                            "default units are a length (mm, cm, m, in) and/or an angle (deg, rad)",
                        ),
                    ),
                }
            }
        }
        u
    }

    /// Loads an import; returns the module value and its hash.
    fn import(
        &mut self,
        imp: &ast::Import,
        dir: Option<&Path>,
        stack: &mut Vec<FileId>,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Option<(Value, u64)> {
        let path = imp.path.node.as_str();
        let (name, text, mdir) = if let Some(rest) = path.strip_prefix("std/") {
            match stdlib::get(rest) {
                Some(text) => (format!("std/{rest}"), text.to_string(), None),
                None => {
                    let d = Diagnostic::new(
                        "die::import_not_found",
                        format!("the standard library has no module `{path}`"),
                        imp.path.span,
                        "no such module",
                    );
                    let d = match did_you_mean(rest, stdlib::names()) {
                        Some(s) => d.with_help(format!("did you mean `std/{s}`?")),
                        None => d.with_help(format!(
                            "standard modules: {}",
                            stdlib::names()
                                .map(|n| format!("std/{n}"))
                                .collect::<Vec<_>>()
                                .join(", ")
                        )),
                    };
                    diagnostics.push(d);
                    return None;
                }
            }
        } else {
            match self.resolve_file(path, dir, imp.path.span) {
                Ok((full, text)) => {
                    let name = self.display_name(&full);
                    let mdir = full.parent().map(Path::to_path_buf);
                    (name, text, mdir)
                }
                Err(d) => {
                    diagnostics.push(d);
                    return None;
                }
            }
        };
        if let Some(existing) = self.sources.find(&name) {
            if let Some(pos) = stack.iter().position(|f| *f == existing) {
                let mut chain: Vec<String> = stack[pos..]
                    .iter()
                    .filter_map(|f| self.sources.get(*f).map(|s| format!("`{}`", s.name)))
                    .collect();
                chain.push(format!("`{name}`"));
                diagnostics.push(
                    Diagnostic::new(
                        "die::import_cycle",
                        format!("modules import each other in a circle: {}", chain.join(" -> ")),
                        imp.path.span,
                        "this import closes the circle",
                    )
                    .with_help("modules cannot import each other in a circle; move what both need into a third module"),
                );
                return None;
            }
        }
        // A module imported again in this evaluation (a diamond of imports) is shared,
        // not evaluated again; `None` marks one that failed.
        let file = match self.loaded.get(&name) {
            Some(&loaded) => loaded?,
            None => {
                let reported = diagnostics.len();
                let (file, _) = self.load(&name, &text, mdir, stack, diagnostics, FileRole::Import);
                // A module with errors of its own is a failed import: its errors are
                // reported once, and what uses it is skipped quietly rather than told the
                // module "has no field".
                let loaded = (diagnostics.len() == reported).then_some(file);
                self.loaded.insert(name, loaded);
                loaded?
            }
        };
        let st = self.files.get(&file)?;
        let mut members: Vec<(String, Value)> = st
            .globals
            .decls
            .iter()
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        members.extend(
            st.globals
                .functions
                .iter()
                .map(|(k, c)| (k.clone(), Value::new(Data::Function(c.clone()), imp.span))),
        );
        members.sort_by(|a, b| a.0.cmp(&b.0));
        let module = Module {
            path: path.to_string(),
            file,
            members,
        };
        Some((
            Value::new(Data::Module(Arc::new(module)), imp.span),
            st.module_hash,
        ))
    }

    /// Parses the standard-library modules among `imports` side by side, ahead of the
    /// imports themselves (which then find them parsed): the fender's four take 10 ms
    /// one after the other, the first thing every cold build waits for. Only the
    /// leading run of `std/` imports, so source ids are given out in the order the
    /// imports give them; a module that does not parse is left for its import to
    /// report.
    fn parse_standard_imports(&mut self, imports: &[&ast::Import]) {
        let mut todo: Vec<(FileId, &'static str)> = Vec::new();
        for imp in imports {
            let Some(text) = imp.path.node.strip_prefix("std/").and_then(stdlib::get) else {
                break;
            };
            let file = self.sources.add(imp.path.node.as_str(), text);
            let parsed = self.parsed.get(&file);
            if parsed.is_none_or(|(h, _, _)| *h != hash_of(&text)) {
                todo.push((file, text));
            }
        }
        if todo.len() < 2 {
            return;
        }
        let limits = self.limits;
        let asts: Vec<_> = todo
            .par_iter()
            .map(|&(file, text)| parse_with(text, file, &limits))
            .collect();
        for ((file, text), ast) in todo.into_iter().zip(asts) {
            if let Ok(ast) = ast {
                self.parsed
                    .insert(file, (hash_of(&text), Arc::from(text), Arc::new(ast)));
            }
        }
    }

    /// Resolves a relative `.die` path against `dir`, refusing other files and paths
    /// outside the root, and reads it (a regular file within the `file_bytes` limit).
    fn resolve_file(
        &self,
        path: &str,
        dir: Option<&Path>,
        span: Span,
    ) -> Result<(PathBuf, String), Diagnostic> {
        paths::check_module_name(path, span)?;
        let full = resolve_in_root(path, dir, self.root.as_deref(), span)?;
        // A regular file within the size limit (the checked reader), then UTF-8 text.
        let bytes = paths::read_regular(&full, self.limits.get(Limit::FileBytes))
            .map_err(|r| paths::refusal_diagnostic(path, &r, span, &self.limits))?;
        let text = crate::diag::decode_source(bytes)
            .map_err(|e| e.import_diagnostic(path, span, &self.limits))?;
        Ok((full, text))
    }

    /// Evaluates a file's declarations in dependency order, with the memo: the order
    /// and the cycles from `run`'s declaration graph first, then (for the script) the
    /// `-D` names, then each declaration in turn.
    fn evaluate_decls(
        &mut self,
        mut run: FileRun,
        items: &Items,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Vec<DeclResult> {
        let (order, in_cycle) = evaluation_order(items, &run.graph, diagnostics);
        if run.role == FileRole::Script {
            self.check_override_names(items, diagnostics);
        }
        for wave in waves(&order, items, &run.graph) {
            self.evaluate_wave(&mut run, items, &wave, &in_cycle, diagnostics);
        }
        self.decl_results(run.file, items)
    }

    /// Evaluates one wave of declarations (none uses another of the same wave; see
    /// [`waves`]): each is skipped, taken from the memo or evaluated fresh in its turn
    /// (see [`Engine::turn_key`]), but the fresh ones without a `-D` override
    /// are evaluated side by side first. Their outcomes are then kept in wave order, so
    /// the memo, the diagnostics and [`Engine::last_evaluated`] are as if evaluated one
    /// after the other.
    fn evaluate_wave(
        &mut self,
        run: &mut FileRun,
        items: &Items,
        wave: &[usize],
        in_cycle: &HashSet<usize>,
        diagnostics: &mut Vec<Diagnostic>,
    ) {
        let mut turns = Vec::with_capacity(wave.len());
        for &i in wave {
            let d = items.decls[i];
            if let Some((key, override_text)) = self.turn_key(run, d, in_cycle.contains(&i)) {
                turns.push((d, key, override_text));
            }
        }
        let plain: Vec<&ast::Decl> = turns
            .iter()
            .filter(|(_, _, o)| o.is_none())
            .map(|(d, _, _)| *d)
            .collect();
        let file = run.file;
        let mut evaluated = if plain.len() > 1 {
            let engine: &Engine = self;
            plain
                .par_iter()
                .map(|d| engine.evaluate_alone(file, d))
                .collect::<Vec<_>>()
        } else {
            plain.iter().map(|d| self.evaluate_alone(file, d)).collect()
        }
        .into_iter();
        for (d, key, override_text) in turns {
            let fresh = match override_text {
                Some(text) => self.evaluate_overridden(file, d, text, run.units),
                // One per declaration without an override, in the same order.
                None => evaluated.next().expect("one evaluation per plain turn"),
            };
            self.settle(run, d.name.node.as_str(), key, fresh, diagnostics);
        }
    }

    /// CLI hook: each `-D` override must name a `param` of the script.
    fn check_override_names(&mut self, items: &Items, diagnostics: &mut Vec<Diagnostic>) {
        if self.overrides.is_empty() {
            return;
        }
        let overrides = self.overrides.clone();
        diagnostics.extend(super::overrides::check_names(
            &mut self.sources,
            &overrides,
            &items.decls,
        ));
    }

    /// Where one declaration stands at its turn: `None` when it is skipped (and marked
    /// failed, so what uses it is skipped too) because it sits in a cycle or uses a
    /// failed import or declaration, or taken from the memo because its key is
    /// unchanged; else its memo key and its `-D` override text, to be evaluated fresh.
    fn turn_key(
        &mut self,
        run: &mut FileRun,
        d: &ast::Decl,
        in_cycle: bool,
    ) -> Option<(u64, Option<String>)> {
        let name = d.name.node.as_str();
        if in_cycle || run.uses_a_failure(name) {
            run.failed.insert(name.to_string());
            self.mark_failed(run.file, name);
            return None;
        }
        let override_text = self.override_for(run.role, d);
        let key = run.memo_key(d, override_text.as_deref());
        run.hashes.insert(name.to_string(), key);
        (!self.reuse_memoized(run, name, key)).then_some((key, override_text))
    }

    /// Takes `name`'s value from the memo when its entry was computed under `key` and
    /// every file it read is unchanged, its spans moved to where the declarations now
    /// stand; what it read joins its key, as when it was computed. Whether it did.
    fn reuse_memoized(&mut self, run: &mut FileRun, name: &str, key: u64) -> bool {
        let fresh = |e: &&MemoEntry| {
            e.hash == key && e.reads.iter().all(|(p, c)| paths::content_hash(p) == *c)
        };
        let Some(entry) = self.memo.get(&(run.file, name.to_string())).filter(fresh) else {
            return false;
        };
        for (_, c) in &entry.reads {
            run.fold_read(name, key, *c);
        }
        let value = remap(&entry.value, &entry.layout, &run.layout, run.file);
        self.set_decl(run.file, name, value);
        true
    }

    /// Evaluates `d` from its body, timed, with the files it read: what may run beside
    /// other declarations of its wave (the engine is only read).
    fn evaluate_alone(&self, file: FileId, d: &ast::Decl) -> Fresh {
        paths::take_reads();
        let started = Instant::now();
        let result = self.evaluate_decl(file, d);
        Fresh {
            took: started.elapsed(),
            reads: paths::take_reads(),
            result,
        }
    }

    /// CLI hook: `d` from its `-D` override text, checked against the value as written.
    fn evaluate_overridden(
        &mut self,
        file: FileId,
        d: &ast::Decl,
        text: String,
        units: Units,
    ) -> Fresh {
        paths::take_reads();
        let started = Instant::now();
        let src = self
            .sources
            .add(super::overrides::source_name(&d.name.node), text.as_str());
        let declared = self.evaluate_decl(file, d);
        let result =
            super::overrides::evaluate_override(src, d, &text, units, declared, &self.limits);
        Fresh {
            took: started.elapsed(),
            reads: paths::take_reads(),
            result,
        }
    }

    /// Counts and records a fresh evaluation of `name`, notes the files it read, and
    /// keeps the outcome.
    fn settle(
        &mut self,
        run: &mut FileRun,
        name: &str,
        key: u64,
        fresh: Fresh,
        diagnostics: &mut Vec<Diagnostic>,
    ) {
        self.record_evaluation(run, name, fresh.took);
        let reads = self.note_reads(run, name, key, fresh.reads);
        self.keep(run, name, key, fresh.result, reads, diagnostics);
    }

    /// Counts one evaluation of `name` and records it and how long it took, for
    /// [`Engine::last_evaluated`] and [`Engine::last_timings`] (a module's
    /// declarations named `file:name`).
    fn record_evaluation(&mut self, run: &FileRun, name: &str, took: Duration) {
        self.evaluations += 1;
        let shown = match run.role {
            FileRole::Script => name.to_string(),
            FileRole::Import => format!(
                "{}:{name}",
                self.sources.get(run.file).map_or("", |f| f.name.as_str())
            ),
        };
        self.last_evaluated.push(shown.clone());
        self.last_timings.push((shown, took));
    }

    /// The files the evaluation of `name` just read (builtins such as `read_obj`), with
    /// their content hashes: each joins `name`'s key (so dependents see a changed
    /// file), and new ones are added to [`Engine::read_files`] for `watch`.
    fn note_reads(
        &mut self,
        run: &mut FileRun,
        name: &str,
        key: u64,
        read: Vec<PathBuf>,
    ) -> Vec<(PathBuf, u64)> {
        let reads: Vec<(PathBuf, u64)> = read
            .into_iter()
            .map(|p| {
                let c = paths::content_hash(&p);
                (p, c)
            })
            .collect();
        for (p, c) in &reads {
            run.fold_read(name, key, *c);
            if !self.read_files.contains(p) {
                self.read_files.push(p.clone());
            }
        }
        reads
    }

    /// Keeps a fresh evaluation's outcome: the value in the file's globals and, unless
    /// it holds a function (whose spans cannot be moved), in the memo under `key`; a
    /// failure reported and marked, so what uses it is skipped.
    fn keep(
        &mut self,
        run: &mut FileRun,
        name: &str,
        key: u64,
        result: Result<Value, Diagnostic>,
        reads: Vec<(PathBuf, u64)>,
        diagnostics: &mut Vec<Diagnostic>,
    ) {
        match result {
            Ok(value) => {
                if !contains_function(&value) {
                    self.memo.insert(
                        (run.file, name.to_string()),
                        MemoEntry {
                            hash: key,
                            value: value.clone(),
                            reads,
                            layout: run.layout.clone(),
                        },
                    );
                }
                self.set_decl(run.file, name, value);
            }
            Err(diag) => {
                // Once the steps have run out, every declaration still to come runs out
                // at once: only the first is reported.
                let budget_limit = [Limit::Work, Limit::MemoryMb]
                    .iter()
                    .any(|&l| diag.code == limit_code(l));
                if !budget_limit || self.budget.first_out_of_work() {
                    diagnostics.push(diag);
                }
                run.failed.insert(name.to_string());
                self.mark_failed(run.file, name);
            }
        }
    }

    /// Each of the file's declarations in source order, with its value (`None` when it
    /// failed or was skipped).
    fn decl_results(&self, file: FileId, items: &Items) -> Vec<DeclResult> {
        items
            .decls
            .iter()
            .map(|d| DeclResult {
                kind: d.kind.node.clone(),
                name: d.name.node.clone(),
                span: d.span,
                value: self
                    .files
                    .get(&file)
                    .and_then(|f| f.globals.decls.get(&d.name.node).cloned()),
            })
            .collect()
    }

    /// The `-D` text for `d` if it is a `param` of the script with an override.
    fn override_for(&self, role: FileRole, d: &ast::Decl) -> Option<String> {
        (role == FileRole::Script && d.kind.node == "param")
            .then(|| self.overrides.iter().find(|(n, _)| *n == d.name.node))
            .flatten()
            .map(|(_, t)| t.clone())
    }

    /// Stores a declaration's value in its file's globals.
    fn set_decl(&mut self, file: FileId, name: &str, value: Value) {
        self.files
            .get_mut(&file)
            // `load` inserts the file's state before it evaluates the declarations.
            .expect("the file's state exists while its declarations are evaluated")
            .globals
            .decls
            .insert(name.to_string(), value);
    }

    /// Records that a declaration failed (or was skipped): it has no value.
    fn mark_failed(&mut self, file: FileId, name: &str) {
        if let Some(st) = self.files.get_mut(&file) {
            st.globals.failed.insert(name.to_string());
            st.globals.decls.remove(name);
        }
    }

    /// How many feature pieces the last evaluation built and how many it reused from
    /// earlier ones ([`crate::die::memo`]).
    pub fn piece_counts(&self) -> (usize, usize) {
        self.pieces.counts()
    }

    /// The feature kinds this engine builds blocks with.
    pub fn registry(&self) -> &Registry {
        &self.registry
    }

    /// The die model of an outcome of this engine (see [`super::model::die_model`]).
    pub fn die_model(&self, outcome: &Outcome) -> crate::die::model::DieModel {
        super::model::die_model(outcome, &self.sources, &self.registry)
    }

    /// Every declaration kind this engine knows: the plain ones, then the features.
    pub fn kinds(&self) -> Vec<&'static str> {
        PLAIN_KINDS
            .iter()
            .copied()
            .chain(self.registry.names())
            .collect()
    }

    /// Adds a feature kind to this engine's registry: `kind name { ... }` blocks are then
    /// built by it (a plug-in feature, or a test's).
    pub fn register(&mut self, kind: &'static dyn FeatureKind) {
        self.registry.register(kind);
    }

    /// The diagnostic for a declaration whose kind no one knows.
    fn unknown_kind(&self, d: &ast::Decl) -> Diagnostic {
        let kind = d.kind.node.as_str();
        let kinds = self.kinds();
        let diag = Diagnostic::new(
            "die::unknown_kind",
            format!("`{kind}` is not a kind of declaration"),
            d.kind.span,
            "unknown kind",
        );
        match did_you_mean(kind, kinds.iter().copied()) {
            Some(s) => diag.with_help(format!("did you mean `{s}`?")),
            None => diag.with_help(format!(
                "declarations start with one of: {}",
                kinds.join(", ")
            )),
        }
    }

    /// Evaluates one declaration's body and checks it against its kind.
    fn evaluate_decl(&self, file: FileId, d: &ast::Decl) -> Result<Value, Diagnostic> {
        let kind = d.kind.node.as_str();
        let feature = self.registry.get(kind);
        if feature.is_none() && !PLAIN_KINDS.contains(&kind) {
            return Err(self.unknown_kind(d));
        }
        let ctx = Ctx {
            world: self,
            file,
            decl: Some(d.name.node.as_str()),
            depth: 0,
            call: None,
        };
        if let Some(feature) = feature {
            return self.evaluate_feature(feature, &ctx, d);
        }
        let value = match &d.body {
            DeclBody::Expr(e) => ctx.eval(e, &Locals::new())?,
            DeclBody::Block(b) => {
                let mut rec = block(&ctx, b)?;
                rec.kind = Some(kind.to_string());
                Value::new(Data::Record(Arc::new(rec)), d.span)
            }
        };
        if kind == "product" {
            check_product(&value)?;
        }
        Ok(value)
    }

    /// A feature block (`punch_opening`, `step_draw`, ...): its fields evaluated, with
    /// where each field's name was written, and handed to [`features::build`].
    fn evaluate_feature(
        &self,
        feature: &dyn FeatureKind,
        ctx: &Ctx,
        d: &ast::Decl,
    ) -> Result<Value, Diagnostic> {
        let kind = d.kind.node.as_str();
        let DeclBody::Block(b) = &d.body else {
            return Err(Diagnostic::new(
                "die::feature_block",
                format!("a `{kind}` is written as a block of fields"),
                d.name.span.to(d.span),
                "written with `=`",
            )
            .with_help(format!(
                "write `{kind} {} {{ field = value ... }}`; see docs/language.md",
                d.name.node
            )));
        };
        let rec = block(ctx, b)?;
        let fields = b
            .fields
            .iter()
            .zip(rec.fields)
            .map(|(f, (_, value))| features::Field {
                words: f.path.iter().map(|w| w.node.clone()).collect(),
                name_span: match (f.path.first(), f.path.last()) {
                    (Some(a), Some(z)) => a.span.to(z.span),
                    _ => f.span,
                },
                value,
            })
            .collect();
        let apply = |g: &Value, args: Vec<Value>, s: Span| ctx.apply(g, args, Vec::new(), s);
        let text = |s: Span| self.sources.slice(s).to_string();
        features::build(
            feature,
            &features::Block {
                kind,
                name: &d.name.node,
                span: d.span,
                fields,
                units: ctx.units(),
                apply: &apply,
                text: &text,
                pieces: self
                    .pieces
                    .for_owner(format!("{}:{}", ctx.file.0, d.name.node)),
            },
        )
    }
}

/// A product is a surface, a mesh, or a list of them.
fn check_product(v: &Value) -> Result<(), Diagnostic> {
    let ok = |d: &Data| matches!(d, Data::Surface(_) | Data::Trimmed(_) | Data::Mesh(_));
    let fine = match &v.data {
        Data::List(items) => !items.is_empty() && items.iter().all(|i| ok(&i.data)),
        d => ok(d),
    };
    if fine {
        Ok(())
    } else {
        Err(Diagnostic::new(
            "die::type_mismatch",
            format!("a product must be a surface, a trimmed surface, a mesh or a list of them, but this is {}", v.type_name()),
            v.span,
            format!("this is {}", v.type_name()),
        )
        .with_help("build the panel with `nurbs_surface(...)`, `loft(...)`, `coons(...)` and trim it at its outline with `trim(panel, outline)`, or read it with `read_obj(\"part.obj\")`"))
    }
}

/// Evaluates a block's fields into a record (field names of several words joined by a
/// space: `side front`).
fn block(ctx: &Ctx, b: &Block) -> Result<Record, Diagnostic> {
    let mut rec = Record::default();
    // Where each field's name was written, for the duplicate-field labels.
    let name_span = |f: &ast::Field| match (f.path.first(), f.path.last()) {
        (Some(a), Some(z)) => a.span.to(z.span),
        _ => f.span,
    };
    for (k, f) in b.fields.iter().enumerate() {
        let name = f
            .path
            .iter()
            .map(|w| w.node.as_str())
            .collect::<Vec<_>>()
            .join(" ");
        if rec.get(&name).is_some() {
            let first = b.fields[..k].iter().find(|g| {
                g.path
                    .iter()
                    .map(|w| w.node.as_str())
                    .collect::<Vec<_>>()
                    .join(" ")
                    == name
            });
            let mut d = Diagnostic::new(
                "die::duplicate_field",
                format!("the field `{name}` is given twice"),
                name_span(f),
                "given again here",
            );
            if let Some(first) = first {
                d = d.with_label(name_span(first), "first given here");
            }
            return Err(d.with_help("remove one of them"));
        }
        let value = match &f.value {
            FieldValue::Expr(e) => ctx.eval(e, &Locals::new())?,
            FieldValue::Block(inner) => {
                Value::new(Data::Record(Arc::new(block(ctx, inner)?)), inner.span)
            }
        };
        rec.fields.push((name, value));
    }
    Ok(rec)
}

/// A file's items by category.
#[derive(Default)]
struct Items<'a> {
    imports: Vec<&'a ast::Import>,
    units: Vec<&'a ast::UnitsDirective>,
    functions: Vec<&'a ast::FnDecl>,
    decls: Vec<&'a ast::Decl>,
    names: Vec<String>,
}

/// Which file [`Engine::load`] is evaluating: only the script's `param`s take `-D`
/// overrides, and only its declarations are listed by their bare names in
/// [`Engine::last_evaluated`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FileRole {
    /// The script given to [`Engine::evaluate`].
    Script,
    /// A module the script (or another module) imports.
    Import,
}

/// A file's declaration graph: the names each declaration uses, directly or through
/// the functions it calls, and the imports that failed to load.
struct DeclGraph<'a> {
    /// The file's declarations by name.
    decl_names: HashSet<&'a str>,
    /// Every name each declaration uses, closed over the functions it calls (the
    /// functions themselves only where the declaration names them).
    uses: HashMap<&'a str, BTreeSet<String>>,
    /// Each function's text hash, closed over the functions it calls: part of the
    /// memo key of a declaration that calls it.
    fn_hash: HashMap<&'a str, u64>,
    /// Imports that failed (already reported): what uses them is skipped quietly.
    failed_imports: HashSet<&'a str>,
}

impl<'a> DeclGraph<'a> {
    /// The graph of `items` (whose source is `text`); `import_hashes` holds the
    /// imports that loaded.
    fn new(items: &Items<'a>, text: &str, import_hashes: &HashMap<String, u64>) -> Self {
        let reach = function_reach(items, text);
        // Each declaration's direct and indirect (through functions) names.
        let uses = items
            .decls
            .iter()
            .map(|d| {
                let mut u = free_names_of_body(&d.body);
                let via: Vec<&str> = u
                    .iter()
                    .filter_map(|n| reach.names.get_key_value(n.as_str()).map(|(k, _)| *k))
                    .collect();
                for f in via {
                    if let Some(more) = reach.names.get(f) {
                        u.extend(more.iter().cloned());
                    }
                }
                (d.name.node.as_str(), u)
            })
            .collect();
        Self {
            decl_names: items.decls.iter().map(|d| d.name.node.as_str()).collect(),
            uses,
            fn_hash: reach.hashes,
            failed_imports: items
                .imports
                .iter()
                .map(|i| i.alias.node.as_str())
                .filter(|a| !import_hashes.contains_key(*a))
                .collect(),
        }
    }

    /// The other declarations of the file that `name` uses: its edges.
    fn deps(&self, name: &str) -> Vec<&str> {
        self.uses.get(name).map_or_else(Vec::new, |u| {
            u.iter()
                .filter(|n| self.decl_names.contains(n.as_str()) && n.as_str() != name)
                .map(|n| n.as_str())
                .collect()
        })
    }

    /// Whether `name` uses an import that failed.
    fn uses_failed_import(&self, name: &str) -> bool {
        self.uses
            .get(name)
            .is_some_and(|u| u.iter().any(|n| self.failed_imports.contains(n.as_str())))
    }
}

/// What each function reaches through the functions it calls, directly or not.
struct FnReach<'a> {
    /// The names other than the file's functions that it and its callees use.
    names: HashMap<&'a str, BTreeSet<String>>,
    /// A hash of its text and its callees' texts.
    hashes: HashMap<&'a str, u64>,
}

/// What each function of `items` (whose source is `text`) reaches (a declaration that
/// calls `f` depends on everything `f` and its callees use). The functions are taken
/// by groups that call each other (strongly connected components), callees first, so
/// each group is closed once over its callees' results: linear in the calls, where
/// closing every function over every other grew with the cube of a chain of calls.
fn function_reach<'a>(items: &Items<'a>, text: &str) -> FnReach<'a> {
    let fns = &items.functions;
    let index: HashMap<&str, usize> = fns
        .iter()
        .enumerate()
        .map(|(i, f)| (f.name.node.as_str(), i))
        .collect();
    let direct: Vec<BTreeSet<String>> = fns
        .iter()
        .map(|f| free_names_of_function(&f.params, &f.body))
        .collect();
    let calls: Vec<Vec<usize>> = direct
        .iter()
        .map(|u| {
            u.iter()
                .filter_map(|n| index.get(n.as_str()).copied())
                .collect()
        })
        .collect();
    let mut group_names: Vec<BTreeSet<String>> = Vec::new();
    let mut group_hash: Vec<u64> = Vec::new();
    let mut group_of: Vec<usize> = vec![usize::MAX; fns.len()];
    for group in call_groups(&calls) {
        let g = group_names.len();
        for &m in &group {
            group_of[m] = g;
        }
        let mut names = BTreeSet::new();
        let mut texts: Vec<&str> = group.iter().map(|&m| &text[fns[m].span.range()]).collect();
        texts.sort_unstable();
        let mut callee_hashes = BTreeSet::new();
        for &m in &group {
            names.extend(
                direct[m]
                    .iter()
                    .filter(|n| !index.contains_key(n.as_str()))
                    .cloned(),
            );
            for &c in &calls[m] {
                let cg = group_of[c];
                if cg != g {
                    names.extend(group_names[cg].iter().cloned());
                    callee_hashes.insert(group_hash[cg]);
                }
            }
        }
        group_names.push(names);
        group_hash.push(hash_of(&(texts, callee_hashes)));
    }
    let mut reach = FnReach {
        names: HashMap::new(),
        hashes: HashMap::new(),
    };
    for (i, f) in fns.iter().enumerate() {
        let name = f.name.node.as_str();
        reach.names.insert(name, group_names[group_of[i]].clone());
        reach.hashes.insert(name, group_hash[group_of[i]]);
    }
    reach
}

/// The groups of functions that call each other (Tarjan's strongly connected
/// components of the call graph `calls`), each after every group it calls.
fn call_groups(calls: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut t = Tarjan {
        calls,
        index: vec![None; calls.len()],
        low: vec![0; calls.len()],
        on_stack: vec![false; calls.len()],
        stack: Vec::new(),
        next: 0,
        groups: Vec::new(),
    };
    for v in 0..calls.len() {
        if t.index[v].is_none() {
            t.connect(v);
        }
    }
    t.groups
}

/// The state of Tarjan's algorithm over a call graph.
struct Tarjan<'g> {
    calls: &'g [Vec<usize>],
    index: Vec<Option<usize>>,
    low: Vec<usize>,
    on_stack: Vec<bool>,
    stack: Vec<usize>,
    next: usize,
    groups: Vec<Vec<usize>>,
}

impl Tarjan<'_> {
    /// Visits `v` and what it calls; closes `v`'s group when `v` is its root.
    fn connect(&mut self, v: usize) {
        self.index[v] = Some(self.next);
        self.low[v] = self.next;
        self.next += 1;
        self.stack.push(v);
        self.on_stack[v] = true;
        let calls = self.calls;
        for &w in &calls[v] {
            match self.index[w] {
                None => {
                    self.connect(w);
                    self.low[v] = self.low[v].min(self.low[w]);
                }
                Some(iw) if self.on_stack[w] => self.low[v] = self.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(self.low[v]) == self.index[v] {
            let mut group = Vec::new();
            while let Some(w) = self.stack.pop() {
                self.on_stack[w] = false;
                group.push(w);
                if w == v {
                    break;
                }
            }
            self.groups.push(group);
        }
    }
}

/// The order to evaluate the declarations in (depth-first post-order, source order
/// first: each after what it uses) and those that sit in a cycle, each cycle reported
/// once; a self-reference (`let a = a + 1`) is a cycle of one.
fn evaluation_order(
    items: &Items,
    graph: &DeclGraph,
    diagnostics: &mut Vec<Diagnostic>,
) -> (Vec<usize>, HashSet<usize>) {
    let index: HashMap<&str, usize> = items
        .decls
        .iter()
        .enumerate()
        .map(|(i, d)| (d.name.node.as_str(), i))
        .collect();
    let deps = |name: &str| graph.deps(name);
    let mut order = Vec::new();
    let mut state = vec![0u8; items.decls.len()]; // 0 new, 1 on stack, 2 done
    let mut in_cycle: HashSet<usize> = HashSet::new();
    for start in 0..items.decls.len() {
        visit(
            start,
            &items.decls,
            &index,
            &deps,
            &mut state,
            &mut Vec::new(),
            &mut order,
            &mut in_cycle,
            diagnostics,
        );
    }
    for (i, d) in items.decls.iter().enumerate() {
        if graph
            .uses
            .get(d.name.node.as_str())
            .is_some_and(|u| u.contains(&d.name.node))
            && !in_cycle.contains(&i)
        {
            in_cycle.insert(i);
            diagnostics.push(
                Diagnostic::new("die::cycle", format!("`{}` is defined in terms of itself", d.name.node), d.name.span, "this declaration")
                    .with_help("a declaration cannot use its own value; give it a value that does not refer to it"),
            );
        }
    }
    (order, in_cycle)
}

/// Where each top-level declaration and function stands in the file (a memoized
/// value's spans move by how far its declaration moved); `previous` when unchanged.
fn item_layout(items: &Items, previous: Option<&Arc<Layout>>) -> Arc<Layout> {
    let decls = items.decls.iter().map(|d| (d.name.node.as_str(), d.span));
    let functions = items
        .functions
        .iter()
        .map(|f| (f.name.node.as_str(), f.span));
    Layout::shared(decls.chain(functions), previous)
}

/// A declaration evaluated fresh: its outcome, how long it took and the files it read.
struct Fresh {
    result: Result<Value, Diagnostic>,
    took: Duration,
    reads: Vec<PathBuf>,
}

/// The evaluation order cut into waves: each declaration goes into the latest wave that
/// still comes before every declaration of this file that uses it (as late as
/// possible), so no declaration uses another of its own wave and a wave's declarations
/// can be evaluated side by side. Within a wave, declarations keep their order in
/// `order`.
///
/// As late as possible, not as early: the features are what takes time, and they are
/// mostly what nothing else uses, so they all land in the last wave and run side by side
/// whatever the length of the chains of cheap declarations that lead to each (the
/// fender's step draw waits for a product four declarations deep, its beads for a
/// binder two deep; as early as possible, the step draw ran only after both beads).
fn waves(order: &[usize], items: &Items, graph: &DeclGraph) -> Vec<Vec<usize>> {
    // How many waves must follow each declaration: one more than the most any of its
    // users needs. `order` puts every declaration after what it uses, so walking it
    // backwards sees each user before what it uses.
    let position: HashMap<&str, usize> = order
        .iter()
        .enumerate()
        .map(|(k, &i)| (items.decls[i].name.node.as_str(), k))
        .collect();
    let mut after = vec![0usize; order.len()];
    for k in (0..order.len()).rev() {
        let name = items.decls[order[k]].name.node.as_str();
        for dep in graph.deps(name) {
            if let Some(&j) = position.get(dep) {
                if j < k {
                    after[j] = after[j].max(after[k] + 1);
                }
            }
        }
    }
    let last = after.iter().copied().max().unwrap_or(0);
    let mut waves: Vec<Vec<usize>> = vec![Vec::new(); last + 1];
    for (k, &i) in order.iter().enumerate() {
        waves[last - after[k]].push(i);
    }
    waves
}

/// One file's declarations being evaluated: what the memo keys are made of, and the
/// keys and failures so far.
struct FileRun<'a> {
    file: FileId,
    text: &'a str,
    role: FileRole,
    units: Units,
    /// The hash of each import that loaded, by alias.
    import_hashes: &'a HashMap<String, u64>,
    /// Where the file's items stand now (see [`item_layout`]).
    layout: Arc<Layout>,
    graph: DeclGraph<'a>,
    /// The memo key of each declaration evaluated so far, with the content of the
    /// files it read folded in: part of its dependents' keys.
    hashes: HashMap<String, u64>,
    /// Declarations that failed or were skipped.
    failed: HashSet<String>,
}

impl<'a> FileRun<'a> {
    /// The run over `items`, the declarations of `file` (whose source is `text`), with
    /// its declaration graph; `import_hashes` holds the imports that loaded.
    fn new(
        file: FileId,
        text: &'a str,
        items: &Items<'a>,
        role: FileRole,
        units: Units,
        import_hashes: &'a HashMap<String, u64>,
        layout: Arc<Layout>,
    ) -> Self {
        FileRun {
            file,
            text,
            role,
            units,
            import_hashes,
            layout,
            graph: DeclGraph::new(items, text, import_hashes),
            hashes: HashMap::new(),
            failed: HashSet::new(),
        }
    }

    /// Whether `name` uses a failed import or a declaration that failed or was skipped.
    fn uses_a_failure(&self, name: &str) -> bool {
        self.graph.uses_failed_import(name)
            || self
                .graph
                .deps(name)
                .iter()
                .any(|dep| self.failed.contains(*dep))
    }

    /// The memo key of `d`: its own text, the file's units, the name and key of each
    /// declaration it uses, the text of each function and the hash of each module it
    /// uses, and its `-D` override's text.
    fn memo_key(&self, d: &ast::Decl, override_text: Option<&str>) -> u64 {
        let name = d.name.node.as_str();
        let mut h = hash_of(&self.text[d.span.range()]);
        h = combine(
            h,
            hash_of(&(self.units.length.to_bits(), self.units.angle.to_bits())),
        );
        for dep in self.graph.deps(name) {
            h = combine(h, hash_of(&dep));
            h = combine(h, self.hashes.get(dep).copied().unwrap_or(0));
        }
        if let Some(u) = self.graph.uses.get(name) {
            for n in u {
                if let Some(fh) = self.graph.fn_hash.get(n.as_str()) {
                    h = combine(h, *fh);
                }
                if let Some(mh) = self.import_hashes.get(n) {
                    h = combine(h, *mh);
                }
            }
        }
        // CLI hook: a `-D` override's text is part of its param's memo key.
        if let Some(t) = override_text {
            h = combine(h, hash_of(t));
        }
        h
    }

    /// Folds the content hash of a file `name` read into its key (`key` until then).
    fn fold_read(&mut self, name: &str, key: u64, content: u64) {
        let folded = combine(self.hashes.get(name).copied().unwrap_or(key), content);
        self.hashes.insert(name.to_string(), folded);
    }
}

/// Depth-first visit for the evaluation order, reporting each cycle once.
#[allow(clippy::too_many_arguments)]
fn visit<'a>(
    i: usize,
    decls: &[&'a ast::Decl],
    index: &HashMap<&str, usize>,
    deps: &dyn Fn(&str) -> Vec<&'a str>,
    state: &mut [u8],
    path: &mut Vec<usize>,
    order: &mut Vec<usize>,
    in_cycle: &mut HashSet<usize>,
    diagnostics: &mut Vec<Diagnostic>,
) {
    if state[i] == 2 {
        return;
    }
    if state[i] == 1 {
        // A cycle: the part of the path from i onwards.
        let pos = path.iter().position(|&p| p == i).unwrap_or(0);
        let cycle: Vec<usize> = path[pos..].to_vec();
        if cycle.iter().all(|c| !in_cycle.contains(c)) {
            let names: Vec<&str> = cycle.iter().map(|&c| decls[c].name.node.as_str()).collect();
            let first = decls[cycle[0]];
            let mut d = Diagnostic::new(
                "die::cycle",
                format!(
                    "these declarations depend on each other in a circle: {} -> {}",
                    names.join(" -> "),
                    names[0]
                ),
                first.name.span,
                format!(
                    "`{}` uses `{}`",
                    names[0],
                    names.get(1).unwrap_or(&names[0])
                ),
            );
            for (k, &c) in cycle.iter().enumerate().skip(1) {
                let next = names[(k + 1) % names.len()];
                d = d.with_label(decls[c].name.span, format!("`{}` uses `{next}`", names[k]));
            }
            diagnostics.push(
                d.with_help("break the circle: one of them must be computed without the others"),
            );
        }
        in_cycle.extend(cycle);
        return;
    }
    state[i] = 1;
    path.push(i);
    for dep in deps(&decls[i].name.node) {
        if let Some(&j) = index.get(dep) {
            visit(
                j,
                decls,
                index,
                deps,
                state,
                path,
                order,
                in_cycle,
                diagnostics,
            );
        }
    }
    path.pop();
    state[i] = 2;
    order.push(i);
}

fn hash_of<T: Hash + ?Sized>(t: &T) -> u64 {
    let mut h = DefaultHasher::new();
    t.hash(&mut h);
    h.finish()
}

fn combine(a: u64, b: u64) -> u64 {
    hash_of(&(a, b))
}

/// Whether a value holds a function (such values are not memoized: their bodies'
/// spans cannot be moved).
fn contains_function(v: &Value) -> bool {
    match &v.data {
        Data::Function(_) => true,
        Data::List(items) | Data::Tuple(items) => items.iter().any(contains_function),
        Data::Record(r) => r.fields.iter().any(|(_, v)| contains_function(v)),
        _ => false,
    }
}
