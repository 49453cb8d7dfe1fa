//! A step-draw profile as a die designer draws it: straight runs joined by round
//! corners, in the section plane's (x, z) with x = 0 at the product edge and x growing
//! towards the punch opening.
//!
//! Sections between key sections are built from this description, not from control
//! points: each run keeps a direction and a length, each corner a radius, and the
//! values are carried along the outline from key section to key section. So an
//! intermediate section has exactly the radii of its neighbours (or between them), its
//! walls the drawn draft, and a feature one key section has and the next lacks (the
//! step of `std/addendum.step` next to a plain wall) fades in as a corner whose turn
//! grows from nothing, instead of two half-corners smeared across the wall.
//!
//! [`Chain::from_curve`] reads a drawn profile (lines and circular arcs, as `sketch`
//! draws them; any other piece is followed by short arcs), [`align`] gives all key
//! sections one list of corners, and [`Chain::reach`] makes a chain end at its opening
//! point by the smallest change of its run lengths.

// Loops over parallel arrays (runs, corners, knots) by index read clearer here than
// zipped iterators.
#![allow(clippy::needless_range_loop)]

use std::f64::consts::PI;

use glam::DVec2;

use crate::geom::Curve2;

/// The shortest a run that the key sections give some length becomes when a section
/// is made to reach its opening point (mm): a run of no length would leave its stretch
/// of the knot vector standing still (a line of the surface with no tangent plane).
pub const MIN_RUN: f64 = 0.5;

/// Corners turning less than this (30 deg) are rounded wider: see [`Chain::arc_length`].
pub const GENTLE_TURN: f64 = std::f64::consts::PI / 6.0;

/// A straight run: its direction (radians from +x towards +z) and length (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Run {
    /// Direction angle.
    pub angle: f64,
    /// Length, 0 or more.
    pub length: f64,
}

/// A profile: runs `0..=K` joined by corners `0..K` (corner `k` turns from run `k` to
/// run `k + 1` with radius `radii[k]`; radius 0 is a sharp corner).
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// The product end, (0, z).
    pub start: DVec2,
    /// The straight runs.
    pub runs: Vec<Run>,
    /// The corner radii.
    pub radii: Vec<f64>,
    /// How square the drawing's plane cuts the walls at the product end and at the
    /// opening end (1 for square; see `super::obliquity`).
    pub obliquity: (f64, f64),
}

/// Where the pieces of a chain lie: each run's usable straight part and each corner's
/// arc, in (x, z).
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// Start and end of each run.
    pub runs: Vec<(DVec2, DVec2)>,
    /// Each corner: arc start, arc end, centre (the arc start when the radius is 0).
    pub arcs: Vec<(DVec2, DVec2, DVec2)>,
}

/// The unit vector at angle `a`.
pub fn dir(a: f64) -> DVec2 {
    DVec2::new(a.cos(), a.sin())
}

/// The signed turn from direction `a` to direction `b`, in (-pi, pi].
fn turn_between(a: DVec2, b: DVec2) -> f64 {
    a.perp_dot(b).atan2(a.dot(b))
}

impl Chain {
    /// The number of corners.
    pub fn corners(&self) -> usize {
        self.radii.len()
    }

    /// The signed turn of corner `k`.
    pub fn turn(&self, k: usize) -> f64 {
        self.runs[k + 1].angle - self.runs[k].angle
    }

    /// The end point.
    pub fn end(&self) -> DVec2 {
        self.layout().runs.last().map_or(self.start, |r| r.1)
    }

    /// The chain walked from its start.
    pub fn layout(&self) -> Layout {
        let mut p = self.start;
        let mut runs = Vec::with_capacity(self.runs.len());
        let mut arcs = Vec::with_capacity(self.radii.len());
        for (k, run) in self.runs.iter().enumerate() {
            let q = p + dir(run.angle) * run.length;
            runs.push((p, q));
            p = q;
            if k < self.radii.len() {
                let (a0, a1) = (run.angle, self.runs[k + 1].angle);
                let theta = a1 - a0;
                let length = self.arc_length(k);
                if theta.abs() <= 1e-12 {
                    let d = dir(a0) * length;
                    arcs.push((p, p + d, p));
                    p += d;
                    continue;
                }
                let r = length / theta.abs();
                let s = theta.signum();
                // The centre lies to the left of the travel for a left (positive) turn.
                let centre = p + DVec2::new(-a0.sin(), a0.cos()) * (r * s);
                let d = DVec2::new(a1.sin() - a0.sin(), a0.cos() - a1.cos()) * (r * s);
                arcs.push((p, p + d, if r > 0.0 { centre } else { p }));
                p += d;
            }
        }
        Layout { runs, arcs }
    }

