//! File paths named in scripts: imports and `read_obj`.
//!
//! Paths are relative to the directory of the script that names them and must stay
//! inside the project root (after resolving `..` and symbolic links), so a script
//! cannot read arbitrary files of the machine it is built on.

use std::path::{Component, Path, PathBuf};

use crate::diag::Diagnostic;
use crate::syntax::Span;

/// The file `path` names, relative to `dir` (the naming script's directory), checked to
/// exist and to lie inside `root` (`None`: no limit). `span` is where the path is written.
pub fn resolve_in_root(
    path: &str,
    dir: Option<&Path>,
    root: Option<&Path>,
    span: Span,
) -> Result<PathBuf, Diagnostic> {
    let Some(dir) = dir else {
        return Err(Diagnostic::new(
            "die::file_not_found",
            format!("`{path}` cannot be read here"),
            span,
            "no script directory",
        )
        .with_help(
            "files can be read only by scripts in a project directory, not by the standard library",
        ));
    };
    let joined = normalize(&dir.join(path));
    let root = root.map(|r| r.canonicalize().unwrap_or_else(|_| normalize(r)));
    let escapes = |p: &Path| root.as_ref().is_some_and(|r| !p.starts_with(r));
    let escape = || {
        Diagnostic::new("die::path_escapes_root", format!("`{path}` lies outside the project folder"), span, "outside the project")
            .with_help("scripts may only read files inside the project folder (the script's folder, or --root); move the file there and name it relative to the script")
    };
    match joined.canonicalize() {
        Ok(full) if escapes(&full) => Err(escape()),
        Ok(full) => Ok(full),
        Err(_) if escapes(&canonical_prefix(&joined)) => Err(escape()),
        Err(_) => Err(Diagnostic::new(
            "die::file_not_found",
            format!("`{path}` does not exist (looked relative to this script's folder)"),
            span,
            "no such file",
        )
        .with_help("paths are relative to the directory of the script that names them")),
    }
}

/// `a/b/../c` -> `a/c`, without touching the file system.
fn normalize(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// A path that may not exist, with its longest existing ancestor canonicalized (so it
/// compares with the canonical root even through symbolic links).
fn canonical_prefix(p: &Path) -> PathBuf {
    let mut existing = p;
    let mut rest = Vec::new();
    loop {
        if let Ok(mut out) = existing.canonicalize() {
            out.extend(rest.iter().rev());
            return out;
        }
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name);
                existing = parent;
            }
            _ => return p.to_path_buf(),
        }
    }
}
