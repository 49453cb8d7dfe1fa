//! The spine: the path of the ball's centre (paper 000, section 2, step 3), where the
//! two base meshes' offsets cross. Each pair of crossing offset triangles gives a
//! segment; their ends, ordered along the chain, are the spine's points, and a point
//! closer than R to either base mesh (where the ball would cut into it) is dropped.

use glam::DVec3;

use super::offset::OffsetMesh;
use crate::geom::mesh::{Mesh, VertexId};

/// Points of the spine closer together than this, relative to the radius, are one.
const SAME_POINT: f64 = 1e-9;

use super::index::{PolylineIndex, Triangle, TriangleGrid};

/// The triangles of `offset`, each corner at its offset point (faces with a folded
/// corner, or not triangles, are left out).
pub fn offset_triangles(mesh: &Mesh, offset: &OffsetMesh) -> Vec<Triangle> {
    offset
        .faces
        .iter()
        .filter_map(|&f| {
            let face = mesh.face(f)?;
            let ids: Vec<VertexId> = face.vertices().collect();
            let [a, b, c] = ids[..] else { return None };
            if [a, b, c].iter().any(|v| offset.folded.contains(v)) {
                return None;
            }
            Some([
                *offset.points.get(&a)?,
                *offset.points.get(&b)?,
                *offset.points.get(&c)?,
            ])
        })
        .collect()
}

/// The triangles of the base faces `faces` of `mesh` (triangles only).
pub fn base_triangles(mesh: &Mesh, faces: &[crate::geom::mesh::FaceId]) -> Vec<Triangle> {
    faces
        .iter()
        .filter_map(|&f| {
            let p: Vec<DVec3> = mesh
                .face(f)?
                .vertices()
                .filter_map(|v| mesh.position(v))
                .collect();
            match p[..] {
                [a, b, c] => Some([a, b, c]),
                _ => None,
            }
        })
        .collect()
}

/// Where triangles `s` and `t` cross: the segment both hold, if any (coplanar
/// triangles give none).
pub fn triangle_crossing(s: &Triangle, t: &Triangle) -> Option<(DVec3, DVec3)> {
    let ns = (s[1] - s[0]).cross(s[2] - s[0]);
    let nt = (t[1] - t[0]).cross(t[2] - t[0]);
    let line = ns.cross(nt);
    if line.length_squared() <= 1e-24 * ns.length_squared() * nt.length_squared() {
        return None;
    }
    // Each triangle's stretch of the line where it meets the other's plane.
    let cut = |a: &Triangle, plane_point: DVec3, n: DVec3| -> Option<[DVec3; 2]> {
        let d: [f64; 3] = [0, 1, 2].map(|i| n.dot(a[i] - plane_point));
        let mut hits = Vec::with_capacity(2);
        for i in 0..3 {
            let j = (i + 1) % 3;
            if d[i] == 0.0 {
                hits.push(a[i]);
            }
            if d[i] * d[j] < 0.0 {
                hits.push(a[i] + (a[j] - a[i]) * (d[i] / (d[i] - d[j])));
            }
        }
        match hits[..] {
            [p, q] => Some([p, q]),
            [p] => Some([p, p]),
            [p, _, q] | [p, q, _] if p != q => Some([p, q]),
            _ => None,
        }
    };
    let a = cut(s, t[0], nt)?;
    let b = cut(t, s[0], ns)?;
    // Overlap of the two stretches along the line.
    let dir = line.normalize();
    let (mut a0, mut a1) = (dir.dot(a[0]), dir.dot(a[1]));
    let (mut a_lo, mut a_hi) = (a[0], a[1]);
    if a0 > a1 {
        std::mem::swap(&mut a0, &mut a1);
        std::mem::swap(&mut a_lo, &mut a_hi);
    }
    let (mut b0, mut b1) = (dir.dot(b[0]), dir.dot(b[1]));
    let (mut b_lo, mut b_hi) = (b[0], b[1]);
    if b0 > b1 {
        std::mem::swap(&mut b0, &mut b1);
        std::mem::swap(&mut b_lo, &mut b_hi);
    }
    let (lo, lo_p) = if a0 >= b0 { (a0, a_lo) } else { (b0, b_lo) };
    let (hi, hi_p) = if a1 <= b1 { (a1, a_hi) } else { (b1, b_hi) };
    (lo <= hi).then_some((lo_p, hi_p))
}

/// Where on triangle `t` the point nearest `p` lies, and which part of it that is.
pub fn nearest_on_triangle(p: DVec3, t: &Triangle) -> (DVec3, Region) {
    // Ericson, Real-Time Collision Detection, 5.1.5: by the Voronoi regions of the
    // triangle's corners, edges and face.
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Region::Corner(0));
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Region::Corner(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), Region::Edge(0));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Region::Corner(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), Region::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return (
            b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))),
            Region::Edge(1),
        );
    }
    let denom = 1.0 / (va + vb + vc);
    (a + ab * (vb * denom) + ac * (vc * denom), Region::Face)
}

/// Which part of a triangle a nearest point lies on (the paper's contact regions).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Region {
    /// Inside the face: the foot of the normal.
    Face,
    /// On edge K (from corner K to the next).
    Edge(usize),
    /// At corner K.
    Corner(usize),
}

/// The spine of a round of radius `radius`: the points where the offsets `one` and
/// `other` of the two base meshes (their triangles) cross, ordered along `guide` (the
/// chain's polyline, or the line an existing round runs along), less those closer than
/// the radius to either base mesh (`bases`, indexed).
pub fn spine(
    guide: &[DVec3],
    (one, other): (&[Triangle], &[Triangle]),
    bases: (&TriangleGrid, &TriangleGrid),
    radius: f64,
) -> Vec<DVec3> {
    let bounds = |t: &Triangle| (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
    let other = TriangleGrid::new(other.to_vec());
    let mut points = Vec::new();
    for s in one {
        let (lo, hi) = bounds(s);
        for k in other.candidates(lo, hi) {
            let t = &other.triangles[k as usize];
            let (tlo, thi) = bounds(t);
            if lo.cmpgt(thi).any() || tlo.cmpgt(hi).any() {
                continue;
            }
            if let Some((p, q)) = triangle_crossing(s, t) {
                points.extend([p, q]);
            }
        }
    }
    // Along the guide: each point by the arc length of its nearest point on it.
    let guide = PolylineIndex::new(guide);
    let along = |p: DVec3| guide.nearest(p).1;
    let mut keyed: Vec<(f64, DVec3)> = points.into_iter().map(|p| (along(p), p)).collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.x.total_cmp(&b.1.x)));
    let same = SAME_POINT * radius.max(1.0);
    let mut out: Vec<DVec3> = Vec::with_capacity(keyed.len());
    for (_, p) in keyed {
        if out.last().is_some_and(|q| q.distance(p) <= same) {
            continue;
        }
        let clear = |base: &TriangleGrid| {
            base.nearest(p)
                .is_none_or(|(_, d, _)| d >= radius * (1.0 - 1e-6))
        };
        if clear(bases.0) && clear(bases.1) {
            out.push(p);
        }
    }
    out
}
