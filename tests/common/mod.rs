//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};

/// Every `.die` file under `dir` (relative to the crate root), recursively, sorted.
#[allow(dead_code)] // not every test crate that shares these helpers reads the corpus
pub fn die_files(dir: &str) -> Vec<PathBuf> {
    fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                collect(&p, out);
            } else if p.extension().is_some_and(|x| x == "die") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    collect(&Path::new(env!("CARGO_MANIFEST_DIR")).join(dir), &mut out);
    out.sort();
    out
}

/// The temporary files (`*.tmp`) left in `dir`: a build or watch that was stopped, or
/// failed, must leave none.
#[allow(dead_code)] // not every test crate that shares these helpers writes files
pub fn temp_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("list the folder")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// A fresh, empty folder for one test, `target/tmp/SUITE/NAME` (removed first if a
/// previous run left it).
#[allow(dead_code)] // not every test crate that shares these helpers writes files
pub fn fresh_dir(suite: &str, name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(suite)
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Runs the `dieface` binary in `dir` with `args`: its exit code, stdout and stderr.
#[allow(dead_code)] // not every test crate that shares these helpers runs the binary
pub fn run_dieface(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dieface"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run dieface");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
