//! Quad meshing of a plane region by domain decomposition (paper 004, section 4; issue
//! 18): forming simulation takes a die face as shell elements, mostly quads.
//!
//! The steps, each its own module and tested function:
//!
//! - [`boundary`]: nodes placed along each loop of the region at the element size, its
//!   corners kept, an even number on every loop (a region bounded by an odd number of
//!   nodes cannot be all quads);
//! - [`cut`]: each inner loop joined to the outer one by a cut line, nodes on it at the
//!   element size, so the region is bounded by one continuous loop;
//! - [`split`]: that loop split at the best visible node pair (the paper's four
//!   criteria: split angles, area balance, length, node spacing), nodes placed along the
//!   split line so both halves keep an even count, again and again until every loop
//!   has four nodes; loops of six and eight nodes are also tried against their
//!   templates (three or four quads round a centre node);
//! - [`swap`]: where a quad is poor after smoothing, the edge it shares with a
//!   neighbour swapped when the pair's hexagon filled the other way (its inner nodes
//!   relaxed) leaves the quads round it better, then smoothing again: a quad on three
//!   nodes of a gently curving boundary, or on three nodes of a split line, which no
//!   node move can mend;
//! - [`smooth`]: the inner nodes moved towards their neighbours' centre (the paper stops
//!   before this; every mesher a CAE engineer uses does it), a move kept only where it
//!   leaves no element worse than its floor;
//! - [`quality`]: the figures an FE engineer reads off a shell mesh (scaled Jacobian,
//!   corner angles, aspect ratio), the same way for any mesh so a peer's can be compared.
//!
//! Everything is in the plane: a surface is meshed by mapping a region drawn in its
//! projection plane or parameters here, and the mesh back.

pub mod band;
pub mod boundary;
pub mod cut;
pub mod mend;
pub mod quality;
pub mod shell;
pub mod sizing;
pub mod smooth;
pub mod split;
pub mod surface;
pub mod swap;

use std::sync::Arc;

use glam::{DVec2, DVec3};

use sizing::{SizeGrid, Sizes};

use super::{Face, Mesh};
use crate::geom::trimmed::polygon_area;

/// A plane region: an outer loop and the holes inside it, each a closed polygon (the
/// first point not repeated at the end), either way round.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// The outer boundary.
    pub outer: Vec<DVec2>,
    /// The inner loops (holes).
    pub holes: Vec<Vec<DVec2>>,
}

/// How a region is meshed.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadOptions {
    /// The element size along the boundary and inside (mm): the largest anywhere.
    pub size: f64,
    /// Finer sizes over the plane (a surface's curvature seen in its plane), if any.
    pub grading: Option<Arc<SizeGrid>>,
    /// Where a loop turns by more than this (rad), the node there is a corner: it is
    /// kept as a node and the boundary's nodes are spaced between corners.
    pub corner_angle: f64,
    /// How far a boundary piece's chord may sag off a curved loop (mm): the boundary's
    /// nodes are closer than `size` where it curves tightly.
    pub chord_tolerance: f64,
    /// Smoothing passes over the inner nodes (0: none).
    pub smoothing: usize,
    /// The most elements the region may be meshed into; more is refused before any
    /// meshing starts.
    pub max_elements: usize,
    /// Take the loops' points as the boundary nodes, as they are, instead of placing
    /// nodes along the loops: how neighbouring regions share the nodes of their seam.
    /// Their total must be even (a region bounded by an odd number of nodes cannot be
    /// all quads) and no two neighbours may coincide.
    pub keep_boundary: bool,
}

impl QuadOptions {
    /// Elements about `size` long: corners where a loop turns by 30 deg or more, a
    /// boundary sag of at most a twentieth of the size, ten smoothing passes, at most
    /// two million elements.
    pub fn at_size(size: f64) -> QuadOptions {
        QuadOptions {
            size,
            grading: None,
            corner_angle: 30f64.to_radians(),
            chord_tolerance: 0.05 * size,
            smoothing: 10,
            max_elements: 2_000_000,
            keep_boundary: false,
        }
    }

    /// The size wanted at each point: `size`, finer where `grading` asks.
    pub fn sizes(&self) -> Sizes<'_> {
        Sizes {
            size: self.size,
            grid: self.grading.as_deref(),
        }
    }
}

/// A region meshed in its plane.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneMesh {
    /// The nodes: the boundary's first (outer loop, then each hole, in the loops'
    /// order), then the ones on cut and split lines and inside.
    pub points: Vec<DVec2>,
    /// How many of `points` lie on the region's boundary.
    pub boundary_nodes: usize,
    /// The quads, counter-clockwise.
    pub quads: Vec<[u32; 4]>,
    /// The triangles left where quads could not be made (a quad the splitting and
    /// smoothing left folded, split in two), counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
}

