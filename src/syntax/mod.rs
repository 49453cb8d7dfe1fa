//! The first pipeline stage: source text to an AST with spans.
//!
//! The grammar is `grammar/die.pest`; [`parse`] turns pest's pairs into [`ast::File`],
//! and syntax errors into diagnostics that name what was expected in words.

pub mod ast;
pub mod incremental;
pub mod parse;
pub mod print;
pub mod span;

pub use parse::{parse, SyntaxError};
pub use span::{FileId, Span, Spanned};
