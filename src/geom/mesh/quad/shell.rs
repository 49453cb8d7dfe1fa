//! One conforming quad mesh over faces sewn into a shell (issue 18): a die face's
//! product, step-draw and binder patches meshed so that every seam between two faces
//! carries the same nodes on both sides: no gap, no T-junction, no duplicate node, and
//! every seam (the product outline, the punch opening) on element edges.
//!
//! The steps:
//!
//! 1. the shell ([`crate::geom::sew`]) gives the faces' shared edges and vertices;
//! 2. every edge gets its nodes once ([`edge_nodes`]): its two vertices, and nodes
//!    between them by arc length at the smaller element size of the faces that use
//!    it, closer where the edge curves so no chord sags more than the tolerance;
//! 3. every face must be bounded by an even number of nodes to be all quads; where
//!    one is not, a piece is added to an edge, chosen along a tree of the faces rooted
//!    outside the shell ([`even_loops`]), so each change mends one face and passes
//!    the odd count on towards the shell's free boundary (or to the tree's root face,
//!    which a closed group leaves even by itself);
//! 4. each face is meshed inside its loop of edge nodes, the nodes kept exactly as
//!    given ([`super::QuadOptions::keep_boundary`]) and the elements turned the way
//!    the shell is oriented;
//! 5. the faces' elements are joined on the shared node numbers.
//!
//! A face whose sections curve tighter than its element size allows (a step draw's
//! patch across its die radius) is a band ([`super::band`]): it places the nodes on its
//! own edges (rows spaced by the sections' curvature, columns by the size), is left out
//! of step 3's tree, and is meshed as mapped quads in step 4.

use glam::DVec3;
use rayon::prelude::*;

use super::band::{find_bands, Band};
use super::sizing::chord_measures;
use super::surface::{quad_mesh_surface, SurfaceMeshError, SurfaceMeshOptions, SurfaceRegion};
use crate::geom::curve::Curve3;
use crate::geom::mesh::{Face, Mesh};
use crate::geom::sew::Shell;

/// A shell meshed: the nodes and each face's elements on them.
#[derive(Debug, Clone, PartialEq)]
pub struct ShellMesh {
    /// Every node, the shell's vertices first, then the edges' inner nodes (edge by
    /// edge), then each face's inner nodes (face by face).
    pub positions: Vec<DVec3>,
    /// Each face's elements (in the shell's face order), numbered on `positions`,
    /// turned the way the shell is oriented.
    pub elements: Vec<Vec<Face>>,
    /// How many segments each edge of the shell was divided into: the same nodes on
    /// both faces of a seam.
    pub edge_segments: Vec<usize>,
}

impl ShellMesh {
    /// The elements of the faces `faces` as one mesh, keeping only the nodes they use
    /// (in the order of their first use), at exactly the shell mesh's positions: two
    /// such meshes meet on identical points where their faces share a seam.
    pub fn mesh_of(&self, faces: &[usize]) -> Result<Mesh, String> {
        let mut renumber = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        let mut out = Vec::new();
        for &f in faces {
            for e in self.elements.get(f).into_iter().flatten() {
                out.push(e.renumbered(|v| {
                    if renumber[v as usize] == u32::MAX {
                        renumber[v as usize] = positions.len() as u32;
                        positions.push(self.positions[v as usize]);
                    }
                    renumber[v as usize]
                }));
            }
        }
        Mesh::new(positions, out).map_err(|e| e.to_string())
    }

    /// All faces' elements as one mesh.
    pub fn whole(&self) -> Result<Mesh, String> {
        let all: Vec<usize> = (0..self.elements.len()).collect();
        self.mesh_of(&all)
    }
}

/// Why a shell could not be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShellMeshError {
    /// One face could not be meshed inside its seam nodes.
    #[error("face {face} (`{name}`): {error}")]
    Face {
        /// The face's index in the shell.
        face: usize,
        /// The face's name.
        name: String,
        /// Why.
        error: SurfaceMeshError,
    },
    /// An element size is not a positive length.
    #[error("face {face}: the element size must be above 0 mm, not {size} mm")]
    Size { face: usize, size: f64 },
    /// The faces would be meshed into more elements than the limit (estimated from
    /// the areas inside their seams, before any face is meshed).
    #[error("about {estimate} elements, more than the limit of {limit}")]
    TooMany { estimate: usize, limit: usize },
}