    /// Reads a drawn profile, already in (x, z): its pieces are classified as lines
    /// and circular arcs (within `1e-7` of the profile's size); a piece that is neither
    /// is followed by 16 arcs through its points.
    pub fn from_curve(curve: &Curve2) -> Chain {
        let scale = curve.control_scale().max(1.0);
        let eps = 1e-7 * scale;
        let breaks: Vec<f64> = curve.knots().distinct().iter().map(|&(k, _)| k).collect();
        let mut elements: Vec<Element> = Vec::new();
        for w in breaks.windows(2) {
            let (ta, tb) = (w[0], w[1]);
            let pts: Vec<DVec2> = (0..=8)
                .map(|i| curve.point_at(ta + (tb - ta) * i as f64 / 8.0))
                .collect();
            match classify(&pts, eps) {
                Some(e) => elements.push(e),
                None => {
                    // A free-form piece: bends between its tangents at 8 points, each
                    // as long as its chord.
                    let n = 8;
                    for i in 0..n {
                        let t0 = ta + (tb - ta) * i as f64 / n as f64;
                        let t1 = ta + (tb - ta) * (i + 1) as f64 / n as f64;
                        let (a, b) = (curve.point_at(t0), curve.point_at(t1));
                        let d0 = curve.derivative_at(t0).normalize_or_zero();
                        let d1 = curve.derivative_at(t1).normalize_or_zero();
                        let turn = turn_between(d0, d1);
                        let chord = a.distance(b);
                        elements.push(Element::Arc {
                            centre: DVec2::NAN,
                            radius: chord / turn.abs().max(GENTLE_TURN),
                            turn,
                            start: d0,
                        });
                    }
                }
            }
        }
        build_chain(curve.start_point(), &elements, eps)
    }

    /// The length of corner `k`'s arc: its radius times its turn, but at least its
    /// radius times [`GENTLE_TURN`]. A corner that turns less (one fading in or out
    /// between key sections) is rounded over that length with a wider radius, a smooth
    /// bend instead of a tight radius shrinking to a point (whose cubic would overshoot
    /// below the drawn radius); it moves the profile by at most `r t (GENTLE_TURN - t)
    /// / 8` for a turn `t`. With no turn it is a straight piece of that length.
    pub fn arc_length(&self, k: usize) -> f64 {
        self.radii[k] * self.turn(k).abs().max(GENTLE_TURN)
    }

    /// The same chain ending at `target`, by the smallest change of the run lengths
    /// (each weighted by its length plus 1 mm, so long runs take up more than short
    /// ones; runs in `fixed` keep their length). Where the free runs cannot do it (all
    /// parallel, or none), the whole chain is turned and scaled about its start. Fails
    /// when lengths would turn negative.
    pub fn reach(&self, target: DVec2, fixed: &[bool]) -> Option<Chain> {
        self.reach_by_lengths(target, fixed).or_else(|| {
            // The free runs are parallel or there are none (a straight or free-form
            // profile): turn and scale the whole chain, radii too, so its chord lies on
            // the target's. A similarity, so the shape is kept.
            let (from, to) = (self.end() - self.start, target - self.start);
            if from.length() <= 0.0 || to.length() <= 0.0 {
                return None;
            }
            let turn = turn_between(from, to);
            let scale = to.length() / from.length();
            let mut turned = self.clone();
            for r in turned.runs.iter_mut() {
                r.angle += turn;
                r.length *= scale;
            }
            for r in turned.radii.iter_mut() {
                *r *= scale;
            }
            Some(turned)
        })
    }

