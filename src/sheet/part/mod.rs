//! A sheet part as a designer declares it: a plate over an outline on a working plane,
//! with a thickness, holes punched through it, regions lifted, faces moved and
//! removed, bend lines across it, flanges on its edges and joints rounded; built by
//! the sheet operations ([`super::topology`]), placed ([`super::geometry`]) and made
//! solid ([`super::thicken`]).
//!
//! [`build`] runs the operations in a fixed order: the rounds give their joints a
//! radius, the flanges along runs of edges become a strip per edge, the flat plate is
//! split along the bends' creases, the holes and lifts go into the parts that hold
//! them, the moves, removals and flanges follow, and the bends turn last, carrying
//! what stands beyond them. Its helpers: `layout` (the flat plate and its loops),
//! `creases` (a bend's creases), `corners` (flanges joined at a corner), `runs` (a
//! flange along a run of edges), `rounds` (joints rounded after the fact), `strips` (a
//! flange's bend facets), `names` (the solid's face names) and `measure` (the
//! mid-surface mesh, areas and volumes).

mod corners;
mod creases;
mod layout;
mod measure;
mod names;
mod rounds;
mod runs;
mod strips;

use std::collections::BTreeSet;
use std::sync::Arc;

use std::f64::consts::FRAC_PI_2;

use glam::{DVec2, DVec3};

use super::base::{BaseError, BaseSurface};
use super::geometry::{
    bend, distance_to_segment, move_face, move_vertex, vertices_by_distance, MidSurface,
};
use super::junction::{junctions, Junction};
use super::laid::{lay_mid_surface, lay_solid, LaidError, Refiner};
use super::thicken::{plan_solid, thicken_named, Gauge, ThickenError};
use super::topology::{
    EdgeId, EdgeRole, FaceId, FaceRole, Piece, Removal, Sheet, TopologyError, VertexId,
};
use crate::geom::mesh::{crossings, Mesh};
use crate::geom::tessellate::triangulate_loops;
use crate::geom::trimmed::polygon_winding;
use crate::geom::{NurbsSurface, MAX_COORDINATE};
use corners::{mitre_top, Standing};
use creases::{creases, Crease};
pub use layout::SPAN_TOLERANCE;
use layout::{
    add_loop, counter_clockwise, crosses_outline, inset, part_holding, place_ring, split_outline,
    tidy, Frame,
};
pub use measure::SheetFigures;
use measure::{mid_surface, sheet_figures};
use names::FaceNames;
pub use rounds::RoundSpec;
use strips::flange_reaches;

/// What a plate part is made of.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateSpec {
    /// The outline's points on the working plane, either way round (3 or more).
    pub outline: Vec<DVec3>,
    /// The working plane's normal: the plate's first side faces this way.
    pub normal: DVec3,
    /// The holes, inside the outline.
    pub holes: Vec<HoleSpec>,
    /// The lifted regions (embossments), inside the outline and clear of the holes.
    pub lifts: Vec<LiftSpec>,
    /// Bends across the plate, in order.
    pub bends: Vec<BendSpec>,
    /// Faces moved, each picked by a point.
    pub moves: Vec<MoveSpec>,
    /// Faces removed, each picked by a point.
    pub removals: Vec<RemoveSpec>,
    /// The flanges, in order.
    pub flanges: Vec<FlangeSpec>,
    /// Joints (flange feet, bend lines) given a radius after the fact, each picked by a
    /// point.
    pub rounds: Vec<RoundSpec>,
    /// Sheets across the far edges of two flanges, in order.
    pub covers: Vec<CoverSpec>,
    /// The thickness (mm) of the plate, and of each flange not given its own.
    pub thickness: f64,
    /// The surface the part lies on, seen along `normal` ([`super::base`]): the part is
    /// built flat and laid onto it. `None`: the part stays on its working plane.
    pub base: Option<Arc<NurbsSurface>>,
}

/// A hole punched through the plate.
#[derive(Debug, Clone, PartialEq)]
pub struct HoleSpec {
    /// Its name: the solid's faces lining it are `NAME.wall_K`.
    pub name: String,
    /// Its points, either way round.
    pub points: Vec<DVec3>,
}

/// A bend across the plate along a line (paper 003, section 4.5, Fig. 14: geometry
/// only): the plate is split along the line and the part to its left (seen along the
/// plate's normal, from `from` to `to`) turned about it.
#[derive(Debug, Clone, PartialEq)]
pub struct BendSpec {
    /// Its name: the turned part's faces are `NAME.top` and `NAME.bottom`.
    pub name: String,
    /// Where the bend line starts and ends: on the outline's edges (within
    /// [`SPAN_TOLERANCE`]), across the plate.
    pub from: DVec3,
    pub to: DVec3,
    /// How far the part is turned (radians, between -180 and 180 deg; above 0 towards
    /// the plate's normal).
    pub angle: f64,
    /// The inside radius (mm; 0 for a sharp crease): the bend is then a zone of narrow
    /// facets centred on the line, chords of the mid-surface's arc.
    pub radius: f64,
}

/// A face or a corner moved (paper 003, section 4: moving a vertex or a face).
#[derive(Debug, Clone, PartialEq)]
pub struct MoveSpec {
    /// Its name.
    pub name: String,
    /// What it picks: for a face, a point over it in the outline's view (on the working
    /// plane); for a corner, a point near it (3-D, in press coordinates, on the part as
    /// built before it is laid on a surface).
    pub at: DVec3,
    /// How far the face or corner moves (mm, in press coordinates).
    pub by: DVec3,
    /// Whether it moves a face or a corner.
    pub pick: MovePick,
}

/// What a move picks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MovePick {
    /// The face under the point: so far a lifted region's top, its walls following (a
    /// translated top keeps each wall's edges parallel, so the walls stay flat). Moved
    /// before the flanges are added.
    Face,
    /// The corner of the part nearest the point (within [`PICK_REACH`]), once every
    /// other operation is done: the faces that meet there follow, and must keep their
    /// planes.
    Corner,
}

/// A face removed from the part (paper 003, section 4.4, Fig. 11-12), picked by a point
/// over it in the outline's view: so far a lifted region's top, which leaves a passage
/// lined by the region's walls (a collar, as an extruded hole).
#[derive(Debug, Clone, PartialEq)]
pub struct RemoveSpec {
    /// Its name.
    pub name: String,
    /// What it removes.
    pub target: RemoveTarget,
}

/// What a removal picks.
#[derive(Debug, Clone, PartialEq)]
pub enum RemoveTarget {
    /// The face under a point in the outline's view (on the working plane): a lifted
    /// region's top, or a part a bend splits off.
    Face(DVec3),
    /// A flange by name (a strip of a run of edges as `NAME.K`): once every flange is
    /// added, its sides (on a radius, its strips from the far one in) go, and the edge
    /// it stood on is free again.
    Flange(String),
    /// A cover by name: once every cover is added, its sides go, and the far edges it
    /// stood across are free again (a tube's lid taken off: the passage it closed is
    /// lost).
    Cover(String),
}

/// A region of the plate lifted (or pushed down) on walls: an embossment.
#[derive(Debug, Clone, PartialEq)]
pub struct LiftSpec {
    /// Its name: the solid's faces are `NAME.top`, `NAME.bottom` and
    /// `NAME.wall_K.top`, `.bottom`.
    pub name: String,
    /// The region's outline, either way round, inside the plate's.
    pub points: Vec<DVec3>,
    /// How far it is lifted along the plate's normal (mm; below 0 pushes it down).
    pub height: f64,
    /// The walls' draft from square to the plate (radians, 0 up to 90 deg): the top is
    /// the region inset by the height times its tangent.
    pub draft: f64,
}

/// A flange on the outline's edge nearest a point.
#[derive(Debug, Clone, PartialEq)]
pub struct FlangeSpec {
    /// Its name: the solid's faces of the flange are `NAME.inside`, `NAME.outside` and
    /// `NAME.edge_K`.
    pub name: String,
    /// A point near the edge.
    pub near: DVec3,
    /// How far the flange reaches from the edge (mm).
    pub height: f64,
    /// Its angle up from the plate's plane (radians; 90 deg stands square to it, towards
    /// the normal).
    pub angle: f64,
    /// Its own thickness (mm), when not the plate's.
    pub thickness: Option<f64>,
    /// When the flange stands on part of an edge: the two points it runs between, on
    /// (or within [`SPAN_TOLERANCE`] of) one edge of the outline; `near` is then their
    /// midpoint.
    pub span: Option<(DVec3, DVec3)>,
    /// The inside radius of its bend from the plate (mm; 0 for a sharp fold): the bend
    /// is made of narrow strips, chords of the arc, and the straight flange runs
    /// `height` on from the bend's end.
    pub radius: f64,
    /// Its outline drawn in its own plane, when not a rectangle `height` high: the
    /// boundary curves (followed by straight edges) from the edge's left end to its
    /// right end, seen from outside the part, as points `(s, z)`: `s` along the edge
    /// from its left end, `z` up the flange away from it. The edge closes the loop.
    pub shape: Option<Vec<DVec2>>,
    /// Whether it runs all round the outline, one strip per edge joined at every
    /// corner (`near` and `span` are then not used).
    pub around: bool,
    /// The earlier flange on whose far edge it stands (a return flange), by name: it
    /// then runs that whole edge, and its `angle` is up from that flange, towards the
    /// side that continues the plate's top (`near` and `span` are not used).
    pub on: Option<String>,
}

