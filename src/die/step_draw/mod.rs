//! The step draw (addendum) between the product outline and the punch opening line
//! (paper 001 section 4, eq. 5-9, Fig. 9-12; `docs/methods.md`).
//!
//! The two guides are the product outline `G_D`, which the step draw meets exactly, and
//! the punch opening line `G_U`, which it follows within a reported deviation (the crease
//! there is machined into a fillet anyway). The designer places key sections, each a
//! vertical plane through two top-view points (eq. 5) with a 2-D profile drawn in it from
//! the product to the opening. [`build`]:
//!
//! 1. finds where each section plane meets both guides, checks the profile reaches both
//!    points and never folds back, and approximates every profile by a non-rational
//!    cubic on one shared knot vector `U` (so all sections are compatible), running from
//!    `G_U` (u = 0) to `G_D` (u = 1);
//! 2. splits the guides at the sections into patches; in each patch the product piece
//!    keeps its own knots `V` (refined where the opening needs it: knot insertion does not
//!    move the product) and the opening piece is re-approximated at those knots, each
//!    product point matched with the opening point on its normal in the top view
//!    ([`matching`]; the paper matches by arc-length fraction, which slants the sections
//!    in corners and tightens the radii there): the guides are then compatible;
//! 3. puts an intermediate section at every knot of `V` (eq. 7-9): each end section is
//!    carried along `G_U` (translated, turned about Z with the guide), scaled (eq. 7) and
//!    rotated so its ends land on `G_U(v_j)` and `G_D(v_j)` (turned about Z, then tilted
//!    within its vertical plane, so sections stay vertical), the two blended linearly
//!    (eq. 8); the same anchored on `G_D`; the two results Hermite-blended across the
//!    section (eq. 9), on the control points;
//! 4. interpolates each row of section control points along the patch with end
//!    derivatives from Fig. 12: direction from the circle through the neighbouring rows'
//!    points, magnitude varying linearly across the section between the guides' end
//!    derivatives and matched across the boundary by eq. 4; the product row is the
//!    product piece itself. Patches are C1 where they meet, and the product edge is the
//!    outline.
//!
//! A product piece with a repeated knot (a C1 or C0 joint of the outline) is split there
//! into sub-patches whose shared section is computed like an intermediate one.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

mod along;
mod chain;
mod fit;
mod matching;
mod slant;
mod slopes;

use along::Along;
use chain::{align, Chain};
use fit::SectionBasis;
use matching::Matching;
use slant::{log_mean, obliquity, OpeningDirection};
use slopes::{BinderSlope, ProductSlope};

use super::continuity::{measure_join, JoinQuality};
use super::figures::{edge_samples, seam, Edge, Facing, Seam};
use crate::geom::curve::ArcLengths;
use crate::geom::interpolate::{interpolate_at, Interpolation, KnotPlacement};
use crate::geom::intersect::{intersect_curve_plane, Plane};
use crate::geom::inversion::{
    closest_point_on_curve, project_to_curve_locally, project_to_curve_near,
};
use crate::geom::join::join_curves;
use crate::geom::tessellate::{tessellate_curve, Tolerance};
use crate::geom::{Curve2, Curve3, GeomError, NurbsSurface};

/// The two guides.
#[derive(Debug, Clone, PartialEq)]
pub struct Guides {
    /// `G_D`: the product outline (cubic, non-rational).
    pub product: Curve3,
    /// `G_U`: the punch opening line.
    pub opening: Curve3,
    /// Whether the section sequence wraps around (both guides closed).
    pub closed: bool,
    /// The product surface the outline lies on, when known: the step draw then leaves
    /// it tangentially (its slope across the trim line starts every section).
    pub product_surface: Option<NurbsSurface>,
    /// The binder's patches, when known: the step draw then meets the binder
    /// tangentially across the punch opening line.
    pub binder: Vec<NurbsSurface>,
}

/// A key section as the designer gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionSpec {
    /// Its name.
    pub name: String,
    /// First top-view point: the plane's origin (s = 0).
    pub a: DVec2,
    /// Second top-view point: +s points from `a` towards it.
    pub b: DVec2,
    /// The profile in the plane, (s, z), from the product to the opening (either
    /// direction is accepted).
    pub profile: Curve2,
}

/// Where a section plane meets the guides, in the plane's (s, z) and in press
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionEnds {
    /// The product point (s, z).
    pub product: DVec2,
    /// The opening point (s, z).
    pub opening: DVec2,
    /// Parameter on `G_D`.
    pub product_t: f64,
    /// Parameter on `G_U`.
    pub opening_t: f64,
}

/// Options of [`build`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// How far (mm) a drawn profile's ends may lie from the guides (they are then moved
    /// onto them), and the accuracy asked of the profile approximation and of the
    /// opening-side guide.
    pub tolerance: f64,
    /// Start every section along the product's slope (when the product surface is
    /// known); `false` keeps each profile's drawn first direction (a deliberate crease
    /// at the trim line).
    pub tangent_product: bool,
    /// End every section along the binder's slope (when the binder is known); `false`
    /// keeps each profile's drawn last direction.
    pub tangent_binder: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            tolerance: 0.01,
            tangent_product: true,
            tangent_binder: true,
        }
    }
}

/// One patch of the step draw.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// `<left section>_to_<right section>`, with `_2`, `_3` for sub-patches.
    pub name: String,
    /// The surface: u along the outline (the guides' direction), v across from the
    /// opening (0) to the product (1), or reversed so the normal points up.
    pub surface: NurbsSurface,
    /// Whether v was reversed (then v = 0 is the product edge).
    pub reversed: bool,
    /// The sections at the knots, from `G_U` to `G_D` (key and intermediate).
    pub sections: Vec<Curve3>,
    /// The smallest radius drawn in the patch's two key sections (mm; infinite when
    /// they draw none): no radius on the patch may be much tighter.
    pub drawn_radius: f64,
}

/// Quality figures.
#[derive(Debug, Clone, PartialEq)]
pub struct Quality {
    /// Largest distance (mm) from the step draw's product edge to the product outline.
    pub product_gap: f64,
    /// Largest distance (mm) from the step draw's punch edge to the punch opening line.
    pub opening_deviation: f64,
    /// Largest distance (mm) between a key profile and its cubic approximation.
    pub section_fit: f64,
    /// Largest distance (mm) a drawn profile's end was moved onto its guide (within the
    /// tolerance).
    pub end_snap: f64,
    /// Largest distance (mm) a key section's product end slid along the outline onto a
    /// knot less than `SNAP_FRACTION` of a span away (which avoids sliver spans).
    pub knot_move: f64,
    /// Both moves for each key section, by name, in order.
    pub per_section: Vec<(String, SectionMoves)>,
    /// Every join between neighbouring patches.
    pub joins: Vec<(String, String, JoinQuality)>,
    /// Along the trim line: the gap and crease between the step draw and the product
    /// surface (when the product is given as a surface).
    pub trim: Option<Seam>,
    /// Along the punch opening line: the gap and crease between the step draw and the
    /// binder (when the binder is given).
    pub opening_seam: Option<Seam>,
}

/// How far one key section's ends were moved (mm): see [`Quality`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionMoves {
    /// The profile's ends onto the guides.
    pub end_snap: f64,
    /// The product end along the outline onto a knot.
    pub knot_move: f64,
}

/// The built step draw.
#[derive(Debug, Clone, PartialEq)]
pub struct StepDraw {
    /// Patches in order along the outline.
    pub patches: Vec<Patch>,
    /// The key sections in 3-D (exact profiles placed in their planes).
    pub key_sections: Vec<(String, Curve3)>,
    /// Quality figures.
    pub quality: Quality,
}

/// What went wrong, and at which section.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// Index of the culprit section (0 when it concerns the whole feature).
    pub section: usize,
    /// The problem.
    pub problem: Problem,
}

