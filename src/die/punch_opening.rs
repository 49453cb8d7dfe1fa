//! The punch opening line (paper 001 sections 3.1-3.2; `docs/methods.md`): one closed 3-D
//! curve, made of sides and corners, where the punch ends and the blankholder begins.
//!
//! The designer draws the opening once in the top view (a closed profile: sides joined
//! by fillets, the corners) and, per side, the binder wrap in a side view. [`build`]:
//!
//! 1. each side is the 3-D curve whose projections are its top-view piece and its side
//!    view ([`side_curve_from_two_views`]: the paper's stepping, eq. 1-2, steps 1-7),
//!    re-interpolated with end tangents taken from the two views, so neighbouring pieces
//!    agree on their tangent direction exactly;
//! 2. two sides that meet without a corner (a tangent join in the top view) must agree in
//!    3-D within `delta`; they are snapped to a common point and tangent;
//! 3. each corner is the cubic Hermite curve between its sides' ends with the designer's
//!    end-tangent magnitudes and the sides' directions, corrected onto the vertical
//!    surface swept from the top-view fillet (eq. 3, [`build_corner`]);
//! 4. the pieces, in drawing order, are joined into one closed curve.
//!
//! The punch direction is press -Z: the views are drawn in press coordinates, with the
//! product already tipped into draw position.
//!
//! [`PunchOpening::quality`] holds the figures a reviewer checks: how far each side
//! strays from its two drawings, and whether corners are G1 with the asked magnitudes.

use super::memo::Pieces;
use crate::geom::fingerprint::Fingerprint;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::corner::{build_corner, CornerInput};
use super::two_view::{parameter_at_x, side_curve_from_two_views, TwoView};
use crate::geom::interpolate::{interpolate, Interpolation};
use crate::geom::intersect::{polyline_self_crossing, sample_spans};
use crate::geom::inversion::project_to_curve_near;
use crate::geom::join::join_curves;
use crate::geom::{Curve2, Curve3, GeomError};

/// The punch moves along press -Z.
pub const PUNCH_DIRECTION: DVec3 = DVec3::NEG_Z;

/// The largest top-view angle (degrees) between two sides that meet without a corner.
/// Larger kinks need a fillet: a corner.
pub const MAX_SIDE_JOIN_ANGLE_DEG: f64 = 0.5;

/// A vertical view a side's binder wrap is drawn in: the side-view curve's first
/// coordinate runs along `axis` from `origin` (top-view coordinates), its second is
/// press z. `side_xz` is origin 0 with axis +X, `side_yz` axis +Y, a section plane
/// through `a`, `b` has origin `a` and axis `b - a`.
#[derive(Debug, Clone, PartialEq)]
pub struct SideView {
    /// Top-view point where the view's first coordinate is zero.
    pub origin: DVec2,
    /// Unit top-view direction of the view's first coordinate (the common axis).
    pub axis: DVec2,
    /// The binder wrap: (position along `axis`, z).
    pub curve: Curve2,
}

impl SideView {
    /// The top-view point `p` in the view's frame: (along the axis, across it).
    fn local(&self, p: DVec2) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.axis), d.dot(self.axis.perp()))
    }

    /// The press point of view-frame coordinates (along, across, z).
    fn press(&self, p: DVec3) -> DVec3 {
        (self.origin + self.axis * p.x + self.axis.perp() * p.y).extend(p.z)
    }
}

/// One side as the designer gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct SideSpec {
    /// Its name (`front`, `rear`): pieces are referred to by name.
    pub name: String,
    /// Its piece of the top-view profile, in the profile's drawing direction.
    pub top: Curve2,
    /// Its side view.
    pub view: SideView,
}

/// The magnitude of a corner's end tangent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Magnitude {
    /// A derivative length in mm (w.r.t. the corner's parameter on [0, 1]).
    Length(f64),
    /// A factor of the natural magnitude: the arc length of the circular arc with the
    /// corner's chord and end-tangent angle (`1` gives a circle-like corner, smaller
    /// values a tauter one that runs closer to the chord, larger ones a fuller one).
    Natural(f64),
}

