//! Atomic file writes: a build either replaces its output completely or leaves the
//! previous file as it was.

use std::fs::{self, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporary files of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes via a temp file in the same directory, then renames: a failure leaves the old
/// file.
///
/// The temporary file (`.NAME.PID-N.tmp` beside `path`) is created exclusively, written,
/// flushed to disk and renamed over `path`; a rename within one directory is atomic on
/// the platforms we support, so readers see the old file or the new one, never a part.
/// On any error the temporary file is removed and `path` is untouched. A directory that
/// does not exist is an error (nothing is created).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path, bytes, Durability::Flushed)
}

/// Whether an atomic write waits for the disk before the rename.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Durability {
    /// The new file is flushed to disk (fsync) before it replaces the old one: a power
    /// loss right after the build leaves the old file or the new one. What `build` does.
    Flushed,
    /// The rename happens without waiting for the disk: readers still see the old file
    /// or the new one whole, and a crash of the program never leaves a part; only a
    /// power loss in the seconds after a write could lose it. What `watch` does for its
    /// previews, which the next save rewrites anyway (the fsync of a 5 MB GLB is about
    /// half of a small rebuild).
    Renamed,
}

/// [`write_atomic`] with a choice of [`Durability`].
pub fn write_atomic_with(path: &Path, bytes: &[u8], durability: Durability) -> io::Result<()> {
    let tmp = temp_path(path)?;
    let result = (|| {
        let mut file = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        file.write_all(bytes)?;
        if durability == Durability::Flushed {
            file.sync_all()?;
        }
        drop(file);
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        // Best effort: the temporary file may not even exist.
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// `.NAME.PID-N.tmp` in `path`'s directory.
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("`{}` does not name a file", path.display()),
        )
    })?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp_name = format!(".{}.{}-{n}.tmp", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(tmp_name))
}
