//! Atomic file writes: a build either replaces its output completely or leaves the
//! previous file as it was.
//!
//! The temporary file is named `.NAME.PID-NONCE.tmp` beside the output: the process id
//! and a nonce from the clock and a counter, created exclusively and renamed again on
//! the rare collision, so two writers (or a later process that got a dead one's id)
//! never meet. It is removed on every error, and on Ctrl-C by
//! [`remove_temp_files`], which the commands call from their signal handler; the
//! temporary files of the same output left by a process that was killed outright are
//! removed by the next write ([`remove_stale_temps`]). An existing output that is not
//! writable (a file the user protected) or is not a regular file is never replaced.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// Distinguishes temporary files of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// How many names a write tries before it gives up on creating its temporary file.
const NAME_ATTEMPTS: u32 = 16;

/// A temporary file older than this is stale even when a process with the id in its
/// name is alive (that id has been reused): no write takes this long.
const STALE_AGE: Duration = Duration::from_secs(3600);

/// The temporary files this process is writing, so a signal handler can remove them.
struct InFlight {
    /// Temporary files created and not yet renamed or removed.
    paths: Vec<PathBuf>,
    /// Set by [`remove_temp_files`]: the process is ending, no new temporary file.
    closing: bool,
}

static IN_FLIGHT: Mutex<InFlight> = Mutex::new(InFlight {
    paths: Vec::new(),
    closing: false,
});

/// The in-flight list, even if a thread panicked while holding it (the list stays
/// consistent: every change is a single push or retain).
fn in_flight() -> MutexGuard<'static, InFlight> {
    IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes every temporary file this process is writing and refuses new ones: what a
/// Ctrl-C (SIGINT, SIGTERM) handler calls before it ends the process, so an
/// interrupted build leaves no `.tmp` file and the outputs as they were.
pub fn remove_temp_files() {
    let mut flight = in_flight();
    flight.closing = true;
    for tmp in flight.paths.drain(..) {
        let _ = fs::remove_file(tmp);
    }
}

/// Writes via a temp file in the same directory, then renames: a failure leaves the old
/// file.
///
/// The temporary file (see the module's documentation) is created exclusively,
/// written, flushed to disk and renamed over `path`; a rename within one directory is
/// atomic on the platforms we support, so readers see the old file or the new one,
/// never a part. On any error the temporary file is removed and `path` is untouched. A
/// directory that does not exist is an error (nothing is created), and so is an
/// existing `path` that [`check_replaceable`] refuses.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path, bytes, Durability::Flushed)
}

/// Whether the file at `path` may be replaced by an output: it does not exist, or it is
/// a regular file we may write. A read-only output (protected with `chmod a-w`, or not
/// ours to write) is refused rather than silently replaced by the rename, and so is a
/// folder, a device or a FIFO. The error says why, in words for the command line.
pub fn check_replaceable(path: &Path) -> io::Result<()> {
    let meta = match fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e),
    };
    if !meta.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "it exists and is not a regular file; outputs are written as regular files, so name a file",
        ));
    }
    if meta.permissions().readonly() || !writable_by_us(path) {
        return Err(io::Error::new(
            io::ErrorKind::PermissionDenied,
            "the file exists and is read-only, so it is not replaced; make it writable (chmod u+w) or write to another file",
        ));
    }
    Ok(())
}

/// Whether this process may write the existing file at `path` (the system's own test,
/// for files whose owner or group keep us out).
#[cfg(unix)]
fn writable_by_us(path: &Path) -> bool {
    use std::os::unix::ffi::OsStrExt;
    let Ok(c) = std::ffi::CString::new(path.as_os_str().as_bytes()) else {
        return false;
    };
    // SAFETY: a NUL-terminated path that outlives the call.
    unsafe { libc::access(c.as_ptr(), libc::W_OK) == 0 }
}

#[cfg(not(unix))]
fn writable_by_us(_path: &Path) -> bool {
    true
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
    check_replaceable(path)?;
    remove_stale_temps(path);
    let (mut file, tmp) = create_temp(path)?;
    let result = (|| {
        file.write_all(bytes)?;
        if durability == Durability::Flushed {
            file.sync_all()?;
        }
        drop(file);
        put_in_place(&tmp, path, durability)
    })();
    if result.is_err() {
        // Best effort: the temporary file may already be gone.
        let _ = fs::remove_file(&tmp);
    }
    in_flight().paths.retain(|p| *p != tmp);
    result
}

