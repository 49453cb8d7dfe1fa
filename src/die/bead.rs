//! Draw beads on the blankholder (primer section 5; paper 001 section 5, Fig. 13).
//!
//! The designer draws the bead's centre line, or its two boundaries, in the top view
//! and gives its cross-section at key sections. [`build`] makes the paper's curve net
//! and skins it:
//!
//! 1. **Boundaries** (step 1): the top-view course is projected along the
//!    blank-holding direction (press Z) onto the binder, across side and corner
//!    patches. With a centre line the feet lie at the profile's own half widths; with
//!    two boundaries each section's profile is stretched across to them.
//! 2. **Key sections** (step 2): at designer positions along the bead, each with its
//!    own profile (height above the binder across the bead). Between key sections the
//!    profile changes smoothly (an [`ease`] blend of corresponding points), and its
//!    height runs out to zero over the `taper` length at both ends.
//! 3. **Rules** (step 3): where the designer gives rule points (positions across each
//!    key section that belong together, such as the crests of a round and a double
//!    bead), corresponding points are matched piece by piece between them, so the rule
//!    curves run through the same feature of every section; without rules the whole
//!    profile is matched by arc length.
//! 4. **Skinning** (step 4): sections every `spacing` (more where the skin would
//!    leave the binder) are placed in vertical planes across the bead, dropped onto the
//!    binder, raised by the profile, and skinned by [`loft`]; every section, foot line
//!    and rule is an iso-curve of the surface.
//!
//! The centre line resampled every `line_spacing` is the *line bead* of forming
//! simulation (a polyline with a restraining force). Heights are measured along press
//! Z, the direction the binder closes in.

use glam::{DVec2, DVec3};

use super::punch_opening::inside_outline;
use crate::geom::construct::{loft, section_parameters, Loft};
use crate::geom::curve::ArcLengths;
use crate::geom::interpolate::{interpolate, interpolate_at, Interpolation};
use crate::geom::inversion::project_to_curve_near;
use crate::geom::{Curve2, Curve3, Direction, GeomError, NurbsSurface};

/// Where the bead runs in the top view.
#[derive(Debug, Clone, PartialEq)]
pub enum Course {
    /// The centre line: the profile keeps its own width around it.
    Centre(Curve2),
    /// The two boundary lines (the feet): each section's profile is stretched across
    /// from one to the other, so the bead may widen and narrow.
    Boundaries(Curve2, Curve2),
}

/// A position along the bead's centre line in the top view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Along {
    /// A fraction (0 to 1) of the centre line's length.
    Fraction(f64),
    /// A length (mm) from the start of the centre line.
    Length(f64),
}

/// The bead's cross-section at one designer position.
#[derive(Debug, Clone, PartialEq)]
pub struct KeySection {
    /// Position along the bead.
    pub at: Along,
    /// The cross-section: (s across the bead, height above the binder), from foot to
    /// foot, both at height 0; s increases to the left of the direction of travel.
    pub profile: Curve2,
    /// Rule points: positions s across this profile that correspond, in order, to the
    /// rule points of the other key sections.
    pub rules: Vec<f64>,
}

/// The designer's input for one bead.
#[derive(Debug, Clone, PartialEq)]
pub struct BeadSpec {
    /// The course in the top view.
    pub course: Course,
    /// Key sections, at least one, in order along the bead.
    pub sections: Vec<KeySection>,
    /// Length (mm) over which the height runs out to zero at both ends; 0 for none.
    pub taper: f64,
    /// Distance (mm) between sections along the bead.
    pub spacing: f64,
    /// Distance (mm) between the line bead's points.
    pub line_spacing: f64,
    /// The tallest bead (mm) the binder allows.
    pub max_height: f64,
}

/// Quality figures of a bead.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeadQuality {
    /// Largest distance (mm, along Z) between the bead's feet and the binder, sampled.
    pub foot_gap: f64,
    /// Largest distance (mm, along Z) between a section's points and the binder plus
    /// the profile height they should have.
    pub section_error: f64,
    /// Number of sections skinned.
    pub sections: usize,
    /// Length (mm) of the centre line on the binder.
    pub length: f64,
    /// The tallest point (mm) of the bead above the binder.
    pub height: f64,
    /// Narrowest and widest distance (mm, top view) between the feet.
    pub width: (f64, f64),
}

/// A built bead.
#[derive(Debug, Clone, PartialEq)]
pub struct Bead {
    /// The bead surface: u across the bead from its left foot (u = 0) to its right
    /// foot (u = 1), v along it, so its normal points up, away from the binder.
    pub surface: NurbsSurface,
    /// The centre line on the binder.
    pub centre: Curve3,
    /// The line bead: the centre line resampled every `line_spacing`.
    pub line_points: Vec<DVec3>,
    /// The key sections in 3-D, in the order given.
    pub sections: Vec<Curve3>,
    /// The rule curves (iso-curves through the rule points), in order across.
    pub rules: Vec<Curve3>,
    /// Quality figures.
    pub quality: BeadQuality,
}

