//! Free edges and hole filling on FE meshes (paper 002; issue 17): a tool mesh from CAD
//! arrives with holes and free edges, which break forming simulation's contact search
//! and tool offsetting. Each hole is filled from a smooth base surface, so the fill
//! follows the panel round it; the panel's outer boundary is kept.
//!
//! The steps, each its own module and tested function:
//!
//! - [`cracks`]: pairs of free-edge chains closer than a tolerance (CAD patches exported
//!   apart) stitched by merging nodes, nodes on the opposite chain's edges splitting
//!   them first so no T-junction is left;
//! - [`loops`]: the loops of free edges, found from each node's star (the nodes whose
//!   faces do not close round it) and traced on the half-edge topology where one of
//!   them is not simple (the same loops either way, property-tested), their length and
//!   span, each piece's outer boundary (the loop enclosing the others in the
//!   piece's projection), and the checks on the mesh round a loop;
//! - [`plane`]: a hole's projection plane, square to the mean of its nodes' normals;
//! - [`base`]: the initial grid on that plane projected onto the mesh round the hole,
//!   and the base surface through it ([`thin_plate`]: the thin plate of least bending
//!   energy, held at the mesh's positions and so its slopes; a planar loop's plane
//!   directly), as bicubic Ferguson patches ([`ferguson`]);
//! - [`trim`]: the loop projected onto the base surface by Newton-Raphson, its trim loop
//!   in `(u, v)`;
//! - [`patch`]: the trimmed region meshed by a constrained Delaunay triangulation in
//!   `(u, v)`, its interior points sized from the loop's own edges;
//! - [`fill_holes`] (here): the steps put together, each fill joined to its loop's own
//!   nodes and wound as the faces beside it; all holes or none.

pub mod base;
pub mod cracks;
pub mod ferguson;
pub mod loops;
pub mod patch;
pub mod plane;
pub mod thin_plate;
pub mod trim;

use std::collections::BTreeSet;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use self::base::{base_surface_with, BaseError, BaseSurface, FloodScratch};
use self::loops::{
    check_loop, check_nodes, check_shape, scan, FreeEdges, FreeLoop, LoopProblem, Scan,
};
use self::patch::{mesh_region, RegionError};
use self::plane::loop_plane;
use self::trim::trim_loop;
use super::stars::VertexStars;
use super::{Face, Mesh};
use crate::geom::trimmed::polygon_area;

/// The least cosine between a face at a loop and the loop's plane normal: a face turned
/// more than 75 deg from the plane (a hole wrapping round a hairpin or a sharp feature)
/// makes the loop not single-valued over its plane.
const FACING: f64 = 0.26;

/// Which holes to fill.
#[derive(Debug, Clone, PartialEq)]
pub enum HoleChoice {
    /// Every loop but the outer boundaries.
    All,
    /// The loops (but the outer boundaries) at most this far across (mm).
    UpTo(f64),
    /// The loop nearest each point (an outer boundary too, when picked).
    At(Vec<DVec3>),
}

/// How holes are filled.
#[derive(Debug, Clone, PartialEq)]
pub struct FillOptions {
    /// Which holes.
    pub holes: HoleChoice,
    /// A point nearest the outer boundary, where the designer decides it.
    pub outer: Option<DVec3>,
    /// The element size inside the fills (mm); the loop's mean edge length if `None`.
    pub size: Option<f64>,
}

/// One hole filled, and how well.
#[derive(Debug, Clone)]
pub struct FilledHole {
    /// The loop it filled (its index in [`Filled::free`]).
    pub loop_index: usize,
    /// The fill alone: the loop's nodes and the new ones inside it, and its triangles.
    pub patch: Mesh,
    /// Its base surface.
    pub base: BaseSurface,
    /// How far the loop's nodes lie from the base surface, at the most (mm): how well
    /// the base surface meets the hole's rim.
    pub rim_gap: f64,
    /// The largest angle between a fill triangle and the mesh face across a loop edge
    /// from it (deg).
    pub normal_jump: f64,
    /// The smallest angle of a fill triangle (deg).
    pub min_angle: f64,
}

/// A mesh with holes filled.
#[derive(Debug, Clone)]
pub struct Filled {
    /// The mesh with every chosen hole filled: its own faces first, then each fill's.
    pub mesh: Mesh,
    /// The holes filled, in loop order.
    pub holes: Vec<FilledHole>,
    /// The free edges before filling.
    pub free: FreeEdges,
}

