//! Measuring a die face as a die engineer does (`docs/methods.md`, "What a die engineer
//! checks"): the smallest radius of each patch, the draft of its walls against the press
//! direction, the sag of a section, and the gap and crease along a seam between two
//! surfaces.
//!
//! These are pure functions of kernel types (surfaces, curves, points): the features
//! call them on their own outputs, and `eval` puts the results in the features'
//! `quality` records where `die_checks` compares them with the designer's limits.
//!
//! # Conventions
//!
//! * The press direction is +Z up; the punch moves down (-Z).
//! * A patch is judged with its normal turned up: the normal `S_u x S_v` is flipped
//!   when the patch's mean normal (the sum of the unit normals over its sample grid,
//!   every knot span sampled) points down. A patch that faces down as a whole is therefore a
//!   patch whose parametrization runs the other way, not an undercut.
//! * Draft is `asin(n_z)` of the up-turned unit normal, in degrees: 0 on a vertical
//!   wall, 90 on a flat; negative where the surface overhangs (an undercut).

use glam::DVec3;

use crate::geom::curvature::{
    curvature_steps, principal_curvatures, principal_of, refine_lowest_minima, span_steps,
};
use crate::geom::inversion::project_to_surface_near;
use crate::geom::{Curve3, GeomError, KnotVector, NurbsSurface};

/// Draft (degrees) below which a point counts as an undercut: a vertical wall measured
/// to rounding (`n_z` of about `-1e-17`) is not one.
pub const UNDERCUT_TOLERANCE: f64 = 1e-6;

/// Target number of samples per surface direction: a direction with few knot spans is
/// sampled several times per span, one with many spans (a step draw runs seventy
/// sections along the outline and fits its profiles on a hundred spans) once per span.
const SAMPLES_PER_DIRECTION: usize = 96;

/// Most samples per knot span and direction.
const MAX_PER_SPAN: usize = 12;

/// Samples per knot span of a section curve.
const SECTION_PER_SPAN: usize = 2;

/// What a die engineer reads off one patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceFigures {
    /// The smallest radius of curvature (mm); infinite on a flat patch.
    pub min_radius: f64,
    /// Where it is.
    pub min_radius_at: DVec3,
    /// The smallest draft (degrees; see the module conventions).
    pub draft: f64,
    /// Where it is.
    pub draft_at: DVec3,
    /// Whether the patch overhangs anywhere (draft below `-UNDERCUT_TOLERANCE`); then
    /// `draft_at` is the worst overhang.
    pub undercut: bool,
    /// Whether the normal was turned up (the patch's mean normal points down).
    pub flipped: bool,
}

/// The distinct knots of a direction.
fn breaks(knots: &KnotVector) -> Vec<f64> {
    knots.distinct().iter().map(|&(t, _)| t).collect()
}

/// The sample grid of a surface: every knot span of each direction, `96 / spans`
/// samples per span (1 to 12), and at least two (its ends and middle) across the
/// direction with more spans: the finely knotted direction is the one a tight radius
/// hides in (a step-draw profile), the other is sampled at its knots (a step draw's
/// sections) and between them only where the worst sample is refined.
fn grid(s: &NurbsSurface) -> (Vec<f64>, Vec<f64>) {
    let (bu, bv) = (breaks(s.knots_u()), breaks(s.knots_v()));
    let spans = |b: &[f64]| b.len().saturating_sub(1).max(1);
    let per = |n: usize| (SAMPLES_PER_DIRECTION / n).clamp(1, MAX_PER_SPAN);
    let (mut pu, mut pv) = (per(spans(&bu)), per(spans(&bv)));
    if spans(&bu) > spans(&bv) {
        pu = pu.max(2);
    } else {
        pv = pv.max(2);
    }
    (
        curvature_steps(s.knots_u(), s.degree_u(), pu),
        curvature_steps(s.knots_v(), s.degree_v(), pv),
    )
}

/// `+1` when the mean normal of `s` (the sum of the unit normals over its sample grid)
/// points up or lies level, `-1` when it points down.
pub fn up_sign(s: &NurbsSurface) -> f64 {
    let (us, vs) = grid(s);
    let mut mean = DVec3::ZERO;
    // The basis functions once per grid line (the same numbers as `unit_normal`).
    let basis_v: Vec<_> = vs.iter().map(|&v| s.basis_v::<2>(v)).collect();
    for &u in &us {
        let bu = s.basis_u::<2>(u);
        for bv in &basis_v {
            mean += normal_of(&s.derivatives_from(&bu, bv)).unwrap_or(DVec3::ZERO);
        }
    }
    if mean.z < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// A surface with its [`up_sign`], worked out once: what [`seam`] compares, so a
/// surface met along many seams (a binder patch against every step-draw patch) is not
/// sampled again for each.
#[derive(Debug, Clone, Copy)]
pub struct Facing<'s> {
    /// The surface.
    pub surface: &'s NurbsSurface,
    /// `+1` when its mean normal points up or lies level, `-1` when down.
    pub up: f64,
}

