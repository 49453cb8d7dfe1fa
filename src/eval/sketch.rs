//! Sketches: 2-D profiles drawn in a named view, evaluated to exact NURBS.
//!
//! A designer draws punch profiles, sections and bead outlines as a sequence of
//! commands: a start point, lines, arcs, splines, fillets at corners, tangency to the
//! previous segment. [`build`] turns the evaluated commands into one 2-D NURBS curve
//! (lines and arcs exact, arcs rational, segments joined with C0 knots) plus the list of
//! its segments, so features can refer to pieces. The [`View`] places the profile in
//! press coordinates.

use glam::{DVec2, DVec3};

use crate::diag::Diagnostic;
use crate::geom::arc::{arc_through_points, circular_arc};
use crate::geom::interpolate::{interpolate, Interpolation};
use crate::geom::join::join_curves;
use crate::geom::{Curve2, Curve3, GeomError};
use crate::syntax::Span;

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
        let (lo, hi) = self.curve.domain();
        let tail = if a > lo {
            self.curve.split_at(a)?.1
        } else {
            self.curve.clone()
        };
        if b < hi {
            Ok(tail.split_at(b)?.0)
        } else {
            Ok(tail)
        }
    }
}

/// A sketch command with its arguments evaluated (points in mm, radii in mm).
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// `from p`
    From(DVec2),
    /// `line to p`
    LineTo(DVec2),
    /// `arc to p through q`
    ArcThrough { to: DVec2, through: DVec2 },
    /// `tangent arc to p`
    TangentArcTo(DVec2),
    /// `spline through [..]`, optionally leaving tangent to the previous segment.
    Spline { through: Vec<DVec2>, tangent: bool },
    /// `fillet r`
    Fillet(f64),
    /// `close`
    Close,
}

