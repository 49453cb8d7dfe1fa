//! Uniform grids of cells for the rounding's searches: over triangles, the offset
//! triangles that may cross one (the spine) and the triangle nearest a point (the
//! contacts, and whether a spine point keeps R from a base mesh); over a polyline (the
//! chain, or an existing round's middle), its point nearest a node (the base meshes'
//! reach, the spine's order, the cut). Without them each search tests every triangle
//! or segment, quadratic on a fine mesh.

use glam::DVec3;

use super::spine::{nearest_on_triangle, Region};
use crate::geom::mesh::box_grid::BoxGrid;

/// A triangle's corners.
pub type Triangle = [DVec3; 3];

/// Triangles in a [`BoxGrid`], for the crossing and nearest-point searches.
#[derive(Debug, Clone)]
pub struct TriangleGrid {
    /// The triangles, in the order given.
    pub triangles: Vec<Triangle>,
    grid: BoxGrid,
}

impl TriangleGrid {
    /// The grid over `triangles`.
    pub fn new(triangles: Vec<Triangle>) -> TriangleGrid {
        let boxes: Vec<(DVec3, DVec3)> = triangles
            .iter()
            .map(|t| (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2])))
            .collect();
        TriangleGrid {
            grid: BoxGrid::new(&boxes),
            triangles,
        }
    }

    /// The triangles that may overlap the box from `lo` to `hi` (every one that does),
    /// each once.
    pub fn candidates(&self, lo: DVec3, hi: DVec3) -> Vec<u32> {
        self.grid.candidates(lo, hi)
    }

    /// The point of the triangles nearest `p`, its distance and region.
    pub fn nearest(&self, p: DVec3) -> Option<(DVec3, f64, Region)> {
        self.grid
            .nearest(p, |k| {
                let (q, r) = nearest_on_triangle(p, &self.triangles[k as usize]);
                (q.distance(p), (q, r))
            })
            .map(|(_, d, (q, r))| (q, d, r))
    }
}

/// A polyline's segments in a [`BoxGrid`], for its point nearest a node.
#[derive(Debug, Clone)]
pub struct PolylineIndex {
    points: Vec<DVec3>,
    /// The arc length at each point.
    run: Vec<f64>,
    grid: BoxGrid,
}

impl PolylineIndex {
    /// The index over the polyline through `points`.
    pub fn new(points: &[DVec3]) -> PolylineIndex {
        let boxes: Vec<(DVec3, DVec3)> = points
            .windows(2)
            .map(|w| (w[0].min(w[1]), w[0].max(w[1])))
            .collect();
        let mut run = vec![0.0];
        for w in points.windows(2) {
            run.push(run[run.len() - 1] + w[0].distance(w[1]));
        }
        PolylineIndex {
            points: points.to_vec(),
            run,
            grid: BoxGrid::new(&boxes),
        }
    }

    /// The polyline's point nearest `p`: its distance from `p`, the arc length along
    /// the polyline to it, and the point, as [`super::polyline_nearest`] gives them
    /// (infinite distance and `p` itself for fewer than two points).
    pub fn nearest(&self, p: DVec3) -> (f64, f64, DVec3) {
        let found = self.grid.nearest(p, |k| {
            let (a, b) = (self.points[k as usize], self.points[k as usize + 1]);
            let ab = b - a;
            let t = ((p - a).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            let q = a + t * ab;
            (p.distance(q), (t * ab.length(), q))
        });
        match found {
            Some((k, d, (along, q))) => (d, self.run[k as usize] + along, q),
            None => (f64::INFINITY, 0.0, p),
        }
    }
}
