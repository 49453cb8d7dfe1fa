//! A sheet model made solid: its mid-surface points offset by half the thickness to
//! each side, the solid's vertices where the offset faces meet (paper 003, section 5;
//! primer section 9: junction type 1, where the solid's mid-surfaces are the sheets).
//!
//! Every side face of the sheet model is offset along its outward normal by half the
//! thickness: the two sides of a sheet, whose loops run opposite ways, move apart. A
//! thickness face (a zero-area loop) becomes the real face across the sheet's edge: for
//! each of its side edges, the plane through the edge square to the side it bounds. A
//! solid vertex lies where the planes of the faces round it meet, found by least
//! squares (nalgebra's SVD), moved from the mid-surface point by the smallest step (a
//! vertex inside a flat region meets only its side's plane). Where a flange meets its
//! sheet the two sides' offset planes cross on the mitre, and the solid's mid-surfaces
//! are the sheets.
//!
//! Each sheet may have its own thickness ([`Gauge`]: a 1.2 mm flange on a 0.8 mm
//! panel, one of the paper's open problems): a side moves out by half its own sheet's
//! thickness. The thickness faces' planes stand square to the sides, whatever their
//! thickness, so where two sheets of different thickness meet the offset sides still
//! cross on a mitre and the solid's mid-surfaces are still the sheets: its volume is
//! each sheet's area times its own thickness.
//!
//! Where the planes round a vertex miss one point (two sheets meeting on the free
//! boundary whose thickness faces are not one plane), the vertex is split by its
//! junction's topology change ([`super::junction`]; `split` below); where no split
//! joins them it is refused, never put at a compromise that warps the faces.
//!
//! Planar faces only so far: each face of the solid is triangulated in its own plane,
//! its triangles a named group of the mesh.

use glam::{DMat3, DVec2, DVec3};
use nalgebra::{DMatrix, DVector};

use super::geometry::{newell, MidSurface};
use super::junction::{junctions, Junction, JunctionType};
use super::topology::{
    Brep, EdgeRole, FaceId, FaceRole, HalfEdgeId, Sheet, TopologyError, VertexId,
};
use crate::geom::mesh::{Face, FaceId as MeshFaceId, Mesh};
use crate::geom::tessellate::triangulate_loops;
use crate::geom::GeomError;

/// Why a sheet could not be made solid.
#[derive(Debug, Clone, PartialEq)]
pub enum ThickenError {
    /// The thickness is not a length above zero.
    Thickness(f64),
    /// A vertex has no mid-surface point (or one that is not finite).
    Unplaced(VertexId),
    /// A side face spans no area (its points on one line), so it has no normal.
    Degenerate(FaceId),
    /// A face of the solid could not be triangulated (its outline crosses itself).
    Triangulation(FaceId, GeomError),
    /// The faces round a vertex of the solid do not meet at one point, so offsetting
    /// alone would warp them (paper 003, Fig. 16(b)), and no junction's topology change
    /// joins them: three sheets or more meet there, or the vertex splits into points far
    /// off or on planes that never meet. `miss` is how far the best point lies off the
    /// planes (mm); `kind` the junction type the paper's rule chose there, if any.
    Junction {
        at: DVec3,
        miss: f64,
        kind: Option<JunctionType>,
    },
    /// The sheet model's topology is broken.
    Topology(TopologyError),
}

