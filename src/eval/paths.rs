//! File paths named in scripts, and reading them: imports, `read_obj` and the MTL an
//! OBJ names.
//!
//! Paths are relative to the directory of the script that names them and must stay
//! inside the project root (after resolving `..` and symbolic links), so a script
//! cannot read arbitrary files of the machine it is built on. Every file the program
//! reads (the script, its modules, an OBJ, its MTL) is read by [`read_regular`]: only a
//! regular file, never a FIFO or a device (which would block or never end), and never
//! more than the `file_bytes` limit, checked before a byte is read.

use std::cell::RefCell;
use std::fs::{File, Metadata};
use std::io::{self, Read};
use std::path::{Component, Path, PathBuf};

use crate::diag::Diagnostic;
use crate::limits::{Limit, Limits};
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
    // No root (an engine made without one) reads nothing from disk; a root that does
    // not exist (the command line refuses one) contains nothing.
    let root = root.map(|r| r.canonicalize().unwrap_or_else(|_| normalize(r)));
    let escapes = |p: &Path| root.as_ref().is_none_or(|r| !p.starts_with(r));
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

/// A hash of a file's bytes (0 when it cannot be read, or is no longer a regular
/// file): what a memoized value that read the file is checked against.
pub fn content_hash(path: &Path) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    match read_regular(path, u64::MAX) {
        Ok(bytes) => bytes.hash(&mut h),
        Err(_) => 0u8.hash(&mut h),
    }
    h.finish()
}

/// Why a file could not be read by [`read_regular`].
#[derive(Debug)]
pub enum ReadRefusal {
    /// The path names something other than a regular file (a folder, a FIFO, a
    /// device, a socket), named in words.
    NotRegular(&'static str),
    /// The file holds more bytes than the `file_bytes` limit allows.
    TooLarge {
        /// Its size in bytes (at least the limit plus one when it grew while read).
        bytes: u64,
    },
    /// The system refused (permissions, a vanished file).
    Io(io::Error),
}

impl std::fmt::Display for ReadRefusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadRefusal::NotRegular(kind) => {
                write!(f, "it is {kind}, not a regular file")
            }
            ReadRefusal::TooLarge { bytes } => write!(f, "it holds {bytes} bytes"),
            ReadRefusal::Io(e) => write!(f, "{e}"),
        }
    }
}

/// The bytes of the regular file at `path`, at most `max_bytes` of them.
///
/// The file's type and size are checked from its metadata before it is opened (so a
/// FIFO or a device is never opened at all), then again on the open file (it is opened
/// non-blocking, so a FIFO swapped in between cannot block the open), and the read
/// stops one byte past the limit (so a file that grows while read cannot exhaust
/// memory).
pub fn read_regular(path: &Path, max_bytes: u64) -> Result<Vec<u8>, ReadRefusal> {
    check_regular(
        &std::fs::metadata(path).map_err(ReadRefusal::Io)?,
        max_bytes,
    )?;
    let file = open_nonblocking(path).map_err(ReadRefusal::Io)?;
    check_regular(&file.metadata().map_err(ReadRefusal::Io)?, max_bytes)?;
    let mut bytes = Vec::new();
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(ReadRefusal::Io)?;
    if bytes.len() as u64 > max_bytes {
        return Err(ReadRefusal::TooLarge {
            bytes: bytes.len() as u64,
        });
    }
    Ok(bytes)
}

/// [`read_regular`] of a text file: the bytes as UTF-8 (an error of kind `InvalidData`
/// when they are not).
pub fn read_regular_text(path: &Path, max_bytes: u64) -> Result<String, ReadRefusal> {
    let bytes = read_regular(path, max_bytes)?;
    String::from_utf8(bytes).map_err(|e| {
        ReadRefusal::Io(io::Error::new(
            io::ErrorKind::InvalidData,
            not_utf8(e.as_bytes(), e.utf8_error().valid_up_to()),
        ))
    })
}

