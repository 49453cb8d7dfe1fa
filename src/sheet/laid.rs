//! A sheet part laid on its base surface ([`super::base`]): its mid-surface and its
//! solid, with every face cut finely enough to follow the surface.
//!
//! The part is built and made solid flat, as the designer draws it ([`super::thicken`]
//! plans the solid: each point with the mid-surface point it came from and the planes
//! it lies on). Laying it works each point out again on the curved faces:
//! - the mid-surface point goes onto the surface (`S(q) + z N(q)`);
//! - each plane is worked out again there from the map's derivative: a side's plane
//!   is its laid tangent plane, offset by half its sheet's thickness along the laid
//!   normal; a thickness face's plane runs through the laid edge, square to the laid
//!   side across it;
//! - the point goes where those planes meet, nearest the laid mid-surface point (least
//!   squares, as flat).
//!
//! So a side's points lie at exactly half the thickness from the laid mid-surface
//! along its normal, two sheets meeting on an edge still meet on the mitre of their
//! offset sides, and each edge of the free boundary is still square to its side.
//!
//! Each edge of the mid-surface is cut into segments whose laid midpoints stray at most
//! [`LAID_TOLERANCE`] from their chords, each solid edge along it at the same
//! fractions; each side face is filled with a grid of points (at the spacing a circle
//! of the surface's largest curvature needs for that tolerance) and triangulated with
//! its cut edges, flat, where its faces are planar; the triangles keep their corners'
//! order once laid. A sample's place along the edge follows the flat one (its offset
//! along the edge from its mid-surface point is the flat offset, stretched as the map
//! stretches the edge), so the samples stay in order between mitred corners.

use std::collections::hash_map::Entry;
use std::collections::HashMap;

use glam::{DMat3, DVec2, DVec3};
use nalgebra::{DMatrix, DVector};

use super::base::{BaseError, BaseSurface};
use super::geometry::{distance_to_segment, face_loops, mid_sides, newell, MidSurface};
use super::thicken::{PlaneRule, SolidPlan, ThickenError};
use super::topology::{FaceId, Sheet, TopologyError};
use crate::geom::mesh::{Face, FaceId as MeshFaceId, Mesh};
use crate::geom::tessellate::triangulate_loops_with;
use crate::geom::trimmed::polygon_winding;
use crate::geom::GeomError;

/// How far (mm) a laid face's triangles may stray from the face: the mid-surface's
/// chords from the surface, as a bend's facets from their arc.
pub const LAID_TOLERANCE: f64 = 0.01;

/// The widest and narrowest spacing (mm) of the points a laid face is filled with.
const WIDEST: f64 = 25.0;
const NARROWEST: f64 = 0.25;

/// The most segments an edge is cut into.
const MOST_SEGMENTS: usize = 4096;

/// The most grid points a face is filled with: beyond, the grid is spread wider (a face
/// far larger than the surface's curvature asks for would otherwise take millions).
const MOST_FILL: f64 = 40_000.0;

/// Singular values below this count as none (the planes' normals are unit vectors).
const RANK_TOLERANCE: f64 = 1e-9;

/// Why a part could not be laid on its surface.
#[derive(Debug, Clone, PartialEq)]
pub enum LaidError {
    /// A point of the part does not lie over the surface, or the surface stands too
    /// steep under it.
    Base(BaseError),
    /// The laid solid could not be made (a face that does not triangulate, a plane
    /// system that does not solve).
    Thicken(ThickenError),
}

