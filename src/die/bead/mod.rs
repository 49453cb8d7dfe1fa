//! Draw beads on the blankholder (paper 001 section 5, Fig. 13; `docs/methods.md`).
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
//!    height runs out to zero over the `taper` length at both ends, the profile sunk
//!    into the binder with its new feet rounded (`runout`), so the drawn radii stay.
//! 3. **Rules** (step 3): where the designer gives rule points (positions across each
//!    key section that belong together, such as the crests of a round and a double
//!    bead), corresponding points are matched piece by piece between them, so the rule
//!    curves run through the same feature of every section; without rules the whole
//!    profile is matched by arc length.
//! 4. **Skinning** (step 4): sections every `spacing` (more where the skin would
//!    leave the binder) are placed in vertical planes across the bead, dropped onto the
//!    binder, raised by the profile square to the binder, and skinned by [`loft`];
//!    every section, foot line and rule is an iso-curve of the surface.
//!
//! The centre line resampled every `line_spacing` is the *line bead* of forming
//! simulation (a polyline with a restraining force). The course is dropped onto the
//! binder along press Z, the direction the binder closes in; the profile's heights
//! stand square to the binder's trace in each section plane ([`raised`]), so a bead
//! across a sloping binder keeps its drawn radii.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::die::figures::{surface_figures, SurfaceFigures};
use crate::geom::construct::{loft, section_parameters, Loft};
use crate::geom::curvature::{curvature_steps, principal_of};
use crate::geom::curve::ArcLengths;
use crate::geom::interpolate::{interpolate, interpolate_at, Interpolation};
use crate::geom::inversion::project_to_curve_near;
use crate::geom::{Curve2, Curve3, Direction, GeomError, NurbsSurface};

mod binder;
mod course;
mod profiles;
mod runout;

pub use binder::Binder;
use course::CourseMap;
use profiles::{matched_profiles, MatchedProfiles};

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
    /// Largest distance (mm, in the section plane) between a section's points and the
    /// profile they should follow, standing square to the binder's trace.
    pub section_error: f64,
    /// Number of sections skinned.
    pub sections: usize,
    /// Length (mm) of the centre line on the binder.
    pub length: f64,
    /// The tallest point (mm) of the bead above the binder (square to its trace across
    /// the bead).
    pub height: f64,
    /// Narrowest and widest distance (mm, top view) between the feet.
    pub width: (f64, f64),
    /// The smallest radius of curvature (mm) of the skin over its full-height part
    /// (outside the tapered ends), sampled [`RADIUS_SAMPLES_PER_SPAN`] times across
    /// every knot span of every section and half-way between sections.
    pub min_radius: f64,
    /// Where [`Self::min_radius`] was found.
    pub min_radius_at: DVec3,
    /// The smallest radius (mm) within the tapered ends, where the height runs out;
    /// [`Self::min_radius`] when the bead has no taper.
    pub end_min_radius: f64,
    /// The smallest radius (mm) drawn in the key sections' profiles (their arcs), the
    /// figure the skin's radii answer to; infinite for profiles without a bend.
    pub drawn_radius: f64,
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
    /// The skin's figures as every die-face surface is measured ([`surface_figures`]:
    /// its draft and undercut, its smallest radius on the common grid), measured
    /// beside the bead's own quality work.
    pub figures: SurfaceFigures,
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

/// How far (mm, across the bead in the top view) a rule may drift between two
/// sections from where the section there has it before a section is added between them.
const RULE_TOLERANCE: f64 = 0.0005;

/// Rounds of section insertion.
const MAX_REFINEMENTS: usize = 6;

/// The most sections a bead may take (a 4 m bead at 2 mm).
const MAX_SECTIONS: usize = 2000;

/// The most line-bead points a bead may take.
const MAX_LINE_POINTS: usize = 100_000;

/// Samples along each foot for the foot-gap figure.
pub const FOOT_SAMPLES: usize = 400;

