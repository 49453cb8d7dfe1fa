//! A stable, indented text dump of an AST, for snapshot tests.
//!
//! One node per line: its kind, its key data, and where it is as
//! `@line:col..line:col` (1-based, columns in characters, the end exclusive). Children
//! are indented two spaces; a child in a named role is prefixed `role:`. Numbers are
//! printed with at most 6 significant digits so snapshots do not churn on float noise.

use std::fmt::Write as _;

use super::ast::{
    Arg, Block, DeclBody, Expr, ExprKind, Field, FieldValue, File, Item, Param, SketchCommandKind,
    UnaryOp,
};
use super::span::Span;

/// Dumps `file`, whose spans index into `source`.
pub fn print_ast(file: &File, source: &str) -> String {
    let mut p = Printer {
        out: String::new(),
        lines: LineIndex::new(source),
    };
    p.line(
        0,
        "",
        &format!("File ({} items)", file.items.len()),
        file.span,
    );
    for item in &file.items {
        p.item(1, item);
    }
    p.out
}

/// Byte offset to 1-based line and column.
struct LineIndex<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    fn new(text: &'a str) -> Self {
        let mut starts = vec![0];
        // `\n`, `\r\n` and a lone `\r` each end a line.
        let bytes = text.as_bytes();
        starts.extend(
            bytes
                .iter()
                .enumerate()
                .filter(|&(i, &b)| b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n')))
                .map(|(i, _)| i + 1),
        );
        Self { text, starts }
    }

    fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let start = self.starts[line];
        let col = self
            .text
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count());
        (line + 1, col + 1)
    }

    fn at(&self, span: Span) -> String {
        let (l1, c1) = self.line_col(span.start as usize);
        let (l2, c2) = self.line_col(span.end as usize);
        format!("@{l1}:{c1}..{l2}:{c2}")
    }
}

struct Printer<'a> {
    out: String,
    lines: LineIndex<'a>,
}

/// `v` with at most 6 significant digits, without trailing zeros.
pub fn format_number(v: f64) -> String {
    if v == 0.0 {
        return "0".to_string();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if (-4..15).contains(&mag) {
        let decimals = (5 - mag).max(0) as usize;
        let s = format!("{v:.decimals$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        if s == "-0" {
            "0".to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.5e}");
        let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exp}")
    }
}

fn quote(s: &str) -> String {
    format!("{s:?}")
}

