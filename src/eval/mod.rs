//! The second pipeline stage: evaluation of declarations into values.
//!
//! A file is a set of named declarations evaluated as a dependency graph, each once,
//! memoized by a hash of its source and its inputs' hashes ([`engine`]). Expressions are
//! evaluated by [`expr`], operators with dimension checks by [`ops`]; every number
//! is finite and geometry within range ([`finite`]); [`builtins`] binds
//! the geometry kernel; [`sketch`] draws 2-D profiles in views; modules come from the
//! embedded standard library ([`stdlib`]) or from files relative to the importer.

pub mod budget;
pub mod builtins;
pub mod deps;
pub mod engine;
pub mod expr;
pub mod features;
pub mod finite;
pub mod layout;
pub mod model;
pub mod ops;
pub mod overrides;
pub mod paths;
pub mod sketch;
pub mod stdlib;
pub mod summary;
pub mod units;
pub mod value;
pub mod views;

pub use engine::{DeclResult, Engine, Outcome};
pub use value::{Data, Value};
