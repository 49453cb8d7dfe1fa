//! Surface builtins: NURBS from a control net, the constructions die faces are made of
//! (ruled, loft, Coons, revolution), and curves projected onto a surface.
//!
//! Curves given to them are 3-D: sketches are placed through their views and 2-D
//! curves lie at z = 0.

use std::f64::consts::TAU;
use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::diag::Diagnostic;
use crate::geom::construct::{
    coons as coons_patch, coons_triangle, loft as loft_surface, revolve as revolve_surface,
    ruled as ruled_surface, Loft,
};
use crate::geom::curve::CLOSED_TOLERANCE;
use crate::geom::interpolate::{
    closed_parameters, interpolate, interpolate_closed, parameters, Interpolation, Parametrization,
};
use crate::geom::intersect::intersect_line_surface_all;
use crate::geom::tessellate::{tessellate_curve, Tolerance};
use crate::geom::{Curve3, GeomError, KnotVector, NurbsSurface, TrimmedSurface};

use super::super::value::{Data, Value};
use super::args::{bad_argument, direction3, opt_count, span_of, vector3, what};
use super::{as_count, as_curve3, as_number, as_point3, opt, req, type_error, Builtin, Call};

/// The surface builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin {
        name: "nurbs_surface",
        params: &[req("degree"), req("points"), opt("knots_u"), opt("knots_v"), opt("weights")],
        doc: "the NURBS surface from its degree (one number or (u, v)) and rows of 3-D control points; knots default to clamped uniform",
        run: nurbs_surface,
    },
    Builtin { name: "ruled", params: &[req("a"), req("b")], doc: "the ruled surface of straight lines between two curves", run: ruled },
    Builtin {
        name: "loft",
        params: &[req("sections"), opt("degree"), opt("start_tangent"), opt("end_tangent")],
        doc: "the surface skinned through a list of section curves, optionally with cross-boundary tangent curves at the first and last",
        run: loft,
    },
    Builtin {
        name: "coons",
        params: &[req("bottom"), req("top"), req("left"), req("right")],
        doc: "the Coons patch of four boundary curves (bottom and top run along u, left and right along v)",
        run: coons,
    },
    Builtin { name: "coons3", params: &[req("a"), req("b"), req("c")], doc: "the three-sided Coons patch of three boundary curves meeting end to end", run: coons3 },
    Builtin {
        name: "revolve",
        params: &[req("profile"), req("axis_point"), req("axis_dir"), opt("angle")],
        doc: "the exact surface swept by a profile turning about an axis (a full turn by default)",
        run: revolve,
    },
    Builtin {
        name: "project",
        params: &[req("curve"), req("surface"), opt("direction")],
        doc: "the curve on a surface under a curve seen along a direction (default press -Z: a trim line drawn in the top view, dropped onto the product); a smooth cubic, closed if the curve is",
        run: project,
    },
    Builtin {
        name: "trim",
        params: &[req("surface"), req("outline")],
        doc: "the surface trimmed at a closed 3-D outline lying on it (such as `project(trim_line, panel)`): the part inside the outline, the product as the die face carries it",
        run: trim,
    },
];

/// `(u, v)` degrees from a number or a pair of numbers.
fn degrees(call: &Call) -> Result<(usize, usize), Diagnostic> {
    let v = call.required("degree")?;
    let w = what(call, "degree");
    match &v.data {
        Data::Tuple(items) if items.len() == 2 => {
            Ok((as_count(&items[0], &w)?, as_count(&items[1], &w)?))
        }
        Data::Number(_) => {
            let d = as_count(v, &w)?;
            Ok((d, d))
        }
        _ => Err(type_error(
            v,
            &w,
            "a degree such as `3` or a pair `(3, 2)` for u and v",
        )),
    }
}

/// A list of rows (lists) of items converted by `f`.
fn rows<T>(
    call: &Call,
    name: &str,
    f: impl Fn(&Value, &str) -> Result<T, Diagnostic>,
) -> Result<Vec<Vec<T>>, Diagnostic> {
    let w = what(call, name);
    call.list(name)?
        .iter()
        .map(|row| match &row.data {
            Data::List(items) => items.iter().map(|v| f(v, &w)).collect(),
            _ => Err(type_error(row, &w, "a list of rows, each a list `[...]`")),
        })
        .collect()
}

