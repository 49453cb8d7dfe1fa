//! Planar polygons with holes to triangles: a constrained Delaunay triangulation of
//! their loops (`spade`), kept where the loops enclose.

use glam::DVec2;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::geom::error::{GeomError, Result};

/// Coordinates below this are taken as 0 (the triangulation refuses magnitudes under
/// about 1e-43).
const TINY: f64 = 1e-30;

/// The triangles of the region bounded by `loops` (an outer loop and any holes, each a
/// closed polygon of 3 points or more, its last point joined to its first), as indices
/// into the loops' points taken in order, counter-clockwise. A point is inside when an
/// odd number of loops run round it, so the holes may run either way. Refused: fewer
/// than 3 points in a loop, and loops that cross or touch.
pub fn triangulate_loops(loops: &[Vec<DVec2>]) -> Result<Vec<[usize; 3]>> {
    triangulate_loops_with(loops, &[])
}

/// [`triangulate_loops`] with `inside` points added as corners of the triangles (a
/// face refined for a curved surface it will be laid on): their indices follow the
/// loops' points. Each must lie inside the region, clear of the loops and of each
/// other; one that repeats a point is refused.
pub fn triangulate_loops_with(loops: &[Vec<DVec2>], inside: &[DVec2]) -> Result<Vec<[usize; 3]>> {
    let invalid = |reason: String| GeomError::InvalidMesh { reason };
    let mut points = Vec::new();
    let mut edges = Vec::new();
    for ring in loops {
        if ring.len() < 3 {
            return Err(invalid(format!(
                "a polygon's loop needs 3 points or more, not {}",
                ring.len()
            )));
        }
        let first = points.len();
        for (i, q) in ring.iter().enumerate() {
            // Coordinates too small for the triangulation to take (far below any length
            // a model holds) are 0.
            let snap = |x: f64| if x.abs() < TINY { 0.0 } else { x };
            points.push(Point2::new(snap(q.x), snap(q.y)));
            edges.push([first + i, first + (i + 1) % ring.len()]);
        }
    }
    for q in inside {
        points.push(Point2::new(q.x, q.y));
    }
    let count = points.len();
    let mut conflicts = 0usize;
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(points, edges, |_| conflicts += 1)
            .map_err(|e| invalid(format!("triangulation failed: {e:?}")))?;
    if conflicts > 0 || cdt.num_vertices() != count {
        return Err(invalid(
            "the polygon's loops cross or touch (or a point repeats)".into(),
        ));
    }
    // Inside where an odd number of loops run round: the triangles reached from the
    // outside across an odd number of the loops' edges (flooding the triangulation,
    // so a sliver along nearly straight points of a loop is judged by its neighbours,
    // not by where its centre falls).
    let mut crossings: Vec<Option<usize>> = vec![None; cdt.num_all_faces()];
    let mut queue = std::collections::VecDeque::new();
    for e in cdt.convex_hull() {
        let rev = e.rev();
        if let Some(f) = rev.face().as_inner() {
            let n = usize::from(cdt.is_constraint_edge(e.as_undirected().fix()));
            if crossings[f.fix().index()].is_none() {
                crossings[f.fix().index()] = Some(n);
                queue.push_back(f);
            }
        }
    }
    while let Some(f) = queue.pop_front() {
        let n = crossings[f.fix().index()].unwrap_or(0);
        for e in f.adjacent_edges() {
            let Some(g) = e.rev().face().as_inner() else {
                continue;
            };
            if crossings[g.fix().index()].is_none() {
                let m = n + usize::from(cdt.is_constraint_edge(e.as_undirected().fix()));
                crossings[g.fix().index()] = Some(m);
                queue.push_back(g);
            }
        }
    }
    let mut out = Vec::new();
    for f in cdt.inner_faces() {
        let ids = f.vertices().map(|v| v.fix().index());
        if crossings[f.fix().index()].is_some_and(|n| n % 2 == 1) {
            out.push(ids);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(loops: &[Vec<DVec2>], tris: &[[usize; 3]]) -> f64 {
        let pts: Vec<DVec2> = loops.iter().flatten().copied().collect();
        tris.iter()
            .map(|&[a, b, c]| 0.5 * (pts[b] - pts[a]).perp_dot(pts[c] - pts[a]))
            .sum()
    }

    #[test]
    fn a_square_with_a_square_hole_has_the_area_between() {
        let square = |c: f64, h: f64| {
            vec![
                DVec2::new(c - h, c - h),
                DVec2::new(c + h, c - h),
                DVec2::new(c + h, c + h),
                DVec2::new(c - h, c + h),
            ]
        };
        let loops = vec![square(0.0, 2.0), square(0.5, 0.5)];
        let tris = triangulate_loops(&loops).unwrap();
        // Counter-clockwise, so every triangle's area is positive and they add up.
        assert!((area(&loops, &tris) - (16.0 - 1.0)).abs() < 1e-12);
        // A hole given the other way round is the same hole.
        let mut reversed = loops.clone();
        reversed[1].reverse();
        assert!((area(&reversed, &triangulate_loops(&reversed).unwrap()) - 15.0).abs() < 1e-12);
    }

    #[test]
    fn crossing_loops_and_short_loops_are_refused() {
        let bow = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 1.0),
        ];
        assert!(triangulate_loops(&[bow]).is_err());
        assert!(triangulate_loops(&[vec![DVec2::ZERO, DVec2::X]]).is_err());
    }
}
