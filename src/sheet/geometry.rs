//! Where a sheet model lies: each vertex's point on the mid-surface, and the operations
//! that change only that (paper 003, section 4.5: bend about an edge, move a vertex or a
//! face), with edges and faces picked by a point near them, never by an internal index,
//! so a script stays valid when an earlier operation renumbers the model.

use glam::{DQuat, DVec3};

use super::topology::{EdgeId, EdgeRole, FaceId, FaceRole, Sheet, TopologyError, VertexId};
use crate::geom::intersect::polyline_self_crossing;

/// Where each vertex of a sheet model lies on the mid-surface. A vertex and its twin lie
/// at the same point: they part only when the sheet is thickened.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MidSurface {
    points: Vec<Option<DVec3>>,
}

impl MidSurface {
    /// No vertex placed yet.
    pub fn new() -> MidSurface {
        MidSurface::default()
    }

    /// Places vertex `v` of `sheet`, and its twin, at `p`.
    pub fn place(&mut self, sheet: &Sheet, v: VertexId, p: DVec3) -> Result<(), TopologyError> {
        let w = sheet.twin_vertex(v)?;
        for u in [v, w] {
            if self.points.len() <= u.index() {
                self.points.resize(u.index() + 1, None);
            }
            self.points[u.index()] = Some(p);
        }
        Ok(())
    }

    /// Where vertex `v` lies, once placed.
    pub fn point(&self, v: VertexId) -> Option<DVec3> {
        self.points.get(v.index()).copied().flatten()
    }
}

/// One side of each sheet: of each pair of twin sides, the one of lower id (what the
/// mid-surface mesh shows and measures).
pub fn mid_sides(sheet: &Sheet) -> Result<Vec<FaceId>, TopologyError> {
    let mut out = Vec::new();
    for f in sheet.brep.faces() {
        if let FaceRole::Side { twin } = sheet.face_role(f)? {
            if f < twin {
                out.push(f);
            }
        }
    }
    Ok(out)
}

/// The mid-surface points of each loop of face `f` (the outer loop first).
pub fn face_loops(
    sheet: &Sheet,
    mid: &MidSurface,
    f: FaceId,
) -> Result<Vec<Vec<DVec3>>, TopologyError> {
    let b = &sheet.brep;
    b.loops_of(f)?
        .iter()
        .map(|&l| {
            b.loop_halves(l)?
                .into_iter()
                .map(|h| {
                    let v = b.vertex(h)?;
                    mid.point(v)
                        .ok_or_else(|| TopologyError::Dead(format!("point of vertex {}", v.0)))
                })
                .collect()
        })
        .collect()
}

/// The vertices of `sheet` by distance from `q`, nearest first, each with its distance:
/// of a vertex and its twin (at one point) only the one of lower id.
pub fn vertices_by_distance(sheet: &Sheet, mid: &MidSurface, q: DVec3) -> Vec<(f64, VertexId)> {
    let mut found: Vec<(f64, VertexId)> = sheet
        .brep
        .vertices()
        .filter(|&v| sheet.twin_vertex(v).is_ok_and(|w| v <= w))
        .filter_map(|v| Some((mid.point(v)?.distance(q), v)))
        .collect();
    found.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    found
}

