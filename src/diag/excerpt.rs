//! The text a rendered diagnostic shows: the source with every lone `\r` line end made
//! `\n` and every very long line cut to a window around its labels.
//!
//! miette prints a label's line whole and pads with the label's column, which it cannot
//! do past 65,535 columns (it panics: "Formatting argument out of range"); nor does it
//! end a line at a lone `\r` (old Mac line ends) when it prints one, though it counts one
//! when it numbers lines. [`Excerpt`] is the [`miette::SourceCode`] it reads instead:
//! every line keeps its number, a line longer than [`LONG_LINE`] bytes shows a window of
//! [`WINDOW`] bytes around its first label between `…` marks, and the `[file:line:col]`
//! header still gives the column in the whole line. Labels are moved into the excerpt
//! with [`Excerpt::span`].

use miette::{MietteError, MietteSpanContents, SourceCode, SourceSpan, SpanContents};

/// Lines longer than this many bytes are cut to a window (shorter ones are shown whole,
/// as miette would show them).
pub const LONG_LINE: usize = 400;

/// Bytes of a long line shown around its first label.
pub const WINDOW: usize = 160;

/// Bytes of the window before the label's start.
const LEAD: usize = 60;

/// The mark where a long line is cut.
const CUT: &str = "…";

/// One long line as the excerpt shows it.
#[derive(Debug, Clone, Copy)]
struct Cut {
    /// Where the line starts in the source.
    line_start: usize,
    /// Where its text ends in the source (its line end excluded).
    line_end: usize,
    /// The window of the source shown, `window.0..window.1`.
    window: (usize, usize),
    /// Where the shown line starts in the excerpt.
    start: usize,
    /// Bytes of the mark before the window (0 when the window starts the line).
    lead: usize,
    /// How far the excerpt is ahead of the source after this line (negative: behind).
    shift_after: isize,
}

/// A source file as miette is shown it: see the module documentation.
#[derive(Debug)]
pub struct Excerpt {
    name: String,
    text: String,
    cuts: Vec<Cut>,
}

impl Excerpt {
    /// The excerpt of `source` named `name`; `anchors` are the label starts, first the
    /// primary (a long line's window is placed around the first anchor on it).
    pub fn new(name: String, source: &str, anchors: &[usize]) -> Self {
        let mut text = String::with_capacity(source.len().min(1 << 20));
        let mut cuts = Vec::new();
        let mut at = 0;
        while at < source.len() {
            let (end, next) = line_end(source, at);
            if end - at > LONG_LINE {
                let anchor = anchors
                    .iter()
                    .copied()
                    .find(|&a| a >= at && a <= end)
                    .unwrap_or(at);
                let cut = cut_line(source, at, end, anchor, text.len(), &mut text);
                cuts.push(cut);
            } else {
                push_shown(&source[at..end], &mut text);
            }
            // A lone `\r` becomes `\n` (miette ends a printed line only at `\n`); `\r\n`
            // and `\n` stay, so the excerpt's offsets move only at a cut line.
            match &source[end..next] {
                "\r" => text.push('\n'),
                other => text.push_str(other),
            }
            at = next;
        }
        Self { name, text, cuts }
    }

    /// Where the source offset `at` is shown in the excerpt (an offset inside a long
    /// line's hidden part goes to the nearer end of its window).
    pub fn offset(&self, at: usize) -> usize {
        let k = self.cuts.partition_point(|c| c.line_start <= at);
        let Some(cut) = k.checked_sub(1).map(|i| self.cuts[i]) else {
            return at;
        };
        if at <= cut.line_end {
            let inside = at.clamp(cut.window.0, cut.window.1) - cut.window.0;
            return cut.start + cut.lead + inside;
        }
        at.saturating_add_signed(cut.shift_after)
    }

    /// Whether the source offset `at` is shown (it is not when it lies on a long line
    /// outside the window shown of it).
    pub fn shows(&self, at: usize) -> bool {
        let k = self.cuts.partition_point(|c| c.line_start <= at);
        match k.checked_sub(1).map(|i| self.cuts[i]) {
            Some(cut) if at <= cut.line_end => cut.window.0 <= at && at <= cut.window.1,
            _ => true,
        }
    }

    /// A source span moved into the excerpt.
    pub fn span(&self, start: usize, end: usize) -> SourceSpan {
        let s = self.offset(start);
        let e = self.offset(end).max(s);
        (s, e - s).into()
    }

