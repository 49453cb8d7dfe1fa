//! Every syntax error has a `help:` line (issue 14): a seeded set of mutations of the
//! examples, the standard library and the diagnostics corpus (a token deleted,
//! duplicated or swapped with the next, a bracket or comma dropped, a stray operator or
//! keyword inserted, a line deleted) is parsed, and each failure must say how to fix it.
//! No allow-list is needed: every kind of parse error has something useful to say.

use std::path::Path;

use dieface::syntax::{parse, FileId};

/// A small deterministic generator (64-bit LCG), so the set is the same on every run.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 33) as usize) % n.max(1)
    }
}

/// The scripts mutated: the examples, the standard library and the corpus.
fn sources() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in [
        "examples/fender",
        "examples/door",
        "examples/door_outer",
        "examples/sections",
        "stdlib",
        "tests/diagnostics",
    ] {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        let mut names: Vec<_> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "die"))
            .collect();
        names.sort();
        files.extend(
            names
                .into_iter()
                .filter_map(|p| std::fs::read_to_string(p).ok()),
        );
    }
    files
}

/// Byte ranges of the tokens of `text` (comments and strings are single tokens and left
/// alone as wholes).
fn tokens(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let start = i;
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if text[i..].starts_with("//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' && b[i] != b'\n' {
                i += 1;
            }
            i = (i + 1).min(b.len());
        } else if c.is_ascii_alphanumeric()
            || c == b'_'
            || c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit)
        {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_' || b[i] == b'.') {
                i += 1;
            }
        } else if ["|>", "==", "!=", "<=", ">=", "=>"]
            .iter()
            .any(|p| text[i..].starts_with(p))
        {
            i += 2;
        } else {
            i += text[i..].chars().next().map_or(1, char::len_utf8);
        }
        out.push((start, i));
    }
    out
}

/// One mutation of `text`, or `None` when the chosen kind does not apply.
fn mutate(text: &str, rng: &mut Lcg) -> Option<String> {
    let toks = tokens(text);
    if toks.len() < 2 {
        return None;
    }
    let (s, e) = toks[rng.below(toks.len())];
    let tok = &text[s..e];
    let splice = |a: usize, b: usize, with: &str| format!("{}{with}{}", &text[..a], &text[b..]);
    Some(match rng.below(7) {
        0 => splice(s, e, ""),
        1 => splice(e, e, &format!(" {tok}")),
        2 => {
            let k = toks.iter().position(|t| t.0 == s)?;
            let (s2, e2) = *toks.get(k + 1)?;
            format!(
                "{}{}{}{}{}",
                &text[..s],
                &text[s2..e2],
                &text[e..s2],
                tok,
                &text[e2..]
            )
        }
        3 | 4 => {
            let set: &[&str] = if rng.below(2) == 0 {
                &["{", "}", "(", ")", "[", "]"]
            } else {
                &[","]
            };
            let hits: Vec<_> = toks
                .iter()
                .filter(|(a, b)| set.contains(&&text[*a..*b]))
                .collect();
            let &&(a, b) = hits.get(rng.below(hits.len()))?;
            splice(a, b, "")
        }
        5 => {
            const STRAY: [&str; 16] = [
                "+", "*", "=", ",", ")", "}", "]", "|>", ".", "<", "not", "then", "=>", ":", "(",
                "{",
            ];
            splice(s, s, &format!("{} ", STRAY[rng.below(STRAY.len())]))
        }
        _ => {
            let lines: Vec<&str> = text.lines().collect();
            let k = rng.below(lines.len());
            lines
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != k)
                .map(|(_, l)| *l)
                .collect::<Vec<_>>()
                .join("\n")
        }
    })
}

#[test]
fn every_syntax_error_of_seeded_mutations_has_help() {
    let sources = sources();
    assert!(sources.len() > 50, "examples, stdlib and corpus found");
    let mut rng = Lcg(14);
    let (mut tried, mut failures, mut missing) = (0, 0, Vec::new());
    while tried < 600 {
        let text = &sources[rng.below(sources.len())];
        let Some(mutated) = mutate(text, &mut rng) else {
            continue;
        };
        tried += 1;
        if let Err(d) = parse(&mutated, FileId(0)) {
            failures += 1;
            if d.help.as_deref().is_none_or(str::is_empty) {
                missing.push(format!("{}\n--- in ---\n{}", d.message, mutated));
            }
        }
    }
    assert!(
        failures > 200,
        "most mutations are syntax errors ({failures} of {tried})"
    );
    assert!(
        missing.is_empty(),
        "{} syntax errors without help, the first:\n{}",
        missing.len(),
        missing[0]
    );
}