/// Moves vertex `v` of `sheet` (and its twin) by `offset` (paper 003, section 4: moving
/// a vertex). The faces are planar, so every side face at the vertex must keep its
/// plane: a plate's corner moves in the plate's plane, a flange's foot corner along
/// the line where the flange meets the plate. Refused, with nothing moved, when a side
/// face would leave its plane or cross itself.
pub fn move_vertex(
    sheet: &Sheet,
    mid: &mut MidSurface,
    v: VertexId,
    offset: DVec3,
) -> Result<(), TopologyError> {
    let b = &sheet.brep;
    let p = mid
        .point(v)
        .ok_or_else(|| TopologyError::NotApplicable(format!("vertex {} has no point", v.0)))?;
    let mut moved = mid.clone();
    moved.place(sheet, v, p + offset)?;
    let twin = sheet.twin_vertex(v)?;
    for f in b.faces() {
        if !matches!(sheet.face_role(f)?, FaceRole::Side { .. }) {
            continue;
        }
        let mut touches = false;
        for &l in b.loops_of(f)? {
            for h in b.loop_halves(l)? {
                let u = b.vertex(h)?;
                touches |= u == v || u == twin;
            }
        }
        if !touches {
            continue;
        }
        // The face's plane before the move: the corner must stay in it.
        let before = face_loops(sheet, mid, f)?;
        let n = newell(&before[0]).normalize_or_zero();
        let off = n.dot(offset).abs();
        if off > 1e-9 * offset.length().max(1.0) {
            return Err(TopologyError::NotApplicable(format!(
                "would take a face at the corner {off:.3} mm out of its plane: a corner \
                 moves in the plane of every face that meets there (along the line where \
                 two meet)"
            )));
        }
        let loops = face_loops(sheet, &moved, f)?;
        if newell(&loops[0]).dot(n) <= 0.0 {
            return Err(TopologyError::NotApplicable(
                "would turn a face at the corner over".into(),
            ));
        }
        let u = n.any_orthonormal_vector();
        let w = n.cross(u);
        for ring in &loops {
            let flat: Vec<glam::DVec2> = ring
                .iter()
                .map(|q| glam::DVec2::new(q.dot(u), q.dot(w)))
                .collect();
            if polyline_self_crossing(&flat, true).is_some() {
                return Err(TopologyError::NotApplicable(
                    "would make a face at the corner cross itself".into(),
                ));
            }
        }
    }
    *mid = moved;
    Ok(())
}

/// The side face of `sheet` nearest `q` (the distance to its outer loop's plane inside
/// the loop, else to the loop), of two twins at the same place the one whose outward
/// normal faces `q`; `None` when no side is placed.
pub fn face_near(sheet: &Sheet, mid: &MidSurface, q: DVec3) -> Option<FaceId> {
    let b = &sheet.brep;
    let mut best: Option<(f64, f64, FaceId)> = None;
    for f in b.faces() {
        if !matches!(sheet.face_role(f).ok()?, FaceRole::Side { .. }) {
            continue;
        }
        let Some(points) = outer_points(sheet, mid, f) else {
            continue;
        };
        let n = newell(&points);
        if n.length() == 0.0 {
            continue;
        }
        let n = n.normalize();
        let d = distance_to_polygon(&points, n, q);
        // Twins lie at the same distance: the one facing q first.
        let facing = -n.dot(q - points[0]);
        let better = match best {
            None => true,
            Some((bd, bf, _)) => d < bd - 1e-9 || (d <= bd + 1e-9 && facing < bf),
        };
        if better {
            best = Some((d, facing, f));
        }
    }
    best.map(|(_, _, f)| f)
}

/// The side edge of `sheet` nearest `q`, of two twins the one on a side that faces `q`
/// (see [`face_near`]'s tie rule); `None` when no edge is placed.
pub fn edge_near(sheet: &Sheet, mid: &MidSurface, q: DVec3) -> Option<EdgeId> {
    let b = &sheet.brep;
    let mut best: Option<(f64, f64, EdgeId)> = None;
    for e in b.edges() {
        if sheet.edge_role(e).ok()? == EdgeRole::ZeroLength {
            continue;
        }
        let (p, m) = b.halves_of(e).ok()?;
        let (Some(x), Some(y)) = (mid.point(b.vertex(p).ok()?), mid.point(b.vertex(m).ok()?))
        else {
            continue;
        };
        let d = distance_to_segment(x, y, q);
        // Of twins, the one on the side facing q: its side's normal points at q.
        let facing = [p, m]
            .into_iter()
            .filter_map(|h| b.face_with(b.loop_with(h).ok()?).ok())
            .filter(|&f| matches!(sheet.face_role(f), Ok(FaceRole::Side { .. })))
            .filter_map(|f| outer_points(sheet, mid, f).map(|pts| newell(&pts)))
            .map(|n| -n.normalize_or_zero().dot(q - x))
            .fold(f64::INFINITY, f64::min);
        let better = match best {
            None => true,
            Some((bd, bf, _)) => d < bd - 1e-9 || (d <= bd + 1e-9 && facing < bf),
        };
        if better {
            best = Some((d, facing, e));
        }
    }
    best.map(|(_, _, e)| e)
}

