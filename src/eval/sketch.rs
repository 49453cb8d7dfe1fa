//! Sketches: 2-D profiles drawn in a named view, evaluated to exact NURBS.
//!
//! A designer draws punch profiles, sections and bead outlines as a sequence of
//! commands: a start point, lines, arcs, splines, fillets at corners, tangency to the
//! previous segment. [`build`] hands the evaluated commands to the kernel
//! ([`crate::geom::sketch::draw`]), which makes one 2-D NURBS curve (lines and arcs
//! exact, arcs rational, segments joined with C0 knots) plus the list of its segments,
//! so features can refer to pieces; here each segment gets the span of its command and
//! each kernel error becomes a `die::sketch` diagnostic at the command at fault. The
//! [`View`] places the profile in press coordinates.

use glam::{DVec2, DVec3};

use crate::diag::Diagnostic;
use crate::geom::sketch::{draw, Profile, SketchError};
use crate::geom::{Curve2, Curve3, GeomError};
use crate::syntax::Span;

pub use crate::geom::sketch::Command;

use super::finite;
use super::units::round;

/// The plane a sketch is drawn in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum View {
    /// The top view: sketch (x, y) is press (x, y, 0).
    Top,
    /// The side view along -Y: sketch (x, z) is press (x, 0, z).
    SideXZ,
    /// The side view along X: sketch (y, z) is press (0, y, z).
    SideYZ,
    /// A vertical section plane through two top-view points `a` and `b` (paper 001 eq. 5):
    /// sketch (s, z) is press `a + s (b - a)/|b - a| + z Z`.
    Section {
        /// First top-view point (the sketch origin).
        a: DVec2,
        /// Second top-view point (sets the sketch's +s direction).
        b: DVec2,
    },
    /// A section profile drawn before its plane is known (the step draw's addendum
    /// profiles, `std/addendum`): sketch (s, z), s along the section and z up. The
    /// feature that uses the profile places it in its own section planes; on its own it
    /// is shown like `side_xz`, at press (s, 0, z).
    Profile,
}

impl View {
    /// Where the sketch point `p` lies in press coordinates.
    pub fn place(&self, p: DVec2) -> DVec3 {
        match *self {
            View::Top => DVec3::new(p.x, p.y, 0.0),
            View::SideXZ | View::Profile => DVec3::new(p.x, 0.0, p.y),
            View::SideYZ => DVec3::new(0.0, p.x, p.y),
            View::Section { a, b } => {
                let d = (b - a).normalize_or_zero();
                (a + d * p.x).extend(p.y)
            }
        }
    }

    /// The view's name as scripts write it.
    pub fn name(&self) -> &'static str {
        match self {
            View::Top => "top",
            View::SideXZ => "side_xz",
            View::SideYZ => "side_yz",
            View::Section { .. } => "section",
            View::Profile => "profile",
        }
    }
}

/// One drawn piece of a sketch.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// `line`, `arc`, `fillet`, `spline`.
    pub kind: &'static str,
    /// The command that drew it.
    pub span: Span,
    /// Its parameter range in the joined curve.
    pub range: (f64, f64),
}

/// A finished sketch.
#[derive(Debug, Clone, PartialEq)]
pub struct Sketch {
    /// The view it was drawn in.
    pub view: View,
    /// The whole profile as one 2-D NURBS curve (C0 at corners).
    pub curve: Curve2,
    /// The pieces in drawing order.
    pub segments: Vec<Segment>,
    /// Whether the profile ends where it started.
    pub closed: bool,
}

impl Sketch {
    /// The profile placed in press coordinates (exact: views are affine).
    pub fn to_3d(&self) -> Curve3 {
        self.curve.map_points(|p| self.view.place(p))
    }

    /// Segment `k` on its own, on its parameter range `[k, k + 1]` of the joined curve.
    pub fn segment_curve(&self, k: usize) -> crate::geom::Result<Curve2> {
        let (a, b) = self.segments.get(k).map_or((0.0, 1.0), |s| s.range);
        self.curve.between(a, b)
    }
}

/// Draws the commands (each with the span of its source) in `view`: the geometry is
/// [`crate::geom::sketch::draw`] (its documentation gives the semantics, command by
/// command); every problem is a `die::sketch` diagnostic at the offending command's
/// span (the whole sketch's `span` when no one command is at fault).
///
/// Segment `k` of [`Sketch::segments`] has the parameter range `[k, k + 1]`.
pub fn build(view: View, commands: &[(Command, Span)], span: Span) -> Result<Sketch, Diagnostic> {
    let drawn: Vec<Command> = commands.iter().map(|(c, _)| c.clone()).collect();
    let Profile {
        curve,
        segments,
        closed,
    } = draw(&drawn).map_err(|e| diagnostic(&e, commands, span))?;
    let segments = segments
        .iter()
        .map(|s| Segment {
            kind: s.kind,
            span: commands[s.command].1,
            range: s.range,
        })
        .collect();
    Ok(Sketch {
        view,
        curve,
        segments,
        closed,
    })
}

