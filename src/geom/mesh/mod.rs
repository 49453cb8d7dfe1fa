//! Indexed polygon meshes of triangles and quads, and their half-edge topology.
//!
//! A die face is modelled with NURBS, but several later steps work on meshes: rolling-
//! ball rounding of die shoulders on shell meshes, filling holes bounded by free edges,
//! quad meshing, and sheet modelling where three or more sheets meet at one edge. This
//! module is their common ground:
//!
//! * [`Mesh`] holds the data: `f64` positions, faces (each a [`Face`], a triangle or a
//!   quad, wound counter-clockwise around its normal), optional per-vertex normals and
//!   named [`Group`]s of faces. It validates its input once, in [`Mesh::new`], so every
//!   later step can rely on in-range indices, distinct corners and finite coordinates.
//! * [`Topology`] is the connectivity built from a mesh: one half-edge per face side,
//!   undirected edges with their radial list of half-edges (so non-manifold edges shared
//!   by three or more faces are represented, not rejected), vertex stars, free edges
//!   chained into [`BoundaryLoops`], dihedral angles, orientation checks and connected
//!   components.
//! * [`curvature`] reads each node's curvature off a quadric fitted to its neighbours
//!   (paper 000, section 4), to find the rounds a mesh already has.
//!
//! Everything is deterministic: the same input gives the same ids and the same order of
//! every output list. Nothing panics on any mesh data; invalid input is a
//! [`GeomError`].

mod boundary;
pub mod box_grid;
mod crossing;
pub mod curvature;
pub mod distance;
pub mod holes;
mod ids;
pub mod obj;
mod ops;
pub mod quad;
pub mod rounding;
pub mod stars;
mod topology;

pub use boundary::{BoundaryChain, BoundaryLoops};
pub use crossing::{crossings, Crossing};
pub use ids::{EdgeId, FaceId, HalfEdgeId, VertexId};
pub use topology::{HalfEdge, Topology};

use crate::geom::error::{GeomError, Result};
use glam::DVec3;
use ids::to_u32;

/// The largest number of vertices a mesh may have: vertex ids are `u32`.
pub const MAX_VERTICES: usize = u32::MAX as usize;

/// The largest number of faces a mesh may have: every face side becomes a half-edge
/// with a `u32` id, and a face has up to four sides.
pub const MAX_FACES: usize = (u32::MAX / 4) as usize;

/// One face of a [`Mesh`]: a triangle or a quad, given by vertex indices in winding
/// order (counter-clockwise when seen from the side the normal points to).
///
/// Stored inline (no allocation per face). A `Face` on its own is not checked; the mesh
/// checks it against its vertices in [`Mesh::new`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Face {
    /// Corner vertex indices; only the first `len` are meaningful, the rest are zero so
    /// that derived equality and hashing see equal faces as equal.
    verts: [u32; 4],
    /// 3 or 4.
    len: u8,
}

impl Face {
    /// A triangle with corners `a`, `b`, `c` in winding order.
    pub fn triangle(a: u32, b: u32, c: u32) -> Face {
        Face {
            verts: [a, b, c, 0],
            len: 3,
        }
    }

    /// A quad with corners `a`, `b`, `c`, `d` in winding order.
    pub fn quad(a: u32, b: u32, c: u32, d: u32) -> Face {
        Face {
            verts: [a, b, c, d],
            len: 4,
        }
    }

    /// A face from 3 or 4 indices, for readers of polygon files; other lengths are an
    /// [`GeomError::InvalidMesh`] (polygons with more sides must be split first).
    pub fn from_slice(indices: &[u32]) -> Result<Face> {
        match *indices {
            [a, b, c] => Ok(Face::triangle(a, b, c)),
            [a, b, c, d] => Ok(Face::quad(a, b, c, d)),
            _ => Err(GeomError::InvalidMesh {
                reason: format!("a face needs 3 or 4 vertices, got {}", indices.len()),
            }),
        }
    }

    /// The corner indices in winding order (3 or 4 of them).
    pub fn indices(&self) -> &[u32] {
        &self.verts[..self.len as usize]
    }

