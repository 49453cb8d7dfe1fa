//! The die model tessellated: a scene of named nodes, what glTF and OBJ write.
//!
//! Each [`Part`] of the [`DieModel`] becomes a [`Node`] with the same name, kind,
//! colour, line and children; its shape becomes a primitive:
//!
//! * a surface: triangles within the chordal tolerance, with the surface normals;
//! * a trimmed surface (the product trimmed at its outline): the same, cut exactly at
//!   the outline (its boundary vertices are points of the outline);
//! * a mesh: its faces as triangles (quads split along the shorter diagonal), with its
//!   own normals or, when it has none, angle-weighted vertex normals;
//! * a curve: a line strip within the tolerance.
//!
//! A part whose tessellation is empty (a mesh without faces) gives no geometry, and a
//! node left with neither geometry nor children is dropped.
//!
//! [`SceneCache`] keeps tessellations between builds by the content of the geometry
//! ([`Fingerprint`]), so a rebuild after an edit re-tessellates only the pieces whose
//! geometry changed: what `dieface watch` uses.

use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;

pub use crate::die::model::LineBead;
use crate::die::model::{DieModel, Part, Shape};
use crate::geom::mesh::Mesh;
use crate::geom::tessellate::{
    tessellate_curve_within, tessellate_surface_within, tessellate_trimmed_within, SurfaceMesh,
    Tolerance, MAX_VERTICES,
};
use crate::geom::GeomError;

/// Tessellated declarations, in press coordinates (millimetres, Z up).
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Top-level nodes, one per exported declaration, in source order.
    pub nodes: Vec<Node>,
    /// The chordal tolerance the geometry was tessellated to, in millimetres.
    pub tolerance_mm: f64,
    /// The script's name as diagnostics show it (relative to the project root).
    pub source_name: String,
}

/// One exported declaration or one of its parts.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Full path name: `fender`, `bead_lines/0`, `pol/side-front`.
    pub name: String,
    /// The declaration's kind (`product`, `let`, `punch_opening`, ...); parts inherit it.
    pub kind: String,
    /// The kind's material colour (linear RGB).
    pub color: [f64; 3],
    /// 1-based source line of the declaration (or of the part's expression).
    pub line: usize,
    /// Parts of a list or a feature block.
    pub children: Vec<Node>,
    /// The node's own primitives (none for a pure group).
    pub geometry: Vec<Arc<Geometry>>,
    /// For a draw bead, its line bead for forming simulation (written to glTF extras).
    pub line_bead: Option<LineBead>,
}

/// A primitive, in press coordinates (millimetres).
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// Indexed triangles, counter-clockwise around their normals; unit normals per vertex.
    Triangles {
        /// Vertex positions.
        positions: Vec<DVec3>,
        /// Unit vertex normals, one per position.
        normals: Vec<DVec3>,
        /// Three indices per triangle.
        indices: Vec<u32>,
        /// Named sets of the triangles (a solid's faces, one group each), in order;
        /// empty when the piece has none.
        groups: Vec<TriangleGroup>,
    },
    /// A polyline through the points in order.
    LineStrip {
        /// The vertices (two or more).
        points: Vec<DVec3>,
    },
}

/// A named set of a primitive's triangles: one face of a solid, so that tools and
/// reviewers can pick it out (OBJ writes it as a group `g`, glTF as the primitive's
/// `extras.groups`).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleGroup {
    /// The name, as the kernel mesh's group has it.
    pub name: String,
    /// The triangles' numbers (index triple / 3), ascending.
    pub triangles: Vec<u32>,
}

impl TriangleGroup {
    /// The triangles as runs of consecutive numbers, each `[first, count]`.
    pub fn runs(&self) -> Vec<[u32; 2]> {
        let mut runs: Vec<[u32; 2]> = Vec::new();
        for &t in &self.triangles {
            match runs.last_mut() {
                Some([first, count]) if *first + *count == t => *count += 1,
                _ => runs.push([t, 1]),
            }
        }
        runs
    }
}

