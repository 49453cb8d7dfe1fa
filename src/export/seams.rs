//! The normal jump across the seams between a scene's surface pieces: where the open
//! edge of one piece's tessellation lies on the open edge of another (a binder patch
//! beside the next, the step draw against the punch opening), how far the two surfaces'
//! normals turn from one side of the seam to the other. A die engineer asks for G1
//! (tangent) continuity there, within 0.5 deg by common CAD defaults (primer section
//! 11); the live viewer's analysis mode draws these points coloured by their jump.
//!
//! Each open-edge vertex of a piece is matched with the nearest point on another
//! piece's open edges within a gap (the edges filed in a `geom::mesh::box_grid`); the other side's normal there is interpolated
//! along that edge. Both sides are measured (a side meshed finer has more points).
//! Normals are compared as lines, not as arrows: a piece whose surface runs the other
//! way round is not a crease. Solids and sheets are left out: their sharp edges are
//! meant.

use std::collections::HashMap;

use glam::DVec3;

use crate::geom::mesh::box_grid::BoxGrid;

use super::scene::{Geometry, Node, Scene};

/// Kinds whose sharp edges are meant (a solid's, a sheet's rim), so their open edges are
/// not seams.
const NOT_SEAMS: [&str; 2] = ["solid", "sheet"];

/// One point of a seam and the normal jump there.
#[derive(Debug, Clone, PartialEq)]
pub struct SeamPoint {
    /// Where (press mm): a vertex on the open edge of `piece`.
    pub at: DVec3,
    /// The angle between the two pieces' normals there (degrees, 0 to 90).
    pub jump_deg: f64,
    /// The piece the vertex belongs to.
    pub piece: String,
    /// The piece on the other side.
    pub other: String,
}

/// An open (boundary) edge of one piece's tessellation, with the normals at its ends.
struct OpenEdge {
    piece: usize,
    a: DVec3,
    b: DVec3,
    na: DVec3,
    nb: DVec3,
}

/// The seam points of `scene`: every open-edge vertex of a surface piece that lies
/// within `gap` mm of another piece's open edge, with the normal jump there, in scene
/// order (piece, then vertex).
pub fn seam_points(scene: &Scene, gap: f64) -> Vec<SeamPoint> {
    let pieces: Vec<&Node> = scene
        .all_nodes()
        .into_iter()
        .filter(|n| !NOT_SEAMS.contains(&n.kind.as_str()))
        .collect();
    let mut edges = Vec::new();
    for (i, node) in pieces.iter().enumerate() {
        for g in &node.geometry {
            if let Geometry::Triangles {
                positions,
                normals,
                indices,
                ..
            } = g.as_ref()
            {
                edges.extend(open_edges(i, positions, normals, indices));
            }
        }
    }
    let boxes: Vec<(DVec3, DVec3)> = edges.iter().map(|e| (e.a.min(e.b), e.a.max(e.b))).collect();
    let grid = BoxGrid::new(&boxes);
    let mut out = Vec::new();
    let mut seen: Vec<std::collections::HashSet<[i64; 3]>> = vec![Default::default(); pieces.len()];
    for e in &edges {
        for (p, n) in [(e.a, e.na), (e.b, e.nb)] {
            // Each vertex once per piece (it ends two open edges).
            if !seen[e.piece].insert(key(p)) {
                continue;
            }
            if let Some((other, m)) = nearest_normal(&grid, &edges, p, e.piece, gap) {
                out.push(SeamPoint {
                    at: p,
                    jump_deg: line_angle_deg(n, m),
                    piece: pieces[e.piece].name.clone(),
                    other: pieces[other].name.clone(),
                });
            }
        }
    }
    out
}

/// A position as integer micrometres: the identity of a vertex shared by two edges.
fn key(p: DVec3) -> [i64; 3] {
    (p * 1000.0).round().as_i64vec3().to_array()
}

/// The angle between two normals taken as lines (degrees, 0 to 90); 0 when either is
/// zero.
fn line_angle_deg(n: DVec3, m: DVec3) -> f64 {
    let (Some(n), Some(m)) = (n.try_normalize(), m.try_normalize()) else {
        return 0.0;
    };
    n.dot(m).abs().min(1.0).acos().to_degrees()
}

/// The edges of a triangle list used by one triangle only, as stored (an edge and its
/// reverse are the same edge).
fn open_edges(
    piece: usize,
    positions: &[DVec3],
    normals: &[DVec3],
    indices: &[u32],
) -> Vec<OpenEdge> {
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    let mut order = Vec::new();
    for t in indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let k = (a.min(b), a.max(b));
            let c = count.entry(k).or_insert(0);
            if *c == 0 {
                order.push(k);
            }
            *c += 1;
        }
    }
    let at = |i: u32| positions.get(i as usize).copied();
    let normal = |i: u32| normals.get(i as usize).copied().unwrap_or(DVec3::Z);
    order
        .into_iter()
        .filter(|k| count[k] == 1)
        .filter_map(|(a, b)| {
            Some(OpenEdge {
                piece,
                a: at(a)?,
                b: at(b)?,
                na: normal(a),
                nb: normal(b),
            })
        })
        .collect()
}