/// Builds a bead on `binder` (module documentation).
///
/// The binder remembers where it last found a point (the next search starts there),
/// so the steps ask it in a fixed order; they are kept in that order here.
pub fn build(binder: &Binder, spec: &BeadSpec) -> Result<Bead, Problem> {
    check_lengths(spec)?;
    let course = CourseMap::new(&spec.course)?;
    check_course(spec, &course)?;
    let ats = key_positions(spec, course.length)?;
    // The profiles matched and the turns checked beside step 1, the centre line on the
    // binder (the first question the binder is asked); the problems in that order.
    let (profiles, centre) = beside(
        || -> Result<_, Problem> {
            let profiles = matched_profiles(spec, &ats)?;
            check_turns(&course, &profiles)?;
            Ok(profiles)
        },
        || centre_line(binder, &course),
    );
    let profiles = profiles?;
    let centre = centre?;
    // Steps 2-3: a section at any fraction along the bead, from the matched profiles.
    let maker = SectionMaker {
        course: &course,
        profiles: &profiles,
        taper: spec.taper,
    };
    // Step 4: sections along the bead, skinned and refined; beside it, the line bead.
    let (line_bead, skin) = beside(
        || line_bead(&centre, spec.line_spacing),
        || refined_skin(binder, &maker, initial_stations(&course, spec, &ats)),
    );
    let skin = skin?;
    // The sections run across from the right foot to the left, so S_u x S_v points
    // down; the skin is turned round in u to face up like the binder under it.
    let surface = skin.surface.reversed(Direction::U);

    // Quality: the feet on the binder, and every section at the height it should have
    // (asking the binder); beside them, the skin's radii and figures.
    let questions = BinderQuestions::new(&maker, spec, &ats, &skin, &surface);
    let (shape, answers) = beside(
        || {
            let radii = skin_radii(
                &surface,
                &skin.sections,
                &skin.stations,
                spec.taper / course.length,
            );
            (radii, surface_figures(&surface))
        },
        || questions.answers(binder),
    );
    let (foot_gap, height, section_error) = answers?.figures()?;
    let key_sections = key_sections(&ats, &skin.stations, &skin.sections);
    let (radii, figures) = shape;
    let radii = radii?;
    let drawn_radius = profiles.drawn;
    let rules = profiles
        .rule_params
        .iter()
        .map(|&u| surface.iso_curve(Direction::U, 1.0 - u))
        .collect();
    let (line_points, length) = line_bead?;
    Ok(Bead {
        surface,
        centre,
        line_points,
        sections: key_sections,
        rules,
        quality: BeadQuality {
            foot_gap,
            section_error,
            sections: skin.sections.len(),
            length,
            height,
            width: (skin.narrow, skin.wide),
            min_radius: radii.full,
            min_radius_at: radii.full_at,
            end_min_radius: radii.ends,
            drawn_radius,
        },
        figures,
    })
}

/// Runs `pure` (work on its own) on the thread pool beside `ordered` (work that asks the
/// binder, which must stay on this thread: the binder remembers where it last found a
/// point) and waits for both.
fn beside<A: Send, B>(pure: impl FnOnce() -> A + Send, ordered: impl FnOnce() -> B) -> (A, B) {
    let mut done = None;
    let b = rayon::in_place_scope(|scope| {
        scope.spawn(|_| done = Some(pure()));
        ordered()
    });
    (done.expect("the scope waits for the work it spawned"), b)
}

