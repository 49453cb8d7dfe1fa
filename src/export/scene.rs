//! Declarations to a scene of named, tessellated nodes.
//!
//! What becomes a node (everything else, numbers, strings, points, functions, is not
//! exported):
//!
//! * a surface: triangles within the chordal tolerance, with the surface normals;
//! * a trimmed surface (the product trimmed at its outline): the same, cut exactly at
//!   the outline (its boundary vertices are points of the outline);
//! * a mesh: its faces as triangles (quads split along the shorter diagonal), with its
//!   own normals or, when it has none, angle-weighted vertex normals;
//! * a 3-D curve, a sketch (placed in its view) or a 2-D curve (at z = 0): a line strip
//!   within the tolerance;
//! * a list: one child per geometric element, named `name/0`, `name/1`, ... by the
//!   element's index in the list (so names stay stable when a non-geometric element sits
//!   in between). Children rather than one node with several primitives, so every part
//!   can be picked, hidden and traced on its own in a viewer;
//! * a record (a nested block or a record literal): one child per geometric field, named
//!   `rec/side-front` (the words of a field name joined by `-`);
//! * a feature (`punch_opening opening { ... }`, `blankholder binder { ... }`): one child
//!   per piece, `opening/front`, `opening/front_nose`, `binder/front`; the opening's
//!   closed `line` is not repeated, its pieces are the line.
//!
//! A top-level `let` whose surface a `product` trims (`let panel = ...`,
//! `product fender = trim(panel, outline)`) is not exported: the product is that panel,
//! cut at its outline.
//!
//! Node names are full paths from the declaration (`pol/side-front`, `bead_lines/1`), so
//! they are unique in the scene and an OBJ group keeps the nesting. Children carry the
//! declaration's kind (so a feature's parts share its material) and the line of the
//! expression that made them when it lies inside the declaration, else the
//! declaration's line. A list or record without any geometry gives no node, and a part
//! whose tessellation is empty (a mesh without faces) gives no geometry.

use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::Arc;

use glam::DVec3;

use crate::diag::{Diagnostic, Sources};
use crate::die::bead::Bead;
use crate::eval::value::{Data, Feature, Record, Value};
use crate::eval::Outcome;
use crate::geom::mesh::Mesh;
use crate::geom::tessellate::{
    tessellate_curve, tessellate_surface, tessellate_trimmed, SurfaceMesh, Tolerance,
};
use crate::geom::{Curve3, GeomError};
use crate::syntax::Span;

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
    /// 1-based source line of the declaration (or of the part's expression).
    pub line: usize,
    /// Parts of a list or a feature block.
    pub children: Vec<Node>,
    /// The node's own primitives (none for a pure group).
    pub geometry: Vec<Geometry>,
    /// For a draw bead, its line bead for forming simulation (written to glTF extras).
    pub line_bead: Option<LineBead>,
}

/// A line bead: the bead's centre line on the binder as points every `spacing`, with
/// the restraining force a forming simulation applies along it (LS-DYNA
/// `*CONTACT_DRAWBEAD`-style).
#[derive(Debug, Clone, PartialEq)]
pub struct LineBead {
    /// Points in press coordinates (mm).
    pub points: Vec<DVec3>,
    /// Distance between the points along the line (mm).
    pub spacing: f64,
    /// Restraining force per unit length (N/mm), if the script gives one.
    pub force: Option<f64>,
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
    },
    /// A polyline through the points in order.
    LineStrip {
        /// The vertices (two or more).
        points: Vec<DVec3>,
    },
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

/// Tessellates every declaration whose value is geometry into a node (press coordinates,
/// mm).
///
/// Declarations that failed (no value) are skipped: reporting them is the caller's job.
/// A tessellation failure (a tolerance far too fine for the geometry) is a
/// `die::geometry` diagnostic at the declaration.
pub fn build_scene(
    outcome: &Outcome,
    sources: &Sources,
    tol: &Tolerance,
) -> Result<Scene, Diagnostic> {
    build_with_cache(outcome, sources, tol, None)
}

/// Tessellations kept between builds, so a rebuild after an edit re-tessellates only
/// the geometry that changed: what `dieface watch` uses with one long-lived engine.
///
/// Geometry is recognised by identity: the engine's memo hands back the very same
/// shared surface, mesh or curve for a declaration it did not re-evaluate, and the
/// cache holds a reference to each one it stores, so an address cannot be reused by new
/// geometry while its entry lives. Entries not used by a build are dropped after it, and
/// a change of tolerance empties the cache.
#[derive(Default)]
pub struct SceneCache {
    tolerance: Option<(u64, u64)>,
    entries: RefCell<HashMap<usize, (Data, Geometry, bool)>>,
}