impl Printer<'_> {
    fn line(&mut self, depth: usize, role: &str, text: &str, span: Span) {
        let at = self.lines.at(span);
        let _ = writeln!(
            self.out,
            "{:indent$}{role}{text} {at}",
            "",
            indent = depth * 2
        );
    }

    fn item(&mut self, d: usize, item: &Item) {
        match item {
            Item::Import(i) => {
                self.line(
                    d,
                    "",
                    &format!("Import {} as {}", quote(&i.path.node), i.alias.node),
                    i.span,
                );
            }
            Item::Units(u) => {
                let names: Vec<&str> = u.units.iter().map(|u| u.node.symbol()).collect();
                self.line(d, "", &format!("Units {}", names.join(" ")), u.span);
            }
            Item::Function(f) => {
                self.line(d, "", &format!("Fn {}", f.name.node), f.span);
                self.params(d + 1, &f.params);
                self.expr(d + 1, "body: ", &f.body);
            }
            Item::Decl(decl) => {
                self.line(
                    d,
                    "",
                    &format!("Decl {} {}", decl.kind.node, decl.name.node),
                    decl.span,
                );
                match &decl.body {
                    DeclBody::Expr(e) => self.expr(d + 1, "", e),
                    DeclBody::Block(b) => self.block(d + 1, "", b),
                }
            }
        }
    }

    fn params(&mut self, d: usize, params: &[Param]) {
        for p in params {
            self.line(d, "", &format!("Param {}", p.name.node), p.name.span);
            if let Some(default) = &p.default {
                self.expr(d + 1, "default: ", default);
            }
        }
    }

    fn block(&mut self, d: usize, role: &str, b: &Block) {
        self.line(
            d,
            role,
            &format!("Block ({} fields)", b.fields.len()),
            b.span,
        );
        for f in &b.fields {
            self.field(d + 1, f);
        }
    }

    fn field(&mut self, d: usize, f: &Field) {
        let path: Vec<&str> = f.path.iter().map(|p| p.node.as_str()).collect();
        self.line(d, "", &format!("Field {}", path.join(" ")), f.span);
        match &f.value {
            FieldValue::Expr(e) => self.expr(d + 1, "", e),
            FieldValue::Block(b) => self.block(d + 1, "", b),
        }
    }

    fn args(&mut self, d: usize, args: &[Arg]) {
        for a in args {
            match &a.name {
                Some(n) => self.expr(d, &format!("arg {}: ", n.node), &a.value),
                None => self.expr(d, "arg: ", &a.value),
            }
        }
    }

    fn expr(&mut self, d: usize, role: &str, e: &Expr) {
        let s = e.span;
        match &e.kind {
            ExprKind::Number { value, unit } => {
                let text = match unit {
                    Some(u) => format!(
                        "Number {} {} (unit {})",
                        format_number(*value),
                        u.node.symbol(),
                        self.lines.at(u.span)
                    ),
                    None => format!("Number {}", format_number(*value)),
                };
                self.line(d, role, &text, s);
            }
            ExprKind::Str(v) => self.line(d, role, &format!("Str {}", quote(v)), s),
            ExprKind::Bool(b) => self.line(d, role, &format!("Bool {b}"), s),
            ExprKind::Name(n) => self.line(d, role, &format!("Name {n}"), s),
            ExprKind::List(items) => {
                self.line(d, role, &format!("List ({} items)", items.len()), s);
                for i in items {
                    self.expr(d + 1, "", i);
                }
            }
            ExprKind::Comprehension {
                body,
                var,
                iter,
                cond,
            } => {
                self.line(d, role, &format!("Comprehension for {}", var.node), s);
                self.expr(d + 1, "body: ", body);
                self.expr(d + 1, "in: ", iter);
                if let Some(c) = cond {
                    self.expr(d + 1, "if: ", c);
                }
            }
            ExprKind::Tuple(items) => {
                self.line(d, role, &format!("Tuple ({} items)", items.len()), s);
                for i in items {
                    self.expr(d + 1, "", i);
                }
            }
            ExprKind::Record(fields) => {
                self.line(d, role, &format!("Record ({} fields)", fields.len()), s);
                for (k, v) in fields {
                    self.expr(d + 1, &format!("{}: ", k.node), v);
                }
            }
            ExprKind::Field { target, name } => {
                self.line(d, role, &format!("Field .{}", name.node), s);
                self.expr(d + 1, "", target);
            }
            ExprKind::Index { target, index } => {
                self.line(d, role, "Index", s);
                self.expr(d + 1, "", target);
                self.expr(d + 1, "index: ", index);
            }
            ExprKind::Call { callee, args } => {
                self.line(d, role, &format!("Call ({} args)", args.len()), s);
                self.expr(d + 1, "callee: ", callee);
                self.args(d + 1, args);
            }
            ExprKind::Pipe { input, call } => {
                self.line(d, role, "Pipe", s);
                self.expr(d + 1, "input: ", input);
                self.expr(d + 1, "into: ", call);
            }
            ExprKind::Unary { op, operand } => {
                let sym = match op.node {
                    UnaryOp::Neg => "-",
                    UnaryOp::Not => "not",
                };
                self.line(d, role, &format!("Unary {sym}"), s);
                self.expr(d + 1, "", operand);
            }
            ExprKind::Binary { op, lhs, rhs } => {
                self.line(d, role, &format!("Binary {}", op.node.symbol()), s);
                self.expr(d + 1, "", lhs);
                self.expr(d + 1, "", rhs);
            }
            ExprKind::If {
                cond,
                then,
                otherwise,
            } => {
                self.line(d, role, "If", s);
                self.expr(d + 1, "if: ", cond);
                self.expr(d + 1, "then: ", then);
                self.expr(d + 1, "else: ", otherwise);
            }
            ExprKind::Lambda { params, body } => {
                self.line(d, role, "Lambda", s);
                self.params(d + 1, params);
                self.expr(d + 1, "body: ", body);
            }
            ExprKind::Sketch { view, commands } => {
                self.line(d, role, &format!("Sketch ({} commands)", commands.len()), s);
                self.expr(d + 1, "view: ", view);
                for c in commands {
                    let d = d + 1;
                    match &c.kind {
                        SketchCommandKind::From(p) => {
                            self.line(d, "", "From", c.span);
                            self.expr(d + 1, "", p);
                        }
                        SketchCommandKind::LineTo(p) => {
                            self.line(d, "", "LineTo", c.span);
                            self.expr(d + 1, "", p);
                        }
                        SketchCommandKind::ArcThrough { to, through } => {
                            self.line(d, "", "ArcThrough", c.span);
                            self.expr(d + 1, "to: ", to);
                            self.expr(d + 1, "through: ", through);
                        }
                        SketchCommandKind::TangentArcTo(p) => {
                            self.line(d, "", "TangentArcTo", c.span);
                            self.expr(d + 1, "", p);
                        }
                        SketchCommandKind::Spline { through, tangent } => {
                            self.line(
                                d,
                                "",
                                if *tangent { "Spline tangent" } else { "Spline" },
                                c.span,
                            );
                            self.expr(d + 1, "through: ", through);
                        }
                        SketchCommandKind::Fillet(r) => {
                            self.line(d, "", "Fillet", c.span);
                            self.expr(d + 1, "", r);
                        }
                        SketchCommandKind::Close => self.line(d, "", "Close", c.span),
                    }
                }
            }
        }
    }
}
