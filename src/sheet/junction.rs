//! Where two sheets meet on the free boundary: the junction type the solid takes there
//! (paper 003, section 5.2, Fig. 16-21).
//!
//! At a vertex v where the edge two sheets share (the common edge) ends on the free
//! boundary, each sheet has a free edge leaving v, and its thickness face along it.
//! Offsetting alone (section 5.1) puts the solid's vertex where the planes of the four
//! faces round it meet: the two sheets' sides and their two thickness faces. When the
//! thickness faces are not one plane those four do not meet at one point, and the
//! solid needs a topology change there: the paper's junction types. Its rule, per
//! vertex, from four angles (the names are the paper's; the text of Fig. 18-19 is all
//! we have of the figures, so the readings below are ours, chosen so that each angle
//! is well defined for any placement):
//!
//! - α: the angle between the two sheets across the common edge (90 deg for a flange
//!   square to its plate, 180 deg for two sheets that continue flat);
//! - β₁, β₂: each sheet's corner angle at v, between the common edge and its free edge;
//!   β the larger. f1 is the sheet with β, f2 the other;
//! - θ: in f1, the angle between the common edge and the line where a plane parallel
//!   to f2's thickness face (through v) cuts f1;
//! - φ: the angle between t1 and t2, the two sheets' thickness faces at v (0 when they
//!   lie in one plane, as at the square end of a flange on a square plate).
//!
//! Type 1 when α > φ and β > θ (the sheets are the solid's mid-surfaces), type 2 when
//! α <= φ and β > θ, type 3 otherwise. β equal to θ (within [`ANGLE_TOLERANCE`]) counts
//! as greater: f2's thickness face then runs exactly along f1's free edge, and the two
//! thickness faces line up.

use glam::DVec3;

use super::geometry::{newell, MidSurface};
use super::topology::{EdgeId, EdgeRole, FaceId, FaceRole, Sheet, TopologyError, VertexId};

/// Angles closer than this (radians) count as equal.
pub const ANGLE_TOLERANCE: f64 = 1e-9;

/// How near 180 deg (radians) the angle between two sheets is when they lie in one
/// plane: a junction there is type 1 whatever the other angles.
pub const FLAT: f64 = 1e-6;

/// A junction type of paper 003 (Fig. 16-17).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum JunctionType {
    /// The preferred junction: the sheets are the solid's mid-surfaces.
    One,
    /// The thickness faces turn by more than the sheets do (α <= φ).
    Two,
    /// f2's thickness face, continued, misses f1 (β < θ): always possible, least
    /// desirable.
    Three,
}

impl JunctionType {
    /// The paper's number for the type.
    pub fn number(self) -> u8 {
        match self {
            JunctionType::One => 1,
            JunctionType::Two => 2,
            JunctionType::Three => 3,
        }
    }
}

/// The junction at one vertex where two sheets meet on the free boundary.
#[derive(Debug, Clone, PartialEq)]
pub struct Junction {
    /// The vertex (of a vertex and its twin, the one of lower id).
    pub vertex: VertexId,
    /// Where it lies on the mid-surface.
    pub at: DVec3,
    /// The angle between the sheets (radians).
    pub alpha: f64,
    /// The larger corner angle, f1's (radians).
    pub beta: f64,
    /// The angle in f1 between the common edge and f2's thickness face's trace (radians).
    pub theta: f64,
    /// The angle between the two thickness faces (radians).
    pub phi: f64,
    /// The type the rule chooses.
    pub kind: JunctionType,
    /// f1's side at `vertex` and its thickness face there.
    pub f1: (FaceId, FaceId),
    /// f2's side at `vertex` and its thickness face there.
    pub f2: (FaceId, FaceId),
}

/// What meets at a vertex of the free boundary where sheets meet.
#[derive(Debug, Clone, PartialEq)]
pub enum Meeting {
    /// Two sheets: a junction of one of the paper's types.
    Two(Junction),
    /// Three sheets or more meet at `vertex` (a lower-id vertex of a twin pair).
    Many {
        /// The vertex.
        vertex: VertexId,
        /// Where it lies.
        at: DVec3,
        /// How many sheets meet there.
        sheets: usize,
    },
}