fn knots(call: &Call, name: &str) -> Result<Option<Vec<f64>>, Diagnostic> {
    if call.arg(name).is_none() {
        return Ok(None);
    }
    let w = what(call, name);
    call.list(name)?
        .iter()
        .map(|v| as_number(v, &w))
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

fn nurbs_surface(call: &Call) -> Result<Data, Diagnostic> {
    let (du, dv) = degrees(call)?;
    let units = call.units;
    let net = rows(call, "points", |v, w| as_point3(v, units, w))?;
    let count_u = net.len();
    let count_v = net.first().map_or(0, Vec::len);
    if let Some(i) = net.iter().position(|r| r.len() != count_v) {
        return Err(bad_argument(
            call,
            "points",
            format!(
                "row {i} of the control net has {} points, but row 0 has {count_v}",
                net[i].len()
            ),
            "every row of the net needs the same number of points",
        ));
    }
    let degree_fail = |e: GeomError| call.kernel_error(e, Some("degree"));
    let ku = match knots(call, "knots_u")? {
        Some(k) => {
            KnotVector::new(k, du, count_u).map_err(|e| call.kernel_error(e, Some("knots_u")))?
        }
        None => KnotVector::uniform(du, count_u).map_err(|e| match e {
            GeomError::TooFewPoints { .. } => call.kernel_error(e, Some("points")),
            e => degree_fail(e),
        })?,
    };
    let kv = match knots(call, "knots_v")? {
        Some(k) => {
            KnotVector::new(k, dv, count_v).map_err(|e| call.kernel_error(e, Some("knots_v")))?
        }
        None => KnotVector::uniform(dv, count_v).map_err(|e| match e {
            GeomError::TooFewPoints { .. } => call.kernel_error(e, Some("points")),
            e => degree_fail(e),
        })?,
    };
    let (ku, kv) = (ku.into_vec(), kv.into_vec());
    let surface = if call.arg("weights").is_some() {
        let weights = rows(call, "weights", as_number)?;
        if weights.len() != count_u || weights.iter().any(|r| r.len() != count_v) {
            return Err(bad_argument(
                call,
                "weights",
                format!("the weights must form a {count_u} x {count_v} net like the points"),
                "give one weight per control point, in rows like the points",
            ));
        }
        NurbsSurface::new_rational(du, dv, ku, kv, net, weights)
            .map_err(|e| call.kernel_error(e, Some("weights")))?
    } else {
        NurbsSurface::new(du, dv, ku, kv, net).map_err(|e| call.kernel_error(e, Some("points")))?
    };
    Ok(Data::Surface(Arc::new(surface)))
}

fn ruled(call: &Call) -> Result<Data, Diagnostic> {
    let (a, b) = (call.curve3("a")?, call.curve3("b")?);
    Ok(Data::Surface(Arc::new(
        ruled_surface(&a, &b).map_err(|e| call.kernel_error(e, Some("b")))?,
    )))
}

fn optional_curve(call: &Call, name: &str) -> Result<Option<Curve3>, Diagnostic> {
    call.arg(name)
        .map(|_| call.curve3(name).map(|c| (*c).clone()))
        .transpose()
}

fn loft(call: &Call) -> Result<Data, Diagnostic> {
    let w = what(call, "sections");
    let sections = call
        .list("sections")?
        .iter()
        .map(|v| as_curve3(v, &w).map(|c| (*c).clone()))
        .collect::<Result<Vec<_>, _>>()?;
    let opts = Loft {
        degree: opt_count(call, "degree", 0)?,
        start_tangent: optional_curve(call, "start_tangent")?,
        end_tangent: optional_curve(call, "end_tangent")?,
        ..Loft::default()
    };
    // The sections are made compatible by merging their knots, so the surface may have
    // as many control points as the sections have together, times the sections.
    let merged: usize = sections.iter().map(|c| c.control_points().len()).sum();
    call.check_samples(
        "sections",
        merged as f64 * sections.len() as f64,
        "control points (the sections' points together, once per section)",
    )?;
    let s = loft_surface(&sections, &opts).map_err(|e| {
        let arg = match &e {
            GeomError::RationalNotSupported { .. } | GeomError::ZeroVector { .. } => {
                if opts.start_tangent.is_some() {
                    "start_tangent"
                } else {
                    "end_tangent"
                }
            }
            _ => "sections",
        };
        call.kernel_error(e, Some(arg))
    })?;
    Ok(Data::Surface(Arc::new(s)))
}

fn coons(call: &Call) -> Result<Data, Diagnostic> {
    let (b, t, l, r) = (
        call.curve3("bottom")?,
        call.curve3("top")?,
        call.curve3("left")?,
        call.curve3("right")?,
    );
    Ok(Data::Surface(Arc::new(
        coons_patch(&b, &t, &l, &r).map_err(|e| call.kernel_error(e, None))?,
    )))
}

fn coons3(call: &Call) -> Result<Data, Diagnostic> {
    let (a, b, c) = (call.curve3("a")?, call.curve3("b")?, call.curve3("c")?);
    Ok(Data::Surface(Arc::new(
        coons_triangle(&a, &b, &c).map_err(|e| call.kernel_error(e, None))?,
    )))
}

fn revolve(call: &Call) -> Result<Data, Diagnostic> {
    let profile = call.curve3("profile")?;
    let point = vector3(call, "axis_point")?;
    let dir = direction3(call, "axis_dir")?;
    let angle = if call.arg("angle").is_some() {
        call.angle("angle")?
    } else {
        TAU
    };
    if !(angle > 0.0 && angle <= TAU + 1e-12) {
        return Err(bad_argument(
            call,
            "angle",
            format!(
                "a revolution turns by more than 0 and at most 360 deg, not {} deg",
                crate::eval::units::round(angle.to_degrees())
            ),
            "give an angle such as `90 deg`; leave it out for a full turn",
        ));
    }
    let s = revolve_surface(&profile, point, dir, angle)
        .map_err(|e| call.kernel_error(e, Some("profile")))?;
    Ok(Data::Surface(Arc::new(s)))
}

// ---- project --------------------------------------------------------------------------
//
// The curve is sampled densely (the chordal tessellation, with an edge limit so straight
// pieces get points too), every sample is moved along the direction onto the surface
// (Newton continuing from the previous sample's (u, v); a global line-surface search
// where that fails), and the hits are interpolated by one cubic B-spline (chord length,
// averaged knots: simple interior knots, so the result is C2 between its samples). A
// closed curve is sampled segment by segment (between its C0 knots) and its hits get
// the periodic cubic (`interpolate_closed`): neither the samples nor the fit then
// depend on where the closed sketch starts, and the seam is C2 like the rest. The
// fit is then checked at the middle of every sample interval against the true
// projection there, and intervals that deviate get that point as a new sample, until
// the fit holds everywhere.

/// Chordal tolerance (mm) of the first sampling of the input curve.
const PROJECT_CHORDAL: f64 = 0.005;

/// Longest step (mm) between first samples, so straight pieces get points too.
const PROJECT_MAX_EDGE: f64 = 20.0;

/// A short curve gets at least about this many first samples.
const PROJECT_MIN_SAMPLES: f64 = 16.0;

/// Largest deviation (mm) of the fitted curve from the true projection, measured across
/// the curve at the middle of every sample interval.
const PROJECT_FIT: f64 = 1e-4;

/// Rounds of the fit check at most (each adds points only where the fit is off).
const PROJECT_ROUNDS: usize = 12;

/// Most samples the fit may use (the interpolation solves a dense system).
const PROJECT_MAX_SAMPLES: usize = 4000;

/// A turn of the input curve's direction (across the projection direction) larger than
/// this at one point is a corner, which one smooth cubic cannot follow: 0.5 deg.
const PROJECT_CORNER: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// The input direction is nearly parallel to the surface (the projected tangent is
/// ill-conditioned) where `|direction . normal|` is below this; there an open curve's
/// end is left free.
const PROJECT_GRAZING: f64 = 0.05;

/// A point of the projected curve with its surface parameters.
#[derive(Debug, Clone, Copy)]
struct Hit {
    u: f64,
    v: f64,
    point: DVec3,
}

/// Moves points along a fixed direction onto a surface.
struct Projector<'a> {
    surface: &'a NurbsSurface,
    /// Unit direction.
    dir: DVec3,
    /// Unit vectors across the direction.
    across: (DVec3, DVec3),
    /// Accepted distance of a hit from its line (mm).
    tol: f64,
}