/// A cover: a new sheet across the far edges of two flanges (paper 003, section 4.2,
/// Fig. 6(c): a sheet on two picked edges, added by Smep then Smel), the plane quad
/// between them, closing a channel into a box section (a passage made).
#[derive(Debug, Clone, PartialEq)]
pub struct CoverSpec {
    /// Its name: the solid's faces of the cover are `NAME.inside` (the side that
    /// continues the plate's top), `NAME.outside` and `NAME.edge_K`.
    pub name: String,
    /// The two flanges, by name, on whose far edges it stands.
    pub on: [String; 2],
    /// Its own thickness (mm), when not the plate's.
    pub thickness: Option<f64>,
}

/// Why a plate could not be built.
#[derive(Debug, Clone, PartialEq)]
pub enum PartProblem {
    /// The outline is not a polygon that bounds an area.
    Outline(String),
    /// Hole `index` is not inside the outline, or crosses another.
    Hole { index: usize, why: String },
    /// Lift `index` cannot be made.
    Lift { index: usize, why: String },
    /// Bend `index` cannot be made.
    Bend { index: usize, why: String },
    /// Move `index` cannot be made.
    Move { index: usize, why: String },
    /// Removal `index` cannot be made.
    Remove { index: usize, why: String },
    /// Flange `index` cannot be added.
    Flange { index: usize, why: String },
    /// Round `index` cannot be made.
    Round { index: usize, why: String },
    /// Cover `index` cannot be added.
    Cover { index: usize, why: String },
    /// Flange `index` meets the earlier flange `other` at the corner `at` and cannot be
    /// joined to it there, for the reason `why`.
    FlangesMeet {
        index: usize,
        other: usize,
        at: DVec3,
        why: String,
    },
    /// The solid could not be made.
    Thicken(ThickenError),
    /// The faces round a vertex of the solid do not meet at one point, near `at` (two
    /// sheets of different thickness meeting almost flat, say): flange `flange` is the
    /// nearest, when there are flanges.
    Junction { at: DVec3, flange: Option<usize> },
    /// The solid passes through itself at `at` (two flanges closer than the thickness,
    /// say): flange `flange` is the nearest, when there are flanges.
    SelfIntersection { at: DVec3, flange: Option<usize> },
    /// The part cannot be laid on its surface: a point of it does not lie over the
    /// surface, or the surface stands too steep under it.
    Base(BaseError),
}

impl std::fmt::Display for PartProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PartProblem::Outline(why) => write!(f, "the outline {why}"),
            PartProblem::Hole { why, .. } => write!(f, "the hole {why}"),
            PartProblem::Flange { why, .. } => write!(f, "the flange {why}"),
            PartProblem::Lift { why, .. } => write!(f, "the lifted region {why}"),
            PartProblem::Bend { why, .. } => write!(f, "the bend {why}"),
            PartProblem::Remove { why, .. } => write!(f, "the removal {why}"),
            PartProblem::Move { why, .. } => write!(f, "the move {why}"),
            PartProblem::Round { why, .. } => write!(f, "the round {why}"),
            PartProblem::Cover { why, .. } => write!(f, "the cover {why}"),
            PartProblem::FlangesMeet { at, why, .. } => write!(
                f,
                "the flanges meet at the corner {} and cannot be joined there: {why}",
                show(*at)
            ),
            PartProblem::Thicken(e) => write!(f, "{e}"),
            PartProblem::Junction { at, .. } => write!(
                f,
                "the solid's faces do not meet at one point near ({}, {}, {}), and no \
                 junction joins them there: the sheets meet almost flat, or three meet at \
                 one corner",
                tidy(at.x),
                tidy(at.y),
                tidy(at.z)
            ),
            PartProblem::SelfIntersection { at, .. } => write!(
                f,
                "the solid passes through itself near ({}, {}, {})",
                tidy(at.x),
                tidy(at.y),
                tidy(at.z)
            ),
            PartProblem::Base(e) => write!(f, "{e}"),
        }
    }
}

/// A built plate.
#[derive(Debug, Clone)]
pub struct SheetPart {
    /// The sheet model.
    pub sheet: Sheet,
    /// Where it lies.
    pub mid: MidSurface,
    /// The mid-surface: one side of each sheet, triangulated.
    pub mid_mesh: Arc<Mesh>,
    /// The solid at the thickness, closed and facing out.
    pub solid: Arc<Mesh>,
    /// The mid-surface's area (mm^2).
    pub area: f64,
    /// The solid's volume (mm^3).
    pub volume: f64,
    /// The junction at each vertex where two sheets meet on the free boundary, with
    /// the type the paper's rule chose there.
    pub junctions: Vec<Junction>,
    /// What each removal did, in the paper's cases.
    pub removals: Vec<Removal>,
    /// Each named sheet's area and thickness (`plate`, each flange, lifted region and
    /// bend's turned part), by name.
    pub sheets: Vec<SheetFigures>,
}

/// Builds the plate of `spec`: the initial sheet over the outline split along the
/// bends' creases, each hole punched, each region lifted, each move and removal, each
/// flange added on the free edge nearest its point (joined at corners), the bends
/// turned, then the solid. The rounds first give their joints a radius.
pub fn build(spec: &PlateSpec) -> Result<SheetPart, PartProblem> {
    let n = spec.normal.normalize_or_zero();
    if n == DVec3::ZERO || spec.outline.len() < 3 {
        return Err(PartProblem::Outline(
            "needs 3 points or more on a plane".into(),
        ));
    }
    check_sizes(spec)?;
    let spec = rounds::apply_rounds(spec)?;
    let (spec, origin) = runs::expand_runs(&spec)?;
    // Errors name the flange as written, not the strip of a run.
    let written = |i: usize| origin.get(i).copied().unwrap_or(i);
    build_strips(&spec).map_err(|p| match p {
        PartProblem::Flange { index, why } => PartProblem::Flange {
            index: written(index),
            why,
        },
        PartProblem::FlangesMeet {
            index,
            other,
            at,
            why,
        } => PartProblem::FlangesMeet {
            index: written(index),
            other: written(other),
            at,
            why,
        },
        PartProblem::Junction { at, flange } => PartProblem::Junction {
            at,
            flange: flange.map(written),
        },
        PartProblem::SelfIntersection { at, flange } => PartProblem::SelfIntersection {
            at,
            flange: flange.map(written),
        },
        p => p,
    })
}