/// Moves face `f` (and its twin) by `offset`: every vertex of its loops.
pub fn move_face(
    sheet: &Sheet,
    mid: &mut MidSurface,
    f: FaceId,
    offset: DVec3,
) -> Result<(), TopologyError> {
    let b = &sheet.brep;
    let mut vertices: Vec<VertexId> = Vec::new();
    for &l in b.loops_of(f)? {
        for h in b.loop_halves(l)? {
            let v = b.vertex(h)?;
            if !vertices.contains(&v) {
                vertices.push(v);
            }
        }
    }
    for v in vertices {
        let p = mid
            .point(v)
            .ok_or_else(|| TopologyError::NotApplicable(format!("vertex {} has no point", v.0)))?;
        mid.place(sheet, v, p + offset)?;
    }
    Ok(())
}

/// Bends the sheet about `edge` (a side edge between two sides of one sheet, as a
/// split leaves) by `angle` (radians, between -180 and 180 deg exclusive): every side
/// reached from the far side of the edge without crossing it (and whatever is joined
/// to those, flanges included) turns about the edge's line; `fixed`, the side on the
/// near side, stays. A positive angle folds the far part towards `fixed`'s outward
/// normal. Geometry only (paper 003, Fig. 14): the topology does not change, and the
/// edge stays a sharp crease. Refused: an edge on the free boundary, a `fixed` face
/// not beside the edge, a sheet that joins the far part back to the near one
/// elsewhere, and an angle outside the range.
pub fn bend(
    sheet: &Sheet,
    mid: &mut MidSurface,
    fixed: FaceId,
    edge: EdgeId,
    angle: f64,
) -> Result<(), TopologyError> {
    let refuse = |why: String| Err(TopologyError::NotApplicable(why));
    if !(angle.is_finite() && angle.abs() < std::f64::consts::PI) {
        return refuse(format!(
            "a bend angle lies between -180 and 180 deg, not {angle} rad"
        ));
    }
    let b = &sheet.brep;
    let EdgeRole::Side { twin } = sheet.edge_role(edge)? else {
        return refuse("a sheet bends about a side edge, not a zero-length one".into());
    };
    let (p, m) = b.halves_of(edge)?;
    let faces = [b.face_with(b.loop_with(p)?)?, b.face_with(b.loop_with(m)?)?];
    let Some(near_half) = [p, m].into_iter().zip(faces).find(|&(_, f)| f == fixed) else {
        return refuse(format!("face {} is not beside edge {}", fixed.0, edge.0));
    };
    let far = if faces[0] == fixed {
        faces[1]
    } else {
        faces[0]
    };
    if !matches!(sheet.face_role(far)?, FaceRole::Side { .. }) {
        return refuse(format!(
            "edge {} is on the sheet's free boundary: nothing lies beyond it to bend",
            edge.0
        ));
    }
    // The far part: sides reached from `far` across side edges other than the bend
    // edge and its twin, with their twins.
    let mut part: Vec<FaceId> = vec![far];
    let mut k = 0;
    while k < part.len() {
        let f = part[k];
        k += 1;
        let mut next = Vec::new();
        if let FaceRole::Side { twin: t } = sheet.face_role(f)? {
            next.push(t);
        }
        for &l in b.loops_of(f)? {
            for h in b.loop_halves(l)? {
                let Some(e) = b.edge(h)? else { continue };
                if e == edge || e == twin || sheet.edge_role(e)? == EdgeRole::ZeroLength {
                    continue;
                }
                let g = b.face_with(b.loop_with(b.mate(h)?)?)?;
                if matches!(sheet.face_role(g)?, FaceRole::Side { .. }) {
                    next.push(g);
                }
            }
        }
        for g in next {
            if g == fixed {
                return refuse(format!(
                    "the sheet joins the far side of edge {} back to face {} elsewhere: it \
                     cannot bend there",
                    edge.0, fixed.0
                ));
            }
            if !part.contains(&g) {
                part.push(g);
            }
        }
    }
    // The edge's line, as `fixed` runs along it, and the turn about it.
    let (a, c) = (b.vertex(near_half.0)?, b.vertex(b.mate(near_half.0)?)?);
    let point = |v: VertexId| {
        mid.point(v)
            .ok_or_else(|| TopologyError::NotApplicable(format!("vertex {} has no point", v.0)))
    };
    let (origin, axis) = (point(a)?, (point(c)? - point(a)?).normalize_or_zero());
    if axis == DVec3::ZERO {
        return refuse(format!("edge {} has no length", edge.0));
    }
    let turn = DQuat::from_axis_angle(axis, -angle);
    let hinge = [a, c, sheet.twin_vertex(a)?, sheet.twin_vertex(c)?];
    let mut moved: Vec<VertexId> = Vec::new();
    for &f in &part {
        for &l in b.loops_of(f)? {
            for h in b.loop_halves(l)? {
                let v = b.vertex(h)?;
                if !hinge.contains(&v) && !moved.contains(&v) {
                    moved.push(v);
                }
            }
        }
    }
    let turned: Vec<(VertexId, DVec3)> = moved
        .into_iter()
        .map(|v| Ok((v, origin + turn * (point(v)? - origin))))
        .collect::<Result<_, TopologyError>>()?;
    for (v, q) in turned {
        mid.place(sheet, v, q)?;
    }
    Ok(())
}

