//! The vector spaces the kernel computes in.
//!
//! Curves are generic over their control-point type so that one implementation serves
//! the 2-D profiles the designer draws in a view and the 3-D curves of the die face.
//! [`Point`] is implemented for glam's `DVec2` and `DVec3`; algorithms that only need
//! linear combinations (knot insertion, degree elevation) work on any [`Linear`] type,
//! including homogeneous points.

use glam::{DVec2, DVec3, DVec4};
use std::fmt::Debug;
use std::ops::{Add, Mul, Sub};

/// A value that can be added, subtracted and scaled: enough for the B-spline
/// algorithms that only form affine or linear combinations of control points.
pub trait Linear:
    Copy + Debug + PartialEq + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self>
{
    /// The additive identity.
    const ZERO: Self;
}

/// A Euclidean point or vector in 2 or 3 dimensions.
pub trait Point: Linear + Send + Sync + 'static {
    /// Number of coordinates.
    const DIM: usize;
    /// Scalar product.
    fn dot(self, other: Self) -> f64;
    /// Euclidean length.
    fn length(self) -> f64 {
        self.dot(self).sqrt()
    }
    /// Distance between two points.
    fn distance(self, other: Self) -> f64 {
        (self - other).length()
    }
    /// The point in 3-D; 2-D points get z = 0 (the view's plane).
    fn to_3d(self) -> DVec3;
    /// Coordinate `i` (0 = x, 1 = y, 2 = z).
    fn coord(self, i: usize) -> f64;
    /// Whether every coordinate is finite.
    fn is_finite(self) -> bool;
    /// The unit vector along coordinate axis `i` (zero for `i >= DIM`).
    fn axis(i: usize) -> Self;
}

impl Linear for f64 {
    const ZERO: Self = 0.0;
}

impl Linear for DVec2 {
    const ZERO: Self = DVec2::ZERO;
}

impl Linear for DVec3 {
    const ZERO: Self = DVec3::ZERO;
}

impl Linear for DVec4 {
    const ZERO: Self = DVec4::ZERO;
}

impl Point for DVec2 {
    const DIM: usize = 2;
    fn dot(self, other: Self) -> f64 {
        DVec2::dot(self, other)
    }
    fn to_3d(self) -> DVec3 {
        self.extend(0.0)
    }
    fn coord(self, i: usize) -> f64 {
        self.to_array().get(i).copied().unwrap_or(0.0)
    }
    fn is_finite(self) -> bool {
        DVec2::is_finite(self)
    }
    fn axis(i: usize) -> Self {
        [DVec2::X, DVec2::Y].get(i).copied().unwrap_or(DVec2::ZERO)
    }
}

impl Point for DVec3 {
    const DIM: usize = 3;
    fn dot(self, other: Self) -> f64 {
        DVec3::dot(self, other)
    }
    fn to_3d(self) -> DVec3 {
        self
    }
    fn coord(self, i: usize) -> f64 {
        self.to_array().get(i).copied().unwrap_or(0.0)
    }
    fn is_finite(self) -> bool {
        DVec3::is_finite(self)
    }
    fn axis(i: usize) -> Self {
        [DVec3::X, DVec3::Y, DVec3::Z]
            .get(i)
            .copied()
            .unwrap_or(DVec3::ZERO)
    }
}

/// 4-D points: 3-D control points in homogeneous form `(wx, wy, wz, w)`, so that
/// interpolation can run across rational sections (skinning) as if they were polynomial.
impl Point for DVec4 {
    const DIM: usize = 4;
    fn dot(self, other: Self) -> f64 {
        DVec4::dot(self, other)
    }
    fn to_3d(self) -> DVec3 {
        self.truncate()
    }
    fn coord(self, i: usize) -> f64 {
        self.to_array().get(i).copied().unwrap_or(0.0)
    }
    fn is_finite(self) -> bool {
        DVec4::is_finite(self)
    }
    fn axis(i: usize) -> Self {
        [DVec4::X, DVec4::Y, DVec4::Z, DVec4::W]
            .get(i)
            .copied()
            .unwrap_or(DVec4::ZERO)
    }
}

/// A control point in homogeneous form `(w * P, w)`: rational B-spline algorithms run
/// on these as if they were polynomial, then divide by the weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Homogeneous<P> {
    /// The weighted point `w * P`.
    pub weighted: P,
    /// The weight `w`.
    pub weight: f64,
}

impl<P: Point> Homogeneous<P> {
    /// Lifts a Euclidean point with its weight.
    pub fn from_point(p: P, w: f64) -> Self {
        Self {
            weighted: p * w,
            weight: w,
        }
    }
    /// Projects back to the Euclidean point.
    pub fn to_point(self) -> P {
        self.weighted * (1.0 / self.weight)
    }
}

impl<P: Linear> Add for Homogeneous<P> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            weighted: self.weighted + o.weighted,
            weight: self.weight + o.weight,
        }
    }
}

impl<P: Linear> Sub for Homogeneous<P> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            weighted: self.weighted - o.weighted,
            weight: self.weight - o.weight,
        }
    }
}

impl<P: Linear> Mul<f64> for Homogeneous<P> {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self {
            weighted: self.weighted * s,
            weight: self.weight * s,
        }
    }
}

impl<P: Linear> Linear for Homogeneous<P> {
    const ZERO: Self = Self {
        weighted: P::ZERO,
        weight: 0.0,
    };
}