/// [`build`] once every flange along a run of edges is one strip per edge.
fn build_strips(spec: &PlateSpec) -> Result<SheetPart, PartProblem> {
    let n = spec.normal.normalize_or_zero();
    let frame = Frame::new(spec.outline[0], n);
    let mut outline = counter_clockwise(&spec.outline, n);
    let mut nears: Vec<DVec3> = spec.flanges.iter().map(|f| f.near).collect();
    for (index, flange) in spec.flanges.iter().enumerate() {
        if let Some((from, to)) = flange.span {
            nears[index] = split_outline(&mut outline, from, to)
                .map_err(|why| PartProblem::Flange { index, why })?;
        }
    }
    // Each bend's creases: its line, or the edges of its facets on a radius.
    let mut bend_creases: Vec<Crease> = Vec::with_capacity(spec.bends.len());
    for (index, bend) in spec.bends.iter().enumerate() {
        let bad = |why: String| PartProblem::Bend { index, why };
        if !(bend.angle.is_finite() && bend.angle.abs() < std::f64::consts::PI) {
            return Err(bad("angle must lie between -180 and 180 deg".into()));
        }
        if !(bend.radius.is_finite() && bend.radius >= 0.0) {
            return Err(bad(format!(
                "radius must be 0 or more, not {}",
                bend.radius
            )));
        }
        bend_creases
            .extend(creases(&mut outline, &frame, index, bend, spec.thickness, n).map_err(bad)?);
    }
    let flat_outline: Vec<DVec2> = outline.iter().map(|&p| frame.flat(p)).collect();
    if triangulate_loops(std::slice::from_ref(&flat_outline)).is_err() {
        return Err(PartProblem::Outline("crosses or touches itself".into()));
    }
    let topo = |e: TopologyError| PartProblem::Outline(e.to_string());
    let (mut sheet, _, top) = Sheet::initial(outline.len()).map_err(topo)?;
    let mut mid = MidSurface::new();
    let corners = sheet.brep.outer_vertices(top).map_err(topo)?;
    for (&v, &p) in corners.iter().zip(&outline) {
        mid.place(&sheet, v, p).map_err(topo)?;
    }
    // Bends: the plate split along each line now, while it is flat and has no holes;
    // turned at the end, carrying what was built beyond the line.
    let mut parts = vec![top];
    let mut cuts = Vec::with_capacity(bend_creases.len());
    for crease in &bend_creases {
        let (from, to) = (crease.from, crease.to);
        let bad = |why: String| PartProblem::Bend {
            index: crease.bend,
            why,
        };
        let corner = |p: DVec3| {
            corners
                .iter()
                .zip(&outline)
                .find(|(_, &q)| q.distance(p) < 1e-9)
                .map(|(&v, _)| v)
        };
        let (Some(vf), Some(vt)) = (corner(from), corner(to)) else {
            return Err(bad("has an end that is not a corner of the outline".into()));
        };
        let (ff, ft) = (frame.flat(from), frame.flat(to));
        if crosses_outline(&flat_outline, ff, ft) {
            return Err(bad(
                "line leaves the plate: it must run across it from edge to edge".into(),
            ));
        }
        let part = parts
            .iter()
            .copied()
            .find(|&f| {
                sheet
                    .brep
                    .outer_vertices(f)
                    .is_ok_and(|vs| vs.contains(&vf) && vs.contains(&vt))
            })
            .ok_or_else(|| bad("line crosses an earlier bend's line".into()))?;
        let (edge, new) = sheet.split(part, vf, vt).map_err(|e| bad(e.to_string()))?;
        parts.push(new);
        // The part to the left of the line, seen along the normal, turns.
        let points: Vec<DVec2> = sheet
            .brep
            .outer_vertices(new)
            .map_err(|e| bad(e.to_string()))?
            .into_iter()
            .filter_map(|v| mid.point(v))
            .map(|p| frame.flat(p))
            .collect();
        let centre = points.iter().sum::<DVec2>() / points.len().max(1) as f64;
        let left = (ft - ff).perp_dot(centre - ff) > 0.0;
        let (fixed, moved) = if left { (part, new) } else { (new, part) };
        cuts.push(Cut {
            part,
            fixed,
            moved,
            crease: edge,
            name: crease.name.clone(),
        });
    }
    // Holes: each inside the outline, clear of the others.
    let mut flat_loops = vec![flat_outline.clone()];
    let mut hole_rings = Vec::with_capacity(spec.holes.len());
    for (index, hole) in spec.holes.iter().enumerate() {
        let hole = &hole.points;
        let bad = |why: String| PartProblem::Hole { index, why };
        if hole.len() < 3 {
            return Err(bad("needs 3 points or more".into()));
        }
        let ring = counter_clockwise(hole, n);
        let flat: Vec<DVec2> = ring.iter().map(|&p| frame.flat(p)).collect();
        let (part, at) = part_holding(&sheet, &mid, &frame, &parts, &flat).map_err(bad)?;
        add_loop(&flat_outline, &mut flat_loops, flat).map_err(bad)?;
        sheet
            .punch(part, at, ring.len())
            .map_err(|e| bad(e.to_string()))?;
        let ring_vertices =
            place_ring(&sheet, &mut mid, part, &ring).map_err(|e| bad(e.to_string()))?;
        hole_rings.push(ring_vertices);
    }
    // Lifts: a region inside the plate, raised (or pushed down) on walls.
    let mut lifted = Vec::with_capacity(spec.lifts.len());
    // Each lifted region's top, flat in the outline's view.
    let mut lift_tops: Vec<Vec<DVec2>> = Vec::with_capacity(spec.lifts.len());
    for (index, lift) in spec.lifts.iter().enumerate() {
        let bad = |why: String| PartProblem::Lift { index, why };
        if lift.points.len() < 3 {
            return Err(bad("needs 3 points or more".into()));
        }
        if !(lift.height.is_finite() && lift.height != 0.0) {
            return Err(bad(format!(
                "height must be a length other than 0, not {}",
                lift.height
            )));
        }
        if !(lift.draft.is_finite() && (0.0..FRAC_PI_2).contains(&lift.draft)) {
            return Err(bad(
                "draft must lie from 0 up to (not including) 90 deg".into()
            ));
        }
        let ring = counter_clockwise(&lift.points, n);
        let flat: Vec<DVec2> = ring.iter().map(|&p| frame.flat(p)).collect();
        let (part, at) = part_holding(&sheet, &mid, &frame, &parts, &flat).map_err(bad)?;
        add_loop(&flat_outline, &mut flat_loops, flat).map_err(bad)?;
        let tops = inset(&ring, n, lift.height.abs() * lift.draft.tan()).ok_or_else(|| {
            bad("is too small for its draft: its top would turn inside out".into())
        })?;
        let topo = |e: TopologyError| bad(e.to_string());
        let region = sheet.region(part, at, ring.len()).map_err(topo)?;
        place_ring(&sheet, &mut mid, part, &ring).map_err(topo)?;
        let walls = sheet.lift(region.face).map_err(topo)?;
        // Each top corner stands over the base corner it was swept from: the one
        // placed corner its edges reach.
        let b = &sheet.brep;
        for t in b.outer_vertices(region.face).map_err(topo)? {
            let mut base = None;
            for e in b.edges_at(t).map_err(topo)? {
                let (p, m) = b.halves_of(e).map_err(topo)?;
                for h in [p, m] {
                    let u = b.vertex(h).map_err(topo)?;
                    if u != t {
                        base = base.or_else(|| mid.point(u));
                    }
                }
            }
            let base = base.ok_or_else(|| bad("a lifted corner has no base".into()))?;
            // The top corner over this base, by its place in the ring.
            let k = ring
                .iter()
                .position(|&p| p.distance(base) < 1e-12)
                .ok_or_else(|| bad("a lifted corner is off its ring".into()))?;
            mid.place(&sheet, t, tops[k] + lift.height * n)
                .map_err(topo)?;
        }
        lifted.push((region.face, walls));
        lift_tops.push(tops.iter().map(|&p| frame.flat(p)).collect::<Vec<DVec2>>());
    }
    // Moves: the lifted top under each point, its walls following.
    for (index, step) in spec.moves.iter().enumerate() {
        if step.pick != MovePick::Face {
            continue;
        }
        let bad = |why: String| PartProblem::Move { index, why };
        let q = frame.flat(step.at);
        let k = lift_tops
            .iter()
            .position(|ring| polygon_winding(ring, q) != 0)
            .ok_or_else(|| {
                bad(
                    "finds no face to move under its point: give a point on a lifted \
                     region's top"
                        .into(),
                )
            })?;
        let height = spec.lifts[k].height + step.by.dot(n);
        if height * spec.lifts[k].height <= 0.0 {
            return Err(bad(format!(
                "would take the top of `{}` through the plate: it stands {} mm off it, and \
                 the move takes it {} mm along the normal",
                spec.lifts[k].name,
                tidy(spec.lifts[k].height),
                tidy(step.by.dot(n))
            )));
        }
        move_face(&sheet, &mut mid, lifted[k].0, step.by).map_err(|e| bad(e.to_string()))?;
        let shift = frame.flat(step.at + step.by) - q;
        for p in &mut lift_tops[k] {
            *p += shift;
        }
    }
    // Removals: the face under each point, in the paper's cases (section 4.4).
    let mut removals = Vec::with_capacity(spec.removals.len());
    for (index, removal) in spec.removals.iter().enumerate() {
        let RemoveTarget::Face(at) = removal.target else {
            continue;
        };
        let bad = |why: String| PartProblem::Remove { index, why };
        let q = frame.flat(at);
        let top = lift_tops
            .iter()
            .position(|ring| polygon_winding(ring, q) != 0)
            .map(|k| lifted[k].0);
        let over_hole = flat_loops[1..].iter().any(|l| polygon_winding(l, q) != 0);
        // The plate's part under the point (bends split the plate into parts).
        let part = parts.iter().copied().find(|&f| {
            let ring: Vec<DVec2> = sheet
                .brep
                .outer_vertices(f)
                .map(|vs| vs.iter().filter_map(|&v| mid.point(v)).collect::<Vec<_>>())
                .unwrap_or_default()
                .into_iter()
                .map(|p| frame.flat(p))
                .collect();
            polygon_winding(&ring, q) != 0
        });
        let face = match (top, part) {
            (Some(face), _) => face,
            (None, Some(_)) if over_hole => {
                return Err(bad(
                    "lies over a hole or a lifted region's wall: give a point on the face \
                     to remove"
                        .into(),
                ))
            }
            (None, Some(_)) if parts.len() == 1 => {
                return Err(bad(
                    "would take the whole plate: nothing would be left".into()
                ))
            }
            (None, Some(part)) => part,
            (None, None) => {
                return Err(bad(
                    "finds no face to remove under its point: give a point on a lifted \
                     region's top, or on a part of the plate a bend's line splits off"
                        .into(),
                ))
            }
        };
        let case = sheet.remove(face).map_err(|e| bad(e.to_string()))?;
        if let Removal::Trimmed { pieces_made, .. } = case {
            if pieces_made > 0 {
                return Err(bad("would cut the part in two".into()));
            }
        }
        parts.retain(|&f| f != face);
        removals.push(case);
    }
    // Flanges: on the outline edge nearest each point, if it is still free; two on the
    // edges at one corner are joined there (a closed corner).
    let mut flange_edges: Vec<(VertexId, VertexId, DVec3, DVec3)> =
        Vec::with_capacity(spec.flanges.len());
    let mut standing = Vec::with_capacity(spec.flanges.len());
    for (index, flange) in spec.flanges.iter().enumerate() {
        let bad = |why: String| PartProblem::Flange { index, why };
        check_flange(flange).map_err(bad)?;
        if flange.on.is_some() {
            // A return flange stands on another flange, not on the plate: it is added
            // with the others below, and meets no flange at the plate's corners.
            flange_edges.push((NO_VERTEX, NO_VERTEX, DVec3::ZERO, DVec3::ZERO));
            standing.push(Standing {
                from: DVec3::ZERO,
                to: DVec3::ZERO,
                rise: n,
                height: flange.height,
            });
            continue;
        }
        let (a, c, pa, pc) = nearest_edge(&sheet, &mid, &parts, nears[index]).map_err(bad)?;
        if flange_edges.iter().any(|&(x, y, ..)| (x, y) == (a, c)) {
            return Err(bad(format!(
                "cannot go on the edge nearest its point, from {} to {}: another flange \
                 is there already",
                show(pa),
                show(pc)
            )));
        }
        flange_edges.push((a, c, pa, pc));
        let out = (pc - pa).cross(n).normalize_or_zero();
        standing.push(Standing {
            from: pa,
            to: pc,
            rise: flange.angle.cos() * out + flange.angle.sin() * n,
            height: flange.height,
        });
    }
    // The closed corners: where each flange's end (at its edge's first and last
    // vertex) meets an earlier flange, and where its far corner goes on the mitre line.
    let mut joined: Vec<[Option<usize>; 2]> = vec![[None, None]; spec.flanges.len()];
    let mut mitred: Vec<[Option<DVec3>; 2]> = vec![[None, None]; spec.flanges.len()];
    for index in 0..spec.flanges.len() {
        let (a, c, pa, pc) = flange_edges[index];
        if spec.flanges[index].on.is_some() {
            continue;
        }
        for (end, (v, p)) in [(a, pa), (c, pc)].into_iter().enumerate() {
            let Some(other) = flange_edges[..index]
                .iter()
                .position(|&(x, y, ..)| x == v || y == v)
            else {
                continue;
            };
            let meet = |why: String| PartProblem::FlangesMeet {
                index,
                other,
                at: p,
                why,
            };
            if spec.flanges[index].shape.is_some() || spec.flanges[other].shape.is_some() {
                return Err(meet(
                    "a flange with a drawn `shape` cannot be joined at a corner yet: end \
                     its shape short of the corner, or draw the other flange to meet it"
                        .into(),
                ));
            }
            if spec.flanges[index].radius > 0.0 || spec.flanges[other].radius > 0.0 {
                return Err(meet(
                    "a flange with a bend radius cannot be joined at a corner yet: the \
                     bends would need a curved corner between them"
                        .into(),
                ));
            }
            let top = mitre_top(p, &standing[other], &standing[index], n).map_err(meet)?;
            let other_end = if flange_edges[other].0 == v { 0 } else { 1 };
            joined[index][end] = Some(other);
            mitred[index][end] = Some(top);
            mitred[other][other_end] = Some(top);
        }
    }
    let mut gauge = Gauge::uniform(spec.thickness);
    let mut flange_sides = Vec::with_capacity(spec.flanges.len());
    // Each flange's far corners, over its edge's first and last vertex.
    let mut far_corners: Vec<[VertexId; 2]> = Vec::with_capacity(spec.flanges.len());
    // Each flange's far edge, where a return flange may stand, with the flange's frame
    // (the direction it rises in from its foot, and its inside's normal); `None` where
    // it has no one far edge free to stand on (a drawn shape, a closed corner).
    let mut far_edges: Vec<Option<(EdgeId, DVec3, DVec3)>> = Vec::with_capacity(spec.flanges.len());
    // Each return flange's foot, where later returns join it.
    let mut feet: Vec<Option<ReturnFoot>> = Vec::with_capacity(spec.flanges.len());
    // Which of each flange's far corners (in `far_corners`' order) it shares with a
    // flange joined to it there (a flange joined at either is joined at a corner: its
    // far edge runs on into the other's), and each return's foot ends on its parent's
    // far corners: (the return, its end, the parent, the parent's far corner).
    let mut ends_joined: Vec<[bool; 2]> = Vec::with_capacity(spec.flanges.len());
    let mut at_corners: Vec<(usize, usize, usize, usize)> = Vec::new();
    for (index, flange) in spec.flanges.iter().enumerate() {
        let bad = |why: String| PartProblem::Flange { index, why };
        let topo = |e: TopologyError| bad(e.to_string());
        if let Some(parent) = &flange.on {
            let context = Earlier {
                far_edges: &far_edges,
                ends_joined: &ends_joined,
                feet: &feet,
            };
            let added = add_return(&mut sheet, &mut mid, spec, index, parent, &context).map_err(
                |e| match e {
                    ReturnProblem::Alone(why) => bad(why),
                    ReturnProblem::Meets { other, at, why } => PartProblem::FlangesMeet {
                        index,
                        other,
                        at,
                        why,
                    },
                },
            )?;
            // The far corners shared with earlier returns were placed on their
            // mitres by `add_return`; both returns are joined at those ends now.
            let mut own = [false; 2];
            for join in &added.joins {
                own[join.own_end] = true;
                ends_joined[join.other][join.their_end] = true;
            }
            // Where its foot's ends are its parent's joined far corners, it must be
            // joined there too (checked once every flange stands).
            if let Some(p) = spec.flanges[..index]
                .iter()
                .rposition(|f| Some(&f.name) == flange.on.as_ref())
            {
                for (e, &v) in added.foot_of.ends.iter().enumerate() {
                    let twin = sheet.twin_vertex(v).map_err(topo)?;
                    if let Some(j) = far_corners[p].iter().position(|&f| f == v || f == twin) {
                        at_corners.push((index, e, p, j));
                    }
                }
            }
            ends_joined.push(own);
            feet.push(Some(added.foot_of));
            flange_edges[index] = (NO_VERTEX, NO_VERTEX, added.foot.0, added.foot.1);
            far_corners.push(added.far_corners);
            far_edges.push(Some(added.far_edge));
            if let Some(t) = flange.thickness {
                gauge
                    .sheets
                    .extend(added.strips.iter().map(|&(side, _)| (side, t)));
            }
            flange_sides.push(added.strips);
            continue;
        }
        let (a, c, pa, pc) = flange_edges[index];
        // The run of picked edges: the plate's edge, and on up the end of each flange
        // it is joined to.
        let far_of = |end: usize| {
            joined[index][end].map(|other| {
                let (x, ..) = flange_edges[other];
                let v = [a, c][end];
                far_corners[other][if x == v { 0 } else { 1 }]
            })
        };
        let (before, after) = (far_of(0), far_of(1));
        let mut path: Vec<VertexId> = before.into_iter().collect();
        path.extend([a, c]);
        path.extend(after);
        let shape = match &flange.shape {
            Some(shape) => Some(shape_chain(shape, pa.distance(pc)).map_err(bad)?),
            None => None,
        };
        let curves = match &shape {
            Some(points) => points.len() - 1,
            None => 3 - before.iter().count() - after.iter().count(),
        };
        let added = sheet
            .add_sheet(&[Piece::Picked(path.clone()), Piece::Curves(curves)])
            .map_err(|e| {
                bad(format!(
                    "cannot go on the edge nearest its point, from {} to {}: {e}",
                    show(pa),
                    show(pc)
                ))
            })?;
        // The new boundary curves run from the run's last vertex round to its first:
        // from c (or the far corner over it) to the new far corners and back to a.
        let chain = curve_chain(&sheet, path[path.len() - 1], &added.curves).map_err(topo)?;
        let k = chain.len();
        let out = (pc - pa).cross(n).normalize_or_zero();
        let reaches = flange_reaches(flange, spec.thickness, out, n);
        if k != curves + 1 {
            return Err(bad("a new far edge is not a chain of curves".into()));
        }
        let far_a = before.unwrap_or(chain[k - 2]);
        let far_c = after.unwrap_or(chain[1]);
        if let Some(points) = &shape {
            // The chain runs from c back to a: the shape's points the other way round.
            let rise = flange.angle.cos() * out + flange.angle.sin() * n;
            let along = (pc - pa) / pa.distance(pc);
            for (v, q) in chain[1..k - 1].iter().zip(points[1..k - 1].iter().rev()) {
                mid.place(&sheet, *v, pa + q.x * along + q.y * rise)
                    .map_err(topo)?;
            }
        } else {
            for (end, (v, p)) in [(far_a, pa), (far_c, pc)].into_iter().enumerate() {
                if joined[index][end].is_none() {
                    let at = mitred[index][end].unwrap_or(p + reaches[0]);
                    mid.place(&sheet, v, at).map_err(topo)?;
                }
            }
        }
        far_corners.push([far_a, far_c]);
        let mut strips = vec![added.sides];
        let bends = &reaches[1..];
        // The far edge: the new curve between the far corners, or the last strip's on
        // a radius.
        let mut far_of_strips = far_curve(&sheet, &added.curves, [far_a, far_c]);
        if !bends.is_empty() {
            // A flange on a bend radius (never joined at a corner): the straight
            // flange's curve is the second, the far edge.
            let mut far = added.curves[1];
            let mut last = reaches[0];
            for &reach in bends {
                let strip = sheet.flange(far).map_err(topo)?;
                for (base, end) in strip.far_ends {
                    let from = mid
                        .point(base)
                        .ok_or_else(|| bad("a bend's edge has no point".into()))?;
                    mid.place(&sheet, end, from + reach - last).map_err(topo)?;
                }
                let [one, other] = strip.sides[..] else {
                    return Err(bad("a bend's strip has not two sides".into()));
                };
                strips.push((one, other));
                far = strip.far_edge;
                last = reach;
            }
            far_of_strips = Some(far);
        }
        if let Some(t) = flange.thickness {
            gauge
                .sheets
                .extend(strips.iter().map(|&(side, _)| (side, t)));
        }
        // The far edge a return flange may stand on: the straight flange's (not a
        // drawn shape's); joined at a corner (either way round), it runs on into the
        // other flange's far edge there.
        let rise = flange.angle.cos() * out + flange.angle.sin() * n;
        let inside = -flange.angle.sin() * out + flange.angle.cos() * n;
        far_edges.push(
            far_of_strips
                .filter(|_| shape.is_none())
                .map(|e| (e, rise, inside)),
        );
        ends_joined.push([mitred[index][0].is_some(), mitred[index][1].is_some()]);
        feet.push(None);
        flange_sides.push(strips);
    }
    // A return on a flange joined at a corner meets the neighbour there: it is made
    // only joined to a return on the neighbour (four sheets round the corner).
    for &(index, end, p, j) in &at_corners {
        if ends_joined[p][j] && !ends_joined[index][end] {
            let at = mid.point(far_corners[p][j]).unwrap_or_default();
            return Err(PartProblem::Flange {
                index,
                why: format!(
                    "cannot end at {} where flange `{}` is joined to another at a corner: a \
                     return there must be joined to a return on the other flange (give it \
                     one, or stand this one on a flange standing alone)",
                    show(at),
                    spec.flanges[p].name
                ),
            });
        }
    }
    // Covers across two flanges' far edges, once every flange stands.
    let mut cover_sides: Vec<Option<(FaceId, FaceId)>> = Vec::with_capacity(spec.covers.len());
    for (index, cover) in spec.covers.iter().enumerate() {
        let bad = |why: String| PartProblem::Cover { index, why };
        let mut edges = Vec::with_capacity(2);
        for name in &cover.on {
            let k = flange_named(spec, name).map_err(bad)?;
            if ends_joined[k].contains(&true) {
                return Err(bad(format!(
                    "cannot stand on flange `{name}`: it is joined to another at a corner, \
                     and the cover's corner there would meet them both on the free boundary"
                )));
            }
            let (edge, ..) = far_edges[k].ok_or_else(|| {
                bad(format!(
                    "cannot stand on flange `{name}`: its far edge is drawn (a `shape`), not \
                     one straight edge"
                ))
            })?;
            edges.push((k, edge));
        }
        if edges[0].0 == edges[1].0 {
            return Err(bad(format!(
                "names flange `{}` twice: it stands across two flanges' far edges",
                cover.on[0]
            )));
        }
        let (sides, inside) =
            add_cover(&mut sheet, &mid, &parts, [edges[0].1, edges[1].1]).map_err(bad)?;
        if let Some(t) = cover.thickness {
            gauge.sheets.push((sides.0, t));
        }
        let outside = if inside == sides.0 { sides.1 } else { sides.0 };
        cover_sides.push(Some((inside, outside)));
    }
    // Flanges and covers removed, by name, once every one stands, in the paper's
    // cases: a flange on the free boundary trims the sheet; one a cover stands on, or
    // the cover itself, loses the passage the cover closed.
    for (index, removal) in spec.removals.iter().enumerate() {
        let bad = |why: String| PartProblem::Remove { index, why };
        // The sides to remove, from the far one in, with what they are.
        let (sides, what) = match &removal.target {
            RemoveTarget::Face(_) => continue,
            RemoveTarget::Flange(name) => {
                let k = flange_named(spec, name).map_err(bad)?;
                let strips = std::mem::take(&mut flange_sides[k]);
                if strips.is_empty() {
                    return Err(bad(format!("finds flange `{name}` removed already")));
                }
                far_edges[k] = None;
                let sides: Vec<FaceId> = strips.iter().rev().map(|&(side, _)| side).collect();
                (sides, format!("flange `{name}`"))
            }
            RemoveTarget::Cover(name) => {
                let k = spec
                    .covers
                    .iter()
                    .position(|c| &c.name == name)
                    .ok_or_else(|| bad(format!("finds no cover `{name}`")))?;
                let (inside, _) = cover_sides[k]
                    .take()
                    .ok_or_else(|| bad(format!("finds cover `{name}` removed already")))?;
                (vec![inside], format!("cover `{name}`"))
            }
        };
        // Each stands free but for the edges it joins.
        for side in sides {
            let case = sheet.remove(side).map_err(|e| bad(e.to_string()))?;
            if let Removal::Trimmed { pieces_made, .. } = &case {
                if *pieces_made > 0 {
                    return Err(bad(format!(
                        "would cut the part in two: another flange stands on {what} alone; \
                         remove that one first"
                    )));
                }
            }
            removals.push(case);
        }
    }
    let flange_edges: Vec<(DVec3, DVec3)> = flange_edges
        .iter()
        .map(|&(_, _, pa, pc)| (pa, pc))
        .collect();
    // The bends turned, in order; a bend line may not end on a flange's edge (the
    // flange would have to bend too).
    for (cut, crease) in cuts.iter().zip(&bend_creases) {
        let bad = |why: String| PartProblem::Bend {
            index: crease.bend,
            why,
        };
        // A crease whose part on one side was removed joins nothing: nothing turns.
        if removed_beside(&sheet, cut.crease) {
            continue;
        }
        let (from, to) = (crease.from, crease.to);
        for (k, &(a, c)) in flange_edges.iter().enumerate() {
            if [from, to]
                .iter()
                .any(|&p| distance_to_segment(a, c, p) < SPAN_TOLERANCE)
            {
                return Err(bad(format!(
                    "line ends on the edge of flange `{}`: the flange would have to bend too",
                    spec.flanges[k].name
                )));
            }
        }
        bend(&sheet, &mut mid, cut.fixed, cut.crease, crease.angle)
            .map_err(|e| bad(e.to_string()))?;
    }
    // Corners moved, last: the one nearest each point, the faces there following.
    for (index, step) in spec.moves.iter().enumerate() {
        if step.pick != MovePick::Corner {
            continue;
        }
        let bad = |why: String| PartProblem::Move { index, why };
        let v = corner_near(&sheet, &mid, step.at).map_err(bad)?;
        move_vertex(&sheet, &mut mid, v, step.by).map_err(|e| bad(e.to_string()))?;
    }
    // A solid that cannot be made, or passes through itself, is blamed on the flange
    // nearest the place at fault.
    let nearest_flange = |at: DVec3| {
        flange_edges
            .iter()
            .enumerate()
            .map(|(i, &(a, b))| (distance_to_segment(a, b, at), i))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map(|(_, i)| i)
    };
    let pieces = names::Pieces {
        cuts: &cuts,
        hole_rings: &hole_rings,
        lifts: &lifted,
        flanges: &flange_sides,
        covers: &cover_sides,
    };
    let names =
        FaceNames::new(&sheet, spec, top, &pieces).map_err(|e| PartProblem::Thicken(e.into()))?;
    let mut junctions = junctions(&sheet, &mid).map_err(|e| PartProblem::Thicken(e.into()))?;
    let refused = |e: ThickenError| match e {
        ThickenError::Junction { at, .. } => PartProblem::Junction {
            at,
            flange: nearest_flange(at),
        },
        e => PartProblem::Thicken(e),
    };
    let laid_refused = |e: LaidError| match e {
        LaidError::Base(e) => PartProblem::Base(e),
        LaidError::Thicken(e) => refused(e),
    };
    let (solid, mid_mesh, side_areas) = match &spec.base {
        None => {
            let solid = thicken_named(&sheet, &mid, &gauge, &junctions, |f| names.of(f))
                .map_err(refused)?;
            let (mid_mesh, side_areas) = mid_surface(&sheet, &mid).map_err(PartProblem::Thicken)?;
            (solid, mid_mesh, side_areas)
        }
        Some(surface) => {
            // Built flat, laid on the surface: each face cut to follow it.
            let base = BaseSurface::new((**surface).clone(), spec.outline[0], n);
            let mut refiner = Refiner::new(&base);
            let plan = plan_solid(&sheet, &mid, &gauge, &junctions).map_err(refused)?;
            let solid = lay_solid(&plan, &mut refiner, |f| names.of(f)).map_err(laid_refused)?;
            let (mid_mesh, side_areas) =
                lay_mid_surface(&sheet, &mid, &mut refiner).map_err(laid_refused)?;
            for j in &mut junctions {
                j.at = base.lay(j.at).map_err(PartProblem::Base)?;
            }
            (solid, mid_mesh, side_areas)
        }
    };
    if let Some(c) = crossings(&solid).first() {
        return Err(PartProblem::SelfIntersection {
            at: c.at,
            flange: nearest_flange(c.at),
        });
    }
    let sheets = sheet_figures(
        &side_areas,
        |f| names.of(f),
        |f| match sheet.face_role(f) {
            Ok(FaceRole::Side { twin }) => gauge.of(f, twin),
            _ => gauge.base,
        },
    );
    let area = mid_mesh.total_area();
    let volume = solid.enclosed_volume();
    Ok(SheetPart {
        sheet,
        mid,
        mid_mesh: Arc::new(mid_mesh),
        solid: Arc::new(solid),
        area,
        volume,
        junctions,
        removals,
        sheets,
    })
}

