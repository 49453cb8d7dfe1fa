//! Rolling-ball rounding of sharp edges on a shell mesh (paper 000; issue 16, under
//! way): a die shoulder that is sharp in a tool mesh tears the sheet in forming
//! simulation, so the designer rounds the chain of sharp edges through a picked node
//! directly on the mesh. Each step of the paper's method is its own tested function;
//! so far:
//!
//! 1. [`chain`]: the chain of sharp edges through a picked node, followed both ways to
//!    the mesh's boundary or back to the start (section 2, step 1); [`base`]: the faces
//!    within 3R of it, split by it into the two base meshes;
//! 2. [`offset`]: each base mesh offset by R keeping its topology (Fig. 7b), its nodes
//!    marked where the surface curves tighter than R towards the ball;
//! 3. [`spine`]: the ball centre's path, where the two offsets cross, ordered along the
//!    chain, points closer than R to a base mesh dropped;
//! 4. [`contact`]: each spine point's contact on each base mesh (in a face, on an edge
//!    or at a corner), the ball re-centred to touch both at R exactly, and the profile
//!    arc between them (step 5, constant radius).
//!
//! The curvature each node has, to find the rounds a mesh already has (section 4), is
//! [`super::curvature`].

pub mod base;
pub mod chain;
pub mod contact;
pub mod offset;
pub mod spine;
