//! The abstract syntax tree of a `.die` file.
//!
//! A file is a set of items: imports, a `units` directive, function declarations and
//! named declarations (`kind name = expr` or `kind name { fields }`). Every node has the
//! span of its source text. The tree is plain data: evaluation lives in `eval`.

use super::span::{Span, Spanned};

/// A name as written, with its span.
pub type Ident = Spanned<String>;

/// A parsed file.
#[derive(Debug, Clone, PartialEq)]
pub struct File {
    /// The items in source order (order carries no meaning for evaluation).
    pub items: Vec<Item>,
    /// The whole file.
    pub span: Span,
}

/// A top-level item.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// `import "std/profiles" as profiles`
    Import(Import),
    /// `units cm rad`: the file's default units for bare numbers.
    Units(UnitsDirective),
    /// `fn name(a, b = 2 mm) = expr`
    Function(FnDecl),
    /// `kind name = expr` or `kind name { ... }`
    Decl(Decl),
}

/// `import "path" as alias`.
#[derive(Debug, Clone, PartialEq)]
pub struct Import {
    /// The path string: `std/...` for the standard library, else relative to the file.
    pub path: Spanned<String>,
    /// The namespace the module's declarations are reached through.
    pub alias: Ident,
    /// The whole item.
    pub span: Span,
}

/// `units mm deg`: default length and/or angle unit for bare numbers in this file.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitsDirective {
    /// The units named, each a length or an angle unit.
    pub units: Vec<Spanned<Unit>>,
    /// The whole item.
    pub span: Span,
}

/// A user-defined pure function.
#[derive(Debug, Clone, PartialEq)]
pub struct FnDecl {
    /// Its name.
    pub name: Ident,
    /// Parameters, positional or named at the call, with optional defaults.
    pub params: Vec<Param>,
    /// The body expression.
    pub body: Expr,
    /// The whole item.
    pub span: Span,
}

/// A function or lambda parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// Its name.
    pub name: Ident,
    /// Default value, evaluated at the call when the argument is omitted.
    pub default: Option<Expr>,
}

/// A named top-level declaration.
#[derive(Debug, Clone, PartialEq)]
pub struct Decl {
    /// `let`, `param`, or a die-face noun such as `product` or `punch_opening`.
    pub kind: Ident,
    /// The declared name.
    pub name: Ident,
    /// `= expr` or `{ fields }`.
    pub body: DeclBody,
    /// The whole item.
    pub span: Span,
}

/// The right-hand side of a declaration.
#[derive(Debug, Clone, PartialEq)]
pub enum DeclBody {
    /// `= expr`
    Expr(Expr),
    /// `{ field = expr ... }`
    Block(Block),
}

/// `{ field = expr; sub { ... } }`: the body of a feature declaration.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// Fields in source order.
    pub fields: Vec<Field>,
    /// From `{` to `}`.
    pub span: Span,
}

/// One field of a block: `top = sketch(...)`, `side front = ...` (a qualified name of
/// several words), or a nested block `corners { tangent = 60 mm }`.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    /// One or more words naming the field.
    pub path: Vec<Ident>,
    /// `= expr` or a nested block.
    pub value: FieldValue,
    /// The whole field.
    pub span: Span,
}

/// A field's value.
#[derive(Debug, Clone, PartialEq)]
pub enum FieldValue {
    /// `= expr`
    Expr(Expr),
    /// `{ ... }`
    Block(Block),
}

/// An expression with its span.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Where it is.
    pub span: Span,
}

