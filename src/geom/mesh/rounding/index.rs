//! A uniform grid of cells over a set of triangles, for the rounding's searches: the
//! offset triangles that may cross one (the spine), and the triangle nearest a point
//! (the contacts, and whether a spine point keeps R from a base mesh). Without it both
//! searches test every triangle, quadratic on a fine mesh.

use std::collections::HashMap;

use glam::DVec3;

use super::spine::{nearest_on_triangle, Region};

/// A triangle's corners.
pub type Triangle = [DVec3; 3];

/// Triangles with the grid cells their bounding boxes overlap.
#[derive(Debug, Clone)]
pub struct TriangleGrid {
    /// The triangles, in the order given.
    pub triangles: Vec<Triangle>,
    origin: DVec3,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
    /// The bounding box of all the triangles.
    lo: DVec3,
    hi: DVec3,
}

impl TriangleGrid {
    /// The grid over `triangles`, its cells twice the triangles' mean bounding-box
    /// size.
    pub fn new(triangles: Vec<Triangle>) -> TriangleGrid {
        let bounds = |t: &Triangle| (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let mut size = 0.0;
        for t in &triangles {
            let (a, b) = bounds(t);
            lo = lo.min(a);
            hi = hi.max(b);
            size += (b - a).max_element();
        }
        let n = triangles.len().max(1) as f64;
        let cell = (2.0 * size / n).max(1e-9 * (hi - lo).max_element().max(1.0));
        let origin = if triangles.is_empty() {
            DVec3::ZERO
        } else {
            lo
        };
        let mut grid = TriangleGrid {
            triangles: Vec::new(),
            origin,
            cell,
            cells: HashMap::new(),
            lo,
            hi,
        };
        for (k, t) in triangles.iter().enumerate() {
            let (a, b) = bounds(t);
            let (ca, cb) = (grid.cell_of(a), grid.cell_of(b));
            for i in ca[0]..=cb[0] {
                for j in ca[1]..=cb[1] {
                    for l in ca[2]..=cb[2] {
                        grid.cells.entry([i, j, l]).or_default().push(k as u32);
                    }
                }
            }
        }
        grid.triangles = triangles;
        grid
    }

    fn cell_of(&self, p: DVec3) -> [i64; 3] {
        let c = ((p - self.origin) / self.cell).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    }

    /// The triangles whose cells overlap the box from `lo` to `hi`, ascending, each
    /// once.
    pub fn candidates(&self, lo: DVec3, hi: DVec3) -> Vec<u32> {
        let lo = lo.max(self.lo - DVec3::splat(self.cell));
        let hi = hi.min(self.hi + DVec3::splat(self.cell));
        if lo.cmpgt(hi).any() {
            return Vec::new();
        }
        let (ca, cb) = (self.cell_of(lo), self.cell_of(hi));
        let mut out = Vec::new();
        for i in ca[0]..=cb[0] {
            for j in ca[1]..=cb[1] {
                for l in ca[2]..=cb[2] {
                    if let Some(ids) = self.cells.get(&[i, j, l]) {
                        out.extend_from_slice(ids);
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The point of the triangles nearest `p`, its distance and region: the cells round
    /// `p` searched in growing boxes until the nearest found lies within the box (so no
    /// triangle outside it can be nearer).
    pub fn nearest(&self, p: DVec3) -> Option<(DVec3, f64, Region)> {
        if self.triangles.is_empty() {
            return None;
        }
        let span = (self.hi - self.lo).max_element() + (p - self.lo).abs().max_element();
        let mut reach = self.cell;
        loop {
            let best = self
                .candidates(p - DVec3::splat(reach), p + DVec3::splat(reach))
                .into_iter()
                .map(|k| {
                    let (q, r) = nearest_on_triangle(p, &self.triangles[k as usize]);
                    (q, q.distance(p), r, k)
                })
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.3.cmp(&b.3)));
            match best {
                Some((q, d, r, _)) if d <= reach => return Some((q, d, r)),
                _ if reach > span => {
                    return best.map(|(q, d, r, _)| (q, d, r));
                }
                Some((_, d, _, _)) => reach = d.max(2.0 * reach),
                None => reach *= 2.0,
            }
        }
    }
}