impl std::fmt::Display for ThickenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ThickenError::Thickness(t) => write!(f, "a thickness must be above 0, not {t}"),
            ThickenError::Unplaced(v) => write!(f, "vertex {} has no point", v.0),
            ThickenError::Degenerate(face) => {
                write!(f, "face {} spans no area: its points lie on a line", face.0)
            }
            ThickenError::Triangulation(face, e) => {
                write!(f, "face {} of the solid cannot be meshed: {e}", face.0)
            }
            ThickenError::Junction { at, miss, .. } => write!(
                f,
                "the solid's faces do not meet at one point near ({:.3}, {:.3}, {:.3}) \
                 ({miss:.3} mm apart), and no junction joins them there",
                at.x, at.y, at.z
            ),
            ThickenError::Topology(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for ThickenError {}

impl From<TopologyError> for ThickenError {
    fn from(e: TopologyError) -> Self {
        ThickenError::Topology(e)
    }
}

/// The thickness of each sheet of a model: one for every sheet, save those given their
/// own (a 1.2 mm flange on a 0.8 mm panel).
#[derive(Debug, Clone, PartialEq)]
pub struct Gauge {
    /// The thickness of a sheet not given its own (mm).
    pub base: f64,
    /// Sheets with their own thickness (mm), each named by one of its two sides; a side
    /// split from a named one later is named again.
    pub sheets: Vec<(FaceId, f64)>,
}

impl Gauge {
    /// Every sheet at `thickness`.
    pub fn uniform(thickness: f64) -> Gauge {
        Gauge {
            base: thickness,
            sheets: Vec::new(),
        }
    }

    /// The thickness of the sheet whose side (or its twin) is `side`.
    pub fn of(&self, side: FaceId, twin: FaceId) -> f64 {
        self.sheets
            .iter()
            .find(|&&(f, _)| f == side || f == twin)
            .map_or(self.base, |&(_, t)| t)
    }

    /// The largest thickness.
    fn thickest(&self) -> f64 {
        self.sheets
            .iter()
            .map(|&(_, t)| t)
            .fold(self.base, f64::max)
    }

    /// The first thickness that is not a length above zero.
    fn invalid(&self) -> Option<f64> {
        std::iter::once(self.base)
            .chain(self.sheets.iter().map(|&(_, t)| t))
            .find(|t| !(t.is_finite() && *t > 0.0))
    }
}

/// Singular values of the planes' normals below this count as none: the planes then
/// fix no direction there (the normals are unit vectors).
const RANK_TOLERANCE: f64 = 1e-9;

/// How far a solid vertex may lie off one of the planes round it, relative to the
/// thickest sheet, before the planes count as not meeting at one point.
const MEET_TOLERANCE: f64 = 1e-7;

/// The solid of `sheet` (placed by `mid`) with each sheet at its thickness in `gauge`,
/// as a closed triangle mesh whose triangles face out of the solid, one group per face
/// of the solid named `face N` (N the sheet model's face id).
pub fn thicken(sheet: &Sheet, mid: &MidSurface, gauge: &Gauge) -> Result<Mesh, ThickenError> {
    let junctions = junctions(sheet, mid)?;
    thicken_named(sheet, mid, gauge, &junctions, |f| format!("face {}", f.0))
}

/// [`thicken`], with the model's junctions already found ([`junctions`]) and each
/// face's group named by `name` (names must differ).
pub fn thicken_named(
    sheet: &Sheet,
    mid: &MidSurface,
    gauge: &Gauge,
    junctions: &[Junction],
    name: impl Fn(FaceId) -> String,
) -> Result<Mesh, ThickenError> {
    let plan = plan_solid(sheet, mid, gauge, junctions)?;
    // Every face of the solid triangulated in its own plane, its triangles a group.
    let b = &sheet.brep;
    let mut faces = Vec::new();
    let mut groups = Vec::new();
    for face in &plan.faces {
        let f = face.face;
        let first = faces.len();
        let loops: Vec<Vec<u32>> = face
            .loops
            .iter()
            .map(|ring| ring.iter().map(|c| c.at).collect())
            .collect();
        let outer: Vec<DVec3> = loops[0]
            .iter()
            .map(|&i| plan.positions[i as usize])
            .collect();
        let n = newell(&outer);
        if n.length() <= 1e-12 * scale(&outer) {
            return Err(ThickenError::Degenerate(f));
        }
        let n = n.normalize();
        let u = n.any_orthonormal_vector();
        let w = n.cross(u);
        let flat: Vec<Vec<DVec2>> = loops
            .iter()
            .map(|ring| {
                ring.iter()
                    .map(|&i| {
                        let p = plan.positions[i as usize];
                        DVec2::new(p.dot(u), p.dot(w))
                    })
                    .collect()
            })
            .collect();
        let all: Vec<u32> = loops.iter().flatten().copied().collect();
        // A face whose outline crosses itself at a split vertex: that split leaves a
        // piece of the solid uncovered (a corner too narrow for the other sheet's
        // thickness face to cross), so the junction is refused there.
        let triangles = triangulate_loops(&flat).map_err(|e| {
            let split_here = plan
                .splits
                .iter()
                .find(|(v, ..)| b.outer_vertices(f).is_ok_and(|vs| vs.contains(v)));
            match split_here {
                Some(&(_, at, miss, kind)) => ThickenError::Junction { at, miss, kind },
                None => ThickenError::Triangulation(f, e),
            }
        })?;
        for [a, c, d] in triangles {
            faces.push(Face::triangle(all[a], all[c], all[d]));
        }
        groups.push((name(f), first..faces.len()));
    }
    let invalid = |e: GeomError| ThickenError::Topology(TopologyError::Invalid(e.to_string()));
    let mut mesh = Mesh::new(plan.positions, faces).map_err(invalid)?;
    for (group, range) in groups {
        mesh.add_group(group, range.map(|t| MeshFaceId(t as u32)))
            .map_err(invalid)?;
    }
    Ok(mesh)
}

/// A plane a point of the solid lies on, as the face it bounds defines it: kept so the
/// laid solid ([`super::laid`]) can work each plane out again where a face is curved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum PlaneRule {
    /// A side's offset: along the side's outward `normal`, `half` its sheet's
    /// thickness out from the mid-surface.
    Side {
        face: FaceId,
        normal: DVec3,
        half: f64,
    },
    /// A thickness face's plane through the side edge from `from` to `to` (mid-surface
    /// points), square to `side`, the side across that edge.
    Across {
        face: FaceId,
        side: FaceId,
        from: DVec3,
        to: DVec3,
    },
}

