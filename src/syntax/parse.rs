//! Source text to [`ast::File`], with syntax errors as [`Diagnostic`]s.
//!
//! pest does the recognising (`grammar/die.pest`); this module builds the AST from the
//! pairs and, on failure, turns pest's "expected one of these rules" into a sentence a
//! die designer can act on. A small lexical pass (`lex`) runs only after a failure: it
//! finds what pest cannot describe well (an unterminated string or comment, an unknown
//! character, a word after a number that is not a unit) and the brackets still open at
//! the failure point, so the message can point at the `(` that was never closed.

// The API returns the diagnostic by value, as every stage does; it is built once per
// failed parse, so its size does not matter.
#![allow(clippy::result_large_err)]

use pest::error::{ErrorVariant, InputLocation};
use pest::iterators::Pair;
use pest::Parser as _;
use pest_derive::Parser;
use std::cell::Cell;

use super::ast::{
    self, Arg, BinaryOp, Block, Decl, DeclBody, Expr, ExprKind, Field, FieldValue, FnDecl, Ident,
    Import, Item, Param, SketchCommand, SketchCommandKind, UnaryOp, Unit, UnitsDirective,
};
use super::span::{FileId, Span, Spanned};
use crate::diag::Diagnostic;
use crate::limits::{Limit, Limits};

/// A syntax error: a diagnostic with code `die::syntax`.
pub type SyntaxError = Diagnostic;

/// The diagnostic code of every syntax error.
const CODE: &str = "die::syntax";

/// Stack a parse needs per level of nesting: pest's generated parser takes tens of
/// kilobytes of stack per level in a debug build.
const STACK_PER_LEVEL: usize = 512 << 10;

#[derive(Parser)]
#[grammar = "../grammar/die.pest"]
struct DieParser;

/// Parses one file's text with the default [`Limits`]; `file` is stamped into every
/// span. See [`parse_with`].
pub fn parse(text: &str, file: FileId) -> Result<ast::File, SyntaxError> {
    parse_with(text, file, &Limits::default())
}

/// Parses one file's text; `file` is stamped into every span.
///
/// The tree is never deeper than the `nesting` limit: brackets, prefix operators and
/// every operator of a chain (`a + b + c` is `(a + b) + c`, two levels) count, so every
/// later pass, which recurses over the tree (evaluation, free names, hashing, dropping),
/// recurses at most that deep, whatever the input.
///
/// Returns the first syntax error as a diagnostic whose primary span is the offending
/// token; when the file ends too early, the character after the last token (or the
/// last character), labelled "the file ends here".
pub fn parse_with(text: &str, file: FileId, limits: &Limits) -> Result<ast::File, SyntaxError> {
    if let Some(d) = lex::too_deep(text, file, limits) {
        return Err(d);
    }
    let stack = limits
        .count(Limit::Nesting)
        .saturating_mul(STACK_PER_LEVEL)
        .clamp(PARSE_STACK, MAX_PARSE_STACK);
    if stack <= PARSE_STACK && LARGE_STACK.with(Cell::get) {
        return parse_here(text, file, limits);
    }
    // More stack than a test thread's 2 MiB allows at the depth limit: parse on a thread
    // of our own with room to spare (the memory is only committed as it is touched).
    let spawned = std::thread::scope(|scope| {
        std::thread::Builder::new()
            .name("dieface-parse".into())
            .stack_size(stack)
            .spawn_scoped(scope, || parse_here(text, file, limits))
            .ok()
            .map(|h| h.join())
    });
    match spawned {
        Some(Ok(result)) => result,
        Some(Err(panic)) => std::panic::resume_unwind(panic),
        None => parse_here(text, file, limits),
    }
}

thread_local! {
    /// Set on threads whose stack is at least [`PARSE_STACK`] (the evaluation thread):
    /// they parse in place instead of starting a thread.
    static LARGE_STACK: Cell<bool> = const { Cell::new(false) };
}

/// Declares that the calling thread's stack is at least [`PARSE_STACK`] bytes, so
/// [`parse`] may run on it directly.
pub fn mark_large_stack() {
    LARGE_STACK.with(|f| f.set(true));
}

/// Stack for the parsing thread: enough for the default nesting limit (128 levels) in a
/// debug build.
const PARSE_STACK: usize = 64 << 20;

/// The most stack a parse asks for, however far `--limit nesting` is raised (address
/// space only: the memory is committed as it is touched). Beyond about 8,000 levels a
/// debug build may run out of it; docs/limits.md says so.
const MAX_PARSE_STACK: usize = 4 << 30;

fn parse_here(text: &str, file: FileId, limits: &Limits) -> Result<ast::File, SyntaxError> {
    let mut pairs = match DieParser::parse(Rule::file, text) {
        Ok(pairs) => pairs,
        Err(err) => return Err(errors::convert(&err, text, file)),
    };
    let root = pairs.next().expect("the file rule always produces a pair");
    let mut b = Builder {
        file,
        depth: 0,
        limits: *limits,
    };
    let mut items = Vec::new();
    for p in root.into_inner() {
        match p.as_rule() {
            Rule::import => items.push(Item::Import(b.import(p))),
            Rule::units => items.push(Item::Units(b.units(p)?)),
            Rule::fn_decl => items.push(Item::Function(b.fn_decl(p)?)),
            Rule::decl => items.push(Item::Decl(b.decl(p)?)),
            _ => {}
        }
    }
    Ok(ast::File {
        items,
        span: Span::new(file, 0, text.len()),
    })
}

// ---------------------------------------------------------------------------------------
// AST building

struct Builder {
    file: FileId,
    /// Levels of the tree above the node being built.
    depth: usize,
    /// The limits in force (the tree may not be deeper than `nesting`).
    limits: Limits,
}

type Res<T> = Result<T, SyntaxError>;

/// Whether a rule is punctuation or a keyword token the builder never turns into a node.
fn is_token(rule: Rule) -> bool {
    matches!(
        rule,
        Rule::kw_import
            | Rule::kw_as
            | Rule::kw_units
            | Rule::kw_fn
            | Rule::kw_if
            | Rule::kw_then
            | Rule::kw_else
            | Rule::kw_for
            | Rule::kw_in
            | Rule::kw_sketch
            | Rule::kw_from
            | Rule::kw_line
            | Rule::kw_to
            | Rule::kw_arc
            | Rule::kw_through
            | Rule::kw_spline
            | Rule::kw_fillet
            | Rule::kw_close
            | Rule::assign
            | Rule::fn_assign
            | Rule::arrow
            | Rule::colon
            | Rule::pipe_op
            | Rule::block_close
            | Rule::params_close
            | Rule::index_close
            | Rule::args_close
            | Rule::list_close
            | Rule::paren_close
            | Rule::record_close
            | Rule::sketch_close
    )
}

/// The end of a pair's text without trailing whitespace or comments: pest may leave
/// trivia at the end of a rule that ends in an optional or repeated part.
fn exact_end(pair: &Pair<Rule>) -> usize {
    // Iterative: nesting can be deep, and this runs before the depth check.
    let mut pair = pair.clone();
    loop {
        match pair.as_rule() {
            // Atomic rules never contain trivia.
            Rule::number | Rule::string => return pair.as_span().end(),
            // From the back: `last()` would walk every child, and this runs for
            // every span made (a long list's children, again at each level).
            _ => match pair.clone().into_inner().next_back() {
                Some(last) => pair = last,
                None => return pair.as_span().end(),
            },
        }
    }
}

/// Children that carry meaning (keywords and punctuation skipped).
fn kids<'i>(pair: Pair<'i, Rule>) -> impl Iterator<Item = Pair<'i, Rule>> {
    pair.into_inner().filter(|p| !is_token(p.as_rule()))
}

impl Builder {
    fn span(&self, pair: &Pair<Rule>) -> Span {
        Span::new(self.file, pair.as_span().start(), exact_end(pair))
    }

    fn ident(&self, pair: &Pair<Rule>) -> Ident {
        Spanned::new(pair.as_str().to_string(), self.span(pair))
    }

    fn import(&self, pair: Pair<Rule>) -> Import {
        let span = self.span(&pair);
        let mut it = kids(pair);
        let path = it.next().expect("import has a path");
        let alias = it.next().expect("import has an alias");
        Import {
            path: Spanned::new(unescape(path.as_str()), self.span(&path)),
            alias: self.ident(&alias),
            span,
        }
    }

    fn units(&self, pair: Pair<Rule>) -> Res<UnitsDirective> {
        const NAMES: [&str; 6] = ["mm", "cm", "m", "in", "deg", "rad"];
        let span = self.span(&pair);
        let mut units = Vec::new();
        for p in kids(pair) {
            let w = p.as_str();
            if !NAMES.contains(&w) {
                let mut help =
                    "the default units are mm, cm, m, in (lengths) and deg, rad (angles)"
                        .to_string();
                if let Some(s) = crate::diag::did_you_mean(w, NAMES) {
                    help = format!("did you mean `{s}`? {help}");
                }
                return Err(Diagnostic::new(
                    CODE,
                    format!("`{w}` is not a unit"),
                    self.span(&p),
                    "unknown unit",
                )
                .with_help(help));
            }
            units.push(Spanned::new(unit_of(w), self.span(&p)));
        }
        Ok(UnitsDirective { units, span })
    }