/// The problems [`build`] reports.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// The course (or the bead's width around it) leaves the binder in the top view.
    LeavesBinder {
        /// The top-view point with no binder under it.
        at: DVec2,
        /// How far (mm) across from the centre line that point is: 0 for the centre
        /// line itself, otherwise the bead's width reaches over; `None` for a point of
        /// the skinned surface.
        offset: Option<f64>,
    },
    /// The bead crosses into the punch opening.
    CrossesOpening {
        /// The top-view point inside the opening.
        at: DVec2,
        /// How far (mm) across from the centre line that point is (as for
        /// `LeavesBinder`).
        offset: Option<f64>,
    },
    /// The centre line turns tighter than the bead is wide: the bead's inner side would
    /// fold over itself.
    TooTight {
        /// The centre-line point where it turns tightest.
        at: DVec2,
        /// The centre line's turning radius there (mm); 0 at a sharp corner.
        radius: f64,
        /// How far (mm) the bead reaches to the inside of the turn.
        reach: f64,
    },
    /// A key section's profile dips below the binder, or never rises above it.
    BelowBinder {
        /// The key section.
        section: usize,
        /// Where across the profile (mm).
        s: f64,
    },
    /// A closed centre line (a ring) with a taper: a ring has no ends to run out.
    ClosedTaper,
    /// So many sections or line-bead points that the build would not finish.
    TooFine {
        /// Which spacing.
        what: &'static str,
        /// How many it would take.
        count: usize,
    },
    /// A key section's profile does not start and end at height 0.
    ProfileFeet {
        /// The key section.
        section: usize,
    },
    /// A key section's profile runs backwards across the bead: the bead would overhang
    /// (an undercut in the press direction).
    ProfileFolds {
        /// The key section.
        section: usize,
        /// Where across the profile it turns back (mm).
        s: f64,
    },
    /// A key section is taller than the binder allows.
    TooTall {
        /// The key section.
        section: usize,
        /// Its height (mm).
        height: f64,
        /// The binder's limit (mm).
        limit: f64,
    },
    /// Key sections with different numbers of rule points.
    RuleCount {
        /// The key section that differs from the first.
        section: usize,
        /// The first key section's count.
        expected: usize,
        /// This section's count.
        given: usize,
    },
    /// A rule point outside its profile's feet, or out of order.
    RuleOutside {
        /// The key section.
        section: usize,
        /// The rule point (mm across).
        s: f64,
        /// The profile's feet (mm across).
        feet: (f64, f64),
    },
    /// Key section positions outside the bead, or not in order along it.
    SectionOrder {
        /// The first key section out of place.
        section: usize,
    },
    /// The two boundaries cross, or come closer than `MIN_WIDTH`.
    BoundariesCross {
        /// The centre-line point where they do.
        at: DVec2,
    },
    /// A section line across the bead does not meet a boundary.
    MissesBoundary {
        /// Which boundary (0 or 1).
        boundary: usize,
        /// The centre-line point of that section.
        at: DVec2,
    },
    /// A taper longer than half the bead: the bead would never reach its height.
    TaperTooLong {
        /// The taper length (mm).
        taper: f64,
        /// The centre line's top-view length (mm).
        length: f64,
    },
    /// A spacing or taper that is not a positive (or, for taper, non-negative) length.
    BadLength(&'static str),
    /// The kernel failed.
    Kernel(GeomError),
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::LeavesBinder { at, .. } => write!(
                f,
                "the bead leaves the binder near ({:.1}, {:.1})",
                at.x, at.y
            ),
            Problem::CrossesOpening { at, .. } => write!(
                f,
                "the bead crosses into the punch opening near ({:.1}, {:.1})",
                at.x, at.y
            ),
            Problem::TooTight { at, radius, reach } => write!(
                f,
                "the centre line turns with a radius of {radius:.1} mm near ({:.1}, {:.1}), tighter than the bead's {reach:.1} mm to the inside",
                at.x, at.y
            ),
            Problem::BelowBinder { section, s } => write!(
                f,
                "the profile of key section {section} is not above the binder at s = {s:.2} mm"
            ),
            Problem::ClosedTaper => write!(f, "a closed bead has no ends to taper"),
            Problem::TooFine { what, count } => {
                write!(f, "the {what} would take {count} sections or points")
            }
            Problem::ProfileFeet { section } => write!(
                f,
                "the profile of key section {section} does not start and end at height 0"
            ),
            Problem::ProfileFolds { section, s } => write!(
                f,
                "the profile of key section {section} runs backwards at s = {s:.2} mm"
            ),
            Problem::TooTall {
                section,
                height,
                limit,
            } => write!(
                f,
                "key section {section} is {height:.2} mm tall; the binder allows {limit:.2} mm"
            ),
            Problem::RuleCount {
                section,
                expected,
                given,
            } => write!(
                f,
                "key section {section} has {given} rule points, the first has {expected}"
            ),
            Problem::RuleOutside { section, s, feet } => write!(
                f,
                "rule point {s:.2} mm of key section {section} is not inside its feet ({:.2}, {:.2}) in order",
                feet.0, feet.1
            ),
            Problem::SectionOrder { section } => {
                write!(f, "key section {section} is out of order along the bead")
            }
            Problem::BoundariesCross { at } => write!(
                f,
                "the boundaries cross or touch near ({:.1}, {:.1})",
                at.x, at.y
            ),
            Problem::MissesBoundary { boundary, at } => write!(
                f,
                "the section across ({:.1}, {:.1}) does not meet boundary {boundary}",
                at.x, at.y
            ),
            Problem::TaperTooLong { taper, length } => write!(
                f,
                "a taper of {taper:.1} mm at both ends is more than half the bead's {length:.1} mm"
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

/// Intervals across a section (points per section minus one).
const SECTION_INTERVALS: usize = 48;

/// The foot gap (mm) above which a section is added between two others.
const FOOT_TOLERANCE: f64 = 0.0005;

/// Rounds of section insertion.
const MAX_REFINEMENTS: usize = 6;

/// The most sections a bead may take (a 4 m bead at 2 mm).
const MAX_SECTIONS: usize = 2000;

/// The most line-bead points a bead may take.
const MAX_LINE_POINTS: usize = 100_000;

/// Distance (mm) between the centre-line samples of the turning check.
const TURN_SAMPLE_STEP: f64 = 0.5;

/// A direction jump (degrees) at a knot of the centre line that counts as a sharp
/// corner.
const KINK_DEGREES: f64 = 0.5;

/// Samples along each foot for the foot-gap figure.
pub const FOOT_SAMPLES: usize = 400;

/// Samples of a profile for its fold and rule checks.
const PROFILE_SAMPLES: usize = 512;

/// Samples of a boundary line for finding where a section crosses it.
const BOUNDARY_SAMPLES: usize = 512;

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

    /// The binder point under `p`, `offset` mm across from the centre line, or why
    /// there is none.
    fn base(&self, p: DVec2, offset: Option<f64>) -> Result<DVec3, Problem> {
        if self.in_opening(p) {
            return Err(Problem::CrossesOpening { at: p, offset });
        }
        self.point_over(p)
            .ok_or(Problem::LeavesBinder { at: p, offset })
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
    check_lengths(spec)?;
    let course = CourseMap::new(&spec.course)?;
    if course.closed() && spec.taper > 0.0 {
        return Err(Problem::ClosedTaper);
    }
    for (what, spacing, most) in [
        ("section spacing", spec.spacing, MAX_SECTIONS),
        ("line-bead spacing", spec.line_spacing, MAX_LINE_POINTS),
    ] {
        let count = course.length / spacing;
        if count > most as f64 {
            return Err(Problem::TooFine {
                what,
                count: count.min(usize::MAX as f64) as usize,
            });
        }
    }
    if 2.0 * spec.taper > course.length {
        return Err(Problem::TaperTooLong {
            taper: spec.taper,
            length: course.length,
        });
    }
    let ats = key_positions(spec, course.length)?;
    let profiles = matched_profiles(spec, &ats)?;
    if let Some(problem) = course.too_tight(&profiles) {
        return Err(problem);
    }
    if let Some(at) = course.kink() {
        let reach = profiles
            .points
            .iter()
            .flatten()
            .map(|q| q.x.abs())
            .fold(0.0, f64::max);
        return Err(Problem::TooTight {
            at,
            radius: 0.0,
            reach,
        });
    }

    // Step 1: the centre line on the binder, sampled about every 2 mm; the course must
    // stay over the binder and outside the opening.
    let length2 = course.length;
    let samples = ((length2 / 2.0).ceil() as usize).clamp(8, 4000);
    let mut centre_points = Vec::with_capacity(samples + 1);
    for i in 0..=samples {
        let (c, _) = course.frame(i as f64 / samples as f64)?;
        centre_points.push(binder.base(c, Some(0.0))?);
    }
    let centre = interpolate(&centre_points, &Interpolation::default())?;

    // Steps 2-3: a section at any fraction along the bead, from the matched profiles.
    let section_at = |along: f64| -> Result<(Curve3, f64), Problem> {
        let (c, across, turn) = course.frame_and_turn(along)?;
        let height_factor = taper_factor(along * length2, length2, spec.taper);
        let shape = profiles.blend(along);
        let (s0, s1) = (shape[0].x, shape[shape.len() - 1].x);
        let stretch = course.feet(c, across)?;
        let mut points = Vec::with_capacity(shape.len());
        for q in &shape {
            let offset = match stretch {
                None => q.x,
                Some((low, high)) => low + (q.x - s0) / (s1 - s0) * (high - low),
            };
            // An offset line folds where it reaches the turn's centre: offset * turn = 1.
            if offset * turn >= 1.0 {
                return Err(Problem::TooTight {
                    at: c,
                    radius: 1.0 / turn.abs(),
                    reach: offset.abs(),
                });
            }
            let base = binder.base(c + across * offset, Some(offset))?;
            points.push(base + DVec3::Z * (q.y * height_factor));
        }
        let width = points[0]
            .truncate()
            .distance(points[points.len() - 1].truncate());
        let curve = interpolate_at(&points, &profiles.params, &Interpolation::default())?;
        Ok((curve, width))
    };

    // Step 4: sections every `spacing` and at every key section, then more where the
    // skinned feet leave the binder by more than FOOT_TOLERANCE between two sections.
    let mut stations = station_fractions(length2, spec.spacing, spec.taper);
    for &at in &ats {
        let i = stations.partition_point(|&x| x < at);
        let near = |j: usize| stations.get(j).is_some_and(|&x| (x - at).abs() < 1e-9);
        let present = near(i) || (i > 0 && near(i - 1));
        if !present {
            stations.insert(i, at);
        }
    }
    let mut sections = Vec::with_capacity(stations.len());
    let (mut narrow, mut wide) = (f64::INFINITY, 0.0f64);
    for &a in &stations {
        let (s, w) = section_at(a)?;
        narrow = narrow.min(w);
        wide = wide.max(w);
        sections.push(s);
    }
    let ring = course.closed();
    let mut surface = skin(&sections, ring)?;
    for _ in 0..MAX_REFINEMENTS {
        let vs = section_parameters(&sections, Loft::default().parametrization)?;
        let mut inserted = Vec::new();
        for k in 0..sections.len() - 1 {
            let v = 0.5 * (vs[k] + vs[k + 1]);
            if foot_gap_at(binder, &surface, v)? > FOOT_TOLERANCE {
                inserted.push(0.5 * (stations[k] + stations[k + 1]));
            }
        }
        if inserted.is_empty() {
            break;
        }
        for a in inserted {
            let i = stations.partition_point(|&x| x < a);
            let (s, w) = section_at(a)?;
            narrow = narrow.min(w);
            wide = wide.max(w);
            stations.insert(i, a);
            sections.insert(i, s);
        }
        surface = skin(&sections, ring)?;
    }

    // The sections run across from the right foot to the left, so S_u x S_v points
    // down; the skin is turned round in u to face up like the binder under it.
    let surface = surface.reversed(Direction::U);

    // Quality: the feet on the binder, and every section at the height it should have.
    let (v0, v1) = surface.domain_v();
    let mut foot_gap = 0.0f64;
    for i in 0..=FOOT_SAMPLES {
        let v = v0 + (v1 - v0) * i as f64 / FOOT_SAMPLES as f64;
        foot_gap = foot_gap.max(foot_gap_at(binder, &surface, v)?);
    }
    let mut height = 0.0f64;
    for s in &sections {
        for &u in &profiles.params {
            let p = s.point_at(u);
            height = height.max(p.z - binder.base(p.truncate(), None)?.z);
        }
    }
    let key_sections = ats
        .iter()
        .map(|&at| {
            let i = stations.partition_point(|&x| x < at - 1e-9);
            sections[i.min(sections.len() - 1)].clone()
        })
        .collect::<Vec<Curve3>>();
    // Section conformance: the key sections, and every CONFORMANCE_STRIDE-th skinned
    // section whose exact profile is known (between two key sections with the same
    // profile).
    let mut section_error = 0.0f64;
    for (i, (section, &along)) in sections.iter().zip(&stations).enumerate() {
        let k = ats
            .partition_point(|&a| a < along - 1e-9)
            .min(ats.len() - 1);
        let at_key = (ats[k] - along).abs() <= 1e-9;
        if !at_key && i % CONFORMANCE_STRIDE != 0 {
            continue;
        }
        let key = if at_key || k == 0 {
            Some(&spec.sections[k])
        } else {
            let (a, b) = (&spec.sections[k - 1], &spec.sections[k]);
            (a.profile == b.profile && a.rules == b.rules).then_some(a)
        };
        if let Some(key) = key {
            let error = conformance(binder, &course, spec.taper, key, along, section)?;
            section_error = section_error.max(error);
        }
    }
    let rules = profiles
        .rule_params
        .iter()
        .map(|&u| surface.iso_curve(Direction::U, 1.0 - u))
        .collect();

    // The line bead.
    let centre_table = ArcLengths::new(&centre);
    let length3 = centre_table.total();
    let n = ((length3 / spec.line_spacing).ceil() as usize).max(1);
    let mut line_points = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let t = centre_table.parameter_at_fraction(i as f64 / n as f64)?;
        line_points.push(centre.point_at(t));
    }
    Ok(Bead {
        surface,
        centre,
        line_points,
        sections: key_sections,
        rules,
        quality: BeadQuality {
            foot_gap,
            section_error,
            sections: sections.len(),
            length: length3,
            height,
            width: (narrow, wide),
        },
    })
}

/// Samples across a section for its conformance figure: four between every two
/// interpolated points.
const CONFORMANCE_SAMPLES: usize = 4 * SECTION_INTERVALS;

/// Every how many skinned sections one is measured for conformance (besides the key
/// sections): the sections are built alike, so a sample of them tells.
const CONFORMANCE_STRIDE: usize = 5;

/// How closely a skinned section follows its designer profile: the largest
/// distance, in the section plane, between the section's points (across offset, height
/// above the binder) and the profile (scaled by the taper, stretched to the
/// boundaries), sampled between the interpolated points as well as at them.
fn conformance(
    binder: &Binder,
    course: &CourseMap,
    taper: f64,
    key: &KeySection,
    at: f64,
    section: &Curve3,
) -> Result<f64, Problem> {
    let (c, across) = course.frame(at)?;
    let factor = taper_factor(at * course.length, course.length, taper);
    let (s0, s1) = (key.profile.start_point().x, key.profile.end_point().x);
    let stretch = course.feet(c, across)?;
    let exact = key.profile.map_points(|q| DVec2::new(q.x, q.y * factor));
    let (t0, t1) = section.domain();
    let mut worst = 0.0f64;
    let mut guess = exact.domain().0;
    for i in 0..=CONFORMANCE_SAMPLES {
        let p = section.point_at(t0 + (t1 - t0) * i as f64 / CONFORMANCE_SAMPLES as f64);
        let offset = (p.truncate() - c).dot(across);
        let s = match stretch {
            None => offset,
            Some((low, high)) => s0 + (offset - low) / (high - low) * (s1 - s0),
        };
        let h = p.z - binder.base(p.truncate(), None)?.z;
        let hit = project_to_curve_near(&exact, DVec2::new(s, h), guess)?;
        guess = hit.t;
        worst = worst.max(hit.distance);
    }
    Ok(worst)
}

/// The key sections' positions as fractions of the centre line's length (`length`
/// mm), checked to lie on the bead in increasing order.
fn key_positions(spec: &BeadSpec, length: f64) -> Result<Vec<f64>, Problem> {
    if spec.sections.is_empty() {
        return Err(Problem::SectionOrder { section: 0 });
    }
    let mut ats = Vec::with_capacity(spec.sections.len());
    for (k, key) in spec.sections.iter().enumerate() {
        let f = match key.at {
            Along::Fraction(f) => f,
            Along::Length(l) => l / length,
        };
        let after_previous = ats.last().is_none_or(|&prev| f > prev);
        if !(f.is_finite() && (0.0..=1.0).contains(&f) && after_previous) {
            return Err(Problem::SectionOrder { section: k });
        }
        ats.push(f);
    }
    Ok(ats)
}

/// Sections along the bead as fractions of its length: every `spacing`, and in the
/// tapered ends (and one `spacing` beyond) every `taper / TAPER_SECTIONS` when that is
/// closer, so the run-out is resolved, not smoothed over by the skinning.
fn station_fractions(length: f64, spacing: f64, taper: f64) -> Vec<f64> {
    let mut stations = Vec::new();
    let mut push_run = |from: f64, to: f64, step: f64| {
        let n = (((to - from) / step).ceil() as usize).max(1);
        for k in 0..n {
            stations.push((from + (to - from) * k as f64 / n as f64) / length);
        }
    };
    // The fine sections run one `spacing` past the taper, where the run-out's
    // curvature ends, so the skinning does not overshoot there.
    let fine_zone = (taper + spacing).min(0.5 * length);
    if taper > 0.0 && taper / (TAPER_SECTIONS as f64) < spacing {
        let fine = taper / TAPER_SECTIONS as f64;
        push_run(0.0, fine_zone, fine);
        if length - fine_zone > fine_zone {
            push_run(fine_zone, length - fine_zone, spacing);
        }
        push_run(length - fine_zone, length, fine);
    } else {
        push_run(0.0, length, spacing);
    }
    stations.push(1.0);
    stations.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    if stations.len() < 3 {
        stations = vec![0.0, 0.5, 1.0];
    }
    stations
}

/// Sections across each tapered end.
const TAPER_SECTIONS: usize = 16;

/// Refuses spacings and tapers that are not lengths the bead can use.
fn check_lengths(spec: &BeadSpec) -> Result<(), Problem> {
    for (what, value, strict) in [
        ("section spacing", spec.spacing, true),
        ("line-bead spacing", spec.line_spacing, true),
        ("taper length", spec.taper, false),
        ("height limit", spec.max_height, true),
    ] {
        let ok = value.is_finite() && if strict { value > 0.0 } else { value >= 0.0 };
        if !ok {
            return Err(Problem::BadLength(what));
        }
    }
    Ok(())
}

/// The largest distance along Z between the binder and the surface's two feet at `v`.
fn foot_gap_at(binder: &Binder, surface: &NurbsSurface, v: f64) -> Result<f64, Problem> {
    let (u0, u1) = surface.domain_u();
    let mut worst = 0.0f64;
    for u in [u0, u1] {
        let p = surface.point_at(u, v);
        let base = binder.base(p.truncate(), None)?;
        worst = worst.max((p.z - base.z).abs());
    }
    Ok(worst)
}

/// The key sections' profiles resampled at corresponding points: the same number of
/// points in every piece between rule points, spaced by arc length within a piece.
struct MatchedProfiles {
    /// Key positions along the bead (fractions).
    at: Vec<f64>,
    /// Each key section's points, (s, height).
    points: Vec<Vec<DVec2>>,
    /// The shared interpolation parameters across a section (0 to 1).
    params: Vec<f64>,
    /// The parameters of the rule points.
    rule_params: Vec<f64>,
}

impl MatchedProfiles {
    /// The profile at fraction `along`: the neighbouring key sections' points blended
    /// by [`ease`], so the shape stops changing at each key section.
    fn blend(&self, along: f64) -> Vec<DVec2> {
        let k = self.at.partition_point(|&a| a <= along);
        if k == 0 {
            return self.points[0].clone();
        }
        if k == self.at.len() {
            return self.points[k - 1].clone();
        }
        let x = (along - self.at[k - 1]) / (self.at[k] - self.at[k - 1]);
        let w = ease(x);
        self.points[k - 1]
            .iter()
            .zip(&self.points[k])
            .map(|(a, b)| a.lerp(*b, w))
            .collect()
    }
}

/// Checks every key section's profile (feet at 0, not folding back, not too tall,
/// rules inside and in order) and resamples them at corresponding points.
fn matched_profiles(spec: &BeadSpec, ats: &[f64]) -> Result<MatchedProfiles, Problem> {
    let rule_count = spec.sections[0].rules.len();
    let mut pieces_per_section = Vec::with_capacity(spec.sections.len());
    for (k, key) in spec.sections.iter().enumerate() {
        let profile = &key.profile;
        let (a, b) = (profile.start_point(), profile.end_point());
        let scale = profile.control_scale().max(1.0);
        if a.y.abs() > 1e-9 * scale || b.y.abs() > 1e-9 * scale {
            return Err(Problem::ProfileFeet { section: k });
        }
        let (t0, t1) = profile.domain();
        let samples: Vec<(f64, DVec2)> = (0..=PROFILE_SAMPLES)
            .map(|i| {
                let t = t0 + (t1 - t0) * i as f64 / PROFILE_SAMPLES as f64;
                (t, profile.point_at(t))
            })
            .collect();
        let backwards = 1e-9 * scale;
        if b.x <= a.x {
            return Err(Problem::ProfileFolds { section: k, s: a.x });
        }
        if let Some(w) = samples.windows(2).find(|w| w[1].1.x < w[0].1.x - backwards) {
            return Err(Problem::ProfileFolds {
                section: k,
                s: w[0].1.x,
            });
        }
        let lowest = samples
            .iter()
            .map(|&(_, p)| p)
            .min_by(|p, q| p.y.total_cmp(&q.y))
            .expect("PROFILE_SAMPLES + 1 samples");
        if lowest.y < -1e-9 * scale {
            return Err(Problem::BelowBinder {
                section: k,
                s: lowest.x,
            });
        }
        let tallest = samples.iter().map(|(_, p)| p.y).fold(0.0, f64::max);
        if tallest <= 1e-9 * scale {
            return Err(Problem::BelowBinder {
                section: k,
                s: 0.5 * (a.x + b.x),
            });
        }
        if tallest > spec.max_height {
            return Err(Problem::TooTall {
                section: k,
                height: tallest,
                limit: spec.max_height,
            });
        }
        if key.rules.len() != rule_count {
            return Err(Problem::RuleCount {
                section: k,
                expected: rule_count,
                given: key.rules.len(),
            });
        }
        // Piece boundaries: the feet and the rule points, strictly increasing in s.
        let feet = (a.x, b.x);
        let mut cuts = vec![t0];
        let mut last_s = a.x;
        for &s in &key.rules {
            if !(s > last_s && s < b.x) {
                return Err(Problem::RuleOutside {
                    section: k,
                    s,
                    feet,
                });
            }
            cuts.push(parameter_at_s(profile, &samples, s));
            last_s = s;
        }
        cuts.push(t1);
        pieces_per_section.push(cuts);
    }

    // Intervals per piece: in proportion to the longest the piece is on any section
    // (as a fraction of that section's length), at least two each.
    let tables: Vec<ArcLengths<DVec2>> = spec
        .sections
        .iter()
        .map(|k| ArcLengths::new(&k.profile))
        .collect();
    let pieces = rule_count + 1;
    let mut share = vec![0.0f64; pieces];
    let mut piece_lengths = Vec::with_capacity(spec.sections.len());
    for (table, cuts) in tables.iter().zip(&pieces_per_section) {
        let lengths: Vec<f64> = cuts.iter().map(|&t| table.length_at(t)).collect();
        for j in 0..pieces {
            share[j] = share[j].max((lengths[j + 1] - lengths[j]) / table.total());
        }
        piece_lengths.push(lengths);
    }
    let total_share: f64 = share.iter().sum();
    let counts: Vec<usize> = share
        .iter()
        .map(|s| ((s / total_share * SECTION_INTERVALS as f64).round() as usize).max(2))
        .collect();

    let mut points = Vec::with_capacity(spec.sections.len());
    for ((key, table), lengths) in spec.sections.iter().zip(&tables).zip(&piece_lengths) {
        let mut section = Vec::new();
        for j in 0..pieces {
            let first = if j == 0 { 0 } else { 1 };
            for i in first..=counts[j] {
                let l = lengths[j] + (lengths[j + 1] - lengths[j]) * i as f64 / counts[j] as f64;
                section.push(key.profile.point_at(table.parameter_at(l)?));
            }
        }
        points.push(section);
    }

    // Shared parameters: the chord-length fractions, averaged over the key sections.
    let n = points[0].len();
    let mut params = vec![0.0; n];
    for section in &points {
        let mut acc = vec![0.0; n];
        for i in 1..n {
            acc[i] = acc[i - 1] + section[i].distance(section[i - 1]).max(1e-12);
        }
        for i in 0..n {
            params[i] += acc[i] / acc[n - 1] / points.len() as f64;
        }
    }
    params[0] = 0.0;
    params[n - 1] = 1.0;
    let mut rule_params = Vec::with_capacity(rule_count);
    let mut index = 0;
    for &c in counts.iter().take(rule_count) {
        index += c;
        rule_params.push(params[index]);
    }
    Ok(MatchedProfiles {
        at: ats.to_vec(),
        points,
        params,
        rule_params,
    })
}

/// The parameter where a profile that never runs backwards reaches `s` across, from its
/// samples and bisection between them.
fn parameter_at_s(profile: &Curve2, samples: &[(f64, DVec2)], s: f64) -> f64 {
    let i = samples
        .windows(2)
        .position(|w| w[0].1.x <= s && s <= w[1].1.x)
        .unwrap_or(samples.len() - 2);
    let (mut lo, mut hi) = (samples[i].0, samples[i + 1].0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if profile.point_at(mid).x < s {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The course in the top view, ready for sections: the centre line by arc length, and
/// the boundaries (if any) sampled for crossings.
struct CourseMap {
    centre: Curve2,
    table_length: Vec<(f64, f64)>,
    length: f64,
    boundaries: Option<[BoundarySamples; 2]>,
    /// Whether the first boundary lies to the left of the centre line (it must stay
    /// there: boundaries that swap sides cross).
    first_left: bool,
}

/// A boundary line with samples to find crossings from.
struct BoundarySamples {
    curve: Curve2,
    samples: Vec<(f64, DVec2)>,
}

/// The narrowest bead (mm, between its boundaries) that is not a mistake.
const MIN_WIDTH: f64 = 1.0;

impl CourseMap {
    fn new(course: &Course) -> Result<Self, Problem> {
        let (centre, boundaries) = match course {
            Course::Centre(c) => (c.clone(), None),
            Course::Boundaries(a, b) => {
                // Boundaries drawn from opposite ends still bound one bead: run the
                // second the way the first runs.
                let (a0, a1) = (a.start_point(), a.end_point());
                let b = if b.start_point().distance(a1) + b.end_point().distance(a0)
                    < b.start_point().distance(a0) + b.end_point().distance(a1)
                {
                    b.reversed()
                } else {
                    b.clone()
                };
                let samples = [BoundarySamples::new(a.clone()), BoundarySamples::new(b)];
                let mid = mid_line(&samples[0].curve, &samples[1].curve, &samples)?;
                (mid, Some(samples))
            }
        };
        let table = ArcLengths::new(&centre);
        let length = table.total();
        // Fractions 0..1 of the length to parameters, tabulated once (every section
        // and every centre-line sample asks).
        let n = 1024;
        let mut table_length = Vec::with_capacity(n + 1);
        for i in 0..=n {
            let f = i as f64 / n as f64;
            table_length.push((f, table.parameter_at_fraction(f)?));
        }
        let mut map = Self {
            centre,
            table_length,
            length,
            boundaries,
            first_left: true,
        };
        // Which side the first boundary is on, read where the bead is widest of five
        // places along it (boundaries that cross are caught at the sections).
        if let Some(bounds) = &map.boundaries {
            let mut widest = 0.0f64;
            for f in [0.0, 0.25, 0.5, 0.75, 1.0] {
                let (c, across) = map.frame(f)?;
                let side = |b: &BoundarySamples| b.crossing(c, across).map(|p| (p - c).dot(across));
                if let (Some(a), Some(b)) = (side(&bounds[0]), side(&bounds[1])) {
                    if (a - b).abs() > widest {
                        widest = (a - b).abs();
                        map.first_left = a > b;
                    }
                }
            }
        }
        Ok(map)
    }

    /// The centre point and the unit direction across (to the left) at fraction `f`.
    fn frame(&self, f: f64) -> Result<(DVec2, DVec2), Problem> {
        let (c, across, _) = self.frame_and_turn(f)?;
        Ok((c, across))
    }

    /// [`CourseMap::frame`] and the centre line's signed curvature there (1/mm,
    /// positive turning left).
    fn frame_and_turn(&self, f: f64) -> Result<(DVec2, DVec2, f64), Problem> {
        let t = self.parameter(f)?;
        let [c, d, dd] = self.centre.derivatives::<3>(t);
        let across = d.normalize_or_zero().perp();
        if across == DVec2::ZERO {
            return Err(Problem::Kernel(GeomError::ZeroVector {
                what: "bead centre-line tangent",
            }));
        }
        let speed = d.length();
        Ok((c, across, d.perp_dot(dd) / (speed * speed * speed)))
    }

    /// For a centre-line course: the first place where the centre line turns tighter
    /// than the bead reaches to the inside of the turn, sampled every
    /// `TURN_SAMPLE_STEP` mm (so a small fillet between two sections is not missed).
    fn too_tight(&self, profiles: &MatchedProfiles) -> Option<Problem> {
        if self.boundaries.is_some() {
            return None;
        }
        let all = || profiles.points.iter().flatten();
        let left = all().map(|q| q.x).fold(0.0, f64::max);
        let right = all().map(|q| -q.x).fold(0.0, f64::max);
        let n = ((self.length / TURN_SAMPLE_STEP).ceil() as usize).clamp(64, 100_000);
        (0..=n).find_map(|i| {
            let (c, _, turn) = self.frame_and_turn(i as f64 / n as f64).ok()?;
            let reach = if turn > 0.0 { left } else { right };
            (reach * turn.abs() >= 1.0).then(|| Problem::TooTight {
                at: c,
                radius: 1.0 / turn.abs(),
                reach,
            })
        })
    }

    /// Whether the centre line is a closed ring.
    fn closed(&self) -> bool {
        let (t0, t1) = self.centre.domain();
        let (a, b) = (self.centre.point_at(t0), self.centre.point_at(t1));
        a.distance(b) <= 1e-6 * (1.0 + self.length)
    }

    /// The first sharp corner of the centre line (a knot where its direction jumps by
    /// more than `KINK_DEGREES`), if any.
    fn kink(&self) -> Option<DVec2> {
        let (t0, t1) = self.centre.domain();
        let eps = 1e-9 * (t1 - t0);
        self.centre
            .span_breaks()
            .into_iter()
            .filter(|&k| k > t0 + eps && k < t1 - eps)
            .find(|&k| {
                let before = self.centre.derivative_at(k - eps);
                let after = self.centre.derivative_at(k + eps);
                before.angle_to(after).abs().to_degrees() > KINK_DEGREES
            })
            .map(|k| self.centre.point_at(k))
    }

    /// The parameter at fraction `f` of the length: the tabulated neighbours, then
    /// Newton on the exact arc length.
    fn parameter(&self, f: f64) -> Result<f64, Problem> {
        let f = f.clamp(0.0, 1.0);
        let n = self.table_length.len() - 1;
        let i = ((f * n as f64).floor() as usize).min(n - 1);
        let (fa, ta) = self.table_length[i];
        let (fb, tb) = self.table_length[i + 1];
        if f == fa {
            return Ok(ta);
        }
        if f == fb {
            return Ok(tb);
        }
        // Newton from the linear guess, on length(ta, t) = (f - fa) * length.
        let want = (f - fa) * self.length;
        let mut t = ta + (tb - ta) * (f - fa) / (fb - fa);
        for _ in 0..20 {
            let err = self.centre.length_between(ta, t) - want;
            if err.abs() <= 1e-12 * self.length.max(1.0) {
                break;
            }
            let speed = self.centre.derivative_at(t).length();
            if speed <= 0.0 {
                break;
            }
            t = (t - err / speed).clamp(ta, tb);
        }
        Ok(t)
    }

    /// Where the section through `c`, running `across`, meets the two
    /// boundaries, as offsets along `across` (low, high); `None` for a centre line.
    fn feet(&self, c: DVec2, across: DVec2) -> Result<Option<(f64, f64)>, Problem> {
        let Some(bounds) = &self.boundaries else {
            return Ok(None);
        };
        let mut offsets = [0.0; 2];
        for (k, b) in bounds.iter().enumerate() {
            let hit = b
                .crossing(c, across)
                .ok_or(Problem::MissesBoundary { boundary: k, at: c })?;
            offsets[k] = (hit - c).dot(across);
        }
        let (left, right) = if self.first_left {
            (offsets[0], offsets[1])
        } else {
            (offsets[1], offsets[0])
        };
        if left - right < MIN_WIDTH {
            return Err(Problem::BoundariesCross { at: c });
        }
        Ok(Some((right, left)))
    }
}

impl BoundarySamples {
    fn new(curve: Curve2) -> Self {
        let (t0, t1) = curve.domain();
        let samples = (0..=BOUNDARY_SAMPLES)
            .map(|i| {
                let t = t0 + (t1 - t0) * i as f64 / BOUNDARY_SAMPLES as f64;
                (t, curve.point_at(t))
            })
            .collect();
        Self { curve, samples }
    }

    /// The point of the boundary on the line through `c` along `across` nearest `c`.
    /// A boundary that stops a little short of the line (by at most half the distance
    /// from `c`, or 1 mm) is extended along its end tangent, so boundaries drawn with
    /// slightly different ends still bound the end sections.
    fn crossing(&self, c: DVec2, across: DVec2) -> Option<DVec2> {
        let along = across.perp();
        let g = |p: DVec2| (p - c).dot(along);
        let zero = 1e-9 * (1.0 + c.length());
        let mut hits: Vec<DVec2> = Vec::new();
        let mut consider = |p: DVec2| hits.push(p);
        for w in self.samples.windows(2) {
            let ((ta, pa), (tb, pb)) = (w[0], w[1]);
            let (ga, gb) = (g(pa), g(pb));
            if ga.abs() <= zero {
                consider(pa);
            } else if gb.abs() <= zero {
                consider(pb);
            } else if (ga < 0.0) != (gb < 0.0) {
                let (mut lo, mut hi) = (ta, tb);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if (g(self.curve.point_at(mid)) < 0.0) == (ga < 0.0) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                consider(self.curve.point_at(0.5 * (lo + hi)));
            }
        }
        if hits.is_empty() {
            let (t0, t1) = self.curve.domain();
            for (t, outward) in [(t0, -1.0), (t1, 1.0)] {
                let p = self.curve.point_at(t);
                let tangent = self.curve.derivative_at(t).normalize_or_zero();
                let rate = tangent.dot(along);
                if rate.abs() < 1e-12 {
                    continue;
                }
                let reach = -g(p) / rate;
                let q = p + tangent * reach;
                if reach * outward >= 0.0 && reach.abs() <= (0.5 * q.distance(c)).max(1.0) {
                    hits.push(q);
                }
            }
        }
        hits.into_iter()
            .min_by(|a, b| a.distance(c).total_cmp(&b.distance(c)))
    }
}

/// The line halfway between two boundaries: midpoints of points at equal arc-length
/// fractions, then corrected once to the midpoints of the crossings of the lines
/// normal to that first guess.
fn mid_line(a: &Curve2, b: &Curve2, samples: &[BoundarySamples; 2]) -> Result<Curve2, Problem> {
    let (ta, tb) = (ArcLengths::new(a), ArcLengths::new(b));
    let n = ((ta.total().max(tb.total()) / 4.0).ceil() as usize).clamp(16, 2000);
    let mut guess = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let f = i as f64 / n as f64;
        let (pa, pb) = (
            a.point_at(ta.parameter_at_fraction(f)?),
            b.point_at(tb.parameter_at_fraction(f)?),
        );
        guess.push(0.5 * (pa + pb));
    }
    let first = interpolate(&guess, &Interpolation::default())?;
    let mut corrected = Vec::with_capacity(n + 1);
    for (i, &g) in guess.iter().enumerate() {
        let t = first.domain().0 + (first.domain().1 - first.domain().0) * i as f64 / n as f64;
        let t = crate::geom::inversion::closest_point_on_curve(&first, g)
            .map(|h| h.t)
            .unwrap_or(t);
        let across = first.derivative_at(t).normalize_or_zero().perp();
        let hits = (
            samples[0].crossing(g, across),
            samples[1].crossing(g, across),
        );
        corrected.push(match hits {
            (Some(p), Some(q)) if i > 0 && i < n => 0.5 * (p + q),
            _ => g,
        });
    }
    Ok(interpolate(&corrected, &Interpolation::default())?)
}

/// The bead surface through `sections` (all on one knot vector, non-rational). An open
/// bead is lofted with free ends; a ring (`closed`, its first and last sections the
/// same) gets the same cross-boundary derivative at both ends, the three-point
/// derivative across the seam at the loft's own section parameters, so the skin is C1
/// all round.
fn skin(sections: &[Curve3], closed: bool) -> Result<NurbsSurface, Problem> {
    let n = sections.len();
    if !closed || n < 4 {
        return Ok(loft(sections, &Loft::default())?);
    }
    let params = section_parameters(sections, Loft::default().parametrization)?;
    let (before, after) = (1.0 - params[n - 2], params[1]);
    let (previous, seam, next) = (&sections[n - 2], &sections[0], &sections[1]);
    let derivative: Vec<DVec3> = seam
        .control_points()
        .iter()
        .zip(previous.control_points())
        .zip(next.control_points())
        .map(|((&f0, &fm), &fp)| {
            (fp - f0) * (before / (after * (before + after)))
                + (f0 - fm) * (after / (before * (before + after)))
        })
        .collect();
    let tangent = Curve3::new(seam.degree(), seam.knots().as_slice().to_vec(), derivative)?;
    Ok(loft(
        sections,
        &Loft {
            start_tangent: Some(tangent.clone()),
            end_tangent: Some(tangent),
            ..Loft::default()
        },
    )?)
}

/// 1 along the bead, running out to 0 over `taper` at both ends by [`ease`].
fn taper_factor(s: f64, length: f64, taper: f64) -> f64 {
    if taper <= 0.0 {
        return 1.0;
    }
    ease((s.min(length - s) / taper).clamp(0.0, 1.0))
}

/// The quintic "smootherstep" `x^3 (10 - 15 x + 6 x^2)` on [0, 1]: 0 to 1 with zero
/// slope and zero curvature at both ends, so a taper or a blend meets the constant
/// part of the bead without a kink in curvature the skinning would overshoot on.
pub fn ease(x: f64) -> f64 {
    x * x * x * (10.0 + x * (6.0 * x - 15.0))
}
