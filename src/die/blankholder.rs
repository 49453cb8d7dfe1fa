//! The blankholder (binder) around a punch opening (paper 001 sections 3.3-3.4, eq. 4,
//! Fig. 6-8): a ring of ruled patches, one per side and one per corner, C1
//! where they meet.
//!
//! **Sides.** At designer-chosen stations `P_i` along a side's punch-opening curve `C_s`
//! the designer gives a top-view direction `u_i` (default: straight out of the opening),
//! a rise angle `theta_i` above the horizontal and a width `d_i`; they place
//! `Q_i = P_i + d_i (cos(theta_i) u_i + sin(theta_i) Z)`. The outer curve interpolates the
//! `Q_i` at the stations' own parameters on `C_s` (so each ruling through a station runs
//! from `P_i` to `Q_i`), with end tangents along `C_s`'s end tangents unless the designer
//! gives directions; the side patch rules between `C_s` and the outer curve.
//!
//! **Corners** (section 3.4), between the outer ends `A`, `B` of the neighbouring sides:
//! 1. the punch-opening corner `g0` is moved so its ends land on `A` and `B`: a top-view
//!    similarity (rotation and scale about Z) and a height correction linear in the
//!    parameter. `tautness` in [0, 1] then pulls the heights towards the straight blend
//!    of the end heights (0 keeps the sag of `g0`, 1 removes it);
//! 2. eq. 4 gives the end tangents: with `g0'(0) = lambda0 C_a'(1)` (the opening is G1),
//!    the outer corner needs `g1'(0) = lambda0 Q_a'(1)`, and likewise at its end;
//! 3. `g1` interpolates the moved curve, sampled at `g0`'s step-rule parameters, with
//!    those tangents: the classic C2 cubic spline, knots at the parameters. Eq. 4 asks
//!    for an end speed and slope that differ from the moved curve's (about a third of
//!    its speed, three times its slope on ordinary corners); the difference is spread
//!    over the whole corner by a smooth reparametrization and a height correction, so
//!    the edge turns into its neighbours without a curvature spike (see
//!    [`outer_corner`]);
//! 4. the corner patch rules between `g0` and `g1`.
//!
//! Two sides that meet without a corner share their boundary ruling; their outer curves
//! get end tangents in the same ratio as the opening's, which is again eq. 4.
//!
//! Every patch is degree 1 across the binder and its normal points up (+Z); a patch
//! that folds over itself (its normal turning down) is refused.

use glam::{DVec2, DVec3};

use super::continuity::{measure_join, JoinQuality};
use super::punch_opening::{inside_outline, PieceKind, PunchOpening};
use crate::geom::construct::ruled;
use crate::geom::curve::ArcLengths;
use crate::geom::interpolate::{interpolate_at, Interpolation, KnotPlacement};
use crate::geom::tessellate::{tessellate_curve, Tolerance};
use crate::geom::{Curve3, GeomError, NurbsSurface};

/// One station of a side: where along the side, and how the outer point is placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Station {
    /// Position along the side as a fraction of its length, 0 (start) to 1 (end).
    pub at: f64,
    /// Width `d` of the binder, in mm, measured along the placing direction.
    pub width: f64,
    /// Rise `theta` of the binder above the horizontal, in radians (positive: outward
    /// and up).
    pub angle: f64,
    /// Top-view direction `u`; `None` is the outward normal of the opening.
    pub direction: Option<DVec2>,
}

/// The designer's input for one side.
#[derive(Debug, Clone, PartialEq)]
pub struct SideSpec {
    /// Stations in increasing `at`, the first at 0 and the last at 1.
    pub stations: Vec<Station>,
    /// Direction of the outer curve at its start; `None` follows the opening.
    pub start_tangent: Option<DVec3>,
    /// Direction of the outer curve at its end; `None` follows the opening.
    pub end_tangent: Option<DVec3>,
}

/// The input of [`build`]: one entry per piece of the opening, in its order.
#[derive(Debug, Clone, PartialEq)]
pub enum PieceSpec {
    /// A side's stations and tangents.
    Side(SideSpec),
    /// A corner's tautness in [0, 1].
    Corner {
        /// 0 keeps the sag of the punch-opening corner, 1 makes the outer edge's height
        /// vary linearly between its ends.
        tautness: f64,
    },
}