    /// The corners as typed vertex ids, in winding order.
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        self.indices().iter().map(|&v| VertexId(v))
    }

    /// Corner `i` (0-based, in winding order), or `None` past the last corner.
    pub fn vertex(&self, i: usize) -> Option<VertexId> {
        self.indices().get(i).map(|&v| VertexId(v))
    }

    /// Number of corners: 3 or 4.
    pub fn vertex_count(&self) -> usize {
        self.len as usize
    }

    /// Whether the face is a triangle.
    pub fn is_triangle(&self) -> bool {
        self.len == 3
    }

    /// Whether the face is a quad.
    pub fn is_quad(&self) -> bool {
        self.len == 4
    }

    /// The directed sides `(from, to)` in winding order; side `i` runs from corner `i`
    /// to corner `i + 1` (cyclically). These become the face's half-edges.
    pub fn sides(&self) -> impl Iterator<Item = (VertexId, VertexId)> + '_ {
        let v = self.indices();
        let n = v.len();
        (0..n).map(move |i| (VertexId(v[i]), VertexId(v[(i + 1) % n])))
    }

    /// The same face with each corner's index mapped by `new_index`, its corners in the
    /// same order: a face moved into another mesh's numbering without a list made per
    /// face (assembling a die face's mesh renumbers hundreds of thousands).
    pub fn renumbered(&self, mut new_index: impl FnMut(u32) -> u32) -> Face {
        let mut face = *self;
        for v in &mut face.verts[..face.len as usize] {
            *v = new_index(*v);
        }
        face
    }

    /// The same face wound the other way (its normal flipped). Corner 0 stays first.
    pub fn reversed(&self) -> Face {
        match *self.indices() {
            [a, b, c, d] => Face::quad(a, d, c, b),
            [a, b, c] => Face::triangle(a, c, b),
            // `len` is always 3 or 4: the constructors are the only way to make a Face.
            _ => *self,
        }
    }

    /// The two triangles this face splits into, as corner positions (`0, 1, 2` of the
    /// face) in winding order. A triangle yields itself and `None`; a quad is split
    /// along its shorter diagonal (ties: diagonal 0–2), the rule shared by
    /// [`Mesh::face_area`] and [`Mesh::triangulated`] so both agree.
    pub(crate) fn split_corners(&self, p: &[DVec3; 4]) -> ([usize; 3], Option<[usize; 3]>) {
        if self.is_triangle() {
            return ([0, 1, 2], None);
        }
        if p[0].distance_squared(p[2]) <= p[1].distance_squared(p[3]) {
            ([0, 1, 2], Some([0, 2, 3]))
        } else {
            ([1, 2, 3], Some([1, 3, 0]))
        }
    }
}

/// A named set of faces, e.g. "binder", "punch opening", "addendum": how the language
/// layer tags which part of the die face a mesh region came from.
///
/// Faces are kept sorted and without duplicates, so a group is a set.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Group {
    name: String,
    faces: Vec<FaceId>,
}

impl Group {
    /// The group's name, unique within its mesh.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The group's faces, sorted ascending.
    pub fn faces(&self) -> &[FaceId] {
        &self.faces
    }
}

/// An indexed mesh of triangles and quads with `f64` positions.
///
/// Invariants, established by [`Mesh::new`] and kept by every method: every face index
/// is in range, no face repeats a vertex, every coordinate (and normal) is finite, the
/// normals (if any) number one per vertex, group faces are in range and group names are
/// unique. Vertices not used by any face are allowed (they are simply isolated).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    positions: Vec<DVec3>,
    faces: Vec<Face>,
    normals: Option<Vec<DVec3>>,
    groups: Vec<Group>,
}

impl Mesh {
    /// Builds a mesh from positions and faces, checking that every index is in range,
    /// no face repeats a vertex, every coordinate is finite and the counts fit the
    /// `u32` ids ([`MAX_VERTICES`], [`MAX_FACES`]).
    pub fn new(positions: Vec<DVec3>, faces: Vec<Face>) -> Result<Mesh> {
        check_counts(positions.len(), faces.len())?;
        check_finite(&positions, "mesh vertex position")?;
        for (f, face) in faces.iter().enumerate() {
            check_face(f, face, positions.len())?;
        }
        Ok(Mesh {
            positions,
            faces,
            normals: None,
            groups: Vec::new(),
        })
    }

    /// The mesh with per-vertex normals attached (one per vertex, finite; they are
    /// stored as given, not normalised). Replaces any normals it had.
    pub fn with_normals(mut self, normals: Vec<DVec3>) -> Result<Mesh> {
        if normals.len() != self.positions.len() {
            return Err(GeomError::LengthMismatch {
                what: "vertex normals",
                expected: self.positions.len(),
                given: normals.len(),
            });
        }
        check_finite(&normals, "mesh vertex normal")?;
        self.normals = Some(normals);
        Ok(self)
    }

    /// The mesh without per-vertex normals.
    pub fn without_normals(mut self) -> Mesh {
        self.normals = None;
        self
    }

