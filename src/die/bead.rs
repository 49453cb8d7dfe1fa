//! Draw beads on the blankholder (primer section 5; paper 001 section 5, Fig. 13).
//!
//! The designer draws the bead's centre line in the top view and picks a cross-section
//! profile (height above the binder across the bead). [`build`]:
//!
//! 1. projects the centre line along the blank-holding direction (press Z) onto the
//!    binder, across side and corner patches: a 3-D curve on the binder;
//! 2. places key sections every `spacing` along it: each runs across the bead in the
//!    vertical plane normal to the centre line's top-view tangent, its points dropped
//!    onto the binder and raised by the profile's height (scaled down to zero over the
//!    `taper` length at both ends), so the bead's feet lie on the binder;
//! 3. skins the sections into the bead surface ([`loft`]);
//! 4. resamples the centre line every `line_spacing` for the line bead of forming
//!    simulation (a polyline with a restraining force).
//!
//! Heights are measured along press Z, the direction the binder closes in.

use glam::{DVec2, DVec3};

use super::punch_opening::inside_outline;
use crate::geom::construct::{loft, Loft};
use crate::geom::interpolate::{interpolate, interpolate_at, Interpolation};
use crate::geom::{Curve2, Curve3, GeomError, NurbsSurface};

/// The designer's input for one bead.
#[derive(Debug, Clone, PartialEq)]
pub struct BeadSpec {
    /// The centre line in the top view.
    pub centre: Curve2,
    /// The cross-section: (s across the bead, height above the binder), from the left
    /// foot to the right foot, both at height 0.
    pub profile: Curve2,
    /// Length (mm) over which the height runs out to zero at both ends; 0 for none.
    pub taper: f64,
    /// Distance (mm) between key sections along the bead.
    pub spacing: f64,
    /// Distance (mm) between the line bead's points.
    pub line_spacing: f64,
}

/// Quality figures of a bead.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeadQuality {
    /// Largest distance (mm, along Z) between the bead's feet and the binder, sampled.
    pub foot_gap: f64,
    /// Largest distance (mm, along Z) between a key section's points and the binder plus
    /// the profile height they should have.
    pub section_error: f64,
    /// Number of key sections.
    pub sections: usize,
    /// Length (mm) of the centre line on the binder.
    pub length: f64,
}

/// A built bead.
#[derive(Debug, Clone, PartialEq)]
pub struct Bead {
    /// The bead surface: u across the bead (feet at u = 0 and 1), v along it.
    pub surface: NurbsSurface,
    /// The centre line on the binder.
    pub centre: Curve3,
    /// The line bead: the centre line resampled every `line_spacing`.
    pub line_points: Vec<DVec3>,
    /// The key sections in 3-D.
    pub sections: Vec<Curve3>,
    /// Quality figures.
    pub quality: BeadQuality,
}

/// The problems [`build`] reports.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// The centre line (or the bead's width around it) leaves the binder in the top view.
    LeavesBinder {
        /// The top-view point with no binder under it.
        at: DVec2,
    },
    /// The bead crosses into the punch opening.
    CrossesOpening {
        /// The top-view point inside the opening.
        at: DVec2,
    },
    /// The profile does not start and end at height 0.
    ProfileFeet,
    /// A spacing or taper that is not a positive (or, for taper, non-negative) length.
    BadLength(&'static str),
    /// The kernel failed.
    Kernel(GeomError),
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::LeavesBinder { at } => write!(
                f,
                "the bead leaves the binder near ({:.1}, {:.1})",
                at.x, at.y
            ),
            Problem::CrossesOpening { at } => write!(
                f,
                "the bead crosses into the punch opening near ({:.1}, {:.1})",
                at.x, at.y
            ),
            Problem::ProfileFeet => write!(
                f,
                "a bead profile starts and ends on the binder, at height 0"
            ),
            Problem::BadLength(what) => write!(f, "the {what} must be a positive length"),
            Problem::Kernel(e) => write!(f, "{e}"),
        }
    }
}

impl From<GeomError> for Problem {
    fn from(e: GeomError) -> Self {
        Problem::Kernel(e)
    }
}

/// Points per key section.
const SECTION_POINTS: usize = 41;

/// The foot gap (mm) above which a section is added between two others.
const FOOT_TOLERANCE: f64 = 0.0005;