/// One corner as the designer gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct CornerSpec {
    /// Its name (`front_right`).
    pub name: String,
    /// `C_TOP`: its fillet in the top view.
    pub top: Curve2,
    /// End-tangent magnitudes at its start and end.
    pub magnitudes: [Magnitude; 2],
}

/// A piece of the top-view profile.
#[derive(Debug, Clone, PartialEq)]
pub enum PieceSpec {
    /// A side, built from two views.
    Side(SideSpec),
    /// A corner between two sides.
    Corner(CornerSpec),
}

impl PieceSpec {
    fn name(&self) -> &str {
        match self {
            PieceSpec::Side(s) => &s.name,
            PieceSpec::Corner(c) => &c.name,
        }
    }
}

/// The whole input of [`build`].
#[derive(Debug, Clone, PartialEq)]
pub struct PunchOpeningSpec {
    /// The pieces in the top-view profile's drawing order, closing on the first.
    pub pieces: Vec<PieceSpec>,
    /// The tolerance `delta` (mm) of the two-view stepping and the corner sampling.
    pub delta: f64,
    /// `L_max` (mm); `None` derives it from the curves' lengths.
    pub max_step: Option<f64>,
}

/// Whether a piece is a side or a corner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PieceKind {
    /// Built from two views.
    Side,
    /// Built from tangent magnitudes and corrected onto the top-view fillet.
    Corner,
}

/// A finished piece of the punch opening.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// The designer's name.
    pub name: String,
    /// Side or corner.
    pub kind: PieceKind,
    /// The 3-D curve, domain [0, 1], running in the profile's direction.
    pub curve: Curve3,
    /// The top-view piece it was built from.
    pub top: Curve2,
}

/// Quality figures of one side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideQuality {
    /// Largest distance (mm) between the side's top-view projection and its top view.
    pub top_deviation: f64,
    /// Largest distance (mm) between the side's projection into its side view and the
    /// side-view curve.
    pub side_deviation: f64,
    /// Points `R_i` the two-view stepping produced.
    pub points: usize,
}

/// Quality figures of one corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerQuality {
    /// Angle (degrees) between the previous side's end tangent and the corner's start.
    pub angle_in: f64,
    /// Angle (degrees) between the corner's end tangent and the next side's start.
    pub angle_out: f64,
    /// The asked end-tangent magnitudes (mm).
    pub asked: (f64, f64),
    /// The corner's actual end-derivative lengths (mm).
    pub actual: (f64, f64),
    /// Largest distance (mm) between the corner's top-view projection and its fillet.
    pub top_deviation: f64,
}

/// Quality figures of a piece.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PieceQuality {
    /// Of a side.
    Side(SideQuality),
    /// Of a corner.
    Corner(CornerQuality),
}

/// The punch opening line.
#[derive(Debug, Clone, PartialEq)]
pub struct PunchOpening {
    /// Sides and corners in drawing order; each ends where the next starts.
    pub pieces: Vec<Piece>,
    /// Quality figures, one per piece.
    pub quality: Vec<PieceQuality>,
    /// All pieces joined into one closed curve (piece `k` on parameters `[k, k + 1]`).
    pub line: Curve3,
    /// Whether the top-view profile runs counter-clockwise (seen from +Z).
    pub counter_clockwise: bool,
    /// The tolerance the opening was built to (mm).
    pub delta: f64,
}

impl PunchOpening {
    /// The piece named `name`.
    pub fn piece(&self, name: &str) -> Option<&Piece> {
        self.pieces.iter().find(|p| p.name == name)
    }

    /// The unit top-view direction pointing out of the opening (towards the binder) at
    /// a point whose 3-D tangent is `tangent`.
    pub fn outward(&self, tangent: DVec3) -> DVec2 {
        let t = tangent.truncate().normalize_or_zero();
        if self.counter_clockwise {
            DVec2::new(t.y, -t.x)
        } else {
            DVec2::new(-t.y, t.x)
        }
    }