/// Meshes every face of `shell` with quads, face `f` at element size `sizes[f]`, so
/// that faces sharing an edge share its nodes. `options` gives the chordal tolerance,
/// corners, smoothing and the element limit (its size is ignored: `sizes` rules).
pub fn quad_mesh_shell(
    shell: &Shell,
    sizes: &[f64],
    options: &SurfaceMeshOptions,
) -> Result<ShellMesh, ShellMeshError> {
    for (face, &size) in sizes.iter().enumerate() {
        if !(size.is_finite() && size > 0.0) {
            return Err(ShellMeshError::Size { face, size });
        }
    }
    let size_of = |f: usize| sizes.get(f).copied().unwrap_or(options.quad.size);
    // Each edge at the finest size of the faces using it.
    let mut edge_size = vec![f64::INFINITY; shell.edges.len()];
    for (f, face) in shell.faces.iter().enumerate() {
        for &(e, _) in face.loop_edges() {
            edge_size[e] = edge_size[e].min(size_of(f));
        }
    }
    let tolerance = options.quad.chord_tolerance;
    let spacing: Vec<EdgeSpacing> = shell
        .edges
        .par_iter()
        .zip(&edge_size)
        .map(|(edge, &h)| EdgeSpacing::of(&edge.curve, h, tolerance))
        .collect();
    let mut segments: Vec<usize> = spacing.iter().map(|s| s.segments()).collect();
    // The faces meshed as bands of mapped quads place the nodes on their own edges.
    let face_sizes: Vec<f64> = (0..shell.faces.len()).map(size_of).collect();
    let mut bands = find_bands(shell, &face_sizes, tolerance, options.quad.max_elements);
    let mut band_of = vec![None; shell.faces.len()];
    for (i, band) in bands.iter().enumerate() {
        band_of[band.face] = Some(i);
    }
    let frozen: Vec<bool> = band_of.iter().map(Option::is_some).collect();
    let mut placed: Vec<Option<Vec<DVec3>>> = vec![None; shell.edges.len()];
    let place = |band: &Band, segments: &mut [usize], placed: &mut [Option<Vec<DVec3>>]| {
        for (e, nodes) in band.side_nodes(shell) {
            segments[e] = nodes.len() + 1;
            placed[e] = Some(nodes);
        }
    };
    for band in &bands {
        place(band, &mut segments, &mut placed);
    }
    // Every loop even: the faces round the bands by the tree, and a face the tree
    // cannot mend (closed in by bands, as the product is by the step draw) by one more
    // column of a band beside it, which passes the odd count across the band.
    for _ in 0..8 {
        even_loops_around(shell, &mut segments, &frozen);
        let odd = (0..shell.faces.len()).find(|&f| {
            !frozen[f]
                && shell.faces[f]
                    .loop_edges()
                    .map(|&(e, _)| segments[e])
                    .sum::<usize>()
                    % 2
                    == 1
        });
        let Some(f) = odd else { break };
        let beside = shell.faces[f]
            .loop_edges()
            .find_map(|&(e, _)| bands.iter().position(|b| b.on_long_side(shell, e)));
        let Some(i) = beside else { break };
        bands[i].add_column();
        place(&bands[i], &mut segments, &mut placed);
    }
    let seam_nodes: usize = segments.iter().sum();
    let limit = options.quad.max_elements;
    if seam_nodes > limit {
        return Err(ShellMeshError::TooMany {
            estimate: seam_nodes,
            limit,
        });
    }
    // The seam nodes: the vertices, then each edge's inner nodes.
    let mut positions = shell.vertices.clone();
    let mut edge_ids: Vec<Vec<u32>> = Vec::with_capacity(shell.edges.len());
    for (((edge, s), &n), placed) in shell.edges.iter().zip(&spacing).zip(&segments).zip(placed) {
        let mut ids = vec![edge.start as u32];
        let nodes = match placed {
            Some(nodes) => nodes,
            None => s.nodes(&edge.curve, n),
        };
        for p in nodes {
            ids.push(positions.len() as u32);
            positions.push(p);
        }
        ids.push(edge.end as u32);
        edge_ids.push(ids);
    }
    // Each face inside its loops of seam nodes: the outer loop, then its holes.
    let loop_ids = |l: &[(usize, bool)]| -> Vec<u32> {
        let mut ids = Vec::new();
        for &(e, forward) in l {
            let along = &edge_ids[e];
            if forward {
                ids.extend(&along[..along.len() - 1]);
            } else {
                ids.extend(along[1..].iter().rev());
            }
        }
        ids
    };
    let loops: Vec<Vec<Vec<u32>>> = shell
        .faces
        .iter()
        .map(|face| {
            std::iter::once(&face.bound)
                .chain(&face.holes)
                .map(|l| loop_ids(l))
                .collect()
        })
        .collect();
    // Each face's elements: the area inside its seam nodes (the polygons' vector
    // area, the holes running the other way; close to the surface's on a die face's
    // gently curved patches) over its size squared.
    let estimate: f64 = loops
        .iter()
        .enumerate()
        .map(|(f, face_loops)| {
            let area = face_loops
                .iter()
                .map(|ids| {
                    let p: Vec<DVec3> = ids.iter().map(|&v| positions[v as usize]).collect();
                    (0..p.len())
                        .map(|i| p[i].cross(p[(i + 1) % p.len()]))
                        .sum::<DVec3>()
                })
                .sum::<DVec3>()
                .length()
                * 0.5;
            area / (size_of(f) * size_of(f))
        })
        .sum();
    if estimate > limit as f64 {
        return Err(ShellMeshError::TooMany {
            estimate: estimate.ceil() as usize,
            limit,
        });
    }
    let meshed: Vec<Result<_, ShellMeshError>> = shell
        .faces
        .par_iter()
        .zip(&loops)
        .enumerate()
        .map(|(f, (face, face_loops))| {
            let mut face_options = options.clone();
            face_options.quad.size = size_of(f);
            face_options.quad.keep_boundary = true;
            let points = |ids: &Vec<u32>| ids.iter().map(|&v| positions[v as usize]).collect();
            if let Some(i) = band_of[f] {
                let boundary: Vec<DVec3> = points(&face_loops[0]);
                if let Some(mesh) = bands[i].mesh(shell, &segments, &boundary) {
                    return Ok(mesh);
                }
            }
            let region = SurfaceRegion {
                outer: Some(points(&face_loops[0])),
                holes: face_loops[1..].iter().map(points).collect(),
            };
            quad_mesh_surface(face.face.surface(), &region, &face_options)
                .map(|m| m.mesh)
                .map_err(|error| ShellMeshError::Face {
                    face: f,
                    name: face.face.name.clone(),
                    error,
                })
        })
        .collect();
    let mut elements = Vec::with_capacity(shell.faces.len());
    for ((face, face_loops), result) in shell.faces.iter().zip(&loops).zip(meshed) {
        let local = &result?;
        // Local boundary node k is the loops' k-th seam node (outer loop, then the
        // holes); the rest are new.
        let mut global: Vec<u32> = face_loops.concat();
        let ids = global.clone();
        for &p in &local.positions()[ids.len().min(local.vertex_count())..] {
            global.push(positions.len() as u32);
            positions.push(p);
        }
        let faces: Vec<Face> = local
            .faces()
            .iter()
            .map(|e| {
                let f = e.renumbered(|v| global[v as usize]);
                if face.reversed {
                    f.reversed()
                } else {
                    f
                }
            })
            .collect();
        elements.push(faces);
    }
    Ok(ShellMesh {
        positions,
        elements,
        edge_segments: segments,
    })
}