    /// The column (in bytes from the line's start, as miette counts) in the source of
    /// the excerpt's offset `at`, given its column `shown` in the excerpt.
    fn source_column(&self, at: usize, shown: usize) -> usize {
        let k = self.cuts.partition_point(|c| c.start <= at);
        match k.checked_sub(1).map(|i| self.cuts[i]) {
            Some(cut) if at <= cut.start + cut.lead + (cut.window.1 - cut.window.0) => {
                let inside = at.saturating_sub(cut.start + cut.lead);
                cut.window.0 - cut.line_start + inside
            }
            _ => shown,
        }
    }
}

/// The end of the line starting at `at` (its text, its line end excluded) and the start
/// of the next: `\n`, `\r\n` and a lone `\r` all end a line.
fn line_end(source: &str, at: usize) -> (usize, usize) {
    let bytes = source.as_bytes();
    match bytes[at..].iter().position(|&b| b == b'\n' || b == b'\r') {
        None => (source.len(), source.len()),
        Some(i) => {
            let end = at + i;
            let crlf = bytes[end] == b'\r' && bytes.get(end + 1) == Some(&b'\n');
            (end, end + 1 + usize::from(crlf))
        }
    }
}

/// Writes `line` as the terminal should see it: a control character (a NUL, an escape)
/// or an invisible format character (a zero-width space, a direction override that would
/// turn the printed line around) is replaced by a visible one of the same length in
/// bytes, so every offset stays.
fn push_shown(line: &str, out: &mut String) {
    if !line.chars().any(hidden) {
        out.push_str(line);
        return;
    }
    for c in line.chars() {
        if !hidden(c) {
            out.push(c);
            continue;
        }
        out.push(match c.len_utf8() {
            1 => '?',
            2 => '\u{B7}',
            3 => '\u{FFFD}',
            _ => '\u{1F5CC}',
        });
    }
}

/// Whether a character would not show (or would disturb the line) when printed.
fn hidden(c: char) -> bool {
    (c.is_control() && c != '\t')
        || matches!(c, '\u{AD}' | '\u{200B}'..='\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2060}'..='\u{2069}')
}

/// Writes the window of the long line `line_start..line_end` around `anchor` to `out`
/// (which is `start` bytes long), with marks where it is cut.
fn cut_line(
    source: &str,
    line_start: usize,
    line_end: usize,
    anchor: usize,
    start: usize,
    out: &mut String,
) -> Cut {
    let mut a = anchor.saturating_sub(LEAD).max(line_start);
    while !source.is_char_boundary(a) {
        a -= 1;
    }
    let mut b = (a + WINDOW).min(line_end);
    while !source.is_char_boundary(b) {
        b -= 1;
    }
    let lead = if a > line_start { CUT.len() } else { 0 };
    if lead > 0 {
        out.push_str(CUT);
    }
    push_shown(&source[a..b], out);
    if b < line_end {
        out.push_str(CUT);
    }
    let shown_end = out.len();
    Cut {
        line_start,
        line_end,
        window: (a, b),
        start,
        lead,
        shift_after: shown_end as isize - line_end as isize,
    }
}

impl SourceCode for Excerpt {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let inner =
            self.text
                .as_str()
                .read_span(span, context_lines_before, context_lines_after)?;
        let column = self.source_column(inner.span().offset(), inner.column());
        Ok(Box::new(
            MietteSpanContents::new_named(
                self.name.clone(),
                inner.data(),
                *inner.span(),
                inner.line(),
                column,
                inner.line_count(),
            )
            .with_language("die"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_lines_are_shown_as_they_are_with_a_lone_cr_made_a_newline() {
        let e = Excerpt::new("f".into(), "a = 1\r\nb = 2\rc = 3\n", &[]);
        assert_eq!(e.text, "a = 1\r\nb = 2\nc = 3\n");
        assert_eq!(e.offset(14), 14);
    }

    #[test]
    fn a_long_line_is_cut_around_its_label_and_keeps_its_column() {
        let line = format!("let a = {}bad{}", "x".repeat(10_000), "y".repeat(10_000));
        let src = format!("first\n{line}\nlast\n");
        let label = 6 + 8 + 10_000;
        let e = Excerpt::new("f".into(), &src, &[label]);
        assert!(e.text.len() < 400, "{}", e.text.len());
        let at = e.offset(label);
        assert_eq!(&e.text[at..at + 3], "bad");
        let shown = e
            .text
            .read_span(&e.span(label, label + 3), 0, 0)
            .expect("in range");
        assert_eq!(e.source_column(at, shown.column()), 8 + 10_000);
        let last = src.len() - 5;
        assert_eq!(&e.text[e.offset(last)..e.offset(last) + 4], "last");
    }
}
