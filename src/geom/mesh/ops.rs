//! Operations that derive a new mesh or per-vertex data from a [`Mesh`]:
//! triangulation, vertex normals, concatenation and welding.

use super::ids::to_u32;
use super::{check_counts, check_face, check_finite, Face, FaceId, Group, Mesh, VertexId};
use crate::geom::error::{GeomError, Result};
use glam::DVec3;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

impl Mesh {
    /// The mesh with every quad split into two triangles along its shorter diagonal
    /// (ties: diagonal 0–2), keeping winding, vertices, normals and groups. Rolling-ball
    /// rounding and most intersection code want triangles; the shorter diagonal keeps
    /// the triangles better shaped and, for a non-planar quad, is the split
    /// [`Mesh::face_area`] measures. Triangles are copied unchanged.
    pub fn triangulated(&self) -> Mesh {
        self.triangulated_with_map().0
    }

    /// [`Mesh::triangulated`], also returning for every new face the original face it
    /// came from (ascending), so per-face data can be carried over.
    pub fn triangulated_with_map(&self) -> (Mesh, Vec<FaceId>) {
        let mut faces = Vec::with_capacity(self.faces.len() * 2);
        let mut origin = Vec::with_capacity(self.faces.len() * 2);
        for (f, face) in self.faces.iter().enumerate() {
            let v = face.indices();
            let mut p = [DVec3::ZERO; 4];
            for (slot, &i) in p.iter_mut().zip(v) {
                // Mesh::new checked every face index against the positions.
                *slot = self.positions[i as usize];
            }
            let (first, second) = face.split_corners(&p);
            for [a, b, c] in std::iter::once(first).chain(second) {
                faces.push(Face::triangle(v[a], v[b], v[c]));
                origin.push(FaceId(to_u32(f)));
            }
        }
        let groups = remap_groups(&self.groups, self.faces.len(), &origin);
        let mesh = Mesh {
            positions: self.positions.clone(),
            faces,
            normals: self.normals.clone(),
            groups,
        };
        (mesh, origin)
    }

    /// Angle-weighted vertex normals (Thürmer and Wüthrich): each face adds its unit
    /// normal times its corner angle at the vertex, and the sum is normalised. Unlike
    /// area weighting, this does not depend on how a surface is cut into faces, so a
    /// planar quad and its two triangles give the same normals. Vertices without faces (or
    /// only degenerate ones) get the zero vector.
    pub fn compute_vertex_normals(&self) -> Vec<DVec3> {
        let mut sums = vec![DVec3::ZERO; self.positions.len()];
        for (f, face) in self.faces.iter().enumerate() {
            let Some(normal) = self.face_normal(FaceId(to_u32(f))) else {
                continue;
            };
            let v = face.indices();
            for i in 0..v.len() {
                sums[v[i] as usize] += normal * self.corner_angle(face, i);
            }
        }
        sums.into_iter().map(DVec3::normalize_or_zero).collect()
    }

    /// The normal at vertex `v` alone, as [`Mesh::compute_vertex_normals`] gives it,
    /// from `faces`, the faces using `v` in id order ([`super::Topology::vertex_faces`]):
    /// for a few nodes (a hole's rim) without working out every node's.
    pub fn vertex_normal(&self, v: VertexId, faces: &[FaceId]) -> DVec3 {
        let mut sum = DVec3::ZERO;
        for &f in faces {
            let (Some(face), Some(normal)) = (self.faces.get(f.index()), self.face_normal(f))
            else {
                continue;
            };
            if let Some(i) = face.indices().iter().position(|&w| w == v.0) {
                sum += normal * self.corner_angle(face, i);
            }
        }
        sum.normalize_or_zero()
    }

    /// The angle of `face` at its corner `i` (rad).
    fn corner_angle(&self, face: &Face, i: usize) -> f64 {
        let v = face.indices();
        let n = v.len();
        // Mesh::new checked every face index against the positions.
        let here = self.positions[v[i] as usize];
        let to_next = self.positions[v[(i + 1) % n] as usize] - here;
        let to_prev = self.positions[v[(i + n - 1) % n] as usize] - here;
        to_next.cross(to_prev).length().atan2(to_next.dot(to_prev))
    }