impl Geometry {
    /// Whether the primitive has nothing to draw (no triangle, fewer than two points).
    pub fn is_empty(&self) -> bool {
        match self {
            Geometry::Triangles {
                positions, indices, ..
            } => positions.is_empty() || indices.len() < 3,
            Geometry::LineStrip { points } => points.len() < 2,
        }
    }
}

impl Node {
    /// The node's own primitives that have something to draw (what an encoder writes).
    pub fn primitives(&self) -> Vec<&Geometry> {
        self.geometry
            .iter()
            .map(|g| &**g)
            .filter(|g| !g.is_empty())
            .collect()
    }

    /// The node's own triangles, as corner positions (indices past the positions are
    /// skipped): what a distance between two tessellations is measured on.
    pub fn triangles(&self) -> Vec<[DVec3; 3]> {
        let mut out = Vec::new();
        for g in &self.geometry {
            if let Geometry::Triangles {
                positions, indices, ..
            } = g.as_ref()
            {
                let corner = |k: u32| positions.get(k as usize).copied();
                out.extend(
                    indices
                        .chunks_exact(3)
                        .filter_map(|t| Some([corner(t[0])?, corner(t[1])?, corner(t[2])?])),
                );
            }
        }
        out
    }

    /// This node and all its descendants, depth first, parents before children.
    pub fn walk(&self) -> Vec<&Node> {
        let mut out = vec![self];
        for c in &self.children {
            out.extend(c.walk());
        }
        out
    }
}

impl Scene {
    /// Every node of the scene, depth first in source order, parents before children.
    pub fn all_nodes(&self) -> Vec<&Node> {
        self.nodes.iter().flat_map(Node::walk).collect()
    }

    /// The node with the full path name `name`.
    pub fn find(&self, name: &str) -> Option<&Node> {
        self.all_nodes().into_iter().find(|n| n.name == name)
    }
}

/// A piece that could not be tessellated within the tolerance (a tolerance far too fine
/// for the geometry).
#[derive(Debug, Clone, PartialEq)]
pub struct TessellationError {
    /// The part's full name (`binder/front`): its first segment is the declaration.
    pub part: String,
    /// The part's source line.
    pub line: usize,
    /// What the kernel said.
    pub error: GeomError,
}

