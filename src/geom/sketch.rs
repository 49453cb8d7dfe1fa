//! Profiles drawn as a sequence of commands (a start point, lines, arcs, splines,
//! fillets at corners, tangency to the previous segment) and turned into one exact 2-D
//! NURBS curve: lines and arcs exact, arcs rational, segments joined with C0 knots.
//!
//! This is the geometry behind the language's sketches: [`draw`] takes the commands as
//! plain points and lengths (millimetres) and returns the profile with the command that
//! drew each segment, or a [`SketchError`] naming the command at fault, so the language
//! can point at its source.

use glam::DVec2;
use thiserror::Error;

use super::arc::{arc_through_points, circular_arc};
use super::curve::Curve2;
use super::error::GeomError;
use super::interpolate::{interpolate, Interpolation};
use super::join::join_curves;

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

/// A drawn profile.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// The whole profile as one 2-D NURBS curve (C0 at corners).
    pub curve: Curve2,
    /// The pieces in drawing order; piece `k` has the parameter range `[k, k + 1]`.
    pub segments: Vec<Segment>,
    /// Whether the profile ends where it started (only `close` makes it so).
    pub closed: bool,
}

/// One drawn piece of a profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// `line`, `arc`, `fillet`, `spline` (the designer's words for it).
    pub kind: &'static str,
    /// The index of the command that drew it.
    pub command: usize,
    /// Its parameter range in the joined curve.
    pub range: (f64, f64),
}

/// Why a profile cannot be drawn. Each variant names the command at fault (its index in
/// the list given to [`draw`]) and the numbers a designer needs to correct it.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SketchError {
    /// No commands at all.
    #[error("the sketch is empty")]
    Empty,
    /// The first command is not `from`.
    #[error("command {command} comes before any `from`")]
    NoStart { command: usize },
    /// A point of the command is NaN or infinite.
    #[error("a point of command {command} is not finite")]
    NotFinite { command: usize },
    /// A point of the command lies beyond [`super::MAX_COORDINATE`] in some axis:
    /// `value` is that coordinate.
    #[error("a point of command {command} lies beyond the modelling range")]
    OutOfRange { command: usize, value: f64 },
    /// A second `from`.
    #[error("command {command} is a second `from`")]
    SecondStart { command: usize },
    /// A command other than a start-corner fillet after `close`.
    #[error("command {command} follows `close`")]
    AfterClose { command: usize },
    /// A line to the current point.
    #[error("command {command} draws a zero-length line at ({}, {})", at.x, at.y)]
    ZeroLengthLine { command: usize, at: DVec2 },
    /// Two of an arc's points coincide: `first` and `second` index the arc's points
    /// (0 the current point, 1 `through`, 2 the end point); `at` is where.
    #[error("points {first} and {second} of the arc of command {command} coincide")]
    ArcPointsCoincide {
        command: usize,
        first: usize,
        second: usize,
        at: DVec2,
    },
    /// An arc's three points (current, through, end) lie on one line.
    #[error("the arc's three points of command {command} lie on one line")]
    ArcCollinear { command: usize, points: [DVec2; 3] },
    /// A tangent arc, or a spline with `tangent`, with no segment before it.
    #[error("command {command} continues a direction, but no segment comes before it")]
    NoPreviousDirection { command: usize },
    /// A tangent arc to the current point.
    #[error("the tangent arc of command {command} ends where it starts")]
    ZeroLengthArc { command: usize, at: DVec2 },
    /// A tangent arc's end point behind the current point on the tangent line.
    #[error(
        "the end point of the tangent arc of command {command} lies behind it on the tangent line"
    )]
    ArcEndBehind { command: usize, at: DVec2 },
    /// A spline with no points.
    #[error("the spline of command {command} has no points")]
    SplineEmpty { command: usize },
    /// A spline through the same point twice in a row: `item` counts the points of the
    /// list from 1, 0 meaning the current point the spline starts at (so the repeat is
    /// items `item` and `item + 1`); `at` is the point.
    #[error("the spline of command {command} passes through a point twice in a row")]
    SplineRepeatsPoint {
        command: usize,
        item: usize,
        at: DVec2,
    },
    /// A fillet radius that is negative or not finite.
    #[error("the fillet radius of command {command} is {radius}")]
    BadRadius { command: usize, radius: f64 },
    /// Two fillets at one corner (not the start corner).
    #[error("command {command} is a second fillet at one corner")]
    TwoFillets { command: usize },
    /// Two fillets at the start corner of a closed sketch.
    #[error("command {command} is a second fillet at the start corner")]
    TwoStartFillets { command: usize },
    /// A fillet with nothing drawn after it.
    #[error("the fillet of command {command} has no second segment")]
    FilletWithoutNext { command: usize },
    /// A start-corner fillet on a sketch that is not closed.
    #[error("the start-corner fillet of command {command} is on an open sketch")]
    StartFilletOnOpen { command: usize },
    /// Nothing drawn after `from`.
    #[error("nothing is drawn after `from`")]
    NoSegments,
    /// `close` right after `from`.
    #[error("command {command} closes a sketch with no segments")]
    NothingToClose { command: usize },
    /// A fillet at a corner where a segment is not a line: `other` is the command that
    /// drew it, `other_kind` what it is.
    #[error("the fillet of command {fillet} meets a {other_kind} (command {other})")]
    FilletNeedsLines {
        fillet: usize,
        other: usize,
        other_kind: &'static str,
    },
    /// A fillet on a single piece closing on itself (kept as an error, never a panic;
    /// the piece is never a line, so [`SketchError::FilletNeedsLines`] comes first).
    #[error("the fillet of command {fillet} has only one segment")]
    FilletOnOnePiece { fillet: usize },
    /// A fillet (of positive radius) at a straight or tangent corner: the segments
    /// before and after it (`prev` and `next` the commands that drew them) continue in
    /// one direction, so there is no corner to round.
    #[error("the fillet of command {fillet} has no corner to round")]
    FilletNoCorner {
        fillet: usize,
        prev: usize,
        next: usize,
    },
    /// A fillet where the lines double back on each other (`prev` and `next` the
    /// commands that drew them).
    #[error(
        "the lines of commands {prev} and {next} double back at the fillet of command {fillet}"
    )]
    FilletDoublesBack {
        fillet: usize,
        prev: usize,
        next: usize,
    },
    /// A fillet longer than its lines: each line's `lengths`, the `angle` between them
    /// (radians, pi for a straight corner), the length `takes` the fillet takes of each
    /// (`radius / tan(angle / 2)`) and the `largest` radius that fits.
    #[error("the fillet of radius {radius} of command {fillet} does not fit")]
    FilletDoesNotFit {
        fillet: usize,
        prev: usize,
        next: usize,
        radius: f64,
        lengths: (f64, f64),
        angle: f64,
        takes: f64,
        largest: f64,
    },
    /// A kernel construction failed on the command's points (`None`: joining the whole
    /// profile).
    #[error("{error}")]
    Kernel {
        command: Option<usize>,
        error: GeomError,
    },
}