/// The problems [`build`] reports.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// Fewer sections than the outline needs.
    TooFewSections {
        /// Needed.
        needed: usize,
    },
    /// The section plane does not meet a guide.
    MissesGuide {
        /// `true` for the product outline, `false` for the opening.
        product: bool,
    },
    /// The profile's ends are not at the guides' points.
    EndsOffGuides {
        /// Where the product point is (s, z).
        product: DVec2,
        /// Where the opening point is (s, z).
        opening: DVec2,
        /// Largest distance of a profile end from its point.
        gap: f64,
    },
    /// The profile turns back towards where it came from.
    FoldsBack {
        /// The point (s, z) where it runs backwards.
        at: DVec2,
    },
    /// This section comes before the previous one along the outline.
    WrongOrder,
    /// The product outline is not a non-rational cubic.
    ProductNotCubic,
    /// A section between key sections cannot reach the opening point with its runs
    /// (every way of lengthening them would make one negative).
    CannotReach {
        /// The section's product point.
        at: DVec3,
    },
    /// The kernel failed.
    Kernel(GeomError),
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::TooFewSections { needed } => {
                write!(f, "the step draw needs at least {needed} sections")
            }
            Problem::MissesGuide { product: true } => {
                write!(f, "the section plane does not meet the product outline")
            }
            Problem::MissesGuide { product: false } => {
                write!(f, "the section plane does not meet the punch opening line")
            }
            Problem::EndsOffGuides { gap, .. } => {
                write!(f, "the profile's ends are {gap:.3} mm from the guides")
            }
            Problem::FoldsBack { at } => write!(
                f,
                "the profile folds back on itself near ({:.2}, {:.2})",
                at.x, at.y
            ),
            Problem::WrongOrder => write!(
                f,
                "this section comes before the previous one along the outline"
            ),
            Problem::ProductNotCubic => {
                write!(f, "the product outline must be a non-rational cubic curve")
            }
            Problem::CannotReach { at } => write!(
                f,
                "the section at ({:.2}, {:.2}, {:.2}) cannot reach the punch opening with its runs and corners",
                at.x, at.y, at.z
            ),
            Problem::Kernel(e) => write!(f, "{e}"),
        }
    }
}

impl From<GeomError> for Problem {
    fn from(e: GeomError) -> Self {
        Problem::Kernel(e)
    }
}

fn at(section: usize) -> impl Fn(GeomError) -> Error {
    move |e| Error {
        section,
        problem: Problem::Kernel(e),
    }
}

fn fail(section: usize, problem: Problem) -> Error {
    Error { section, problem }
}

/// Spans of the product piece shorter than this (mm) are not split further for the
/// opening's sake.
const MIN_SPAN: f64 = 2.0;

/// How long (mm) the flat on to the opening takes to turn onto the binder's slope (at
/// most 40 % of the flat). The turn is kept near the opening: the flat keeps its drawn
/// direction, so a binder whose slope across the opening changes along it does not
/// lever the die radius, a flat's length away, up and down.
const BINDER_BLEND: f64 = 20.0;

/// The share of the tolerance the step draw's punch edge may leave the opening line by:
/// the binder's inner edge is the opening line itself, so this is the gap along the
/// seam between step draw and binder (0.001 mm, a strict checker's limit, at the
/// default tolerance).
const OPENING_SHARE: f64 = 0.1;

/// The most distinct knots a patch's product piece gets by refinement.
const MAX_KNOTS: usize = 400;

/// Samples per patch for the quality figures.
pub const QUALITY_SAMPLES: usize = 1000;

/// Samples per boundary for the join figures.
pub const JOIN_SAMPLES: usize = 200;

/// The guides run counter-clockwise seen from above when closed (a closed guide drawn
/// clockwise is reversed), so the sections' order along both agrees.
pub fn oriented(guides: Guides) -> Guides {
    let ccw = |c: &Curve3| -> Curve3 {
        if !guides.closed {
            return c.clone();
        }
        let (t0, t1) = c.domain();
        let n = 256;
        let pts: Vec<DVec2> = (0..n)
            .map(|i| c.point_at(t0 + (t1 - t0) * i as f64 / n as f64).truncate())
            .collect();
        let area: f64 = (0..n).map(|k| pts[k].perp_dot(pts[(k + 1) % n])).sum();
        if area < 0.0 {
            c.reversed()
        } else {
            c.clone()
        }
    };
    Guides {
        product: ccw(&guides.product),
        opening: ccw(&guides.opening),
        ..guides
    }
}

