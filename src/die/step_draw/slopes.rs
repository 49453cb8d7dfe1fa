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
    /// Each patch's control-point box (infinite when a weight is not positive): the
    /// patch lies inside it, so a patch whose box is farther than a foot point already
    /// found cannot hold a nearer one.
    boxes: Vec<(DVec3, DVec3)>,
    last: Cell<Option<(usize, f64, f64)>>,
}

impl<'a> BinderSlope<'a> {
    /// Slopes of the binder made of `patches`.
    pub fn new(patches: &'a [NurbsSurface]) -> Self {
        Self::starting_at(patches, None)
    }

    /// Slopes of the binder made of `patches`, whose first look-up starts from the
    /// patch and foot point `last`, `(patch, u, v)`.
    pub fn starting_at(patches: &'a [NurbsSurface], last: Option<(usize, f64, f64)>) -> Self {
        let boxes = patches
            .iter()
            .map(|s| {
                // A rational patch with a weight that is not positive leaves the convex
                // hull of its control points: no box bounds it.
                if s.weights().is_some_and(|w| w.iter().any(|&w| w <= 0.0)) {
                    (DVec3::NEG_INFINITY, DVec3::INFINITY)
                } else {
                    s.control_bounds()
                }
            })
            .collect();
        Self {
            patches,
            boxes,
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
        // The nearest foot point over all patches (the first patch of equal distance),
        // searching the patches nearest by their boxes first and skipping those whose
        // box is farther than the best foot point found: the same answer as searching
        // every patch, without the global search of the patches far away.
        let mut order: Vec<(f64, usize)> = self
            .boxes
            .iter()
            .enumerate()
            .map(|(k, &(lo, hi))| (p.clamp(lo, hi).distance(p), k))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut best: Option<(usize, f64, f64, f64)> = None;
        for (reach, k) in order {
            if best.is_some_and(|b| reach > b.3) {
                break;
            }
            if let Ok(hit) = closest_point_on_surface(&self.patches[k], p) {
                let better =
                    best.is_none_or(|b| hit.distance < b.3 || (hit.distance == b.3 && k < b.0));
                if better {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The flat patch through four corners, `p[i][j]` (`i` along u).
    fn bilinear(p: [[DVec3; 2]; 2]) -> NurbsSurface {
        let knots = vec![0.0, 0.0, 1.0, 1.0];
        NurbsSurface::new(1, 1, knots.clone(), knots, p.map(Vec::from).to_vec())
            .expect("four finite corners make a valid patch")
    }

    /// The nearest foot point over every patch (the first patch of equal distance) and
    /// its slope: what the box-pruned search must answer.
    fn exhaustive(patches: &[NurbsSurface], p: DVec3, h: DVec3) -> Option<f64> {
        let mut best: Option<(usize, f64, f64, f64)> = None;
        for (k, s) in patches.iter().enumerate() {
            if let Ok(hit) = closest_point_on_surface(s, p) {
                if best.is_none_or(|b| hit.distance < b.3) {
                    best = Some((k, hit.u, hit.v, hit.distance));
                }
            }
        }
        let (k, u, v, d) = best?;
        if d > ON_SURFACE {
            return None;
        }
        slope_at(&patches[k], u, v, h)
    }

    /// Eight tilted quads round a square opening, each rising outwards at its own
    /// slope, sharing their edges like a binder's patches.
    fn ring() -> Vec<NurbsSurface> {
        let corner = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let mut out = Vec::new();
        for k in 0..8 {
            let a0 = k as f64 * std::f64::consts::FRAC_PI_4;
            let a1 = a0 + std::f64::consts::FRAC_PI_4;
            let (r0, r1) = (300.0, 500.0);
            let rise = 10.0 + 5.0 * k as f64;
            out.push(bilinear([
                [
                    corner(r0 * a0.cos(), r0 * a0.sin(), 0.0),
                    corner(r1 * a0.cos(), r1 * a0.sin(), rise),
                ],
                [
                    corner(r0 * a1.cos(), r0 * a1.sin(), 0.0),
                    corner(r1 * a1.cos(), r1 * a1.sin(), rise),
                ],
            ]));
        }
        out
    }

    #[test]
    fn the_pruned_search_finds_what_searching_every_patch_finds() {
        let patches = ring();
        for i in 0..200 {
            let angle = i as f64 * 0.0317;
            let radius = 300.0 + (i % 7) as f64;
            let p = DVec3::new(radius * angle.cos(), radius * angle.sin(), 0.0);
            let h = DVec3::new(angle.cos(), angle.sin(), 0.0);
            // A fresh look-up has no last foot point: the global search answers.
            let pruned = BinderSlope::new(&patches).at(p, h);
            assert_eq!(pruned, exhaustive(&patches, p, h), "point {i} at {p}");
        }
    }
}
