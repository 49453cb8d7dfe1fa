//! No input panics: every example and corpus file is mutated many times (tokens
//! deleted, duplicated and swapped, random bytes inserted, text truncated) and
//! evaluated; evaluation must return (with or without diagnostics), never panic. A few
//! mutants also go through the real `dieface check` binary, which must exit 0 or 1.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::Command;

use dieface::eval::Engine;

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

fn inputs() -> Vec<PathBuf> {
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in ["examples", "tests/diagnostics"] {
        let mut stack = vec![base.join(dir)];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
                let p = e.path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "die") {
                    out.push(p);
                }
            }
        }
    }
    out.sort();
    out
}

/// Splits text into rough tokens (words, numbers, single punctuation, whitespace).
fn tokens(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for c in text.chars() {
        let word = c.is_alphanumeric() || c == '_' || c == '.';
        match out.last_mut() {
            Some(last)
                if word
                    && last
                        .chars()
                        .all(|d| d.is_alphanumeric() || d == '_' || d == '.') =>
            {
                last.push(c)
            }
            _ => out.push(c.to_string()),
        }
    }
    out
}

fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut t = tokens(text);
    let edits = 1 + rng.below(3);
    for _ in 0..edits {
        if t.is_empty() {
            break;
        }
        let i = rng.below(t.len());
        match rng.below(6) {
            0 => {
                t.remove(i);
            }
            1 => {
                let tok = t[i].clone();
                t.insert(i, tok);
            }
            2 => {
                let j = rng.below(t.len());
                t.swap(i, j);
            }
            3 => {
                let bytes = [
                    "(", ")", "{", "}", "[", "]", "\"", "/*", "mm", "deg", "|>", ",", "0",
                    "-1e308", "é", "\u{0}",
                ];
                t.insert(i, bytes[rng.below(bytes.len())].to_string());
            }
            4 => {
                t.truncate(i);
            }
            _ => {
                let j = rng.below(t.len());
                let tok = t[j].clone();
                t[i] = tok;
            }
        }
    }
    t.concat()
}

#[test]
fn mutated_scripts_never_panic() {
    let files = inputs();
    assert!(!files.is_empty());
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut evaluated = 0;
    for path in &files {
        let text = std::fs::read_to_string(path).expect("readable");
        let dir = path.parent().map(Path::to_path_buf);
        for _ in 0..60 {
            let mutant = mutate(&text, &mut rng);
            let root = dir.clone();
            let result = catch_unwind(AssertUnwindSafe(|| {
                let mut engine = Engine::new(root.clone());
                engine.evaluate("mutant.die", &mutant, root.clone())
            }));
            assert!(
                result.is_ok(),
                "panic on a mutant of {}:\n{mutant}",
                path.display()
            );
            evaluated += 1;
        }
    }
    assert!(evaluated >= 60 * files.len());
}

#[test]
fn the_check_binary_exits_0_or_1_on_mutants() {
    let files = inputs();
    let mut rng = Rng(0xD1E_FACE);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mutants");
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (k, path) in files.iter().enumerate().take(12) {
        let text = std::fs::read_to_string(path).expect("readable");
        let mutant = mutate(&text, &mut rng);
        let file = dir.join(format!("mutant{k}.die"));
        std::fs::write(&file, &mutant).expect("write mutant");
        let status = Command::new(env!("CARGO_BIN_EXE_dieface"))
            .args(["check", "--color", "never"])
            .arg(&file)
            .output()
            .expect("run dieface");
        let code = status.status.code();
        assert!(
            matches!(code, Some(0) | Some(1)),
            "exit {code:?} on a mutant of {}:\n{mutant}",
            path.display()
        );
    }
}