/// Where the section plane through `a`, `b` meets the guides: the crossing of each
/// guide nearest to the segment `a b` in the top view.
pub fn section_ends(guides: &Guides, a: DVec2, b: DVec2) -> Result<SectionEnds, Problem> {
    let d = (b - a).normalize_or_zero();
    if d == DVec2::ZERO {
        return Err(Problem::Kernel(GeomError::ZeroVector {
            what: "section plane direction",
        }));
    }
    let plane = Plane::new(a.extend(0.0), DVec3::new(-d.y, d.x, 0.0)).map_err(Problem::Kernel)?;
    let pick = |curve: &Curve3, product: bool| -> Result<(f64, DVec2), Problem> {
        let hits = intersect_curve_plane(curve, &plane).map_err(Problem::Kernel)?;
        let len = a.distance(b);
        hits.iter()
            .map(|h| {
                let s = (h.point.truncate() - a).dot(d);
                let off = if s < 0.0 {
                    -s
                } else if s > len {
                    s - len
                } else {
                    0.0
                };
                (off, h.t, DVec2::new(s, h.point.z))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map(|(_, t, p)| (t, p))
            .ok_or(Problem::MissesGuide { product })
    };
    let (product_t, product) = pick(&guides.product, true)?;
    let (opening_t, opening) = pick(&guides.opening, false)?;
    Ok(SectionEnds {
        product,
        opening,
        product_t,
        opening_t,
    })
}

/// Builds the step draw (module documentation).
pub fn build(guides: &Guides, sections: &[SectionSpec], opts: &Options) -> Result<StepDraw, Error> {
    check_inputs(guides, sections)?;
    let tol = opts.tolerance;

    // Step 1: ends, orientation, folds, placement.
    let product_knots: Vec<f64> = guides
        .product
        .knots()
        .distinct()
        .iter()
        .map(|&(k, _)| k)
        .collect();
    let opening_direction = OpeningDirection::new(&guides.opening, guides.closed);
    let placed = sections
        .iter()
        .enumerate()
        .map(|(k, s)| place_key_section(guides, k, s, &product_knots, &opening_direction, tol))
        .collect::<Result<Vec<_>, _>>()?;
    let ends: Vec<SectionEnds> = placed.iter().map(|p| p.ends).collect();
    check_sections_in_order(&ends, guides.closed)?;

    // Step 1 (continued): one list of corners for all key sections, one knot vector
    // for every section, and the key sections' runs and corners carried along the
    // outline by their positions on it.
    let key_chains: Vec<Chain> = placed.iter().map(|p| p.chain.clone()).collect();
    let binder_tangent = opts.tangent_binder && !guides.binder.is_empty();
    let aligned = aligned_chains(&key_chains, binder_tangent);
    let basis = SectionBasis::new(&aligned).map_err(at(0))?;
    let (positions, outline_length) = outline_positions(&guides.product, &ends, guides.closed);
    let along = Along::new(
        positions.clone(),
        aligned,
        guides.closed.then_some(outline_length),
    );
    let stations = Stations {
        along: &along,
        basis: &basis,
        opening: &opening_direction,
        product: guides
            .product_surface
            .as_ref()
            .filter(|_| opts.tangent_product)
            .map(ProductSlope::new),
        binder: binder_tangent.then(|| BinderSlope::new(&guides.binder)),
    };
    let KeySections {
        curves: key_sections,
        section_fit,
        starts,
    } = key_sections(guides, sections, &ends, &positions, &stations)?;
    let u_knots = key_sections[0].1.knots().as_slice().to_vec();

    // Step 2-3: patches, their guides and sections.
    let subs = sub_patches(
        guides,
        sections,
        &placed,
        &positions,
        &stations,
        (&key_sections, &starts),
        tol,
    )?;
    // Step 4: rows with the Fig. 12 end derivatives.
    let patches = interpolate_rows(&subs, &u_knots, guides.closed)?;

    let per_section = sections
        .iter()
        .zip(&placed)
        .map(|(s, p)| (s.name.clone(), p.moves))
        .collect();
    let quality = quality(guides, &patches, tol, per_section, section_fit)?;
    Ok(StepDraw {
        patches,
        key_sections,
        quality,
    })
}

/// Refuses what no step draw can be built from: fewer key sections than the outline
/// needs (two for an open one, three for a closed one), or a product outline that is
/// not a non-rational cubic (its knots become the patches' knots along the outline).
fn check_inputs(guides: &Guides, sections: &[SectionSpec]) -> Result<(), Error> {
    let needed = if guides.closed { 3 } else { 2 };
    if sections.len() < needed {
        return Err(fail(
            sections.len().saturating_sub(1),
            Problem::TooFewSections { needed },
        ));
    }
    let product = &guides.product;
    if product.degree() != 3 || product.is_rational() {
        return Err(fail(0, Problem::ProductNotCubic));
    }
    Ok(())
}

/// A key section placed on the guides.
struct PlacedSection {
    /// Where its plane meets the guides (the product end moved onto a nearby knot).
    ends: SectionEnds,
    /// Its drawing as runs and corners from the product end, x = 0 there and growing
    /// towards the opening, with the plane's obliquity.
    chain: Chain,
    /// How far its ends were moved.
    moves: SectionMoves,
}

/// Places key section `k` (`s`) on the guides (step 1): where its plane meets them,
/// its product end moved onto a knot of the outline a sliver away (`product_knots`),
/// its profile turned to run from the opening to the product, checked to reach both
/// guides within `tol` and never to fold back, and drawn as a chain from the product.
fn place_key_section(
    guides: &Guides,
    k: usize,
    s: &SectionSpec,
    product_knots: &[f64],
    opening_direction: &OpeningDirection,
    tol: f64,
) -> Result<PlacedSection, Error> {
    let product = &guides.product;
    let mut e = section_ends(guides, s.a, s.b).map_err(|p| fail(k, p))?;
    // A cut just beside a knot of the outline would leave a sliver span (a kink in
    // every row there): the section's product end moves along the outline onto the
    // knot instead, a fraction of a span away; the move counts in `knot_move`.
    let snapped = snap_to_knot(product_knots, e.product_t);
    let mut knot_move = 0.0;
    if snapped != e.product_t {
        knot_move = product
            .point_at(snapped)
            .distance(product.point_at(e.product_t));
        e.product_t = snapped;
    }
    let (p0, p1) = (s.profile.start_point(), s.profile.end_point());
    let forward = p0.distance(e.product) + p1.distance(e.opening);
    let backward = p1.distance(e.product) + p0.distance(e.opening);
    // u = 0 at the opening, u = 1 at the product.
    let profile = if forward <= backward {
        s.profile.reversed()
    } else {
        s.profile.clone()
    };
    let gap = profile
        .start_point()
        .distance(e.opening)
        .max(profile.end_point().distance(e.product));
    if gap > tol {
        return Err(fail(
            k,
            Problem::EndsOffGuides {
                product: e.product,
                opening: e.opening,
                gap,
            },
        ));
    }
    let moves = SectionMoves {
        end_snap: gap,
        knot_move,
    };
    check_no_fold(&profile, e).map_err(|p| fail(k, p))?;
    // The profile from the product to the opening, in (x, z): x = 0 at the
    // product, growing towards the opening.
    let sign = if e.opening.x >= e.product.x {
        1.0
    } else {
        -1.0
    };
    let drawn = profile
        .reversed()
        .map_points(|p: DVec2| DVec2::new((p.x - e.product.x) * sign, p.y));
    let c = obliquity(
        (s.b - s.a).normalize_or_zero().extend(0.0),
        (
            opening_direction
                .at(e.opening_t)
                .map_err(|g| fail(k, g.into()))?,
            product.derivative_at(e.product_t),
        ),
    );
    let mut chain = Chain::from_curve(&drawn);
    chain.start = DVec2::new(0.0, e.product.y);
    chain.obliquity = c;
    Ok(PlacedSection {
        ends: e,
        chain,
        moves,
    })
}

/// The key sections must come in order along both guides (cyclically on closed ones).
fn check_sections_in_order(ends: &[SectionEnds], closed: bool) -> Result<(), Error> {
    check_order(
        &ends.iter().map(|e| e.product_t).collect::<Vec<_>>(),
        closed,
    )?;
    check_order(
        &ends.iter().map(|e| e.opening_t).collect::<Vec<_>>(),
        closed,
    )
}

/// The key sections' chains with one list of corners for all ([`align`]); with
/// `binder_tangent`, each gets a last corner that turns its last run onto the binder
/// over its last [`BINDER_BLEND`] (a corner of no drawn turn whose outgoing run, of no
/// length, takes the binder's slope at each section).
fn aligned_chains(key_chains: &[Chain], binder_tangent: bool) -> Vec<Chain> {
    let mut aligned = align(key_chains);
    if binder_tangent {
        for c in &mut aligned {
            let last = *c.runs.last().expect("a chain always has a run");
            c.radii
                .push(BINDER_BLEND.min(0.4 * last.length) / chain::GENTLE_TURN);
            c.runs.push(chain::Run {
                angle: last.angle,
                length: 0.0,
            });
        }
    }
    aligned
}

/// Each key section's position along the product outline (mm from the first key
/// section, modulo the outline's length when `closed`), and that length: where
/// [`Along`] carries the runs and corners from.
fn outline_positions(product: &Curve3, ends: &[SectionEnds], closed: bool) -> (Vec<f64>, f64) {
    let outline = ArcFractions::new(product);
    let origin = outline.fraction_at(ends[0].product_t) * outline.total;
    let positions = ends
        .iter()
        .map(|e| {
            let s = outline.fraction_at(e.product_t) * outline.total - origin;
            if closed {
                s.rem_euclid(outline.total)
            } else {
                s
            }
        })
        .collect();
    (positions, outline.total)
}

/// The key sections themselves, as built by `stations` (named, in 3-D), and how closely
/// their cubics follow the exact runs and corners (the largest distance).
fn key_sections(
    guides: &Guides,
    sections: &[SectionSpec],
    ends: &[SectionEnds],
    positions: &[f64],
    stations: &Stations,
) -> Result<KeySections, Error> {
    let mut key_sections = Vec::with_capacity(sections.len());
    let mut starts = Vec::with_capacity(sections.len());
    let mut section_fit: f64 = 0.0;
    for (k, e) in ends.iter().enumerate() {
        let (a, b) = (
            guides.opening.point_at(e.opening_t),
            guides.product.point_at(e.product_t),
        );
        let tangents = (
            stations
                .opening
                .at(e.opening_t)
                .map_err(|g| fail(k, g.into()))?,
            guides.product.derivative_at(e.product_t),
        );
        let (curve, error) = stations
            .section_with_error(positions[k], (a, b), tangents)
            .map_err(|p| fail(k, p))?;
        section_fit = section_fit.max(error);
        key_sections.push((sections[k].name.clone(), curve));
        starts.push(SlopeStart::of(stations));
    }
    Ok(KeySections {
        curves: key_sections,
        section_fit,
        starts,
    })
}

/// The key sections built as their stations, in order.
struct KeySections {
    /// Each key section's name and curve.
    curves: Vec<(String, Curve3)>,
    /// The largest distance of a key section from its exact runs and corners.
    section_fit: f64,
    /// Where the slopes' look-ups ended at each key section.
    starts: Vec<SlopeStart>,
}

/// Steps 2-3: the sub-patches between each key section and the next (round to the
/// first on a closed outline), in order along it, named `<left>_to_<right>` (`_2`,
/// `_3` for a patch split at a joint of the outline), each with the smaller drawn
/// radius of its two key sections.
fn sub_patches(
    guides: &Guides,
    sections: &[SectionSpec],
    placed: &[PlacedSection],
    positions: &[f64],
    stations: &Stations,
    (keys, starts): (&[(String, Curve3)], &[SlopeStart]),
    tol: f64,
) -> Result<Vec<SubPatch>, Error> {
    let n = sections.len();
    let patch_count = if guides.closed { n } else { n - 1 };
    let inputs = StationInputs::of(stations);
    // Each patch on its own (side by side), with its own slope look-ups.
    let built: Vec<Result<Vec<SubPatch>, Error>> = (0..patch_count)
        .into_par_iter()
        .map(|k| {
            let next = (k + 1) % n;
            patch(
                guides,
                (&placed[k].ends, &placed[next].ends),
                (&keys[k].1, &keys[next].1),
                positions[k],
                &inputs.stations(starts[k]),
                tol,
            )
            .map_err(|p| fail(next, p))
        })
        .collect();
    let mut chain: Vec<SubPatch> = Vec::new();
    for (k, subs) in built.into_iter().enumerate() {
        let next = (k + 1) % n;
        let subs = subs?;
        let base = format!("{}_to_{}", sections[k].name, sections[next].name);
        let drawn = drawn_radius(&placed[k].chain).min(drawn_radius(&placed[next].chain));
        let count = subs.len();
        for (i, mut s) in subs.into_iter().enumerate() {
            s.drawn_radius = drawn;
            s.name = if i == 0 || count == 1 {
                base.clone()
            } else {
                format!("{base}_{}", i + 1)
            };
            chain.push(s);
        }
    }
    Ok(chain)
}

/// Step 4: each sub-patch's surface, its rows of section control points interpolated
/// along it with the Fig. 12 end derivatives shared with its neighbours (free ends at
/// the ends of an open outline), turned so its normal points up.
fn interpolate_rows(
    chain: &[SubPatch],
    u_knots: &[f64],
    closed: bool,
) -> Result<Vec<Patch>, Error> {
    let m = u_knots.len() - 4;
    let nodes = greville(u_knots, m);
    let count = chain.len();
    let mut patches = Vec::with_capacity(count);
    for (c, sub) in chain.iter().enumerate() {
        let prev = if c > 0 {
            Some(&chain[c - 1])
        } else if closed {
            chain.last()
        } else {
            None
        };
        let next = if c + 1 < count {
            Some(&chain[c + 1])
        } else if closed {
            chain.first()
        } else {
            None
        };
        let start = boundary_derivatives(prev, sub, &nodes, End::Start);
        let end = boundary_derivatives(Some(sub), next.unwrap_or(sub), &nodes, End::End);
        let end = if next.is_none() {
            open_end_derivatives(sub, &nodes, End::End)
        } else {
            end
        };
        let start = if prev.is_none() {
            open_end_derivatives(sub, &nodes, End::Start)
        } else {
            start
        };
        let surface = rows_to_surface(sub, u_knots, &start, &end).map_err(at(0))?;
        let (surface, reversed) = upward(surface);
        patches.push(Patch {
            name: sub.name.clone(),
            surface,
            reversed,
            sections: sub.sections.clone(),
            drawn_radius: sub.drawn_radius,
        });
    }
    Ok(patches)
}

/// The step draw's quality figures: its edges against the guides, the joins between
/// neighbouring patches, the seams with the product and the binder, and the key
/// sections' moves (`per_section`) and fit (`section_fit`).
fn quality(
    guides: &Guides,
    patches: &[Patch],
    tol: f64,
    per_section: Vec<(String, SectionMoves)>,
    section_fit: f64,
) -> Result<Quality, Error> {
    let (product_gap, opening_deviation) = edge_deviations(guides, patches, tol)?;
    let joins = joins(patches, guides.closed);
    let (trim, opening_seam) = seams(guides, patches)?;
    Ok(Quality {
        product_gap,
        opening_deviation,
        section_fit,
        end_snap: per_section
            .iter()
            .map(|(_, m)| m.end_snap)
            .fold(0.0, f64::max),
        knot_move: per_section
            .iter()
            .map(|(_, m)| m.knot_move)
            .fold(0.0, f64::max),
        per_section,
        joins,
        trim,
        opening_seam,
    })
}

/// The largest distance from the patches' product edges to the product outline, and
/// from their punch edges to the opening line. The latter is measured to the opening
/// line tessellated to a hundredth of `tol` (its chords are that close to it).
fn edge_deviations(guides: &Guides, patches: &[Patch], tol: f64) -> Result<(f64, f64), Error> {
    let opening_polyline = tessellate_curve(
        &guides.opening,
        &Tolerance::new(tol / 100.0).map_err(at(0))?,
    )
    .map_err(at(0))?
    .points;
    // Each patch on its own (in parallel); the largest of each is the same in any order.
    let per_patch: Vec<_> = patches
        .par_iter()
        .map(|p| {
            let (pv, ov) = if p.reversed { (0.0, 1.0) } else { (1.0, 0.0) };
            let product = edge_distance(&p.surface, pv, &guides.product);
            (product, edge_to_polyline(&p.surface, ov, &opening_polyline))
        })
        .collect();
    let mut product_gap: f64 = 0.0;
    let mut opening_deviation: f64 = 0.0;
    for (product, opening) in per_patch {
        product_gap = product_gap.max(product.map_err(at(0))?);
        opening_deviation = opening_deviation.max(opening);
    }
    Ok((product_gap, opening_deviation))
}

/// Every join between neighbouring patches (the last with the first on a closed
/// outline), measured at [`JOIN_SAMPLES`] points.
fn joins(patches: &[Patch], closed: bool) -> Vec<(String, String, JoinQuality)> {
    let count = patches.len();
    let pairs = if closed { count } else { count - 1 };
    (0..pairs)
        .into_par_iter()
        .map(|c| {
            let (a, b) = (&patches[c], &patches[(c + 1) % count]);
            (
                a.name.clone(),
                b.name.clone(),
                measure_join(&a.surface, &b.surface, JOIN_SAMPLES),
            )
        })
        .collect()
}

/// The worst gap and crease along the trim line (against the product surface, when
/// given) and along the punch opening line (against the binder, when given).
fn seams(guides: &Guides, patches: &[Patch]) -> Result<(Option<Seam>, Option<Seam>), Error> {
    let surfaces_edge = |p: &Patch, product_edge: bool| {
        let edge = match (product_edge, p.reversed) {
            (true, false) | (false, true) => Edge::V1,
            _ => Edge::V0,
        };
        edge_samples(&p.surface, edge, 4)
    };
    let product: Vec<Facing> = guides.product_surface.iter().map(Facing::new).collect();
    let binder: Vec<Facing> = guides.binder.par_iter().map(Facing::new).collect();
    // Each patch's two seams on their own (in parallel), then the worst in patch order.
    let per_patch: Vec<_> = patches
        .par_iter()
        .map(|p| {
            let patch = Facing::new(&p.surface);
            let trim = (!product.is_empty())
                .then(|| seam(patch, &surfaces_edge(p, true), &product))
                .transpose();
            let opening = (!binder.is_empty())
                .then(|| seam(patch, &surfaces_edge(p, false), &binder))
                .transpose();
            (trim, opening)
        })
        .collect();
    let mut trim: Option<Seam> = None;
    let mut opening_seam: Option<Seam> = None;
    for (t, o) in per_patch {
        if let Some(s) = t.map_err(at(0))? {
            trim = Some(worse_seam(trim, s));
        }
        if let Some(s) = o.map_err(at(0))? {
            opening_seam = Some(worse_seam(opening_seam, s));
        }
    }
    Ok((trim, opening_seam))
}

/// The worse of two seams' figures, each figure on its own.
fn worse_seam(a: Option<Seam>, b: Seam) -> Seam {
    let Some(a) = a else { return b };
    let (gap, gap_at) = if b.gap > a.gap {
        (b.gap, b.gap_at)
    } else {
        (a.gap, a.gap_at)
    };
    let (crease, crease_at) = if b.crease > a.crease {
        (b.crease, b.crease_at)
    } else {
        (a.crease, a.crease_at)
    };
    Seam {
        gap,
        gap_at,
        crease,
        crease_at,
    }
}

/// The smallest radius a key section draws (its corners that turn; infinite when it
/// has none).
fn drawn_radius(chain: &Chain) -> f64 {
    (0..chain.corners())
        .filter(|&k| chain.turn(k).abs() > 1e-6 && chain.radii[k] > 0.0)
        .map(|k| chain.radii[k])
        .fold(f64::INFINITY, f64::min)
}

/// Builds the section at any position along the outline: the key sections' runs and
/// corners carried there ([`Along`]), started along the product's slope and ended
/// along the binder's where those are known, made to reach the opening point, and
/// fitted on the shared knots ([`SectionBasis`]); with the opening line's direction
/// that the sections' slant is measured against.
struct Stations<'a> {
    along: &'a Along,
    basis: &'a SectionBasis,
    opening: &'a OpeningDirection<'a>,
    product: Option<ProductSlope<'a>>,
    binder: Option<BinderSlope<'a>>,
}

/// What [`Stations`] are made of, without the slopes' last foot points: shared by the
/// patches built side by side, each making its own [`Stations`] from it, with look-ups
/// that start where its first key section's ended, so a patch does not depend on the
/// patches built before it.
#[derive(Clone, Copy)]
struct StationInputs<'a> {
    along: &'a Along,
    basis: &'a SectionBasis,
    opening: &'a OpeningDirection<'a>,
    product: Option<&'a NurbsSurface>,
    binder: Option<&'a [NurbsSurface]>,
}

