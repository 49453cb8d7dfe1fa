//! A surface, or a trimmed part of it, meshed with quads (paper 004, sections 2-4;
//! issue 18).
//!
//! The steps:
//!
//! 1. [`ProjectionPlane::of`]: the plane of the largest triangle of three of the
//!    surface's four corners; the corners seen on it span a bilinear quad `T(s, t)`
//!    (eq. 2).
//! 2. [`parameters_of`]: each trim point (3-D) to the surface's `(u, v)`: the bilinear
//!    inverse of its projection as the start, clamped to the domain, then Newton,
//!    `dU = (A^T A)^-1 A^T dP` with `A = [S_u S_v]` (eq. 5-6), until the step is below
//!    `1e-4` of the domain (eq. 7; we go on to full precision, since neighbouring
//!    patches must meet at the same seam nodes).
//! 3. The region drawn in a plane and meshed there by [`quad_mesh_region`]: in the
//!    projection plane, as the paper does, where the surface is seen from it without
//!    turning away (every normal within [`STEEPEST`] of the plane's); otherwise in the
//!    surface's parameters, stretched to the lengths of its iso-curves (a revolved part
//!    seen round its axis). The element size in the plane is graded so that on the
//!    surface an element's chord sags at most the chordal tolerance and is at most the
//!    size long however slanted the surface is seen ([`sizing`](super::sizing)).
//! 4. Each node back to `(u, v)` (in the projection plane by Newton on the node's
//!    projection) and onto the surface; every element is checked against the surface
//!    normal, so a folded mesh is refused rather than returned.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::sizing::{chord_for_sag, SizeGrid};
use super::{quad_mesh_region, PlaneMesh, QuadError, QuadOptions, Region};
use crate::geom::curvature::principal_of;
use crate::geom::mesh::box_grid::BoxGrid;
use crate::geom::mesh::{Face, Mesh};
use crate::geom::NurbsSurface;

/// The steepest a surface may turn from its projection plane (rad) and still be meshed
/// there: beyond it elements seen in the plane would stand on edge on the surface.
pub const STEEPEST: f64 = 1.3089969389957472; // 75 deg

/// Newton's steps at most, per point.
const NEWTON_STEPS: usize = 60;

/// The paper's convergence (eq. 7): the step relative to the domain.
const RELATIVE_STEP: f64 = 1e-4;

/// Samples per direction for the plane choice and the size grid.
const SAMPLES: usize = 48;

/// Where a region on a surface is meshed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MeshPlane {
    /// The projection plane of the surface's corners (the paper's way).
    Projection,
    /// The plane square to a view direction (the press direction for a die face, the
    /// axis of a revolved part), the surface seen along it.
    View(DVec3),
    /// The surface's parameters, stretched to its iso-curves' lengths.
    Parameters,
}

/// The plane of the largest triangle of three of a surface's corners, with the
/// bilinear quad the corners span on it (eq. 2).
#[derive(Debug, Clone, PartialEq)]
pub struct ProjectionPlane {
    origin: DVec3,
    e1: DVec3,
    e2: DVec3,
    /// The plane's unit normal (right-handed with `e1`, `e2`).
    pub normal: DVec3,
    /// The corners seen on the plane, at `(s, t)` = (0, 0), (1, 0), (1, 1), (0, 1).
    corners: [DVec2; 4],
    domain_u: (f64, f64),
    domain_v: (f64, f64),
}

impl ProjectionPlane {
    /// The projection plane of `surface`, or `None` when every three of its corners lie
    /// on a line (a surface collapsed to a curve at its corners).
    pub fn of(surface: &NurbsSurface) -> Option<ProjectionPlane> {
        let (u0, u1) = surface.domain_u();
        let (v0, v1) = surface.domain_v();
        let c = [
            surface.point_at(u0, v0),
            surface.point_at(u1, v0),
            surface.point_at(u1, v1),
            surface.point_at(u0, v1),
        ];
        // The four triangles of three corners; the one leaving out corner k.
        let (mut best, mut normal) = (0.0, DVec3::ZERO);
        for k in 0..4 {
            let [a, b, d] = [(k + 1) % 4, (k + 2) % 4, (k + 3) % 4].map(|i| c[i]);
            let n = (b - a).cross(d - a);
            if n.length() > best {
                best = n.length();
                normal = n;
            }
        }
        let scale = c.iter().map(|p| p.distance(c[0])).fold(0.0, f64::max);
        if best.is_nan() || best <= 1e-12 * scale * scale {
            return None;
        }
        let normal = normal.normalize();
        let along = c[1] - c[0] + (c[2] - c[3]);
        let along = along - normal * along.dot(normal);
        let e1 = if along.length() > 1e-12 * scale {
            along.normalize()
        } else {
            normal.any_orthonormal_vector()
        };
        let e2 = normal.cross(e1);
        let origin = c[0];
        let seen = |p: DVec3| DVec2::new((p - origin).dot(e1), (p - origin).dot(e2));
        Some(ProjectionPlane {
            origin,
            e1,
            e2,
            normal,
            corners: c.map(seen),
            domain_u: (u0, u1),
            domain_v: (v0, v1),
        })
    }