impl<'a> Projector<'a> {
    fn new(surface: &'a NurbsSurface, dir: DVec3, size: f64) -> Self {
        let e1 = dir.any_orthonormal_vector();
        Self {
            surface,
            dir,
            across: (e1, dir.cross(e1)),
            tol: 1e-12 * size.max(1.0),
        }
    }

    /// Where the line through `p` leaves the line, in the plane across it.
    fn offset(&self, q: DVec3) -> DVec2 {
        DVec2::new(q.dot(self.across.0), q.dot(self.across.1))
    }

    /// Newton on `(S(u, v) - p)` across the direction, from `(u, v)`, clamped to the
    /// domain, with step halving; `None` where it does not converge (the line leaves
    /// the patch there, or the surface is parallel to the direction).
    fn near(&self, p: DVec3, u: f64, v: f64) -> Option<Hit> {
        let s = self.surface;
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let (mut u, mut v) = (u, v);
        for _ in 0..40 {
            let d = s.derivatives::<2>(u, v);
            let f = self.offset(d[0][0] - p);
            let res = f.length();
            if !res.is_finite() {
                return None;
            }
            if res <= self.tol {
                return Some(Hit {
                    u,
                    v,
                    point: d[0][0],
                });
            }
            let (su, sv) = (self.offset(d[1][0]), self.offset(d[0][1]));
            let det = su.perp_dot(sv);
            if !det.is_finite() || det.abs() <= 1e-14 * su.length() * sv.length() {
                return None;
            }
            // Solve [su sv] (du, dv) = -f.
            let du = -f.perp_dot(sv) / det;
            let dv = -su.perp_dot(f) / det;
            let mut lambda = 1.0;
            let mut moved = false;
            for _ in 0..30 {
                let nu = (u + lambda * du).clamp(u0, u1);
                let nv = (v + lambda * dv).clamp(v0, v1);
                if self.offset(s.point_at(nu, nv) - p).length() < res {
                    (u, v, moved) = (nu, nv, true);
                    break;
                }
                lambda *= 0.5;
            }
            if !moved {
                return None;
            }
        }
        None
    }

