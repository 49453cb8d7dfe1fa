//! Shell element quality as an FE engineer reads it off a mesh, computed the same way
//! for any mesh (ours or a peer's), so two meshers can be compared figure for figure.
//!
//! - **Scaled Jacobian**: at each corner, the cross product of the two sides leaving it
//!   over the product of their lengths (the sine of the corner angle), signed against
//!   the element's normal; the element's value is the least of its corners. 1 for a
//!   square, 0 for a corner folded flat, negative for an inverted (or concave) corner.
//!   For a triangle it is scaled by 2/sqrt(3), so an equilateral one scores 1.
//! - **Corner angles**: the smallest and largest over the mesh.
//! - **Aspect ratio**: the element's longest side over its shortest.

use glam::{DVec2, DVec3};

use crate::geom::mesh::Mesh;

/// The least over an element's `k` corners of `sine(i)`, corner `i`'s signed sine,
/// scaled so an equilateral triangle scores 1 (see the module notes).
fn least_corner(k: usize, sine: impl Fn(usize) -> f64) -> f64 {
    let scale = if k == 3 { 2.0 / 3f64.sqrt() } else { 1.0 };
    (0..k)
        .map(|i| (sine(i) * scale).min(1.0))
        .fold(f64::INFINITY, f64::min)
}

/// The scaled Jacobian of a plane element, corners counter-clockwise (see the module
/// notes).
pub fn scaled_jacobian_2d(corners: &[DVec2]) -> f64 {
    let k = corners.len();
    if k > 4 {
        return least_corner(k, |i| corner_sine_2d(corners, i));
    }
    // The same numbers as `corner_sine_2d` gives, each side's vector and length
    // worked out once rather than at both its corners (the meshing judges elements
    // millions of times): corner i's sides are side i and side i - 1 turned round,
    // and turning a vector round (`b - a` for `a - b`) changes no bit of it or of its
    // length.
    let mut side = [DVec2::ZERO; 4];
    let mut length = [0.0; 4];
    for i in 0..k {
        side[i] = corners[(i + 1) % k] - corners[i];
        length[i] = side[i].length();
    }
    least_corner(k, |i| {
        let before = (i + k - 1) % k;
        let l = length[i] * length[before];
        if l <= f64::MIN_POSITIVE {
            -1.0
        } else {
            side[i].perp_dot(-side[before]) / l
        }
    })
}

/// The worst scaled Jacobian of plane `quads` (node ids into `points`): how the
/// meshing steps judge a set of quads before and after a change (infinite for none).
pub fn worst_quad_2d(points: &[DVec2], quads: &[[u32; 4]]) -> f64 {
    quads
        .iter()
        .map(|q| scaled_jacobian_2d(&q.map(|v| points[v as usize])))
        .fold(f64::INFINITY, f64::min)
}

/// The mean of a plane element's corner sines (signed, corners counter-clockwise): 1
/// for a square, 0 for an element whose nodes lie on one line. Where the scaled
/// Jacobian sees only the worst corner, this tells an element with one straight corner
/// from one of no area.
pub fn mean_corner_sine_2d(corners: &[DVec2]) -> f64 {
    let k = corners.len();
    (0..k).map(|i| corner_sine_2d(corners, i)).sum::<f64>() / k as f64
}

/// The sine of corner `i` of a plane element: the cross product of its two sides over
/// their lengths (-1 where a side has no length).
fn corner_sine_2d(corners: &[DVec2], i: usize) -> f64 {
    let k = corners.len();
    let at = corners[i];
    let a = corners[(i + 1) % k] - at;
    let b = corners[(i + k - 1) % k] - at;
    let l = a.length() * b.length();
    if l <= f64::MIN_POSITIVE {
        -1.0
    } else {
        a.perp_dot(b) / l
    }
}