    /// The plane square to `direction` through the origin, with the surface's corners
    /// seen on it for the bilinear start (which may be poor where the corners overlap
    /// seen along `direction`; starts then come from the nearest sample). `None` for a
    /// direction of no length.
    pub fn square_to(surface: &NurbsSurface, direction: DVec3) -> Option<ProjectionPlane> {
        let normal = direction.try_normalize()?;
        let e1 = normal.any_orthonormal_vector();
        let e2 = normal.cross(e1);
        let (u0, u1) = surface.domain_u();
        let (v0, v1) = surface.domain_v();
        let seen = |p: DVec3| DVec2::new(p.dot(e1), p.dot(e2));
        Some(ProjectionPlane {
            origin: DVec3::ZERO,
            e1,
            e2,
            normal,
            corners: [
                surface.point_at(u0, v0),
                surface.point_at(u1, v0),
                surface.point_at(u1, v1),
                surface.point_at(u0, v1),
            ]
            .map(seen),
            domain_u: (u0, u1),
            domain_v: (v0, v1),
        })
    }

    /// `p` seen on the plane (its coordinates along the plane's axes).
    pub fn project(&self, p: DVec3) -> DVec2 {
        DVec2::new(
            (p - self.origin).dot(self.e1),
            (p - self.origin).dot(self.e2),
        )
    }

    /// A vector's components along the plane's axes.
    fn along(&self, d: DVec3) -> DVec2 {
        DVec2::new(d.dot(self.e1), d.dot(self.e2))
    }

    /// The bilinear quad at `(s, t)` in `[0, 1]^2` (eq. 2).
    pub fn bilinear(&self, s: f64, t: f64) -> DVec2 {
        let [a, b, c, d] = self.corners;
        (1.0 - t) * ((1.0 - s) * a + s * b) + t * ((1.0 - s) * d + s * c)
    }

    /// The `(s, t)` in `[0, 1]^2` whose bilinear point is `q`, or nearest it: Newton on
    /// the bilinear map from the centre, each step clamped to the square.
    pub fn bilinear_inverse(&self, q: DVec2) -> DVec2 {
        let [a, b, c, d] = self.corners;
        let mut st = DVec2::splat(0.5);
        for _ in 0..20 {
            let (s, t) = (st.x, st.y);
            let r = self.bilinear(s, t) - q;
            let ds = (1.0 - t) * (b - a) + t * (c - d);
            let dt = (1.0 - s) * (d - a) + s * (c - b);
            let det = ds.perp_dot(dt);
            if det.abs() <= f64::MIN_POSITIVE {
                break;
            }
            let step = DVec2::new(r.perp_dot(dt), ds.perp_dot(r)) / det;
            let next = (st - step).clamp(DVec2::ZERO, DVec2::ONE);
            let moved = next.distance(st);
            st = next;
            if moved < 1e-12 {
                break;
            }
        }
        st
    }

    /// The starting parameters of a point seen at `q`: its bilinear inverse, scaled to
    /// the surface's domain.
    pub fn start(&self, q: DVec2) -> DVec2 {
        let st = self.bilinear_inverse(q);
        DVec2::new(
            self.domain_u.0 + st.x * (self.domain_u.1 - self.domain_u.0),
            self.domain_v.0 + st.y * (self.domain_v.1 - self.domain_v.0),
        )
    }
}

/// A point's place on the surface (eq. 2-7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foot {
    /// Its parameters.
    pub uv: DVec2,
    /// Its distance from the surface point there (mm).
    pub distance: f64,
}

/// The domain's lower corner and span.
fn domain(surface: &NurbsSurface) -> (DVec2, DVec2) {
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    (DVec2::new(u0, v0), DVec2::new(u1 - u0, v1 - v0))
}

/// The parameters of the surface point nearest `p` (paper 004, eq. 2-7): the bilinear
/// inverse of `p` seen on the projection plane as the start, then Newton's least-squares
/// steps `dU = (A^T A)^-1 A^T dP`, clamped to the domain. `None` if the steps do not
/// come below the paper's `1e-4` of the domain (eq. 7) within [`NEWTON_STEPS`].
pub fn parameters_of(surface: &NurbsSurface, plane: &ProjectionPlane, p: DVec3) -> Option<Foot> {
    newton_foot(surface, plane.start(plane.project(p)), p)
}

