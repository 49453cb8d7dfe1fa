//! Diagnostics: what went wrong, where, and how to fix it.
//!
//! Every stage reports failures as a [`Diagnostic`]: a stable code (`die::unit_mismatch`),
//! a message, a primary label at the culprit, secondary labels where a second place
//! matters (the other operand, the earlier definition, the rest of a cycle), and help.
//! [`Sources`] holds the text of every loaded file so a diagnostic can be rendered with
//! miette, file name, line and column included.

use std::fmt;

use miette::{GraphicalReportHandler, GraphicalTheme, LabeledSpan, NamedSource, SourceSpan};

use crate::syntax::{FileId, Span};

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

    /// 1-based line and column of a span's start.
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

/// A diagnostic bound to its primary file, in the shape miette renders. Secondary
/// labels in other files become related reports of their own.
#[derive(Debug)]
struct Report {
    code: &'static str,
    message: String,
    help: Option<String>,
    source: NamedSource<String>,
    labels: Vec<LabeledSpan>,
    related: Vec<Report>,
}

impl Report {
    fn new(sources: &Sources, diag: &Diagnostic) -> Self {
        let file = diag.primary.span.file;
        let (name, text) = sources
            .get(file)
            .map_or(("<unknown>".to_string(), String::new()), |f| {
                (f.name.clone(), f.text.clone())
            });
        let clamp = |s: Span| -> SourceSpan {
            let start = (s.start as usize).min(text.len());
            let end = (s.end as usize).clamp(start, text.len());
            (start, end - start).into()
        };
        let mut labels = vec![LabeledSpan::new_primary_with_span(
            Some(diag.primary.message.clone()),
            clamp(diag.primary.span),
        )];
        let mut related = Vec::new();
        for l in &diag.secondary {
            if l.span.file == file {
                labels.push(LabeledSpan::new_with_span(
                    Some(l.message.clone()),
                    clamp(l.span),
                ));
            } else {
                let other =
                    Diagnostic::new(diag.code, l.message.clone(), l.span, l.message.clone());
                related.push(Report::new(sources, &other));
            }
        }
        Self {
            code: diag.code,
            message: diag.message.clone(),
            help: diag.help.clone(),
            source: NamedSource::new(name, text).with_language("die"),
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

/// The byte offset where each line of `text` starts: 0, then after each `\n`.
fn line_starts(text: &str) -> Vec<usize> {
    std::iter::once(0)
        .chain(text.match_indices('\n').map(|(i, _)| i + 1))
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
