//! The pipeline's direction, checked on the source: data flows
//! `syntax -> eval -> geom / die / sheet -> export -> pipeline -> cli`, and a module never
//! reaches back up it. `limits` is a leaf every stage may read; so is `heap`, the count
//! of memory held, which the evaluation's budget reads. The kernel (`geom`) and the die-face features (`die`) know
//! nothing of the language; the exporters read the die model, never language values.
//!
//! Every `crate::<module>` path, and every `super::` chain that climbs to the crate
//! root, in each file under `src/<module>/` is checked against the modules that one
//! may use. A new dependency against the direction fails here, naming the file.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// What each top-level module may use besides itself.
const ALLOWED: &[(&str, &[&str])] = &[
    ("limits", &[]),
    ("heap", &[]),
    ("diag", &["syntax", "limits"]),
    ("syntax", &["diag", "limits"]),
    ("geom", &["limits"]),
    ("die", &["geom", "limits"]),
    ("sheet", &["geom", "limits"]),
    (
        "eval",
        &["diag", "syntax", "geom", "die", "sheet", "limits", "heap"],
    ),
    ("export", &["geom", "die", "sheet", "limits"]),
    (
        "pipeline",
        &[
            "diag", "syntax", "eval", "geom", "die", "sheet", "export", "limits",
        ],
    ),
    (
        "cli",
        &[
            "diag", "syntax", "eval", "geom", "die", "sheet", "export", "pipeline", "limits",
        ],
    ),
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The top-level modules a file's source refers to: `crate::x` paths, and `super::`
/// chains long enough to climb out of the file's own module to the crate root.
fn uses(src: &Path, file: &Path, text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    for (i, _) in text.match_indices("crate::") {
        // `dieface_crate::` or `the crate::` in prose would not be a path start.
        let before = text[..i].chars().last();
        if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
            continue;
        }
        out.insert(ident(&text[i + "crate::".len()..]));
    }
    // The file's module depth below the crate root: src/eval/features/bead.rs is 3,
    // src/eval/features/mod.rs is 2.
    let rel = file.strip_prefix(src).expect("under src");
    let mut depth = rel.components().count();
    if rel.file_name().is_some_and(|n| n == "mod.rs") {
        depth -= 1;
    }
    let climb = "super::".repeat(depth);
    for (i, _) in text.match_indices(&climb) {
        if text[..i].ends_with("super::") {
            continue;
        }
        out.insert(ident(&text[i + climb.len()..]));
    }
    out
}

#[test]
fn no_module_reaches_back_up_the_pipeline() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut violations = Vec::new();
    let mut checked = 0;
    for (module, allowed) in ALLOWED {
        let mut files = Vec::new();
        let dir = src.join(module);
        rust_files(&dir, &mut files);
        let single = src.join(format!("{module}.rs"));
        if single.is_file() {
            files.push(single);
        }
        assert!(!files.is_empty(), "src/{module} has sources");
        for file in files {
            let text = std::fs::read_to_string(&file).expect("readable source");
            for used in uses(&src, &file, &text) {
                checked += 1;
                if used == *module || used.is_empty() || allowed.contains(&used.as_str()) {
                    continue;
                }
                violations.push(format!(
                    "{} uses `{used}`, against the pipeline's direction ({module} may use: {})",
                    file.strip_prefix(&src).unwrap().display(),
                    allowed.join(", ")
                ));
            }
        }
    }
    assert!(
        checked > 50,
        "the scan found the modules' paths ({checked})"
    );
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

/// Every top-level module of the library is in the table, so a new one is placed in
/// the direction deliberately.
#[test]
fn every_module_has_a_place_in_the_direction() {
    let lib = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/lib.rs"))
        .expect("lib.rs");
    let declared: BTreeSet<&str> = lib
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|l| l.trim_end_matches(';'))
        .collect();
    let known: BTreeSet<&str> = ALLOWED.iter().map(|(m, _)| *m).collect();
    assert_eq!(declared, known);
}

/// The scan itself finds a path against the direction (so the test above can fail).
#[test]
fn the_scan_sees_crate_paths_and_climbing_super_chains() {
    let src = Path::new("/x/src");
    let found = uses(
        src,
        Path::new("/x/src/export/scene.rs"),
        "use crate::eval::Value;\nuse super::super::cli::run;\nuse super::gltf;",
    );
    assert_eq!(
        found,
        BTreeSet::from(["eval".to_string(), "cli".to_string()])
    );
}
