//! Where a triangle mesh passes through itself: pairs of triangles that share no edge
//! and cross, found by sweeping their bounding boxes along X.

use glam::DVec3;

use super::Mesh;

/// A place where two triangles of a mesh cross.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// The two faces (indices into the mesh's faces), the lower first.
    pub faces: (usize, usize),
    /// A point on both.
    pub at: DVec3,
}

/// The pairs of triangles of `mesh` that share no edge and cross (an edge of one passes
/// through the inside of the other), each with a point where they do; faces with more
/// than three vertices are skipped. Triangles that only touch (a vertex or
/// an edge on the other's plane within `1e-9` of the mesh's size) do not count, so a
/// closed solid whose faces meet only along shared edges has none.
pub fn crossings(mesh: &Mesh) -> Vec<Crossing> {
    let p = mesh.positions();
    let tris: Vec<(usize, [u32; 3])> = mesh
        .faces()
        .iter()
        .enumerate()
        .filter_map(|(i, f)| match f.indices() {
            &[a, b, c] => Some((i, [a, b, c])),
            _ => None,
        })
        .collect();
    let (lo, hi) = p
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &q| {
            (lo.min(q), hi.max(q))
        });
    let eps = 1e-9 * (hi - lo).length().max(1.0);
    let boxes: Vec<(DVec3, DVec3)> = tris
        .iter()
        .map(|(_, t)| {
            let q = t.map(|i| p[i as usize]);
            (q[0].min(q[1]).min(q[2]), q[0].max(q[1]).max(q[2]))
        })
        .collect();
    let mut order: Vec<usize> = (0..tris.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut out = Vec::new();
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            if boxes[b].0.x > boxes[a].1.x + eps {
                break;
            }
            let overlap = (boxes[a].0 - DVec3::splat(eps)).cmple(boxes[b].1).all()
                && (boxes[b].0 - DVec3::splat(eps)).cmple(boxes[a].1).all();
            let (ta, tb) = (tris[a].1, tris[b].1);
            // Neighbours sharing an edge meet only along it; an edge of one that runs
            // from a shared vertex starts on the other's plane, so it never counts as
            // crossing it (below), and only the edges away from a shared vertex are
            // tried: triangles sharing one vertex can still cross.
            if !overlap || ta.iter().filter(|v| tb.contains(v)).count() >= 2 {
                continue;
            }
            let qa = ta.map(|i| p[i as usize]);
            let qb = tb.map(|i| p[i as usize]);
            if let Some(at) = cross(qa, qb, eps).or_else(|| cross(qb, qa, eps)) {
                let (i, j) = (tris[a].0.min(tris[b].0), tris[a].0.max(tris[b].0));
                out.push(Crossing { faces: (i, j), at });
            }
        }
    }
    out.sort_by_key(|c| c.faces);
    out
}

/// A point where an edge of triangle `s` passes through the inside of triangle `t`.
fn cross(s: [DVec3; 3], t: [DVec3; 3], eps: f64) -> Option<DVec3> {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let len = n.length();
    if len == 0.0 {
        return None;
    }
    let n = n / len;
    for k in 0..3 {
        let (a, b) = (s[k], s[(k + 1) % 3]);
        let (da, db) = (n.dot(a - t[0]), n.dot(b - t[0]));
        // Strictly on both sides of the plane: an edge that touches it does not cross.
        if !((da > eps && db < -eps) || (da < -eps && db > eps)) {
            continue;
        }
        let x = a + (b - a) * (da / (da - db));
        if inside(x, t, n, eps) {
            return Some(x);
        }
    }
    None
}

/// Whether `x`, on the plane of `t` (unit normal `n`), lies inside `t` by more than `eps`
/// from each of its edges.
fn inside(x: DVec3, t: [DVec3; 3], n: DVec3, eps: f64) -> bool {
    (0..3).all(|k| {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let edge = b - a;
        let l = edge.length();
        l > 0.0 && n.cross(edge).dot(x - a) / l > eps
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::mesh::Face;

    #[test]
    fn two_crossing_triangles_are_found_and_touching_ones_are_not() {
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
            // Through the first, from below to above.
            DVec3::new(0.5, 0.5, -1.0),
            DVec3::new(0.5, 0.5, 1.0),
            DVec3::new(0.6, -1.0, 0.0),
            // Standing on the first's plane outside it: touches nothing.
            DVec3::new(5.0, 5.0, 0.0),
            DVec3::new(6.0, 5.0, 0.0),
            DVec3::new(5.0, 5.0, 1.0),
            DVec3::new(5.0, 5.0, -2.0),
        ];
        let faces = vec![
            Face::triangle(0, 1, 2),
            Face::triangle(3, 4, 5),
            Face::triangle(6, 7, 8),
            // Sharing an edge with the first: never counted.
            Face::triangle(1, 2, 9),
        ];
        let mesh = Mesh::new(positions, faces).unwrap();
        let found = crossings(&mesh);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].faces, (0, 1));
        // On both: the first triangle's plane, and the second's (x = 0.5 - 0.1 (y - 0.5) / 1.5).
        let at = found[0].at;
        assert!(at.z.abs() < 1e-12, "{at}");
        assert!(
            (at.x - (0.5 - 0.1 * (at.y - 0.5) / 1.5)).abs() < 1e-12,
            "{at}"
        );
    }
}