/// The element's normal: for a quad, across its diagonals; for a triangle, its plane's.
fn element_normal(corners: &[DVec3]) -> DVec3 {
    if corners.len() == 4 {
        (corners[2] - corners[0])
            .cross(corners[3] - corners[1])
            .normalize_or_zero()
    } else {
        (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize_or_zero()
    }
}

/// The scaled Jacobian of a shell element in space, signed against its own normal (see
/// the module notes).
pub fn scaled_jacobian(corners: &[DVec3]) -> f64 {
    let k = corners.len();
    let n = element_normal(corners);
    least_corner(k, |i| {
        let at = corners[i];
        let a = corners[(i + 1) % k] - at;
        let b = corners[(i + k - 1) % k] - at;
        let l = a.length() * b.length();
        if l <= f64::MIN_POSITIVE || n == DVec3::ZERO {
            -1.0
        } else {
            a.cross(b).dot(n) / l
        }
    })
}

/// A mesh's element quality.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshQuality {
    /// How many quads and triangles.
    pub quads: usize,
    pub triangles: usize,
    /// The least and the mean scaled Jacobian over the elements.
    pub min_scaled_jacobian: f64,
    pub mean_scaled_jacobian: f64,
    /// The smallest and largest corner angle (deg).
    pub min_angle: f64,
    pub max_angle: f64,
    /// The largest aspect ratio (longest side over shortest).
    pub max_aspect: f64,
    /// Elements whose scaled Jacobian is zero or less (folded or inverted).
    pub inverted: usize,
}

impl MeshQuality {
    /// The share of elements that are quads.
    pub fn quad_share(&self) -> f64 {
        self.quads as f64 / (self.quads + self.triangles).max(1) as f64
    }
}

/// The quality of every element of `mesh` (see the module notes).
pub fn mesh_quality(mesh: &Mesh) -> MeshQuality {
    let mut q = MeshQuality {
        quads: 0,
        triangles: 0,
        min_scaled_jacobian: f64::INFINITY,
        mean_scaled_jacobian: 0.0,
        min_angle: 180.0,
        max_angle: 0.0,
        max_aspect: 1.0,
        inverted: 0,
    };
    let mut sum = 0.0;
    for face in mesh.faces() {
        let corners: Vec<DVec3> = face
            .indices()
            .iter()
            .map(|&v| mesh.positions()[v as usize])
            .collect();
        let k = corners.len();
        if k == 4 {
            q.quads += 1;
        } else {
            q.triangles += 1;
        }
        let j = scaled_jacobian(&corners);
        sum += j;
        q.min_scaled_jacobian = q.min_scaled_jacobian.min(j);
        if j <= 0.0 {
            q.inverted += 1;
        }
        let (mut shortest, mut longest) = (f64::INFINITY, 0.0f64);
        for i in 0..k {
            let a = corners[(i + 1) % k] - corners[i];
            let b = corners[(i + k - 1) % k] - corners[i];
            let angle = a.angle_between(b).to_degrees();
            q.min_angle = q.min_angle.min(angle);
            q.max_angle = q.max_angle.max(angle);
            shortest = shortest.min(a.length());
            longest = longest.max(a.length());
        }
        q.max_aspect = q.max_aspect.max(longest / shortest.max(f64::MIN_POSITIVE));
    }
    let n = q.quads + q.triangles;
    q.mean_scaled_jacobian = if n == 0 { 0.0 } else { sum / n as f64 };
    if n == 0 {
        q.min_scaled_jacobian = 0.0;
        q.min_angle = 0.0;
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_scores_one_and_a_rhombus_its_sine() {
        let square = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        assert!((scaled_jacobian_2d(&square) - 1.0).abs() < 1e-15);
        let a = 60f64.to_radians();
        let rhombus = [
            DVec2::ZERO,
            DVec2::X,
            DVec2::X + DVec2::new(a.cos(), a.sin()),
            DVec2::new(a.cos(), a.sin()),
        ];
        assert!((scaled_jacobian_2d(&rhombus) - a.sin()).abs() < 1e-12);
        let flipped: Vec<DVec2> = square.iter().rev().copied().collect();
        assert!(scaled_jacobian_2d(&flipped) < 0.0);
        let equilateral = [DVec2::ZERO, DVec2::X, DVec2::new(0.5, 0.75f64.sqrt())];
        assert!((scaled_jacobian_2d(&equilateral) - 1.0).abs() < 1e-12);
    }
}
