//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};

/// Every `.die` file under `dir` (relative to the crate root), recursively, sorted.
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