/// Rounds of section insertion.
const MAX_REFINEMENTS: usize = 6;

/// Samples along each foot for the foot-gap figure.
pub const FOOT_SAMPLES: usize = 400;

/// A patch sample `(u, v, top-view point)`, a start for Newton.
type GridSample = (f64, f64, DVec2);

/// The binder as a height field over the top view: each patch with a grid of samples
/// to start Newton from.
pub struct Binder<'a> {
    patches: Vec<(&'a NurbsSurface, Vec<GridSample>)>,
    inner: &'a [DVec2],
    /// The patch and parameters of the last hit: the next query (usually nearby)
    /// starts Newton there.
    last: std::cell::Cell<Option<(usize, f64, f64)>>,
}

impl<'a> Binder<'a> {
    /// The height field of `patches`, whose inner edge is the closed polygon `inner`.
    pub fn new(patches: Vec<&'a NurbsSurface>, inner: &'a [DVec2]) -> Self {
        let patches = patches
            .into_iter()
            .map(|s| {
                let (u0, u1) = s.domain_u();
                let (v0, v1) = s.domain_v();
                let mut grid = Vec::new();
                for i in 0..=48 {
                    for j in 0..=6 {
                        let (u, v) = (
                            u0 + (u1 - u0) * i as f64 / 48.0,
                            v0 + (v1 - v0) * j as f64 / 6.0,
                        );
                        grid.push((u, v, s.point_at(u, v).truncate()));
                    }
                }
                (s, grid)
            })
            .collect();
        Self {
            patches,
            inner,
            last: std::cell::Cell::new(None),
        }
    }

    /// The binder point above or below the top-view point `p`, if any patch lies there.
    pub fn point_over(&self, p: DVec2) -> Option<DVec3> {
        if let Some((k, u, v)) = self.last.get() {
            if let Some((hit, u, v)) = solve_xy(self.patches[k].0, p, u, v) {
                self.last.set(Some((k, u, v)));
                return Some(hit);
            }
        }
        let mut starts: Vec<(f64, usize, f64, f64)> = Vec::new();
        for (k, (_, grid)) in self.patches.iter().enumerate() {
            let best = grid
                .iter()
                .map(|&(u, v, q)| (q.distance_squared(p), u, v))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((d, u, v)) = best {
                starts.push((d, k, u, v));
            }
        }
        starts.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &(_, k, u, v) in starts.iter().take(4) {
            if let Some((hit, u, v)) = solve_xy(self.patches[k].0, p, u, v) {
                self.last.set(Some((k, u, v)));
                return Some(hit);
            }
        }
        None
    }

    /// Whether `p` lies inside the binder's inner edge (the punch opening).
    pub fn in_opening(&self, p: DVec2) -> bool {
        inside_outline(self.inner, p)
    }
}

/// Newton on `S(u, v).xy = p` from `(u, v)`, inside the domain; the point if it
/// converges there.
fn solve_xy(s: &NurbsSurface, p: DVec2, mut u: f64, mut v: f64) -> Option<(DVec3, f64, f64)> {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let tol = 1e-10 * (1.0 + p.length());
    for _ in 0..40 {
        let d = s.derivatives::<2>(u, v);
        let (pt, su, sv) = (d[0][0], d[1][0], d[0][1]);
        let f = pt.truncate() - p;
        if f.length() <= tol {
            return Some((pt, u, v));
        }
        let det = su.x * sv.y - su.y * sv.x;
        if det.abs() < 1e-300 {
            return None;
        }
        let du = (f.x * sv.y - f.y * sv.x) / det;
        let dv = (su.x * f.y - su.y * f.x) / det;
        let (nu, nv) = (u - du, v - dv);
        let eps_u = 1e-9 * (u1 - u0);
        let eps_v = 1e-9 * (v1 - v0);
        if nu < u0 - eps_u || nu > u1 + eps_u || nv < v0 - eps_v || nv > v1 + eps_v {
            // Allow one clamped step before giving up: the point may lie in a
            // neighbouring patch.
            let (cu, cv) = (nu.clamp(u0, u1), nv.clamp(v0, v1));
            if (cu - u).abs() < eps_u && (cv - v).abs() < eps_v {
                return None;
            }
            u = cu;
            v = cv;
        } else {
            u = nu.clamp(u0, u1);
            v = nv.clamp(v0, v1);
        }
    }
    let pt = s.point_at(u, v);
    (pt.truncate().distance(p) <= 1e-7 * (1.0 + p.length())).then_some((pt, u, v))
}

