//! How far one tessellated shape lies from another: the largest and the mean distance
//! from sample points of one to the nearest point of the other, for reviewing an edit
//! (`dieface diff`). Triangles and polylines are searched through the rounding's grids
//! ([`TriangleGrid`], [`PolylineIndex`]), so the cost grows with the samples times a few
//! cells, not with the product of the two shapes' sizes.

use glam::DVec3;

use super::rounding::index::{PolylineIndex, Triangle, TriangleGrid};

/// The distances from a set of sample points to a shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deviation {
    /// The largest distance (mm).
    pub max: f64,
    /// The sample point where it is reached.
    pub at: DVec3,
    /// The mean distance over the samples (mm).
    pub mean: f64,
    /// How many samples were measured.
    pub samples: usize,
}

impl Deviation {
    /// The larger of two deviations (`self` on a tie), with the mean of both weighted by
    /// their samples: the two directions of a symmetric comparison put together.
    pub fn merge(self, other: Deviation) -> Deviation {
        let samples = self.samples + other.samples;
        let mean = if samples == 0 {
            0.0
        } else {
            (self.mean * self.samples as f64 + other.mean * other.samples as f64) / samples as f64
        };
        let (max, at) = if other.max > self.max {
            (other.max, other.at)
        } else {
            (self.max, self.at)
        };
        Deviation {
            max,
            at,
            mean,
            samples,
        }
    }
}

/// The deviation of `samples` from whatever `nearest` measures (a distance per point),
/// or `None` when there is no sample or nothing to measure against (an infinite
/// distance).
fn deviation(samples: &[DVec3], nearest: impl Fn(DVec3) -> f64) -> Option<Deviation> {
    let mut best: Option<(f64, DVec3)> = None;
    let mut sum = 0.0;
    for &p in samples {
        let d = nearest(p);
        if !d.is_finite() {
            return None;
        }
        sum += d;
        if best.is_none_or(|(m, _)| d > m) {
            best = Some((d, p));
        }
    }
    let (max, at) = best?;
    Some(Deviation {
        max,
        at,
        mean: sum / samples.len() as f64,
        samples: samples.len(),
    })
}

/// Triangles indexed for the distance from any point to the nearest of them: a
/// tessellation coloured by how far it lies from another, point by point (built once,
/// asked for many points).
pub struct NearestTriangles {
    grid: Option<TriangleGrid>,
}

impl NearestTriangles {
    /// The index of `triangles` (none: every distance is infinite).
    pub fn new(triangles: Vec<Triangle>) -> NearestTriangles {
        NearestTriangles {
            grid: (!triangles.is_empty()).then(|| TriangleGrid::new(triangles)),
        }
    }

    /// Each of `points`' distance to the nearest triangle (infinite with none).
    pub fn distances(&self, points: &[DVec3]) -> Vec<f64> {
        points
            .iter()
            .map(|&p| {
                self.grid
                    .as_ref()
                    .and_then(|g| g.nearest(p))
                    .map_or(f64::INFINITY, |n| n.1)
            })
            .collect()
    }
}

/// Sample points of a triangle soup: its corners and each triangle's centroid (so a
/// large flat triangle is measured inside as well as at its corners).
pub fn triangle_samples(triangles: &[Triangle]) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(triangles.len() * 4);
    for t in triangles {
        out.extend_from_slice(t);
        out.push((t[0] + t[1] + t[2]) / 3.0);
    }
    out
}

/// Sample points of a polyline: its points and each segment's midpoint.
pub fn polyline_samples(points: &[DVec3]) -> Vec<DVec3> {
    let mut out = points.to_vec();
    out.extend(points.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    out
}

/// How far the triangles `new` lie from the triangles `old`, both ways: each side's
/// samples ([`triangle_samples`]) measured to the nearest point of the other side's
/// triangles, the largest of both and the mean over all samples. `None` when either
/// side has no triangle.
pub fn triangles_deviation(old: &[Triangle], new: &[Triangle]) -> Option<Deviation> {
    if old.is_empty() || new.is_empty() {
        return None;
    }
    let to_old = TriangleGrid::new(old.to_vec());
    let to_new = TriangleGrid::new(new.to_vec());
    let measure = |grid: &TriangleGrid, samples: &[DVec3]| {
        deviation(samples, |p| grid.nearest(p).map_or(f64::INFINITY, |n| n.1))
    };
    let forward = measure(&to_old, &triangle_samples(new))?;
    let back = measure(&to_new, &triangle_samples(old))?;
    Some(forward.merge(back))
}

/// How far the polylines `new` lie from the polylines `old`, both ways, as
/// [`triangles_deviation`] measures triangles: each sample to the nearest of the other
/// side's polylines. `None` when either side has no segment.
pub fn polylines_deviation(old: &[Vec<DVec3>], new: &[Vec<DVec3>]) -> Option<Deviation> {
    let index = |lines: &[Vec<DVec3>]| -> Vec<PolylineIndex> {
        lines
            .iter()
            .filter(|l| l.len() >= 2)
            .map(|l| PolylineIndex::new(l))
            .collect()
    };
    let samples = |lines: &[Vec<DVec3>]| -> Vec<DVec3> {
        lines
            .iter()
            .filter(|l| l.len() >= 2)
            .flat_map(|l| polyline_samples(l))
            .collect()
    };
    let (old_index, new_index) = (index(old), index(new));
    if old_index.is_empty() || new_index.is_empty() {
        return None;
    }
    let measure = |indices: &[PolylineIndex], samples: &[DVec3]| {
        deviation(samples, |p| {
            indices
                .iter()
                .map(|i| i.nearest(p).0)
                .fold(f64::INFINITY, f64::min)
        })
    };
    let forward = measure(&old_index, &samples(new))?;
    let back = measure(&new_index, &samples(old))?;
    Some(forward.merge(back))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(z: f64, shift: f64) -> Vec<Triangle> {
        let p = |x: f64, y: f64| DVec3::new(x + shift, y, z);
        vec![
            [p(0.0, 0.0), p(10.0, 0.0), p(10.0, 10.0)],
            [p(0.0, 0.0), p(10.0, 10.0), p(0.0, 10.0)],
        ]
    }

    #[test]
    fn a_square_lifted_by_two_is_two_away_everywhere() {
        let d = triangles_deviation(&square(0.0, 0.0), &square(2.0, 0.0)).expect("both sides");
        assert!(
            (d.max - 2.0).abs() < 1e-12 && (d.mean - 2.0).abs() < 1e-12,
            "{d:?}"
        );
    }

    #[test]
    fn a_square_slid_along_itself_is_measured_at_its_overhang() {
        let d = triangles_deviation(&square(0.0, 0.0), &square(0.0, 3.0)).expect("both sides");
        assert!((d.max - 3.0).abs() < 1e-12, "{d:?}");
        assert!(d.mean < 3.0 && d.mean > 0.0, "{d:?}");
    }

    #[test]
    fn a_polyline_moved_sideways() {
        let line = |y: f64| vec![DVec3::new(0.0, y, 0.0), DVec3::new(100.0, y, 0.0)];
        let d = polylines_deviation(&[line(0.0)], &[line(5.0)]).expect("both sides");
        assert!(
            (d.max - 5.0).abs() < 1e-12 && (d.mean - 5.0).abs() < 1e-12,
            "{d:?}"
        );
        assert!(polylines_deviation(&[], &[line(0.0)]).is_none());
    }
}
