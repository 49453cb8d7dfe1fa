//! The blankholder (binder) around a punch opening (primer section 3; paper 001
//! sections 3.3-3.4): a ring of ruled patches, one per side and one per corner, C1
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
//!    those tangents: the classic C2 cubic spline, knots at the parameters (see
//!    [`outer_corner`] for why not averaged knots);
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
    let length = c.length();
    let mut params = Vec::with_capacity(side.stations.len());
    let mut points = Vec::with_capacity(side.stations.len());
    for st in &side.stations {
        let t = if st.at <= 0.0 {
            0.0
        } else if st.at >= 1.0 {
            1.0
        } else {
            c.parameter_at_length(st.at * length).map_err(at(k))?
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
/// The interpolant's knots lie at the sample parameters, one span per step. The eq. 4
/// derivatives generally differ from the moved curve's own: the similarity scales `g0`
/// (at a convex corner the outer edge is longer, by `(r + w) / r` on a fillet of radius
/// `r` with a binder `w` wide), while the straight sides' outer edges run as fast as
/// the sides, so `g1` leaves its ends slower than the moved curve and must speed up
/// within its end spans. The step rule's last step is what remains of `g0`, however
/// short. With averaged knots (P&T eq. 9.22) that sliver shares the last knot span with
/// the step before it: the end point, the sample a sliver before it and the end
/// derivative then all bind one cubic piece, which takes up the change of speed with a
/// huge second derivative and swings the curve back on itself (its control polygon runs
/// backwards), so the patch folded on ordinary corners in narrow bands of radius, width
/// and corner tangent. With knots at the parameters the sliver is a span of its own
/// whose speed stays between the neighbouring samples' and the end derivative's, and
/// the spline is otherwise the same.
pub fn outer_corner(
    g0: &Curve3,
    a: DVec3,
    b: DVec3,
    tautness: f64,
    d0: DVec3,
    d1: DVec3,
    delta: f64,
) -> crate::geom::Result<Curve3> {
    let (p0, p1) = (g0.start_point(), g0.end_point());
    let (from, to) = ((p1 - p0).truncate(), (b - a).truncate());
    if from.length() <= 1e-12 || to.length() <= 1e-12 {
        return Err(GeomError::Singular {
            what: "a blankholder corner whose ends coincide in the top view",
        });
    }
    // The top-view similarity as a complex factor: rotation and scale.
    let factor = DVec2::new(
        to.dot(from) / from.length_squared(),
        from.perp_dot(to) / from.length_squared(),
    );
    let (za, zb) = (a.z - p0.z, b.z - p1.z);
    let samples = tessellate_curve(g0, &Tolerance::new(delta)?)?;
    let mut params = samples.params;
    let mut points: Vec<DVec3> = samples.points;
    // A cubic with both end tangents needs at least two points; more keep the shape.
    if params.len() < 5 {
        params = (0..=4).map(|i| i as f64 / 4.0).collect();
        points = params.iter().map(|&t| g0.point_at(t)).collect();
    }
    let (t0, t1) = (params[0], params[params.len() - 1]);
    let moved: Vec<DVec3> = params
        .iter()
        .zip(&points)
        .map(|(&t, &p)| {
            let f = (t - t0) / (t1 - t0);
            let d = (p - p0).truncate();
            let xy = a.truncate()
                + DVec2::new(
                    d.x * factor.x - d.y * factor.y,
                    d.x * factor.y + d.y * factor.x,
                );
            let z = p.z + (1.0 - f) * za + f * zb;
            let straight = (1.0 - f) * a.z + f * b.z;
            xy.extend((1.0 - tautness) * z + tautness * straight)
        })
        .collect();
    let mut moved = moved;
    let last = moved.len() - 1;
    moved[0] = a;
    moved[last] = b;
    // Knots at the parameters, not averaged: a short last step must not share a knot
    // span with the step before it (see above).
    let opts = Interpolation {
        knots: KnotPlacement::AtParameters,
        ..Interpolation::cubic_with_tangents(d0, d1)
    };
    interpolate_at(&moved, &params, &opts)
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