/// Draws the profile the commands describe.
///
/// Semantics, command by command:
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
///   span. Consecutive equal points are an error naming them.
/// - `fillet r` rounds the corner at the current point, between the previous segment
///   and the next one, so it takes effect when the next segment is drawn (or at
///   `close`, for the closing corner). Right after `from`, or right after `close`, it
///   rounds the start corner of a closed sketch (the joined curve then starts at the
///   end of that fillet, on the first segment, and the fillet is the last segment). The
///   fillet is the exact arc tangent to both segments; they must be lines, long enough
///   for the tangent length `r / tan(theta / 2)` (theta the angle between the lines),
///   counting what other fillets already took of them. A line used up entirely by
///   fillets disappears. At a straight (tangent) corner there is nothing to round, and
///   a fillet there is an error rather than silently dropped; `fillet 0` does nothing
///   (a sharp corner, what a profile with a radius parameter of 0 asks for).
/// - `close` draws a line back to the start point unless the sketch is already there,
///   and marks the sketch closed; only a `fillet` (of the start corner) may follow it.
///   Only `close` makes a sketch closed.
///
/// Points closer than 1e-9 of the sketch's size (its largest coordinate, at least 1 mm)
/// are one point. The result joins the pieces with [`join_curves`]: segment `k` has the
/// parameter range `[k, k + 1]`.
pub fn draw(commands: &[Command]) -> Result<Profile, SketchError> {
    let Some(first) = commands.first() else {
        return Err(SketchError::Empty);
    };
    let Command::From(start) = *first else {
        return Err(SketchError::NoStart { command: 0 });
    };
    let scale = commands
        .iter()
        .flat_map(command_points)
        .fold(1.0f64, |m, p| m.max(p.abs().max_element()));
    if let Some(command) = commands
        .iter()
        .position(|c| command_points(c).iter().any(|p| !p.is_finite()))
    {
        return Err(SketchError::NotFinite { command });
    }
    let beyond = |p: &DVec2| p.abs().max_element() > super::MAX_COORDINATE;
    if let Some((command, p)) = commands
        .iter()
        .enumerate()
        .find_map(|(k, c)| command_points(c).into_iter().find(beyond).map(|p| (k, p)))
    {
        let value = if p.x.abs() >= p.y.abs() { p.x } else { p.y };
        return Err(SketchError::OutOfRange { command, value });
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
    for (k, cmd) in commands.iter().enumerate().skip(1) {
        d.command(cmd, k)?;
    }
    d.finish()
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

/// A kernel failure on the points of `command`.
fn kernel(command: usize) -> impl Fn(GeomError) -> SketchError {
    move |error| SketchError::Kernel {
        command: Some(command),
        error,
    }
}

/// The geometry of one piece before the join.
#[derive(Debug, Clone)]
enum Shape {
    /// A straight segment (kept as end points so fillets can trim it).
    Line(DVec2, DVec2),
    /// An arc or a spline.
    Curve(Curve2),
}

/// A drawn piece with what drew it.
#[derive(Debug, Clone)]
struct Piece {
    kind: &'static str,
    command: usize,
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

    /// Moves the end of a line (a fillet trims it); other shapes keep theirs.
    fn set_end(&mut self, p: DVec2) {
        if let Shape::Line(_, b) = &mut self.shape {
            *b = p;
        }
    }

    /// Moves the start of a line (a fillet trims it); other shapes keep theirs.
    fn set_start(&mut self, p: DVec2) {
        if let Shape::Line(a, _) = &mut self.shape {
            *a = p;
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

/// The drawing state: the pieces so far and the fillets waiting for their corner.
struct Drawer {
    start: DVec2,
    current: DVec2,
    pieces: Vec<Piece>,
    /// A fillet (radius, command) waiting for the segment after the current point.
    pending: Option<(f64, usize)>,
    /// A fillet given right after `from`: the start corner of a closed sketch.
    start_fillet: Option<(f64, usize)>,
    closed: bool,
    tol: f64,
}

impl Drawer {
    fn command(&mut self, cmd: &Command, k: usize) -> Result<(), SketchError> {
        if self.closed {
            if let Command::Fillet(r) = cmd {
                return self.fillet_after_close(*r, k);
            }
            return Err(SketchError::AfterClose { command: k });
        }
        match cmd {
            Command::From(_) => Err(SketchError::SecondStart { command: k }),
            Command::LineTo(p) => {
                if p.distance(self.current) <= self.tol {
                    return Err(SketchError::ZeroLengthLine { command: k, at: *p });
                }
                self.push(Piece {
                    kind: "line",
                    command: k,
                    shape: Shape::Line(self.current, *p),
                })
            }
            Command::ArcThrough { to, through } => {
                let piece = self.arc_through(*to, *through, k)?;
                self.push(piece)
            }
            Command::TangentArcTo(p) => {
                let piece = self.tangent_arc(*p, k)?;
                self.push(piece)
            }
            Command::Spline { through, tangent } => {
                let piece = self.spline(through, *tangent, k)?;
                self.push(piece)
            }
            Command::Fillet(r) => self.fillet(*r, k),
            Command::Close => self.close(k),
        }
    }

    /// The checks after the last command, then the pieces joined into one curve.
    fn finish(self) -> Result<Profile, SketchError> {
        if let Some((_, command)) = self.pending {
            return Err(SketchError::FilletWithoutNext { command });
        }
        if let Some((_, command)) = self.start_fillet {
            if !self.closed {
                return Err(SketchError::StartFilletOnOpen { command });
            }
        }
        if self.pieces.is_empty() {
            return Err(SketchError::NoSegments);
        }
        let tol = self.tol;
        let pieces: Vec<Piece> = self
            .pieces
            .into_iter()
            .filter(|p| !matches!(p.shape, Shape::Line(a, b) if a.distance(b) <= tol))
            .collect();
        let mut curves = Vec::with_capacity(pieces.len());
        for p in &pieces {
            curves.push(p.curve().map_err(kernel(p.command))?);
        }
        let curve = join_curves(&curves).map_err(|error| SketchError::Kernel {
            command: None,
            error,
        })?;
        let segments = pieces
            .iter()
            .enumerate()
            .map(|(k, p)| Segment {
                kind: p.kind,
                command: p.command,
                range: (k as f64, k as f64 + 1.0),
            })
            .collect();
        Ok(Profile {
            curve,
            segments,
            closed: self.closed,
        })
    }

    /// Appends a piece, first rounding the corner before it if a fillet waits there.
    fn push(&mut self, mut piece: Piece) -> Result<(), SketchError> {
        if let Some((r, fillet)) = self.pending.take() {
            let prev = self
                .pieces
                .last()
                .expect("a pending fillet follows a segment");
            if let Some(round) = round_corner(prev, &piece, r, fillet, self.tol)? {
                let last = self.pieces.len() - 1;
                self.pieces[last].set_end(round.prev_end);
                piece.set_start(round.next_start);
                self.pieces.push(round.arc);
            }
        }
        self.current = piece.end();
        self.pieces.push(piece);
        Ok(())
    }

    /// The end direction of the previous segment, for tangent continuations.
    fn previous_direction(&self, k: usize) -> Result<DVec2, SketchError> {
        let dir = self
            .pieces
            .last()
            .map(Piece::end_dir)
            .unwrap_or(DVec2::ZERO);
        if dir == DVec2::ZERO {
            return Err(SketchError::NoPreviousDirection { command: k });
        }
        Ok(dir)
    }

    fn arc_through(&self, to: DVec2, through: DVec2, k: usize) -> Result<Piece, SketchError> {
        let pts = [self.current, through, to];
        for (i, j) in [(0, 1), (1, 2), (0, 2)] {
            if pts[i].distance(pts[j]) <= self.tol {
                return Err(SketchError::ArcPointsCoincide {
                    command: k,
                    first: i,
                    second: j,
                    at: pts[i],
                });
            }
        }
        let arc = match arc_through_points(self.current, through, to) {
            Ok(arc) => arc,
            Err(GeomError::Singular { .. }) => {
                return Err(SketchError::ArcCollinear {
                    command: k,
                    points: pts,
                });
            }
            Err(e) => return Err(kernel(k)(e)),
        };
        let arc = snap_ends(&arc, self.current, to).map_err(kernel(k))?;
        Ok(Piece {
            kind: "arc",
            command: k,
            shape: Shape::Curve(arc),
        })
    }

    fn tangent_arc(&self, to: DVec2, k: usize) -> Result<Piece, SketchError> {
        let d = self.previous_direction(k)?;
        let p = self.current;
        let c = to - p;
        let len = c.length();
        if len <= self.tol {
            return Err(SketchError::ZeroLengthArc { command: k, at: to });
        }
        let cross = d.perp_dot(c);
        let dot = d.dot(c);
        if cross.abs() <= 1e-12 * len {
            if dot > 0.0 {
                return Ok(Piece {
                    kind: "line",
                    command: k,
                    shape: Shape::Line(p, to),
                });
            }
            return Err(SketchError::ArcEndBehind { command: k, at: to });
        }
        // Unit normal towards the end point; the centre lies on it.
        let n = d.perp() * cross.signum();
        let radius = len * len / (2.0 * c.dot(n));
        let center = p + n * radius;
        let sweep = 2.0 * cross.abs().atan2(dot);
        let arc = circular_arc(center, -n, d, radius, 0.0, sweep)
            .and_then(|a| snap_ends(&a, p, to))
            .map_err(kernel(k))?;
        Ok(Piece {
            kind: "arc",
            command: k,
            shape: Shape::Curve(arc),
        })
    }

    fn spline(&self, through: &[DVec2], tangent: bool, k: usize) -> Result<Piece, SketchError> {
        if through.is_empty() {
            return Err(SketchError::SplineEmpty { command: k });
        }
        let mut points = Vec::with_capacity(through.len() + 1);
        points.push(self.current);
        points.extend_from_slice(through);
        if let Some(item) = points
            .windows(2)
            .position(|w| w[0].distance(w[1]) <= self.tol)
        {
            return Err(SketchError::SplineRepeatsPoint {
                command: k,
                item,
                at: points[item + 1],
            });
        }
        let start_tangent = if tangent {
            let d = self.previous_direction(k)?;
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
            .map_err(kernel(k))?;
        Ok(Piece {
            kind: "spline",
            command: k,
            shape: Shape::Curve(curve),
        })
    }

    fn fillet(&mut self, r: f64, k: usize) -> Result<(), SketchError> {
        check_radius(r, k)?;
        let slot = if self.pieces.is_empty() {
            &mut self.start_fillet
        } else {
            &mut self.pending
        };
        if slot.is_some() {
            return Err(SketchError::TwoFillets { command: k });
        }
        if r > 0.0 {
            *slot = Some((r, k));
        }
        Ok(())
    }

    fn close(&mut self, k: usize) -> Result<(), SketchError> {
        if self.pieces.is_empty() {
            return Err(SketchError::NothingToClose { command: k });
        }
        if self.current.distance(self.start) > self.tol {
            self.push(Piece {
                kind: "line",
                command: k,
                shape: Shape::Line(self.current, self.start),
            })?;
        } else if let Some(f) = self.pending.take() {
            // Already back at the start: the waiting fillet rounds the start corner.
            if self.start_fillet.is_some() {
                return Err(SketchError::TwoStartFillets { command: f.1 });
            }
            self.start_fillet = Some(f);
        }
        self.closed = true;
        if let Some((r, fillet)) = self.start_fillet {
            self.round_start(r, fillet)?;
        }
        Ok(())
    }

    /// `fillet r` after `close`: rounds the start corner, like a fillet right after
    /// `from`.
    fn fillet_after_close(&mut self, r: f64, k: usize) -> Result<(), SketchError> {
        check_radius(r, k)?;
        if self.start_fillet.is_some() {
            return Err(SketchError::TwoStartFillets { command: k });
        }
        if r > 0.0 {
            self.start_fillet = Some((r, k));
            self.round_start(r, k)?;
        }
        Ok(())
    }

    /// Rounds the corner where the closed sketch's last segment meets its first; the
    /// fillet becomes the last segment.
    fn round_start(&mut self, r: f64, fillet: usize) -> Result<(), SketchError> {
        let last = self.pieces.len() - 1;
        if let Some(round) = round_corner(&self.pieces[last], &self.pieces[0], r, fillet, self.tol)?
        {
            if last == 0 {
                return Err(SketchError::FilletOnOnePiece { fillet });
            }
            self.pieces[last].set_end(round.prev_end);
            self.pieces[0].set_start(round.next_start);
            self.pieces.push(round.arc);
        }
        Ok(())
    }
}

/// A fillet radius must be finite and >= 0 (0: no fillet).
fn check_radius(r: f64, k: usize) -> Result<(), SketchError> {
    if !(r.is_finite() && r >= 0.0) {
        return Err(SketchError::BadRadius {
            command: k,
            radius: r,
        });
    }
    Ok(())
}

/// The fillet of radius `r` (drawn by command `fillet`) at the corner where `prev` ends
/// and `next` starts; at a straight corner an error, as there is nothing to round
/// (`Option` stays for callers that round only where a corner is).
fn round_corner(
    prev: &Piece,
    next: &Piece,
    r: f64,
    fillet: usize,
    tol: f64,
) -> Result<Option<Rounding>, SketchError> {
    let d_in = prev.end_dir();
    let d_out = next.start_dir();
    let cross = d_in.perp_dot(d_out);
    let dot = d_in.dot(d_out);
    if cross.abs() <= 1e-9 && dot > 0.0 {
        return Err(SketchError::FilletNoCorner {
            fillet,
            prev: prev.command,
            next: next.command,
        });
    }
    let (Shape::Line(a, v), Shape::Line(_, b)) = (&prev.shape, &next.shape) else {
        let other = if matches!(prev.shape, Shape::Line(..)) {
            next
        } else {
            prev
        };
        return Err(SketchError::FilletNeedsLines {
            fillet,
            other: other.command,
            other_kind: other.kind,
        });
    };
    if cross.abs() <= 1e-9 {
        return Err(SketchError::FilletDoublesBack {
            fillet,
            prev: prev.command,
            next: next.command,
        });
    }
    let (len1, len2) = (a.distance(*v), v.distance(*b));
    // theta: the angle between the two lines at the corner (pi for a straight one).
    let theta = (-dot).clamp(-1.0, 1.0).acos();
    let half = 0.5 * theta;
    let t = r / half.tan();
    if t > len1 + tol || t > len2 + tol {
        return Err(SketchError::FilletDoesNotFit {
            fillet,
            prev: prev.command,
            next: next.command,
            radius: r,
            lengths: (len1, len2),
            angle: theta,
            takes: t,
            largest: len1.min(len2) * half.tan(),
        });
    }
    let t1 = if t >= len1 { *a } else { *v - d_in * t };
    let t2 = if t >= len2 { *b } else { *v + d_out * t };
    let arc = Curve2::new_rational(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        vec![t1, *v, t2],
        vec![1.0, half.sin(), 1.0],
    )
    .map_err(kernel(fillet))?;
    Ok(Some(Rounding {
        prev_end: t1,
        next_start: t2,
        arc: Piece {
            kind: "fillet",
            command: fillet,
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