    /// [`Chain::reach`] by the run lengths alone.
    fn reach_by_lengths(&self, target: DVec2, fixed: &[bool]) -> Option<Chain> {
        let mut out = self.clone();
        let n = out.runs.len();
        let mut pinned: Vec<bool> = (0..n)
            .map(|k| fixed.get(k).copied().unwrap_or(false))
            .collect();
        for _ in 0..=n {
            let e = target - out.end();
            if e.length() <= 1e-12 * (1.0 + target.length()) {
                return Some(out);
            }
            // delta = W D^T (D W D^T)^-1 e over the free runs.
            let mut m = [[0.0; 2]; 2];
            for k in 0..n {
                if pinned[k] {
                    continue;
                }
                let w = out.runs[k].length + 1.0;
                let d = dir(out.runs[k].angle);
                m[0][0] += w * d.x * d.x;
                m[0][1] += w * d.x * d.y;
                m[1][1] += w * d.y * d.y;
            }
            let det = m[0][0] * m[1][1] - m[0][1] * m[0][1];
            if det.abs() <= 1e-12 * (m[0][0] + m[1][1]).powi(2).max(1e-300) {
                return None;
            }
            let lam = DVec2::new(
                (m[1][1] * e.x - m[0][1] * e.y) / det,
                (m[0][0] * e.y - m[0][1] * e.x) / det,
            );
            let mut clamped = false;
            let mut next = out.clone();
            for k in 0..n {
                if pinned[k] {
                    continue;
                }
                let w = out.runs[k].length + 1.0;
                let l = out.runs[k].length + w * dir(out.runs[k].angle).dot(lam);
                if l < MIN_RUN {
                    next.runs[k].length = MIN_RUN.min(out.runs[k].length.max(0.0));
                    pinned[k] = true;
                    clamped = true;
                } else {
                    next.runs[k].length = l;
                }
            }
            out = next;
            if !clamped {
                return Some(out);
            }
        }
        None
    }
}

/// A piece of a drawn profile.
#[derive(Debug, Clone, Copy)]
enum Element {
    Line {
        a: DVec2,
        b: DVec2,
    },
    /// A circular arc (or a bend of a free-form piece, whose centre is NaN), leaving
    /// its start along `start`.
    Arc {
        centre: DVec2,
        radius: f64,
        turn: f64,
        start: DVec2,
    },
}

impl Element {
    fn start_dir(&self) -> DVec2 {
        match *self {
            Element::Line { a, b } => (b - a).normalize_or_zero(),
            Element::Arc { start, .. } => start,
        }
    }
}

/// A line or an arc through sampled points, or `None` for a free-form piece.
fn classify(pts: &[DVec2], eps: f64) -> Option<Element> {
    let (a, b) = (pts[0], pts[pts.len() - 1]);
    let m = pts[pts.len() / 2];
    let chord = b - a;
    if chord.length() <= eps {
        return None;
    }
    let off_line = |p: DVec2| chord.perp_dot(p - a).abs() / chord.length();
    if pts.iter().all(|&p| off_line(p) <= eps) {
        return Some(Element::Line { a, b });
    }
    let e = arc_or_line(a, m, b, eps);
    if let Element::Arc { centre, radius, .. } = e {
        if pts
            .iter()
            .all(|&p| (p.distance(centre) - radius).abs() <= eps)
        {
            return Some(e);
        }
    }
    None
}

/// The arc through `a`, `m`, `b`, or the line `a b` when they are collinear.
fn arc_or_line(a: DVec2, m: DVec2, b: DVec2, eps: f64) -> Element {
    let (u, v) = (m - a, b - a);
    let den = 2.0 * u.perp_dot(v);
    if den.abs() <= eps * v.length() {
        return Element::Line { a, b };
    }
    let centre = a + DVec2::new(
        v.y * u.length_squared() - u.y * v.length_squared(),
        u.x * v.length_squared() - v.x * u.length_squared(),
    ) / den;
    let radius = centre.distance(a);
    let (ra, rm, rb) = (a - centre, m - centre, b - centre);
    let turn = turn_between(ra, rm) + turn_between(rm, rb);
    Element::Arc {
        centre,
        radius,
        turn,
        start: DVec2::new(-ra.y, ra.x).normalize_or_zero() * turn.signum(),
    }
}

/// The chain of runs and corners through the elements, merging collinear lines and
/// arcs of one circle, with sharp corners where pieces meet at an angle.
fn build_chain(start: DVec2, elements: &[Element], eps: f64) -> Chain {
    let first_dir = elements.first().map_or(DVec2::X, Element::start_dir);
    let mut runs = vec![Run {
        angle: first_dir.y.atan2(first_dir.x),
        length: 0.0,
    }];
    let mut radii: Vec<f64> = Vec::new();
    // The arc being accumulated into the last corner: (centre, radius).
    let mut open_arc: Option<(DVec2, f64)> = None;
    let mut heading = runs[0].angle;
    for e in elements {
        let sd = e.start_dir();
        let tangent_turn = turn_between(dir(heading), sd);
        if tangent_turn.abs() > 1e-6 {
            // A sharp corner where the pieces meet.
            if open_arc.is_some()
                || runs.last().is_some_and(|r| r.length > 0.0)
                || !radii.is_empty()
            {
                heading += tangent_turn;
                radii.push(0.0);
                runs.push(Run {
                    angle: heading,
                    length: 0.0,
                });
                open_arc = None;
            } else {
                heading += tangent_turn;
                runs[0].angle = heading;
            }
        }
        match *e {
            Element::Line { a, b } => {
                let last = runs.last_mut().expect("a chain always has a run");
                last.length += a.distance(b);
                open_arc = None;
            }
            Element::Arc {
                centre,
                radius,
                turn,
                ..
            } => {
                let same = open_arc.is_some_and(|(c, r)| {
                    c.distance(centre) <= 10.0 * eps && (r - radius).abs() <= 10.0 * eps
                }) && runs.last().is_some_and(|r| r.length == 0.0);
                heading += turn;
                if same {
                    // Continue the corner: its outgoing run turns further.
                    runs.last_mut().expect("a chain always has a run").angle = heading;
                } else {
                    radii.push(radius);
                    runs.push(Run {
                        angle: heading,
                        length: 0.0,
                    });
                }
                open_arc = Some((centre, radius));
            }
        }
    }
    Chain {
        start,
        runs,
        radii,
        obliquity: (1.0, 1.0),
    }
}