impl PlaneMesh {
    /// The mesh in 3-D through `place`, which takes a plane point to space (a surface
    /// evaluated at its parameters, or a projection plane lifted back).
    pub fn lifted(&self, place: impl Fn(DVec2) -> DVec3) -> Result<Mesh, QuadError> {
        let positions: Vec<DVec3> = self.points.iter().map(|&q| place(q)).collect();
        let faces: Vec<Face> = self
            .quads
            .iter()
            .map(|q| Face::quad(q[0], q[1], q[2], q[3]))
            .chain(
                self.triangles
                    .iter()
                    .map(|t| Face::triangle(t[0], t[1], t[2])),
            )
            .collect();
        Mesh::new(positions, faces).map_err(|e| QuadError::Mesh(e.to_string()))
    }

    /// The mesh on the plane `z = 0`.
    pub fn flat(&self) -> Result<Mesh, QuadError> {
        self.lifted(|q| q.extend(0.0))
    }
}

/// Why a region could not be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QuadError {
    /// The element size is not a positive length.
    #[error("the element size must be positive, got {0}")]
    Size(f64),
    /// A loop has fewer than three distinct points, or encloses no area.
    #[error("loop {loop_index} encloses no area")]
    Degenerate { loop_index: usize },
    /// A point is not finite.
    #[error("loop {loop_index} has a point that is not a finite number")]
    NotFinite { loop_index: usize },
    /// Two loops, or one loop with itself, cross or touch.
    #[error("loop {first} and loop {second} cross or touch near ({:.3}, {:.3})", at.x, at.y)]
    Crossing {
        first: usize,
        second: usize,
        at: DVec2,
    },
    /// An inner loop lies outside the outer one.
    #[error("loop {loop_index} lies outside the outer loop")]
    Outside { loop_index: usize },
    /// The boundary nodes given (`keep_boundary`) are an odd number.
    #[error("the loops have {nodes} nodes in all, an odd number: a region needs an even number of boundary nodes to be meshed with quads")]
    OddBoundary { nodes: usize },
    /// Two neighbouring boundary nodes given (`keep_boundary`) coincide.
    #[error("loop {loop_index} has two neighbouring nodes in one place")]
    RepeatedNode { loop_index: usize },
    /// The element size would make more elements than allowed.
    #[error(
        "the element size would make about {estimate} elements, more than the limit of {limit}"
    )]
    TooMany { estimate: usize, limit: usize },
    /// No split line could be found for a loop (it should not happen on a region whose
    /// loops do not cross).
    #[error("no split line found for a loop of {nodes} nodes near ({:.3}, {:.3})", at.x, at.y)]
    NoSplit { nodes: usize, at: DVec2 },
    /// The mesh could not be made (too large, or a point not finite after mapping).
    #[error("the mesh could not be made: {0}")]
    Mesh(String),
}

/// A quad's scaled Jacobian below which it counts as folded: a corner within 6 deg of
/// straight, or past it.
pub(super) const FOLDED: f64 = 0.1;

/// The quads that smoothing left folded (see [`FOLDED`]), each split into two
/// triangles along the diagonal whose worse triangle is better than the quad: the
/// quads kept and the triangles made. A quad neither diagonal mends is kept as it is.
fn split_folded(points: &[DVec2], quads: Vec<[u32; 4]>) -> (Vec<[u32; 4]>, Vec<[u32; 3]>) {
    let mut kept = Vec::with_capacity(quads.len());
    let mut triangles = Vec::new();
    let at = |v: u32| points[v as usize];
    for q in quads {
        let own = quality::scaled_jacobian_2d(&q.map(at));
        if own >= FOLDED {
            kept.push(q);
            continue;
        }
        let splits = [
            [[q[0], q[1], q[2]], [q[2], q[3], q[0]]],
            [[q[1], q[2], q[3]], [q[3], q[0], q[1]]],
        ];
        let worst = |pair: &[[u32; 3]; 2]| {
            pair.iter()
                .map(|t| quality::scaled_jacobian_2d(&t.map(at)))
                .fold(f64::INFINITY, f64::min)
        };
        match splits.iter().max_by(|x, y| worst(x).total_cmp(&worst(y))) {
            Some(pair) if worst(pair) > own.max(0.0) => triangles.extend(pair),
            _ => kept.push(q),
        }
    }
    (kept, triangles)
}