impl PlaneRule {
    /// The face of the solid the plane belongs to.
    pub(crate) fn face(&self) -> FaceId {
        match *self {
            PlaneRule::Side { face, .. } | PlaneRule::Across { face, .. } => face,
        }
    }
}

/// The solid's points and faces before the faces are triangulated: each point with the
/// mid-surface point it was offset from and the planes it lies on, each face of the
/// solid as loops of points.
#[derive(Debug, Clone)]
pub(crate) struct SolidPlan {
    /// The solid's points.
    pub positions: Vec<DVec3>,
    /// Per point, the mid-surface point it was offset from.
    pub mids: Vec<DVec3>,
    /// Per point, the planes it lies on.
    pub rules: Vec<Vec<PlaneRule>>,
    /// The faces of the solid, one per face of the sheet model.
    pub faces: Vec<PlanFace>,
    /// The split vertices: where, how far its planes missed, the junction's type.
    splits: Vec<(VertexId, DVec3, f64, Option<JunctionType>)>,
}

/// A face of the solid in a [`SolidPlan`].
#[derive(Debug, Clone)]
pub(crate) struct PlanFace {
    /// The sheet model's face.
    pub face: FaceId,
    /// Its loops (the outer first), each a ring of points.
    pub loops: Vec<Vec<PlanCorner>>,
    /// For a side: its outward normal on the mid-surface and half its thickness.
    pub side: Option<(DVec3, f64)>,
}

/// A point on a face's loop in a [`SolidPlan`], with what the loop runs along from it
/// to the next point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PlanCorner {
    /// The point.
    pub at: u32,
    /// The face across, where the loop runs on along a side edge of the sheet model;
    /// `None` where it crosses the thickness (a zero-length edge, a split's edge).
    pub along: Option<FaceId>,
}

