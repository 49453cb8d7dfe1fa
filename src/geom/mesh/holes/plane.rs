//! The projection plane of a hole (paper 002, section 3, Fig. 3): square to the mean of
//! the normals at the loop's nodes, through the loop's middle, its in-plane axes along
//! the loop's longest and shortest spread (so the grid over a slot is long and narrow,
//! not square).

use glam::{DVec2, DVec3};

/// A plane with axes: `origin`, the unit in-plane axes `e1` and `e2`, and the unit
/// `normal` (`e1 x e2`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProjectionPlane {
    /// A point of the plane: the loop's mean node.
    pub origin: DVec3,
    /// The in-plane axis along the loop's longest spread.
    pub e1: DVec3,
    /// The other in-plane axis, `normal x e1`.
    pub e2: DVec3,
    /// The unit normal: the mean of the loop's node normals.
    pub normal: DVec3,
}

impl ProjectionPlane {
    /// `p` in the plane's coordinates: where it projects along the normal, and its
    /// height above the plane.
    pub fn to_plane(&self, p: DVec3) -> (DVec2, f64) {
        let d = p - self.origin;
        (
            DVec2::new(d.dot(self.e1), d.dot(self.e2)),
            d.dot(self.normal),
        )
    }

    /// The point at `q` in the plane, `height` above it.
    pub fn from_plane(&self, q: DVec2, height: f64) -> DVec3 {
        self.origin + q.x * self.e1 + q.y * self.e2 + height * self.normal
    }
}

/// The projection plane of the loop through `points` whose nodes have the unit normals
/// `normals`; `None` when the normals cancel out (a loop whose faces turn every way).
pub fn loop_plane(points: &[DVec3], normals: &[DVec3]) -> Option<ProjectionPlane> {
    let normal = normals.iter().copied().sum::<DVec3>().try_normalize()?;
    let n = points.len().max(1) as f64;
    let origin = points.iter().copied().sum::<DVec3>() / n;
    // The in-plane spread of the loop, a 2 x 2 symmetric matrix in any in-plane frame.
    let a = normal.any_orthonormal_vector();
    let b = normal.cross(a);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points {
        let d = *p - origin;
        let (x, y) = (d.dot(a), d.dot(b));
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
    }
    // The direction of largest spread: the angle that diagonalises the matrix.
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let e1 = (angle.cos() * a + angle.sin() * b).normalize();
    let e2 = normal.cross(e1);
    Some(ProjectionPlane {
        origin,
        e1,
        e2,
        normal,
    })
}