/// Every length and point of `spec` within [`MAX_COORDINATE`] (mm): beyond it the
/// solid's coordinates leave what the kernel and the GLB hold (`docs/limits.md`).
fn check_sizes(spec: &PlateSpec) -> Result<(), PartProblem> {
    let fits = |x: f64| x.is_finite() && x.abs() <= MAX_COORDINATE;
    let point = |p: &DVec3| fits(p.x) && fits(p.y) && fits(p.z);
    let why = |what: &str| {
        format!(
            "has {what} beyond {MAX_COORDINATE} mm: every length of a sheet part lies within it"
        )
    };
    if !spec.outline.iter().all(point) {
        return Err(PartProblem::Outline(why("a point")));
    }
    if !fits(spec.thickness) {
        return Err(PartProblem::Thicken(ThickenError::Thickness(
            spec.thickness,
        )));
    }
    for (index, h) in spec.holes.iter().enumerate() {
        if !h.points.iter().all(point) {
            return Err(PartProblem::Hole {
                index,
                why: why("a point"),
            });
        }
    }
    for (index, l) in spec.lifts.iter().enumerate() {
        if !(l.points.iter().all(point) && fits(l.height)) {
            return Err(PartProblem::Lift {
                index,
                why: why("a point or a height"),
            });
        }
    }
    for (index, b) in spec.bends.iter().enumerate() {
        if !(point(&b.from) && point(&b.to)) {
            return Err(PartProblem::Bend {
                index,
                why: why("a point"),
            });
        }
    }
    for (index, r) in spec.removals.iter().enumerate() {
        if matches!(r.target, RemoveTarget::Face(at) if !point(&at)) {
            return Err(PartProblem::Remove {
                index,
                why: why("its point"),
            });
        }
    }
    for (index, m) in spec.moves.iter().enumerate() {
        if !(point(&m.at) && point(&m.by)) {
            return Err(PartProblem::Move {
                index,
                why: why("its point or its offset"),
            });
        }
    }
    for (index, r) in spec.rounds.iter().enumerate() {
        if !(point(&r.at) && fits(r.radius)) {
            return Err(PartProblem::Round {
                index,
                why: why("its point or its radius"),
            });
        }
    }
    for (index, f) in spec.flanges.iter().enumerate() {
        let span = f.span.is_none_or(|(a, c)| point(&a) && point(&c));
        let thick = f.thickness.is_none_or(fits);
        let shape = f
            .shape
            .as_ref()
            .is_none_or(|s| s.iter().all(|p| fits(p.x) && fits(p.y)));
        if !(point(&f.near) && span && fits(f.height) && fits(f.radius) && thick && shape) {
            return Err(PartProblem::Flange {
                index,
                why: why("a point, a height, a radius or a thickness"),
            });
        }
    }
    Ok(())
}

