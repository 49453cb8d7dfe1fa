//! Diagnostics: what went wrong, where, and how to fix it.
//!
//! Every stage reports failures as a [`Diagnostic`]: a stable code (`die::unit_mismatch`),
//! a message, a primary label at the culprit, secondary labels where a second place
//! matters (the other operand, the earlier definition, the rest of a cycle), and help.
//! [`Sources`] holds the text of every loaded file so a diagnostic can be rendered with
//! miette, file name, line and column included.

mod excerpt;

use std::fmt;

use miette::{GraphicalReportHandler, GraphicalTheme, LabeledSpan};

use crate::limits::{Limit, Limits};
use crate::syntax::{FileId, Span};

pub use excerpt::Excerpt;

/// A located message.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    /// Where.
    pub span: Span,
    /// What this place has to do with the problem.
    pub message: String,
}

/// One problem found in a script.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Stable code, `die::<name>`, for documentation and tests.
    pub code: &'static str,
    /// One sentence saying what is wrong.
    pub message: String,
    /// The culprit.
    pub primary: Label,
    /// Other places that matter.
    pub secondary: Vec<Label>,
    /// How to fix it.
    pub help: Option<String>,
}

impl Diagnostic {
    /// A diagnostic with its primary label.
    pub fn new(
        code: &'static str,
        message: impl Into<String>,
        span: Span,
        label: impl Into<String>,
    ) -> Self {
        Self {
            code,
            message: message.into(),
            primary: Label {
                span,
                message: label.into(),
            },
            secondary: Vec::new(),
            help: None,
        }
    }

    /// Adds a secondary label.
    pub fn with_label(mut self, span: Span, message: impl Into<String>) -> Self {
        self.secondary.push(Label {
            span,
            message: message.into(),
        });
        self
    }

    /// Sets the help text.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }
}

/// A loaded source file.
#[derive(Debug, Clone, PartialEq)]
pub struct SourceFile {
    /// The name shown in diagnostics (a path relative to the project, or `std/...`).
    pub name: String,
    /// Its text.
    pub text: String,
}

/// All files loaded in one run, indexed by [`FileId`].
#[derive(Debug, Clone, Default)]
pub struct Sources {
    files: Vec<SourceFile>,
    /// Where each line of each file starts (byte offsets, by file): a span's line is
    /// found by binary search, so reporting every declaration's line stays linear.
    line_starts: Vec<Vec<usize>>,
}

impl Sources {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a file (or replaces the one with the same name) and returns its id.
    pub fn add(&mut self, name: impl Into<String>, text: impl Into<String>) -> FileId {
        let name = name.into();
        let text = text.into();
        let starts = line_starts(&text);
        if let Some(i) = self.files.iter().position(|f| f.name == name) {
            self.files[i].text = text;
            self.line_starts[i] = starts;
            return FileId(i as u32);
        }
        self.files.push(SourceFile { name, text });
        self.line_starts.push(starts);
        FileId((self.files.len() - 1) as u32)
    }

    /// The file with `id`.
    pub fn get(&self, id: FileId) -> Option<&SourceFile> {
        self.files.get(id.0 as usize)
    }

    /// The id of the file named `name`.
    pub fn find(&self, name: &str) -> Option<FileId> {
        self.files
            .iter()
            .position(|f| f.name == name)
            .map(|i| FileId(i as u32))
    }

    /// The text a span covers (empty if out of range).
    pub fn slice(&self, span: Span) -> &str {
        self.get(span.file)
            .and_then(|f| f.text.get(span.range()))
            .unwrap_or("")
    }

    /// 1-based line of a span's start (0 when its file is unknown); unlike
    /// [`Sources::line_col`], it takes no longer on a long line.
    pub fn line(&self, span: Span) -> usize {
        let Some(file) = self.get(span.file) else {
            return 0;
        };
        let at = (span.start as usize).min(file.text.len());
        // The number of lines starting at or before `at` (the first starts at 0).
        self.line_starts[span.file.0 as usize].partition_point(|&s| s <= at)
    }

    /// 1-based line and column (in characters) of a span's start; `\n`, `\r\n` and a
    /// lone `\r` each end a line.
    pub fn line_col(&self, span: Span) -> (usize, usize) {
        let Some(file) = self.get(span.file) else {
            return (0, 0);
        };
        let at = (span.start as usize).min(file.text.len());
        let line = self.line(span);
        let start = self.line_starts[span.file.0 as usize][line.saturating_sub(1)];
        let col = file.text.get(start..at).map_or(0, |l| l.chars().count()) + 1;
        (line, col)
    }

    /// Renders `diag` as text, with colour or without (tests and pipes).
    pub fn render(&self, diag: &Diagnostic, color: bool) -> String {
        let report = Report::new(self, diag);
        let theme = if color {
            GraphicalTheme::unicode()
        } else {
            GraphicalTheme::unicode_nocolor()
        };
        let handler = GraphicalReportHandler::new_themed(theme)
            .with_width(100)
            .with_links(false);
        let mut out = String::new();
        if handler.render_report(&mut out, &report).is_err() {
            out = format!("error[{}]: {}", diag.code, diag.message);
        }
        out
    }
}