/// One patch of the blankholder.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// The opening piece's name.
    pub name: String,
    /// Side or corner.
    pub kind: PieceKind,
    /// The ruled surface: u along the opening, v from the outer edge (0) to the opening
    /// (1) or the reverse, whichever makes the normal point up.
    pub surface: NurbsSurface,
    /// The outer edge.
    pub outer: Curve3,
}

/// The measured join between a patch and the next.
#[derive(Debug, Clone, PartialEq)]
pub struct Join {
    /// The patch before the join.
    pub before: String,
    /// The patch after it.
    pub after: String,
    /// Its figures.
    pub quality: JoinQuality,
}

/// The built blankholder.
#[derive(Debug, Clone, PartialEq)]
pub struct Blankholder {
    /// One patch per opening piece, in order.
    pub patches: Vec<Patch>,
    /// Every join between neighbouring patches (the last with the first included).
    pub joins: Vec<Join>,
    /// The punch opening's top-view outline (a closed polygon): the binder's inner edge,
    /// which features on the binder (beads) must stay outside.
    pub inner_outline: Vec<DVec2>,
    /// The tallest draw bead (mm) the binder takes: the depth of the bead groove its
    /// lower ring can carry. Beads taller than this are refused.
    pub max_bead_height: f64,
}

/// The default [`Blankholder::max_bead_height`] (mm): draw beads on sheet steel run
/// 4-12 mm high; a bead much taller than that is a mistake, or a special die whose
/// designer raises the limit.
pub const DEFAULT_MAX_BEAD_HEIGHT: f64 = 15.0;

/// What went wrong, and at which piece of the opening.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// Index of the culprit piece.
    pub piece: usize,
    /// The problem.
    pub problem: Problem,
}

/// The problems [`build`] reports.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// The spec does not have one entry per piece, or the kinds do not match.
    Mismatch,
    /// Stations must start at 0, end at 1 and increase.
    Stations,
    /// A width that is not positive.
    Width(f64),
    /// A tautness outside [0, 1].
    Tautness(f64),
    /// A station direction that points into the opening or has no length.
    Direction,
    /// An outer curve whose top view enters the punch opening.
    CrossesOpening {
        /// The first sampled point inside (press coordinates).
        at: DVec3,
    },
    /// Two sides that meet without a corner place their outer ends differently.
    OuterEndsDisagree {
        /// The distance between the two outer ends (mm).
        gap: f64,
    },
    /// A designer tangent at an end shared with another side (where eq. 4 decides it).
    TangentAtSideJoin,
    /// The kernel failed.
    Kernel(GeomError),
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::Mismatch => write!(f, "the blankholder input does not match the opening's pieces"),
            Problem::Stations => write!(f, "stations must start at 0, end at 1 and increase"),
            Problem::Width(w) => write!(f, "a binder width must be positive, but this is {w} mm"),
            Problem::Tautness(t) => write!(f, "a corner tautness must lie in [0, 1], but this is {t}"),
            Problem::Direction => write!(f, "a station direction must point out of the opening"),
            Problem::CrossesOpening { at } => write!(
                f,
                "the outer edge enters the punch opening in the top view near ({:.1}, {:.1}, {:.1})",
                at.x, at.y, at.z
            ),
            Problem::OuterEndsDisagree { gap } => write!(
                f,
                "two sides meeting without a corner place their outer ends {gap:.4} mm apart"
            ),
            Problem::TangentAtSideJoin => write!(
                f,
                "this end meets another side without a corner: its tangent follows from C1 continuity"
            ),
            Problem::Kernel(e) => write!(f, "{e}"),
        }
    }
}

fn at(piece: usize) -> impl Fn(GeomError) -> Error {
    move |e| Error {
        piece,
        problem: Problem::Kernel(e),
    }
}

fn fail(piece: usize, problem: Problem) -> Error {
    Error { piece, problem }
}

/// Samples per boundary for the join figures.
pub const JOIN_SAMPLES: usize = 200;

/// Samples per outer edge for the "crosses the opening" check.
const CROSSING_SAMPLES: usize = 200;

