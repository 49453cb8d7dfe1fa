//! Re-parsing after an edit: only the top-level items the edit touched.
//!
//! `dieface watch` re-parses the script at every save; the parser costs microseconds per
//! declaration, so re-parsing a long file dominates a rebuild that re-evaluates one
//! declaration. [`reparse`] compares the new text with the previous one, keeps the items
//! before the edit as they were and those after it shifted by the change in length, and
//! parses only the items in between. When the middle does not parse on its own, or the
//! edit is not safely delimited by item boundaries at line starts, it parses the whole
//! file, so diagnostics are exactly those of [`parse`].

use super::ast::*;
use super::parse::{parse_with, SyntaxError};
use super::span::{FileId, Span, Spanned};
use crate::limits::Limits;

/// The AST of `new_text`, reusing `old` (the parse of `old_text`) where the text is
/// unchanged. Equal to `parse(new_text, file)`.
pub fn reparse(
    old_text: &str,
    old: &File,
    new_text: &str,
    file: FileId,
) -> Result<File, SyntaxError> {
    reparse_with(old_text, old, new_text, file, &Limits::default())
}

/// [`reparse`] held to `limits`: equal to `parse_with(new_text, file, limits)`.
pub fn reparse_with(
    old_text: &str,
    old: &File,
    new_text: &str,
    file: FileId,
    limits: &Limits,
) -> Result<File, SyntaxError> {
    match reparse_items_with(old_text, old, new_text, file, limits) {
        Some(f) => Ok(f),
        None => parse_with(new_text, file, limits),
    }
}

/// The incremental step alone: `None` when the edit cannot be re-parsed by items (the
/// caller then parses the whole file).
pub fn reparse_items(old_text: &str, old: &File, new_text: &str, file: FileId) -> Option<File> {
    reparse_items_with(old_text, old, new_text, file, &Limits::default())
}

/// [`reparse_items`] held to `limits`.
fn reparse_items_with(
    old_text: &str,
    old: &File,
    new_text: &str,
    file: FileId,
    limits: &Limits,
) -> Option<File> {
    if old.items.is_empty() || old.span.file != file {
        return None;
    }
    // The changed region: common prefix and suffix of the two texts (on char boundaries).
    let prefix = common_prefix(old_text, new_text);
    let suffix = common_suffix(&old_text[prefix..], &new_text[prefix..]);
    let old_end = old_text.len() - suffix; // changed region in the old text: prefix..old_end
    let delta = new_text.len() as i64 - old_text.len() as i64;

    // Items wholly before the change, wholly after it, and those it touches.
    let starts: Vec<usize> = old
        .items
        .iter()
        .map(|i| item_span(i).start as usize)
        .collect();
    let ends: Vec<usize> = old
        .items
        .iter()
        .map(|i| item_span(i).end as usize)
        .collect();
    let first_touched = (0..old.items.len()).find(|&k| ends[k] >= prefix)?;
    let after = (first_touched..old.items.len())
        .find(|&k| starts[k] > old_end)
        .unwrap_or(old.items.len());
    // The re-parsed chunk runs from the first touched item's start (or the end of the
    // item before) to the start of the first untouched item after the edit.
    let chunk_start = if first_touched == 0 {
        0
    } else {
        ends[first_touched - 1]
    };
    let chunk_end_old = if after < old.items.len() {
        starts[after]
    } else {
        old_text.len()
    };
    if chunk_start > prefix {
        return None;
    }
    let chunk_end_new = (chunk_end_old as i64 + delta) as usize;
    if chunk_end_new < chunk_start || chunk_end_new > new_text.len() {
        return None;
    }
    // The next item must start a line, so no expression of the chunk can run into it
    // (units and continuations stay on their line).
    if after < old.items.len() && !starts_line(new_text, chunk_end_new) {
        return None;
    }
    let chunk = new_text.get(chunk_start..chunk_end_new)?;
    let parsed = parse_with(chunk, file, limits).ok()?;

    let mut items: Vec<Item> = old.items[..first_touched].to_vec();
    for mut item in parsed.items {
        item.shift(chunk_start as i64);
        items.push(item);
    }
    for item in &old.items[after..] {
        let mut item = item.clone();
        item.shift(delta);
        items.push(item);
    }
    Some(File {
        items,
        span: Span::new(file, 0, new_text.len()),
    })
}

fn common_prefix(a: &str, b: &str) -> usize {
    let mut n = a.bytes().zip(b.bytes()).take_while(|(x, y)| x == y).count();
    while !a.is_char_boundary(n) || !b.is_char_boundary(n) {
        n -= 1;
    }
    n
}

fn common_suffix(a: &str, b: &str) -> usize {
    let mut n = a
        .bytes()
        .rev()
        .zip(b.bytes().rev())
        .take_while(|(x, y)| x == y)
        .count();
    while !a.is_char_boundary(a.len() - n) || !b.is_char_boundary(b.len() - n) {
        n -= 1;
    }
    n
}