/// Expression forms.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// `12`, `12 mm`, `3.5deg`, `50 %`
    Number {
        value: f64,
        unit: Option<Spanned<Unit>>,
    },
    /// `"text"` (escapes resolved)
    Str(String),
    /// `true`, `false`
    Bool(bool),
    /// A name: a declaration, parameter, function, builtin or module alias.
    Name(String),
    /// `[a, b, c]`
    List(Vec<Expr>),
    /// `[body for var in iter if cond]`
    Comprehension {
        body: Box<Expr>,
        var: Ident,
        iter: Box<Expr>,
        cond: Option<Box<Expr>>,
    },
    /// `(a, b)` or `(a, b, c)`: points, vectors, pairs.
    Tuple(Vec<Expr>),
    /// `{ a: 1, b: 2 mm }`
    Record(Vec<(Ident, Expr)>),
    /// `target.name`
    Field { target: Box<Expr>, name: Ident },
    /// `target[index]`
    Index { target: Box<Expr>, index: Box<Expr> },
    /// `callee(args)`
    Call { callee: Box<Expr>, args: Vec<Arg> },
    /// `input |> call`: `call` is a call (its arguments follow the input) or a name.
    Pipe { input: Box<Expr>, call: Box<Expr> },
    /// `-x`, `not x`
    Unary {
        op: Spanned<UnaryOp>,
        operand: Box<Expr>,
    },
    /// `a + b`, `a and b`, `a <= b`, ...
    Binary {
        op: Spanned<BinaryOp>,
        lhs: Box<Expr>,
        rhs: Box<Expr>,
    },
    /// `if cond then a else b`
    If {
        cond: Box<Expr>,
        then: Box<Expr>,
        otherwise: Box<Expr>,
    },
    /// `fn(x, y = 1) => expr`
    Lambda { params: Vec<Param>, body: Box<Expr> },
    /// `sketch(view) { from p; line to q; ... }`
    Sketch {
        view: Box<Expr>,
        commands: Vec<SketchCommand>,
    },
}

/// A call argument, positional or `name: value`.
#[derive(Debug, Clone, PartialEq)]
pub struct Arg {
    /// The parameter name for a named argument.
    pub name: Option<Ident>,
    /// The value.
    pub value: Expr,
}

/// Units a number literal (or a `units` directive) can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Unit {
    /// millimetre
    Mm,
    /// centimetre
    Cm,
    /// metre
    M,
    /// inch
    In,
    /// degree
    Deg,
    /// radian
    Rad,
    /// percent (a dimensionless fraction: `50 %` is 0.5)
    Percent,
}

impl Unit {
    /// How the unit is written.
    pub fn symbol(self) -> &'static str {
        match self {
            Unit::Mm => "mm",
            Unit::Cm => "cm",
            Unit::M => "m",
            Unit::In => "in",
            Unit::Deg => "deg",
            Unit::Rad => "rad",
            Unit::Percent => "%",
        }
    }
}

/// Prefix operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    /// `-`
    Neg,
    /// `not`
    Not,
}

/// Infix operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `and`
    And,
    /// `or`
    Or,
}

impl BinaryOp {
    /// How the operator is written.
    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Add => "+",
            BinaryOp::Sub => "-",
            BinaryOp::Mul => "*",
            BinaryOp::Div => "/",
            BinaryOp::Eq => "==",
            BinaryOp::Ne => "!=",
            BinaryOp::Lt => "<",
            BinaryOp::Le => "<=",
            BinaryOp::Gt => ">",
            BinaryOp::Ge => ">=",
            BinaryOp::And => "and",
            BinaryOp::Or => "or",
        }
    }
}

/// One drawing command of a sketch.
#[derive(Debug, Clone, PartialEq)]
pub struct SketchCommand {
    /// What it draws.
    pub kind: SketchCommandKind,
    /// The whole command.
    pub span: Span,
}

/// Sketch commands, as a designer draws: a start point, then segments; `fillet r`
/// rounds the corner between the previous segment and the next one; `tangent` makes a
/// segment start in the direction the previous one ended.
#[derive(Debug, Clone, PartialEq)]
pub enum SketchCommandKind {
    /// `from (x, y)`
    From(Expr),
    /// `line to (x, y)`
    LineTo(Expr),
    /// `arc to (x, y) through (x, y)`
    ArcThrough { to: Expr, through: Expr },
    /// `tangent arc to (x, y)`: the arc leaving tangent to the previous segment.
    TangentArcTo(Expr),
    /// `spline through [p, q, ...]` or `tangent spline through [...]`
    Spline { through: Expr, tangent: bool },
    /// `fillet 5 mm`
    Fillet(Expr),
    /// `close`: a line back to the start (or nothing if already there).
    Close,
}