    /// Appends `other` to this mesh: its vertices and faces come after this mesh's,
    /// with indices offset accordingly. Groups of `other` are offset too; a group whose
    /// name already exists here is merged into that group. If only one mesh has
    /// normals, the other's are computed ([`Mesh::compute_vertex_normals`]) so no normal
    /// is lost. Fails (leaving this mesh unchanged) if the result would be too large.
    pub fn append(&mut self, other: &Mesh) -> Result<()> {
        check_counts(
            self.positions.len().saturating_add(other.positions.len()),
            self.faces.len().saturating_add(other.faces.len()),
        )?;
        let vertex_offset = to_u32(self.positions.len());
        let face_offset = to_u32(self.faces.len());

        self.normals = match (self.normals.take(), &other.normals) {
            (None, None) => None,
            (mine, theirs) => {
                let mut normals = mine.unwrap_or_else(|| self.compute_vertex_normals());
                match theirs {
                    Some(t) => normals.extend_from_slice(t),
                    None => normals.extend(other.compute_vertex_normals()),
                }
                Some(normals)
            }
        };
        self.positions.extend_from_slice(&other.positions);
        self.faces.extend(
            other
                .faces
                .iter()
                .map(|face| offset_face(face, vertex_offset)),
        );
        for group in &other.groups {
            let shifted = group.faces.iter().map(|f| FaceId(f.0 + face_offset));
            match self.groups.iter_mut().find(|g| g.name == group.name) {
                Some(existing) => {
                    existing.faces.extend(shifted);
                    existing.faces.sort_unstable();
                    existing.faces.dedup();
                }
                None => self.groups.push(Group {
                    name: group.name.clone(),
                    faces: shifted.collect(),
                }),
            }
        }
        Ok(())
    }

    /// This mesh with `from`'s face groups carried over, for a mesh derived from
    /// `from` whose face `i` came from `from`'s face `origin[i]` (ascending; a face
    /// split into several repeats its origin). Faces that came from nowhere (`origin`
    /// shorter than the face list: faces added at the end, such as fills) join no
    /// group. Replaces any groups this mesh had.
    pub fn with_groups_of(mut self, from: &Mesh, origin: &[FaceId]) -> Mesh {
        self.groups = remap_groups(&from.groups, from.faces.len(), origin);
        self
    }

    /// This mesh followed by `other`, as [`Mesh::append`] describes.
    pub fn merged(&self, other: &Mesh) -> Result<Mesh> {
        let mut mesh = self.clone();
        mesh.append(other)?;
        Ok(mesh)
    }

    /// Adds `positions` after this mesh's nodes and `faces` after its faces, the faces
    /// indexing the mesh's own nodes and the new ones: what a fill joined to a hole's
    /// rim adds. Only the new items are checked (finite, in range, no node repeated);
    /// the mesh's faces keep their numbers and so their groups. Its normals, if any,
    /// are dropped (the new faces would have none). Fails, leaving the mesh unchanged,
    /// where a new item is bad or the mesh would grow too large.
    pub fn add(&mut self, positions: &[DVec3], faces: &[Face]) -> Result<()> {
        let vertices = self.positions.len().saturating_add(positions.len());
        check_counts(vertices, self.faces.len().saturating_add(faces.len()))?;
        check_finite(positions, "mesh vertex position")?;
        for (k, face) in faces.iter().enumerate() {
            check_face(self.faces.len() + k, face, vertices)?;
        }
        self.normals = None;
        // Room for the new items, the two tables grown side by side: where the
        // allocator cannot grow a large mesh's table in place, growing it is a copy.
        // A mesh made with room for them (`with_added`) needs neither.
        if self.positions.capacity() - self.positions.len() < positions.len()
            || self.faces.capacity() - self.faces.len() < faces.len()
        {
            let (own_positions, own_faces) = (&mut self.positions, &mut self.faces);
            rayon::join(
                || own_positions.reserve(positions.len()),
                || own_faces.reserve(faces.len()),
            );
        }
        self.positions.extend_from_slice(positions);
        self.faces.extend_from_slice(faces);
        Ok(())
    }