impl SceneCache {
    /// Builds the scene like [`build_scene`], reusing cached tessellations.
    pub fn build(
        &mut self,
        outcome: &Outcome,
        sources: &Sources,
        tol: &Tolerance,
    ) -> Result<Scene, Diagnostic> {
        let key = (tol.chordal.to_bits(), tol.angle.to_bits());
        if self.tolerance != Some(key) {
            self.entries.get_mut().clear();
            self.tolerance = Some(key);
        }
        for entry in self.entries.get_mut().values_mut() {
            entry.2 = false;
        }
        let scene = build_with_cache(outcome, sources, tol, Some(&self.entries));
        self.entries.get_mut().retain(|_, e| e.2);
        scene
    }

    /// How many tessellations are cached.
    pub fn len(&self) -> usize {
        self.entries.borrow().len()
    }

    /// Whether nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

type Cache = RefCell<HashMap<usize, (Data, Geometry, bool)>>;

/// The address that identifies shared geometry, for the cache.
fn identity(data: &Data) -> Option<usize> {
    match data {
        Data::Surface(s) => Some(Arc::as_ptr(s) as *const () as usize),
        Data::Trimmed(t) => Some(Arc::as_ptr(t) as *const () as usize),
        Data::Mesh(m) => Some(Arc::as_ptr(m) as *const () as usize),
        Data::Curve3(c) => Some(Arc::as_ptr(c) as *const () as usize),
        Data::Curve2(c) => Some(Arc::as_ptr(c) as *const () as usize),
        Data::Sketch(s) => Some(Arc::as_ptr(s) as *const () as usize),
        _ => None,
    }
}

fn build_with_cache(
    outcome: &Outcome,
    sources: &Sources,
    tol: &Tolerance,
    cache: Option<&Cache>,
) -> Result<Scene, Diagnostic> {
    let source_name = sources
        .get(outcome.file)
        .map_or_else(String::new, |f| f.name.clone());
    let trimmed = trimmed_panels(outcome);
    let mut nodes = Vec::new();
    for d in &outcome.decls {
        let Some(value) = &d.value else { continue };
        if d.kind == "let" && matches!(&value.data, Data::Surface(s) if trimmed.contains(&&**s)) {
            continue;
        }
        let ctx = Ctx {
            sources,
            tol,
            cache,
            kind: &d.kind,
            decl: &d.name,
            decl_span: d.span,
            decl_line: sources.line_col(d.span).0,
        };
        if let Some(node) = ctx.node(d.name.clone(), value)? {
            nodes.push(node);
        }
    }
    Ok(Scene {
        nodes,
        tolerance_mm: tol.chordal,
        source_name,
    })
}

/// The untrimmed surfaces of the products trimmed at their outline: a `let` holding
/// one of them is the panel the product was cut from, and exporting it too would put
/// the untrimmed product back over the step draw.
fn trimmed_panels(outcome: &Outcome) -> Vec<&crate::geom::NurbsSurface> {
    let mut out = Vec::new();
    for d in outcome.decls.iter().filter(|d| d.kind == "product") {
        let Some(value) = &d.value else { continue };
        let items: Vec<&Value> = match &value.data {
            Data::List(items) => items.iter().collect(),
            _ => vec![value],
        };
        for v in items {
            if let Data::Trimmed(t) = &v.data {
                out.push(t.surface());
            }
        }
    }
    out
}

/// What every node of one declaration shares.
struct Ctx<'a> {
    sources: &'a Sources,
    tol: &'a Tolerance,
    cache: Option<&'a Cache>,
    kind: &'a str,
    decl: &'a str,
    decl_span: Span,
    decl_line: usize,
}