/// Newton's least-squares steps towards the surface point nearest `p` from `start`.
fn newton_foot(surface: &NurbsSurface, start: DVec2, p: DVec3) -> Option<Foot> {
    let (lo, span) = domain(surface);
    let hi = lo + span;
    let mut uv = start.clamp(lo, hi);
    let mut converged = false;
    for _ in 0..NEWTON_STEPS {
        let d = surface.derivatives::<2>(uv.x, uv.y);
        let (su, sv) = (d[1][0], d[0][1]);
        let dp = p - d[0][0];
        // The normal equations of A dU = dP, A = [S_u S_v] (eq. 5-6).
        let (a, b, c) = (su.dot(su), su.dot(sv), sv.dot(sv));
        let det = a * c - b * b;
        if det.is_nan() || det <= 1e-300 {
            break;
        }
        let (ru, rv) = (su.dot(dp), sv.dot(dp));
        let step = DVec2::new(c * ru - b * rv, a * rv - b * ru) / det;
        let next = (uv + step).clamp(lo, hi);
        let moved = (next - uv) / span;
        uv = next;
        if moved.abs().max_element() < RELATIVE_STEP {
            converged = true;
        }
        if moved.abs().max_element() < 1e-13 {
            break;
        }
    }
    converged.then(|| Foot {
        uv,
        distance: surface.point_at(uv.x, uv.y).distance(p),
    })
}

/// A region of a surface: inside its outer trim loop (the surface's own edges when
/// none is given) and outside its holes, each loop as 3-D points on the surface.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SurfaceRegion {
    /// The outer trim loop, or `None` for the whole surface.
    pub outer: Option<Vec<DVec3>>,
    /// The holes.
    pub holes: Vec<Vec<DVec3>>,
}

/// How a surface is meshed.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceMeshOptions {
    /// The element size, the boundary's corners and tolerance, smoothing and the
    /// element limit; `chord_tolerance` is the largest sag of an element's chord off
    /// the surface (mm), the size is made finer where the surface curves more.
    pub quad: QuadOptions,
    /// Where to mesh, or `None` to choose: the projection plane unless the surface
    /// turns more than [`STEEPEST`] from it.
    pub plane: Option<MeshPlane>,
    /// How far a trim point may lie off the surface (mm).
    pub on_surface: f64,
}

impl SurfaceMeshOptions {
    /// Elements about `size` long ([`QuadOptions::at_size`]), the plane chosen, trim
    /// points within 0.1 mm of the surface.
    pub fn at_size(size: f64) -> SurfaceMeshOptions {
        SurfaceMeshOptions {
            quad: QuadOptions::at_size(size),
            plane: None,
            on_surface: 0.1,
        }
    }
}

/// A surface region meshed.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceMesh {
    /// The elements on the surface (quads and the triangles left), their normals
    /// along the surface's `S_u x S_v`.
    pub mesh: Mesh,
    /// Each node's parameters.
    pub uv: Vec<DVec2>,
    /// How many nodes lie on the region's boundary (the first ones).
    pub boundary_nodes: usize,
    /// Where it was meshed.
    pub plane: MeshPlane,
    /// The least element size the curvature asked for (mm; the size where none did).
    pub least_size: f64,
}

/// Why a surface region could not be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SurfaceMeshError {
    /// The surface's corners lie on one line: no projection plane.
    #[error("the surface's corners lie on one line, so it has no projection plane")]
    NoPlane,
    /// Newton did not converge for a trim point.
    #[error("point {point} of loop {loop_index} could not be placed on the surface (Newton did not converge) near ({:.3}, {:.3}, {:.3})", at.x, at.y, at.z)]
    NoConvergence {
        loop_index: usize,
        point: usize,
        at: DVec3,
    },
    /// A trim point lies off the surface.
    #[error("point {point} of loop {loop_index} lies {distance:.3} mm off the surface at ({:.3}, {:.3}, {:.3})", at.x, at.y, at.z)]
    OffSurface {
        loop_index: usize,
        point: usize,
        distance: f64,
        at: DVec3,
    },
    /// A node of the plane mesh has no surface point seen there (the surface folds
    /// over itself seen from the projection plane), or an element came out folded.
    #[error("the surface is too distorted for its projection plane near ({:.3}, {:.3}, {:.3}): Newton found no surface point under a node", at.x, at.y, at.z)]
    Distorted { at: DVec3 },
    /// The region in the plane could not be meshed (loop 0 is the outer one).
    #[error("{0}")]
    Region(QuadError),
}

/// The surface's trim loops in parameters (loop 0 the outer one).
fn trim_parameters(
    surface: &NurbsSurface,
    plane: &ProjectionPlane,
    starts: &[(DVec3, DVec2)],
    region: &SurfaceRegion,
    on_surface: f64,
) -> Result<Vec<Vec<DVec2>>, SurfaceMeshError> {
    let mut loops = Vec::with_capacity(region.holes.len() + 1);
    loops.push(match &region.outer {
        Some(outer) => map_loop(surface, plane, starts, outer, 0, on_surface)?,
        None => domain_edges(surface),
    });
    for (h, hole) in region.holes.iter().enumerate() {
        loops.push(map_loop(surface, plane, starts, hole, h + 1, on_surface)?);
    }
    Ok(loops)
}