/// Refuses a course the spec cannot be built on: a taper on a ring bead (it has no
/// ends), more sections or line-bead points than a bead may take, or tapers longer
/// together than the bead.
fn check_course(spec: &BeadSpec, course: &CourseMap) -> Result<(), Problem> {
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
    // A short taper is resolved by its own fine sections (`station_fractions`): a
    // taper of a micrometre would ask for millions of them.
    if spec.taper > 0.0 && spec.taper / (TAPER_SECTIONS as f64) < spec.spacing {
        let fine_zone = (spec.taper + spec.spacing).min(0.5 * course.length);
        let count = 2.0 * fine_zone / (spec.taper / TAPER_SECTIONS as f64);
        if count > MAX_SECTIONS as f64 {
            return Err(Problem::TooFine {
                what: "taper",
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
    Ok(())
}

/// Refuses a course that turns tighter than the profiles' reach across it (their feet
/// lines would fold), or kinks.
fn check_turns(course: &CourseMap, profiles: &MatchedProfiles) -> Result<(), Problem> {
    if let Some(problem) = course.too_tight(profiles) {
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
    Ok(())
}

/// Step 1: the centre line on the binder, sampled about every 2 mm and interpolated;
/// the course must stay over the binder and outside the opening.
fn centre_line(binder: &Binder, course: &CourseMap) -> Result<Curve3, Problem> {
    let samples = ((course.length / 2.0).ceil() as usize).clamp(8, 4000);
    let mut centre_points = Vec::with_capacity(samples + 1);
    for i in 0..=samples {
        let (c, _) = course.frame(i as f64 / samples as f64)?;
        centre_points.push(binder.base(c, Some(0.0))?);
    }
    Ok(interpolate(&centre_points, &Interpolation::default())?)
}

/// The points of a section raised by their heights above the binder, each square to the
/// binder's trace in the section plane (the line the binder points `bases` draw across
/// the bead, in order), not straight up: a profile raised along press Z on a binder that
/// slopes across the bead is sheared, and its radius on the downhill side comes out
/// tighter than drawn (a 3 mm shoulder at 2.6 mm on a 3 deg slope).
fn raised(bases: &[DVec3], heights: impl Iterator<Item = f64>) -> Vec<DVec3> {
    let (Some(first), Some(last)) = (bases.first(), bases.last()) else {
        return Vec::new();
    };
    // The section's points lie on one line across in the top view.
    let across = (last.truncate() - first.truncate()).normalize_or_zero();
    let offsets: Vec<f64> = bases
        .iter()
        .map(|b| (b.truncate() - first.truncate()).dot(across))
        .collect();
    let trace: Vec<f64> = bases.iter().map(|b| b.z).collect();
    bases
        .iter()
        .zip(trace_slopes(&offsets, &trace))
        .zip(heights)
        .map(|((&base, slope), h)| {
            // The trace's normal in the section plane: its tangent turned a quarter up.
            let cos = 1.0 / slope.hypot(1.0);
            base + (-across * slope * cos).extend(cos) * h
        })
        .collect()
}

/// The binder trace's slope (rise per unit across) at each of its points, from their
/// neighbours (one-sided at the ends; 0 where they do not spread across).
fn trace_slopes(offsets: &[f64], trace: &[f64]) -> Vec<f64> {
    let n = offsets.len().min(trace.len());
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            let run = offsets[b] - offsets[a];
            if run.abs() > 0.0 {
                (trace[b] - trace[a]) / run
            } else {
                0.0
            }
        })
        .collect()
}

/// Points of one section, in order across, measured in the frame [`raised`] builds
/// them in: each point's (offset across, height) from the binder's trace, square to it.
/// `offsets` are the points' top-view offsets across, `vertical` their heights straight
/// above the binder and `trace` the binder's heights under them. A point `v` above the
/// trace where it climbs at angle `a` across stands `v cos a` square to it, above the
/// trace point `v sin a cos a` further across.
fn square_to_trace(offsets: &[f64], vertical: &[f64], trace: &[f64]) -> Vec<(f64, f64)> {
    trace_slopes(offsets, trace)
        .into_iter()
        .zip(offsets.iter().zip(vertical))
        .map(|(slope, (&offset, &v))| {
            let cos = 1.0 / slope.hypot(1.0);
            (offset + v * slope * cos * cos, v * cos)
        })
        .collect()
}

/// Steps 2-3: makes the bead's section at any fraction along it, in three steps: laid
/// out in the top view ([`SectionMaker::layout`], on its own for each section, so
/// sections are laid out in parallel), dropped onto the binder
/// ([`SectionMaker::on_binder`], in the order the binder is asked, see [`build`]), and
/// interpolated ([`SectionMaker::curve`], again on its own).
struct SectionMaker<'a> {
    course: &'a CourseMap,
    profiles: &'a MatchedProfiles,
    /// The taper length (mm).
    taper: f64,
}

/// A section laid out in the top view, before the binder is under it.
struct Layout {
    /// Per point across the section: its top-view point, its offset (mm) across from
    /// the centre line, and its height above the binder.
    points: Vec<(DVec2, f64, f64)>,
    /// Where the offset line folds (the turn is tighter than the point's reach), the
    /// problem met right after `points`.
    folds: Option<Problem>,
}

impl SectionMaker<'_> {
    /// The section at fraction `along` of the bead laid out in the top view: the matched
    /// profiles blended there and run out by the taper, stretched to the boundaries
    /// when there are two, and laid across the course; up to the first point where
    /// the offset line folds.
    fn layout(&self, along: f64) -> Result<Layout, Problem> {
        let (course, profiles, length) = (self.course, self.profiles, self.course.length);
        let (c, across, turn) = course.frame_and_turn(along)?;
        let height_factor = taper_factor(along * length, length, self.taper);
        let rate = taper_rate(along * length, length, self.taper);
        let shape = profiles.shape(along, height_factor, rate);
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
                let folds = Problem::TooTight {
                    at: c,
                    radius: 1.0 / turn.abs(),
                    reach: offset.abs(),
                };
                return Ok(Layout {
                    points,
                    folds: Some(folds),
                });
            }
            points.push((c + across * offset, offset, q.y));
        }
        Ok(Layout {
            points,
            folds: None,
        })
    }

    /// The laid-out section's points on `binder`, raised by the profile's heights.
    fn on_binder(binder: &Binder, layout: &Layout) -> Result<Vec<DVec3>, Problem> {
        let mut bases = Vec::with_capacity(layout.points.len());
        for &(p, offset, _) in &layout.points {
            bases.push(binder.base(p, Some(offset))?);
        }
        let points = raised(&bases, layout.points.iter().map(|&(_, _, h)| h));
        match &layout.folds {
            Some(problem) => Err(problem.clone()),
            None => Ok(points),
        }
    }

    /// The section through `points` (on the binder) and its top-view width,
    /// interpolated by a quadratic.
    fn curve(&self, points: &[DVec3]) -> Result<(Curve3, f64), Problem> {
        let width = points[0]
            .truncate()
            .distance(points[points.len() - 1].truncate());
        // Quadratic: a C2 cubic through the points of a profile whose curvature jumps
        // where two of its pieces meet overshoots by about an eighth of the jump on
        // either side (a 3 mm shoulder next to a 6 mm crest came out at 2.33 mm); the
        // quadratic, C1 like the profile itself, overshoots less.
        let curve = interpolate_at(
            points,
            &self.profiles.params,
            &Interpolation {
                degree: 2,
                ..Interpolation::default()
            },
        )?;
        Ok((curve, width))
    }

    /// The sections at the fractions `layouts` were laid out at (see
    /// [`SectionMaker::layout`]): dropped onto `binder` one after the other, then
    /// interpolated in parallel. The problem reported is the one the sections made one
    /// by one would meet first.
    fn sections(
        &self,
        binder: &Binder,
        layouts: Vec<Result<Layout, Problem>>,
    ) -> Result<Vec<(Curve3, f64)>, Problem> {
        let (dropped, stop) = in_order(layouts, |layout| {
            layout.and_then(|l| Self::on_binder(binder, &l))
        });
        let curves = dropped
            .par_iter()
            .map(|points| self.curve(points))
            .collect();
        first_problem(curves, stop)
    }

    /// The sections at the fractions `alongs`, laid out in parallel (see
    /// [`SectionMaker::sections`]).
    fn sections_at(&self, binder: &Binder, alongs: &[f64]) -> Result<Vec<(Curve3, f64)>, Problem> {
        let layouts = alongs.par_iter().map(|&a| self.layout(a)).collect();
        self.sections(binder, layouts)
    }
}