/// A crease's split of the plate: the part split, the part that stays and the part that
/// turns (one of them the part split), the crease between them, and the name of the
/// part that turns (`BEND` or a facet's `BEND.bend_K`).
pub(super) struct Cut {
    part: FaceId,
    fixed: FaceId,
    moved: FaceId,
    crease: EdgeId,
    name: String,
}

/// A flange's own fields checked: a height above 0, a thickness above 0 when given, a
/// radius of 0 or more (not with a thickness of its own), an angle from 0 up to 180
/// deg.
fn check_flange(flange: &FlangeSpec) -> Result<(), String> {
    if !(flange.height.is_finite() && flange.height > 0.0) {
        return Err(format!("height must be above 0, not {}", flange.height));
    }
    if let Some(t) = flange.thickness {
        if !(t.is_finite() && t > 0.0) {
            return Err(format!("thickness must be above 0, not {t}"));
        }
    }
    if !(flange.radius.is_finite() && flange.radius >= 0.0) {
        return Err(format!("radius must be 0 or more, not {}", flange.radius));
    }
    if flange.radius > 0.0 && flange.thickness.is_some() {
        return Err(
            "cannot have both a bend radius and its own thickness: a flange of another \
             gauge is a separate piece joined at the edge, not bent from the plate"
                .into(),
        );
    }
    if flange.on.is_some() {
        let pi = std::f64::consts::PI;
        if !(flange.angle.is_finite() && flange.angle > -pi && flange.angle < pi) {
            return Err(
                "angle must lie between -180 and 180 deg (above 0 towards the inside of \
                 the flange it stands on)"
                    .into(),
            );
        }
    } else if !(flange.angle.is_finite() && (0.0..std::f64::consts::PI).contains(&flange.angle)) {
        return Err("angle must lie from 0 up to (not including) 180 deg".into());
    }
    if flange.shape.is_some() && flange.radius > 0.0 {
        return Err(
            "cannot have both a drawn `shape` and a bend radius yet: a shaped flange is \
             folded sharp"
                .into(),
        );
    }
    Ok(())
}