    /// The hit of the line through `p`: continuing from `prev` when given, else (or
    /// where that fails) the global search's hit nearest to `prev`'s point, or to `p`
    /// along the line. `None`: the line misses the surface.
    fn hit(&self, p: DVec3, prev: Option<Hit>) -> Result<Option<Hit>, GeomError> {
        if let Some(h) = prev {
            if let Some(found) = self.near(p, h.u, h.v) {
                return Ok(Some(found));
            }
        }
        let hits = intersect_line_surface_all(p, self.dir, self.surface)?;
        let key = |h: &crate::geom::intersect::RayHit| match prev {
            Some(q) => h.point.distance(q.point),
            None => h.w.abs(),
        };
        Ok(hits
            .iter()
            .min_by(|a, b| key(a).total_cmp(&key(b)))
            .map(|h| Hit {
                u: h.u,
                v: h.v,
                point: h.point,
            }))
    }

    /// The unit tangent of the projected curve where the input curve runs along
    /// `tangent` and its projection is at `hit` (the tangent moved along the direction
    /// into the surface's tangent plane), or `None` where the surface is too steep to
    /// tell.
    fn tangent(&self, tangent: DVec3, hit: Hit) -> Option<DVec3> {
        let n = self.surface.normal(hit.u, hit.v).ok()?;
        let rn = self.dir.dot(n);
        if rn.abs() < PROJECT_GRAZING {
            return None;
        }
        (tangent - self.dir * (tangent.dot(n) / rn)).try_normalize()
    }
}

/// The part of `v` across the unit direction `dir`, normalized.
fn across(v: DVec3, dir: DVec3) -> Option<DVec3> {
    (v - dir * v.dot(dir)).try_normalize()
}

