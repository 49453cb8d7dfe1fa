//! Die-face features, built on the geometry kernel ([`crate::geom`]).
//!
//! Each feature turns the designer's few inputs (profiles drawn in views, radii,
//! heights) into the curves and surfaces of the die face, following the method of
//! paper 001 (Park, Lee and Jun; its steps in our words in `docs/methods.md`):
//!
//! - [`punch_opening`]: the punch opening line, one closed 3-D curve: each side built
//!   from its top and side views ([`two_view`]), neighbouring sides joined by corners
//!   corrected onto the top-view corner ([`corner`]);
//! - [`blankholder`]: the binder around the opening, ruled side and corner patches, C1
//!   where they meet;
//! - [`step_draw`]: the addendum from the product outline to the opening line through
//!   the designer's key sections, C1 across its patches;
//! - [`bead`]: draw beads draped on the binder, and line beads for forming simulation;
//! - [`continuity`]: the C1 test on two patches' control nets (eq. 4) and the measured
//!   gap and normal jump along their boundary;
//! - [`figures`]: the die engineer's figures (smallest radius, draft, sag, seams) the
//!   features report in their `quality`.
//!
//! A feature takes plain kernel inputs (curves, surfaces, numbers) and returns its
//! pieces, its quality figures, and errors that carry the index of the piece at fault,
//! so the language layer can point at the field or sketch segment.

pub mod bead;
pub mod blankholder;
pub mod continuity;
pub mod corner;
pub mod figures;
pub mod memo;
pub mod model;
pub mod punch_opening;
pub mod step_draw;
pub mod two_view;