/// Samples along each patch for the "normal points up" check.
const FOLD_SAMPLES: usize = 400;

/// Builds the blankholder around `opening` (module documentation).
pub fn build(opening: &PunchOpening, spec: &[PieceSpec]) -> Result<Blankholder, Error> {
    let n = opening.pieces.len();
    let outline = opening.top_outline();
    if spec.len() != n {
        return Err(fail(0, Problem::Mismatch));
    }
    for (k, (piece, s)) in opening.pieces.iter().zip(spec).enumerate() {
        match (piece.kind, s) {
            (PieceKind::Side, PieceSpec::Side(side)) => check_side(k, side)?,
            (PieceKind::Corner, PieceSpec::Corner { tautness }) => {
                if !(0.0..=1.0).contains(tautness) {
                    return Err(fail(k, Problem::Tautness(*tautness)));
                }
            }
            _ => return Err(fail(k, Problem::Mismatch)),
        }
    }

    // Outer points of every side, and the tangent scale of each side's ends.
    let mut outer_points: Vec<Option<OuterPoints>> = vec![None; n];
    for (k, s) in spec.iter().enumerate() {
        if let PieceSpec::Side(side) = s {
            outer_points[k] = Some(outer_points_of(opening, k, side)?);
        }
    }
    // Sides meeting without a corner: shared outer end, one tangent scale (eq. 4).
    for k in 0..n {
        let next = (k + 1) % n;
        let (Some(a), Some(b)) = (&outer_points[k], &outer_points[next]) else {
            continue;
        };
        let gap = a.points[a.points.len() - 1].distance(b.points[0]);
        if gap > 1e-9 * (1.0 + a.points[0].length()) {
            return Err(fail(next, Problem::OuterEndsDisagree { gap }));
        }
        if let (PieceSpec::Side(sa), PieceSpec::Side(sb)) = (&spec[k], &spec[next]) {
            if sa.end_tangent.is_some() {
                return Err(fail(k, Problem::TangentAtSideJoin));
            }
            if sb.start_tangent.is_some() {
                return Err(fail(next, Problem::TangentAtSideJoin));
            }
        }
        let shared = 0.5 * (a.scale + b.scale);
        if let Some(a) = outer_points[k].as_mut() {
            a.end_scale = shared;
        }
        if let Some(b) = outer_points[next].as_mut() {
            b.start_scale = shared;
        }
    }

    let up_first = !opening.counter_clockwise;
    let rule = |inner: &Curve3, outer: &Curve3| {
        if up_first {
            ruled(inner, outer)
        } else {
            ruled(outer, inner)
        }
    };

    // Side patches.
    let mut outers: Vec<Option<Curve3>> = vec![None; n];
    for (k, points) in outer_points.iter().enumerate() {
        let Some(points) = points else { continue };
        let PieceSpec::Side(side) = &spec[k] else {
            continue;
        };
        let c = &opening.pieces[k].curve;
        let (d0, d1) = (c.derivative_at(0.0), c.derivative_at(1.0));
        let start = match side.start_tangent {
            Some(t) => unit(t, k)? * (d0.length() * points.start_scale),
            None => d0 * points.start_scale,
        };
        let end = match side.end_tangent {
            Some(t) => unit(t, k)? * (d1.length() * points.end_scale),
            None => d1 * points.end_scale,
        };
        let outer = interpolate_at(
            &points.points,
            &points.params,
            &Interpolation::cubic_with_tangents(start, end),
        )
        .map_err(at(k))?;
        check_outside(&outline, &outer, k)?;
        outers[k] = Some(outer);
    }

    // Corner outer edges.
    for (k, s) in spec.iter().enumerate() {
        let PieceSpec::Corner { tautness } = s else {
            continue;
        };
        let (prev, next) = ((k + n - 1) % n, (k + 1) % n);
        let (Some(qa), Some(qb)) = (&outers[prev], &outers[next]) else {
            return Err(fail(k, Problem::Mismatch));
        };
        let g0 = &opening.pieces[k].curve;
        let ca = &opening.pieces[prev].curve;
        let cb = &opening.pieces[next].curve;
        let lambda0 = g0.derivative_at(0.0).length() / ca.derivative_at(1.0).length();
        let lambda1 = g0.derivative_at(1.0).length() / cb.derivative_at(0.0).length();
        let g1 = outer_corner(
            g0,
            qa.end_point(),
            qb.start_point(),
            *tautness,
            qa.derivative_at(1.0) * lambda0,
            qb.derivative_at(0.0) * lambda1,
            opening.delta,
        )
        .map_err(at(k))?;
        check_outside(&outline, &g1, k)?;
        outers[k] = Some(g1);
    }

    let mut patches = Vec::with_capacity(n);
    for (k, (piece, outer)) in opening.pieces.iter().zip(outers).enumerate() {
        let Some(outer) = outer else {
            return Err(fail(k, Problem::Mismatch));
        };
        let surface = rule(&piece.curve, &outer).map_err(at(k))?;
        check_upward(&surface, k)?;
        patches.push(Patch {
            name: piece.name.clone(),
            kind: piece.kind,
            surface,
            outer,
        });
    }
    let joins = (0..n)
        .map(|k| {
            let (a, b) = (&patches[k], &patches[(k + 1) % n]);
            Join {
                before: a.name.clone(),
                after: b.name.clone(),
                quality: measure_join(&a.surface, &b.surface, JOIN_SAMPLES),
            }
        })
        .collect();
    Ok(Blankholder {
        patches,
        joins,
        inner_outline: outline,
        max_bead_height: DEFAULT_MAX_BEAD_HEIGHT,
    })
}