/// Builds a bead on `binder` (module documentation).
pub fn build(binder: &Binder, spec: &BeadSpec) -> Result<Bead, Problem> {
    for (what, value, strict) in [
        ("section spacing", spec.spacing, true),
        ("line-bead spacing", spec.line_spacing, true),
        ("taper length", spec.taper, false),
    ] {
        let ok = value.is_finite() && if strict { value > 0.0 } else { value >= 0.0 };
        if !ok {
            return Err(Problem::BadLength(what));
        }
    }
    let (a, b) = (spec.profile.start_point(), spec.profile.end_point());
    let scale = spec.profile.control_scale().max(1.0);
    if a.y.abs() > 1e-9 * scale || b.y.abs() > 1e-9 * scale {
        return Err(Problem::ProfileFeet);
    }

    // Step 1: the centre line on the binder, sampled about every 2 mm.
    let centre2 = &spec.centre;
    let length2 = centre2.length();
    let samples = ((length2 / 2.0).ceil() as usize).clamp(8, 4000);
    let mut centre_points = Vec::with_capacity(samples + 1);
    for i in 0..=samples {
        let t = parameter_at_fraction(centre2, i as f64 / samples as f64, length2)?;
        let p = centre2.point_at(t);
        if binder.in_opening(p) {
            return Err(Problem::CrossesOpening { at: p });
        }
        let q = binder
            .point_over(p)
            .ok_or(Problem::LeavesBinder { at: p })?;
        centre_points.push(q);
    }
    let centre = interpolate(&centre_points, &Interpolation::default())?;

    // Step 2: key sections, every `spacing`, then more where the skinned feet leave
    // the binder by more than FOOT_TOLERANCE between two sections.
    let profile_params: Vec<f64> = (0..SECTION_POINTS)
        .map(|i| i as f64 / (SECTION_POINTS - 1) as f64)
        .collect();
    let profile_length = spec.profile.length();
    let mut profile_points = Vec::with_capacity(SECTION_POINTS);
    for &f in &profile_params {
        profile_points.push(spec.profile.point_at(parameter_at_fraction(
            &spec.profile,
            f,
            profile_length,
        )?));
    }
    let section_at = |along: f64| -> Result<Curve3, Problem> {
        let t = parameter_at_fraction(centre2, along, length2)?;
        let [c, d] = centre2.derivatives::<2>(t);
        let across = d.normalize_or_zero().perp();
        if across == DVec2::ZERO {
            return Err(Problem::Kernel(GeomError::ZeroVector {
                what: "bead centre-line tangent",
            }));
        }
        let height_factor = taper_factor(along * length2, length2, spec.taper);
        let mut points = Vec::with_capacity(SECTION_POINTS);
        for q in &profile_points {
            let p = c + across * q.x;
            if binder.in_opening(p) {
                return Err(Problem::CrossesOpening { at: p });
            }
            let base = binder
                .point_over(p)
                .ok_or(Problem::LeavesBinder { at: p })?;
            points.push(base + DVec3::Z * (q.y * height_factor));
        }
        Ok(interpolate_at(
            &points,
            &profile_params,
            &Interpolation::default(),
        )?)
    };
    let count = ((length2 / spec.spacing).ceil() as usize).max(2);
    let mut stations: Vec<f64> = (0..=count).map(|k| k as f64 / count as f64).collect();
    let mut sections = stations
        .iter()
        .map(|&a| section_at(a))
        .collect::<Result<Vec<_>, _>>()?;
    let mut surface = loft(&sections, &Loft::default())?;
    for _ in 0..MAX_REFINEMENTS {
        // The foot gap halfway between neighbouring sections, in the loft's v.
        let vs = section_parameters(&surface, sections.len());
        let mut inserted = Vec::new();
        for k in 0..sections.len() - 1 {
            let v = 0.5 * (vs[k] + vs[k + 1]);
            let mut worst: f64 = 0.0;
            for u in [surface.domain_u().0, surface.domain_u().1] {
                let p = surface.point_at(u, v);
                let base = binder
                    .point_over(p.truncate())
                    .ok_or(Problem::LeavesBinder { at: p.truncate() })?;
                worst = worst.max((p.z - base.z).abs());
            }
            if worst > FOOT_TOLERANCE {
                inserted.push(0.5 * (stations[k] + stations[k + 1]));
            }
        }
        if inserted.is_empty() {
            break;
        }
        for a in inserted {
            let i = stations.partition_point(|&x| x < a);
            stations.insert(i, a);
            sections.insert(i, section_at(a)?);
        }
        surface = loft(&sections, &Loft::default())?;
    }

    // Quality: the feet on the binder, and the sections at their heights.
    let (mut foot_gap, mut section_error) = (0.0f64, 0.0f64);
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    for u in [u0, u1] {
        for i in 0..=FOOT_SAMPLES {
            let v = v0 + (v1 - v0) * i as f64 / FOOT_SAMPLES as f64;
            let p = surface.point_at(u, v);
            let base = binder
                .point_over(p.truncate())
                .ok_or(Problem::LeavesBinder { at: p.truncate() })?;
            foot_gap = foot_gap.max((p.z - base.z).abs());
        }
    }
    let checks = 4 * SECTION_POINTS;
    let exact_profile = (0..=checks)
        .map(|i| {
            let f = i as f64 / checks as f64;
            parameter_at_fraction(&spec.profile, f, profile_length)
                .map(|t| spec.profile.point_at(t))
        })
        .collect::<Result<Vec<_>, _>>()?;
    for (s, &along) in sections.iter().zip(&stations) {
        let height_factor = taper_factor(along * length2, length2, spec.taper);
        for (i, exact) in exact_profile.iter().enumerate() {
            let p = s.point_at(i as f64 / checks as f64);
            let base = binder
                .point_over(p.truncate())
                .ok_or(Problem::LeavesBinder { at: p.truncate() })?;
            section_error = section_error.max((p.z - base.z - exact.y * height_factor).abs());
        }
    }
    let count = sections.len() - 1;

    // Step 4: the line bead.
    let length3 = centre.length();
    let n = ((length3 / spec.line_spacing).ceil() as usize).max(1);
    let mut line_points = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let t = parameter_at_fraction(&centre, i as f64 / n as f64, length3)?;
        line_points.push(centre.point_at(t));
    }
    Ok(Bead {
        surface,
        centre,
        line_points,
        sections,
        quality: BeadQuality {
            foot_gap,
            section_error,
            sections: count + 1,
            length: length3,
        },
    })
}