/// The piece and the interpolated normal of the nearest open edge of a piece other
/// than `piece` within `gap` of `p`, if any.
fn nearest_normal(
    grid: &BoxGrid,
    edges: &[OpenEdge],
    p: DVec3,
    piece: usize,
    gap: f64,
) -> Option<(usize, DVec3)> {
    let reach = DVec3::splat(gap);
    let mut best: Option<(f64, usize, DVec3)> = None;
    for i in grid.candidates(p - reach, p + reach) {
        let e = &edges[i as usize];
        if e.piece == piece {
            continue;
        }
        let ab = e.b - e.a;
        let len2 = ab.length_squared();
        let t = if len2 > 0.0 {
            ((p - e.a).dot(ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = p.distance(e.a + ab * t);
        if d <= gap && best.as_ref().is_none_or(|b| d < b.0) {
            best = Some((d, e.piece, e.na.lerp(e.nb, t)));
        }
    }
    best.map(|(_, piece, n)| (piece, n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    /// A strip of two triangles from x = x0 to x1, y in 0..10, its normals turned by
    /// `tilt` degrees about the X axis.
    fn strip(name: &str, kind: &str, x0: f64, x1: f64, tilt: f64) -> Node {
        let n = DVec3::new(0.0, -tilt.to_radians().sin(), tilt.to_radians().cos());
        Node {
            name: name.into(),
            kind: kind.into(),
            color: [0.5; 3],
            line: 1,
            children: vec![],
            geometry: vec![Arc::new(Geometry::Triangles {
                positions: vec![
                    DVec3::new(x0, 0.0, 0.0),
                    DVec3::new(x1, 0.0, 0.0),
                    DVec3::new(x1, 10.0, 0.0),
                    DVec3::new(x0, 10.0, 0.0),
                ],
                normals: vec![n; 4],
                indices: vec![0, 1, 2, 0, 2, 3],
                groups: vec![],
            })],
            line_bead: None,
        }
    }

    fn scene(nodes: Vec<Node>) -> Scene {
        Scene {
            nodes,
            tolerance_mm: 0.05,
            source_name: "t.die".into(),
        }
    }

    #[test]
    fn two_patches_meeting_at_an_angle_report_it_on_both_sides() {
        let s = scene(vec![
            strip("a", "blankholder", 0.0, 10.0, 0.0),
            strip("b", "blankholder", 10.0, 20.0, 3.0),
        ]);
        let points = seam_points(&s, 0.01);
        // The shared edge x = 10 has two vertices, seen from each side.
        assert_eq!(points.len(), 4, "{points:?}");
        for p in &points {
            assert!((p.at.x - 10.0).abs() < 1e-12);
            assert!((p.jump_deg - 3.0).abs() < 1e-9, "{}", p.jump_deg);
        }
        assert_eq!(points[0].piece, "a");
        assert_eq!(points[0].other, "b");
    }

    #[test]
    fn a_gap_wider_than_asked_is_no_seam_and_a_flipped_normal_is_no_jump() {
        let apart = scene(vec![
            strip("a", "product", 0.0, 10.0, 0.0),
            strip("b", "product", 10.5, 20.0, 0.0),
        ]);
        assert!(seam_points(&apart, 0.1).is_empty());
        let flipped = scene(vec![
            strip("a", "product", 0.0, 10.0, 0.0),
            strip("b", "product", 10.0, 20.0, 180.0),
        ]);
        let points = seam_points(&flipped, 0.01);
        assert_eq!(points.len(), 4);
        assert!(points.iter().all(|p| p.jump_deg < 1e-6));
    }

    #[test]
    fn a_vertex_midway_along_the_other_side_gets_the_interpolated_normal() {
        // Piece b's edge at x = 10 runs y 0..10 with normals 0 and 4 deg at its ends;
        // a's vertex at y = 5 sits halfway, so the other side's normal is the mean.
        let mut b = strip("b", "product", 10.0, 20.0, 0.0);
        let tilt = |d: f64| DVec3::new(0.0, -d.to_radians().sin(), d.to_radians().cos());
        if let Geometry::Triangles { normals, .. } = Arc::make_mut(&mut b.geometry[0]) {
            normals[3] = tilt(4.0);
            normals[0] = tilt(0.0);
        }
        let mut a = strip("a", "product", 0.0, 10.0, 0.0);
        if let Geometry::Triangles { positions, .. } = Arc::make_mut(&mut a.geometry[0]) {
            positions[1].y = 5.0; // the vertex (10, 0) moved to (10, 5)
        }
        let points = seam_points(&scene(vec![a, b]), 0.01);
        let mid = points
            .iter()
            .find(|p| p.piece == "a" && (p.at.y - 5.0).abs() < 1e-9)
            .expect("a's vertex at (10, 5) lies on b's edge");
        let expected = line_angle_deg(DVec3::Z, tilt(0.0).lerp(tilt(4.0), 0.5));
        assert!((mid.jump_deg - expected).abs() < 1e-9 && (expected - 2.0).abs() < 0.01);
    }

    #[test]
    fn solids_are_not_seams() {
        let s = scene(vec![
            strip("a", "solid", 0.0, 10.0, 0.0),
            strip("b", "solid", 10.0, 20.0, 30.0),
        ]);
        assert!(seam_points(&s, 0.01).is_empty());
    }
}
