//! The corner of a punch opening between two adjacent 3-D side curves (paper 001
//! section 3.2, eq. 3, Fig. 5; `docs/methods.md`).
//!
//! Adjacent sides of the punch opening are joined by a corner curve. The designer gives
//! the corner in the top view as a 2-D curve `C_TOP` (usually an arc) and, in 3-D, only
//! the *magnitudes* of the end tangents: their directions come from the neighbouring
//! sides, and the magnitudes decide how the corner sags (which decides wrinkles and
//! bulges). A cubic with those end conditions no longer projects onto `C_TOP`, so it is
//! corrected ([`build_corner`]):
//!
//! 1. `C0`: the cubic Hermite (Bezier) curve on [0, 1] from the end of the previous side
//!    to the start of the next, with end derivatives `m0 T0` and `m1 T1`;
//! 2. points `P_i` are sampled on `C0` with the step rule (chordal tolerance `delta`,
//!    [`tessellate_curve`]);
//! 3. `S` is the ruled surface sweeping `C_TOP` along the punch direction, and each
//!    `P_i` is moved along a direction `r_i` onto it by solving `P_i + w r_i = S(u, v)`
//!    (eq. 3, [`intersect_ray_surface`]): the points `X_i`;
//! 4. `C_F`: the cubic B-spline through the `X_i` with the end derivatives `m0 T0`,
//!    `m1 T1` ([`interpolate`], chord-length parameters on [0, 1]).
//!
//! The projection direction follows the paper (step 2): with `N0 = T0 x punch`,
//! `Nm = Tm x punch` the lines `P_0 + s N0` and `P_m + s Nm` meet `S` at `A` and `B`;
//! the similarity transform (translation, rotation, uniform scale) taking `C0`'s ends
//! onto `A`, `B` gives `C_R`, and `r_i = C_R(t_i) - P_i`. When the sides already end on
//! `C_TOP` (the usual case: the sides are built from the same top view), `A` and `B` are
//! `C0`'s own ends, `C_R = C0` and that `r_i` vanishes; then (and wherever its component
//! across the punch direction is below `1e-3 delta`) the direction is the horizontal
//! normal of `C0`'s top-view projection, `r_i = C0'(t_i) x punch`.
//!
//! The ends of `C_F` are the given side ends exactly (`X_0`, `X_m` are not moved), so the
//! punch-opening line stays closed even when a side end is slightly off `C_TOP`.

use glam::DVec3;

use crate::geom::construct::ruled;
use crate::geom::interpolate::{interpolate, Interpolation};
use crate::geom::intersect::intersect_ray_surface;
use crate::geom::tessellate::{tessellate_curve, Tolerance};
use crate::geom::{Curve2, Curve3, GeomError, NurbsCurve, NurbsSurface, Result, Transform};

/// The designer's inputs of one corner.
#[derive(Debug, Clone, Copy)]
pub struct CornerInput<'a> {
    /// The last point of the previous side: the corner's start.
    pub end_of_previous: DVec3,
    /// Direction of the previous side at its end (normalized here; must not be zero).
    pub tangent_in: DVec3,
    /// The first point of the next side: the corner's end.
    pub start_of_next: DVec3,
    /// Direction of the next side at its start (normalized here; must not be zero).
    pub tangent_out: DVec3,
    /// The designer's end-tangent magnitudes `(m0, m1)`, both finite and > 0. They are
    /// derivatives with respect to the curve parameter on [0, 1]: for `C0` the uniform
    /// Hermite parameter, for `C_F` the chord-length parameter of the corrected points.
    /// A magnitude near the corner's chord length gives a natural, moderately taut curve;
    /// smaller ones pull the corner towards the chord, larger ones make it bulge.
    pub magnitudes: (f64, f64),
    /// `C_TOP`: the corner as drawn in the top view (XY).
    pub top_view_corner: &'a Curve2,
    /// The punch direction (usually `-Z`); normalized here, must not be zero.
    pub punch_dir: DVec3,
    /// The tolerance `delta` (mm) of the step rule sampling `C0`, finite and > 0.
    pub delta: f64,
}

/// The corner curves of [`build_corner`].
#[derive(Debug, Clone, PartialEq)]
pub struct Corner {
    /// `C0`: the uncorrected cubic Hermite corner on [0, 1].
    pub initial: Curve3,
    /// `X_i`: the step-rule samples of `C0` moved onto the swept top-view corner, ends
    /// included (those are the given side ends, unmoved).
    pub corrected_points: Vec<DVec3>,
    /// `C_F`: the final corner, the cubic B-spline through [`Self::corrected_points`]
    /// with the end derivatives `m0 T0`, `m1 T1` (chord-length parameters on [0, 1]).
    pub curve: Curve3,
}