/// Draws the commands (each with the span of its source) in `view`.
///
/// Semantics, command by command (every problem is a `die::sketch` diagnostic at the
/// offending command's span):
///
/// - `from p` must come first, and only there.
/// - `line to p`: a straight segment (degree 1; raised by the join to the sketch's
///   degree). Drawing to the current point is an error (a zero-length line).
/// - `arc to p through q`: the circular arc from the current point through `q` to `p`,
///   an exact rational quadratic; three points on one line are an error.
/// - `tangent arc to p`: the circular arc that leaves the current point along the end
///   direction of the previous segment and ends at `p`. If `p` lies ahead on that
///   tangent line the "arc" is a straight line (recorded as a `line`); behind it, no
///   arc exists and it is an error.
/// - `spline through [..]`: the interpolating B-spline from the current point through
///   the listed points, chord-length parametrized on [0, 1]; cubic, or of lower degree
///   when there are too few points for a cubic (two points without `tangent` give a
///   straight spline). With `tangent`, the start derivative is the previous segment's
///   unit end direction times the spline's total chord length: with chord-length
///   parameters on [0, 1] that is the speed the first span has anyway (its chord over
///   its parameter step), so the tangent condition does not bunch or stretch the first
///   span. Consecutive equal points are an error naming them (1-based in the list).
/// - `fillet r` rounds the corner at the current point, between the previous segment
///   and the next one, so it takes effect when the next segment is drawn (or at
///   `close`, for the closing corner). Right after `from`, or right after `close`, it
///   rounds the start corner of a closed sketch (the joined curve then starts at the
///   end of that fillet, on the first segment, and the fillet is the last segment). The fillet is the exact arc tangent to both segments; they must be
///   lines, long enough for the tangent length `r / tan(theta / 2)` (theta the angle
///   between the lines), counting what other fillets already took of them. A line used
///   up entirely by fillets disappears. At a straight (tangent) corner a fillet does
///   nothing, whatever the segments; `fillet 0` does nothing either.
/// - `close` draws a line back to the start point unless the sketch is already there,
///   and marks the sketch closed; only a `fillet` (of the start corner) may follow it.
///   Only `close` makes a sketch closed.
///
/// The result joins the pieces with [`crate::geom::join::join_curves`]: segment `k` of
/// [`Sketch::segments`] has the parameter range `[k, k + 1]`.
pub fn build(view: View, commands: &[(Command, Span)], span: Span) -> Result<Sketch, Diagnostic> {
    let Some((first, first_span)) = commands.first() else {
        return Err(sketch_error(
            "a sketch starts with `from (x, y)`",
            span,
            "this sketch is empty",
        )
        .with_help("begin the sketch with `from (x, y)`, then draw lines, arcs or splines"));
    };
    let Command::From(start) = *first else {
        return Err(sketch_error(
            "a sketch starts with `from (x, y)`",
            *first_span,
            "this comes before any `from`",
        )
        .with_help("begin the sketch with `from (x, y)`: the point the first segment starts at"));
    };
    let scale = commands
        .iter()
        .flat_map(|(c, _)| command_points(c))
        .fold(1.0f64, |m, p| m.max(p.abs().max_element()));
    for (c, s) in commands {
        if command_points(c).iter().any(|p| !p.is_finite()) {
            return Err(sketch_error(
                "a point of this command is not a finite number",
                *s,
                "not finite",
            )
            .with_help("check for a division by zero in the coordinates"));
        }
    }
    let mut d = Drawer {
        start,
        current: start,
        pieces: Vec::new(),
        pending: None,
        start_fillet: None,
        closed: false,
        tol: 1e-9 * scale,
    };
    for (cmd, cspan) in &commands[1..] {
        d.command(cmd, *cspan)?;
    }
    if let Some((_, fspan)) = d.pending {
        return Err(sketch_error("this fillet has no second segment to round to", fspan, "nothing is drawn after it")
            .with_help("a fillet rounds the corner between the segment before it and the one after it; draw the next segment or `close` the sketch"));
    }
    if let Some((_, fspan)) = d.start_fillet {
        if !d.closed {
            return Err(sketch_error("a fillet right after `from` rounds the start corner, which only a closed sketch has", fspan, "at the start of an open sketch")
                .with_help("end the sketch with `close`, or move the fillet to a corner"));
        }
    }
    if d.pieces.is_empty() {
        return Err(sketch_error(
            "a sketch needs at least one segment after `from`",
            span,
            "nothing is drawn",
        )
        .with_help("draw a `line to`, an arc or a spline after `from`"));
    }
    let tol = d.tol;
    let pieces: Vec<Piece> = d
        .pieces
        .into_iter()
        .filter(|p| !matches!(p.shape, Shape::Line(a, b) if a.distance(b) <= tol))
        .collect();
    let mut curves = Vec::with_capacity(pieces.len());
    for p in &pieces {
        curves.push(p.curve().map_err(|e| kernel(e, p.span))?);
    }
    let curve = join_curves(&curves).map_err(|e| kernel(e, span))?;
    let segments = pieces
        .iter()
        .enumerate()
        .map(|(k, p)| Segment {
            kind: p.kind,
            span: p.span,
            range: (k as f64, k as f64 + 1.0),
        })
        .collect();
    Ok(Sketch {
        view,
        curve,
        segments,
        closed: d.closed,
    })
}

/// The points a command mentions (for the size and finiteness checks).
fn command_points(c: &Command) -> Vec<DVec2> {
    match c {
        Command::From(p) | Command::LineTo(p) | Command::TangentArcTo(p) => vec![*p],
        Command::ArcThrough { to, through } => vec![*to, *through],
        Command::Spline { through, .. } => through.clone(),
        Command::Fillet(_) | Command::Close => Vec::new(),
    }
}

fn sketch_error(message: impl Into<String>, span: Span, label: impl Into<String>) -> Diagnostic {
    Diagnostic::new("die::sketch", message, span, label)
}