/// A side's outer points at its stations, with their parameters on the side curve.
#[derive(Debug, Clone)]
struct OuterPoints {
    params: Vec<f64>,
    points: Vec<DVec3>,
    /// Outer-to-inner length ratio: the default scale of the end tangents.
    scale: f64,
    start_scale: f64,
    end_scale: f64,
}

fn check_side(k: usize, side: &SideSpec) -> Result<(), Error> {
    let s = &side.stations;
    let ordered = s.len() >= 2
        && s[0].at == 0.0
        && s[s.len() - 1].at == 1.0
        && s.windows(2).all(|w| w[1].at > w[0].at);
    if !ordered {
        return Err(fail(k, Problem::Stations));
    }
    for st in s {
        if !(st.width.is_finite() && st.width > 0.0) {
            return Err(fail(k, Problem::Width(st.width)));
        }
    }
    Ok(())
}

fn outer_points_of(
    opening: &PunchOpening,
    k: usize,
    side: &SideSpec,
) -> Result<OuterPoints, Error> {
    let c = &opening.pieces[k].curve;
    // The side's arc length tabulated once for all its stations (a long side of many
    // spans measured from its start for every station took seconds).
    let lengths = ArcLengths::new(c);
    let length = lengths.total();
    let mut params = Vec::with_capacity(side.stations.len());
    let mut points = Vec::with_capacity(side.stations.len());
    for st in &side.stations {
        let t = if st.at <= 0.0 {
            0.0
        } else if st.at >= 1.0 {
            1.0
        } else {
            lengths.parameter_at(st.at * length).map_err(at(k))?
        };
        let [p, d] = c.derivatives::<2>(t);
        let outward = opening.outward(d);
        let u = match st.direction {
            Some(dir) => {
                let u = dir.normalize_or_zero();
                if u == DVec2::ZERO || u.dot(outward) <= 0.0 {
                    return Err(fail(k, Problem::Direction));
                }
                u
            }
            None => outward,
        };
        if u == DVec2::ZERO {
            return Err(fail(k, Problem::Direction));
        }
        let q = p + st.width * (st.angle.cos() * u.extend(0.0) + st.angle.sin() * DVec3::Z);
        params.push(t);
        points.push(q);
    }
    let outer_len: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    let inner_len: f64 = params
        .windows(2)
        .map(|w| c.point_at(w[0]).distance(c.point_at(w[1])))
        .sum();
    let scale = if inner_len > 0.0 {
        outer_len / inner_len
    } else {
        1.0
    };
    Ok(OuterPoints {
        params,
        points,
        scale,
        start_scale: scale,
        end_scale: scale,
    })
}

