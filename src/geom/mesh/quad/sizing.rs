//! The element size wanted at each point of the plane a region is meshed in: one size,
//! or a grid of sizes finer where the surface the plane stands for curves (so an
//! element's chord sags at most the chordal tolerance off it) or is seen slanted.
//!
//! The grid is made from scattered samples (each a plane point and the size wanted
//! there), each node taking the least size sampled nearest it, then graded: a node's
//! size is at most its neighbour's plus [`GROWTH`] times their distance, so sizes change
//! gently (a mesher cannot go from 1 mm to 20 mm elements across one element) and nodes
//! no sample reached take the size their surroundings allow.

use glam::{DVec2, DVec3};

/// How fast the size may grow with distance (mm per mm): elements about a third larger
/// per element's length.
pub const GROWTH: f64 = 0.3;

/// The chord of a circle of radius `r` that sags `t` off it, `2 sqrt(2 r t - t^2)`
/// (the whole diameter when `t >= r`): the longest element edge a curve or surface of
/// that radius allows at a chordal tolerance of `t`.
pub fn chord_for_sag(r: f64, t: f64) -> f64 {
    if t >= r {
        2.0 * r
    } else {
        2.0 * (2.0 * r * t - t * t).sqrt()
    }
}

/// The radius of the circle through three points (infinite on a line).
pub fn circumradius(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, bc, ca) = (a.distance(b), b.distance(c), c.distance(a));
    let twice_area = (b - a).cross(c - a).length();
    if twice_area <= 1e-15 * ab * bc {
        f64::INFINITY
    } else {
        ab * bc * ca / (2.0 * twice_area)
    }
}

/// Along a polyline of samples of a curve, each piece's length over the longest chord
/// the curvature there allows at `tolerance` (at most `size`; the curvature read from
/// the circle through each sample and its neighbours): summed, how many elements the
/// curve needs, and where they go when divided evenly in this measure.
pub fn chord_measures(points: &[DVec3], size: f64, tolerance: f64) -> Vec<f64> {
    let allowed: Vec<f64> = (0..points.len())
        .map(|k| {
            if k == 0 || k + 1 >= points.len() || tolerance <= 0.0 {
                size
            } else {
                size.min(chord_for_sag(
                    circumradius(points[k - 1], points[k], points[k + 1]),
                    tolerance,
                ))
            }
        })
        .collect();
    points
        .windows(2)
        .enumerate()
        .map(|(k, w)| w[0].distance(w[1]) / allowed[k].min(allowed[k + 1]).max(1e-9))
        .collect()
}

/// The size wanted at a point: `size`, or less where the grid asks.
#[derive(Debug, Clone, Copy)]
pub struct Sizes<'a> {
    /// The element size (mm): the largest wanted anywhere.
    pub size: f64,
    /// Finer sizes over the plane, if any.
    pub grid: Option<&'a SizeGrid>,
}

impl<'a> Sizes<'a> {
    /// One size everywhere.
    pub fn uniform(size: f64) -> Sizes<'static> {
        Sizes { size, grid: None }
    }

    /// The size wanted at `p`.
    pub fn at(&self, p: DVec2) -> f64 {
        match self.grid {
            Some(g) => g.at(p).min(self.size),
            None => self.size,
        }
    }
}

/// Sizes at the nodes of a regular grid over the plane, read between nodes bilinearly
/// (outside the grid, at its nearest edge).
#[derive(Debug, Clone, PartialEq)]
pub struct SizeGrid {
    origin: DVec2,
    step: DVec2,
    nx: usize,
    ny: usize,
    sizes: Vec<f64>,
}