    /// The top-view outline as a closed polygon (first point not repeated).
    pub fn top_outline(&self) -> Vec<DVec2> {
        let mut out = Vec::new();
        for piece in &self.pieces {
            let n = 64;
            let (a, b) = piece.top.domain();
            for i in 0..n {
                out.push(piece.top.point_at(a + (b - a) * i as f64 / n as f64));
            }
        }
        out
    }
}

/// Whether the top-view point `p` lies inside the closed polygon `outline` (even-odd
/// rule; the first point is not repeated): the test of what lies inside a punch
/// opening's [`PunchOpening::top_outline`].
pub fn inside_outline(outline: &[DVec2], p: DVec2) -> bool {
    let mut inside = false;
    for k in 0..outline.len() {
        let a = outline[k];
        let b = outline[(k + 1) % outline.len()];
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// What went wrong, and at which piece.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// Index of the culprit in [`PunchOpeningSpec::pieces`].
    pub piece: usize,
    /// The problem.
    pub problem: Problem,
}

/// The problems [`build`] reports.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// The profile has no side at all.
    NoSides,
    /// A corner follows another corner: nothing lies between them to round.
    CornerAfterCorner,
    /// Two sides meet at a top-view angle larger than [`MAX_SIDE_JOIN_ANGLE_DEG`].
    SharpJoin {
        /// The angle in degrees.
        angle_deg: f64,
    },
    /// Two sides meeting without a corner are more than `delta` apart in 3-D (their side
    /// views give different heights at the shared point).
    SidesDisagree {
        /// The gap in mm.
        gap: f64,
    },
    /// The top view crosses or touches itself: the piece of [`Error::piece`] meets the
    /// piece `other` (possibly itself) at `at`, so the opening is no simple outline.
    CrossesItself {
        /// The other piece's index.
        other: usize,
        /// Where they meet, in top-view mm.
        at: DVec2,
    },
    /// The built side strays from the view it was built from by more than
    /// [`view_deviation_bound`]: the two views could not be followed together (a side
    /// view steeper than its stepping can hold), so the side is not what was drawn.
    OffItsView {
        /// Which view: `"side view"` or `"top view"`.
        view: &'static str,
        /// The largest distance found, in mm.
        deviation: f64,
        /// The bound it exceeds, in mm.
        bound: f64,
    },
    /// The kernel failed (views not overlapping, a view doubling back, no convergence).
    Kernel(GeomError),
}

/// How far (mm) a built side may stray from its top or side view before it is refused:
/// ten times `delta`, and at least 0.01 mm. The construction keeps each side within
/// `delta` of its views (the examples' sides stay within 0.003 mm at delta = 0.01 mm);
/// one that strays further was not built as drawn, and what is built on it (binder,
/// step draw) would inherit the error, metres of it for a side view drawn through a
/// spike.
pub fn view_deviation_bound(delta: f64) -> f64 {
    (10.0 * delta).max(0.01)
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::NoSides => write!(f, "the top view has no side, only corners"),
            Problem::CornerAfterCorner => {
                write!(f, "two corners follow each other with no side between them")
            }
            Problem::SharpJoin { angle_deg } => write!(
                f,
                "two sides meet at an angle of {angle_deg:.3} deg without a corner"
            ),
            Problem::SidesDisagree { gap } => write!(
                f,
                "two sides meeting without a corner are {gap:.4} mm apart in 3-D"
            ),
            Problem::CrossesItself { other, at } => write!(
                f,
                "the top view crosses itself at ({:.3}, {:.3}), where it meets piece {other}",
                at.x, at.y
            ),
            Problem::OffItsView {
                view,
                deviation,
                bound,
            } => write!(
                f,
                "the side strays {deviation:.3} mm from its {view} (at most {bound} mm)"
            ),
            Problem::Kernel(e) => write!(f, "{e}"),
        }
    }
}