/// The solid of `sheet` before its faces are triangulated ([`thicken_named`]).
pub(crate) fn plan_solid(
    sheet: &Sheet,
    mid: &MidSurface,
    gauge: &Gauge,
    junctions: &[Junction],
) -> Result<SolidPlan, ThickenError> {
    if let Some(t) = gauge.invalid() {
        return Err(ThickenError::Thickness(t));
    }
    let b = &sheet.brep;
    // A point that is not finite would stall the SVD below: refused as unplaced.
    let at = |v: VertexId| {
        mid.point(v)
            .filter(|p| p.is_finite())
            .ok_or(ThickenError::Unplaced(v))
    };
    // Each side face's outward normal on the mid-surface (Newell's, along its loop).
    let mut normals: Vec<Option<DVec3>> = vec![None; face_slots(b)];
    for f in b.faces() {
        if let FaceRole::Side { .. } = sheet.face_role(f)? {
            let points: Vec<DVec3> = b
                .outer_vertices(f)?
                .into_iter()
                .map(at)
                .collect::<Result<_, _>>()?;
            let n = newell(&points);
            if n.length() <= 1e-12 * scale(&points) {
                return Err(ThickenError::Degenerate(f));
            }
            normals[f.index()] = Some(n.normalize());
        }
    }
    let normal = |f: FaceId| normals[f.index()].ok_or(ThickenError::Degenerate(f));
    // The planes (normal, offset) round each vertex.
    let mut planes: Vec<Vec<(FaceId, DVec3, f64)>> = vec![Vec::new(); vertex_slots(b)];
    // The same planes as the faces define them, for the laid solid.
    let mut plane_rules: Vec<Vec<PlaneRule>> = vec![Vec::new(); vertex_slots(b)];
    for f in b.faces() {
        let role = sheet.face_role(f)?;
        for &l in b.loops_of(f)? {
            for h in b.loop_halves(l)? {
                let v = b.vertex(h)?;
                match role {
                    FaceRole::Side { twin } => {
                        let n = normal(f)?;
                        let half = 0.5 * gauge.of(f, twin);
                        planes[v.index()].push((f, n, n.dot(at(v)?) + half));
                        plane_rules[v.index()].push(PlaneRule::Side {
                            face: f,
                            normal: n,
                            half,
                        });
                    }
                    FaceRole::Thickness => {
                        // The side edges of the thickness face at v: the one leaving v
                        // and the one arriving.
                        let prev = b.prev(h)?;
                        for (edge_half, from, to) in
                            [(h, v, b.vertex(b.next(h)?)?), (prev, b.vertex(prev)?, v)]
                        {
                            let Some(e) = b.edge(edge_half)? else {
                                continue;
                            };
                            if sheet.edge_role(e)? == EdgeRole::ZeroLength {
                                continue;
                            }
                            // The side across the edge runs it the other way: to -> from.
                            let side = b.face_with(b.loop_with(b.mate(edge_half)?)?)?;
                            let d = at(from)? - at(to)?;
                            let m = d.cross(normal(side)?);
                            if m.length() > 0.0 {
                                let m = m.normalize();
                                planes[v.index()].push((f, m, m.dot(at(v)?)));
                                plane_rules[v.index()].push(PlaneRule::Across {
                                    face: f,
                                    side,
                                    from: at(from)?,
                                    to: at(to)?,
                                });
                            }
                        }
                    }
                }
            }
        }
    }
    // Each vertex where its planes meet: the mid-surface point moved by the smallest
    // step that puts it on every plane (least squares where they disagree), so along a
    // direction no plane fixes it stays where it was. Where two sheets meet on the free
    // boundary and the four planes round the vertex miss one point, the vertex is split
    // in two by the junction's topology change (`split`).
    let mut corners: Vec<Corner> = vec![Corner::One(u32::MAX); vertex_slots(b)];
    // The split vertices: where, how far its planes missed, the junction's type.
    let mut splits: Vec<(VertexId, DVec3, f64, Option<JunctionType>)> = Vec::new();
    let mut positions = Vec::new();
    let mut mids = Vec::new();
    let mut rules = Vec::new();
    for v in b.vertices() {
        let p = at(v)?;
        let round = &planes[v.index()];
        let mut a = DMatrix::<f64>::zeros(round.len(), 3);
        let mut r = DVector::<f64>::zeros(round.len());
        for (i, &(_, n, d)) in round.iter().enumerate() {
            a[(i, 0)] = n.x;
            a[(i, 1)] = n.y;
            a[(i, 2)] = n.z;
            r[i] = d - n.dot(p);
        }
        let step = if round.is_empty() {
            DVec3::ZERO
        } else {
            let x = a
                .svd(true, true)
                .solve(&r, RANK_TOLERANCE)
                .map_err(|e| TopologyError::Invalid(format!("vertex {}: {e}", v.0)))?;
            DVec3::new(x[0], x[1], x[2])
        };
        let q = p + step;
        let miss = round
            .iter()
            .map(|&(_, n, d)| (n.dot(q) - d).abs())
            .fold(0.0, f64::max);
        if miss <= MEET_TOLERANCE * gauge.thickest() {
            corners[v.index()] = Corner::One(positions.len() as u32);
            positions.push(q);
            mids.push(p);
            rules.push(plane_rules[v.index()].clone());
            continue;
        }
        let twin = sheet.twin_vertex(v)?;
        let junction = junctions.iter().find(|j| j.vertex == v || j.vertex == twin);
        let Some(points) =
            junction.and_then(|j| split(sheet, mid, j, v, round, p, gauge).transpose())
        else {
            return Err(ThickenError::Junction {
                at: p,
                miss,
                kind: junction.map(|j| j.kind),
            });
        };
        let points = points?;
        let first = positions.len() as u32;
        for (point, on) in points {
            positions.push(point);
            mids.push(p);
            // The first plane of each face, as `split` reads them.
            rules.push(
                on.iter()
                    .filter_map(|&f| plane_rules[v.index()].iter().find(|r| r.face() == f))
                    .copied()
                    .collect(),
            );
        }
        corners[v.index()] = Corner::Split([(first, points[0].1), (first + 1, points[1].1)]);
        splits.push((v, p, miss, junction.map(|j| j.kind)));
    }
    // Each face of the solid as loops of points, with what each loop runs along.
    let mut faces = Vec::new();
    for f in b.faces() {
        let side = match sheet.face_role(f)? {
            FaceRole::Side { twin } => Some((normal(f)?, 0.5 * gauge.of(f, twin))),
            FaceRole::Thickness => None,
        };
        let loops: Vec<Vec<PlanCorner>> = b
            .loops_of(f)?
            .iter()
            .map(|&l| {
                let mut ring: Vec<(u32, HalfEdgeId)> = Vec::new();
                for h in b.loop_halves(l)? {
                    match corners[b.vertex(h)?.index()] {
                        Corner::One(i) => ring.push((i, h)),
                        Corner::Split(points) => {
                            // The points on this face, the one on the face across the
                            // edge arriving here first.
                            let arriving = b.face_with(b.loop_with(b.mate(b.prev(h)?)?)?)?;
                            let on: Vec<(u32, [FaceId; 3])> = points
                                .into_iter()
                                .filter(|(_, fs)| fs.contains(&f))
                                .collect();
                            match on.as_slice() {
                                [(i, _)] => ring.push((*i, h)),
                                [(i, fi), (j, _)] if fi.contains(&arriving) => {
                                    ring.extend([(*i, h), (*j, h)])
                                }
                                [(i, _), (j, _)] => ring.extend([(*j, h), (*i, h)]),
                                _ => {
                                    return Err(TopologyError::Invalid(format!(
                                        "face {} has no corner at a split vertex",
                                        f.0
                                    )))
                                }
                            }
                        }
                    }
                }
                // From each point the loop runs along its half-edge's edge when the
                // next point is on the next half-edge and that edge is a side edge.
                let n = ring.len();
                (0..n)
                    .map(|k| {
                        let (at, h) = ring[k];
                        let next = ring[(k + 1) % n].1;
                        let along = if next == h {
                            None
                        } else {
                            match b.edge(h)? {
                                Some(e) if sheet.edge_role(e)? != EdgeRole::ZeroLength => {
                                    Some(b.face_with(b.loop_with(b.mate(h)?)?)?)
                                }
                                _ => None,
                            }
                        };
                        Ok(PlanCorner { at, along })
                    })
                    .collect()
            })
            .collect::<Result<_, TopologyError>>()?;
        faces.push(PlanFace {
            face: f,
            loops,
            side,
        });
    }
    Ok(SolidPlan {
        positions,
        mids,
        rules,
        faces,
        splits,
    })
}

