//! Rolling-ball rounding of sharp edges on a shell mesh (paper 000; issue 16, under
//! way): a die shoulder that is sharp in a tool mesh tears the sheet in forming
//! simulation, so the designer rounds the chain of sharp edges through a picked node
//! directly on the mesh. Each step of the paper's method is its own tested function.
//! A constant or variable radius ([`radius`]), on a closed chain or an open one (its
//! round carried on to the mesh's boundary and trimmed there), or on a round the mesh
//! already has ([`existing`]).
//!
//! The steps, numbered as the paper's:
//!
//! - step 1, [`chain`]: the chain of sharp edges through a picked node, followed both ways to
//!   the mesh's boundary or back to the start (section 2, step 1); [`base`]: the faces
//!   within 3R of it, split by it into the two base meshes;
//! - step 2, [`offset`]: each base mesh offset by R keeping its topology (Fig. 7b), its nodes
//!   marked where the surface curves tighter than R towards the ball;
//! - step 3, [`spine`]: the ball centre's path, where the two offsets cross, ordered along the
//!   chain, points closer than R to a base mesh dropped;
//! - steps 4 and 5, [`contact`]: each spine point's contact on each base mesh (in a face, on an edge
//!   or at a corner), the ball re-centred to touch both at R exactly, and the profile
//!   arc between them; for a variable radius ([`radius`]: a cubic spline in arc length
//!   along the chain) each ball moved within its plane to its own radius;
//! - step 7, [`cut`]: the mesh cut along the trim lines (faces split where a trim line
//!   crosses them, nodes within a fifth of an edge of it snapped onto it);
//! - steps 6 to 8, [`round`]: the steps put together: the profiles lofted into the rounding
//!   surface (an open round's carried on past the boundary and trimmed there), the mesh
//!   cut and the surface's strip stitched in.
//!
//! The curvature each node has is [`super::curvature`]; [`existing`] finds a round a
//! mesh already has by it (section 4) and makes the site to round it again.

pub mod base;
pub mod chain;
pub mod contact;
pub mod cut;
pub mod existing;
pub mod index;
pub mod offset;
pub mod radius;
pub mod round;
pub mod spine;

use glam::DVec3;

/// The point of the polyline `points` nearest `p`: its distance from `p`, the arc
/// length along the polyline to it, and the point (infinite distance and `p` itself
/// for fewer than two points).
pub fn polyline_nearest(points: &[DVec3], p: DVec3) -> (f64, f64, DVec3) {
    let (mut best, mut at, mut point, mut run) = (f64::INFINITY, 0.0, p, 0.0);
    for w in points.windows(2) {
        let ab = w[1] - w[0];
        let t = ((p - w[0]).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        let q = w[0] + t * ab;
        let d = p.distance(q);
        if d < best {
            (best, at, point) = (d, run + t * ab.length(), q);
        }
        run += ab.length();
    }
    (best, at, point)
}

/// The points of `chain`'s nodes in order, the first again at the end when it is
/// closed: its polyline.
pub fn chain_polyline(mesh: &crate::geom::mesh::Mesh, chain: &chain::SharpChain) -> Vec<DVec3> {
    chain
        .nodes
        .iter()
        .chain(chain.closed.then_some(&chain.nodes[0]))
        .filter_map(|&v| mesh.position(v))
        .collect()
}