impl<'s> Facing<'s> {
    /// The surface with its up sign.
    pub fn new(surface: &'s NurbsSurface) -> Self {
        Facing {
            surface,
            up: up_sign(surface),
        }
    }
}

/// The draft (degrees) of a unit normal turned by `sign`.
fn draft_of(normal: DVec3, sign: f64) -> f64 {
    (sign * normal.z).clamp(-1.0, 1.0).asin().to_degrees()
}

/// The unit normal at `(u, v)`, or `None` at a degenerate point.
fn unit_normal(s: &NurbsSurface, u: f64, v: f64) -> Option<DVec3> {
    normal_of(&s.derivatives::<2>(u, v))
}

/// [`unit_normal`] from the surface's first partial derivatives at the point.
fn normal_of(d: &[[DVec3; 2]; 2]) -> Option<DVec3> {
    let n = d[1][0].cross(d[0][1]);
    let len = n.length();
    (len > 1e-12 * (d[1][0].length_squared() + d[0][1].length_squared()).max(f64::MIN_POSITIVE))
        .then(|| n / len)
}

/// The smallest radius and the smallest draft of a patch.
///
/// One pass over a grid of every knot span in both directions (see `grid`: at least
/// two samples per span across the more finely knotted direction) computes the
/// principal curvatures and the normal at each sample; then finer grids over the cells
/// around the lowest few local minima of the radius, and of the draft, refine both. Degenerate
/// points (collapsed edges) are skipped.
pub fn surface_figures(s: &NurbsSurface) -> SurfaceFigures {
    let (us, vs) = grid(s);
    let nv = vs.len();
    let mut radius = vec![f64::INFINITY; us.len() * nv];
    let mut normal = vec![None; us.len() * nv];
    let mut mean = DVec3::ZERO;
    // The basis functions once per grid line, not once per sample: the same numbers
    // as `principal_curvatures` at each (u, v).
    let basis_v: Vec<_> = vs.iter().map(|&v| s.basis_v::<3>(v)).collect();
    for (i, &u) in us.iter().enumerate() {
        let bu = s.basis_u::<3>(u);
        for (j, bv) in basis_v.iter().enumerate() {
            if let Some(p) = principal_of(&s.derivatives_from(&bu, bv)) {
                radius[i * nv + j] = p.min_radius();
                normal[i * nv + j] = Some(p.normal);
                mean += p.normal;
            }
        }
    }
    let sign = if mean.z < 0.0 { -1.0 } else { 1.0 };
    let draft: Vec<f64> = normal
        .iter()
        .map(|n| n.map_or(f64::INFINITY, |n| draft_of(n, sign)))
        .collect();
    let (min_radius, ruv) = refine_lowest_minima(&us, &vs, &radius, &|u, v| {
        principal_curvatures(s, u, v).map(|p| p.min_radius())
    })
    .unwrap_or((f64::INFINITY, (us[0], vs[0])));
    let (draft, duv) = refine_lowest_minima(&us, &vs, &draft, &|u, v| {
        unit_normal(s, u, v).map(|n| draft_of(n, sign))
    })
    .unwrap_or((90.0, (us[0], vs[0])));
    SurfaceFigures {
        min_radius,
        min_radius_at: s.point_at(ruv.0, ruv.1),
        draft,
        draft_at: s.point_at(duv.0, duv.1),
        undercut: draft < -UNDERCUT_TOLERANCE,
        flipped: sign < 0.0,
    }
}

/// Which end of a section curve lies on the punch opening.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SectionEnd {
    /// The curve starts on the opening (a step draw's sections run from the opening to
    /// the product).
    Start,
    /// The curve ends on the opening.
    End,
}

/// How far a section dips (mm, never negative), and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sag {
    /// The largest depth of the section below the straight line between its ends,
    /// measured vertically (along the press direction), 0 if it never goes below.
    pub below_chord: f64,
    /// Where.
    pub below_chord_at: DVec3,
    /// The depth of the section's lowest point below its opening end, 0 if it never
    /// goes below.
    pub below_opening: f64,
    /// Where (the lowest point).
    pub below_opening_at: DVec3,
}