fn starts_line(text: &str, at: usize) -> bool {
    at == 0 || matches!(text.as_bytes().get(at - 1), Some(b'\n' | b'\r'))
}

fn item_span(item: &Item) -> Span {
    match item {
        Item::Import(i) => i.span,
        Item::Units(u) => u.span,
        Item::Function(f) => f.span,
        Item::Decl(d) => d.span,
    }
}

/// Moving every span of a node by a byte offset.
trait Shift {
    fn shift(&mut self, d: i64);
}

impl Shift for Span {
    fn shift(&mut self, d: i64) {
        self.start = (i64::from(self.start) + d) as u32;
        self.end = (i64::from(self.end) + d) as u32;
    }
}

impl<T> Shift for Spanned<T> {
    fn shift(&mut self, d: i64) {
        self.span.shift(d);
    }
}

impl<T: Shift> Shift for Vec<T> {
    fn shift(&mut self, d: i64) {
        self.iter_mut().for_each(|x| x.shift(d));
    }
}

impl<T: Shift> Shift for Option<T> {
    fn shift(&mut self, d: i64) {
        if let Some(x) = self {
            x.shift(d);
        }
    }
}

impl<T: Shift> Shift for Box<T> {
    fn shift(&mut self, d: i64) {
        (**self).shift(d);
    }
}

impl Shift for Item {
    fn shift(&mut self, d: i64) {
        match self {
            Item::Import(i) => {
                i.path.shift(d);
                i.alias.shift(d);
                i.span.shift(d);
            }
            Item::Units(u) => {
                u.units.shift(d);
                u.span.shift(d);
            }
            Item::Function(f) => {
                f.name.shift(d);
                f.params.shift(d);
                f.body.shift(d);
                f.span.shift(d);
            }
            Item::Decl(x) => {
                x.kind.shift(d);
                x.name.shift(d);
                match &mut x.body {
                    DeclBody::Expr(e) => e.shift(d),
                    DeclBody::Block(b) => b.shift(d),
                }
                x.span.shift(d);
            }
        }
    }
}

impl Shift for Param {
    fn shift(&mut self, d: i64) {
        self.name.shift(d);
        self.default.shift(d);
    }
}

impl Shift for Block {
    fn shift(&mut self, d: i64) {
        self.fields.shift(d);
        self.span.shift(d);
    }
}

impl Shift for Field {
    fn shift(&mut self, d: i64) {
        self.path.shift(d);
        match &mut self.value {
            FieldValue::Expr(e) => e.shift(d),
            FieldValue::Block(b) => b.shift(d),
        }
        self.span.shift(d);
    }
}

impl Shift for Arg {
    fn shift(&mut self, d: i64) {
        self.name.shift(d);
        self.value.shift(d);
    }
}

impl Shift for SketchCommand {
    fn shift(&mut self, d: i64) {
        match &mut self.kind {
            SketchCommandKind::From(e)
            | SketchCommandKind::LineTo(e)
            | SketchCommandKind::TangentArcTo(e)
            | SketchCommandKind::Fillet(e) => e.shift(d),
            SketchCommandKind::ArcThrough { to, through } => {
                to.shift(d);
                through.shift(d);
            }
            SketchCommandKind::Spline { through, .. } => through.shift(d),
            SketchCommandKind::Close => {}
        }
        self.span.shift(d);
    }
}

impl Shift for Expr {
    fn shift(&mut self, d: i64) {
        self.span.shift(d);
        match &mut self.kind {
            ExprKind::Number { unit, .. } => unit.shift(d),
            ExprKind::Str(_) | ExprKind::Bool(_) | ExprKind::Name(_) => {}
            ExprKind::List(items) | ExprKind::Tuple(items) => items.shift(d),
            ExprKind::Comprehension {
                body,
                var,
                iter,
                cond,
            } => {
                body.shift(d);
                var.shift(d);
                iter.shift(d);
                cond.shift(d);
            }
            ExprKind::Record(fields) => {
                for (k, v) in fields {
                    k.shift(d);
                    v.shift(d);
                }
            }
            ExprKind::Field { target, name } => {
                target.shift(d);
                name.shift(d);
            }
            ExprKind::Index { target, index } => {
                target.shift(d);
                index.shift(d);
            }
            ExprKind::Call { callee, args } => {
                callee.shift(d);
                args.shift(d);
            }
            ExprKind::Pipe { input, call } => {
                input.shift(d);
                call.shift(d);
            }
            ExprKind::Unary { op, operand } => {
                op.shift(d);
                operand.shift(d);
            }
            ExprKind::Binary { op, lhs, rhs } => {
                op.shift(d);
                lhs.shift(d);
                rhs.shift(d);
            }
            ExprKind::If {
                cond,
                then,
                otherwise,
            } => {
                cond.shift(d);
                then.shift(d);
                otherwise.shift(d);
            }
            ExprKind::Lambda { params, body } => {
                params.shift(d);
                body.shift(d);
            }
            ExprKind::Sketch { view, commands } => {
                view.shift(d);
                commands.shift(d);
            }
        }
    }
}