impl SizeGrid {
    /// The grid of `cells` x `cells` cells over the samples' bounding box, each node
    /// the least size sampled nearest it, then graded by [`GROWTH`]. `None` without a
    /// finite positive sample.
    pub fn from_samples(samples: &[(DVec2, f64)], cells: usize) -> Option<SizeGrid> {
        let good: Vec<(DVec2, f64)> = samples
            .iter()
            .copied()
            .filter(|(p, h)| p.is_finite() && h.is_finite() && *h > 0.0)
            .collect();
        let first = good.first()?;
        let (mut lo, mut hi) = (first.0, first.0);
        for (p, _) in &good {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let cells = cells.max(1);
        let step = ((hi - lo) / cells as f64).max(DVec2::splat(1e-9));
        let (nx, ny) = (cells + 1, cells + 1);
        let mut sizes = vec![f64::INFINITY; nx * ny];
        for (p, h) in &good {
            let c = ((*p - lo) / step).round();
            let (i, j) = (
                (c.x.max(0.0) as usize).min(nx - 1),
                (c.y.max(0.0) as usize).min(ny - 1),
            );
            let slot = &mut sizes[j * nx + i];
            *slot = slot.min(*h);
        }
        let mut grid = SizeGrid {
            origin: lo,
            step,
            nx,
            ny,
            sizes,
        };
        grid.grade();
        Some(grid)
    }

    /// Limits every node's size to its neighbours' plus [`GROWTH`] times the distance
    /// (two chamfer sweeps, forwards and backwards, over the eight neighbours).
    fn grade(&mut self) {
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        let step = self.step;
        let reach = move |di: isize, dj: isize| {
            GROWTH * DVec2::new(di as f64 * step.x, dj as f64 * step.y).length()
        };
        let before = [(-1, 0), (-1, -1), (0, -1), (1, -1)];
        let after = [(1, 0), (1, 1), (0, 1), (-1, 1)];
        for _ in 0..2 {
            for j in 0..ny {
                for i in 0..nx {
                    self.relax(i, j, &before, &reach);
                }
            }
            for j in (0..ny).rev() {
                for i in (0..nx).rev() {
                    self.relax(i, j, &after, &reach);
                }
            }
        }
    }

    fn relax(
        &mut self,
        i: isize,
        j: isize,
        around: &[(isize, isize)],
        reach: &impl Fn(isize, isize) -> f64,
    ) {
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        let here = (j * nx + i) as usize;
        for &(di, dj) in around {
            let (a, b) = (i + di, j + dj);
            if a < 0 || b < 0 || a >= nx || b >= ny {
                continue;
            }
            let there = self.sizes[(b * nx + a) as usize] + reach(di, dj);
            if there < self.sizes[here] {
                self.sizes[here] = there;
            }
        }
    }

    /// The size at `p` (bilinear between the nodes round it).
    pub fn at(&self, p: DVec2) -> f64 {
        let c = (p - self.origin) / self.step;
        let fx = c.x.clamp(0.0, (self.nx - 1) as f64);
        let fy = c.y.clamp(0.0, (self.ny - 1) as f64);
        let (i, j) = (
            (fx.floor() as usize).min(self.nx.saturating_sub(2)),
            (fy.floor() as usize).min(self.ny.saturating_sub(2)),
        );
        let (s, t) = (fx - i as f64, fy - j as f64);
        let node =
            |a: usize, b: usize| self.sizes[b.min(self.ny - 1) * self.nx + a.min(self.nx - 1)];
        (1.0 - t) * ((1.0 - s) * node(i, j) + s * node(i + 1, j))
            + t * ((1.0 - s) * node(i, j + 1) + s * node(i + 1, j + 1))
    }

    /// The least size anywhere on the grid.
    pub fn least(&self) -> f64 {
        self.sizes.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// About how many elements of the grid's sizes (at most `size`) fill `area`: the
    /// area over the mean of `1 / h^2` across the grid.
    pub fn elements(&self, area: f64, size: f64) -> f64 {
        let mean: f64 = self
            .sizes
            .iter()
            .map(|h| 1.0 / h.min(size).powi(2))
            .sum::<f64>()
            / self.sizes.len() as f64;
        area * mean
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fine_sample_grades_out_to_the_coarse_size() {
        let mut samples = vec![(DVec2::ZERO, 1.0)];
        samples.push((DVec2::new(100.0, 100.0), 50.0));
        let grid = SizeGrid::from_samples(&samples, 20).expect("a grid");
        assert!((grid.at(DVec2::ZERO) - 1.0).abs() < 1e-12);
        // 30 mm away the size has grown by GROWTH per mm, no more.
        let at = DVec2::new(30.0, 0.0);
        assert!(
            (grid.at(at) - (1.0 + GROWTH * 30.0)).abs() < 1e-9,
            "{}",
            grid.at(at)
        );
        let sizes = Sizes {
            size: 5.0,
            grid: Some(&grid),
        };
        assert_eq!(sizes.at(DVec2::new(100.0, 100.0)), 5.0);
    }

    #[test]
    fn no_usable_sample_gives_no_grid() {
        assert!(SizeGrid::from_samples(&[(DVec2::ZERO, f64::NAN)], 8).is_none());
        assert!(SizeGrid::from_samples(&[], 8).is_none());
    }
}
