//! A sheet part as a designer declares it: a plate over an outline on a working plane,
//! holes punched through it, flanges on its edges, and a thickness; built by the sheet
//! operations ([`super::topology`]), placed ([`super::geometry`]) and made solid
//! ([`super::thicken`]).

use std::sync::Arc;

use std::f64::consts::FRAC_PI_2;

use glam::{DVec2, DVec3};

use super::geometry::{bend, distance_to_segment, newell, MidSurface};
use super::junction::{meetings, Junction, Meeting};
use super::thicken::{thicken_named, Gauge, ThickenError};
use super::topology::{
    EdgeId, EdgeRole, FaceId, FaceRole, Piece, Removal, Sheet, TopologyError, VertexId,
};
use crate::geom::mesh::{crossings, Face, Mesh};
use crate::geom::tessellate::triangulate_loops;
use crate::geom::trimmed::polygon_winding;
use crate::geom::MAX_COORDINATE;

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
    /// Faces removed, each picked by a point.
    pub removals: Vec<RemoveSpec>,
    /// The flanges, in order.
    pub flanges: Vec<FlangeSpec>,
    /// The thickness (mm) of the plate, and of each flange not given its own.
    pub thickness: f64,
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
}

/// A face removed from the part (paper 003, section 4.4, Fig. 11-12), picked by a point
/// over it in the outline's view: so far a lifted region's top, which leaves a passage
/// lined by the region's walls (a collar, as an extruded hole).
#[derive(Debug, Clone, PartialEq)]
pub struct RemoveSpec {
    /// Its name.
    pub name: String,
    /// A point over the face, in the outline's view (on the working plane).
    pub at: DVec3,
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
    /// Removal `index` cannot be made.
    Remove { index: usize, why: String },
    /// Flange `index` cannot be added.
    Flange { index: usize, why: String },
    /// Flange `index` meets flange `other` at the corner `at`: three sheets would meet at
    /// one vertex, which the thickening does not make yet (one of the paper's open
    /// problems).
    FlangesMeet {
        index: usize,
        other: usize,
        at: DVec3,
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
            PartProblem::FlangesMeet { at, .. } => write!(
                f,
                "the flanges meet at the corner ({}, {}, {}): three sheets would meet at one \
                 vertex, which the thickening does not make yet",
                tidy(at.x),
                tidy(at.y),
                tidy(at.z)
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
}

/// Builds the plate of `spec`: the initial sheet over the outline, each hole punched,
/// each flange added on the free edge nearest its point (three boundary curves), then
/// the solid.
pub fn build(spec: &PlateSpec) -> Result<SheetPart, PartProblem> {
    let n = spec.normal.normalize_or_zero();
    if n == DVec3::ZERO || spec.outline.len() < 3 {
        return Err(PartProblem::Outline(
            "needs 3 points or more on a plane".into(),
        ));
    }
    check_sizes(spec)?;
    let frame = Frame::new(spec.outline[0], n);
    let mut outline = counter_clockwise(&spec.outline, n);
    let mut nears: Vec<DVec3> = spec.flanges.iter().map(|f| f.near).collect();
    for (index, flange) in spec.flanges.iter().enumerate() {
        if let Some((from, to)) = flange.span {
            nears[index] = split_outline(&mut outline, from, to)
                .map_err(|why| PartProblem::Flange { index, why })?;
        }
    }
    let mut bend_ends = Vec::with_capacity(spec.bends.len());
    for (index, bend) in spec.bends.iter().enumerate() {
        let bad = |why: String| PartProblem::Bend { index, why };
        if !(bend.angle.is_finite() && bend.angle.abs() < std::f64::consts::PI) {
            return Err(bad("angle must lie between -180 and 180 deg".into()));
        }
        let from = add_corner(&mut outline, bend.from).map_err(bad)?;
        let to = add_corner(&mut outline, bend.to).map_err(bad)?;
        if from.distance(to) < 10.0 * SPAN_TOLERANCE {
            return Err(bad("`from` and `to` lie too close together".into()));
        }
        bend_ends.push((from, to));
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
    let mut cuts = Vec::with_capacity(spec.bends.len());
    for (index, &(from, to)) in bend_ends.iter().enumerate() {
        let bad = |why: String| PartProblem::Bend { index, why };
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
        let (crease, new) = sheet.split(part, vf, vt).map_err(|e| bad(e.to_string()))?;
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
            crease,
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
    // Removals: the face under each point, in the paper's cases (section 4.4).
    let mut removals = Vec::with_capacity(spec.removals.len());
    for (index, removal) in spec.removals.iter().enumerate() {
        let bad = |why: String| PartProblem::Remove { index, why };
        let q = frame.flat(removal.at);
        let top = lift_tops
            .iter()
            .position(|ring| polygon_winding(ring, q) != 0)
            .map(|k| lifted[k].0);
        let face = match top {
            Some(face) => face,
            None if cuts.is_empty()
                && flat_loops[1..].iter().all(|l| polygon_winding(l, q) == 0) =>
            {
                return Err(bad(
                    "would take the whole plate: nothing would be left".into()
                ))
            }
            None => {
                return Err(bad(
                    "finds no face to remove under its point: give a point on a lifted \
                     region's top"
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
        removals.push(case);
    }
    // Flanges: on the outline edge nearest each point, if it is still free.
    let mut flange_edges = Vec::with_capacity(spec.flanges.len());
    let mut gauge = Gauge::uniform(spec.thickness);
    let mut flange_sides = Vec::with_capacity(spec.flanges.len());
    for (index, flange) in spec.flanges.iter().enumerate() {
        let bad = |why: String| PartProblem::Flange { index, why };
        if !(flange.height.is_finite() && flange.height > 0.0) {
            return Err(bad(format!(
                "height must be above 0, not {}",
                flange.height
            )));
        }
        if let Some(t) = flange.thickness {
            if !(t.is_finite() && t > 0.0) {
                return Err(bad(format!("thickness must be above 0, not {t}")));
            }
        }
        if !(flange.radius.is_finite() && flange.radius >= 0.0) {
            return Err(bad(format!(
                "radius must be 0 or more, not {}",
                flange.radius
            )));
        }
        if flange.radius > 0.0 && flange.thickness.is_some() {
            return Err(bad(
                "cannot have both a bend radius and its own thickness: a flange of \
                 another gauge is a separate piece joined at the edge, not bent from the \
                 plate"
                    .into(),
            ));
        }
        if !(flange.angle.is_finite() && (0.0..std::f64::consts::PI).contains(&flange.angle)) {
            return Err(bad(
                "angle must lie from 0 up to (not including) 180 deg".into()
            ));
        }
        // The edges of the plate's parts, each as its part's outer loop runs it.
        let mut edges = Vec::new();
        for &part in &parts {
            let ring = sheet
                .brep
                .outer_vertices(part)
                .map_err(|e| bad(e.to_string()))?;
            let k = ring.len();
            edges.extend((0..k).map(|i| (ring[i], ring[(i + 1) % k])));
        }
        let (a, c) = edges
            .iter()
            .map(|&(a, c)| {
                let d = match (mid.point(a), mid.point(c)) {
                    (Some(pa), Some(pc)) => distance_to_segment(pa, pc, nears[index]),
                    _ => f64::INFINITY,
                };
                (d, (a, c))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map(|(_, e)| e)
            .ok_or_else(|| bad("finds no edge".into()))?;
        let (pa, pc) = (
            mid.point(a)
                .ok_or_else(|| bad("edge has no point".into()))?,
            mid.point(c)
                .ok_or_else(|| bad("edge has no point".into()))?,
        );
        let show = |p: DVec3| format!("({}, {}, {})", tidy(p.x), tidy(p.y), tidy(p.z));
        // Three sheets at one vertex (two flanges meeting at a corner) are one of the
        // paper's open problems: the solid there is not made yet, so it is refused.
        for (other, &(x, y)) in flange_edges.iter().enumerate() {
            let same = |p: DVec3, q: DVec3| p.distance(q) < 1e-9;
            if (same(pa, x) && same(pc, y)) || (same(pa, y) && same(pc, x)) {
                return Err(bad(format!(
                    "cannot go on the edge nearest its point, from {} to {}: another flange \
                     is there already",
                    show(pa),
                    show(pc)
                )));
            }
            for corner in [pa, pc] {
                if corner.distance(x) < 1e-9 || corner.distance(y) < 1e-9 {
                    return Err(PartProblem::FlangesMeet {
                        index,
                        other,
                        at: corner,
                    });
                }
            }
        }
        let added = sheet
            .add_sheet(&[Piece::Picked(vec![a, c]), Piece::Curves(3)])
            .map_err(|_| {
                bad(format!(
                    "cannot go on the edge nearest its point, from {} to {}: another flange \
                     is there already",
                    show(pa),
                    show(pc)
                ))
            })?;
        flange_edges.push((pa, pc));
        // Where each strip's far edge lies, from the edge: the bend's facets, then the
        // straight flange.
        let out = (pc - pa).cross(n).normalize_or_zero();
        let reaches = flange_reaches(flange, spec.thickness, out, n);
        // The first curve runs from c to the new vertex beside it, the second (the far
        // edge) on to the new vertex beside a, the third back to a.
        let b = &sheet.brep;
        let far_end = |curve: usize, from: VertexId| -> Result<VertexId, PartProblem> {
            let (p, m) = b
                .halves_of(added.curves[curve])
                .map_err(|e| bad(e.to_string()))?;
            let ends = [b.vertex(p), b.vertex(m)].map(|r| r.map_err(|e| bad(e.to_string())));
            let [x, y] = ends;
            let (x, y) = (x?, y?);
            Ok(if x == from { y } else { x })
        };
        let (wc, wa) = (far_end(0, c)?, far_end(2, a)?);
        mid.place(&sheet, wc, pc + reaches[0])
            .map_err(|e| bad(e.to_string()))?;
        mid.place(&sheet, wa, pa + reaches[0])
            .map_err(|e| bad(e.to_string()))?;
        let mut strips = vec![added.sides];
        let mut far = added.curves[1];
        for step in reaches.windows(2) {
            let strip = sheet.flange(far).map_err(|e| bad(e.to_string()))?;
            for (base, end) in strip.far_ends {
                let from = mid
                    .point(base)
                    .ok_or_else(|| bad("a bend's edge has no point".into()))?;
                mid.place(&sheet, end, from + step[1] - step[0])
                    .map_err(|e| bad(e.to_string()))?;
            }
            let [one, other] = strip.sides[..] else {
                return Err(bad("a bend's strip has not two sides".into()));
            };
            strips.push((one, other));
            far = strip.far_edge;
        }
        if let Some(t) = flange.thickness {
            gauge
                .sheets
                .extend(strips.iter().map(|&(side, _)| (side, t)));
        }
        flange_sides.push(strips);
    }
    // The bends turned, in order; a bend line may not end on a flange's edge (the
    // flange would have to bend too).
    for (index, cut) in cuts.iter().enumerate() {
        let bad = |why: String| PartProblem::Bend { index, why };
        let (from, to) = bend_ends[index];
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
        bend(
            &sheet,
            &mut mid,
            cut.fixed,
            cut.crease,
            spec.bends[index].angle,
        )
        .map_err(|e| bad(e.to_string()))?;
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
    let names = FaceNames::new(
        &sheet,
        spec,
        top,
        &cuts,
        &hole_rings,
        &lifted,
        &flange_sides,
    )
    .map_err(|e| PartProblem::Thicken(e.into()))?;
    let solid = thicken_named(&sheet, &mid, &gauge, |f| names.of(f)).map_err(|e| match e {
        ThickenError::Junction { at, .. } => PartProblem::Junction {
            at,
            flange: nearest_flange(at),
        },
        e => PartProblem::Thicken(e),
    })?;
    if let Some(c) = crossings(&solid).first() {
        return Err(PartProblem::SelfIntersection {
            at: c.at,
            flange: nearest_flange(c.at),
        });
    }
    let junctions = meetings(&sheet, &mid)
        .map_err(|e| PartProblem::Thicken(e.into()))?
        .into_iter()
        .filter_map(|m| match m {
            Meeting::Two(j) => Some(j),
            Meeting::Many { .. } => None,
        })
        .collect();
    let mid_mesh = mid_surface(&sheet, &mid).map_err(PartProblem::Thicken)?;
    let area = mesh_area(&mid_mesh);
    let volume = mesh_volume(&solid);
    Ok(SheetPart {
        sheet,
        mid,
        mid_mesh: Arc::new(mid_mesh),
        solid: Arc::new(solid),
        area,
        volume,
        junctions,
        removals,
    })
}

/// The name of each face of a plate's solid, as a designer would call it: `plate.top`
/// and `plate.bottom` (the top faces the working plane's normal), `plate.edge_K` across
/// the outline's edges, `HOLE.wall_K` lining a hole, and per flange `NAME.inside` (the
/// side that continues the plate's top, inside the bend), `NAME.outside` and
/// `NAME.edge_K`, and a bend's facets `NAME.bend_K.inside` and `.outside`; K counts
/// from 1 in the model's face order.
struct FaceNames {
    names: std::collections::BTreeMap<FaceId, String>,
}

impl FaceNames {
    fn new(
        sheet: &Sheet,
        spec: &PlateSpec,
        top: FaceId,
        cuts: &[Cut],
        hole_rings: &[Vec<VertexId>],
        lifts: &[(FaceId, Vec<FaceId>)],
        flanges: &[Vec<(FaceId, FaceId)>],
    ) -> Result<FaceNames, TopologyError> {
        let b = &sheet.brep;
        let mut names = std::collections::BTreeMap::new();
        // The plate's parts, named by the bend that turned them (the rest `plate`).
        let mut part_names = std::collections::BTreeMap::new();
        part_names.insert(top, "plate".to_string());
        for (k, cut) in cuts.iter().enumerate() {
            let before = part_names.get(&cut.part).cloned().unwrap_or_default();
            part_names.insert(cut.fixed, before);
            part_names.insert(cut.moved, spec.bends[k].name.clone());
        }
        for (&part, name) in &part_names {
            names.insert(part, format!("{name}.top"));
            if let FaceRole::Side { twin } = sheet.face_role(part)? {
                names.insert(twin, format!("{name}.bottom"));
            }
        }
        // The sides across the non-zero-length edges of face f.
        let neighbours = |f: FaceId| -> Result<Vec<FaceId>, TopologyError> {
            let mut out = Vec::new();
            for &l in b.loops_of(f)? {
                for h in b.loop_halves(l)? {
                    let Some(e) = b.edge(h)? else { continue };
                    if sheet.edge_role(e)? != EdgeRole::ZeroLength {
                        out.push(b.face_with(b.loop_with(b.mate(h)?)?)?);
                    }
                }
            }
            Ok(out)
        };
        for (k, strips) in flanges.iter().enumerate() {
            let name = &spec.flanges[k].name;
            // Each strip's inside continues the one before it (the plate's top first).
            let mut before = top;
            for (i, &(a, c)) in strips.iter().enumerate() {
                let inside = if neighbours(a)?.contains(&before) {
                    a
                } else {
                    c
                };
                let outside = if inside == a { c } else { a };
                let part = if i + 1 == strips.len() {
                    name.clone()
                } else {
                    format!("{name}.bend_{}", i + 1)
                };
                names.insert(inside, format!("{part}.inside"));
                names.insert(outside, format!("{part}.outside"));
                before = inside;
            }
        }
        let twin = |f: FaceId| -> Result<FaceId, TopologyError> {
            match sheet.face_role(f)? {
                FaceRole::Side { twin } => Ok(twin),
                FaceRole::Thickness => Ok(f),
            }
        };
        for (k, (cap, walls)) in lifts.iter().enumerate() {
            let name = &spec.lifts[k].name;
            names.insert(*cap, format!("{name}.top"));
            names.insert(twin(*cap)?, format!("{name}.bottom"));
            for (i, &w) in walls.iter().enumerate() {
                names.insert(w, format!("{name}.wall_{}.top", i + 1));
                names.insert(twin(w)?, format!("{name}.wall_{}.bottom", i + 1));
            }
        }
        // Thickness faces, named after the sheet they edge (or the hole they line).
        let mut counts = std::collections::BTreeMap::<String, usize>::new();
        for f in b.faces() {
            if sheet.face_role(f)? != FaceRole::Thickness {
                continue;
            }
            let vertices = b.outer_vertices(f)?;
            let hole = hole_rings.iter().position(|ring| {
                vertices.iter().any(|&v| {
                    ring.contains(&v) || sheet.twin_vertex(v).is_ok_and(|w| ring.contains(&w))
                })
            });
            let owner = neighbours(f)?.into_iter().find_map(|side| {
                flanges
                    .iter()
                    .position(|strips| strips.iter().any(|&(a, c)| side == a || side == c))
            });
            let prefix = match (hole, owner) {
                (Some(i), _) => format!("{}.wall", spec.holes[i].name),
                (None, Some(k)) => format!("{}.edge", spec.flanges[k].name),
                (None, None) => "plate.edge".to_string(),
            };
            let n = counts.entry(prefix.clone()).or_insert(0);
            *n += 1;
            names.insert(f, format!("{prefix}_{n}"));
        }
        // A hole or flange named `plate` could repeat a name: the later face gets its
        // id added, so every group name stays unique.
        let mut seen = std::collections::BTreeSet::new();
        for (f, name) in names.iter_mut() {
            if !seen.insert(name.clone()) {
                name.push_str(&format!("_{}", f.0));
                seen.insert(name.clone());
            }
        }
        Ok(FaceNames { names })
    }

    /// The name of face `f` (`face N` for one not named above).
    fn of(&self, f: FaceId) -> String {
        self.names
            .get(&f)
            .cloned()
            .unwrap_or_else(|| format!("face {}", f.0))
    }
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
        if !point(&r.at) {
            return Err(PartProblem::Remove {
                index,
                why: why("its point"),
            });
        }
    }
    for (index, f) in spec.flanges.iter().enumerate() {
        let span = f.span.is_none_or(|(a, c)| point(&a) && point(&c));
        let thick = f.thickness.is_none_or(fits);
        if !(point(&f.near) && span && fits(f.height) && fits(f.radius) && thick) {
            return Err(PartProblem::Flange {
                index,
                why: why("a point, a height, a radius or a thickness"),
            });
        }
    }
    Ok(())
}

/// A bend's split of the plate: the part split, the part that stays and the part that
/// turns (one of them the part split), and the crease between them.
struct Cut {
    part: FaceId,
    fixed: FaceId,
    moved: FaceId,
    crease: EdgeId,
}

/// Puts `p` into the outline as a corner of the edge nearest it (unless it is a corner
/// already) and returns it as placed. Refused when it lies off the outline.
fn add_corner(outline: &mut Vec<DVec3>, p: DVec3) -> Result<DVec3, String> {
    let k = outline.len();
    let (d, nearest) = (0..k)
        .map(|i| (distance_to_segment(outline[i], outline[(i + 1) % k], p), i))
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .ok_or_else(|| "finds no edge".to_string())?;
    if d > SPAN_TOLERANCE {
        return Err(format!(
            "must end on the outline, but ({}, {}, {}) is {} mm off it",
            tidy(p.x),
            tidy(p.y),
            tidy(p.z),
            tidy(d)
        ));
    }
    let (a, c) = (outline[nearest], outline[(nearest + 1) % k]);
    for corner in [a, c] {
        if corner.distance(p) <= SPAN_TOLERANCE {
            return Ok(corner);
        }
    }
    let along = c - a;
    let q = a + ((p - a).dot(along) / along.length_squared()) * along;
    outline.insert(nearest + 1, q);
    Ok(q)
}

/// Whether the open segment from `a` to `c` crosses the polygon's boundary (touching
/// it only at its ends, on corners, is not crossing) or runs outside it.
fn crosses_outline(outline: &[DVec2], a: DVec2, c: DVec2) -> bool {
    let k = outline.len();
    let near = |p: DVec2, q: DVec2| p.distance(q) < 1e-9;
    for i in 0..k {
        let (p, q) = (outline[i], outline[(i + 1) % k]);
        if near(p, a) || near(p, c) || near(q, a) || near(q, c) {
            continue;
        }
        let d = c - a;
        let e = q - p;
        let denom = d.perp_dot(e);
        if denom.abs() < 1e-12 {
            continue;
        }
        let t = (p - a).perp_dot(e) / denom;
        let u = (p - a).perp_dot(d) / denom;
        if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
            return true;
        }
    }
    polygon_winding(outline, 0.5 * (a + c)) == 0
}

/// The part of the plate (a side split off by bends) whose outline holds every point
/// of `flat`, and a corner of it to bridge a ring from.
fn part_holding(
    sheet: &Sheet,
    mid: &MidSurface,
    frame: &Frame,
    parts: &[FaceId],
    flat: &[DVec2],
) -> Result<(FaceId, VertexId), String> {
    for &part in parts {
        let corners = sheet.brep.outer_vertices(part).map_err(|e| e.to_string())?;
        let outline: Vec<DVec2> = corners
            .iter()
            .filter_map(|&v| mid.point(v))
            .map(|p| frame.flat(p))
            .collect();
        if flat.iter().all(|&q| polygon_winding(&outline, q) != 0) {
            return Ok((part, corners[0]));
        }
    }
    if parts.len() > 1 {
        Err("crosses a bend line, or is not inside the outline".into())
    } else {
        Err("is not inside the outline".into())
    }
}

/// Adds `flat`, a new loop inside the plate (a hole or a lifted region), to the plate's
/// loops: refused when a point of it lies outside the outline, when it crosses the
/// outline or another loop, or when it lies inside another loop or holds one.
fn add_loop(
    outline: &[DVec2],
    loops: &mut Vec<Vec<DVec2>>,
    flat: Vec<DVec2>,
) -> Result<(), String> {
    if flat.iter().any(|&q| polygon_winding(outline, q) == 0) {
        return Err("is not inside the outline".into());
    }
    for other in &loops[1..] {
        if other.iter().any(|&q| polygon_winding(&flat, q) != 0)
            || flat.iter().any(|&q| polygon_winding(other, q) != 0)
        {
            return Err("lies inside another hole or lifted region, or holds one".into());
        }
    }
    let mut trial = loops.clone();
    trial.push(flat);
    if triangulate_loops(&trial).is_err() {
        return Err("crosses the outline or another hole or lifted region".into());
    }
    *loops = trial;
    Ok(())
}

/// Places the ring a punch or region just made on side `top` (its last loop, which
/// runs against the outline: clockwise) at `ring` (counter-clockwise).
fn place_ring(
    sheet: &Sheet,
    mid: &mut MidSurface,
    top: FaceId,
    ring: &[DVec3],
) -> Result<Vec<VertexId>, TopologyError> {
    let b = &sheet.brep;
    let loops = b.loops_of(top)?;
    // `punch` and `region` leave the new ring last (`lkemr` appends it); a face has one
    // loop at least.
    let last = *loops.last().expect("a face has its outer loop");
    let vertices: Vec<VertexId> = b
        .loop_halves(last)?
        .into_iter()
        .map(|h| b.vertex(h))
        .collect::<Result<_, _>>()?;
    for (&v, &p) in vertices.iter().zip(ring.iter().rev()) {
        mid.place(sheet, v, p)?;
    }
    Ok(vertices)
}

/// The counter-clockwise polygon `ring` (seen along `n`) with every edge moved inward
/// by `by`, its corners where the moved edges meet; `None` when an edge would turn
/// round (the polygon too small for the inset).
fn inset(ring: &[DVec3], n: DVec3, by: f64) -> Option<Vec<DVec3>> {
    if by == 0.0 {
        return Some(ring.to_vec());
    }
    let k = ring.len();
    let inward = |i: usize| n.cross(ring[(i + 1) % k] - ring[i]).normalize_or_zero();
    let out: Vec<DVec3> = (0..k)
        .map(|i| {
            let (a, c) = (inward((i + k - 1) % k), inward(i));
            let denom = 1.0 + a.dot(c);
            if denom < 1e-9 {
                ring[i] + by * c
            } else {
                ring[i] + by * (a + c) / denom
            }
        })
        .collect();
    // Each edge keeps its direction.
    let keeps = (0..k).all(|i| {
        let before = ring[(i + 1) % k] - ring[i];
        let after = out[(i + 1) % k] - out[i];
        before.dot(after) > 0.0
    });
    keeps.then_some(out)
}

/// How far a flange's `from` and `to` may lie off the outline's edge (mm).
pub const SPAN_TOLERANCE: f64 = 0.01;

/// Puts the ends of a flange on part of an edge, `from` and `to`, into the outline as
/// vertices of the edge nearest their midpoint (where they are not corners already),
/// and returns a point on the part between them. Refused when they do not lie on one
/// edge or are too close together.
fn split_outline(outline: &mut Vec<DVec3>, from: DVec3, to: DVec3) -> Result<DVec3, String> {
    let k = outline.len();
    let middle = 0.5 * (from + to);
    let nearest = (0..k)
        .map(|i| {
            (
                distance_to_segment(outline[i], outline[(i + 1) % k], middle),
                i,
            )
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, i)| i)
        .ok_or_else(|| "finds no edge".to_string())?;
    let (a, c) = (outline[nearest], outline[(nearest + 1) % k]);
    let along = c - a;
    let length = along.length();
    let at = |p: DVec3| ((p - a).dot(along) / (length * length)).clamp(0.0, 1.0);
    for p in [from, to] {
        if distance_to_segment(a, c, p) > SPAN_TOLERANCE {
            return Err(format!(
                "`from` and `to` must lie on one edge of the outline, but ({}, {}, {}) is \
                 {} mm off the edge nearest them",
                tidy(p.x),
                tidy(p.y),
                tidy(p.z),
                tidy(distance_to_segment(a, c, p))
            ));
        }
    }
    let (s, e) = (at(from).min(at(to)), at(from).max(at(to)));
    if (e - s) * length < 10.0 * SPAN_TOLERANCE {
        return Err("`from` and `to` lie too close together on the edge".into());
    }
    // The new corners, in the outline's order along the edge; ends at a corner are kept.
    let inner: Vec<DVec3> = [s, e]
        .into_iter()
        .filter(|&u| u * length > SPAN_TOLERANCE && (1.0 - u) * length > SPAN_TOLERANCE)
        .map(|u| a + u * along)
        .collect();
    let count = inner.len();
    outline.splice(nearest + 1..nearest + 1, inner);
    debug_assert!(outline.len() == k + count);
    Ok(a + 0.5 * (s + e) * along)
}

/// The largest angle one facet of a bend turns through.
const BEND_STEP: f64 = std::f64::consts::PI / 12.0;

/// How far a bend's facets may lie inside its arc (mm).
const BEND_TOLERANCE: f64 = 0.01;

/// Where the far edge of each strip of a flange lies, from the edge it stands on
/// (`out` in the plate's plane away from it, `n` the plate's normal): first the facets
/// of its bend, as chords of the mid-surface's arc (inside radius plus half the
/// thickness) within [`BEND_TOLERANCE`] and [`BEND_STEP`], then the straight flange,
/// `height` long, at `angle` to the plate.
fn flange_reaches(flange: &FlangeSpec, thickness: f64, out: DVec3, n: DVec3) -> Vec<DVec3> {
    let dir = flange.angle.cos() * out + flange.angle.sin() * n;
    let rho = flange.radius + 0.5 * flange.thickness.unwrap_or(thickness);
    let steps = if flange.radius > 0.0 && flange.angle > 0.0 {
        let by_angle = (flange.angle / BEND_STEP).ceil();
        let chord = 2.0 * (1.0 - BEND_TOLERANCE / rho).clamp(-1.0, 1.0).acos();
        let by_sag = (flange.angle / chord.max(1e-3)).ceil();
        by_angle.max(by_sag).min(MAX_BEND_FACETS as f64) as usize
    } else {
        0
    };
    let arc = |phi: f64| rho * (phi.sin() * out + (1.0 - phi.cos()) * n);
    let mut reaches: Vec<DVec3> = (1..=steps)
        .map(|i| arc(flange.angle * i as f64 / steps as f64))
        .collect();
    let start = reaches.last().copied().unwrap_or(DVec3::ZERO);
    reaches.push(start + flange.height * dir);
    reaches
}

/// The most facets a bend is cut into.
const MAX_BEND_FACETS: usize = 64;

/// One side of each sheet (the one of lower id of a pair of twins), each face
/// triangulated in its plane.
fn mid_surface(sheet: &Sheet, mid: &MidSurface) -> Result<Mesh, ThickenError> {
    let b = &sheet.brep;
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for f in b.faces() {
        let FaceRole::Side { twin } = sheet.face_role(f)? else {
            continue;
        };
        if twin < f {
            continue;
        }
        let loops: Vec<Vec<DVec3>> = b
            .loops_of(f)?
            .iter()
            .map(|&l| {
                b.loop_halves(l)?
                    .into_iter()
                    .map(|h| {
                        let v = b.vertex(h)?;
                        mid.point(v)
                            .ok_or_else(|| TopologyError::Dead(format!("point of vertex {}", v.0)))
                    })
                    .collect::<Result<Vec<DVec3>, TopologyError>>()
            })
            .collect::<Result<_, _>>()?;
        let normal = newell(&loops[0]).normalize_or_zero();
        if normal == DVec3::ZERO {
            return Err(ThickenError::Degenerate(f));
        }
        let frame = Frame::new(loops[0][0], normal);
        let flat: Vec<Vec<DVec2>> = loops
            .iter()
            .map(|ring| ring.iter().map(|&p| frame.flat(p)).collect())
            .collect();
        let first = positions.len() as u32;
        positions.extend(loops.iter().flatten().copied());
        for [a, c, d] in triangulate_loops(&flat).map_err(|e| ThickenError::Triangulation(f, e))? {
            faces.push(Face::triangle(
                first + a as u32,
                first + c as u32,
                first + d as u32,
            ));
        }
    }
    Mesh::new(positions, faces)
        .map_err(|e| ThickenError::Topology(TopologyError::Invalid(e.to_string())))
}

/// `points` running counter-clockwise seen from along `n`.
fn counter_clockwise(points: &[DVec3], n: DVec3) -> Vec<DVec3> {
    let mut out = points.to_vec();
    if newell(&out).dot(n) < 0.0 {
        out.reverse();
    }
    out
}

/// A plane's 2-D coordinates.
struct Frame {
    origin: DVec3,
    u: DVec3,
    w: DVec3,
}

impl Frame {
    fn new(origin: DVec3, n: DVec3) -> Frame {
        let u = n.any_orthonormal_vector();
        Frame {
            origin,
            u,
            w: n.cross(u),
        }
    }

    fn flat(&self, p: DVec3) -> DVec2 {
        DVec2::new((p - self.origin).dot(self.u), (p - self.origin).dot(self.w))
    }
}

/// The area of a triangle mesh.
fn mesh_area(mesh: &Mesh) -> f64 {
    let p = mesh.positions();
    mesh.faces()
        .iter()
        .map(|f| {
            let i = f.indices();
            let (a, b, c) = (p[i[0] as usize], p[i[1] as usize], p[i[2] as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

/// The volume a closed, outward-facing triangle mesh encloses (divergence theorem).
fn mesh_volume(mesh: &Mesh) -> f64 {
    let p = mesh.positions();
    mesh.faces()
        .iter()
        .map(|f| {
            let i = f.indices();
            let (a, b, c) = (p[i[0] as usize], p[i[1] as usize], p[i[2] as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// A coordinate for a message: to 0.001 mm, without trailing zeros.
fn tidy(x: f64) -> String {
    let s = format!("{:.3}", x);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}