    /// This mesh with `positions` and `faces` added, as [`Mesh::add`] adds them, its
    /// own items copied once into room for all.
    pub fn with_added(&self, positions: &[DVec3], faces: &[Face]) -> Result<Mesh> {
        let mut mesh = Mesh {
            positions: Vec::with_capacity(self.positions.len() + positions.len()),
            faces: Vec::with_capacity(self.faces.len() + faces.len()),
            normals: None,
            groups: self.groups.clone(),
        };
        mesh.positions.extend_from_slice(&self.positions);
        mesh.faces.extend_from_slice(&self.faces);
        mesh.add(positions, faces)?;
        Ok(mesh)
    }

    /// Merges vertices at most `tolerance` apart (Euclidean distance; `0` merges only
    /// exact duplicates), as needed after reading a triangle soup (STL) or
    /// after [`Mesh::append`]ing patches that share a seam. See
    /// [`Mesh::weld_with_map`] for the rules.
    pub fn weld(&self, tolerance: f64) -> Result<Mesh> {
        Ok(self.weld_with_map(tolerance)?.0)
    }

    /// [`Mesh::weld`], also returning for every old vertex its new vertex.
    ///
    /// Deterministic rules: vertices are visited in index order; each joins the
    /// lowest-numbered earlier *representative* within `tolerance`, or becomes a new
    /// representative. Positions are the representatives' own (not averaged), so no
    /// chain of near points drifts further than `tolerance` from where it was. New
    /// vertex order is the order of the representatives. Faces that lose corners are
    /// repaired: repeated neighbouring corners collapse (a quad may become a triangle);
    /// faces left with fewer than three distinct corners, or with a repeated corner
    /// that is not a neighbour, are dropped (also from groups). Normals of merged
    /// vertices are averaged and normalised. Vertices not used by faces are kept.
    pub fn weld_with_map(&self, tolerance: f64) -> Result<(Mesh, Vec<VertexId>)> {
        if tolerance.is_nan() || tolerance < 0.0 {
            return Err(GeomError::NotPositive {
                what: "weld tolerance",
                value: tolerance,
            });
        }
        if tolerance.is_infinite() {
            return Err(GeomError::NotFinite {
                what: "weld tolerance",
            });
        }
        let (representatives, vertex_map) = cluster_vertices(&self.positions, tolerance);
        let positions: Vec<DVec3> = representatives
            .iter()
            .map(|&old| self.positions[old])
            .collect();
        let normals = self
            .normals
            .as_ref()
            .map(|normals| merge_normals(normals, &representatives, &vertex_map));

        let mut faces = Vec::with_capacity(self.faces.len());
        let mut origin = Vec::with_capacity(self.faces.len());
        for (f, face) in self.faces.iter().enumerate() {
            if let Some(welded) = weld_face(face, &vertex_map) {
                faces.push(welded);
                origin.push(FaceId(to_u32(f)));
            }
        }
        let groups = remap_groups(&self.groups, self.faces.len(), &origin);
        let mesh = Mesh {
            positions,
            faces,
            normals,
            groups,
        };
        Ok((mesh, vertex_map.into_iter().map(VertexId).collect()))
    }
}

/// Face `face` with every index shifted by `offset`.
fn offset_face(face: &Face, offset: u32) -> Face {
    match *face.indices() {
        [a, b, c, d] => Face::quad(a + offset, b + offset, c + offset, d + offset),
        [a, b, c] => Face::triangle(a + offset, b + offset, c + offset),
        // A Face always has 3 or 4 corners (its constructors guarantee it).
        _ => *face,
    }
}

/// Groups carried over to a derived mesh whose face `i` came from old face
/// `origin[i]`; `origin` must be ascending. Groups keep their order, even if empty.
fn remap_groups(groups: &[Group], old_face_count: usize, origin: &[FaceId]) -> Vec<Group> {
    groups
        .iter()
        .map(|group| {
            let mut member = vec![false; old_face_count];
            for f in &group.faces {
                member[f.index()] = true;
            }
            let faces = origin
                .iter()
                .enumerate()
                .filter(|(_, old)| member[old.index()])
                .map(|(new, _)| FaceId(to_u32(new)))
                .collect();
            Group {
                name: group.name.clone(),
                faces,
            }
        })
        .collect()
}