/// The region's own loop points as its boundary nodes, in the order given (outer loop,
/// then each hole), and each loop's nodes in the order the mesher walks it (the outer
/// loop counter-clockwise, the holes clockwise: [`boundary::checked_loops`] turns a loop
/// given the other way round).
fn given_nodes(
    region: &Region,
    checked: &[Vec<DVec2>],
    points: &mut Vec<DVec2>,
    loop_nodes: &mut Vec<Vec<u32>>,
) -> Result<(), QuadError> {
    for (k, (raw, l)) in std::iter::once(&region.outer)
        .chain(&region.holes)
        .zip(checked)
        .enumerate()
    {
        // A repeated point was dropped by the check: two nodes in one place.
        if raw.len() != l.len() {
            return Err(QuadError::RepeatedNode { loop_index: k });
        }
        let n = raw.len() as u32;
        let first = points.len() as u32;
        let turned = raw[0] != l[0] || (n > 1 && raw[1] != l[1]);
        loop_nodes.push(if turned {
            // `l` is `raw` reversed: l[i] = raw[n - 1 - i].
            (0..n).map(|i| first + (n - 1 - i)).collect()
        } else {
            (first..first + n).collect()
        });
        points.extend(raw.iter().copied());
    }
    if points.len() % 2 == 1 {
        return Err(QuadError::OddBoundary {
            nodes: points.len(),
        });
    }
    Ok(())
}

/// Meshes `region` with quads of about `options.size` (paper 004, section 4): boundary
/// nodes placed, holes cut into one loop, the loop split down to quads, the inner nodes
/// smoothed, and a quad left folded split into two triangles.
pub fn quad_mesh_region(region: &Region, options: &QuadOptions) -> Result<PlaneMesh, QuadError> {
    let size = options.size;
    if !(size.is_finite() && size > 0.0) {
        return Err(QuadError::Size(size));
    }
    let loops = boundary::checked_loops(region)?;
    let area: f64 = loops.iter().map(|l| polygon_area(l.iter().copied())).sum();
    // Each quad covers about size^2; the boundary's own count bounds the work too.
    let estimate = match &options.grading {
        Some(grid) => grid.elements(area.abs(), size),
        None => area.abs() / (size * size),
    }
    .ceil() as usize;
    if estimate > options.max_elements {
        return Err(QuadError::TooMany {
            estimate,
            limit: options.max_elements,
        });
    }
    let mut points: Vec<DVec2> = Vec::new();
    let mut loop_nodes: Vec<Vec<u32>> = Vec::new();
    if options.keep_boundary {
        given_nodes(region, &loops, &mut points, &mut loop_nodes)?;
    } else {
        for l in &loops {
            let placed = boundary::place_nodes(
                l,
                options.sizes(),
                options.corner_angle,
                options.chord_tolerance,
            );
            let first = points.len() as u32;
            loop_nodes.push((first..first + placed.len() as u32).collect());
            points.extend(placed);
        }
    }
    let boundary_nodes = points.len();
    let perimeter_nodes: usize = loop_nodes.iter().map(Vec::len).sum();
    if perimeter_nodes > options.max_elements {
        return Err(QuadError::TooMany {
            estimate: perimeter_nodes,
            limit: options.max_elements,
        });
    }
    let single = cut::join_holes(&mut points, &loop_nodes, options.sizes())?;
    let mut quads = Vec::new();
    let mut triangles = Vec::new();
    split::split_down(
        &mut points,
        single,
        options.sizes(),
        &mut quads,
        &mut triangles,
    )?;
    // The inner nodes smoothed after the split, and again after each step that
    // changed elements (the smoothing moves only nodes near a change the second time).
    let smoothed = |points: &mut Vec<DVec2>, quads: &[[u32; 4]], triangles: &[[u32; 3]]| {
        smooth::smooth(points, boundary_nodes, quads, triangles, options.smoothing)
    };
    smoothed(&mut points, &quads, &triangles);
    if options.smoothing > 0
        && swap::swap_edges(
            &mut points,
            boundary_nodes,
            &mut quads,
            &triangles,
            smooth::POOR,
        ) > 0
    {
        smoothed(&mut points, &quads, &triangles);
    }
    if options.smoothing > 0
        && mend::mend_folded(
            &mut points,
            boundary_nodes,
            &mut quads,
            &mut triangles,
            options.sizes(),
            FOLDED,
        ) > 0
    {
        smoothed(&mut points, &quads, &triangles);
    }
    let (quads, folded) = split_folded(&points, quads);
    if !folded.is_empty() && options.smoothing > 0 {
        // The triangles a folded quad became: their inner nodes searched again, now
        // that the quad's diagonal no longer pins them.
        triangles.extend(folded);
        smooth::smooth(&mut points, boundary_nodes, &quads, &triangles, 1);
    } else {
        triangles.extend(folded);
    }
    Ok(PlaneMesh {
        points,
        boundary_nodes,
        quads,
        triangles,
    })
}