/// Works `items` through `ask` in order (questions to the binder, each starting where
/// the last one ended) up to the first problem: the answers before it, and the problem.
fn in_order<T, U>(
    items: impl IntoIterator<Item = T>,
    mut ask: impl FnMut(T) -> Result<U, Problem>,
) -> (Vec<U>, Option<Problem>) {
    let mut answers = Vec::new();
    for item in items {
        match ask(item) {
            Ok(answer) => answers.push(answer),
            Err(problem) => return (answers, Some(problem)),
        }
    }
    (answers, None)
}

/// The results of work split into a part in order (which stopped at `stop`, if it
/// did) and a part done in parallel afterwards (`results`, in the order of the items):
/// the problem met first when each item is worked through in turn (the first failed
/// result, which comes before the item that stopped), or all the results.
fn first_problem<T>(
    results: Vec<Result<T, Problem>>,
    stop: Option<Problem>,
) -> Result<Vec<T>, Problem> {
    let results = results.into_iter().collect::<Result<Vec<T>, Problem>>()?;
    match stop {
        Some(problem) => Err(problem),
        None => Ok(results),
    }
}

/// Where the first sections go, as fractions of the bead: every `spacing` (closer in
/// the tapered ends, [`station_fractions`]) and at every key section (`ats`).
fn initial_stations(course: &CourseMap, spec: &BeadSpec, ats: &[f64]) -> Vec<f64> {
    let mut stations = station_fractions(course.length, spec.spacing, spec.taper);
    for &at in ats {
        let i = stations.partition_point(|&x| x < at);
        let near = |j: usize| stations.get(j).is_some_and(|&x| (x - at).abs() < 1e-9);
        let present = near(i) || (i > 0 && near(i - 1));
        if !present {
            stations.insert(i, at);
        }
    }
    stations
}

/// The skinned bead before it is turned to face up.
struct Skin {
    /// The sections' fractions along the bead, increasing.
    stations: Vec<f64>,
    /// The section at each station.
    sections: Vec<Curve3>,
    /// The skin through them (u from the right foot to the left).
    surface: NurbsSurface,
    /// The narrowest section's top-view width (mm).
    narrow: f64,
    /// The widest section's top-view width (mm).
    wide: f64,
}

/// Step 4: sections at `stations`, skinned; then, for up to [`MAX_REFINEMENTS`]
/// rounds, a section added half-way between two where the skin leaves what the
/// sections there should be ([`sections_needed`]), and skinned again.
fn refined_skin(
    binder: &Binder,
    maker: &SectionMaker,
    mut stations: Vec<f64>,
) -> Result<Skin, Problem> {
    let mut sections = Vec::with_capacity(stations.len());
    let (mut narrow, mut wide) = (f64::INFINITY, 0.0f64);
    for (s, w) in maker.sections_at(binder, &stations)? {
        narrow = narrow.min(w);
        wide = wide.max(w);
        sections.push(s);
    }
    let ring = maker.course.closed();
    let mut surface = skin(&sections, ring)?;
    for _ in 0..MAX_REFINEMENTS {
        let vs = section_parameters(&sections, Loft::default().parametrization)?;
        let halves: Vec<(f64, f64)> = (0..sections.len() - 1)
            .map(|k| {
                (
                    0.5 * (vs[k] + vs[k + 1]),
                    0.5 * (stations[k] + stations[k + 1]),
                )
            })
            .collect();
        let (needed, mut layouts) = sections_needed(binder, maker, &surface, &halves)?;
        let mut inserted = Vec::new();
        let mut inserted_layouts = Vec::new();
        for (k, &(_, along)) in halves.iter().enumerate() {
            if needed[k] {
                inserted.push(along);
                inserted_layouts.push(layouts[k].take());
            }
        }
        if inserted.is_empty() {
            break;
        }
        // Laid out for the check, or (without rules) only now, for the sections added.
        let missing: Vec<usize> = (0..inserted.len())
            .filter(|&i| inserted_layouts[i].is_none())
            .collect();
        let made: Vec<Result<Layout, Problem>> = missing
            .par_iter()
            .map(|&i| maker.layout(inserted[i]))
            .collect();
        for (i, layout) in missing.into_iter().zip(made) {
            inserted_layouts[i] = Some(layout);
        }
        let layouts = inserted_layouts.into_iter().flatten().collect();
        for (a, (s, w)) in inserted.into_iter().zip(maker.sections(binder, layouts)?) {
            let i = stations.partition_point(|&x| x < a);
            narrow = narrow.min(w);
            wide = wide.max(w);
            stations.insert(i, a);
            sections.insert(i, s);
        }
        surface = skin(&sections, ring)?;
    }
    Ok(Skin {
        stations,
        sections,
        surface,
        narrow,
        wide,
    })
}