/// Makes every face's loop an even number of nodes (and at least four) by adding
/// pieces to edges: along a breadth-first tree of the faces rooted outside the shell
/// (a face on the free boundary hangs from one of its free edges), a face left odd
/// once its subtree is done takes one more piece on the edge to its parent, which
/// passes the odd count up; outside the shell absorbs it. A group of faces with no
/// free edge has a root face instead, left even by the others (the counts round a
/// closed group add up to an even number).
pub fn even_loops(shell: &Shell, segments: &mut [usize]) {
    even_loops_around(shell, segments, &vec![false; shell.faces.len()]);
}

/// [`even_loops`] over the faces not `frozen`: a frozen face (a band of mapped quads)
/// is left out of the tree and none of its edges takes a piece.
pub fn even_loops_around(shell: &Shell, segments: &mut [usize], frozen: &[bool]) {
    let uses = shell.edge_uses();
    let mut users: Vec<Vec<usize>> = vec![Vec::new(); shell.edges.len()];
    for (f, face) in shell.faces.iter().enumerate() {
        for &(e, _) in face.loop_edges() {
            users[e].push(f);
        }
    }
    let n = shell.faces.len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    let mut seen: Vec<bool> = (0..n)
        .map(|f| frozen.get(f).copied().unwrap_or(false))
        .collect();
    let mut order = Vec::with_capacity(n);
    let mut queue = std::collections::VecDeque::new();
    for (f, face) in shell.faces.iter().enumerate() {
        if seen[f] {
            continue;
        }
        if let Some(&(e, _)) = face.loop_edges().find(|(e, _)| uses[*e] == 1) {
            seen[f] = true;
            parent[f] = Some(e);
            queue.push_back(f);
        }
    }
    let mut next_root = 0;
    loop {
        while let Some(f) = queue.pop_front() {
            order.push(f);
            for &(e, _) in shell.faces[f].loop_edges() {
                for &g in &users[e] {
                    if !seen[g] {
                        seen[g] = true;
                        parent[g] = Some(e);
                        queue.push_back(g);
                    }
                }
            }
        }
        while next_root < n && seen[next_root] {
            next_root += 1;
        }
        if next_root == n {
            break;
        }
        seen[next_root] = true;
        queue.push_back(next_root);
    }
    let total = |f: usize, segments: &[usize]| -> usize {
        shell.faces[f].loop_edges().map(|&(e, _)| segments[e]).sum()
    };
    for &f in order.iter().rev() {
        if total(f, segments) % 2 == 1 {
            if let Some(e) = parent[f] {
                segments[e] += 1;
            }
        }
    }
    // A face of two one-piece edges: two more pieces on its longer side keep every
    // count's parity.
    let is_frozen = |f: usize| frozen.get(f).copied().unwrap_or(false);
    for f in 0..n {
        if !is_frozen(f) && total(f, segments) < 4 {
            if let Some(&(e, _)) = shell.faces[f]
                .loop_edges()
                .filter(|(e, _)| !users[*e].iter().any(|&g| is_frozen(g)))
                .max_by_key(|(e, _)| segments[*e])
            {
                segments[e] += 2;
            }
        }
    }
}