/// Creates a new temporary file beside `path` under a name no other writer uses,
/// registered for [`remove_temp_files`]; a name that exists already is passed over.
fn create_temp(path: &Path) -> io::Result<(File, PathBuf)> {
    for _ in 0..NAME_ATTEMPTS {
        let tmp = temp_path(path)?;
        let mut flight = in_flight();
        if flight.closing {
            return Err(io::Error::new(
                io::ErrorKind::Interrupted,
                "interrupted: the program is stopping",
            ));
        }
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(file) => {
                flight.paths.push(tmp.clone());
                return Ok((file, tmp));
            }
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::AlreadyExists,
        format!(
            "no free temporary file name beside `{}` after {NAME_ATTEMPTS} tries",
            path.display()
        ),
    ))
}

/// Removes the temporary files of `path` that no running write owns: those of a
/// process that has ended (killed before it could clean up), or older than
/// [`STALE_AGE`]. Best effort: a file that cannot be listed or removed stays.
pub fn remove_stale_temps(path: &Path) {
    let (Some(dir), Some(name)) = (path.parent(), path.file_name()) else {
        return;
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let prefix = format!(".{}.", name.to_string_lossy());
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let file_name = file_name.to_string_lossy();
        let Some(pid) = temp_owner(&file_name, &prefix) else {
            continue;
        };
        let tmp = entry.path();
        if is_stale(&tmp, pid) {
            let _ = fs::remove_file(&tmp);
        }
    }
}

/// The process id in a temporary file name `PREFIX PID-NONCE.tmp`, if it is one.
fn temp_owner(file_name: &str, prefix: &str) -> Option<u32> {
    let middle = file_name.strip_prefix(prefix)?.strip_suffix(".tmp")?;
    let (pid, nonce) = middle.split_once('-')?;
    (!nonce.is_empty() && nonce.bytes().all(|b| b.is_ascii_alphanumeric()))
        .then(|| pid.parse().ok())
        .flatten()
}

/// Whether the temporary file `tmp`, named with process id `pid`, is left over: not one
/// this process is writing, and its writer has ended (or it is very old).
fn is_stale(tmp: &Path, pid: u32) -> bool {
    if in_flight().paths.iter().any(|p| p == tmp) {
        return false;
    }
    // A file with our own id that we are not writing was left by an earlier process
    // that had the same id.
    if pid == std::process::id() || !process_alive(pid) {
        return true;
    }
    fs::symlink_metadata(tmp)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.elapsed().ok())
        .is_some_and(|age| age > STALE_AGE)
}

/// Whether a process with this id is running (on Unix, `kill(pid, 0)`; elsewhere we
/// cannot tell, and say yes so that only the age rule applies).
#[cfg(unix)]
fn process_alive(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return false;
    };
    if pid <= 0 {
        return false;
    }
    // SAFETY: signal 0 only checks that the process exists and may be signalled.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

#[cfg(not(unix))]
fn process_alive(_pid: u32) -> bool {
    true
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

/// `.NAME.PID-NONCE.tmp` in `path`'s directory: the nonce mixes the clock's
/// nanoseconds with a counter, so names differ across processes that share an id and
/// within one process.
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("`{}` does not name a file", path.display()),
        )
    })?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    let nonce = nanos ^ n.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let tmp_name = format!(
        ".{}.{}-{nonce:x}.tmp",
        name.to_string_lossy(),
        std::process::id()
    );
    Ok(path.with_file_name(tmp_name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temp_names_are_recognised_and_unique() {
        let a = temp_path(Path::new("x/out.glb")).expect("a name");
        let b = temp_path(Path::new("x/out.glb")).expect("a name");
        assert_ne!(a, b);
        let name = a.file_name().and_then(|n| n.to_str()).expect("utf-8");
        assert_eq!(temp_owner(name, ".out.glb."), Some(std::process::id()));
        assert_eq!(temp_owner(".out.glb.12-3.tmp", ".out.glb."), Some(12));
        assert_eq!(temp_owner(".out.glb.12.tmp", ".out.glb."), None);
        assert_eq!(temp_owner(".out.glbx.12-3.tmp", ".out.glb."), None);
    }
}
