//! Curvature at the nodes of a shell mesh (paper 000, section 4: finding existing
//! rounds). A tool mesh from CAD carries its rounds only as facets; to find a round and
//! re-round it, each node's curvature is read off a quadric fitted to its neighbours:
//!
//! 1. a local frame at the node, `d` along the node's normal (the mean of its faces'
//!    normals, each weighted by its corner angle there: `Mesh::compute_vertex_normals`)
//!    and `u`, `v` across it;
//! 2. the quadric `d = c20 u² + c11 uv + c02 v² + c10 u + c01 v + c00` fitted by least
//!    squares to the node and its neighbours (the ring of nodes sharing an edge with it,
//!    and the next ring too where that ring has fewer than 6);
//! 3. the Gaussian, mean and principal curvatures of that quadric's graph at the node's
//!    foot, `(0, 0)`, from its first and second fundamental forms (Monge patch).
//!
//! Signs: a curvature is positive where the surface bends away from the normal, so on
//! a sphere whose normals point out every curvature is `1 / R`; on a cylinder so
//! oriented `max` is `1 / R` and `min` 0.

use glam::DVec3;
use nalgebra::{Matrix6, SymmetricEigen, Vector6};

use super::topology::Topology;
use super::{Mesh, VertexId};

/// The fewest neighbours a node's quadric is fitted to (the paper's six: one more than
/// the quadric's unknowns less its constant).
pub const FIT_NEIGHBOURS: usize = 6;

/// The curvature of a mesh at one node, read off the quadric fitted round it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeCurvature {
    /// The unit normal the frame was set up on.
    pub normal: DVec3,
    /// The Gaussian curvature K (1/mm²): the product of the principal curvatures.
    pub gaussian: f64,
    /// The mean curvature H (1/mm): half their sum.
    pub mean: f64,
    /// The larger principal curvature (1/mm).
    pub max: f64,
    /// The smaller principal curvature (1/mm).
    pub min: f64,
    /// How many neighbours the quadric was fitted to.
    pub neighbours: usize,
}

impl NodeCurvature {
    /// The radius of the sharper bend there, `1 / |k|` of the principal curvature
    /// largest in size (infinite on a flat).
    pub fn radius(&self) -> f64 {
        1.0 / self.max.abs().max(self.min.abs())
    }
}

/// The curvature at the nodes of a mesh, each worked out when first asked for and kept:
/// finding one round reads the nodes round it, not the whole mesh.
pub struct CurvatureAt<'a> {
    mesh: &'a Mesh,
    topology: &'a Topology,
    normals: Vec<DVec3>,
    known: Vec<std::cell::OnceCell<Option<NodeCurvature>>>,
}

impl<'a> CurvatureAt<'a> {
    /// The curvatures of `mesh` (its `topology`), none yet worked out.
    pub fn new(mesh: &'a Mesh, topology: &'a Topology) -> CurvatureAt<'a> {
        CurvatureAt {
            mesh,
            topology,
            normals: mesh.compute_vertex_normals(),
            known: (0..mesh.vertex_count())
                .map(|_| std::cell::OnceCell::new())
                .collect(),
        }
    }

    /// The curvature at node `v`, as [`node_curvatures`] gives it.
    pub fn at(&self, v: VertexId) -> Option<NodeCurvature> {
        *self.known.get(v.index())?.get_or_init(|| {
            let normal = self.normals[v.index()].try_normalize()?;
            node_curvature(self.mesh, self.topology, v, normal)
        })
    }
}

/// The curvature at every node of `mesh` (`None` at a node with no normal, too few
/// neighbours, or neighbours the quadric cannot be fitted to: all on one line, say).
pub fn node_curvatures(mesh: &Mesh) -> Vec<Option<NodeCurvature>> {
    let topology = Topology::build(mesh);
    let normals = mesh.compute_vertex_normals();
    (0..mesh.vertex_count())
        .map(|i| {
            let normal = normals[i].try_normalize()?;
            node_curvature(mesh, &topology, VertexId(i as u32), normal)
        })
        .collect()
}

