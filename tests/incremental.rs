//! Incremental re-parsing equals a full parse: for every example and corpus file, many
//! random edits (tokens replaced, deleted, duplicated, lines inserted), the AST of
//! `reparse(old, new)` is the AST of `parse(new)`, and errors are the same.

use std::path::{Path, PathBuf};

use dieface::syntax::incremental::{reparse, reparse_items};
use dieface::syntax::{parse, FileId};

struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        if n == 0 {
            0
        } else {
            (self.0 % n as u64) as usize
        }
    }
}

fn files() -> Vec<PathBuf> {
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in [
        "examples/fender",
        "examples/sections",
        "examples/door",
        "tests/diagnostics",
        "stdlib",
    ] {
        for e in std::fs::read_dir(base.join(dir))
            .into_iter()
            .flatten()
            .flatten()
        {
            if e.path().extension().is_some_and(|x| x == "die") {
                out.push(e.path());
            }
        }
    }
    out.sort();
    out
}

/// An edit a designer might make: change a number, rename, delete or duplicate a line,
/// insert a declaration or a comment, or break something.
fn edit(text: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = text.lines().collect();
    if lines.is_empty() {
        return "let a = 1\n".into();
    }
    let i = rng.below(lines.len());
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    match rng.below(7) {
        0 => out[i] = out[i].replacen(char::is_numeric, "7", 1),
        1 => {
            out.remove(i);
        }
        2 => {
            let l = out[i].clone();
            out.insert(i, l);
        }
        3 => out.insert(i, "let inserted = 3 mm".into()),
        4 => out.insert(i, "// a new comment".into()),
        5 => out[i].push_str(" + 1"),
        _ => {
            let cut = rng.below(out[i].len() + 1);
            let cut = (0..=cut)
                .rev()
                .find(|&c| out[i].is_char_boundary(c))
                .unwrap_or(0);
            out[i].truncate(cut);
        }
    }
    let mut s = out.join("\n");
    s.push('\n');
    s
}

#[test]
fn reparse_equals_a_full_parse() {
    let mut rng = Rng(0x5EED_1234_ABCD_0001);
    let mut incremental_hits = 0;
    for path in files() {
        let mut text = std::fs::read_to_string(&path).expect("readable");
        let Ok(mut ast) = parse(&text, FileId(3)) else {
            continue;
        };
        for _ in 0..40 {
            let new = edit(&text, &mut rng);
            let full = parse(&new, FileId(3));
            if let Some(items) = reparse_items(&text, &ast, &new, FileId(3)) {
                let expected = full
                    .as_ref()
                    .expect("an item-wise parse only succeeds where the whole file parses");
                assert_eq!(
                    expected,
                    &items,
                    "{}: item-wise parse differs after the edit\n{new}",
                    path.display()
                );
                incremental_hits += 1;
            }
            let inc = reparse(&text, &ast, &new, FileId(3));
            match (&full, &inc) {
                (Ok(a), Ok(b)) => assert_eq!(a, b, "{}: after the edit\n{new}", path.display()),
                (Err(a), Err(b)) => assert_eq!(a, b, "{}: different errors", path.display()),
                _ => panic!(
                    "{}: full {:?} vs incremental {:?}\n{new}",
                    path.display(),
                    full.is_ok(),
                    inc.is_ok()
                ),
            }
            if let Ok(a) = full {
                text = new;
                ast = a;
            }
        }
    }
    println!("item-wise re-parses compared: {incremental_hits}");
    assert!(
        incremental_hits > 300,
        "the item-wise path was exercised: {incremental_hits} times"
    );
}
