//! The geometry kernel: NURBS curves and surfaces, meshes and tessellation.
//!
//! This stage of the pipeline knows nothing of the language. Everything is f64 and glam
//! (`DVec2`, `DVec3`, `DMat4`); nalgebra is used only for linear solves. Every operation
//! that can fail on user input returns [`GeomError`] instead of panicking.
//!
//! Conventions: millimetres and radians (the language converts units before calling),
//! clamped knot vectors, control points and weights stored separately (Euclidean points,
//! like OpenCascade), surfaces with control points indexed `[i][j]`, `i` along u.
//!
//! ```
//! use dieface::geom::construct::{loft, Loft};
//! use dieface::geom::interpolate::{interpolate, Interpolation};
//! use dieface::geom::tessellate::{tessellate_surface, Tolerance};
//! use glam::DVec3;
//!
//! // Three sections through points, skinned into a surface, tessellated to 0.01 mm.
//! let section = |y: f64, sag: f64| {
//!     let pts = [DVec3::new(0.0, y, 0.0), DVec3::new(50.0, y, -sag), DVec3::new(100.0, y, 0.0)];
//!     interpolate(&pts, &Interpolation { degree: 2, ..Interpolation::default() })
//! };
//! let sections = [section(0.0, 10.0)?, section(60.0, 14.0)?, section(120.0, 9.0)?];
//! let surface = loft(&sections, &Loft::default())?;
//! let mesh = tessellate_surface(&surface, &Tolerance::new(0.01)?)?;
//! assert!(mesh.triangles.len() > 100);
//! # Ok::<(), dieface::geom::GeomError>(())
//! ```

pub mod arc;
pub mod banded;
pub mod compat;
pub mod construct;
pub mod curvature;
pub mod curve;
pub mod error;
pub mod fingerprint;
pub(crate) mod grid;
pub mod imprint;
pub mod interpolate;
pub mod intersect;
pub mod inversion;
pub mod join;
pub mod knots;
pub mod mesh;
pub mod offset;
pub mod ops;
pub mod point;
pub mod quadrature;
pub mod sew;
pub mod sketch;
pub mod surface;
pub mod tessellate;
pub mod transform;
pub mod trimmed;
pub mod union_find;

pub use curve::{Curve2, Curve3, NurbsCurve};
pub use error::{GeomError, Result};
pub use knots::KnotVector;
pub use point::{Homogeneous, Linear, Point};
pub use surface::{Direction, NurbsSurface};
pub use transform::Transform;
pub use trimmed::{TrimLoop, TrimmedSurface};

/// Highest degree the kernel evaluates. OpenCascade allows 25; die-face geometry stays
/// below 10, and a small fixed bound keeps basis evaluation on the stack.
pub const MAX_DEGREE: usize = 15;

/// Largest coordinate (mm, in any axis) of die-face geometry a script may make: 1 km
/// from the origin. A press is a few metres wide and car coordinates stay within a few
/// metres, so this is generous; and it is where the GLB's 32-bit floats (metres) still
/// hold the default tolerance (their rounding at 1 km is 0.03 mm), and far below where
/// squared distances in the kernel overflow. `docs/limits.md` lists it.
pub const MAX_COORDINATE: f64 = 1e6;

/// Highest derivative order evaluated in one call (point, first, second, third).
pub const MAX_DERIVATIVE: usize = 3;