/// What the binder answered for the check half-way between two sections.
enum HalfWay {
    /// The feet leave the binder: a section is needed.
    FeetOff,
    /// The feet are on the binder and there are no rules to check.
    Fine,
    /// The feet are on the binder; the exact section's points, for the rules' drift.
    Section(Vec<DVec3>),
}

/// Whether the skin needs a section half-way between each two, at `halves` (skin
/// parameter `v`, fraction `along`): its feet leave the binder there by more than
/// [`FOOT_TOLERANCE`], or a rule drifts off the feature it runs through, across the
/// bead, by more than [`RULE_TOLERANCE`]. With it, the sections laid out there (with
/// rules only). The binder is asked in the order of `halves`, each check's feet and then
/// its section; the rest is worked out in parallel.
#[allow(clippy::type_complexity)]
fn sections_needed(
    binder: &Binder,
    maker: &SectionMaker,
    surface: &NurbsSurface,
    halves: &[(f64, f64)],
) -> Result<(Vec<bool>, Vec<Option<Result<Layout, Problem>>>), Problem> {
    let rules = !maker.profiles.rule_params.is_empty();
    let prepared: Vec<([DVec3; 2], Option<Result<Layout, Problem>>)> = halves
        .par_iter()
        .map(|&(v, along)| (feet_at(surface, v), rules.then(|| maker.layout(along))))
        .collect();
    let (answers, stop) = in_order(&prepared, |(feet, layout)| {
        let gap = foot_gap_of(binder, feet)?;
        if gap > FOOT_TOLERANCE {
            return Ok(HalfWay::FeetOff);
        }
        match layout {
            None => Ok(HalfWay::Fine),
            Some(Err(problem)) => Err(problem.clone()),
            Some(Ok(layout)) => Ok(HalfWay::Section(SectionMaker::on_binder(binder, layout)?)),
        }
    });
    // The rules run through the same feature of every section; between two sections
    // they must not drift off it across the bead.
    let needed = answers
        .par_iter()
        .zip(halves)
        .map(|(answer, &(v, along))| match answer {
            HalfWay::FeetOff => Ok(true),
            HalfWay::Fine => Ok(false),
            HalfWay::Section(points) => {
                let (exact, _) = maker.curve(points)?;
                let (_, across) = maker.course.frame(along)?;
                Ok(maker.profiles.rule_params.iter().any(|&u| {
                    let drift = surface.point_at(u, v) - exact.point_at(u);
                    drift.truncate().dot(across).abs() > RULE_TOLERANCE
                }))
            }
        })
        .collect();
    let needed = first_problem(needed, stop)?;
    Ok((needed, prepared.into_iter().map(|(_, l)| l).collect()))
}

/// The quality figures that ask the binder (the foot gap, the height, the section
/// conformance), the points they ask about worked out first, in parallel.
struct BinderQuestions {
    /// The skin's feet at [`FOOT_SAMPLES`] places along it, for the foot gap.
    feet: Vec<[DVec3; 2]>,
    /// Every section's interpolated points, for the height.
    tops: Vec<Vec<DVec3>>,
    /// The sections measured for conformance ([`measured_key`]), sampled.
    conformance: Vec<Result<Conformance, Problem>>,
}

/// The binder's answers to [`BinderQuestions`]: the foot gap and the height, and the
/// heights above the binder of each measured section's samples (fewer for the last one
/// when the binder was missed under it, `stop`).
struct BinderAnswers<'q> {
    foot_gap: f64,
    height: f64,
    samples: Vec<(&'q Conformance, Vec<f64>)>,
    stop: Option<Problem>,
}

