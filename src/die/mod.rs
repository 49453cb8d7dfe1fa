//! Die-face features, built on the geometry kernel ([`crate::geom`]).
//!
//! Each feature turns the designer's few inputs (profiles drawn in views, radii,
//! heights) into the curves and surfaces of the die face, following the method of the
//! die-face primer (`../shared/docs/die-face-primer.md`). The module is young: its first
//! piece is [`two_view`], the 3-D side curve built from its top and side views, which is
//! the first step of the punch opening line (`punch_opening`, to come: sides joined by
//! corrected corners).

pub mod bead;
pub mod blankholder;
pub mod continuity;
pub mod corner;
pub mod figures;
pub mod model;
pub mod punch_opening;
pub mod step_draw;
pub mod two_view;