/// The first kink of `curve` seen along `dir` (a C0 knot, or the seam of a closed
/// curve, where the direction turns by more than [`PROJECT_CORNER`]): the point and
/// the turn in radians.
fn first_corner(curve: &Curve3, dir: DVec3, closed: bool) -> Option<(DVec3, f64)> {
    let (t0, t1) = curve.domain();
    let turn = |a: Option<DVec3>, b: Option<DVec3>| match (a, b) {
        (Some(a), Some(b)) => a.angle_between(b),
        _ => 0.0,
    };
    let end_dir = |c: &Curve3, t: f64| c.unit_tangent(t).ok().and_then(|d| across(d, dir));
    for (k, m) in curve.knots().distinct() {
        if k <= t0 || k >= t1 || m < curve.degree() {
            continue;
        }
        let Ok((left, right)) = curve.split_at(k) else {
            continue;
        };
        let a = turn(
            end_dir(&left, left.domain().1),
            end_dir(&right, right.domain().0),
        );
        if a > PROJECT_CORNER {
            return Some((curve.point_at(k), a));
        }
    }
    if closed {
        let a = turn(end_dir(curve, t1), end_dir(curve, t0));
        if a > PROJECT_CORNER {
            return Some((curve.start_point(), a));
        }
    }
    None
}

/// The cubic through `points` (chord length), with end tangents along the unit
/// directions given, scaled to the parameter speed (the total chord on [0, 1]).
fn fit(points: &[DVec3], ends: (Option<DVec3>, Option<DVec3>)) -> Result<Curve3, GeomError> {
    let chord: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    let opts = Interpolation {
        degree: 3,
        parametrization: Parametrization::ChordLength,
        start_tangent: ends.0.map(|d| d * chord),
        end_tangent: ends.1.map(|d| d * chord),
        ..Interpolation::default()
    };
    interpolate(points, &opts)
}

/// A closed curve cut at its C0 knots (multiplicity >= degree: a sketch's segment
/// joins) into pieces, each on [0, 1] with its first weight 1. The same segment then has
/// the same numbers whichever segment the sketch starts with (the cut and the remap are
/// exact for a sketch's segments on [k, k + 1]), so its samples are the same points.
fn pieces_between_corners(curve: &Curve3) -> Result<Vec<Curve3>, GeomError> {
    curve
        .smooth_pieces()?
        .into_iter()
        .map(|piece| {
            let piece = piece.reparametrized(0.0, 1.0)?;
            match piece.weights() {
                Some(w) => {
                    let w0 = w[0];
                    let weights = w.iter().map(|&x| x / w0).collect();
                    Curve3::new_rational(
                        piece.degree(),
                        piece.knots().as_slice().to_vec(),
                        piece.control_points().to_vec(),
                        weights,
                    )
                }
                None => Ok(piece),
            }
        })
        .collect()
}

/// A point in words: `(x, y)` across a vertical direction, else `(x, y, z)`.
fn place(p: DVec3, dir: DVec3) -> String {
    let r = crate::eval::units::round;
    if dir.z.abs() >= 1.0 - 1e-12 {
        format!("({}, {})", r(p.x), r(p.y))
    } else {
        format!("({}, {}, {})", r(p.x), r(p.y), r(p.z))
    }
}