impl fmt::Display for TessellationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}` cannot be tessellated: {}", self.part, self.error)
    }
}

/// Tessellates every part of the model into a node (press coordinates, mm).
pub fn build_scene(model: &DieModel, tol: &Tolerance) -> Result<Scene, TessellationError> {
    SceneCache::default().build(model, tol)
}

/// Tessellations kept between builds, so a rebuild after an edit re-tessellates only
/// the geometry that changed: what `dieface watch` uses.
///
/// Geometry is recognised by its content: the cache keys each tessellation on the
/// geometry's [`Fingerprint`] and keeps the geometry beside it, and reuses the
/// tessellation only when the new geometry is equal to the kept one. So a piece that a
/// rebuilt feature made again bit for bit is not tessellated again, and a fingerprint
/// collision costs a tessellation, never a wrong mesh. Entries not used by a build are
/// dropped after it, and a change of tolerance empties the cache.
#[derive(Default)]
pub struct SceneCache {
    tolerance: Option<(u64, u64)>,
    entries: HashMap<u64, Entry>,
    /// The fingerprint of each cached shape by the address of its shared geometry: a
    /// declaration the engine did not re-evaluate hands back the very same geometry,
    /// found here without hashing it again. The entry holds that geometry, so the
    /// address cannot be reused by another while it is listed.
    by_address: HashMap<usize, u64>,
    misses: usize,
    /// Most points of one curve's line strip (`None`: the kernel's own limit); the
    /// pipeline sets the `samples` limit here.
    max_curve_points: Option<usize>,
    /// Most vertices of one surface's mesh (`None`: the kernel's own limit); the
    /// pipeline sets the `mesh_vertices` limit here.
    max_mesh_vertices: Option<usize>,
}

/// One cached tessellation: the shape it was made from, the primitive, and whether the
/// current build used it.
struct Entry {
    shape: Shape,
    geometry: Arc<Geometry>,
    used: bool,
}

impl SceneCache {
    /// Limits the points of each curve's line strip (the `samples` limit): a curve
    /// that needs more fails with
    /// [`crate::geom::tessellate::CURVE_POINT_LIMIT`]. A new limit empties the cache.
    pub fn set_max_curve_points(&mut self, max: usize) {
        if self.max_curve_points != Some(max) {
            self.max_curve_points = Some(max);
            self.entries.clear();
            self.by_address.clear();
        }
    }

    /// Limits the vertices of each surface's mesh (the `mesh_vertices` limit): a surface
    /// that needs more fails with
    /// [`crate::geom::tessellate::SURFACE_VERTEX_LIMIT`]. A new limit empties the cache.
    pub fn set_max_mesh_vertices(&mut self, max: usize) {
        if self.max_mesh_vertices != Some(max) {
            self.max_mesh_vertices = Some(max);
            self.entries.clear();
            self.by_address.clear();
        }
    }

    /// Builds the scene like [`build_scene`], reusing cached tessellations.
    ///
    /// Three passes: every shape is looked up in the cache (in part order), the shapes
    /// not found are tessellated in parallel (each on its own, so the meshes do not
    /// depend on the number of threads), and the nodes are put together. When several
    /// pieces fail, the error is the first part's in model order.
    pub fn build(&mut self, model: &DieModel, tol: &Tolerance) -> Result<Scene, TessellationError> {
        let key = (tol.chordal.to_bits(), tol.angle.to_bits());
        let max_points = self.max_curve_points.unwrap_or(MAX_VERTICES);
        let max_vertices = self.max_mesh_vertices.unwrap_or(MAX_VERTICES);
        if self.tolerance != Some(key) {
            self.entries.clear();
            self.by_address.clear();
            self.tolerance = Some(key);
        }
        for entry in self.entries.values_mut() {
            entry.used = false;
        }
        let mut found = HashMap::new();
        let mut missing = Missing::default();
        for part in &model.parts {
            self.look_up(part, &mut found, &mut missing);
        }
        let Missing { unique, all, .. } = missing;
        let missing = unique;
        self.misses = missing.len();
        let made: Vec<Result<Geometry, GeomError>> = missing
            .par_iter()
            .map(|(_, _, shape)| tessellate(shape, tol, (max_points, max_vertices)))
            .collect();
        let mut made_here = Vec::with_capacity(made.len());
        for ((key, part, shape), geometry) in missing.into_iter().zip(made) {
            let geometry = Arc::new(geometry.map_err(|error| TessellationError {
                part: part.name.clone(),
                line: part.line,
                error,
            })?);
            made_here.push(geometry.clone());
            self.by_address.insert(address(shape), key);
            self.entries.insert(
                key,
                Entry {
                    shape: shape.clone(),
                    geometry,
                    used: true,
                },
            );
        }
        for (at, k) in all {
            found.insert(at, made_here[k].clone());
        }
        let nodes = model
            .parts
            .iter()
            .filter_map(|part| node(part, &found))
            .collect();
        self.entries.retain(|_, e| e.used);
        let entries = &self.entries;
        self.by_address.retain(|_, key| entries.contains_key(key));
        Ok(Scene {
            nodes,
            tolerance_mm: tol.chordal,
            source_name: model.source_name.clone(),
        })
    }

    /// How many tessellations are cached.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// How many pieces the last build tessellated (not found in the cache).
    pub fn last_misses(&self) -> usize {
        self.misses
    }

    /// Looks up the shapes of `part` and its children: those in the cache go into
    /// `found` by address, the others into `missing`.
    fn look_up<'m>(
        &mut self,
        part: &'m Part,
        found: &mut HashMap<usize, Arc<Geometry>>,
        missing: &mut Missing<'m>,
    ) {
        if let Some(shape) = &part.shape {
            let at = address(shape);
            if !found.contains_key(&at) && !missing.has(at) {
                match self.cached(shape) {
                    Ok(geometry) => {
                        found.insert(at, geometry);
                    }
                    Err(key) => missing.add(key, part, shape),
                }
            }
        }
        for child in &part.children {
            self.look_up(child, found, missing);
        }
    }

    /// The cached primitive of a shape (marked used), or the shape's fingerprint when
    /// it is not cached.
    fn cached(&mut self, shape: &Shape) -> Result<Arc<Geometry>, u64> {
        // The same shared geometry as a cached entry: no hashing needed.
        if let Some(key) = self.by_address.get(&address(shape)) {
            if let Some(entry) = self.entries.get_mut(key) {
                if same(&entry.shape, shape) {
                    entry.used = true;
                    return Ok(entry.geometry.clone());
                }
            }
        }
        let key = shape.fingerprint();
        match self.entries.get_mut(&key) {
            Some(entry) if same(&entry.shape, shape) => {
                entry.used = true;
                Ok(entry.geometry.clone())
            }
            _ => Err(key),
        }
    }
}

/// The shapes of a build not found in the cache.
#[derive(Default)]
struct Missing<'m> {
    /// One shape per content, with its fingerprint and the first part that holds it:
    /// what is tessellated.
    unique: Vec<(u64, &'m Part, &'m Shape)>,
    /// The indices into `unique` of each fingerprint's shapes.
    by_key: HashMap<u64, Vec<usize>>,
    /// Every missing shape's address, with the index of its content in `unique`.
    all: HashMap<usize, usize>,
}

impl<'m> Missing<'m> {
    /// Whether the shape at address `at` is already noted.
    fn has(&self, at: usize) -> bool {
        self.all.contains_key(&at)
    }

    /// Notes a shape not in the cache, tessellated once however many parts hold it.
    fn add(&mut self, key: u64, part: &'m Part, shape: &'m Shape) {
        let same_key = self.by_key.entry(key).or_default();
        let k = match same_key
            .iter()
            .copied()
            .find(|&k| same(self.unique[k].2, shape))
        {
            Some(k) => k,
            None => {
                self.unique.push((key, part, shape));
                same_key.push(self.unique.len() - 1);
                self.unique.len() - 1
            }
        };
        self.all.insert(address(shape), k);
    }
}

/// The node of one part, with its primitive from `found` (by the address of its
/// shape), or `None` when it holds nothing to draw.
fn node(part: &Part, found: &HashMap<usize, Arc<Geometry>>) -> Option<Node> {
    let mut out = Node {
        name: part.name.clone(),
        kind: part.kind.clone(),
        color: part.color,
        line: part.line,
        children: Vec::new(),
        geometry: Vec::new(),
        line_bead: part.line_bead.clone(),
    };
    if let Some(g) = part.shape.as_ref().and_then(|s| found.get(&address(s))) {
        if !g.is_empty() {
            out.geometry.push(g.clone());
        }
    }
    out.children = part
        .children
        .iter()
        .filter_map(|child| node(child, found))
        .collect();
    if out.geometry.is_empty() && out.children.is_empty() {
        return None;
    }
    Some(out)
}

/// The address of a shape's shared geometry.
fn address(shape: &Shape) -> usize {
    match shape {
        Shape::Surface(s) => Arc::as_ptr(s) as *const () as usize,
        Shape::Trimmed(t) => Arc::as_ptr(t) as *const () as usize,
        Shape::Mesh(m) => Arc::as_ptr(m) as *const () as usize,
        Shape::Curve(c) => Arc::as_ptr(c) as *const () as usize,
    }
}

/// Whether two shapes are the same geometry (the same object, or equal content).
fn same(a: &Shape, b: &Shape) -> bool {
    match (a, b) {
        (Shape::Surface(a), Shape::Surface(b)) => Arc::ptr_eq(a, b) || a == b,
        (Shape::Trimmed(a), Shape::Trimmed(b)) => Arc::ptr_eq(a, b) || a == b,
        (Shape::Mesh(a), Shape::Mesh(b)) => Arc::ptr_eq(a, b) || a == b,
        (Shape::Curve(a), Shape::Curve(b)) => Arc::ptr_eq(a, b) || a == b,
        _ => false,
    }
}

/// Tessellates one shape within the tolerance, a curve in at most `max_points` points.
fn tessellate(
    shape: &Shape,
    tol: &Tolerance,
    (max_points, max_vertices): (usize, usize),
) -> Result<Geometry, GeomError> {
    Ok(match shape {
        Shape::Surface(s) => surface_triangles(tessellate_surface_within(s, tol, max_vertices)?),
        Shape::Trimmed(t) => surface_triangles(tessellate_trimmed_within(t, tol, max_vertices)?),
        Shape::Mesh(m) => mesh_triangles(m),
        Shape::Curve(c) => Geometry::LineStrip {
            points: tessellate_curve_within(c, tol, max_points)?.points,
        },
    })
}

/// A surface tessellation as triangles with unit normals.
fn surface_triangles(mesh: SurfaceMesh) -> Geometry {
    let normals = mesh
        .normals
        .iter()
        .map(|n| n.try_normalize().unwrap_or(DVec3::Z))
        .collect();
    let indices = mesh.triangles.iter().flatten().copied().collect();
    Geometry::Triangles {
        positions: mesh.positions,
        normals,
        indices,
        groups: Vec::new(),
    }
}

/// A kernel mesh as triangles with unit normals: quads split, the mesh's own normals
/// normalised (computed ones where it has none or one is zero).
/// The name of the triangle group that holds a mesh's quads, each as its two
/// consecutive triangles (glTF `extras.groups`, OBJ group).
pub const QUADS_GROUP: &str = "quads";

fn mesh_triangles(m: &Mesh) -> Geometry {
    let (tri, origin) = m.triangulated_with_map();
    let computed = tri.compute_vertex_normals();
    let normals = match tri.normals() {
        Some(given) => given
            .iter()
            .zip(&computed)
            .map(|(g, c)| g.try_normalize().unwrap_or(*c))
            .collect::<Vec<_>>(),
        None => computed,
    };
    // A vertex used only by degenerate faces (or by none) has no normal: any unit vector
    // will do, and +Z (press up) is what a die face mostly faces.
    let normals = normals
        .into_iter()
        .map(|n| n.try_normalize().unwrap_or(DVec3::Z))
        .collect();
    let indices = tri
        .faces()
        .iter()
        .flat_map(|f| f.indices().to_vec())
        .collect();
    // `triangulated` keeps each group on the triangles its faces became.
    let mut groups: Vec<TriangleGroup> = tri
        .groups()
        .iter()
        .map(|g| TriangleGroup {
            name: g.name().to_string(),
            triangles: g.faces().iter().map(|f| f.0).collect(),
        })
        .collect();
    // A shell mesh's quad structure, for viewers and reviewers: the triangles each quad
    // became, its two consecutive ones (a quad too flat to split keeps one).
    if m.faces().iter().any(|f| f.is_quad()) {
        groups.push(TriangleGroup {
            name: QUADS_GROUP.to_string(),
            triangles: (0..origin.len() as u32)
                .filter(|&t| m.faces()[origin[t as usize].0 as usize].is_quad())
                .collect(),
        });
    }
    Geometry::Triangles {
        positions: tri.positions().to_vec(),
        normals,
        indices,
        groups,
    }
}