/// The diagnostic for a sketch the kernel could not draw, at the command at fault.
fn diagnostic(e: &SketchError, commands: &[(Command, Span)], span: Span) -> Diagnostic {
    let at = |k: usize| commands[k].1;
    match *e {
        SketchError::Empty => sketch_error(
            "a sketch starts with `from (x, y)`",
            span,
            "this sketch is empty",
        )
        .with_help("begin the sketch with `from (x, y)`, then draw lines, arcs or splines"),
        SketchError::NoStart { command } => sketch_error(
            "a sketch starts with `from (x, y)`",
            at(command),
            "this comes before any `from`",
        )
        .with_help("begin the sketch with `from (x, y)`: the point the first segment starts at"),
        SketchError::NotFinite { command } => sketch_error(
            "a point of this command is not a finite number",
            at(command),
            "not finite",
        )
        .with_help("check for a division by zero in the coordinates"),
        SketchError::OutOfRange { command, value } => sketch_error(
            format!("a point of this command has a coordinate of {} mm, beyond the modelling range of {} mm from the origin", finite::show(value), finite::show(crate::geom::MAX_COORDINATE)),
            at(command),
            "beyond the modelling range",
        )
        .with_help("die faces are modelled in millimetres within 1 km of the origin, where the GLB's 32-bit floats still hold the default tolerance; check the units and magnitudes of the coordinates"),
        SketchError::SecondStart { command } => sketch_error(
            "`from` can only start a sketch",
            at(command),
            "a second `from`",
        )
        .with_help("a sketch is one connected profile; draw another profile as a separate sketch"),
        SketchError::AfterClose { command } => sketch_error(
            "the sketch is already closed",
            at(command),
            "nothing can follow `close`",
        )
        .with_help("move this command before `close`, or start another sketch"),
        SketchError::ZeroLengthLine { command, at: p } => sketch_error(
            format!("this line ends where it starts, at {}: a zero-length line", pt(p)),
            at(command),
            "zero-length line",
        )
        .with_help("remove this line or change its end point"),
        SketchError::ArcPointsCoincide {
            command,
            first,
            second,
            at: p,
        } => {
            let names = ["the current point", "`through`", "the end point"];
            sketch_error(
                format!("{} and {} of this arc are the same point {}", names[first], names[second], pt(p)),
                at(command),
                "degenerate arc",
            )
            .with_help("an arc needs three distinct points: where it starts, one it passes through, and where it ends")
        }
        SketchError::ArcCollinear {
            command,
            points: [from, through, to],
        } => sketch_error(
            format!("the arc's three points {}, {} and {} lie on one line", pt(from), pt(through), pt(to)),
            at(command),
            "collinear points",
        )
        .with_help("move `through` off the line from the current point to the end point, or draw a `line to`"),
        SketchError::NoPreviousDirection { command } => {
            let what = match commands[command].0 {
                Command::TangentArcTo(_) => "a tangent arc",
                _ => "a spline with `tangent`",
            };
            sketch_error(
                format!("{what} continues the direction of the previous segment, but there is none"),
                at(command),
                "no segment before this one",
            )
            .with_help("draw a line or an arc first, or give the direction explicitly (`arc to p through q`, a spline without `tangent`)")
        }
        SketchError::ZeroLengthArc { command, at: p } => sketch_error(
            format!("this tangent arc ends where it starts, at {}", pt(p)),
            at(command),
            "zero-length arc",
        )
        .with_help("remove it or change its end point"),
        SketchError::ArcEndBehind { command, at: p } => sketch_error(
            format!("{} lies behind the current point on the tangent line: no arc leaving tangentially reaches it", pt(p)),
            at(command),
            "unreachable end point",
        )
        .with_help("a tangent arc turns left or right from the previous segment's direction; pick an end point off that line"),
        SketchError::SplineEmpty { command } => sketch_error(
            "a spline needs at least one point to pass through",
            at(command),
            "no points",
        )
        .with_help("write `spline through [(x1, y1), (x2, y2), ...]`"),
        SketchError::SplineRepeatsPoint {
            command,
            item,
            at: p,
        } => {
            let message = if item == 0 {
                format!(
                    "point 1 of the spline, {}, is the current point where the spline starts",
                    pt(p)
                )
            } else {
                format!(
                    "the spline passes through {} twice in a row (items {} and {} of the list, counting from 1)",
                    pt(p),
                    item,
                    item + 1
                )
            };
            sketch_error(message, at(command), "repeated point")
                .with_help("a spline cannot pass through the same point twice in a row; remove one of them")
        }
        SketchError::BadRadius { command, radius } => sketch_error(
            format!("a fillet radius must be positive, got {}", mm(radius)),
            at(command),
            "negative radius",
        )
        .with_help("give the radius as a positive length such as `fillet 5 mm`"),
        SketchError::TwoFillets { command } => sketch_error(
            "two fillets at the same corner",
            at(command),
            "a second fillet here",
        )
        .with_help("keep one fillet per corner"),
        SketchError::TwoStartFillets { command } => sketch_error(
            "two fillets at the start corner",
            at(command),
            "a second fillet here",
        )
        .with_help("keep one fillet per corner"),
        SketchError::FilletWithoutNext { command } => sketch_error("this fillet has no second segment to round to", at(command), "nothing is drawn after it")
            .with_help("a fillet rounds the corner between the segment before it and the one after it; draw the next segment or `close` the sketch"),
        SketchError::StartFilletOnOpen { command } => sketch_error("a fillet right after `from` rounds the start corner, which only a closed sketch has", at(command), "at the start of an open sketch")
            .with_help("end the sketch with `close`, or move the fillet to a corner"),
        SketchError::NoSegments => sketch_error(
            "a sketch needs at least one segment after `from`",
            span,
            "nothing is drawn",
        )
        .with_help("draw a `line to`, an arc or a spline after `from`"),
        SketchError::NothingToClose { command } => sketch_error(
            "nothing to close: the sketch has no segments",
            at(command),
            "right after `from`",
        )
        .with_help("draw at least two segments before `close`"),
        SketchError::FilletNeedsLines {
            fillet,
            other,
            other_kind,
        } => sketch_error(
            "a fillet rounds the corner between two lines",
            at(fillet),
            "this fillet",
        )
        .with_label(
            at(other),
            format!(
                "this segment is a{} {}",
                if other_kind == "arc" { "n" } else { "" },
                other_kind
            ),
        )
        .with_help("draw the corner with two lines, or continue with a `tangent arc`"),
        SketchError::FilletOnOnePiece { fillet } => sketch_error(
            "a fillet rounds the corner between two lines",
            at(fillet),
            "this fillet",
        ),
        SketchError::FilletNoCorner { fillet, prev, next } => sketch_error(
            "this fillet has no corner to round: the segments before and after it continue in one direction",
            at(fillet),
            "nothing to round here",
        )
        .with_label(at(prev), "this segment")
        .with_label(at(next), "continues straight on in this one")
        .with_help("remove the fillet (a straight or tangent join needs no rounding), or move a point so the segments meet at an angle"),
        SketchError::FilletDoublesBack { fillet, prev, next } => sketch_error(
            "the lines double back at this corner, so no fillet can round it",
            at(fillet),
            "this fillet",
        )
        .with_label(at(prev), "this line")
        .with_label(at(next), "runs back along this one")
        .with_help("remove the fillet or change the lines"),
        SketchError::FilletDoesNotFit {
            fillet,
            prev,
            next,
            radius,
            lengths: (len1, len2),
            angle,
            takes,
            largest,
        } => sketch_error(
            format!("fillet {} does not fit: the lines are {} and {} long", mm(radius), mm(len1), mm(len2)),
            at(fillet),
            "this fillet",
        )
        .with_label(at(prev), format!("{} long", mm(len1)))
        .with_label(at(next), format!("{} long", mm(len2)))
        .with_help(format!(
            "at this {} deg corner a fillet of {} takes {} of each line (r / tan(angle / 2)); the largest that fits is {}",
            round(angle.to_degrees()),
            mm(radius),
            mm(takes),
            mm(largest)
        )),
        SketchError::Kernel { command, ref error } => {
            kernel(error, command.map_or(span, at))
        }
    }
}

fn sketch_error(message: impl Into<String>, span: Span, label: impl Into<String>) -> Diagnostic {
    Diagnostic::new("die::sketch", message, span, label)
}

fn kernel(err: &GeomError, span: Span) -> Diagnostic {
    sketch_error(
        format!("this sketch segment cannot be built: {err}"),
        span,
        format!("{err}"),
    )
    .with_help("check the points of this command for coincident or degenerate input")
}

fn mm(v: f64) -> String {
    format!("{} mm", round(v))
}

fn pt(p: DVec2) -> String {
    format!("({}, {})", round(p.x), round(p.y))
}