/// A flange's drawn shape checked against the length of its edge: it must run from the
/// edge's left end `(0, 0)` to its right end `(length, 0)` (each within
/// [`SPAN_TOLERANCE`], then put on it exactly), stay above the edge between, and with
/// the edge bound an area without crossing itself.
fn shape_chain(shape: &[DVec2], length: f64) -> Result<Vec<DVec2>, String> {
    let show = |p: DVec2| format!("({}, {})", tidy(p.x), tidy(p.y));
    let (start, end) = (DVec2::ZERO, DVec2::new(length, 0.0));
    let (Some(&first), Some(&last)) = (shape.first(), shape.last()) else {
        return Err("is drawn with no points".into());
    };
    if first.distance(start) > SPAN_TOLERANCE {
        return Err(format!(
            "is drawn to start at {}, not at the edge's left end {}: its boundary curves \
             must close a loop with the edge, from one end of it to the other",
            show(first),
            show(start)
        ));
    }
    if last.distance(end) > SPAN_TOLERANCE {
        return Err(format!(
            "is drawn to end at {}, not at the edge's right end {} (the edge is {} mm \
             long): its boundary curves must close a loop with the edge, from one end of \
             it to the other",
            show(last),
            show(end),
            tidy(length)
        ));
    }
    let mut points = shape.to_vec();
    let k = points.len();
    points[0] = start;
    points[k - 1] = end;
    if k < 3 {
        return Err("is drawn along the edge only: it must rise from it".into());
    }
    if let Some(&low) = points[1..k - 1].iter().find(|p| p.y <= SPAN_TOLERANCE) {
        return Err(format!(
            "is drawn down to the edge (or below it) at {}: between its ends it must \
             stay above the edge",
            show(low)
        ));
    }
    if triangulate_loops(&[points.clone()]).is_err() {
        return Err("is drawn crossing itself".into());
    }
    Ok(points)
}

/// How far from its edge a flange's point may lie (mm): further, the point picks no
/// edge of the sheet.
pub const PICK_REACH: f64 = 5.0;

/// A vertex id no vertex has: the edge of a return flange, which stands on no edge of
/// the plate, in the lists of the plate's flange edges.
const NO_VERTEX: VertexId = VertexId(u32::MAX);

/// What [`add_return`] added: the edge it stands on (its ends' points), its far
/// corners (over the foot's ends, in order), its own far edge with its frame, its strips' sides (on a radius, the bend's
/// facets, then the straight return), and its foot as later returns see it.
struct AddedReturn {
    foot: (DVec3, DVec3),
    far_corners: [VertexId; 2],
    far_edge: (EdgeId, DVec3, DVec3),
    strips: Vec<(FaceId, FaceId)>,
    foot_of: ReturnFoot,
    /// The joins made with earlier returns.
    joins: Vec<ReturnJoin>,
}

/// A return joined to an earlier one at a corner: the earlier return, which end of
/// each (in their feet's order) meets the other there.
#[derive(Debug, Clone, Copy)]
struct ReturnJoin {
    other: usize,
    their_end: usize,
    own_end: usize,
}

/// A return flange as a later return on a neighbouring flange sees it: the vertices at
/// the ends of the edge it stands on, how it stands there, and its far corners over
/// those ends (in the same order).
#[derive(Debug, Clone)]
struct ReturnFoot {
    ends: [VertexId; 2],
    standing: Standing,
    far_corners: [VertexId; 2],
}

/// What a return flange finds of the flanges before it: each one's far edge with its
/// frame (see [`add_return`]), which of its far corners it shares with a flange joined
/// to it there, and each return's foot.
struct Earlier<'a> {
    far_edges: &'a [Option<(EdgeId, DVec3, DVec3)>],
    ends_joined: &'a [[bool; 2]],
    feet: &'a [Option<ReturnFoot>],
}

/// Why a return flange could not be added: a reason of its own, or a reason it cannot
/// be joined to the earlier return `other` at the corner `at`.
enum ReturnProblem {
    Alone(String),
    Meets {
        other: usize,
        at: DVec3,
        why: String,
    },
}

impl From<String> for ReturnProblem {
    fn from(why: String) -> Self {
        ReturnProblem::Alone(why)
    }
}