/// One trim loop's points to parameters by eq. 2-7; where that start leads off the
/// surface (a surface seen folded from its plane), again from the previous point's foot
/// and from the nearest of the coarse `starts`, keeping the nearest foot.
fn map_loop(
    surface: &NurbsSurface,
    plane: &ProjectionPlane,
    starts: &[(DVec3, DVec2)],
    points: &[DVec3],
    loop_index: usize,
    on_surface: f64,
) -> Result<Vec<DVec2>, SurfaceMeshError> {
    let mut uvs: Vec<DVec2> = Vec::with_capacity(points.len());
    for (k, &p) in points.iter().enumerate() {
        let mut foot = parameters_of(surface, plane, p);
        if foot.is_none_or(|f| f.distance > on_surface) {
            let nearest = starts
                .iter()
                .min_by(|x, y| x.0.distance_squared(p).total_cmp(&y.0.distance_squared(p)))
                .map(|s| s.1);
            for start in uvs.last().copied().into_iter().chain(nearest) {
                let again = newton_foot(surface, start, p);
                if again.is_some_and(|a| foot.is_none_or(|f| a.distance < f.distance)) {
                    foot = again;
                }
            }
        }
        let Some(foot) = foot else {
            return Err(SurfaceMeshError::NoConvergence {
                loop_index,
                point: k,
                at: p,
            });
        };
        if foot.distance.is_nan() || foot.distance > on_surface {
            return Err(SurfaceMeshError::OffSurface {
                loop_index,
                point: k,
                distance: foot.distance,
                at: p,
            });
        }
        uvs.push(foot.uv);
    }
    Ok(uvs)
}

/// The domain's four edges, counter-clockwise, sampled finely enough to follow the
/// surface's edges seen in either plane.
fn domain_edges(surface: &NurbsSurface) -> Vec<DVec2> {
    let (lo, span) = domain(surface);
    let per_edge = 64;
    let corners = [
        lo,
        lo + DVec2::new(span.x, 0.0),
        lo + span,
        lo + DVec2::new(0.0, span.y),
    ];
    (0..4)
        .flat_map(|e| {
            let (a, b) = (corners[e], corners[(e + 1) % 4]);
            (0..per_edge).map(move |k| a.lerp(b, k as f64 / per_edge as f64))
        })
        .collect()
}

/// Points drawn in a view laid onto the surface: each point moved along `direction`
/// (press Z for the top view) to the surface point seen there, found by Newton from the
/// nearest of a coarse grid of samples. `Err(k)` names the first point the surface is
/// not seen under (outside it, or where Newton fails).
pub fn lay_onto(
    surface: &NurbsSurface,
    direction: DVec3,
    points: &[DVec3],
) -> Result<Vec<DVec3>, usize> {
    let plane = ProjectionPlane::square_to(surface, direction).ok_or(0usize)?;
    let (lo, span) = domain(surface);
    let map = PlaneMap {
        surface,
        seen: Some(&plane),
        lo,
        span,
        lengths: iso_lengths(surface),
        closed: (false, false),
    };
    let coarse: Vec<(DVec2, DVec2)> = grid_of(lo, lo + span, 32)
        .map(|uv| (map.to_plane(uv), uv))
        .collect();
    points
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            let q = plane.project(p);
            let start = coarse
                .iter()
                .min_by(|x, y| x.0.distance_squared(q).total_cmp(&y.0.distance_squared(q)))
                .map_or(lo, |c| c.1);
            let uv = map.to_parameters(q, start).ok_or(k)?;
            Ok(surface.point_at(uv.x, uv.y))
        })
        .collect()
}

/// How the plane stands for the surface: parameters to plane points and back.
struct PlaneMap<'a> {
    surface: &'a NurbsSurface,
    /// The plane the surface is seen on, or `None` for its parameters.
    seen: Option<&'a ProjectionPlane>,
    lo: DVec2,
    span: DVec2,
    /// The iso-curves' mean lengths along u and v (parameters plane).
    lengths: DVec2,
    /// Whether the surface closes on itself across u and across v (a full revolution).
    closed: (bool, bool),
}

