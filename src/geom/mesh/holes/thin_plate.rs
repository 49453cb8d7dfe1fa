//! The thin elastic plate over a hole (paper 002, section 3): the base surface bends as
//! little as it can while it keeps the heights, and so the slopes, of the mesh round
//! the hole. On a grid of heights above the projection plane the bending energy is the
//! sum over the nodes of the squared discrete Laplacian (each node's neighbours'
//! heights less its own, four neighbours inside the grid and fewer at its edge); the
//! nodes that lie on the mesh keep their heights, and the rest (the hole, and the grid
//! beyond the panel's edge) take the heights that make the energy least: the discrete
//! biharmonic equation, a least-squares problem solved by its normal equations, which
//! are banded when the unknowns are numbered line by line.
//!
//! Two rings of known nodes round the hole fix the position and the slope the plate
//! starts from there: the paper's position and slope conditions. A plane (every known
//! height on one plane) is reproduced exactly, and so is any quadratic height field
//! away from the grid's edge, its Laplacian being constant.

use crate::geom::banded::SymmetricBand;

/// A grid of heights, `nx + 1` nodes along x by `ny + 1` along y, row by row (`x`
/// fastest): the known ones given, the others to be found.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightGrid {
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Each node's height, where the mesh gives it.
    pub known: Vec<Option<f64>>,
}

/// Why a plate could not be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlateError {
    /// No node of the grid lies on the mesh: nothing holds the plate.
    #[error("no node of the grid lies on the mesh round the hole")]
    NothingKnown,
    /// The normal equations were singular (cannot happen with a known node; kept so a
    /// numerical breakdown is reported, not unwrapped).
    #[error("the plate's equations could not be solved")]
    Singular,
}

impl HeightGrid {
    fn index(&self, i: usize, j: usize) -> usize {
        j * (self.nx + 1) + i
    }

    /// The grid neighbours of node `(i, j)`.
    fn neighbours(&self, i: usize, j: usize) -> impl Iterator<Item = usize> + '_ {
        let (nx, ny) = (self.nx, self.ny);
        [
            (i > 0).then(|| (i - 1, j)),
            (i < nx).then(|| (i + 1, j)),
            (j > 0).then(|| (i, j - 1)),
            (j < ny).then(|| (i, j + 1)),
        ]
        .into_iter()
        .flatten()
        .map(move |(a, b)| b * (nx + 1) + a)
    }
}

/// Every node's height: the known ones as given, the others those of least bending.
pub fn solve_plate(grid: &HeightGrid) -> Result<Vec<f64>, PlateError> {
    let nodes = (grid.nx + 1) * (grid.ny + 1);
    if grid.known.iter().all(Option::is_none) {
        return Err(PlateError::NothingKnown);
    }
    // The unknown nodes numbered along the grid's shorter direction first (row by row
    // where the grid is taller than wide, column by column where it is wider), so
    // that the normal equations' band, about two lines of unknowns, is as narrow as
    // the grid allows: a slot's long grid costs a quarter of what row order would.
    let order: Vec<usize> = if grid.nx > grid.ny {
        (0..=grid.nx)
            .flat_map(|i| (0..=grid.ny).map(move |j| (i, j)))
            .map(|(i, j)| grid.index(i, j))
            .collect()
    } else {
        (0..nodes).collect()
    };
    let mut unknown = vec![usize::MAX; nodes];
    let mut count = 0;
    for k in order {
        if grid.known[k].is_none() {
            unknown[k] = count;
            count += 1;
        }
    }
    let mut heights: Vec<f64> = grid.known.iter().map(|h| h.unwrap_or(0.0)).collect();
    if count == 0 {
        return Ok(heights);
    }
    // The Laplacian at each node: +1 at each grid neighbour, -(neighbours) at itself;
    // only the rows that hold an unknown node count. Gathered once, in node order, for
    // the band and then the equations.
    let is_unknown = |n: usize| unknown[n] != usize::MAX;
    let mut rows: Vec<([(usize, f64); 5], usize)> = Vec::new();
    for j in 0..=grid.ny {
        for i in 0..=grid.nx {
            let mut row = [(0usize, 0.0f64); 5];
            let mut len = 0;
            for n in grid.neighbours(i, j) {
                row[len] = (n, 1.0);
                len += 1;
            }
            row[len] = (grid.index(i, j), -(len as f64));
            len += 1;
            if row[..len].iter().any(|&(n, _)| is_unknown(n)) {
                rows.push((row, len));
            }
        }
    }
    // The normal equations couple two unknowns that share a row; numbered as above
    // they lie at most two grid lines apart, and the band is the widest such gap (a
    // hole narrower than the grid has fewer unknowns between).
    let band = rows
        .iter()
        .map(|(row, len)| {
            let (lo, hi) = row[..*len]
                .iter()
                .filter(|&&(n, _)| is_unknown(n))
                .fold((usize::MAX, 0), |(lo, hi), &(n, _)| {
                    (lo.min(unknown[n]), hi.max(unknown[n]))
                });
            hi - lo
        })
        .max()
        .unwrap_or(0);
    let mut a = SymmetricBand::zeros(count, band);
    let mut rhs = vec![0.0; count];
    for (row, len) in &rows {
        let row = &row[..*len];
        let fixed: f64 = row
            .iter()
            .filter_map(|&(n, w)| grid.known[n].map(|h| w * h))
            .sum();
        for &(p, wp) in row.iter().filter(|&&(n, _)| is_unknown(n)) {
            let r = unknown[p];
            rhs[r] -= wp * fixed;
            // The lower triangle only: the matrix is symmetric.
            for &(q, wq) in row.iter().filter(|&&(n, _)| is_unknown(n)) {
                let c = unknown[q];
                if c <= r {
                    a.add(r, c, wp * wq);
                }
            }
        }
    }
    a.solve(&mut rhs).ok_or(PlateError::Singular)?;
    for (k, h) in heights.iter_mut().enumerate() {
        if unknown[k] != usize::MAX {
            *h = rhs[unknown[k]];
        }
    }
    Ok(heights)
}