impl<'a> StationInputs<'a> {
    /// The inputs of `stations`.
    fn of(stations: &Stations<'a>) -> Self {
        StationInputs {
            along: stations.along,
            basis: stations.basis,
            opening: stations.opening,
            product: stations.product.as_ref().map(ProductSlope::surface),
            binder: stations.binder.as_ref().map(BinderSlope::patches),
        }
    }

    /// Stations whose slope look-ups start from the feet `start`.
    fn stations(&self, start: SlopeStart) -> Stations<'a> {
        Stations {
            along: self.along,
            basis: self.basis,
            opening: self.opening,
            product: self
                .product
                .map(|s| ProductSlope::starting_at(s, start.product)),
            binder: self
                .binder
                .map(|b| BinderSlope::starting_at(b, start.binder)),
        }
    }
}

/// Where the slopes' look-ups ended at a key section: where those of the patch that
/// starts there start.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct SlopeStart {
    product: Option<(f64, f64)>,
    binder: Option<(usize, f64, f64)>,
}

impl SlopeStart {
    /// Where the look-ups of `stations` stand now.
    fn of(stations: &Stations) -> Self {
        SlopeStart {
            product: stations.product.as_ref().and_then(ProductSlope::last),
            binder: stations.binder.as_ref().and_then(BinderSlope::last),
        }
    }
}

