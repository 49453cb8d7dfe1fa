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
        put_in_place(&tmp, path, durability)
    })();
    if result.is_err() {
        // Best effort: the temporary file may not even exist.
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Puts the written temporary file `tmp` in the place of `path`, atomically.
///
/// A rename over an existing file makes ext4 allocate the new file's blocks at once (its
/// `auto_da_alloc` guard for writes that were not flushed) and free the old file's, about
/// 4 ms for a 5 MB GLB: most of a small `watch` rebuild. So a [`Durability::Renamed`]
/// write over a regular file on Linux exchanges the two names instead
/// (`renameat2(RENAME_EXCHANGE)`, as atomic for readers) and then removes the old file
/// from under the temporary name. Everywhere else, and when the exchange is refused
/// (an older kernel or a file system without it), a plain rename.
fn put_in_place(tmp: &Path, path: &Path, durability: Durability) -> io::Result<()> {
    #[cfg(target_os = "linux")]
    if durability == Durability::Renamed
        && fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_file())
        && exchange(tmp, path).is_ok()
    {
        // `tmp` now names the previous file; a failure to remove it leaves a stray
        // temporary file, never a wrong output.
        let _ = fs::remove_file(tmp);
        return Ok(());
    }
    #[cfg(not(target_os = "linux"))]
    let _ = durability; // only Linux has the exchange
    fs::rename(tmp, path)
}

/// Exchanges the files named `a` and `b` atomically.
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> io::Result<()> {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let a = CString::new(a.as_os_str().as_bytes())?;
    let b = CString::new(b.as_os_str().as_bytes())?;
    // SAFETY: both are NUL-terminated paths that outlive the call; AT_FDCWD makes them
    // relative to the working directory, as `fs::rename` takes them.
    let r = unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    if r == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
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