/// Why holes could not be filled. Nothing is filled when any chosen hole fails.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HoleError {
    /// Holes were picked by points on a mesh with no loop of free edges.
    #[error("the mesh has no hole")]
    NoHole,
    /// A picked point is farther from every loop than the nearest loop is across.
    #[error("no hole near {point}: the nearest is {distance} mm away")]
    NothingNear { point: DVec3, distance: f64 },
    /// The mesh round a loop is not sound (`loop_index` is `None` for a chain of free
    /// edges that does not close).
    #[error("the hole at {centre} cannot be filled: {problem}")]
    Loop {
        loop_index: Option<usize>,
        centre: DVec3,
        problem: LoopProblem,
    },
    /// A loop is not single-valued over its projection plane (it wraps round a sharp
    /// feature): a fill over it would fold.
    #[error("the hole at {centre} is not single-valued over its plane: {reason}")]
    NotSingleValued {
        loop_index: usize,
        centre: DVec3,
        reason: String,
    },
    /// The base surface could not be made.
    #[error("the hole at {centre} has no base surface: {problem}")]
    Base {
        loop_index: usize,
        centre: DVec3,
        problem: BaseError,
    },
    /// The filled mesh could not be made (too large for a mesh, or a point of a fill
    /// not finite).
    #[error("the filled mesh could not be made: {0}")]
    Mesh(String),
}

/// Refuses a chain of free edges that does not close when `options` would fill it:
/// every chain for all holes, those up to the size by size, and one nearer a picked
/// point than any loop. The chain is where a face is wound the wrong way or an edge
/// has more than two faces, and the diagnostic says which.
fn refuse_open_chains(
    stars: &VertexStars,
    free: &FreeEdges,
    options: &FillOptions,
) -> Result<(), HoleError> {
    let mesh = stars.mesh();
    for chain in &free.open_chains {
        let points: Vec<DVec3> = chain.iter().map(|v| mesh.positions()[v.index()]).collect();
        let near = |p: DVec3| {
            points
                .iter()
                .map(|q| q.distance(p))
                .fold(f64::INFINITY, f64::min)
        };
        let chosen = match &options.holes {
            HoleChoice::All => true,
            HoleChoice::UpTo(size) => loops::span_of(&points) <= *size,
            HoleChoice::At(picks) => picks.iter().any(|&p| {
                let to_loops = free
                    .loops
                    .iter()
                    .flat_map(|l| l.nodes.iter())
                    .map(|v| mesh.positions()[v.index()].distance(p))
                    .fold(f64::INFINITY, f64::min);
                near(p) < to_loops
            }),
        };
        if chosen {
            let centre = points.iter().copied().sum::<DVec3>() / points.len().max(1) as f64;
            let problem = match check_nodes(stars, chain) {
                Err(problem) => problem,
                Ok(()) => LoopProblem::Open,
            };
            return Err(HoleError::Loop {
                loop_index: None,
                centre,
                problem,
            });
        }
    }
    Ok(())
}

/// The loops `options` choose among `free`'s.
fn chosen(mesh: &Mesh, free: &FreeEdges, options: &FillOptions) -> Result<Vec<usize>, HoleError> {
    let ids: Vec<usize> = match &options.holes {
        HoleChoice::All => (0..free.loops.len())
            .filter(|&k| !free.loops[k].outer)
            .collect(),
        HoleChoice::UpTo(size) => (0..free.loops.len())
            .filter(|&k| !free.loops[k].outer && free.loops[k].span <= *size)
            .collect(),
        HoleChoice::At(points) => {
            let mut picked = BTreeSet::new();
            for &p in points {
                let distance = |k: usize| {
                    free.loops[k]
                        .nodes
                        .iter()
                        .map(|v| mesh.positions()[v.index()].distance(p))
                        .fold(f64::INFINITY, f64::min)
                };
                let nearest = (0..free.loops.len())
                    .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
                    .ok_or(HoleError::NoHole)?;
                // A point picks a hole when it lies within the hole's own span of its
                // rim (inside it, or on the panel next to it); farther off it is a
                // mistake, not a choice.
                let d = distance(nearest);
                if d > free.loops[nearest].span {
                    return Err(HoleError::NothingNear {
                        point: p,
                        distance: d,
                    });
                }
                picked.insert(nearest);
            }
            picked.into_iter().collect()
        }
    };
    Ok(ids)
}

/// Fills the holes of `mesh` (triangles and quads) that `options` choose (paper 002):
/// the filled mesh is a copy of `mesh` with the fills, triangles, added.
pub fn fill_holes(mesh: &Mesh, options: &FillOptions) -> Result<Filled, HoleError> {
    let (holes, free) = fills(mesh, options)?;
    let (positions, faces) = joined(&free, &holes, mesh.vertex_count());
    let filled = mesh
        .with_added(&positions, &faces)
        .map_err(|e| HoleError::Mesh(e.to_string()))?;
    Ok(Filled {
        mesh: filled,
        holes,
        free,
    })
}

