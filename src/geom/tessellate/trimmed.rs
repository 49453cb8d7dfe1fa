//! Trimmed faces to triangles, cut exactly at the outline.
//!
//! The boundary is the outline tessellated within the tolerance (so its vertices are
//! exact points of the outline, and a neighbour that tessellates the same curve the
//! same way shares them); the interior points are the untrimmed surface's own
//! tessellation grid (sized by the tolerance and the curvature) inside the loop, kept
//! away from the boundary so no sliver forms. A constrained Delaunay triangulation in
//! `(u, v)` (the `spade` crate) joins them with the boundary segments as constraints;
//! triangles outside the loop are dropped. A triangle whose middle or an inner edge's
//! midpoint deviates from the surface by more than the tolerance gets a new vertex at
//! the worst of them, for a few rounds (the outline's own segments are its chords
//! within the tolerance already).

use std::collections::HashSet;

use glam::{DVec2, DVec3};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::super::error::{GeomError, Result};
use super::super::trimmed::{polygon_winding, TrimmedSurface};
use super::{tessellate_curve, tessellate_surface_within, SurfaceMesh, Tolerance};

/// Rounds of inserting points where a triangle deviates from the surface.
const REFINE_ROUNDS: usize = 8;

/// An interior grid point closer to the boundary than this fraction of the nearest
/// boundary segment's `(u, v)` length is dropped (it would make a sliver).
const CLEARANCE: f64 = 0.4;

/// Tessellates `face` within `tol`: boundary vertices on the outline itself, triangles
/// counter-clockwise in `(u, v)` (normals like `S_u x S_v`), the mesh cut at the
/// outline.
///
/// Errors: the curve and surface tessellators' errors; [`GeomError::InvalidMesh`] if
/// the triangulation fails (a self-crossing outline in `(u, v)`).
pub fn tessellate_trimmed(face: &TrimmedSurface, tol: &Tolerance) -> Result<SurfaceMesh> {
    tessellate_trimmed_within(face, tol, super::MAX_VERTICES)
}

/// [`tessellate_trimmed`] with the untrimmed surface's grid within `max_vertices` (see
/// [`super::tessellate_surface_within`]).
pub fn tessellate_trimmed_within(
    face: &TrimmedSurface,
    tol: &Tolerance,
    max_vertices: usize,
) -> Result<SurfaceMesh> {
    tol.validate()?;
    let s = face.surface();
    let outer = face.outer();
    let line = tessellate_curve(outer.curve(), tol)?;
    // The closed loop's last vertex repeats its first.
    let n = line.points.len() - 1;
    let mut uv: Vec<DVec2> = line.params[..n].iter().map(|&t| face.uv_at(t)).collect();
    let mut positions: Vec<DVec3> = line.points[..n].to_vec();
    let boundary: Vec<DVec2> = uv.clone();
    // Outside the loop's box the winding number is 0: most of the untrimmed grid's
    // points are settled without walking the loop.
    let (lo, hi) = boundary
        .iter()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &q| {
            (lo.min(q), hi.max(q))
        });
    let inside =
        |q: DVec2| q.cmpge(lo).all() && q.cmple(hi).all() && polygon_winding(&boundary, q) != 0;

    // Interior points: the untrimmed tessellation's grid inside the loop, clear of it.
    let grid = tessellate_surface_within(s, tol, max_vertices)?;
    let segments = Segments::new(&boundary);
    for (&q, &p) in grid.uv.iter().zip(&grid.positions) {
        if inside(q) && segments.clear(q) {
            uv.push(q);
            positions.push(p);
        }
    }
    let edges: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    let points: Vec<Point2<f64>> = uv.iter().map(|q| Point2::new(q.x, q.y)).collect();
    let mut conflicts = 0usize;
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(points, edges, |_| conflicts += 1)
            .map_err(|e| invalid(format!("triangulation failed: {e:?}")))?;
    if conflicts > 0 || cdt.num_vertices() != uv.len() {
        return Err(invalid(
            "the outline crosses itself (or touches itself) in the surface's (u, v) plane".into(),
        ));
    }

    // Triangles that met the tolerance in an earlier round: a triangle's check depends
    // on its three vertices only, so one still in the triangulation passes again and is
    // not measured again.
    let mut passed: HashSet<[usize; 3]> = HashSet::new();
    for _ in 0..REFINE_ROUNDS {
        let mut added = false;
        let faces = inner_triangles(&cdt, n, &inside);
        let mut inserts: Vec<DVec2> = Vec::new();
        for [a, b, c] in faces {
            let mut key = [a, b, c];
            key.sort_unstable();
            if passed.contains(&key) {
                continue;
            }
            // The middle and the midpoints of the edges that are not outline segments
            // (those are the outline's own chords, within the tolerance already).
            let outline_edge = |i: usize, j: usize| {
                i < n && j < n && (i + 1 == j || j + 1 == i || (i + j + 1 == n && i.min(j) == 0))
            };
            let mut probes = [(DVec2::ZERO, DVec3::ZERO); 4];
            probes[0] = (
                (uv[a] + uv[b] + uv[c]) / 3.0,
                (positions[a] + positions[b] + positions[c]) / 3.0,
            );
            let mut count = 1;
            for (i, j) in [(a, b), (b, c), (c, a)] {
                if !outline_edge(i, j) {
                    probes[count] = (0.5 * (uv[i] + uv[j]), 0.5 * (positions[i] + positions[j]));
                    count += 1;
                }
            }
            let worst = probes[..count]
                .iter()
                .map(|&(q, flat)| (q, s.point_at(q.x, q.y).distance(flat)))
                .max_by(|x, y| x.1.total_cmp(&y.1));
            match worst.filter(|w| w.1 > tol.chordal) {
                Some((q, _)) => inserts.push(q),
                None => {
                    passed.insert(key);
                }
            }
        }
        for q in inserts {
            let idx = cdt
                .insert(Point2::new(q.x, q.y))
                .map_err(|e| invalid(format!("triangulation failed: {e:?}")))?;
            if idx.index() == uv.len() {
                uv.push(q);
                positions.push(s.point_at(q.x, q.y));
                added = true;
            }
        }
        if !added {
            break;
        }
    }

    let triangles: Vec<[u32; 3]> = inner_triangles(&cdt, n, &inside)
        .into_iter()
        .map(|[a, b, c]| [a as u32, b as u32, c as u32])
        .collect();
    let extent = s.net_extent();
    let normals = uv
        .iter()
        .map(|q| s.normal_within(q.x, q.y, extent).unwrap_or(DVec3::Z))
        .collect();
    Ok(SurfaceMesh {
        uv,
        positions,
        normals,
        triangles,
    })
}