impl Ctx<'_> {
    /// The node for `value` named `name`, or `None` when it holds no geometry.
    fn node(&self, name: String, value: &Value) -> Result<Option<Node>, Diagnostic> {
        let mut node = Node {
            name,
            kind: self.kind.to_string(),
            line: self.line_of(value.span),
            children: Vec::new(),
            geometry: Vec::new(),
            line_bead: None,
        };
        if let (Some(cache), Some(id)) = (self.cache, identity(&value.data)) {
            if let Some(entry) = cache.borrow_mut().get_mut(&id) {
                entry.2 = true;
                node.geometry.push(entry.1.clone());
                node.geometry.retain(|g| !g.is_empty());
                return Ok((!node.geometry.is_empty()).then_some(node));
            }
        }
        match &value.data {
            Data::Surface(s) => {
                let mesh = tessellate_surface(s, self.tol).map_err(|e| self.error(value, e))?;
                node.geometry.push(surface_triangles(mesh));
            }
            Data::Trimmed(t) => {
                let mesh = tessellate_trimmed(t, self.tol).map_err(|e| self.error(value, e))?;
                node.geometry.push(surface_triangles(mesh));
            }
            Data::Mesh(m) => node.geometry.push(mesh_triangles(m)),
            Data::Curve3(c) => node.geometry.push(self.line_strip(c, value)?),
            Data::Curve2(c) => {
                let c3 = c.map_points(|p| p.extend(0.0));
                node.geometry.push(self.line_strip(&c3, value)?);
            }
            Data::Sketch(s) => node.geometry.push(self.line_strip(&s.to_3d(), value)?),
            Data::List(items) => {
                for (i, item) in items.iter().enumerate() {
                    if let Some(child) = self.node(format!("{}/{i}", node.name), item)? {
                        node.children.push(child);
                    }
                }
            }
            Data::Record(r) => {
                if let Some(Feature::Bead(b)) = &r.feature {
                    node.line_bead = Some(line_bead(b, r));
                }
                for (field, v) in &r.fields {
                    if r.feature.as_ref().is_some_and(|f| !f.exports_field(field)) {
                        continue;
                    }
                    let part = field.split_whitespace().collect::<Vec<_>>().join("-");
                    if let Some(child) = self.node(format!("{}/{part}", node.name), v)? {
                        node.children.push(child);
                    }
                }
            }
            _ => return Ok(None),
        }
        if let (Some(cache), Some(id), Some(g)) =
            (self.cache, identity(&value.data), node.geometry.first())
        {
            cache
                .borrow_mut()
                .insert(id, (value.data.clone(), g.clone(), true));
        }
        node.geometry.retain(|g| !g.is_empty());
        if node.geometry.is_empty() && node.children.is_empty() {
            return Ok(None);
        }
        Ok(Some(node))
    }

    /// The line of `span` when it lies in the declaration, else the declaration's line.
    fn line_of(&self, span: Span) -> usize {
        let d = self.decl_span;
        if span.file == d.file && span.start >= d.start && span.end <= d.end {
            self.sources.line_col(span).0
        } else {
            self.decl_line
        }
    }

    fn line_strip(&self, curve: &Curve3, value: &Value) -> Result<Geometry, Diagnostic> {
        let line = tessellate_curve(curve, self.tol).map_err(|e| self.error(value, e))?;
        Ok(Geometry::LineStrip {
            points: line.points,
        })
    }

    fn error(&self, value: &Value, err: GeomError) -> Diagnostic {
        Diagnostic::new(
            "die::geometry",
            format!(
                "`{}` cannot be tessellated for export within {} mm: {err}",
                self.decl, self.tol.chordal
            ),
            value.span,
            "this geometry",
        )
        .with_label(self.decl_span, "in this declaration")
        .with_help("use a coarser tolerance (`--tolerance`), e.g. 0.01mm or 0.05mm")
    }
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
    }
}

/// A kernel mesh as triangles with unit normals: quads split, the mesh's own normals
/// normalised (computed ones where it has none or one is zero).
fn mesh_triangles(m: &Mesh) -> Geometry {
    let tri = m.triangulated();
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
    Geometry::Triangles {
        positions: tri.positions().to_vec(),
        normals,
        indices,
    }
}

/// The line bead of a bead feature's record: its points, and the spacing and force the
/// record's `line_bead` field holds.
fn line_bead(bead: &Bead, r: &Record) -> LineBead {
    let number = |name: &str| -> Option<f64> {
        let Some(Value {
            data: Data::Record(lb),
            ..
        }) = r.get("line_bead")
        else {
            return None;
        };
        match lb.get(name).map(|v| &v.data) {
            Some(Data::Number(q)) => Some(q.value),
            _ => None,
        }
    };
    LineBead {
        points: bead.line_points.clone(),
        spacing: number("spacing").unwrap_or(0.0),
        force: number("force"),
    }
}