    fn fn_decl(&mut self, pair: Pair<Rule>) -> Res<FnDecl> {
        let span = self.span(&pair);
        let mut it = kids(pair);
        let name = self.ident(&it.next().expect("fn has a name"));
        let params = self.params(it.next().expect("fn has parameters"))?;
        let body = self.expr(it.next().expect("fn has a body"))?;
        Ok(FnDecl {
            name,
            params,
            body,
            span,
        })
    }

    fn params(&mut self, pair: Pair<Rule>) -> Res<Vec<Param>> {
        kids(pair)
            .map(|p| {
                let mut it = kids(p);
                let name = self.ident(&it.next().expect("param has a name"));
                let default = it.next().map(|e| self.expr(e)).transpose()?;
                Ok(Param { name, default })
            })
            .collect()
    }

    fn decl(&mut self, pair: Pair<Rule>) -> Res<Decl> {
        let span = self.span(&pair);
        let mut it = kids(pair);
        let kind = self.ident(&it.next().expect("decl has a kind"));
        let name = self.ident(&it.next().expect("decl has a name"));
        let body = it.next().expect("decl has a body");
        let body = match body.as_rule() {
            Rule::block if VALUE_KINDS.contains(&kind.node.as_str()) => {
                return Err(block_for_value(&kind, &name, self.span(&body)));
            }
            Rule::block => DeclBody::Block(self.block(body)?),
            _ => DeclBody::Expr(self.expr(body)?),
        };
        Ok(Decl {
            kind,
            name,
            body,
            span,
        })
    }

    fn block(&mut self, pair: Pair<Rule>) -> Res<Block> {
        let span = self.span(&pair);
        let mut fields = Vec::new();
        for f in kids(pair) {
            let fspan = self.span(&f);
            let mut path = Vec::new();
            let mut value = None;
            for p in kids(f) {
                match p.as_rule() {
                    Rule::field_word => path.push(self.ident(&p)),
                    Rule::block => value = Some(FieldValue::Block(self.block(p)?)),
                    _ => value = Some(FieldValue::Expr(self.expr(p)?)),
                }
            }
            fields.push(Field {
                path,
                value: value.expect("field has a value"),
                span: fspan,
            });
        }
        Ok(Block { fields, span })
    }

    /// Any expression-level pair.
    fn expr(&mut self, pair: Pair<Rule>) -> Res<Expr> {
        // Count nesting, not precedence levels: a whole expression (inside brackets, a
        // branch, an argument) or a prefix operator is one level.
        let counts = match pair.as_rule() {
            Rule::expr => true,
            Rule::unary | Rule::not_expr => pair.clone().into_inner().nth(1).is_some(),
            _ => false,
        };
        if !counts {
            return self.expr_inner(pair);
        }
        self.depth += 1;
        if self.depth > self.limits.count(Limit::Nesting) {
            let span = self.span(&pair);
            return Err(Diagnostic::new(
                CODE,
                format!(
                    "expression nested more than {} levels deep",
                    self.limits.get(Limit::Nesting)
                ),
                Span::new(self.file, span.start as usize, span.start as usize + 1),
                "nested too deeply",
            )
            .with_help(format!(
                "split it into named declarations; {}",
                Limit::Nesting.help(&self.limits)
            )));
        }
        let out = self.expr_inner(pair);
        self.depth -= 1;
        out
    }

    /// Enters the levels a chain adds to the tree, one per operation after the first
    /// (`ops`, where each is written): `a + b + c` is `(a + b) + c`, so the first operand
    /// (`first`) sits under every operation of the chain. The first operation is not
    /// counted, as a bracket is one level with what it holds: the tree is then at most
    /// twice as deep as the nesting limit. A chain that would pass the limit is refused
    /// at the operation that passes it. Leave with [`Builder::leave_chain`].
    fn enter_chain(&mut self, first: &Pair<Rule>, ops: &[Span]) -> Res<()> {
        let room = self.limits.count(Limit::Nesting).saturating_sub(self.depth);
        if let Some(&at) = ops.get(room + 1) {
            let start = first.as_span().start();
            let head = first.as_str().chars().next().map_or(0, char::len_utf8);
            let end = if exact_end(first) - start <= 40 {
                exact_end(first)
            } else {
                start + head
            };
            return Err(Diagnostic::new(
                CODE,
                format!(
                    "this chain of {} operations is nested more than {} levels deep",
                    ops.len(),
                    self.limits.get(Limit::Nesting)
                ),
                at,
                "the nesting limit is passed here",
            )
            .with_label(Span::new(self.file, start, end), "the chain starts here")
            .with_help(format!(
                "each operation of a chain holds the ones before it (`a + b + c` is `(a + b) + c`): \
                 split the chain into named declarations (`let part = ...`) and chain their names, \
                 or add up a list with `sum([...])`; {}",
                Limit::Nesting.help(&self.limits)
            )));
        }
        self.depth += chain_levels(ops);
        Ok(())
    }

    /// Leaves the levels [`Builder::enter_chain`] entered.
    fn leave_chain(&mut self, ops: &[Span]) {
        self.depth -= chain_levels(ops);
    }

    /// Where a chain's operations are written: its pairs that are not `first` operand or
    /// operands (`keep` says which pairs are operations), each as its first character
    /// (a call's arguments may be long).
    fn op_spans(&self, pair: &Pair<Rule>, keep: impl Fn(Rule) -> bool) -> Vec<Span> {
        pair.clone()
            .into_inner()
            .skip(1)
            .filter(|p| keep(p.as_rule()))
            .map(|p| {
                let start = p.as_span().start();
                let len = p.as_str().chars().next().map_or(0, char::len_utf8);
                let end = if p.as_str().len() <= 3 {
                    exact_end(&p)
                } else {
                    start + len
                };
                Span::new(self.file, start, end)
            })
            .collect()
    }

    /// An expression pair turned into its node: one builder per expression form.
    fn expr_inner(&mut self, pair: Pair<Rule>) -> Res<Expr> {
        let span = self.span(&pair);
        match pair.as_rule() {
            Rule::expr => self.pipe_chain(pair),
            rule @ (Rule::or_expr
            | Rule::and_expr
            | Rule::add_expr
            | Rule::mul_expr
            | Rule::cmp_expr) => self.binary_chain(pair, rule),
            Rule::not_expr | Rule::unary => self.prefixed(pair),
            Rule::postfix_expr | Rule::pipe_target => self.postfixed(pair),
            Rule::number => self.number(pair, span),
            Rule::string => {
                let inner = pair.into_inner().next().map_or("", |p| p.as_str());
                Ok(Expr {
                    kind: ExprKind::Str(unescape_inner(inner)),
                    span,
                })
            }
            Rule::bool_lit => Ok(Expr {
                kind: ExprKind::Bool(pair.as_str() == "true"),
                span,
            }),
            Rule::name => Ok(Expr {
                kind: ExprKind::Name(pair.as_str().to_string()),
                span,
            }),
            Rule::if_expr => self.if_expr(pair, span),
            Rule::lambda => self.lambda(pair, span),
            Rule::list => self.list(pair, span),
            Rule::paren => self.paren(pair, span),
            Rule::record => self.record(pair, span),
            Rule::sketch => self.sketch(pair, span),
            other => unreachable!("not an expression rule: {other:?}"),
        }
    }

    /// `a |> f(x) |> g`: each stage a pipe node whose input is everything before it.
    fn pipe_chain(&mut self, pair: Pair<Rule>) -> Res<Expr> {
        let ops = self.op_spans(&pair, |r| r == Rule::pipe_op);
        let mut it = kids(pair);
        let first = it.next().expect("expr has an operand");
        self.enter_chain(&first, &ops)?;
        let out = self.pipe_stages(first, it);
        self.leave_chain(&ops);
        out
    }