impl std::fmt::Display for LaidError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LaidError::Base(e) => write!(f, "{e}"),
            LaidError::Thicken(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for LaidError {}

impl From<BaseError> for LaidError {
    fn from(e: BaseError) -> Self {
        LaidError::Base(e)
    }
}

impl From<ThickenError> for LaidError {
    fn from(e: ThickenError) -> Self {
        LaidError::Thicken(e)
    }
}

impl From<TopologyError> for LaidError {
    fn from(e: TopologyError) -> Self {
        LaidError::Thicken(ThickenError::Topology(e))
    }
}

/// How a part's faces are cut to follow the surface: the spacing of the points that
/// fill a face, and each mid-surface edge's cuts, worked out once and shared by every
/// face along the edge.
pub struct Refiner<'a> {
    base: &'a BaseSurface,
    spacing: f64,
    /// Per edge (its ends in a fixed order), its cuts: the points and their fractions.
    edges: HashMap<[u64; 6], Vec<(DVec3, f64)>>,
}

impl<'a> Refiner<'a> {
    /// Cuts for a part laid on `base`.
    pub fn new(base: &'a BaseSurface) -> Refiner<'a> {
        let curvature = base.curvature_bound();
        // A circle of radius r strays h = s^2 / (8 r) from a chord s long.
        let spacing = if curvature > 0.0 {
            (8.0 * LAID_TOLERANCE / curvature).sqrt()
        } else {
            WIDEST
        };
        Refiner {
            base,
            spacing: spacing.clamp(NARROWEST, WIDEST),
            edges: HashMap::new(),
        }
    }

    /// Where the mid-surface edge from `a` to `b` is cut, from `a` on: each cut's point
    /// and its fraction of the way to `b` (strictly between 0 and 1). The same points,
    /// bit for bit, whichever way round the edge is asked.
    fn cuts(&mut self, a: DVec3, b: DVec3) -> Result<Vec<(DVec3, f64)>, BaseError> {
        let key = |p: DVec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        let (ka, kb) = (key(a), key(b));
        let flipped = ka > kb;
        let (c, d) = if flipped { (b, a) } else { (a, b) };
        let id = if flipped {
            [kb[0], kb[1], kb[2], ka[0], ka[1], ka[2]]
        } else {
            [ka[0], ka[1], ka[2], kb[0], kb[1], kb[2]]
        };
        if !self.edges.contains_key(&id) {
            let cuts = self.cut(c, d)?;
            self.edges.insert(id, cuts);
        }
        let cuts = &self.edges[&id];
        Ok(if flipped {
            cuts.iter().rev().map(|&(p, t)| (p, 1.0 - t)).collect()
        } else {
            cuts.clone()
        })
    }

    /// The cuts of the edge from `c` to `d`: as many equal segments as the spacing
    /// asks, doubled until each laid segment's midpoint lies within the tolerance of
    /// its chord.
    fn cut(&self, c: DVec3, d: DVec3) -> Result<Vec<(DVec3, f64)>, BaseError> {
        if c == d {
            return Ok(Vec::new());
        }
        let (lc, ld) = (self.base.lay(c)?, self.base.lay(d)?);
        let mut n = ((ld - lc).length() / self.spacing).ceil().max(1.0) as usize;
        loop {
            let point = |k: usize| c + (d - c) * (k as f64 / n as f64);
            let laid: Vec<DVec3> = (0..=n)
                .map(|k| self.base.lay(point(k)))
                .collect::<Result<_, _>>()?;
            let mut fine = true;
            for k in 0..n {
                let middle = c + (d - c) * ((k as f64 + 0.5) / n as f64);
                let chord = 0.5 * (laid[k] + laid[k + 1]);
                if self.base.lay(middle)?.distance(chord) > LAID_TOLERANCE {
                    fine = false;
                    break;
                }
            }
            if fine || n >= MOST_SEGMENTS {
                return Ok((1..n).map(|k| (point(k), k as f64 / n as f64)).collect());
            }
            n *= 2;
        }
    }
}

/// The mid-surface of a part laid on `base`: one side of each sheet (the one of lower
/// id of a pair of twins), each face cut by `refiner` and laid, with each such side's
/// laid area (mm²).
pub fn lay_mid_surface(
    sheet: &Sheet,
    mid: &MidSurface,
    refiner: &mut Refiner,
) -> Result<(Mesh, Vec<(FaceId, f64)>), LaidError> {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let mut areas = Vec::new();
    for f in mid_sides(sheet)? {
        // The face's loops, each edge cut.
        let mut loops: Vec<Vec<DVec3>> = Vec::new();
        for corners in face_loops(sheet, mid, f)? {
            let mut ring = Vec::new();
            for (k, &p) in corners.iter().enumerate() {
                ring.push(p);
                let next = corners[(k + 1) % corners.len()];
                ring.extend(refiner.cuts(p, next)?.into_iter().map(|(q, _)| q));
            }
            loops.push(ring);
        }
        let normal = newell(&loops[0]).normalize_or_zero();
        if normal == DVec3::ZERO {
            return Err(ThickenError::Degenerate(f).into());
        }
        let plane = Plane::new(normal, loops[0][0]);
        let flat: Vec<Vec<DVec2>> = loops
            .iter()
            .map(|ring| ring.iter().map(|&p| plane.flat(p)).collect())
            .collect();
        let inside = fill(&flat, refiner.spacing);
        let points: Vec<DVec3> = loops
            .iter()
            .flatten()
            .copied()
            .chain(inside.iter().map(|&q| plane.point(q)))
            .collect();
        let first = positions.len();
        for &p in &points {
            positions.push(refiner.base.lay(p)?);
        }
        let mut area = 0.0;
        let triangles = triangulate_loops_with(&flat, &inside)
            .map_err(|e| ThickenError::Triangulation(f, e))?;
        for [a, c, d] in triangles {
            let [pa, pc, pd] = [a, c, d].map(|i| positions[first + i]);
            area += 0.5 * (pc - pa).cross(pd - pa).length();
            faces.push(Face::triangle(
                (first + a) as u32,
                (first + c) as u32,
                (first + d) as u32,
            ));
        }
        areas.push((f, area));
    }
    let mesh = Mesh::new(positions, faces).map_err(invalid)?;
    Ok((mesh, areas))
}

/// The solid of `plan` laid on the refiner's surface: each face cut, filled and
/// triangulated flat, its points worked out again on the laid faces (the module's
/// doc), one group per face named by `name`.
pub(crate) fn lay_solid(
    plan: &SolidPlan,
    refiner: &mut Refiner,
    name: impl Fn(FaceId) -> String,
) -> Result<Mesh, LaidError> {
    let base = refiner.base;
    let sides: HashMap<FaceId, DVec3> = plan
        .faces
        .iter()
        .filter_map(|f| f.side.map(|(n, _)| (f.face, n)))
        .collect();
    let side_normal = |f: FaceId| {
        sides.get(&f).copied().ok_or_else(|| {
            LaidError::from(TopologyError::Invalid(format!(
                "face {} is not a side with a normal",
                f.0
            )))
        })
    };
    // The plan's points, flat (for the triangulation) and laid.
    let mut flat = plan.positions.clone();
    let mut laid = Vec::with_capacity(flat.len());
    for (m, rules) in plan.mids.iter().zip(&plan.rules) {
        laid.push(settle(base, *m, rules, &side_normal)?);
    }
    // Each solid edge's cuts, by its ends' points (the lower first), from the lower on.
    let mut edge_points: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    let mut faces = Vec::new();
    let mut groups = Vec::new();
    for face in &plan.faces {
        let f = face.face;
        let mut loops: Vec<Vec<u32>> = Vec::with_capacity(face.loops.len());
        for ring in &face.loops {
            let mut out = Vec::new();
            for (k, corner) in ring.iter().enumerate() {
                out.push(corner.at);
                let Some(across) = corner.along else {
                    continue;
                };
                let (a, c) = (corner.at, ring[(k + 1) % ring.len()].at);
                let id = (a.min(c), a.max(c));
                if let Entry::Vacant(slot) = edge_points.entry(id) {
                    let (lo, hi) = (id.0 as usize, id.1 as usize);
                    let (ma, mb) = (plan.mids[lo], plan.mids[hi]);
                    let (qa, qb) = (plan.positions[lo], plan.positions[hi]);
                    // The planes of the two faces along the edge, as its lower end has
                    // them (a thickness face's plane through this edge only).
                    let rules: Vec<PlaneRule> = plan.rules[lo]
                        .iter()
                        .filter(|r| match **r {
                            PlaneRule::Side { face, .. } => face == f || face == across,
                            PlaneRule::Across { face, from, to, .. } => {
                                (face == f || face == across)
                                    && ((from == ma && to == mb) || (from == mb && to == ma))
                            }
                        })
                        .copied()
                        .collect();
                    let direction = (mb - ma).normalize_or_zero();
                    let mut indices = Vec::new();
                    for (_, t) in refiner.cuts(ma, mb)? {
                        // The cut of the solid edge, and the mid-surface point it stands
                        // square over (the solid edge runs parallel to the mid one).
                        let q = qa + (qb - qa) * t;
                        let m = ma + direction * (q - ma).dot(direction);
                        let point = settle(base, m, &rules, &side_normal)?;
                        indices.push(flat.len() as u32);
                        flat.push(q);
                        laid.push(point);
                    }
                    slot.insert(indices);
                }
                let cuts = &edge_points[&id];
                if a < c {
                    out.extend(cuts.iter().copied());
                } else {
                    out.extend(cuts.iter().rev().copied());
                }
            }
            loops.push(out);
        }
        // The face's plane, flat.
        let outer: Vec<DVec3> = loops[0].iter().map(|&i| flat[i as usize]).collect();
        let n = newell(&outer).normalize_or_zero();
        if n == DVec3::ZERO {
            return Err(ThickenError::Degenerate(f).into());
        }
        let plane = Plane::new(n, outer[0]);
        let rings: Vec<Vec<DVec2>> = loops
            .iter()
            .map(|ring| ring.iter().map(|&i| plane.flat(flat[i as usize])).collect())
            .collect();
        // A side is filled; a thickness face is a strip as wide as the sheet is thick.
        let inside = match face.side {
            Some(_) => fill(&rings, refiner.spacing),
            None => Vec::new(),
        };
        let mut all: Vec<u32> = loops.iter().flatten().copied().collect();
        if let Some((normal, half)) = face.side {
            let rule = [PlaneRule::Side {
                face: f,
                normal,
                half,
            }];
            for &q in &inside {
                let q = plane.point(q);
                let m = q - half * normal;
                all.push(flat.len() as u32);
                flat.push(q);
                laid.push(settle(base, m, &rule, &side_normal)?);
            }
        }
        let first = faces.len();
        let triangles = triangulate_loops_with(&rings, &inside)
            .map_err(|e| ThickenError::Triangulation(f, e))?;
        for [a, c, d] in triangles {
            faces.push(Face::triangle(all[a], all[c], all[d]));
        }
        groups.push((name(f), first..faces.len()));
    }
    let mut mesh = Mesh::new(laid, faces).map_err(invalid)?;
    for (group, range) in groups {
        mesh.add_group(group, range.map(|t| MeshFaceId(t as u32)))
            .map_err(invalid)?;
    }
    Ok(mesh)
}

/// Where a point of the solid lies once laid: its mid-surface point `mid` laid, moved
/// by the smallest step that puts it on every plane of `rules` worked out again there.
fn settle(
    base: &BaseSurface,
    mid: DVec3,
    rules: &[PlaneRule],
    side_normal: &impl Fn(FaceId) -> Result<DVec3, LaidError>,
) -> Result<DVec3, LaidError> {
    let (at, jacobian) = base.jacobian(mid)?;
    let laid_normal = |n: DVec3| laid_normal(&jacobian, n);
    let mut rows: Vec<(DVec3, f64)> = Vec::with_capacity(rules.len() + 1);
    for rule in rules {
        match *rule {
            PlaneRule::Side { normal, half, .. } => rows.push((laid_normal(normal), half)),
            PlaneRule::Across { side, from, to, .. } => {
                let m = (jacobian * (from - to)).cross(laid_normal(side_normal(side)?));
                let m = m.normalize_or_zero();
                if m != DVec3::ZERO {
                    rows.push((m, 0.0));
                }
            }
        }
    }
    if rows.is_empty() {
        return Ok(at);
    }
    let mut a = DMatrix::<f64>::zeros(rows.len(), 3);
    let mut r = DVector::<f64>::zeros(rows.len());
    for (i, &(n, d)) in rows.iter().enumerate() {
        a[(i, 0)] = n.x;
        a[(i, 1)] = n.y;
        a[(i, 2)] = n.z;
        r[i] = d;
    }
    let x = a
        .svd(true, true)
        .solve(&r, RANK_TOLERANCE)
        .map_err(|e| TopologyError::Invalid(format!("a laid point's planes: {e}")))?;
    Ok(at + DVec3::new(x[0], x[1], x[2]))
}

/// The laid normal of a face whose flat normal is `n`: the cross product of the images
/// of two of its flat directions (the map keeps their order, so the side stays out).
fn laid_normal(jacobian: &DMat3, n: DVec3) -> DVec3 {
    let a = n.any_orthonormal_vector();
    let b = n.cross(a);
    (*jacobian * a).cross(*jacobian * b).normalize_or_zero()
}

/// A face's plane, with axes to flatten its points and raise them again.
struct Plane {
    origin: DVec3,
    u: DVec3,
    w: DVec3,
}

impl Plane {
    fn new(normal: DVec3, origin: DVec3) -> Plane {
        let u = normal.any_orthonormal_vector();
        Plane {
            origin,
            u,
            w: normal.cross(u),
        }
    }