/// The 1-based line and column just after `upto` (a text's beginning).
fn line_col_in(upto: &str) -> (usize, usize) {
    let bytes = upto.as_bytes();
    let ends = bytes
        .iter()
        .enumerate()
        .filter(|&(i, &b)| b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n')))
        .count();
    let last = upto.rfind(['\n', '\r']).map_or(0, |i| i + 1);
    (ends + 1, upto[last..].chars().count() + 1)
}

/// A diagnostic bound to its primary file, in the shape miette renders. Secondary
/// labels in other files become related reports of their own.
#[derive(Debug)]
struct Report {
    code: &'static str,
    message: String,
    help: Option<String>,
    source: Excerpt,
    labels: Vec<LabeledSpan>,
    related: Vec<Report>,
}

impl Report {
    fn new(sources: &Sources, diag: &Diagnostic) -> Self {
        let file = diag.primary.span.file;
        let (name, text) = sources
            .get(file)
            .map_or(("<unknown>", ""), |f| (f.name.as_str(), f.text.as_str()));
        let here = std::iter::once(&diag.primary)
            .chain(&diag.secondary)
            .filter(|l| l.span.file == file);
        let anchors: Vec<usize> = here.clone().map(|l| l.span.start as usize).collect();
        let source = Excerpt::new(name.to_string(), text, &anchors);
        let clamp = |s: Span| {
            let start = (s.start as usize).min(text.len());
            let end = (s.end as usize).clamp(start, text.len());
            source.span(start, end)
        };
        let mut labels = vec![LabeledSpan::new_primary_with_span(
            Some(diag.primary.message.clone()),
            clamp(diag.primary.span),
        )];
        // A label on a long line outside the window shown of it would point at the wrong
        // place: it is left out (the message and the primary label still say enough).
        labels.extend(
            here.skip(1)
                .filter(|l| source.shows(l.span.start as usize))
                .map(|l| LabeledSpan::new_with_span(Some(l.message.clone()), clamp(l.span))),
        );
        let related = diag
            .secondary
            .iter()
            .filter(|l| l.span.file != file)
            .map(|l| {
                let other =
                    Diagnostic::new(diag.code, l.message.clone(), l.span, l.message.clone());
                Report::new(sources, &other)
            })
            .collect();
        Self {
            code: diag.code,
            message: diag.message.clone(),
            help: diag.help.clone(),
            source,
            labels,
            related,
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Report {}

impl miette::Diagnostic for Report {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.code))
    }
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }
    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(&self.source)
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        Some(Box::new(self.labels.iter().cloned()))
    }
    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn miette::Diagnostic> + 'a>> {
        if self.related.is_empty() {
            None
        } else {
            Some(Box::new(
                self.related.iter().map(|r| r as &dyn miette::Diagnostic),
            ))
        }
    }
}

/// The byte offset where each line of `text` starts: 0, then after each `\n`, `\r\n`
/// or lone `\r` (a line end of old Mac files).
fn line_starts(text: &str) -> Vec<usize> {
    let bytes = text.as_bytes();
    std::iter::once(0)
        .chain(
            bytes
                .iter()
                .enumerate()
                .filter(|&(i, &b)| b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n')))
                .map(|(i, _)| i + 1),
        )
        .collect()
}

/// Names longer than this get no "did you mean": no one mistypes one, and comparing
/// it with every candidate would be the slowest part of a diagnostic.
const MAX_SUGGESTED_NAME_CHARS: usize = 64;

/// The candidate closest to `name` by edit distance, if close enough to be a likely
/// typo: used for "did you mean" on unknown names, arguments and kinds. Candidates whose
/// length alone puts them too far are not compared, so the work stays small whatever
/// the name's length.
pub fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    // One- and two-letter names are too short for a typo to be told from another name.
    let len = name.chars().count();
    if len <= 2 || len > MAX_SUGGESTED_NAME_CHARS {
        return None;
    }
    let limit = (len / 3).max(1);
    let name: Vec<char> = name.chars().collect();
    candidates
        .into_iter()
        .filter(|c| c.chars().count().abs_diff(len) <= limit)
        .map(|c| (edit_distance(&name, c), c))
        .filter(|(d, _)| *d <= limit)
        .min_by(|a, b| a.0.cmp(&b.0).then(a.1.cmp(b.1)))
        .map(|(_, c)| c)
}

/// Edit distance by characters, counting a swap of two neighbours as one edit (the
/// optimal-string-alignment distance): `widht` is one edit from `width`. Three rows of
/// the table are kept, not all of it.
fn edit_distance(a: &[char], b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut row: Vec<usize> = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        row[0] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (prev[j] + 1).min(row[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(before[j - 2] + 1);
            }
            row[j] = best;
        }
        std::mem::swap(&mut before, &mut prev);
        std::mem::swap(&mut prev, &mut row);
    }
    prev[b.len()]
}