impl Stations<'_> {
    /// The section at outline position `s` (mm from the first key section) from the
    /// opening point `a` (u = 0) to the product point `b` (u = 1), where the guides'
    /// tangents are `tangents` (opening, product).
    fn section(
        &self,
        s: f64,
        ends: (DVec3, DVec3),
        tangents: (DVec3, DVec3),
    ) -> Result<Curve3, Problem> {
        Ok(self.section_with_error(s, ends, tangents)?.0)
    }

    /// [`Stations::section`] and its largest distance from the exact runs and corners.
    ///
    /// A section's plane is vertical through its two guide points, which may cut the
    /// walls at a slant. A key section is built as drawn in its plane; a section cut
    /// more slanted than its key sections (by the ratio of their [`obliquity`], at each
    /// end) is stretched across by that ratio, so the walls keep their true radii and
    /// draft instead of turning tighter and steeper in the slanted cut.
    fn section_with_error(
        &self,
        s: f64,
        (a, b): (DVec3, DVec3),
        tangents: (DVec3, DVec3),
    ) -> Result<(Curve3, f64), Problem> {
        let across = (a - b).truncate();
        let length = across.length();
        if length <= 1e-6 {
            return Err(Problem::CannotReach { at: b });
        }
        let h = (across / length).extend(0.0);
        let mut chain = self.along.at(s);
        // How much more slanted this plane is than the key sections' (whose drawings
        // are taken as they are), at the product end and at the opening end; the slant
        // goes linearly from one to the other across the section. (The sections leave
        // the product square ([`matching`]), so the two differ only where the opening
        // turns otherwise than the outline.)
        let (cp, co) = obliquity(h, tangents);
        let c0 = (cp / chain.obliquity.0).clamp(0.5, 2.0);
        let c1 = (co / chain.obliquity.1).clamp(0.5, 2.0);
        let square = |angle: f64, c: f64| angle.sin().atan2(angle.cos() * c);
        chain.start = DVec2::new(0.0, b.z);
        let last = chain.runs.len() - 1;
        if let Some(slope) = self.product.as_ref().and_then(|p| p.at(b, h)) {
            chain.runs[0].angle = square(slope, c0);
        }
        if let Some(slope) = self.binder.as_ref().and_then(|p| p.at(a, h)) {
            chain.runs[last].angle = square(slope, c1);
        }
        let fixed: Vec<bool> = self
            .basis
            .runs_with_stretch()
            .iter()
            .map(|&own| !own)
            .collect();
        // Across the section the slant goes linearly from c0 to c1: a width `dx` seen
        // square to the walls takes `dx / c(x)` of the plane, so the whole width takes
        // the logarithmic mean of the two.
        let square_length = length * log_mean(c0, c1);
        let chain = chain
            .reach(DVec2::new(square_length, a.z), &fixed)
            .ok_or(Problem::CannotReach { at: b })?;
        let (_, error) = self.basis.fit(&chain)?;
        let warp = |p: DVec2| {
            let x = p.x;
            let slope = (c1 - c0) / square_length.max(1e-9);
            let across = if (c1 - c0).abs() <= 1e-9 * c0 {
                x / c0
            } else {
                ((c0 + slope * x).max(0.25 * c0) / c0).ln() / slope
            };
            DVec2::new(across, p.y)
        };
        let fitted = self.basis.fit_warped(&chain, warp)?;
        let fitted =
            fitted.map_points(|p: DVec2| DVec3::new(b.x + h.x * p.x, b.y + h.y * p.x, p.y));
        let end = fitted.end_point();
        // The warp maps the chain's end onto the opening up to rounding: pin it there.
        let fitted = if end.distance(a) > 0.0 {
            let mut pts = fitted.control_points().to_vec();
            let n = pts.len();
            pts[n - 1] = a;
            Curve3::new(3, fitted.knots().as_slice().to_vec(), pts)?
        } else {
            fitted
        };
        Ok((fitted.reversed(), error / c0.min(c1)))
    }
}

/// A patch between two sections before its rows are interpolated.
#[derive(Debug, Clone)]
struct SubPatch {
    name: String,
    /// The smallest radius drawn in the two key sections.
    drawn_radius: f64,
    /// The product piece on [0, 1] (simple interior knots).
    product: Curve3,
    /// The opening piece re-approximated on the product piece's knots.
    opening: Curve3,
    /// Sections at the distinct knots of `product`, compatible (knot vector U).
    sections: Vec<Curve3>,
    /// The distinct knots.
    params: Vec<f64>,
}

#[derive(Clone, Copy, PartialEq)]
enum End {
    Start,
    End,
}

/// The profile (u = 0 at the opening) must advance from the opening towards the product
/// in s, never turning back.
fn check_no_fold(profile: &Curve2, e: SectionEnds) -> Result<(), Problem> {
    let sign = (e.product.x - e.opening.x).signum();
    let sign = if sign == 0.0 { 1.0 } else { sign };
    let (t0, t1) = profile.domain();
    let scale = profile.control_scale().max(1.0);
    let mut furthest = f64::NEG_INFINITY;
    let samples = 400;
    for i in 0..=samples {
        let p = profile.point_at(t0 + (t1 - t0) * i as f64 / samples as f64);
        let s = p.x * sign;
        if s < furthest - 1e-6 * scale {
            return Err(Problem::FoldsBack { at: p });
        }
        furthest = furthest.max(s);
    }
    Ok(())
}

/// How close (as a share of the shorter neighbouring span) a section's cut must come to
/// a knot of the outline to be moved onto it.
const SNAP_FRACTION: f64 = 0.1;

