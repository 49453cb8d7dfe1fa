//! The slopes a section must meet at its two ends: the product's across the trim line
//! and the binder's across the punch opening line, each seen in the section's vertical
//! plane.
//!
//! A die face is G1 from product to binder where the designer has not asked for a
//! crease (`docs/methods.md`, "What a die engineer checks"): the addendum leaves the
//! product tangentially and runs into the binder tangentially. The slope at a point is
//! where the surface's tangent plane cuts the section plane, as an angle from the
//! horizontal, positive upwards, measured towards the opening.

use std::cell::Cell;

use glam::DVec3;

use crate::geom::inversion::{closest_point_on_surface, project_to_surface_near};
use crate::geom::NurbsSurface;

/// Beyond this distance (mm) a guide point is taken as off a surface: its slope is not
/// used.
const ON_SURFACE: f64 = 0.05;

/// The slope of `surface` at its point nearest `p`, in the vertical plane through `p`
/// along the horizontal unit direction `h`: the angle of the tangent line there, from
/// `h` towards +Z. `None` where the tangent plane is vertical along `h`.
fn slope_at(surface: &NurbsSurface, u: f64, v: f64, h: DVec3) -> Option<f64> {
    let n = surface.normal(u, v).ok()?;
    let across = h.cross(DVec3::Z);
    let t = n.cross(across);
    let along = t.dot(h);
    if along.abs() <= 1e-9 * t.length() {
        return None;
    }
    let t = if along < 0.0 { -t } else { t };
    Some(t.z.atan2(t.dot(h)))
}

/// The product surface, with the last foot point as the start for the next.
pub struct ProductSlope<'a> {
    surface: &'a NurbsSurface,
    last: Cell<Option<(f64, f64)>>,
}

impl<'a> ProductSlope<'a> {
    /// Slopes of `surface`.
    pub fn new(surface: &'a NurbsSurface) -> Self {
        Self {
            surface,
            last: Cell::new(None),
        }
    }

    /// Slopes of `surface`, whose first look-up starts from the foot point `last`.
    pub fn starting_at(surface: &'a NurbsSurface, last: Option<(f64, f64)>) -> Self {
        Self {
            surface,
            last: Cell::new(last),
        }
    }

    /// The product surface.
    pub fn surface(&self) -> &'a NurbsSurface {
        self.surface
    }

    /// The foot point of the last look-up, `(u, v)`.
    pub fn last(&self) -> Option<(f64, f64)> {
        self.last.get()
    }

    /// The product's slope at the outline point `p`, along `h` (towards the opening).
    pub fn at(&self, p: DVec3, h: DVec3) -> Option<f64> {
        let hit = match self.last.get() {
            Some((u, v)) => project_to_surface_near(self.surface, p, (u, v)),
            None => closest_point_on_surface(self.surface, p),
        }
        .ok()?;
        self.last.set(Some((hit.u, hit.v)));
        if hit.distance > ON_SURFACE {
            return None;
        }
        slope_at(self.surface, hit.u, hit.v, h)
    }
}

/// The binder's patches, with the patch and foot point of the last query.
pub struct BinderSlope<'a> {
    patches: &'a [NurbsSurface],
    last: Cell<Option<(usize, f64, f64)>>,
}

impl<'a> BinderSlope<'a> {
    /// Slopes of the binder made of `patches`.
    pub fn new(patches: &'a [NurbsSurface]) -> Self {
        Self {
            patches,
            last: Cell::new(None),
        }
    }

    /// Slopes of the binder made of `patches`, whose first look-up starts from the
    /// patch and foot point `last`, `(patch, u, v)`.
    pub fn starting_at(patches: &'a [NurbsSurface], last: Option<(usize, f64, f64)>) -> Self {
        Self {
            patches,
            last: Cell::new(last),
        }
    }

    /// The binder's patches.
    pub fn patches(&self) -> &'a [NurbsSurface] {
        self.patches
    }

    /// The patch and foot point of the last look-up, `(patch, u, v)`.
    pub fn last(&self) -> Option<(usize, f64, f64)> {
        self.last.get()
    }

    /// The binder's slope at the opening point `p`, along `h` (outwards).
    pub fn at(&self, p: DVec3, h: DVec3) -> Option<f64> {
        if let Some((k, u, v)) = self.last.get() {
            if let Ok(hit) = project_to_surface_near(&self.patches[k], p, (u, v)) {
                if hit.distance <= 1e-3 {
                    self.last.set(Some((k, hit.u, hit.v)));
                    return slope_at(&self.patches[k], hit.u, hit.v, h);
                }
            }
        }
        let mut best: Option<(usize, f64, f64, f64)> = None;
        for (k, s) in self.patches.iter().enumerate() {
            if let Ok(hit) = closest_point_on_surface(s, p) {
                if best.is_none_or(|b| hit.distance < b.3) {
                    best = Some((k, hit.u, hit.v, hit.distance));
                }
            }
        }
        let (k, u, v, d) = best?;
        self.last.set(Some((k, u, v)));
        if d > ON_SURFACE {
            return None;
        }
        slope_at(&self.patches[k], u, v, h)
    }
}