/// Samples per knot span of a top-view piece for the self-crossing check: enough that a
/// fillet's polyline stays within 0.03 % of its radius of the arc.
const CROSSING_SAMPLES: usize = 32;

/// The top view as one closed outline must not cross or touch itself (a figure of
/// eight would build a line that passes through itself): the first crossing, as the
/// pieces that meet there.
fn check_simple(spec: &PunchOpeningSpec) -> Result<(), Error> {
    let mut points = Vec::new();
    let mut owner = Vec::new();
    for (k, piece) in spec.pieces.iter().enumerate() {
        let top = match piece {
            PieceSpec::Side(s) => &s.top,
            PieceSpec::Corner(c) => &c.top,
        };
        for (_, p) in sample_spans(top, CROSSING_SAMPLES) {
            points.push(p);
            owner.push(k);
        }
    }
    match polyline_self_crossing(&points, true) {
        Some(c) => Err(Error {
            piece: owner[c.first],
            problem: Problem::CrossesItself {
                other: owner[c.second],
                at: c.at,
            },
        }),
        None => Ok(()),
    }
}

fn at(piece: usize) -> impl Fn(GeomError) -> Error {
    move |e| Error {
        piece,
        problem: Problem::Kernel(e),
    }
}

/// Builds the punch opening line (the steps of the module documentation).
pub fn build(spec: &PunchOpeningSpec) -> Result<PunchOpening, Error> {
    build_with(spec, &Pieces::none())
}

