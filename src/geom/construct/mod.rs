//! Surfaces built from curves: the constructions die-face features are made of.
//!
//! - [`ruled`]: straight lines between two curves (blankholder sides and corners);
//! - [`loft`]: skinning through a sequence of sections, with optional cross-boundary
//!   tangents at the first and last section (step-draw patches, beads);
//! - [`coons`] and [`coons_triangle`]: bilinearly blended Coons patches from four (or
//!   three) boundary curves;
//! - [`revolve`]: exact surfaces of revolution;
//! - [`ferguson`]: the bicubic Hermite patch from corner points, tangents and twists.

mod coons;
mod ferguson;
mod loft;
mod revolve;
mod ruled;

pub use coons::{coons, coons_triangle};
pub use ferguson::{ferguson, HermiteCorners};
pub use loft::{loft, section_parameters, Loft};
pub use revolve::revolve;
pub use ruled::ruled;