/// How nodes are spread along an edge: its curve sampled densely, with each sample
/// piece's share of the edge's element count.
struct EdgeSpacing {
    /// Parameters of the samples.
    params: Vec<f64>,
    /// Each sample piece's length over the spacing allowed there.
    measure: Vec<f64>,
}

impl EdgeSpacing {
    /// The spacing along `curve` at most `size` apart, closer where the curve turns so
    /// that a chord sags at most `tolerance` off it.
    fn of(curve: &Curve3, size: f64, tolerance: f64) -> EdgeSpacing {
        let (t0, t1) = curve.domain();
        let length = curve.length();
        // Samples at most a tenth of the size apart (and 32 at least).
        let n = ((10.0 * length / size).ceil() as usize).clamp(32, 20_000);
        let params: Vec<f64> = (0..=n)
            .map(|k| t0 + (t1 - t0) * k as f64 / n as f64)
            .collect();
        let points: Vec<DVec3> = params.iter().map(|&t| curve.point_at(t)).collect();
        let measure = chord_measures(&points, size, tolerance);
        EdgeSpacing { params, measure }
    }

    /// The pieces the edge is divided into before any is added for parity.
    fn segments(&self) -> usize {
        (self.measure.iter().sum::<f64>().round() as usize).max(1)
    }

    /// The `count - 1` inner nodes dividing the edge into `count` pieces of equal
    /// measure, each on the curve.
    fn nodes(&self, curve: &Curve3, count: usize) -> Vec<DVec3> {
        let total: f64 = self.measure.iter().sum();
        let mut out = Vec::with_capacity(count.saturating_sub(1));
        let (mut walked, mut seg) = (0.0, 0);
        for k in 1..count {
            let target = total * k as f64 / count as f64;
            while seg + 1 < self.measure.len() && walked + self.measure[seg] < target {
                walked += self.measure[seg];
                seg += 1;
            }
            let s = ((target - walked) / self.measure[seg].max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            let t = self.params[seg] + s * (self.params[seg + 1] - self.params[seg]);
            out.push(curve.point_at(t));
        }
        out
    }
}
