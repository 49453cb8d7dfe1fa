//! Typed failures of the geometry kernel.
//!
//! The kernel never panics on user input: every degenerate or invalid input comes back
//! as a [`GeomError`]. The language layer turns these into diagnostics, adding which
//! declaration and which argument fed the failing operation, so each variant carries
//! the index or value that lets it point at the culprit.

use thiserror::Error;

/// Everything that can go wrong inside the geometry kernel.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GeomError {
    /// A knot vector that is not non-decreasing, has the wrong length for its degree
    /// and control points, is not clamped, or has a knot repeated too often.
    #[error("invalid knot vector: {reason}")]
    KnotVector { reason: String },

    /// A degree of zero, or above [`crate::geom::MAX_DEGREE`].
    #[error("degree {degree} is not supported (allowed: 1 to {max})")]
    Degree { degree: usize, max: usize },

    /// Fewer input points (or control points) than the operation needs.
    #[error("too few points: {needed} needed, {given} given")]
    TooFewPoints { needed: usize, given: usize },

    /// Two consecutive input points coincide, so no parameter step can separate them.
    #[error("points {first} and {second} (counting from 0) coincide")]
    CoincidentPoints { first: usize, second: usize },

    /// A tangent or direction of zero length where a direction is required.
    #[error("the {what} has zero length")]
    ZeroVector { what: &'static str },

    /// A weight that is not finite and strictly positive.
    #[error("weight {index} is {value}; weights must be finite and positive")]
    Weight { index: usize, value: f64 },

    /// A coordinate, parameter or scalar that is NaN or infinite.
    #[error("the {what} is not a finite number")]
    NotFinite { what: &'static str },

    /// Arrays that must agree in length do not.
    #[error("{what}: expected {expected} items, got {given}")]
    LengthMismatch {
        what: &'static str,
        expected: usize,
        given: usize,
    },

    /// A parameter outside the curve's or surface's domain.
    #[error("parameter {value} lies outside the domain [{min}, {max}]")]
    ParameterOutOfRange { value: f64, min: f64, max: f64 },

    /// A value that must be positive (a tolerance, a radius, a length) is not.
    #[error("the {what} must be positive, got {value}")]
    NotPositive { what: &'static str, value: f64 },

    /// Boundary curves that should meet at a corner leave a gap there.
    #[error("boundary curves do not meet at corner {corner}: they are {gap} mm apart")]
    CornersDoNotMeet { corner: usize, gap: f64 },

    /// An iterative solver (Newton, bisection) did not reach its tolerance.
    #[error("{what} did not converge after {iterations} iterations (residual {residual})")]
    NoConvergence {
        what: &'static str,
        iterations: usize,
        residual: f64,
    },

    /// A ray, plane or curve that has no intersection with the target.
    #[error("no intersection: {what}")]
    NoIntersection { what: &'static str },

    /// Input that admits no unique result: a singular interpolation system, three
    /// collinear points asked for a circle, non-positive weights out of a loft.
    #[error("degenerate input: {what}")]
    Singular { what: &'static str },

    /// A closed outline that crosses or touches itself (a figure of eight), so it
    /// bounds no single region: `at` is where, in press mm.
    #[error("the outline crosses itself near ({:.4}, {:.4}, {:.4})", at.0, at.1, at.2)]
    SelfCrossing { at: (f64, f64, f64) },

    /// A matrix given as an affine transform has a projective last row or is singular.
    #[error("the matrix is not an invertible affine transform")]
    NotAffine,

    /// An operation that is defined only for polynomial (non-rational) geometry.
    #[error("{what} needs non-rational (polynomial) input")]
    RationalNotSupported { what: &'static str },

    /// A mesh face or index that does not describe valid geometry.
    #[error("invalid mesh: {reason}")]
    InvalidMesh { reason: String },

    /// The intersection is not a set of isolated points: the whole curve lies in the
    /// plane (or on the coordinate value) within tolerance.
    #[error("{what}: the curve lies entirely in the intersecting plane")]
    Overlap { what: &'static str },

    /// The side view of a punch-opening side does not cover the x range of its top
    /// view, so part of the 3-D side curve would have no height: both ranges are given
    /// (x from, x to) so the short end can be found.
    #[error("the side view covers x in [{}, {}] but the top view spans [{}, {}]: the side view must cover the whole top view", side.0, side.1, top.0, top.1)]
    ViewsDoNotOverlap { top: (f64, f64), side: (f64, f64) },

    /// A curve whose direction jumps at one point (a knot, or the seam of a closed
    /// curve) by more than an operation allows: `turn` in radians, `at` the point and
    /// `parameter` where it lies. The offset of a corner is not one smooth curve.
    #[error("the curve has a sharp corner at ({:.4}, {:.4}): its direction turns by {:.4} deg there", at.0, at.1, turn.to_degrees())]
    SharpCorner {
        at: (f64, f64),
        turn: f64,
        parameter: f64,
    },

    /// An offset distance at or beyond the radius of curvature on the inside of a
    /// turn: the offset would fold back on itself there. `radius` is the smallest
    /// radius on that side, at `at` (`parameter`).
    #[error("an offset of {distance} mm folds where the curve turns with radius {radius:.4} mm at ({:.4}, {:.4})", at.0, at.1)]
    OffsetFolds {
        distance: f64,
        radius: f64,
        at: (f64, f64),
        parameter: f64,
    },

    /// An offset that comes closer to another part of the curve than the distance
    /// asked (the curve is narrower than twice the distance there): `gap` is how close
    /// the offset point `at` comes.
    #[error("the offset comes within {gap:.4} mm of another part of the curve near ({:.4}, {:.4})", at.0, at.1)]
    OffsetOverlaps { at: (f64, f64), gap: f64 },

    /// An offset that would need more sample points than allowed to stay within its
    /// tolerance.
    #[error("the offset needs {needed} points or more to stay within tolerance (at most {limit})")]
    TooManyPoints { needed: usize, limit: usize },

    /// Two points that project to the same place on a curve, so the stretch between
    /// them is empty.
    #[error("both points project to the same place on the curve, ({:.4}, {:.4})", at.0, at.1)]
    SameProjection { at: (f64, f64), parameter: f64 },

    /// On an open curve, the end of a stretch lies before its start along the curve's
    /// direction (parameters given).
    #[error("the end of the stretch (parameter {to}) comes before its start (parameter {from}) along the open curve")]
    StretchBackwards { from: f64, to: f64 },

    /// A boundary loop that must be closed has its ends `gap` mm apart.
    #[error("the loop is open: its ends are {gap} mm apart")]
    OpenLoop { gap: f64 },

    /// A curve that must lie on a surface is `distance` mm from it at the point `at`.
    #[error("the curve lies {distance} mm off the surface at ({}, {}, {})", at.0, at.1, at.2)]
    OffSurface { distance: f64, at: (f64, f64, f64) },
}

/// The kernel's result type.
pub type Result<T> = std::result::Result<T, GeomError>;