/// [`build`], keeping each side's two-view curve in `pieces`: an edit of one side's
/// views re-runs the two-view stepping of that side only.
pub fn build_with(spec: &PunchOpeningSpec, pieces: &Pieces) -> Result<PunchOpening, Error> {
    let n = spec.pieces.len();
    if !spec.pieces.iter().any(|p| matches!(p, PieceSpec::Side(_))) {
        return Err(Error {
            piece: 0,
            problem: Problem::NoSides,
        });
    }
    for k in 0..n {
        if matches!(spec.pieces[k], PieceSpec::Corner(_))
            && matches!(spec.pieces[(k + 1) % n], PieceSpec::Corner(_))
        {
            return Err(Error {
                piece: (k + 1) % n,
                problem: Problem::CornerAfterCorner,
            });
        }
    }
    check_simple(spec)?;
    let opts = TwoView {
        delta: spec.delta,
        max_step: spec.max_step,
    };

    // Step 1: the sides from their two views.
    let mut sides: Vec<Option<SideBuild>> = vec![None; n];
    for (k, piece) in spec.pieces.iter().enumerate() {
        if let PieceSpec::Side(s) = piece {
            let inputs = (s.clone(), opts);
            let side = pieces.piece("side", side_key(s, &opts), &inputs, || {
                side_points(s, &opts)
            });
            sides[k] = Some(side.map_err(at(k))?);
        }
    }

    // Step 2: sides that meet without a corner share their end point and tangent.
    for k in 0..n {
        let next = (k + 1) % n;
        if next == k {
            continue;
        }
        let (Some(a), Some(b)) = (&sides[k], &sides[next]) else {
            continue;
        };
        let (PieceSpec::Side(sa), PieceSpec::Side(sb)) = (&spec.pieces[k], &spec.pieces[next])
        else {
            continue;
        };
        let top_a = sa.top.unit_tangent(sa.top.domain().1).map_err(at(k))?;
        let top_b = sb.top.unit_tangent(sb.top.domain().0).map_err(at(next))?;
        let angle_deg = angle_between(top_a.extend(0.0), top_b.extend(0.0)).to_degrees();
        if angle_deg > MAX_SIDE_JOIN_ANGLE_DEG {
            return Err(Error {
                piece: next,
                problem: Problem::SharpJoin { angle_deg },
            });
        }
        let (end, start) = (a.points[a.points.len() - 1], b.points[0]);
        let gap = end.distance(start);
        if gap > spec.delta {
            return Err(Error {
                piece: next,
                problem: Problem::SidesDisagree { gap },
            });
        }
        let shared = 0.5 * (end + start);
        let dir = (a.end_dir + b.start_dir).normalize_or_zero();
        if let Some(a) = sides[k].as_mut() {
            let last = a.points.len() - 1;
            a.points[last] = shared;
            a.end_dir = dir;
        }
        if let Some(b) = sides[next].as_mut() {
            b.points[0] = shared;
            b.start_dir = dir;
        }
    }
    let mut curves: Vec<Option<Curve3>> = vec![None; n];
    for (k, side) in sides.iter().enumerate() {
        if let Some(side) = side {
            curves[k] = Some(side.curve().map_err(at(k))?);
        }
    }

    // The sides' figures (a thousand projections each), each side on its own, in
    // parallel; a side that strays from its views is refused before corners are built
    // on its ends.
    let figures: Vec<Option<crate::geom::Result<SideQuality>>> = spec
        .pieces
        .par_iter()
        .zip(&curves)
        .map(|(piece, curve)| match (piece, curve) {
            (PieceSpec::Side(s), Some(curve)) => Some(side_quality(curve, s, QUALITY_SAMPLES)),
            _ => None,
        })
        .collect();
    let bound = view_deviation_bound(spec.delta);
    let mut side_figures: Vec<Option<SideQuality>> = Vec::with_capacity(n);
    for (k, f) in figures.into_iter().enumerate() {
        let Some(f) = f else {
            side_figures.push(None);
            continue;
        };
        let f = f.map_err(at(k))?;
        for (view, deviation) in [
            ("side view", f.side_deviation),
            ("top view", f.top_deviation),
        ] {
            if deviation.is_nan() || deviation > bound {
                return Err(Error {
                    piece: k,
                    problem: Problem::OffItsView {
                        view,
                        deviation,
                        bound,
                    },
                });
            }
        }
        side_figures.push(Some(f));
    }

    // Step 3: the corners between their sides' ends.
    let mut corner_quality = vec![None; n];
    for (k, piece) in spec.pieces.iter().enumerate() {
        let PieceSpec::Corner(c) = piece else {
            continue;
        };
        let (prev, next) = ((k + n - 1) % n, (k + 1) % n);
        let (Some(a), Some(b)) = (&curves[prev], &curves[next]) else {
            continue; // corners never neighbour corners (checked above)
        };
        let (p0, p3) = (a.end_point(), b.start_point());
        let (t_in, t_out) = (a.derivative_at(1.0), b.derivative_at(0.0));
        let natural = natural_magnitude(p0, p3, t_in, t_out);
        let asked = c.magnitudes.map(|m| match m {
            Magnitude::Length(l) => l,
            Magnitude::Natural(f) => f * natural,
        });
        let corner = build_corner(&CornerInput {
            end_of_previous: p0,
            tangent_in: t_in,
            start_of_next: p3,
            tangent_out: t_out,
            magnitudes: (asked[0], asked[1]),
            top_view_corner: &c.top,
            punch_dir: PUNCH_DIRECTION,
            delta: spec.delta,
        })
        .map_err(at(k))?;
        let curve = corner.curve;
        let (d0, d1) = (curve.derivative_at(0.0), curve.derivative_at(1.0));
        corner_quality[k] = Some(CornerQuality {
            angle_in: angle_between(t_in, d0).to_degrees(),
            angle_out: angle_between(d1, t_out).to_degrees(),
            asked: (asked[0], asked[1]),
            actual: (d0.length(), d1.length()),
            top_deviation: top_deviation(&curve, &c.top, QUALITY_SAMPLES).map_err(at(k))?,
        });
        curves[k] = Some(curve);
    }

    // Step 4: the pieces in order, joined.
    let mut pieces = Vec::with_capacity(n);
    let mut quality = Vec::with_capacity(n);
    for (k, (piece, curve)) in spec.pieces.iter().zip(curves).enumerate() {
        let Some(curve) = curve else {
            // Every side was built in step 1 and every corner in step 3.
            return Err(Error {
                piece: k,
                problem: Problem::CornerAfterCorner,
            });
        };
        match piece {
            PieceSpec::Side(s) => {
                let figures = side_figures[k]
                    .take()
                    .expect("every side has its figures (worked out and checked above)");
                quality.push(PieceQuality::Side(figures));
                if let Some(PieceQuality::Side(q)) = quality.last_mut() {
                    q.points = sides[k].as_ref().map_or(0, |b| b.points.len());
                }
                pieces.push(Piece {
                    name: s.name.clone(),
                    kind: PieceKind::Side,
                    curve,
                    top: s.top.clone(),
                });
            }
            PieceSpec::Corner(c) => {
                if let Some(q) = corner_quality[k] {
                    quality.push(PieceQuality::Corner(q));
                }
                pieces.push(Piece {
                    name: c.name.clone(),
                    kind: PieceKind::Corner,
                    curve,
                    top: c.top.clone(),
                });
            }
        }
    }
    let curves: Vec<Curve3> = pieces.iter().map(|p| p.curve.clone()).collect();
    let line = join_curves(&curves).map_err(at(0))?;
    let counter_clockwise = signed_area(spec) > 0.0;
    Ok(PunchOpening {
        pieces,
        quality,
        line,
        counter_clockwise,
        delta: spec.delta,
    })
}