    /// The mesh with angle-weighted vertex normals computed from its faces attached
    /// (see [`Mesh::compute_vertex_normals`]).
    pub fn with_computed_normals(mut self) -> Mesh {
        self.normals = Some(self.compute_vertex_normals());
        self
    }

    /// Adds a named group of faces. The faces are stored sorted and deduplicated. Fails
    /// if a face is out of range or a group of that name already exists.
    pub fn add_group(
        &mut self,
        name: impl Into<String>,
        faces: impl IntoIterator<Item = FaceId>,
    ) -> Result<()> {
        let name = name.into();
        if self.group(&name).is_some() {
            return Err(GeomError::InvalidMesh {
                reason: format!("a group named {name:?} already exists"),
            });
        }
        let mut faces: Vec<FaceId> = faces.into_iter().collect();
        if let Some(bad) = faces.iter().find(|f| f.index() >= self.faces.len()) {
            return Err(GeomError::InvalidMesh {
                reason: format!(
                    "group {name:?} refers to face {}, but the mesh has {} faces",
                    bad.0,
                    self.faces.len()
                ),
            });
        }
        faces.sort_unstable();
        faces.dedup();
        self.groups.push(Group { name, faces });
        Ok(())
    }

    /// Builder form of [`Mesh::add_group`].
    pub fn with_group(
        mut self,
        name: impl Into<String>,
        faces: impl IntoIterator<Item = FaceId>,
    ) -> Result<Mesh> {
        self.add_group(name, faces)?;
        Ok(self)
    }

    /// Moves vertex `v` to `position` (connectivity unchanged, so a [`Topology`] built
    /// earlier stays valid). Fails if `v` is out of range or `position` not finite.
    pub fn set_position(&mut self, v: VertexId, position: DVec3) -> Result<()> {
        if !position.is_finite() {
            return Err(GeomError::NotFinite {
                what: "mesh vertex position",
            });
        }
        let count = self.positions.len();
        let slot = self
            .positions
            .get_mut(v.index())
            .ok_or_else(|| GeomError::InvalidMesh {
                reason: format!(
                    "vertex {} out of range (the mesh has {count} vertices)",
                    v.0
                ),
            })?;
        *slot = position;
        Ok(())
    }

    /// All vertex positions, indexed by [`VertexId::index`].
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// All faces, indexed by [`FaceId::index`].
    pub fn faces(&self) -> &[Face] {
        &self.faces
    }

    /// The per-vertex normals, if the mesh has them.
    pub fn normals(&self) -> Option<&[DVec3]> {
        self.normals.as_deref()
    }

    /// The named groups, in the order they were added.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// The group called `name`, if any.
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// Number of vertices (positions), including any not used by a face.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Number of triangles and number of quads.
    pub fn triangle_and_quad_counts(&self) -> (usize, usize) {
        let tris = self.faces.iter().filter(|f| f.is_triangle()).count();
        (tris, self.faces.len() - tris)
    }

    /// Whether the mesh has no faces.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// The position of vertex `v`, or `None` if out of range.
    pub fn position(&self, v: VertexId) -> Option<DVec3> {
        self.positions.get(v.index()).copied()
    }

    /// Face `f`, or `None` if out of range.
    pub fn face(&self, f: FaceId) -> Option<Face> {
        self.faces.get(f.index()).copied()
    }

    /// The corner positions of face `f` (unused fourth slot of a triangle is zero) and
    /// the face itself, or `None` if `f` is out of range.
    fn corners(&self, f: FaceId) -> Option<(Face, [DVec3; 4])> {
        let face = self.face(f)?;
        let mut p = [DVec3::ZERO; 4];
        for (slot, &v) in p.iter_mut().zip(face.indices()) {
            // Mesh::new checked every face index against the positions.
            *slot = self.positions[v as usize];
        }
        Some((face, p))
    }

    /// The vector area of face `f`: its normal direction scaled by its (projected)
    /// area. For a quad this is half the cross product of its diagonals, which equals
    /// Newell's formula, so non-planar quads get the normal of their best-fit plane.
    /// Summing these over faces gives area-weighted normals. `None` if out of range.
    pub fn face_vector_area(&self, f: FaceId) -> Option<DVec3> {
        let (face, p) = self.corners(f)?;
        let doubled = if face.is_quad() {
            (p[2] - p[0]).cross(p[3] - p[1])
        } else {
            (p[1] - p[0]).cross(p[2] - p[0])
        };
        Some(doubled * 0.5)
    }

