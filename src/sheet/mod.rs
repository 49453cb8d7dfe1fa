//! Sheet modeling (paper 003; `docs/methods.md`): thin parts declared as zero-thickness
//! sheets that store the topology of the solid they will become.
//!
//! A sheet's two sides are two faces of that solid (twins), each of its edges and
//! vertices has a twin on the other side, the solid's thickness faces are zero-area
//! loops and the edges between them zero-length edges (paper 003, section 2, Fig. 3).
//! The topology changes only through Euler operators ([`topology`]), so it stays valid
//! after every operation.
//!
//! What is here so far: the boundary representation with its Euler operators and its
//! validity check, the initial sheet, and the topology of the sheet operations (add a
//! sheet on picked edges, flange, split, punch, lift, remove), the placed model with
//! picking by points, moves and bends ([`geometry`]), the junction type at each vertex
//! where two sheets meet ([`junction`]), its solid at each sheet's thickness
//! ([`thicken`]), a part laid on a curved surface ([`base`], [`laid`]: its faces cut
//! to follow the surface and its solid worked out again there), and a plate part as the
//! language declares it ([`part`]).

pub mod base;
pub mod geometry;
pub mod junction;
pub mod laid;
pub mod part;
pub mod thicken;
pub mod topology;