fn invalid(reason: String) -> GeomError {
    GeomError::InvalidMesh { reason }
}

/// The triangles of `cdt` inside the loop, counter-clockwise, as vertex indices (the
/// insertion order). The first `boundary` vertices are the outline's; every other
/// vertex lies inside it, so only a triangle of three outline vertices needs the
/// inside test.
fn inner_triangles(
    cdt: &ConstrainedDelaunayTriangulation<Point2<f64>>,
    boundary: usize,
    inside: &impl Fn(DVec2) -> bool,
) -> Vec<[usize; 3]> {
    let mut out = Vec::new();
    for f in cdt.inner_faces() {
        let [a, b, c] = f.vertices();
        let ids = [a.fix().index(), b.fix().index(), c.fix().index()];
        if ids.iter().any(|&i| i >= boundary) {
            out.push(ids);
            continue;
        }
        let p = |v: &spade::handles::VertexHandle<'_, Point2<f64>, (), _, ()>| {
            let q = v.position();
            DVec2::new(q.x, q.y)
        };
        let centre = (p(&a) + p(&b) + p(&c)) / 3.0;
        if inside(centre) {
            out.push(ids);
        }
    }
    out
}

/// The boundary segments in a bucket grid, for the clearance test.
struct Segments {
    points: Vec<DVec2>,
    origin: DVec2,
    cell: f64,
    cols: usize,
    rows: usize,
    buckets: Vec<Vec<usize>>,
}

impl Segments {
    fn new(points: &[DVec2]) -> Self {
        let n = points.len();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        let mut total = 0.0;
        for i in 0..n {
            lo = lo.min(points[i]);
            hi = hi.max(points[i]);
            total += points[i].distance(points[(i + 1) % n]);
        }
        let cell = (total / n.max(1) as f64)
            .max((hi - lo).max_element() / 512.0)
            .max(1e-12);
        let cols = (((hi.x - lo.x) / cell) as usize + 1).min(1024);
        let rows = (((hi.y - lo.y) / cell) as usize + 1).min(1024);
        let mut grid = Self {
            points: points.to_vec(),
            origin: lo,
            cell,
            cols,
            rows,
            buckets: vec![Vec::new(); cols * rows],
        };
        for i in 0..n {
            let (a, b) = (points[i], points[(i + 1) % n]);
            let (c0, r0) = grid.cell_of(a.min(b));
            let (c1, r1) = grid.cell_of(a.max(b));
            for r in r0..=r1 {
                for c in c0..=c1 {
                    grid.buckets[r * cols + c].push(i);
                }
            }
        }
        grid
    }

    fn cell_of(&self, q: DVec2) -> (usize, usize) {
        let d = (q - self.origin) / self.cell;
        (
            (d.x.max(0.0) as usize).min(self.cols - 1),
            (d.y.max(0.0) as usize).min(self.rows - 1),
        )
    }

    /// Whether `q` keeps [`CLEARANCE`] times the nearest segment's length from it.
    fn clear(&self, q: DVec2) -> bool {
        let n = self.points.len();
        let (c, r) = self.cell_of(q);
        let reach = 2usize;
        for rr in r.saturating_sub(reach)..=(r + reach).min(self.rows - 1) {
            for cc in c.saturating_sub(reach)..=(c + reach).min(self.cols - 1) {
                for &i in &self.buckets[rr * self.cols + cc] {
                    let (a, b) = (self.points[i], self.points[(i + 1) % n]);
                    let ab = b - a;
                    let len2 = ab.length_squared();
                    let t = if len2 > 0.0 {
                        ((q - a).dot(ab) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    if q.distance(a + ab * t) < CLEARANCE * len2.sqrt() {
                        return false;
                    }
                }
            }
        }
        true
    }
}