/// Every vertex of `sheet`'s free boundary where sheets meet, in vertex order, once per
/// vertex and twin.
pub fn meetings(sheet: &Sheet, mid: &MidSurface) -> Result<Vec<Meeting>, TopologyError> {
    let b = &sheet.brep;
    let mut out = Vec::new();
    for v in b.vertices() {
        if sheet.twin_vertex(v)? < v {
            continue;
        }
        let Some(at) = mid.point(v) else {
            continue;
        };
        let round = Round::at(sheet, v)?;
        if round.thickness.is_empty() {
            continue;
        }
        let mut sheets: Vec<FaceId> = Vec::new();
        for &s in &round.sides {
            let FaceRole::Side { twin } = sheet.face_role(s)? else {
                continue;
            };
            let key = s.min(twin);
            if !sheets.contains(&key) {
                sheets.push(key);
            }
        }
        match sheets.len() {
            0 | 1 => {}
            2 if round.sides.len() == 2 && round.thickness.len() == 2 => {
                if let Some(j) = junction(sheet, mid, v, at, &round)? {
                    out.push(Meeting::Two(j));
                }
            }
            n => out.push(Meeting::Many {
                vertex: v,
                at,
                sheets: n,
            }),
        }
    }
    Ok(out)
}

/// The junctions of `sheet`: its [`meetings`] of two sheets (three or more have no
/// junction type).
pub fn junctions(sheet: &Sheet, mid: &MidSurface) -> Result<Vec<Junction>, TopologyError> {
    Ok(meetings(sheet, mid)?
        .into_iter()
        .filter_map(|m| match m {
            Meeting::Two(j) => Some(j),
            Meeting::Many { .. } => None,
        })
        .collect())
}

/// The faces round a vertex, and its edges with the two faces each joins.
struct Round {
    sides: Vec<FaceId>,
    thickness: Vec<FaceId>,
    edges: Vec<(EdgeId, FaceId, FaceId)>,
}

impl Round {
    fn at(sheet: &Sheet, v: VertexId) -> Result<Round, TopologyError> {
        let b = &sheet.brep;
        let mut round = Round {
            sides: Vec::new(),
            thickness: Vec::new(),
            edges: Vec::new(),
        };
        for e in b.edges_at(v)? {
            let (p, m) = b.halves_of(e)?;
            let faces = [p, m].map(|h| b.loop_with(h).and_then(|l| b.face_with(l)));
            let [fp, fm] = faces;
            let (fp, fm) = (fp?, fm?);
            for f in [fp, fm] {
                let list = match sheet.face_role(f)? {
                    FaceRole::Side { .. } => &mut round.sides,
                    FaceRole::Thickness => &mut round.thickness,
                };
                if !list.contains(&f) {
                    list.push(f);
                }
            }
            if sheet.edge_role(e)? != EdgeRole::ZeroLength {
                round.edges.push((e, fp, fm));
            }
        }
        Ok(round)
    }

    /// The edge joining faces `a` and `c`.
    fn edge(&self, a: FaceId, c: FaceId) -> Option<EdgeId> {
        self.edges
            .iter()
            .find(|&&(_, x, y)| (x == a && y == c) || (x == c && y == a))
            .map(|&(e, _, _)| e)
    }
}