/// Builds the corner `C_F` of the punch opening (steps 1-4 of the module docs).
///
/// Errors: [`GeomError::NotPositive`] for a magnitude (`"corner tangent magnitude"`) or
/// `delta` (`"corner tolerance"`) that is not > 0; [`GeomError::ZeroVector`] for a zero
/// tangent or punch direction, or where `C0` runs along the punch direction (no top-view
/// normal); [`GeomError::NotFinite`] for NaN or infinite input; the errors of
/// [`intersect_ray_surface`] (`NoIntersection` when a projection line misses the swept
/// `C_TOP`, e.g. a `C_TOP` that does not match the sides) and of [`interpolate`].
pub fn build_corner(input: &CornerInput) -> Result<Corner> {
    let (m0, m1) = input.magnitudes;
    for m in [m0, m1] {
        if m.is_nan() || m == f64::INFINITY {
            return Err(GeomError::NotFinite {
                what: "corner tangent magnitude",
            });
        }
        if m <= 0.0 {
            return Err(GeomError::NotPositive {
                what: "corner tangent magnitude",
                value: m,
            });
        }
    }
    if input.delta.is_nan() || input.delta == f64::INFINITY {
        return Err(GeomError::NotFinite {
            what: "corner tolerance",
        });
    }
    if input.delta <= 0.0 {
        return Err(GeomError::NotPositive {
            what: "corner tolerance",
            value: input.delta,
        });
    }
    if !(input.end_of_previous.is_finite() && input.start_of_next.is_finite()) {
        return Err(GeomError::NotFinite {
            what: "corner end point",
        });
    }
    let t0 = unit(input.tangent_in, "corner start tangent")?;
    let t1 = unit(input.tangent_out, "corner end tangent")?;
    let punch = unit(input.punch_dir, "punch direction")?;
    let (p0, p3) = (input.end_of_previous, input.start_of_next);

    // Step 1: C0, the cubic Hermite curve as a Bezier curve on [0, 1].
    let initial = NurbsCurve::bezier(vec![p0, p0 + t0 * (m0 / 3.0), p3 - t1 * (m1 / 3.0), p3])?;

    // Step 2: samples by the step rule.
    let samples = tessellate_curve(&initial, &Tolerance::new(input.delta)?)?;

    // Step 3: the swept top-view corner, spanning far beyond the corner along the punch.
    let surface = swept_top_view(input.top_view_corner, &initial, punch)?;
    let projected = projection_guide(&initial, &surface, t0, t1, punch)?;
    let last = samples.points.len() - 1;
    let mut corrected_points = Vec::with_capacity(samples.points.len());
    for (i, (&t, &p)) in samples.params.iter().zip(&samples.points).enumerate() {
        if i == 0 {
            corrected_points.push(p0);
            continue;
        }
        if i == last {
            corrected_points.push(p3);
            continue;
        }
        let mut r = projected
            .as_ref()
            .map_or(DVec3::ZERO, |c| c.point_at(t) - p);
        if (r - punch * r.dot(punch)).length() <= 1e-3 * input.delta {
            r = initial.derivative_at(t).cross(punch);
            if r.length() <= 1e-12 * initial.derivative_at(t).length().max(f64::MIN_POSITIVE) {
                return Err(GeomError::ZeroVector {
                    what: "corner tangent in the top view",
                });
            }
        }
        corrected_points.push(intersect_ray_surface(p, r, &surface)?.point);
    }

    // Step 4: the final corner.
    let curve = interpolate(
        &corrected_points,
        &Interpolation::cubic_with_tangents(t0 * m0, t1 * m1),
    )?;
    Ok(Corner {
        initial,
        corrected_points,
        curve,
    })
}

/// The ruled surface sweeping `C_TOP` (placed at z = 0) along `punch`, from `-H` to `+H`
/// with `H` ten times the size of the corner and its distance from the origin along the
/// punch direction, so every projection line meets it within its v range.
fn swept_top_view(top: &Curve2, corner: &Curve3, punch: DVec3) -> Result<NurbsSurface> {
    let base = top.to_3d();
    let (lo, hi) = corner.control_bounds();
    let (tlo, thi) = base.control_bounds();
    let reach = lo
        .length()
        .max(hi.length())
        .max(tlo.length())
        .max(thi.length());
    let h = 10.0 * ((hi - lo).length() + (thi - tlo).length() + reach).max(1.0);
    let up = Transform::translate(-punch * h)?.apply_curve(&base);
    let down = Transform::translate(punch * h)?.apply_curve(&base);
    ruled(&up, &down)
}

/// `C_R` of the paper (section 3.2, step 2), whose points give the projection
/// directions: `C0` moved by the similarity that takes its ends onto `A`, `B`, where the
/// lines `P0 + s (T0 x punch)`, `Pm + s (Tm x punch)` meet the swept `C_TOP`.
/// `None` when that construction is not available (an end tangent along the punch, a
/// line missing the surface, or coincident ends): the caller then uses the top-view
/// normal.
fn projection_guide(
    initial: &Curve3,
    surface: &NurbsSurface,
    t0: DVec3,
    t1: DVec3,
    punch: DVec3,
) -> Result<Option<Curve3>> {
    let (p0, p3) = (initial.start_point(), initial.end_point());
    let (n0, n1) = (t0.cross(punch), t1.cross(punch));
    if n0.length() <= 1e-12 || n1.length() <= 1e-12 {
        return Ok(None);
    }
    let (Ok(a), Ok(b)) = (
        intersect_ray_surface(p0, n0, surface),
        intersect_ray_surface(p3, n1, surface),
    ) else {
        return Ok(None);
    };
    let (a, b) = (a.point, b.point);
    let (from, to) = (p3 - p0, b - a);
    if from.length() <= 1e-12 * p0.length().max(1.0) || to.length() <= 1e-12 * a.length().max(1.0) {
        return Ok(None);
    }
    let similarity = Transform::translate(-p0)?
        .then(Transform::rotation_between(from, to)?)
        .then(Transform::scale_about(
            DVec3::ZERO,
            to.length() / from.length(),
        )?)
        .then(Transform::translate(a)?);
    Ok(Some(similarity.apply_curve(initial)))
}

fn unit(v: DVec3, what: &'static str) -> Result<DVec3> {
    if !v.is_finite() {
        return Err(GeomError::NotFinite { what });
    }
    let big = v.abs().max_element();
    if big == 0.0 {
        return Err(GeomError::ZeroVector { what });
    }
    let s = v / big;
    Ok(s / s.length())
}