    /// The unit normal of face `f` (Newell's method, so quads work), pointing to the
    /// side from which the winding is counter-clockwise. `None` if `f` is out of range
    /// or the face is degenerate (zero area).
    pub fn face_normal(&self, f: FaceId) -> Option<DVec3> {
        self.face_vector_area(f)?.try_normalize()
    }

    /// The area of face `f`; a quad counts as the two triangles of its split along the
    /// shorter diagonal (the split [`Mesh::triangulated`] makes), so non-planar quads
    /// get the area of that surface. `None` if `f` is out of range.
    pub fn face_area(&self, f: FaceId) -> Option<f64> {
        let (face, p) = self.corners(f)?;
        let (first, second) = face.split_corners(&p);
        let tri = |[a, b, c]: [usize; 3]| 0.5 * (p[b] - p[a]).cross(p[c] - p[a]).length();
        Some(tri(first) + second.map_or(0.0, tri))
    }

    /// The centroid of face `f`'s corners (the average of its 3 or 4 vertex positions),
    /// or `None` if out of range. For a planar parallelogram this is also its area
    /// centroid; for other quads it is close to it.
    pub fn face_centroid(&self, f: FaceId) -> Option<DVec3> {
        let (face, p) = self.corners(f)?;
        let n = face.vertex_count();
        Some(p[..n].iter().copied().sum::<DVec3>() / n as f64)
    }

    /// The axis-aligned bounding box `(min, max)` of all positions (including vertices
    /// not used by a face), or `None` for a mesh without vertices.
    pub fn bounding_box(&self) -> Option<(DVec3, DVec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }

    /// The sum of all face areas (see [`Mesh::face_area`]).
    pub fn total_area(&self) -> f64 {
        (0..self.faces.len())
            .filter_map(|f| self.face_area(FaceId(to_u32(f))))
            .sum()
    }

    /// The volume a closed mesh whose faces face out encloses (the divergence theorem
    /// over its faces, quads split on their 0-2 diagonal); meaningless for an open one.
    pub fn enclosed_volume(&self) -> f64 {
        let p = &self.positions;
        let tet =
            |a: u32, b: u32, c: u32| p[a as usize].dot(p[b as usize].cross(p[c as usize])) / 6.0;
        self.faces
            .iter()
            .map(|f| match *f.indices() {
                [a, b, c] => tet(a, b, c),
                [a, b, c, d] => tet(a, b, c) + tet(a, c, d),
                _ => 0.0,
            })
            .sum()
    }

    /// The half-edge topology of this mesh; see [`Topology::build`].
    pub fn topology(&self) -> Topology {
        Topology::build(self)
    }

    /// Iterator over all face ids, in order.
    pub fn face_ids(&self) -> impl Iterator<Item = FaceId> {
        (0..to_u32(self.faces.len())).map(FaceId)
    }

    /// Iterator over all vertex ids, in order.
    pub fn vertex_ids(&self) -> impl Iterator<Item = VertexId> {
        (0..to_u32(self.positions.len())).map(VertexId)
    }
}

/// Rejects meshes whose counts do not fit the `u32` ids.
fn check_counts(vertices: usize, faces: usize) -> Result<()> {
    if vertices > MAX_VERTICES {
        return Err(GeomError::InvalidMesh {
            reason: format!("{vertices} vertices exceed the limit of {MAX_VERTICES}"),
        });
    }
    if faces > MAX_FACES {
        return Err(GeomError::InvalidMesh {
            reason: format!("{faces} faces exceed the limit of {MAX_FACES}"),
        });
    }
    Ok(())
}

/// Rejects any vector with a NaN or infinite coordinate.
fn check_finite(vectors: &[DVec3], what: &'static str) -> Result<()> {
    if vectors.iter().all(|p| p.is_finite()) {
        Ok(())
    } else {
        Err(GeomError::NotFinite { what })
    }
}

/// Checks face `f`: every index below `vertex_count`, no index repeated.
fn check_face(f: usize, face: &Face, vertex_count: usize) -> Result<()> {
    let v = face.indices();
    if let Some(&bad) = v.iter().find(|&&i| i as usize >= vertex_count) {
        return Err(GeomError::InvalidMesh {
            reason: format!(
                "face {f} refers to vertex {bad}, but the mesh has {vertex_count} vertices"
            ),
        });
    }
    for i in 0..v.len() {
        if v[i + 1..].contains(&v[i]) {
            return Err(GeomError::InvalidMesh {
                reason: format!("face {f} uses vertex {} more than once", v[i]),
            });
        }
    }
    Ok(())
}