/// Adds return flange `index` of `spec` on the far edge of the earlier flange named
/// `parent`, its far corners `height` away, rising `angle` up from the parent towards
/// the parent's inside (the far edge's frame: the direction the parent rises in from
/// its foot and its inside's normal). A return on a flange standing alone is
/// `Sheet::flange` on that edge (and on each strip's far edge in turn, on a radius).
/// Where the parent is joined to a neighbour at a corner and a return already stands
/// on that neighbour, the two returns are joined there too (four sheets meet at the
/// corner: a brim round a tray's rim), each cut on the line where they meet
/// ([`corners::return_mitre`]): the return is added on a run of picked edges that goes
/// up the earlier return's end and along the parent's far edge (Skze, then Smev and
/// Smel, as a plate's flanges at a corner).
fn add_return(
    sheet: &mut Sheet,
    mid: &mut MidSurface,
    spec: &PlateSpec,
    index: usize,
    parent: &str,
    earlier: &Earlier,
) -> Result<AddedReturn, ReturnProblem> {
    let flange = &spec.flanges[index];
    let topo = |e: TopologyError| ReturnProblem::Alone(e.to_string());
    let Some(p) = spec.flanges[..index].iter().rposition(|f| f.name == parent) else {
        let run = spec.flanges[..index]
            .iter()
            .any(|f| f.name.starts_with(&format!("{parent}.")));
        return Err(if run {
            format!(
                "cannot stand on flange `{parent}`: it runs along several edges, so it has \
                 no one far edge (a return named after a run runs along it all)"
            )
        } else {
            format!("stands `on` flange `{parent}`, but no flange of that name comes before it")
        }
        .into());
    };
    let Some((edge, rise, inside)) = earlier.far_edges.get(p).copied().flatten() else {
        return Err(format!(
            "cannot stand on flange `{parent}`: its far edge is drawn (a `shape`), not one \
             straight edge"
        )
        .into());
    };
    let (h1, _) = sheet.brep.halves_of(edge).map_err(topo)?;
    let ends = [
        sheet.brep.vertex(h1).map_err(topo)?,
        sheet
            .brep
            .vertex(sheet.brep.next(h1).map_err(topo)?)
            .map_err(topo)?,
    ];
    let point = |mid: &MidSurface, v: VertexId| {
        mid.point(v)
            .ok_or_else(|| ReturnProblem::Alone("an edge without points".into()))
    };
    let foot = (point(mid, ends[0])?, point(mid, ends[1])?);
    // Its strips' reaches from the edge: on a radius, the bend's chords first (turning
    // towards the inside, or away from it for an angle below 0), then the straight
    // return.
    let towards = if flange.angle < 0.0 { -inside } else { inside };
    let turned = FlangeSpec {
        angle: flange.angle.abs(),
        ..flange.clone()
    };
    let reaches = flange_reaches(&turned, spec.thickness, rise, towards);
    let standing = Standing {
        from: foot.0,
        to: foot.1,
        rise: turned.angle.cos() * rise + turned.angle.sin() * towards,
        height: flange.height,
    };
    let (b, a) = (flange.angle.sin(), flange.angle.cos());
    let frame = (a * rise + b * inside, -b * rise + a * inside);
    // The earlier returns it meets at its ends: each (the return, its end there, the
    // far corner over that end on this return's side of the sheet).
    let mut meets: [Option<(usize, usize, VertexId)>; 2] = [None, None];
    for (end, &v) in ends.iter().enumerate() {
        let twin = sheet.twin_vertex(v).map_err(topo)?;
        for (k, foot) in earlier.feet[..index].iter().enumerate() {
            let Some(foot) = foot else { continue };
            for j in 0..2 {
                if foot.ends[j] == v {
                    meets[end] = Some((k, j, foot.far_corners[j]));
                } else if foot.ends[j] == twin {
                    let far = sheet.twin_vertex(foot.far_corners[j]).map_err(topo)?;
                    meets[end] = Some((k, j, far));
                }
            }
        }
    }
    if meets == [None, None] && !earlier.ends_joined[p].contains(&true) {
        // Standing alone on a flange standing alone: swept off its far edge.
        let mut strips = Vec::with_capacity(reaches.len());
        let mut far = edge;
        let mut last = DVec3::ZERO;
        let mut far_corners = [NO_VERTEX; 2];
        for &reach in &reaches {
            let made = sheet.flange(far).map_err(topo)?;
            for (base, end) in made.far_ends {
                let from = point(mid, base)?;
                mid.place(sheet, end, from + reach - last).map_err(topo)?;
            }
            let [one, other] = made.sides[..] else {
                return Err("a return flange's strip has not two sides"
                    .to_string()
                    .into());
            };
            strips.push((one, other));
            far_corners = made.far_ends.map(|(_, end)| end);
            far = made.far_edge;
            last = reach;
        }
        // Its far corners in the order of its foot's ends, for later returns.
        let mut over_ends = far_corners;
        let first = point(mid, far_corners[0])?;
        if first.distance(foot.1) < first.distance(foot.0) {
            over_ends.swap(0, 1);
        }
        let foot_of = ReturnFoot {
            ends,
            standing,
            far_corners: over_ends,
        };
        let added = AddedReturn {
            foot,
            far_corners: over_ends,
            far_edge: (far, frame.0, frame.1),
            strips,
            foot_of,
            joins: Vec::new(),
        };
        return Ok(added);
    }
    if flange.radius > 0.0 {
        return Err(format!(
            "cannot have a bend radius on flange `{parent}`, which is joined to another at \
             a corner: the bends would need a curved corner between them"
        )
        .into());
    }
    // Joined: where each joined end's far corner goes, on the line the two meet on.
    let mut joins = Vec::new();
    let mut tops = [None, None];
    for (end, meet) in meets.iter().enumerate() {
        let Some((other, j, _)) = *meet else { continue };
        let at = [foot.0, foot.1][end];
        let fail = |why: String| ReturnProblem::Meets { other, at, why };
        if spec.flanges[other].radius > 0.0 {
            return Err(fail(
                "a return flange with a bend radius cannot be joined at a corner yet: the \
                 bends would need a curved corner between them"
                    .into(),
            ));
        }
        let Some(theirs) = &earlier.feet[other] else {
            continue;
        };
        let top = corners::return_mitre(at, &theirs.standing, &standing).map_err(fail)?;
        tops[end] = Some(top);
        joins.push(ReturnJoin {
            other,
            their_end: j,
            own_end: end,
        });
    }
    let (before, after) = (meets[0].map(|m| m.2), meets[1].map(|m| m.2));
    let mut path: Vec<VertexId> = before.into_iter().collect();
    path.extend(ends);
    path.extend(after);
    let curves = 3 - before.iter().count() - after.iter().count();
    let added = sheet
        .add_sheet(&[Piece::Picked(path.clone()), Piece::Curves(curves)])
        .map_err(topo)?;
    let chain = curve_chain(sheet, path[path.len() - 1], &added.curves).map_err(topo)?;
    let k = chain.len();
    if k != curves + 1 {
        return Err("a new far edge is not a chain of curves".to_string().into());
    }
    let far_corners = [before.unwrap_or(chain[k - 2]), after.unwrap_or(chain[1])];
    for (end, (&v, at)) in far_corners.iter().zip([foot.0, foot.1]).enumerate() {
        let to = tops[end].unwrap_or(at + flange.height * standing.rise);
        mid.place(sheet, v, to).map_err(topo)?;
    }
    let far = far_curve(sheet, &added.curves, far_corners)
        .ok_or_else(|| ReturnProblem::Alone("a return flange has no far edge".into()))?;
    let foot_of = ReturnFoot {
        ends,
        standing,
        far_corners,
    };
    let added = AddedReturn {
        foot,
        far_corners,
        far_edge: (far, frame.0, frame.1),
        strips: vec![added.sides],
        foot_of,
        joins,
    };
    Ok(added)
}

/// The index of the flange named `name` in `spec`; refused, saying so, when there is
/// none (or only a run's strips by that name: then one of them must be named).
fn flange_named(spec: &PlateSpec, name: &str) -> Result<usize, String> {
    if let Some(k) = spec.flanges.iter().position(|f| f.name == name) {
        return Ok(k);
    }
    let run = spec
        .flanges
        .iter()
        .any(|f| f.name.starts_with(&format!("{name}.")));
    Err(if run {
        format!(
            "finds no one flange `{name}`: it runs along several edges; name one of its \
             strips, `{name}.1`, `{name}.2`, ..."
        )
    } else {
        format!("finds no flange `{name}`")
    })
}