/// `t` moved onto the nearest knot when it lies within [`SNAP_FRACTION`] of the shorter
/// neighbouring span of it.
fn snap_to_knot(knots: &[f64], t: f64) -> f64 {
    let i = knots.partition_point(|&k| k < t);
    let (mut best, mut best_gap) = (t, f64::INFINITY);
    for j in [i.saturating_sub(1), i.min(knots.len() - 1)] {
        let k = knots[j];
        let before = if j > 0 {
            k - knots[j - 1]
        } else {
            f64::INFINITY
        };
        let after = if j + 1 < knots.len() {
            knots[j + 1] - k
        } else {
            f64::INFINITY
        };
        let span = before.min(after);
        let gap = (t - k).abs();
        if gap <= SNAP_FRACTION * span && gap < best_gap {
            (best, best_gap) = (k, gap);
        }
    }
    best
}

/// Sections' parameters must increase along the guide (cyclically for a closed one).
fn check_order(ts: &[f64], closed: bool) -> Result<(), Error> {
    let mut wraps = 0;
    for k in 1..ts.len() {
        if ts[k] <= ts[k - 1] {
            wraps += 1;
            if !closed || wraps > 1 {
                return Err(fail(k, Problem::WrongOrder));
            }
        }
    }
    if closed && wraps == 1 && ts[ts.len() - 1] >= ts[0] {
        // Wrapped once and then passed the first section again.
        let k = (1..ts.len()).find(|&k| ts[k] <= ts[k - 1]).unwrap_or(1);
        return Err(fail(k, Problem::WrongOrder));
    }
    Ok(())
}

/// Where [`piece`] cuts a curve: one stretch of its domain, or the stretch from a
/// parameter to the end followed by the one from the start to another (over the seam of
/// a closed curve).
#[derive(Debug, Clone, Copy)]
enum Cut {
    Within(f64, f64),
    OverSeam(f64, f64),
}

impl Cut {
    /// The cut of `curve` from `t0` to `t1`, wrapping over the seam when `t1 <= t0`; a
    /// cut within rounding of an existing knot is made at the knot (no sliver spans).
    fn of(curve: &Curve3, t0: f64, t1: f64) -> Cut {
        let (lo, hi) = curve.domain();
        let snap = |t: f64| -> f64 {
            curve
                .knots()
                .distinct()
                .iter()
                .map(|&(k, _)| k)
                .find(|k| (k - t).abs() <= 1e-9 * (hi - lo))
                .unwrap_or(t)
        };
        let (t0, t1) = (snap(t0), snap(t1));
        if t1 > t0 {
            Cut::Within(t0, t1)
        } else if t1 <= lo {
            Cut::Within(t0, hi)
        } else if t0 >= hi {
            Cut::Within(lo, t1)
        } else {
            Cut::OverSeam(t0, t1)
        }
    }
}

/// The piece of `curve` from `t0` to `t1`, wrapping over the seam of a closed curve when
/// `t1 <= t0`, on [0, 1].
fn piece(curve: &Curve3, t0: f64, t1: f64) -> crate::geom::Result<Curve3> {
    let (lo, hi) = curve.domain();
    let p = match Cut::of(curve, t0, t1) {
        Cut::Within(a, b) => curve.between(a, b)?,
        Cut::OverSeam(a, b) => across_seam(&curve.between(a, hi)?, &curve.between(lo, b)?)?,
    };
    p.reparametrized(0.0, 1.0)
}

/// Where parameter `t` of [`piece`]`(curve, t0, t1)` (on [0, 1]) lies on `curve` itself.
fn whole_parameter(curve: &Curve3, t0: f64, t1: f64) -> impl Fn(f64) -> f64 {
    let (lo, hi) = curve.domain();
    let period = hi - lo;
    // The piece's start and the length of parameter it covers.
    let (start, span) = match Cut::of(curve, t0, t1) {
        Cut::Within(a, b) => (a, b - a),
        Cut::OverSeam(a, b) => (a, b + period - a),
    };
    move |t| {
        let w = start + t * span;
        if w > hi {
            w - period
        } else {
            w
        }
    }
}

/// The piece of a closed curve that runs over its seam: the end `first` (up to the
/// seam) and the start `second` joined with the parameter running on at the same rate,
/// then the seam's knot removed as often as the curve allows within 1e-9 of its size.
/// A curve that is smooth at its seam (a closed outline from `project`) then has no
/// joint there, so the step draw does not depend on where the outline starts.
fn across_seam(first: &Curve3, second: &Curve3) -> crate::geom::Result<Curve3> {
    if first.is_rational() || second.is_rational() || first.degree() != second.degree() {
        return join_curves(&[first.clone(), second.clone()]);
    }
    let p = first.degree();
    let (_, a1) = first.domain();
    let (b0, _) = second.domain();
    let shift = a1 - b0;
    let k1 = first.knots().as_slice();
    let k2 = second.knots().as_slice();
    let mut knots: Vec<f64> = k1[..k1.len() - 1].to_vec();
    knots.extend(k2[p + 1..].iter().map(|k| k + shift));
    let mut points = first.control_points().to_vec();
    points.extend_from_slice(&second.control_points()[1..]);
    let joined = Curve3::new(p, knots, points)?;
    let tolerance = 1e-9 * joined.control_scale().max(1.0);
    let (out, _) = joined.remove_knot(a1, p, tolerance)?;
    Ok(out)
}

/// The sub-patches of the patch between two key sections (`keys`, as built once for
/// both their patches); `start` is the left key section's position along the outline
/// (for [`Stations::section`]).
fn patch(
    guides: &Guides,
    ends: (&SectionEnds, &SectionEnds),
    keys: (&Curve3, &Curve3),
    start: f64,
    stations: &Stations,
    tol: f64,
) -> Result<Vec<SubPatch>, Problem> {
    let product = piece(&guides.product, ends.0.product_t, ends.1.product_t)?;
    let opening = piece(&guides.opening, ends.0.opening_t, ends.1.opening_t)?;
    // The whole line's parameter of a point of the piece, for its averaged direction.
    let on_whole = whole_parameter(&guides.opening, ends.0.opening_t, ends.1.opening_t);
    let mut matching = Matching::new(&product, &opening);
    let mut refined = refine_for_opening(&product, &opening, &matching, OPENING_SHARE * tol)?;
    if !refined.settled && matching.along_normals() {
        // Somewhere a normal meets the opening at a graze and the matched points race
        // along it: no knots follow that, so the patch is matched by arc length.
        matching = Matching::by_arc_length(&product, &opening);
        refined = refine_for_opening(&product, &opening, &matching, OPENING_SHARE * tol)?;
    }
    let Refined {
        product,
        opening_ts,
        ..
    } = refined;
    let knots = product.knots().distinct();
    let params: Vec<f64> = knots.iter().map(|&(k, _)| k).collect();
    // Each knot's section, between its product point and its matched opening point.
    let mut sections = Vec::with_capacity(params.len());
    for (i, &v) in params.iter().enumerate() {
        // The two key sections as built once for both their patches, so neighbours
        // share them exactly.
        if i == 0 || i + 1 == params.len() {
            sections.push(if i == 0 { keys.0 } else { keys.1 }.clone());
            continue;
        }
        let t = opening_ts[i];
        let (a, b) = (opening.point_at(t), product.point_at(v));
        let lengths = &matching.product_lengths;
        let s = start + lengths.fraction_at(v) * lengths.total;
        let tangents = (stations.opening.at(on_whole(t))?, product.derivative_at(v));
        sections.push(stations.section(s, (a, b), tangents)?);
    }
    // The opening guide on the product's knots: through the sections' opening ends.
    let opening_points: Vec<DVec3> = sections.iter().map(Curve3::start_point).collect();
    // Split at repeated knots into sub-patches with simple knots.
    let mut cuts = vec![0usize];
    for (i, &(_, mult)) in knots.iter().enumerate() {
        if i > 0 && i + 1 < knots.len() && mult > 1 {
            cuts.push(i);
        }
    }
    cuts.push(knots.len() - 1);
    let mut subs = Vec::new();
    for w in cuts.windows(2) {
        let (i0, i1) = (w[0], w[1]);
        let (v0, v1) = (params[i0], params[i1]);
        // The product piece is on [0, 1] (from `piece`, refined in place).
        let sub_product = product.between(v0, v1)?.reparametrized(0.0, 1.0)?;
        let sub_params: Vec<f64> = params[i0..=i1]
            .iter()
            .map(|v| (v - v0) / (v1 - v0))
            .collect();
        // One-sided at a joint of the product piece: the sub-piece's own end speeds.
        let d0 = matching.opening_derivative_at_speed(
            &opening,
            params[i0],
            sub_product.derivative_at(0.0).length(),
        );
        let d1 = matching.opening_derivative_at_speed(
            &opening,
            params[i1],
            sub_product.derivative_at(1.0).length(),
        );
        let sub_opening = interpolate_at(
            &opening_points[i0..=i1],
            &sub_params,
            &Interpolation {
                knots: KnotPlacement::AtParameters,
                ..Interpolation::cubic_with_tangents(d0, d1)
            },
        )?;
        subs.push(SubPatch {
            name: String::new(),
            drawn_radius: f64::INFINITY,
            product: sub_product,
            opening: sub_opening,
            sections: sections[i0..=i1].to_vec(),
            params: sub_params,
        });
    }
    Ok(subs)
}