/// Steps 1-3 of a corner: `g0` moved onto `a`, `b`, made taut, re-interpolated with the
/// eq. 4 end derivatives `d0`, `d1`.
///
/// The eq. 4 derivatives generally differ from the moved curve's own, in speed and in
/// slope: the similarity scales `g0` (at a convex corner the outer edge is longer, by
/// `(r + w) / r` on a fillet of radius `r` with a binder `w` wide), while the sides'
/// outer edges run about as fast as the sides, so eq. 4 asks for an end speed of about
/// a third of the moved curve's on ordinary corners; and the heights, carried over
/// per parameter onto a top view three times as long, climb at a third of the slope of
/// the sides' outer edges. Interpolating the moved curve at `g0`'s parameters with
/// those end derivatives forced the whole change into the last knot span: the edge met
/// its neighbour's slope only in its last 2 mm, with radii of 2 to 5 mm there (a kink
/// a die engineer sends back). Instead, both differences are spread over the corner
/// ([`corner_reparametrization`]):
///
/// - the speed: the interpolant's parameter is `s = phi(t)`, a smooth increasing map of
///   `g0`'s domain onto itself whose slope at each end is the ratio of the moved
///   curve's speed to the eq. 4 speed, so the eq. 4 end derivative is the moved curve's
///   own speed in `s` (the ruled patch pairs `g0(u)` with the outer point moved from
///   `g0(phi^-1(u))`; its rulings lean a little near the ends);
/// - the direction: what is left of `phi'(end) d - X'(end)` (the slope difference, and
///   any top-view turn a designer's side tangent asks for) is added to the moved points
///   as a cubic Hermite correction that vanishes at both ends, spread over the whole
///   corner.
///
/// The interpolant's knots lie at the reparametrized sample parameters, one span per
/// step: the step rule's last step is what remains of `g0`, however short, and with
/// averaged knots (P&T eq. 9.22) that sliver shared a knot span with the step before it
/// and swung the curve back on itself.
pub fn outer_corner(
    g0: &Curve3,
    a: DVec3,
    b: DVec3,
    tautness: f64,
    d0: DVec3,
    d1: DVec3,
    delta: f64,
) -> crate::geom::Result<Curve3> {
    Ok(outer_corner_samples(g0, a, b, tautness, d0, d1, delta)?.curve)
}

/// The outer corner of [`outer_corner`] with the points it interpolates and their
/// parameters on it.
#[derive(Debug, Clone, PartialEq)]
pub struct OuterCorner {
    /// `g1`, on `g0`'s domain.
    pub curve: Curve3,
    /// `g0`'s step-rule sample parameters `t_i` (the interpolated points come from
    /// `g0(t_i)`).
    pub sample_params: Vec<f64>,
    /// The moved, taut and slope-corrected points `Y_i` that `g1` passes through.
    pub points: Vec<DVec3>,
    /// Their parameters on `g1`, `s_i = phi(t_i)`.
    pub params: Vec<f64>,
}