fn kernel(err: GeomError, span: Span) -> Diagnostic {
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

/// The geometry of one piece before the join.
#[derive(Debug, Clone)]
enum Shape {
    /// A straight segment (kept as end points so fillets can trim it).
    Line(DVec2, DVec2),
    /// An arc or a spline.
    Curve(Curve2),
}

#[derive(Debug, Clone)]
struct Piece {
    kind: &'static str,
    span: Span,
    shape: Shape,
}

impl Piece {
    fn end(&self) -> DVec2 {
        match &self.shape {
            Shape::Line(_, b) => *b,
            Shape::Curve(c) => c.end_point(),
        }
    }

    /// Unit direction of travel at the start.
    fn start_dir(&self) -> DVec2 {
        match &self.shape {
            Shape::Line(a, b) => (*b - *a).normalize_or_zero(),
            Shape::Curve(c) => c.unit_tangent(c.domain().0).unwrap_or(DVec2::ZERO),
        }
    }

    /// Unit direction of travel at the end.
    fn end_dir(&self) -> DVec2 {
        match &self.shape {
            Shape::Line(a, b) => (*b - *a).normalize_or_zero(),
            Shape::Curve(c) => c.unit_tangent(c.domain().1).unwrap_or(DVec2::ZERO),
        }
    }

    fn curve(&self) -> crate::geom::Result<Curve2> {
        match &self.shape {
            Shape::Line(a, b) => Curve2::line(*a, *b),
            Shape::Curve(c) => Ok(c.clone()),
        }
    }
}

/// What a fillet does to its corner.
struct Rounding {
    /// New end of the previous line.
    prev_end: DVec2,
    /// New start of the next line.
    next_start: DVec2,
    /// The fillet arc.
    arc: Piece,
}

struct Drawer {
    start: DVec2,
    current: DVec2,
    pieces: Vec<Piece>,
    /// A fillet waiting for the segment after the current point.
    pending: Option<(f64, Span)>,
    /// A fillet given right after `from`: the start corner of a closed sketch.
    start_fillet: Option<(f64, Span)>,
    closed: bool,
    tol: f64,
}

impl Drawer {
    fn command(&mut self, cmd: &Command, span: Span) -> Result<(), Diagnostic> {
        if self.closed {
            if let Command::Fillet(r) = cmd {
                return self.fillet_after_close(*r, span);
            }
            return Err(sketch_error(
                "the sketch is already closed",
                span,
                "nothing can follow `close`",
            )
            .with_help("move this command before `close`, or start another sketch"));
        }
        match cmd {
            Command::From(_) => Err(sketch_error(
                "`from` can only start a sketch",
                span,
                "a second `from`",
            )
            .with_help(
                "a sketch is one connected profile; draw another profile as a separate sketch",
            )),
            Command::LineTo(p) => {
                if p.distance(self.current) <= self.tol {
                    return Err(sketch_error(
                        format!(
                            "this line ends where it starts, at {}: a zero-length line",
                            pt(*p)
                        ),
                        span,
                        "zero-length line",
                    )
                    .with_help("remove this line or change its end point"));
                }
                self.push(Piece {
                    kind: "line",
                    span,
                    shape: Shape::Line(self.current, *p),
                })
            }
            Command::ArcThrough { to, through } => {
                let piece = self.arc_through(*to, *through, span)?;
                self.push(piece)
            }
            Command::TangentArcTo(p) => {
                let piece = self.tangent_arc(*p, span)?;
                self.push(piece)
            }
            Command::Spline { through, tangent } => {
                let piece = self.spline(through, *tangent, span)?;
                self.push(piece)
            }
            Command::Fillet(r) => self.fillet(*r, span),
            Command::Close => self.close(span),
        }
    }

    /// Appends a piece, first rounding the corner before it if a fillet waits there.
    fn push(&mut self, mut piece: Piece) -> Result<(), Diagnostic> {
        if let Some((r, fspan)) = self.pending.take() {
            let prev = self
                .pieces
                .last()
                .expect("a pending fillet follows a segment");
            if let Some(round) = round_corner(prev, &piece, r, fspan, self.tol)? {
                let last = self.pieces.len() - 1;
                set_end(&mut self.pieces[last], round.prev_end);
                set_start(&mut piece, round.next_start);
                self.pieces.push(round.arc);
            }
        }
        self.current = piece.end();
        self.pieces.push(piece);
        Ok(())
    }

    /// The end direction of the previous segment, for tangent continuations.
    fn previous_direction(&self, span: Span, what: &str) -> Result<DVec2, Diagnostic> {
        let dir = self
            .pieces
            .last()
            .map(Piece::end_dir)
            .unwrap_or(DVec2::ZERO);
        if dir == DVec2::ZERO {
            return Err(sketch_error(
                format!("{what} continues the direction of the previous segment, but there is none"),
                span,
                "no segment before this one",
            )
            .with_help("draw a line or an arc first, or give the direction explicitly (`arc to p through q`, a spline without `tangent`)"));
        }
        Ok(dir)
    }

    fn arc_through(&self, to: DVec2, through: DVec2, span: Span) -> Result<Piece, Diagnostic> {
        let names = ["the current point", "`through`", "the end point"];
        let pts = [self.current, through, to];
        for (i, j) in [(0, 1), (1, 2), (0, 2)] {
            if pts[i].distance(pts[j]) <= self.tol {
                return Err(sketch_error(
                    format!("{} and {} of this arc are the same point {}", names[i], names[j], pt(pts[i])),
                    span,
                    "degenerate arc",
                )
                .with_help("an arc needs three distinct points: where it starts, one it passes through, and where it ends"));
            }
        }
        let arc = match arc_through_points(self.current, through, to) {
            Ok(arc) => arc,
            Err(GeomError::Singular { .. }) => {
                return Err(sketch_error(
                    format!("the arc's three points {}, {} and {} lie on one line", pt(self.current), pt(through), pt(to)),
                    span,
                    "collinear points",
                )
                .with_help("move `through` off the line from the current point to the end point, or draw a `line to`"));
            }
            Err(e) => return Err(kernel(e, span)),
        };
        let arc = snap_ends(&arc, self.current, to).map_err(|e| kernel(e, span))?;
        Ok(Piece {
            kind: "arc",
            span,
            shape: Shape::Curve(arc),
        })
    }

    fn tangent_arc(&self, to: DVec2, span: Span) -> Result<Piece, Diagnostic> {
        let d = self.previous_direction(span, "a tangent arc")?;
        let p = self.current;
        let c = to - p;
        let len = c.length();
        if len <= self.tol {
            return Err(sketch_error(
                format!("this tangent arc ends where it starts, at {}", pt(to)),
                span,
                "zero-length arc",
            )
            .with_help("remove it or change its end point"));
        }
        let cross = d.perp_dot(c);
        let dot = d.dot(c);
        if cross.abs() <= 1e-12 * len {
            if dot > 0.0 {
                return Ok(Piece {
                    kind: "line",
                    span,
                    shape: Shape::Line(p, to),
                });
            }
            return Err(sketch_error(
                format!("{} lies behind the current point on the tangent line: no arc leaving tangentially reaches it", pt(to)),
                span,
                "unreachable end point",
            )
            .with_help("a tangent arc turns left or right from the previous segment's direction; pick an end point off that line"));
        }
        // Unit normal towards the end point; the centre lies on it.
        let n = d.perp() * cross.signum();
        let radius = len * len / (2.0 * c.dot(n));
        let center = p + n * radius;
        let sweep = 2.0 * cross.abs().atan2(dot);
        let arc = circular_arc(center, -n, d, radius, 0.0, sweep)
            .and_then(|a| snap_ends(&a, p, to))
            .map_err(|e| kernel(e, span))?;
        Ok(Piece {
            kind: "arc",
            span,
            shape: Shape::Curve(arc),
        })
    }

    fn spline(&self, through: &[DVec2], tangent: bool, span: Span) -> Result<Piece, Diagnostic> {
        if through.is_empty() {
            return Err(sketch_error(
                "a spline needs at least one point to pass through",
                span,
                "no points",
            )
            .with_help("write `spline through [(x1, y1), (x2, y2), ...]`"));
        }
        let mut points = Vec::with_capacity(through.len() + 1);
        points.push(self.current);
        points.extend_from_slice(through);
        for (i, w) in points.windows(2).enumerate() {
            if w[0].distance(w[1]) <= self.tol {
                let message = if i == 0 {
                    format!(
                        "point 1 of the spline, {}, is the current point where the spline starts",
                        pt(w[1])
                    )
                } else {
                    format!(
                        "the spline passes through {} twice in a row (items {} and {} of the list, counting from 1)",
                        pt(w[1]),
                        i,
                        i + 1
                    )
                };
                return Err(sketch_error(message, span, "repeated point")
                    .with_help("a spline cannot pass through the same point twice in a row; remove one of them"));
            }
        }
        let start_tangent = if tangent {
            let d = self.previous_direction(span, "a spline with `tangent`")?;
            let chord: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
            Some(d * chord)
        } else {
            None
        };
        let controls = points.len() + usize::from(tangent);
        let degree = (controls - 1).min(3);
        let opts = Interpolation {
            degree,
            start_tangent,
            ..Interpolation::default()
        };
        let curve = interpolate(&points, &opts)
            .and_then(|c| snap_ends(&c, self.current, points[points.len() - 1]))
            .map_err(|e| kernel(e, span))?;
        Ok(Piece {
            kind: "spline",
            span,
            shape: Shape::Curve(curve),
        })
    }

    fn fillet(&mut self, r: f64, span: Span) -> Result<(), Diagnostic> {
        check_radius(r, span)?;
        let twice = || {
            sketch_error(
                "two fillets at the same corner",
                span,
                "a second fillet here",
            )
            .with_help("keep one fillet per corner")
        };
        if self.pieces.is_empty() {
            if self.start_fillet.is_some() {
                return Err(twice());
            }
            if r > 0.0 {
                self.start_fillet = Some((r, span));
            }
        } else {
            if self.pending.is_some() {
                return Err(twice());
            }
            if r > 0.0 {
                self.pending = Some((r, span));
            }
        }
        Ok(())
    }

    fn close(&mut self, span: Span) -> Result<(), Diagnostic> {
        if self.pieces.is_empty() {
            return Err(sketch_error(
                "nothing to close: the sketch has no segments",
                span,
                "right after `from`",
            )
            .with_help("draw at least two segments before `close`"));
        }
        if self.current.distance(self.start) > self.tol {
            self.push(Piece {
                kind: "line",
                span,
                shape: Shape::Line(self.current, self.start),
            })?;
        } else if let Some(f) = self.pending.take() {
            // Already back at the start: the waiting fillet rounds the start corner.
            if self.start_fillet.is_some() {
                return Err(sketch_error(
                    "two fillets at the start corner",
                    f.1,
                    "a second fillet here",
                )
                .with_help("keep one fillet per corner"));
            }
            self.start_fillet = Some(f);
        }
        self.closed = true;
        if let Some((r, fspan)) = self.start_fillet {
            self.round_start(r, fspan)?;
        }
        Ok(())
    }

    /// `fillet r` after `close`: rounds the start corner, like a fillet right after
    /// `from`.
    fn fillet_after_close(&mut self, r: f64, span: Span) -> Result<(), Diagnostic> {
        check_radius(r, span)?;
        if self.start_fillet.is_some() {
            return Err(sketch_error(
                "two fillets at the start corner",
                span,
                "a second fillet here",
            )
            .with_help("keep one fillet per corner"));
        }
        if r > 0.0 {
            self.start_fillet = Some((r, span));
            self.round_start(r, span)?;
        }
        Ok(())
    }

    /// Rounds the corner where the closed sketch's last segment meets its first; the
    /// fillet becomes the last segment.
    fn round_start(&mut self, r: f64, fspan: Span) -> Result<(), Diagnostic> {
        let last = self.pieces.len() - 1;
        if let Some(round) = round_corner(&self.pieces[last], &self.pieces[0], r, fspan, self.tol)?
        {
            if last == 0 {
                // A single piece closing on itself is never a line, so round_corner
                // refuses it before this; kept as a diagnostic rather than a panic.
                return Err(sketch_error(
                    "a fillet rounds the corner between two lines",
                    fspan,
                    "this fillet",
                ));
            }
            set_end(&mut self.pieces[last], round.prev_end);
            set_start(&mut self.pieces[0], round.next_start);
            self.pieces.push(round.arc);
        }
        Ok(())
    }
}

/// A fillet radius must be finite and >= 0 (0: no fillet).
fn check_radius(r: f64, span: Span) -> Result<(), Diagnostic> {
    if !(r.is_finite() && r >= 0.0) {
        return Err(sketch_error(
            format!("a fillet radius must be positive, got {}", mm(r)),
            span,
            "negative radius",
        )
        .with_help("give the radius as a positive length such as `fillet 5 mm`"));
    }
    Ok(())
}

fn set_end(piece: &mut Piece, p: DVec2) {
    if let Shape::Line(_, b) = &mut piece.shape {
        *b = p;
    }
}

fn set_start(piece: &mut Piece, p: DVec2) {
    if let Shape::Line(a, _) = &mut piece.shape {
        *a = p;
    }
}

/// The fillet of radius `r` at the corner where `prev` ends and `next` starts, or
/// `None` at a straight corner.
fn round_corner(
    prev: &Piece,
    next: &Piece,
    r: f64,
    span: Span,
    tol: f64,
) -> Result<Option<Rounding>, Diagnostic> {
    let d_in = prev.end_dir();
    let d_out = next.start_dir();
    let cross = d_in.perp_dot(d_out);
    let dot = d_in.dot(d_out);
    if cross.abs() <= 1e-9 && dot > 0.0 {
        return Ok(None);
    }
    let (Shape::Line(a, v), Shape::Line(_, b)) = (&prev.shape, &next.shape) else {
        let other = if matches!(prev.shape, Shape::Line(..)) {
            next
        } else {
            prev
        };
        return Err(sketch_error(
            "a fillet rounds the corner between two lines",
            span,
            "this fillet",
        )
        .with_label(
            other.span,
            format!(
                "this segment is a{} {}",
                if other.kind == "arc" { "n" } else { "" },
                other.kind
            ),
        )
        .with_help("draw the corner with two lines, or continue with a `tangent arc`"));
    };
    if cross.abs() <= 1e-9 {
        return Err(sketch_error(
            "the lines double back at this corner, so no fillet can round it",
            span,
            "this fillet",
        )
        .with_label(prev.span, "this line")
        .with_label(next.span, "runs back along this one")
        .with_help("remove the fillet or change the lines"));
    }
    let (len1, len2) = (a.distance(*v), v.distance(*b));
    // theta: the angle between the two lines at the corner (pi for a straight one).
    let theta = (-dot).clamp(-1.0, 1.0).acos();
    let half = 0.5 * theta;
    let t = r / half.tan();
    if t > len1 + tol || t > len2 + tol {
        let fits = len1.min(len2) * half.tan();
        return Err(sketch_error(
            format!("fillet {} does not fit: the lines are {} and {} long", mm(r), mm(len1), mm(len2)),
            span,
            "this fillet",
        )
        .with_label(prev.span, format!("{} long", mm(len1)))
        .with_label(next.span, format!("{} long", mm(len2)))
        .with_help(format!(
            "at this {} deg corner a fillet of {} takes {} of each line (r / tan(angle / 2)); the largest that fits is {}",
            round(theta.to_degrees()),
            mm(r),
            mm(t),
            mm(fits)
        )));
    }
    let t1 = if t >= len1 { *a } else { *v - d_in * t };
    let t2 = if t >= len2 { *b } else { *v + d_out * t };
    let arc = Curve2::new_rational(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        vec![t1, *v, t2],
        vec![1.0, half.sin(), 1.0],
    )
    .map_err(|e| kernel(e, span))?;
    Ok(Some(Rounding {
        prev_end: t1,
        next_start: t2,
        arc: Piece {
            kind: "fillet",
            span,
            shape: Shape::Curve(arc),
        },
    }))
}

/// The curve with its first and last control points moved exactly onto `a` and `b`
/// (they are there to rounding already; exact ends make the join exact).
fn snap_ends(c: &Curve2, a: DVec2, b: DVec2) -> crate::geom::Result<Curve2> {
    let mut points = c.control_points().to_vec();
    let n = points.len();
    points[0] = a;
    points[n - 1] = b;
    let knots = c.knots().as_slice().to_vec();
    match c.weights() {
        Some(w) => Curve2::new_rational(c.degree(), knots, points, w.to_vec()),
        None => Curve2::new(c.degree(), knots, points),
    }
}
