//! A banded linear solve for B-spline collocation systems.
//!
//! Interpolating n points with a degree-p B-spline gives an n x n system whose rows
//! each hold p + 1 neighbouring basis values: a band matrix. Gaussian elimination with
//! partial pivoting inside the band (LAPACK's `gbsv` scheme) solves it in
//! O(n p^2) instead of the O(n^3) of a dense LU, which is what lets a bead or a step
//! draw interpolate hundreds of sections per build.

/// A square band matrix being built, then solved in place.
#[derive(Debug, Clone)]
pub struct BandMatrix {
    n: usize,
    /// Sub-diagonals the matrix may hold.
    lower: usize,
    /// Super-diagonals the matrix may hold (before pivoting widens them by `lower`).
    upper: usize,
    /// Row `i` keeps columns `i - lower ..= i + lower + upper` (row-major, fixed width).
    data: Vec<f64>,
}

impl BandMatrix {
    /// An n x n zero matrix with `lower` sub- and `upper` super-diagonals.
    pub fn zeros(n: usize, lower: usize, upper: usize) -> Self {
        let width = 2 * lower + upper + 1;
        Self {
            n,
            lower,
            upper,
            data: vec![0.0; n * width],
        }
    }

    fn width(&self) -> usize {
        2 * self.lower + self.upper + 1
    }

    /// Storage index of entry (i, j); `None` outside the stored band.
    fn index(&self, i: usize, j: usize) -> Option<usize> {
        let first = i as isize - self.lower as isize;
        let offset = j as isize - first;
        (i < self.n && j < self.n && offset >= 0 && (offset as usize) < self.width())
            .then(|| i * self.width() + offset as usize)
    }

    /// Entry (i, j); zero outside the band.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.index(i, j).map_or(0.0, |k| self.data[k])
    }

    /// Sets entry (i, j). Returns false when (i, j) lies outside the declared band
    /// (`j + lower < i` or `j > i + upper`), which is a caller's bug.
    pub fn set(&mut self, i: usize, j: usize, value: f64) -> bool {
        if j + self.lower < i || j > i + self.upper {
            return false;
        }
        match self.index(i, j) {
            Some(k) => {
                self.data[k] = value;
                true
            }
            None => false,
        }
    }

    /// Solves `A X = B` for the `columns` right-hand sides stored row by row in `rhs`
    /// (`rhs[i * columns + c]`), overwriting `rhs` with X. Consumes the matrix (it
    /// holds the factors afterwards). `None` when a pivot is exactly zero.
    pub fn solve(mut self, rhs: &mut [f64], columns: usize) -> Option<()> {
        let n = self.n;
        assert_eq!(
            rhs.len(),
            n * columns,
            "one right-hand-side row per matrix row"
        );
        let reach = self.lower + self.upper;
        for k in 0..n {
            let last_row = (k + self.lower).min(n - 1);
            let last_col = (k + reach).min(n - 1);
            // Partial pivoting within the band.
            let pivot = (k..=last_row)
                .max_by(|&a, &b| self.get(a, k).abs().total_cmp(&self.get(b, k).abs()))
                .unwrap_or(k);
            if self.get(pivot, k) == 0.0 {
                return None;
            }
            if pivot != k {
                for j in k..=last_col {
                    let (a, b) = (self.get(k, j), self.get(pivot, j));
                    self.put(k, j, b);
                    self.put(pivot, j, a);
                }
                for c in 0..columns {
                    rhs.swap(k * columns + c, pivot * columns + c);
                }
            }
            let diagonal = self.get(k, k);
            for i in k + 1..=last_row {
                let factor = self.get(i, k) / diagonal;
                if factor == 0.0 {
                    continue;
                }
                self.put(i, k, 0.0);
                for j in k + 1..=last_col {
                    let v = self.get(i, j) - factor * self.get(k, j);
                    self.put(i, j, v);
                }
                for c in 0..columns {
                    rhs[i * columns + c] -= factor * rhs[k * columns + c];
                }
            }
        }
        for k in (0..n).rev() {
            let last_col = (k + reach).min(n - 1);
            for c in 0..columns {
                let mut sum = rhs[k * columns + c];
                for j in k + 1..=last_col {
                    sum -= self.get(k, j) * rhs[j * columns + c];
                }
                rhs[k * columns + c] = sum / self.get(k, k);
            }
        }
        Some(())
    }

    /// Writes inside the stored band during elimination (fill-in stays inside it).
    fn put(&mut self, i: usize, j: usize, value: f64) {
        let k = self
            .index(i, j)
            .expect("elimination only touches columns within lower + upper of the pivot row");
        self.data[k] = value;
    }
}