/// Adds a cover across the far edges `far` of two flanges: `add_sheet` on the two
/// edges, each a picked run, with one boundary curve after each (Smep joins the two
/// edges' zero-area loops, Smel closes the sheet). The edges are taken on the sides
/// that continue the plate's top (`parts`, the plate's parts on its top), so the cover
/// continues them, and its loop runs along each as that side does: the curves go from
/// the end of one edge to the start of the other. The four corners must lie in one
/// plane and bound a quad that does not cross itself. Returns the cover's sides and
/// which of them continues the plate's top.
fn add_cover(
    sheet: &mut Sheet,
    mid: &MidSurface,
    parts: &[FaceId],
    far: [EdgeId; 2],
) -> Result<((FaceId, FaceId), FaceId), String> {
    let topo = |e: TopologyError| e.to_string();
    let top = top_sides(sheet, parts).map_err(topo)?;
    // Each edge's run along the top's side: its half-edge in a face of `top`.
    let mut runs = Vec::with_capacity(2);
    for edge in far {
        let EdgeRole::Side { twin } = sheet.edge_role(edge).map_err(topo)? else {
            return Err("stands on an edge that is not a sheet's edge".into());
        };
        let b = &sheet.brep;
        let mut run = None;
        for e in [edge, twin] {
            let (p, m) = b.halves_of(e).map_err(topo)?;
            for h in [p, m] {
                let face = b.face_with(b.loop_with(h).map_err(topo)?).map_err(topo)?;
                if top.contains(&face) {
                    run = Some([
                        b.vertex(h).map_err(topo)?,
                        b.vertex(b.next(h).map_err(topo)?).map_err(topo)?,
                    ]);
                }
            }
        }
        runs.push(run.ok_or_else(|| "stands on an edge no side of the part reaches".to_string())?);
    }
    let point = |v: VertexId| {
        mid.point(v)
            .ok_or_else(|| "an edge without points".to_string())
    };
    let quad = [
        point(runs[0][0])?,
        point(runs[0][1])?,
        point(runs[1][0])?,
        point(runs[1][1])?,
    ];
    check_cover_quad(&quad)?;
    let added = sheet
        .add_sheet(&[
            Piece::Picked(runs[0].to_vec()),
            Piece::Curves(1),
            Piece::Picked(runs[1].to_vec()),
            Piece::Curves(1),
        ])
        .map_err(|e| format!("cannot be added across the two far edges: {e}"))?;
    let top = top_sides(sheet, parts).map_err(topo)?;
    let inside = if top.contains(&added.sides.0) {
        added.sides.0
    } else {
        added.sides.1
    };
    Ok((added.sides, inside))
}

/// How far off one plane a cover's corners may lie (mm).
const COVER_PLANE: f64 = 1e-6;

/// A cover's quad (its corners in the order its loop runs) checked: in one plane, of
/// an area, and not crossing itself (the two far edges running the same way round).
fn check_cover_quad(quad: &[DVec3; 4]) -> Result<(), String> {
    let centre = quad.iter().sum::<DVec3>() / 4.0;
    let normal = (0..4)
        .map(|i| quad[i].cross(quad[(i + 1) % 4]))
        .sum::<DVec3>()
        .normalize_or_zero();
    if normal == DVec3::ZERO {
        return Err("would have no area: the two far edges lie on one line".into());
    }
    let off = quad
        .iter()
        .map(|p| (*p - centre).dot(normal).abs())
        .fold(0.0, f64::max);
    if off > COVER_PLANE {
        return Err(format!(
            "would not be flat: the two far edges do not lie in one plane (a corner is {} mm \
             off the plane of the four)",
            tidy(off)
        ));
    }
    let across = normal.any_orthonormal_vector();
    let up = normal.cross(across);
    let flat: Vec<DVec2> = quad
        .iter()
        .map(|p| DVec2::new((*p - centre).dot(across), (*p - centre).dot(up)))
        .collect();
    if triangulate_loops(&[flat]).is_err() {
        return Err(
            "would cross itself: its far edges run the same way, so joining each's end to \
             the other's start crosses the two joins"
                .into(),
        );
    }
    Ok(())
}

/// The sides on the plate's top side of the part: the parts `parts`, and every side
/// reached from them across an edge two sides share (the insides of flanges, the tops
/// of lifted regions, ...), so all that face the way the plate's top does.
fn top_sides(sheet: &Sheet, parts: &[FaceId]) -> Result<BTreeSet<FaceId>, TopologyError> {
    let b = &sheet.brep;
    let mut seen: BTreeSet<FaceId> = parts.iter().copied().collect();
    let mut queue: Vec<FaceId> = parts.to_vec();
    while let Some(f) = queue.pop() {
        for &l in b.loops_of(f)? {
            for h in b.loop_halves(l)? {
                let across = b.face_with(b.loop_with(b.mate(h)?)?)?;
                if matches!(sheet.face_role(across)?, FaceRole::Side { .. }) && seen.insert(across)
                {
                    queue.push(across);
                }
            }
        }
    }
    Ok(seen)
}

/// A new sheet's far edge: of its boundary curves `curves`, the one between its far
/// corners `far_corners` (either of a twin pair).
fn far_curve(sheet: &Sheet, curves: &[EdgeId], far_corners: [VertexId; 2]) -> Option<EdgeId> {
    let b = &sheet.brep;
    let twins = |v: VertexId| [Some(v), sheet.twin_vertex(v).ok()];
    curves.iter().copied().find(|&c| {
        b.halves_of(c)
            .and_then(|(x, y)| Ok([b.vertex(x)?, b.vertex(y)?]))
            .is_ok_and(|vs| {
                vs[0] != vs[1]
                    && vs
                        .iter()
                        .all(|&v| far_corners.iter().any(|&f| twins(f).contains(&Some(v))))
            })
    })
}

/// The corner of the part nearest `near` (of a vertex and its twin, the one of lower
/// id). Refused when none lies within [`PICK_REACH`], or two lie as near.
fn corner_near(sheet: &Sheet, mid: &MidSurface, near: DVec3) -> Result<VertexId, String> {
    let found = vertices_by_distance(sheet, mid, near);
    let Some(&(d, v)) = found.first() else {
        return Err("finds no corner".into());
    };
    if d > PICK_REACH {
        return Err(format!(
            "picks no corner of the part: its point {} lies {} mm from the nearest, and a \
             picked corner must lie within {} mm of its point",
            show(near),
            tidy(d),
            tidy(PICK_REACH)
        ));
    }
    if let Some(&(d2, w)) = found.get(1) {
        if d2 - d < 1e-9 {
            let at = |u: VertexId| mid.point(u).map(show).unwrap_or_default();
            return Err(format!(
                "picks no one corner: its point {} lies as near the corner at {} as the \
                 corner at {}",
                show(near),
                at(v),
                at(w)
            ));
        }
    }
    Ok(v)
}

/// The edge of the plate's parts nearest `near`: its vertices on the top side, in the
/// order the part's outer loop runs them, and their points. Refused when `near` lies
/// more than [`PICK_REACH`] from every edge, or as near two edges (a corner).
fn nearest_edge(
    sheet: &Sheet,
    mid: &MidSurface,
    parts: &[FaceId],
    near: DVec3,
) -> Result<(VertexId, VertexId, DVec3, DVec3), String> {
    let mut edges = Vec::new();
    for &part in parts {
        let ring = sheet.brep.outer_vertices(part).map_err(|e| e.to_string())?;
        let k = ring.len();
        edges.extend((0..k).map(|i| (ring[i], ring[(i + 1) % k])));
    }
    let mut found: Vec<(f64, (VertexId, VertexId, DVec3, DVec3))> = edges
        .iter()
        .filter_map(|&(a, c)| {
            let (pa, pc) = (mid.point(a)?, mid.point(c)?);
            Some((distance_to_segment(pa, pc, near), (a, c, pa, pc)))
        })
        .collect();
    found.sort_by(|x, y| x.0.total_cmp(&y.0));
    let Some(&(d, edge)) = found.first() else {
        return Err("finds no edge".into());
    };
    if d > PICK_REACH {
        return Err(format!(
            "picks no edge of the sheet: its point {} lies {} mm from the nearest edge, \
             and a picked edge must lie within {} mm of its point",
            show(near),
            tidy(d),
            tidy(PICK_REACH)
        ));
    }
    let (a, c, pa, pc) = edge;
    // The next edge other than this one (a crease is in two parts' rings).
    let other = found
        .iter()
        .find(|(_, (x, y, ..))| (*x, *y) != (a, c) && (*x, *y) != (c, a));
    if let Some(&(d2, (_, _, qa, qc))) = other {
        if d2 - d < 1e-9 {
            return Err(format!(
                "picks no one edge: its point {} lies as near the edge from {} to {} as the \
                 edge from {} to {}",
                show(near),
                show(pa),
                show(pc),
                show(qa),
                show(qc)
            ));
        }
    }
    Ok(edge)
}

/// A point as a designer reads it: `(x, y, z)` to the micrometre.
fn show(p: DVec3) -> String {
    format!("({}, {}, {})", tidy(p.x), tidy(p.y), tidy(p.z))
}

/// The vertices along a new sheet's boundary curves `curves`, which run one after
/// another from `start`: `start`, then each curve's far end.
fn curve_chain(
    sheet: &Sheet,
    start: VertexId,
    curves: &[EdgeId],
) -> Result<Vec<VertexId>, TopologyError> {
    let b = &sheet.brep;
    let mut chain = vec![start];
    for &curve in curves {
        let (p, m) = b.halves_of(curve)?;
        let (x, y) = (b.vertex(p)?, b.vertex(m)?);
        let at = chain[chain.len() - 1];
        chain.push(if x == at { y } else { x });
    }
    Ok(chain)
}

/// Whether the crease `e` lost the part on one side of it to a removal: it is gone, or
/// a thickness face now lines it (it lies on the free boundary).
fn removed_beside(sheet: &Sheet, e: EdgeId) -> bool {
    let b = &sheet.brep;
    let Ok((p, m)) = b.halves_of(e) else {
        return true;
    };
    [p, m].into_iter().any(|h| {
        b.loop_with(h)
            .and_then(|l| b.face_with(l))
            .and_then(|f| sheet.face_role(f))
            .map_or(true, |r| r == FaceRole::Thickness)
    })
}