/// One corner slot of the common structure of all key sections: its reference turn,
/// radius and position (fraction of the profile's length).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Slot {
    turn: f64,
    radius: f64,
    position: f64,
}

/// The corners of `c` as slots.
fn slots_of(c: &Chain) -> Vec<Slot> {
    let mut total = 0.0;
    let mut at = Vec::with_capacity(c.corners());
    for k in 0..=c.corners() {
        total += c.runs[k].length;
        if k < c.corners() {
            let arc = c.arc_length(k);
            at.push(total + 0.5 * arc);
            total += arc;
        }
    }
    let total = total.max(1e-12);
    (0..c.corners())
        .map(|k| Slot {
            turn: c.turn(k),
            radius: c.radii[k],
            position: at[k] / total,
        })
        .collect()
}

/// Which slot of `b` each slot of `a` matches (order kept). The first corners match
/// (the punch radius) and so do the last (the die radius) when they turn the same way;
/// between them, the smallest total of turn differences wins, an unmatched corner
/// costing its whole turn. So a plain wall next to a step keeps its punch and die
/// radii in step with the step's, and the step's own corners grow inside the wall.
fn match_slots(a: &[Slot], b: &[Slot]) -> Vec<(Option<usize>, Option<usize>)> {
    let same = |x: &Slot, y: &Slot| x.turn.signum() == y.turn.signum();
    let (n, m) = (a.len(), b.len());
    if n >= 2 && m >= 2 && same(&a[0], &b[0]) && same(&a[n - 1], &b[m - 1]) {
        let inner = match_inner(&a[1..n - 1], &b[1..m - 1]);
        let mut out = vec![(Some(0), Some(0))];
        out.extend(
            inner
                .into_iter()
                .map(|(i, j)| (i.map(|i| i + 1), j.map(|j| j + 1))),
        );
        out.push((Some(n - 1), Some(m - 1)));
        return out;
    }
    match_inner(a, b)
}

/// [`match_slots`] without the fixed ends.
fn match_inner(a: &[Slot], b: &[Slot]) -> Vec<(Option<usize>, Option<usize>)> {
    let (n, m) = (a.len(), b.len());
    let cost_match = |i: usize, j: usize| {
        let same_side =
            a[i].turn.signum() == b[j].turn.signum() || a[i].turn == 0.0 || b[j].turn == 0.0;
        let base = (a[i].turn - b[j].turn).abs() + 0.25 * (a[i].position - b[j].position).abs();
        if same_side {
            base
        } else {
            base + PI
        }
    };
    let mut d = vec![vec![0.0; m + 1]; n + 1];
    for i in 1..=n {
        d[i][0] = d[i - 1][0] + a[i - 1].turn.abs();
    }
    for j in 1..=m {
        d[0][j] = d[0][j - 1] + b[j - 1].turn.abs();
    }
    for i in 1..=n {
        for j in 1..=m {
            d[i][j] = (d[i - 1][j - 1] + cost_match(i - 1, j - 1))
                .min(d[i - 1][j] + a[i - 1].turn.abs())
                .min(d[i][j - 1] + b[j - 1].turn.abs());
        }
    }
    let (mut i, mut j) = (n, m);
    let mut out = Vec::new();
    while i > 0 || j > 0 {
        if i > 0 && j > 0 && (d[i][j] - (d[i - 1][j - 1] + cost_match(i - 1, j - 1))).abs() <= 1e-12
        {
            out.push((Some(i - 1), Some(j - 1)));
            i -= 1;
            j -= 1;
        } else if i > 0
            && (j == 0 || (d[i][j] - (d[i - 1][j] + a[i - 1].turn.abs())).abs() <= 1e-12)
        {
            out.push((Some(i - 1), None));
            i -= 1;
        } else {
            out.push((None, Some(j - 1)));
            j -= 1;
        }
    }
    out.reverse();
    out
}