/// [`outer_corner`] with its samples, for checks.
pub fn outer_corner_samples(
    g0: &Curve3,
    a: DVec3,
    b: DVec3,
    tautness: f64,
    d0: DVec3,
    d1: DVec3,
    delta: f64,
) -> crate::geom::Result<OuterCorner> {
    let (p0, p1) = (g0.start_point(), g0.end_point());
    let (from, to) = ((p1 - p0).truncate(), (b - a).truncate());
    if from.length() <= 1e-12 || to.length() <= 1e-12 {
        return Err(GeomError::Singular {
            what: "a blankholder corner whose ends coincide in the top view",
        });
    }
    if d0.length() <= 0.0 || d1.length() <= 0.0 || !d0.is_finite() || !d1.is_finite() {
        return Err(GeomError::ZeroVector {
            what: "blankholder corner end derivative",
        });
    }
    // The top-view similarity as a complex factor: rotation and scale.
    let factor = DVec2::new(
        to.dot(from) / from.length_squared(),
        from.perp_dot(to) / from.length_squared(),
    );
    let rotate = |d: DVec2| {
        DVec2::new(
            d.x * factor.x - d.y * factor.y,
            d.x * factor.y + d.y * factor.x,
        )
    };
    let (za, zb) = (a.z - p0.z, b.z - p1.z);
    let samples = tessellate_curve(g0, &Tolerance::new(delta)?)?;
    let mut params = samples.params;
    // A cubic with both end tangents needs at least two points; more keep the shape.
    if params.len() < 5 {
        params = (0..=4).map(|i| i as f64 / 4.0).collect();
    }
    let (t0, t1) = (params[0], params[params.len() - 1]);
    let span = t1 - t0;
    // The moved curve X(t) and its derivative.
    let moved = |t: f64| -> DVec3 {
        let p = g0.point_at(t);
        let f = (t - t0) / span;
        let xy = a.truncate() + rotate((p - p0).truncate());
        let z = p.z + (1.0 - f) * za + f * zb;
        let straight = (1.0 - f) * a.z + f * b.z;
        xy.extend((1.0 - tautness) * z + tautness * straight)
    };
    let moved_derivative = |t: f64| -> DVec3 {
        let d = g0.derivative_at(t);
        let z = d.z + (zb - za) / span;
        let straight = (b.z - a.z) / span;
        rotate(d.truncate()).extend((1.0 - tautness) * z + tautness * straight)
    };
    // The end slopes of phi: the moved curve's speed over the eq. 4 speed, taken along
    // the eq. 4 direction (the factor that leaves the smallest correction).
    let slope = |x: DVec3, d: DVec3| {
        let along = x.dot(d) / d.length_squared();
        if along > 1e-3 * x.length() / d.length() {
            along
        } else {
            x.length() / d.length()
        }
    };
    let (x0, x1) = (moved_derivative(t0), moved_derivative(t1));
    let (r0, r1) = (slope(x0, d0), slope(x1, d1));
    let phi = corner_reparametrization(r0, r1);
    // The direction correction: a cubic Hermite in f that vanishes at both ends with
    // derivatives (per unit t) e0, e1.
    let (e0, e1) = (d0 * r0 - x0, d1 * r1 - x1);
    let correction = |f: f64| {
        let h10 = f * f * f - 2.0 * f * f + f;
        let h11 = f * f * f - f * f;
        (e0 * h10 + e1 * h11) * span
    };
    let last = params.len() - 1;
    let mut points = Vec::with_capacity(params.len());
    let mut s = Vec::with_capacity(params.len());
    for (i, &t) in params.iter().enumerate() {
        let f = (t - t0) / span;
        let p = if i == 0 {
            a
        } else if i == last {
            b
        } else {
            moved(t) + correction(f)
        };
        points.push(p);
        s.push(if i == 0 {
            t0
        } else if i == last {
            t1
        } else {
            t0 + span * phi.at(f)
        });
    }
    let opts = Interpolation {
        knots: KnotPlacement::AtParameters,
        ..Interpolation::cubic_with_tangents(d0, d1)
    };
    let curve = interpolate_at(&points, &s, &opts)?;
    Ok(OuterCorner {
        curve,
        sample_params: params,
        points,
        params: s,
    })
}

/// The reparametrization `phi` of an outer corner ([`outer_corner`]): an increasing map
/// of [0, 1] onto itself with `phi'(0) = r0`, `phi'(1) = r1`, its slope
/// `exp(E0(f) ln r0 + E1(f) ln r1 + W(f) c)` with `E0 = (1 - f)^2`, `E1 = f^2`,
/// `W = 2 f (1 - f)`: the log-slope blends smoothly from each end's value into a middle
/// value `c`, the one number that makes the slope's mean 1. The mean grows with `c`
/// from 0 to infinity, so `c` exists for every pair of positive end slopes.
#[derive(Debug, Clone, Copy)]
pub struct Reparametrization {
    ln_r0: f64,
    ln_r1: f64,
    c: f64,
}

/// Gauss-Legendre panels over [0, 1] for the integrals of [`Reparametrization`]: the
/// slope is an exponential of a quadratic, smooth, and 64 panels of 5 points integrate
/// it to rounding for end slopes up to 100.
const PHI_PANELS: usize = 64;

impl Reparametrization {
    fn slope(&self, f: f64) -> f64 {
        let (e0, e1) = ((1.0 - f) * (1.0 - f), f * f);
        (e0 * self.ln_r0 + e1 * self.ln_r1 + (1.0 - e0 - e1) * self.c).exp()
    }