/// [`fill_holes`] on a mesh handed over: the fills are added to it in place, as a mesh
/// editor's "close holes" does, and its own nodes and faces are not copied. When a hole
/// cannot be filled the mesh is dropped with the error.
pub fn fill_holes_in(mut mesh: Mesh, options: &FillOptions) -> Result<Filled, HoleError> {
    let (holes, free) = fills(&mesh, options)?;
    let (positions, faces) = joined(&free, &holes, mesh.vertex_count());
    mesh.add(&positions, &faces)
        .map_err(|e| HoleError::Mesh(e.to_string()))?;
    Ok(Filled { mesh, holes, free })
}

/// Every chosen hole of `mesh` filled, in loop order, with the free edges they were
/// found among; the first hole (in loop order) that cannot be filled is the error.
/// The holes are filled side by side: each reads the mesh and writes only its patch.
fn fills(mesh: &Mesh, options: &FillOptions) -> Result<(Vec<FilledHole>, FreeEdges), HoleError> {
    let Scan {
        stars,
        free,
        nodes_sound,
    } = scan(mesh, options.outer);
    refuse_open_chains(&stars, &free, options)?;
    let ids = chosen(mesh, &free, options)?;
    // Each thread's holes share one set of flood marks over the mesh. Every hole's
    // result is kept, so that the error is the first hole in loop order that could
    // not be filled, whichever thread met one first.
    let filled: Vec<Result<FilledHole, HoleError>> = ids
        .par_iter()
        .map_init(
            || FloodScratch::new(mesh),
            |scratch, &k| {
                let l = &free.loops[k];
                // The scan checked every free edge's nodes where it found them all simple.
                let checked = if nodes_sound {
                    check_shape(mesh, l)
                } else {
                    check_loop(&stars, l)
                };
                checked
                    .map_err(|problem| HoleError::Loop {
                        loop_index: Some(k),
                        centre: l.centre,
                        problem,
                    })
                    .and_then(|()| fill_one(&stars, k, l, options.size, scratch))
            },
        )
        .collect();
    let holes = filled.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok((holes, free))
}

/// The nodes and faces the fills add to a mesh of `own_nodes` nodes: each fill's new
/// nodes after the mesh's, its faces on the loop's own nodes and the new ones.
fn joined(free: &FreeEdges, holes: &[FilledHole], own_nodes: usize) -> (Vec<DVec3>, Vec<Face>) {
    let mut positions: Vec<DVec3> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    for hole in holes {
        let l = &free.loops[hole.loop_index];
        let n = l.nodes.len();
        let first_new = (own_nodes + positions.len()) as u32;
        positions.extend_from_slice(&hole.patch.positions()[n..]);
        let id = |i: u32| -> u32 {
            if (i as usize) < n {
                l.nodes[i as usize].0
            } else {
                first_new + i - n as u32
            }
        };
        for f in hole.patch.faces() {
            let t = f.indices();
            faces.push(Face::triangle(id(t[0]), id(t[1]), id(t[2])));
        }
    }
    (positions, faces)
}

/// The smallest angle of the triangle `a b c` (deg): the corner with the largest
/// cosine, so one arc cosine per triangle.
fn smallest_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let cosine = |p: DVec3, q: DVec3, r: DVec3| {
        let (u, v) = (q - p, r - p);
        let lengths = (u.length_squared() * v.length_squared()).sqrt();
        if lengths > 0.0 {
            (u.dot(v) / lengths).clamp(-1.0, 1.0)
        } else {
            // A corner with no side has no angle; the triangle's smallest is zero.
            1.0
        }
    };
    let largest = cosine(a, b, c).max(cosine(b, c, a)).max(cosine(c, a, b));
    largest.acos().to_degrees()
}