impl PlaneMap<'_> {
    fn to_plane(&self, uv: DVec2) -> DVec2 {
        match self.seen {
            Some(plane) => plane.project(self.surface.point_at(uv.x, uv.y)),
            None => (uv - self.lo) / self.span * self.lengths,
        }
    }

    /// The parameters of a plane point; for the projection plane, Newton on the
    /// surface point's projection from `start`.
    fn to_parameters(&self, q: DVec2, start: DVec2) -> Option<DVec2> {
        match self.seen {
            None => Some(self.lo + q / self.lengths * self.span),
            Some(plane) => {
                let hi = self.lo + self.span;
                let mut uv = start.clamp(self.lo, hi);
                let scale = self.lengths.max_element().max(1.0);
                for _ in 0..NEWTON_STEPS {
                    let d = self.surface.derivatives::<2>(uv.x, uv.y);
                    let r = q - plane.project(d[0][0]);
                    if r.length() < 1e-10 * scale {
                        return Some(uv);
                    }
                    let (a, b) = (plane.along(d[1][0]), plane.along(d[0][1]));
                    let det = a.perp_dot(b);
                    if det.abs() <= 1e-300 {
                        return None;
                    }
                    let step = DVec2::new(r.perp_dot(b), a.perp_dot(r)) / det;
                    uv = (uv + step).clamp(self.lo, hi);
                }
                let r = q - plane.project(self.surface.point_at(uv.x, uv.y));
                (r.length() < 1e-6 * scale).then_some(uv)
            }
        }
    }

    /// The map from the plane to the surface's tangent plane at `d` (its largest
    /// stretch): how much longer a plane length is on the surface, at most.
    fn stretch(&self, d: &[[DVec3; 3]; 3]) -> Option<f64> {
        let (su, sv) = (d[1][0], d[0][1]);
        // dS/dq = [S_u S_v] (dq/duv)^-1.
        let (ju, jv) = match self.seen {
            None => (
                su * self.span.x / self.lengths.x,
                sv * self.span.y / self.lengths.y,
            ),
            Some(plane) => {
                let (a, b) = (plane.along(su), plane.along(sv));
                let det = a.perp_dot(b);
                if det.abs() <= 1e-300 {
                    return None;
                }
                // The inverse of [a b] is [b.y -b.x; -a.y a.x] / det.
                ((su * b.y - sv * a.y) / det, (sv * a.x - su * b.x) / det)
            }
        };
        let (e, f, g) = (ju.dot(ju), ju.dot(jv), jv.dot(jv));
        let largest = 0.5 * (e + g) + (0.25 * (e - g).powi(2) + f * f).sqrt();
        (largest > 0.0).then(|| largest.sqrt())
    }
}

/// Whether the surface's opposite edges meet (a full revolution, a closed loft): across
/// u, across v.
fn closed(surface: &NurbsSurface) -> (bool, bool) {
    let (lo, span) = domain(surface);
    let tolerance = 1e-9 * surface.control_scale().max(1.0);
    let meets = |a: &dyn Fn(f64) -> DVec2, b: &dyn Fn(f64) -> DVec2| {
        (0..=8).all(|k| {
            let t = k as f64 / 8.0;
            let (p, q) = (a(t), b(t));
            surface
                .point_at(p.x, p.y)
                .distance(surface.point_at(q.x, q.y))
                <= tolerance
        })
    };
    let across_u = meets(&|t| lo + span * DVec2::new(0.0, t), &|t| {
        lo + span * DVec2::new(1.0, t)
    });
    let across_v = meets(&|t| lo + span * DVec2::new(t, 0.0), &|t| {
        lo + span * DVec2::new(t, 1.0)
    });
    (across_u, across_v)
}

/// The `(n + 1)^2` parameters of a regular grid from `a` to `b`.
fn grid_of(a: DVec2, b: DVec2, n: usize) -> impl Iterator<Item = DVec2> {
    (0..=n).flat_map(move |j| {
        (0..=n).map(move |i| a + (b - a) * DVec2::new(i as f64, j as f64) / n as f64)
    })
}

/// The mean length of a few iso-curves of each direction: (along u, along v).
fn iso_lengths(surface: &NurbsSurface) -> DVec2 {
    let (lo, span) = domain(surface);
    let polyline = |f: &dyn Fn(f64) -> DVec2| -> f64 {
        let n = 64;
        (0..n)
            .map(|k| {
                let (a, b) = (f(k as f64 / n as f64), f((k + 1) as f64 / n as f64));
                surface
                    .point_at(a.x, a.y)
                    .distance(surface.point_at(b.x, b.y))
            })
            .sum()
    };
    let fractions = [0.0, 0.25, 0.5, 0.75, 1.0];
    let along_u: f64 = fractions
        .iter()
        .map(|&t| polyline(&|s| lo + span * DVec2::new(s, t)))
        .sum::<f64>()
        / 5.0;
    let along_v: f64 = fractions
        .iter()
        .map(|&s| polyline(&|t| lo + span * DVec2::new(s, t)))
        .sum::<f64>()
        / 5.0;
    DVec2::new(along_u, along_v).max(DVec2::splat(1e-9))
}