/// Samples per piece for the quality figures [`build`] stores.
pub const QUALITY_SAMPLES: usize = 1000;

/// The two-view points of a side with its end directions, before interpolation.
#[derive(Debug, Clone)]
struct SideBuild {
    points: Vec<DVec3>,
    start_dir: DVec3,
    end_dir: DVec3,
}

impl SideBuild {
    /// The cubic through the points with the end directions; magnitudes are the polygon
    /// length, the natural speed of a chord-length parameter on [0, 1].
    fn curve(&self) -> crate::geom::Result<Curve3> {
        let length: f64 = self.points.windows(2).map(|w| w[0].distance(w[1])).sum();
        interpolate(
            &self.points,
            &Interpolation::cubic_with_tangents(self.start_dir * length, self.end_dir * length),
        )
    }
}

/// The fingerprint of one side's inputs to [`side_points`], for the piece memo.
fn side_key(side: &SideSpec, opts: &TwoView) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    side.top.fingerprint().hash(&mut h);
    side.view.curve.fingerprint().hash(&mut h);
    for c in [side.view.origin, side.view.axis] {
        (c.x.to_bits(), c.y.to_bits()).hash(&mut h);
    }
    opts.delta.to_bits().hash(&mut h);
    opts.max_step.map(f64::to_bits).hash(&mut h);
    h.finish()
}

/// Step 1 for one side: the two-view points in press coordinates, in the top view's
/// drawing direction, with the 3-D unit tangents the two views give at the ends.
fn side_points(side: &SideSpec, opts: &TwoView) -> crate::geom::Result<SideBuild> {
    let view = &side.view;
    let top = side.top.map_points(|p| view.local(p));
    let built = side_curve_from_two_views(&top, &view.curve, opts)?;
    let mut points: Vec<DVec3> = built.points.iter().map(|&p| view.press(p)).collect();
    let forward = top.end_point().x >= top.start_point().x;
    if !forward {
        points.reverse();
    }
    let (d0, d1) = top.domain();
    let start_dir = view_tangent(&top, d0, &view.curve, view, forward)?;
    let end_dir = view_tangent(&top, d1, &view.curve, view, forward)?;
    Ok(SideBuild {
        points,
        start_dir,
        end_dir,
    })
}