/// A symmetric positive definite band matrix being built, then solved in place by a
/// banded Cholesky factorisation (`A = L Lᵀ`, LAPACK's `pbsv` scheme). Least-squares
/// normal equations are such matrices: no pivoting is needed, only the lower band is
/// stored, and each step is a dot product of two contiguous rows, so it solves in
/// about a quarter of the work of [`BandMatrix`]'s pivoted elimination.
#[derive(Debug, Clone)]
pub struct SymmetricBand {
    n: usize,
    /// Sub-diagonals (equal to the super-diagonals).
    band: usize,
    /// Row `i` keeps columns `i - band ..= i` (row-major, `band + 1` wide; the columns
    /// before 0 of the first rows are zero padding).
    data: Vec<f64>,
}

impl SymmetricBand {
    /// An n x n zero matrix with `band` diagonals on either side of the main one.
    pub fn zeros(n: usize, band: usize) -> Self {
        Self {
            n,
            band,
            data: vec![0.0; n * (band + 1)],
        }
    }

    /// Storage index of entry (i, j) with `j <= i`, `None` outside the band.
    fn index(&self, i: usize, j: usize) -> Option<usize> {
        (i < self.n && j <= i && i - j <= self.band)
            .then(|| i * (self.band + 1) + self.band - (i - j))
    }

    /// Entry (i, j) (either triangle); zero outside the band.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.index(i.max(j), i.min(j)).map_or(0.0, |k| self.data[k])
    }

    /// Adds `value` to entry (i, j) and so to (j, i). Returns false outside the band
    /// (a caller's bug).
    pub fn add(&mut self, i: usize, j: usize, value: f64) -> bool {
        match self.index(i.max(j), i.min(j)) {
            Some(k) => {
                self.data[k] += value;
                true
            }
            None => false,
        }
    }

    /// Solves `A x = b`, overwriting `rhs` (b) with x. Consumes the matrix (it holds
    /// the factor afterwards). `None` when the matrix is not positive definite (a pivot
    /// at or below zero: the system is singular).
    pub fn solve(mut self, rhs: &mut [f64]) -> Option<()> {
        let (n, w) = (self.n, self.band + 1);
        assert_eq!(rhs.len(), n, "one right-hand side per matrix row");
        // Factor row by row: L[i][j] = (A[i][j] - sum_k L[i][k] L[j][k]) / L[j][j] over
        // the columns k both rows hold, then L[i][i] from the row's own squares.
        for i in 0..n {
            let first = i.saturating_sub(self.band);
            for j in first..=i {
                // Columns k in first..j of rows i and j, as slices of their storage.
                let row_i = i * w + self.band - (i - first);
                let row_j = j * w + self.band - (j - first);
                let len = j - first;
                let dot: f64 = self.data[row_i..row_i + len]
                    .iter()
                    .zip(&self.data[row_j..row_j + len])
                    .map(|(a, b)| a * b)
                    .sum();
                let at = i * w + self.band - (i - j);
                let value = self.data[at] - dot;
                if j == i {
                    if value <= 0.0 || !value.is_finite() {
                        return None;
                    }
                    self.data[at] = value.sqrt();
                } else {
                    self.data[at] = value / self.data[j * w + self.band];
                }
            }
        }
        // L y = b, then Lᵀ x = y; row i's stored columns first..i lie just before its
        // diagonal.
        let row = |i: usize| {
            let first = i.saturating_sub(self.band);
            let diagonal = i * w + self.band;
            (first, diagonal - (i - first), diagonal)
        };
        for i in 0..n {
            let (first, start, diagonal) = row(i);
            let dot: f64 = self.data[start..diagonal]
                .iter()
                .zip(&rhs[first..i])
                .map(|(l, y)| l * y)
                .sum();
            rhs[i] = (rhs[i] - dot) / self.data[diagonal];
        }
        for i in (0..n).rev() {
            let (first, start, diagonal) = row(i);
            rhs[i] /= self.data[diagonal];
            let xi = rhs[i];
            for (x, l) in rhs[first..i].iter_mut().zip(&self.data[start..diagonal]) {
                *x -= l * xi;
            }
        }
        Some(())
    }
}