fn project(call: &Call) -> Result<Data, Diagnostic> {
    let input = call.curve3("curve")?;
    let surface = call.surface("surface")?;
    let dir = match call.arg("direction") {
        Some(_) => direction3(call, "direction")?,
        None => -DVec3::Z,
    };
    let Some(dir) = dir.try_normalize() else {
        return Err(bad_argument(
            call,
            "direction",
            "`direction` of `project` has zero length",
            "give a direction of non-zero length, such as `(0, 0, -1)` (the default)",
        ));
    };
    let (t0, t1) = input.domain();
    let scale = input.control_scale().max(surface.control_scale());
    let closed = match &call.required("curve")?.data {
        Data::Sketch(s) => s.closed,
        _ => input.start_point().distance(input.end_point()) <= CLOSED_TOLERANCE * scale.max(1.0),
    };
    if let Some((p, turn)) = first_corner(&input, dir, closed) {
        return Err(bad_argument(
            call,
            "curve",
            format!(
                "the curve has a corner at {} (it turns by {} deg there); `project` makes one smooth curve and cannot follow it",
                place(p, dir),
                crate::eval::units::round(turn.to_degrees())
            ),
            "round the corner with a `fillet` (or draw it with a `tangent arc` or `tangent spline`), or project the pieces on either side of it separately",
        ));
    }
    let length = input.length();
    if !(length.is_finite() && length > 0.0) {
        return Err(bad_argument(
            call,
            "curve",
            "the curve to project has no length",
            "pass a curve that goes somewhere",
        ));
    }
    let fail = |e: GeomError| call.kernel_error(e, Some("curve"));
    let tol = Tolerance::new(PROJECT_CHORDAL)
        .and_then(|t| t.with_max_edge(PROJECT_MAX_EDGE.min(length / PROJECT_MIN_SAMPLES)))
        .map_err(fail)?;
    // The input's pieces (one for an open curve; for a closed one, one per stretch
    // between its C0 knots, each on [0, 1], so that the samples of a sketch's segment do
    // not depend on where the sketch starts) and their samples: `samples[k]` is
    // `(piece, s)`, the piece of the interval that ends there and the parameter on it.
    let pieces = if closed {
        pieces_between_corners(&input).map_err(fail)?
    } else {
        vec![(*input).clone()]
    };
    let mut samples: Vec<(usize, f64)> = Vec::new();
    let mut sample_points: Vec<DVec3> = Vec::new();
    for (j, piece) in pieces.iter().enumerate() {
        let line = tessellate_curve(piece, &tol).map_err(fail)?;
        let skip = usize::from(j > 0); // the previous piece's end
        for (&t, &p) in line.params.iter().zip(&line.points).skip(skip) {
            samples.push((j, t));
            sample_points.push(p);
        }
    }
    let too_many = |n: usize| {
        bad_argument(
            call,
            "curve",
            format!(
                "projecting this curve needs more than {PROJECT_MAX_SAMPLES} points ({n} so far)"
            ),
            "the curve is very long or very finely curved for the surface; project it in pieces",
        )
    };
    if samples.len() > PROJECT_MAX_SAMPLES {
        return Err(too_many(samples.len()));
    }
    let projector = Projector::new(&surface, dir, scale);
    let leaves = |p: DVec3| {
        bad_argument(
            call,
            "curve",
            format!(
                "the curve leaves the surface near {}: the line through it along the direction misses the surface",
                place(p, dir)
            ),
            "keep the curve inside the surface's outline as seen along the direction (the top view by default), or extend the surface",
        )
        .with_label(span_of(call, "surface"), "the surface")
    };
    let mut hits: Vec<Hit> = Vec::with_capacity(samples.len());
    for &p in &sample_points {
        let h = projector
            .hit(p, hits.last().copied())
            .map_err(fail)?
            .ok_or_else(|| leaves(p))?;
        hits.push(h);
    }
    if closed {
        // The seam: the same point at both ends.
        let n = hits.len() - 1;
        hits[n] = hits[0];
    }
    if let Some(i) = (1..hits.len())
        .find(|&i| hits[i].point.distance(hits[i - 1].point) <= 1e-9 * scale.max(1.0))
    {
        return Err(bad_argument(
            call,
            "curve",
            format!(
                "the curve runs along the direction near {}: its projection there shrinks to a point",
                place(sample_points[i], dir)
            ),
            "a projected curve must advance across the direction; project a curve drawn across it (in the top view for the default direction)",
        ));
    }
    // A closed curve gets the periodic cubic through its samples (the seam repeated in
    // `hits` is dropped for the fit): no end conditions, so the outline does not depend
    // on where the sketch starts. An open one gets end tangents from the input's, moved
    // onto the surface, or free ends where the surface is too steep for that.
    let end_tangents = |hits: &[Hit]| -> (Option<DVec3>, Option<DVec3>) {
        let at = |t: f64, h: Hit| {
            input
                .unit_tangent(t)
                .ok()
                .and_then(|d| projector.tangent(d, h))
        };
        let n = hits.len() - 1;
        (at(t0, hits[0]), at(t1, hits[n]))
    };
    let points = |hits: &[Hit]| hits.iter().map(|h| h.point).collect::<Vec<_>>();
    let fit_hits = |hits: &[Hit]| -> Result<Curve3, GeomError> {
        let pts = points(hits);
        if closed {
            interpolate_closed(&pts[..pts.len() - 1], Parametrization::ChordLength)
        } else {
            fit(&pts, end_tangents(hits))
        }
    };
    // The fitted curve's parameter of every sample (the seam's twice when closed: 0 and 1).
    let fit_parameters = |pts: &[DVec3]| -> Result<Vec<f64>, GeomError> {
        if closed {
            let mut s = closed_parameters(&pts[..pts.len() - 1], Parametrization::ChordLength)?;
            s.push(1.0);
            Ok(s)
        } else {
            parameters(pts, Parametrization::ChordLength)
        }
    };
    let mut curve = fit_hits(&hits).map_err(fail)?;
    for _ in 0..PROJECT_ROUNDS {
        let pts = points(&hits);
        let s = fit_parameters(&pts).map_err(fail)?;
        let mut inserts: Vec<(usize, (usize, f64), Hit)> = Vec::new();
        for i in 0..hits.len() - 1 {
            // The interval's piece, and its start on it (0 where the interval starts
            // the piece).
            let (j, end) = samples[i + 1];
            let begin = if samples[i].0 == j { samples[i].1 } else { 0.0 };
            let tm = 0.5 * (begin + end);
            let pm = pieces[j].point_at(tm);
            let truth = projector
                .hit(pm, Some(hits[i]))
                .map_err(fail)?
                .ok_or_else(|| leaves(pm))?;
            let sm = 0.5 * (s[i] + s[i + 1]);
            let [c, d] = curve.derivatives::<2>(sm);
            let off = c - truth.point;
            let across = match d.try_normalize() {
                Some(u) => off - u * off.dot(u),
                None => off,
            };
            if across.length() > PROJECT_FIT {
                inserts.push((i, (j, tm), truth));
            }
        }
        if inserts.is_empty() {
            break;
        }
        if hits.len() + inserts.len() > PROJECT_MAX_SAMPLES {
            return Err(too_many(hits.len() + inserts.len()));
        }
        let mut new_samples = Vec::with_capacity(samples.len() + inserts.len());
        let mut new_hits = Vec::with_capacity(samples.len() + inserts.len());
        let mut next = inserts.iter().peekable();
        for i in 0..hits.len() {
            new_samples.push(samples[i]);
            new_hits.push(hits[i]);
            if let Some(&(_, at, h)) = next.next_if(|(k, _, _)| *k == i) {
                new_samples.push(at);
                new_hits.push(h);
            }
        }
        (samples, hits) = (new_samples, new_hits);
        curve = fit_hits(&hits).map_err(fail)?;
    }
    Ok(Data::Curve3(Arc::new(curve)))
}

