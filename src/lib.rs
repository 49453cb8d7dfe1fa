//! dieface: a declarative language and interpreter for modeling the faces of automotive
//! stamping dies.
//!
//! The pipeline runs one way: source text -> [`syntax`] -> [`eval`] -> [`geom`] (the
//! geometry kernel) -> `die` features -> `export` -> [`cli`]. [`diag`] and [`limits`] are shared by
//! all stages. See `ARCHITECTURE.md` for the map.

// `Diagnostic` is a rich value (labels, help) returned on the cold error path only;
// boxing it everywhere would cost more clarity than the larger `Result` costs speed.
#![allow(clippy::result_large_err)]

pub mod cli;
pub mod diag;
pub mod die;
pub mod eval;
pub mod export;
pub mod geom;
pub mod heap;
pub mod limits;
pub mod pipeline;
pub mod sheet;
pub mod syntax;
