//! dieface: a declarative language and interpreter for modeling the faces of automotive
//! stamping dies.
//!
//! The pipeline runs one way: source text -> `syntax` -> `eval` -> [`geom`] (the geometry
//! kernel) -> `die` features -> `export` -> `cli`. Only the kernel exists so far; see
//! `ARCHITECTURE.md` for the map.

pub mod geom;