/// A vertex of the sheet model in the solid: one point, or two joined by a new edge
/// (a junction's topology change), each with the three faces it lies on.
#[derive(Debug, Clone, Copy)]
enum Corner {
    One(u32),
    Split([(u32, [FaceId; 3]); 2]),
}

/// A point a vertex splits into, with the three faces whose planes meet there.
type SplitPoint = (DVec3, [FaceId; 3]);

/// The two points a junction's vertex `v` splits into (its faces' planes `round`,
/// mid-surface point `p`), or `None` when neither split exists. The four faces round v
/// are f1's side S1 and thickness face E1, and f2's S2 and E2 (the sides on v's side
/// of the sheets). A new edge joins two faces that did not touch at v: for types 1 and
/// 2, S1 and E2 (f2's thickness face carries on across f1's thickness, A = S1 S2 E2,
/// B = S1 E1 E2); for type 3, S2 and E1 (A = S1 S2 E1, B = S2 E1 E2). The other split
/// is tried when the chosen one's planes do not meet at a point near v.
fn split(
    sheet: &Sheet,
    mid: &MidSurface,
    j: &Junction,
    v: VertexId,
    round: &[(FaceId, DVec3, f64)],
    p: DVec3,
    gauge: &Gauge,
) -> Result<Option<[SplitPoint; 2]>, ThickenError> {
    let on_side = |f: FaceId| -> Result<FaceId, ThickenError> {
        if j.vertex == v {
            return Ok(f);
        }
        match sheet.face_role(f)? {
            FaceRole::Side { twin } => Ok(twin),
            FaceRole::Thickness => Ok(f),
        }
    };
    let (s1, e1) = (on_side(j.f1.0)?, j.f1.1);
    let (s2, e2) = (on_side(j.f2.0)?, j.f2.1);
    let plane = |f: FaceId| {
        round
            .iter()
            .find(|&&(g, _, _)| g == f)
            .map(|&(_, n, d)| (n, d))
    };
    let reach = SPLIT_REACH * gauge.thickest();
    let meet = |fs: [FaceId; 3]| -> Option<DVec3> {
        let [a, c, d] = fs.map(plane);
        let ((na, da), (nc, dc), (nd, dd)) = (a?, c?, d?);
        let m = DMat3::from_cols(na, nc, nd).transpose();
        if m.determinant().abs() < SPLIT_DETERMINANT {
            return None;
        }
        let q = m.inverse() * DVec3::new(da, dc, dd);
        (q.distance(p) <= reach).then_some(q)
    };
    let across_f1 = [[s1, s2, e2], [s1, e1, e2]];
    let across_f2 = [[s1, s2, e1], [s2, e1, e2]];
    let mut order = if j.kind == JunctionType::Three {
        [across_f2, across_f1]
    } else {
        [across_f1, across_f2]
    };
    // At a type 3 junction, which thickness face carries on across the other sheet is
    // read off the line where the two sides meet (the solid's edge along the common
    // edge): coming along it from the common edge's far end, the first thickness face
    // met bounds both sheets there and cuts the other's. The two sides of a sheet may
    // need different ones: a flange end leaning over a narrow plate corner meets the
    // plate's edge first on one side and its own end first on the other. (Types 1 and
    // 2 keep the paper's split, f2's face across f1's, on both sides.)
    if j.kind == JunctionType::Three {
        if let (Some(along), Some(by_e2), Some(by_e1)) = (
            common_edge_direction(sheet, mid, s1, s2, v, p)?,
            meet([s1, s2, e2]),
            meet([s1, s2, e1]),
        ) {
            let (t2, t1) = ((by_e2 - p).dot(along), (by_e1 - p).dot(along));
            if (t2 - t1).abs() > MEET_TOLERANCE * gauge.thickest() {
                order = if t2 > t1 {
                    [across_f1, across_f2]
                } else {
                    [across_f2, across_f1]
                };
            }
        }
    }
    for [fa, fb] in order {
        if let (Some(a), Some(c)) = (meet(fa), meet(fb)) {
            if a.distance(c) > MEET_TOLERANCE * gauge.thickest() {
                return Ok(Some([(a, fa), (c, fb)]));
            }
        }
    }
    Ok(None)
}