/// Arc-length fractions of a curve: [`ArcLengths`] (exact lengths by Gauss-Legendre
/// quadrature, parameters by Newton inside one tabulated piece) seen as fractions of
/// the whole length.
pub(super) struct ArcFractions<'a> {
    lengths: ArcLengths<'a, DVec3>,
    pub(super) total: f64,
}

impl<'a> ArcFractions<'a> {
    pub(super) fn new(c: &'a Curve3) -> Self {
        let lengths = ArcLengths::new(c);
        let total = lengths.total();
        Self { lengths, total }
    }

    /// The fraction of the length up to parameter `t`.
    pub(super) fn fraction_at(&self, t: f64) -> f64 {
        if self.total == 0.0 {
            return 0.0;
        }
        self.lengths.length_at(t) / self.total
    }

    /// The parameter at fraction `f` of the length.
    pub(super) fn t_at(&self, f: f64) -> f64 {
        let s = f.clamp(0.0, 1.0) * self.total;
        // Only a non-finite length is refused: the curve's start stands in for it.
        self.lengths
            .parameter_at(s)
            .unwrap_or_else(|_| self.lengths.curve().domain().0)
    }
}

/// The product piece refined for the opening ([`refine_for_opening`]): its knots, each
/// knot's matched opening parameter, and whether the refinement got within tolerance.
struct Refined {
    product: Curve3,
    /// The matched opening parameter at each distinct knot of `product`, in order.
    opening_ts: Vec<f64>,
    /// False when the rounds or the knots ran out before the opening was followed.
    settled: bool,
}

/// Inserts knots into the product piece (which leaves it unchanged) until the opening
/// re-approximated at its knots stays within `tol` of the real opening piece, or the
/// spans are short. Each knot's match is worked out once (a match is a Newton solve
/// started from an arc-length quadrature), not again in every round.
fn refine_for_opening(
    product: &Curve3,
    opening: &Curve3,
    matching: &Matching,
    tol: f64,
) -> crate::geom::Result<Refined> {
    let mut product = product.clone();
    let mut known: Vec<(f64, f64)> = Vec::new();
    for _ in 0..8 {
        let knots: Vec<f64> = product.knots().distinct().iter().map(|&(k, _)| k).collect();
        let ts = matched_at(&knots, &known, matching);
        known = knots.iter().copied().zip(ts.iter().copied()).collect();
        let points: Vec<DVec3> = ts.iter().map(|&t| opening.point_at(t)).collect();
        let d0 = matching.opening_derivative(&product, opening, 0.0);
        let d1 = matching.opening_derivative(&product, opening, 1.0);
        let Ok(approx) = interpolate_at(
            &points,
            &knots,
            &Interpolation {
                knots: KnotPlacement::AtParameters,
                ..Interpolation::cubic_with_tangents(d0, d1)
            },
        ) else {
            break;
        };
        // The geometric distance of the approximation from the opening (not from the
        // matched point, which may slide along the curve without any shape error).
        let mut bad = Vec::new();
        for (i, w) in knots.windows(2).enumerate() {
            // A span is short when both its guides' pieces are (the matching spreads a
            // short product span over a long opening span round a corner).
            let span_length = product
                .point_at(w[0])
                .distance(product.point_at(w[1]))
                .max(points[i].distance(points[i + 1]));
            if span_length < MIN_SPAN {
                continue;
            }
            for q in [0.25, 0.5, 0.75] {
                let v = w[0] + (w[1] - w[0]) * q;
                // Near the span's own stretch of opening only (the matching runs
                // forward, so its knots' matches bracket it): where Newton does not
                // settle, its last point's distance (an upper bound) marks the span
                // for refinement rather than searching the whole opening.
                let guess = ts[i] + (ts[i + 1] - ts[i]) * q;
                let hit = project_to_curve_locally(opening, approx.point_at(v), guess)?;
                if hit.distance > tol {
                    bad.push(0.5 * (w[0] + w[1]));
                    break;
                }
            }
        }
        if bad.is_empty() {
            return Ok(Refined {
                product,
                opening_ts: ts,
                settled: true,
            });
        }
        if knots.len() + bad.len() > MAX_KNOTS {
            break;
        }
        product = product.refine(&bad)?;
    }
    let knots: Vec<f64> = product.knots().distinct().iter().map(|&(k, _)| k).collect();
    let opening_ts = matched_at(&knots, &known, matching);
    Ok(Refined {
        product,
        opening_ts,
        settled: false,
    })
}

/// The matched opening parameter at each of `knots` (increasing), taken from `known`
/// (earlier knots with their matches, increasing) where a knot is there already:
/// inserting knots leaves the others exactly as they were.
fn matched_at(knots: &[f64], known: &[(f64, f64)], matching: &Matching) -> Vec<f64> {
    let mut next = known.iter().peekable();
    knots
        .iter()
        .map(|&v| {
            while next.peek().is_some_and(|&&(k, _)| k < v) {
                next.next();
            }
            match next.peek() {
                Some(&&(k, t)) if k == v => t,
                _ => matching.opening_t(v),
            }
        })
        .collect()
}

