//! Uniform grids of cells for the rounding's searches: over triangles, the offset
//! triangles that may cross one (the spine) and the triangle nearest a point (the
//! contacts, and whether a spine point keeps R from a base mesh); over a polyline (the
//! chain, or an existing round's middle), its point nearest a node (the base meshes'
//! reach, the spine's order, the cut). Without them each search tests every triangle
//! or segment, quadratic on a fine mesh.

use glam::DVec3;

use super::spine::{nearest_on_triangle, Region};

/// A triangle's corners.
pub type Triangle = [DVec3; 3];

/// Items with bounding boxes, filed in a dense grid of cells over all their boxes, each
/// in the one cell holding its box's centre (so a search lists each item once, with no
/// sorting), each cell's items one after another (`starts[c]` to `starts[c + 1]` in
/// `items`). A search widens its box by `pad`, the largest half-size of an item's box,
/// to reach the items filed in a cell outside it.
#[derive(Debug, Clone)]
struct BoxGrid {
    origin: DVec3,
    cell: f64,
    dims: [usize; 3],
    pad: DVec3,
    starts: Vec<u32>,
    items: Vec<u32>,
    /// The box round every item's.
    lo: DVec3,
    hi: DVec3,
    /// How many items there are.
    count: usize,
}

/// The most cells a grid has per item: a grid over a long, thin or sparse set of small
/// items takes larger cells rather than many empty ones.
const CELLS_PER_ITEM: usize = 8;

impl BoxGrid {
    /// The grid over items with the boxes `boxes` (low and high corners), its cells
    /// twice the boxes' mean size (larger where that would make more than
    /// [`CELLS_PER_ITEM`] cells an item).
    fn new(boxes: &[(DVec3, DVec3)]) -> BoxGrid {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let mut size = 0.0;
        let mut pad = DVec3::ZERO;
        for &(a, b) in boxes {
            lo = lo.min(a);
            hi = hi.max(b);
            size += (b - a).max_element();
            pad = pad.max(0.5 * (b - a));
        }
        if boxes.is_empty() {
            (lo, hi) = (DVec3::ZERO, DVec3::ZERO);
        }
        let n = boxes.len().max(1) as f64;
        let mut cell = (2.0 * size / n).max(1e-9 * (hi - lo).max_element().max(1.0));
        let dims_for = |cell: f64| {
            let d = ((hi - lo) / cell).floor();
            [d.x as usize + 1, d.y as usize + 1, d.z as usize + 1]
        };
        let most = CELLS_PER_ITEM * boxes.len().max(8);
        while dims_for(cell).iter().product::<usize>() > most {
            cell *= 1.5;
        }
        let dims = dims_for(cell);
        let mut grid = BoxGrid {
            origin: lo,
            cell,
            dims,
            pad,
            starts: Vec::new(),
            items: Vec::new(),
            lo,
            hi,
            count: boxes.len(),
        };
        // Counted first, then filled: each cell's items in the order given.
        let homes: Vec<usize> = boxes
            .iter()
            .map(|&(a, b)| grid.index(grid.cell_of(0.5 * (a + b))))
            .collect();
        let mut counts = vec![0u32; dims.iter().product::<usize>() + 1];
        for &c in &homes {
            counts[c + 1] += 1;
        }
        for c in 1..counts.len() {
            counts[c] += counts[c - 1];
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; boxes.len()];
        for (k, &c) in homes.iter().enumerate() {
            items[fill[c] as usize] = k as u32;
            fill[c] += 1;
        }
        grid.starts = counts;
        grid.items = items;
        grid
    }

    /// The cell holding `p`, clamped into the grid.
    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        let c = ((p - self.origin) / self.cell).floor().max(DVec3::ZERO);
        [
            (c.x as usize).min(self.dims[0] - 1),
            (c.y as usize).min(self.dims[1] - 1),
            (c.z as usize).min(self.dims[2] - 1),
        ]
    }

    /// The index of cell `c` in `starts`.
    fn index(&self, c: [usize; 3]) -> usize {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    /// The items whose boxes may overlap the box from `lo` to `hi` (every one that
    /// does), each once, cell by cell in a fixed order.
    fn candidates(&self, lo: DVec3, hi: DVec3) -> Vec<u32> {
        let (lo, hi) = (lo - self.pad, hi + self.pad);
        if self.count == 0 || lo.cmpgt(self.hi).any() || self.lo.cmpgt(hi).any() {
            return Vec::new();
        }
        let (ca, cb) = (self.cell_of(lo), self.cell_of(hi));
        let mut out = Vec::new();
        for l in ca[2]..=cb[2] {
            for j in ca[1]..=cb[1] {
                // A row of cells along x is one run of `items`.
                let row = self.index([0, j, l]);
                let (from, to) = (
                    self.starts[row + ca[0]] as usize,
                    self.starts[row + cb[0] + 1] as usize,
                );
                out.extend_from_slice(&self.items[from..to]);
            }
        }
        out
    }

    /// The nearest item to `p` by `distance` (an item's distance and what goes with
    /// it), ties to the lowest index: the cells round `p` searched in growing boxes
    /// until the nearest found lies within the box (so no item outside it can be
    /// nearer). `None` when there are no items.
    fn nearest<T>(&self, p: DVec3, distance: impl Fn(u32) -> (f64, T)) -> Option<(u32, f64, T)> {
        if self.count == 0 {
            return None;
        }
        let span = (self.hi - self.lo).max_element() + (p - self.lo).abs().max_element();
        let mut reach = self.cell;
        loop {
            let mut best: Option<(u32, f64, T)> = None;
            for k in self.candidates(p - DVec3::splat(reach), p + DVec3::splat(reach)) {
                let (d, extra) = distance(k);
                let better = match &best {
                    None => true,
                    Some((bk, bd, _)) => d < *bd || (d == *bd && k < *bk),
                };
                if better {
                    best = Some((k, d, extra));
                }
            }
            match best {
                Some(b) if b.1 <= reach => return Some(b),
                found if reach > span => return found,
                Some((_, d, _)) => reach = d.max(2.0 * reach),
                None => reach *= 2.0,
            }
        }
    }
}

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
