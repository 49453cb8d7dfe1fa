//! File paths named in scripts: imports and `read_obj`.
//!
//! Paths are relative to the directory of the script that names them and must stay
//! inside the project root (after resolving `..` and symbolic links), so a script
//! cannot read arbitrary files of the machine it is built on.

use std::cell::RefCell;
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

thread_local! {
    /// Files read by builtins during the declaration being evaluated.
    static READS: RefCell<Vec<PathBuf>> = const { RefCell::new(Vec::new()) };
}

/// Records that the declaration being evaluated read `path` (a product OBJ, say): its
/// memoized value is then only reused while the file is unchanged, and `watch` watches it.
pub fn record_read(path: &Path) {
    READS.with(|r| r.borrow_mut().push(path.to_path_buf()));
}

/// The files recorded since the last call, and forgets them.
pub fn take_reads() -> Vec<PathBuf> {
    READS.with(|r| std::mem::take(&mut *r.borrow_mut()))
}

/// A hash of a file's bytes (0 when it cannot be read): what a memoized value that read
/// the file is checked against.
pub fn content_hash(path: &Path) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    match std::fs::read(path) {
        Ok(bytes) => bytes.hash(&mut h),
        Err(_) => 0u8.hash(&mut h),
    }
    h.finish()
}