/// `text` for a message: whole when it has at most `max` characters, else its first
/// `max - 3` characters and `...`, so a huge input never floods a message.
pub fn abridged(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_string()
    } else {
        let head: String = text.chars().take(max.saturating_sub(3)).collect();
        format!("{head}...")
    }
}

/// Why a source file (a script or a module) could not be taken as text.
#[derive(Debug)]
pub enum SourceError {
    /// It could not be read (missing, a folder, no permission).
    Io(std::io::Error),
    /// It is larger than the `file_bytes` limit.
    TooLarge {
        /// Its size in bytes (at least the limit plus one).
        size: u64,
    },
    /// It is not UTF-8 text.
    NotUtf8 {
        /// Its text with each bad byte sequence replaced by U+FFFD (which ends no line
        /// and starts at the same offset, so line and column of `at` are right in it).
        text: String,
        /// The byte offset of the first bad byte.
        at: usize,
        /// That byte.
        byte: u8,
    },
}

/// Reads the source file at `path` as text: at most `limits`' `file_bytes` bytes, UTF-8
/// (a byte-order mark is fine; the grammar skips it).
pub fn read_source(path: &std::path::Path, limits: &Limits) -> Result<String, SourceError> {
    use std::io::Read;
    let max = limits.get(Limit::FileBytes);
    let file = std::fs::File::open(path).map_err(SourceError::Io)?;
    let mut bytes = Vec::new();
    file.take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(SourceError::Io)?;
    if bytes.len() as u64 > max {
        let size = std::fs::metadata(path).map_or(bytes.len() as u64, |m| m.len());
        return Err(SourceError::TooLarge {
            size: size.max(bytes.len() as u64),
        });
    }
    decode_source(bytes)
}

/// A source file's bytes as text, or [`SourceError::NotUtf8`] naming the first bad
/// byte.
pub fn decode_source(bytes: Vec<u8>) -> Result<String, SourceError> {
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let bytes = e.into_bytes();
        SourceError::NotUtf8 {
            byte: bytes[at],
            text: String::from_utf8_lossy(&bytes).into_owned(),
            at,
        }
    })
}

impl SourceError {
    /// The diagnostic for the source `name` (which it adds to `sources`, as much of it
    /// as can be shown), or the read error back when the file could not be read at all
    /// (the caller's usage error).
    pub fn diagnostic(
        self,
        sources: &mut Sources,
        name: &str,
        limits: &Limits,
    ) -> Result<Diagnostic, std::io::Error> {
        match self {
            SourceError::Io(e) => Err(e),
            SourceError::TooLarge { size } => {
                let file = sources.add(name, "");
                Ok(Diagnostic::new(
                    "die::limit::file_bytes",
                    format!("`{name}` has {size} bytes, more than the `file_bytes` limit allows"),
                    Span::new(file, 0, 0),
                    "this file",
                )
                .with_help(Limit::FileBytes.help(limits)))
            }
            SourceError::NotUtf8 { text, at, byte } => {
                let (line, column) = line_col_in(&text[..at]);
                let len = text[at..].chars().next().map_or(0, char::len_utf8);
                let file = sources.add(name, text);
                Ok(Diagnostic::new(
                    "die::not_utf8",
                    format!(
                        "`{name}` is not UTF-8 text: byte 0x{byte:02X} at offset {at} (line {line}, column {column})"
                    ),
                    Span::new(file, at, at + len),
                    format!("byte 0x{byte:02X} is not UTF-8"),
                )
                .with_help(
                    "save the file as UTF-8 (a byte-order mark is fine); a character that does not show may be the culprit: retype it",
                ))
            }
        }
    }

    /// The diagnostic for a module that cannot be taken as text, at `span`, where it is
    /// imported as `path`.
    pub fn import_diagnostic(&self, path: &str, span: Span, limits: &Limits) -> Diagnostic {
        let (code, message, help) = match self {
            SourceError::Io(e) => (
                "die::file_not_found",
                format!("cannot read `{path}`: {e}"),
                "check the file's permissions".to_string(),
            ),
            SourceError::TooLarge { size } => (
                "die::limit::file_bytes",
                format!("`{path}` has {size} bytes, more than the `file_bytes` limit allows"),
                Limit::FileBytes.help(limits),
            ),
            SourceError::NotUtf8 { text, at, byte } => {
                let (line, column) = line_col_in(&text[..*at]);
                (
                    "die::not_utf8",
                    format!(
                        "`{path}` is not UTF-8 text: byte 0x{byte:02X} at offset {at} (line {line}, column {column})"
                    ),
                    "save the file as UTF-8 (a byte-order mark is fine)".to_string(),
                )
            }
        };
        Diagnostic::new(code, message, span, "this file").with_help(help)
    }
}
