//! Tessellation: NURBS curves to polylines and NURBS surfaces to triangle meshes, both
//! within a chordal tolerance.
//!
//! Both tessellators follow the same pattern: a *first guess* from local differential
//! geometry (the step rule of paper 001, section 3.2, eq. 1, `L = 2 sqrt(2 rho delta - delta^2)`
//! for a chord `L` on a radius of curvature `rho` at tolerance `delta`, or its surface
//! analogue from second-derivative bounds), then a *verification* that measures the
//! actual deviation between the true geometry and the piecewise-linear approximation and
//! refines wherever the tolerance is not met. The guess makes the output near-minimal;
//! the check is what makes the tolerance hold where curvature varies.
//!
//! * [`tessellate_curve`] gives a [`Polyline`]: every C0 knot (multiplicity >= degree) is
//!   a vertex, so kinks stay exact corners.
//! * [`tessellate_surface`] gives a [`SurfaceMesh`]: a structured tensor grid whose
//!   parameter lines are shared across the whole surface, hence watertight by
//!   construction (no T-junctions), triangles wound like `S_u x S_v`.
//! * [`tessellate_trimmed`] gives a [`SurfaceMesh`] of a trimmed face, cut exactly at
//!   its outline (a constrained Delaunay triangulation in `(u, v)`).
//!
//! Everything is deterministic (no threads, no hashing) and never panics; invalid
//! tolerances and runaway refinement come back as [`GeomError`].

mod curve;
mod polygon;
mod surface;
mod trimmed;

pub use curve::{tessellate_curve, tessellate_curve_within, CURVE_POINT_LIMIT};
pub use polygon::{triangulate_loops, triangulate_loops_with};
pub use surface::{tessellate_surface, tessellate_surface_within, SURFACE_VERTEX_LIMIT};
pub use trimmed::{tessellate_trimmed, tessellate_trimmed_within};

use glam::{DVec2, DVec3};

use super::error::{GeomError, Result};
use super::mesh::{Face, Mesh};

/// Hard cap on the number of vertices one tessellation may produce (about 16.8 million,
/// about 1 GB of mesh data). Reaching it means the tolerance is far too fine for the
/// size of the geometry; the tessellators then fail with
/// [`GeomError::NoConvergence`] instead of exhausting memory.
pub const MAX_VERTICES: usize = 1 << 24;

/// Default limit on the turn of the normal (surfaces) or tangent (curves) between
/// neighbouring vertices: 15 degrees, enough for smooth shading and for the angle-based
/// checks downstream, without dominating the chordal criterion on die-face radii.
pub const DEFAULT_ANGLE: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// How fine a tessellation must be.
///
/// The fields are public so callers can build one literally; the tessellators validate
/// them on entry all the same (as [`Tolerance::validate`] does).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Chordal tolerance in millimetres: the largest allowed distance between the true
    /// geometry and the polyline or mesh, everywhere (triangle interiors included).
    /// Finite and positive.
    pub chordal: f64,
    /// Largest allowed turn, in radians, of the tangent (curves) or normal (surfaces)
    /// between neighbouring vertices. Finite and positive; values of pi or more switch
    /// the criterion off in practice.
    pub angle: f64,
    /// Optional limit on the 3-D length of every edge (the `L_max` of the step rule used
    /// where the curvature vanishes). `None` means unlimited.
    pub max_edge: Option<f64>,
}

impl Tolerance {
    /// A tolerance with the given chordal deviation, the [`DEFAULT_ANGLE`] and no edge
    /// length limit. Fails with [`GeomError::NotPositive`] (or [`GeomError::NotFinite`])
    /// unless `chordal` is finite and positive.
    pub fn new(chordal: f64) -> Result<Self> {
        let tol = Self {
            chordal,
            angle: DEFAULT_ANGLE,
            max_edge: None,
        };
        tol.validate()?;
        Ok(tol)
    }

    /// The same tolerance with another angle limit (radians, finite and positive).
    pub fn with_angle(self, angle: f64) -> Result<Self> {
        let tol = Self { angle, ..self };
        tol.validate()?;
        Ok(tol)
    }

    /// The same tolerance with an edge length limit (millimetres, finite and positive).
    pub fn with_max_edge(self, max_edge: f64) -> Result<Self> {
        let tol = Self {
            max_edge: Some(max_edge),
            ..self
        };
        tol.validate()?;
        Ok(tol)
    }

    /// Checks every field: each must be finite and strictly positive.
    pub fn validate(&self) -> Result<()> {
        positive("chordal tolerance", self.chordal)?;
        positive("angle tolerance", self.angle)?;
        if let Some(l) = self.max_edge {
            positive("maximum edge length", l)?;
        }
        Ok(())
    }

    /// The edge length limit, infinite when there is none.
    fn edge_limit(&self) -> f64 {
        self.max_edge.unwrap_or(f64::INFINITY)
    }
}

fn positive(what: &'static str, value: f64) -> Result<()> {
    if value.is_nan() || value == f64::INFINITY {
        return Err(GeomError::NotFinite { what });
    }
    if value <= 0.0 {
        return Err(GeomError::NotPositive { what, value });
    }
    Ok(())
}

/// A curve approximated by straight segments.
///
/// `points[i]` is exactly the curve point at `params[i]`; parameters increase strictly
/// from the start to the end of the domain. Each segment stays within the chordal
/// tolerance of the curve arc it replaces.
#[derive(Debug, Clone, PartialEq)]
pub struct Polyline<P> {
    /// Curve parameter of every vertex, strictly increasing, ends included.
    pub params: Vec<f64>,
    /// The vertices, `curve.point_at(params[i])`.
    pub points: Vec<P>,
}

impl<P> Polyline<P> {
    /// Number of straight segments (vertices minus one).
    pub fn segment_count(&self) -> usize {
        self.points.len().saturating_sub(1)
    }
}

/// A surface approximated by triangles.
///
/// Vertex `i` has parameters `uv[i]`, lies exactly on the surface at `positions[i]` and
/// carries the unit surface normal `normals[i]`. Triangles are counter-clockwise in the
/// parameter plane, so their geometric normals agree with `S_u x S_v`. The mesh is
/// watertight: every edge is shared by two triangles except those on the boundary of the
/// parameter domain. Where a whole edge of the domain collapses to a point (the apex of a
/// three-sided patch), its vertices are welded into one, which keeps the `uv` of the
/// first of them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Surface parameters of every vertex.
    pub uv: Vec<DVec2>,
    /// Vertex positions, `S(uv[i])`.
    pub positions: Vec<DVec3>,
    /// Unit normals, oriented like `S_u x S_v`; at degenerate points (collapsed edges)
    /// the area-weighted average of the adjacent triangles' normals.
    pub normals: Vec<DVec3>,
    /// Vertex indices of each triangle, counter-clockwise in `(u, v)`.
    pub triangles: Vec<[u32; 3]>,
}

impl SurfaceMesh {
    /// The tessellation as a kernel [`Mesh`] with its normals, for the mesh operations
    /// (topology, boundary loops, rounding) and the exporters.
    pub fn to_mesh(&self) -> Result<Mesh> {
        let faces = self
            .triangles
            .iter()
            .map(|&[a, b, c]| Face::triangle(a, b, c))
            .collect();
        Mesh::new(self.positions.clone(), faces)?.with_normals(self.normals.clone())
    }
}