/// Meshes a region of `surface` with quads of about `options.quad.size` (paper 004):
/// trim loops to parameters (eq. 2-7), the region meshed in the projection plane (or
/// the parameters where the surface turns away from it), the nodes mapped back.
pub fn quad_mesh_surface(
    surface: &NurbsSurface,
    region: &SurfaceRegion,
    options: &SurfaceMeshOptions,
) -> Result<SurfaceMesh, SurfaceMeshError> {
    let size = options.quad.size;
    if !(size.is_finite() && size > 0.0) {
        return Err(SurfaceMeshError::Region(QuadError::Size(size)));
    }
    let (lo, span) = domain(surface);
    // A coarse look at the whole surface: its mean normal, and starts for Newton.
    let coarse: Vec<(DVec3, DVec2, DVec3)> = grid_of(lo, lo + span, 24)
        .map(|uv| {
            let d = surface.derivatives::<2>(uv.x, uv.y);
            (d[0][0], uv, d[1][0].cross(d[0][1]).normalize_or_zero())
        })
        .collect();
    let mean_normal = coarse.iter().map(|c| c.2).sum::<DVec3>();
    let corner_plane = ProjectionPlane::of(surface);
    let start_plane = match (options.plane, &corner_plane) {
        (Some(MeshPlane::View(d)), _) => ProjectionPlane::square_to(surface, d),
        (_, Some(p)) => Some(p.clone()),
        (_, None) => ProjectionPlane::square_to(surface, mean_normal),
    }
    .ok_or(SurfaceMeshError::NoPlane)?;
    let starts: Vec<(DVec3, DVec2)> = coarse.iter().map(|c| (c.0, c.1)).collect();
    let loops = trim_parameters(surface, &start_plane, &starts, region, options.on_surface)?;
    // The samples: a grid over the outer loop's parameters.
    let (mut a, mut b) = (loops[0][0], loops[0][0]);
    for uv in &loops[0] {
        a = a.min(*uv);
        b = b.max(*uv);
    }
    let samples: Vec<(DVec2, [[DVec3; 3]; 3])> = grid_of(a, b, SAMPLES)
        .map(|uv| (uv, surface.derivatives::<3>(uv.x, uv.y)))
        .collect();
    let normals: Vec<DVec3> = samples
        .iter()
        .map(|(_, d)| d[1][0].cross(d[0][1]).normalize_or_zero())
        .collect();
    // How far the region's surface turns from a plane's normal at most.
    let steepest = |normal: DVec3| {
        let facing = normals.iter().sum::<DVec3>().dot(normal).signum();
        normals
            .iter()
            .filter(|n| **n != DVec3::ZERO)
            .map(|n| (facing * n.dot(normal)).clamp(-1.0, 1.0).acos())
            .fold(0.0, f64::max)
    };
    let region_normal = normals.iter().sum::<DVec3>();
    let kind = match options.plane {
        Some(kind) => kind,
        None => match &corner_plane {
            Some(p) if steepest(p.normal) <= STEEPEST => MeshPlane::Projection,
            _ if region_normal.length() > 0.0 && steepest(region_normal) <= STEEPEST => {
                MeshPlane::View(region_normal.normalize())
            }
            _ => MeshPlane::Parameters,
        },
    };
    let seen_plane = match kind {
        MeshPlane::Projection => Some(corner_plane.clone().ok_or(SurfaceMeshError::NoPlane)?),
        MeshPlane::View(d) => {
            Some(ProjectionPlane::square_to(surface, d).ok_or(SurfaceMeshError::NoPlane)?)
        }
        MeshPlane::Parameters => None,
    };
    let map = PlaneMap {
        surface,
        seen: seen_plane.as_ref(),
        lo,
        span,
        lengths: iso_lengths(surface),
        closed: closed(surface),
    };
    let plane_loops: Vec<Vec<DVec2>> = loops
        .iter()
        .map(|l| l.iter().map(|&uv| map.to_plane(uv)).collect())
        .collect();
    // The size wanted in the plane: the chord the curvature allows on the surface,
    // shrunk by how much the plane stretches onto the surface there.
    let tolerance = options.quad.chord_tolerance;
    let sized: Vec<(DVec2, f64, f64)> = samples
        .iter()
        .filter_map(|(uv, d)| {
            let on_surface = match principal_of(d) {
                Some(p) if tolerance > 0.0 => size.min(chord_for_sag(p.min_radius(), tolerance)),
                _ => size,
            };
            let stretch = map.stretch(d)?;
            Some((map.to_plane(*uv), on_surface / stretch, on_surface))
        })
        .collect();
    let mut in_plane: Vec<(DVec2, f64)> = sized.iter().map(|s| (s.0, s.1)).collect();
    if options.quad.keep_boundary {
        // The nodes given along the loops ask for their own spacing inside too, so
        // the elements grade from a seam's spacing to the region's size.
        for l in &plane_loops {
            for (k, &q) in l.iter().enumerate() {
                let (prev, next) = (l[(k + l.len() - 1) % l.len()], l[(k + 1) % l.len()]);
                in_plane.push((q, 0.5 * (q.distance(prev) + q.distance(next))));
            }
        }
    }
    let grid = SizeGrid::from_samples(&in_plane, SAMPLES);
    let least_size = sized.iter().map(|s| s.2).fold(size, f64::min);
    let mut quad = options.quad.clone();
    quad.grading = grid.filter(|g| g.least() < size).map(std::sync::Arc::new);
    let plane_region = Region {
        outer: plane_loops[0].clone(),
        holes: plane_loops[1..].to_vec(),
    };
    let meshed = quad_mesh_region(&plane_region, &quad).map_err(SurfaceMeshError::Region)?;
    let mut uv = back_to_parameters(&map, &start_plane, &meshed, &plane_loops, &loops, &samples)?;
    let mut positions: Vec<DVec3> = uv.par_iter().map(|p| surface.point_at(p.x, p.y)).collect();
    if options.quad.keep_boundary {
        // The nodes given are the boundary nodes, in their order: kept exactly where
        // they were given, so a neighbouring region meshed with the same seam nodes
        // shares them to the last bit.
        let given = region
            .outer
            .iter()
            .flatten()
            .chain(region.holes.iter().flatten());
        let given_uv = loops.iter().flatten();
        for (k, (&p, &at)) in given.zip(given_uv).enumerate().take(meshed.boundary_nodes) {
            positions[k] = p;
            uv[k] = at;
        }
    }
    let faces = oriented_faces(surface, &meshed, &uv, &positions)?;
    let mesh = Mesh::new(positions, faces)
        .map_err(|e| SurfaceMeshError::Region(QuadError::Mesh(e.to_string())))?;
    Ok(SurfaceMesh {
        mesh,
        uv,
        boundary_nodes: meshed.boundary_nodes,
        plane: kind,
        least_size,
    })
}