/// Where a text stops being UTF-8, in words: the byte and its line and column (the
/// file cannot be shown, so the message says where to look).
fn not_utf8(bytes: &[u8], at: usize) -> String {
    let before = &bytes[..at.min(bytes.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let column = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    let byte = bytes.get(at).copied().unwrap_or(0);
    format!(
        "the file is not UTF-8 text: byte 0x{byte:02X} at line {line}, column {column}; save it as UTF-8"
    )
}

/// Checks, from its metadata and without opening it, that `path` is a regular file of
/// at most `max_bytes` (what [`read_regular`] checks first): for a command line's
/// early "cannot read" message.
pub fn check_regular_path(path: &Path, max_bytes: u64) -> Result<(), ReadRefusal> {
    check_regular(
        &std::fs::metadata(path).map_err(ReadRefusal::Io)?,
        max_bytes,
    )
}

/// Refuses what is not a regular file, or is larger than `max_bytes`.
fn check_regular(meta: &Metadata, max_bytes: u64) -> Result<(), ReadRefusal> {
    if !meta.is_file() {
        return Err(ReadRefusal::NotRegular(file_kind(meta)));
    }
    if meta.len() > max_bytes {
        return Err(ReadRefusal::TooLarge { bytes: meta.len() });
    }
    Ok(())
}

/// What a path that is not a regular file is, in words.
fn file_kind(meta: &Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
    }
    "not a regular file"
}

/// Opens `path` for reading without blocking on a FIFO that has no writer.
fn open_nonblocking(path: &Path) -> io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    options.open(path)
}

/// A [`ReadRefusal`] of the file `shown` (as the script wrote it) as a diagnostic at
/// `span`: `die::not_a_file` for what is not a regular file, `die::limit` with the
/// limit's help for a file over `file_bytes`, `die::file_not_found` otherwise.
pub fn refusal_diagnostic(
    shown: &str,
    refusal: &ReadRefusal,
    span: Span,
    limits: &Limits,
) -> Diagnostic {
    match refusal {
        ReadRefusal::NotRegular(kind) => Diagnostic::new(
            "die::not_a_file",
            format!("`{shown}` is {kind}, not a regular file"),
            span,
            "not a regular file",
        )
        .with_help("scripts read regular files only (a folder, a named pipe or a device cannot be read); name the file itself"),
        ReadRefusal::TooLarge { bytes } => Diagnostic::new(
            "die::limit::file_bytes",
            format!(
                "`{shown}` holds {bytes} bytes, more than the `{}` limit allows",
                Limit::FileBytes
            ),
            span,
            "this file is too large",
        )
        .with_help(Limit::FileBytes.help(limits)),
        ReadRefusal::Io(e) if e.kind() == io::ErrorKind::InvalidData => Diagnostic::new(
            "die::not_utf8",
            format!("cannot read `{shown}`: {e}"),
            span,
            "this file",
        )
        .with_help("scripts are UTF-8 text; re-save the file as UTF-8 in your editor"),
        ReadRefusal::Io(e) => Diagnostic::new(
            "die::file_not_found",
            format!("cannot read `{shown}`: {e}"),
            span,
            "this file",
        )
        .with_help("check the file's permissions and that it is UTF-8 text"),
    }
}

/// Reads the main script at `path` (named on the command line, so not checked against
/// the root) as text, with the same checks as every other read: a regular file of at
/// most `file_bytes`. The error says why in words, with the limit's help when the file
/// is too large.
pub fn read_script(path: &Path, limits: &Limits) -> io::Result<String> {
    read_regular_text(path, limits.get(Limit::FileBytes)).map_err(|r| match r {
        ReadRefusal::Io(e) => e,
        ReadRefusal::TooLarge { bytes } => io::Error::new(
            io::ErrorKind::FileTooLarge,
            format!(
                "it holds {bytes} bytes, more than the `{}` limit allows\nhelp: {}",
                Limit::FileBytes,
                Limit::FileBytes.help(limits)
            ),
        ),
        other => io::Error::new(io::ErrorKind::InvalidInput, other.to_string()),
    })
}

/// An imported file must be a `.die` script: anything else is refused before it is
/// read, so a module's syntax error can never print a line of some other file.
pub fn check_module_name(path: &str, span: Span) -> Result<(), Diagnostic> {
    if Path::new(path).extension().is_some_and(|e| e == "die") {
        return Ok(());
    }
    Err(Diagnostic::new(
        "die::import_not_a_script",
        format!("`{path}` is not a `.die` script"),
        span,
        "not a .die file",
    )
    .with_help(
        "`import` loads dieface scripts, whose names end in `.die`; read a mesh with `read_obj`",
    ))
}

/// Reads a module that [`resolve_in_root`] found (named `shown` in the script, at
/// `span`) as text, with [`read_regular`]'s checks.
pub fn read_module(
    full: &Path,
    shown: &str,
    span: Span,
    limits: &Limits,
) -> Result<String, Diagnostic> {
    read_regular_text(full, limits.get(Limit::FileBytes))
        .map_err(|r| refusal_diagnostic(shown, &r, span, limits))
}