    /// The operand and pipe targets of [`Builder::pipe_chain`], folded to the left.
    fn pipe_stages<'i>(
        &mut self,
        first: Pair<'i, Rule>,
        targets: impl Iterator<Item = Pair<'i, Rule>>,
    ) -> Res<Expr> {
        let mut acc = self.expr(first)?;
        for target in targets {
            let call = self.expr(target.into_inner().next().expect("pipe target"))?;
            let span = acc.span.to(call.span);
            acc = Expr {
                kind: ExprKind::Pipe {
                    input: Box::new(acc),
                    call: Box::new(call),
                },
                span,
            };
        }
        Ok(acc)
    }

    /// Operands joined by the operators of one precedence level (`rule`), grouped to the
    /// left; a second comparison in one chain (`a < b < c`) is refused: comparisons do
    /// not chain, and the message names both.
    fn binary_chain(&mut self, pair: Pair<Rule>, rule: Rule) -> Res<Expr> {
        let ops = self.op_spans(&pair, |r| {
            matches!(
                r,
                Rule::add_op | Rule::mul_op | Rule::cmp_op | Rule::kw_and | Rule::kw_or
            )
        });
        if let (Rule::cmp_expr, [first, second, ..]) = (rule, ops.as_slice()) {
            return Err(chained_comparison(*first, *second));
        }
        let mut it = pair.into_inner();
        let first = it.next().expect("chain has an operand");
        self.enter_chain(&first, &ops)?;
        let out = self.binary_operands(first, it, rule);
        self.leave_chain(&ops);
        out
    }

    /// The operands and operators of [`Builder::binary_chain`], folded to the left.
    fn binary_operands<'i>(
        &mut self,
        first: Pair<'i, Rule>,
        mut it: impl Iterator<Item = Pair<'i, Rule>>,
        rule: Rule,
    ) -> Res<Expr> {
        let mut acc = self.expr(first)?;
        let mut first_cmp: Option<Span> = None;
        while let Some(op) = it.next() {
            let op_span = self.span(&op);
            let bop = binary_op(op.as_str());
            if rule == Rule::cmp_expr {
                if let Some(first) = first_cmp {
                    return Err(chained_comparison(first, op_span));
                }
                first_cmp = Some(op_span);
            }
            let rhs = self.expr(it.next().expect("operator has a right operand"))?;
            let span = acc.span.to(rhs.span);
            acc = Expr {
                kind: ExprKind::Binary {
                    op: Spanned::new(bop, op_span),
                    lhs: Box::new(acc),
                    rhs: Box::new(rhs),
                },
                span,
            };
        }
        Ok(acc)
    }

    /// `not x` or `-x`, or the operand alone when the level has no operator.
    fn prefixed(&mut self, pair: Pair<Rule>) -> Res<Expr> {
        let mut it = pair.into_inner();
        let first = it.next().expect("unary has a child");
        let op = match first.as_rule() {
            Rule::kw_not => UnaryOp::Not,
            Rule::neg_op => UnaryOp::Neg,
            _ => return self.expr(first),
        };
        let op = Spanned::new(op, self.span(&first));
        let operand = self.expr(it.next().expect("unary has an operand"))?;
        let span = op.span.to(operand.span);
        Ok(Expr {
            kind: ExprKind::Unary {
                op,
                operand: Box::new(operand),
            },
            span,
        })
    }

    /// A primary followed by field accesses, indexes and calls, applied left to right
    /// (`a.b[0](x)`); each node spans from the primary to its own end.
    fn postfixed(&mut self, pair: Pair<Rule>) -> Res<Expr> {
        let ops = self.op_spans(&pair, |_| true);
        let mut it = pair.into_inner();
        let first = it.next().expect("postfix has a primary");
        self.enter_chain(&first, &ops)?;
        let out = self.postfix_ops(first, it);
        self.leave_chain(&ops);
        out
    }

    /// The primary and postfix operations of [`Builder::postfixed`], applied in order.
    fn postfix_ops<'i>(
        &mut self,
        first: Pair<'i, Rule>,
        posts: impl Iterator<Item = Pair<'i, Rule>>,
    ) -> Res<Expr> {
        let mut acc = self.expr(first)?;
        for post in posts {
            let end = exact_end(&post);
            let span = Span::new(self.file, acc.span.start as usize, end);
            let target = Box::new(acc);
            let kind = match post.as_rule() {
                Rule::field_access => ExprKind::Field {
                    target,
                    name: self.ident(&post.into_inner().next().expect("field name")),
                },
                Rule::index => ExprKind::Index {
                    target,
                    index: Box::new(self.expr(kids(post).next().expect("index expression"))?),
                },
                _ => ExprKind::Call {
                    callee: target,
                    args: self.call_args(post)?,
                },
            };
            acc = Expr { kind, span };
        }
        Ok(acc)
    }

    /// A call's arguments, each positional or named (`name: value`).
    fn call_args(&mut self, pair: Pair<Rule>) -> Res<Vec<Arg>> {
        let mut args = Vec::new();
        for a in kids(pair) {
            let mut name = None;
            let mut value = None;
            for p in kids(a) {
                if p.as_rule() == Rule::arg_name {
                    name = Some(self.ident(&p));
                } else {
                    value = Some(self.expr(p)?);
                }
            }
            args.push(Arg {
                name,
                value: value.expect("argument has a value"),
            });
        }
        Ok(args)
    }

    /// A number with its unit if one is written (`12.5 mm`); one too large for an f64
    /// is refused rather than read as infinity, one too small rather than read as 0
    /// ([`literal_range`]).
    fn number(&self, pair: Pair<Rule>, span: Span) -> Res<Expr> {
        let mut value = 0.0;
        let mut unit = None;
        for p in pair.into_inner() {
            match p.as_rule() {
                Rule::num_lit => {
                    value = p.as_str().parse::<f64>().unwrap_or(f64::INFINITY);
                    if let Some(d) = literal_range(value, p.as_str(), self.span(&p)) {
                        return Err(d);
                    }
                }
                _ => unit = Some(Spanned::new(unit_of(p.as_str()), self.span(&p))),
            }
        }
        Ok(Expr {
            kind: ExprKind::Number { value, unit },
            span,
        })
    }

    /// `if c then a else b`.
    fn if_expr(&mut self, pair: Pair<Rule>, span: Span) -> Res<Expr> {
        let mut it = kids(pair);
        let cond = self.expr(it.next().expect("if condition"))?;
        let then = self.expr(it.next().expect("then branch"))?;
        let otherwise = self.expr(it.next().expect("else branch"))?;
        Ok(Expr {
            kind: ExprKind::If {
                cond: Box::new(cond),
                then: Box::new(then),
                otherwise: Box::new(otherwise),
            },
            span,
        })
    }

    /// `fn(x, y = 1) => body`.
    fn lambda(&mut self, pair: Pair<Rule>, span: Span) -> Res<Expr> {
        let mut it = kids(pair);
        let params = self.params(it.next().expect("lambda parameters"))?;
        let body = self.expr(it.next().expect("lambda body"))?;
        Ok(Expr {
            kind: ExprKind::Lambda {
                params,
                body: Box::new(body),
            },
            span,
        })
    }

    /// `[a, b, c]`, or a comprehension `[body for x in xs if c]` (the grammar puts the
    /// body first, then the `for` part).
    fn list(&mut self, pair: Pair<Rule>, span: Span) -> Res<Expr> {
        let mut items = Vec::new();
        let mut comp = None;
        for p in kids(pair) {
            if p.as_rule() == Rule::comprehension {
                comp = Some(p);
            } else {
                items.push(self.expr(p)?);
            }
        }
        let kind = match comp {
            None => ExprKind::List(items),
            Some(c) => {
                let body = items.pop().expect("comprehension body");
                self.comprehension(c, body)?
            }
        };
        Ok(Expr { kind, span })
    }

    /// The `for x in xs if c` part of a comprehension, around its `body`.
    fn comprehension(&mut self, pair: Pair<Rule>, body: Expr) -> Res<ExprKind> {
        let mut it = kids(pair);
        let var = self.ident(&it.next().expect("loop variable"));
        let iter = self.expr(it.next().expect("iterated expression"))?;
        let cond = it.next().map(|e| self.expr(e)).transpose()?.map(Box::new);
        Ok(ExprKind::Comprehension {
            body: Box::new(body),
            var,
            iter: Box::new(iter),
            cond,
        })
    }

    /// `(a)`, the expression itself, or `(a, b)`, a tuple.
    fn paren(&mut self, pair: Pair<Rule>, span: Span) -> Res<Expr> {
        let mut items = kids(pair).map(|p| self.expr(p)).collect::<Res<Vec<_>>>()?;
        if items.len() == 1 {
            // A parenthesised expression keeps its node; its span grows to the
            // parentheses so `(a + b) * c` spans from `(`.
            let mut inner = items.pop().expect("one element");
            inner.span = span;
            Ok(inner)
        } else {
            Ok(Expr {
                kind: ExprKind::Tuple(items),
                span,
            })
        }
    }

    /// `{ key: value, ... }`.
    fn record(&mut self, pair: Pair<Rule>, span: Span) -> Res<Expr> {
        let mut fields = Vec::new();
        for f in kids(pair) {
            let mut it = kids(f);
            let key = self.ident(&it.next().expect("record key"));
            let value = self.expr(it.next().expect("record value"))?;
            fields.push((key, value));
        }
        Ok(Expr {
            kind: ExprKind::Record(fields),
            span,
        })
    }

    /// `sketch(view) { commands }`.
    fn sketch(&mut self, pair: Pair<Rule>, span: Span) -> Res<Expr> {
        let mut it = kids(pair);
        let view = self.expr(it.next().expect("sketch view"))?;
        let mut commands = Vec::new();
        for c in it {
            commands.push(self.sketch_command(c)?);
        }
        Ok(Expr {
            kind: ExprKind::Sketch {
                view: Box::new(view),
                commands,
            },
            span,
        })
    }

    fn sketch_command(&mut self, pair: Pair<Rule>) -> Res<SketchCommand> {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let tangent = pair
            .clone()
            .into_inner()
            .any(|p| p.as_rule() == Rule::kw_tangent);
        let mut exprs = Vec::new();
        for p in kids(pair) {
            if p.as_rule() != Rule::kw_tangent {
                exprs.push(self.expr(p)?);
            }
        }
        let mut it = exprs.into_iter();
        let mut next = || it.next().expect("sketch command operand");
        let kind = match rule {
            Rule::cmd_from => SketchCommandKind::From(next()),
            Rule::cmd_line => SketchCommandKind::LineTo(next()),
            Rule::cmd_arc => {
                let to = next();
                SketchCommandKind::ArcThrough {
                    to,
                    through: next(),
                }
            }
            Rule::cmd_tangent_arc => SketchCommandKind::TangentArcTo(next()),
            Rule::cmd_spline => SketchCommandKind::Spline {
                through: next(),
                tangent,
            },
            Rule::cmd_fillet => SketchCommandKind::Fillet(next()),
            _ => SketchCommandKind::Close,
        };
        Ok(SketchCommand { kind, span })
    }
}

