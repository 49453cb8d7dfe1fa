//! A base mesh offset by the ball's radius, keeping its topology (paper 000, section 2,
//! step 2, Fig. 7b): each node goes where the planes of its faces, each moved the
//! radius along its normal, meet, so a flat stays a flat and a fold's offset keeps its
//! crease (a node moved along its own normal would round the crease off). Where the
//! surface curves towards the ball more tightly than the radius, the offset folds over
//! itself; those nodes are marked, and later steps leave them out.

use std::collections::BTreeMap;

use glam::DVec3;
use nalgebra::{DMatrix, DVector};

use crate::geom::mesh::{FaceId, Mesh, Topology, VertexId};

/// A base mesh offset: each node's offset point, and whether it is to be trusted.
#[derive(Debug, Clone, PartialEq)]
pub struct OffsetMesh {
    /// The faces offset (the base mesh's).
    pub faces: Vec<FaceId>,
    /// Each node of those faces, with its offset point.
    pub points: BTreeMap<VertexId, DVec3>,
    /// The nodes where the surface curves towards the ball more tightly than the
    /// radius (its offset folds over there).
    pub folded: Vec<VertexId>,
}

/// How far apart (as the sine of the angle) two face normals must be for their offset
/// planes to pin a node's tangent position; below it they count as one plane.
const DISTINCT: f64 = 1e-6;

/// How far past the bound a node's offset step may reach before the node is taken as
/// folded: 2 %.
const FOLD_SLACK: f64 = 0.02;

/// The faces `faces` of `mesh` offset by `distance` along their normals (below 0:
/// against them). Each node of the faces goes to the least-squares meeting point of its
/// faces' offset planes (those among `faces`), taking the smallest step from the node
/// where the planes leave it free (on a flat, straight along the normal). A node is
/// `folded` when its step is longer than the planes' meeting allows on a surface that
/// curves with a radius above `|distance|`: more than `|distance|` divided by the cosine
/// of half the largest angle between its faces, or where a face's offset turns over
/// (its normal reversed).
pub fn offset_faces(
    mesh: &Mesh,
    topology: &Topology,
    faces: &[FaceId],
    distance: f64,
) -> OffsetMesh {
    let in_base: std::collections::BTreeSet<FaceId> = faces.iter().copied().collect();
    let mut points = BTreeMap::new();
    let mut folded = Vec::new();
    let nodes: std::collections::BTreeSet<VertexId> = faces
        .iter()
        .filter_map(|&f| mesh.face(f))
        .flat_map(|face| face.vertices().collect::<Vec<_>>())
        .collect();
    for v in nodes {
        let Some(p) = mesh.position(v) else { continue };
        let normals: Vec<DVec3> = topology
            .vertex_faces(v)
            .iter()
            .filter(|f| in_base.contains(f))
            .filter_map(|&f| mesh.face_normal(f))
            .collect();
        if normals.is_empty() {
            continue;
        }
        // The step d from p: n · d = distance for each face, least squares, smallest.
        let mut a = DMatrix::<f64>::zeros(normals.len(), 3);
        let b = DVector::<f64>::from_element(normals.len(), distance);
        for (r, n) in normals.iter().enumerate() {
            a[(r, 0)] = n.x;
            a[(r, 1)] = n.y;
            a[(r, 2)] = n.z;
        }
        let svd = a.svd(true, true);
        let largest = svd.singular_values.max();
        let step = match svd.solve(&b, DISTINCT * largest) {
            Ok(d) => DVec3::new(d[0], d[1], d[2]),
            Err(_) => normals[0] * distance,
        };
        points.insert(v, p + step);
        // The widest turn between two of its faces bounds how far the planes' meeting
        // may lie from the node: |distance| / cos(turn / 2).
        let mut widest: f64 = 0.0;
        for (i, n) in normals.iter().enumerate() {
            for m in &normals[i + 1..] {
                widest = widest.max(n.dot(*m).clamp(-1.0, 1.0).acos());
            }
        }
        // Planes that do not meet in one point (the two triangles of a twisted cell)
        // give a least-squares step a little past the bound; a fold, one far past it.
        let bound = distance.abs() / (0.5 * widest).cos().max(1e-9);
        if step.length() > bound * (1.0 + FOLD_SLACK) + 1e-12 {
            folded.push(v);
        }
    }
    // A face whose offset turned over (its offset normal against its own) has folded.
    for &f in faces {
        let Some(face) = mesh.face(f) else { continue };
        let corners: Vec<DVec3> = face
            .vertices()
            .filter_map(|v| points.get(&v).copied())
            .collect();
        let Some(n) = mesh.face_normal(f) else {
            continue;
        };
        if corners.len() == 3
            && (corners[1] - corners[0])
                .cross(corners[2] - corners[0])
                .dot(n)
                < 0.0
        {
            folded.extend(face.vertices());
        }
    }
    folded.sort();
    folded.dedup();
    OffsetMesh {
        faces: faces.to_vec(),
        points,
        folded,
    }
}