/// Fills hole `k`, loop `l`, of `mesh`: its plane, base surface, trim loop and region
/// meshed, as a patch over the loop's own nodes (patch node `i < n` is the loop's
/// node `i`).
fn fill_one(
    stars: &VertexStars,
    k: usize,
    l: &FreeLoop,
    size: Option<f64>,
    scratch: &mut FloodScratch,
) -> Result<FilledHole, HoleError> {
    let mesh = stars.mesh();
    let refuse = |reason: String| HoleError::NotSingleValued {
        loop_index: k,
        centre: l.centre,
        reason,
    };
    let points: Vec<DVec3> = l
        .nodes
        .iter()
        .map(|v| mesh.positions()[v.index()])
        .collect();
    let node_normals: Vec<DVec3> = l
        .nodes
        .iter()
        .map(|&v| mesh.vertex_normal(v, stars.faces(v)))
        .collect();
    let plane = loop_plane(&points, &node_normals)
        .ok_or_else(|| refuse("its nodes' normals cancel out".into()))?;
    // Single-valued over the plane: every face at the loop faces the plane, and the loop
    // runs round the hole clockwise seen from it (as a hole's free edges do).
    for &v in &l.nodes {
        for &f in stars.faces(v) {
            let facing = mesh.face_normal(f).map_or(0.0, |n| n.dot(plane.normal));
            if facing <= FACING {
                let at = mesh.face_centroid(f).unwrap_or(points[0]);
                return Err(refuse(format!(
                    "the faces round it turn away from its plane near ({:.3}, {:.3}, {:.3}): it wraps round a sharp feature",
                    at.x, at.y, at.z
                )));
            }
        }
    }
    let above: Vec<DVec2> = points.iter().map(|&p| plane.to_plane(p).0).collect();
    if polygon_area(above.iter().copied()) >= 0.0 {
        return Err(refuse(
            "it runs the wrong way round over its plane (an outer boundary, or the faces round it fold over)"
                .into(),
        ));
    }
    let mean_edge = l.length / points.len() as f64;
    let size = size.unwrap_or(mean_edge).max(1e-6);
    let base = base_surface_with(stars, &l.nodes, &plane, size, scratch).map_err(|problem| {
        HoleError::Base {
            loop_index: k,
            centre: l.centre,
            problem,
        }
    })?;
    // The trim loop by normal projection (eq. 7-9). Where that loop crosses itself or a
    // fill triangle over it would fold (a loop far off its base surface: across a
    // crease, the base surface rounds the crease and the nodes on it project well
    // inside), the points straight above the nodes, which lie in the plane's order.
    let trimmed = trim_loop(&base, &points);
    let rim_gap = trimmed.iter().map(|t| t.1).fold(0.0, f64::max);
    let normal_uv: Vec<DVec2> = trimmed.iter().map(|t| t.0).collect();
    let straight_uv: Vec<DVec2> = points.iter().map(|&p| base.uv_above(p)).collect();
    let n = points.len();
    let attempt = |loop_uv: &[DVec2]| -> Result<(Vec<DVec3>, Vec<[usize; 3]>), String> {
        // The region is meshed counter-clockwise: the loop reversed, so it runs round
        // the region the way a boundary does; region point i < n is loop node n - 1 - i.
        let reversed: Vec<DVec2> = loop_uv.iter().rev().copied().collect();
        let meshed = mesh_region(&reversed, size).map_err(|e: RegionError| e.to_string())?;
        let node_of = |i: usize| if i < n { n - 1 - i } else { i };
        let mut positions: Vec<DVec3> = points.clone();
        positions.extend(meshed.uv[n..].iter().map(|&q| base.point_at(q)));
        let triangles: Vec<[usize; 3]> = meshed.triangles.iter().map(|t| t.map(node_of)).collect();
        // No fold: every fill triangle faces the plane.
        for t in &triangles {
            let [a, b, c] = t.map(|i| positions[i]);
            if (b - a).cross(c - a).dot(plane.normal) <= 0.0 {
                return Err(format!(
                    "a fill triangle would fold over near ({:.3}, {:.3}, {:.3})",
                    a.x, a.y, a.z
                ));
            }
        }
        Ok((positions, triangles))
    };
    let (positions, triangles) = match attempt(&normal_uv) {
        Ok(done) => done,
        Err(_) => attempt(&straight_uv).map_err(refuse)?,
    };
    let min_angle = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i]);
            smallest_angle(a, b, c)
        })
        .fold(180.0, f64::min);
    // The normal jump across each loop edge: the fill triangle on it against the mesh
    // face its free half-edge bounds.
    // The fill runs loop edge i (node i to node i + 1) the other way from the mesh's
    // free half-edge: the triangle on it has the side from i + 1 to i.
    let mut on_edge: Vec<Option<[usize; 3]>> = vec![None; n];
    for t in &triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            if a < n && b < n && a == (b + 1) % n {
                on_edge[b] = Some(*t);
            }
        }
    }
    let mut normal_jump = 0.0f64;
    for (i, &face) in l.faces.iter().enumerate() {
        let Some(t) = on_edge[i] else {
            return Err(refuse(format!(
                "the fill does not meet the loop's edge at ({:.3}, {:.3}, {:.3})",
                points[i].x, points[i].y, points[i].z
            )));
        };
        let [a, b, c] = t.map(|v| positions[v]);
        let fill_normal = (b - a).cross(c - a).normalize_or_zero();
        if let Some(mesh_normal) = mesh.face_normal(face) {
            normal_jump = normal_jump.max(fill_normal.angle_between(mesh_normal).to_degrees());
        }
    }
    let faces: Vec<Face> = triangles
        .iter()
        .map(|t| Face::triangle(t[0] as u32, t[1] as u32, t[2] as u32))
        .collect();
    let patch = Mesh::new(positions, faces).map_err(|e| HoleError::Mesh(e.to_string()))?;
    Ok(FilledHole {
        loop_index: k,
        patch,
        base,
        rim_gap,
        normal_jump,
        min_angle,
    })
}
