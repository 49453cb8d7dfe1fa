//! Planar polygons with holes to triangles: a constrained Delaunay triangulation of
//! their loops (`spade`), kept where the loops enclose.

use glam::DVec2;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::geom::error::{GeomError, Result};
use crate::geom::trimmed::polygon_winding;

/// Coordinates below this are taken as 0 (the triangulation refuses magnitudes under
/// about 1e-43).
const TINY: f64 = 1e-30;

/// The triangles of the region bounded by `loops` (an outer loop and any holes, each a
/// closed polygon of 3 points or more, its last point joined to its first), as indices
/// into the loops' points taken in order, counter-clockwise. A point is inside when an
/// odd number of loops run round it, so the holes may run either way. Refused: fewer
/// than 3 points in a loop, and loops that cross or touch.
pub fn triangulate_loops(loops: &[Vec<DVec2>]) -> Result<Vec<[usize; 3]>> {
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
    let inside = |q: DVec2| {
        loops
            .iter()
            .filter(|ring| polygon_winding(ring, q) != 0)
            .count()
            % 2
            == 1
    };
    let mut out = Vec::new();
    for f in cdt.inner_faces() {
        let vs = f.vertices();
        let ids = vs.map(|v| v.fix().index());
        let centre = vs
            .iter()
            .map(|v| DVec2::new(v.position().x, v.position().y))
            .sum::<DVec2>()
            / 3.0;
        if inside(centre) {
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