/// A point seen in the plane: where, its parameters, and (for a sample on the
/// projection plane) the plane's rates along u and v there.
type Seen = (DVec2, DVec2, Option<(DVec2, DVec2)>);

/// Every node's parameters. A boundary node lies on a trim loop's chord in the plane:
/// its parameters are those of the chord's ends blended (a trim runs straight in the
/// parameters between its points, so a node lies on the surface between two trim
/// points even where the chord seen in the plane runs just outside the surface's
/// edge); where the two ends lie across a closed surface's seam, the surface point
/// nearest the 3-D chord instead. An inner node is found by Newton from the nearest
/// sample.
fn back_to_parameters(
    map: &PlaneMap,
    start_plane: &ProjectionPlane,
    meshed: &PlaneMesh,
    plane_loops: &[Vec<DVec2>],
    loops: &[Vec<DVec2>],
    samples: &[(DVec2, [[DVec3; 3]; 3])],
) -> Result<Vec<DVec2>, SurfaceMeshError> {
    // Each seen point with its parameters and, for a sample on the projection plane,
    // how the plane point moves with them (the surface's derivatives seen in the
    // plane), so Newton starts one linear step nearer (a step per node saved).
    let seen: Vec<Seen> = samples
        .iter()
        .map(|(uv, d)| {
            let slopes = map
                .seen
                .map(|plane| (plane.along(d[1][0]), plane.along(d[0][1])));
            (map.to_plane(*uv), *uv, slopes)
        })
        .chain(
            plane_loops
                .iter()
                .zip(loops)
                .flat_map(|(q, uv)| q.iter().copied().zip(uv.iter().copied()))
                .map(|(q, uv)| (q, uv, None)),
        )
        .collect();
    // A linear step is taken only within a sample cell of the sample.
    let cell = match samples {
        [first, .., last] => (last.0 - first.0).abs() / SAMPLES as f64,
        _ => DVec2::ZERO,
    };
    let linear_start = |q: DVec2, (at, uv, slopes): &Seen| {
        let Some((a, b)) = slopes else {
            return *uv;
        };
        let det = a.perp_dot(*b);
        if det.abs() <= 1e-300 {
            return *uv;
        }
        let r = q - *at;
        let step = DVec2::new(r.perp_dot(*b), a.perp_dot(r)) / det;
        if step.abs().cmple(cell).all() {
            *uv + step
        } else {
            *uv
        }
    };
    // The seen points on a grid (in the plane z = 0), for the one nearest each node.
    let boxes: Vec<(DVec3, DVec3)> = seen
        .iter()
        .map(|(q, _, _)| (q.extend(0.0), q.extend(0.0)))
        .collect();
    let grid = BoxGrid::new(&boxes);
    let on_trim = |q: DVec2| -> Option<DVec2> {
        let mut best: Option<(f64, DVec2)> = None;
        for (ql, uvl) in plane_loops.iter().zip(loops) {
            for i in 0..ql.len() {
                let j = (i + 1) % ql.len();
                let d = ql[j] - ql[i];
                let t = ((q - ql[i]).dot(d) / d.length_squared().max(f64::MIN_POSITIVE))
                    .clamp(0.0, 1.0);
                let gap = q.distance(ql[i] + t * d);
                if best.is_none_or(|b| gap < b.0) {
                    let (a, b) = (uvl[i], uvl[j]);
                    let jump = ((b - a) / map.span).abs();
                    let across_seam =
                        (map.closed.0 && jump.x > 0.5) || (map.closed.1 && jump.y > 0.5);
                    let uv = if !across_seam {
                        a.lerp(b, t)
                    } else {
                        let chord = map
                            .surface
                            .point_at(a.x, a.y)
                            .lerp(map.surface.point_at(b.x, b.y), t);
                        let near = if t < 0.5 { a } else { b };
                        newton_foot(map.surface, near, chord).map_or(near, |f| f.uv)
                    };
                    best = Some((gap, uv));
                }
            }
        }
        best.map(|b| b.1)
    };
    // Each node on its own, side by side (a large face's nodes are most of its
    // meshing after the split); the first node that fails, in node order, is reported.
    let found: Vec<Result<DVec2, SurfaceMeshError>> = meshed
        .points
        .par_iter()
        .enumerate()
        .map(|(k, &q)| {
            if k < meshed.boundary_nodes {
                if let Some(uv) = on_trim(q) {
                    return Ok(uv);
                }
            }
            let start = grid
                .nearest(q.extend(0.0), |k| (seen[k as usize].0.distance(q), ()))
                .map_or(map.lo, |(k, _, _)| linear_start(q, &seen[k as usize]));
            map.to_parameters(q, start)
                .or_else(|| map.to_parameters(q, start_plane.start(q)))
                .ok_or_else(|| SurfaceMeshError::Distorted {
                    at: map.surface.point_at(start.x, start.y),
                })
        })
        .collect();
    found.into_iter().collect()
}

