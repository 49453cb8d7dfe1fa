//! Mutations of real scripts: the examples, the diagnostics corpus, the standard
//! library and the regression corpus, changed one to four times each at the level of
//! tokens, numbers, lines and bytes, or grown (a fragment repeated, nesting deepened) to
//! reach the size limits.

use crate::rng::Rng;

/// Tokens that may be dropped in: operators, punctuation, keywords, units, extreme
/// numbers and characters that are not part of the language.
const TOKENS: &[&str] = &[
    "+",
    "-",
    "*",
    "/",
    "|>",
    "==",
    "<",
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    ",",
    ";",
    ":",
    ".",
    "=",
    "=>",
    "fn",
    "if",
    "then",
    "else",
    "for",
    "in",
    "and",
    "or",
    "not",
    "sketch",
    "from",
    "line",
    "to",
    "arc",
    "through",
    "tangent",
    "spline",
    "fillet",
    "close",
    "import",
    "as",
    "units",
    "let",
    "param",
    "product",
    "mm",
    "deg",
    "%",
    "0",
    "-0",
    "1e308",
    "1e-400",
    "1e309",
    "4294967297",
    "0.000000001",
    "\"",
    "\"std/addendum\"",
    "//",
    "/*",
    "\r",
    "\u{200B}",
    "\0",
    "\u{A0}",
    "\u{202E}",
    "\u{FEFF}",
    "é",
    "🙂",
];

/// Numbers a literal may become.
const NUMBERS: &[&str] = &[
    "0",
    "0.0",
    "1",
    "2",
    "-1",
    "1e-12",
    "1e-300",
    "1e300",
    "1e308",
    "1e-400",
    "1e400",
    "100000",
    "1000000",
    "1e9",
    "3.4e38",
    "3.5e38",
    "123456789012345678901234567890",
];

/// The text split into tokens: runs of word characters, runs of digits and dots (a
/// number), runs of spaces, and single other characters.
fn tokens(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut chars = text.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        let class = |c: char| {
            if c.is_alphanumeric() || c == '_' || c == '.' {
                1
            } else if c == ' ' || c == '\t' {
                2
            } else {
                0
            }
        };
        let k = class(c);
        let mut end = i + c.len_utf8();
        if k != 0 {
            while let Some(&(j, d)) = chars.peek() {
                if class(d) != k {
                    break;
                }
                end = j + d.len_utf8();
                chars.next();
            }
        }
        if i > start {
            out.push(&text[start..i]);
        }
        out.push(&text[i..end]);
        start = end;
    }
    if start < text.len() {
        out.push(&text[start..]);
    }
    out
}

/// `text` changed one to four times; `donors` are other seeds to splice from.
pub fn mutate(rng: &mut Rng, text: &str, donors: &[String]) -> String {
    let mut out = text.to_string();
    for _ in 0..rng.between(1, 4) {
        out = once(rng, &out, donors);
        truncate(&mut out, MAX_INPUT_BYTES);
    }
    out
}

/// The largest input a mutation makes (bytes). Repeats compound over the rounds of
/// [`mutate`] (20,000 times 20,000 made a 5 GB script, more than a frame to a worker
/// holds); past this size an input only meets the file limit, which
/// `tests/cli_limits.rs` tests on its own.
pub const MAX_INPUT_BYTES: usize = 32 << 20;

/// `text` cut to at most `max` bytes, on a character boundary.
fn truncate(text: &mut String, max: usize) {
    if text.len() > max {
        let mut cut = max;
        while !text.is_char_boundary(cut) {
            cut -= 1;
        }
        text.truncate(cut);
    }
}

fn once(rng: &mut Rng, text: &str, donors: &[String]) -> String {
    let toks = tokens(text);
    if toks.is_empty() {
        return rng.pick(TOKENS).to_string();
    }
    let i = rng.below(toks.len());
    let j = rng.below(toks.len());
    let mut t: Vec<String> = toks.iter().map(|s| s.to_string()).collect();
    match rng.below(14) {
        0 => {
            t.remove(i);
        }
        1 => {
            let x = t[i].clone();
            t.insert(i, x);
        }
        2 => t.swap(i, j),
        3 => t.insert(i, rng.pick(TOKENS).to_string()),
        4 => t[i] = rng.pick(TOKENS).to_string(),
        5 | 6 => {
            // A number literal becomes another.
            let numbers: Vec<usize> = (0..t.len())
                .filter(|&k| t[k].starts_with(|c: char| c.is_ascii_digit()))
                .collect();
            if !numbers.is_empty() {
                let k = *rng.pick(&numbers);
                t[k] = rng.pick(NUMBERS).to_string();
            }
        }
        7 => return lines(rng, text),
        8 => {
            // Truncated anywhere (on a character boundary).
            let mut cut = rng.below(text.len() + 1);
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            return text[..cut].to_string();
        }
        9 => {
            // A random byte sequence (valid UTF-8) inserted.
            let junk: String = (0..rng.between(1, 8))
                .map(|_| char::from_u32(rng.below(0x3000) as u32).unwrap_or('?'))
                .collect();
            t.insert(i, junk);
        }
        10 if !donors.is_empty() => {
            // A fragment of another seed spliced in.
            let donor: &String = rng.pick(donors);
            let d = tokens(donor);
            if !d.is_empty() {
                let a = rng.below(d.len());
                let b = (a + rng.between(1, 40)).min(d.len());
                t.insert(i, d[a..b].concat());
            }
        }
        11 => {
            // A fragment repeated many times: long lines, long chains, big lists.
            let b = (i + rng.between(1, 6)).min(t.len());
            let piece = t[i..b].concat();
            let times = *rng.pick(&[10, 100, 1000, 20000]);
            let times = times.min(MAX_INPUT_BYTES / piece.len().max(1));
            t.insert(b, piece.repeat(times));
        }
        12 => {
            // Deeper nesting around one token.
            let n = *rng.pick(&[5, 50, 200, 5000]);
            let (open, close) = *rng.pick(&[("(", ")"), ("[", "]"), ("-", ""), ("not ", "")]);
            t[i] = format!("{}{}{}", open.repeat(n), t[i], close.repeat(n));
        }
        _ => {
            // A line ending style changed for the whole text.
            let eol = *rng.pick(&["\r\n", "\r", "\n\n"]);
            return text.replace('\n', eol);
        }
    }
    t.concat()
}

/// A line deleted, duplicated or moved.
fn lines(rng: &mut Rng, text: &str) -> String {
    let mut ls: Vec<&str> = text.split_inclusive('\n').collect();
    if ls.is_empty() {
        return String::new();
    }
    let i = rng.below(ls.len());
    match rng.below(3) {
        0 => {
            ls.remove(i);
        }
        1 => ls.insert(i, ls[i]),
        _ => {
            let l = ls.remove(i);
            let j = rng.below(ls.len() + 1);
            ls.insert(j, l);
        }
    }
    ls.concat()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mutations_stay_within_the_input_cap() {
        let text = "let a = [1 mm, 2 mm, 3 mm]\nlet b = a\n".repeat(50);
        for seed in 0..300 {
            let mut rng = Rng::for_input(17, seed);
            let mut out = text.clone();
            for _ in 0..4 {
                out = mutate(&mut rng, &out, std::slice::from_ref(&text));
                assert!(
                    out.len() <= MAX_INPUT_BYTES,
                    "seed {seed}: {} bytes",
                    out.len()
                );
            }
        }
    }

    #[test]
    fn tokens_cover_the_text() {
        let text = "let a = 12.5 mm + f(x) // c\n";
        assert_eq!(tokens(text).concat(), text);
    }
}