/// The vertical depth of `p` below the chord from `a` to `b`: the chord's height at the
/// top-view projection of `p` onto it (clamped to the chord), minus `p.z`. On a
/// vertical chord, the depth below its lower end.
fn depth_below_chord(a: DVec3, b: DVec3, p: DVec3) -> f64 {
    let h = (b - a).truncate();
    let hh = h.length_squared();
    let scale = (a.length() + b.length()).max(1.0);
    if hh <= (1e-12 * scale).powi(2) {
        return a.z.min(b.z) - p.z;
    }
    let s = ((p - a).truncate().dot(h) / hh).clamp(0.0, 1.0);
    a.z + s * (b.z - a.z) - p.z
}

/// The largest of `f` between the parameters `lo` and `hi`, starting from the sampled
/// best `(value, t)`: a golden-section search.
fn golden_max(
    f: &dyn Fn(f64) -> f64,
    mut lo: f64,
    mut hi: f64,
    mut best: (f64, f64),
) -> (f64, f64) {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..60 {
        if hi - lo <= 1e-12 * (1.0 + hi.abs()) {
            break;
        }
        let (x1, x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
        let (f1, f2) = (f(x1), f(x2));
        for (fx, x) in [(f1, x1), (f2, x2)] {
            if fx > best.0 {
                best = (fx, x);
            }
        }
        if f1 > f2 {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    best
}

/// How far a section dips below its chord and below its opening end: every knot span
/// sampled [`SECTION_PER_SPAN`] times, each figure's worst sample refined by a
/// golden-section search between its neighbours.
pub fn section_sag(section: &Curve3, opening: SectionEnd) -> Sag {
    let (a, b) = (section.start_point(), section.end_point());
    let open_z = match opening {
        SectionEnd::Start => a.z,
        SectionEnd::End => b.z,
    };
    let ts = span_steps(&section.span_breaks(), SECTION_PER_SPAN);
    let chord_depth = |t: f64| depth_below_chord(a, b, section.point_at(t));
    let depth = |t: f64| -section.point_at(t).z;
    let (mut kc, mut kl) = (0, 0);
    let (mut dc, mut dl) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for (k, &t) in ts.iter().enumerate() {
        let p = section.point_at(t);
        let c = depth_below_chord(a, b, p);
        if c > dc {
            (dc, kc) = (c, k);
        }
        if -p.z > dl {
            (dl, kl) = (-p.z, k);
        }
    }
    let around = |k: usize| (ts[k.saturating_sub(1)], ts[(k + 1).min(ts.len() - 1)]);
    let ((lo, hi), (lo2, hi2)) = (around(kc), around(kl));
    let (chord, tc) = golden_max(&chord_depth, lo, hi, (dc, ts[kc]));
    let (low, tl) = golden_max(&depth, lo2, hi2, (dl, ts[kl]));
    Sag {
        below_chord: chord.max(0.0),
        below_chord_at: section.point_at(tc),
        below_opening: (open_z + low).max(0.0),
        below_opening_at: section.point_at(tl),
    }
}

/// The gap and crease along a seam between surface A and surfaces B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seam {
    /// The largest distance (mm) from a sample of A's boundary to the nearest point of
    /// the surfaces B.
    pub gap: f64,
    /// Where (on A).
    pub gap_at: DVec3,
    /// The largest angle (degrees) between A's tangent plane and B's at the nearest
    /// point: 0 where the seam is tangent.
    pub crease: f64,
    /// Where (on A).
    pub crease_at: DVec3,
}

/// One edge of a surface's parameter domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Edge {
    /// `u` at its start.
    U0,
    /// `u` at its end.
    U1,
    /// `v` at its start.
    V0,
    /// `v` at its end.
    V1,
}

/// Parameters along one edge of `s`, every knot span of the running direction sampled
/// `per_span` times (span ends included).
pub fn edge_samples(s: &NurbsSurface, edge: Edge, per_span: usize) -> Vec<(f64, f64)> {
    let (knots, fixed, along_u) = match edge {
        Edge::U0 => (s.knots_v(), s.domain_u().0, false),
        Edge::U1 => (s.knots_v(), s.domain_u().1, false),
        Edge::V0 => (s.knots_u(), s.domain_v().0, true),
        Edge::V1 => (s.knots_u(), s.domain_v().1, true),
    };
    let ts = span_steps(&breaks(knots), per_span);
    ts.into_iter()
        .map(|t| if along_u { (t, fixed) } else { (fixed, t) })
        .collect()
}

/// The parameters of the sample of `s`'s grid nearest to `p`: the start of the first
/// projection onto a surface along a seam.
fn nearest_on_grid(s: &NurbsSurface, p: DVec3) -> (f64, f64) {
    let (us, vs) = grid(s);
    let mut best = (f64::INFINITY, (us[0], vs[0]));
    for &u in &us {
        for &v in &vs {
            let d = s.point_at(u, v).distance_squared(p);
            if d < best.0 {
                best = (d, (u, v));
            }
        }
    }
    best.1
}

/// The nearest point to `p` on the four boundary curves of `s`.
fn nearest_on_edges(s: &NurbsSurface, p: DVec3) -> Option<crate::geom::inversion::SurfacePoint> {
    use crate::geom::inversion::{closest_point_on_curve, SurfacePoint};
    use crate::geom::Direction;
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let mut best: Option<SurfacePoint> = None;
    for (dir, fixed) in [
        (Direction::U, u0),
        (Direction::U, u1),
        (Direction::V, v0),
        (Direction::V, v1),
    ] {
        let Ok(cp) = closest_point_on_curve(&s.iso_curve(dir, fixed), p) else {
            continue;
        };
        let (u, v) = match dir {
            Direction::U => (fixed, cp.t),
            Direction::V => (cp.t, fixed),
        };
        if best.as_ref().is_none_or(|b| cp.distance < b.distance) {
            best = Some(SurfacePoint {
                u,
                v,
                point: cp.point,
                distance: cp.distance,
            });
        }
    }
    best
}

/// The distance from `p` to the box `lo..hi`.
fn box_distance(lo: DVec3, hi: DVec3, p: DVec3) -> f64 {
    (lo - p).max(p - hi).max(DVec3::ZERO).length()
}

/// The gap and crease along a seam: at each parameter pair `along` of surface `a`
/// (samples of one of its boundaries, e.g. from [`edge_samples`]), the nearest point of
/// the surfaces `b` (closest-point inversion started from the previous sample's foot on
/// each surface, or from its nearest grid sample the first time; surfaces whose control
/// box lies farther than the best found skipped; a surface whose inversion does not
/// converge skipped for that sample),
/// the distance to it, and the angle between the two tangent planes there. Both normals
/// are turned up by their patch's mean normal ([`Facing::up`]), so a crease is the angle
/// between the up-facing normals: 0 for a tangent seam, whichever way each surface is
/// parametrized.
///
/// Errors: the inversion's, for non-finite geometry.
pub fn seam(a: Facing, along: &[(f64, f64)], b: &[Facing]) -> Result<Seam, GeomError> {
    let (sign_a, a) = (a.up, a.surface);
    let signs: Vec<f64> = b.iter().map(|f| f.up).collect();
    let b: Vec<&NurbsSurface> = b.iter().map(|f| f.surface).collect();
    let boxes: Vec<(DVec3, DVec3)> = b.iter().map(|s| s.control_bounds()).collect();
    let mut guesses: Vec<Option<(f64, f64)>> = vec![None; b.len()];
    let mut out = Seam {
        gap: 0.0,
        gap_at: along
            .first()
            .map_or(DVec3::ZERO, |&(u, v)| a.point_at(u, v)),
        crease: 0.0,
        crease_at: along
            .first()
            .map_or(DVec3::ZERO, |&(u, v)| a.point_at(u, v)),
    };
    for &(u, v) in along {
        let p = a.point_at(u, v);
        let mut order: Vec<usize> = (0..b.len()).collect();
        order.sort_by(|&i, &j| {
            box_distance(boxes[i].0, boxes[i].1, p)
                .total_cmp(&box_distance(boxes[j].0, boxes[j].1, p))
        });
        let mut best: Option<(usize, crate::geom::inversion::SurfacePoint)> = None;
        for k in order {
            if let Some((_, sp)) = &best {
                if box_distance(boxes[k].0, boxes[k].1, p) > sp.distance {
                    break;
                }
            }
            let guess = guesses[k].unwrap_or_else(|| nearest_on_grid(b[k], p));
            let sp = match project_to_surface_near(b[k], p, guess) {
                Ok(sp) => sp,
                // A foot on the boundary (a seam runs along B's edge) can fail the
                // interior test: the nearest point of B's four edges answers instead.
                Err(GeomError::NoConvergence { .. }) => match nearest_on_edges(b[k], p) {
                    Some(sp) => sp,
                    None => continue,
                },
                Err(e) => return Err(e),
            };
            guesses[k] = Some((sp.u, sp.v));
            if best.as_ref().is_none_or(|(_, x)| sp.distance < x.distance) {
                best = Some((k, sp));
            }
        }
        let Some((k, sp)) = best else { continue };
        if sp.distance > out.gap {
            out.gap = sp.distance;
            out.gap_at = p;
        }
        if let (Some(na), Some(nb)) = (unit_normal(a, u, v), unit_normal(b[k], sp.u, sp.v)) {
            let cos = (sign_a * na).dot(signs[k] * nb).clamp(-1.0, 1.0);
            let angle = cos.acos().to_degrees();
            if angle > out.crease {
                out.crease = angle;
                out.crease_at = p;
            }
        }
    }
    Ok(out)
}