/// The levels a chain of operations `ops` adds to the tree (see
/// [`Builder::enter_chain`]).
fn chain_levels(ops: &[Span]) -> usize {
    ops.len().saturating_sub(1)
}

fn binary_op(s: &str) -> BinaryOp {
    match s {
        "+" => BinaryOp::Add,
        "-" => BinaryOp::Sub,
        "*" => BinaryOp::Mul,
        "/" => BinaryOp::Div,
        "==" => BinaryOp::Eq,
        "!=" => BinaryOp::Ne,
        "<" => BinaryOp::Lt,
        "<=" => BinaryOp::Le,
        ">" => BinaryOp::Gt,
        ">=" => BinaryOp::Ge,
        "and" => BinaryOp::And,
        _ => BinaryOp::Or,
    }
}

fn unit_of(s: &str) -> Unit {
    match s {
        "mm" => Unit::Mm,
        "cm" => Unit::Cm,
        "m" => Unit::M,
        "in" => Unit::In,
        "deg" => Unit::Deg,
        "rad" => Unit::Rad,
        _ => Unit::Percent,
    }
}

/// A string literal's value, quotes included in `lit`.
fn unescape(lit: &str) -> String {
    unescape_inner(
        lit.strip_prefix('"')
            .and_then(|s| s.strip_suffix('"'))
            .unwrap_or(lit),
    )
}