/// All key chains with one list of corners: where a chain lacks a corner another has,
/// a corner with no turn (and the other's radius) is put into its run, splitting the
/// run where the corner lies in the chain that has it. Chains keep their shape.
pub fn align(chains: &[Chain]) -> Vec<Chain> {
    if chains.is_empty() {
        return Vec::new();
    }
    // The master list of slots, grown chain by chain.
    let mut master = slots_of(&chains[0]);
    for c in &chains[1..] {
        let pairs = match_slots(&master, &slots_of(c));
        let own = slots_of(c);
        master = pairs
            .iter()
            .map(|&(a, b)| match (a, b) {
                (Some(i), Some(j)) => Slot {
                    turn: if master[i].turn.abs() >= own[j].turn.abs() {
                        master[i].turn
                    } else {
                        own[j].turn
                    },
                    radius: master[i].radius.max(own[j].radius),
                    position: 0.5 * (master[i].position + own[j].position),
                },
                (Some(i), None) => master[i],
                (None, Some(j)) => own[j],
                (None, None) => unreachable!("each pair holds at least one slot"),
            })
            .collect();
    }
    chains.iter().map(|c| expand(c, &master)).collect()
}

/// `c` with a corner for every slot of `master` (turnless where `c` has none).
fn expand(c: &Chain, master: &[Slot]) -> Chain {
    let own = slots_of(c);
    let pairs = match_slots(master, &own);
    // For every own run, the master slots that fall inside it.
    let mut runs = Vec::with_capacity(master.len() + 1);
    let mut radii = Vec::with_capacity(master.len());
    let mut pending: Vec<Slot> = Vec::new();
    let mut run_index = 0;
    let flush = |run: Run,
                 pending: &mut Vec<Slot>,
                 runs: &mut Vec<Run>,
                 radii: &mut Vec<f64>,
                 left: f64,
                 right: f64| {
        // Split `run` at the pending slots by their positions between `left` and `right`.
        // Each new corner has no turn but a straight arc of `r GENTLE_TURN`
        // ([`Chain::arc_length`]), taken from the run so the shape is kept (radii
        // scaled down where the run is too short for them).
        let span = (right - left).max(1e-12);
        let wanted: f64 = pending.iter().map(|s| s.radius * GENTLE_TURN).sum();
        let room = 0.8 * run.length;
        let shrink = if wanted > room && wanted > 0.0 {
            room / wanted
        } else {
            1.0
        };
        let straight = run.length - wanted * shrink;
        let mut last_f = 0.0;
        let count = pending.len() as f64;
        for (i, s) in pending.iter().enumerate() {
            // Every piece keeps at least 5 % of the run, so none has no length.
            let lo: f64 = last_f + 0.05;
            let hi: f64 = 1.0 - 0.05 * (count - i as f64);
            let f = ((s.position - left) / span).clamp(lo.min(hi), hi.max(lo));
            runs.push(Run {
                angle: run.angle,
                length: straight * (f - last_f),
            });
            radii.push(s.radius * shrink);
            last_f = f;
        }
        runs.push(Run {
            angle: run.angle,
            length: straight * (1.0 - last_f),
        });
        pending.clear();
    };
    let mut left_pos = 0.0;
    for &(mi, oi) in &pairs {
        match (mi, oi) {
            (Some(_), None) | (None, None) => {
                if let Some(m) = mi {
                    pending.push(master[m]);
                }
            }
            (m, Some(o)) => {
                // `c`'s own corner: close the run before it (splitting it at the
                // pending master corners). A corner of `c` the master lacks cannot
                // happen (the master holds every chain's corners); it is kept all the
                // same rather than losing the shape.
                let right = m.map_or(own[o].position, |m| master[m].position);
                flush(
                    c.runs[run_index],
                    &mut pending,
                    &mut runs,
                    &mut radii,
                    left_pos,
                    right,
                );
                let fallback = m
                    .filter(|_| c.turn(o) == 0.0)
                    .map_or(0.0, |m| master[m].radius);
                radii.push(c.radii[o].max(fallback));
                run_index = o + 1;
                left_pos = right;
            }
        }
    }
    flush(
        c.runs[run_index],
        &mut pending,
        &mut runs,
        &mut radii,
        left_pos,
        1.0,
    );
    Chain {
        start: c.start,
        runs,
        radii,
        obliquity: c.obliquity,
    }
}