impl BinderQuestions {
    fn new(
        maker: &SectionMaker,
        spec: &BeadSpec,
        ats: &[f64],
        skin: &Skin,
        surface: &NurbsSurface,
    ) -> Self {
        let (v0, v1) = surface.domain_v();
        let feet = (0..=FOOT_SAMPLES)
            .into_par_iter()
            .map(|i| feet_at(surface, v0 + (v1 - v0) * i as f64 / FOOT_SAMPLES as f64))
            .collect();
        let params = &maker.profiles.params;
        let tops = skin
            .sections
            .par_iter()
            .map(|s| params.iter().map(|&u| s.point_at(u)).collect())
            .collect();
        let measured: Vec<(usize, f64, &Curve3)> = skin
            .sections
            .iter()
            .zip(&skin.stations)
            .enumerate()
            .filter_map(|(i, (section, &along))| {
                measured_key(spec, ats, i, along).map(|key| (key, along, section))
            })
            .collect();
        let conformance = measured
            .par_iter()
            .map(|&(key, along, section)| Conformance::new(maker, spec, key, along, section))
            .collect();
        Self {
            feet,
            tops,
            conformance,
        }
    }

    /// Asks `binder`, in order: the largest distance along Z between it and the skin's
    /// feet; the tallest point of the sections above it; the height above it of every
    /// conformance sample.
    fn answers(&self, binder: &Binder) -> Result<BinderAnswers<'_>, Problem> {
        let mut foot_gap = 0.0f64;
        for f in &self.feet {
            foot_gap = foot_gap.max(foot_gap_of(binder, f)?);
        }
        let mut height = 0.0f64;
        for section in &self.tops {
            // Square to the binder's trace across the section, as it was raised.
            let (Some(first), Some(last)) = (section.first(), section.last()) else {
                continue;
            };
            let across = (last.truncate() - first.truncate()).normalize_or_zero();
            let mut offsets = Vec::with_capacity(section.len());
            let mut vertical = Vec::with_capacity(section.len());
            let mut trace = Vec::with_capacity(section.len());
            for p in section {
                let base = binder.base(p.truncate(), None)?;
                offsets.push((p.truncate() - first.truncate()).dot(across));
                vertical.push(p.z - base.z);
                trace.push(base.z);
            }
            for (_, h) in square_to_trace(&offsets, &vertical, &trace) {
                height = height.max(h);
            }
        }
        let mut samples = Vec::with_capacity(self.conformance.len());
        let mut stop = None;
        'sections: for c in &self.conformance {
            let c = match c {
                Ok(c) => c,
                Err(problem) => {
                    stop = Some(problem.clone());
                    break;
                }
            };
            let mut hs = Vec::with_capacity(c.samples.len());
            for p in &c.samples {
                match binder.base(p.truncate(), None) {
                    Ok(base) => hs.push(p.z - base.z),
                    Err(problem) => {
                        // The samples measured before it come first.
                        samples.push((c, hs));
                        stop = Some(problem);
                        break 'sections;
                    }
                }
            }
            samples.push((c, hs));
        }
        Ok(BinderAnswers {
            foot_gap,
            height,
            samples,
            stop,
        })
    }
}

impl BinderAnswers<'_> {
    /// The foot gap, the height, and the section conformance (the section error): the
    /// largest [`Conformance::worst`] distance, the sections measured in parallel.
    fn figures(self) -> Result<(f64, f64, f64), Problem> {
        let errors = self.samples.par_iter().map(|(c, hs)| c.worst(hs)).collect();
        let errors = first_problem(errors, self.stop)?;
        let section_error = errors.into_iter().fold(0.0f64, f64::max);
        Ok((self.foot_gap, self.height, section_error))
    }
}

/// The sections at the key sections' positions (`ats`), in the order given.
fn key_sections(ats: &[f64], stations: &[f64], sections: &[Curve3]) -> Vec<Curve3> {
    ats.iter()
        .map(|&at| {
            let i = stations.partition_point(|&x| x < at - 1e-9);
            sections[i.min(sections.len() - 1)].clone()
        })
        .collect()
}

/// Which key section's exact profile the skinned section `i` at fraction `along` is
/// measured against for the section conformance, if it is measured: the key sections,
/// and every [`CONFORMANCE_STRIDE`]-th skinned section whose exact profile is known
/// (between two key sections with the same profile).
fn measured_key(spec: &BeadSpec, ats: &[f64], i: usize, along: f64) -> Option<usize> {
    let k = ats
        .partition_point(|&a| a < along - 1e-9)
        .min(ats.len() - 1);
    let at_key = (ats[k] - along).abs() <= 1e-9;
    if !at_key && i % CONFORMANCE_STRIDE != 0 {
        return None;
    }
    if at_key || k == 0 {
        Some(k)
    } else {
        let (a, b) = (&spec.sections[k - 1], &spec.sections[k]);
        (a.profile == b.profile && a.rules == b.rules).then_some(k - 1)
    }
}

/// The line bead: the centre line resampled every `spacing` (mm, evenly by arc
/// length, at least one interval), and its length.
fn line_bead(centre: &Curve3, spacing: f64) -> Result<(Vec<DVec3>, f64), Problem> {
    let centre_table = ArcLengths::new(centre);
    let length = centre_table.total();
    let n = ((length / spacing).ceil() as usize).max(1);
    let mut line_points = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let t = centre_table.parameter_at_fraction(i as f64 / n as f64)?;
        line_points.push(centre.point_at(t));
    }
    Ok((line_points, length))
}