/// Resolves `\" \\ \n \t` (the grammar admits no other escape).
fn unescape_inner(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars();
    while let Some(c) = chars.next() {
        if c == '\\' {
            match chars.next() {
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                Some(other) => out.push(other),
                None => {}
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// Declaration kinds that take `= value`, never a block of fields (the engine's plain
/// kinds; every other kind is a feature, written as a block).
pub const VALUE_KINDS: [&str; 3] = ["let", "param", "product"];

/// `let a { x = 1 }`: a block after a kind that takes `= value`.
fn block_for_value(kind: &Ident, name: &Ident, block: Span) -> Diagnostic {
    let k = kind.node.as_str();
    let n = name.node.as_str();
    let help = if k == "product" {
        "a product declaration names the finished part: a surface, a mesh or a list of surfaces, \
         as in `product door = trim(panel, outline)` or `product door = read_obj(\"door.obj\")`; \
         blocks of fields belong to features such as `punch_opening opening { ... }`"
            .to_string()
    } else {
        format!(
            "write `{k} {n} = value`; a record of fields is a value too: `{k} {n} = {{ x: 1, y: 2 }}`"
        )
    };
    Diagnostic::new(
        CODE,
        format!("`{k}` takes `= value`, not a block of fields"),
        Span::new(block.file, block.start as usize, block.start as usize + 1),
        "a block",
    )
    .with_label(kind.span, format!("a `{k}` declaration"))
    .with_help(help)
}

fn chained_comparison(first: Span, second: Span) -> Diagnostic {
    Diagnostic::new(
        CODE,
        "comparisons cannot be chained",
        second,
        "a second comparison",
    )
    .with_label(first, "after this one")
    .with_help("compare twice and join with `and`: `a < b and b < c`")
}

// ---------------------------------------------------------------------------------------
// Errors

mod errors {
    use super::lex::{self, Tok, TokKind};
    use super::*;

    /// What pest expected, as words.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
    enum Want {
        // Ordered by how specific (and so how useful) the phrase is.
        ArgsClose,
        ParamsClose,
        IndexClose,
        ListClose,
        ParenClose,
        RecordClose,
        BlockField,
        SketchCommand,
        ArcOrSpline,
        AssignOrBlock,
        FnAssign,
        Arrow,
        Colon,
        Then,
        Else,
        In,
        As,
        To,
        Through,
        UnitName,
        ImportPath,
        DeclName,
        FnName,
        ParamName,
        VarName,
        Alias,
        FieldName,
        Expr,
        Item,
        Operator,
    }

    impl Want {
        fn phrase(self) -> &'static str {
            match self {
                Want::ArgsClose => "`,` or `)` to close the argument list",
                Want::ParamsClose => "`,` or `)` to close the parameter list",
                Want::IndexClose => "`]` to close the index",
                Want::ListClose => "`,` or `]` to close the list",
                Want::ParenClose => "`)` to close the parenthesis",
                Want::RecordClose => "`,` or `}` to close the record",
                Want::BlockField => "a field such as `depth = 40 mm`, or `}` to close the block",
                Want::SketchCommand => {
                    "a sketch command (from, line to, arc to, tangent arc to, spline through, fillet, close) or `}`"
                }
                Want::ArcOrSpline => "`arc to` or `spline through`",
                Want::AssignOrBlock => "`=` followed by a value, or a `{` block",
                Want::FnAssign => "`=` followed by the function body",
                Want::Arrow => "`=>` followed by the function body",
                Want::Colon => "`:` followed by a value",
                Want::Then => "`then`",
                Want::Else => "`else`",
                Want::In => "`in`",
                Want::As => "`as` and a name for the module",
                Want::To => "`to` and a point",
                Want::Through => "`through` and a point",
                Want::UnitName => "a unit (mm, cm, m, in, deg, rad)",
                Want::ImportPath => "a path in quotes such as \"std/profiles\"",
                Want::DeclName => "a name for the declaration",
                Want::FnName => "a name for the function",
                Want::ParamName => "a parameter name",
                Want::VarName => "a name for the loop variable",
                Want::Alias => "a name for the module",
                Want::FieldName => "a field name",
                Want::Expr => "an expression",
                Want::Item => "a declaration such as `let width = 550 mm`",
                Want::Operator => "an operator",
            }
        }

        /// Whether the phrase asks for a name (so a keyword there deserves a hint).
        fn is_name(self) -> bool {
            matches!(
                self,
                Want::DeclName | Want::FnName | Want::ParamName | Want::VarName | Want::Alias
            )
        }
    }

    /// The phrases for pest's positives, most specific first; continuations of a
    /// finished expression ("an operator") only when nothing else was possible.
    fn wants(positives: &[Rule]) -> Vec<Want> {
        let has = |r: Rule| positives.contains(&r);
        let item_context = has(Rule::EOI) || has(Rule::decl_kind);
        let mut out = Vec::new();
        for &r in positives {
            let w = match r {
                Rule::args_close => Want::ArgsClose,
                Rule::params_close => Want::ParamsClose,
                Rule::index_close => Want::IndexClose,
                Rule::list_close => Want::ListClose,
                Rule::paren_close => Want::ParenClose,
                Rule::record_close => Want::RecordClose,
                Rule::block_close => Want::BlockField,
                Rule::sketch_close
                | Rule::kw_from
                | Rule::kw_line
                | Rule::kw_fillet
                | Rule::kw_close => Want::SketchCommand,
                Rule::kw_arc | Rule::kw_spline | Rule::kw_tangent => {
                    if has(Rule::sketch_close) || has(Rule::kw_from) {
                        Want::SketchCommand
                    } else {
                        Want::ArcOrSpline
                    }
                }
                Rule::assign | Rule::block => {
                    if has(Rule::params_close) {
                        continue; // a parameter's default: the `,`/`)` phrase says enough
                    }
                    Want::AssignOrBlock
                }
                Rule::fn_assign => Want::FnAssign,
                Rule::arrow => Want::Arrow,
                Rule::colon => {
                    // After a word that may be a named argument or a record key, the
                    // closing bracket is the better suggestion.
                    if has(Rule::args_close)
                        || has(Rule::record_close)
                        || positives.iter().any(|r| is_expr_start(*r))
                    {
                        continue;
                    }
                    Want::Colon
                }
                Rule::kw_then => Want::Then,
                Rule::kw_else => Want::Else,
                Rule::kw_in => Want::In,
                Rule::kw_as => Want::As,
                Rule::kw_to => Want::To,
                Rule::kw_through => Want::Through,
                Rule::unit_name => Want::UnitName,
                Rule::decl_name => Want::DeclName,
                Rule::fn_name => Want::FnName,
                Rule::param_name => {
                    if has(Rule::params_close) {
                        continue;
                    }
                    Want::ParamName
                }
                Rule::var_name => Want::VarName,
                Rule::alias => Want::Alias,
                Rule::field_word => {
                    if has(Rule::assign) || has(Rule::block_close) {
                        continue;
                    }
                    Want::FieldName
                }
                Rule::key | Rule::record_field => {
                    if has(Rule::record_close) {
                        continue;
                    }
                    Want::FieldName
                }
                Rule::string
                    if !positives
                        .iter()
                        .any(|r| *r != Rule::string && is_expr_start(*r)) =>
                {
                    Want::ImportPath
                }
                Rule::EOI
                | Rule::decl_kind
                | Rule::kw_import
                | Rule::kw_units
                | Rule::import
                | Rule::units => Want::Item,
                Rule::kw_fn if item_context => Want::Item,
                Rule::fn_decl | Rule::decl | Rule::file => Want::Item,
                r if is_expr_start(r) => Want::Expr,
                _ => Want::Operator,
            };
            out.push(w);
        }
        out.sort();
        out.dedup();
        if out.len() > 1 {
            out.retain(|w| *w != Want::Operator);
        }
        // A closing bracket or a block field says more than "an expression could go on".
        if out.iter().any(|w| *w < Want::Expr) {
            out.retain(|w| *w != Want::Item);
        }
        out
    }

    /// Rules that begin an expression (pest reports the innermost rule with several
    /// alternatives, which can be any level of the precedence ladder).
    fn is_expr_start(r: Rule) -> bool {
        matches!(
            r,
            Rule::expr
                | Rule::or_expr
                | Rule::and_expr
                | Rule::not_expr
                | Rule::cmp_expr
                | Rule::add_expr
                | Rule::mul_expr
                | Rule::unary
                | Rule::neg_op
                | Rule::kw_not
                | Rule::postfix_expr
                | Rule::pipe_target
                | Rule::number
                | Rule::num_lit
                | Rule::string
                | Rule::bool_lit
                | Rule::if_expr
                | Rule::kw_if
                | Rule::lambda
                | Rule::kw_fn
                | Rule::sketch
                | Rule::kw_sketch
                | Rule::list
                | Rule::paren
                | Rule::record
                | Rule::name
                | Rule::arg
                | Rule::arg_name
        )
    }

    fn join(wants: &[Want]) -> String {
        let phrases: Vec<&str> = wants.iter().map(|w| w.phrase()).collect();
        match phrases.as_slice() {
            [] => "something else".to_string(),
            [one] => one.to_string(),
            [init @ .., last] => format!("{} or {}", init.join(", "), last),
        }
    }

    pub(super) fn convert(err: &pest::error::Error<Rule>, text: &str, file: FileId) -> Diagnostic {
        let pos = match err.location {
            InputLocation::Pos(p) => p,
            InputLocation::Span((s, _)) => s,
        };
        let toks = lex::tokens(text);
        if let Some(d) = lex::problem_before(&toks, text, pos, file) {
            return d;
        }
        let positives = match &err.variant {
            ErrorVariant::ParsingError { positives, .. } => positives.clone(),
            ErrorVariant::CustomError { .. } => {
                // pest's stack guard: only pathological nesting gets here.
                return Diagnostic::new(
                    CODE,
                    "this file is nested too deeply to read",
                    Span::new(file, pos, (pos + 1).min(text.len())),
                    "nested too deeply",
                )
                .with_help("split deeply nested expressions into named declarations");
            }
        };
        let wants = wants(&positives);
        let found = lex::found_at(&toks, text, pos);
        let span = if found.kind == TokKind::Eof {
            eof_span(text, file)
        } else {
            Span::new(file, found.start, found.end)
        };
        let at_eof = found.kind == TokKind::Eof;
        let found_desc = describe(&found, text);
        let word = &text[found.start..found.end];
        let label = if at_eof {
            "the file ends here".to_string()
        } else {
            format!("expected {}", short(&wants))
        };

        // A keyword where a name belongs.
        let name_rules = [
            Rule::decl_name,
            Rule::fn_name,
            Rule::param_name,
            Rule::var_name,
            Rule::alias,
        ];
        if found.kind == TokKind::Word
            && lex::is_keyword(word)
            && (wants.iter().any(|w| w.is_name())
                || positives.iter().any(|r| name_rules.contains(r)))
        {
            return Diagnostic::new(
                CODE,
                format!("expected {}, found the keyword `{word}`", join(&wants)),
                span,
                "a keyword, not a name",
            )
            .with_help(format!("`{word}` is a keyword; choose another name"));
        }

        let mut d = Diagnostic::new(
            CODE,
            format!("expected {}, found {found_desc}", join(&wants)),
            span,
            label,
        );

        // Unbalanced brackets: point at the one still open.
        let closer = wants.iter().find_map(|w| match w {
            Want::ArgsClose | Want::ParamsClose | Want::ParenClose => Some('('),
            Want::IndexClose | Want::ListClose => Some('['),
            Want::RecordClose | Want::BlockField | Want::SketchCommand => Some('{'),
            _ => None,
        });
        let open = lex::open_brackets(&toks, text, pos);
        if let Some(opener) = closer {
            if let Some(&(_, at)) = open.iter().rev().find(|(c, _)| *c == opener) {
                let what = match wants[0] {
                    Want::ArgsClose => "the argument list",
                    Want::ParamsClose => "the parameter list",
                    Want::IndexClose => "the index",
                    Want::ListClose => "the list",
                    Want::RecordClose => "the record",
                    Want::BlockField => "the block",
                    Want::SketchCommand => "the sketch",
                    _ => "the parenthesis",
                };
                d = d.with_label(
                    Span::new(file, at, at + 1),
                    format!("{what} opened here is not closed"),
                );
                // The error begins a new line: the closer is missing before it.
                if at_eof || !lex::same_line_as_previous(text, &found) {
                    let close = match opener {
                        '(' => ')',
                        '[' => ']',
                        _ => '}',
                    };
                    let opened = line_of(text, at);
                    let before = text[..found.start.min(text.len())].trim_end();
                    let missing = if opener == '{' {
                        unclosed_block(&[(opener, at)], &found, text, false)
                            .map(|(_, _, m)| format!("before line {m}"))
                    } else {
                        Some(format!(
                            "at the end of line {}",
                            line_of(text, before.len())
                        ))
                    };
                    if let Some(missing) = missing {
                        d = d.with_help(format!(
                            "{what} opened on line {opened} is not closed: is a `{close}` missing {missing}?"
                        ));
                    }
                }
            }
            // `f(a b)`: an operand where a separator belongs, on the same line.
            let separated = matches!(
                wants[0],
                Want::ArgsClose
                    | Want::ParamsClose
                    | Want::ListClose
                    | Want::RecordClose
                    | Want::ParenClose
            );
            if separated
                && lex::starts_operand(&found, text)
                && lex::same_line_as_previous(text, &found)
            {
                let what = match wants[0] {
                    Want::ArgsClose => "arguments",
                    Want::ParamsClose => "parameters",
                    Want::RecordClose => "record fields",
                    _ => "elements",
                };
                d = d.with_help(format!(
                    "{what} are separated by commas: is a `,` missing before {found_desc}?"
                ));
            }
        }
        match word {
            "=" if wants.contains(&Want::DeclName) => {
                d = d.with_help(
                    "a declaration starts with its kind, then its name: `let width = 550 mm`",
                );
            }
            "=" if positives.contains(&Rule::cmp_op) || wants.contains(&Want::Then) => {
                d = d.with_help(
                    "to compare two values write `==`; a single `=` gives a name its value",
                );
            }
            "==" if wants.contains(&Want::AssignOrBlock) => {
                d = d.with_help("a declaration takes a single `=`");
            }
            ")" | "]" | "}" => {
                let opener = match word {
                    ")" => '(',
                    "]" => '[',
                    _ => '{',
                };
                match open.last() {
                    None => d = d.with_help(format!("this `{word}` has no matching `{opener}`")),
                    Some(&(c, at)) if c != opener && closer.is_none() => {
                        d = d.with_label(
                            Span::new(file, at, at + 1),
                            format!("this `{c}` is still open"),
                        );
                    }
                    _ => {}
                }
            }
            w if found.kind == TokKind::Word
                && lex::is_keyword(w)
                && wants.contains(&Want::Expr) =>
            {
                d = d.with_help(format!("`{w}` is a keyword; it cannot be used as a name"));
            }
            _ => {}
        }
        if matches!(closer, None | Some('{')) {
            if let Some((at, opened, missing)) = unclosed_block(&open, &found, text, true) {
                if closer.is_none() {
                    d = d.with_label(Span::new(file, at, at + 1), "this block is not closed");
                }
                if d.help.is_none() {
                    d = d.with_help(format!(
                        "the block opened on line {opened} is not closed: is a `}}` missing before line {missing}?"
                    ));
                }
            }
        }
        if d.help.is_none() {
            let in_block = open.last().is_some_and(|&(c, _)| c == '{');
            d = d.with_help(fallback_help(&wants, &found, text, at_eof, in_block));
        }
        d
    }

    /// An error after a `{` still open: most likely its `}` is missing, and the error is
    /// where the next item begins. The `{`'s offset, its line, and the line that
    /// probably lacks the `}` (the first after it that starts without indentation).
    /// With `unclosed_only`, only a `{` that no `}` in the whole file closes counts.
    fn unclosed_block(
        open: &[(char, usize)],
        found: &Tok,
        text: &str,
        unclosed_only: bool,
    ) -> Option<(usize, usize, usize)> {
        let toks = if unclosed_only {
            lex::tokens(text)
        } else {
            Vec::new()
        };
        let &(_, at) = open
            .iter()
            .rev()
            .find(|&&(c, at)| c == '{' && !(unclosed_only && lex::closed_later(&toks, text, at)))?;
        let opened = line_of(text, at);
        let after = text[at..found.start.min(text.len())]
            .match_indices(['\n', '\r'])
            .map(|(i, _)| at + i + 1)
            .find(|&i| {
                text[i..]
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            });
        let missing = after.map_or_else(
            || line_of(text, found.start.min(text.len())),
            |i| line_of(text, i),
        );
        (missing > opened).then_some((at, opened, missing))
    }

    /// The 1-based line of byte `pos` (`\n`, `\r\n` and a lone `\r` end a line).
    fn line_of(text: &str, pos: usize) -> usize {
        let upto = &text[..pos];
        upto.matches(['\n', '\r']).count() - upto.matches("\r\n").count() + 1
    }

    /// The help of a syntax error no case above explained: how the expected thing is
    /// written, in the light of what was found.
    fn fallback_help(
        wants: &[Want],
        found: &Tok,
        text: &str,
        at_eof: bool,
        in_block: bool,
    ) -> String {
        let word = &text[found.start..found.end];
        let Some(first) = wants.first() else {
            return "remove or rewrite this part; docs/language.md shows each form".to_string();
        };
        match first {
            Want::Expr => match word {
                ")" | "]" | "}" | "," | ";" => format!(
                    "a value is missing before `{word}`: write one (`10 mm`, a name, `f(x)`, `(x, y)`), or remove the `{word}`"
                ),
                "+" | "-" | "*" | "/" | "<" | ">" | "<=" | ">=" | "==" | "!=" | "|>" | "and" | "or" => {
                    format!("`{word}` needs a value on each side: is a value missing, or is an operator doubled?")
                }
                ":" => "`:` follows a name, as in a named argument `f(x, by: 2 mm)` or a record `{ depth: 40 mm }`".to_string(),
                "%" => "`%` follows a number directly: `50 %`".to_string(),
                _ if at_eof => "the expression is not finished: write the value it still needs".to_string(),
                _ => "an expression is a value such as `10 mm`, a name, a call `f(x)`, a point `(x, y)`, a list `[a, b]` or `if c then a else b`".to_string(),
            },
            Want::Operator => "the expression is complete before this: join what follows with an operator (`+`, `*`, `|>`), or start it on a line of its own".to_string(),
            Want::ParenClose => format!(
                "close the parenthesis with `)` before {}; a point separates its coordinates with `,`: `(x, y)`",
                if at_eof { "the end".to_string() } else { format!("`{word}`") }
            ),
            Want::ArgsClose => "separate the arguments with `,` and close the call with `)`: `f(a, b, by: 2 mm)`".to_string(),
            Want::ParamsClose => "separate the parameters with `,` and close them with `)`: `fn f(a, b = 2 mm) = ...`".to_string(),
            Want::ListClose => "separate the elements with `,` and close the list with `]`: `[a, b, c]`".to_string(),
            Want::RecordClose => "separate the fields with `,` and close the record with `}`: `{ depth: 40 mm, angle: 8 deg }`".to_string(),
            Want::IndexClose => "close the index with `]`: `xs[0]`".to_string(),
            Want::BlockField if at_eof => "close the block with `}`".to_string(),
            Want::BlockField => "a block holds fields, `name = value` or `name { ... }`, one after another; close it with `}`".to_string(),
            Want::SketchCommand => "a sketch's commands are `from p`, `line to p`, `arc to p through q`, `tangent arc to p`, `spline through [points]`, `fillet r` and `close`; close the sketch with `}`".to_string(),
            Want::ArcOrSpline => "after `tangent` write `arc to p` or `spline through [points]`".to_string(),
            Want::AssignOrBlock if in_block => "a field is its name, then `= value` or a `{ ... }` block: `depth = 40 mm`".to_string(),
            Want::AssignOrBlock => "a declaration is `kind name = value` or `kind name { fields }`; a function is `fn name(x) = body`".to_string(),
            Want::FnAssign => "a function is `fn name(x, y) = body`".to_string(),
            Want::Arrow => "a function value is `fn(x) => body`".to_string(),
            Want::Colon => "a record field is `name: value`".to_string(),
            Want::Then | Want::Else => "a conditional is `if condition then a else b`, all three parts given".to_string(),
            Want::In => "a comprehension is `[body for x in list]`".to_string(),
            Want::As => "an import names its module: `import \"std/addendum\" as add`".to_string(),
            Want::To => "write `line to (x, y)`, `arc to (x, y) through (x, y)` or `tangent arc to (x, y)`".to_string(),
            Want::Through => "write `arc to p through q` or `spline through [points]`".to_string(),
            Want::UnitName => "the units are mm, cm, m, in (lengths) and deg, rad (angles): `units mm deg`".to_string(),
            Want::ImportPath => "write the path in double quotes: `import \"std/addendum\" as add`".to_string(),
            Want::DeclName => "a declaration is its kind, its name and its value: `let width = 550 mm`".to_string(),
            Want::FnName | Want::ParamName | Want::VarName | Want::Alias | Want::FieldName => {
                "a name starts with a letter or `_`, followed by letters, digits and `_`".to_string()
            }
            Want::Item => format!(
                "each top-level item is a declaration (`let width = 550 mm`), a `fn`, an `import` or `units`: is {} left over from the line before?",
                if word.is_empty() { "this".to_string() } else { format!("`{word}`") }
            ),
        }
    }

    /// Where "the file ends here" points: the character after the last token (so the
    /// label sits right behind it), or the last character when nothing follows.
    fn eof_span(text: &str, file: FileId) -> Span {
        let t = text.trim_end().len();
        match text[t..].chars().next() {
            Some(c) => Span::new(file, t, t + c.len_utf8()),
            None => match text.char_indices().last() {
                Some((i, _)) => Span::new(file, i, text.len()),
                None => Span::new(file, 0, 0),
            },
        }
    }

    fn short(wants: &[Want]) -> &'static str {
        wants.first().map_or("something else", |w| w.phrase())
    }

    fn describe(tok: &Tok, text: &str) -> String {
        match tok.kind {
            TokKind::Eof => "the end of the file".to_string(),
            TokKind::Space { newline: true } => "the end of the line".to_string(),
            TokKind::Space { newline: false } => "a space".to_string(),
            TokKind::Word if lex::is_keyword(&text[tok.start..tok.end]) => {
                format!("the keyword `{}`", &text[tok.start..tok.end])
            }
            _ => {
                let s = &text[tok.start..tok.end];
                if s.chars().count() > 30 {
                    format!("`{}...`", s.chars().take(27).collect::<String>())
                } else {
                    format!("`{s}`")
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// The lexical pass for error reporting

mod lex {
    use super::{Diagnostic, FileId, Limit, Limits, Span, CODE};

    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub(super) enum TokKind {
        Word,
        Number,
        /// `terminated`, and the byte offset of the first bad escape.
        Str {
            terminated: bool,
            bad_escape: Option<usize>,
        },
        LineComment,
        BlockComment {
            terminated: bool,
        },
        Space {
            newline: bool,
        },
        Punct,
        Unknown,
        Eof,
    }

    #[derive(Debug, Clone, Copy)]
    pub(super) struct Tok {
        pub kind: TokKind,
        pub start: usize,
        pub end: usize,
    }

    const KEYWORDS: &[&str] = &[
        "import", "as", "units", "fn", "if", "then", "else", "for", "in", "and", "or", "not",
        "true", "false", "sketch", "from", "line", "to", "arc", "through", "tangent", "spline",
        "fillet", "close",
    ];
    const UNITS: &[&str] = &["mm", "cm", "m", "in", "deg", "rad"];
    const PUNCT2: &[&str] = &["==", "!=", "<=", ">=", "|>", "=>"];
    const PUNCT1: &str = "()[]{}.,;:=<>+-*/%";

    pub(super) fn is_keyword(w: &str) -> bool {
        KEYWORDS.contains(&w)
    }

    /// Whether a byte is whitespace to the grammar (a form feed, say, is not).
    fn is_space(c: u8) -> bool {
        matches!(c, b' ' | b'\t' | b'\r' | b'\n')
    }

    /// Whether a byte ends a line: `\n`, or `\r` alone or before `\n`.
    fn is_line_end(c: u8) -> bool {
        c == b'\n' || c == b'\r'
    }

    fn is_ident_char(c: u8) -> bool {
        c.is_ascii_alphanumeric() || c == b'_'
    }

    /// Splits the whole text into tokens the way the grammar would, tolerating anything.
    pub(super) fn tokens(text: &str) -> Vec<Tok> {
        let b = text.as_bytes();
        let mut out = Vec::new();
        let mut i = 0;
        while i < b.len() {
            let start = i;
            let c = b[i];
            let kind = if c == b'/' && b.get(i + 1) == Some(&b'/') {
                while i < b.len() && !is_line_end(b[i]) {
                    i += 1;
                }
                TokKind::LineComment
            } else if c == b'/' && b.get(i + 1) == Some(&b'*') {
                i += 2;
                let mut terminated = false;
                while i < b.len() {
                    if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                        i += 2;
                        terminated = true;
                        break;
                    }
                    i += 1;
                }
                TokKind::BlockComment { terminated }
            } else if c == b'"' {
                i += 1;
                let mut terminated = false;
                let mut bad_escape = None;
                while i < b.len() && !is_line_end(b[i]) {
                    if b[i] == b'"' {
                        i += 1;
                        terminated = true;
                        break;
                    }
                    if b[i] == b'\\' {
                        if !matches!(b.get(i + 1), Some(b'"' | b'\\' | b'n' | b't'))
                            && bad_escape.is_none()
                        {
                            bad_escape = Some(i);
                        }
                        if matches!(b.get(i + 1), Some(b'\n' | b'\r') | None) {
                            i += 1;
                            continue;
                        }
                        i += 1;
                    }
                    i += 1;
                }
                TokKind::Str {
                    terminated,
                    bad_escape,
                }
            } else if is_space(c) || text[i..].starts_with('\u{FEFF}') {
                let mut newline = false;
                while i < b.len() && (is_space(b[i]) || text[i..].starts_with('\u{FEFF}')) {
                    newline |= is_line_end(b[i]);
                    i += if is_space(b[i]) { 1 } else { 3 };
                }
                TokKind::Space { newline }
            } else if c.is_ascii_digit() {
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
                if b.get(i) == Some(&b'.') && b.get(i + 1).is_some_and(u8::is_ascii_digit) {
                    i += 1;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
                if matches!(b.get(i), Some(b'e' | b'E')) {
                    let mut j = i + 1;
                    if matches!(b.get(j), Some(b'+' | b'-')) {
                        j += 1;
                    }
                    if b.get(j).is_some_and(u8::is_ascii_digit) {
                        i = j;
                        while i < b.len() && b[i].is_ascii_digit() {
                            i += 1;
                        }
                    }
                }
                TokKind::Number
            } else if c.is_ascii_alphabetic() || c == b'_' {
                while i < b.len() && is_ident_char(b[i]) {
                    i += 1;
                }
                TokKind::Word
            } else if PUNCT2.iter().any(|p| text[i..].starts_with(p)) {
                i += 2;
                TokKind::Punct
            } else if PUNCT1.as_bytes().contains(&c) {
                i += 1;
                TokKind::Punct
            } else {
                i += text[i..].chars().next().map_or(1, char::len_utf8);
                TokKind::Unknown
            };
            out.push(Tok {
                kind,
                start,
                end: i,
            });
        }
        out
    }

    /// The token at byte `pos` (an empty end-of-file token past the last one).
    /// A position inside whitespace (only atomic rules such as `units` fail there) is
    /// the one character at `pos`.
    pub(super) fn found_at(toks: &[Tok], text: &str, pos: usize) -> Tok {
        let eof = Tok {
            kind: TokKind::Eof,
            start: text.len().min(pos),
            end: text.len().min(pos),
        };
        let Some(t) = toks.iter().find(|t| t.start <= pos && pos < t.end) else {
            return eof;
        };
        match t.kind {
            TokKind::Space { .. } if text[pos..].trim().is_empty() => eof,
            TokKind::Space { .. } => {
                let c = text[pos..].chars().next().map_or(1, char::len_utf8);
                Tok {
                    kind: TokKind::Space {
                        newline: text[pos..].starts_with(['\n', '\r']),
                    },
                    start: pos,
                    end: pos + c,
                }
            }
            _ if t.start == pos => *t,
            _ => Tok {
                kind: t.kind,
                start: pos,
                end: t.end,
            },
        }
    }

    /// The first lexical problem that starts at or before `pos`, as a diagnostic.
    pub(super) fn problem_before(
        toks: &[Tok],
        text: &str,
        pos: usize,
        file: FileId,
    ) -> Option<Diagnostic> {
        let span = |s: usize, e: usize| Span::new(file, s, e);
        for (k, t) in toks.iter().enumerate() {
            if t.start > pos {
                break;
            }
            match t.kind {
                TokKind::Str {
                    terminated: false, ..
                } => {
                    return Some(
                        Diagnostic::new(
                            CODE,
                            "unterminated string",
                            span(t.start, t.end),
                            "this string is never closed",
                        )
                        .with_help("end the string with `\"` on the same line"),
                    );
                }
                TokKind::Str {
                    bad_escape: Some(at),
                    ..
                } => {
                    let len = text[at + 1..].chars().next().map_or(0, char::len_utf8);
                    let esc = &text[at..at + 1 + len];
                    return Some(
                        Diagnostic::new(
                            CODE,
                            format!("unknown escape `{esc}` in a string"),
                            span(at, at + 1 + len),
                            "unknown escape",
                        )
                        .with_help("the escapes are \\\" \\\\ \\n and \\t"),
                    );
                }
                TokKind::BlockComment { terminated: false } => {
                    return Some(
                        Diagnostic::new(
                            CODE,
                            "unterminated block comment",
                            span(t.start, t.start + 2),
                            "this comment is never closed",
                        )
                        .with_help("end the comment with `*/`"),
                    );
                }
                TokKind::Unknown => {
                    return Some(unknown_character(
                        &text[t.start..t.end],
                        span(t.start, t.end),
                    ));
                }
                TokKind::Number => {
                    if let Some(d) = bad_unit(toks, k, text, file) {
                        if d.primary.span.start as usize <= pos {
                            return Some(d);
                        }
                    }
                }
                _ => {}
            }
        }
        None
    }

    /// A character the language does not use. One that does not show (a zero-width
    /// or no-break space, a control or direction mark) is named by its code point, since
    /// quoting it would show nothing; a look-alike of an operator or quote says which.
    fn unknown_character(c: &str, span: Span) -> Diagnostic {
        let ch = c.chars().next().unwrap_or('\0');
        let code = format!("U+{:04X}", u32::from(ch));
        if let Some(name) = invisible_name(ch) {
            let help = if name.contains("SPACE") && !name.contains("ZERO") {
                "it looks like a space but is not one: replace it with an ordinary space"
            } else {
                "it does not show: delete it (retype the text around it if you cannot find it)"
            };
            return Diagnostic::new(
                CODE,
                format!("invisible character {code} {name}"),
                span,
                format!("{code} {name} is here"),
            )
            .with_help(help);
        }
        // A visible non-ASCII character is named by its code point too (a look-alike of an
        // ASCII one is told apart by it).
        let message = if ch.is_ascii() {
            format!("unknown character `{c}`")
        } else {
            format!("unknown character `{c}` ({code})")
        };
        let d = Diagnostic::new(CODE, message, span, "not part of the language");
        let help = match ch {
            '\'' | '\u{2018}' | '\u{2019}' => "strings are written in straight double quotes: \"...\"",
            '\u{201C}' | '\u{201D}' | '\u{201E}' => {
                "this is a typographic quote: write strings in straight double quotes, \"...\""
            }
            '#' => "comments start with `//`",
            '!' => "write `not x` for negation and `!=` for inequality",
            '&' => "write `and`",
            '|' => "write `or`, or `|>` to pipe a value into a function",
            '\u{2212}' | '\u{2013}' | '\u{2014}' | '\u{2010}' => {
                "this is a typographic dash: write the minus sign as `-`"
            }
            '\u{00D7}' | '\u{22C5}' | '\u{00B7}' => "write multiplication as `*`",
            '\u{00F7}' => "write division as `/`",
            '\u{00B0}' => "write angles with their unit: `8 deg`",
            '\u{2264}' => "write `<=`",
            '\u{2265}' => "write `>=`",
            '\u{2260}' => "write `!=`",
            _ => "the language is written in ASCII outside strings and comments: remove it, or put text in a string",
        };
        d.with_help(help)
    }

    /// The Unicode name of a character that does not show, or `None` for one that does.
    fn invisible_name(c: char) -> Option<&'static str> {
        Some(match c {
            '\0' => "NULL",
            '\u{7F}' => "DELETE",
            '\u{0B}' => "LINE TABULATION",
            '\u{0C}' => "FORM FEED",
            '\u{A0}' => "NO-BREAK SPACE",
            '\u{AD}' => "SOFT HYPHEN",
            '\u{85}' => "NEXT LINE",
            '\u{1680}' => "OGHAM SPACE MARK",
            '\u{2000}'..='\u{200A}' => "SPACE (a typographic width)",
            '\u{200B}' => "ZERO WIDTH SPACE",
            '\u{200C}' => "ZERO WIDTH NON-JOINER",
            '\u{200D}' => "ZERO WIDTH JOINER",
            '\u{200E}' => "LEFT-TO-RIGHT MARK",
            '\u{200F}' => "RIGHT-TO-LEFT MARK",
            '\u{2028}' => "LINE SEPARATOR",
            '\u{2029}' => "PARAGRAPH SEPARATOR",
            '\u{202A}' => "LEFT-TO-RIGHT EMBEDDING",
            '\u{202B}' => "RIGHT-TO-LEFT EMBEDDING",
            '\u{202C}' => "POP DIRECTIONAL FORMATTING",
            '\u{202D}' => "LEFT-TO-RIGHT OVERRIDE",
            '\u{202E}' => "RIGHT-TO-LEFT OVERRIDE",
            '\u{202F}' => "NARROW NO-BREAK SPACE",
            '\u{205F}' => "MEDIUM MATHEMATICAL SPACE",
            '\u{2060}' => "WORD JOINER",
            '\u{2061}'..='\u{2064}' => "INVISIBLE OPERATOR",
            '\u{2066}' => "LEFT-TO-RIGHT ISOLATE",
            '\u{2067}' => "RIGHT-TO-LEFT ISOLATE",
            '\u{2068}' => "FIRST STRONG ISOLATE",
            '\u{2069}' => "POP DIRECTIONAL ISOLATE",
            '\u{3000}' => "IDEOGRAPHIC SPACE",
            '\u{FEFF}' => "ZERO WIDTH NO-BREAK SPACE",
            '\u{FFFC}' => "OBJECT REPLACEMENT CHARACTER",
            c if c.is_control() => "CONTROL CHARACTER",
            _ => return None,
        })
    }

    /// `12 mmm`, `5x`: a word after a number that is not a unit. Glued to the number it
    /// is always a mistake; after spaces only when nothing but the line's end, a closing
    /// bracket, a separator or an operator follows (else it may begin the next field).
    fn bad_unit(toks: &[Tok], k: usize, text: &str, file: FileId) -> Option<Diagnostic> {
        let next = toks.get(k + 1)?;
        let (word, glued) = match next.kind {
            TokKind::Word => (*next, true),
            TokKind::Space { newline: false } => {
                let w = toks.get(k + 2)?;
                if w.kind != TokKind::Word {
                    return None;
                }
                (*w, false)
            }
            _ => return None,
        };
        let w = &text[word.start..word.end];
        if UNITS.contains(&w) || is_keyword(w) {
            return None;
        }
        if !glued {
            let mut j = toks.iter().position(|t| t.start == word.end);
            if let Some(i) = j {
                if matches!(toks[i].kind, TokKind::Space { newline: false }) {
                    j = Some(i + 1);
                }
            }
            let ends = match j.and_then(|i| toks.get(i)) {
                None => true,
                Some(t) => match t.kind {
                    TokKind::Space { newline: true }
                    | TokKind::LineComment
                    | TokKind::BlockComment { .. } => true,
                    TokKind::Punct => {
                        !matches!(&text[t.start..t.end], "=" | "{" | "(" | "[" | "." | ":")
                    }
                    _ => false,
                },
            };
            if !ends {
                return None;
            }
        }
        let mut d = Diagnostic::new(
            CODE,
            format!("`{w}` is not a unit"),
            Span::new(file, word.start, word.end),
            "unknown unit",
        )
        .with_label(
            Span::new(file, toks[k].start, toks[k].end),
            "after this number",
        );
        let mut help = "units are mm, cm, m, in, deg, rad and %".to_string();
        if let Some(s) = crate::diag::did_you_mean(w, UNITS.iter().copied()) {
            help = format!("did you mean `{s}`? {help}");
        }
        d = d.with_help(help);
        Some(d)
    }

    /// The first place nested more than `max` levels deep, as a diagnostic: checked
    /// before parsing because pest, the builder and every later pass recurse once per
    /// level. A level is a bracket, or a prefix `-`/`not`, `if` or `fn` inside the current
    /// element (those nest until the element ends at `,`, `;` or `=`).
    pub(super) fn too_deep(text: &str, file: FileId, limits: &Limits) -> Option<Diagnostic> {
        let max = limits.count(Limit::Nesting);
        let mut stack: Vec<usize> = vec![0]; // prefix-like levels per open bracket
        let mut prev_operand = false; // whether the previous token ends an operand
        for t in tokens(text) {
            let s = &text[t.start..t.end];
            let mut level_up = false;
            match t.kind {
                TokKind::Space { .. } | TokKind::LineComment | TokKind::BlockComment { .. } => {
                    continue
                }
                TokKind::Punct => match s {
                    "(" | "[" | "{" => stack.push(0),
                    ")" | "]" | "}" if stack.len() > 1 => {
                        stack.pop();
                    }
                    "," | ";" | "=" => *stack.last_mut().expect("never empty") = 0,
                    "-" => level_up = !prev_operand,
                    _ => {}
                },
                TokKind::Word => level_up = matches!(s, "not" | "if" | "fn"),
                _ => {}
            }
            if level_up {
                *stack.last_mut().expect("never empty") += 1;
            }
            prev_operand = match t.kind {
                TokKind::Word => !is_keyword(s) || matches!(s, "true" | "false"),
                TokKind::Number | TokKind::Str { .. } => true,
                TokKind::Punct => matches!(s, ")" | "]" | "}" | "%"),
                _ => false,
            };
            let depth = stack.len() - 1 + stack.iter().sum::<usize>();
            if depth > max {
                return Some(
                    Diagnostic::new(
                        CODE,
                        format!("nested more than {max} levels deep"),
                        Span::new(file, t.start, t.end),
                        "nested too deeply",
                    )
                    .with_help(format!(
                        "split the expression into named declarations; {}",
                        Limit::Nesting.help(limits)
                    )),
                );
            }
        }
        None
    }

    /// Brackets opened before `pos` and not yet closed, innermost last.
    pub(super) fn open_brackets(toks: &[Tok], text: &str, pos: usize) -> Vec<(char, usize)> {
        let mut stack = Vec::new();
        for t in toks.iter().take_while(|t| t.start < pos) {
            if t.kind != TokKind::Punct {
                continue;
            }
            match &text[t.start..t.end] {
                "(" => stack.push(('(', t.start)),
                "[" => stack.push(('[', t.start)),
                "{" => stack.push(('{', t.start)),
                c @ (")" | "]" | "}") => {
                    let open = match c {
                        ")" => '(',
                        "]" => '[',
                        _ => '{',
                    };
                    if let Some(i) = stack.iter().rposition(|(o, _)| *o == open) {
                        stack.truncate(i);
                    }
                }
                _ => {}
            }
        }
        stack
    }

    /// Whether a `}` later in the file closes the `{` at byte `at`.
    pub(super) fn closed_later(toks: &[Tok], text: &str, at: usize) -> bool {
        let mut depth = 0usize;
        for t in toks
            .iter()
            .filter(|t| t.start >= at && t.kind == TokKind::Punct)
        {
            match &text[t.start..t.end] {
                "{" => depth += 1,
                "}" => {
                    depth -= 1;
                    if depth == 0 {
                        return true;
                    }
                }
                _ => {}
            }
        }
        false
    }

    /// Whether a token could begin an operand (so a comma may be what is missing).
    pub(super) fn starts_operand(t: &Tok, text: &str) -> bool {
        match t.kind {
            TokKind::Word => {
                !is_keyword(&text[t.start..t.end])
                    || matches!(&text[t.start..t.end], "true" | "false")
            }
            TokKind::Number | TokKind::Str { .. } => true,
            TokKind::Punct => matches!(&text[t.start..t.end], "(" | "["),
            _ => false,
        }
    }

    /// Whether no newline separates `t` from the token before it.
    pub(super) fn same_line_as_previous(text: &str, t: &Tok) -> bool {
        !text[..t.start]
            .trim_end_matches([' ', '\t'])
            .ends_with(['\n', '\r'])
    }
}

/// The diagnostic for a number literal `text` that an f64 cannot hold as written: too
/// large (it would read as infinity), or non-zero but below the smallest normal number
/// (it would read as 0 or lose its precision). Both ends are refused alike, so a
/// written number is always the number used.
fn literal_range(value: f64, text: &str, span: Span) -> Option<Diagnostic> {
    let written_zero = text
        .split(['e', 'E'])
        .next()
        .is_some_and(|m| m.chars().all(|c| c == '0' || c == '.'));
    if !value.is_finite() {
        Some(
            Diagnostic::new(
                CODE,
                format!("the number `{text}` is too large"),
                span,
                "too large",
            )
            .with_help("numbers lie between about -1.8e308 and 1.8e308"),
        )
    } else if !written_zero && value.abs() < f64::MIN_POSITIVE {
        Some(
            Diagnostic::new(
                CODE,
                format!(
                    "the number `{text}` is below the smallest number (about 2.2e-308) and would be read as {}",
                    if value == 0.0 { "0" } else { "a number with fewer digits than written" }
                ),
                span,
                "too small",
            )
            .with_help("write 0 if zero is meant; otherwise use a larger unit or a larger value"),
        )
    } else {
        None
    }
}