/// The loft parameter `v` of each section: where the loft's iso-curve equals the section
/// (the loft interpolates its sections at chord-length-averaged parameters, which it
/// does not return, so they are recovered from its knot vector's Greville abscissae as
/// a good enough midpoint estimate for the foot check).
fn section_parameters(surface: &NurbsSurface, n: usize) -> Vec<f64> {
    let (v0, v1) = surface.domain_v();
    // Sections sit at the loft's interpolation parameters; for averaged knots those are
    // close to the knots' running averages. Sample the midpoints between them.
    let knots = surface.knots_v().as_slice();
    let p = surface.degree_v();
    let m = knots.len() - p - 1;
    if m == n {
        (0..n)
            .map(|i| knots[i + 1..=i + p].iter().sum::<f64>() / p as f64)
            .collect()
    } else {
        (0..n)
            .map(|i| v0 + (v1 - v0) * i as f64 / (n - 1) as f64)
            .collect()
    }
}

/// 1 along the bead, running smoothly (a cubic smoothstep) to 0 over `taper` at both
/// ends.
fn taper_factor(s: f64, length: f64, taper: f64) -> f64 {
    if taper <= 0.0 {
        return 1.0;
    }
    let x = (s.min(length - s) / taper).clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// The parameter at fraction `f` of a curve's length.
fn parameter_at_fraction<P: crate::geom::Point>(
    c: &crate::geom::NurbsCurve<P>,
    f: f64,
    length: f64,
) -> Result<f64, GeomError> {
    let (t0, t1) = c.domain();
    if f <= 0.0 {
        Ok(t0)
    } else if f >= 1.0 {
        Ok(t1)
    } else {
        c.parameter_at_length(f * length)
    }
}