/// Greedy, order-dependent clustering for [`Mesh::weld_with_map`]: returns the old
/// index of each representative (ascending) and, per old vertex, its new index.
///
/// Representatives are filed in a hash grid with cells twice the tolerance wide, so the
/// ball of radius `tolerance` around a point reaches at most one neighbouring cell per
/// axis: eight cells to search. The map is only probed, never iterated, and within a
/// cell the lowest representative wins, so no hash order leaks into the result.
fn cluster_vertices(positions: &[DVec3], tolerance: f64) -> (Vec<usize>, Vec<u32>) {
    const NONE: u32 = u32::MAX;
    let cell = if tolerance > 0.0 {
        2.0 * tolerance
    } else {
        1.0
    };
    // Per cell, its most recent representative; per representative, the previous one in
    // its cell (NONE ends the list). Linked lists avoid a Vec allocation per cell.
    let mut newest_in_cell: HashMap<[i64; 3], u32, BuildCellHasher> = HashMap::default();
    let mut previous_in_cell: Vec<u32> = Vec::new();
    let mut representatives: Vec<usize> = Vec::new();
    let mut vertex_map = Vec::with_capacity(positions.len());
    for (i, &p) in positions.iter().enumerate() {
        let scaled = p / cell;
        // `as` saturates for huge quotients, which only crowds a cell.
        let key = scaled.floor().to_array().map(|c| c as i64);
        // Per axis, the neighbouring cell on the side of the cell's centre line the
        // point lies on (points are at most half a cell from that neighbour).
        let side = (scaled - scaled.floor())
            .to_array()
            .map(|f| if f < 0.5 { -1i64 } else { 1 });
        let mut best: Option<u32> = None;
        for corner in 0..8u32 {
            let k: [i64; 3] = std::array::from_fn(|axis| {
                let step = if corner >> axis & 1 == 1 {
                    side[axis]
                } else {
                    0
                };
                key[axis].saturating_add(step)
            });
            let mut rep = newest_in_cell.get(&k).copied().unwrap_or(NONE);
            while rep != NONE {
                let close = positions[representatives[rep as usize]].distance(p) <= tolerance;
                if close && best.is_none_or(|b| rep < b) {
                    best = Some(rep);
                }
                rep = previous_in_cell[rep as usize];
            }
        }
        let new = best.unwrap_or_else(|| {
            let new = to_u32(representatives.len());
            representatives.push(i);
            let previous = newest_in_cell.insert(key, new).unwrap_or(NONE);
            previous_in_cell.push(previous);
            new
        });
        vertex_map.push(new);
    }
    (representatives, vertex_map)
}

/// A small, fast hasher for integer grid keys: FxHash's multiplicative mix per word and
/// the SplitMix64 finaliser, so all output bits depend on all input bits. The standard
/// SipHash dominates welding time otherwise; hash flooding is no concern here.
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }

    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

/// Builds [`CellHasher`]s for the weld grid.
type BuildCellHasher = BuildHasherDefault<CellHasher>;

/// Per new vertex: its single old normal, or the normalised mean of the merged ones
/// (falling back to the representative's normal if they cancel out).
fn merge_normals(normals: &[DVec3], representatives: &[usize], vertex_map: &[u32]) -> Vec<DVec3> {
    let mut sums = vec![DVec3::ZERO; representatives.len()];
    let mut counts = vec![0usize; representatives.len()];
    for (old, &new) in vertex_map.iter().enumerate() {
        sums[new as usize] += normals[old];
        counts[new as usize] += 1;
    }
    representatives
        .iter()
        .enumerate()
        .map(|(new, &rep)| match counts[new] {
            1 => normals[rep],
            _ => sums[new].try_normalize().unwrap_or(normals[rep]),
        })
        .collect()
}

/// Face `face` with indices mapped through `vertex_map`, neighbouring duplicates
/// collapsed; `None` if fewer than three distinct corners remain or a corner repeats.
fn weld_face(face: &Face, vertex_map: &[u32]) -> Option<Face> {
    let mut mapped = [0u32; 4];
    let n = face.vertex_count();
    for (slot, &v) in mapped.iter_mut().zip(face.indices()) {
        *slot = vertex_map[v as usize];
    }
    let mut kept = [0u32; 4];
    let mut len = 0;
    for i in 0..n {
        if mapped[i] != mapped[(i + 1) % n] {
            kept[len] = mapped[i];
            len += 1;
        }
    }
    let kept = &kept[..len];
    let distinct = kept
        .iter()
        .enumerate()
        .all(|(i, v)| !kept[i + 1..].contains(v));
    if distinct {
        Face::from_slice(kept).ok()
    } else {
        None
    }
}