/// Greville abscissae (control nodes) of a cubic with `m` control points, on [0, 1].
fn greville(knots: &[f64], m: usize) -> Vec<f64> {
    let (lo, hi) = (knots[0], knots[knots.len() - 1]);
    (0..m)
        .map(|i| ((knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0 - lo) / (hi - lo))
        .collect()
}

/// Row derivatives (one per section control point) at the boundary between `a` (before)
/// and `b` (after), for `b`'s start (`End::Start`) or `a`'s end (`End::End`): Fig. 12.
fn boundary_derivatives(
    a: Option<&SubPatch>,
    b: &SubPatch,
    nodes: &[f64],
    which: End,
) -> Vec<DVec3> {
    let Some(a) = a else {
        return open_end_derivatives(b, nodes, End::Start);
    };
    let m = nodes.len();
    let na = a.sections.len();
    let q = &a.sections[na - 1];
    let p = &a.sections[na - 2];
    let r = &b.sections[1];
    // Magnitudes: per unit of product length, the opening's speed relative to the
    // product's (the mean of both patches', so neither patch leads and the result is
    // the same built either way round) blended across the section; then times each
    // patch's own product speed, so the ratio between the two sides is the same for
    // every row (eq. 4: C1 across the boundary).
    let ta = a.product.derivative_at(1.0).length();
    let ta_u = a.opening.derivative_at(1.0).length();
    let tb = b.product.derivative_at(0.0).length();
    let tb_u = b.opening.derivative_at(0.0).length();
    let ratio = if ta > 0.0 && tb > 0.0 {
        0.5 * (ta_u / ta + tb_u / tb)
    } else {
        1.0
    };
    let speed = match which {
        End::End => ta,
        End::Start => tb,
    };
    (0..m)
        .map(|i| {
            let dir = circle_tangent(
                p.control_points()[i],
                q.control_points()[i],
                r.control_points()[i],
            );
            let xi = nodes[i];
            dir * (((1.0 - xi) * ratio + xi) * speed)
        })
        .collect()
}

/// Row derivatives at an open end of the step draw: the tangent at the end of the
/// circle through the end section's point and the next two, magnitudes blended between
/// the guides' end derivatives.
fn open_end_derivatives(s: &SubPatch, nodes: &[f64], which: End) -> Vec<DVec3> {
    let n = s.sections.len();
    let (i0, i1, i2, t) = match which {
        End::Start => (0, 1, 2.min(n - 1), 0.0),
        End::End => (n - 1, n - 2, n.saturating_sub(3), 1.0),
    };
    let td = s.product.derivative_at(t).length();
    let tu = s.opening.derivative_at(t).length();
    (0..nodes.len())
        .map(|i| {
            let q = s.sections[i0].control_points()[i];
            let r = s.sections[i1].control_points()[i];
            let w = s.sections[i2].control_points()[i];
            // Pointing from the end into the patch, then along the travel direction.
            let inward = tangent_at(q, q, r, w, r - q);
            let dir = match which {
                End::Start => inward,
                End::End => -inward,
            };
            let xi = nodes[i];
            dir * ((1.0 - xi) * tu + xi * td)
        })
        .collect()
}

/// Unit tangent at `q` of the circle through `p`, `q`, `r`, pointing from `p` towards
/// `r` (Fig. 12, step 1).
fn circle_tangent(p: DVec3, q: DVec3, r: DVec3) -> DVec3 {
    tangent_at(q, p, q, r, r - p)
}

/// Unit tangent at `x` (one of `p`, `q`, `r`) of the circle through the three points,
/// oriented along `toward`; the chord `p r` direction when they are collinear.
fn tangent_at(x: DVec3, p: DVec3, q: DVec3, r: DVec3, toward: DVec3) -> DVec3 {
    let (a, b) = (p - q, r - q);
    let n = a.cross(b);
    let t = if n.length() <= 1e-12 * a.length() * b.length() {
        (r - p).normalize_or_zero()
    } else {
        let center = q
            + (b.length_squared() * n.cross(a) + a.length_squared() * b.cross(n))
                / (2.0 * n.length_squared());
        n.cross(x - center).normalize_or_zero()
    };
    if t.dot(toward) < 0.0 {
        -t
    } else {
        t
    }
}

/// Interpolates every row of section control points along the patch (AtParameters on
/// the product piece's knots), with the given end derivatives; the product row is the
/// product piece itself. Returns S(u along, v across) with v = 0 at the opening.
fn rows_to_surface(
    sub: &SubPatch,
    u_knots: &[f64],
    start: &[DVec3],
    end: &[DVec3],
) -> crate::geom::Result<NurbsSurface> {
    let m = u_knots.len() - 4;
    let mut rows = Vec::with_capacity(m);
    for i in 0..m {
        if i == m - 1 {
            rows.push(sub.product.control_points().to_vec());
            continue;
        }
        let points: Vec<DVec3> = sub.sections.iter().map(|c| c.control_points()[i]).collect();
        let row = interpolate_at(
            &points,
            &sub.params,
            &Interpolation {
                knots: KnotPlacement::AtParameters,
                ..Interpolation::cubic_with_tangents(start[i], end[i])
            },
        )?;
        rows.push(row.control_points().to_vec());
    }
    let nv = rows[0].len();
    if rows.iter().any(|r| r.len() != nv) {
        return Err(GeomError::LengthMismatch {
            what: "step-draw row",
            expected: nv,
            given: rows.iter().map(Vec::len).find(|&l| l != nv).unwrap_or(0),
        });
    }
    // net[j][i]: j along the outline (u), i across (v).
    let net: Vec<Vec<DVec3>> = (0..nv)
        .map(|j| (0..m).map(|i| rows[i][j]).collect())
        .collect();
    NurbsSurface::new(
        3,
        3,
        sub.product.knots().as_slice().to_vec(),
        u_knots.to_vec(),
        net,
    )
}

/// The surface with its across direction reversed if its normal points down.
fn upward(s: NurbsSurface) -> (NurbsSurface, bool) {
    let up = s.normal(0.5, 0.5).map_or(0.0, |n| n.z);
    if up >= 0.0 {
        (s, false)
    } else {
        (reverse_across(&s), true)
    }
}

/// The surface with its v direction reversed (non-rational step-draw patches).
fn reverse_across(s: &NurbsSurface) -> NurbsSurface {
    let (nu, nv) = s.counts();
    let kv = s.knots_v().as_slice();
    let (lo, hi) = (kv[0], kv[kv.len() - 1]);
    let knots_v: Vec<f64> = kv.iter().rev().map(|k| lo + hi - k).collect();
    let net: Vec<Vec<DVec3>> = (0..nu)
        .map(|i| (0..nv).rev().map(|j| s.control_point(i, j)).collect())
        .collect();
    // Same degrees, mirrored knots, same net size: a valid surface.
    NurbsSurface::new(
        s.degree_u(),
        s.degree_v(),
        s.knots_u().as_slice().to_vec(),
        knots_v,
        net,
    )
    .unwrap_or_else(|_| s.clone())
}

/// Largest distance from the iso-curve `v = v_edge` of `s` to a polyline, sampled.
///
/// Consecutive samples have nearby feet, so each search looks at a window of segments
/// around the previous foot first, and scans the whole polyline only when the best in
/// the window sits at its edge (the foot may lie beyond it) or is more than 0.1 mm off.
/// The window is wide enough for the examples' tightest corners (there a sample's foot
/// moves two or three segments), so the whole scan is rare.
fn edge_to_polyline(s: &NurbsSurface, v_edge: f64, line: &[DVec3]) -> f64 {
    const WINDOW: usize = 16;
    let segments = line.len().saturating_sub(1);
    if segments == 0 {
        return f64::INFINITY;
    }
    let nearest = |p: DVec3, range: std::ops::Range<usize>| -> (usize, f64) {
        range
            .map(|k| (k, distance_to_segment(p, line[k], line[k + 1])))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, f64::INFINITY))
    };
    let (u0, u1) = s.domain_u();
    let mut worst: f64 = 0.0;
    let mut last: Option<usize> = None;
    for i in 0..=QUALITY_SAMPLES {
        let p = s.point_at(u0 + (u1 - u0) * i as f64 / QUALITY_SAMPLES as f64, v_edge);
        let (k, d) = match last {
            Some(k) => {
                let (lo, hi) = (k.saturating_sub(WINDOW), (k + WINDOW + 1).min(segments));
                let (best, d) = nearest(p, lo..hi);
                // At either end of the window (the polyline's own ends included: a
                // closed line's foot may wrap round) or far off: look everywhere.
                let at_edge = best == lo || best + 1 == hi;
                if at_edge || d > 0.1 {
                    nearest(p, 0..segments)
                } else {
                    (best, d)
                }
            }
            None => nearest(p, 0..segments),
        };
        last = Some(k);
        worst = worst.max(d);
    }
    worst
}

/// Distance from `p` to the segment `a b`.
fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

/// Largest distance from the iso-curve `v = v_edge` of `s` to `curve`, sampled.
fn edge_distance(s: &NurbsSurface, v_edge: f64, curve: &Curve3) -> crate::geom::Result<f64> {
    let (u0, u1) = s.domain_u();
    let mut worst: f64 = 0.0;
    let mut guess = None;
    for i in 0..=QUALITY_SAMPLES {
        let p = s.point_at(u0 + (u1 - u0) * i as f64 / QUALITY_SAMPLES as f64, v_edge);
        // Marching from the last foot point, except where that lands far off (across
        // the seam of a closed curve, where the local search stops at the domain's end).
        let hit = match guess {
            Some(t) => {
                let near = project_to_curve_near(curve, p, t)?;
                if near.distance > 0.1 {
                    closest_point_on_curve(curve, p)?
                } else {
                    near
                }
            }
            None => closest_point_on_curve(curve, p)?,
        };
        guess = Some(hit.t);
        worst = worst.max(hit.distance);
    }
    Ok(worst)
}