/// The nodes the quadric at `v` is fitted to besides `v`: its ring of neighbours, and
/// where that holds fewer than [`FIT_NEIGHBOURS`], the next ring as well.
pub fn fit_neighbours(topology: &Topology, v: VertexId) -> Vec<VertexId> {
    let mut ring = topology.vertex_neighbors(v);
    if ring.len() < FIT_NEIGHBOURS {
        let first = ring.clone();
        for u in first {
            for w in topology.vertex_neighbors(u) {
                if w != v && !ring.contains(&w) {
                    ring.push(w);
                }
            }
        }
    }
    ring
}

/// The curvature at node `v` of `mesh`, its frame set on `normal` (unit): the quadric
/// fitted to it and its [`fit_neighbours`] by least squares, read at the node's foot.
pub fn node_curvature(
    mesh: &Mesh,
    topology: &Topology,
    v: VertexId,
    normal: DVec3,
) -> Option<NodeCurvature> {
    let p = mesh.positions();
    let origin = *p.get(v.index())?;
    let around = fit_neighbours(topology, v);
    if around.len() < FIT_NEIGHBOURS - 1 {
        return None;
    }
    let u_axis = normal.any_orthonormal_vector();
    let v_axis = normal.cross(u_axis);
    let points: Vec<DVec3> = std::iter::once(origin)
        .chain(around.iter().map(|w| p[w.index()]))
        .collect();
    // The rows (u², uv, v², u, v, 1) and the heights d, scaled by the neighbourhood's
    // size so the fit is as well conditioned on a 0.1 mm mesh as on a 100 mm one.
    let scale = points
        .iter()
        .map(|q| (*q - origin).length())
        .fold(0.0, f64::max);
    if scale <= 0.0 || !scale.is_finite() {
        return None;
    }
    // The normal equations (AᵀA) c = Aᵀd, summed row by row: 6 x 6 whatever the number
    // of neighbours.
    let mut ata = Matrix6::<f64>::zeros();
    let mut atd = Vector6::<f64>::zeros();
    for q in &points {
        let rel = (*q - origin) / scale;
        let (x, y) = (rel.dot(u_axis), rel.dot(v_axis));
        let row = Vector6::new(x * x, x * y, y * y, x, y, 1.0);
        ata += row * row.transpose();
        atd += row * rel.dot(normal);
    }
    let eigen = SymmetricEigen::new(ata);
    // Neighbours that pin no quadric (on one line, or one point) leave the fit singular:
    // its smallest singular value (the root of AᵀA's smallest eigenvalue) a millionth of
    // its largest or less. The rows are scaled to within 1, so a real fit is far above.
    let largest = eigen.eigenvalues.max();
    if largest.is_nan() || largest <= 0.0 || eigen.eigenvalues.min() <= 1e-12 * largest {
        return None;
    }
    let inverse = eigen.eigenvalues.map(|l| 1.0 / l);
    let c = eigen.eigenvectors
        * Matrix6::from_diagonal(&inverse)
        * eigen.eigenvectors.transpose()
        * atd;
    // Back to millimetres: d = scale * g(u / scale, v / scale), so each derivative of
    // order k is divided by scale^(k - 1).
    let (fu, fv) = (c[3], c[4]);
    let (fuu, fuv, fvv) = (2.0 * c[0] / scale, c[1] / scale, 2.0 * c[2] / scale);
    let (e, f, g) = (1.0 + fu * fu, fu * fv, 1.0 + fv * fv);
    let w = (1.0 + fu * fu + fv * fv).sqrt();
    // Bending away from the normal counts positive: the second form's sign turned.
    let (l, m, n) = (-fuu / w, -fuv / w, -fvv / w);
    let det = e * g - f * f;
    let gaussian = (l * n - m * m) / det;
    let mean = (e * n - 2.0 * f * m + g * l) / (2.0 * det);
    let root = (mean * mean - gaussian).max(0.0).sqrt();
    Some(NodeCurvature {
        normal,
        gaussian,
        mean,
        max: mean + root,
        min: mean - root,
        neighbours: around.len(),
    })
}