/// The plane mesh's elements on the surface, turned so each normal runs along the
/// surface's `S_u x S_v`; an element facing against it (folded) is refused.
fn oriented_faces(
    surface: &NurbsSurface,
    meshed: &PlaneMesh,
    uv: &[DVec2],
    positions: &[DVec3],
) -> Result<Vec<Face>, SurfaceMeshError> {
    let elements: Vec<Vec<u32>> = meshed
        .quads
        .iter()
        .map(|q| q.to_vec())
        .chain(meshed.triangles.iter().map(|t| t.to_vec()))
        .collect();
    let facing = |e: &[u32]| -> (f64, DVec3) {
        let p: Vec<DVec3> = e.iter().map(|&v| positions[v as usize]).collect();
        let n = if p.len() == 4 {
            (p[2] - p[0]).cross(p[3] - p[1])
        } else {
            (p[1] - p[0]).cross(p[2] - p[0])
        };
        let centre = e.iter().map(|&v| uv[v as usize]).sum::<DVec2>() / e.len() as f64;
        let d = surface.derivatives::<2>(centre.x, centre.y);
        let along = d[1][0].cross(d[0][1]);
        (n.dot(along), p.iter().sum::<DVec3>() / p.len() as f64)
    };
    // The plane's winding against the surface's: the sign most elements agree on.
    let signs: Vec<(f64, DVec3)> = elements.par_iter().map(|e| facing(e)).collect();
    let agree = signs.iter().filter(|s| s.0 > 0.0).count();
    let flip = agree * 2 < signs.len();
    let mut faces = Vec::with_capacity(elements.len());
    for (e, (sign, centre)) in elements.iter().zip(&signs) {
        if (*sign > 0.0) == flip || *sign == 0.0 {
            return Err(SurfaceMeshError::Distorted { at: *centre });
        }
        let face = Face::from_slice(e)
            .map_err(|err| SurfaceMeshError::Region(QuadError::Mesh(err.to_string())))?;
        faces.push(if flip { face.reversed() } else { face });
    }
    Ok(faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bump() -> NurbsSurface {
        // A bicubic 4 x 4 net over 200 x 100 mm, lifted in the middle.
        let net: Vec<Vec<DVec3>> = (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| {
                        let inner = (1..3).contains(&i) && (1..3).contains(&j);
                        let z = if inner { 30.0 } else { 0.0 };
                        DVec3::new(i as f64 * 200.0 / 3.0, j as f64 * 100.0 / 3.0, z)
                    })
                    .collect()
            })
            .collect();
        let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        NurbsSurface::new(3, 3, knots.clone(), knots, net).expect("a valid net")
    }

    #[test]
    fn a_point_on_the_surface_maps_to_its_own_parameters() {
        let s = bump();
        let plane = ProjectionPlane::of(&s).expect("a plane");
        for &(u, v) in &[(0.3, 0.7), (0.5, 0.5), (0.01, 0.99), (0.9, 0.2)] {
            let p = s.point_at(u, v);
            let foot = parameters_of(&s, &plane, p).expect("converges");
            assert!((foot.uv - DVec2::new(u, v)).length() < 1e-9, "{foot:?}");
            assert!(foot.distance < 1e-9);
        }
    }

    #[test]
    fn the_bilinear_inverse_undoes_the_bilinear_map() {
        let plane = ProjectionPlane::of(&bump()).expect("a plane");
        for &(s, t) in &[(0.1, 0.2), (0.5, 0.5), (0.95, 0.05)] {
            let st = plane.bilinear_inverse(plane.bilinear(s, t));
            assert!((st - DVec2::new(s, t)).length() < 1e-12);
        }
    }
}