/// The unit direction from vertex `v` (at `p`) along the edge that sides `s1` and `s2`
/// share there, or `None` when they share none at `v`.
fn common_edge_direction(
    sheet: &Sheet,
    mid: &MidSurface,
    s1: FaceId,
    s2: FaceId,
    v: VertexId,
    p: DVec3,
) -> Result<Option<DVec3>, ThickenError> {
    let b = &sheet.brep;
    for &l in b.loops_of(s1)? {
        for h in b.loop_halves(l)? {
            let across = b.face_with(b.loop_with(b.mate(h)?)?)?;
            if across != s2 {
                continue;
            }
            let (from, to) = (b.vertex(h)?, b.vertex(b.next(h)?)?);
            let other = if from == v {
                to
            } else if to == v {
                from
            } else {
                continue;
            };
            let q = mid.point(other).ok_or(ThickenError::Unplaced(other))?;
            return Ok(Some((q - p).normalize_or_zero()).filter(|d| *d != DVec3::ZERO));
        }
    }
    Ok(None)
}

/// The determinant (of three unit normals) below which three planes count as not
/// meeting at a point.
const SPLIT_DETERMINANT: f64 = 1e-6;

/// How far from the mid-surface point, in thicknesses, a split's point may lie.
const SPLIT_REACH: f64 = 20.0;

/// A length the size of `points`, for relative tests.
fn scale(points: &[DVec3]) -> f64 {
    let (lo, hi) = points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    (hi - lo).length().powi(2).max(f64::MIN_POSITIVE)
}

/// Slots for face ids (live or not).
fn face_slots(b: &Brep) -> usize {
    b.faces().map(|f| f.index() + 1).max().unwrap_or(0)
}

/// Slots for vertex ids (live or not).
fn vertex_slots(b: &Brep) -> usize {
    b.vertices().map(|v| v.index() + 1).max().unwrap_or(0)
}