    fn flat(&self, p: DVec3) -> DVec2 {
        DVec2::new((p - self.origin).dot(self.u), (p - self.origin).dot(self.w))
    }

    fn point(&self, q: DVec2) -> DVec3 {
        self.origin + q.x * self.u + q.y * self.w
    }
}

/// The points of a square grid at `spacing` inside the region of `loops` (odd winding),
/// each clear of every loop's edges by a third of the spacing: the corners a face is
/// filled with. A face so large that the grid would pass [`MOST_FILL`] points gets a
/// wider one.
fn fill(loops: &[Vec<DVec2>], spacing: f64) -> Vec<DVec2> {
    let (lo, hi) = loops.iter().flatten().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    if !(lo.is_finite() && hi.is_finite()) {
        return Vec::new();
    }
    let span = hi - lo;
    let spacing = spacing.max((span.x * span.y / MOST_FILL).sqrt());
    let clear = spacing / 3.0;
    let segments: Vec<(DVec2, DVec2)> = loops
        .iter()
        .flat_map(|ring| (0..ring.len()).map(move |k| (ring[k], ring[(k + 1) % ring.len()])))
        .collect();
    let (i0, i1) = (
        (lo.x / spacing).ceil() as i64,
        (hi.x / spacing).floor() as i64,
    );
    let (j0, j1) = (
        (lo.y / spacing).ceil() as i64,
        (hi.y / spacing).floor() as i64,
    );
    let mut out = Vec::new();
    for i in i0..=i1 {
        for j in j0..=j1 {
            let q = DVec2::new(i as f64 * spacing, j as f64 * spacing);
            let winding = loops
                .iter()
                .filter(|ring| polygon_winding(ring, q) != 0)
                .count();
            if winding % 2 == 0 {
                continue;
            }
            if segments.iter().all(|&(a, b)| {
                distance_to_segment(a.extend(0.0), b.extend(0.0), q.extend(0.0)) > clear
            }) {
                out.push(q);
            }
        }
    }
    out
}

fn invalid(e: GeomError) -> LaidError {
    LaidError::Thicken(ThickenError::Topology(TopologyError::Invalid(
        e.to_string(),
    )))
}