/// Samples across a section for its conformance figure: four between every two
/// interpolated points.
const CONFORMANCE_SAMPLES: usize = 4 * SECTION_INTERVALS;

/// Every how many skinned sections one is measured for conformance (besides the key
/// sections): the sections are built alike, so a sample of them tells.
const CONFORMANCE_STRIDE: usize = 5;

/// A polyline through `points` (degree 1, knots at the chord lengths).
fn polyline(points: &[DVec2]) -> Result<Curve2, Problem> {
    let mut knots = vec![0.0, 0.0];
    let mut acc = 0.0;
    for w in points.windows(2).take(points.len().saturating_sub(2)) {
        acc += w[0].distance(w[1]).max(1e-12);
        knots.push(acc);
    }
    let last = acc
        + points[points.len() - 1]
            .distance(points[points.len() - 2])
            .max(1e-12);
    knots.extend([last, last]);
    Ok(Curve2::new(1, knots, points.to_vec())?)
}

/// How closely a skinned section follows its designer profile: the largest
/// distance, in the section plane, between the section's points (across offset, height
/// above the binder) and `exact`, the key section's profile (run out by the taper, see
/// [`runout`]), stretched to the boundaries, sampled between the interpolated points as
/// well as at them. Made in two steps around the binder: [`Conformance::new`] samples
/// the section, [`Conformance::worst`] measures it with the binder's heights under the
/// samples.
struct Conformance {
    /// The exact profile.
    exact: Curve2,
    /// The centre point and the direction across of the section's frame.
    frame: (DVec2, DVec2),
    /// The key profile's feet (s across).
    feet: (f64, f64),
    /// Where the section line meets the boundaries, if there are two.
    stretch: Option<(f64, f64)>,
    /// The section's samples.
    samples: Vec<DVec3>,
}

impl Conformance {
    /// The section `section` at fraction `at`, to be measured against key section
    /// `key` (its exact profile run out by the taper there).
    fn new(
        maker: &SectionMaker,
        spec: &BeadSpec,
        key: usize,
        at: f64,
        section: &Curve3,
    ) -> Result<Self, Problem> {
        let length = maker.course.length;
        let factor = taper_factor(at * length, length, spec.taper);
        let exact = if factor >= 1.0 {
            spec.sections[key].profile.clone()
        } else {
            let rate = taper_rate(at * length, length, spec.taper);
            polyline(&maker.profiles.run_out_of_key(key, factor, rate))?
        };
        let profile = &spec.sections[key].profile;
        let (c, across) = maker.course.frame(at)?;
        let feet = (profile.start_point().x, profile.end_point().x);
        let stretch = maker.course.feet(c, across)?;
        let (t0, t1) = section.domain();
        let samples = (0..=CONFORMANCE_SAMPLES)
            .map(|i| section.point_at(t0 + (t1 - t0) * i as f64 / CONFORMANCE_SAMPLES as f64))
            .collect();
        Ok(Self {
            exact,
            frame: (c, across),
            feet,
            stretch,
            samples,
        })
    }