/// The points of face `f`'s outer loop, when all are placed.
fn outer_points(sheet: &Sheet, mid: &MidSurface, f: FaceId) -> Option<Vec<DVec3>> {
    let b = &sheet.brep;
    b.loop_halves(b.loops_of(f).ok()?[0])
        .ok()?
        .into_iter()
        .map(|h| mid.point(b.vertex(h).ok()?))
        .collect()
}

/// Newell's normal of a closed polygon: twice its vector area, along the normal its
/// points run counter-clockwise round.
pub(super) fn newell(points: &[DVec3]) -> DVec3 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].cross(points[(i + 1) % n]))
        .sum::<DVec3>()
}

/// The distance from `q` to the segment from `a` to `b`.
pub(super) fn distance_to_segment(a: DVec3, b: DVec3, q: DVec3) -> f64 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((q - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t).distance(q)
}

/// The distance from `q` to the planar polygon `points` (normal `n`): to its plane
/// where `q`'s foot lies inside, else to its nearest side.
fn distance_to_polygon(points: &[DVec3], n: DVec3, q: DVec3) -> f64 {
    let foot = q - n * n.dot(q - points[0]);
    let k = points.len();
    // Inside when the foot lies left of every side seen from n, for a convex polygon;
    // in general by the winding of the sides round it.
    let mut winding = 0.0;
    for i in 0..k {
        let (a, b) = (points[i] - foot, points[(i + 1) % k] - foot);
        winding += a.cross(b).dot(n).atan2(a.dot(b));
    }
    if winding.abs() > std::f64::consts::PI {
        n.dot(q - points[0]).abs()
    } else {
        (0..k)
            .map(|i| distance_to_segment(points[i], points[(i + 1) % k], q))
            .fold(f64::INFINITY, f64::min)
    }
}