// ---- trim -----------------------------------------------------------------------------

/// How far (mm) the outline of `trim` may lie from the surface, and its ends from each
/// other: die-face accuracy (`project` itself fits within 1e-4 mm).
const TRIM_TOLERANCE: f64 = 0.01;

fn trim(call: &Call) -> Result<Data, Diagnostic> {
    let surface = call.surface("surface")?;
    let outline = call.curve3("outline")?;
    let r = crate::eval::units::round;
    match TrimmedSurface::new((*surface).clone(), (*outline).clone(), TRIM_TOLERANCE) {
        Ok(t) => Ok(Data::Trimmed(Arc::new(t))),
        Err(GeomError::OpenLoop { gap }) => Err(bad_argument(
            call,
            "outline",
            format!("the outline of `trim` must be closed, but its ends are {} mm apart", r(gap)),
            "trim at a closed outline: draw the trim line closed (`close` in the sketch) and project it onto the surface, `project(trim_line, panel)`",
        )),
        Err(GeomError::OffSurface { distance, at }) => Err(bad_argument(
            call,
            "outline",
            format!(
                "the outline of `trim` must lie on the surface, but it is {} mm off it near ({}, {}, {})",
                r(distance),
                r(at.0),
                r(at.1),
                r(at.2)
            ),
            format!("the outline must lie within {TRIM_TOLERANCE} mm of the surface: project the trim line onto this very surface, `project(trim_line, panel)`"),
        )
        .with_label(span_of(call, "surface"), "the surface")),
        Err(GeomError::SelfCrossing { at }) => Err(bad_argument(
            call,
            "outline",
            format!(
                "the outline of `trim` crosses itself near ({}, {}, {})",
                r(at.0),
                r(at.1),
                r(at.2)
            ),
            "a trim outline goes round the product once: move the points of the trim line so it does not cross or touch itself",
        )),
        Err(e) => Err(call.kernel_error(e, Some("outline"))),
    }
}