    /// The largest distance of the samples from the exact profile, each sample at the
    /// height `heights` (in order; as many as there are, fewer when the binder was
    /// missed) above the binder.
    fn worst(&self, heights: &[f64]) -> Result<f64, Problem> {
        let (c, across) = self.frame;
        let (s0, s1) = self.feet;
        let exact = &self.exact;
        let mut worst = 0.0f64;
        let mut guess = exact.domain().0;
        // A run-out profile is a polyline: measured segment by segment.
        let polyline = (exact.degree() == 1).then(|| runout::Segments::new(exact.control_points()));
        let mut segment = 0;
        // As many samples as the binder answered for.
        let samples = &self.samples[..heights.len()];
        let offsets: Vec<f64> = samples
            .iter()
            .map(|p| (p.truncate() - c).dot(across))
            .collect();
        let trace: Vec<f64> = samples.iter().zip(heights).map(|(p, h)| p.z - h).collect();
        for (offset, h) in square_to_trace(&offsets, heights, &trace) {
            let s = match self.stretch {
                None => offset,
                Some((low, high)) => s0 + (offset - low) / (high - low) * (s1 - s0),
            };
            let target = DVec2::new(s, h);
            match &polyline {
                Some(segments) if target.is_finite() => {
                    worst = worst.max(segments.distance_from(target, &mut segment));
                }
                _ => {
                    let hit = project_to_curve_near(exact, target, guess)?;
                    guess = hit.t;
                    worst = worst.max(hit.distance);
                }
            }
        }
        Ok(worst)
    }
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

/// The surface's two feet at `v`.
fn feet_at(surface: &NurbsSurface, v: f64) -> [DVec3; 2] {
    let (u0, u1) = surface.domain_u();
    [surface.point_at(u0, v), surface.point_at(u1, v)]
}

/// The largest distance along Z between the binder and `feet`.
fn foot_gap_of(binder: &Binder, feet: &[DVec3; 2]) -> Result<f64, Problem> {
    let mut worst = 0.0f64;
    for p in feet {
        let base = binder.base(p.truncate(), None)?;
        worst = worst.max((p.z - base.z).abs());
    }
    Ok(worst)
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

/// How fast (per mm along the bead) [`taper_factor`] changes at `s`, in size.
fn taper_rate(s: f64, length: f64, taper: f64) -> f64 {
    if taper <= 0.0 {
        return 0.0;
    }
    let x = (s.min(length - s) / taper).clamp(0.0, 1.0);
    30.0 * x * x * (1.0 - x) * (1.0 - x) / taper
}

/// The quintic "smootherstep" `x^3 (10 - 15 x + 6 x^2)` on [0, 1]: 0 to 1 with zero
/// slope and zero curvature at both ends, so a taper or a blend meets the constant
/// part of the bead without a kink in curvature the skinning would overshoot on.
pub fn ease(x: f64) -> f64 {
    x * x * x * (10.0 + x * (6.0 * x - 15.0))
}

/// Samples across every knot span of the skin for its radius figures.
pub const RADIUS_SAMPLES_PER_SPAN: usize = 4;

/// Samples per key profile for its drawn radius.
const DRAWN_RADIUS_SAMPLES: usize = 2048;

/// The skin's smallest radii: over the full-height part (and where), and within the
/// tapered ends.
struct SkinRadii {
    full: f64,
    full_at: DVec3,
    ends: f64,
}

/// The smallest radius of curvature of the skin `surface` (lofted through `sections`
/// at the fractions `stations` along the bead), sampled at every section and half-way
/// between neighbours, [`RADIUS_SAMPLES_PER_SPAN`] times across each knot span and on
/// the near side of each knot, where a quadratic section's curvature jumps
/// ([`curvature_steps`]); split
/// into the full-height part and the tapered ends (the first and last `taper`
/// fraction of the bead).
fn skin_radii(
    surface: &NurbsSurface,
    sections: &[Curve3],
    stations: &[f64],
    taper: f64,
) -> Result<SkinRadii, Problem> {
    let vs = section_parameters(sections, Loft::default().parametrization)?;
    let mut along = Vec::with_capacity(2 * vs.len());
    for k in 0..vs.len() {
        along.push((vs[k], stations[k]));
        if k + 1 < vs.len() {
            along.push((
                0.5 * (vs[k] + vs[k + 1]),
                0.5 * (stations[k] + stations[k + 1]),
            ));
        }
    }
    let us = curvature_steps(
        surface.knots_u(),
        surface.degree_u(),
        RADIUS_SAMPLES_PER_SPAN,
    );
    let mut radii = SkinRadii {
        full: f64::INFINITY,
        full_at: surface.point_at(us[0], along[0].0),
        ends: f64::INFINITY,
    };
    // The fraction a hair inside the taper still counts as the end.
    let in_end = |f: f64| taper > 0.0 && (f < taper - 1e-9 || f > 1.0 - taper + 1e-9);
    // Every sample on its own, in parallel, with each u's and v's basis worked out
    // once; the smallest kept in order.
    let bases_u: Vec<_> = us.iter().map(|&u| surface.basis_u::<3>(u)).collect();
    let radii_along: Vec<Vec<(f64, f64, f64, f64)>> = along
        .par_iter()
        .map(|&(v, f)| {
            let bv = surface.basis_v::<3>(v);
            us.iter()
                .zip(&bases_u)
                .filter_map(|(&u, bu)| {
                    principal_of(&surface.derivatives_from(bu, &bv))
                        .map(|p| (u, v, f, p.min_radius()))
                })
                .collect()
        })
        .collect();
    for (u, v, f, r) in radii_along.into_iter().flatten() {
        if in_end(f) {
            radii.ends = radii.ends.min(r);
        } else if r < radii.full {
            radii.full = r;
            radii.full_at = surface.point_at(u, v);
        }
    }
    if taper <= 0.0 {
        radii.ends = radii.full;
    }
    Ok(radii)
}

/// The smallest radius of curvature drawn in a key profile: the tightest of its arcs,
/// sampled [`DRAWN_RADIUS_SAMPLES`] times and at every knot (infinite for a profile of
/// straight lines).
fn drawn_radius(profile: &Curve2) -> f64 {
    let (t0, t1) = profile.domain();
    let mut ts: Vec<f64> = (0..=DRAWN_RADIUS_SAMPLES)
        .map(|i| t0 + (t1 - t0) * i as f64 / DRAWN_RADIUS_SAMPLES as f64)
        .collect();
    ts.extend(profile.span_breaks());
    ts.iter()
        .map(|&t| profile.curvature(t))
        .filter(|k| k.is_finite())
        .fold(0.0f64, f64::max)
        .recip()
}