    /// `phi'(f)`.
    pub fn derivative(&self, f: f64) -> f64 {
        self.slope(f)
    }

    /// `phi(f)` for `f` in [0, 1].
    pub fn at(&self, f: f64) -> f64 {
        integrate(|x| self.slope(x), 0.0, f.clamp(0.0, 1.0))
    }
}

/// The map `phi` with end slopes `r0`, `r1` (both > 0) ([`Reparametrization`]).
pub fn corner_reparametrization(r0: f64, r1: f64) -> Reparametrization {
    let mut phi = Reparametrization {
        ln_r0: r0.ln(),
        ln_r1: r1.ln(),
        c: 0.0,
    };
    let mean = |phi: &Reparametrization| integrate(|x| phi.slope(x), 0.0, 1.0);
    // Bracket c, then bisect: the mean is increasing in c.
    let (mut lo, mut hi) = (-1.0, 1.0);
    for _ in 0..200 {
        phi.c = lo;
        if mean(&phi) < 1.0 {
            break;
        }
        lo *= 2.0;
    }
    for _ in 0..200 {
        phi.c = hi;
        if mean(&phi) > 1.0 {
            break;
        }
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        phi.c = mid;
        if mean(&phi) < 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * (1.0 + mid.abs()) {
            break;
        }
    }
    phi.c = 0.5 * (lo + hi);
    phi
}

/// Composite 5-point Gauss-Legendre over [a, b] with panels as [0, 1] is cut into
/// ([`PHI_PANELS`]), the last panel cut at `b`.
fn integrate(g: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const X: [f64; 5] = [
        0.0,
        -0.538_469_310_105_683,
        0.538_469_310_105_683,
        -0.906_179_845_938_664,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
        0.236_926_885_056_189,
    ];
    let h = 1.0 / PHI_PANELS as f64;
    let mut sum = 0.0;
    let mut lo = a;
    while lo < b {
        let hi = (lo + h).min(b);
        let (m, r) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        sum += r * X.iter().zip(W).map(|(x, w)| w * g(m + r * x)).sum::<f64>();
        lo = hi;
    }
    sum
}

fn check_outside(outline: &[DVec2], outer: &Curve3, k: usize) -> Result<(), Error> {
    let (t0, t1) = outer.domain();
    // The ends sit on the opening's normal lines; interior samples must lie outside.
    for i in 1..CROSSING_SAMPLES {
        let p = outer.point_at(t0 + (t1 - t0) * i as f64 / CROSSING_SAMPLES as f64);
        if inside_outline(outline, p.truncate()) {
            return Err(fail(k, Problem::CrossesOpening { at: p }));
        }
    }
    Ok(())
}

/// Refuses a patch whose normal does not point up somewhere: a fold, where the outer
/// edge runs back against the opening (a station direction almost along the opening, an
/// end tangent turning back, an outer corner rotated the other way round at a concave
/// corner) and the rulings cross. The patch is ruled, `S = (1 - v) A(u) + v B(u)`, so the
/// +Z component of `S_u x S_v` is linear in v along every ruling: its signs on the two
/// long edges decide the whole ruling.
fn check_upward(surface: &NurbsSurface, k: usize) -> Result<(), Error> {
    let ((u0, u1), (v0, v1)) = (surface.domain_u(), surface.domain_v());
    for i in 0..=FOLD_SAMPLES {
        let u = u0 + (u1 - u0) * i as f64 / FOLD_SAMPLES as f64;
        for v in [v0, v1] {
            let d = surface.derivatives::<2>(u, v);
            if d[1][0].cross(d[0][1]).z.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return Err(fail(
                    k,
                    Problem::Kernel(GeomError::Singular {
                        what: "the binder patch folds over itself (its normal turns down there)",
                    }),
                ));
            }
        }
    }
    Ok(())
}

fn unit(v: DVec3, k: usize) -> Result<DVec3, Error> {
    let u = v.normalize_or_zero();
    if u == DVec3::ZERO || !u.is_finite() {
        return Err(fail(
            k,
            Problem::Kernel(GeomError::ZeroVector {
                what: "outer-curve end tangent",
            }),
        ));
    }
    Ok(u)
}
