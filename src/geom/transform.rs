//! Rigid and affine transforms of points, curves and surfaces.
//!
//! NURBS are invariant under affine maps: transforming the control points (weights
//! unchanged) transforms the curve exactly. A [`Transform`] therefore holds an affine
//! `DMat4` and refuses projective matrices. The constructors are the ones die-face work
//! uses: translate, rotate about an axis through a point (tipping a product into draw
//! position), scale about a point (the step draw's eq. 7), and the rotation that takes
//! one direction onto another (aligning a section with the guide curves).

use glam::{DMat3, DMat4, DVec3, DVec4};

use super::curve::Curve3;
use super::error::{GeomError, Result};
use super::surface::NurbsSurface;

/// An invertible affine transform of press coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    matrix: DMat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Self = Self {
        matrix: DMat4::IDENTITY,
    };

    /// Wraps an affine matrix: finite, last row `(0, 0, 0, 1)`, invertible linear part.
    pub fn from_matrix(matrix: DMat4) -> Result<Self> {
        if !matrix.is_finite() {
            return Err(GeomError::NotFinite {
                what: "transform matrix",
            });
        }
        if matrix.row(3) != DVec4::new(0.0, 0.0, 0.0, 1.0) {
            return Err(GeomError::NotAffine);
        }
        let det = DMat3::from_mat4(matrix).determinant();
        let scale = DMat3::from_mat4(matrix)
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        if det.abs() <= 1e-14 * scale.powi(3) {
            return Err(GeomError::NotAffine);
        }
        Ok(Self { matrix })
    }

    /// Translation by `offset`.
    pub fn translate(offset: DVec3) -> Result<Self> {
        check_finite(offset, "translation")?;
        Ok(Self {
            matrix: DMat4::from_translation(offset),
        })
    }

    /// Rotation by `angle` radians (right-handed) about the axis through `point` along
    /// `axis`.
    pub fn rotate_about_axis(point: DVec3, axis: DVec3, angle: f64) -> Result<Self> {
        check_finite(point, "rotation centre")?;
        let axis = unit(axis, "rotation axis")?;
        if !angle.is_finite() {
            return Err(GeomError::NotFinite {
                what: "rotation angle",
            });
        }
        let m = DMat4::from_translation(point)
            * DMat4::from_axis_angle(axis, angle)
            * DMat4::from_translation(-point);
        Ok(Self { matrix: m })
    }

    /// Uniform scaling by `factor` about `center`.
    pub fn scale_about(center: DVec3, factor: f64) -> Result<Self> {
        check_finite(center, "scale centre")?;
        if !(factor.is_finite() && factor != 0.0) {
            return Err(GeomError::NotPositive {
                what: "scale factor",
                value: factor,
            });
        }
        let m = DMat4::from_translation(center)
            * DMat4::from_scale(DVec3::splat(factor))
            * DMat4::from_translation(-center);
        Ok(Self { matrix: m })
    }

    /// The rotation about the origin that takes direction `from` onto direction `to`
    /// (the shortest one; for opposite vectors, a half turn about an axis perpendicular
    /// to `from`).
    pub fn rotation_between(from: DVec3, to: DVec3) -> Result<Self> {
        let a = unit(from, "source direction")?;
        let b = unit(to, "target direction")?;
        let axis = a.cross(b);
        let sin = axis.length();
        let cos = a.dot(b);
        let angle = sin.atan2(cos);
        let axis = if sin > 1e-12 {
            axis / sin
        } else {
            a.any_orthonormal_vector()
        };
        if sin <= 1e-12 && cos > 0.0 {
            return Ok(Self::IDENTITY);
        }
        Ok(Self {
            matrix: DMat4::from_axis_angle(axis, angle),
        })
    }

    /// `self` after `first`: applying the result equals applying `first`, then `self`.
    pub fn then_after(self, first: Transform) -> Self {
        Self {
            matrix: self.matrix * first.matrix,
        }
    }

    /// `other` after `self`.
    pub fn then(self, other: Transform) -> Self {
        other.then_after(self)
    }

    /// The inverse transform.
    pub fn inverse(self) -> Self {
        Self {
            matrix: self.matrix.inverse(),
        }
    }

    /// The affine matrix.
    pub fn matrix(&self) -> DMat4 {
        self.matrix
    }

    /// Transforms a point.
    pub fn apply_point(&self, p: DVec3) -> DVec3 {
        self.matrix.transform_point3(p)
    }

    /// Transforms a direction (translation ignored).
    pub fn apply_vector(&self, v: DVec3) -> DVec3 {
        self.matrix.transform_vector3(v)
    }

    /// Transforms a curve exactly (control points mapped, weights kept).
    pub fn apply_curve(&self, c: &Curve3) -> Curve3 {
        c.map_points(|p| self.apply_point(p))
    }

    /// Transforms a surface exactly (control points mapped, weights kept).
    pub fn apply_surface(&self, s: &NurbsSurface) -> NurbsSurface {
        s.map_points(|p| self.apply_point(p))
    }
}

fn check_finite(v: DVec3, what: &'static str) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(GeomError::NotFinite { what })
    }
}

/// The unit vector along `v`, or an error for zero or non-finite vectors.
pub(crate) fn unit(v: DVec3, what: &'static str) -> Result<DVec3> {
    check_finite(v, what)?;
    let len = v.length();
    if len == 0.0 || !len.is_finite() {
        return Err(GeomError::ZeroVector { what });
    }
    Ok(v / len)
}
