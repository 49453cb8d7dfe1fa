//! A uniform grid of cells over items with bounding boxes (triangles, segments,
//! points), for the mesh operations' near searches: the items whose boxes may meet a
//! box, and the item nearest a point. Rounding searches its triangles and guide with
//! it, hole filling its free nodes and free edges; without it each search tests every
//! item, quadratic on a fine mesh.

use glam::DVec3;

/// Items with bounding boxes, filed in a dense grid of cells over all their boxes, each
/// in the one cell holding its box's centre (so a search lists each item once, with no
/// sorting), each cell's items one after another (`starts[c]` to `starts[c + 1]` in
/// `items`). A search widens its box by `pad`, the largest half-size of an item's box,
/// to reach the items filed in a cell outside it.
#[derive(Debug, Clone)]
pub struct BoxGrid {
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
    pub fn new(boxes: &[(DVec3, DVec3)]) -> BoxGrid {
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
        // Counted in f64: for items of no size (points) the first cell is tiny and the
        // count of cells it would take overflows any integer.
        let most = (CELLS_PER_ITEM * boxes.len().max(8)) as f64;
        let cells_for = |cell: f64| {
            let d = ((hi - lo) / cell).floor() + DVec3::ONE;
            d.x * d.y * d.z
        };
        while cells_for(cell) > most {
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
    pub fn candidates(&self, lo: DVec3, hi: DVec3) -> Vec<u32> {
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
    pub fn nearest<T>(
        &self,
        p: DVec3,
        distance: impl Fn(u32) -> (f64, T),
    ) -> Option<(u32, f64, T)> {
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