/// The unit 3-D tangent, in the drawing direction, of the curve whose views are `top`
/// (view frame) and `side`, at the top view's parameter `u`: `(1, dy/dx, dz/dx)` in the
/// view frame.
fn view_tangent(
    top: &Curve2,
    u: f64,
    side: &Curve2,
    view: &SideView,
    forward: bool,
) -> crate::geom::Result<DVec3> {
    let [p, d] = top.derivatives::<2>(u);
    if d.x.abs() <= 1e-12 * d.length() {
        return Err(GeomError::Singular {
            what: "the top view runs across its side view's axis at an end of the side",
        });
    }
    let side = if side.end_point().x < side.start_point().x {
        side.reversed()
    } else {
        side.clone()
    };
    let su = parameter_at_x(&side, p.x, side.domain().0)?;
    let sd = side.derivative_at(su);
    if sd.x.abs() <= 1e-12 * sd.length() {
        return Err(GeomError::Singular {
            what: "the side view is vertical at an end of the side",
        });
    }
    let local = DVec3::new(1.0, d.y / d.x, sd.y / sd.x);
    let local = if forward { local } else { -local };
    let dir = view.press(local) - view.press(DVec3::ZERO);
    Ok(dir.normalize())
}

/// The arc length of the circular arc with chord `p0 p3` and end tangents `t0`, `t1`:
/// `c (theta/2) / sin(theta/2)`, the chord itself when the tangents are parallel.
pub fn natural_magnitude(p0: DVec3, p3: DVec3, t0: DVec3, t1: DVec3) -> f64 {
    let c = p0.distance(p3);
    let half = 0.5 * angle_between(t0, t1);
    if half < 1e-9 {
        c
    } else {
        c * half / half.sin()
    }
}

/// The angle (radians) between two vectors, robust near 0 and pi.
pub fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Quality figures of a built side, sampled at `samples` points.
pub fn side_quality(
    curve: &Curve3,
    side: &SideSpec,
    samples: usize,
) -> crate::geom::Result<SideQuality> {
    let top_deviation = top_deviation(curve, &side.top, samples)?;
    let view = &side.view;
    let mut worst: f64 = 0.0;
    let mut guess = view.curve.domain().0;
    let mut first = true;
    for i in 0..=samples {
        let p = curve.point_at(i as f64 / samples as f64);
        let l = view.local(p.truncate());
        let target = DVec2::new(l.x, p.z);
        let hit = if first {
            crate::geom::inversion::closest_point_on_curve(&view.curve, target)?
        } else {
            project_to_curve_near(&view.curve, target, guess)?
        };
        first = false;
        guess = hit.t;
        worst = worst.max(hit.distance);
    }
    Ok(SideQuality {
        top_deviation,
        side_deviation: worst,
        points: 0,
    })
}

/// The largest distance between `curve`'s top-view projection and `top`, at `samples`
/// points.
pub fn top_deviation(curve: &Curve3, top: &Curve2, samples: usize) -> crate::geom::Result<f64> {
    let (a, b) = curve.domain();
    let mut worst: f64 = 0.0;
    let mut guess = top.domain().0;
    for i in 0..=samples {
        let p = curve
            .point_at(a + (b - a) * i as f64 / samples as f64)
            .truncate();
        let hit = if i == 0 {
            crate::geom::inversion::closest_point_on_curve(top, p)?
        } else {
            project_to_curve_near(top, p, guess)?
        };
        guess = hit.t;
        worst = worst.max(hit.distance);
    }
    Ok(worst)
}

/// Twice the signed area of the top-view profile (positive counter-clockwise).
fn signed_area(spec: &PunchOpeningSpec) -> f64 {
    let mut pts = Vec::new();
    for piece in &spec.pieces {
        let top = match piece {
            PieceSpec::Side(s) => &s.top,
            PieceSpec::Corner(c) => &c.top,
        };
        let (a, b) = top.domain();
        for i in 0..32 {
            pts.push(top.point_at(a + (b - a) * i as f64 / 32.0));
        }
    }
    (0..pts.len())
        .map(|k| pts[k].perp_dot(pts[(k + 1) % pts.len()]))
        .sum()
}

/// The names of the pieces, for messages.
pub fn piece_names(spec: &PunchOpeningSpec) -> Vec<&str> {
    spec.pieces.iter().map(PieceSpec::name).collect()
}