/// The junction at `v` (two sides and two thickness faces round it), or `None` when an
/// edge there has no length to measure an angle by.
fn junction(
    sheet: &Sheet,
    mid: &MidSurface,
    v: VertexId,
    at: DVec3,
    round: &Round,
) -> Result<Option<Junction>, TopologyError> {
    let b = &sheet.brep;
    let (sa, sc) = (round.sides[0], round.sides[1]);
    let Some(common) = round.edge(sa, sc) else {
        return Ok(None);
    };
    // Each side's thickness face: the one it shares an edge with at v.
    let thickness_of = |s: FaceId| {
        round
            .thickness
            .iter()
            .copied()
            .find(|&t| round.edge(s, t).is_some())
    };
    let (Some(ta), Some(tc)) = (thickness_of(sa), thickness_of(sc)) else {
        return Ok(None);
    };
    let toward = |e: EdgeId| -> Result<Option<DVec3>, TopologyError> {
        let (p, m) = b.halves_of(e)?;
        let (x, y) = (b.vertex(p)?, b.vertex(m)?);
        let other = if x == v { y } else { x };
        Ok(mid.point(other).and_then(|q| (q - at).try_normalize()))
    };
    let (Some(e), Some(free_a), Some(free_c)) = (
        toward(common)?,
        round.edge(sa, ta).map(toward).transpose()?.flatten(),
        round.edge(sc, tc).map(toward).transpose()?.flatten(),
    ) else {
        return Ok(None);
    };
    let (Some(na), Some(nc)) = (side_normal(sheet, mid, sa)?, side_normal(sheet, mid, sc)?) else {
        return Ok(None);
    };
    let (Some(da), Some(dc)) = (
        inward(sheet, mid, sa, common, na)?,
        inward(sheet, mid, sc, common, nc)?,
    ) else {
        return Ok(None);
    };
    let alpha = angle(da, dc);
    let (beta_a, beta_c) = (angle(e, free_a), angle(e, free_c));
    // f1: the sheet with the larger corner angle (ties: the side of lower id).
    let a_first = beta_a > beta_c + ANGLE_TOLERANCE
        || ((beta_a - beta_c).abs() <= ANGLE_TOLERANCE && sa < sc);
    let (f1, f2) = if a_first {
        ((sa, ta, na, da, free_a), (sc, tc, nc, free_c))
    } else {
        ((sc, tc, nc, dc, free_c), (sa, ta, na, free_a))
    };
    let beta = beta_a.max(beta_c);
    // The thickness faces' planes: through the free edge, square to the side.
    let (m1, m2) = (f1.4.cross(f1.2), f2.3.cross(f2.2));
    let (Some(m1), Some(m2)) = (m1.try_normalize(), m2.try_normalize()) else {
        return Ok(None);
    };
    // Where a plane parallel to f2's thickness face cuts f1: the ray into f1's material.
    let theta = match m2.cross(f1.2).try_normalize() {
        Some(w) => angle(e, if w.dot(f1.3) < 0.0 { -w } else { w }),
        // f2's thickness face lies parallel to f1: it never crosses it.
        None => 0.0,
    };
    let phi = m1.dot(m2).abs().min(1.0).acos();
    // Two sheets in one plane (a level brim's corner, joined on the line halving it)
    // are one flat sheet there: their sides' offsets are two planes, whatever the
    // angles, so the sheets are the solid's mid-surfaces (type 1). The paper's angles
    // are read on a fold and mean nothing without one.
    let kind = if alpha > std::f64::consts::PI - FLAT {
        JunctionType::One
    } else if beta + ANGLE_TOLERANCE >= theta {
        if alpha > phi + ANGLE_TOLERANCE {
            JunctionType::One
        } else {
            JunctionType::Two
        }
    } else {
        JunctionType::Three
    };
    Ok(Some(Junction {
        vertex: v,
        at,
        alpha,
        beta,
        theta,
        phi,
        kind,
        f1: (f1.0, f1.1),
        f2: (f2.0, f2.1),
    }))
}

/// The unit normal of side `f` (Newell's, along its outer loop), if it spans an area.
fn side_normal(sheet: &Sheet, mid: &MidSurface, f: FaceId) -> Result<Option<DVec3>, TopologyError> {
    let points: Option<Vec<DVec3>> = sheet
        .brep
        .outer_vertices(f)?
        .into_iter()
        .map(|v| mid.point(v))
        .collect();
    Ok(points.and_then(|p| newell(&p).try_normalize()))
}

/// The unit direction in side `f` square to edge `e`, into the side's material: left of
/// the edge as `f`'s loop runs it (a loop runs counter-clockwise round its normal).
fn inward(
    sheet: &Sheet,
    mid: &MidSurface,
    f: FaceId,
    e: EdgeId,
    n: DVec3,
) -> Result<Option<DVec3>, TopologyError> {
    let b = &sheet.brep;
    for &l in b.loops_of(f)? {
        for h in b.loop_halves(l)? {
            if b.edge(h)? == Some(e) {
                let (p, q) = (mid.point(b.vertex(h)?), mid.point(b.vertex(b.next(h)?)?));
                return Ok(match (p, q) {
                    (Some(p), Some(q)) => n.cross(q - p).try_normalize(),
                    _ => None,
                });
            }
        }
    }
    Ok(None)
}

/// The angle between two unit vectors (radians, 0 to pi).
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.dot(b).clamp(-1.0, 1.0).acos()
}
